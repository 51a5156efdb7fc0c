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
**
** Counting. The Makefile builds this file once more, into bvh_count_avx.o
** (AVX, with -DGG_TRAV_COUNT): names ending in _count, every walk and
** leaf test counting its kernel calls into g->kcount (gg_kcount, geom.h),
** for `ggrt bench limit`. The walk and the leaves are this source's, so
** the counts are those of the AVX, AVX2 and AVX-512 builds alike; those
** builds count nothing (GG_KCOUNT below is empty there).
** And into bvh_kloop_avx.o, bvh_kloop_avx2.o, bvh_kloop_avx512.o
** (-DGG_TRAV_KLOOP): the kernels alone in loops, gg_bvh_kloop_*, each
** ISA's kernels as its walks inline them, in objects of their own so that
** the walks' objects stay as they were (a second caller of the packet
** set-up changed what GCC inlines into the packet walk).
*/
#include "core.h"

#include "bvh_int.h"

#if GG_HAVE_BVH_AVX
#if !defined(__AVX__) || !defined(GG_ISA)
#error "bvh_avx.c is compiled with -mavx and -DGG_ISA (Makefile: isa_flags)"
#endif

#include <immintrin.h>

#ifdef GG_TRAV_COUNT
#define GG_KCOUNT(g, f) ((void)((g)->kcount->f++))
#define GG_KNAME(f)     gg_##f##_count
#elif defined(GG_TRAV_KLOOP)
/* the kernel loops' build: the walks only as a source of kernels */
#define GG_KCOUNT(g, f) ((void)0)
#define GG_KNAME(f)     f##_unused
#else
#define GG_KCOUNT(g, f) ((void)0)
#define GG_KNAME(f)     GG_ISA_NAME(gg_##f)
#endif

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

/* tri4_test's distances: the scalar kernel's sz (U Az + V Bz + W Cz) / det
   in each lane, as T * (1 / det); *rcp gets 1 / det. */
GG_INLINE __m256d tri4_dist(const gg_tx *x, __m256d Az, __m256d Bz, __m256d Cz, __m256d U,
                            __m256d V, __m256d W, __m256d det, __m256d *rcp)
{
    __m256d T = _mm256_mul_pd(
        x->sz, _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(U, Az), _mm256_mul_pd(V, Bz)),
                             _mm256_mul_pd(W, Cz)));
    *rcp = _mm256_div_pd(_mm256_set1_pd(1.0), det);
    return _mm256_mul_pd(T, *rcp);
}

/* tri4_test's answer: the hit and zero masks, and t, b1, b2 if a lane hits. */
GG_INLINE unsigned tri4_put(tri4_out *o, unsigned hm, unsigned zm, __m256d tt, __m256d V,
                            __m256d W, __m256d rcp)
{
    o->zero = zm;
    o->hit = hm;
    if (hm) {
        _mm256_storeu_pd(o->t, tt);
        _mm256_storeu_pd(o->b1, _mm256_mul_pd(V, rcp));
        _mm256_storeu_pd(o->b2, _mm256_mul_pd(W, rcp));
    }
    return hm | zm;
}

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
    __m256d det = _mm256_add_pd(_mm256_add_pd(U, V), W), rcp, tt;
    unsigned lm = ~(neg & pos) & _mm256_cmp_pd_mask(det, zero, _CMP_NEQ_UQ), zm, hm;
    if (!lm) return 0;
    zm = (_mm256_cmp_pd_mask(U, zero, _CMP_EQ_OQ) | _mm256_cmp_pd_mask(V, zero, _CMP_EQ_OQ) |
          _mm256_cmp_pd_mask(W, zero, _CMP_EQ_OQ)) &
         lm;
    tt = tri4_dist(x, Az, Bz, Cz, U, V, W, det, &rcp);
    hm = _mm256_cmp_pd_mask(tt, x->tmin, _CMP_GT_OQ) &
         _mm256_cmp_pd_mask(tt, _mm256_set1_pd(tmax), _CMP_LE_OQ) & lm & ~zm;
    return tri4_put(o, hm, zm, tt, V, W, rcp);
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
    __m256d z, rcp, tt, in;
    unsigned lm = (unsigned)_mm256_movemask_pd(live), zm, hm;
    if (!lm) return 0;
    z = _mm256_or_pd(
        _mm256_or_pd(_mm256_cmp_pd(U, zero, _CMP_EQ_OQ), _mm256_cmp_pd(V, zero, _CMP_EQ_OQ)),
        _mm256_cmp_pd(W, zero, _CMP_EQ_OQ));
    zm = (unsigned)_mm256_movemask_pd(z) & lm;
    tt = tri4_dist(x, Az, Bz, Cz, U, V, W, det, &rcp);
    in = _mm256_and_pd(_mm256_cmp_pd(tt, x->tmin, _CMP_GT_OQ),
                       _mm256_cmp_pd(tt, _mm256_set1_pd(tmax), _CMP_LE_OQ));
    hm = (unsigned)_mm256_movemask_pd(in) & lm & ~zm;
    return tri4_put(o, hm, zm, tt, V, W, rcp);
