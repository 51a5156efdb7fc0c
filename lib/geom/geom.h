/* SPDX-License-Identifier: MIT */
/*
** geom.h -- primitives, their intersection, and the BVH over them
** (internal). The scene owns one gg_geom; every primitive remembers the
** scene object it belongs to.
**
** Hits come in two steps: a query finds (t, prim, b1, b2) as cheaply as
** possible; gg_geom_surface then works out the point, normals and (u, v)
** for the one hit that is shaded. There are two queries: the closest hit
** (gg_geom_intersect) and occlusion (gg_geom_occluded), each with its
** options in the query.
**
** Exactness: gg_geom_intersect returns exactly what testing every
** primitive returns (same prim, same t to the bit; equal t is settled by
** the smaller primitive index), whatever the traversal order. The float
** boxes are conservative (see bvh.c), triangles are watertight (a ray
** through a shared edge or vertex hits exactly one of the triangles).
**
** Threads: adds, gg_geom_set_flags and gg_geom_build write; everything
** else only reads, so after gg_geom_build any number of threads may run
** queries and surface calls at once. Nothing a query is given (its
** gg_qopt included) is stored in the geometry: two renders with different
** options may share one built gg_geom.
**
** Spawning a secondary ray from a hit (what the renderer does):
**     gg_geom_surface(g, &q, &hit, &s, 0);
**     q2 = gg_rayq_make(gg_offset_origin(&s, dir), dir, 0, INFINITY, q.opt)
**         (for a shadow ray with dir = light - origin, tmax
**         gg_offset_end(origin, light), just short of 1);
**     q2.ignore_prim = hit.prim for planar kinds (TRIANGLE, POLYGON, RECT;
**         a flat surface cannot be met again), UINT32_MAX for curved ones
**         (SPHERE, CONE, IMPLICIT: the far side is the same primitive);
**     q2.inside = hit.prim when the ray enters a sphere (refracted in).
** The offset alone is enough to never find the surface just left
** (tests/unit/geom/test_offset.c: 1e6 rays at scales 1e-6..1e6); ignore_prim merely
** saves the test.
*/
#ifndef GG_GEOM_H
#define GG_GEOM_H

#include "core.h"

/* Per-primitive flags, tested by gg_rayq.skip_flags. */
#define GG_PRIM_TRANSPARENT 1u

/* ---- building ---- */

typedef struct gg_geom gg_geom;

gg_geom *gg_geom_create(const ggAllocator *alloc);
void gg_geom_free(gg_geom *g);

/* What the add functions return instead of a primitive index: the input
   is degenerate (the shape cannot be hit; nothing was added), memory ran
   out, or the element limit GG_MAX_ELEMS is reached. */
#define GG_GEOM_DEGENERATE (-1)
#define GG_GEOM_NOMEM      (-2)
#define GG_GEOM_LIMIT      (-3)

/* Add primitives. `obj` is the owning scene object. Each returns the
   primitive index (>= 0; indices are consecutive from 0), GG_GEOM_NOMEM,
   GG_GEOM_LIMIT or GG_GEOM_DEGENERATE on degenerate input: NaN/infinite coordinates, radius <= 0,
   zero-area triangle, polygon with n < 3 or no area, cone with a negative
   radius, both radii 0 or zero height, rectangle with parallel edges.
   A polygon of 3 vertices becomes a triangle (kind GG_SHAPE_TRIANGLE).
   Larger polygons are split into triangles by ear clipping when they are
   simple; self-intersecting ones and those beyond 4096 vertices stay
   whole and use the even-odd crossing test. Triangle normals that are
   zero or NaN make the triangle flat-shaded. */
/* Room for nprim primitives of which ntri are triangles (of
   gg_geom_add_triangle, or polygons of 3 vertices) in all, so that
   adding that many grows no array: each is allocated once at its size
   instead of doubled and copied. A hint: adding more still works.
   Returns 0 or GG_GEOM_NOMEM (then nothing is lost). */
int gg_geom_reserve(gg_geom *g, size_t nprim, size_t ntri);

int gg_geom_add_sphere(gg_geom *g, ggVec3 c, double r, int32_t obj);
int gg_geom_add_triangle(gg_geom *g, const ggVec3 p[3], const ggVec3 *n /* 3 or NULL */,
                         int32_t obj);
