/* SPDX-License-Identifier: MIT */
/*
** geom_int.h -- the layout behind gg_geom, shared by geom.c, bvh.c and the
** shape_*.c files (private to lib/geom: docs/internals.md, "Headers").
**
** Primitives are kept twice: in insertion order with everything shading
** needs (normals, frames), and, after the build, as compact intersection
** records copied in BVH leaf order so that a traversal walks memory
** forwards. A polygon usually becomes several triangles ("pieces") in the
** BVH; they report the polygon's primitive index.
*/
#ifndef GG_GEOM_INT_H
#define GG_GEOM_INT_H

#include "geom.h"
#include "vec.h"

#include <float.h>
#include <math.h>
#include <string.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

/* Unit roundoff of double and pbrt's gamma(n) = n u / (1 - n u), the
   bound on the relative error of n chained roundings. */
#define GG_U 0x1p-53
static inline double gg_gamma(int n)
{
    return n * GG_U / (1 - n * GG_U);
}

/* The next double toward -inf / +inf (nextafter without the libm call;
   NaN and infinities pass through). */
static inline double gg_next_down(double x)
{
    uint64_t u;
    if (!(x > -INFINITY)) return x;
    if (x == 0) return -0x1p-1074;
    memcpy(&u, &x, 8);
    u = x > 0 ? u - 1 : u + 1;
    memcpy(&x, &u, 8);
    return x;
}
/* gg_next_down(x), the case of a query's tmax (positive, often infinite)
   tested first: one compare and one step, where gg_next_down's form
   takes about a dozen instructions. Not for values of either sign
   (offsets of coordinates): that compare would then be a coin toss. */
static inline double gg_next_down_tmax(double x)
{
    uint64_t u;
    if (!(x > 0)) return gg_next_down(x);
    memcpy(&u, &x, 8);
    u--;
    memcpy(&x, &u, 8);
    return x;
}
static inline double gg_next_up(double x)
{
    return -gg_next_down(-x);
}

/* x rounded to the nearest float: the operands of the single-precision
   kernels (GG_ISECT_FLOAT, shape_tri.h, shape_sphere.h). Beyond the
   float range IEC 60559 arithmetic (C99 Annex F.4, __STDC_IEC_559__)
   gives +-inf, which no test of the kernels accepts; elsewhere such a
   conversion is undefined (C99 6.3.1.5) and x is clamped to +-FLT_MAX. */
static inline float gg_flt(double x)
{
#ifdef __STDC_IEC_559__
    return (float)x;
#else
    return (float)(x < -FLT_MAX ? -FLT_MAX : x > FLT_MAX ? FLT_MAX : x);
#endif
}

/* Kinds of BVH element (what the intersection kernels know). */
enum { GG_EK_SPHERE = 0, GG_EK_TRI, GG_EK_CONE, GG_EK_RECT, GG_EK_POLY, GG_EK_IMPLICIT };
#define GG_EK_SHIFT 29
#define GG_EK_INDEX ((1u << GG_EK_SHIFT) - 1)
/* Largest number of BVH elements (leaf references pack 28 bits). */
#define GG_MAX_ELEMS (1u << 28)

/* One BVH element in leaf order: the primitive it reports, its kind and
   the index of its record in the leaf-ordered array of that kind, and the
   sub-primitive (triangle of a split polygon, else 0). */
typedef struct gg_slot {
    uint32_t prim;
    uint32_t ki; /* kind << GG_EK_SHIFT | index */
    uint32_t sub;
} gg_slot;

/* Everything a query precomputes once per ray. */
typedef struct gg_rpre {
    double o[3], d[3];
    double tmin;
    double a, inv_a; /* d . d and its inverse */
    /* Woop-Benthin-Wald shear: kz is the dominant axis of d. */
    double sx, sy, sz;
    int kx, ky, kz;
    const gg_qopt *opt;     /* the query's options, never NULL */
    uint64_t *implicit_cut; /* the query's, or NULL */
    uint32_t ignore;
    unsigned skip;
} gg_rpre;

/* ---- intersection records (leaf order) ---- */
typedef struct gg_ksph {
    double c[3], r2;
} gg_ksph;
typedef struct gg_ktri {
    double v[3][3];
} gg_ktri;
typedef struct gg_kcone {
    double base[3], ex[3], ey[3], ez[3]; /* orthonormal frame, ez along the axis */
    double rb, k, h;                     /* radius rb + k z for z in [0, h] */
    double zlo, zhi;                     /* the slice of [0, h] this element covers */
} gg_kcone;
typedef struct gg_krect {
    double v[4][3];            /* corners c, c + e1, (c + e1) + e2, c + e2 */
    double n[3], a1[3], a2[3]; /* e1 x e2, dual basis of (e1, e2) */
} gg_krect;

