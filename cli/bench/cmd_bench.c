/* SPDX-License-Identifier: MIT */
/*
** cmd_bench.c -- `ggrt bench NAME [options]`: which benchmark, with which
** options. Every figure is measured in the same run it is printed in.
*/
#include "bench/bench.h"

#include <stdio.h>
#include <string.h>

/* Each benchmark: its name, what it measures (ggrt bench --help lists
   them all; ggrt bench NAME --help prints its own with only the options
   it reads), its default --size, the scenes --scenes picks from, and the
   options it reads nothing from, refused rather than ignored. --embree,
   --accuracy, --pov and --no-pov are spd's alone, --knobs and --out
   accuracy's (bench_takes). */
static const struct {
    const char *name;
    int (*run)(const bench_opts *bo);
    const char *args; /* its usage's arguments */
    const char *about;
    int size;                  /* default --size; 0: the benchmark's own */
    const char *const *scenes; /* the names --scenes picks from (NULL: no --scenes) */
    int nscenes;
    const char *const unused[3];
} benches[] = {
    {"spd",
     bench_spd,
     "[options]",
     "the 7 SPD scenes (depth 5, pixel centres, no antialiasing) and,\n"
     "if povray is installed, the same scenes with POV-Ray 3.7: trace\n"
     "times, ratios, rays per second, peak memory, bytes per primitive;\n"
     "with --embree, also the Embree anchor, all three interleaved",
     1024,
     bench_spd_scenes,
     BENCH_NSPD,
     {NULL}},
    {"counts",
     bench_counts,
     "[options]",
     "SPD rules (pixel corners, depth 5, transmitters reflect) at\n"
     "512x512: eye-hit, reflect, refract and shadow rays against the\n"
     "SPD's table",
     0,
     bench_spd_scenes,
     BENCH_NSPD,
     {"runs", "size"}},
    {"effects",
     bench_effects,
     "[options]",
     "each example scene rendered with its own effect set and with\n"
     "every effect forced on: times, ratio, whether the images match",
     320,
     bench_effects_scenes,
     BENCH_NEFFECTS,
     {"spd"}},
    {"accuracy",
     bench_accuracy,
     "SCENE... [options]",
     "sweep each accuracy knob from the accurate default: median time,\n"
     "rays, RMSE, max error, PSNR, share of pixels off by > 1/255 and\n"
     "pixels whose ray tree changed, against an all-accurate\n"
     "reference; writes DIR/accuracy.csv and DIR/accuracy.svg\n"
     "(docs/accuracy.md), then the scaling tables",
     0,
     NULL,
     0,
     {"spd"}},
    {"scaling",
     bench_scaling,
     "[options]",
     "render time against primitives (balls-s1..s4, fitted against\n"
     "ln n), image size and threads; per SPD scene 1 and 2 threads,\n"
     "the speed-up and the serial share (time outside the tile loop)",
     0,
     bench_spd_scenes,
     BENCH_NSPD,
     {NULL}},
    {"rays",
     bench_rays,
     "[SCENE...] [options]",
     "per SPD scene (or per SCENE given), Mrays/s on one core for the\n"
     "eye, secondary and shadow rays of a 256x256 render, cast again\n"
     "one by one",
     256,
     bench_spd_scenes,
     BENCH_NSPD,
     {"threads"}},
    {"limit",
     bench_limit,
     "[SCENE...] [options]",
     "per SPD scene (or per SCENE given), one thread: the kernel calls\n"
     "per ray of a render (node, packet and leaf tests, hits shaded),\n"
     "each kernel's ns per call alone in a loop on cached data, the\n"
     "bound (calls x ns) and the render's time over it",
     512,
     bench_spd_scenes,
     BENCH_NSPD,
     {"threads"}},
};
#define NBENCH ((int)(sizeof benches / sizeof benches[0]))

static const char tail[] =
    "Scene folders are relative to the current directory: run from the source tree\n"
    "or name them with --spd and --pov.";
static const char tail_spd[] =
    "The scene folder is relative to the current directory: run from the source tree\n"
    "or name it with --spd.";

/* Whether benchmark b reads the option of long name `opt`. */
static int bench_takes(int b, const char *opt)
{
    int k;
    if (!strcmp(opt, "embree") || !strcmp(opt, "accuracy") || !strcmp(opt, "pov") ||
        !strcmp(opt, "no-pov"))
        return benches[b].run == bench_spd;
    if (!strcmp(opt, "knobs") || !strcmp(opt, "out")) return benches[b].run == bench_accuracy;
    if (!strcmp(opt, "scenes")) return benches[b].scenes != NULL;
    for (k = 0; k < 3 && benches[b].unused[k]; k++)
        if (!strcmp(opt, benches[b].unused[k])) return 0;
    return 1;
}

/* Whether exactly one benchmark reads option `opt` (--embree: spd). */
static int one_takes(const char *opt)
{
    int b, n = 0;
    for (b = 0; b < NBENCH; b++) n += bench_takes(b, opt);
    return n == 1;
}

