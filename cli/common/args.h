/* SPDX-License-Identifier: MIT */
/*
** args.h -- the one command-line parser every ggrt command uses.
**
** A command declares its options as a table of cli_opt (with the CLI_OPT_*
** macros below), its positional arguments and its help text in a cli_cmd,
** and calls cli_parse. The parser
**  - accepts -x VALUE, -xVALUE, --name VALUE, --name=VALUE, grouped short
**    flags (-qv), and "--" to end the options; a value may start with '-'
**    (--v -1,0,0);
**  - parses every value completely: a number with anything after it
**    (1,2junk), too many or too few fields (1,2,3 for X,Y; 8x6x4), an
**    overflow or a value outside the option's range is an error whose
**    message names the option, echoes the value as given and states what
**    is allowed ("expected X,Y: two whole numbers from 0 to 65535");
**  - refuses an option that takes a value given twice (-s 8x6 ... -s 4x4),
**    naming both values, unless the table says it repeats (CLI_OPT_MANY);
**  - never writes into argv (values are parsed in place, read-only);
**  - prints --help from the same tables, so help cannot forget an option
**    (tests/cli/manpage.py checks that docs/ggrt.1 documents each one).
**
** Example (a command with one flag, one number, the shared render options
** and one scene):
**
**     int quiet = 0, port = 8080, rc;
**     const char *scene;
**     cli_render ro;
**     cli_opt mine[] = {
**         CLI_OPT_INT('p', "port", &port, 1, 65535, "N", "port to listen on (default 8080)"),
**         CLI_OPT_FLAG('q', "quiet", &quiet, "print nothing but errors"),
**         CLI_OPT_END,
**     };
**     cli_cmd cmd = {.name = "serve", .usage = "SCENE [options]",
**                    .about = "Serve a scene to a browser.",
**                    .opts = {mine, ro.table}, .args = &scene, .min_args = 1, .max_args = 1};
**     cli_render_init(&ro, CLI_RENDER_ALL);
**     if ((rc = cli_parse(&cmd, argc, argv)) != CLI_GO) return rc;
**     cli_render_finish(&ro);   (ro.opt is now the ggRenderOptions to render with)
**
** The tables live on the caller's stack: C99 allows non-constant
** initializers there, and the macros check each destination's type.
*/
#ifndef GG_CLI_ARGS_H
#define GG_CLI_ARGS_H

#include "ggrt.h"

#include <stddef.h>
#include <stdio.h>

/* Lets GCC and clang check a printf-style function's arguments against its
   format (argument fmt_index is the format, first_arg the first value);
   the CLI's only compiler-specific spelling. */
#if defined(__GNUC__)
#define CLI_PRINTF(fmt_index, first_arg) __attribute__((format(printf, fmt_index, first_arg)))
#else
#define CLI_PRINTF(fmt_index, first_arg)
#endif

/* What an option's value is, and what dst points to. */
enum cli_kind {
    CLI_END = 0, /* ends a table */
    CLI_SECTION, /* a heading in --help ("render options:"); help = the title */
    CLI_FLAG,    /* no value; int *dst = 1 */
    CLI_INT,     /* int *dst in [lo, hi] */
    CLI_DOUBLE,  /* double *dst, finite, in [lo, hi] */
    CLI_STRING,  /* const char **dst = the argument itself (not copied) */
    CLI_CHOICE,  /* int *dst = index of the value in choices (NULL-terminated) */
    CLI_SIZE,    /* int dst[2] = W, H from "WxH", each in [lo, hi], W*H at most
                    GG_IMAGE_MAX_PIXELS (an image's size) */
    CLI_XY,      /* int dst[2] = X, Y from "X,Y", each in [lo, hi] */
    CLI_BOX,     /* int dst[4] = X0, Y0, X1, Y1 from "X0,Y0,X1,Y1", each in [lo, hi] */
    CLI_VEC3,    /* ggVec3 *dst from "X,Y,Z", three finite numbers */
    CLI_FUNC     /* fn(ud, value, why, whylen) parses it: 0, or non-zero with why set */
};

typedef int (*cli_func)(void *ud, const char *value, char *why, size_t whylen);

typedef struct cli_opt {
    int kind;                   /* enum cli_kind */
    char shrt;                  /* 'o' for -o, or 0 */
    const char *name;           /* "output" for --output, or NULL */
    const char *arg;            /* placeholder in help ("FILE"); NULL for flags */
    const char *help;           /* help text; '\n' starts a continuation line */
    void *dst;                  /* where the value goes (see cli_kind) */
    double lo, hi;              /* allowed range of numbers */
    const char *const *choices; /* CLI_CHOICE */
    cli_func fn;                /* CLI_FUNC */
    void *ud;                   /* CLI_FUNC */
    int many;                   /* may be given more than once (CLI_OPT_MANY) */
    int given;                  /* set by cli_parse: how many times the option appeared */
    const char *last;           /* set by cli_parse: its value as given last time */
} cli_opt;

