/* SPDX-License-Identifier: MIT */
/*
** main.c -- `ggrt`: dispatch to a subcommand.
*/
#include "common/cli.h"

#include <string.h>

typedef struct command {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *summary;
} command;

static const command commands[] = {
    {"render", cmd_render, "render a scene to PNG or EXR"},
    {"plan", cmd_plan, "cut an image into tiles of equal cost for render --plan"},
    {"merge", cmd_merge, "join render --tile's tiles or find/check/diff --tile's reports"},
    {"trace", cmd_trace, "print the ray tree of one pixel"},
    {"find", cmd_find, "the pixels whose rays satisfy a predicate"},
    {"check", cmd_check, "scan every pixel for invariants (NaN, energy, truncation...)"},
    {"diff", cmd_diff, "compare two renders ray by ray"},
    {"info", cmd_info, "describe a scene: objects, lights, BVH, effects"},
    {"optics", cmd_optics, "one reflection, refraction or Fresnel evaluation"},
    {"bench", cmd_bench, "benchmarks: SPD scenes, accuracy versus time"},
    {"serve", cmd_serve, "the ray debugger in a browser: a local HTTP server"},
};

static void usage(FILE *f)
{
    size_t i;
    fprintf(f, "usage: ggrt <command> [options]\n"
               "       ggrt --version\n\ncommands:\n");
    for (i = 0; i < sizeof commands / sizeof commands[0]; i++)
        fprintf(f, "  %-8s %s\n", commands[i].name, commands[i].summary);
    fprintf(f, "\noptions:\n"
               "  -h, --help     this text\n"
               "      --version  print ggrt's version and exit\n"
               "\n'ggrt help <command>' or 'ggrt <command> --help' describes one command;\n"
               "'man ggrt' all of them.\n"
               "Exit codes: 0 success, 1 usage, 2 bad input, 3 I/O error, 4 a check failed\n"
               "(ggrt check, ggrt optics check).\n");
}

static int dispatch(int argc, char **argv);

/* `ggrt help CMD [SUB...]` (or --help, -h): CMD's own --help, as
   `ggrt CMD [SUB...] --help` gives it; an unknown CMD is dispatch's
   usage error. */
static int help_on(int argc, char **argv)
{
    char *args[16];
    int i, n = argc - 1;
    if (!strcmp(argv[2], "-h") || !strcmp(argv[2], "--help") || !strcmp(argv[2], "help") ||
        !strcmp(argv[2], "--version") || !strcmp(argv[2], "version")) {
        usage(stdout); /* `ggrt help help`: the usage says both */
        return EXIT_OK;
    }
    if (n + 1 > (int)(sizeof args / sizeof args[0])) {
        cli_error("too many words after '%s'", argv[1]);
        return EXIT_USAGE;
    }
    args[0] = argv[0];
    for (i = 2; i < argc; i++) args[i - 1] = argv[i];
    args[n] = "--help";
    return dispatch(n + 1, args);
}

static int dispatch(int argc, char **argv)
{
    const char *names[sizeof commands / sizeof commands[0]], *near;
    size_t i;
    int ended = 0; /* `ggrt -- CMD`: what follows -- is the command, as in a command's options */
    if (argc >= 2 && !strcmp(argv[1], "--")) argc--, argv++, ended = 1;
    if (argc < 2) {
        usage(stderr);
        return EXIT_USAGE;
    }
    if (!ended &&
        (!strcmp(argv[1], "-h") || !strcmp(argv[1], "--help") || !strcmp(argv[1], "help"))) {
        if (argc > 2) return help_on(argc, argv);
        usage(stdout);
        return EXIT_OK;
    }
    if (!ended && (!strcmp(argv[1], "--version") || !strcmp(argv[1], "version"))) {
        if (argc > 2 && (!strcmp(argv[2], "--help") || !strcmp(argv[2], "-h"))) {
            usage(stdout); /* --help anywhere: the usage, which lists --version */
            return EXIT_OK;
        }
        if (argc > 2) {
            cli_error("unexpected argument '%s' (%s takes none)", argv[2], argv[1]);
            fprintf(stderr, "run 'ggrt --help' for the list of commands\n");
            return EXIT_USAGE;
        }
        printf("ggrt %s (build %s)\n", ggVersion(), ggBuildId());
        return EXIT_OK;
    }
    for (i = 0; i < sizeof commands / sizeof commands[0]; i++) {
        names[i] = commands[i].name;
        if (!strcmp(argv[1], commands[i].name)) {
            cli_set_command(commands[i].name);
            return commands[i].run(argc - 1, argv + 1);
        }
    }
    /* A usage error like a subcommand's unknown option (exit 1), in two
       lines, not the whole usage: the typo and where the list is. */
    if (argv[1][0] == '-' && !ended) {
        static const char *const opts[] = {"--help", "--version"};
        near = cli_suggest(argv[1], opts, sizeof opts / sizeof opts[0]);
        if (near)
            cli_error("unknown option '%s'; did you mean '%s'?", argv[1], near);
        else
            cli_error("unknown option '%s'", argv[1]);
    } else {
        near = cli_suggest(argv[1], names, i);
        if (near)
            cli_error("unknown command '%s'; did you mean '%s'?", argv[1], near);
        else
            cli_error("unknown command '%s'", argv[1]);
    }
    fprintf(stderr, "run 'ggrt --help' for the list of commands\n");
    return EXIT_USAGE;
}

int main(int argc, char **argv)
{
    int rc = dispatch(argc, argv);
    /* Output that did not reach stdout (a full disk, /dev/full, a closed
       pipe's EIO) is an I/O error even when the command itself succeeded,
       and wins over a failed check: the report of what failed was lost. */
    int out = cli_close_stdout();
    return (rc == EXIT_OK || rc == EXIT_CHECK) && out ? out : rc;
}
