/*
** bvh.c -- the bounding volume hierarchy: binned SAH build, collapse to a
** 4-wide tree, and the closest-hit and any-hit traversals.
**
** Layout. A node holds the boxes of its four children as float SoA rows
** (lo x, y, z, hi x, y, z; one lane per child) and four child references:
** 128 bytes, aligned to 64, i.e. 32 bytes per child box -- the size of a
** classic binary node, but one SSE pass tests all four boxes. A reference
** with the top bit set is a leaf: up to 8 consecutive slots (first << 3 |
** count - 1) of the leaf-ordered element array; otherwise it is a node
** index. Unused lanes hold an inverted box that no ray can enter.
**
** Conservative float boxes. Boxes are rounded outward to float (and one
** more float ulp out). The ray's origin is rounded up or down per axis so
** that each slab distance can only come out too small for the entry plane
** and too large for the exit plane; what is left (the two roundings of
** 1/d, those of the subtraction and of the product, each < 2^-24
** relative) is absorbed by scaling the exit distance by 1 + 5 * 2^-23 >
** (1 + gamma(4)) / (1 - gamma(4)), as in Ize, "Robust BVH Ray Traversal",
** JCGT 2013. So a box that the
** exact ray touches is always entered: the BVH finds exactly what brute
** force finds.
*/
#include "geom_leaf.h"

#include <string.h>

#if defined(__SSE2__) && !defined(GG_BVH_NO_SIMD)
#define GG_BVH_SIMD 1
#include <emmintrin.h>
#endif

struct gg_bnode {
    float b[6][4];
    uint32_t child[4];
    uint32_t pad[4];
};

#define GG_LEAF       0x80000000u
#define GG_MAX_LEAF   4   /* elements per leaf */
#define GG_NBINS      32  /* SAH bins per axis */
#define GG_SAH_TRAV   1.0 /* cost of a node visit, in element tests */
#define GG_SAH_ISECT  1.0
#define GG_MEDIAN_AT  40                         /* from this depth on, median splits only */
#define GG_STACK      256                        /* > 3 * maximum depth (see build2) */
#define GG_EXIT_SCALE 1.00000059604644775390625f /* 1 + 5 * 2^-23 */

/* ---- float rounding helpers ---- */

/* The next float toward +inf (nextafterf without the libm call). */
static inline float f_next_up(float f)
{
    uint32_t u;
    if (!(f < INFINITY)) return f;
    if (f == 0) return 0x1p-149f;
    memcpy(&u, &f, 4);
    u = f > 0 ? u + 1 : u - 1;
    memcpy(&f, &u, 4);
    return f;
}
static inline float f_next_down(float f)
{
    return -f_next_up(-f);
}

/* Round to the nearest float, or toward +-inf when out of range. */
static inline float f_near(double x)
{
    if (x > FLT_MAX) return INFINITY;
    if (x < -FLT_MAX) return -INFINITY;
    return (float)x;
}

/* A float <= x (> x is impossible), one float ulp below the largest. */
static inline float f_down(double x)
{
    float f = f_near(x);
    if ((double)f > x) f = f_next_down(f);
    return f_next_down(f);
}

static inline float f_up(double x)
{
    float f = f_near(x);
    if ((double)f < x) f = f_next_up(f);
    return f_next_up(f);
}

/* ---- build ---- */

typedef struct bnode2 {
    double lo[3], hi[3];
    uint32_t a, b; /* children, or first element and count */
    int leaf;
} bnode2;

typedef struct bctx {
    const double (*lo)[3], (*hi)[3];
    double (*cen)[3];
    uint32_t *idx;
    bnode2 *n;
    size_t nn, ninner;
} bctx;

static double half_area(const double lo[3], const double hi[3])
{
    double x = hi[0] - lo[0], y = hi[1] - lo[1], z = hi[2] - lo[2];
    return x * y + y * z + z * x;
}

static void grow_box(double lo[3], double hi[3], const double l[3], const double h[3])
{
    int k;
    for (k = 0; k < 3; k++) {
        if (l[k] < lo[k]) lo[k] = l[k];
        if (h[k] > hi[k]) hi[k] = h[k];
    }
}

