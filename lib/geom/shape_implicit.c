/* SPDX-License-Identifier: MIT */
/*
** shape_implicit.c -- implicit surfaces as BVH elements: glue between the
** geometry module and the root finder of lib/implicit/implicit.c.
*/
#include "implicit.h"

#include "geom_int.h"

void gg_implicit_shape_bounds(const ggImplicit *imp, double lo[3], double hi[3])
{
    ggVec3 l, h;
    double pad;
    gg_implicit_bounds(imp, &l, &h);
    pad = (v3maxabs(l) + v3maxabs(h)) * 0x1p-48;
    lo[0] = l.x - pad, lo[1] = l.y - pad, lo[2] = l.z - pad;
    hi[0] = h.x + pad, hi[1] = h.y + pad, hi[2] = h.z + pad;
}

int gg_implicit_shape_hit(const ggImplicit *imp, const gg_rpre *r, double tmax, double *t)
{
    ggVec3 o = v3(r->o[0], r->o[1], r->o[2]), d = v3(r->d[0], r->d[1], r->d[2]);
    unsigned warn = 0;
    /* The root finder takes an open interval; ours is (tmin, tmax]. */
    int hit = gg_implicit_intersect_warn(imp, o, d, r->tmin, nextafter(tmax, INFINITY),
                                         r->opt->implicit_tol, t, &warn);
    if ((warn & GG_IMPLICIT_WARN_BUDGET) && r->implicit_cut) ++*r->implicit_cut;
    return hit;
}

/* ng = normalised grad f (pointing to where f grows); (u, v) = (0, 0). */
void gg_implicit_shape_surface(const ggImplicit *imp, const gg_rayq *q, const gg_hit *h,
                               gg_surf *out)
{
    ggVec3 n;
    double tol = q->opt->implicit_tol > 0 ? q->opt->implicit_tol : gg_implicit_tolerance(imp);
    out->p = v3madd(q->o, q->d, h->t);
    n = gg_implicit_normal_step(imp, out->p, q->opt->gradient_h);
    /* v3unit: |grad f|^2 underflows below about 2^-537 and overflows
       above 2^512, yet the gradient has a direction (f and 1e200 f are
       the same surface) */
    n = v3unit(n);
    if (!(v3dot(n, n) > 0)) n = v3norm(v3neg(q->d)); /* a critical point of f */
    out->ng = n;
    out->ns = n;
    out->u = 0;
    out->v = 0;
    /* The root finder's tolerance (the query's, else the surface's: a hit
       is within it of a sign change of f) plus the rounding of o + t d.
       It was 1e-9 of the box's largest side, 1000 times the default
       tolerance: in a box 2e6 wide, offsets of 0.016 lost the shadows
       of objects resting on the surface. */
    out->perr = tol + gg_gamma(4) * (v3maxabs(q->o) + h->t * v3maxabs(q->d));
}
