/* SPDX-License-Identifier: MIT */
/*
** bvh.c -- the bounding volume hierarchy: node layout, triangle blocks,
** and the plain copy of the traversals (bvh_trav.inc.h). The build is in
** bvh_build.c.
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
** four at a time, with the same bits as the scalar kernel. For that copy
** the tree is also kept in 8-wide nodes (collapsed from the binary tree
** with it, bvh_build.c; gg_bvh_wide points their leaves at the blocks:
** the same float boxes and leaves), which its walks take, single rays and
** packets: one 8-lane AVX pass tests eight boxes, and a walk visits fewer
** nodes. The frustum test, the recorder's cost copy and the
** single-precision copy walk the 4-wide tree.
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

/* ---- run-time choice of the AVX traversal ---- */

/* The copy of the traversal g's build takes (an index into bvh.c's
   copies): the kernel table's (gg_cpu_kernels, what the CPU runs), no
   more than g allows (gg_geom_set_cpu) and this build has. */
static int trav_copy_of(const gg_geom *g)
{
    int k = gg_cpu_kernels()->trav;
    if (!GG_HAVE_BVH_AVX || !(g->cpu & GG_CPU_AVX)) return GG_KERNEL_PLAIN;
    if (k > GG_KERNEL_AVX && !(g->cpu & GG_CPU_AVX2)) return GG_KERNEL_AVX;
    if (k > GG_KERNEL_AVX2 && !(g->cpu & GG_CPU_AVX512)) return GG_KERNEL_AVX2;
    return k;
}

/* Whether builds of g make triangle blocks for the AVX traversal: this
   build has it, the CPU runs it and g allows it (gg_geom_set_cpu). */
int gg_bvh_avx_wanted(const gg_geom *g)
{
    return trav_copy_of(g) != GG_KERNEL_PLAIN;
}

void gg_bvh_free(gg_geom *g)
{
    gg_mem_free(g->alloc, g->node_mem);
    gg_mem_free(g->alloc, g->tleaf_mem);
    gg_mem_free(g->alloc, g->wnode_mem);
    g->wnode_mem = NULL;
    g->wnodes = NULL;
    g->nwnodes = 0;
    g->node_mem = NULL;
    g->nodes = NULL;
    g->tleaf_mem = NULL;
    g->tleaves = NULL;
    g->nnodes = g->nleaves = g->max_depth = g->ntleaves = 0;
    g->trav_avx = 0;
}