/* ---- primitives in insertion order ---- */
typedef struct gg_prim {
    uint8_t kind;  /* ggShapeKind */
    uint32_t data; /* index in the array of that kind */
    int32_t obj;
    int32_t tag; /* the owner's (gg_geom_set_tag) */
} gg_prim;

typedef struct gg_sph {
    ggVec3 c;
    double r;
} gg_sph;

/* 104 bytes, two lines read per hit: the vertex normals, which most
   triangles lack, live apart (gg_geom.tnrm). */
typedef struct gg_tri {
    gg_ktri k;
    ggVec3 ng;   /* the unit geometric normal, flip applied (gg_tri_set_normal) */
    uint32_t ni; /* vertex normals (unit): gg_geom.tnrm[3 ni ..], or GG_TRI_FLAT */
    int flip;    /* the vertex normals face -(B-A)x(C-A): ng is flipped to match */
} gg_tri;
#define GG_TRI_FLAT UINT32_MAX

typedef struct gg_poly {
    uint32_t vfirst, nv;          /* vertices in gg_geom.pverts */
    uint32_t piece_first, npiece; /* triangles in gg_geom.pieces; 0 = crossing test */
    gg_uv_plane f;                /* plane (unit Newell normal f.n, the front side; first
                                     vertex f.p0) and (u, v) frame (geom.h) */
} gg_poly;

typedef struct gg_cone {
    gg_kcone k;
    double ra;
} gg_cone;

typedef struct gg_rect {
    gg_krect k;
    ggVec3 e1, e2;
} gg_rect;

/* A triangle mesh of gg_geom_add_mesh; the arrays belong to the caller.
   Its triangles are the primitives pfirst .. pfirst + ntri - 1, of kind
   GG_SHAPE_MESH in gg_prim (data = the mesh's index); queries report them
   as triangles (gg_geom_prim_kind). */
typedef struct gg_gmesh {
    const ggVec3 *pos, *nrm; /* nrm: unit (or zero) per vertex, or NULL */
    const double *uv;        /* 2 per vertex, or NULL */
    const uint32_t *idx;     /* 3 per triangle */
    uint32_t pfirst, ntri;
} gg_gmesh;

/* ---- the BVH ---- */
typedef struct gg_bnode gg_bnode; /* defined in bvh_int.h */
typedef struct gg_wnode gg_wnode; /* defined in bvh_int.h */
typedef struct gg_tleaf gg_tleaf; /* defined in bvh_int.h */

/* How polygons with more than 3 vertices are intersected (poly_mode; the
   tests set GG_POLY_CROSSING to check that kernel on every polygon). */
#define GG_POLY_TRIANGULATE 0 /* ear-clipped into watertight triangles (default) */
#define GG_POLY_CROSSING    1 /* one primitive, crossing test (also the fallback) */

struct gg_geom {
    ggAllocator alloc_copy;
    const ggAllocator *alloc;
    int poly_mode; /* for polygons added from then on */

    gg_prim *prims;
    uint8_t *pflags;
    size_t nprim, cap_prim, cap_flags;

    gg_sph *sphs;
    size_t nsph, cap_sph;
    gg_tri *tris;
    size_t ntri, cap_tri;
    ggVec3 *tnrm; /* 3 per triangle that has vertex normals */
    size_t ntnrm, cap_tnrm;
    gg_poly *polys;
    size_t npoly, cap_poly;
    double (*pverts)[3];
    size_t npverts, cap_pverts;
    gg_ktri *pieces;
    size_t npieces, cap_pieces;
    gg_cone *cones;
    size_t ncone, cap_cone;
    gg_rect *rects;
    size_t nrect, cap_rect;
    const ggImplicit **imps;
    size_t nimp, cap_imp;
    gg_gmesh *gmeshes;
    size_t ngmesh, cap_gmesh, nmtri; /* nmtri: triangles of all meshes */

    /* built */
    int built;
    ggVec3 lo, hi;
    /* Per primitive: a sphere whose ball (grown by iso_margin) meets no
       other element's box, see gg_geom_inside_hit; else 0. */
    uint8_t *iso;
    double *iso_margin;
    gg_slot *slots;
    size_t nslots;
    int clipped; /* some element has more than one slot (bvh_build.c, spatial splits) */
    gg_ksph *lsph;
    gg_ktri *ltri;
    gg_kcone *lcone;
    size_t nlcone; /* cone slices */
    gg_krect *lrect;
    void *node_mem; /* raw allocation; nodes is it aligned to 64 */
    gg_bnode *nodes;
    size_t nnodes, nleaves, max_depth;
    void *tleaf_mem; /* raw allocation; tleaves is it aligned to 64 */
    gg_tleaf *tleaves;
    size_t ntleaves;
    void *wnode_mem;  /* raw allocation; wnodes is it aligned to 64 */
    gg_wnode *wnodes; /* the tree again in 8-wide nodes, for the AVX single-ray walks */
    size_t nwnodes;
    unsigned cpu; /* GG_CPU_* the build may use (gg_geom_set_cpu) */
    int trav_avx; /* the walk copy queries take: 0 plain, 1 AVX (bvh_avx.c), 2 its AVX2 build,
                     3 its AVX-512 build */
    double build_seconds;
    gg_progress *prog; /* the next build's progress (gg_geom_set_progress), or NULL */
    /* What the counting copy (bvh_count_avx.o) counts into while
       gg_geom_count_begin has it in place; NULL otherwise. Last, so that
       no other member moved for the copies that never read it. */
    gg_kcount *kcount;
};

