/* SPDX-License-Identifier: MIT */
/*
** bvh_trav.h -- the BVH traversals (closest hit, any hit, shadow query),
** included once per instruction set: bvh.c compiles the plain copy,
** bvh_avx.c, a per-ISA object (compiler.h), the AVX one (internal to the
** BVH).
**
** The including file defines, before including this:
**   GG_TRAV_LINK                     linkage of the three functions;
**   GG_TRAV_INTERSECT, GG_TRAV_OCCLUDER, GG_TRAV_SHADOW  their names;
**   gg_tx, and tx_init, tx_fill, tx_closest, tx_any, tx_shadow: the
**       per-ray state of its leaf tests (tx_init may defer filling it to
**       the first leaf that needs it, tx_fill fills it at once) and the
**       leaf tests of a leaf reference, with the contracts of
**       gg_leaf_closest, gg_leaf_any and gg_leaf_shadow.
** Both copies thus share the node walk; only the leaves differ.
** With GG_TRAV_COST defined, GG_TRAV_INTERSECT takes a gg_trav_cost *
** more and counts into it, and the other two are left out (bvh_cost.c,
** the ray-tree recorder's copy).
*/
#ifndef GG_BVH_TRAV_H
#define GG_BVH_TRAV_H

#include "bvh_int.h"

#if defined(__SSE2__) && !defined(GG_BVH_NO_SIMD)
#define GG_BVH_SIMD 1
#include <emmintrin.h>
#endif

typedef struct trav {
#ifdef GG_BVH_SIMD
    __m128 inv[3], invf[3], on[3], of[3];
#else
    float inv[3], invf[3], on[3], of[3];
#endif
    size_t nr[3], fr[3]; /* byte offsets of the entry and exit rows per axis */
} trav;

/* Byte offsets of the entry (lo if the axis' 1/d >= 0, else hi) and exit
   rows of each axis, by the sign mask of 1/d (bit k: axis k negative). */
#define GG_ROWS(ng, k) ((k) + 3 * (ng)) * sizeof(float[4])
#define GG_ROWSET(m)                                                                               \
    {                                                                                              \
        {GG_ROWS((m)&1, 0), GG_ROWS(((m) >> 1) & 1, 1), GG_ROWS(((m) >> 2) & 1, 2)},               \
        {                                                                                          \
            GG_ROWS(1 - ((m)&1), 0), GG_ROWS(1 - (((m) >> 1) & 1), 1),                             \
                GG_ROWS(1 - (((m) >> 2) & 1), 2)                                                   \
        }                                                                                          \
    }
static const size_t row_offsets[8][2][3] = {GG_ROWSET(0), GG_ROWSET(1), GG_ROWSET(2), GG_ROWSET(3),
                                            GG_ROWSET(4), GG_ROWSET(5), GG_ROWSET(6), GG_ROWSET(7)};
#undef GG_ROWSET
#undef GG_ROWS

/* Per-ray setup of the float slab test. Returns 0 when the float
   traversal cannot represent the ray (an origin beyond 1e30).
   The origin is rounded to float and then moved out by 4 float half-ulps
   on each side (|o - fl(o)| <= 2^-24 |fl(o)| < 2^-22 |fl(o)|): `up` >= o >=
   `dn` for sure, without exact directed rounding. 1/d goes through float:
   two roundings, which the exit scale allows for. The sign of 1/d (not of
   d) picks the planes, so d = -0 (1/d = -inf) is handled as negative.
   Entry plane lo with the origin rounded up can only shorten the entry
   distance, exit plane hi with it rounded down only lengthen the exit. */
