/* SPDX-License-Identifier: MIT */
/*
** dd.h -- double-double arithmetic and error-free transformations
** (internal).
**
** A gg_dd is an unevaluated sum hi + lo with |lo| <= ulp(hi)/2, about 106
** bits of precision. The optics module uses it where a result is the small
** difference of large terms (the refraction discriminant near the critical
** angle, a tangential component near normal incidence).
**
** The algorithms are the classical ones: TwoSum (Knuth, The Art of
** Computer Programming vol. 2, 4.2.2), Fast2Sum and TwoProd (Dekker, "A
** floating-point technique for extending the available precision",
** Numer. Math. 18, 1971; TwoProd is one fma in a per-ISA object built for
** it, else Dekker's product with Veltkamp's split) and the double-word
** operations of Joldes, Muller and Popescu, "Tight and rigorous error
** bounds for basic building blocks of double-word arithmetic", ACM TOMS
** 44(2), 2017: relative error at most 3u^2 for a sum (even under
** cancellation) and 7u^2 for a product (their Algorithm 10), u = 2^-53.
**
** They are exact only in binary64 arithmetic without excess precision
** (FLT_EVAL_METHOD == 0, true on x86-64 and AArch64) and without
** reassociation (-ffast-math breaks them). Operands must stay well inside
** the exponent range: Veltkamp's split overflows above 2^995 and error
** terms below 2^-969 may be rounded. The callers scale their inputs first.
*/
#ifndef GG_DD_H
#define GG_DD_H

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "compiler.h" /* GG_FMA; FP_CONTRACT OFF, which the error-free transformations need */

#if FLT_EVAL_METHOD != 0
#error "dd.h needs FLT_EVAL_METHOD == 0 (SSE2 doubles, not x87)"
#endif

/* Exponent helpers, for scaling inputs by exact powers of two. */
/* 2^e for -1022 <= e <= 1023. */
static inline double dd_pow2(int e)
{
    uint64_t b = (uint64_t)(e + 1023) << 52;
    double d;
    memcpy(&d, &b, sizeof d);
    return d;
}

/* e with 2^e <= |x| < 2^(e+1), for finite non-zero x. */
static inline int dd_expo(double x)
{
    uint64_t b;
    int e;
    memcpy(&b, &x, sizeof b);
    e = (int)((b >> 52) & 0x7ff);
    return e ? e - 1023 : ilogb(x);
}

/* x * 2^e, exact unless the result underflows. */
static inline double dd_scale2(double x, int e)
{
    return e >= -1022 && e <= 1023 ? x * dd_pow2(e) : scalbn(x, e);
}

typedef struct gg_dd {
    double hi, lo;
} gg_dd;

static inline gg_dd dd_make(double hi, double lo)
{
    gg_dd r;
    r.hi = hi, r.lo = lo;
    return r;
}

/* a + b = s + e exactly, any a, b. */
static inline gg_dd dd_two_sum(double a, double b)
{
    double s = a + b, bb = s - a;
    return dd_make(s, (a - (s - bb)) + (b - bb));
}

/* a + b = s + e exactly when |a| >= |b| (or a == 0). */
static inline gg_dd dd_fast_two_sum(double a, double b)
{
    double s = a + b;
    return dd_make(s, b - (s - a));
}

/* a * b = p + e exactly (barring underflow of e). */
static inline gg_dd dd_two_prod(double a, double b)
{
    double p = a * b;
#if defined(GG_DD_FMA)
    /* a translation unit compiled for fma (refract_fma.c) */
    return dd_make(p, GG_FMA(a, b, -p));
#elif defined(FP_FAST_FMA)
    return dd_make(p, fma(a, b, -p));
#else
    /* Veltkamp split into 26-bit halves, then Dekker's exact product. */
    const double split = 134217729.0; /* 2^27 + 1 */
    double ta = split * a, tb = split * b;
    double ah = ta - (ta - a), al = a - ah;
    double bh = tb - (tb - b), bl = b - bh;
    return dd_make(p, ((ah * bh - p) + ah * bl + al * bh) + al * bl);
#endif
}

static inline gg_dd dd_from(double a)
{
    return dd_make(a, 0.0);
}
static inline gg_dd dd_neg(gg_dd a)
{
    return dd_make(-a.hi, -a.lo);
}

/* Accurate double-word sum (JMP 2017, Algorithm 6): relative error <= 3u^2
   whatever the cancellation. */
static inline gg_dd dd_add(gg_dd x, gg_dd y)
{
    gg_dd s = dd_two_sum(x.hi, y.hi), t = dd_two_sum(x.lo, y.lo), v;
    double c = s.lo + t.hi, w;
    v = dd_fast_two_sum(s.hi, c);
    w = t.lo + v.lo;
    return dd_fast_two_sum(v.hi, w);
}

