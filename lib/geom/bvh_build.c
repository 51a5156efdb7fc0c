/* SPDX-License-Identifier: MIT */
/*
** bvh_build.c -- the BVH build: binned SAH over element boxes (object
** and spatial splits) into a binary tree, then collapsed to the 4-wide
** nodes of bvh_int.h.
**
** Records. Each element becomes a 32-byte record of its box rounded
** outward to float, with its index and whether it is a triangle; the
** build partitions the records themselves, so every pass over a node
** reads memory in order (Wald, "On fast construction of SAH-based
** bounding volume hierarchies", IEEE RT 2007, bins primitive references
** the same way). The union of float boxes is exact, so a node's box,
** rounded once more outward in set_lane, is the one the double boxes
** would give.
**
** Spatial splits (section below) clip triangles, so that one element
** may have records in several leaves: a subtree gets room for more
** records than it starts with (GG_SPLIT_REFS more per element in all),
** shared out between the children in proportion to their counts, and
** the leaves' records are packed into consecutive slots at the end.
**
** Deterministic threads. A subtree with room for m records owns the
** 2m - 1 binary nodes after its root's slot, its left child's subtree
** first: where a node lands depends on the splits only, never on which
** thread built it. The calling thread splits the top of the tree (its largest nodes
** binned by all threads, each over a part of the records, the parts'
** bins merged: min, max and counts do not depend on the order); the
** subtrees below task_max elements are then built by the threads,
** largest first. The tree is bit for bit the one a single thread builds.
*/
#include "bvh_int.h"

#include <pthread.h>
#include <string.h>
#include <unistd.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#define GG_NBINS      32  /* SAH bins per axis */
#define GG_TWO_SETS   256 /* nodes this large are binned in two sets (struct bins) */
#define GG_SAH_TRAV   0.7 /* a node visit, in element tests (docs/performance.md, "Node cost") */
#define GG_SAH_ISECT  1.0
#define GG_SAH_TLEAF  2.0 /* a block of triangles, in single tests */
#define GG_MEDIAN_AT  40  /* from this depth on, median splits only */
#define GG_NSBINS     8   /* spatial-split bins per axis (docs/performance.md, "Spatial splits") */
#define GG_SPLIT_MAX  16384 /* larger nodes: object splits only (the top is built serially) */
#define GG_SPLIT_MIN  24    /* and nodes this small too: cheaper builds, no worse trees */
#define GG_SPLIT_REFS 0.5   /* spatial splits may add this many references per element */
/* Spatial splits are tried where the object split's children overlap by
   more than GG_SPLIT_ALPHA of the root's area (Stich et al., Section 4.5)
   and GG_SPLIT_BETA of the node's own, which spares the build of meshes
   of small triangles a search that does not pay there. */
#define GG_SPLIT_ALPHA 1e-5
#define GG_SPLIT_BETA  0.2
#define GG_MAX_THREAD  16

/* Fewer elements: one thread builds; subtrees at most task_max large go
   to the threads; nodes at least pbin_min large are binned by all
   threads (gg_bvh_set_build_sizes). */
static size_t par_min = 20000, task_max = 16384, pbin_min = 131072;

/* ---- four floats ---- */

#if defined(__SSE2__)
typedef __m128 v4;
#define v4_ld(p)     _mm_loadu_ps(p)
#define v4_st(p, a)  _mm_storeu_ps(p, a)
#define v4_min(a, b) _mm_min_ps(a, b)
#define v4_max(a, b) _mm_max_ps(a, b)
#define v4_add(a, b) _mm_add_ps(a, b)
#define v4_sub(a, b) _mm_sub_ps(a, b)
#define v4_mul(a, b) _mm_mul_ps(a, b)
#else
typedef struct v4 {
    float f[4];
} v4;
static inline v4 v4_ld(const float *p)
{
    v4 a;
    memcpy(a.f, p, sizeof a.f);
    return a;
}
static inline void v4_st(float *p, v4 a)
{
    memcpy(p, a.f, sizeof a.f);
}
/* min and max as SSE's minps and maxps: the second operand unless the
   comparison holds. */
static inline v4 v4_min(v4 a, v4 b)
{
    int i;
    for (i = 0; i < 4; i++) a.f[i] = a.f[i] < b.f[i] ? a.f[i] : b.f[i];
    return a;
}
static inline v4 v4_max(v4 a, v4 b)
{
    int i;
    for (i = 0; i < 4; i++) a.f[i] = a.f[i] > b.f[i] ? a.f[i] : b.f[i];
    return a;
}
static inline v4 v4_add(v4 a, v4 b)
{
    int i;
    for (i = 0; i < 4; i++) a.f[i] += b.f[i];
    return a;
}
static inline v4 v4_sub(v4 a, v4 b)
{
    int i;
    for (i = 0; i < 4; i++) a.f[i] -= b.f[i];
    return a;
}
static inline v4 v4_mul(v4 a, v4 b)
{
    int i;
    for (i = 0; i < 4; i++) a.f[i] *= b.f[i];
    return a;
}
#endif

/* ---- records, nodes, boxes ---- */

/* An element's box, clamped to +-FLT_MAX (set_lane's extra ulp turns
   FLT_MAX into infinity again), so that centroids stay finite; lane 3 is
   zero. */
typedef struct bref {
    float lo[4], hi[4];
} bref;

typedef struct bnode2 {
    float lo[3], hi[3];
    uint32_t a, b; /* children, or first element and count */
    int leaf;
} bnode2;

typedef struct bbox {
    v4 lo, hi;
} bbox;

/* A subtree to build: its root's slot, its records, its box and the box
   of its records' centroids. */
typedef struct span {
    uint32_t node, begin, end, cap; /* records [begin, end), room up to cap */
    int depth;
    bbox b, c;
} span;

typedef struct bctx {
    const ggAllocator *alloc;
    bref *r;
    uint32_t *id;        /* element of each record, moved with it */
    const uint8_t *tri;  /* per element: a triangle (only when blocks are made) */
    const uint8_t *clip; /* per element: a triangle that spatial splits may clip */
    gg_bvh_verts verts;  /* its vertices */
    const void *ud;
    double root_area;
    bnode2 *n;
    int threads;
    span *task;
    size_t ntask, cap, next;
    pthread_mutex_t mu;
    /* Progress: the calling thread reports done (elements of the finished
       tasks and of the leaves it made outside them) to prog; stop, set
       when prog asks, ends the build (both under mu while tasks run). */
    gg_progress *prog;
    size_t done, total;
    int stop;
} bctx;

/* Per-axis bins over a node: b[0] and cnt[0] once merged; while binning,
   even records go to set 0 and odd ones to set 1, so that a run of
   records in the same bin makes two chains of loads and stores that wait
   on each other, not one. */
typedef struct bins {
    bbox b[2][3][GG_NBINS];
    uint32_t cnt[2][3][GG_NBINS];
} bins;

/* Spatial bins over a node's box: the clipped references' boxes, and
   how many references begin and end in each bin. */
typedef struct sbins {
    bbox b[3][GG_NSBINS];
    uint32_t enter[3][GG_NSBINS], leave[3][GG_NSBINS];
} sbins;

