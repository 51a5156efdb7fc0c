/* SPDX-License-Identifier: MIT */
/*
** trace_out.h -- writing a recorded ray tree: text, JSON, SVG, OBJ.
*/
#ifndef GG_TRACE_OUT_H
#define GG_TRACE_OUT_H

#include "cli.h"

typedef struct trace_view {
    ggScene *scene;
    const ggTrace *trace;
    const ggRenderOptions *opt;
    const char *path;
    int x, y, sample;
    ggColor pixel;
    ggRayStats stats;
} trace_view;

void trace_print_text(FILE *f, const trace_view *v, int utf8);
void trace_print_json(FILE *f, const trace_view *v);
int trace_write_svg(const char *path, const trace_view *v, ggError *err);
/* The SVG to a stream; camera: also the camera view (renders the scene
   small, through a temporary PNG file). GG_ERROR_INVALID if the scene is
   not prepared. */
int trace_print_svg(FILE *f, const trace_view *v, int camera);
int trace_write_obj(const char *path, const trace_view *v, ggError *err);

/* Children of node i, in order: fills kids (up to max), returns count. */
int trace_children(const ggTrace *t, int i, int *kids, int max);

#endif