/* ggrt bench --help's list: each benchmark's name and what it measures. */
static const char *about_all(void)
{
    static char buf[2048];
    size_t n = 0;
    int b;
    const char *p;
    for (b = 0; b < NBENCH; b++) {
        n += (size_t)snprintf(buf + n, sizeof buf - n, "%s  %-9s ", b ? "\n" : "", benches[b].name);
        for (p = benches[b].about; *p && n + 16 < sizeof buf; p++) {
            buf[n++] = *p;
            if (*p == '\n') n += (size_t)snprintf(buf + n, sizeof buf - n, "%12s", "");
        }
        buf[n] = '\0';
    }
    return buf;
}

/* "a, b, c" of names[0..n) into out (size outsize). */
static void join_names(char *out, size_t outsize, const char *const *names, int n)
{
    int i;
    out[0] = '\0';
    for (i = 0; i < n; i++)
        snprintf(out + strlen(out), outsize - strlen(out), "%s%s", i ? ", " : "", names[i]);
}

/* --knobs against bench accuracy's knob names: 0, or a usage error's code. */
static int check_knobs(const cli_cmd *cmd, const bench_opts *bo)
{
    const char *names[32];
    char bad[64], all[512];
    int n = bench_knob_names(names, 32);
    if (!bo->knobs || !bench_unknown(bo->knobs, (const char *const *)names, n, bad, sizeof bad))
        return 0;
    join_names(all, sizeof all, (const char *const *)names, n);
    return cli_usage_error(cmd, "--knobs: no knob '%s' (the knobs: %s)", bad, all);
}

/* --scenes against benchmark b's names: 0, or a usage error's code. */
static int check_scenes(const cli_cmd *cmd, int b, const bench_opts *bo)
{
    char bad[64], names[256];
    if (!bo->scenes) return 0;
    if (!benches[b].scenes)
        return cli_usage_error(cmd,
                               "--scenes does not apply to this benchmark (it takes scene files)");
    if (bo->nargs)
        return cli_usage_error(cmd,
                               "--scenes picks SPD scenes; give scene files or --scenes, not both");
    if (!bench_unknown(bo->scenes, benches[b].scenes, benches[b].nscenes, bad, sizeof bad))
        return 0;
    join_names(names, sizeof names, benches[b].scenes, benches[b].nscenes);
    return cli_usage_error(cmd, "--scenes: no scene '%s' in this benchmark (its scenes: %s)", bad,
                           names);
}

/* An option given that benchmark b reads nothing from: a usage error
   naming it, rather than the option ignored. */
static int check_options(const cli_cmd *cmd, const cli_opt *opts, int b)
{
    int k, c;
    for (k = 0; opts[k].kind != CLI_END; k++) {
        const char *o = opts[k].name;
        if (!opts[k].given || bench_takes(b, o)) continue;
        if (!strcmp(o, "scenes"))
            return cli_usage_error(
                cmd, "--scenes does not apply to this benchmark (it takes scene files)");
        /* Its reference table is for one size: another would be ignored. */
        if (!strcmp(o, "size") && benches[b].run == bench_counts)
            return cli_usage_error(cmd, "--size does not apply to this benchmark (it renders "
                                        "at the SPD table's 513x513)");
        /* one benchmark's own (--embree: spd's) */
        for (c = 0; c < NBENCH && !bench_takes(c, o); c++) {
        }
        if (c < NBENCH && one_takes(o))
            return cli_usage_error(cmd, "--%s is an option of bench %s only", o, benches[c].name);
        return cli_usage_error(
            cmd, "--%s does not apply to this benchmark (it reads nothing from it)", o);
    }
    return 0;
}

/* ggrt bench NAME --help: NAME's own usage, text and options. */
static int bench_help(cli_cmd *cmd, const cli_opt *opts, int b, char *name, size_t len)
{
    cli_opt own[16];
    int k, n = 0;
    for (k = 0; opts[k].kind != CLI_END && n < 15; k++)
        if (bench_takes(b, opts[k].name)) own[n++] = opts[k];
    own[n] = opts[k]; /* CLI_END */
    snprintf(name, len, "bench %s", benches[b].name);
    cmd->name = name;
    cmd->usage = benches[b].args;
    cmd->about = benches[b].about;
    cmd->opts[0] = own;
    cmd->tail = bench_takes(b, "pov") ? tail : bench_takes(b, "spd") ? tail_spd : NULL;
    cli_set_command(name);
    cli_help(stdout, cmd);
    return EXIT_OK;
}

/* The benchmark that the first argument names (-1 if none), and whether
   --help is asked for (before any "--"). */
static int named_bench(int argc, char **argv, int *help)
{
    int i, b = -1;
    *help = 0;
    for (i = 1; i < argc && strcmp(argv[i], "--"); i++)
        if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) *help = 1;
    for (i = 0; argc > 1 && i < NBENCH; i++)
        if (!strcmp(argv[1], benches[i].name)) b = i;
    return b;
}

