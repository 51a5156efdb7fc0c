/* SPDX-License-Identifier: MIT */
/*
** bvh_build.c -- the BVH build: binned SAH over element boxes into a
** binary tree, then collapsed to the 4-wide nodes of bvh_int.h.
*/
#include "bvh_int.h"

#include <string.h>

#define GG_NBINS     32  /* SAH bins per axis */
#define GG_SAH_TRAV  1.0 /* cost of a node visit, in element tests */
#define GG_SAH_ISECT 1.0
#define GG_SAH_TLEAF 2.0 /* a block of triangles, in single tests */
#define GG_MEDIAN_AT 40  /* from this depth on, median splits only */

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
    c.tri = gg_bvh_avx_wanted(g) ? tri : NULL;
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
