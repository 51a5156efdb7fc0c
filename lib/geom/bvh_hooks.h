/* SPDX-License-Identifier: MIT */
/*
** bvh_hooks.h -- the leaf hooks of bvh_trav.inc.h for the copies whose
** leaves are the scalar loops of geom_leaf.h (internal): the plain copy
** (bvh.c), the single-precision one (bvh_float.c) and the recorder's
** counting one (bvh_cost.c). They keep no per-ray leaf state (tx_init
** and tx_fill do nothing) and find a triangle block (built for the AVX
** copy, when a test runs both copies on one tree) through its first
** slot. The includer defines GG_TX_FLOAT first: the precision argument
** of the geom_leaf.h loops (0 double, 1 float, or an expression of r).
** The AVX copy has hooks of its own (bvh_avx.c).
*/
#ifndef GG_BVH_HOOKS_H
#define GG_BVH_HOOKS_H

#include "bvh_int.h"

#ifndef GG_TX_FLOAT
#error "define GG_TX_FLOAT before including bvh_hooks.h"
#endif

typedef struct gg_tx {
    int unused;
} gg_tx;

static inline void tx_init(gg_tx *x, const gg_rpre *r)
{
    (void)x, (void)r;
}

static inline void tx_fill(gg_tx *x, const gg_rpre *r)
{
    (void)x, (void)r;
}

static inline uint32_t tx_first(const gg_geom *g, uint32_t ref)
{
    return ref & GG_TLEAF ? g->tleaves[GG_LEAF_I(ref)].first : GG_LEAF_I(ref);
}

GG_INLINE int tx_closest(const gg_geom *g, const gg_rpre *r, gg_tx *x, uint32_t ref, gg_hit *best)
{
    (void)x;
    return gg_leaf_closest_p(g, r, tx_first(g, ref), GG_LEAF_N(ref), best, GG_TX_FLOAT);
}

GG_INLINE uint32_t tx_any(const gg_geom *g, const gg_rpre *r, gg_tx *x, uint32_t ref, double tmax)
{
    (void)x;
    return gg_leaf_any_p(g, r, tx_first(g, ref), GG_LEAF_N(ref), tmax, GG_TX_FLOAT);
}

GG_INLINE uint32_t tx_shadow(const gg_geom *g, const gg_rpre *r, gg_tx *x, uint32_t ref,
                             double tmax, gg_hit *best, gg_tcol *col)
{
    (void)x;
    return gg_leaf_shadow_p(g, r, tx_first(g, ref), GG_LEAF_N(ref), tmax, best, col, GG_TX_FLOAT);
}

/* A run of slots outside the leaf tests: the occluder cache and the
   fallbacks for rays the float boxes cannot take (every slot). */
GG_INLINE uint32_t tx_slots_any(const gg_geom *g, const gg_rpre *r, uint32_t first, uint32_t n,
                                double tmax)
{
    return gg_leaf_any_p(g, r, first, n, tmax, GG_TX_FLOAT);
}

GG_INLINE uint32_t tx_slots_shadow(const gg_geom *g, const gg_rpre *r, uint32_t first, uint32_t n,
                                   double tmax, gg_hit *best, gg_tcol *col)
{
    return gg_leaf_shadow_p(g, r, first, n, tmax, best, col, GG_TX_FLOAT);
}

#endif
