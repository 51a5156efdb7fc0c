/* SPDX-License-Identifier: MIT */
/*
** debug.h -- what the debugger's commands (find, check, diff, trace
** --ledger/--diff) share: progress and cancellation, replay
** commands, and their JSON documents (written with common/json.h, to a
** FILE* so that ggrt serve writes the same documents into memory; the
** schemas are in docs/debugging.md).
*/
#ifndef GG_CLI_DEBUG_H
#define GG_CLI_DEBUG_H

#include "common/cli.h"
#include "common/json.h"
#include "render/tile.h"

/* A progress callback for ggFind, ggCheck, ggDiff: a bar on a terminal
   (ud: a dbg_progress_state, NULL for none) and the way a signal cancels. */
typedef struct dbg_progress_state {
    const char *what;
    cli_bar bar;
} dbg_progress_state;
void dbg_progress_begin(dbg_progress_state *p, const char *what, int quiet);
int dbg_progress(void *ud, long done, long total);
void dbg_progress_end(dbg_progress_state *p);

/* diff and trace --diff of one scene: a warning when the two sides
   render with the same options (nothing can differ), naming -a, which
   sets both, beside --a and --b, which set one each. */
void dbg_warn_same_sides(int nscenes, const ggRenderOptions *oa, const ggRenderOptions *ob);

/* "ggrt trace SCENE [SCENE_B] <the pixel options of ro> --pixel X,Y" and
   then the words of `extra` (NULL-terminated, may be NULL), each quoted
   for a shell. No newline. */
void dbg_replay(FILE *f, const char *scene, const char *scene_b, const cli_render *ro, int x, int y,
                const char *const *extra);

/* ggrt check --aov-sum LAYERS.exr [SCENE] (aov_sum.c): the exit status. */
int aov_sum_check(const char *exr, const char *scene);

/* Print a predicate's parse error ("ggrt CMD: --where:L:C: ...") with the line
   of text and a caret under the column; returns EXIT_USAGE. */
int dbg_predicate_error(const char *cmd, const char *text, const ggError *err);
/* The same for the expression of option --OPTION ("where", "path"). */
int dbg_expr_error(const char *cmd, const char *option, const char *text, const ggError *err);

/* "eye > refract > tir" for node i: the kinds from its root down. */
void dbg_path(char *buf, size_t n, const ggTrace *t, int i);

/* Write a w x h byte map as a PNG or EXR image through the CLI's output
   rules: `colour` gives the RGB of each value. Returns an exit code. */
int dbg_write_map(const char *cmd, const char *path, const unsigned char *map, int w, int h,
                  const float colour[][3], int ncolours);

/* The first divergence of two trees in words ("ray #3 (eye > refract):
   a hits object #2, b leaves the scene"). */
void dbg_divergence_text(char *buf, size_t n, const ggTrace *ta, const ggTrace *tb,
                         const ggDivergence *d);

/* ---- matching paths written out (paths_out.c) ---- */

/* --paths-jsonl FILE: one JSON object a line, a path each: pixel, events
   (as ggPathFormat writes them), term, node, light, points (eye to light,
   ggPathPoints), weights (one per point), contribution (the term's value)
   and share. --paths-obj FILE: each path an object with its vertices and
   one polyline (l). Both written whole or not at all (cli_out). */
typedef struct dbg_paths_out {
    const char *cmd;
    cli_out jsonl, obj;
    int have_jsonl, have_obj;
    long paths;    /* paths written */
    long vertices; /* OBJ vertices written */
    uint64_t max;  /* --paths-max: bytes of both files at most, 0 no limit */
} dbg_paths_out;
/* --paths-max SIZE (find, trace): the bytes the two files may take
   together, a whole number with K, M or G (powers of 1024), 0 for no
   limit; default DBG_PATHS_MAX (4 GiB: a whole image of default.nff with
   every path, 'C.*', is 570 MB; a pixel of nested glass can be 14 MB).
   dbg_paths_max_parse is its CLI_OPT_FUNC (ud: a uint64_t). */