/* Per-shape code (shape_*.c). Bounds are conservative boxes in double. */
void gg_sphere_bounds(const gg_sph *s, double lo[3], double hi[3]);
void gg_sphere_surface(const gg_sph *s, const gg_rayq *q, const gg_hit *h, gg_surf *out,
                       unsigned what);
void gg_tri_bounds(const gg_ktri *t, double lo[3], double hi[3]);
/* t->ng from t->k and t->flip: call once the two are set (a hit reads it,
   rather than normalising a cross product every time). */
void gg_tri_set_normal(gg_tri *t);
/* n: t's three vertex normals (t->ni's), or NULL for a flat triangle. */
void gg_tri_surface(const gg_tri *t, const ggVec3 *n, const gg_rayq *q, const gg_hit *h,
                    gg_surf *out, unsigned what);
/* Point on a triangle from barycentrics (b1, b2 of vertices 1, 2) and its
   error bound. */
ggVec3 gg_tri_point(const gg_ktri *t, double b1, double b2, double *perr);
/* 0, GG_GEOM_DEGENERATE or GG_GEOM_NOMEM (geom.h). */
int gg_poly_prepare(gg_geom *g, const ggVec3 *p, int n, gg_poly *out);
void gg_poly_bounds(const gg_geom *g, const gg_poly *pl, double lo[3], double hi[3]);
void gg_poly_surface(const gg_geom *g, const gg_poly *pl, const gg_rayq *q, const gg_hit *h,
                     gg_surf *out, unsigned what);
int gg_cone_prepare(ggVec3 base, double rb, ggVec3 apex, double ra, gg_cone *out);
/* Long thin cones are split into slices along the axis, one BVH element
   each, so that their boxes hug them (a diagonal cylinder's box is mostly
   empty). Slice i of n covers z in [h i/n, h (i+1)/n]. */
uint32_t gg_cone_slices(const gg_cone *c);
void gg_cone_slice(const gg_cone *c, uint32_t i, uint32_t n, gg_kcone *out);
void gg_cone_bounds(const gg_kcone *k, double lo[3], double hi[3]);
void gg_cone_surface(const gg_cone *c, const gg_rayq *q, const gg_hit *h, gg_surf *out,
                     unsigned what);
int gg_rect_prepare(ggVec3 corner, ggVec3 e1, ggVec3 e2, gg_rect *out);
void gg_rect_bounds(const gg_rect *r, double lo[3], double hi[3]);
void gg_rect_surface(const gg_rect *r, const gg_rayq *q, const gg_hit *h, gg_surf *out);
void gg_implicit_shape_bounds(const ggImplicit *imp, double lo[3], double hi[3]);
/* Mesh triangles (shape_mesh.c): the vertices of primitive `prim` (of kind
   GG_SHAPE_MESH) as an intersection record, and its surface. */
void gg_mesh_ktri(const gg_geom *g, uint32_t prim, gg_ktri *k);
void gg_mesh_surface(const gg_geom *g, uint32_t prim, const gg_rayq *q, const gg_hit *h,
                     gg_surf *out, unsigned what);
int gg_implicit_shape_hit(const ggImplicit *imp, const gg_rpre *r, double tmax, double *t);
void gg_implicit_shape_surface(const ggImplicit *imp, const gg_rayq *q, const gg_hit *h,
                               gg_surf *out);

/* Closest hit by testing every element (geom.c): the traversal's fallback
   for rays its float boxes cannot represent, and the tests' reference. */
int gg_geom_intersect_brute(const gg_geom *g, const gg_rayq *q, gg_hit *hit);

/* The q->inside shortcut (geom.c): when sphere q->inside is isolated and
   the origin lies in its grown ball, its hit (tested with the skip flags
   `skip` instead of q's) is the closest of anything: 1 with *hit filled.
   -1 when it cannot say (no such sphere, origin outside, no hit). */
int gg_geom_inside_hit(const gg_geom *g, const gg_rayq *q, unsigned skip, gg_hit *hit);

