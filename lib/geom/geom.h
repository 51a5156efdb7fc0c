/* SPDX-License-Identifier: MIT */
/*
** geom.h -- primitives, their intersection, and the BVH over them
** (internal). The scene owns one gg_geom; every primitive remembers the
** scene object it belongs to.
**
** Hits come in two steps: traversal finds (t, prim, b1, b2) as cheaply as
** possible; gg_geom_surface then works out the point, normals and (u, v)
** for the one hit that is shaded.
**
** Exactness: gg_geom_intersect returns exactly what testing every
** primitive returns (same prim, same t to the bit; equal t is settled by
** the smaller primitive index), whatever the traversal order. The float
** boxes are conservative (see bvh.c), triangles are watertight (a ray
** through a shared edge or vertex hits exactly one of the triangles).
**
** Thread safety: after gg_geom_build, all queries are const and may run
** concurrently; adds, gg_geom_set_* and builds may not overlap queries.
**
** Spawning a secondary ray from a hit (what the renderer should do):
**     gg_geom_surface(g, &q, &hit, &s);
**     q2.o = gg_offset_origin(&s, dir, GG_OFFSET_SCALED);
**     q2.d = dir; q2.tmin = 0; q2.tmax = INFINITY (or 1 for a shadow ray
**     with dir = light - q2.o);
**     q2.ignore_prim = hit.prim for planar kinds (TRIANGLE, POLYGON, RECT;
**         a flat surface cannot be met again), UINT32_MAX for curved ones
**         (SPHERE, CONE, IMPLICIT: the far side is the same primitive);
**     q2.skip_flags = GG_PRIM_TRANSPARENT for shadow rays that let
**         transparent occluders through (they are then handled apart).
** The offset alone is enough to never find the surface just left (tested
** on 1e6 rays at scales 1e-6..1e6); ignore_prim merely saves the test.
*/
#ifndef GG_GEOM_H
#define GG_GEOM_H

#include "core.h"

/* Per-primitive flags, tested by gg_rayq.skip_flags. */
#define GG_PRIM_TRANSPARENT 1u

/* Numerical variants, selectable for the accuracy study (issue 6). */
#define GG_SPHERE_STABLE   0 /* Haines et al., Ray Tracing Gems ch. 7 */
#define GG_SPHERE_TEXTBOOK 1 /* b^2 - 4ac */
#define GG_OFFSET_SCALED   0 /* offset scaled to the hit point's magnitude */
#define GG_OFFSET_FIXED    1 /* one fixed epsilon (1e-6 unless set) */

typedef struct gg_geom gg_geom;

gg_geom *gg_geom_create(const ggAllocator *alloc);
void gg_geom_free(gg_geom *g);

/* Add primitives. `obj` is the owning scene object. Each returns the
   primitive index (>= 0; indices are consecutive from 0) or -1 when out of
   memory or on degenerate input: NaN/infinite coordinates, radius <= 0,
   zero-area triangle, polygon with n < 3 or no area, cone with a negative
   radius, both radii 0 or zero height, rectangle with parallel edges.
   A polygon of 3 vertices becomes a triangle (kind GG_SHAPE_TRIANGLE).
   Larger polygons are split into triangles by ear clipping when they are
   simple (GG_POLY_TRIANGULATE); self-intersecting ones and those beyond
   4096 vertices stay whole and use the even-odd crossing test. Triangle
   normals that are zero or NaN make the triangle flat-shaded. */
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
   and returns the first's index, or -1 when out of memory or beyond the
   element limit. Every triangle must have finite vertices and a nonzero
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

/* Build the BVH (SAH). Must be called after the last add and before any
   query. Returns GG_OK or GG_ERROR_NOMEM. */
int gg_geom_build(gg_geom *g, ggError *err);

/* Select numerical variants (defaults: stable sphere, scaled offset). */
void gg_geom_set_sphere_mode(gg_geom *g, int mode);

/* How polygons with more than 3 vertices are intersected. Takes effect for
   polygons added after the call. */
