/* SPDX-License-Identifier: MIT */
/*
** shape_sphere.h -- ray/sphere intersection kernel (internal, inlined into
** the traversal loops).
*/
#ifndef GG_SHAPE_SPHERE_H
#define GG_SHAPE_SPHERE_H

#include "geom_int.h"

/* gg_sphere_kernel in single precision (GG_ISECT_FLOAT): the same
   formula (the stable one, or the textbook one as r->opt->sphere says) on
   the origin, direction, centre and r^2 rounded to float, every operation
   in float. The stable form still avoids the cancellation, but f = o - c
   keeps only 24 bits of the coordinates, and t only 24 bits of the
   distance: far from the origin, or far from the eye against the radius,
   the hit point goes wrong (docs/accuracy.md: acc-far, acc-distant). */
int gg_sphere_kernel_f(const gg_ksph *s, const gg_rpre *r, double tmax, double *t);

/* Smallest root t in (r->tmin, tmax] of |o + t d - c|^2 = r^2; 1 if found.
   Stable form (Haines, Guenther, Akenine-Moeller, Ray Tracing Gems ch. 7):
   with f = o - c and b = f.d the discriminant b^2 - a(f.f - r^2) is
   computed as a (r^2 - |f - (b/a) d|^2). |f - (b/a) d| is the distance of
   the line from the centre, so the subtraction that cancels is between two
   quantities of size r^2 rather than |f|^2 -- a far sphere keeps its
   precision. The roots come from q = -(b + sign(b) sqrt(disc)): t = c/q
   and q/a, which never subtracts nearly equal numbers. */
GG_INLINE int gg_sphere_kernel(const gg_ksph *s, const gg_rpre *r, double tmax, double *t)
{
    double fx = r->o[0] - s->c[0], fy = r->o[1] - s->c[1], fz = r->o[2] - s->c[2];
    double dx = r->d[0], dy = r->d[1], dz = r->d[2];
    double b = fx * dx + fy * dy + fz * dz;
    double c, disc, q, t0, t1;
    if (GG_LIKELY(r->opt->sphere == GG_SPHERE_STABLE)) {
        double k = b * r->inv_a;
        double lx = fx - k * dx, ly = fy - k * dy, lz = fz - k * dz;
        disc = s->r2 - (lx * lx + ly * ly + lz * lz);
        if (disc < 0) return 0;
        c = fx * fx + fy * fy + fz * fz - s->r2;
        disc = sqrt(r->a * disc);
        q = b >= 0 ? -(b + disc) : disc - b;
        if (q == 0) return 0; /* b = 0 and tangent: the double root is t = 0 */
        t0 = c / q;
        t1 = q * r->inv_a;
        if (t0 > t1) {
            double tt = t0;
            t0 = t1, t1 = tt;
        }
    } else {
        /* The textbook form, kept for the accuracy study: b^2 - 4ac with
           B = 2 f.d, then (-B -+ sqrt) / 2a. */
        double bb = 2 * b, a = r->a;
        c = fx * fx + fy * fy + fz * fz - s->r2;
        disc = bb * bb - 4 * a * c;
        if (disc < 0) return 0;
        disc = sqrt(disc);
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

#endif