typedef struct bwork {
    bctx *c;
    size_t ninner;
    int top;     /* the calling thread, splitting the top: may hand out tasks */
    int first;   /* the calling thread: reports progress, and stops when told */
    int in_task; /* building a task (its elements count when it ends) */
    size_t told; /* c->done when it last reported */
    bins bn;
    sbins sb;
    bref *tmp; /* the right side of a spatial split, while partitioning */
    uint32_t *tmp_id;
    size_t ntmp;
} bwork;

static bbox box_empty(void)
{
    static const float inf[4] = {INFINITY, INFINITY, INFINITY, INFINITY};
    static const float ninf[4] = {-INFINITY, -INFINITY, -INFINITY, -INFINITY};
    bbox b;
    b.lo = v4_ld(inf), b.hi = v4_ld(ninf);
    return b;
}

static void box_grow(bbox *b, v4 lo, v4 hi)
{
    b->lo = v4_min(b->lo, lo), b->hi = v4_max(b->hi, hi);
}

static float half_area(bbox b)
{
#if defined(__SSE2__)
    /* the lanes taken in registers (a store and three loads stalled) */
    v4 d = v4_sub(b.hi, b.lo);
    float x = _mm_cvtss_f32(d), y = _mm_cvtss_f32(_mm_shuffle_ps(d, d, 0x55)),
          z = _mm_cvtss_f32(_mm_shuffle_ps(d, d, 0xaa));
    return x * y + y * z + z * x;
#else
    float d[4];
    v4_st(d, v4_sub(b.hi, b.lo));
    return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
#endif
}

static v4 centroid(v4 lo, v4 hi)
{
    static const float half[4] = {0.5f, 0.5f, 0.5f, 0.5f};
    v4 h = v4_ld(half);
    return v4_add(v4_mul(lo, h), v4_mul(hi, h));
}

/* Bin coordinates of a centroid: (c - base) * scale per axis. */
static v4 bin_coord(v4 cen, v4 base, v4 scale)
{
    return v4_mul(v4_sub(cen, base), scale);
}

/* The bins of a centroid's coordinates x, clamped to [0, nb - 1] before
   the conversion (max, then min: NaN becomes 0). */
static void bin_index(v4 x, int nb, int b[4])
{
    static const float zero[4] = {0, 0, 0, 0};
    float top[4];
    int k;
    for (k = 0; k < 4; k++) top[k] = (float)(nb - 1);
    x = v4_min(v4_max(x, v4_ld(zero)), v4_ld(top));
#if defined(__SSE2__)
    _mm_storeu_si128((__m128i *)(void *)b, _mm_cvttps_epi32(x));
#else
    for (k = 0; k < 4; k++) b[k] = (int)x.f[k];
#endif
}

static void span_box(const bctx *c, span *s)
{
    uint32_t i;
    s->b = box_empty(), s->c = box_empty();
    for (i = s->begin; i < s->end; i++) {
        v4 lo = v4_ld(c->r[i].lo), hi = v4_ld(c->r[i].hi), ce = centroid(lo, hi);
        box_grow(&s->b, lo, hi);
        box_grow(&s->c, ce, ce);
    }
}

/* ---- binning ---- */

/* Merge set 1 of bins a (or set 0 of another bins) into set 0 of a. */
static void bins_merge(bins *a, const bins *o, int set, int nb)
{
    int k, b;
    for (k = 0; k < 3; k++)
        for (b = 0; b < nb; b++) {
            a->cnt[0][k][b] += o->cnt[set][k][b];
            box_grow(&a->b[0][k][b], o->b[set][k][b].lo, o->b[set][k][b].hi);
        }
}

static void bin_range(const bctx *c, bins *bn, uint32_t begin, uint32_t end, v4 base, v4 scale,
                      int nb)
{
    uint32_t i, two = end - begin >= GG_TWO_SETS; /* 1: even and odd records apart */
    int k, b, h;
    bbox e = box_empty();
    for (h = 0; h <= (int)two; h++)
        for (k = 0; k < 3; k++)
            for (b = 0; b < nb; b++) bn->cnt[h][k][b] = 0, bn->b[h][k][b] = e;
    for (i = begin; i < end; i++) {
        v4 lo = v4_ld(c->r[i].lo), hi = v4_ld(c->r[i].hi);
        int x[4];
        h = (int)(i & two);
        bin_index(bin_coord(centroid(lo, hi), base, scale), nb, x);
        for (k = 0; k < 3; k++) {
            bn->cnt[h][k][x[k]]++;
            box_grow(&bn->b[h][k][x[k]], lo, hi);
        }
    }
    /* min, max and counts: the same bins whichever set a record went to */
    if (two) bins_merge(bn, bn, 1, nb);
}

typedef struct pbin {
    const bctx *c;
    bins *bn;
    uint32_t begin, end;
    v4 base, scale;
    int nb;
} pbin;

static void *pbin_run(void *p)
{
    pbin *a = p;
    bin_range(a->c, a->bn, a->begin, a->end, a->base, a->scale, a->nb);
    return NULL;
}

/* Bin a large node with all threads, each over its part of the records,
   then merge the parts in part order. */
static void bin_parallel(bwork *w, const span *s, v4 base, v4 scale, int nb)
{
    pbin part[GG_MAX_THREAD];
    pthread_t th[GG_MAX_THREAD];
    int started[GG_MAX_THREAD], t, nt = w->c->threads;
    uint32_t n = s->end - s->begin;
    bins *extra = gg_mem_alloc(w->c->alloc, (size_t)(nt - 1) * sizeof *extra);
    if (!extra) {
        bin_range(w->c, &w->bn, s->begin, s->end, base, scale, nb);
        return;
    }
    for (t = 0; t < nt; t++) {
        part[t].c = w->c, part[t].bn = t ? &extra[t - 1] : &w->bn;
        part[t].begin = s->begin + (uint32_t)((uint64_t)n * t / nt);
        part[t].end = s->begin + (uint32_t)((uint64_t)n * (t + 1) / nt);
        part[t].base = base, part[t].scale = scale, part[t].nb = nb;
        started[t] = t && !pthread_create(&th[t], NULL, pbin_run, &part[t]);
    }
    pbin_run(&part[0]);
    for (t = 1; t < nt; t++) {
        if (started[t])
            pthread_join(th[t], NULL);
        else
            pbin_run(&part[t]);
        bins_merge(&w->bn, &extra[t - 1], 0, nb);
    }
    gg_mem_free(w->c->alloc, extra);
}

/* ---- split ---- */

typedef struct split {
    int axis, bin, nb; /* axis -1: none found */
    double cost;
    v4 base, scale;
} split;

/* SAH cost of a leaf of records [begin, begin + n). 2 to 4 triangles
   become a block that the AVX traversal tests in one go, for about the
   price of GG_SAH_TLEAF single tests (its value: docs/performance.md,
   "Four triangles at once"). The tree's shape changes, not its answers,
   which are those of testing every element. */
static double leaf_cost(const bctx *c, uint32_t begin, uint32_t n)
{
    uint32_t i;
    if (!c->tri || n < 2) return GG_SAH_ISECT * n;
    for (i = begin; i < begin + n; i++)
        if (!c->tri[c->id[i]]) return GG_SAH_ISECT * n;
    return GG_SAH_ISECT * GG_SAH_TLEAF;
}

/* Sweep the bins of one axis for its best split into sp, by the
   numerator of the SAH cost: sum of area times count over both sides
   (sp->cost holds the numerator until find_split divides). */
