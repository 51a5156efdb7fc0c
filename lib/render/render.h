/* SPDX-License-Identifier: MIT */
/*
** render.h -- what the render layer offers the layers above it
** (internal): a tracer that traces single pixels of one render setting
** from many threads, for the image-level debugger (lib/debug).
*/
#ifndef GG_RENDER_H
#define GG_RENDER_H

#include "core.h"

/* One render setting (scene + options, resolved once), ready to trace any
   pixel of it exactly as ggRender computes it. */
typedef struct gg_tracer gg_tracer;

/* Resolve opt (NULL: defaults) for scene s, preparing s if needed (which
   writes into it: not thread-safe), as ggRender does. The tracer keeps a
   pointer to s, which must outlive it and not change meanwhile. */
int gg_tracer_create(ggScene *s, const ggRenderOptions *opt, gg_tracer **out, ggError *err);
void gg_tracer_free(gg_tracer *t);

typedef struct gg_tracer_desc {
    int width, height;     /* the image */
    int x0, y0, x1, y1;    /* the crop window (the whole image by default) */
    int samples;           /* trees recorded per pixel: samples, or 4 corners */
    int max_depth;         /* resolved depth limit */
    int threads;           /* resolved worker threads */
    ggProgressFn progress; /* the options' callback, or NULL */
    void *progress_ud;
} gg_tracer_desc;
void gg_tracer_info(const gg_tracer *t, gg_tracer_desc *d);

/* Pixel (x, y) (inside the image), bit for bit what ggRender writes. With
   rec, every sample's tree is recorded into it (cleared first; check
   gg_tracer_status for NOMEM); rec NULL traces without recording. st (may
   be NULL) is added to. t is only read: any number of threads may trace
   with one tracer at once, each with its own recorder. */
ggColor gg_tracer_pixel(const gg_tracer *t, int x, int y, ggTrace *rec, ggRayStats *st);
/* GG_OK, or GG_ERROR_NOMEM when a record of the last trace was lost. */
int gg_tracer_status(const ggTrace *rec);
/* 1 when no eye ray of the pixels [x0, x1) x [y0, y1) (image
   coordinates, inside the crop window) can hit anything, so each of them
   is the miss of its first one but for the direction of its rays: the
   renderer's empty-tile test (tile_empty in render.c). */
int gg_tracer_empty(const gg_tracer *t, int x0, int y0, int x1, int y1);

/* ggRender with path layers l (lpe.h), for the debugger: the image into
   *out and, per layer and pixel of opt's window, the sum in double of the
   terms the layer takes, r + g + b (sums: one double per pixel, layer
   after layer, row by row) and whether it took a non-zero term (hits: 1
   or 0, one byte per pixel, the same order); outside the window both are
   left as they are. In the order the ledger adds a pixel's terms (the
   order its rays are cast), so for one sample per pixel at its centre
   the sums are ggPathMatch's values' r + g + b bit for bit (as gg_path_run
   adds them for a share); GG_ERROR_UNSUPPORTED
   for more samples or pixel corners. */
int gg_render_layer_sums(ggScene *s, const ggRenderOptions *opt, const ggPathLayers *l,
                         double *sums, unsigned char *hits, ggImage **out, ggRayStats *stats,
                         ggError *err);

#endif
