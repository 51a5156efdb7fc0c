/* SPDX-License-Identifier: MIT */
/*
** ival.h -- interval arithmetic on doubles (internal).
**
** An interval [lo, hi] encloses every real value a computation can take.
** The processor rounds to nearest, so after each operation the bounds are
** pushed outward by a relative amount that covers the rounding error of the
** operation (one to a few ulps) plus the smallest subnormal, so that zero
** and subnormal results are covered too. This costs a few flops and needs
** no change of the rounding mode (which -O2 code would not honour).
**
** The empty interval (an operation outside its domain everywhere, e.g.
** sqrt of [-2, -1]) is [NaN, NaN]; operations on it give it back. Infinite
** bounds are allowed: 1 / [-1, 1] is [-inf, inf].
*/
#ifndef GG_IVAL_H
#define GG_IVAL_H

#include <float.h>
#include <math.h>

typedef struct gg_ival {
    double lo, hi;
} gg_ival;

/* Relative widening: one for correctly rounded operations (+ - * / sqrt:
   2 ulps is a safe margin over their half ulp), one for libm functions
   (glibc documents at most a few ulps for exp, log, sin, cos, tan, pow). */
#define GG_IV_REL  0x1p-51
#define GG_IV_RELF 0x1p-49
#define GG_IV_TINY 0x1p-1074

static inline gg_ival gg_iv(double lo, double hi)
{
    gg_ival r;
    r.lo = lo, r.hi = hi;
    return r;
}
static inline gg_ival gg_iv_empty(void)
{
    return gg_iv(NAN, NAN);
}
static inline gg_ival gg_iv_entire(void)
{
    return gg_iv(-INFINITY, INFINITY);
}
static inline int gg_iv_isempty(gg_ival a)
{
    return a.lo != a.lo || a.hi != a.hi;
}
static inline int gg_iv_has0(gg_ival a)
{
    return a.lo <= 0 && a.hi >= 0;
}
static inline int gg_iv_finite(gg_ival a)
{
    return isfinite(a.lo) && isfinite(a.hi);
}

/* x moved down (up) by `rel` of its magnitude. +inf stays representable as
   a lower bound only as DBL_MAX (inf - inf would be NaN). */
static inline double gg_iv_dn(double x, double rel)
{
    double r = x - (fabs(x) * rel + GG_IV_TINY);
    return r == r ? r : (x > 0 ? DBL_MAX : x);
}
static inline double gg_iv_up(double x, double rel)
{
    double r = x + (fabs(x) * rel + GG_IV_TINY);
    return r == r ? r : (x < 0 ? -DBL_MAX : x);
}
static inline gg_ival gg_iv_widen(double lo, double hi, double rel)
{
    return gg_iv(gg_iv_dn(lo, rel), gg_iv_up(hi, rel));
}

/* Enclosure of the single value o + t*d as the processor computes it: the
   product and the sum each round, so the error bound is relative to both
   |t*d| and the result (cancellation in the sum). */
static inline gg_ival gg_iv_affine_pt(double o, double t, double d)
{
    double td = t * d, v = o + td, e = (fabs(td) + fabs(v)) * GG_IV_REL + GG_IV_TINY;
    return gg_iv(v - e, v + e);
}
/* o + T*d for T = [a, b] (o, d exact). */
static inline gg_ival gg_iv_affine(double o, gg_ival t, double d)
{
    gg_ival p = gg_iv_affine_pt(o, t.lo, d), q = gg_iv_affine_pt(o, t.hi, d);
    return d >= 0 ? gg_iv(p.lo, q.hi) : gg_iv(q.lo, p.hi);
}

static inline gg_ival gg_iv_neg(gg_ival a)
{
    return gg_iv(-a.hi, -a.lo);
}

/* A bound of inf - inf is NaN, which would read as empty; it stands for
   "anything on that side" (the point computation can give any value or
   -inf there, e.g. x - 1/0 = -inf and 1 / that = -0). */
static inline gg_ival gg_iv_sum(gg_ival a, gg_ival b, double lo, double hi)
{
    if (lo != lo || hi != hi) {
        if (gg_iv_isempty(a) || gg_iv_isempty(b)) return gg_iv_empty();
        if (lo != lo) lo = -INFINITY;
        if (hi != hi) hi = INFINITY;
    }
    return gg_iv_widen(lo, hi, GG_IV_REL);
}
static inline gg_ival gg_iv_add(gg_ival a, gg_ival b)
{
    return gg_iv_sum(a, b, a.lo + b.lo, a.hi + b.hi);
}
static inline gg_ival gg_iv_sub(gg_ival a, gg_ival b)
{
    return gg_iv_sum(a, b, a.lo - b.hi, a.hi - b.lo);
}