int gg_geom_add_polygon(gg_geom *g, const ggVec3 *p, int n, int32_t obj);
int gg_geom_add_cone(gg_geom *g, ggVec3 base, double rb, ggVec3 apex, double ra, int32_t obj);
int gg_geom_add_rect(gg_geom *g, ggVec3 corner, ggVec3 e1, ggVec3 e2, int32_t obj);
/* The implicit surface stays owned by the caller and must outlive g. */
int gg_geom_add_implicit(gg_geom *g, const ggImplicit *imp, int32_t obj);

/* A triangle mesh: vertices pos[0..), unit normals nrm (or NULL: flat;
   a zero normal at a corner makes that triangle flat), texture
   coordinates uv (2 per vertex, or NULL: (u, v) are the barycentrics as
   for triangles) and idx[3 ntri] into them. The arrays stay owned by the
   caller and must not change or move while g uses them. Adds ntri
   consecutive primitives of object obj, reported as GG_SHAPE_TRIANGLE,
   and returns the first's index, GG_GEOM_NOMEM or GG_GEOM_LIMIT (or
   GG_GEOM_DEGENERATE for no triangles). Every triangle must have finite vertices and a nonzero
   finite edge cross product (the caller checks; a triangle with none is
   never hit). Surfaces follow gg_geom_add_triangle's rules (the vertex
   normals decide which side ng faces), with (u, v) interpolated from uv. */
int gg_geom_add_mesh(gg_geom *g, const ggVec3 *pos, const ggVec3 *nrm, const double *uv,
                     const uint32_t *idx, size_t ntri, int32_t obj);
/* For a primitive of a mesh: the index of its triangle in that call's idx
   (0 .. ntri - 1); -1 for other primitives. */
long gg_geom_prim_mesh_triangle(const gg_geom *g, uint32_t prim);

void gg_geom_set_flags(gg_geom *g, int prim, unsigned flags);
size_t gg_geom_prim_count(const gg_geom *g);
int32_t gg_geom_prim_object(const gg_geom *g, uint32_t prim);
int gg_geom_prim_kind(const gg_geom *g, uint32_t prim); /* ggShapeKind */

/* A number the owner keeps per primitive, beside its object: 0 until
   gg_geom_set_tag sets it on primitives first .. first + n - 1 (those
   that exist). The scene keeps each object's material there, so shading
   a hit reads one primitive record and no object record: on a mesh of
   10^6 NFF triangles the object records (one per triangle) are a miss
   per hit. */
void gg_geom_set_tag(gg_geom *g, size_t first, size_t n, int32_t tag);

/* A hint, before shading a hit on prim, that starts reading what
   gg_geom_prim_info and gg_geom_surface will read, one dependent step per
   stage: 0 the primitive's record; 1 (once that is in) its shape's record,
   or a mesh triangle's indices; 2 (once those are in) a triangle's vertex
   normals, a mesh triangle's vertices and normals. Reads nothing out of range and changes nothing;
   stages given too early only wait as the reads would have. */
void gg_geom_prefetch_hit(const gg_geom *g, uint32_t prim, int stage);

/* What gg_geom_prim_object, gg_geom_prim_kind and the tag say of prim,
   from its one record. Returns 0 (and leaves *out) if prim is out of
   range, else 1. */
typedef struct gg_prim_info {
    int32_t obj, tag;
    int kind; /* as gg_geom_prim_kind */
} gg_prim_info;
int gg_geom_prim_info(const gg_geom *g, uint32_t prim, gg_prim_info *out);

/* The instruction sets (GG_CPU_* of core.h) that g's BVH and queries
   may use, of those the CPU runs; GG_CPU_ALL (the default) is the
   fastest, 0 the plain code. Takes effect at the next gg_geom_build. */
void gg_geom_set_cpu(gg_geom *g, unsigned cpu);

/* The progress of g's next gg_geom_build (and of no later one): the
   elements of the BVH's finished subtrees, out of all, reported to p from
   the calling thread, which may stop the build. NULL: none. p must
   outlive that build. */
void gg_geom_set_progress(gg_geom *g, gg_progress *p);

/* Build the BVH (SAH). Must be called after the last add and before any
   query. Returns GG_OK, GG_ERROR_LIMIT, GG_ERROR_NOMEM, or
   GG_ERROR_CANCELLED when the progress set with gg_geom_set_progress
   asked to stop (then g is as after a failed build: unbuilt, its
   primitives kept). */
int gg_geom_build(gg_geom *g, ggError *err);

