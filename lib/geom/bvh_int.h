/* SPDX-License-Identifier: MIT */
/*
** bvh_int.h -- the BVH's node and leaf layout and its float rounding
** helpers, shared by the build and the traversal copies (bvh.c, bvh_avx.c,
** bvh_trav.inc.h; private to lib/geom: docs/internals.md, "Headers").
**
** References. A child reference with the top bit set is a leaf:
**   GG_LEAF | first << 3 | count - 1             a run of slots, or
**   GG_LEAF | GG_TLEAF | block << 3 | count - 1  a leaf of triangles only,
** whose vertices are also kept as one gg_tleaf block for the 4-wide test
** (bvh_avx.c); the block knows the leaf's first slot. Otherwise the
** reference is a node index.
*/
#ifndef GG_BVH_INT_H
#define GG_BVH_INT_H

#include "geom_leaf.h"

#include <string.h>

struct gg_bnode {
    float b[6][4];
    uint32_t child[4];
    uint32_t pad[4];
};

/* The same tree in 8-wide nodes (bvh_build.c, collapse8: which binary
   nodes become wide nodes is chosen by dynamic programming over the
   binary tree), for the AVX copy's single-ray walks: one 8-lane AVX pass
   tests eight boxes. The references are the 4-wide tree's leaves (and
   blocks, gg_bvh_wide) and wide node indices. A walk's stack: a wide
   node is no deeper than its binary node, so GG_WSTACK holds as GG_STACK
   does. 256 bytes. */
struct gg_wnode {
    float b[6][8];
    uint32_t child[8];
    uint32_t pad[8];
};

#define GG_LEAF      0x80000000u
#define GG_TLEAF     4u /* flag of a reference to a gg_tleaf block */
#define GG_LEAF_N(r) (((r)&3) + 1)
#define GG_LEAF_I(r) (((r) & ~GG_LEAF) >> 3) /* first slot, or block index */
#define GG_MAX_LEAF  4                       /* elements per leaf (at most 4: two bits of count) */
#define GG_STACK     256                     /* > 3 * maximum depth (see build2) */
/* the same for 8-wide nodes: each pushes <= 7; and one more, as the
   AVX-512 build's any-hit descent stores eight lanes (any_descend) */
#define GG_WSTACK     (7 * (GG_STACK / 3) + 8)
#define GG_EXIT_SCALE 1.00000059604644775390625f /* 1 + 5 * 2^-23 */

/* A leaf of 2 to 4 triangles in SoA form: v[axis][vertex][lane] holds
   coordinate `axis` of vertex `vertex` of the leaf's triangle `lane`, so
   a ray's axis permutation (kx, ky, kz) only picks rows and one 4-wide
   load fetches a coordinate of all four triangles. Unused lanes hold NaN:
   every edge function and t is then NaN, which no test accepts. */
struct gg_tleaf {
    double v[3][3][4];
    uint32_t first, n; /* the leaf's slots */
    uint32_t pad[6];
};

/* The copy for single-precision queries (GG_ISECT_FLOAT, bvh_float.c). */
int gg_bvh_intersect_float(const gg_geom *g, const gg_rayq *q, gg_hit *hit);
uint32_t gg_bvh_occluder_float(const gg_geom *g, const gg_rayq *q, uint32_t *cache);
int gg_bvh_shadow_float(const gg_geom *g, const gg_rayq *q, uint32_t *cache, gg_tcol *col);

/* The AVX copy of the traversal (bvh_avx.c) is a per-ISA object
   (compiler.h, "Per-ISA code"); the portable build of the BVH
   (GG_BVH_NO_SIMD, tests/unit/geom/test_bvh_scalar.c) has none. Which copy a query
   takes is the geometry's (gg_geom_set_cpu, g->trav_avx). */
