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
    double len = v3len(pl), uv[2];
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
        gg_uv_sphere_dir(n, uv);
        out->u = uv[0], out->v = uv[1];
    }
    /* |pl| is within gamma(5) of r per component, and the sum c + pl adds
       one rounding of |p|. */
    out->perr = gg_gamma(6) * v3maxabs(pl) + gg_gamma(2) * v3maxabs(out->p);
}

/* gg_sphere_kernel_f: see shape_sphere.h. */
int gg_sphere_kernel_f(const gg_ksph *s, const gg_rpre *r, double tmax, double *t)
{
    float fx = gg_flt(r->o[0]) - gg_flt(s->c[0]), fy = gg_flt(r->o[1]) - gg_flt(s->c[1]);
    float fz = gg_flt(r->o[2]) - gg_flt(s->c[2]);
    float dx = gg_flt(r->d[0]), dy = gg_flt(r->d[1]), dz = gg_flt(r->d[2]);
    float r2 = gg_flt(s->r2), a = dx * dx + dy * dy + dz * dz, b = fx * dx + fy * dy + fz * dz;
    float c = fx * fx + fy * fy + fz * fz - r2, disc, q, t0, t1;
    if (!(a > 0) || !(a < FLT_MAX)) return 0; /* d underflowed or overflowed in float */
    if (r->opt->sphere == GG_SPHERE_STABLE) {
        float k = b / a, lx = fx - k * dx, ly = fy - k * dy, lz = fz - k * dz;
        disc = r2 - (lx * lx + ly * ly + lz * lz);
        if (disc < 0) return 0;
        disc = sqrtf(a * disc);
        q = b >= 0 ? -(b + disc) : disc - b;
        if (q == 0) return 0;
        t0 = c / q;
        t1 = q / a;
        if (t0 > t1) {
            float tt = t0;
            t0 = t1, t1 = tt;
        }
    } else {
        float bb = 2 * b;
        disc = bb * bb - 4 * a * c;
        if (disc < 0) return 0;
        disc = sqrtf(disc);
        t0 = (-bb - disc) / (2 * a);
        t1 = (-bb + disc) / (2 * a);
    }
    if (t0 > r->tmin && t0 <= tmax) {
        *t = t0;
        return 1;
    }
    if (t1 > r->tmin && t1 <= tmax) {
        *t = t1;
        return 1;
    }
    return 0;
}