/* Scene bounds (valid after build). */
void gg_geom_bounds(const gg_geom *g, ggVec3 *lo, ggVec3 *hi);

/* BVH statistics for reports and benchmarks. */
typedef struct gg_bvh_stats {
    size_t nodes, leaves, max_depth, bytes;
    size_t blocks; /* AVX four-triangle leaf blocks (0: plain traversal) */
    double build_seconds;
    const char *traversal; /* the copy queries take: "avx512", "avx2", "avx", "sse2" or "c" */
} gg_bvh_stats;
void gg_geom_bvh_stats(const gg_geom *g, gg_bvh_stats *st);

/* ---- queries ---- */

/* The choices of a render that change what the geometry answers (its
   accuracy knobs). A query carries them (gg_rayq.opt); they are never
   stored in the geometry. All zero is the default. */
#define GG_SPHERE_STABLE   0 /* Haines et al., Ray Tracing Gems ch. 7 (default) */
#define GG_SPHERE_TEXTBOOK 1 /* b^2 - 4ac, for the accuracy study */
/* The precision of the triangle and sphere tests (ggAccuracy.intersect,
   include/ggrt/render.h; the sphere formula is still `sphere`'s). With
   GG_ISECT_FLOAT the queries take a traversal copy of their own
   (bvh_float.c: the plain node walk, float triangle leaves), and
   gg_geom_surface scales the error bound of sphere and triangle hits to
   float roundings, so that gg_offset_origin clears them. */
#define GG_ISECT_DOUBLE 0
#define GG_ISECT_FLOAT  1
typedef struct gg_qopt {
    int sphere;          /* GG_SPHERE_* */
    int isect;           /* GG_ISECT_* */
    double implicit_tol; /* > 0: root tolerance of every implicit surface, in scene
                            units; 0: each surface's own (ggImplicitSetTolerance) */
    double gradient_h;   /* > 0: implicit normals by central differences with this
                            step; 0: each surface's own (ggImplicitSetNormalStep) */
} gg_qopt;

/* A ray query. d need not be unit length; t is in units of |d|. The
   interval (tmin, tmax) is open at both ends; tmin >= 0 is the fast path
   (a negative tmin works, by testing every primitive). NaN or infinite
   o or d, d = 0, or tmax <= tmin: no hit. gg_rayq_make fills the fields
   that are not the ray with their neutral values. */
typedef struct gg_rayq {
    ggVec3 o, d;
    double tmin, tmax;
    uint32_t ignore_prim; /* a primitive to skip (the one the ray leaves), or UINT32_MAX */
    unsigned skip_flags;  /* skip primitives with any of these flags */
    /* A sphere the ray starts inside of (refracted into it), or
       UINT32_MAX: a hint that may save the traversal (gg_geom_intersect,
       gg_geom_occluded), never changes an answer. */
    uint32_t inside;
    const gg_qopt *opt; /* never NULL (gg_rayq_make puts in the defaults) */
    /* NULL, or a counter of the implicit surfaces whose test of this ray ran
       out of evaluations (ggRayStats.implicit_cut) */
    uint64_t *implicit_cut;
} gg_rayq;

/* The default options: all zero. */
extern const gg_qopt gg_qopt_default;

static inline gg_rayq gg_rayq_make(ggVec3 o, ggVec3 d, double tmin, double tmax,
                                   const gg_qopt *opt /* NULL: the defaults */)
{
    gg_rayq q;
    q.o = o, q.d = d, q.tmin = tmin, q.tmax = tmax;
    q.ignore_prim = UINT32_MAX, q.skip_flags = 0, q.inside = UINT32_MAX;
    q.opt = opt ? opt : &gg_qopt_default;
    q.implicit_cut = NULL;
    return q;
}

typedef struct gg_hit {
    double t;
    uint32_t prim;
    uint32_t sub;  /* internal: which triangle of a split polygon (else 0) */
    double b1, b2; /* shape-specific: barycentrics, or (u, v) */
} gg_hit;

/* Closest hit in (tmin, tmax): fills *hit, returns 1; 0 if none (then
   *hit is untouched). hit->b1, b2: triangles the barycentric weights of
   vertices 1 and 2; polygons the same for the triangle hit->sub of the
   polygon's split; rectangles (s, t); other kinds 0.
   With q->inside, when that sphere is isolated (at build time no other
   element's box came within a margin of its ball) and the origin lies in
   the grown ball, the sphere alone is tested: nothing else can be nearer.
   The answer is the same as without the hint. */