#if GG_ISA_X86 && !defined(GG_BVH_NO_SIMD)
#define GG_HAVE_BVH_AVX 1
int gg_bvh_intersect_avx(const gg_geom *g, const gg_rayq *q, gg_hit *hit);
uint32_t gg_bvh_occluder_avx(const gg_geom *g, const gg_rayq *q, uint32_t *cache);
int gg_bvh_shadow_avx(const gg_geom *g, const gg_rayq *q, uint32_t *cache, gg_tcol *col);
unsigned gg_bvh_packet_avx(const gg_geom *g, const gg_rayq *q, unsigned lanes, gg_hit *hit);
/* The same source compiled for AVX2 (bvh_avx2.o, Makefile: ISA_AGAIN);
   call only where gg_cpu_features() has GG_CPU_AVX2. */
int gg_bvh_intersect_avx2(const gg_geom *g, const gg_rayq *q, gg_hit *hit);
uint32_t gg_bvh_occluder_avx2(const gg_geom *g, const gg_rayq *q, uint32_t *cache);
int gg_bvh_shadow_avx2(const gg_geom *g, const gg_rayq *q, uint32_t *cache, gg_tcol *col);
unsigned gg_bvh_packet_avx2(const gg_geom *g, const gg_rayq *q, unsigned lanes, gg_hit *hit);
/* And for AVX-512 (bvh_avx512.o, ISA_AGAIN): mask registers in the node
   and triangle tests; call only where gg_cpu_features() has
   GG_CPU_AVX512. */
int gg_bvh_intersect_avx512(const gg_geom *g, const gg_rayq *q, gg_hit *hit);
uint32_t gg_bvh_occluder_avx512(const gg_geom *g, const gg_rayq *q, uint32_t *cache);
int gg_bvh_shadow_avx512(const gg_geom *g, const gg_rayq *q, uint32_t *cache, gg_tcol *col);
unsigned gg_bvh_packet_avx512(const gg_geom *g, const gg_rayq *q, unsigned lanes, gg_hit *hit);
/* For tests: the 4-wide triangle test of block L alone. Returns the mask
   of lanes hit with t in (r->tmin, tmax] and fills t, b1, b2 for them;
   *zero gets the lanes left to the scalar kernel (an edge function
   exactly 0). Call only where gg_cpu_features() has GG_CPU_AVX. */
/* The counting build (bvh_count_avx.o: GG_TRAV_COUNT; call only where
   the CPU has AVX and g has an AVX copy's tree): g->kcount counts. */
int gg_bvh_intersect_count(const gg_geom *g, const gg_rayq *q, gg_hit *hit);
uint32_t gg_bvh_occluder_count(const gg_geom *g, const gg_rayq *q, uint32_t *cache);
int gg_bvh_shadow_count(const gg_geom *g, const gg_rayq *q, uint32_t *cache, gg_tcol *col);
unsigned gg_bvh_packet_count(const gg_geom *g, const gg_rayq *q, unsigned lanes, gg_hit *hit);
/* gg_geom_kloop in each build. */
double gg_bvh_kloop_avx(const gg_geom *g, int k, const gg_rayq *q, long n);
double gg_bvh_kloop_avx2(const gg_geom *g, int k, const gg_rayq *q, long n);
double gg_bvh_kloop_avx512(const gg_geom *g, int k, const gg_rayq *q, long n);
unsigned gg_bvh_tri4_avx(const gg_tleaf *L, const gg_rpre *r, double tmax, double t[4],
                         double b1[4], double b2[4], unsigned *zero);
unsigned gg_bvh_tri4_avx2(const gg_tleaf *L, const gg_rpre *r, double tmax, double t[4],
                          double b1[4], double b2[4], unsigned *zero);
unsigned gg_bvh_tri4_avx512(const gg_tleaf *L, const gg_rpre *r, double tmax, double t[4],
                            double b1[4], double b2[4], unsigned *zero);
#else
#define GG_HAVE_BVH_AVX 0
#endif

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

#endif