static void sweep_axis(const bins *bn, int k, split *sp)
{
    float rarea[GG_NBINS];
    uint32_t rcnt[GG_NBINS], lcnt = 0;
    bbox r = box_empty(), l = box_empty();
    int b, nb = sp->nb;
    rcnt[0] = 0;
    for (b = nb - 1; b > 0; b--) {
        box_grow(&r, bn->b[0][k][b].lo, bn->b[0][k][b].hi);
        rcnt[b] = bn->cnt[0][k][b] + (b < nb - 1 ? rcnt[b + 1] : 0);
        rarea[b] = rcnt[b] ? half_area(r) : 0;
    }
    for (b = 1; b < nb; b++) {
        double num;
        box_grow(&l, bn->b[0][k][b - 1].lo, bn->b[0][k][b - 1].hi);
        lcnt += bn->cnt[0][k][b - 1];
        if (!lcnt || !rcnt[b]) continue;
        num = (double)half_area(l) * lcnt + (double)rarea[b] * rcnt[b];
        if (num < sp->cost) sp->cost = num, sp->axis = k, sp->bin = b;
    }
}

/* The best binned SAH split of s, if any. */
static void find_split(bwork *w, const span *s, split *sp)
{
    uint32_t n = s->end - s->begin;
    float ext[4], scale[4];
    double parea = half_area(s->b);
    int k;
    sp->axis = -1, sp->bin = 0, sp->cost = INFINITY;
    /* Small nodes get fewer bins: sweeping 32 mostly empty bins per axis
       dominated the build time, for no better splits. */
    sp->nb = n < GG_NBINS / 2 ? 2 * (int)n : GG_NBINS;
    v4_st(ext, v4_sub(s->c.hi, s->c.lo));
    for (k = 0; k < 4; k++) scale[k] = k < 3 && ext[k] > 0 ? (float)sp->nb / ext[k] : 0;
    sp->base = s->c.lo, sp->scale = v4_ld(scale);
    if (w->top && w->c->threads > 1 && n >= pbin_min)
        bin_parallel(w, s, sp->base, sp->scale, sp->nb);
    else
        bin_range(w->c, &w->bn, s->begin, s->end, sp->base, sp->scale, sp->nb);
    for (k = 0; k < 3; k++)
        if (ext[k] > 0) sweep_axis(&w->bn, k, sp);
    /* cost = traversal + intersections weighted by area; a flat node
       (zero area) costs half its elements */
    if (sp->axis >= 0)
        sp->cost = parea > 0 ? GG_SAH_TRAV + GG_SAH_ISECT * sp->cost / parea
                             : GG_SAH_TRAV + GG_SAH_ISECT * 0.5 * n;
}

static void swap_rec(bctx *c, uint32_t i, uint32_t j)
{
    bref t = c->r[i];
    uint32_t u = c->id[i];
    c->r[i] = c->r[j], c->r[j] = t;
    c->id[i] = c->id[j], c->id[j] = u;
}

/* Records left of the split first; returns the first right one and
   fills the boxes of both sides. */
static uint32_t partition(bctx *c, const span *s, const split *sp, span *L, span *R)
{
    uint32_t l = s->begin, r = s->end;
    L->b = L->c = R->b = R->c = box_empty();
    while (l < r) {
        v4 lo = v4_ld(c->r[l].lo), hi = v4_ld(c->r[l].hi), ce = centroid(lo, hi);
        int x[4];
        bin_index(bin_coord(ce, sp->base, sp->scale), sp->nb, x);
        if (x[sp->axis] < sp->bin) {
            box_grow(&L->b, lo, hi), box_grow(&L->c, ce, ce);
            l++;
        } else {
            box_grow(&R->b, lo, hi), box_grow(&R->c, ce, ce);
            swap_rec(c, l, --r);
        }
    }
    return l;
}

static float cen_key(const bctx *c, uint32_t i, int axis)
{
    float x[4];
    v4_st(x, centroid(v4_ld(c->r[i].lo), v4_ld(c->r[i].hi)));
    return x[axis];
}

/* Quickselect (Hoare partition): reorder records lo..hi (inclusive) so
   that position k holds the one whose centroid along `axis` would be
   there if sorted, smaller ones before it, larger after. */
static void select_mid(bctx *c, long lo, long hi, long k, int axis)
{
    while (lo < hi) {
        float pv = cen_key(c, (uint32_t)(lo + (hi - lo) / 2), axis);
        long i = lo, j = hi;
        while (i <= j) {
            while (cen_key(c, (uint32_t)i, axis) < pv) i++;
            while (cen_key(c, (uint32_t)j, axis) > pv) j--;
            if (i <= j) swap_rec(c, (uint32_t)i++, (uint32_t)j--);
        }
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            return;
    }
}

/* No useful SAH split (deep, or centroids coincide): halve by count
   along the widest centroid extent. */
static uint32_t split_median(bctx *c, const span *s, span *L, span *R)
{
    float e[4];
    uint32_t mid = s->begin + (s->end - s->begin) / 2;
    int axis;
    v4_st(e, v4_sub(s->c.hi, s->c.lo));
    axis = e[0] >= e[1] && e[0] >= e[2] ? 0 : e[1] >= e[2] ? 1 : 2;
    select_mid(c, (long)s->begin, (long)s->end - 1, (long)mid, axis);
    L->begin = s->begin, L->end = mid, R->begin = mid, R->end = s->end;
    span_box(c, L);
    span_box(c, R);
    return mid;
}

/* A float <= x, clamped to +-FLT_MAX (NaN: -FLT_MAX). */
static float rec_lo(double x)
{
    float f;
    if (!(x >= -FLT_MAX)) return -FLT_MAX;
    if (x > FLT_MAX) return FLT_MAX;
    f = (float)x;
    return (double)f > x ? f_next_down(f) : f;
}

static float rec_hi(double x)
{
    float f;
    if (!(x <= FLT_MAX)) return FLT_MAX;
    if (x < -FLT_MAX) return -FLT_MAX;
    f = (float)x;
    return (double)f < x ? f_next_up(f) : f;
}

/* ---- spatial splits ---- */

/* Stich, Friedrich and Dietrich, "Spatial Splits in Bounding Volume
   Hierarchies", HPG 2009: where the children of the best object split
   overlap, a plane may also cut the triangles that straddle it, each
   side keeping the box of its part. A record's box bounds the part of
   its triangle inside the region its ancestors' planes cut out; every
   box computed here holds that part (rounded outward), so every point of
   a triangle stays in the box of some leaf that holds it, and the
   traversal still finds what testing every element finds. */

typedef struct ssplit {
    int axis, bin, nb; /* axis -1: none */
    double cost;
    float lo[3], w[3]; /* bin b of axis k starts at lo[k] + b * w[k] */
} ssplit;

static float plane_at(const ssplit *sp, int k, int b)
{
    return sp->lo[k] + (float)b * sp->w[k];
}

static int sbin_of(const ssplit *sp, int k, float x)
{
    float f = (x - sp->lo[k]) / sp->w[k];
    if (!(f > 0)) return 0;
    return f < (float)sp->nb ? (int)f : sp->nb - 1;
}

static void grow_pt(double lo[3], double hi[3], const double x[3])
{
    int j;
    for (j = 0; j < 3; j++) {
        if (x[j] < lo[j]) lo[j] = x[j];
        if (x[j] > hi[j]) hi[j] = x[j];
    }
}

