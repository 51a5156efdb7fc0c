/* SPDX-License-Identifier: MIT */
/*
** bvh_cost.c -- the closest-hit traversal once more (bvh_trav.h with
** GG_TRAV_COST), counting the nodes and elements it tests: the traversal
** cost that the ray-tree recorder keeps per ray (ggTraceNode.nodes,
** .prims). Its leaves are the plain copy's (bvh.c); the AVX copy's give
** the same hits (bvh_avx.c), so the walk, and the counts, are the same.
*/
#include "bvh_int.h"

typedef struct gg_tx {
    int unused;
} gg_tx;

static inline void tx_init(gg_tx *x, const gg_rpre *r)
{
    (void)x, (void)r;
}

static inline uint32_t tx_first(const gg_geom *g, uint32_t ref)
{
    return ref & GG_TLEAF ? g->tleaves[GG_LEAF_I(ref)].first : GG_LEAF_I(ref);
}

/* Both precisions (GG_ISECT_FLOAT: bvh_float.c's leaves), by the
   query's: this copy serves only the recorder. */
GG_INLINE int tx_closest(const gg_geom *g, const gg_rpre *r, gg_tx *x, uint32_t ref, gg_hit *best)
{
    (void)x;
    if (r->opt->isect == GG_ISECT_FLOAT)
        return gg_leaf_closest_p(g, r, tx_first(g, ref), GG_LEAF_N(ref), best, 1);
    return gg_leaf_closest(g, r, tx_first(g, ref), GG_LEAF_N(ref), best);
}

#define GG_TRAV_COST
#define GG_TRAV_LINK      static
#define GG_TRAV_INTERSECT intersect_cost
#include "bvh_trav.inc.h"

int gg_geom_intersect_cost(const gg_geom *g, const gg_rayq *q, gg_hit *hit, gg_trav_cost *cost)
{
    if (q->inside != UINT32_MAX) {
        cost->prims++;
        if (gg_geom_inside_hit(g, q, q->skip_flags, hit) > 0) return 1;
    }
    return intersect_cost(g, q, hit, cost);
}
