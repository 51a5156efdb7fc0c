/* SPDX-License-Identifier: MIT */
/*
** optics_ref.h -- a 128-bit reference for the optics tests and the fuzz
** harness: "long double-double", pairs of x86 80-bit long doubles (64-bit
** significands) combined with the error-free transformations of lib/core/dd.h.
**
** ref_refract evaluates the TEXTBOOK formula
**   t = eta v + (eta c - sqrt(1 - eta^2 (1 - c^2))) N
** on the exactly normalised inputs; with 128 bits the cancellations that
** ruin that formula in double cost at most 2^-64 (at exactly the critical
** angle, where the sqrt turns a 2^-128 error into 2^-64), 0.002 of the
** 2^-53 unit the bounds are stated in. So the reference is independent of
** the library's formula and far more precise than the bounds it checks.
**
** Call ref_init() first; it returns 0 when long double is no wider than
** double here (valgrind, -mlong-double-64, AArch64 Apple), and then the
** reference must not be used.
*/
#ifndef GG_OPTICS_REF_H
#define GG_OPTICS_REF_H

#include "ggrt.h"

#include <float.h>
#include <math.h>

typedef long double ld;
typedef struct ldd {
    ld hi, lo;
} ldd;

static ld split_const = 4294967297.0L; /* 2^ceil(p/2) + 1, set by ref_init */

static inline ldd mk(ld hi, ld lo)
{
    ldd r;
    r.hi = hi, r.lo = lo;
    return r;
}
static inline ldd two_sum(ld a, ld b)
{
    volatile ld s = a + b; /* volatile: keep each rounding */
    ld bb = s - a;
    return mk(s, (a - (s - bb)) + (b - bb));
}
static inline ldd fast_two_sum(ld a, ld b)
{
    volatile ld s = a + b;
    return mk(s, b - (s - a));
}
static inline ldd two_prod(ld a, ld b)
{
    volatile ld p = a * b, ta = split_const * a, tb = split_const * b;
    ld ah = ta - (ta - a), al = a - ah, bh = tb - (tb - b), bl = b - bh;
    return mk(p, ((ah * bh - p) + ah * bl + al * bh) + al * bl);
}
static inline ldd L(ld a) { return mk(a, 0); }
static inline ldd add(ldd x, ldd y)
{
    ldd s = two_sum(x.hi, y.hi), t = two_sum(x.lo, y.lo), v;
    ld c = s.lo + t.hi, w;
    v = fast_two_sum(s.hi, c);
    w = t.lo + v.lo;
    return fast_two_sum(v.hi, w);
}
static inline ldd neg(ldd x) { return mk(-x.hi, -x.lo); }
static inline ldd sub(ldd x, ldd y) { return add(x, neg(y)); }
static inline ldd mul(ldd x, ldd y)
{
    ldd c = two_prod(x.hi, y.hi);
    return fast_two_sum(c.hi, c.lo + (x.hi * y.lo + x.lo * y.hi));
}
static inline ldd dvd(ldd x, ldd y)
{
    ld q1 = x.hi / y.hi, q2;
    ldd r = sub(x, mul(y, L(q1)));
    q2 = r.hi / y.hi;
    r = sub(r, mul(y, L(q2)));
    return add(fast_two_sum(q1, q2), L(r.hi / y.hi));
}
static inline ldd sqrt_ldd(ldd x)
{
    ld s;
    ldd r;
    if (x.hi <= 0) return L(0);
    s = sqrtl(x.hi);
    r = sub(x, two_prod(s, s));
    return fast_two_sum(s, r.hi / (2 * s));
}
static inline int sgn(ldd x) { return x.hi > 0 ? 1 : x.hi < 0 ? -1 : 0; }

/* Is long double really wider than double here? Sets the split constant. */
static inline int ref_init(void)
{
    volatile ld one = 1, tiny = 0x1p-63L;
    split_const = ldexpl(1.0L, (LDBL_MANT_DIG + 1) / 2) + 1;
    return LDBL_MANT_DIG >= 64 && (one + tiny) - one == tiny;
}

typedef struct ref_result {
    int tir;     /* 1 total internal reflection, 0 transmitted, -1 tangent v */
    int certain; /* the decision is outside the reference's own error band */
    ld cos2;     /* cos^2 of the transmitted angle (negative under TIR) */
    ldd t[3];    /* transmitted or mirror direction, unit */
} ref_result;

