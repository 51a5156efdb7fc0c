/* SPDX-License-Identifier: MIT */
/*
** shape_cone.c -- open cones and cylinders (NFF `c`): frame, bounds and
** surface (the intersection kernel is in shape_cone.h).
*/
#include "shape_cone.h"

int gg_cone_prepare(ggVec3 base, double rb, ggVec3 apex, double ra, gg_cone *out)
{
    ggVec3 ax = v3sub(apex, base), ez, ex, ey;
    double h = v3len(ax), sg, a, b;
    if (!v3finite(base) || !v3finite(apex) || !(rb >= 0) || !(ra >= 0) || !isfinite(rb) ||
        !isfinite(ra) || !(rb + ra > 0) || !(h > 0) || !isfinite(h))
        return -1;
    ez = v3scale(ax, 1 / h);
    /* Duff et al., "Building an Orthonormal Basis, Revisited" (JCGT 2017):
       branch-free and without the 1/(1 + z) blow-up. */
    sg = ez.z >= 0 ? 1.0 : -1.0;
    a = -1 / (sg + ez.z);
    b = ez.x * ez.y * a;
    ex = v3(1 + sg * ez.x * ez.x * a, sg * b, -sg * ez.x);
    ey = v3(b, sg + ez.y * ez.y * a, -ez.y);
    out->k.base[0] = base.x, out->k.base[1] = base.y, out->k.base[2] = base.z;
    out->k.ex[0] = ex.x, out->k.ex[1] = ex.y, out->k.ex[2] = ex.z;
    out->k.ey[0] = ey.x, out->k.ey[1] = ey.y, out->k.ey[2] = ey.z;
    out->k.ez[0] = ez.x, out->k.ez[1] = ez.y, out->k.ez[2] = ez.z;
    out->k.rb = rb;
    out->k.k = (ra - rb) / h;
    out->k.h = h;
    out->k.zlo = 0;
    out->k.zhi = h;
    out->ra = ra;
    return 0;
}

uint32_t gg_cone_slices(const gg_cone *c)
{
    /* about one slice per 3 radii of length, at most 8 */
    double rmax = c->k.rb > c->ra ? c->k.rb : c->ra, n = c->k.h / (3 * rmax);
    return n < 1 ? 1 : n > 8 ? 8 : (uint32_t)n;
}

/* Slice i of n: z in [h i / n, h (i + 1) / n), the last one closed at h.
   Every slice computes the same t and z for a ray (the same kernel data
   but zlo and zhi), so half-open slices give each crossing to exactly
   one of them: with closed ones, a crossing on a boundary entered a
   coloured shadow's list twice and dimmed it twice. */
void gg_cone_slice(const gg_cone *c, uint32_t i, uint32_t n, gg_kcone *out)
{
    *out = c->k;
    out->zlo = i == 0 ? 0 : c->k.h * i / n;
    out->zhi = i + 1 == n ? c->k.h : nextafter(c->k.h * (i + 1) / n, 0);
}

void gg_cone_bounds(const gg_kcone *k, double lo[3], double hi[3])
{
    double r0 = k->rb + k->k * k->zlo, r1 = k->rb + k->k * k->zhi;
    double rmax = r0 > r1 ? r0 : r1;
    double pad = (rmax + k->h + fabs(k->base[0]) + fabs(k->base[1]) + fabs(k->base[2])) * 0x1p-44;
    int i;
    /* A disk of radius r with unit normal a spans r sqrt(1 - a_i^2) along
       axis i; the slice lies within the box of its two end disks. */
    for (i = 0; i < 3; i++) {
        double e = sqrt(fmax(0, 1 - k->ez[i] * k->ez[i]));
        double b0 = k->base[i] + k->zlo * k->ez[i], b1 = k->base[i] + k->zhi * k->ez[i];
        double l0 = b0 - r0 * e, h0 = b0 + r0 * e;
        double l1 = b1 - r1 * e, h1 = b1 + r1 * e;
        lo[i] = (l0 < l1 ? l0 : l1) - pad;
        hi[i] = (h0 > h1 ? h0 : h1) + pad;
    }
}

/* (u, v) = (angle around the axis / 2 pi in [0, 1), height fraction from
   the base). ng points away from the axis (outward). */
void gg_cone_surface(const gg_cone *c, const gg_rayq *q, const gg_hit *h, gg_surf *out,
                     unsigned what)
{
    const gg_kcone *k = &c->k;
    ggVec3 ex = v3(k->ex[0], k->ex[1], k->ex[2]), ey = v3(k->ey[0], k->ey[1], k->ey[2]);
    ggVec3 ez = v3(k->ez[0], k->ez[1], k->ez[2]), base = v3(k->base[0], k->base[1], k->base[2]);
    ggVec3 w = v3sub(v3madd(q->o, q->d, h->t), base), n;
    double x = v3dot(w, ex), y = v3dot(w, ey), z = v3dot(w, ez), rho, len, uv[2];
    z = z < 0 ? 0 : z > k->h ? k->h : z;
    rho = k->rb + k->k * z;
    len = sqrt(x * x + y * y);
    if (len > 0) {
        /* Back onto the surface, as for the sphere: the radial error no
           longer grows with the distance the ray travelled. */
        x *= rho / len, y *= rho / len;
    } else {
        x = rho, y = 0;
    }
    out->p = v3add(base, v3add(v3add(v3scale(ex, x), v3scale(ey, y)), v3scale(ez, z)));
    n = v3add(v3add(v3scale(ex, x), v3scale(ey, y)), v3scale(ez, -k->k * rho));
    if (!(v3dot(n, n) > 0)) n = v3add(ex, v3scale(ez, -k->k)); /* the tip of a cone */
    n = v3norm(n);
    out->ng = n;
    out->ns = n;
    out->u = out->v = 0;
    if (what & GG_SURF_UV) {
        gg_uv_cone_local(x, y, z, k->h, uv);
        out->u = uv[0], out->v = uv[1];
    }
    out->perr = gg_gamma(8) * (v3maxabs(base) + 2 * rho + z) + gg_gamma(2) * v3maxabs(out->p);
}