static inline gg_dd dd_sub(gg_dd x, gg_dd y)
{
    return dd_add(x, dd_neg(y));
}

/* Double-word sum of two operands of the same sign (JMP 2017, Algorithm 5,
   "sloppy"): relative error <= 3u^2 when no cancellation is possible. */
static inline gg_dd dd_add_same(gg_dd x, gg_dd y)
{
    gg_dd s = dd_two_sum(x.hi, y.hi);
    return dd_fast_two_sum(s.hi, s.lo + (x.lo + y.lo));
}

/* Double-word plus double (JMP 2017, Algorithm 4): relative error <= 2u^2. */
static inline gg_dd dd_add_d(gg_dd x, double y)
{
    gg_dd s = dd_two_sum(x.hi, y);
    return dd_fast_two_sum(s.hi, x.lo + s.lo);
}

/* Double-word times double-word (JMP 2017, Algorithm 10, DWTimesDW1):
   relative error <= 7u^2. Not their
   Algorithm 12, which fuses the cross terms: it rounds differently, and
   the plain and the fma copies of a kernel (refract.inc.h) must return
   the same bits; only dd_two_prod, exact either way, uses the fma. */
static inline gg_dd dd_mul(gg_dd x, gg_dd y)
{
    gg_dd c = dd_two_prod(x.hi, y.hi);
    double tl = x.hi * y.lo + x.lo * y.hi;
    return dd_fast_two_sum(c.hi, c.lo + tl);
}

/* Double-word times double (JMP 2017, Algorithm 8, DWTimesFP2): relative
   error <= 3u^2. Not their Algorithm 9, which fuses x.lo * y into c.lo,
   for the same reason as dd_mul. */
static inline gg_dd dd_mul_d(gg_dd x, double y)
{
    gg_dd c = dd_two_prod(x.hi, y);
    return dd_fast_two_sum(c.hi, c.lo + x.lo * y);
}

/* x^2, a little cheaper than dd_mul(x, x). */
static inline gg_dd dd_sqr(gg_dd x)
{
    gg_dd c = dd_two_prod(x.hi, x.hi);
    return dd_fast_two_sum(c.hi, c.lo + 2.0 * x.hi * x.lo);
}

/* x / y (JMP 2017, Algorithm 17 style): relative error about 10u^2. y must
   not be zero. */
static inline gg_dd dd_div(gg_dd x, gg_dd y)
{
    double q1 = x.hi / y.hi;
    gg_dd r = dd_sub(x, dd_mul_d(y, q1));
    double q2 = r.hi / y.hi;
    return dd_fast_two_sum(q1, q2);
}

/* sqrt of a non-negative double-word (0 for x <= 0). */
static inline gg_dd dd_sqrt(gg_dd x)
{
    double s;
    gg_dd r;
    if (x.hi <= 0) return dd_from(0.0);
    s = sqrt(x.hi);
    r = dd_sub(x, dd_two_prod(s, s));
    return dd_fast_two_sum(s, r.hi / (2.0 * s));
}

/* 1/sqrt(x) for x > 0: one Newton step from the double estimate. */
static inline gg_dd dd_rsqrt(gg_dd x)
{
    double r = 1.0 / sqrt(x.hi);
    gg_dd e = dd_sub(dd_from(1.0), dd_mul(x, dd_two_prod(r, r)));
    return dd_fast_two_sum(r, 0.5 * r * e.hi);
}

/* Sum of three doubles' exact squares, a^2 + b^2 + c^2, as a double-word. */
static inline gg_dd dd_sum_sq3(double a, double b, double c)
{
    gg_dd s = dd_add_same(dd_two_prod(a, a), dd_two_prod(b, b));
    return dd_add_same(s, dd_two_prod(c, c));
}

/* a.b for two 3-vectors of doubles, as a double-word with error at most
   gamma_3^2 (|a1 b1| + |a2 b2| + |a3 b3|), gamma_3 = 3u/(1 - 3u), about
   9u^2: Dot2 of Ogita, Rump and Oishi, "Accurate sum and dot product",
   SIAM J. Sci. Comput. 26(6), 2005, with the final rounding left out. */
static inline gg_dd dd_dot3(double a1, double a2, double a3, double b1, double b2, double b3)
{
    gg_dd p = dd_two_prod(a1, b1), q = dd_two_prod(a2, b2), r = dd_two_prod(a3, b3);
    gg_dd s = dd_two_sum(p.hi, q.hi);
    double e = p.lo + q.lo + s.lo;
    gg_dd t = dd_two_sum(s.hi, r.hi);
    e += t.lo + r.lo;
    return dd_fast_two_sum(t.hi, e);
}

#endif