/* v . n of the double inputs, correct to 2^-127 of the result however much
   the products cancel: each product is exact as a pair (53 + 53 bits fit
   in 2 x 64), and the six halves are summed exactly into a nonoverlapping
   expansion (Shewchuk's Grow-Expansion, with two_sum), whose components
   are then added from the smallest up. Normalising first and taking the
   dot product of the unit vectors would leave an absolute error of about
   2^-128: at cos 1.2e-84 (v = (-0x1.11acee560242ap-2, 0x1.9a8365810363fp-1,
   -0x1.11acee560242ap-1), n = (-0x1.eaeaeaeaeaeaep-277, 1, 1.5), the
   input of tests/fuzz/corpus/optics/reference-tiny-cos) that noise decided
   the sign of the cosine, so the reference flipped the normal. */
static inline ldd dot_exact(ggVec3 a, ggVec3 b)
{
    ldd p[3];
    ld x[6], h[6];
    int i, j, m = 0;
    p[0] = two_prod(a.x, b.x), p[1] = two_prod(a.y, b.y), p[2] = two_prod(a.z, b.z);
    for (i = 0; i < 3; i++) x[2 * i] = p[i].hi, x[2 * i + 1] = p[i].lo;
    for (i = 0; i < 6; i++) {
        ld q = x[i];
        for (j = 0; j < m; j++) {
            ldd s = two_sum(q, h[j]);
            q = s.hi, h[j] = s.lo;
        }
        h[m++] = q;
    }
    {
        ldd sum = L(0);
        for (j = 0; j < m; j++) sum = add(sum, L(h[j]));
        return sum;
    }
}

static inline void ref_refract(ggVec3 v, ggVec3 n, double ni, double nt, ref_result *r)
{
    ldd vc[3] = {L(v.x), L(v.y), L(v.z)}, nc[3] = {L(n.x), L(n.y), L(n.z)};
    ldd vv = L(0), nn = L(0), c, lv, ln, eta, k, sin2;
    int i, s;
    for (i = 0; i < 3; i++) {
        vv = add(vv, mul(vc[i], vc[i]));
        nn = add(nn, mul(nc[i], nc[i]));
    }
    lv = sqrt_ldd(vv), ln = sqrt_ldd(nn);
    for (i = 0; i < 3; i++) vc[i] = dvd(vc[i], lv), nc[i] = dvd(nc[i], ln);
    c = dvd(dot_exact(v, n), mul(lv, ln)); /* signed cos */
    s = sgn(c);
    if (s == 0) {
        r->tir = -1, r->certain = 1, r->cos2 = 0;
        for (i = 0; i < 3; i++) r->t[i] = vc[i];
        return;
    }
    eta = dvd(L(ni), L(nt));
    sin2 = mul(sub(L(1), c), add(L(1), c));
    k = sub(L(1), mul(mul(eta, eta), sin2)); /* cos^2 of the transmitted angle */
    r->certain = fabsl(k.hi) > 0x1p-118L;
    r->cos2 = k.hi;
    if (k.hi < 0) {
        ldd c2 = add(c, c);
        r->tir = 1;
        for (i = 0; i < 3; i++) r->t[i] = sub(vc[i], mul(c2, nc[i]));
    } else {
        /* N = -s nc faces v; t = eta v + (eta |c| - cos_t) N. */
        ldd coef = mul(L(-s), sub(mul(eta, s > 0 ? c : neg(c)), sqrt_ldd(k)));
        r->tir = 0;
        for (i = 0; i < 3; i++) r->t[i] = add(mul(eta, vc[i]), mul(coef, nc[i]));
    }
}

/* Error of t in units of 2^-53, max over components. */
static inline double err_ulps(ggVec3 t, const ldd ref[3])
{
    ld d[3];
    int i;
    double m = 0;
    d[0] = ((ld)t.x - ref[0].hi) - ref[0].lo;
    d[1] = ((ld)t.y - ref[1].hi) - ref[1].lo;
    d[2] = ((ld)t.z - ref[2].hi) - ref[2].lo;
    for (i = 0; i < 3; i++) {
        double e = (double)(fabsl(d[i]) * 0x1p53L);
        if (!(e <= m)) m = e; /* NaN propagates */
    }
    return m;
}

#endif
