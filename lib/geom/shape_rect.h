/* SPDX-License-Identifier: MIT */
/*
** shape_rect.h -- ray / parametric rectangle intersection kernel
** (internal, inlined into the traversal loops).
*/
#ifndef GG_SHAPE_RECT_H
#define GG_SHAPE_RECT_H

#include "geom_int.h"
#include "shape_poly.h"

/* Plane hit; then whether the ray passes inside, by gg_poly_inside on the
   four corners (the polygons' test: a rectangle sharing an edge with
   another, or with a polygon, whose corners are the same doubles, leaves
   no crack along it; testing s and t in [0, 1] on each rectangle's own
   dual basis let one ray in ten aimed at a shared edge through); then
   (s, t) of the hit point in the basis (e1, e2) through the dual basis
   a1, a2 (a_i . e_j = delta_ij), so parallelograms work too, clamped to
   [0, 1]. Returns t in (r->tmin, tmax]. */
GG_INLINE int gg_rect_kernel(const gg_krect *rc, const gg_rpre *r, double tmax, double *t,
                             double *s1, double *s2)
{
    double den = rc->n[0] * r->d[0] + rc->n[1] * r->d[1] + rc->n[2] * r->d[2];
    double fx = r->o[0] - rc->v[0][0], fy = r->o[1] - rc->v[0][1], fz = r->o[2] - rc->v[0][2];
    double tt, qx, qy, qz, u, v;
    if (den == 0) return 0;
    tt = -(rc->n[0] * fx + rc->n[1] * fy + rc->n[2] * fz) / den;
    if (!(tt > r->tmin && tt <= tmax)) return 0;
    if (!gg_poly_inside(rc->v, 4, r)) return 0;
    qx = fx + tt * r->d[0], qy = fy + tt * r->d[1], qz = fz + tt * r->d[2];
    u = qx * rc->a1[0] + qy * rc->a1[1] + qz * rc->a1[2];
    v = qx * rc->a2[0] + qy * rc->a2[1] + qz * rc->a2[2];
    *t = tt;
    *s1 = u < 0 ? 0 : u > 1 ? 1 : u;
    *s2 = v < 0 ? 0 : v > 1 ? 1 : v;
    return 1;
}

#endif