static void empty_box(double lo[3], double hi[3])
{
    lo[0] = lo[1] = lo[2] = INFINITY;
    hi[0] = hi[1] = hi[2] = -INFINITY;
}

static int bin_of(double c, double base, double scale, int nb)
{
    int b = (int)((c - base) * scale);
    return b < 0 ? 0 : b >= nb ? nb - 1 : b;
}

/* Quickselect (Hoare partition): reorder idx[lo..hi] (inclusive) so
   that position k holds the element whose centroid along `axis` would be
   there if sorted, smaller ones before it, larger after. */
static void select_mid(bctx *c, long lo, long hi, long k, int axis)
{
    while (lo < hi) {
        double pv = c->cen[c->idx[lo + (hi - lo) / 2]][axis];
        long i = lo, j = hi;
        while (i <= j) {
            while (c->cen[c->idx[i]][axis] < pv) i++;
            while (c->cen[c->idx[j]][axis] > pv) j--;
            if (i <= j) {
                uint32_t t = c->idx[i];
                c->idx[i] = c->idx[j], c->idx[j] = t;
                i++, j--;
            }
        }
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            return;
    }
}

/* Build the binary tree over idx[begin..end); returns the node index.
   Depth stays below GG_MEDIAN_AT + log2(n) + 1, so the traversal stack
   (which holds at most 3 entries per level) cannot overflow. */
static uint32_t build2(bctx *c, uint32_t begin, uint32_t end, int depth)
{
    uint32_t ni = (uint32_t)c->nn++, n = end - begin, i, mid = 0;
    bnode2 *nd = &c->n[ni];
    double clo[3], chi[3], parea;
    int axis, best_axis = -1, best_bin = 0, nb;
    double best_cost = INFINITY;

    empty_box(nd->lo, nd->hi);
    empty_box(clo, chi);
    for (i = begin; i < end; i++) {
        uint32_t e = c->idx[i];
        grow_box(nd->lo, nd->hi, c->lo[e], c->hi[e]);
        grow_box(clo, chi, c->cen[e], c->cen[e]);
    }
    nd->leaf = 0;
    if (n == 1) goto leaf;
    parea = half_area(nd->lo, nd->hi);

    /* Small nodes get fewer bins: sweeping 32 mostly empty bins per axis
       dominated the build time, for no better splits. */
    nb = n < GG_NBINS / 2 ? 2 * (int)n : GG_NBINS;
    if (depth < GG_MEDIAN_AT) {
        for (axis = 0; axis < 3; axis++) {
            double ext = chi[axis] - clo[axis], scale, rlo[GG_NBINS][3], rhi[GG_NBINS][3];
            double blo[GG_NBINS][3], bhi[GG_NBINS][3], llo[3], lhi[3], rarea[GG_NBINS];
            uint32_t cnt[GG_NBINS], rcnt[GG_NBINS], lcnt = 0;
            int b;
            if (!(ext > 0)) continue;
            scale = nb / ext;
            for (b = 0; b < nb; b++) cnt[b] = 0, empty_box(blo[b], bhi[b]);
            for (i = begin; i < end; i++) {
                uint32_t e = c->idx[i];
                b = bin_of(c->cen[e][axis], clo[axis], scale, nb);
                cnt[b]++;
                grow_box(blo[b], bhi[b], c->lo[e], c->hi[e]);
            }
            empty_box(rlo[nb - 1], rhi[nb - 1]);
            for (b = nb - 1; b > 0; b--) {
                /* rlo/rhi[b] = union of bins b..nb-1 */
                if (b < nb - 1) {
                    memcpy(rlo[b], rlo[b + 1], sizeof rlo[b]);
                    memcpy(rhi[b], rhi[b + 1], sizeof rhi[b]);
                }
                grow_box(rlo[b], rhi[b], blo[b], bhi[b]);
                rcnt[b] = cnt[b] + (b < nb - 1 ? rcnt[b + 1] : 0);
                rarea[b] = rcnt[b] ? half_area(rlo[b], rhi[b]) : 0;
            }
            empty_box(llo, lhi);
            for (b = 1; b < nb; b++) {
                double cost, la;
                grow_box(llo, lhi, blo[b - 1], bhi[b - 1]);
                lcnt += cnt[b - 1];
                if (!lcnt || !rcnt[b]) continue;
                la = half_area(llo, lhi);
                cost = parea > 0
                           ? GG_SAH_TRAV + GG_SAH_ISECT * (la * lcnt + rarea[b] * rcnt[b]) / parea
                           : GG_SAH_TRAV + GG_SAH_ISECT * 0.5 * n;
                if (cost < best_cost) best_cost = cost, best_axis = axis, best_bin = b;
            }
        }
        if (n <= GG_MAX_LEAF && (best_axis < 0 || GG_SAH_ISECT * n <= best_cost)) goto leaf;
    } else if (n <= GG_MAX_LEAF) {
        goto leaf;
    }

    if (best_axis >= 0) {
        double scale = nb / (chi[best_axis] - clo[best_axis]);
        uint32_t l = begin, r = end;
        while (l < r) {
            uint32_t e = c->idx[l];
            if (bin_of(c->cen[e][best_axis], clo[best_axis], scale, nb) < best_bin) {
                l++;
            } else {
                c->idx[l] = c->idx[--r];
                c->idx[r] = e;
            }
        }
        mid = l;
    }
    if (best_axis < 0 || mid == begin || mid == end) {
        /* No useful SAH split (deep, or centroids coincide): halve by count
           along the widest centroid extent. */
        double ex = chi[0] - clo[0], ey = chi[1] - clo[1], ez = chi[2] - clo[2];
        axis = ex >= ey && ex >= ez ? 0 : ey >= ez ? 1 : 2;
        mid = begin + n / 2;
        select_mid(c, (long)begin, (long)end - 1, (long)mid, axis);
    }
    c->ninner++;
    {
        uint32_t a = build2(c, begin, mid, depth + 1);
        uint32_t b = build2(c, mid, end, depth + 1);
        nd = &c->n[ni];
        nd->a = a, nd->b = b;
    }
    return ni;
leaf:
    nd->leaf = 1;
    nd->a = begin, nd->b = n;
    return ni;
}

