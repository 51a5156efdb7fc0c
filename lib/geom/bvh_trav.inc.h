/* SPDX-License-Identifier: MIT */
/*
** bvh_trav.inc.h -- the BVH traversals (closest hit, any hit, shadow
** query, packets of closest hits), a template (compiler.h, "Templates";
** internal to the BVH) instantiated by bvh.c (the plain copy), bvh_avx.c
** (the AVX copy; its AVX2 build is the same source compiled again),
** bvh_float.c (single precision) and bvh_cost.c (the recorder's).
**
** The including file defines, before including this:
**   GG_INC_LINK, GG_INC_NAME(f)   linkage and names of the functions
**       bvh_intersect, bvh_occluder, bvh_shadow and bvh_packet (closest
**       hits of a packet of rays);
**   the leaf hooks, with the contracts of gg_leaf_closest, gg_leaf_any
**   and gg_leaf_shadow (geom_leaf.h):
**     gg_tx, tx_init, tx_fill  the per-ray state of its leaf tests
**         (tx_init may defer filling it to the first leaf that needs it,
**         tx_fill fills it at once);
**     tx_closest, tx_any, tx_shadow  the tests of a leaf reference;
**     tx_slots_any, tx_slots_shadow  the tests of a run of slots (the
**         occluder cache, and every slot for a ray the float boxes
**         cannot take).
** bvh_hooks.h has the hooks of the copies with scalar leaves. The copies
** thus share the node walk; only the leaves differ.
** With GG_TRAV_WIDE defined (bvh_avx.c), the walks take the 8-wide
** nodes (g->wnodes, gg_bvh_wide): the single-ray ones by box8, the
** packets by pk_box8.
** With GG_TRAV_SINGLE defined, the packet walk is left out (bvh_float.c).
** With GG_TRAV_COST defined, bvh_intersect takes a gg_trav_cost * more
** and counts into it, and the other three are left out (bvh_cost.c, the
** ray-tree recorder's copy).
** With GG_TRAV_COUNT defined, every walk counts its queries and kernel
** calls into g->kcount (gg_kcount, geom.h; the AVX copy's counting build,
** bvh_count_avx.o); without it GG_COUNT is nothing, and the copies the
** render takes are the same instructions as before.
*/
#ifndef GG_BVH_TRAV_H
#define GG_BVH_TRAV_H

#include "bvh_int.h"

#if !defined(GG_INC_NAME) || !defined(GG_INC_LINK)
#error "define GG_INC_NAME and GG_INC_LINK before including bvh_trav.inc.h"
#endif

#if defined(__SSE2__) && !defined(GG_BVH_NO_SIMD)
#define GG_BVH_SIMD 1
#include <emmintrin.h>
#ifdef __AVX__
#include <immintrin.h> /* the AVX copy's 8-wide lane tests (pk_lanes; 16-wide in its
                          AVX-512 build) */
#endif
#endif

typedef struct trav {
#ifdef GG_BVH_SIMD
    __m128 inv[3], invf[3], on[3], of[3];
#else
    float inv[3], invf[3], on[3], of[3];
#endif
    /* row_offsets' entry for the ray's signs: byte offsets of the entry
       (rows[0][k]) and exit (rows[1][k]) rows of axis k. A pointer, not a
       copy: copying the six offsets was a tenth of the set-up. */
    const size_t (*rows)[3];
} trav;

/* Byte offsets of the entry (lo if the axis' 1/d >= 0, else hi) and exit
   rows of each axis, by the sign mask of 1/d (bit k: axis k negative), in
   a node of w children (rows of w floats). */
#define GG_ROWS(ng, k, w) ((k) + 3 * (ng)) * sizeof(float[w])
#define GG_ROWSET(m, w)                                                                            \
    {                                                                                              \
        {GG_ROWS((m)&1, 0, w), GG_ROWS(((m) >> 1) & 1, 1, w), GG_ROWS(((m) >> 2) & 1, 2, w)},      \
        {                                                                                          \
            GG_ROWS(1 - ((m)&1), 0, w), GG_ROWS(1 - (((m) >> 1) & 1), 1, w),                       \
                GG_ROWS(1 - (((m) >> 2) & 1), 2, w)                                                \
        }                                                                                          \
    }
#define GG_ROWTABLE(w)                                                                             \
    {                                                                                              \
        GG_ROWSET(0, w), GG_ROWSET(1, w), GG_ROWSET(2, w), GG_ROWSET(3, w), GG_ROWSET(4, w),       \
            GG_ROWSET(5, w), GG_ROWSET(6, w), GG_ROWSET(7, w)                                      \
    }
static const size_t row_offsets[8][2][3] = GG_ROWTABLE(4);

/* Per-ray setup of the float slab test. Returns 0 when the float
   traversal cannot represent the ray (an origin beyond 1e30).
   The origin is rounded to float and then moved out by 4 float half-ulps
   on each side (|o - fl(o)| <= 2^-24 |fl(o)| < 2^-22 |fl(o)|): `up` >= o >=
   `dn` for sure, without exact directed rounding. 1/d goes through float:
   two roundings, which the exit scale allows for. The sign of 1/d (not of
   d) picks the planes, so d = -0 (1/d = -inf) is handled as negative.
   Entry plane lo with the origin rounded up can only shorten the entry
   distance, exit plane hi with it rounded down only lengthen the exit.
   From the ray's origin (ox, oy, oz) and direction (dx, dy, dz). */
#ifdef GG_BVH_SIMD
/* The terms as (x, y, z, z) vectors: 1/d, the exit 1/d, the entry and the
   exit origin; 0 for an origin beyond 1e30 (or one that overflowed). */
GG_INLINE int trav_terms(double ox, double oy, double oz, double dx, double dy, double dz,
                         __m128 *inv, __m128 *invf, __m128 *on, __m128 *off)
{
    /* One double at a time: r was just written that way, and a wider
       load would wait for the store buffer (see gg_rpre_init). Two are
       then paired and rounded by one cvtpd2ps (the same rounding as
       cvtsd2ss per value, fewer instructions). */
    __m128 of = _mm_movelh_ps(_mm_cvtpd_ps(_mm_set_pd(oy, ox)), _mm_cvtpd_ps(_mm_set1_pd(oz)));
    __m128 df = _mm_movelh_ps(_mm_cvtpd_ps(_mm_set_pd(dy, dx)), _mm_cvtpd_ps(_mm_set1_pd(dz)));
    __m128 absm = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
    __m128 ao = _mm_and_ps(of, absm);
    __m128 e = _mm_add_ps(_mm_mul_ps(ao, _mm_set1_ps(0x1p-22f)), _mm_set1_ps(1e-37f));
    __m128 up = _mm_add_ps(of, e), dn = _mm_sub_ps(of, e);
    __m128 neg;
    *inv = _mm_div_ps(_mm_set1_ps(1.0f), df);
    neg = _mm_castsi128_ps(_mm_srai_epi32(_mm_castps_si128(*inv), 31));
    *on = _mm_or_ps(_mm_and_ps(neg, dn), _mm_andnot_ps(neg, up));
    *off = _mm_or_ps(_mm_and_ps(neg, up), _mm_andnot_ps(neg, dn));
    *invf = _mm_mul_ps(*inv, _mm_set1_ps(GG_EXIT_SCALE));
    return _mm_movemask_ps(_mm_cmplt_ps(ao, _mm_set1_ps(1e30f))) == 0xf;
}
#endif

