/* SPDX-License-Identifier: MIT */
/*
** bvh_float.c -- the traversals once more (bvh_trav.h) for the queries of
** single precision (GG_ISECT_FLOAT, include/ggrt/render.h): the plain
** copy's node walk, with leaves that test triangles by the float kernel
** (gg_tri_kernel_f, shape_tri.h). A copy of its own so that the double
** copies carry no test of the precision per element: bvh.c picks it once
** per query.
*/
#include "bvh_int.h"

typedef struct gg_tx {
    int unused;
} gg_tx;

static inline void tx_init(gg_tx *x, const gg_rpre *r)
{
    (void)x, (void)r;
}
#define tx_fill tx_init

/* A triangle block (built for the AVX copy) is found through its first
   slot, as in bvh.c. */
static inline uint32_t tx_first(const gg_geom *g, uint32_t ref)
{
    return ref & GG_TLEAF ? g->tleaves[GG_LEAF_I(ref)].first : GG_LEAF_I(ref);
}

GG_INLINE int tx_closest(const gg_geom *g, const gg_rpre *r, gg_tx *x, uint32_t ref, gg_hit *best)
{
    (void)x;
    return gg_leaf_closest_p(g, r, tx_first(g, ref), GG_LEAF_N(ref), best, 1);
}

GG_INLINE uint32_t tx_any(const gg_geom *g, const gg_rpre *r, gg_tx *x, uint32_t ref, double tmax)
{
    (void)x;
    return gg_leaf_any_p(g, r, tx_first(g, ref), GG_LEAF_N(ref), tmax, 1);
}

GG_INLINE uint32_t tx_shadow(const gg_geom *g, const gg_rpre *r, gg_tx *x, uint32_t ref,
                             double tmax, gg_hit *best, gg_tcol *col)
{
    (void)x;
    return gg_leaf_shadow_p(g, r, tx_first(g, ref), GG_LEAF_N(ref), tmax, best, col, 1);
}

/* The walk also tests slots outside the leaf tests: the occluder cache
   and the fallbacks for rays the float boxes cannot take (every slot).
   In this file those are float too. */
#undef gg_leaf_any
#undef gg_leaf_shadow
#define gg_leaf_any(g, r, first, n, tmax) gg_leaf_any_p(g, r, first, n, tmax, 1)
#define gg_leaf_shadow(g, r, first, n, tmax, best, col)                                            \
    gg_leaf_shadow_p(g, r, first, n, tmax, best, col, 1)

#define GG_TRAV_LINK
#define GG_TRAV_INTERSECT gg_bvh_intersect_float
#define GG_TRAV_OCCLUDER  gg_bvh_occluder_float
#define GG_TRAV_SHADOW    gg_bvh_shadow_float
#include "bvh_trav.inc.h"
