/* SPDX-License-Identifier: MIT */
/*
** fresnel.c -- Fresnel reflectance of dielectric and conducting
** interfaces, Schlick's approximation, Beer-Lambert absorption.
** docs/optics.md derives the forms used here; the double-double kernels
** are in fresnel.inc.h (plain here, fma in fresnel_fma.c).
*/
#include "core.h"

#include "dd.h"
#include "fresnel_fma.h"

#include <math.h>

#define GG_INC_NAME(f) f##_plain
#define GG_INC_LINK    static
#include "fresnel.inc.h"

/* The copies, indexed by the kernel table's entry (core.h,
   gg_cpu_kernels): the plain build and, on x86-64, the fma one
   (fresnel_fma.c). Same bits either way; the fma build is faster. */
typedef void dielectric_fn(double c, double a, double b, gg_dd *rs, gg_dd *rp);
typedef void conductor_fn(double c, double n1, double n, double k, gg_dd *rs, gg_dd *rp);
#if GG_ISA_X86
static dielectric_fn *const dielectrics[] = {fresnel_dielectric_plain, gg_fresnel_dielectric_fma};
static conductor_fn *const conductors[] = {fresnel_conductor_plain, gg_fresnel_conductor_fma};
#else
static dielectric_fn *const dielectrics[] = {fresnel_dielectric_plain};
static conductor_fn *const conductors[] = {fresnel_conductor_plain};
#endif

static void dielectric_dd(double c, double a, double b, gg_dd *rs, gg_dd *rp)
{
    dielectrics[gg_cpu_kernels()->fresnel](c, a, b, rs, rp);
}

static void conductor_dd(double c, double n1, double n, double k, gg_dd *rs, gg_dd *rp)
{
    conductors[gg_cpu_kernels()->fresnel](c, n1, n, k, rs, rp);
}

/* |cos_i| clamped to [0, 1]; the caller has checked it is finite. */
static double clamp_cos(double c)
{
    c = fabs(c);
    return c > 1 ? 1 : c;
}

static int dielectric_args(double cos_i, double ni, double nt)
{
    return isfinite(cos_i) && isfinite(ni) && isfinite(nt) && ni != 0 && nt != 0;
}

GG_API void ggFresnelDielectricPolarized(double cos_i, double ni, double nt, double *rs, double *rp)
{
    gg_dd s, p;
    if (!dielectric_args(cos_i, ni, nt)) {
        if (rs) *rs = NAN;
        if (rp) *rp = NAN;
        return;
    }
    dielectric_dd(clamp_cos(cos_i), fabs(ni), fabs(nt), &s, &p);
    if (rs) *rs = s.hi;
    if (rp) *rp = p.hi;
}

GG_API double ggFresnelDielectric(double cos_i, double ni, double nt)
{
    gg_dd s, p, r;
    if (!dielectric_args(cos_i, ni, nt)) return NAN;
    dielectric_dd(clamp_cos(cos_i), fabs(ni), fabs(nt), &s, &p);
    r = dd_add(s, p);
    return 0.5 * r.hi;
}

GG_API double ggFresnelSchlick(double cos_i, double ni, double nt)
{
    double a, b, c, r0, x, x2;
    if (!dielectric_args(cos_i, ni, nt)) return NAN;
    a = fabs(ni), b = fabs(nt), c = clamp_cos(cos_i);
    scale_pair(&a, &b);
    r0 = (a - b) / (a + b);
    r0 *= r0;
    if (a > b) {
        /* Into the less dense medium: Schlick uses the transmitted angle. */
        gg_dd delta, q = cos_t_sq_nt2(a, b, c, &delta);
        if (q.hi <= 0) return 1.0;
        c = sqrt(q.hi) / b;
        if (c > 1) c = 1;
    }
    x = 1 - c;
    x2 = x * x;
    return r0 + (1 - r0) * (x2 * x2 * x);
}