#define GG_POLY_TRIANGULATE 0 /* ear-clipped into watertight triangles (default) */
#define GG_POLY_CROSSING    1 /* one primitive, crossing test (also the fallback) */
void gg_geom_set_poly_mode(gg_geom *g, int mode);

/* A ray query. d need not be unit length; t is in units of |d|. The
   interval (tmin, tmax) is open at both ends; tmin >= 0 is the fast path
   (a negative tmin works, by testing every primitive). NaN or infinite
   o or d, d = 0, or tmax <= tmin: no hit. */
typedef struct gg_rayq {
    ggVec3 o, d;
    double tmin, tmax;
    uint32_t ignore_prim; /* a primitive to skip (the one the ray leaves), or UINT32_MAX */
    unsigned skip_flags;  /* skip primitives with any of these flags */
} gg_rayq;

typedef struct gg_hit {
    double t;
    uint32_t prim;
    uint32_t sub;  /* internal: which triangle of a split polygon (else 0) */
    double b1, b2; /* shape-specific: barycentrics, or (u, v) */
} gg_hit;

/* Closest hit in (tmin, tmax): fills *hit, returns 1; 0 if none (then
   *hit is untouched). hit->b1, b2: triangles the barycentric weights of
   vertices 1 and 2; polygons the same for the triangle hit->sub of the
   polygon's split; rectangles (s, t); other kinds 0. */
int gg_geom_intersect(const gg_geom *g, const gg_rayq *q, gg_hit *hit);
/* Any hit in (tmin, tmax): 1 if occluded. */
int gg_geom_occluded(const gg_geom *g, const gg_rayq *q);

/* gg_geom_occluded with an occluder cache (the SPD-era "shadow cache"):
   *cache is an opaque value the caller keeps per thread and per light
   (start with 0). The element that occluded the previous ray is tested
   first; whatever occludes this ray is remembered, and a ray that nothing
   occludes empties the cache (*cache = 0). Neighbouring shadow rays are
   mostly blocked by the same object, so a full traversal is often
   skipped; after a clear ray the next one mostly is clear too, and
   testing a stale occluder first would be wasted (on the SPD tree, 97%
   of those tests failed). Same answer as gg_geom_occluded. */
int gg_geom_occluded_cached(const gg_geom *g, const gg_rayq *q, uint32_t *cache);

/* The two questions of a coloured shadow ray in one traversal: returns 1
   if a primitive not flagged GG_PRIM_TRANSPARENT is hit in (tmin, tmax)
   (what gg_geom_occluded answers with skip_flags = GG_PRIM_TRANSPARENT);
   else 0, with *has_tr = 1 and *tr the nearest hit when there is one
   (then exactly what gg_geom_intersect returns for q), *has_tr = 0 if
   nothing is hit. q->skip_flags is ignored. */
int gg_geom_shadow_query(const gg_geom *g, const gg_rayq *q, gg_hit *tr, int *has_tr);
/* The same with an occluder cache as gg_geom_occluded_cached's (it may
   share that cache): the opaque element that blocked last is tried first,
   the one that blocks is remembered, and a segment that nothing opaque
   blocks empties it. Same answers. */
int gg_geom_shadow_query_cached(const gg_geom *g, const gg_rayq *q, gg_hit *tr, int *has_tr,
                                uint32_t *cache);

/* Every crossing of a transparent surface on a shadow segment, nearest
   first (gg_geom_shadow_query_all). complete = 1 when h[0..n) is all of
   them: not more than GG_TCOL_CAP, and no implicit surface among them
   (whose roots beyond the first are not searched). Spheres and cone
   slices report both of their roots. */
#define GG_TCOL_CAP 8
typedef struct gg_tcol {
    int n, complete;
    gg_hit h[GG_TCOL_CAP];
} gg_tcol;

/* gg_geom_shadow_query_cached that, when nothing opaque blocks (return
   0), also lists every transparent crossing in (tmin, tmax) in *all,
   sorted by (t, prim, sub); *tr and *has_tr as there. */
int gg_geom_shadow_query_all(const gg_geom *g, const gg_rayq *q, gg_hit *tr, int *has_tr,
                             uint32_t *cache, gg_tcol *all);