/* 0 * inf is NaN in IEEE arithmetic but 0 in interval arithmetic over the
   reals (an infinite bound stands for "unbounded", not for a value). */
static inline double gg_iv_fix(double p)
{
    return p == p ? p : 0.0;
}

static inline gg_ival gg_iv_mul(gg_ival a, gg_ival b)
{
    double p1, p2, p3, p4, lo, hi;
    if (gg_iv_isempty(a) || gg_iv_isempty(b)) return gg_iv_empty();
    if (a.lo >= 0 && b.lo >= 0) { /* the common case in sums of squares */
        p1 = gg_iv_fix(a.lo * b.lo), p4 = gg_iv_fix(a.hi * b.hi);
        return gg_iv_widen(p1, p4, GG_IV_REL);
    }
    p1 = gg_iv_fix(a.lo * b.lo), p2 = gg_iv_fix(a.lo * b.hi);
    p3 = gg_iv_fix(a.hi * b.lo), p4 = gg_iv_fix(a.hi * b.hi);
    lo = p1 < p2 ? p1 : p2;
    lo = lo < p3 ? lo : p3;
    lo = lo < p4 ? lo : p4;
    hi = p1 > p2 ? p1 : p2;
    hi = hi > p3 ? hi : p3;
    hi = hi > p4 ? hi : p4;
    return gg_iv_widen(lo, hi, GG_IV_REL);
}

/* Multiply by an exact scalar. */
static inline gg_ival gg_iv_scale(gg_ival a, double s)
{
    double l = gg_iv_fix(a.lo * s), h = gg_iv_fix(a.hi * s);
    if (gg_iv_isempty(a) || s != s) return gg_iv_empty();
    return s >= 0 ? gg_iv_widen(l, h, GG_IV_REL) : gg_iv_widen(h, l, GG_IV_REL);
}

static inline gg_ival gg_iv_sqr(gg_ival a)
{
    if (gg_iv_isempty(a)) return gg_iv_empty();
    if (a.lo >= 0) return gg_iv_widen(a.lo * a.lo, a.hi * a.hi, GG_IV_REL);
    if (a.hi <= 0) return gg_iv_widen(a.hi * a.hi, a.lo * a.lo, GG_IV_REL);
    {
        double m = -a.lo > a.hi ? -a.lo : a.hi;
        return gg_iv(0.0, gg_iv_up(m * m, GG_IV_REL));
    }
}

static inline gg_ival gg_iv_hull(gg_ival a, gg_ival b)
{
    if (gg_iv_isempty(a)) return b;
    if (gg_iv_isempty(b)) return a;
    return gg_iv(a.lo < b.lo ? a.lo : b.lo, a.hi > b.hi ? a.hi : b.hi);
}

/* Intersection; empty when disjoint. */
static inline gg_ival gg_iv_meet(gg_ival a, gg_ival b)
{
    gg_ival r;
    if (gg_iv_isempty(a) || gg_iv_isempty(b)) return gg_iv_empty();
    r.lo = a.lo > b.lo ? a.lo : b.lo;
    r.hi = a.hi < b.hi ? a.hi : b.hi;
    return r.lo <= r.hi ? r : gg_iv_empty();
}

/* The rest lives in expr_ival.c. */
gg_ival gg_ival_div(gg_ival a, gg_ival b);
gg_ival gg_ival_sqrt(gg_ival a);
gg_ival gg_ival_exp(gg_ival a);
gg_ival gg_ival_log(gg_ival a);
gg_ival gg_ival_sin(gg_ival a);
gg_ival gg_ival_cos(gg_ival a);
gg_ival gg_ival_tan(gg_ival a);
gg_ival gg_ival_abs(gg_ival a);
gg_ival gg_ival_min(gg_ival a, gg_ival b);
gg_ival gg_ival_max(gg_ival a, gg_ival b);
gg_ival gg_ival_powi(gg_ival a, int n);
gg_ival gg_ival_powc(gg_ival a, double c); /* c fractional: domain a >= 0; whole: all a */

#endif