GG_INLINE int trav_init(trav *tv, const gg_rpre *r)
{
    int sm;
#ifdef GG_BVH_SIMD
    {
        /* One double at a time: r was just written that way, and a wider
           load would wait for the store buffer (see gg_rpre_init). Two
           are then paired and rounded by one cvtpd2ps (the same rounding
           as cvtsd2ss per value, fewer instructions). */
        __m128 of = _mm_movelh_ps(_mm_cvtpd_ps(_mm_set_pd(r->o[1], r->o[0])),
                                  _mm_cvtpd_ps(_mm_set1_pd(r->o[2])));
        __m128 df = _mm_movelh_ps(_mm_cvtpd_ps(_mm_set_pd(r->d[1], r->d[0])),
                                  _mm_cvtpd_ps(_mm_set1_pd(r->d[2])));
        __m128 absm = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
        __m128 ao = _mm_and_ps(of, absm);
        __m128 e = _mm_add_ps(_mm_mul_ps(ao, _mm_set1_ps(0x1p-22f)), _mm_set1_ps(1e-37f));
        __m128 up = _mm_add_ps(of, e), dn = _mm_sub_ps(of, e);
        __m128 inv = _mm_div_ps(_mm_set1_ps(1.0f), df);
        __m128 neg = _mm_castsi128_ps(_mm_srai_epi32(_mm_castps_si128(inv), 31));
        __m128 on = _mm_or_ps(_mm_and_ps(neg, dn), _mm_andnot_ps(neg, up));
        __m128 off = _mm_or_ps(_mm_and_ps(neg, up), _mm_andnot_ps(neg, dn));
        __m128 invf = _mm_mul_ps(inv, _mm_set1_ps(GG_EXIT_SCALE));
        /* an origin beyond 1e30 (or one that overflowed to inf) */
        if (_mm_movemask_ps(_mm_cmplt_ps(ao, _mm_set1_ps(1e30f))) != 0xf) return 0;
        sm = _mm_movemask_ps(inv);
        tv->inv[0] = _mm_shuffle_ps(inv, inv, 0x00);
        tv->inv[1] = _mm_shuffle_ps(inv, inv, 0x55);
        tv->inv[2] = _mm_shuffle_ps(inv, inv, 0xaa);
        tv->invf[0] = _mm_shuffle_ps(invf, invf, 0x00);
        tv->invf[1] = _mm_shuffle_ps(invf, invf, 0x55);
        tv->invf[2] = _mm_shuffle_ps(invf, invf, 0xaa);
        tv->on[0] = _mm_shuffle_ps(on, on, 0x00);
        tv->on[1] = _mm_shuffle_ps(on, on, 0x55);
        tv->on[2] = _mm_shuffle_ps(on, on, 0xaa);
        tv->of[0] = _mm_shuffle_ps(off, off, 0x00);
        tv->of[1] = _mm_shuffle_ps(off, off, 0x55);
        tv->of[2] = _mm_shuffle_ps(off, off, 0xaa);
    }
#else
    if (!(fabs(r->o[0]) < 1e30 && fabs(r->o[1]) < 1e30 && fabs(r->o[2]) < 1e30)) return 0;
    sm = 0;
    for (int k = 0; k < 3; k++) {
        float of = (float)r->o[k], df = f_near(r->d[k]);
        float e = fabsf(of) * 0x1p-22f + 1e-37f, up = of + e, dn = of - e;
        float inv = 1.0f / df;
        int ng = signbit(inv) != 0;
        sm |= ng << k;
        tv->inv[k] = inv;
        tv->invf[k] = inv * GG_EXIT_SCALE;
        tv->on[k] = ng ? dn : up;
        tv->of[k] = ng ? up : dn;
    }
#endif
    /* Row offsets from a table: the loop computing them cost a third of
       this function. */
    memcpy(tv->nr, row_offsets[sm & 7][0], sizeof tv->nr);
    memcpy(tv->fr, row_offsets[sm & 7][1], sizeof tv->fr);
    return 1;
}

/* f_down of a query's tmin, whose usual value 0 skips the rounding's
   branches (f_down(0) is the largest float below 0, -2^-149). */
static inline float f_down_tmin(double tmin)
{
    return tmin == 0 ? -0x1p-149f : f_down(tmin);
}

/* A float >= t for 0 <= t (the running closest distance), without the
   exact directed rounding: fl(t) >= t (1 - 2^-24), and the product and sum
   round to nearest. */
static inline float f_above(double t)
{
    return f_near(t) * 1.0000003f + 1e-37f;
}

/* Slab test of the four child boxes: returns the mask of boxes entered
   within [tmin, tmax] and their entry distances. Exit distances use 1/d
   times the exit scale (one more rounding, which the scale's slack of
   1 + 5 * 2^-23 > (1 + gamma(5)) / (1 - gamma(4)) covers).
   A slab distance is NaN only for 1/d = +-inf with the origin exactly on
   that plane. maxps/minps return their second operand when either is NaN,
   so in the order below a NaN can only drop a value out of the max (entry
   earlier) or the min (exit later) -- the test stays conservative -- and
   the result is never NaN because tmin/tmax come second at the bottom. */
