/* SPDX-License-Identifier: MIT */
/*
** tree.c -- what the debugger derives from a recorded ray tree: how many
** trees (samples) it holds and each ray's weight in the pixel.
*/
#include "debug_int.h"

int gg_dbg_roots(const ggTrace *t)
{
    size_t i, n = ggTraceNodeCount(t);
    int k = 0;
    for (i = 0; i < n; i++) k += ggTraceGetNode(t, i)->parent < 0;
    return k;
}

/* The pixel is the mean of its trees' colours (pixel_center and the
   corner average in lib/render/render.c), a node's colour is its
   absorption times (its own terms + sum of weight * child colour)
   (trace_fx and shade_hit in lib/render/shade.c): so d pixel / d colour
   multiplies down the tree. Parents come before their children. */
void gg_dbg_weights(const ggTrace *t, ggColor *w)
{
    size_t i, n = ggTraceNodeCount(t);
    int roots = gg_dbg_roots(t);
    double r = 1.0 / (roots > 0 ? roots : 1);
    for (i = 0; i < n; i++) {
        const ggTraceNode *nd = ggTraceGetNode(t, i);
        if (nd->parent < 0 || (size_t)nd->parent >= i) {
            w[i].r = w[i].g = w[i].b = r;
        } else {
            const ggTraceNode *up = ggTraceGetNode(t, (size_t)nd->parent);
            const ggColor *wp = &w[nd->parent];
            w[i].r = wp->r * up->absorption.r * nd->weight.r;
            w[i].g = wp->g * up->absorption.g * nd->weight.g;
            w[i].b = wp->b * up->absorption.b * nd->weight.b;
        }
    }
}

int gg_dbg_buf_weights(gg_dbg_buf *b, const ggAllocator *a, const ggTrace *t)
{
    size_t n = ggTraceNodeCount(t);
    if (gg_mem_grow(a, (void **)&b->w, &b->cap, n ? n : 1, sizeof *b->w)) return -1;
    gg_dbg_weights(t, b->w);
    return 0;
}
