/* SPDX-License-Identifier: MIT */
/*
** shape_cone.h -- ray / open cone (or cylinder) intersection kernel
** (internal, inlined into the traversal loops).
*/
#ifndef GG_SHAPE_CONE_H
#define GG_SHAPE_CONE_H

#include "geom_int.h"

/* The surface is x^2 + y^2 = (rb + k z)^2, 0 <= z <= h, in the cone's own
   orthonormal frame (origin at the base centre, z along the axis). Working
   in that frame keeps x^2 + y^2 free of the cancellation |w|^2 - (w.a)^2
   that the world-space form suffers. A cylinder (k = 0) uses the same
   stable discriminant as the sphere (distance of the line from the axis);
   a cone uses b^2 - ac with the stable root pair c/q, q/a. Returns the
   nearest root in (r->tmin, tmax] whose z lies in the element's
   [zlo, zhi], all of [0, h] or a slice of it (gg_cone_slice). */
GG_INLINE int gg_cone_kernel(const gg_kcone *cn, const gg_rpre *r, double tmax, double *t)
{
    double wx = r->o[0] - cn->base[0], wy = r->o[1] - cn->base[1], wz = r->o[2] - cn->base[2];
    double fx = wx * cn->ex[0] + wy * cn->ex[1] + wz * cn->ex[2];
    double fy = wx * cn->ey[0] + wy * cn->ey[1] + wz * cn->ey[2];
    double dx = r->d[0] * cn->ex[0] + r->d[1] * cn->ex[1] + r->d[2] * cn->ex[2];
    double dy = r->d[0] * cn->ey[0] + r->d[1] * cn->ey[1] + r->d[2] * cn->ey[2];
    double fz, dz, a, b, c, disc, q, ts[2];
    int i;
    if (cn->k == 0) {
        double lx, ly, kk;
        a = dx * dx + dy * dy;
        if (a == 0) return 0; /* parallel to the axis: never crosses the side */
        b = fx * dx + fy * dy;
        kk = b / a;
        lx = fx - kk * dx, ly = fy - kk * dy;
        disc = cn->rb * cn->rb - (lx * lx + ly * ly);
        if (disc < 0) return 0;
        disc = a * disc;
        c = fx * fx + fy * fy - cn->rb * cn->rb;
        /* the axial coordinates only now: most rays near a cylinder's box
           miss its side, and the test above did not need them */
        fz = wx * cn->ez[0] + wy * cn->ez[1] + wz * cn->ez[2];
        dz = r->d[0] * cn->ez[0] + r->d[1] * cn->ez[1] + r->d[2] * cn->ez[2];
    } else {
        double w, kd;
        fz = wx * cn->ez[0] + wy * cn->ez[1] + wz * cn->ez[2];
        dz = r->d[0] * cn->ez[0] + r->d[1] * cn->ez[1] + r->d[2] * cn->ez[2];
        w = cn->rb + cn->k * fz, kd = cn->k * dz;
        a = dx * dx + dy * dy - kd * kd;
        b = fx * dx + fy * dy - w * kd;
        c = fx * fx + fy * fy - w * w;
        disc = b * b - a * c;
        if (disc < 0) return 0;
    }
    q = b >= 0 ? -(b + sqrt(disc)) : sqrt(disc) - b;
    if (q == 0) return 0;
    ts[0] = c / q;
    ts[1] = q / a; /* +-inf when a = 0 (ray parallel to a generator): rejected below */
    if (ts[0] > ts[1]) {
        double tt = ts[0];
        ts[0] = ts[1], ts[1] = tt;
    }
    for (i = 0; i < 2; i++) {
        double z;
        if (!(ts[i] > r->tmin && ts[i] <= tmax)) continue;
        z = fz + ts[i] * dz;
        if (z >= cn->zlo && z <= cn->zhi) {
            *t = ts[i];
            return 1;
        }
    }
    return 0;
}

#endif