/* Whether edge a-b crosses the plane x_k = p strictly. */
static int straddles(const double a[3], const double b[3], int k, double p)
{
    return (a[k] < p && b[k] > p) || (a[k] > p && b[k] < p);
}

/* The computed point of edge a-b on the plane x_k = p (it straddles). */
static void edge_point(const double a[3], const double b[3], int k, double p, double q[3])
{
    double t = (p - a[k]) / (b[k] - a[k]);
    int j;
    for (j = 0; j < 3; j++) q[j] = a[j] + t * (b[j] - a[j]);
}

/* Where edge a-b crosses x_k = p, as a box: the computed point widened
   by its rounding error (a few ulps of |a| + |b| at most) and kept inside
   the edge's own extent. */
static void edge_cut(const double a[3], const double b[3], int k, float p, double lo[3],
                     double hi[3])
{
    double q[3];
    int j;
    edge_point(a, b, k, p, q);
    for (j = 0; j < 3; j++) {
        double x = q[j], e = 8 * DBL_EPSILON * (fabs(a[j]) + fabs(b[j]));
        double mn = a[j] < b[j] ? a[j] : b[j], mx = a[j] < b[j] ? b[j] : a[j];
        lo[j] = x - e, hi[j] = x + e;
        if (!(lo[j] >= mn)) lo[j] = mn; /* also NaN */
        if (!(hi[j] <= mx)) hi[j] = mx;
    }
    lo[k] = hi[k] = p;
}

/* Box x cut down to lo/hi (rounded outward); whether it is not empty. */
static int clip_box(bref *x, const double lo[3], const double hi[3])
{
    int j, ok = 1;
    for (j = 0; j < 3; j++) {
        float l = rec_lo(lo[j]), h = rec_hi(hi[j]);
        if (l > x->lo[j]) x->lo[j] = l;
        if (h < x->hi[j]) x->hi[j] = h;
        ok &= x->lo[j] <= x->hi[j];
    }
    return ok;
}

/* The boxes of triangle v's parts in box r on either side of the plane
   x_k = p; returns bit 0 if the left one is not empty, bit 1 the right. */
static int clip_tri(const double v[3][3], const bref *r, int k, float p, bref *L, bref *R)
{
    double llo[3], lhi[3], rlo[3], rhi[3];
    int i, j, got;
    for (j = 0; j < 3; j++) llo[j] = rlo[j] = INFINITY, lhi[j] = rhi[j] = -INFINITY;
    for (i = 0; i < 3; i++) {
        const double *a = v[i], *b = v[i == 2 ? 0 : i + 1];
        if (a[k] <= p) grow_pt(llo, lhi, a);
        if (a[k] >= p) grow_pt(rlo, rhi, a);
        if (straddles(a, b, k, p)) {
            double clo[3], chi[3];
            edge_cut(a, b, k, p, clo, chi);
            grow_pt(llo, lhi, clo), grow_pt(llo, lhi, chi);
            grow_pt(rlo, rhi, clo), grow_pt(rlo, rhi, chi);
        }
    }
    *L = *r, *R = *r;
    lhi[k] = p, rlo[k] = p; /* within the box and on its side of the plane */
    got = clip_box(L, llo, lhi);
    got |= clip_box(R, rlo, rhi) << 1;
    return got;
}

/* Four floats: x, y, z of v rounded to nearest, and 0. */
static v4 v4_pt(const double v[3])
{
#if defined(__SSE2__)
    /* in registers: through memory, the three floats' stores and the
       load of all four make the load wait (no store forwarding) */
    return _mm_movelh_ps(_mm_cvtpd_ps(_mm_loadu_pd(v)), _mm_cvtpd_ps(_mm_load_sd(v + 2)));
#else
    float f[4];
    f[0] = (float)v[0], f[1] = (float)v[1], f[2] = (float)v[2], f[3] = 0;
    return v4_ld(f);
#endif
}

/* Grow lo/hi by point p, skipping a NaN coordinate: minps and maxps give
   their second operand unless the comparison holds. */
static void pt_grow(v4 *lo, v4 *hi, v4 p)
{
    *lo = v4_min(p, *lo), *hi = v4_max(p, *hi);
}

/* The box of the points where triangle v's edges cross the plane x_k = p,
   in float; empty (+inf, -inf) if none does. */
static bbox edge_box(const double (*v)[3], int k, float p)
{
    bbox e = box_empty();
    int i;
    for (i = 0; i < 3; i++) {
        const double *a = v[i], *b = v[i == 2 ? 0 : i + 1];
        if (straddles(a, b, k, p)) {
            double q[3];
            edge_point(a, b, k, p, q);
            pt_grow(&e.lo, &e.hi, v4_pt(q));
        }
    }
    return e;
}

/* The bins of a triangle that spans bins b0..b1 of axis k: in each, the
   box of its vertices there and of its edges' points on the bin's
   planes, within its record's box x. Only the split's choice depends on
   these boxes (partition_spatial computes the children's own), so the
   points need no allowance for rounding. Each point is rounded to float
   before the boxes take their minima and maxima, which gives the boxes
   that rounding the double ones would: the rounding is monotonic. Where
   no edge crosses the plane above bin b (a vertex on it, say), growing by
   the empty box e (+inf, -inf) widens bin b to all of x: too large,
   which only the choice of split sees. */
static void sbin_chop(sbins *sb, const ssplit *sp, int k, const bref *x, const double (*v)[3],
                      const v4 vf[3], int b0, int b1)
{
    v4 xlo = v4_ld(x->lo), xhi = v4_ld(x->hi);
    bbox e = box_empty(); /* the edge points on bin b's lower plane */
    int b, i;
    for (b = b0; b <= b1; b++) {
        float pl = plane_at(sp, k, b), ph = plane_at(sp, k, b + 1), y[8];
        v4 lo = e.lo, hi = e.hi;
        for (i = 0; i < 3; i++)
            if ((b == b0 || v[i][k] >= pl) && (b == b1 || v[i][k] <= ph)) pt_grow(&lo, &hi, vf[i]);
        if (b < b1) {
            e = edge_box(v, k, ph);
            pt_grow(&lo, &hi, e.lo), pt_grow(&lo, &hi, e.hi);
        }
        lo = v4_max(lo, xlo), hi = v4_min(hi, xhi);
        v4_st(y, lo), v4_st(y + 4, hi);
        if (y[0] <= y[4] && y[1] <= y[5] && y[2] <= y[6]) box_grow(&sb->b[k][b], lo, hi);
    }
}

/* Bin record x along axis k, given its bins b0..b1 there: a triangle
   (vertices v, vf) chopped at every bin plane it crosses, anything else
   whole. */
static void sbin_rec(sbins *sb, const ssplit *sp, const bref *x, int k, const double (*v)[3],
                     const v4 vf[3], int b0, int b1)
{
    if (b0 == b1)
        box_grow(&sb->b[k][b0], v4_ld(x->lo), v4_ld(x->hi));
    else
        sbin_chop(sb, sp, k, x, v, vf, b0, b1);
    sb->enter[k][b0]++, sb->leave[k][b1]++;
}

/* The best spatial split of s by the SAH (sp->cost as find_split's), if
   its references fit in the room s has. */