/* ------------------------------------------------------------------ */
/* Conductors                                                          */
/* ------------------------------------------------------------------ */

/* Rs and Rp, 0 if the arguments are not valid. */
static int conductor(double cos_i, double n1, double n, double k, gg_dd *rs, gg_dd *rp)
{
    if (!isfinite(cos_i) || !isfinite(n1) || !isfinite(n) || !isfinite(k) || n1 == 0 || n < 0 ||
        k < 0 || (n == 0 && k == 0))
        return 0;
    conductor_dd(clamp_cos(cos_i), fabs(n1), n, k, rs, rp);
    return 1;
}

/* x rounded to a double, at most 1 (an upper bound the double-word forms
   may pass by a few 2^-106). */
static double at_most_1(gg_dd x)
{
    return x.hi > 1 ? 1.0 : x.hi;
}

GG_API void ggFresnelConductorPolarized(double cos_i, double n_outside, double n, double k,
                                        double *rs, double *rp)
{
    gg_dd s, p;
    int ok = conductor(cos_i, n_outside, n, k, &s, &p);
    if (rs) *rs = ok ? at_most_1(s) : NAN;
    if (rp) *rp = ok ? at_most_1(p) : NAN;
}

GG_API double ggFresnelConductor(double cos_i, double n_outside, double n, double k)
{
    gg_dd s, p;
    if (!conductor(cos_i, n_outside, n, k, &s, &p)) return NAN;
    return at_most_1(dd_mul_d(dd_add(s, p), 0.5));
}

/* ------------------------------------------------------------------ */
/* Beer-Lambert                                                        */
/* ------------------------------------------------------------------ */

#define FOUR_PI 12.566370614359172954

GG_API double ggAbsorptionCoefficient(double k, double lambda)
{
    int e;
    if (!isfinite(k) || !isfinite(lambda) || k < 0 || !(lambda > 0)) return NAN;
    if (k == 0) return 0;
    e = dd_expo(k) - dd_expo(lambda);
    if (e > 1018) {
        /* 4 pi k / lambda = q 2^e, q = 4 pi (km / lm) in (6.2, 25.2) with
           km, lm in [1, 2): the same roundings as below, and the result
           overflows only where q 2^e does (e = 1019 never; 1020 for some
           mantissas; it used to give +inf from 1019 on). */
        double q = FOUR_PI * (dd_scale2(k, -dd_expo(k)) / dd_scale2(lambda, -dd_expo(lambda)));
        return dd_expo(q) + e > 1023 ? INFINITY : dd_scale2(q, e);
    }
    return FOUR_PI * (k / lambda);
}

GG_API double ggBeerLambert(double k, double lambda, double distance)
{
    int e;
    double q;
    if (!isfinite(k) || !isfinite(lambda) || isnan(distance) || k < 0 || !(lambda > 0) ||
        distance < 0)
        return NAN;
    if (k == 0 || distance == 0) return 1.0;
    if (isinf(distance)) return 0.0;
    /* q = k d / lambda = (km dm / lm) 2^e with km, dm, lm in [1, 2), so
       nothing overflows; q > 128 (alpha d > 1608) underflows exp anyway. */
    e = dd_expo(k) + dd_expo(distance) - dd_expo(lambda);
    if (e > 7) return 0.0;
    q = dd_scale2(k, -dd_expo(k)) * dd_scale2(distance, -dd_expo(distance)) /
        dd_scale2(lambda, -dd_expo(lambda));
    q = dd_scale2(q, e);
    return exp(-FOUR_PI * q);
}

GG_API ggColor ggBeerLambertColor(ggColor k, ggColor lambda, double distance)
{
    ggColor t;
    t.r = ggBeerLambert(k.r, lambda.r, distance);
    t.g = ggBeerLambert(k.g, lambda.g, distance);
    t.b = ggBeerLambert(k.b, lambda.b, distance);
    return t;
}