int cmd_bench(int argc, char **argv)
{
    bench_opts bo;
    const char *args[BENCH_MAX_ARGS + 1];
    int no_pov = 0, nargs = 0, rc, i, help;
    char name[32];
    cli_opt opts[] = {
        CLI_OPT_INT(0, "size", &bo.size, 1, 4096, "N",
                    "image size N x N (spd: 1024; effects: 320; accuracy: 240\n"
                    "wide, 4:3; scaling: 256; rays: 256; limit: 512; not\n"
                    "counts: the SPD table's 513x513)"),
        CLI_OPT_INT('j', "threads", &bo.threads, 1, 256, "N", "threads (default 2)"),
        CLI_OPT_INT(0, "runs", &bo.runs, 1, 64, "N",
                    "runs per measurement, median reported (default 3)"),
        CLI_OPT_STRING(0, "spd", &bo.spd_dir, "DIR", "NFF scenes (default examples/scenes/spd)"),
        CLI_OPT_STRING(0, "pov", &bo.pov_dir, "DIR",
                       "spd: POV-Ray scenes, .pov.gz (default\n"
                       "examples/scenes/spd-pov)"),
        CLI_OPT_FLAG(0, "no-pov", &no_pov, "spd: do not run POV-Ray"),
        CLI_OPT_STRING(0, "embree", &bo.embree, "BIN",
                       "spd: also time the Embree Whitted anchor BIN\n"
                       "(-p 1 and -p 16), rounds interleaved"),
        CLI_OPT_STRING(0, "scenes", &bo.scenes, "LIST", "comma-separated subset of scene names"),
        CLI_OPT_STRING(0, "out", &bo.out_dir, "DIR",
                       "accuracy: where it writes its CSV and SVG (default .)"),
        CLI_OPT_MANY('a', "accuracy", cli_parse_accuracy, &bo.accuracy, "KNOB=V,...",
                     "spd: render ggrt with these accuracy knobs (as in\n"
                     "'ggrt render --accuracy'), e.g. shadows=opaque for the\n"
                     "Embree anchor's shadow model"),
        CLI_OPT_STRING(0, "knobs", &bo.knobs, "LIST",
                       "accuracy: only these knobs (comma-separated names\n"
                       "as in its tables, e.g. intersect,sphere); the\n"
                       "default row is always measured, the scaling tables\n"
                       "are left out"),
        CLI_OPT_END,
    };
    cli_cmd cmd = {.name = "bench",
                   .usage = "spd|counts|effects|scaling [options]\n"
                            "       ggrt bench rays|limit [SCENE...] [options]\n"
                            "       ggrt bench accuracy SCENE... [options]\n"
                            "       ggrt bench NAME --help   (NAME's own text and options)",
                   .about = about_all(),
                   .tail = tail,
                   .opts = {opts},
                   .args = args,
                   .min_args = 1,
                   .max_args = BENCH_MAX_ARGS + 1,
                   .nargs = &nargs,
                   .args_name = "benchmark name"};
    memset(&bo, 0, sizeof bo);
    bo.threads = 2, bo.runs = 3;
    bo.spd_dir = "examples/scenes/spd";
    bo.pov_dir = "examples/scenes/spd-pov";
    if ((i = named_bench(argc, argv, &help)) >= 0 && help)
        return bench_help(&cmd, opts, i, name, sizeof name);
    if ((rc = cli_parse(&cmd, argc, argv)) != CLI_GO) return rc;
    bo.pov = !no_pov;
    for (i = 1; i < nargs; i++) bo.args[bo.nargs++] = args[i];
    for (i = 0; i < NBENCH; i++) {
        if (strcmp(args[0], benches[i].name)) continue;
        /* "ggrt bench counts: ..." from here on, the usage errors too */
        snprintf(name, sizeof name, "bench %s", benches[i].name);
        cmd.name = name;
        cli_set_command(name);
        if (bo.nargs && benches[i].run != bench_accuracy && benches[i].run != bench_limit &&
            benches[i].run != bench_rays)
            return cli_usage_error(&cmd, "this benchmark takes no scene files ('%s')", bo.args[0]);
        if ((rc = check_scenes(&cmd, i, &bo)) != 0 || (rc = check_knobs(&cmd, &bo)) != 0 ||
            (rc = check_options(&cmd, opts, i)) != 0)
            return rc;
        {
            /* any knob off its default: the options' text is not empty */
            ggRenderOptions t;
            char b[8];
            ggRenderOptionsDefault(&t);
            t.accuracy = bo.accuracy;
            bo.has_accuracy = ggRenderOptionsFormat(&t, b, sizeof b) > 0;
        }
        if (!opts[0].given) bo.size = benches[i].size;
        return benches[i].run(&bo);
    }
    {
        const char *names[NBENCH], *near;
        char all[128];
        for (i = 0; i < NBENCH; i++) names[i] = benches[i].name;
        join_names(all, sizeof all, names, i);
        if ((near = cli_suggest(args[0], names, (size_t)i)))
            return cli_usage_error(&cmd, "unknown benchmark '%s'; did you mean '%s'? (%s)", args[0],
                                   near, all);
        return cli_usage_error(&cmd, "unknown benchmark '%s' (%s)", args[0], all);
    }
}
