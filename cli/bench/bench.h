/* SPDX-License-Identifier: MIT */
/*
** bench.h -- the benchmark harness behind `ggrt bench` (cli/bench/), kept
** apart from the user commands in cli/.
*/
#ifndef GG_BENCH_H
#define GG_BENCH_H

#include "common/cli.h"

#define BENCH_MAX_ARGS 64
/* The plural's "s" of a count: "1 thread", "2 threads". */
#define BENCH_S(n) ((n) == 1 ? "" : "s")

typedef struct bench_opts {
    int size, threads, runs, pov;
    const char *spd_dir, *pov_dir, *scenes, *out_dir;
    const char *embree;  /* spd: the embree-whitted anchor binary, or NULL */
    const char *knobs;   /* accuracy: comma-separated knob names, or NULL (all) */
    ggAccuracy accuracy; /* spd: ggrt's accuracy knobs (--accuracy) */
    int has_accuracy;
    const char *args[BENCH_MAX_ARGS]; /* scene files given on the command line */
    int nargs;
} bench_opts;

/* Median of v[0..n) (sorts v). */
double bench_median(double *v, int n);

/* Run fn(arg, out) in a child process; out (outsize bytes) comes back
   through a pipe and *peak_mb receives the child's peak resident memory.
   Returns 0 on success. */
typedef int (*bench_fn)(void *arg, void *out);
int bench_in_child(bench_fn fn, void *arg, void *out, size_t outsize, double *peak_mb);

/* Is name in the comma-separated list (NULL list: everything)? */
int bench_selected(const char *list, const char *name);

/* Two lines under a table's title: the CPU (its model name, whether it
   has AVX2 and AVX-512F) and the copy of the walks ggrt runs on it
   (ggSceneTraversal). */
void bench_print_machine(void);

/* The name a table row gives scene file `path`: its base name. */
const char *bench_row_name(const char *path);

/* The width of a table's scene column: 11 (the SPD names), or the
   longest row name of bo's scene files. */
int bench_name_width(const bench_opts *bo);

/* The seven SPD scenes the timing tables run (spd, counts, scaling,
   rays, limit), by name in --spd DIR; and the example scenes of bench
   effects (relative to examples/scenes). */
#define BENCH_NSPD 7
extern const char *const bench_spd_scenes[];
#define BENCH_NEFFECTS 10
extern const char *const bench_effects_scenes[];

/* The knob names of bench accuracy's rows (--knobs), each once, into
   names[0..max); returns how many. */
int bench_knob_names(const char **names, int max);

/* The first name of the comma-separated list that is not one of
   names[0..n) (an empty one counts), copied into bad (size badsize);
   0 when all are. */
int bench_unknown(const char *list, const char *const *names, int n, char *bad, size_t badsize);

/* The benchmarks; each returns an exit code. */
int bench_spd(const bench_opts *bo);
int bench_counts(const bench_opts *bo);
int bench_effects(const bench_opts *bo);
int bench_accuracy(const bench_opts *bo);
int bench_scaling(const bench_opts *bo);
int bench_rays(const bench_opts *bo);
int bench_limit(const bench_opts *bo);

#endif
