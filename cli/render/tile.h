/* SPDX-License-Identifier: MIT */
/*
** tile.h -- tiles of one render for several processes or machines
** (ggrt render --tile, ggrt merge; docs/cluster.md).
**
** The cut: N bands of whole rows. The equal cut ("rows N") gives tile I
** (0-based) rows [floor(I H / N), floor((I + 1) H / N)) of an H-row
** image, so bands differ by one row at most and N may be at most H; a
** plan's cut (ggrt plan, "plan Y0,Y1,...,YN") gives tile I rows [YI,
** YI+1), bands of about equal cost. A tile is an OpenEXR file whose data window
** is its band and whose display window is the whole image, with the
** manifest below as string attributes.
*/
#ifndef GG_CLI_TILE_H
#define GG_CLI_TILE_H

#include "common/cli.h"

#define TILE_MAX_LIST 4096 /* indices one --tiles may list */
#define TILE_MAX_PLAN 1024 /* tiles a plan may cut */

/* The manifest's attribute names. */
#define TILE_A_VERSION "ggrt.version"   /* ggVersion() */
#define TILE_A_BUILD   "ggrt.buildId"   /* ggBuildId() */
#define TILE_A_HASH    "ggrt.sceneHash" /* "fnv1a64:HEX" of the scene file's bytes */
#define TILE_A_SCENE   "ggrt.scene"     /* the scene path as given (not compared) */
#define TILE_A_OPTIONS "ggrt.options"   /* ggRenderOptionsFormat, size explicit */
#define TILE_A_CUT     "ggrt.cut"       /* "rows N" or "plan Y0,Y1,...,YN" */
#define TILE_A_TILE    "ggrt.tile"      /* "I" */

/* Which tiles a process renders: idx[0..count) of n. */
typedef struct tile_list {
    int n, count;
    int idx[TILE_MAX_LIST];
} tile_list;

/* CLI_FUNC parsers: --tile I/N (one tile) and --tiles I,J,K/N (several,
   ranges A-B allowed). ud is a tile_list. Without "/N" (a plan gives N)
   n is 0 and the indices are checked by tile_list_check. */
int tile_parse_one(void *ud, const char *value, char *why, size_t whylen);
int tile_parse_list(void *ud, const char *value, char *why, size_t whylen);

/* With n 0 (no "/N"): N from a plan, n; every index must be below it.
   0, or -1 with the reason. */
int tile_list_check(tile_list *tl, int n, char *why, size_t whylen);

/* Rows [*y0, *y1) of tile i of n equal bands of an image of h rows. */
void tile_rows(int i, int n, int h, int *y0, int *y1);

/* A cut: n tiles, equal bands (y NULL) or a plan's n + 1 row boundaries
   (y[0] 0, strictly increasing, y[n] the height). */
typedef struct tile_cut {
    int n;
    int *y;
} tile_cut;

/* Rows [*y0, *y1) of tile i of the cut in an image of h rows. */
void tile_cut_rows(const tile_cut *c, int i, int h, int *y0, int *y1);
/* The manifest's ggrt.cut: "rows N" or "plan Y0,Y1,...,YN". 0, or -1 if
   it does not fit in size bytes. */
int tile_cut_format(const tile_cut *c, char *buf, size_t size);
/* A row number or tile index as ggrt writes them: decimal digits and
   nothing else (strtol would also take spaces and a sign), *end after
   the last. -1 if p does not start with a digit; a number past INT_MAX
   reads as INT_MAX. */
long tile_number(const char *p, const char **end);
/* Read a ggrt.cut for an image of h rows into *c (c->y allocated, to be
   freed with tile_cut_free). 0, or -1 with the reason. */
int tile_cut_parse(const char *text, int h, tile_cut *c, char *why, size_t whylen);
void tile_cut_free(tile_cut *c);

/* The options a tile's manifest (and a plan) records: opt as the render
   takes it (ggRenderOptionsResolve: size, depth, samples and ray budget
   explicit, so -d 5 and the default 5 agree), neither crop nor threads,
   which do not change a pixel, as ggRenderOptionsFormat writes them. *w and *h get the
   size. 0, or -1 if they do not fit in size bytes. */
int tile_options(const ggScene *scene, const ggRenderOptions *opt, int *w, int *h, char *buf,
                 size_t size);

/* A plan file written by ggrt plan (plan.c, docs/cluster.md). */
typedef struct tile_plan {
    char build[64], hash[32], options[2048];
    int width, height;
    tile_cut cut;
} tile_plan;

/* Read and check a plan file (a JSON object: "ggrt_plan", "sceneHash",
   "options", "size", "rows", "buildId"). Prints the reason ("ggrt CMD: FILE: ...")
   and returns an exit code; on success p->cut.y is allocated. */
int tile_plan_read(const char *path, tile_plan *p);

/* The plan must be of this ggrt build (ggBuildId), for this scene file's
   hash, these manifest options and a w x h image: otherwise print why
   (naming the plan file) and return EXIT_INPUT. */
int tile_plan_match(const tile_plan *p, const char *plan_path, const char *hash,
                    const char *options, int w, int h);

/* The output path of tile i: pattern with its "%d" replaced by i (a
   pattern without one is used as it is). 0, or -1 if it does not fit. */
int tile_path(const char *pattern, int i, char *buf, size_t size);

/* 1 if paths a and b name the same file (one given twice to merge). */
int tile_same_file(const char *a, const char *b);

/* "fnv1a64:%016llx" of the file's bytes into buf (at least 32 bytes).
   0, or -1 with errno set. */
int tile_hash_file(const char *path, char *buf, size_t size);

/* One tile's band and manifest, for the commands that scan a tile of an
   image (find, check, diff --tile). */
typedef struct tile_band {
    int index, n, w, h, y0, y1;
    char hash[32], options[2048], cut[TILE_MAX_PLAN * 8 + 16];
} tile_band;

/* The band of tl's one tile (equal bands, or the plan's, checked as by
   render --plan) for the scene and options. Prints why and returns an
   exit code. */
int tile_band_init(tile_band *b, ggScene *scene, const char *scene_path,
                   const ggRenderOptions *opt, tile_list *tl, const char *plan_path);

/* Render the listed tiles of the scene, loaded once, each written as
   a tile file (tile.c) and followed by the warnings a whole render gives
   (warn.h). ro is the render as given (no crop); quiet drops the per-tile
   lines; plan_path a plan file whose cut to use (NULL: equal bands).
   Returns an exit code. */
int tile_render(ggScene *scene, const char *scene_path, const cli_render *ro, tile_list *tl,
                const char *out, int quiet, const char *plan_path);

/* ggrt merge --reports: the JSON reports of find, check and diff --tile
   joined into the whole image's (report_merge.c). Exit code. */
int merge_reports(const char **files, int nfiles, const char *out, int quiet);

#endif
