/* SPDX-License-Identifier: MIT */
/*
** shape_poly.h -- ray / planar polygon kernel for polygons kept whole
** (GG_POLY_CROSSING, or when triangulation was refused). Internal.
*/
#ifndef GG_SHAPE_POLY_H
#define GG_SHAPE_POLY_H

#include "geom_int.h"

/* The even-odd crossing test of the polygon v[0 .. nv-1] (nv >= 3)
   around the ray, in the same sheared ray space as the triangle kernel:
   the ray is the origin of that 2D plane, so no hit point is projected
   and the edge test is the sign of the same 2D cross product a neighbour
   sharing the edge computes (negated exactly when it runs the other way).
   A point exactly on an edge is counted by strict inequalities that agree
   between both sides, so two polygons sharing an edge never both miss it.
   Concave and self-intersecting polygons follow the even-odd rule.
   Returns 1 when the ray passes inside. */
GG_INLINE int gg_poly_inside(const double (*v)[3], uint32_t nv, const gg_rpre *r)
{
    const int kx = r->kx, ky = r->ky, kz = r->kz;
    double px, py, z;
    uint32_t i;
    int inside = 0;
    z = v[nv - 1][kz] - r->o[kz];
    px = v[nv - 1][kx] - r->o[kx] - r->sx * z;
    py = v[nv - 1][ky] - r->o[ky] - r->sy * z;
    for (i = 0; i < nv; i++) {
        double cx, cy;
        z = v[i][kz] - r->o[kz];
        cx = v[i][kx] - r->o[kx] - r->sx * z;
        cy = v[i][ky] - r->o[ky] - r->sy * z;
        if ((py > 0) != (cy > 0)) {
            double e = px * cy - py * cx;
            if (cy > py ? e > 0 : e < 0) inside ^= 1;
        }
        px = cx, py = cy;
    }
    return inside;
}

/* Plane hit, then gg_poly_inside. */
GG_INLINE int gg_poly_kernel(const gg_geom *g, const gg_poly *pl, const gg_rpre *r, double tmax,
                             double *t)
{
    const double(*v)[3] = (const double(*)[3])g->pverts + pl->vfirst;
    double den = pl->f.n.x * r->d[0] + pl->f.n.y * r->d[1] + pl->f.n.z * r->d[2];
    double tt;
    if (den == 0) return 0;
    tt = (pl->f.n.x * (pl->f.p0.x - r->o[0]) + pl->f.n.y * (pl->f.p0.y - r->o[1]) +
          pl->f.n.z * (pl->f.p0.z - r->o[2])) /
         den;
    if (!(tt > r->tmin && tt <= tmax)) return 0;
    if (!gg_poly_inside(v, pl->nv, r)) return 0;
    *t = tt;
    return 1;
}

#endif
