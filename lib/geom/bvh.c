/* SPDX-License-Identifier: MIT */
/*
** bvh.c -- the bounding volume hierarchy: binned SAH build, collapse to a
** 4-wide tree, and the plain copy of the traversals (bvh_trav.h).
**
** Layout. A node holds the boxes of its four children as float SoA rows
** (lo x, y, z, hi x, y, z; one lane per child) and four child references:
** 128 bytes, aligned to 64, i.e. 32 bytes per child box -- the size of a
** classic binary node, but one SSE pass tests all four boxes. A reference
** is a node index or a leaf of up to 4 consecutive slots of the
** leaf-ordered element array (bvh_int.h). Unused lanes hold an inverted
** box that no ray can enter.
**
** Leaves of triangles only are also kept as SoA blocks when the CPU runs
** AVX: the AVX copy of the traversal (bvh_avx.c) tests their triangles
** four at a time, with the same bits as the scalar kernel.
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
#include "bvh_int.h"

#include <string.h>

#define GG_NBINS     32  /* SAH bins per axis */
#define GG_SAH_TRAV  1.0 /* cost of a node visit, in element tests */
#define GG_SAH_ISECT 1.0
#define GG_SAH_TLEAF 2.0 /* a block of triangles, in single tests */
#define GG_MEDIAN_AT 40  /* from this depth on, median splits only */

/* ---- run-time choice of the AVX traversal ---- */

/* Whether builds of g make triangle blocks for the AVX traversal: this
   build has it, the CPU runs it and g allows it (gg_geom_set_cpu). */
static int avx_wanted(const gg_geom *g)
{
    return GG_HAVE_BVH_AVX && (g->cpu & gg_cpu_features() & GG_CPU_AVX);
}

/* ---- build ---- */

typedef struct bnode2 {
    double lo[3], hi[3];
    uint32_t a, b; /* children, or first element and count */
    int leaf;
} bnode2;

