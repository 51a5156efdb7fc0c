/* SPDX-License-Identifier: MIT */
/*
** bvh_avx.c -- the BVH traversals compiled for x86-64 CPUs with AVX,
** which test the triangles of a leaf four at a time (one lane per
** triangle, 4 doubles per register): a per-ISA object, built with -mavx
** (compiler.h, "Per-ISA code"). bvh.c calls them only for a geometry
** whose build chose them (the kernel table, gg_cpu_kernels()->trav).
** The Makefile compiles this file once more, into bvh_avx2.o (ISA_AGAIN),
** with AVX2 and the bit instructions (BMI1/2, LZCNT, POPCNT), under names
** ending in _avx2 (GG_ISA_NAME): the same source and the same bits,
** chosen at run time where the CPU has them, as Embree builds one kernel
** source per instruction set; and once more into bvh_avx512.o with
** AVX-512 F, VL, DQ and BW (names ending in _avx512), where the node and
** triangle tests compare into mask registers and the any-hit walks push
** a node's children with one compress (__AVX512VL__ below). What the AVX2 build bought:
** docs/performance.md, "One source per instruction set".
**
** Same bits as the scalar kernel. Each lane performs exactly the
** operations of gg_tri_kernel (shape_tri.h), in the same order and
** precision: separate multiplies and adds (AVX has no fused multiply-add,
** so nothing can be contracted), IEEE division. The decisions that
** follow are then taken lane by lane in slot order, as the scalar loops
** take them: the ignored primitive and the skip flags, the running
** closest distance, the tie rule (gg_leaf_take), opaque versus
** transparent. The rare lane where an edge function is exactly zero (the
** ray through an edge or a vertex) goes to the scalar kernel, which
** settles the tie by the top-left rule.
*/
#include "core.h"

#include "bvh_int.h"

#if GG_HAVE_BVH_AVX
#if !defined(__AVX__) || !defined(GG_ISA)
#error "bvh_avx.c is compiled with -mavx and -DGG_ISA (Makefile: isa_flags)"
#endif

#include <immintrin.h>

/* Per-ray state of the 4-wide test: the ray's origin and shear broadcast
   to all lanes, and the byte offsets of the kx, ky, kz rows of a block.
   tx_fill fills it; tx_init leaves that to the first triangle block the
   ray reaches (ready = 0), which many closest-hit rays never do. */
typedef struct gg_tx {
    __m256d ox, oy, oz, sx, sy, sz, tmin;
    size_t rx, ry, rz;
    int ready;
} gg_tx;

/* What the 4-wide test found: lanes that hit with t <= tmax (hit), lanes
   to hand to the scalar kernel (zero), and t and the barycentrics of the
   hit lanes. */
typedef struct tri4_out {
    double t[4], b1[4], b2[4];
    unsigned hit, zero;
} tri4_out;

static inline void tx_init(gg_tx *x, const gg_rpre *r)
{
    (void)r;
    x->ready = 0;
}

static inline void tx_fill(gg_tx *x, const gg_rpre *r)
{
    x->ready = 1;
    x->ox = _mm256_set1_pd(r->o[r->kx]);
    x->oy = _mm256_set1_pd(r->o[r->ky]);
    x->oz = _mm256_set1_pd(r->o[r->kz]);
    x->sx = _mm256_set1_pd(r->sx);
    x->sy = _mm256_set1_pd(r->sy);
    x->sz = _mm256_set1_pd(r->sz);
    x->tmin = _mm256_set1_pd(r->tmin);
    x->rx = (size_t)r->kx * sizeof(double[3][4]);
    x->ry = (size_t)r->ky * sizeof(double[3][4]);
    x->rz = (size_t)r->kz * sizeof(double[3][4]);
}

#define GG_TROW(L, off) ((const double *)((const char *)(L)->v + (off)))

#ifdef __AVX512VL__
/* The AVX-512 build's second half of tri4_test: the same compares, each
   writing a mask register (no movemask, no and/or of vectors). */