#endif
}

#if !defined(GG_TRAV_COUNT) && !defined(GG_TRAV_KLOOP)
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
#endif

static inline int lowest_lane(unsigned m)
{
    return GG_CTZ(m);
}

/* Lane i of the block against tmax: from the 4-wide result, or from the
   scalar kernel for a lane with a zero edge function. */
GG_INLINE int tri4_lane(const gg_geom *g, const gg_rpre *r, const gg_slot *s, const tri4_out *o,
                        int i, double tmax, double *t, double *b1, double *b2)
{
    if (o->zero >> i & 1) {
        GG_KCOUNT(g, tri);
        return gg_tri_kernel(&g->ltri[s->ki & GG_EK_INDEX], r, tmax, t, b1, b2);
    }
    if (!(o->t[i] <= tmax)) return 0;
    *t = o->t[i], *b1 = o->b1[i], *b2 = o->b2[i];
    return 1;
}

/* The scalar loops over a run of slots (geom_leaf.h); in the counting
   build slot by slot (the same tests in the same order: each loop is a
   sequence of one-slot steps), counting each element tested. */
#ifdef GG_TRAV_COUNT
static void count_slot(const gg_geom *g, const gg_rpre *r, const gg_slot *s, int skip)
{
    if (s->prim == r->ignore || (skip && r->skip && (g->pflags[s->prim] & r->skip))) return;
    switch (s->ki >> GG_EK_SHIFT) {
    case GG_EK_TRI:
        g->kcount->tri++;
        break;
    case GG_EK_SPHERE:
        g->kcount->sphere++;
        break;
    default:
        g->kcount->other++;
    }
}

static int leaf_closest(const gg_geom *g, const gg_rpre *r, uint32_t first, uint32_t n,
                        gg_hit *best)
{
    uint32_t i;
    int found = 0;
    for (i = 0; i < n; i++) {
        count_slot(g, r, &g->slots[first + i], 1);
        found |= gg_leaf_closest(g, r, first + i, 1, best);
    }
    return found;
}

static uint32_t leaf_any(const gg_geom *g, const gg_rpre *r, uint32_t first, uint32_t n,
                         double tmax)
{
    uint32_t i, h;
    for (i = 0; i < n; i++) {
        count_slot(g, r, &g->slots[first + i], 1);
        if ((h = gg_leaf_any(g, r, first + i, 1, tmax))) return h;
    }
    return 0;
}

static uint32_t leaf_shadow(const gg_geom *g, const gg_rpre *r, uint32_t first, uint32_t n,
                            double tmax, gg_hit *best, gg_tcol *col)
{
    uint32_t i, h;
    for (i = 0; i < n; i++) {
        count_slot(g, r, &g->slots[first + i], 0);
        if ((h = gg_leaf_shadow(g, r, first + i, 1, tmax, best, col))) return h;
    }
    return 0;
}
#else
#define leaf_closest gg_leaf_closest
#define leaf_any     gg_leaf_any
#define leaf_shadow  gg_leaf_shadow
#endif