GG_INLINE int trav_init6(trav *tv, double ox, double oy, double oz, double dx, double dy, double dz)
{
    int sm;
#ifdef GG_BVH_SIMD
    {
        __m128 inv, invf, on, off;
        if (!trav_terms(ox, oy, oz, dx, dy, dz, &inv, &invf, &on, &off)) return 0;
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
    const double o[3] = {ox, oy, oz}, d[3] = {dx, dy, dz};
    if (!(fabs(o[0]) < 1e30 && fabs(o[1]) < 1e30 && fabs(o[2]) < 1e30)) return 0;
    sm = 0;
    for (int k = 0; k < 3; k++) {
        float of = (float)o[k], df = f_near(d[k]);
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
    tv->rows = row_offsets[sm & 7];
    return 1;
}

GG_INLINE int trav_init(trav *tv, const gg_rpre *r)
{
    return trav_init6(tv, r->o[0], r->o[1], r->o[2], r->d[0], r->d[1], r->d[2]);
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
#define GG_ROW(nd, off) ((const float *)((const char *)(nd) + (off)))
#ifdef GG_BVH_SIMD
static inline int box4(const gg_bnode *nd, const trav *tv, __m128 tmin4, __m128 tmax4,
                       float tn_out[4])
{
    const size_t *nr = tv->rows[0], *fr = tv->rows[1];
    __m128 tx0 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(GG_ROW(nd, nr[0])), tv->on[0]), tv->inv[0]);
    __m128 ty0 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(GG_ROW(nd, nr[1])), tv->on[1]), tv->inv[1]);
    __m128 tz0 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(GG_ROW(nd, nr[2])), tv->on[2]), tv->inv[2]);
    __m128 tx1 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(GG_ROW(nd, fr[0])), tv->of[0]), tv->invf[0]);
    __m128 ty1 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(GG_ROW(nd, fr[1])), tv->of[1]), tv->invf[1]);
    __m128 tz1 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(GG_ROW(nd, fr[2])), tv->of[2]), tv->invf[2]);
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
            float a = (nd->b[tv->rows[0][k] / sizeof(float[4])][i] - tv->on[k]) * tv->inv[k];
            float b = (nd->b[tv->rows[1][k] / sizeof(float[4])][i] - tv->of[k]) * tv->invf[k];
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

/* The single-ray walks' nodes: the 4-wide tree, or with GG_TRAV_WIDE (the
   AVX copy) the 8-wide one (gg_wnode, gg_bvh_wide), whose boxes
   are the same floats: box8 is box4's test, lane for lane, on eight
   boxes. ANY_W children a node, ANY_STACK entries a walk's stack. */
#ifdef GG_TRAV_WIDE
static const size_t wrow_offsets[8][2][3] = GG_ROWTABLE(8);

typedef struct wtrav {
    __m256 inv[3], invf[3], on[3], of[3];
    const size_t (*rows)[3];
} wtrav;

/* trav_init6 in eight lanes: the same terms, each (x, y, z) vector copied
   to both halves and then broadcast within them. */
GG_INLINE int wtrav_init6(wtrav *w, double ox, double oy, double oz, double dx, double dy,
                          double dz)
{
    __m128 inv, invf, on, off;
    __m256 i8, f8, n8, o8;
    if (!trav_terms(ox, oy, oz, dx, dy, dz, &inv, &invf, &on, &off)) return 0;
    i8 = _mm256_insertf128_ps(_mm256_castps128_ps256(inv), inv, 1);
    f8 = _mm256_insertf128_ps(_mm256_castps128_ps256(invf), invf, 1);
    n8 = _mm256_insertf128_ps(_mm256_castps128_ps256(on), on, 1);
    o8 = _mm256_insertf128_ps(_mm256_castps128_ps256(off), off, 1);
    w->inv[0] = _mm256_permute_ps(i8, 0x00), w->inv[1] = _mm256_permute_ps(i8, 0x55);
    w->inv[2] = _mm256_permute_ps(i8, 0xaa);
    w->invf[0] = _mm256_permute_ps(f8, 0x00), w->invf[1] = _mm256_permute_ps(f8, 0x55);
    w->invf[2] = _mm256_permute_ps(f8, 0xaa);
    w->on[0] = _mm256_permute_ps(n8, 0x00), w->on[1] = _mm256_permute_ps(n8, 0x55);
    w->on[2] = _mm256_permute_ps(n8, 0xaa);
    w->of[0] = _mm256_permute_ps(o8, 0x00), w->of[1] = _mm256_permute_ps(o8, 0x55);
    w->of[2] = _mm256_permute_ps(o8, 0xaa);
    w->rows = wrow_offsets[_mm_movemask_ps(inv) & 7];
    return 1;
}

/* box4 on the eight boxes of nd: the mask of those entered and, if tn_out
   is not NULL, their entry distances. */
static inline unsigned box8(const gg_wnode *nd, const wtrav *tv, __m256 tmin8, __m256 tmax8,
                            float *tn_out)
{
    const size_t *nr = tv->rows[0], *fr = tv->rows[1];
    __m256 tx0 =
        _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(GG_ROW(nd, nr[0])), tv->on[0]), tv->inv[0]);
    __m256 ty0 =
        _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(GG_ROW(nd, nr[1])), tv->on[1]), tv->inv[1]);
    __m256 tz0 =
        _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(GG_ROW(nd, nr[2])), tv->on[2]), tv->inv[2]);
    __m256 tx1 =
        _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(GG_ROW(nd, fr[0])), tv->of[0]), tv->invf[0]);
    __m256 ty1 =
        _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(GG_ROW(nd, fr[1])), tv->of[1]), tv->invf[1]);
    __m256 tz1 =
        _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(GG_ROW(nd, fr[2])), tv->of[2]), tv->invf[2]);
    __m256 tn = _mm256_max_ps(_mm256_max_ps(tx0, ty0), _mm256_max_ps(tz0, tmin8));
    __m256 tf = _mm256_min_ps(_mm256_min_ps(tx1, ty1), _mm256_min_ps(tz1, tmax8));
    if (tn_out) _mm256_storeu_ps(tn_out, tn);
#ifdef __AVX512VL__
    /* the AVX-512 build: the compare writes the mask register itself */
    return (unsigned)_mm256_cmp_ps_mask(tn, tf, _CMP_LE_OQ);
#else
    return (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(tn, tf, _CMP_LE_OQ));