GG_INLINE unsigned tri4_finish(const gg_tx *x, double tmax, __m256d zero, __m256d Az, __m256d Bz,
                               __m256d Cz, __m256d U, __m256d V, __m256d W, tri4_out *o)
{
    unsigned neg = _mm256_cmp_pd_mask(U, zero, _CMP_LT_OQ) |
                   _mm256_cmp_pd_mask(V, zero, _CMP_LT_OQ) |
                   _mm256_cmp_pd_mask(W, zero, _CMP_LT_OQ);
    unsigned pos = _mm256_cmp_pd_mask(U, zero, _CMP_GT_OQ) |
                   _mm256_cmp_pd_mask(V, zero, _CMP_GT_OQ) |
                   _mm256_cmp_pd_mask(W, zero, _CMP_GT_OQ);
    __m256d det = _mm256_add_pd(_mm256_add_pd(U, V), W), T, rcp, tt;
    unsigned lm = ~(neg & pos) & _mm256_cmp_pd_mask(det, zero, _CMP_NEQ_UQ), zm, hm;
    if (!lm) return 0;
    zm = (_mm256_cmp_pd_mask(U, zero, _CMP_EQ_OQ) | _mm256_cmp_pd_mask(V, zero, _CMP_EQ_OQ) |
          _mm256_cmp_pd_mask(W, zero, _CMP_EQ_OQ)) &
         lm;
    T = _mm256_mul_pd(x->sz,
                      _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(U, Az), _mm256_mul_pd(V, Bz)),
                                    _mm256_mul_pd(W, Cz)));
    rcp = _mm256_div_pd(_mm256_set1_pd(1.0), det);
    tt = _mm256_mul_pd(T, rcp);
    hm = _mm256_cmp_pd_mask(tt, x->tmin, _CMP_GT_OQ) &
         _mm256_cmp_pd_mask(tt, _mm256_set1_pd(tmax), _CMP_LE_OQ) & lm & ~zm;
    o->zero = zm;
    o->hit = hm;
    if (hm) {
        _mm256_storeu_pd(o->t, tt);
        _mm256_storeu_pd(o->b1, _mm256_mul_pd(V, rcp));
        _mm256_storeu_pd(o->b2, _mm256_mul_pd(W, rcp));
    }
    return hm | zm;
}
#endif

/* gg_tri_kernel on the four lanes of block L with t in (tmin, tmax].
   Returns o->hit | o->zero; o->t, b1, b2 are filled when o->hit != 0. */
