/* SPDX-License-Identifier: MIT */
/*
** trace_view.h -- a recorded ray tree and its writers: text, JSON, SVG, OBJ.
*/
#ifndef GG_CLI_TRACE_VIEW_H
#define GG_CLI_TRACE_VIEW_H

#include "common/cli.h"

typedef struct trace_view {
    ggScene *scene;
    const ggTrace *trace;
    const ggRenderOptions *opt;
    const char *path;
    int x, y, sample;
    ggColor pixel;
    ggRayStats stats;
    const ggLedger *ledger; /* when every sample is recorded, else NULL */
    int hide_numeric;       /* text: leave out each hit's numeric state */
} trace_view;

/* Text and JSON (trace_text.c). */
void trace_print_text(FILE *f, const trace_view *v, int utf8);
void trace_print_json(FILE *f, const trace_view *v);
/* SVG (trace_svg.c). Write to f; the caller checks f for errors
   (cli_out_close). With camera, a camera view panel: the image
   trace_camera_render made (NULL: its frame only), embedded as a PNG
   through the file png_tmp (written, then removed: beside the output, in
   the folder checked for it). Without (ggrt serve's views), the top and
   side views alone. GG_OK, or the error of png_tmp (in err). */
int trace_write_svg_views(FILE *f, const trace_view *v, int camera, const ggImage *img,
                          const char *png_tmp, ggError *err);
/* The camera view's image: v's scene with v's options at most 420 pixels
   a side, one sample, no crop; progress and ud as ggRender takes them (a
   deep scene's thumbnail can take seconds). ggRender's result. */
int trace_camera_render(const trace_view *v, ggProgressFn progress, void *ud, ggImage **img,
                        ggError *err);
/* OBJ lines (trace_obj.c); the same error rule as SVG. */
void trace_write_obj(FILE *f, const trace_view *v);
/* The scene's objects as OBJ faces, one OBJ object each ("object3_
   sphere_line12"), to open beside the rays or paths in Blender or
   MeshLab: spheres and cones tessellated (32 segments, fewer in a scene
   of thousands), rects and
   polygons as their face, mesh parts as their triangles, implicit
   surfaces as ggSceneObjectTriangulate's (64 cells along the box's
   longest side; fewer, or none, with a warning, past an equal share of
   what CLI_SCENE_OBJ_TRIANGLES the surfaces before left). path names the
   scene in a comment and the warnings. Stops at a cancel signal: returns
   it (cli_cancelled; the file is then incomplete), else 0. */
int trace_write_scene_obj(FILE *f, const ggScene *s, const char *path);

/* The ledger (trace_debug.c): terms by share, with the rays that carried
   them; at most `max` terms listed (0: all), the rest summed. */
void trace_print_ledger(FILE *f, const trace_view *v, size_t max);
/* Two trees of one pixel side by side, aligned ray by ray, the first
   divergence marked (trace_debug.c). */
void trace_print_diff(FILE *f, const trace_view *a, const trace_view *b, const char *name_a,
                      const char *name_b);

/* The ledger terms whose paths an expression matches (matched: one byte
   per term), with their events, as text or JSON (trace_debug.c). */
void trace_print_paths(FILE *f, const trace_view *v, const char *expr, const unsigned char *matched,
                       const ggPathSummary *sum);
void trace_print_paths_json(FILE *f, const trace_view *v, const char *expr,
                            const unsigned char *matched, const ggPathSummary *sum);

/* The children of a tree's nodes, found in one pass (trace_text.c): node
   i's are kid[first[i]] .. kid[first[i + 1] - 1], in order, the later
   nodes whose parent is i. trace_kids_make: 0, or -1 without memory
   (first and kid NULL). */
typedef struct trace_kids {
    int *first, *kid;
} trace_kids;
int trace_kids_make(trace_kids *k, const ggTrace *t);
void trace_kids_free(trace_kids *k);
/* Children of node i, in order: fills kids (up to max), returns count;
   from k, or where k has no index (NULL, or made without memory) by a
   scan of the later nodes, slower but the same. */
int trace_children(const trace_kids *k, const ggTrace *t, int i, int *kids, int max);

#endif