/* The body of gg_rpre_init, inlined where the traversal sets up its own
   per-ray state right after it (bvh.c): o and d then stay in registers. */
GG_INLINE int gg_rpre_fill(gg_rpre *r, const gg_rayq *q)
{
    double ax = fabs(q->d.x), ay = fabs(q->d.y), az = fabs(q->d.z), dk;
    /* x * 0 is NaN exactly when x is infinite or NaN: one test for the
       origin. A direction that is not finite needs none of its own: d . d
       is then infinite or NaN, which the test of a below turns away. */
    double z = q->o.x * 0 + q->o.y * 0 + q->o.z * 0;
    if (z != 0) return 0;
    r->o[0] = q->o.x, r->o[1] = q->o.y, r->o[2] = q->o.z;
    r->d[0] = q->d.x, r->d[1] = q->d.y, r->d[2] = q->d.z;
    r->a = q->d.x * q->d.x + q->d.y * q->d.y + q->d.z * q->d.z;
    if (!(r->a > 0) || r->a == INFINITY) return 0;
    r->tmin = q->tmin;
    {
        /* Written as selects: random directions make branches here
           unpredictable, and a misprediction costs more than all of it. */
        int kz = ax > ay ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
        int kx = kz == 2 ? 0 : kz + 1, ky = kx == 2 ? 0 : kx + 1;
        int neg = r->d[kz] < 0;
        r->kz = kz;
        r->kx = neg ? ky : kx;
        r->ky = neg ? kx : ky;
        dk = r->d[kz];
    }
#if defined(__SSE2__)
    {
        /* both reciprocals with one division */
        __m128d inv = _mm_div_pd(_mm_set1_pd(1.0), _mm_set_pd(dk, r->a));
        r->inv_a = _mm_cvtsd_f64(inv);
        r->sz = _mm_cvtsd_f64(_mm_unpackhi_pd(inv, inv));
    }
#else
    r->inv_a = 1 / r->a;
    r->sz = 1.0 / dk;
#endif
    r->sx = r->d[r->kx] * r->sz;
    r->sy = r->d[r->ky] * r->sz;
    r->opt = q->opt;
    r->implicit_cut = q->implicit_cut;
    r->ignore = q->ignore_prim;
    r->skip = q->skip_flags;
    return 1;
}

/* Ray precomputation; returns 0 if the ray can hit nothing (NaN, d = 0). */
int gg_rpre_init(gg_rpre *r, const gg_rayq *q);

/* BVH (bvh_build.c): build over element boxes. tri[i] (or NULL) tells
   whether element i is a triangle: leaves of triangles are cheaper for
   the AVX traversal, which the build's cost model then allows for, and
   spatial splits may clip triangles (verts(ud, i, v) gives element i's
   vertices v[vertex][axis]), so that an element may be in more than one
   leaf. Allocates *order (g->alloc) with the element of each of the
   *nref slots in leaf order. Reports to prog (if not NULL) the elements
   of the subtrees finished, out of n, from the calling thread. Returns
   0, -1 when out of memory, -2 when prog asked to stop. */
typedef void (*gg_bvh_verts)(const void *ud, uint32_t i, double v[3][3]);
int gg_bvh_build(gg_geom *g, const double (*lo)[3], const double (*hi)[3], const uint8_t *tri,
                 gg_bvh_verts verts, const void *ud, size_t n, gg_progress *prog, uint32_t **order,
                 size_t *nref);
void gg_bvh_free(gg_geom *g);
/* After the slots are filled: keep the leaves that hold only triangles
   also as gg_tleaf blocks, and choose the traversal copy (g->trav_avx),
   when gg_bvh_avx_wanted(g). Returns -1 when out of memory. */
int gg_bvh_tri_leaves(gg_geom *g);
/* With the AVX copy chosen (after gg_bvh_tri_leaves): the leaves of the
   8-wide nodes gg_bvh_build made (g->wnodes, for the AVX copy's
   single-ray walks) that are triangle blocks in the 4-wide tree become
   those blocks there too. 0, or -1 when out of memory. */
int gg_bvh_wide(gg_geom *g);
/* Whether builds of g make triangle blocks for the AVX traversal (bvh.c):
   this build has it (bvh_avx.c), the CPU runs it and g->cpu allows it. */
int gg_bvh_avx_wanted(const gg_geom *g);
/* Threads of later builds (0: the processors online; small builds use
   one); returns the previous setting. The tree does not depend on it.
   Not thread-safe. */
int gg_bvh_set_threads(int n);
/* For tests: the element counts from which builds use threads, below
   which subtrees are handed to them, and from which a node is binned by
   all of them (sizes[0..2]; 0 keeps one). Swaps in the old values. Not
   thread-safe. */
void gg_bvh_set_build_sizes(size_t sizes[3]);

#endif