static void set_lane(gg_bnode *nd, int lane, const double lo[3], const double hi[3])
{
    int k;
    for (k = 0; k < 3; k++) {
        nd->b[k][lane] = f_down(lo[k]);
        nd->b[k + 3][lane] = f_up(hi[k]);
    }
}

/* Turn the binary subtree at n2 into 4-wide nodes (depth first, parents
   before children, so a traversal mostly walks forward in memory). */
static uint32_t collapse(bctx *c, gg_geom *g, uint32_t n2, size_t depth)
{
    uint32_t ni = (uint32_t)g->nnodes++, kids[4];
    int nk, i;
    if (depth > g->max_depth) g->max_depth = depth;
    if (c->n[n2].leaf) {
        kids[0] = n2, nk = 1;
    } else {
        kids[0] = c->n[n2].a, kids[1] = c->n[n2].b, nk = 2;
    }
    /* Open the largest inner child until there are four. */
    while (nk < 4) {
        int bi = -1;
        double ba = -1;
        for (i = 0; i < nk; i++) {
            const bnode2 *k = &c->n[kids[i]];
            double a = half_area(k->lo, k->hi);
            if (!k->leaf && a > ba) ba = a, bi = i;
        }
        if (bi < 0) break;
        kids[nk++] = c->n[kids[bi]].b;
        kids[bi] = c->n[kids[bi]].a;
    }
    for (i = 0; i < 4; i++) {
        gg_bnode *nd = &g->nodes[ni];
        if (i >= nk) {
            int k;
            for (k = 0; k < 3; k++) nd->b[k][i] = INFINITY, nd->b[k + 3][i] = -INFINITY;
            nd->child[i] = GG_LEAF;
            continue;
        }
        set_lane(nd, i, c->n[kids[i]].lo, c->n[kids[i]].hi);
        if (c->n[kids[i]].leaf) {
            nd->child[i] = GG_LEAF | c->n[kids[i]].a << 3 | (c->n[kids[i]].b - 1);
            g->nleaves++;
        } else {
            uint32_t ch = collapse(c, g, kids[i], depth + 1);
            g->nodes[ni].child[i] = ch;
        }
    }
    return ni;
}