void gg_geom_bvh_stats(const gg_geom *g, gg_bvh_stats *st)
{
    st->nodes = g->nnodes;
    st->leaves = g->nleaves;
    st->max_depth = g->max_depth;
    st->bytes = g->nnodes * sizeof(gg_bnode) + g->nslots * sizeof(gg_slot) +
                g->nsph * sizeof(gg_ksph) + (g->ntri + g->npieces + g->nmtri) * sizeof(gg_ktri) +
                g->nlcone * sizeof(gg_kcone) + g->nrect * sizeof(gg_krect) +
                g->ntleaves * sizeof(gg_tleaf) + g->nwnodes * sizeof(gg_wnode);
    st->build_seconds = g->build_seconds;
    st->blocks = g->trav_avx ? g->ntleaves : 0;
#if defined(__SSE2__) && !defined(GG_BVH_NO_SIMD) /* GG_BVH_SIMD of bvh_trav.inc.h */
    st->traversal = g->trav_avx == GG_KERNEL_AVX512 ? "avx512"
                    : g->trav_avx == GG_KERNEL_AVX2 ? "avx2"
                    : g->trav_avx                   ? "avx"
                                                    : "sse2";
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
    if (!g->nnodes || !gg_bvh_avx_wanted(g)) return 0;
    for (i = 0; i < g->nnodes; i++)
        for (c = 0; c < 4; c++) nb += (size_t)tri_leaf(g, &g->nodes[i], c);
    /* the AVX copy, in its AVX2 build where the CPU and g allow it */
    g->trav_avx = trav_copy_of(g);
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

/* The 8-wide nodes (built with the tree, bvh_build.c) reach the triangle
   blocks gg_bvh_tri_leaves made: each leaf that became a block in the
   4-wide tree, found by its first slot, becomes the same block here. */
int gg_bvh_wide(gg_geom *g)
{
    uint32_t *blk;
    size_t i;
    int c;
    if (!g->trav_avx || !g->wnodes || !g->ntleaves) return 0;
    blk = gg_mem_calloc(g->alloc, g->nslots, sizeof *blk);
    if (!blk) return -1;
    for (i = 0; i < g->ntleaves; i++)
        blk[g->tleaves[i].first] = GG_LEAF | GG_TLEAF | (uint32_t)i << 3 | (g->tleaves[i].n - 1);
    for (i = 0; i < g->nwnodes; i++)
        for (c = 0; c < 8; c++) {
            uint32_t ref = g->wnodes[i].child[c];
            if (!(ref & GG_LEAF) || g->wnodes[i].b[0][c] == INFINITY) continue;
            if (blk[GG_LEAF_I(ref)]) g->wnodes[i].child[c] = blk[GG_LEAF_I(ref)];
        }
    gg_mem_free(g->alloc, blk);
    return 0;
}
#else
int gg_bvh_tri_leaves(gg_geom *g)
{
    g->trav_avx = 0;
    return 0;
}

int gg_bvh_wide(gg_geom *g)
{
    (void)g;
    return 0;
}
#endif

/* ---- the plain traversal ---- */

/* The plain copy tests every leaf with the scalar loops (bvh_hooks.h). */
#define GG_TX_FLOAT    0
#define GG_INC_NAME(f) f##_plain
#define GG_INC_LINK    static
#include "bvh_hooks.h"
#include "bvh_trav.inc.h"

/* The copies of the traversal, indexed by a geometry's g->trav_avx: the
   kernel table's entry (gg_cpu_kernels()->trav: GG_KERNEL_PLAIN, _AVX,
   _AVX2, _AVX512) as g's build restricted it (gg_bvh_tri_leaves). One load and an
   indirect call per query: a second test of trav_avx cost more
   (docs/performance.md, "One source per instruction set"). */
typedef struct trav_copy {
    int (*intersect)(const gg_geom *g, const gg_rayq *q, gg_hit *hit);
    uint32_t (*occluder)(const gg_geom *g, const gg_rayq *q, uint32_t *cache);
    int (*shadow)(const gg_geom *g, const gg_rayq *q, uint32_t *cache, gg_tcol *col);
    unsigned (*packet)(const gg_geom *g, const gg_rayq *q, unsigned lanes, gg_hit *hit);
} trav_copy;

#define GG_TRAV_COPY(isa)                                                                          \
    {                                                                                              \
        bvh_intersect_##isa, bvh_occluder_##isa, bvh_shadow_##isa, bvh_packet_##isa                \
    }
#define GG_TRAV_COPY_GG(isa)                                                                       \
    {                                                                                              \
        gg_bvh_intersect_##isa, gg_bvh_occluder_##isa, gg_bvh_shadow_##isa, gg_bvh_packet_##isa    \
    }
/* The fifth, TRAV_COUNTING, is the AVX copy's counting build
   (gg_geom_count_begin), never a geometry's own. */
#define TRAV_COUNTING 4
static const trav_copy copies[5] = {
    GG_TRAV_COPY(plain),
#if GG_HAVE_BVH_AVX
    GG_TRAV_COPY_GG(avx),
    GG_TRAV_COPY_GG(avx2),
    GG_TRAV_COPY_GG(avx512),
    GG_TRAV_COPY_GG(count),
#else
    GG_TRAV_COPY(plain),
    GG_TRAV_COPY(plain),
    GG_TRAV_COPY(plain),
    GG_TRAV_COPY(plain),
#endif
};
#define COPY(g) (&copies[(g)->trav_avx])

/* ---- counting the kernels (`ggrt bench limit`) ---- */

/* The geometry's own copy while the counting one is in place. */
static int counted_copy(const gg_geom *g)
{
    return g->trav_avx == TRAV_COUNTING ? trav_copy_of(g) : g->trav_avx;
}

int gg_geom_count_begin(gg_geom *g, gg_kcount *kc)
{
    if (!GG_HAVE_BVH_AVX || !g->built || g->trav_avx == GG_KERNEL_PLAIN ||
        g->trav_avx == TRAV_COUNTING)
        return -1;
    g->kcount = kc;
    g->trav_avx = TRAV_COUNTING;
    return 0;
}

void gg_geom_count_end(gg_geom *g)
{
    if (g->trav_avx != TRAV_COUNTING) return;
    g->trav_avx = counted_copy(g);
    g->kcount = NULL;
}

double gg_geom_kloop(const gg_geom *g, int k, const gg_rayq *q, long n)
{
    if (k < 0 || k >= GG_KL_N || n < 0 || !g->built || !g->nslots) return -1;
#if GG_HAVE_BVH_AVX
    switch (counted_copy(g)) {
    case GG_KERNEL_AVX:
        return gg_bvh_kloop_avx(g, k, q, n);
    case GG_KERNEL_AVX2:
        return gg_bvh_kloop_avx2(g, k, q, n);
    case GG_KERNEL_AVX512:
        return gg_bvh_kloop_avx512(g, k, q, n);
    default:
        break;
    }
#else
    (void)q;
#endif
    return -1;
}

/* Single-precision queries (GG_ISECT_FLOAT) take their own copy
   (bvh_float.c), chosen here once per query. */
#define GG_FLOAT_Q(q) GG_UNLIKELY((q)->opt->isect == GG_ISECT_FLOAT)

static int intersect(const gg_geom *g, const gg_rayq *q, gg_hit *hit)
{
    if (GG_FLOAT_Q(q)) return gg_bvh_intersect_float(g, q, hit);
    return COPY(g)->intersect(g, q, hit);
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

unsigned gg_geom_intersect_packet(const gg_geom *g, const gg_rayq *q, unsigned lanes, gg_hit *hit)
{
    unsigned alone = 0, got, m;
    /* An implicit surface's answer depends on the bound it is asked
       with (and may count a cut): one ray at a time, in the usual order. */
    if (g->nimp) alone = lanes;
    /* The packet walk is double; single-precision queries take their own
       copy (GG_FLOAT_Q), one by one too. */
    for (m = lanes & ~alone; m; m &= m - 1) {
        const gg_rayq *qi = &q[GG_CTZ(m)];
        if (qi->inside != UINT32_MAX || GG_FLOAT_Q(qi)) alone |= m & -m;
    }
    lanes &= ~alone;
    got = lanes ? COPY(g)->packet(g, q, lanes, hit) : 0;
    for (m = alone; m; m &= m - 1)
        if (gg_geom_intersect(g, &q[GG_CTZ(m)], &hit[GG_CTZ(m)])) got |= m & -m;
    return got;
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
    if (GG_FLOAT_Q(q) ? gg_bvh_shadow_float(g, q, cache, tr) : COPY(g)->shadow(g, q, cache, tr)) {
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
    hit = GG_FLOAT_Q(q) ? gg_bvh_occluder_float(g, q, cache) : COPY(g)->occluder(g, q, cache);
    *cache = hit;
    return hit != 0;
}
