/* SPDX-License-Identifier: MIT */
/*
** vec.h -- inline vector arithmetic on ggVec3 and ggColor (internal).
*/
#ifndef GG_VEC_H
#define GG_VEC_H

#include "ggrt/base.h"

#include <float.h>
#include <math.h>

static inline ggVec3 v3(double x, double y, double z)
{
    ggVec3 r;
    r.x = x, r.y = y, r.z = z;
    return r;
}
static inline ggVec3 v3add(ggVec3 a, ggVec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline ggVec3 v3sub(ggVec3 a, ggVec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline ggVec3 v3mul(ggVec3 a, ggVec3 b) { return v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static inline ggVec3 v3scale(ggVec3 a, double s) { return v3(a.x * s, a.y * s, a.z * s); }
static inline ggVec3 v3neg(ggVec3 a) { return v3(-a.x, -a.y, -a.z); }
static inline double v3dot(ggVec3 a, ggVec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline ggVec3 v3cross(ggVec3 a, ggVec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline double v3len(ggVec3 a) { return sqrt(v3dot(a, a)); }
/* a + s*b */
static inline ggVec3 v3madd(ggVec3 a, ggVec3 b, double s)
{
    return v3(a.x + b.x * s, a.y + b.y * s, a.z + b.z * s);
}
/* Unit vector; the zero vector stays zero (callers check). */
static inline ggVec3 v3norm(ggVec3 a)
{
    double l = v3len(a);
    return l > 0 ? v3scale(a, 1.0 / l) : a;
}
/* v3norm's slow path (base.c): a scaled by a power of two (exactly)
   before it is squared. */
ggVec3 gg_vec_norm_scaled(ggVec3 a);
/* v3norm for a vector of any size, for the normals of flat shapes that
   may be tiny and gradients that may be tiny or huge: where |a|^2 is
   below 2^-968 some of its terms lose bits in the subnormal range, and
   the normals of triangles 2^-260 across came out 1.3 long (a highlight
   of 1e6); where it overflows, v3norm gives the zero vector. Elsewhere
   v3norm's answer, to the bit; v3norm itself stays one comparison shorter
   for the shading's hot paths (a test there cost 0.5-0.8% of a render's
   instructions). */
#define GG_VEC_SQ_MIN 0x1p-968
static inline ggVec3 v3unit(ggVec3 a)
{
    double l2 = v3dot(a, a);
    if (l2 >= GG_VEC_SQ_MIN && l2 <= DBL_MAX) return v3scale(a, 1.0 / sqrt(l2));
    return gg_vec_norm_scaled(a);
}
static inline double v3maxabs(ggVec3 a)
{
    double x = fabs(a.x), y = fabs(a.y), z = fabs(a.z);
    return x > y ? (x > z ? x : z) : (y > z ? y : z);
}

/* A ray direction of any finite size made safe for the kernels: d scaled
   by 2^k (exactly) when its largest component is outside [2^-64, 2^64],
   where |d|^2 or 1/d would overflow or underflow (the BVH's boxes take 1/d
   in single precision: a d of 2^129 missed everything); k = 0 and d as it
   is otherwise (zero and non-finite d too). The ray o + t d is o + t' d'
   with t' = ldexp(t, -k). */
static inline ggVec3 v3tame(ggVec3 d, int *k)
{
    double m = v3maxabs(d);
    ggVec3 r;
    *k = 0;
    if (!(m > 0) || !isfinite(m) || (m >= 0x1p-64 && m <= 0x1p64)) return d;
    *k = -ilogb(m);
    r.x = ldexp(d.x, *k), r.y = ldexp(d.y, *k), r.z = ldexp(d.z, *k);
    return r;
}
static inline ggVec3 v3min(ggVec3 a, ggVec3 b)
{
    return v3(a.x < b.x ? a.x : b.x, a.y < b.y ? a.y : b.y, a.z < b.z ? a.z : b.z);
}
static inline ggVec3 v3max(ggVec3 a, ggVec3 b)
{
    return v3(a.x > b.x ? a.x : b.x, a.y > b.y ? a.y : b.y, a.z > b.z ? a.z : b.z);
}
static inline double v3get(ggVec3 a, int axis) { return axis == 0 ? a.x : axis == 1 ? a.y : a.z; }
static inline int v3finite(ggVec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }

static inline ggColor rgb(double r, double g, double b)
{
    ggColor c;
    c.r = r, c.g = g, c.b = b;
    return c;
}
static inline ggColor cadd(ggColor a, ggColor b) { return rgb(a.r + b.r, a.g + b.g, a.b + b.b); }
static inline ggColor cmul(ggColor a, ggColor b) { return rgb(a.r * b.r, a.g * b.g, a.b * b.b); }
static inline ggColor cscale(ggColor a, double s) { return rgb(a.r * s, a.g * s, a.b * s); }
/* a + b*c */
static inline ggColor cmadd(ggColor a, ggColor b, ggColor c)
{
    return rgb(a.r + b.r * c.r, a.g + b.g * c.g, a.b + b.b * c.b);
}
static inline int cis0(ggColor a) { return a.r == 0 && a.g == 0 && a.b == 0; }
static inline double cmaxc(ggColor a)
{
    return a.r > a.g ? (a.r > a.b ? a.r : a.b) : (a.g > a.b ? a.g : a.b);
}

#endif