GG_INLINE int tx_closest(const gg_geom *g, const gg_rpre *r, gg_tx *x, uint32_t ref, gg_hit *best)
{
    const gg_tleaf *L;
    tri4_out o;
    unsigned m;
    int found = 0;
    if (!(ref & GG_TLEAF)) return leaf_closest(g, r, GG_LEAF_I(ref), GG_LEAF_N(ref), best);
    L = &g->tleaves[GG_LEAF_I(ref)];
    if (!x->ready) tx_fill(x, r);
    GG_KCOUNT(g, tri4);
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
    if (!(ref & GG_TLEAF)) return leaf_any(g, r, GG_LEAF_I(ref), GG_LEAF_N(ref), tmax);
    L = &g->tleaves[GG_LEAF_I(ref)];
    if (!x->ready) tx_fill(x, r);
    GG_KCOUNT(g, tri4);
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
        return leaf_shadow(g, r, GG_LEAF_I(ref), GG_LEAF_N(ref), tmax, best, col);
    L = &g->tleaves[GG_LEAF_I(ref)];
    if (!x->ready) tx_fill(x, r);
    /* best->t <= tmax: the test against tmax keeps every lane either
       bound accepts. */
    GG_KCOUNT(g, tri4);
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
    return leaf_any(g, r, first, n, tmax);
}

GG_INLINE uint32_t tx_slots_shadow(const gg_geom *g, const gg_rpre *r, uint32_t first, uint32_t n,
                                   double tmax, gg_hit *best, gg_tcol *col)
{
    return leaf_shadow(g, r, first, n, tmax, best, col);
}

#define GG_TRAV_WIDE   /* the single-ray walks on the 8-wide nodes (bvh_trav.inc.h) */
#define GG_INC_NAME(f) GG_KNAME(f) /* gg_bvh_intersect_avx, ..._avx2, ..._count */
#ifdef GG_TRAV_KLOOP
#define GG_INC_LINK static __attribute__((unused))
#else
#define GG_INC_LINK /* external: declared in bvh_int.h */
#endif
#include "bvh_trav.inc.h"

#ifdef GG_TRAV_KLOOP
/* ---- the kernels alone, in a loop (gg_geom_kloop, `ggrt bench limit`) ---- */

/* Read once per loop: the compiler cannot know it is 0, so `x & kl_zero`
   makes each call's input depend on the last call's result. */
static volatile uint32_t kl_zero_v;

/* A point of the element in slot s (its box's centre), or of the scene. */
static void kl_aim(const gg_geom *g, const gg_slot *s, double p[3])
{
    double lo[3], hi[3];
    uint32_t idx = s ? s->ki & GG_EK_INDEX : 0;
    int k;
    memcpy(lo, &g->lo, sizeof lo), memcpy(hi, &g->hi, sizeof hi);
    if (s) switch (s->ki >> GG_EK_SHIFT) {
        case GG_EK_TRI:
            gg_tri_bounds(&g->ltri[idx], lo, hi);
            break;
        case GG_EK_SPHERE:
            for (k = 0; k < 3; k++) lo[k] = hi[k] = g->lsph[idx].c[k];
            break;
        case GG_EK_CONE:
            gg_cone_bounds(&g->lcone[idx], lo, hi);
            break;
        case GG_EK_POLY:
            gg_poly_bounds(g, &g->polys[idx], lo, hi);
            break;
        default:
            break;
        }
    for (k = 0; k < 3; k++) p[k] = 0.5 * (lo[k] + hi[k]);
}

/* The first slot of kind `kind` (-1: of none of triangle and sphere). */
static const gg_slot *kl_slot(const gg_geom *g, int kind)
{
    size_t i;
    for (i = 0; i < g->nslots; i++) {
        int k = (int)(g->slots[i].ki >> GG_EK_SHIFT);
        if (kind >= 0 ? k == kind : k != GG_EK_TRI && k != GG_EK_SPHERE) return &g->slots[i];
    }
    return NULL;
}

/* The ray from q's origin to p (t = 1 at p, tmax far beyond). */
static int kl_ray(gg_rpre *r, gg_rayq *q, const double p[3])
{
    q->d.x = p[0] - q->o.x, q->d.y = p[1] - q->o.y, q->d.z = p[2] - q->o.z;
    q->tmin = 0, q->tmax = 1e30;
    return gg_rpre_fill(r, q);
}

static double kl_box8(const gg_geom *g, const gg_rayq *q, long n)
{
    wtrav tv;
    float tn[8];
    double sum = 0;
    const uint32_t z = kl_zero_v;
    const gg_wnode *nd = g->wnodes;
    __m256 tmin8 = _mm256_set1_ps(f_down_tmin(q->tmin)), tmax8 = _mm256_set1_ps(f_above(q->tmax));
    long i;
    if (!g->wnodes || !wtrav_init6(&tv, q->o.x, q->o.y, q->o.z, q->d.x, q->d.y, q->d.z)) return -1;
    for (i = 0; i < n; i++) {
        unsigned m = box8(nd, &tv, tmin8, tmax8, tn);
        sum += m;
        nd = g->wnodes + (m & z);
    }
    return sum + tn[0];
}