int gg_geom_intersect(const gg_geom *g, const gg_rayq *q, gg_hit *hit);

/* Closest hits of up to GG_PACKET_MAX rays: for each set bit i of lanes
   (i < GG_PACKET_MAX), hit[i] and bit i of the result are what
   gg_geom_intersect(g, &q[i], &hit[i]) gives (hit[i] untouched where
   the bit is 0), bit for bit. Rays of one origin whose directions have
   the same signs (a row of eye rays) walk the BVH once together
   (bvh_trav.inc.h, "eye-ray packets"); others are traced one by one, and so
   is every ray of a geometry with implicit surfaces and every
   single-precision query (GG_ISECT_FLOAT). */
#define GG_PACKET_MAX 16
unsigned gg_geom_intersect_packet(const gg_geom *g, const gg_rayq *q, unsigned lanes, gg_hit *hit);

/* What one closest-hit query did: the BVH nodes whose four child boxes it
   tested, and the elements it tested in leaves (every element when it
   fell back to testing them all; 1 for the isolated-sphere hint). */
typedef struct gg_trav_cost {
    long nodes, prims;
} gg_trav_cost;

/* gg_geom_intersect with the same answer, counting into *cost (adds to
   it): a copy of the plain traversal that only the ray-tree recorder
   calls (bvh_cost.c), so the render's copies stay as they are. The walk
   is the one every copy takes (bvh_trav.inc.h): the counts are the render's. */
int gg_geom_intersect_cost(const gg_geom *g, const gg_rayq *q, gg_hit *hit, gg_trav_cost *cost);

/* The kernel calls of the AVX copies' walks, as a counting copy of them
   (bvh_avx.c built again with GG_TRAV_COUNT: bvh_count_avx.o) makes
   them; the copies the render takes count nothing. Per field: queries
   (closest, any = occluder, shadow = shadow with a crossing list,
   packets = packet walks), kernel calls (box8: 8-box node tests of the
   single-ray walks; pbox4: interval tests of a packet's walk (8 boxes in the
   AVX copies, 4 in the others);
   plane: a packet's 16-lane test of a leaf's box; tri4: 4-wide triangle
   block tests; tri, sphere, other: one element's test, by kind), and
   hits: closest-hit queries (single or packet lanes) that found one. */
typedef struct gg_kcount {
    uint64_t closest, any, shadow, packets;
    uint64_t box8, pbox4, plane, tri4, tri, sphere, other, hits;
} gg_kcount;

/* Route g's queries through the counting copy, counting into *kc (which
   is not cleared), until gg_geom_count_end; 0, or -1 when g's queries
   take no AVX copy (the plain copy has no counting twin) or this build
   has none. Not while other threads query g. */
int gg_geom_count_begin(gg_geom *g, gg_kcount *kc);
void gg_geom_count_end(gg_geom *g);

/* The kernels gg_geom_kloop runs: one call each, on the same data every
   time (cached), each call's input depending on the last one's result,
   as a walk's next node depends on this one's test. */
#define GG_KL_BOX8   0 /* box8 on the root of the 8-wide tree */
#define GG_KL_PBOX4  1 /* a packet's node test (pk_box8, or pk_box4 without the 8-wide
                          tree) on the root of the tree packets walk, a packet of 16 */
#define GG_KL_PLANE  2 /* pk_lanes on a box of that root, the same packet */
#define GG_KL_TRI4   3 /* the 4-wide triangle test of the first block */
#define GG_KL_TRI    4 /* the triangle kernel on the first triangle */
#define GG_KL_SPHERE 5 /* the sphere kernel on the first sphere */
#define GG_KL_OTHER  6 /* gg_elem_hit on the first element of another kind */
#define GG_KL_N      7
/* Run kernel k n times as the AVX copy g's queries take compiles it
   (bvh_kloop_*.o), with a ray from q's origin aimed at the kernel's
   data (the first element of its kind, the scene box's centre for the
   nodes); returns a sum of the results (so that the loop is not
   optimised away), or -1 when g has no such data (no triangle block, no
   sphere, ...) or no AVX copy. GG_KL_* are ggKernelLoop's GG_KERNEL_*. */
double gg_geom_kloop(const gg_geom *g, int k, const gg_rayq *q, long n);

