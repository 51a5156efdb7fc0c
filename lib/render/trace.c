/* SPDX-License-Identifier: MIT */
/*
** trace.c -- storage for recorded ray trees, and the names of their parts.
*/
#include "trace_int.h"

#include <string.h>

GG_API ggTrace *ggTraceCreate(const ggAllocator *alloc)
{
    ggTrace *t = gg_mem_calloc(alloc, 1, sizeof *t);
    if (!t) return NULL;
    if (alloc) {
        t->alloc_copy = *alloc;
        t->alloc = &t->alloc_copy;
    }
    return t;
}

GG_API void ggTraceFree(ggTrace *t)
{
    if (!t) return;
    gg_mem_free(t->alloc, t->nodes);
    gg_mem_free(t->alloc, t->lights);
    gg_mem_free(t->alloc, t);
}

void gg_trace_clear(ggTrace *t)
{
    t->nnodes = 0;
    t->nlights = 0;
    t->status = GG_OK;
}

int gg_trace_add_node(ggTrace *t)
{
    if (gg_mem_grow(t->alloc, (void **)&t->nodes, &t->cap_nodes, t->nnodes + 1, sizeof *t->nodes)) {
        t->status = GG_ERROR_NOMEM;
        return -1;
    }
    memset(&t->nodes[t->nnodes], 0, sizeof *t->nodes);
    return (int)t->nnodes++;
}

int gg_trace_add_light(ggTrace *t)
{
    if (gg_mem_grow(t->alloc, (void **)&t->lights, &t->cap_lights, t->nlights + 1,
                    sizeof *t->lights)) {
        t->status = GG_ERROR_NOMEM;
        return -1;
    }
    memset(&t->lights[t->nlights], 0, sizeof *t->lights);
    return (int)t->nlights++;
}

GG_API size_t ggTraceNodeCount(const ggTrace *t)
{
    return t ? t->nnodes : 0;
}
GG_API const ggTraceNode *ggTraceGetNode(const ggTrace *t, size_t i)
{
    return t && i < t->nnodes ? &t->nodes[i] : NULL;
}
GG_API size_t ggTraceLightCount(const ggTrace *t)
{
    return t ? t->nlights : 0;
}
GG_API const ggTraceLight *ggTraceGetLight(const ggTrace *t, size_t i)
{
    return t && i < t->nlights ? &t->lights[i] : NULL;
}

GG_API const char *ggRayKindName(int kind)
{
    static const char *const n[] = {"eye", "reflect", "refract", "tir"};
    return kind >= 0 && kind < 4 ? n[kind] : "?";
}

GG_API const char *ggStopName(int stop)
{
    static const char *const n[] = {"none", "miss", "depth", "matte", "budget"};
    return stop >= 0 && stop < 5 ? n[stop] : "?";
}

GG_API const char *ggShadowName(int verdict)
{
    static const char *const n[] = {"visible", "blocked", "attenuated", "facing-away"};
    return verdict >= 0 && verdict < 4 ? n[verdict] : "?";
}
