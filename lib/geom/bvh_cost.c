/* SPDX-License-Identifier: MIT */
/*
** bvh_cost.c -- the closest-hit traversal once more (bvh_trav.inc.h with
** GG_TRAV_COST), counting the nodes and elements it tests: the traversal
** cost that the ray-tree recorder keeps per ray (ggTraceNode.nodes,
** .prims). Its leaves are the plain copy's (bvh.c); the AVX copy's give
** the same hits (bvh_avx.c), so the walk, and the counts, are the same
** on one tree. The tree itself is built for the copy the CPU (or
** GGRT_ISA) chose, so one ray's counts under GGRT_ISA=sse2 differ from
** the AVX copies' (ggrt(1), ENVIRONMENT); its hits do not.
*/
#include "bvh_int.h"

/* The plain copy's hooks (bvh_hooks.h) in both precisions
   (GG_ISECT_FLOAT: bvh_float.c's leaves), by the query's: this copy
   serves only the recorder. */
#define GG_TX_FLOAT (r->opt->isect == GG_ISECT_FLOAT)
#define GG_TRAV_COST
#define GG_INC_NAME(f) f##_cost
#define GG_INC_LINK    static
#include "bvh_hooks.h"
#include "bvh_trav.inc.h"

int gg_geom_intersect_cost(const gg_geom *g, const gg_rayq *q, gg_hit *hit, gg_trav_cost *cost)
{
    if (q->inside != UINT32_MAX) {
        cost->prims++;
        if (gg_geom_inside_hit(g, q, q->skip_flags, hit) > 0) return 1;
    }
    return bvh_intersect_cost(g, q, hit, cost);
}