static void find_spatial(bwork *w, const span *s, ssplit *sp)
{
    const bctx *c = w->c;
    sbins *sb = &w->sb;
    uint32_t n = s->end - s->begin, room = s->cap - s->begin, i;
    float lo[4], hi[4];
    double parea = half_area(s->b), best = INFINITY;
    int k, b, use[3];
    sp->axis = -1, sp->cost = INFINITY;
    sp->nb = n < GG_NSBINS / 2 ? 2 * (int)n : GG_NSBINS;
    v4_st(lo, s->b.lo), v4_st(hi, s->b.hi);
    for (k = 0; k < 3; k++) {
        sp->lo[k] = lo[k], sp->w[k] = (hi[k] - lo[k]) / (float)sp->nb;
        for (b = 0; b < sp->nb; b++)
            sb->b[k][b] = box_empty(), sb->enter[k][b] = sb->leave[k][b] = 0;
    }
    for (k = 0; k < 3; k++) use[k] = sp->w[k] > 0 && lo[k] + sp->w[k] < hi[k];
    for (i = s->begin; i < s->end; i++) {
        const bref *x = &c->r[i];
        int tri = c->clip[c->id[i]], cross = 0, b0[3], b1[3];
        double v[3][3];
        v4 vf[3];
        for (k = 0; k < 3; k++) {
            if (!use[k]) continue;
            if (tri) {
                b0[k] = sbin_of(sp, k, x->lo[k]), b1[k] = sbin_of(sp, k, x->hi[k]);
                cross |= b0[k] != b1[k];
            } else {
                b0[k] = b1[k] = sbin_of(sp, k, 0.5f * x->lo[k] + 0.5f * x->hi[k]);
            }
        }
        /* the vertices only for a triangle that crosses a bin plane */
        if (cross) {
            c->verts(c->ud, c->id[i], v);
            for (k = 0; k < 3; k++) vf[k] = v4_pt(v[k]);
        }
        for (k = 0; k < 3; k++)
            if (use[k])
                sbin_rec(sb, sp, x, k, cross ? (const double(*)[3])v : NULL, cross ? vf : NULL,
                         b0[k], b1[k]);
    }
    for (k = 0; k < 3; k++) {
        float rarea[GG_NSBINS];
        uint32_t rcnt[GG_NSBINS], lcnt = 0;
        bbox r = box_empty(), l = box_empty();
        if (!use[k]) continue;
        rcnt[0] = 0;
        for (b = sp->nb - 1; b > 0; b--) {
            box_grow(&r, sb->b[k][b].lo, sb->b[k][b].hi);
            rcnt[b] = sb->leave[k][b] + (b < sp->nb - 1 ? rcnt[b + 1] : 0);
            rarea[b] = rcnt[b] ? half_area(r) : 0;
        }
        for (b = 1; b < sp->nb; b++) {
            double num;
            box_grow(&l, sb->b[k][b - 1].lo, sb->b[k][b - 1].hi);
            lcnt += sb->enter[k][b - 1];
            if (!lcnt || !rcnt[b] || lcnt == n || rcnt[b] == n || lcnt + rcnt[b] > room) continue;
            num = (double)half_area(l) * lcnt + (double)rarea[b] * rcnt[b];
            if (num < best) best = num, sp->axis = k, sp->bin = b;
        }
    }
    if (sp->axis >= 0 && parea > 0)
        sp->cost = GG_SAH_TRAV + GG_SAH_ISECT * best / parea;
    else
        sp->axis = -1;
}

/* Whether the children of object split sp overlap enough to try a
   spatial one (w->bn still holds sp's bins). */
static int worth_spatial(const bwork *w, const span *s, const split *sp)
{
    bbox l = box_empty(), r = box_empty(), o;
    int b;
    if (!w->c->clip || s->cap - s->begin <= s->end - s->begin || s->depth >= GG_MEDIAN_AT ||
        s->end - s->begin > GG_SPLIT_MAX || s->end - s->begin <= GG_SPLIT_MIN)
        return 0;
    if (sp->axis < 0) return 1;
    for (b = 0; b < sp->nb; b++) {
        const bbox *x = &w->bn.b[0][sp->axis][b];
        box_grow(b < sp->bin ? &l : &r, x->lo, x->hi);
    }
    o.lo = v4_max(l.lo, r.lo), o.hi = v4_min(l.hi, r.hi);
    {
        float d[4];
        v4_st(d, v4_sub(o.hi, o.lo));
        if (!(d[0] > 0 && d[1] > 0 && d[2] > 0)) return 0;
    }
    return half_area(o) > GG_SPLIT_ALPHA * w->c->root_area &&
           half_area(o) > GG_SPLIT_BETA * half_area(s->b);
}

/* Room for the right side of a spatial split of n records. */
static int tmp_room(bwork *w, size_t n)
{
    if (w->ntmp >= n) return 1;
    gg_mem_free(w->c->alloc, w->tmp), gg_mem_free(w->c->alloc, w->tmp_id);
    w->tmp = gg_mem_alloc(w->c->alloc, n * sizeof *w->tmp);
    w->tmp_id = gg_mem_alloc(w->c->alloc, n * sizeof *w->tmp_id);
    w->ntmp = w->tmp && w->tmp_id ? n : 0;
    return w->ntmp != 0;
}

static void side_add(span *S, uint32_t at, const bref *x, uint32_t id, bref *to, uint32_t *to_id)
{
    v4 lo = v4_ld(x->lo), hi = v4_ld(x->hi), ce = centroid(lo, hi);
    box_grow(&S->b, lo, hi), box_grow(&S->c, ce, ce);
    to[at] = *x, to_id[at] = id;
}

/* Split s at sp's plane: the left records stay in place from s->begin
   (none is written past the one being read), the right ones go to
   w->tmp; returns their count, and the left one in *nl. */
static uint32_t partition_spatial(bwork *w, const span *s, const ssplit *sp, span *L, span *R,
                                  uint32_t *nl)
{
    bctx *c = w->c;
    uint32_t i, l = s->begin, r = 0;
    int k = sp->axis;
    float p = plane_at(sp, k, sp->bin);
    L->b = L->c = R->b = R->c = box_empty();
    for (i = s->begin; i < s->end; i++) {
        bref x = c->r[i], a, b;
        uint32_t id = c->id[i];
        int side;
        if (!c->clip[id]) {
            side = sbin_of(sp, k, 0.5f * x.lo[k] + 0.5f * x.hi[k]) < sp->bin ? 1 : 2;
            a = b = x;
        } else if (sbin_of(sp, k, x.hi[k]) < sp->bin) {
            side = 1, a = x;
        } else if (sbin_of(sp, k, x.lo[k]) >= sp->bin) {
            side = 2, b = x;
        } else {
            double v[3][3];
            c->verts(c->ud, id, v);
            side = clip_tri((const double(*)[3])v, &x, k, p, &a, &b);
            if (!side) side = 1, a = x; /* cannot happen; keep it whole */
        }
        if (side & 1) side_add(L, l++, &a, id, c->r, c->id);
        if (side & 2) side_add(R, r++, &b, id, w->tmp, w->tmp_id);
    }
    *nl = l - s->begin;
    return r;
}

/* ---- the binary tree ---- */

static void build(bwork *w, const span *s);

/* The calling thread's report of c->done (locked: tasks may be running),
   every 2^14 elements; false once it is told to stop. */