#define DBG_PATHS_MAX ((uint64_t)4 << 30)
#define DBG_PATHS_MAX_HELP                                                                         \
    "--path: the two files' bytes at most, with K, M or G\n"                                       \
    "(default 4G; 0: no limit); past it nothing is written"
int dbg_paths_max_parse(void *ud, const char *value, char *why, size_t whylen);
/* Before the work: the outputs can be written (cli_check_output); NULL
   names are skipped. Returns 0 or an exit code. */
int dbg_paths_check(const char *cmd, const char *jsonl, const char *obj);
int dbg_paths_open(dbg_paths_out *o, const char *cmd, const char *jsonl, const char *obj,
                   uint64_t max);
/* The paths e matches of the pixel (x, y) of value px, whose every sample
   tr holds. Past o->max bytes it says so (exit 2) for the caller to
   abandon the files. Returns an exit code. */
int dbg_paths_pixel(dbg_paths_out *o, const ggPathExpr *e, const ggTrace *tr, int x, int y,
                    ggColor px);
/* Close and rename into place; returns an exit code. abandon: remove the
   temporary files instead. */
int dbg_paths_close(dbg_paths_out *o);
void dbg_paths_abandon(dbg_paths_out *o);

/* ---- JSON ---- */
void json_find(FILE *f, const char *scene, const ggRenderOptions *opt, const char *where,
               const char *path,
               const ggFindResult *r);
void json_check(FILE *f, const char *scene, const ggRenderOptions *opt, const ggCheckResult *r);
void json_diff(FILE *f, const char *scene_a, const char *scene_b, const ggRenderOptions *oa,
               const ggRenderOptions *ob, const ggDiffResult *r);
/* The "ledger" member of a trace document (without the key); numbers
   as json_num_text. */
void json_ledger(FILE *f, const ggTrace *t, const ggLedger *l);
/* A divergence as an object (without a key). */
void json_divergence(FILE *f, const ggDivergence *d);

/* ---- --tile I/N and --plan FILE of find, check and diff (dbg_tile.c) ---- */
typedef struct dbg_tile {
    tile_list tl; /* tl.count 0: no --tile */
    const char *plan;
    tile_band band;
    char *text; /* the report, before its manifest */
    size_t len;
} dbg_tile;

#define DBG_TILE_OPTS(t)                                                                           \
    CLI_OPT_FUNC(0, "tile", tile_parse_one, &(t)->tl, "I/N",                                       \
                 "scan only tile I of N bands of rows (or of --plan's\n"                           \
                 "cut) and write its JSON report (-f json), with a\n"                              \
                 "manifest, for ggrt merge --reports (docs/cluster.md)"),                          \
        CLI_OPT_STRING(0, "plan", &(t)->plan, "FILE",                                              \
                       "with --tile: the cut of a plan from ggrt plan")

/* After parsing: --tile needs -f json (format 1) and no image outputs
   (images: any was given). CLI_GO or a usage error. */
int dbg_tile_check(const cli_cmd *cmd, const dbg_tile *t, int format, int images);
/* With --tile: the band, and opt's crop window set to it. Exit code. */
int dbg_tile_begin(dbg_tile *t, ggScene *scene, const char *scene_path, ggRenderOptions *opt);
/* The options the report names: opt without the band's crop. */
void dbg_tile_options(const dbg_tile *t, const ggRenderOptions *opt, ggRenderOptions *out);
/* Where the JSON report goes: stdout, or with --tile a buffer that
   dbg_tile_close writes to stdout with the manifest ("tile": version,
   buildId, sceneHash, options, cut, index, rows, params: what else must agree)
   as its last member. Exit code. */
FILE *dbg_tile_open(dbg_tile *t);
int dbg_tile_close(dbg_tile *t, FILE *f, const char *params);

#endif
