/*
** geom.h -- primitives, their intersection, and the BVH over them
** (internal). The scene owns one gg_geom; every primitive remembers the
** scene object it belongs to.
**
** Hits come in two steps: traversal finds (t, prim, b1, b2) as cheaply as
** possible; gg_geom_surface then works out the point, normals and (u, v)
** for the one hit that is shaded.
*/
#ifndef GG_GEOM_H
#define GG_GEOM_H

#include "internal.h"

/* Per-primitive flags, tested by gg_rayq.skip_flags. */
#define GG_PRIM_TRANSPARENT 1u

/* Numerical variants, selectable for the accuracy study (issue 6). */
#define GG_SPHERE_STABLE    0 /* Haines et al., Ray Tracing Gems ch. 7 */
#define GG_SPHERE_TEXTBOOK  1 /* b^2 - 4ac */
#define GG_OFFSET_SCALED    0 /* offset scaled to the hit point's magnitude */
#define GG_OFFSET_FIXED     1 /* one fixed epsilon (1e-6 unless set) */

typedef struct gg_geom gg_geom;

gg_geom *gg_geom_create(const ggAllocator *alloc);
void gg_geom_free(gg_geom *g);

/* Add primitives. `obj` is the owning scene object. Each returns the
   primitive index (>= 0) or -1 when out of memory or degenerate input
   (zero radius, collinear polygon...). */
int gg_geom_add_sphere(gg_geom *g, ggVec3 c, double r, int32_t obj);
int gg_geom_add_triangle(gg_geom *g, const ggVec3 p[3], const ggVec3 *n /* 3 or NULL */,
                         int32_t obj);
int gg_geom_add_polygon(gg_geom *g, const ggVec3 *p, int n, int32_t obj);
int gg_geom_add_cone(gg_geom *g, ggVec3 base, double rb, ggVec3 apex, double ra, int32_t obj);
int gg_geom_add_rect(gg_geom *g, ggVec3 corner, ggVec3 e1, ggVec3 e2, int32_t obj);
/* The implicit surface stays owned by the caller and must outlive g. */
int gg_geom_add_implicit(gg_geom *g, const ggImplicit *imp, int32_t obj);

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

/* A ray query. d need not be unit length; t is in units of |d|. */
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

/* Closest hit in (tmin, tmax): fills *hit, returns 1; 0 if none. */
int gg_geom_intersect(const gg_geom *g, const gg_rayq *q, gg_hit *hit);
/* Any hit in (tmin, tmax): 1 if occluded. */
int gg_geom_occluded(const gg_geom *g, const gg_rayq *q);

/* Same answers by testing every primitive (for tests). */
int gg_geom_intersect_brute(const gg_geom *g, const gg_rayq *q, gg_hit *hit);

typedef struct gg_surf {
    ggVec3 p;      /* hit point */
    ggVec3 ng;     /* unit geometric normal as the shape defines it */
    ggVec3 ns;     /* unit shading normal, on ng's side */
    double u, v;   /* surface coordinates */
    double perr;   /* bound on the absolute error of p (for offsets) */
} gg_surf;

void gg_geom_surface(const gg_geom *g, const gg_rayq *q, const gg_hit *hit, gg_surf *s);

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
    double build_seconds;
} gg_bvh_stats;
void gg_geom_bvh_stats(const gg_geom *g, gg_bvh_stats *st);

/* Scene bounds (valid after build). */
void gg_geom_bounds(const gg_geom *g, ggVec3 *lo, ggVec3 *hi);

#endif