/* The transparent surfaces a shadow segment crosses (gg_geom_occluded).
   complete = 1: h[0..n) is every crossing, nearest first (by t, prim,
   sub), and nothing opaque is on the segment; spheres and cone slices
   report both of their roots. complete = 0: the list overflowed
   (GG_TCOL_CAP), met an implicit surface (whose roots beyond the first
   are not searched), or was not made (the q->inside shortcut); then
   has_near tells whether near is the nearest crossing, and only that
   much is known. */
#define GG_TCOL_CAP 8
typedef struct gg_tcol {
    int n, complete;
    gg_hit h[GG_TCOL_CAP];
    int has_near;
    gg_hit near; /* exactly what gg_geom_intersect returns for the segment */
} gg_tcol;

/* Whether the segment (tmin, tmax) is blocked: 1 if it is, 0 if not.
   *cache is an occluder cache the caller keeps per thread and per light
   (start with 0; a caller without one passes a fresh 0): the element
   that blocked that light's previous shadow ray is tested first, and
   whatever blocks is remembered; a segment that nothing blocks empties
   it. Neighbouring shadow rays are mostly blocked by the same element
   (docs/performance.md). The cache changes no answer.
   tr NULL: every primitive blocks but those q->skip_flags skips.
   tr not NULL (coloured shadows): primitives flagged GG_PRIM_TRANSPARENT
   do not block, and when 0 is returned *tr lists what they cross
   (q->skip_flags is then ignored). With q->inside and tr, when the
   sphere's far side is provably the first thing the segment meets (as
   in gg_geom_intersect), 0 is returned with tr->near that hit and
   tr->complete = 0, without looking further: the caller walks on. */
int gg_geom_occluded(const gg_geom *g, const gg_rayq *q, uint32_t *cache, gg_tcol *tr);

/* 1 when no ray from eye into the pyramid spanned by the directions d[0..3]
   (corners of a rectangle of the image plane, in order around it) can hit
   any primitive: no BVH leaf box reaches into it (lib/geom/frustum.c; the
   test is conservative, see there). 0 when one may, or for degenerate
   input. */
int gg_geom_frustum_empty(const gg_geom *g, ggVec3 eye, const ggVec3 d[4]);

/* ---- surfaces and secondary rays ---- */

typedef struct gg_surf {
    ggVec3 p;    /* hit point */
    ggVec3 ng;   /* unit geometric normal as the shape defines it */
    ggVec3 ns;   /* unit shading normal, on ng's side */
    double u, v; /* surface coordinates (0, 0 unless asked for) */
    double perr; /* bound on the absolute error of p (for offsets) */
} gg_surf;

/* Point, normals and, when `what` has GG_SURF_UV, (u, v) of a hit that
   gg_geom_intersect returned for the same query q (whose opt it uses).
   Spheres and cones spend an atan2 on (u, v): untextured materials pass 0.
   Per kind (ng never depends on the ray: the renderer decides front/back
   by the sign of d . ng):
     sphere    ng outward; p re-projected onto the sphere;
               u = azimuth about +z / 2pi in [0,1), v = polar angle from +z / pi
     triangle  ng = unit (v1-v0) x (v2-v0), flipped to agree with the vertex
               normals if given (decided once per triangle); ns = the
               normalised barycentric blend of the vertex normals (ng where
               that would fall behind ng); (u, v) = barycentrics of v1, v2
     polygon   ng = Newell normal, the side from which the vertices run
               counter-clockwise; (u, v) = position in the plane frame
               (first edge, n x first edge) scaled so the polygon's bounding
               rectangle in that frame is [0,1]^2
     cone      ng outward, away from the axis; u = angle about the axis / 2pi,
               v = height fraction from the base (NFF c semantics: open, the
               radius goes linearly from base to apex)
     rect      ng = unit e1 x e2; (u, v) = (s, t) in [0,1]^2
     implicit  ng = unit grad f (toward growing f); (u, v) = (0, 0)
   perr bounds each coordinate's absolute error of p: gamma(n) times the
   magnitudes p was computed from (Pharr, Jakob, Humphreys, Physically Based
   Rendering 3rd ed., 3.9), e.g. gamma(7) * (|b0 v0| + |b1 v1| + |b2 v2|) for
   triangles; see the shape files. */
#define GG_SURF_UV 1u
void gg_geom_surface(const gg_geom *g, const gg_rayq *q, const gg_hit *hit, gg_surf *s,
                     unsigned what);

