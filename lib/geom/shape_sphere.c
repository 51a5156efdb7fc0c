/* SPDX-License-Identifier: MIT */
/*
** shape_sphere.c -- sphere bounds and surface (the intersection kernel is
** in shape_sphere.h).
*/
#include "shape_sphere.h"

void gg_sphere_bounds(const gg_sph *s, double lo[3], double hi[3])
{
    /* c +- r rounds; pad by a few ulps of the larger term. */
    double pad = (s->r + v3maxabs(s->c)) * 0x1p-50;
    lo[0] = s->c.x - s->r - pad, hi[0] = s->c.x + s->r + pad;
    lo[1] = s->c.y - s->r - pad, hi[1] = s->c.y + s->r + pad;
    lo[2] = s->c.z - s->r - pad, hi[2] = s->c.z + s->r + pad;
}

/* (u, v) on a sphere: u = azimuth around +z / 2 pi in [0, 1), v = polar
   angle from +z / pi in [0, 1] (v = 0 at the north pole). */
void gg_sphere_surface(const gg_sph *s, const gg_rayq *q, const gg_hit *h, gg_surf *out,
                       unsigned what)
{
    ggVec3 pl = v3sub(v3madd(q->o, q->d, h->t), s->c);
    double len = v3len(pl), phi;
    ggVec3 n;
    /* Re-project the point onto the sphere: o + t d carries the error of t
       times |d|, which grows with the distance travelled; the projection's
       error is a few ulps of r whatever the distance (pbrt, 3.9). */
    if (len > 0)
        pl = v3scale(pl, s->r / len);
    else
        pl = v3(0, 0, s->r);
    out->p = v3add(s->c, pl);
    n = v3scale(pl, 1 / s->r);
    n = v3norm(n);
    out->ng = n;
    out->ns = n;
    out->u = out->v = 0;
    if (what & GG_SURF_UV) {
        phi = atan2(n.y, n.x);
        if (phi < 0) phi += 2 * GG_PI;
        out->u = phi / (2 * GG_PI);
        if (out->u >= 1) out->u = 0;
        out->v = acos(n.z < -1 ? -1 : n.z > 1 ? 1 : n.z) / GG_PI;
    }
    /* |pl| is within gamma(5) of r per component, and the sum c + pl adds
       one rounding of |p|. */
    out->perr = gg_gamma(6) * v3maxabs(pl) + gg_gamma(2) * v3maxabs(out->p);
}
