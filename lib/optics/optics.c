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

#define GG_REFRACT_NAME refract_plain
#include "refract_core.h"

GG_API ggVec3 ggReflection(ggVec3 v, ggVec3 n)
{
    int ev;
    gg_dd a, nn, k2;
    double c[3], nc[3];
    int i;
    if (!v3finite(v) || !v3valid(n)) return v3nan();
    if (v.x == 0 && v.y == 0 && v.z == 0) return v;
    /* The mirror image is linear in v and independent of |n|. */
    ev = dd_expo(v3maxabs(v));
    v = v3scale2(v, -ev);
    n = v3scale2(n, -dd_expo(v3maxabs(n)));
    a = dd_dot3(v.x, v.y, v.z, n.x, n.y, n.z);
    nn = dd_sum_sq3(n.x, n.y, n.z);
    k2 = dd_div(a, nn);
    k2.hi *= 2.0, k2.lo *= 2.0;
    c[0] = v.x, c[1] = v.y, c[2] = v.z;
    nc[0] = n.x, nc[1] = n.y, nc[2] = n.z;
    for (i = 0; i < 3; i++) c[i] = dd_sub(dd_from(c[i]), dd_mul_d(k2, nc[i])).hi;
    return v3scale2(v3(c[0], c[1], c[2]), ev);
}

#if GG_ISA_X86
static int refract(ggVec3 v, ggVec3 n, double ni, double nt, ggVec3 *t)
{
    /* Same bits either way (refract_core.h). */
    return gg_cpu_features() & GG_CPU_FMA ? gg_refract_fma(v, n, ni, nt, t)
                                          : refract_plain(v, n, ni, nt, t);
}
#else
#define refract refract_plain
#endif

GG_API bool ggRefract(ggVec3 v, ggVec3 n, double ni, double nt, ggVec3 *t)
{
    ggVec3 r;
    int rc = refract(v, n, ni, nt, &r);
    if (t) *t = r;
    return rc == 1;
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
