/* SPDX-License-Identifier: MIT */
/*
** shape_rect.h -- ray / parametric rectangle intersection kernel
** (internal, inlined into the traversal loops).
*/
#ifndef GG_SHAPE_RECT_H
#define GG_SHAPE_RECT_H

#include "geom_int.h"

/* Plane hit, then (s, t) of the hit point in the basis (e1, e2) through
   the dual basis a1, a2 (a_i . e_j = delta_ij), so parallelograms work
   too. Returns t in (r->tmin, tmax] and (s, t) in [0,1]^2. */
GG_INLINE int gg_rect_kernel(const gg_krect *rc, const gg_rpre *r, double tmax, double *t,
                             double *s1, double *s2)
{
    double den = rc->n[0] * r->d[0] + rc->n[1] * r->d[1] + rc->n[2] * r->d[2];
    double fx = r->o[0] - rc->c[0], fy = r->o[1] - rc->c[1], fz = r->o[2] - rc->c[2];
    double tt, qx, qy, qz, u, v;
    if (den == 0) return 0;
    tt = -(rc->n[0] * fx + rc->n[1] * fy + rc->n[2] * fz) / den;
    if (!(tt > r->tmin && tt <= tmax)) return 0;
    qx = fx + tt * r->d[0], qy = fy + tt * r->d[1], qz = fz + tt * r->d[2];
    u = qx * rc->a1[0] + qy * rc->a1[1] + qz * rc->a1[2];
    if (!(u >= 0 && u <= 1)) return 0;
    v = qx * rc->a2[0] + qy * rc->a2[1] + qz * rc->a2[2];
    if (!(v >= 0 && v <= 1)) return 0;
    *t = tt;
    *s1 = u;
    *s2 = v;
    return 1;
}

#endif