static int report(bwork *w, int force)
{
    bctx *c = w->c;
    size_t done;
    int stop;
    if (!w->first || !c->prog) return 1;
    if (c->threads > 1) pthread_mutex_lock(&c->mu);
    done = c->done, stop = c->stop;
    if (c->threads > 1) pthread_mutex_unlock(&c->mu);
    if (stop) return 0;
    if (!force && done - w->told < ((size_t)1 << 14)) return 1;
    w->told = done;
    if (!gg_progress_to(c->prog, done, c->total)) return 1;
    if (c->threads > 1) pthread_mutex_lock(&c->mu);
    c->stop = 1;
    if (c->threads > 1) pthread_mutex_unlock(&c->mu);
    return 0;
}

/* Build subtree k now, or (splitting the top, and small enough) leave
   it to the threads. */
static void build_child(bwork *w, const span *k)
{
    bctx *c = w->c;
    if (w->top && k->end - k->begin <= task_max && c->ntask < c->cap) {
        c->task[c->ntask++] = *k;
        return;
    }
    build(w, k);
}

/* Give the children of s the room s has beyond its records, in
   proportion to their counts, and move the right records to the start of
   theirs (from w->tmp after a spatial split, else from mid). A subtree
   with room for m records owns the 2m - 1 binary nodes after its root. */
static void place(bctx *c, const span *s, span *L, span *R, uint32_t nl, uint32_t nr,
                  const bref *from, const uint32_t *from_id)
{
    uint32_t spare = s->cap - s->begin - nl - nr;
    uint32_t capl = nl + (uint32_t)((uint64_t)spare * nl / (nl + nr));
    uint32_t mid = s->begin + nl;
    L->begin = s->begin, L->end = mid, L->cap = s->begin + capl;
    R->begin = s->begin + capl, R->end = R->begin + nr, R->cap = s->cap;
    if (from) {
        memcpy(c->r + R->begin, from, nr * sizeof *from);
        memcpy(c->id + R->begin, from_id, nr * sizeof *from_id);
    } else if (R->begin != mid) {
        memmove(c->r + R->begin, c->r + mid, nr * sizeof *c->r);
        memmove(c->id + R->begin, c->id + mid, nr * sizeof *c->id);
    }
    L->depth = R->depth = s->depth + 1;
    L->node = s->node + 1, R->node = s->node + 2 * capl;
}

/* The split of s: spatial when it beats the object split (and there is
   room), by the object split's bins otherwise, or at the median. */
static void split_span(bwork *w, const span *s, const split *sp, const ssplit *ssp, span *L,
                       span *R)
{
    bctx *c = w->c;
    span t = *s;
    uint32_t mid = s->begin, nl, nr;
    if (ssp->axis >= 0 && tmp_room(w, s->end - s->begin)) {
        nr = partition_spatial(w, s, ssp, L, R, &nl);
        if (nl && nr) {
            place(c, s, L, R, nl, nr, w->tmp, w->tmp_id);
            return;
        }
        /* the clipped boxes left one side empty: halve what there is */
        if (!nl) {
            memcpy(c->r + s->begin, w->tmp, nr * sizeof *w->tmp);
            memcpy(c->id + s->begin, w->tmp_id, nr * sizeof *w->tmp_id);
        }
        t.end = s->begin + nl + nr;
        span_box(c, &t);
        mid = split_median(c, &t, L, R);
    } else {
        if (sp->axis >= 0) mid = partition(c, s, sp, L, R);
        if (sp->axis < 0 || mid == s->begin || mid == s->end) mid = split_median(c, s, L, R);
    }
    place(c, &t, L, R, mid - t.begin, t.end - mid, NULL, NULL);
}

/* Build the subtree of s into its slots. Depth stays below GG_MEDIAN_AT +
   log2(room) + 1, so the traversal stack (which holds at most 3 entries
   per level) cannot overflow. */
static void build(bwork *w, const span *s)
{
    bctx *c = w->c;
    bnode2 *nd = &c->n[s->node];
    uint32_t n = s->end - s->begin;
    float lo[4], hi[4];
    span L, R;
    split sp;
    ssplit ssp;
    /* A node of the top is a pass over its elements: a report each (in a
       task, only between tasks: worker). Only this thread sets stop. */
    if (w->first && (c->stop || (w->top && !report(w, 1)))) return;
    v4_st(lo, s->b.lo), v4_st(hi, s->b.hi);
    memcpy(nd->lo, lo, sizeof nd->lo), memcpy(nd->hi, hi, sizeof nd->hi);
    sp.axis = ssp.axis = -1, sp.cost = ssp.cost = INFINITY;
    if (n == 1) goto leaf;
    if (s->depth < GG_MEDIAN_AT) {
        find_split(w, s, &sp);
        if (worth_spatial(w, s, &sp)) {
            find_spatial(w, s, &ssp);
            if (!(ssp.cost < sp.cost)) ssp.axis = -1;
        }
        if (n <= GG_MAX_LEAF && (sp.axis < 0 || leaf_cost(c, s->begin, n) <= sp.cost) &&
            (ssp.axis < 0 || leaf_cost(c, s->begin, n) <= ssp.cost))
            goto leaf;
    } else if (n <= GG_MAX_LEAF) {
        goto leaf;
    }
    split_span(w, s, &sp, &ssp, &L, &R);
    nd->leaf = 0, nd->a = L.node, nd->b = R.node;
    w->ninner++;
    build_child(w, &L);
    build_child(w, &R);
    return;
leaf:
    nd->leaf = 1, nd->a = s->begin, nd->b = n;
    if (w->first && !w->in_task) { /* the tasks' elements count when each ends */
        if (c->threads > 1) {
            pthread_mutex_lock(&c->mu);
            c->done += n;
            pthread_mutex_unlock(&c->mu);
        } else if ((c->done += n) - w->told >= ((size_t)1 << 14)) {
            (void)report(w, 1); /* sets stop when told */
        }
    }
}

/* ---- threads ---- */

static int build_threads_set; /* gg_bvh_set_threads; 0: the processors */

int gg_bvh_set_threads(int n)
{
    int was = build_threads_set;
    build_threads_set = n > 0 ? n : 0;
    return was;
}

void gg_bvh_set_build_sizes(size_t sizes[3])
{
    size_t was[3];
    was[0] = par_min, was[1] = task_max, was[2] = pbin_min;
    if (sizes[0]) par_min = sizes[0];
    if (sizes[1]) task_max = sizes[1];
    if (sizes[2]) pbin_min = sizes[2];
    memcpy(sizes, was, sizeof was);
}

static int build_threads(size_t n)
{
    long t = build_threads_set ? build_threads_set : sysconf(_SC_NPROCESSORS_ONLN);
    if (n < par_min || t < 2) return 1;
    return t > GG_MAX_THREAD ? GG_MAX_THREAD : (int)t;
}

static void *worker(void *p)
{
    bwork *w = p;
    bctx *c = w->c;
    span s;
    int have = 0;
    for (;;) {
        pthread_mutex_lock(&c->mu);
        if (have) c->done += s.end - s.begin; /* the task before, finished */
        have = 0;
        if (!c->stop && c->next < c->ntask) s = c->task[c->next++], have = 1;
        pthread_mutex_unlock(&c->mu);
        if (!have || !report(w, 0)) return NULL;
        w->in_task = 1;
        build(w, &s);
        w->in_task = 0;
    }
}