/* ---- (u, v) at a point, without a ray (lib/geom/uv.c) ----
   The (u, v) gg_geom_surface gives a hit at point p, from the shape's
   description alone, for ggSceneObjectUV: the surface functions above
   call the same formulas (gg_uv_sphere_dir, gg_uv_cone_local,
   gg_uv_plane_at, gg_uv_interp), so the two agree to the rounding of the
   hit point. p is taken onto the surface first: along the radius of a
   sphere, around a cone's axis, into the plane of a planar shape. Each
   int function returns 0, or -1 for a shape its gg_geom_add_* refuses
   as degenerate (it is never hit: it has no (u, v)) or a p that is not
   finite. */
/* A sphere from the unit direction n from its centre: u = atan2(n.y,
   n.x) / 2pi in [0, 1), v = acos(n.z) / pi. */
void gg_uv_sphere_dir(ggVec3 n, double uv[2]);
int gg_uv_sphere(ggVec3 c, double r, ggVec3 p, double uv[2]);
/* A cone's frame: e[0], e[1] across the axis (u is the angle from e[0]
   toward e[1]), e[2] the unit axis from base to apex; *h its height. */
int gg_uv_cone_frame(ggVec3 base, double rb, ggVec3 apex, double ra, ggVec3 e[3], double *h);
/* From the point's coordinates (x, y, z) in that frame, about the base:
   u = atan2(y, x) / 2pi in [0, 1), v = z / h clamped to [0, 1]. */
void gg_uv_cone_local(double x, double y, double z, double h, double uv[2]);
int gg_uv_cone(ggVec3 base, double rb, ggVec3 apex, double ra, ggVec3 p, double uv[2]);
/* (s, t) of p = corner + s e1 + t e2 (through the dual basis, as the
   rectangle kernel finds them). */
int gg_uv_rect(ggVec3 corner, ggVec3 e1, ggVec3 e2, ggVec3 p, double uv[2]);
/* A triangle's barycentrics (b1, b2) of vertices 1 and 2 at p; with tuv
   (the corners' (u, v), 6 numbers) the mesh's interpolation of them
   (gg_uv_interp), else (b1, b2) clamped to [0, 1] as gg_tri_surface does. */
int gg_uv_triangle(const ggVec3 v[3], const double *tuv, ggVec3 p, double uv[2]);
void gg_uv_interp(const double *u0, const double *u1, const double *u2, double b1, double b2,
                  double uv[2]);
/* A polygon's plane and (u, v) frame (n > 3 vertices: gg_geom_add_polygon
   makes a triangle of 3): the unit Newell normal n, the first vertex p0,
   eu along the first edge that is not zero, ev = n x eu, and the
   polygon's bounding rectangle in that frame [u0, u0 + 1/su] x [v0, v0 +
   1/sv]. gg_uv_plane_at: (u, v) = ((p - p0) . eu - u0) su and likewise v,
   each clamped to [0, 1]. */
typedef struct gg_uv_plane {
    ggVec3 n, p0, eu, ev;
    double u0, v0, su, sv;
} gg_uv_plane;
int gg_uv_plane_make(const ggVec3 *v, int nv, gg_uv_plane *out);
void gg_uv_plane_at(const gg_uv_plane *f, ggVec3 p, double uv[2]);

/* Origin for a ray leaving surface point s->p in direction d: pushed off
   the surface along ng, to the side d goes to, far enough that the new ray
   cannot find the same surface again and no farther than needed: by
   GG_OFFSET_K * s->perr, rounded away from the surface. d . ng == 0 counts
   as the ng side. gg_offset_origin_fixed pushes by eps instead (the
   textbook epsilon, for the accuracy study). */
#define GG_OFFSET_K 8.0
ggVec3 gg_offset_origin(const gg_surf *s, ggVec3 d);
ggVec3 gg_offset_origin_fixed(const gg_surf *s, ggVec3 d, double eps);

/* The end of a shadow ray's segment o + t (target - o): a t short of 1 by
   GG_OFFSET_K roundings of the coordinates involved, so that a surface
   through the light (a lamp set into a ceiling) does not block it at
   t = 1 - 2^-53. At least 0.5 (a target within rounding of o). The
   fixed-offset knob keeps t = 1: it shows what the textbook epsilon does
   (docs/accuracy.md). */
double gg_offset_end(ggVec3 o, ggVec3 target);

#endif
