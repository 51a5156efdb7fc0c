/* SPDX-License-Identifier: MIT */
/*
** tile.h -- tiles of one render for several processes or machines
** (ggrt render --tile, ggrt merge; docs/cluster.md).
**
** The cut: N bands of whole rows, tile I (0-based) rows [floor(I H / N),
** floor((I + 1) H / N)) of an H-row image, so bands differ by one row at
** most and N may be at most H. A tile is an OpenEXR file whose data window
** is its band and whose display window is the whole image, with the
** manifest below as string attributes.
*/
#ifndef GG_CLI_TILE_H
#define GG_CLI_TILE_H

#include "common/cli.h"

#define TILE_MAX_LIST 4096 /* indices one --tiles may list */

/* The manifest's attribute names. */
#define TILE_A_VERSION "ggrt.version"   /* ggVersion() */
#define TILE_A_HASH    "ggrt.sceneHash" /* "fnv1a64:HEX" of the scene file's bytes */
#define TILE_A_SCENE   "ggrt.scene"     /* the scene path as given (not compared) */
#define TILE_A_OPTIONS "ggrt.options"   /* ggRenderOptionsFormat, size explicit */
#define TILE_A_CUT     "ggrt.cut"       /* "rows N" */
#define TILE_A_TILE    "ggrt.tile"      /* "I" */

/* Which tiles a process renders: idx[0..count) of n. */
typedef struct tile_list {
    int n, count;
    int idx[TILE_MAX_LIST];
} tile_list;

/* CLI_FUNC parsers: --tile I/N (one tile) and --tiles I,J,K/N (several,
   ranges A-B allowed). ud is a tile_list. */
int tile_parse_one(void *ud, const char *value, char *why, size_t whylen);
int tile_parse_list(void *ud, const char *value, char *why, size_t whylen);

/* Rows [*y0, *y1) of tile i of n in an image of h rows. */
void tile_rows(int i, int n, int h, int *y0, int *y1);

/* The output path of tile i: pattern with its "%d" replaced by i (a
   pattern without one is used as it is). 0, or -1 if it does not fit. */
int tile_path(const char *pattern, int i, char *buf, size_t size);

/* "fnv1a64:%016llx" of the file's bytes into buf (at least 32 bytes).
   0, or -1 with errno set. */
int tile_hash_file(const char *path, char *buf, size_t size);

/* Render the listed tiles of the scene, loaded once, each written as
   a tile file (tile.c). opt is the render as given (no crop); quiet drops
   the per-tile lines. Returns an exit code. */
int tile_render(ggScene *scene, const char *scene_path, const ggRenderOptions *opt,
                const tile_list *tl, const char *out, int quiet);

#endif