/* Largest first, so that no thread is left with a big one at the end. */
static int task_cmp(const void *pa, const void *pb)
{
    const span *a = pa, *b = pb;
    uint32_t na = a->end - a->begin, nb = b->end - b->begin;
    return na != nb ? (na < nb ? 1 : -1) : (a->node > b->node) - (a->node < b->node);
}

/* Run the tasks on c->threads threads (fewer if some cannot start). */
static void run_tasks(bctx *c, bwork *w)
{
    pthread_t th[GG_MAX_THREAD];
    int started[GG_MAX_THREAD], t;
    qsort(c->task, c->ntask, sizeof *c->task, task_cmp);
    c->next = 0;
    for (t = 1; t < c->threads; t++) started[t] = !pthread_create(&th[t], NULL, worker, &w[t]);
    worker(&w[0]);
    for (t = 1; t < c->threads; t++)
        if (started[t]) pthread_join(th[t], NULL);
}

/* ---- collapse to 4-wide nodes ---- */

static double node_area(const bnode2 *k)
{
    double x = (double)k->hi[0] - k->lo[0], y = (double)k->hi[1] - k->lo[1],
           z = (double)k->hi[2] - k->lo[2];
    return x * y + y * z + z * x;
}

static void set_lane(gg_bnode *nd, int lane, const float lo[3], const float hi[3])
{
    int k;
    for (k = 0; k < 3; k++) {
        nd->b[k][lane] = f_down(lo[k]);
        nd->b[k + 3][lane] = f_up(hi[k]);
    }
}

/* The children of the 4-wide node for binary node n2: its two children,
   the one of largest area opened while it is inner and there are fewer
   than four (a leaf n2 is its own only child). */
static int open_kids4(const bctx *c, uint32_t n2, uint32_t kids[4])
{
    int nk, i;
    if (c->n[n2].leaf) {
        kids[0] = n2;
        return 1;
    }
    kids[0] = c->n[n2].a, kids[1] = c->n[n2].b, nk = 2;
    while (nk < 4) {
        int bi = -1;
        double ba = -1;
        for (i = 0; i < nk; i++) {
            const bnode2 *k = &c->n[kids[i]];
            double a = node_area(k);
            if (!k->leaf && a > ba) ba = a, bi = i;
        }
        if (bi < 0) break;
        kids[nk++] = c->n[kids[bi]].b;
        kids[bi] = c->n[kids[bi]].a;
    }
    return nk;
}

static uint32_t leaf_ref(const bnode2 *k)
{
    return GG_LEAF | k->a << 3 | (k->b - 1);
}

/* Turn the binary subtree at n2 into 4-wide nodes (depth first, parents
   before children, so a traversal mostly walks forward in memory). */
static uint32_t collapse(const bctx *c, gg_geom *g, uint32_t n2, size_t depth)
{
    uint32_t ni = (uint32_t)g->nnodes++, kids[4];
    int nk = open_kids4(c, n2, kids), i;
    if (depth > g->max_depth) g->max_depth = depth;
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
            nd->child[i] = leaf_ref(&c->n[kids[i]]);
            g->nleaves++;
        } else {
            uint32_t ch = collapse(c, g, kids[i], depth + 1);
            g->nodes[ni].child[i] = ch;
        }
    }
    return ni;
}

/* ---- 8-wide nodes ----

   The 8-wide tree (g->wnodes, for the AVX copy's single-ray walks) is
   collapsed straight from the binary tree, keeping its leaves: from the
   4-wide nodes, whose leaves cannot be opened, it came out about five
   lanes full (docs/performance.md, "Fuller 8-wide nodes"). Which binary
   nodes become wide nodes is chosen as in Ylitie, Karras and Laine,
   "Efficient Incoherent Ray Traversal on GPUs Through Compressed Wide
   BVHs" (HPG 2017), section 4.1, by dynamic programming over the binary
   tree: with the leaves fixed, the SAH cost of a wide tree is, up to a
   constant, the sum of its nodes' areas, and f[n][i-1] is the least such
   sum for the subtree of binary node n given i lanes in its parent. */
typedef struct wctx {
    const bctx *c;
    float (*f)[8];
} wctx;

/* The least cost of giving binary inner node nd's two subtrees j lanes
   between them, and the lanes of the first (*ka). */
static float wide_split(const wctx *x, const bnode2 *nd, int j, int *ka)
{
    float best = INFINITY;
    int k;
    for (k = 1; k < j; k++) {
        float v = x->f[nd->a][k - 1] + x->f[nd->b][j - k - 1];
        if (v < best) best = v, *ka = k;
    }
    return best;
}

static void wide_cost(const wctx *x, uint32_t n)
{
    const bnode2 *nd = &x->c->n[n];
    float *f = x->f[n], own;
    int i, k;
    if (nd->leaf) {
        for (i = 0; i < 8; i++) f[i] = 0;
        return;
    }
    wide_cost(x, nd->a);
    wide_cost(x, nd->b);
    own = (float)node_area(nd) + wide_split(x, nd, 8, &k); /* n as a wide node */
    f[0] = own;
    for (i = 2; i <= 8; i++) {
        float v = wide_split(x, nd, i, &k); /* n's subtrees in its parent's lanes */
        f[i - 1] = v < own ? v : own;
    }
}

/* The lanes of subtree n given j of them, by f's choices. */
static void wide_gather(const wctx *x, uint32_t n, int j, uint32_t *kids, int *nk)
{
    const bnode2 *nd = &x->c->n[n];
    int k = 1;
    if (nd->leaf || j == 1 || !(wide_split(x, nd, j, &k) < x->f[n][0])) {
        kids[(*nk)++] = n;
        return;
    }
    wide_gather(x, nd->a, k, kids, nk);
    wide_gather(x, nd->b, j - k, kids, nk);
}

/* The lanes of the wide node for binary node n (a leaf is its own lane). */
static int wide_kids(const wctx *x, uint32_t n, uint32_t kids[8])
{
    const bnode2 *nd = &x->c->n[n];
    int nk = 0, k = 1;
    if (nd->leaf) {
        kids[0] = n;
        return 1;
    }
    wide_split(x, nd, 8, &k);
    wide_gather(x, nd->a, k, kids, &nk);
    wide_gather(x, nd->b, 8 - k, kids, &nk);
    return nk;
}

/* The wide nodes of the subtree at n2, depth first, parents before
   children. The leaf references are the 4-wide tree's; gg_bvh_wide points
   those of triangle blocks at the blocks. */
static uint32_t collapse8(const wctx *x, gg_geom *g, uint32_t n2)
{
    const bctx *c = x->c;
    uint32_t wi = (uint32_t)g->nwnodes++, kids[8];
    int nk = wide_kids(x, n2, kids), i, k;
    for (i = 0; i < 8; i++) {
        gg_wnode *w = &g->wnodes[wi];
        const bnode2 *kn = i < nk ? &c->n[kids[i]] : NULL;
        for (k = 0; k < 3; k++) {
            w->b[k][i] = kn ? f_down(kn->lo[k]) : INFINITY;
            w->b[k + 3][i] = kn ? f_up(kn->hi[k]) : -INFINITY;
        }
        w->child[i] = kn && kn->leaf ? leaf_ref(kn) : GG_LEAF;
    }
    for (i = 0; i < nk; i++)
        if (!c->n[kids[i]].leaf) {
            uint32_t ch = collapse8(x, g, kids[i]);
            g->wnodes[wi].child[i] = ch;
        }
    return wi;
}

