/* SPDX-License-Identifier: MIT */
/*
** geom_leaf.h -- the loops that test a run of BVH elements against a ray,
** shared by the BVH traversal and the brute-force reference (internal).
** One switch on the element kind, no function pointer: the kernels inline.
*/
#ifndef GG_GEOM_LEAF_H
#define GG_GEOM_LEAF_H

#include "geom_int.h"
#include "shape_cone.h"
#include "shape_poly.h"
#include "shape_rect.h"
#include "shape_sphere.h"
#include "shape_tri.h"

/* Each loop below comes in two precisions, by a compile-time constant
   `fl` of the *_p form: 0 the double kernels (the plain names), 1 the
   single-precision triangle and sphere tests (GG_ISECT_FLOAT;
   bvh_float.c). */

/* Test one element; t in (r->tmin, tmax]. */
GG_INLINE int gg_elem_hit_p(const gg_geom *g, const gg_slot *s, const gg_rpre *r, double tmax,
                            double *t, double *b1, double *b2, int fl)
{
    uint32_t idx = s->ki & GG_EK_INDEX;
    switch (s->ki >> GG_EK_SHIFT) {
    case GG_EK_SPHERE:
        if (fl) return gg_sphere_kernel_f(&g->lsph[idx], r, tmax, t);
        return gg_sphere_kernel(&g->lsph[idx], r, tmax, t);
    case GG_EK_TRI:
        if (fl) return gg_tri_kernel_f(&g->ltri[idx], r, tmax, t, b1, b2);
        return gg_tri_kernel(&g->ltri[idx], r, tmax, t, b1, b2);
    case GG_EK_CONE:
        return gg_cone_kernel(&g->lcone[idx], r, tmax, t);
    case GG_EK_RECT:
        return gg_rect_kernel(&g->lrect[idx], r, tmax, t, b1, b2);
    case GG_EK_POLY:
        return gg_poly_kernel(g, &g->polys[idx], r, tmax, t);
    default:
        return gg_implicit_shape_hit(g->imps[idx], r, tmax, t);
    }
}
#define gg_elem_hit(g, s, r, tmax, t, b1, b2) gg_elem_hit_p(g, s, r, tmax, t, b1, b2, 0)

/* Keep a hit of slot s at t <= best->t if it is closer, or equally close
   with the smaller (prim, sub): the tie rule that makes the closest hit
   independent of visiting order. Returns 1 if it was kept. */
GG_INLINE int gg_leaf_take(gg_hit *best, const gg_slot *s, double t, double b1, double b2)
{
    if (!(t < best->t || s->prim < best->prim || (s->prim == best->prim && s->sub < best->sub)))
        return 0;
    best->t = t;
    best->prim = s->prim;
    best->sub = s->sub;
    best->b1 = b1;
    best->b2 = b2;
    return 1;
}

/* Closest hit among slots [first, first + n). best->t is the inclusive
   upper bound; equal t is settled by the smaller (prim, sub), so the
   answer does not depend on the order elements are visited in. */
GG_INLINE int gg_leaf_closest_p(const gg_geom *g, const gg_rpre *r, uint32_t first, uint32_t n,
                                gg_hit *best, int fl)
{
    const gg_slot *s = g->slots + first, *end = s + n;
    int found = 0;
    for (; s < end; s++) {
        double t, b1 = 0, b2 = 0;
        if (s->prim == r->ignore) continue;
        if (r->skip && (g->pflags[s->prim] & r->skip)) continue;
        if (!gg_elem_hit_p(g, s, r, best->t, &t, &b1, &b2, fl)) continue;
        found |= gg_leaf_take(best, s, t, b1, b2);
    }
    return found;
}
#define gg_leaf_closest(g, r, first, n, best) gg_leaf_closest_p(g, r, first, n, best, 0)

/* Any hit among slots [first, first + n) with t in (tmin, tmax]: returns
   the slot index + 1 of one that is hit, 0 if none. */
