/* SPDX-License-Identifier: MIT */
/*
** optics.c -- reflection and refraction directions: the accurate
** ggReflection and ggRefract, and the textbook refraction kept for the
** accuracy study. docs/optics.md derives the formulas and the error bound.
**
** Both accurate functions depend only on the directions of v and n (and
** on ni/nt), so they first scale v, n and the indices by powers of two
** into [1, 2): exact, and it keeps every square and product below in
** range. The refraction then works with
**
**   a   = v.n                      (compensated dot product, double-double)
**   vt  = v - (a / n.n) n          (tangential part of v, double-double)
**   D   = nt^2 |v|^2 - ni^2 |vt|^2  = nt^2 |v|^2 cos^2(theta_t)
**
** D is a difference of two nearly equal terms close to the critical angle,
** and |vt| is tiny near normal incidence; both are therefore evaluated in
** double-double arithmetic (dd.h), so that their sign and their value are
** right where the textbook 1 - eta^2 (1 - c^2) loses every digit. The
** result t = eta vt/|v| + sign(a) cos_t n/|n| is assembled in
** double-double and rounded once.
*/
#include "core.h"

#include "dd.h"
#include "refract_fma.h"
#include "vec.h"

#include <math.h>

#define GG_INC_NAME(f) f##_plain
#define GG_INC_LINK    static
#include "refract.inc.h"
#include "reflect.inc.h"

/* The copies of each, indexed by the kernel table's entry (core.h,
   gg_cpu_kernels): the plain build and, on x86-64, the fma one
   (refract_fma.c). Same bits either way; the fma build is faster. */
typedef bool refract_fn(ggVec3 v, ggVec3 n, double ni, double nt, ggVec3 *t);
typedef ggVec3 reflect_fn(const ggVec3 *v, const ggVec3 *n);
#if GG_ISA_X86
static refract_fn *const refracts[] = {refract_plain, gg_refract_fma};
static reflect_fn *const reflects[] = {reflect_plain, gg_reflect_fma};
#else
static refract_fn *const refracts[] = {refract_plain};
static reflect_fn *const reflects[] = {reflect_plain};
#endif

GG_API bool ggRefract(ggVec3 v, ggVec3 n, double ni, double nt, ggVec3 *t)
{
    return refracts[gg_cpu_kernels()->refract](v, n, ni, nt, t);
}

GG_API ggVec3 ggReflection(ggVec3 v, ggVec3 n)
{
    return reflects[gg_cpu_kernels()->reflect](&v, &n);
}

GG_API bool ggRefractTextbook(ggVec3 v, ggVec3 n, double ni, double nt, ggVec3 *t)
{
    double c = -v3dot(v, n), eta = ni / nt, k;
    ggVec3 r;
    bool ok;
    if (c < 0) n = v3neg(n), c = -c;
    k = 1.0 - eta * eta * (1.0 - c * c);
    if (k < 0) {
        r = v3madd(v, n, 2.0 * c);
        ok = false;
    } else {
        r = v3add(v3scale(v, eta), v3scale(n, eta * c - sqrt(k)));
        ok = true;
    }
    if (t) *t = r;
    return ok;
}

GG_API double ggCriticalAngle(double ni, double nt)
{
    double a, b;
    int e;
    if (!isfinite(ni) || !isfinite(nt) || ni == 0 || nt == 0) return NAN;
    a = fabs(ni), b = fabs(nt);
    if (b >= a) return GG_PI / 2;
    /* Scale so the squares below neither overflow nor underflow. */
    e = dd_expo(a);
    a = dd_scale2(a, -e), b = dd_scale2(b, -e);
    /* a - b is exact when b > a/2 (Sterbenz), so cos is accurate near 90. */
    return atan2(b, sqrt((a - b) * (a + b)));
}