/* Sixteen rays from q's origin around q's direction, all of one sign. */
static double kl_packet(const gg_geom *g, const gg_rayq *q, int k, long n)
{
    gg_rayq qs[GG_PK];
    pk_all a;
    pk_ray s;
    pkt p;
    float tn[PK_W];
    double sum = 0;
    const uint32_t z = kl_zero_v;
    const pk_node *nd = PK_NODES(g);
    unsigned grp;
    long i;
    int l;
    for (l = 0; l < GG_PK; l++) {
        qs[l] = *q;
        /* (added, not scaled: a component 0 would stay 0, and 1/0 takes
           a lane out of a packet) */
        qs[l].d.x += 1e-3 * (1 + (l & 3)), qs[l].d.y += 1e-3 * (1 + (l >> 2));
        qs[l].d.z += 1e-3;
    }
    grp = pk_setup(&a, &s, qs, (1u << GG_PK) - 1);
    if (grp != (1u << GG_PK) - 1 || pk_same(&a, grp) != grp) return -1;
    pk_pack(&p, &a, grp);
    for (i = 0; i < n; i++) {
        unsigned m = k == GG_KL_PBOX4 ? PK_BOX(nd, &p, PK_SET1(p.tminp), PK_SET1(pk_tmax(&p)), tn)
                                      : pk_lanes(nd, 0, &p);
        sum += m;
        nd = PK_NODES(g) + (m & z);
    }
    return sum;
}

static double kl_tri4(const gg_geom *g, const gg_rpre *r, long n)
{
    gg_tx x;
    tri4_out o;
    double sum = 0;
    const uint32_t z = kl_zero_v;
    const gg_tleaf *L = g->tleaves;
    long i;
    memset(&o, 0, sizeof o);
    tx_fill(&x, r);
    for (i = 0; i < n; i++) {
        unsigned m = tri4_test(L, &x, 1e30, &o);
        sum += m;
        L = g->tleaves + (m & z);
    }
    return sum + o.t[0];
}

/* One element's test, chained through the slot it reads. */
static double kl_elem(const gg_geom *g, const gg_slot *s0, const gg_rpre *r, long n)
{
    double sum = 0, t = 0, b1 = 0, b2 = 0;
    const uint32_t z = kl_zero_v;
    const gg_slot *sl = s0;
    long i;
    for (i = 0; i < n; i++) {
        int h = gg_elem_hit(g, sl, r, 1e30, &t, &b1, &b2);
        sum += h;
        sl = s0 + ((unsigned)h & z);
    }
    return sum + t;
}

double GG_ISA_NAME(gg_bvh_kloop)(const gg_geom *g, int k, const gg_rayq *q0, long n)
{
    static const int kinds[] = {GG_EK_TRI, GG_EK_SPHERE, -1};
    gg_rayq q = *q0;
    gg_rpre r;
    double p[3];
    const gg_slot *sl = NULL;
    if (k == GG_KL_TRI4 && !g->ntleaves) return -1;
    if (k >= GG_KL_TRI && k <= GG_KL_OTHER && !(sl = kl_slot(g, kinds[k - GG_KL_TRI]))) return -1;
    if (k == GG_KL_TRI4) {
        /* the block's first triangle */
        const gg_slot *f = &g->slots[g->tleaves[0].first];
        kl_aim(g, f, p);
    } else
        kl_aim(g, sl, p);
    if (!kl_ray(&r, &q, p)) return -1;
    switch (k) {
    case GG_KL_BOX8:
        return kl_box8(g, &q, n);
    case GG_KL_PBOX4:
    case GG_KL_PLANE:
        return kl_packet(g, &q, k, n);
    case GG_KL_TRI4:
        return kl_tri4(g, &r, n);
    default:
        return kl_elem(g, sl, &r, n);
    }
}
#endif

#else
/* ISO C forbids an empty translation unit. */
typedef int gg_bvh_avx_unused;
#endif