/* Type checks for the macros (a wrong destination type does not compile). */
static inline void *cli_p_int(int *p)
{
    return p;
}
static inline void *cli_p_double(double *p)
{
    return p;
}
static inline void *cli_p_str(const char **p)
{
    return p;
}
static inline void *cli_p_vec3(ggVec3 *p)
{
    return p;
}

#define CLI_OPT_FLAG(s, n, p, h_)                                                                  \
    {                                                                                              \
        .kind = CLI_FLAG, .shrt = (s), .name = (n), .help = (h_), .dst = cli_p_int(p)              \
    }
#define CLI_OPT_INT(s, n, p, lo_, hi_, arg_, h_)                                                   \
    {                                                                                              \
        .kind = CLI_INT, .shrt = (s), .name = (n), .arg = (arg_), .help = (h_),                    \
        .dst = cli_p_int(p), .lo = (lo_), .hi = (hi_)                                              \
    }
#define CLI_OPT_DOUBLE(s, n, p, lo_, hi_, arg_, h_)                                                \
    {                                                                                              \
        .kind = CLI_DOUBLE, .shrt = (s), .name = (n), .arg = (arg_), .help = (h_),                 \
        .dst = cli_p_double(p), .lo = (lo_), .hi = (hi_)                                           \
    }
#define CLI_OPT_STRING(s, n, p, arg_, h_)                                                          \
    {                                                                                              \
        .kind = CLI_STRING, .shrt = (s), .name = (n), .arg = (arg_), .help = (h_),                 \
        .dst = cli_p_str(p)                                                                        \
    }
#define CLI_OPT_CHOICE(s, n, p, list, arg_, h_)                                                    \
    {                                                                                              \
        .kind = CLI_CHOICE, .shrt = (s), .name = (n), .arg = (arg_), .help = (h_),                 \
        .dst = cli_p_int(p), .choices = (list)                                                     \
    }
/* p: int[2] (SIZE, XY) or int[4] (BOX). */
#define CLI_OPT_SIZE(s, n, p, lo_, hi_, arg_, h_)                                                  \
    {                                                                                              \
        .kind = CLI_SIZE, .shrt = (s), .name = (n), .arg = (arg_), .help = (h_),                   \
        .dst = cli_p_int(p), .lo = (lo_), .hi = (hi_)                                              \
    }
#define CLI_OPT_XY(s, n, p, lo_, hi_, arg_, h_)                                                    \
    {                                                                                              \
        .kind = CLI_XY, .shrt = (s), .name = (n), .arg = (arg_), .help = (h_),                     \
        .dst = cli_p_int(p), .lo = (lo_), .hi = (hi_)                                              \
    }
#define CLI_OPT_BOX(s, n, p, lo_, hi_, arg_, h_)                                                   \
    {                                                                                              \
        .kind = CLI_BOX, .shrt = (s), .name = (n), .arg = (arg_), .help = (h_),                    \
        .dst = cli_p_int(p), .lo = (lo_), .hi = (hi_)                                              \
    }
#define CLI_OPT_VEC3(s, n, p, arg_, h_)                                                            \
    {                                                                                              \
        .kind = CLI_VEC3, .shrt = (s), .name = (n), .arg = (arg_), .help = (h_),                   \
        .dst = cli_p_vec3(p)                                                                       \
    }
#define CLI_OPT_FUNC(s, n, fn_, ud_, arg_, h_)                                                     \
    {                                                                                              \
        .kind = CLI_FUNC, .shrt = (s), .name = (n), .arg = (arg_), .help = (h_), .fn = (fn_),      \
        .ud = (ud_)                                                                                \
    }
/* A CLI_FUNC option that may be repeated, each value added to the last
   (--accuracy a=b --accuracy c=d). Every other option that takes a value
   may be given once: a second one is a usage error, not a silent
   override (flags may repeat; they only say yes). */
#define CLI_OPT_MANY(s, n, fn_, ud_, arg_, h_)                                                     \
    {                                                                                              \
        .kind = CLI_FUNC, .shrt = (s), .name = (n), .arg = (arg_), .help = (h_), .fn = (fn_),      \
        .ud = (ud_), .many = 1                                                                     \
    }
#define CLI_OPT_SECTION(title)                                                                     \
    {                                                                                              \
        .kind = CLI_SECTION, .help = (title)                                                       \
    }
#define CLI_OPT_END                                                                                \
    {                                                                                              \
        .kind = CLI_END                                                                            \
    }

#define CLI_MAX_TABLES 6

/* A command: its name for messages ("render", "optics refract"), the
   usage line after "usage: ggrt NAME ", a description and an optional
   closing text for --help, its option tables (NULL-terminated list) and
   where its positional arguments go. */
typedef struct cli_cmd {
    const char *name;
    const char *usage;
    const char *about;
    const char *tail;
    cli_opt *opts[CLI_MAX_TABLES + 1];
    const char **args; /* receives up to max_args positional arguments */
    int min_args, max_args;
    int *nargs;            /* receives their number (may be NULL) */
    const char *args_name; /* what they are, for messages ("scene"); NULL = "argument" */
} cli_cmd;