#endif
}
typedef gg_wnode any_node;
typedef wtrav any_trav;
typedef __m256 any_t;
#define ANY_NODES(g)                     ((g)->wnodes)
#define ANY_INIT6                        wtrav_init6
#define ANY_SET1(x)                      _mm256_set1_ps(x)
#define ANY_BOX(nd, tv, tmin, tmax)      box8(nd, tv, tmin, tmax, NULL)
#define ANY_BOXT(nd, tv, tmin, tmax, tn) box8(nd, tv, tmin, tmax, tn)
#define ANY_W                            8
#define ANY_STACK                        GG_WSTACK
#else
static inline unsigned any_box4(const gg_bnode *nd, const trav *tv, gg_t4 tmin4, gg_t4 tmax4)
{
    float tn[4];
    return (unsigned)box4(nd, tv, tmin4, tmax4, tn);
}
typedef gg_bnode any_node;
typedef trav any_trav;
typedef gg_t4 any_t;
#define ANY_NODES(g)                     ((g)->nodes)
#define ANY_INIT6                        trav_init6
#define ANY_SET1(x)                      GG_T4(x)
#define ANY_BOX(nd, tv, tmin, tmax)      any_box4(nd, tv, tmin, tmax)
#define ANY_BOXT(nd, tv, tmin, tmax, tn) (unsigned)box4(nd, tv, tmin, tmax, tn)
#define ANY_W                            4
#define ANY_STACK                        GG_STACK
#endif
#define ANY_INIT(tv, r)                                                                            \
    ANY_INIT6(tv, (r)->o[0], (r)->o[1], (r)->o[2], (r)->d[0], (r)->d[1], (r)->d[2])

/* gg_rpre_fill and trav_init inline here, reading q one double at a time:
   the caller has usually just written *q field by field, and a 16-byte
   load spanning two 8-byte stores cannot be forwarded from the store
   buffer (GG_NO_SLP, compiler.h). */

#ifdef GG_TRAV_COUNT
#define GG_COUNT(g, f) ((void)((g)->kcount->f++))
#else
#define GG_COUNT(g, f) ((void)0)
#endif

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