#ifdef GG_BVH_SIMD
#define GG_ROW(nd, off) ((const float *)((const char *)(nd) + (off)))
static inline int box4(const gg_bnode *nd, const trav *tv, __m128 tmin4, __m128 tmax4,
                       float tn_out[4])
{
    __m128 tx0 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(GG_ROW(nd, tv->nr[0])), tv->on[0]), tv->inv[0]);
    __m128 ty0 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(GG_ROW(nd, tv->nr[1])), tv->on[1]), tv->inv[1]);
    __m128 tz0 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(GG_ROW(nd, tv->nr[2])), tv->on[2]), tv->inv[2]);
    __m128 tx1 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(GG_ROW(nd, tv->fr[0])), tv->of[0]), tv->invf[0]);
    __m128 ty1 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(GG_ROW(nd, tv->fr[1])), tv->of[1]), tv->invf[1]);
    __m128 tz1 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(GG_ROW(nd, tv->fr[2])), tv->of[2]), tv->invf[2]);
    __m128 tn = _mm_max_ps(_mm_max_ps(tx0, ty0), _mm_max_ps(tz0, tmin4));
    __m128 tf = _mm_min_ps(_mm_min_ps(tx1, ty1), _mm_min_ps(tz1, tmax4));
    _mm_store_ps(tn_out, tn);
    return _mm_movemask_ps(_mm_cmple_ps(tn, tf));
}
#define GG_T4(x) _mm_set1_ps(x)
typedef __m128 gg_t4;
#else
static inline int box4(const gg_bnode *nd, const trav *tv, float tmin, float tmax, float tn_out[4])
{
    int i, k, mask = 0;
    for (i = 0; i < 4; i++) {
        float tn = tmin, tf = tmax;
        for (k = 0; k < 3; k++) {
            float a = (nd->b[tv->nr[k] / sizeof(float[4])][i] - tv->on[k]) * tv->inv[k];
            float b = (nd->b[tv->fr[k] / sizeof(float[4])][i] - tv->of[k]) * tv->invf[k];
            tn = a > tn ? a : tn;
            tf = b < tf ? b : tf;
        }
        tn_out[i] = tn;
        if (tn <= tf) mask |= 1 << i;
    }
    return mask;
}
#define GG_T4(x) (x)
typedef float gg_t4;
#endif

static inline int lowest_bit(unsigned m)
{
    return GG_CTZ(m);
}

/* gg_rpre_fill and trav_init inline here, reading q one double at a time:
   the caller has usually just written *q field by field, and a 16-byte
   load spanning two 8-byte stores cannot be forwarded from the store
   buffer (GG_NO_SLP, compiler.h). */

#ifdef GG_TRAV_COST
#define GG_COST_ARG       , gg_trav_cost *cost
#define GG_COST_NODE()    (cost->nodes++)
#define GG_COST_LEAF(ref) (cost->prims += GG_LEAF_N(ref))
#define GG_COST_ALL()     (cost->prims += (long)g->nslots)
#else
#define GG_COST_ARG
#define GG_COST_NODE()    ((void)0)
#define GG_COST_LEAF(ref) ((void)0)
#define GG_COST_ALL()     ((void)0)
#endif