GG_INLINE uint32_t gg_leaf_any_p(const gg_geom *g, const gg_rpre *r, uint32_t first, uint32_t n,
                                 double tmax, int fl)
{
    const gg_slot *s = g->slots + first, *end = s + n;
    for (; s < end; s++) {
        double t, b1, b2;
        if (s->prim == r->ignore) continue;
        if (r->skip && (g->pflags[s->prim] & r->skip)) continue;
        if (gg_elem_hit_p(g, s, r, tmax, &t, &b1, &b2, fl)) return (uint32_t)(s - g->slots) + 1;
    }
    return 0;
}
#define gg_leaf_any(g, r, first, n, tmax) gg_leaf_any_p(g, r, first, n, tmax, 0)

/* A triangle that a spatial split clipped (bvh_build.c) is in more than
   one leaf and may be met again, with the same t: it crosses once, so
   with `clipped` (g->clipped) an entry equal in (t, prim, sub) to one
   listed is left out. (No element has two roots at one t: a sphere's or
   a cone's second root is asked for beyond the first.) */
static inline void gg_tcol_add(gg_tcol *col, const gg_slot *s, double t, double b1, double b2,
                               int clipped)
{
    gg_hit *h;
    int i;
    if (clipped)
        for (i = 0; i < col->n; i++)
            if (col->h[i].t == t && col->h[i].prim == s->prim && col->h[i].sub == s->sub) return;
    if (col->n == GG_TCOL_CAP) {
        col->complete = 0;
        return;
    }
    h = &col->h[col->n++];
    h->t = t, h->prim = s->prim, h->sub = s->sub, h->b1 = b1, h->b2 = b2;
}

/* A transparent element hit at t (its first root in (r->tmin, tmax]): into
   the list with the roots after it. Planar kinds have no other; spheres
   and cone slices at most one more, found by asking again from t. */
static inline void gg_tcol_elem(const gg_geom *g, const gg_rpre *r, const gg_slot *s, double t,
                                double b1, double b2, double tmax, gg_tcol *col, int fl)
{
    unsigned kind = s->ki >> GG_EK_SHIFT;
    gg_tcol_add(col, s, t, b1, b2, g->clipped);
    if (kind == GG_EK_SPHERE || kind == GG_EK_CONE) {
        gg_rpre r2 = *r;
        double t2, c1 = 0, c2 = 0;
        r2.tmin = t;
        if (gg_elem_hit_p(g, s, &r2, tmax, &t2, &c1, &c2, fl)) gg_tcol_add(col, s, t2, c1, c2, 0);
    } else if (kind == GG_EK_IMPLICIT) {
        col->complete = 0;
    }
}

/* The shadow query's test of slots [first, first + n) (bvh_trav.inc.h): the
   slot index + 1 of the first opaque element hit (then it stops), else 0;
   transparent ones update *best as gg_leaf_closest does, and go into col
   (if not NULL) wherever they are on the segment. */
GG_INLINE uint32_t gg_leaf_shadow_p(const gg_geom *g, const gg_rpre *r, uint32_t first, uint32_t n,
                                    double tmax, gg_hit *best, gg_tcol *col, int fl)
{
    const gg_slot *s = g->slots + first, *end = s + n;
    for (; s < end; s++) {
        double t, b1 = 0, b2 = 0;
        if (s->prim == r->ignore) continue;
        if (!(g->pflags[s->prim] & GG_PRIM_TRANSPARENT)) {
            if (gg_elem_hit_p(g, s, r, tmax, &t, &b1, &b2, fl)) return (uint32_t)(s - g->slots) + 1;
            continue;
        }
        if (col) {
            if (!gg_elem_hit_p(g, s, r, tmax, &t, &b1, &b2, fl)) continue;
            gg_tcol_elem(g, r, s, t, b1, b2, tmax, col, fl);
            if (t <= best->t) gg_leaf_take(best, s, t, b1, b2);
        } else if (gg_elem_hit_p(g, s, r, best->t, &t, &b1, &b2, fl))
            gg_leaf_take(best, s, t, b1, b2);
    }
    return 0;
}
#define gg_leaf_shadow(g, r, first, n, tmax, best, col)                                            \
    gg_leaf_shadow_p(g, r, first, n, tmax, best, col, 0)

#endif