/* 1 when no ray from eye into the pyramid spanned by the directions d[0..3]
   (corners of a rectangle of the image plane, in order around it) can hit
   any primitive: no BVH leaf box reaches into it (lib/geom/frustum.c; the test
   is conservative, see there). 0 when one may, or for degenerate input. */
int gg_geom_frustum_empty(const gg_geom *g, ggVec3 eye, const ggVec3 d[4]);

/* Same answers by testing every primitive (for tests). */
int gg_geom_intersect_brute(const gg_geom *g, const gg_rayq *q, gg_hit *hit);

typedef struct gg_surf {
    ggVec3 p;    /* hit point */
    ggVec3 ng;   /* unit geometric normal as the shape defines it */
    ggVec3 ns;   /* unit shading normal, on ng's side */
    double u, v; /* surface coordinates */
    double perr; /* bound on the absolute error of p (for offsets) */
} gg_surf;

/* Point, normals and (u, v) of a hit returned by gg_geom_intersect for
   the same query q. Per kind (ng never depends on the ray: the renderer
   decides front/back by the sign of d . ng):
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
   magnitudes p was computed from (pbrt's analysis), e.g. gamma(7) * (|b0 v0|
   + |b1 v1| + |b2 v2|) for triangles; see the shape files. */
void gg_geom_surface(const gg_geom *g, const gg_rayq *q, const gg_hit *hit, gg_surf *s);

/* The same, computing (u, v) only when `what` has GG_SURF_UV (spheres and
   cones spend an atan2 on them): untextured materials can pass 0, and
   then s->u = s->v = 0. gg_geom_surface is what = GG_SURF_UV. */
#define GG_SURF_UV 1u
void gg_geom_surface_ex(const gg_geom *g, const gg_rayq *q, const gg_hit *hit, gg_surf *s,
                        unsigned what);

/* Origin for a ray leaving surface point s->p in direction d: pushed off
   the surface along ng, to the side d goes to, far enough that the new ray
   cannot find the same surface again and no farther than needed.
   GG_OFFSET_SCALED pushes by GG_OFFSET_K * s->perr (and rounds away from
   the surface); GG_OFFSET_FIXED by 1e-6 in scene units. d . ng == 0 counts
   as the ng side. */
ggVec3 gg_offset_origin(const gg_surf *s, ggVec3 d, int mode);
/* The fixed-epsilon variant with any epsilon (accuracy study). */
ggVec3 gg_offset_origin_fixed(const gg_surf *s, ggVec3 d, double eps);
#define GG_OFFSET_K 8.0

/* BVH statistics for reports and benchmarks. */
typedef struct gg_bvh_stats {
    size_t nodes, leaves, max_depth, bytes;
    size_t blocks; /* AVX four-triangle leaf blocks (0: plain traversal) */
    double build_seconds;
} gg_bvh_stats;
void gg_geom_bvh_stats(const gg_geom *g, gg_bvh_stats *st);

/* 0 when the segment o + t d, t in [0, 1], certainly meets no primitive
   flagged GG_PRIM_TRANSPARENT (tested against the union of their boxes,
   conservatively); 1 when it may. Cheap: for skipping a transparent walk. */
int gg_geom_transparent_may_hit(const gg_geom *g, ggVec3 o, ggVec3 d);

/* gg_geom_intersect for a ray that starts inside the sphere `prim`
   (a hint: e.g. refracted into it). When that sphere is isolated (at
   build time no other element's box came within a margin of its ball),
   the origin lies in the grown ball and the sphere is hit, nothing else
   can be nearer: the sphere alone is tested, and the answer (1 with *hit
   filled) is exactly gg_geom_intersect's. Returns -1 when it cannot say
   (not an isolated sphere, origin outside, ignored, no hit): the caller
   then asks gg_geom_intersect. */
int gg_geom_intersect_inside(const gg_geom *g, const gg_rayq *q, uint32_t prim, gg_hit *hit);

/* Scene bounds (valid after build). */
void gg_geom_bounds(const gg_geom *g, ggVec3 *lo, ggVec3 *hi);

#endif