GG_TRAV_LINK GG_NO_SLP int GG_TRAV_INTERSECT(const gg_geom *g, const gg_rayq *q,
                                             gg_hit *hit GG_COST_ARG)
{
    gg_rpre r;
    trav tv;
    gg_tx tx;
    gg_hit best;
    uint32_t stack[GG_STACK], cur = 0;
    float stack_t[GG_STACK];
    int sp = 0;
    float tmaxf, tcull;
    gg_t4 tmin4, tmax4;

    if (!g->built || !g->nslots || !gg_rpre_fill(&r, q) || !(q->tmax > q->tmin)) return 0;
    /* The conservative box test assumes tmin >= 0 (a box wholly behind the
       origin could otherwise be lost to the exit scaling). */
    if (!trav_init(&tv, &r) || q->tmin < 0) {
        GG_COST_ALL();
        return gg_geom_intersect_brute(g, q, hit);
    }
    /* Deferred: many closest-hit rays meet no triangle block; the any-hit
       traversals set up eagerly (docs/performance.md, "Four triangles at
       once"). */
    tx_init(&tx, &r);
    best.t = gg_next_down(q->tmax);
    best.prim = UINT32_MAX, best.sub = 0, best.b1 = best.b2 = 0;
    tmaxf = f_above(best.t);
    tcull = tmaxf * GG_EXIT_SCALE;
    tmin4 = GG_T4(f_down_tmin(q->tmin));
    tmax4 = GG_T4(tmaxf);
    for (;;) {
        if (!(cur & GG_LEAF)) {
            const gg_bnode *nd = &g->nodes[cur];
            float tn[4];
            unsigned mask = (unsigned)box4(nd, &tv, tmin4, tmax4, tn);
            int i0, i1;
            GG_COST_NODE();
            if (mask) {
                i0 = lowest_bit(mask);
                mask &= mask - 1;
                if (!mask) {
                    cur = nd->child[i0];
                    continue;
                }
                i1 = lowest_bit(mask);
                mask &= mask - 1;
                if (!mask) {
                    /* Nearer child first, the other on the stack (selects,
                       not a branch: which is nearer is a coin toss). */
                    uint32_t c0 = nd->child[i0], c1 = nd->child[i1];
                    float t0 = tn[i0], t1 = tn[i1];
                    int sw = t1 < t0;
                    stack[sp] = sw ? c0 : c1;
                    stack_t[sp++] = sw ? t0 : t1;
                    cur = sw ? c1 : c0;
                    continue;
                }
                {
                    /* Three or four: sort by entry distance, push the far
                       ones (farthest deepest), descend into the nearest. */
                    uint32_t rf[4];
                    float tt[4];
                    int k = 0, a, b;
                    rf[k] = nd->child[i0], tt[k++] = tn[i0];
                    rf[k] = nd->child[i1], tt[k++] = tn[i1];
                    while (mask) {
                        a = lowest_bit(mask);
                        mask &= mask - 1;
                        rf[k] = nd->child[a], tt[k++] = tn[a];
                    }
                    for (a = 1; a < k; a++)
                        for (b = a; b > 0 && tt[b] > tt[b - 1]; b--) {
                            float ft = tt[b];
                            uint32_t fr = rf[b];
                            tt[b] = tt[b - 1], rf[b] = rf[b - 1];
                            tt[b - 1] = ft, rf[b - 1] = fr;
                        }
                    for (a = 0; a < k - 1; a++) stack[sp] = rf[a], stack_t[sp++] = tt[a];
                    cur = rf[k - 1];
                    continue;
                }
            }
        } else {
            GG_COST_LEAF(cur);
            if (tx_closest(g, &r, &tx, cur, &best)) {
                tmaxf = f_above(best.t);
                tcull = tmaxf * GG_EXIT_SCALE;
                tmax4 = GG_T4(tmaxf);
            }
        }
        /* Pop the next subtree that may still hold a closer hit (entry
           distances are compared with the same slack as in box4). */
        for (;;) {
            if (sp == 0) goto done;
            sp--;
            if (stack_t[sp] <= tcull) break;
        }
        cur = stack[sp];
    }
done:
    if (best.prim == UINT32_MAX) return 0;
    *hit = best;
    return 1;
}

#ifndef GG_TRAV_COST
/* Any-hit descent (the occluder and the shadow query): the first child
   hit next, the others on the stack; the order does not matter for a
   yes/no answer or for a list (nearest-first: docs/performance.md, "Tried
   and not kept"). */
#ifndef GG_TRAV_ANY_DESCEND
#define GG_TRAV_ANY_DESCEND
GG_INLINE uint32_t any_descend(const gg_bnode *nd, unsigned mask, uint32_t *stack, int *sp)
{
    uint32_t first = nd->child[lowest_bit(mask)];
    mask &= mask - 1;
    while (mask) {
        stack[(*sp)++] = nd->child[lowest_bit(mask)];
        mask &= mask - 1;
    }
    return first;
}
#endif

/* Any-hit traversal; returns the slot index + 1 of an occluder, or 0.
   The occluder at slot index *cache - 1 (if *cache is not 0) is tried
   first. */