void gg_bvh_free(gg_geom *g)
{
    gg_mem_free(g->alloc, g->node_mem);
    g->node_mem = NULL;
    g->nodes = NULL;
    g->nnodes = g->nleaves = g->max_depth = 0;
}

int gg_bvh_build(gg_geom *g, const double (*lo)[3], const double (*hi)[3], size_t n,
                 uint32_t *order)
{
    bctx c;
    size_t i;
    int rc = -1;
    gg_bvh_free(g);
    if (n == 0) return 0;
    memset(&c, 0, sizeof c);
    c.lo = lo, c.hi = hi;
    c.cen = gg_mem_calloc(g->alloc, n, sizeof *c.cen);
    c.idx = order;
    c.n = gg_mem_calloc(g->alloc, 2 * n, sizeof *c.n);
    if (!c.cen || !c.n) goto done;
    for (i = 0; i < n; i++) {
        int k;
        for (k = 0; k < 3; k++) c.cen[i][k] = 0.5 * lo[i][k] + 0.5 * hi[i][k];
        order[i] = (uint32_t)i;
    }
    build2(&c, 0, (uint32_t)n, 0);
    {
        size_t cap = c.ninner ? c.ninner : 1;
        g->node_mem = gg_mem_alloc(g->alloc, cap * sizeof(gg_bnode) + 64);
        if (!g->node_mem) goto done;
        g->nodes = (gg_bnode *)(((uintptr_t)g->node_mem + 63) & ~(uintptr_t)63);
        memset(g->nodes, 0, cap * sizeof(gg_bnode));
    }
    collapse(&c, g, 0, 1);
    rc = 0;
done:
    gg_mem_free(g->alloc, c.cen);
    gg_mem_free(g->alloc, c.n);
    if (rc) gg_bvh_free(g);
    return rc;
}

void gg_geom_bvh_stats(const gg_geom *g, gg_bvh_stats *st)
{
    st->nodes = g->nnodes;
    st->leaves = g->nleaves;
    st->max_depth = g->max_depth;
    st->bytes = g->nnodes * sizeof(gg_bnode) + g->nslots * sizeof(gg_slot) +
                g->nsph * sizeof(gg_ksph) + (g->ntri + g->npieces) * sizeof(gg_ktri) +
                g->nlcone * sizeof(gg_kcone) + g->nrect * sizeof(gg_krect);
    st->build_seconds = g->build_seconds;
}

/* ---- traversal ---- */

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
#define GG_ROWSET(m)                                                                             \
    {                                                                                            \
        {GG_ROWS((m) & 1, 0), GG_ROWS(((m) >> 1) & 1, 1), GG_ROWS(((m) >> 2) & 1, 2)},           \
        {                                                                                        \
            GG_ROWS(1 - ((m) & 1), 0), GG_ROWS(1 - (((m) >> 1) & 1), 1),                         \
                GG_ROWS(1 - (((m) >> 2) & 1), 2)                                                 \
        }                                                                                        \
    }
static const size_t row_offsets[8][2][3] = {GG_ROWSET(0), GG_ROWSET(1), GG_ROWSET(2),
                                            GG_ROWSET(3), GG_ROWSET(4), GG_ROWSET(5),
                                            GG_ROWSET(6), GG_ROWSET(7)};
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
           load would wait for the store buffer (see gg_rpre_init). */
        __m128 ox = _mm_cvtsd_ss(_mm_setzero_ps(), _mm_load_sd(r->o));
        __m128 oy = _mm_cvtsd_ss(_mm_setzero_ps(), _mm_load_sd(r->o + 1));
        __m128 oz = _mm_cvtsd_ss(_mm_setzero_ps(), _mm_load_sd(r->o + 2));
        __m128 dx = _mm_cvtsd_ss(_mm_setzero_ps(), _mm_load_sd(r->d));
        __m128 dy = _mm_cvtsd_ss(_mm_setzero_ps(), _mm_load_sd(r->d + 1));
        __m128 dz = _mm_cvtsd_ss(_mm_setzero_ps(), _mm_load_sd(r->d + 2));
        __m128 of = _mm_movelh_ps(_mm_unpacklo_ps(ox, oy), _mm_unpacklo_ps(oz, oz));
        __m128 df = _mm_movelh_ps(_mm_unpacklo_ps(dx, dy), _mm_unpacklo_ps(dz, dz));
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
#if defined(__GNUC__)
    return __builtin_ctz(m);