GG_INLINE unsigned tri4_test(const gg_tleaf *L, const gg_tx *x, double tmax, tri4_out *o)
{
    const double *X = GG_TROW(L, x->rx), *Y = GG_TROW(L, x->ry), *Z = GG_TROW(L, x->rz);
    const __m256d zero = _mm256_setzero_pd();
    __m256d Az = _mm256_sub_pd(_mm256_load_pd(Z), x->oz);
    __m256d Bz = _mm256_sub_pd(_mm256_load_pd(Z + 4), x->oz);
    __m256d Cz = _mm256_sub_pd(_mm256_load_pd(Z + 8), x->oz);
    __m256d ax = _mm256_sub_pd(_mm256_sub_pd(_mm256_load_pd(X), x->ox), _mm256_mul_pd(x->sx, Az));
    __m256d ay = _mm256_sub_pd(_mm256_sub_pd(_mm256_load_pd(Y), x->oy), _mm256_mul_pd(x->sy, Az));
    __m256d bx =
        _mm256_sub_pd(_mm256_sub_pd(_mm256_load_pd(X + 4), x->ox), _mm256_mul_pd(x->sx, Bz));
    __m256d by =
        _mm256_sub_pd(_mm256_sub_pd(_mm256_load_pd(Y + 4), x->oy), _mm256_mul_pd(x->sy, Bz));
    __m256d cx =
        _mm256_sub_pd(_mm256_sub_pd(_mm256_load_pd(X + 8), x->ox), _mm256_mul_pd(x->sx, Cz));
    __m256d cy =
        _mm256_sub_pd(_mm256_sub_pd(_mm256_load_pd(Y + 8), x->oy), _mm256_mul_pd(x->sy, Cz));
    __m256d U = _mm256_sub_pd(_mm256_mul_pd(cx, by), _mm256_mul_pd(cy, bx));
    __m256d V = _mm256_sub_pd(_mm256_mul_pd(ax, cy), _mm256_mul_pd(ay, cx));
    __m256d W = _mm256_sub_pd(_mm256_mul_pd(bx, ay), _mm256_mul_pd(by, ax));
#ifdef __AVX512VL__
    return tri4_finish(x, tmax, zero, Az, Bz, Cz, U, V, W, o);
#else
    __m256d neg = _mm256_or_pd(
        _mm256_or_pd(_mm256_cmp_pd(U, zero, _CMP_LT_OQ), _mm256_cmp_pd(V, zero, _CMP_LT_OQ)),
        _mm256_cmp_pd(W, zero, _CMP_LT_OQ));
    __m256d pos = _mm256_or_pd(
        _mm256_or_pd(_mm256_cmp_pd(U, zero, _CMP_GT_OQ), _mm256_cmp_pd(V, zero, _CMP_GT_OQ)),
        _mm256_cmp_pd(W, zero, _CMP_GT_OQ));
    __m256d det = _mm256_add_pd(_mm256_add_pd(U, V), W);
    /* lanes the scalar kernel would get past its sign and det tests with */
    __m256d live = _mm256_andnot_pd(_mm256_and_pd(neg, pos), _mm256_cmp_pd(det, zero, _CMP_NEQ_UQ));
    __m256d z, T, rcp, tt, in;
    unsigned lm = (unsigned)_mm256_movemask_pd(live), zm, hm;
    if (!lm) return 0;
    z = _mm256_or_pd(
        _mm256_or_pd(_mm256_cmp_pd(U, zero, _CMP_EQ_OQ), _mm256_cmp_pd(V, zero, _CMP_EQ_OQ)),
        _mm256_cmp_pd(W, zero, _CMP_EQ_OQ));
    zm = (unsigned)_mm256_movemask_pd(z) & lm;
    T = _mm256_mul_pd(x->sz,
                      _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(U, Az), _mm256_mul_pd(V, Bz)),
                                    _mm256_mul_pd(W, Cz)));
    rcp = _mm256_div_pd(_mm256_set1_pd(1.0), det);
    tt = _mm256_mul_pd(T, rcp);
    in = _mm256_and_pd(_mm256_cmp_pd(tt, x->tmin, _CMP_GT_OQ),
                       _mm256_cmp_pd(tt, _mm256_set1_pd(tmax), _CMP_LE_OQ));
    hm = (unsigned)_mm256_movemask_pd(in) & lm & ~zm;
    o->zero = zm;
    o->hit = hm;
    if (hm) {
        _mm256_storeu_pd(o->t, tt);
        _mm256_storeu_pd(o->b1, _mm256_mul_pd(V, rcp));
        _mm256_storeu_pd(o->b2, _mm256_mul_pd(W, rcp));
    }
    return hm | zm;
#endif
}

unsigned GG_ISA_NAME(gg_bvh_tri4)(const gg_tleaf *L, const gg_rpre *r, double tmax, double t[4],
                                  double b1[4], double b2[4], unsigned *zero)
{
    gg_tx x;
    tri4_out o;
    unsigned m;
    /* (GCC cannot follow the AVX-512 build's masks to the stores) */
    memset(&o, 0, sizeof o);
    tx_fill(&x, r);
    m = tri4_test(L, &x, tmax, &o);
    *zero = m ? o.zero : 0;
    if (m & ~*zero) {
        memcpy(t, o.t, sizeof o.t);
        memcpy(b1, o.b1, sizeof o.b1);
        memcpy(b2, o.b2, sizeof o.b2);
    }
    return m & ~*zero;
}

static inline int lowest_lane(unsigned m)
{
    return GG_CTZ(m);
}

/* Lane i of the block against tmax: from the 4-wide result, or from the
   scalar kernel for a lane with a zero edge function. */
GG_INLINE int tri4_lane(const gg_geom *g, const gg_rpre *r, const gg_slot *s, const tri4_out *o,
                        int i, double tmax, double *t, double *b1, double *b2)
{
    if (o->zero >> i & 1) return gg_tri_kernel(&g->ltri[s->ki & GG_EK_INDEX], r, tmax, t, b1, b2);
    if (!(o->t[i] <= tmax)) return 0;
    *t = o->t[i], *b1 = o->b1[i], *b2 = o->b2[i];
    return 1;
}