GG_TRAV_LINK GG_NO_SLP uint32_t GG_TRAV_OCCLUDER(const gg_geom *g, const gg_rayq *q,
                                                 uint32_t *cache)
{
    gg_rpre r;
    trav tv;
    gg_tx tx;
    uint32_t stack[GG_STACK], cur = 0, hit;
    int sp = 0;
    double tmax;
    gg_t4 tmin4, tmax4;

    if (!g->built || !g->nslots || !gg_rpre_fill(&r, q) || !(q->tmax > q->tmin)) return 0;
    tmax = gg_next_down(q->tmax);
    if (*cache && *cache <= g->nslots) {
        hit = gg_leaf_any(g, &r, *cache - 1, 1, tmax);
        if (hit) return hit;
    }
    if (!trav_init(&tv, &r) || q->tmin < 0) {
        return gg_leaf_any(g, &r, 0, (uint32_t)g->nslots, tmax);
    }
    tx_fill(&tx, &r);
    tmin4 = GG_T4(f_down_tmin(q->tmin));
    tmax4 = GG_T4(f_above(tmax));
    for (;;) {
        if (!(cur & GG_LEAF)) {
            const gg_bnode *nd = &g->nodes[cur];
            float tn[4];
            unsigned mask = (unsigned)box4(nd, &tv, tmin4, tmax4, tn);
            if (mask) {
                cur = any_descend(nd, mask, stack, &sp);
                continue;
            }
        } else {
            hit = tx_any(g, &r, &tx, cur, tmax);
            if (hit) return hit;
        }
        if (sp == 0) return 0;
        cur = stack[--sp];
    }
}

/* An any-hit traversal over the whole segment (transparent hits do not
   shorten it: an opaque one further on still blocks). The nearest
   transparent hit comes out the same as gg_geom_intersect's because
   every element whose box the segment enters is tested, with the same
   kernels and the same tie rule (the answer of gg_leaf_closest does not
   depend on the visiting order). */
GG_TRAV_LINK GG_NO_SLP int GG_TRAV_SHADOW(const gg_geom *g, const gg_rayq *q, uint32_t *cache,
                                          gg_tcol *col)
{
    gg_rpre r;
    trav tv;
    gg_tx tx;
    gg_hit best;
    uint32_t stack[GG_STACK], cur = 0, hit;
    int sp = 0;
    double tmax;
    gg_t4 tmin4, tmax4;

    if (!g->built || !g->nslots || !gg_rpre_fill(&r, q) || !(q->tmax > q->tmin)) return 0;
    r.skip = 0;
    tmax = gg_next_down(q->tmax);
    best.t = tmax;
    best.prim = UINT32_MAX, best.sub = 0, best.b1 = best.b2 = 0;
    /* The opaque element that blocked this light's previous shadow ray
       first: if it blocks this one too, the answer (1) is the same as the
       traversal's, whichever opaque element that would have found. */
    if (*cache && *cache <= g->nslots &&
        !(g->pflags[g->slots[*cache - 1].prim] & GG_PRIM_TRANSPARENT) &&
        gg_leaf_any(g, &r, *cache - 1, 1, tmax))
        return 1;
    if (!trav_init(&tv, &r) || q->tmin < 0) {
        if ((hit = gg_leaf_shadow(g, &r, 0, (uint32_t)g->nslots, tmax, &best, col))) goto blocked;
        goto done;
    }
    tx_fill(&tx, &r);
    tmin4 = GG_T4(f_down_tmin(q->tmin));
    tmax4 = GG_T4(f_above(tmax));
    for (;;) {
        if (!(cur & GG_LEAF)) {
            const gg_bnode *nd = &g->nodes[cur];
            float tn[4];
            unsigned mask = (unsigned)box4(nd, &tv, tmin4, tmax4, tn);
            if (mask) {
                cur = any_descend(nd, mask, stack, &sp);
                continue;
            }
        } else if ((hit = tx_shadow(g, &r, &tx, cur, tmax, &best, col)))
            goto blocked;
        if (sp == 0) break;
        cur = stack[--sp];
    }
done:
    *cache = 0;
    if (best.prim != UINT32_MAX) {
        col->near = best;
        col->has_near = 1;
    }
    return 0;
blocked:
    *cache = hit;
    return 1;
}

#endif /* GG_TRAV_COST */

#endif