GG_INC_LINK GG_NO_SLP int GG_INC_NAME(bvh_intersect)(const gg_geom *g, const gg_rayq *q,
                                                     gg_hit *hit GG_COST_ARG)
{
    gg_rpre r;
    any_trav tv;
    gg_tx tx;
    gg_hit best;
    uint32_t stack[ANY_STACK], cur = 0;
    float stack_t[ANY_STACK];
    int sp = 0;
    float tmaxf, tcull;
    any_t tmin4, tmax4;

    if (!g->built || !g->nslots || !gg_rpre_fill(&r, q) || !(q->tmax > q->tmin)) return 0;
    GG_COUNT(g, closest);
    /* The conservative box test assumes tmin >= 0 (a box wholly behind the
       origin could otherwise be lost to the exit scaling). */
    if (!ANY_INIT(&tv, &r) || q->tmin < 0) {
        GG_COST_ALL();
        return gg_geom_intersect_brute(g, q, hit);
    }
    /* Deferred: many closest-hit rays meet no triangle block; the any-hit
       traversals set up eagerly (docs/performance.md, "Four triangles at
       once"). */
    tx_init(&tx, &r);
    best.t = gg_next_down_tmax(q->tmax);
    best.prim = UINT32_MAX, best.sub = 0, best.b1 = best.b2 = 0;
    tmaxf = f_above(best.t);
    tcull = tmaxf * GG_EXIT_SCALE;
    tmin4 = ANY_SET1(f_down_tmin(q->tmin));
    tmax4 = ANY_SET1(tmaxf);
    for (;;) {
        if (!(cur & GG_LEAF)) {
            const any_node *nd = &ANY_NODES(g)[cur];
            float tn[ANY_W];
            unsigned mask = ANY_BOXT(nd, &tv, tmin4, tmax4, tn);
            int i0, i1;
            GG_COST_NODE();
            GG_COUNT(g, box8);
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
                    /* Three or more: sort by entry distance, push the far
                       ones (farthest deepest), descend into the nearest. */
                    uint32_t rf[ANY_W];
                    float tt[ANY_W];
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
                tmax4 = ANY_SET1(tmaxf);
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
    GG_COUNT(g, hits);
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
#if defined(GG_TRAV_WIDE) && defined(__AVX512VL__)
/* The AVX-512 build: the children hit packed into the low lanes of one
   register (in lane order, as the loop below pushes them). The first
   goes to the walk from the register, not by a load indexed by the
   mask's lowest bit: that chain (mask to GPR, tzcnt, load) stood between
   a node's test and the next node's (gears 1.035 faster, fastest of 9
   and 11 rounds: docs/performance.md, "The any-hit descent"). The rest,
   shifted down a lane, are stored as eight; the stack has room for the
   lanes past the last (GG_WSTACK). Compressing into a register, not into
   memory: a compressing store is microcoded on some CPUs (AMD Zen 4). */
GG_INLINE uint32_t any_descend(const uint32_t *child, unsigned mask, uint32_t *stack, int *sp)
{
    const __m256i c = _mm256_load_si256((const __m256i *)(const void *)child);
    const __m256i all = _mm256_maskz_compress_epi32((__mmask8)mask, c);
    _mm256_storeu_si256((__m256i *)(void *)(stack + *sp),
                        _mm256_alignr_epi32(_mm256_setzero_si256(), all, 1));
    *sp += __builtin_popcount(mask) - 1;
    return (uint32_t)_mm256_cvtsi256_si32(all);
}
#else
GG_INLINE uint32_t any_descend(const uint32_t *child, unsigned mask, uint32_t *stack, int *sp)
{
    uint32_t first = child[lowest_bit(mask)];
    mask &= mask - 1;
    while (mask) {
        stack[(*sp)++] = child[lowest_bit(mask)];
        mask &= mask - 1;
    }
    return first;
}
#endif
#endif

/* The occluder's walk from the root: with `lazy` (a constant, so each
   caller gets its own copy of the loop) r holds nothing yet and is
   filled from q at the first leaf, with the leaf state. */
GG_INLINE uint32_t occ_walk(const gg_geom *g, const gg_rayq *q, gg_rpre *r, const any_trav *tv,
                            double tmax, const int lazy)
{
    gg_tx tx;
    uint32_t stack[ANY_STACK], cur = 0, hit;
    int sp = 0, ready = !lazy;
    any_t tmin4 = ANY_SET1(f_down_tmin(q->tmin)), tmax4 = ANY_SET1(f_above(tmax));
    if (lazy)
        tx_init(&tx, r);
    else
        tx_fill(&tx, r);
    for (;;) {
        if (!(cur & GG_LEAF)) {
            const any_node *nd = &ANY_NODES(g)[cur];
            unsigned mask = ANY_BOX(nd, tv, tmin4, tmax4);
            GG_COUNT(g, box8);
            if (mask) {
                cur = any_descend(nd->child, mask, stack, &sp);
                continue;
            }
        } else {
            if (lazy && !ready) {
                if (!gg_rpre_fill(r, q)) return 0;
                ready = 1;
            }
            hit = tx_any(g, r, &tx, cur, tmax);
            if (hit) return hit;
        }
        if (sp == 0) return 0;
        cur = stack[--sp];
    }
}

/* Any-hit traversal; returns the slot index + 1 of an occluder, or 0.
   The occluder at slot index *cache - 1 (if *cache is not 0) is tried
   first. With no cached occluder (the previous shadow ray was clear, and
   so is this one, mostly, after a few nodes) the ray's precomputation
   and leaf state wait for the first leaf; trav_init needs only o and d.
   A ray gg_rpre_fill refuses is clear either way. */
GG_INC_LINK GG_NO_SLP uint32_t GG_INC_NAME(bvh_occluder)(const gg_geom *g, const gg_rayq *q,
                                                         uint32_t *cache)
{
    gg_rpre r;
    any_trav tv;
    uint32_t hit;
    double tmax;

    if (!g->built || !g->nslots || !(q->tmax > q->tmin)) return 0;
    GG_COUNT(g, any);
    tmax = gg_next_down_tmax(q->tmax);
    if (!(*cache && *cache <= g->nslots)) {
        if (ANY_INIT6(&tv, q->o.x, q->o.y, q->o.z, q->d.x, q->d.y, q->d.z) && q->tmin >= 0)
            return occ_walk(g, q, &r, &tv, tmax, 1);
        if (!gg_rpre_fill(&r, q)) return 0;
        return tx_slots_any(g, &r, 0, (uint32_t)g->nslots, tmax);
    }
    if (!gg_rpre_fill(&r, q)) return 0;
    hit = tx_slots_any(g, &r, *cache - 1, 1, tmax);
    if (hit) return hit;
    if (!ANY_INIT(&tv, &r) || q->tmin < 0) {
        return tx_slots_any(g, &r, 0, (uint32_t)g->nslots, tmax);
    }
    return occ_walk(g, q, &r, &tv, tmax, 0);
}

/* An any-hit traversal over the whole segment (transparent hits do not
   shorten it: an opaque one further on still blocks). The nearest
   transparent hit comes out the same as gg_geom_intersect's because
   every element whose box the segment enters is tested, with the same
   kernels and the same tie rule (the answer of gg_leaf_closest does not
   depend on the visiting order). */
GG_INC_LINK GG_NO_SLP int GG_INC_NAME(bvh_shadow)(const gg_geom *g, const gg_rayq *q,
                                                  uint32_t *cache, gg_tcol *col)
{
    gg_rpre r;
    any_trav tv;
    gg_tx tx;
    gg_hit best;
    uint32_t stack[ANY_STACK], cur = 0, hit;
    int sp = 0;
    double tmax;
    any_t tmin4, tmax4;

    if (!g->built || !g->nslots || !gg_rpre_fill(&r, q) || !(q->tmax > q->tmin)) return 0;
    GG_COUNT(g, shadow);
    r.skip = 0;
    tmax = gg_next_down_tmax(q->tmax);
    best.t = tmax;
    best.prim = UINT32_MAX, best.sub = 0, best.b1 = best.b2 = 0;
    /* The opaque element that blocked this light's previous shadow ray
       first: if it blocks this one too, the answer (1) is the same as the
       traversal's, whichever opaque element that would have found. */
    if (*cache && *cache <= g->nslots &&
        !(g->pflags[g->slots[*cache - 1].prim] & GG_PRIM_TRANSPARENT) &&
        tx_slots_any(g, &r, *cache - 1, 1, tmax))
        return 1;
    if (!ANY_INIT(&tv, &r) || q->tmin < 0) {
        if ((hit = tx_slots_shadow(g, &r, 0, (uint32_t)g->nslots, tmax, &best, col))) goto blocked;
        goto done;
    }
    tx_fill(&tx, &r);
    tmin4 = ANY_SET1(f_down_tmin(q->tmin));
    tmax4 = ANY_SET1(f_above(tmax));
    for (;;) {
        if (!(cur & GG_LEAF)) {
            const any_node *nd = &ANY_NODES(g)[cur];
            unsigned mask = ANY_BOX(nd, &tv, tmin4, tmax4);
            GG_COUNT(g, box8);
            if (mask) {
                cur = any_descend(nd->child, mask, stack, &sp);
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

#ifndef GG_TRAV_SINGLE
/* ---- ray packets ----

   bvh_packet answers up to GG_PK closest-hit queries with one walk
   of the tree, each lane exactly as bvh_intersect would. The lanes
   of one packet share the origin and the signs of 1/d (a tile row of eye
   rays is one or two packets), so they read the same rows of a node and
   compute the same differences s = row - on; only 1/d differs. Inner
   nodes are tested once for all lanes with the interval [lo, hi] of the
   lanes' 1/d: rounded multiplication is monotone in each operand, so
   min(s lo, s hi) <= s inv for every lane's inv (and the max >= for the
   exit distances), and a box that some lane's box4 would enter is
   entered. At a leaf each lane tests the leaf's box with box4's
   operations and its own bounds, and its elements with the single-ray
   leaf test (tx_closest): every lane tests at least the elements its own
   traversal would, and the closest hit does not depend on the order
   (the tie rule of gg_leaf_take). No lane sees a NaN: a lane joins a
   packet only when each 1/d and exit 1/d is finite and nonzero (box4's
   NaN rule is not the interval's). A lane's ray set-up (gg_rpre_fill,
   tx_init) waits for its first leaf. */

#define GG_PK 16 /* GG_PACKET_MAX of geom.h */

/* Every lane's box-test terms, before the lanes are split into packets:
   1/d and the exit 1/d as trav_init rounds them, the bounds, the signs
   (bit l of neg[k]: lane l's 1/d is negative on axis k), and the shared
   origin rounded up and down. */
typedef struct pk_all {
    float inv[3][GG_PK], invf[3][GG_PK], tmin[GG_PK], tmax[GG_PK];
    float up[3], dn[3];
    unsigned neg[3];
} pk_all;

/* One packet's terms, by the caller's lane index: a lane outside it has
   tmax -inf (it enters no box) and the packet's first lane's 1/d (so it
   does not widen the interval). In the AVX-512 build aligned to 64, so
   that each 16-lane row pk_lanes reads is one cache line. */
#if defined(GG_BVH_SIMD) && defined(__AVX512F__)
#define GG_PKT_ALIGN __attribute__((aligned(64)))
#else
#define GG_PKT_ALIGN
#endif
typedef struct GG_PKT_ALIGN pkt {
    float inv[3][GG_PK], invf[3][GG_PK], tmin[GG_PK], tmax[GG_PK];
    float on[3], of[3], tminp; /* tminp <= every lane's tmin */
    size_t nr[3], fr[3];
    gg_t4 on4[3], of4[3], ilo[3], ihi[3], iflo[3], ifhi[3];
#ifdef GG_TRAV_WIDE
    __m256 on8[3], of8[3], ilo8[3], ihi8[3], iflo8[3], ifhi8[3]; /* the same, eight lanes */
#endif
    unsigned lanes;
} pkt;

/* The tree the packets walk: in the AVX copy's builds (GG_TRAV_WIDE) the
   8-wide one the single rays walk, so that a render keeps one tree in
   the cache, not two (docs/log/2026-12-05-speed.md, "Where the misses
   are"); elsewhere the 4-wide one. PK_W children a node, PK_STACK
   entries a walk's stack. */
#ifdef GG_TRAV_WIDE
#ifndef GG_BVH_SIMD
#error "the 8-wide packet walk needs the SIMD build"
#endif
typedef gg_wnode pk_node;
#define PK_NODES(g) ((g)->wnodes)
#define PK_W        8
#define PK_SHIFT    3
#define PK_STACK    GG_WSTACK
#define PK_ROWS     wrow_offsets
#else
typedef gg_bnode pk_node;
#define PK_NODES(g) ((g)->nodes)
#define PK_W        4
#define PK_SHIFT    2
#define PK_STACK    GG_STACK
#define PK_ROWS     row_offsets
#endif

/* The lanes' rays, by the caller's lane index. */
typedef struct pk_ray {
    const gg_rayq *q;
    gg_rpre r[GG_PK];
    gg_tx tx[GG_PK];
    gg_hit best[GG_PK];
    unsigned ready; /* lanes whose r and tx are set up */
} pk_ray;

/* a's origin terms from q0's origin, as trav_init computes them; 0 when
   the float traversal cannot take it (beyond 1e30, or not finite). */
static int pk_origin(pk_all *a, const gg_rayq *q0)
{
    const double o[3] = {q0->o.x, q0->o.y, q0->o.z};
    int k;
    for (k = 0; k < 3; k++) {
        float of = f_near(o[k]), e = fabsf(of) * 0x1p-22f + 1e-37f;
        if (!(fabsf(of) < 1e30f)) return 0;
        a->up[k] = of + e, a->dn[k] = of - e;
    }
    return 1;
}

/* 1/d and the exit 1/d of the GG_PK directions d[k][l] (trav_init's
   roundings) into a; returns the lanes where all are finite and nonzero. */
static unsigned pk_inverses(pk_all *a, double d[3][GG_PK])
{
    unsigned good = (1u << GG_PK) - 1;
    int k, l;
    for (k = 0; k < 3; k++) {
        unsigned neg = 0, bad = 0;
#ifdef GG_BVH_SIMD
        const __m128 absm = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
        for (l = 0; l < GG_PK; l += 4) {
            __m128 df = _mm_movelh_ps(_mm_cvtpd_ps(_mm_loadu_pd(&d[k][l])),
                                      _mm_cvtpd_ps(_mm_loadu_pd(&d[k][l + 2])));
            __m128 inv = _mm_div_ps(_mm_set1_ps(1.0f), df);
            __m128 invf = _mm_mul_ps(inv, _mm_set1_ps(GG_EXIT_SCALE));
            __m128 ok = _mm_and_ps(_mm_cmple_ps(_mm_and_ps(invf, absm), _mm_set1_ps(FLT_MAX)),
                                   _mm_cmpneq_ps(inv, _mm_setzero_ps()));
            _mm_storeu_ps(&a->inv[k][l], inv);
            _mm_storeu_ps(&a->invf[k][l], invf);
            neg |= (unsigned)_mm_movemask_ps(inv) << l;
            bad |= (unsigned)(~_mm_movemask_ps(ok) & 15) << l;
        }
#else
        for (l = 0; l < GG_PK; l++) {
            float inv = 1.0f / f_near(d[k][l]), invf = inv * GG_EXIT_SCALE;
            a->inv[k][l] = inv, a->invf[k][l] = invf;
            neg |= (unsigned)(signbit(inv) != 0) << l;
            bad |= (unsigned)!(fabsf(invf) <= FLT_MAX && inv != 0) << l;
        }
#endif
        a->neg[k] = neg;
        good &= ~bad;
    }
    return good;
}

/* Sets up a and s for the lanes; returns those that may join a packet:
   one origin (the first lane's), tmin >= 0 < tmax, 1/d finite and
   nonzero (so gg_rpre_fill will take the ray too). */
static unsigned pk_setup(pk_all *a, pk_ray *s, const gg_rayq *q, unsigned lanes)
{
    double d[3][GG_PK];
    const gg_rayq *q0 = &q[lowest_bit(lanes)];
    unsigned ok = 0;
    int l;
    if (!pk_origin(a, q0)) return 0;
    for (l = 0; l < GG_PK; l++) {
        const gg_rayq *ql = &q[l];
        /* Every lane's bounds, taken or not: pk_pack's minimum of tmin
           reads all GG_PK, and an indeterminate one (a NaN) made it NaN. */
        a->tmin[l] = a->tmax[l] = 0;
        if (!(lanes >> l & 1)) {
            d[0][l] = d[1][l] = d[2][l] = 1;
            continue;
        }
        d[0][l] = ql->d.x, d[1][l] = ql->d.y, d[2][l] = ql->d.z;
        /* (equal origins round to the same terms, +0 and -0 included) */
        if (!(ql->o.x == q0->o.x && ql->o.y == q0->o.y && ql->o.z == q0->o.z) ||
            !(ql->tmin >= 0 && ql->tmax > ql->tmin))
            continue;
        ok |= 1u << l;
        a->tmin[l] = f_down_tmin(ql->tmin);
        s->best[l].t = gg_next_down(ql->tmax);
        a->tmax[l] = f_above(s->best[l].t);
        s->best[l].prim = UINT32_MAX, s->best[l].sub = 0;
        s->best[l].b1 = s->best[l].b2 = 0;
    }
    return ok & pk_inverses(a, d);
}

/* The lanes of todo with the signs of its first. */
static inline unsigned pk_same(const pk_all *a, unsigned todo)
{
    int i0 = lowest_bit(todo), k;
    for (k = 0; k < 3; k++) todo &= a->neg[k] >> i0 & 1 ? a->neg[k] : ~a->neg[k];
    return todo;
}

/* The packet of lanes grp (one origin, one set of signs) into p: each
   lane's terms, or the first lane's for lanes outside it, and their
   interval. */
static void pk_pack(pkt *p, const pk_all *a, unsigned grp)
{
    const int i0 = lowest_bit(grp);
    int k, l, sm = 0;
    for (k = 0; k < 3; k++) sm |= (int)(a->neg[k] >> i0 & 1) << k;
    memcpy(p->nr, PK_ROWS[sm][0], sizeof p->nr);
    memcpy(p->fr, PK_ROWS[sm][1], sizeof p->fr);
    p->lanes = grp;
    for (k = 0; k < 3; k++) {
        p->on[k] = sm >> k & 1 ? a->dn[k] : a->up[k];
        p->of[k] = sm >> k & 1 ? a->up[k] : a->dn[k];
        p->on4[k] = GG_T4(p->on[k]), p->of4[k] = GG_T4(p->of[k]);
    }
#ifdef GG_BVH_SIMD
    {
        const __m128i bit = _mm_setr_epi32(1, 2, 4, 8);
        __m128 v0[3], vf0[3], lo[3], hi[3], flo[3], fhi[3];
        for (k = 0; k < 3; k++) {
            v0[k] = lo[k] = hi[k] = _mm_set1_ps(a->inv[k][i0]);
            vf0[k] = flo[k] = fhi[k] = _mm_set1_ps(a->invf[k][i0]);
        }
        for (l = 0; l < GG_PK; l += 4) {
            __m128i b = _mm_and_si128(_mm_set1_epi32((int)(grp >> l)), bit);
            __m128 in = _mm_castsi128_ps(_mm_cmpeq_epi32(b, bit));
            for (k = 0; k < 3; k++) {
                __m128 v = _mm_or_ps(_mm_and_ps(in, _mm_loadu_ps(a->inv[k] + l)),
                                     _mm_andnot_ps(in, v0[k]));
                __m128 vf = _mm_or_ps(_mm_and_ps(in, _mm_loadu_ps(a->invf[k] + l)),
                                      _mm_andnot_ps(in, vf0[k]));
                _mm_store_ps(p->inv[k] + l, v);
                _mm_store_ps(p->invf[k] + l, vf);
                lo[k] = _mm_min_ps(lo[k], v), hi[k] = _mm_max_ps(hi[k], v);
                flo[k] = _mm_min_ps(flo[k], vf), fhi[k] = _mm_max_ps(fhi[k], vf);
            }
            _mm_store_ps(p->tmin + l, _mm_loadu_ps(a->tmin + l));
            _mm_store_ps(p->tmax + l, _mm_or_ps(_mm_and_ps(in, _mm_loadu_ps(a->tmax + l)),
                                                _mm_andnot_ps(in, _mm_set1_ps(-INFINITY))));
        }
        {
            /* the lanes outside grp only lower it: still a bound */
            __m128 t = _mm_min_ps(_mm_min_ps(_mm_load_ps(p->tmin), _mm_load_ps(p->tmin + 4)),
                                  _mm_min_ps(_mm_load_ps(p->tmin + 8), _mm_load_ps(p->tmin + 12)));
            t = _mm_min_ps(t, _mm_movehl_ps(t, t));
            p->tminp = _mm_cvtss_f32(_mm_min_ss(t, _mm_shuffle_ps(t, t, 1)));
        }
        /* the extremes of the four lanes, in all four */
        for (k = 0; k < 3; k++) {
            lo[k] = _mm_min_ps(lo[k], _mm_shuffle_ps(lo[k], lo[k], 0x4e));
            hi[k] = _mm_max_ps(hi[k], _mm_shuffle_ps(hi[k], hi[k], 0x4e));
            flo[k] = _mm_min_ps(flo[k], _mm_shuffle_ps(flo[k], flo[k], 0x4e));
            fhi[k] = _mm_max_ps(fhi[k], _mm_shuffle_ps(fhi[k], fhi[k], 0x4e));
            p->ilo[k] = _mm_min_ps(lo[k], _mm_shuffle_ps(lo[k], lo[k], 0xb1));
            p->ihi[k] = _mm_max_ps(hi[k], _mm_shuffle_ps(hi[k], hi[k], 0xb1));
            p->iflo[k] = _mm_min_ps(flo[k], _mm_shuffle_ps(flo[k], flo[k], 0xb1));
            p->ifhi[k] = _mm_max_ps(fhi[k], _mm_shuffle_ps(fhi[k], fhi[k], 0xb1));
        }
#ifdef GG_TRAV_WIDE
#define PK_TO8(x) _mm256_insertf128_ps(_mm256_castps128_ps256(x), (x), 1)
        for (k = 0; k < 3; k++) {
            p->on8[k] = PK_TO8(p->on4[k]), p->of8[k] = PK_TO8(p->of4[k]);
            p->ilo8[k] = PK_TO8(p->ilo[k]), p->ihi8[k] = PK_TO8(p->ihi[k]);
            p->iflo8[k] = PK_TO8(p->iflo[k]), p->ifhi8[k] = PK_TO8(p->ifhi[k]);
        }
#undef PK_TO8
#endif
    }
#else
    for (k = 0; k < 3; k++) {
        float lo = a->inv[k][i0], hi = lo, flo = a->invf[k][i0], fhi = flo;
        for (l = 0; l < GG_PK; l++) {
            int in = grp >> l & 1;
            float v = in ? a->inv[k][l] : a->inv[k][i0], vf = in ? a->invf[k][l] : a->invf[k][i0];
            p->inv[k][l] = v, p->invf[k][l] = vf;
            lo = v < lo ? v : lo, hi = v > hi ? v : hi;
            flo = vf < flo ? vf : flo, fhi = vf > fhi ? vf : fhi;
        }
        p->ilo[k] = lo, p->ihi[k] = hi, p->iflo[k] = flo, p->ifhi[k] = fhi;
    }
    p->tminp = a->tmin[i0];
    for (l = 0; l < GG_PK; l++) {
        p->tmin[l] = a->tmin[l];
        p->tmax[l] = grp >> l & 1 ? a->tmax[l] : -INFINITY;
        p->tminp = p->tmin[l] < p->tminp ? p->tmin[l] : p->tminp;
    }
#endif
}

/* The interval box test of the four child boxes of nd for every lane of
   p: box4's contract (the mask of boxes that may be entered, and entry
   distances) for all the lanes at once, each distance <= every lane's. */
#ifdef GG_BVH_SIMD
static inline int pk_box4(const gg_bnode *nd, const pkt *p, __m128 tmin4, __m128 tmax4,
                          float tn_out[4])
{
    __m128 a[3], b[3], tn, tf;
    int k;
    for (k = 0; k < 3; k++) {
        __m128 s = _mm_sub_ps(_mm_load_ps(GG_ROW(nd, p->nr[k])), p->on4[k]);
        __m128 e = _mm_sub_ps(_mm_load_ps(GG_ROW(nd, p->fr[k])), p->of4[k]);
        a[k] = _mm_min_ps(_mm_mul_ps(s, p->ilo[k]), _mm_mul_ps(s, p->ihi[k]));
        b[k] = _mm_max_ps(_mm_mul_ps(e, p->iflo[k]), _mm_mul_ps(e, p->ifhi[k]));
    }
    tn = _mm_max_ps(_mm_max_ps(a[0], a[1]), _mm_max_ps(a[2], tmin4));
    tf = _mm_min_ps(_mm_min_ps(b[0], b[1]), _mm_min_ps(b[2], tmax4));
    _mm_store_ps(tn_out, tn);
    return _mm_movemask_ps(_mm_cmple_ps(tn, tf));
}
#else
static inline int pk_box4(const gg_bnode *nd, const pkt *p, float tmin, float tmax, float tn_out[4])
{
    int i, k, mask = 0;
    for (i = 0; i < 4; i++) {
        float tn = tmin, tf = tmax;
        for (k = 0; k < 3; k++) {
            float s = GG_ROW(nd, p->nr[k])[i] - p->on[k];
            float e = GG_ROW(nd, p->fr[k])[i] - p->of[k];
            float a0 = s * p->ilo[k], a1 = s * p->ihi[k];
            float b0 = e * p->iflo[k], b1 = e * p->ifhi[k];
            float a = a0 < a1 ? a0 : a1, b = b0 > b1 ? b0 : b1;
            tn = a > tn ? a : tn;
            tf = b < tf ? b : tf;
        }
        tn_out[i] = tn;
        if (tn <= tf) mask |= 1 << i;
    }
    return mask;
}
#endif

#ifdef GG_TRAV_WIDE
/* pk_box4 on the eight boxes of a wide node: the same operations in the
   same order, lane for lane. */
static inline unsigned pk_box8(const gg_wnode *nd, const pkt *p, __m256 tmin8, __m256 tmax8,
                               float tn_out[8])
{
    __m256 a[3], b[3], tn, tf;
    int k;
    for (k = 0; k < 3; k++) {
        __m256 s = _mm256_sub_ps(_mm256_load_ps(GG_ROW(nd, p->nr[k])), p->on8[k]);
        __m256 e = _mm256_sub_ps(_mm256_load_ps(GG_ROW(nd, p->fr[k])), p->of8[k]);
        a[k] = _mm256_min_ps(_mm256_mul_ps(s, p->ilo8[k]), _mm256_mul_ps(s, p->ihi8[k]));
        b[k] = _mm256_max_ps(_mm256_mul_ps(e, p->iflo8[k]), _mm256_mul_ps(e, p->ifhi8[k]));
    }
    tn = _mm256_max_ps(_mm256_max_ps(a[0], a[1]), _mm256_max_ps(a[2], tmin8));
    tf = _mm256_min_ps(_mm256_min_ps(b[0], b[1]), _mm256_min_ps(b[2], tmax8));
    _mm256_storeu_ps(tn_out, tn);
    return (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(tn, tf, _CMP_LE_OQ));
}
typedef __m256 pk_t;
#define PK_SET1(x)                     _mm256_set1_ps(x)
#define PK_BOX(nd, p, tmin, tmax, tn)  pk_box8(nd, p, tmin, tmax, tn)
#else
typedef gg_t4 pk_t;
#define PK_SET1(x)                     GG_T4(x)
#define PK_BOX(nd, p, tmin, tmax, tn)  (unsigned)pk_box4(nd, p, tmin, tmax, tn)
#endif

/* The lanes of p whose own box4 enters box i of nd: the same products
   s * inv, s' * invf and the same max, min and <= as box4's lane i
   (without NaN the order of max and min does not matter). */
static inline unsigned pk_lanes(const pk_node *nd, int i, const pkt *p)
{
    float s[3], e[3];
    unsigned m = 0;
    int k, l;
    for (k = 0; k < 3; k++) {
        s[k] = GG_ROW(nd, p->nr[k])[i] - p->on[k];
        e[k] = GG_ROW(nd, p->fr[k])[i] - p->of[k];
    }
/* Eight lanes a pass, also in the AVX-512 build: a 16-lane pass in one
   512-bit register made every walk of that build slower on an Intel Xeon
   (Sapphire Rapids), and 512-bit instructions are kept out of it
   (Makefile, ISA_avx512; docs/performance.md, "AVX-512 copies"). */
#if defined(GG_BVH_SIMD) && defined(__AVX__)
    for (l = 0; l < GG_PK; l += 8) {
        __m256 tn = _mm256_max_ps(
            _mm256_max_ps(_mm256_mul_ps(_mm256_set1_ps(s[0]), _mm256_loadu_ps(p->inv[0] + l)),
                          _mm256_mul_ps(_mm256_set1_ps(s[1]), _mm256_loadu_ps(p->inv[1] + l))),
            _mm256_max_ps(_mm256_mul_ps(_mm256_set1_ps(s[2]), _mm256_loadu_ps(p->inv[2] + l)),
                          _mm256_loadu_ps(p->tmin + l)));
        __m256 tf = _mm256_min_ps(
            _mm256_min_ps(_mm256_mul_ps(_mm256_set1_ps(e[0]), _mm256_loadu_ps(p->invf[0] + l)),
                          _mm256_mul_ps(_mm256_set1_ps(e[1]), _mm256_loadu_ps(p->invf[1] + l))),
            _mm256_min_ps(_mm256_mul_ps(_mm256_set1_ps(e[2]), _mm256_loadu_ps(p->invf[2] + l)),
                          _mm256_loadu_ps(p->tmax + l)));
        m |= (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(tn, tf, _CMP_LE_OQ)) << l;
    }
#elif defined(GG_BVH_SIMD)
    for (l = 0; l < GG_PK; l += 4) {
        __m128 tn =
            _mm_max_ps(_mm_max_ps(_mm_mul_ps(_mm_set1_ps(s[0]), _mm_load_ps(p->inv[0] + l)),
                                  _mm_mul_ps(_mm_set1_ps(s[1]), _mm_load_ps(p->inv[1] + l))),
                       _mm_max_ps(_mm_mul_ps(_mm_set1_ps(s[2]), _mm_load_ps(p->inv[2] + l)),
                                  _mm_load_ps(p->tmin + l)));
        __m128 tf =
            _mm_min_ps(_mm_min_ps(_mm_mul_ps(_mm_set1_ps(e[0]), _mm_load_ps(p->invf[0] + l)),
                                  _mm_mul_ps(_mm_set1_ps(e[1]), _mm_load_ps(p->invf[1] + l))),
                       _mm_min_ps(_mm_mul_ps(_mm_set1_ps(e[2]), _mm_load_ps(p->invf[2] + l)),
                                  _mm_load_ps(p->tmax + l)));
        m |= (unsigned)_mm_movemask_ps(_mm_cmple_ps(tn, tf)) << l;
    }
#else
    for (l = 0; l < GG_PK; l++) {
        float tn = p->tmin[l], tf = p->tmax[l];
        for (k = 0; k < 3; k++) {
            float a = s[k] * p->inv[k][l], b = e[k] * p->invf[k][l];
            tn = a > tn ? a : tn;
            tf = b < tf ? b : tf;
        }
        m |= (unsigned)(tn <= tf) << l;
    }
#endif
    return m & p->lanes;
}

/* The largest box-test bound of p's lanes. */
static inline float pk_tmax(const pkt *p)
{
#ifdef GG_BVH_SIMD
    __m128 t = _mm_max_ps(_mm_max_ps(_mm_load_ps(p->tmax), _mm_load_ps(p->tmax + 4)),
                          _mm_max_ps(_mm_load_ps(p->tmax + 8), _mm_load_ps(p->tmax + 12)));
    t = _mm_max_ps(t, _mm_movehl_ps(t, t));
    t = _mm_max_ss(t, _mm_shuffle_ps(t, t, 1));
    return _mm_cvtss_f32(t);
#else
    float t = p->tmax[0];
    int l;
    for (l = 1; l < GG_PK; l++) t = p->tmax[l] > t ? p->tmax[l] : t;
    return t;
#endif
}

/* A stack entry for child i of node `node`: a node index, or for a leaf
   GG_LEAF | node << PK_SHIFT | i, so that its box can be tested lane by
   lane (node indices are below GG_MAX_ELEMS = 2^28). */
static inline uint32_t pk_ref(const pk_node *nd, uint32_t node, int i)
{
    return nd->child[i] & GG_LEAF ? GG_LEAF | node << PK_SHIFT | (uint32_t)i : nd->child[i];
}

/* The children of mask, nearest (by the packet's entry distances) next,
   the others pushed farthest deepest, as bvh_intersect orders them. */
static inline uint32_t pk_descend(const pk_node *nd, uint32_t node, unsigned mask,
                                  const float tn[PK_W], uint32_t *stack, float *stack_t, int *sp)
{
    uint32_t rf[PK_W];
    float tt[PK_W];
    int k = 0, a, b;
    a = lowest_bit(mask);
    mask &= mask - 1;
    if (!mask) return pk_ref(nd, node, a);
    b = lowest_bit(mask);
    if (!(mask & (mask - 1))) {
        uint32_t c0 = pk_ref(nd, node, a), c1 = pk_ref(nd, node, b);
        int sw = tn[b] < tn[a];
        stack[*sp] = sw ? c0 : c1;
        stack_t[(*sp)++] = sw ? tn[a] : tn[b];
        return sw ? c1 : c0;
    }
    mask |= 1u << a;
    while (mask) {
        a = lowest_bit(mask);
        mask &= mask - 1;
        rf[k] = pk_ref(nd, node, a), tt[k++] = tn[a];
    }
    for (a = 1; a < k; a++)
        for (b = a; b > 0 && tt[b] > tt[b - 1]; b--) {
            float ft = tt[b];
            uint32_t fr = rf[b];
            tt[b] = tt[b - 1], rf[b] = rf[b - 1];
            tt[b - 1] = ft, rf[b - 1] = fr;
        }
    for (a = 0; a < k - 1; a++) stack[*sp] = rf[a], stack_t[(*sp)++] = tt[a];
    return rf[k - 1];
}

/* Leaf entry `box` (pk_ref) for the lanes whose box4 enters its box;
   returns whether any lane's closest hit came nearer. */
GG_INLINE int pk_leaf(const gg_geom *g, pkt *p, uint32_t box, pk_ray *s)
{
    const pk_node *nd = &PK_NODES(g)[(box & ~GG_LEAF) >> PK_SHIFT];
    const int i = (int)(box & (PK_W - 1));
    unsigned m = pk_lanes(nd, i, p);
    int found = 0;
    GG_COUNT(g, plane);
    while (m) {
        int l = lowest_bit(m);
        m &= m - 1;
        if (!(s->ready >> l & 1)) {
            s->ready |= 1u << l;
            if (!gg_rpre_fill(&s->r[l], &s->q[l])) { /* not for rays pk_setup took */
                p->tmax[l] = -INFINITY;
                continue;
            }
            tx_init(&s->tx[l], &s->r[l]);
        }
        if (tx_closest(g, &s->r[l], &s->tx[l], nd->child[i], &s->best[l])) {
            p->tmax[l] = f_above(s->best[l].t);
            found = 1;
        }
    }
    return found;
}

/* bvh_intersect's walk for packet p: pk_box4 for box4 with the
   bounds of all lanes (the smallest tmin, the largest tmax), leaves by
   pk_leaf. */
static void pk_walk(const gg_geom *g, pkt *p, pk_ray *s)
{
    uint32_t stack[PK_STACK], cur = 0;
    float stack_t[PK_STACK], tmaxf = pk_tmax(p), tcull = tmaxf * GG_EXIT_SCALE;
    int sp = 0;
    pk_t tmin4 = PK_SET1(p->tminp), tmax4;
    tmax4 = PK_SET1(tmaxf);
    for (;;) {
        if (!(cur & GG_LEAF)) {
            const pk_node *nd = &PK_NODES(g)[cur];
            float tn[PK_W];
            unsigned mask = PK_BOX(nd, p, tmin4, tmax4, tn);
            GG_COUNT(g, pbox4);
            if (mask) {
                cur = pk_descend(nd, cur, mask, tn, stack, stack_t, &sp);
                continue;
            }
        } else if (pk_leaf(g, p, cur, s)) {
            tmaxf = pk_tmax(p);
            tcull = tmaxf * GG_EXIT_SCALE;
            tmax4 = PK_SET1(tmaxf);
        }
        for (;;) {
            if (sp == 0) return;
            sp--;
            if (stack_t[sp] <= tcull) break;
        }
        cur = stack[sp];
    }
}

/* Closest hits of q[l] for the lanes l of `lanes` (below GG_PK): hit[l]
   and bit l of the result as GG_INC_NAME(bvh_intersect)(g, &q[l], &hit[l]) gives
   them. Lanes of one origin and one set of signs walk the tree together;
   a lane alone, or one a packet cannot take, is traced on its own. */
GG_INC_LINK GG_NO_SLP unsigned GG_INC_NAME(bvh_packet)(const gg_geom *g, const gg_rayq *q,
                                                       unsigned lanes, gg_hit *hit)
{
    pk_all a;
    pk_ray s;
    pkt p;
    unsigned todo, got = 0, m;
    lanes &= (1u << GG_PK) - 1;
    if (!g->built || !g->nslots || !lanes) return 0;
    todo = pk_setup(&a, &s, q, lanes);
    s.q = q, s.ready = 0;
    for (m = lanes & ~todo; m; m &= m - 1)
        if (GG_INC_NAME(bvh_intersect)(g, &q[lowest_bit(m)], &hit[lowest_bit(m)])) got |= m & -m;
    while (todo) {
        unsigned grp = pk_same(&a, todo);
        todo &= ~grp;
        if (!(grp & (grp - 1))) {
            if (GG_INC_NAME(bvh_intersect)(g, &q[lowest_bit(grp)], &hit[lowest_bit(grp)]))
                got |= grp;
            continue;
        }
        pk_pack(&p, &a, grp);
        GG_COUNT(g, packets);
        pk_walk(g, &p, &s);
        for (m = grp & s.ready; m; m &= m - 1) { /* (a lane that reached no leaf hit nothing) */
            int l = lowest_bit(m);
            if (s.best[l].prim == UINT32_MAX) continue;
            GG_COUNT(g, hits);
            hit[l] = s.best[l];
            got |= 1u << l;
        }
    }
    return got;
}

#endif /* GG_TRAV_SINGLE */
#endif /* GG_TRAV_COST */

#undef GG_ROWTABLE
#undef GG_ROWSET
#undef GG_ROWS
#undef GG_COUNT

#endif