#else
    int i = 0;
    while (!(m & 1)) m >>= 1, i++;
    return i;
#endif
}

/* gg_rpre_fill and trav_init inline here, reading q one double at a time:
   the caller has usually just written *q field by field, and a 16-byte
   load spanning two 8-byte stores cannot be forwarded from the store
   buffer (GCC's SLP vectoriser would pair the loads up). */
#if defined(__GNUC__) && !defined(__clang__)
#define GG_NO_SLP __attribute__((optimize("no-tree-slp-vectorize")))
#else
#define GG_NO_SLP
#endif

GG_NO_SLP int gg_geom_intersect(const gg_geom *g, const gg_rayq *q, gg_hit *hit)
{
    gg_rpre r;
    trav tv;
    gg_hit best;
    uint32_t stack[GG_STACK], cur = 0;
    float stack_t[GG_STACK];
    int sp = 0;
    float tmaxf, tcull;
    gg_t4 tmin4, tmax4;

    if (!g->built || !g->nslots || !gg_rpre_fill(&r, g, q) || !(q->tmax > q->tmin)) return 0;
    /* The conservative box test assumes tmin >= 0 (a box wholly behind the
       origin could otherwise be lost to the exit scaling). */
    if (!trav_init(&tv, &r) || q->tmin < 0) return gg_geom_intersect_brute(g, q, hit);
    best.t = gg_next_down(q->tmax);
    best.prim = UINT32_MAX, best.sub = 0, best.b1 = best.b2 = 0;
    tmaxf = f_above(best.t);
    tcull = tmaxf * GG_EXIT_SCALE;
    tmin4 = GG_T4(f_down(q->tmin));
    tmax4 = GG_T4(tmaxf);
    for (;;) {
        if (!(cur & GG_LEAF)) {
            const gg_bnode *nd = &g->nodes[cur];
            float tn[4];
            unsigned mask = (unsigned)box4(nd, &tv, tmin4, tmax4, tn);
            int i0, i1;
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
            if (gg_leaf_closest(g, &r, (cur & ~GG_LEAF) >> 3, (cur & 7) + 1, &best)) {
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

/* Any-hit traversal; returns the slot index + 1 of an occluder, or 0. */
GG_NO_SLP static uint32_t occluder(const gg_geom *g, const gg_rayq *q, uint32_t *cache)
{
    gg_rpre r;
    trav tv;
    uint32_t stack[GG_STACK], cur = 0, hit;
    int sp = 0;
    double tmax;
    gg_t4 tmin4, tmax4;

    if (!g->built || !g->nslots || !gg_rpre_fill(&r, g, q) || !(q->tmax > q->tmin)) return 0;
    tmax = gg_next_down(q->tmax);
    if (cache && *cache && *cache <= g->nslots) {
        hit = gg_leaf_any(g, &r, *cache - 1, 1, tmax);
        if (hit) return hit;
    }
    if (!trav_init(&tv, &r) || q->tmin < 0) {
        return gg_leaf_any(g, &r, 0, (uint32_t)g->nslots, tmax);
    }
    tmin4 = GG_T4(f_down(q->tmin));
    tmax4 = GG_T4(f_above(tmax));
    for (;;) {
        if (!(cur & GG_LEAF)) {
            const gg_bnode *nd = &g->nodes[cur];
            float tn[4];
            unsigned mask = (unsigned)box4(nd, &tv, tmin4, tmax4, tn);
            if (mask) {
                cur = nd->child[lowest_bit(mask)];
                mask &= mask - 1;
                while (mask) {
                    stack[sp++] = nd->child[lowest_bit(mask)];
                    mask &= mask - 1;
                }
                continue;
            }
        } else {
            hit = gg_leaf_any(g, &r, (cur & ~GG_LEAF) >> 3, (cur & 7) + 1, tmax);
            if (hit) return hit;
        }
        if (sp == 0) return 0;
        cur = stack[--sp];
    }
}

int gg_geom_occluded(const gg_geom *g, const gg_rayq *q)
{
    return occluder(g, q, NULL) != 0;
}

int gg_geom_occluded_cached(const gg_geom *g, const gg_rayq *q, uint32_t *cache)
{
    uint32_t hit = occluder(g, q, cache);
    if (hit) *cache = hit;
    return hit != 0;
}

/* Leaf of gg_geom_shadow_query: the slot index + 1 of the first opaque
   element hit (then it stops), else 0; transparent ones update *best as
   gg_leaf_closest does. */
GG_INLINE uint32_t leaf_shadow(const gg_geom *g, const gg_rpre *r, uint32_t first, uint32_t n,
                          double tmax, gg_hit *best)
{
    const gg_slot *s = g->slots + first, *end = s + n;
    for (; s < end; s++) {
        double t, b1 = 0, b2 = 0;
        if (s->prim == r->ignore) continue;
        if (!(g->pflags[s->prim] & GG_PRIM_TRANSPARENT)) {
            if (gg_elem_hit(g, s, r, tmax, &t, &b1, &b2)) return (uint32_t)(s - g->slots) + 1;
            continue;
        }
        if (gg_elem_hit(g, s, r, best->t, &t, &b1, &b2)) gg_leaf_take(best, s, t, b1, b2);
    }
    return 0;
}

/* An any-hit traversal over the whole segment (transparent hits do not
   shorten it: an opaque one further on still blocks). The nearest
   transparent hit comes out the same as gg_geom_intersect's because
   every element whose box the segment enters is tested, with the same
   kernels and the same tie rule (the answer of gg_leaf_closest does not
   depend on the visiting order). */
GG_NO_SLP int gg_geom_shadow_query(const gg_geom *g, const gg_rayq *q, gg_hit *tr, int *has_tr)
{
    return gg_geom_shadow_query_cached(g, q, tr, has_tr, NULL);
}

GG_NO_SLP int gg_geom_shadow_query_cached(const gg_geom *g, const gg_rayq *q, gg_hit *tr,
                                          int *has_tr, uint32_t *cache)
{
    gg_rpre r;
    trav tv;
    gg_hit best;
    uint32_t stack[GG_STACK], cur = 0, hit;
    int sp = 0;
    double tmax;
    gg_t4 tmin4, tmax4;

    *has_tr = 0;
    if (!g->built || !g->nslots || !gg_rpre_fill(&r, g, q) || !(q->tmax > q->tmin)) return 0;
    r.skip = 0;
    tmax = gg_next_down(q->tmax);
    best.t = tmax;
    best.prim = UINT32_MAX, best.sub = 0, best.b1 = best.b2 = 0;
    /* The opaque element that blocked this light's previous shadow ray
       first: if it blocks this one too, the answer (1) is the same as the
       traversal's, whichever opaque element that would have found. */
    if (cache && *cache && *cache <= g->nslots &&
        !(g->pflags[g->slots[*cache - 1].prim] & GG_PRIM_TRANSPARENT) &&
        gg_leaf_any(g, &r, *cache - 1, 1, tmax))
        return 1;
    if (!trav_init(&tv, &r) || q->tmin < 0) {
        if ((hit = leaf_shadow(g, &r, 0, (uint32_t)g->nslots, tmax, &best))) goto blocked;
        goto done;
    }
    tmin4 = GG_T4(f_down(q->tmin));
    tmax4 = GG_T4(f_above(tmax));
    for (;;) {
        if (!(cur & GG_LEAF)) {
            const gg_bnode *nd = &g->nodes[cur];
            float tn[4];
            unsigned mask = (unsigned)box4(nd, &tv, tmin4, tmax4, tn);
            if (mask) {
                cur = nd->child[lowest_bit(mask)];
                mask &= mask - 1;
                while (mask) {
                    stack[sp++] = nd->child[lowest_bit(mask)];
                    mask &= mask - 1;
                }
                continue;
            }
        } else if ((hit = leaf_shadow(g, &r, (cur & ~GG_LEAF) >> 3, (cur & 7) + 1, tmax, &best)))
            goto blocked;
        if (sp == 0) break;
        cur = stack[--sp];
    }
done:
    if (best.prim != UINT32_MAX) {
        *tr = best;
        *has_tr = 1;
    }
    return 0;
blocked:
    if (cache) *cache = hit;
    return 1;
}