/* cli_parse's "go on": anything else is the exit code to return now. */
#define CLI_GO (-1)

/* Parse argv[1..argc) (argv[0] is the command's own word). Returns CLI_GO
   when the command should run; EXIT_OK after printing --help to stdout;
   EXIT_USAGE after printing the reason to stderr. Never writes into argv:
   CLI_STRING results and positional arguments point into it. */
int cli_parse(cli_cmd *cmd, int argc, char **argv);

/* --help for cmd, generated from its tables. */
void cli_help(FILE *f, const cli_cmd *cmd);

/* "ggrt NAME: <message>" and "(see 'ggrt NAME --help')" on stderr;
   returns EXIT_USAGE. */
int cli_usage_error(const cli_cmd *cmd, const char *fmt, ...) CLI_PRINTF(2, 3);

/* The name of names[0..n) that word most likely meant (for "did you
   mean"), or NULL: the only one it starts (--out for --output), else the
   nearest by edits (insertions, deletions, changes and swaps of two
   neighbours), at most one edit in three letters and never three
   (--depht: --depth; not --frob: --crop). lib/debug's settings and
   fields (gg_dbg_suggest) follow the same rule. */
const char *cli_suggest(const char *word, const char *const *names, size_t n);

/* How many times option `name` (long name, or the one-letter short name)
   appeared; 0 if it did not or is not in cmd's tables. */
int cli_given(const cli_cmd *cmd, const char *name);

/* The value parsers cli_parse uses, for values that come from elsewhere
   (a CLI_FUNC's sub-fields). Each parses the whole string s or fails: 0 on
   success, else -1 with a reason in why ("'junk' after the number",
   "out of range"). */
int cli_parse_long(const char *s, long lo, long hi, long *out, char *why, size_t whylen);
int cli_parse_num(const char *s, double lo, double hi, double *out, char *why, size_t whylen);

/* ---- the render options every rendering command shares ---- */

/* Which parts of the group a command takes. */
#define CLI_RENDER_SIZE     0x01u /* -s WxH */
#define CLI_RENDER_DEPTH    0x02u /* -d N, --ray-budget N */
#define CLI_RENDER_SAMPLES  0x04u /* -n N */
#define CLI_RENDER_THREADS  0x08u /* -j N */
#define CLI_RENDER_CROP     0x10u /* --crop X0,Y0,X1,Y1 */
#define CLI_RENDER_RULES    0x20u /* --spd, --corners, --force-effects */
#define CLI_RENDER_ACCURACY 0x40u /* --accuracy KNOB=VALUE,... */
/* What decides a pixel's value (a trace of one pixel takes these). */
#define CLI_RENDER_PIXEL                                                                           \
    (CLI_RENDER_SIZE | CLI_RENDER_DEPTH | CLI_RENDER_SAMPLES | CLI_RENDER_RULES |                  \
     CLI_RENDER_ACCURACY)
#define CLI_RENDER_ALL (CLI_RENDER_PIXEL | CLI_RENDER_THREADS | CLI_RENDER_CROP)

#define CLI_RENDER_MAX_OPTS 16

typedef struct cli_render {
    ggRenderOptions opt; /* the result, after cli_render_finish */
    unsigned parts;
    int size[2], depth, budget, samples, threads, crop[4];
    int spd, spd_rules, corners, force;
    cli_opt table[CLI_RENDER_MAX_OPTS]; /* put it in cli_cmd.opts */
} cli_render;

/* Defaults (ggRenderOptionsDefault) and the option table for `parts`. */
void cli_render_init(cli_render *r, unsigned parts);
/* After cli_parse: copy what was given into r->opt (--spd implies pixel
   corners, SPD rules and, unless -d was given, depth 5; --spd-rules is
   the rules alone). */
void cli_render_finish(cli_render *r);
/* Print the given options of `parts` as command-line arguments that
   reproduce r->opt, each preceded by a space ("-s 64x48 --spd"): the
   canonical form of the parsed values, never argv's text. */
void cli_render_print(FILE *f, const cli_render *r, unsigned parts);
/* Two option texts of ggRenderOptionsFormat told apart by their
   settings: "'depth=3', not 'depth=5'", each side only the settings the
   other lacks ("(none)" when it has none), so that a message about two
   long texts names the difference. Into buf (NUL-terminated). */
void cli_render_text_diff(const char *a, const char *b, char *buf, size_t size);
/* The --accuracy option's parser (a CLI_OPT_FUNC; ud is a ggAccuracy *,
   set all or nothing) and its printer (" --accuracy k=v,..." for the
   knobs off their defaults, nothing when all are default). */
int cli_parse_accuracy(void *ud, const char *v, char *why, size_t whylen);
void cli_print_accuracy(FILE *f, const ggAccuracy *a);

#endif