/* How many wide nodes collapse8 makes for the subtree at n2. */
static size_t count8(const wctx *x, uint32_t n2)
{
    uint32_t kids[8];
    int nk = wide_kids(x, n2, kids), i;
    size_t n = 1;
    for (i = 0; i < nk; i++)
        if (!x->c->n[kids[i]].leaf) n += count8(x, kids[i]);
    return n;
}

/* The 8-wide nodes for the AVX copy; c->n has nbin entries. */
static int build_wide(const bctx *c, gg_geom *g, size_t nbin)
{
    wctx x;
    size_t cap;
    if (!gg_bvh_avx_wanted(g)) return 0;
    x.c = c;
    x.f = gg_mem_alloc(g->alloc, nbin * sizeof *x.f);
    if (!x.f) return -1;
    wide_cost(&x, 0);
    cap = count8(&x, 0);
    g->wnode_mem = gg_mem_alloc(g->alloc, cap * sizeof(gg_wnode) + 64);
    if (g->wnode_mem) {
        g->wnodes = (gg_wnode *)(((uintptr_t)g->wnode_mem + 63) & ~(uintptr_t)63);
        memset(g->wnodes, 0, cap * sizeof(gg_wnode));
        collapse8(&x, g, 0);
    }
    gg_mem_free(g->alloc, x.f);
    return g->wnode_mem ? 0 : -1;
}

/* ---- entry ---- */

/* The threads' state and task list; with fewer than two threads, or
   short of memory for them, the calling thread builds alone. */
static bwork *start_work(bctx *c, size_t n, size_t room)
{
    bwork *w;
    int t;
    c->threads = build_threads(n);
    if (c->threads > 1) {
        c->cap = 2 * room / task_max + 256;
        c->task = gg_mem_calloc(c->alloc, c->cap, sizeof *c->task);
        if (!c->task || pthread_mutex_init(&c->mu, NULL)) {
            gg_mem_free(c->alloc, c->task);
            c->task = NULL, c->cap = 0, c->threads = 1;
        }
    }
    w = gg_mem_calloc(c->alloc, (size_t)c->threads, sizeof *w);
    if (!w) return NULL;
    for (t = 0; t < c->threads; t++) w[t].c = c;
    w[0].top = c->threads > 1, w[0].first = 1;
    return w;
}

static int build_tree(bctx *c, bwork *w, size_t n, size_t room, size_t *ninner)
{
    span root;
    int t;
    root.node = 0, root.begin = 0, root.end = (uint32_t)n, root.cap = (uint32_t)room;
    root.depth = 0;
    span_box(c, &root);
    c->root_area = half_area(root.b);
    build(&w[0], &root);
    if (c->threads > 1) {
        w[0].top = 0;
        run_tasks(c, w);
        pthread_mutex_destroy(&c->mu);
    }
    for (*ninner = 0, t = 0; t < c->threads; t++) *ninner += w[t].ninner;
    return 0;
}

/* Close the gaps that the room left between the leaves' records: leaves
   in tree order (left first, as they lie in the records) get consecutive
   slots in order[]. */
static void compact(bctx *c, uint32_t n2, uint32_t *order, size_t *k)
{
    while (!c->n[n2].leaf) {
        compact(c, c->n[n2].a, order, k);
        n2 = c->n[n2].b;
    }
    memmove(order + *k, c->id + c->n[n2].a, c->n[n2].b * sizeof *order);
    c->n[n2].a = (uint32_t)*k;
    *k += c->n[n2].b;
}

/* Room for spatial splits: GG_SPLIT_REFS more references per element
   where some elements are triangles to clip. */
static size_t build_room(const uint8_t *tri, gg_bvh_verts verts, size_t n)
{
    size_t i, extra = (size_t)(GG_SPLIT_REFS * (double)n);
    if (!tri || !verts || n < 2 || n + extra >= GG_MAX_ELEMS) return n;
    for (i = 0; i < n; i++)
        if (tri[i]) return n + extra;
    return n;
}

int gg_bvh_build(gg_geom *g, const double (*lo)[3], const double (*hi)[3], const uint8_t *tri,
                 gg_bvh_verts verts, const void *ud, size_t n, gg_progress *prog, uint32_t **order,
                 size_t *nref)
{
    bctx c;
    bwork *w = NULL;
    size_t i, ninner, room;
    int rc = -1, k;
    gg_bvh_free(g);
    *order = NULL, *nref = 0;
    if (n == 0) return 0;
    room = build_room(tri, verts, n);
    memset(&c, 0, sizeof c);
    c.alloc = g->alloc;
    c.tri = gg_bvh_avx_wanted(g) ? tri : NULL;
    c.clip = room > n ? tri : NULL, c.verts = verts, c.ud = ud;
    /* The count is in references (spatial splits add some, up to room):
       the tree two thirds of it at most, the nodes and the records made
       from it (here and in gg_geom_build) the rest. */
    c.prog = prog, c.total = room + room / 2;
    c.id = gg_mem_alloc(g->alloc, room * sizeof *c.id);
    c.r = gg_mem_calloc(g->alloc, room, sizeof *c.r);
    c.n = gg_mem_alloc(g->alloc, 2 * room * sizeof *c.n);
    if (!c.id || !c.r || !c.n || !(w = start_work(&c, n, room))) goto done;
    for (i = 0; i < n; i++) {
        for (k = 0; k < 3; k++) c.r[i].lo[k] = rec_lo(lo[i][k]), c.r[i].hi[k] = rec_hi(hi[i][k]);
        c.id[i] = (uint32_t)i;
    }
    build_tree(&c, w, n, room, &ninner);
    if (c.stop) { /* the tree is not whole */
        rc = -2;
        goto done;
    }
    gg_mem_free(g->alloc, c.r), c.r = NULL;
    compact(&c, 0, c.id, nref);
    {
        size_t cap = ninner ? ninner : 1;
        g->node_mem = gg_mem_alloc(g->alloc, cap * sizeof(gg_bnode) + 64);
        if (!g->node_mem) goto done;
        g->nodes = (gg_bnode *)(((uintptr_t)g->node_mem + 63) & ~(uintptr_t)63);
        memset(g->nodes, 0, cap * sizeof(gg_bnode));
    }
    collapse(&c, g, 0, 1);
    if (build_wide(&c, g, 2 * room)) goto done;
    if (prog && gg_progress_to(prog, room + room / 4, c.total)) {
        rc = -2;
        goto done;
    }
    *order = c.id, c.id = NULL;
    rc = 0;
done:
    gg_mem_free(g->alloc, c.id);
    gg_mem_free(g->alloc, c.r);
    gg_mem_free(g->alloc, c.n);
    gg_mem_free(g->alloc, c.task);
    if (w)
        for (k = 0; k < c.threads; k++) {
            gg_mem_free(g->alloc, w[k].tmp);
            gg_mem_free(g->alloc, w[k].tmp_id);
        }
    gg_mem_free(g->alloc, w);
    if (rc) gg_bvh_free(g), *nref = 0;
    return rc;
}
