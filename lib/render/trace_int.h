/* SPDX-License-Identifier: MIT */
/*
** trace_int.h -- the ray-tree recorder's insides (private to lib/render:
** docs/internals.md, "Headers").
*/
#ifndef GG_TRACE_INT_H
#define GG_TRACE_INT_H

#include "core.h"

struct ggTrace {
    const ggAllocator *alloc;
    ggAllocator alloc_copy;
    ggTraceNode *nodes;
    size_t nnodes, cap_nodes;
    ggTraceLight *lights;
    size_t nlights, cap_lights;
    int status; /* GG_ERROR_NOMEM once a record could not be stored */
    int sample; /* the sample being recorded */
};

void gg_trace_clear(ggTrace *t);
/* Append a zeroed node / light record; -1 (and status NOMEM) on failure. */
int gg_trace_add_node(ggTrace *t);
int gg_trace_add_light(ggTrace *t);

#endif