typedef struct bctx {
    const double (*lo)[3], (*hi)[3];
    const uint8_t *tri; /* per element: a triangle (only when blocks are made) */
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

/* SAH cost of a leaf of idx[begin..begin + n). 2 to 4 triangles become
   a block that the AVX traversal tests in one go, for about the price of
   GG_SAH_TLEAF single tests (2 measured best on the SPD scenes: fewer
   instructions than 1, 1.5, 2.5 or 3). The tree's shape changes, not its
   answers, which are those of testing every element. */
static double leaf_cost(const bctx *c, uint32_t begin, uint32_t n)
{
    uint32_t i;
    if (!c->tri || n < 2) return GG_SAH_ISECT * n;
    for (i = begin; i < begin + n; i++)
        if (!c->tri[c->idx[i]]) return GG_SAH_ISECT * n;
    return GG_SAH_ISECT * GG_SAH_TLEAF;
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
        if (n <= GG_MAX_LEAF && (best_axis < 0 || leaf_cost(c, begin, n) <= best_cost)) goto leaf;
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
    gg_mem_free(g->alloc, g->tleaf_mem);
    g->node_mem = NULL;
    g->nodes = NULL;
    g->tleaf_mem = NULL;
    g->tleaves = NULL;
    g->nnodes = g->nleaves = g->max_depth = g->ntleaves = 0;
    g->trav_avx = 0;
}

int gg_bvh_build(gg_geom *g, const double (*lo)[3], const double (*hi)[3], const uint8_t *tri,
                 size_t n, uint32_t *order)
{
    bctx c;
    size_t i;
    int rc = -1;
    gg_bvh_free(g);
    if (n == 0) return 0;
    memset(&c, 0, sizeof c);
    c.lo = lo, c.hi = hi;
    c.tri = avx_wanted(g) ? tri : NULL;
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
                g->nsph * sizeof(gg_ksph) + (g->ntri + g->npieces + g->nmtri) * sizeof(gg_ktri) +
                g->nlcone * sizeof(gg_kcone) + g->nrect * sizeof(gg_krect) +
                g->ntleaves * sizeof(gg_tleaf);
    st->build_seconds = g->build_seconds;
    st->blocks = g->trav_avx ? g->ntleaves : 0;
#if defined(__SSE2__) && !defined(GG_BVH_NO_SIMD) /* GG_BVH_SIMD of bvh_trav.h */
    st->traversal = g->trav_avx ? "avx" : "sse2";
#else
    st->traversal = "c";
#endif
}

/* ---- triangle leaves for the AVX traversal ---- */

#if GG_HAVE_BVH_AVX
/* Whether child reference `ref` of node nd (lane i) is a leaf of 2 to 4
   triangles. A single triangle gains nothing from four lanes. */
static int tri_leaf(const gg_geom *g, const gg_bnode *nd, int i)
{
    uint32_t ref = nd->child[i], k, n = GG_LEAF_N(ref);
    /* an unused lane (inverted box) */
    if (!(ref & GG_LEAF) || nd->b[0][i] == INFINITY || n < 2) return 0;
    for (k = 0; k < n; k++)
        if (g->slots[GG_LEAF_I(ref) + k].ki >> GG_EK_SHIFT != GG_EK_TRI) return 0;
    return 1;
}

int gg_bvh_tri_leaves(gg_geom *g)
{
    size_t i, nb = 0;
    int c;
    g->trav_avx = 0;
    if (!g->nnodes || !avx_wanted(g)) return 0;
    for (i = 0; i < g->nnodes; i++)
        for (c = 0; c < 4; c++) nb += (size_t)tri_leaf(g, &g->nodes[i], c);
    g->trav_avx = 1;
    if (!nb) return 0;
    g->tleaf_mem = gg_mem_alloc(g->alloc, nb * sizeof(gg_tleaf) + 64);
    if (!g->tleaf_mem) return -1;
    g->tleaves = (gg_tleaf *)(((uintptr_t)g->tleaf_mem + 63) & ~(uintptr_t)63);
    for (i = 0; i < g->nnodes; i++) {
        gg_bnode *nd = &g->nodes[i];
        for (c = 0; c < 4; c++) {
            uint32_t ref = nd->child[c], n = GG_LEAF_N(ref), first = GG_LEAF_I(ref), k, b;
            gg_tleaf *L = &g->tleaves[g->ntleaves];
            int ax, v;
            if (!tri_leaf(g, nd, c)) continue;
            memset(L, 0, sizeof *L);
            L->first = first, L->n = n;
            for (k = 0; k < 4; k++) {
                const gg_ktri *t = k < n ? &g->ltri[g->slots[first + k].ki & GG_EK_INDEX] : NULL;
                for (ax = 0; ax < 3; ax++)
                    for (v = 0; v < 3; v++) L->v[ax][v][k] = t ? t->v[v][ax] : NAN;
            }
            b = (uint32_t)g->ntleaves++;
            nd->child[c] = GG_LEAF | GG_TLEAF | b << 3 | (n - 1);
        }
    }
    return 0;
}
#else
int gg_bvh_tri_leaves(gg_geom *g)
{
    g->trav_avx = 0;
    return 0;
}
#endif

/* ---- the plain traversal ---- */

/* The plain copy tests every leaf with the scalar loops; a triangle
   block (built for the AVX copy, when a test runs both copies on one
   tree) is found through its first slot. */
typedef struct gg_tx {
    int unused;
} gg_tx;

static inline void tx_init(gg_tx *x, const gg_rpre *r)
{
    (void)x, (void)r;
}
#define tx_fill tx_init

static inline uint32_t tx_first(const gg_geom *g, uint32_t ref)
{
    return ref & GG_TLEAF ? g->tleaves[GG_LEAF_I(ref)].first : GG_LEAF_I(ref);
}

GG_INLINE int tx_closest(const gg_geom *g, const gg_rpre *r, gg_tx *x, uint32_t ref, gg_hit *best)
{
    (void)x;
    return gg_leaf_closest(g, r, tx_first(g, ref), GG_LEAF_N(ref), best);
}

GG_INLINE uint32_t tx_any(const gg_geom *g, const gg_rpre *r, gg_tx *x, uint32_t ref, double tmax)
{
    (void)x;
    return gg_leaf_any(g, r, tx_first(g, ref), GG_LEAF_N(ref), tmax);
}

GG_INLINE uint32_t tx_shadow(const gg_geom *g, const gg_rpre *r, gg_tx *x, uint32_t ref,
                             double tmax, gg_hit *best, gg_tcol *col)
{
    (void)x;
    return gg_leaf_shadow(g, r, tx_first(g, ref), GG_LEAF_N(ref), tmax, best, col);
}

#define GG_TRAV_LINK      static
#define GG_TRAV_INTERSECT intersect_plain
#define GG_TRAV_OCCLUDER  occluder_plain
#define GG_TRAV_SHADOW    shadow_plain
#include "bvh_trav.h"

/* The AVX copy only where the build of g chose it (avx_wanted). */
#if GG_HAVE_BVH_AVX
#define GG_USE_AVX(g) ((g)->trav_avx)
#else
#define GG_USE_AVX(g)        0
#define gg_bvh_intersect_avx intersect_plain
#define gg_bvh_occluder_avx  occluder_plain
#define gg_bvh_shadow_avx    shadow_plain
#endif

static int intersect(const gg_geom *g, const gg_rayq *q, gg_hit *hit)
{
    return GG_USE_AVX(g) ? gg_bvh_intersect_avx(g, q, hit) : intersect_plain(g, q, hit);
}

static GG_NOINLINE int intersect_hinted(const gg_geom *g, const gg_rayq *q, gg_hit *hit)
{
    if (gg_geom_inside_hit(g, q, q->skip_flags, hit) > 0) return 1;
    return intersect(g, q, hit);
}

int gg_geom_intersect(const gg_geom *g, const gg_rayq *q, gg_hit *hit)
{
    if (GG_UNLIKELY(q->inside != UINT32_MAX)) return intersect_hinted(g, q, hit);
    return intersect(g, q, hit);
}

/* Sort a crossing list nearest first, ties by (prim, sub) as gg_leaf_take
   settles them (insertion sort: at most GG_TCOL_CAP entries). */
static void sort_crossings(gg_tcol *tr)
{
    int i, j;
    for (i = 1; i < tr->n; i++)
        for (j = i; j > 0; j--) {
            gg_hit a = tr->h[j - 1], b = tr->h[j];
            if (a.t < b.t ||
                (a.t == b.t && (a.prim < b.prim || (a.prim == b.prim && a.sub <= b.sub))))
                break;
            tr->h[j - 1] = b, tr->h[j] = a;
        }
}

/* gg_geom_occluded with a crossing list (coloured shadows). */
static GG_NOINLINE int occluded_list(const gg_geom *g, const gg_rayq *q, uint32_t *cache,
                                     gg_tcol *tr)
{
    tr->n = 0, tr->complete = 1, tr->has_near = 0;
    if (GG_USE_AVX(g) ? gg_bvh_shadow_avx(g, q, cache, tr) : shadow_plain(g, q, cache, tr)) {
        tr->n = 0, tr->complete = 0, tr->has_near = 0;
        return 1;
    }
    sort_crossings(tr);
    return 0;
}

/* The same from inside an isolated sphere: its far side comes first,
   whatever it is made of; the caller walks on from there. */
static GG_NOINLINE int occluded_inside(const gg_geom *g, const gg_rayq *q, uint32_t *cache,
                                       gg_tcol *tr)
{
    if (gg_geom_inside_hit(g, q, 0, &tr->near) < 0) return occluded_list(g, q, cache, tr);
    tr->n = 0, tr->complete = 0, tr->has_near = 1;
    return 0;
}

int gg_geom_occluded(const gg_geom *g, const gg_rayq *q, uint32_t *cache, gg_tcol *tr)
{
    uint32_t hit;
    if (tr)
        return q->inside == UINT32_MAX ? occluded_list(g, q, cache, tr)
                                       : occluded_inside(g, q, cache, tr);
    hit = GG_USE_AVX(g) ? gg_bvh_occluder_avx(g, q, cache) : occluder_plain(g, q, cache);
    *cache = hit;
    return hit != 0;
}