GG_INLINE int tx_closest(const gg_geom *g, const gg_rpre *r, gg_tx *x, uint32_t ref, gg_hit *best)
{
    const gg_tleaf *L;
    tri4_out o;
    unsigned m;
    int found = 0;
    if (!(ref & GG_TLEAF)) return gg_leaf_closest(g, r, GG_LEAF_I(ref), GG_LEAF_N(ref), best);
    L = &g->tleaves[GG_LEAF_I(ref)];
    if (!x->ready) tx_fill(x, r);
    m = tri4_test(L, x, best->t, &o);
    while (m) {
        int i = lowest_lane(m);
        const gg_slot *s = g->slots + L->first + i;
        double t, b1, b2;
        m &= m - 1;
        if (s->prim == r->ignore) continue;
        if (r->skip && (g->pflags[s->prim] & r->skip)) continue;
        /* best->t may have come down since the 4-wide test */
        if (!tri4_lane(g, r, s, &o, i, best->t, &t, &b1, &b2)) continue;
        found |= gg_leaf_take(best, s, t, b1, b2);
    }
    return found;
}

GG_INLINE uint32_t tx_any(const gg_geom *g, const gg_rpre *r, gg_tx *x, uint32_t ref, double tmax)
{
    const gg_tleaf *L;
    tri4_out o;
    unsigned m;
    if (!(ref & GG_TLEAF)) return gg_leaf_any(g, r, GG_LEAF_I(ref), GG_LEAF_N(ref), tmax);
    L = &g->tleaves[GG_LEAF_I(ref)];
    if (!x->ready) tx_fill(x, r);
    m = tri4_test(L, x, tmax, &o);
    while (m) {
        int i = lowest_lane(m);
        const gg_slot *s = g->slots + L->first + i;
        double t, b1, b2;
        m &= m - 1;
        if (s->prim == r->ignore) continue;
        if (r->skip && (g->pflags[s->prim] & r->skip)) continue;
        if (tri4_lane(g, r, s, &o, i, tmax, &t, &b1, &b2)) return L->first + (uint32_t)i + 1;
    }
    return 0;
}

GG_INLINE uint32_t tx_shadow(const gg_geom *g, const gg_rpre *r, gg_tx *x, uint32_t ref,
                             double tmax, gg_hit *best, gg_tcol *col)
{
    const gg_tleaf *L;
    tri4_out o;
    unsigned m;
    if (!(ref & GG_TLEAF))
        return gg_leaf_shadow(g, r, GG_LEAF_I(ref), GG_LEAF_N(ref), tmax, best, col);
    L = &g->tleaves[GG_LEAF_I(ref)];
    if (!x->ready) tx_fill(x, r);
    /* best->t <= tmax: the test against tmax keeps every lane either
       bound accepts. */
    m = tri4_test(L, x, tmax, &o);
    while (m) {
        int i = lowest_lane(m);
        const gg_slot *s = g->slots + L->first + i;
        double t, b1, b2;
        m &= m - 1;
        if (s->prim == r->ignore) continue;
        if (!(g->pflags[s->prim] & GG_PRIM_TRANSPARENT)) {
            if (tri4_lane(g, r, s, &o, i, tmax, &t, &b1, &b2)) return L->first + (uint32_t)i + 1;
            continue;
        }
        if (col) {
            if (!tri4_lane(g, r, s, &o, i, tmax, &t, &b1, &b2)) continue;
            gg_tcol_add(col, s, t, b1, b2, g->clipped); /* a triangle: one root */
            if (t <= best->t) gg_leaf_take(best, s, t, b1, b2);
        } else if (tri4_lane(g, r, s, &o, i, best->t, &t, &b1, &b2))
            gg_leaf_take(best, s, t, b1, b2);
    }
    return 0;
}

/* Runs of slots (the occluder cache, the fallbacks): the scalar loops. */
GG_INLINE uint32_t tx_slots_any(const gg_geom *g, const gg_rpre *r, uint32_t first, uint32_t n,
                                double tmax)
{
    return gg_leaf_any(g, r, first, n, tmax);
}

GG_INLINE uint32_t tx_slots_shadow(const gg_geom *g, const gg_rpre *r, uint32_t first, uint32_t n,
                                   double tmax, gg_hit *best, gg_tcol *col)
{
    return gg_leaf_shadow(g, r, first, n, tmax, best, col);
}

#define GG_TRAV_WIDE   /* the single-ray walks on the 8-wide nodes (bvh_trav.inc.h) */
#define GG_INC_NAME(f) GG_ISA_NAME(gg_##f) /* gg_bvh_intersect_avx, ..._avx2 */
#define GG_INC_LINK                        /* external: declared in bvh_int.h */
#include "bvh_trav.inc.h"

#else
/* ISO C forbids an empty translation unit. */
typedef int gg_bvh_avx_unused;
#endif
