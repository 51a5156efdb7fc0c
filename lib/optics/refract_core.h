/* SPDX-License-Identifier: MIT */
/*
** refract_core.h -- the bodies of the accurate refraction and reflection
** (internal), included twice: by optics.c as plain code, and by
** refract_fma.c compiled for CPUs with fused multiply-add, where TwoProd is
** one fma instead of Dekker's 17-flop product. TwoProd is exact either way
** (the inputs are scaled so that no error term underflows) and nothing
** else here uses fma, so both copies return the same bits; optics.c picks
** one at run time. Before including, define GG_REFRACT_NAME and
** GG_REFLECT_NAME (the names of the static functions to generate).
**
** Each function first scales its vectors by powers of two (exact) and then
** tries a fast path: double-double where the result needs it, plain double
** elsewhere, with a running bound on the error. When the bound cannot
** guarantee the documented 1 ulp (near the critical angle, a ray almost in
** the surface, |ni/nt| > 4 or negative), the full double-double
** refract_dd decides. docs/optics.md gives the bound and its proof.
*/
#if !defined(GG_REFRACT_NAME) || !defined(GG_REFLECT_NAME)
#error "define GG_REFRACT_NAME and GG_REFLECT_NAME before including refract_core.h"
#endif
/* The linkage of the two generated functions (refract_fma.c exports them). */
#ifndef GG_OPTICS_LINKAGE
#define GG_OPTICS_LINKAGE static
#endif

#include "dd.h"
#include "vec.h"

#include <math.h>

static ggVec3 v3scale2(ggVec3 a, int e)
{
    if (e == 0) return a;
    if (e >= -1022 && e <= 1023) return v3scale(a, dd_pow2(e));
    return v3(scalbn(a.x, e), scalbn(a.y, e), scalbn(a.z, e));
}

static ggVec3 v3nan(void) { return v3(NAN, NAN, NAN); }

/* Sign (-1, 0, 1) of the exact a.b, from the six exact terms of the
   products summed into a non-overlapping expansion (Shewchuk's
   Grow-Expansion): the largest non-zero component carries the sign. Only
   called when the compensated dot product cannot decide. */
static int dot_sign_exact(ggVec3 a, ggVec3 b)
{
    double terms[6], e[6], q;
    int m = 0, i, j;
    gg_dd p;
    p = dd_two_prod(a.x, b.x), terms[0] = p.hi, terms[1] = p.lo;
    p = dd_two_prod(a.y, b.y), terms[2] = p.hi, terms[3] = p.lo;
    p = dd_two_prod(a.z, b.z), terms[4] = p.hi, terms[5] = p.lo;
    for (i = 0; i < 6; i++) {
        q = terms[i];
        for (j = 0; j < m; j++) {
            gg_dd s = dd_two_sum(q, e[j]);
            q = s.hi, e[j] = s.lo;
        }
        e[m++] = q;
    }
    for (i = m - 1; i >= 0; i--)
        if (e[i] != 0) return e[i] > 0 ? 1 : -1;
    return 0;
}

/* True if a and b are exactly parallel (a x b == 0 in exact arithmetic). */
static int parallel_exact(ggVec3 a, ggVec3 b)
{
    gg_dd p, q;
    p = dd_two_prod(a.y, b.z), q = dd_two_prod(a.z, b.y);
    if (p.hi != q.hi || p.lo != q.lo) return 0;
    p = dd_two_prod(a.z, b.x), q = dd_two_prod(a.x, b.z);
    if (p.hi != q.hi || p.lo != q.lo) return 0;
    p = dd_two_prod(a.x, b.y), q = dd_two_prod(a.y, b.x);
    return p.hi == q.hi && p.lo == q.lo;
}

/* a (double-word) times the components of x, rounded. */
static ggVec3 dd_scale_vec(gg_dd a, const gg_dd x[3])
{
    return v3(dd_mul(a, x[0]).hi, dd_mul(a, x[1]).hi, dd_mul(a, x[2]).hi);
}

/* Components below 2^-480 of the largest one (of the same vector) are set
   to zero. They move the direction by less than 2^-427 ulp, and keeping
   them could make products of two of them underflow, which would break
   the exactness of the dot product's sign (every product, and its
   rounding error, must stay a normal number). */
static double flush(double x) { return fabs(x) < 0x1p-480 ? 0.0 : x; }

/* The double-double refraction of normalised inputs (the fallback of the
   fast path below, and its reference in tests/test_refract_fast.c):
   ediff is the exponent of |ni/nt| carried separately when it exceeds
   450. Returns 1 (transmitted) or 0 (total internal reflection or tangent
   v: *t is the mirror direction). */
static int refract_dd(ggVec3 v, ggVec3 n, double ni, double nt, int ediff, ggVec3 *t)
{
    double vc[3], nc[3], sump;
    gg_dd a, vv, nn, k, vt[3], ni2, nt2, A, D, g1, g2;
    int s, i;

    vc[0] = v.x, vc[1] = v.y, vc[2] = v.z;
    nc[0] = n.x, nc[1] = n.y, nc[2] = n.z;

    /* Which side v comes from. Dot2's error is below 2^-104 sum|v_i n_i|;
       only inside that band is the exact sign worked out. */
    a = dd_dot3(v.x, v.y, v.z, n.x, n.y, n.z);
    sump = fabs(v.x * n.x) + fabs(v.y * n.y) + fabs(v.z * n.z);
    if (fabs(a.hi) > 0x1p-100 * sump)
        s = a.hi > 0 ? 1 : -1;
    else
        s = dot_sign_exact(v, n);

    vv = dd_sum_sq3(v.x, v.y, v.z);
    if (s == 0) {
        /* v lies in the surface: it never crosses, and is its own mirror. */
        gg_dd vd[3];
        for (i = 0; i < 3; i++) vd[i] = dd_from(vc[i]);
        *t = dd_scale_vec(dd_rsqrt(vv), vd);
        return 0;
    }
    nn = dd_sum_sq3(n.x, n.y, n.z);
    k = dd_div(a, nn);
    for (i = 0; i < 3; i++) vt[i] = dd_add_d(dd_neg(dd_mul_d(k, nc[i])), vc[i]);

    /* Exactly normal incidence: vt above is only rounding noise (at most
       2^-104 |v|), which a huge eta would magnify. */
    if (fabs(vt[0].hi) + fabs(vt[1].hi) + fabs(vt[2].hi) < 0x1p-90 && parallel_exact(v, n))
        vt[0] = vt[1] = vt[2] = dd_from(0.0);

    /* The error of vt is about 2^-104 |v| along n (from k's rounding);
       t takes eta times it into its normal component. Negligible unless
       eta is huge; then vt is projected again, each pass shrinking the
       error by about 2^-104, until it is below 2^-100 |vt| (so eta times
       it is below 2^-100 wherever the ray is transmitted). */
    if (ediff || fabs(ni) > 0x1p30 * fabs(nt)) {
        int pass;
        for (pass = 0; pass < 12; pass++) {
            gg_dd e = dd_from(0.0);
            double m = fabs(vt[0].hi) + fabs(vt[1].hi) + fabs(vt[2].hi);
            for (i = 0; i < 3; i++) e = dd_add(e, dd_mul_d(vt[i], nc[i]));
            e = dd_div(e, nn);
            if (e.hi == 0) break;
            for (i = 0; i < 3; i++) vt[i] = dd_sub(vt[i], dd_mul_d(e, nc[i]));
            if (fabs(e.hi) * 4.0 <= 0x1p-100 * m) break;
        }
    }

    if (ediff) {
        /* eta > 2^450: transmission needs sin(theta_i) < 1/eta. With
           |v| < 2 sqrt(3) and |vt| >= m / sqrt(3), m >= 2^(4 - ediff)
           means eta sin(theta_i) > 1. Otherwise multiply vt by 2^ediff
           (exact) so the formulas below see eta in (1/2, 2). */
        double m = fabs(vt[0].hi) + fabs(vt[1].hi) + fabs(vt[2].hi);
        if (m != 0 && dd_expo(m) >= 4 - ediff) goto tir;
        for (i = 0; i < 3; i++)
            vt[i].hi = dd_scale2(vt[i].hi, ediff), vt[i].lo = dd_scale2(vt[i].lo, ediff);
    }

    /* D = nt^2 |v|^2 cos^2(theta_t), two ways:
         A - ni^2 |vt|^2                     its error is about u^2 A, fine
                                             unless cos^2 < u^2 (grazing
                                             with eta near 1);
         (nt^2 - ni^2) |v|^2 + ni^2 a^2/|n|^2  no cancellation at all when
                                             nt >= ni; near the critical
                                             angle its error is about
                                             u^2 (eta^2 - 1) A.
       So the second up to eta = 2 and the first beyond. */
    ni2 = dd_two_prod(ni, ni), nt2 = dd_two_prod(nt, nt);
    A = dd_mul(nt2, vv);
    if (!ediff && ni2.hi <= 4.0 * nt2.hi) {
        D = dd_add(dd_mul(dd_sub(nt2, ni2), vv), dd_mul(ni2, dd_mul(a, k)));
    } else {
        gg_dd vt2 = dd_add_same(dd_add_same(dd_sqr(vt[0]), dd_sqr(vt[1])), dd_sqr(vt[2]));
        D = dd_sub(A, dd_mul(ni2, vt2));
    }
    if (D.hi < 0) goto tir;

    /* t = eta vt/|v| + s cos_t n/|n|, with
         eta/|v|       = ni sign(nt) / sqrt(A)
         cos_t / |n|   = sqrt(D / (A |n|^2)). */
    g1 = dd_mul_d(dd_rsqrt(A), nt > 0 ? ni : -ni);
    g2 = dd_sqrt(dd_div(D, dd_mul(A, nn)));
    if (s < 0) g2 = dd_neg(g2);
    {
        /* g1 vt_i + g2 n_i, rounded once: the exact products of the high
           parts are summed with TwoSum and everything else (at most
           2^-104 of the terms, and |t| = 1) in double. */
        double r[3];
        for (i = 0; i < 3; i++) {
            gg_dd p = dd_two_prod(g1.hi, vt[i].hi), q = dd_two_prod(g2.hi, nc[i]);
            gg_dd sum = dd_two_sum(p.hi, q.hi);
            double lo = sum.lo + (p.lo + q.lo) + (g1.hi * vt[i].lo + g1.lo * vt[i].hi) +
                        g2.lo * nc[i];
            r[i] = sum.hi + lo;
        }
        *t = v3(r[0], r[1], r[2]);
    }
    return 1;

tir:
    /* Mirror direction (v - 2k n) / |v|. */
    {
        double r[3];
        gg_dd k2 = dd_make(2.0 * k.hi, 2.0 * k.lo), rv = dd_rsqrt(vv);
        for (i = 0; i < 3; i++) r[i] = dd_mul(dd_sub(dd_from(vc[i]), dd_mul_d(k2, nc[i])), rv).hi;
        *t = v3(r[0], r[1], r[2]);
    }
    return 0;
}


/* ------------------------------------------------------------------ */
/* Fast paths                                                          */
/* ------------------------------------------------------------------ */

/* Double-word products without fma outside TwoProd (so both builds agree):
   JMP 2017 Algorithms 9 and 12, relative error below 2u^2 and 5u^2. */
GG_INLINE gg_dd fd_mul(gg_dd x, gg_dd y)
{
    gg_dd c = dd_two_prod(x.hi, y.hi);
    return dd_fast_two_sum(c.hi, c.lo + (x.hi * y.lo + x.lo * y.hi));
}
GG_INLINE gg_dd fd_mul_d(gg_dd x, double y)
{
    gg_dd c = dd_two_prod(x.hi, y);
    return dd_fast_two_sum(c.hi, c.lo + x.lo * y);
}

/* The bits of the largest |component| (NaN and infinities compare
   largest, so the exponent field is 2047 if any component is not finite). */
GG_INLINE uint64_t max_bits(ggVec3 a)
{
    uint64_t x, y, z;
    memcpy(&x, &a.x, sizeof x), memcpy(&y, &a.y, sizeof y), memcpy(&z, &a.z, sizeof z);
    x &= ~(1ull << 63), y &= ~(1ull << 63), z &= ~(1ull << 63);
    x = x > y ? x : y;
    return x > z ? x : z;
}

/* 2^(1023 - e) for the biased exponent e in [1, 2045]. */
GG_INLINE double pow2_inv(uint64_t e)
{
    uint64_t b = (2046 - e) << 52;
    double d;
    memcpy(&d, &b, sizeof d);
    return d;
}

/* a scaled so its largest component is in [1, 2), given m = max_bits(a)
   (finite, non-zero): the same numbers as v3scale2(a, -dd_expo(max)). */
GG_INLINE ggVec3 scale_unit(ggVec3 a, uint64_t m)
{
    uint64_t e = m >> 52;
    if (e >= 1 && e <= 2045) return v3scale(a, pow2_inv(e));
    return v3scale2(a, -dd_expo(v3maxabs(a)));
}

/* (v - 2 (v.n)/(n.n) n) * rho, each component rounded once, for scaled v
   and n and a double-word rho (rho = 1 for the reflection). a = v.n, nn =
   n.n (double-word). Error: docs/optics.md, "The fast paths". */
GG_INLINE ggVec3 mirror_fast(ggVec3 v, ggVec3 n, gg_dd a, gg_dd nn, gg_dd rho, int unit_rho)
{
    double vc[3], nc[3], r[3], y = 1.0 / nn.hi, q = a.hi * y, rem, kl;
    gg_dd p = dd_two_prod(q, nn.hi);
    int i;
    /* k = 2 a / nn as q + kl: a.hi - p.hi is exact (Sterbenz) */
    rem = (((a.hi - p.hi) - p.lo) + a.lo) - q * nn.lo;
    q *= 2.0, kl = 2.0 * rem * y;
    vc[0] = v.x, vc[1] = v.y, vc[2] = v.z;
    nc[0] = n.x, nc[1] = n.y, nc[2] = n.z;
    for (i = 0; i < 3; i++) {
        gg_dd pk = dd_two_prod(q, nc[i]), s = dd_two_sum(vc[i], -pk.hi);
        double lo = (s.lo - pk.lo) - kl * nc[i];
        if (unit_rho) {
            r[i] = s.hi + lo;
        } else {
            gg_dd m = dd_two_prod(s.hi, rho.hi);
            r[i] = m.hi + (m.lo + (s.hi * rho.lo + lo * rho.hi));
        }
    }
    return v3(r[0], r[1], r[2]);
}

/* The reflection: scale, mirror, scale back. No fallback is needed: the
   bound holds for every scaled input (docs/optics.md). */
GG_OPTICS_LINKAGE void GG_REFLECT_NAME(const ggVec3 *vp, const ggVec3 *np, ggVec3 *out)
{
    ggVec3 v = *vp, n = *np;
    uint64_t mv = max_bits(v), mn = max_bits(n), e = mv >> 52, b;
    gg_dd a, nn, one = {1.0, 0.0};
    ggVec3 r;
    double d;
    int ev;
    if (e == 2047 || mn == 0 || (mn >> 52) == 2047) {
        *out = v3nan();
        return;
    }
    if (mv == 0) {
        *out = v;
        return;
    }
    ev = e >= 1 && e <= 2045 ? 0 : dd_expo(v3maxabs(v));
    v = scale_unit(v, mv), n = scale_unit(n, mn);
    a = dd_dot3(v.x, v.y, v.z, n.x, n.y, n.z);
    nn = dd_sum_sq3(n.x, n.y, n.z);
    r = mirror_fast(v, n, a, nn, one, 1);
    if (ev) {
        *out = v3scale2(r, ev);
        return;
    }
    b = e << 52;
    memcpy(&d, &b, sizeof d);
    *out = v3scale(r, d);
}

/* 1/sqrt(x) for a double-word x > 0: one Newton step from the double
   estimate (relative error below 4u^2). 1 - x y^2 is formed exactly enough
   because x y^2 is within 3u of 1. */
GG_INLINE gg_dd fd_rsqrt(gg_dd x)
{
    double y = 1.0 / sqrt(x.hi);
    gg_dd m = fd_mul(x, dd_two_prod(y, y));
    return dd_fast_two_sum(y, 0.5 * y * ((1.0 - m.hi) - m.lo));
}

/* Sum of the exact squares of a, b, c as hi + lo (not renormalised):
   relative error below 3u^2 (all terms are positive). */
GG_INLINE gg_dd fd_sum_sq3(double a, double b, double c)
{
    gg_dd p = dd_two_prod(a, a), q = dd_two_prod(b, b), r = dd_two_prod(c, c);
    gg_dd s = dd_two_sum(p.hi, q.hi), t = dd_two_sum(s.hi, r.hi);
    return dd_make(t.hi, ((p.lo + q.lo) + (r.lo + s.lo)) + t.lo);
}

/* The fast refraction of scaled inputs (largest components and larger
   index in [1, 2)), for 0 < eta <= 4. Returns 1 or 0 as refract_dd, or 2
   when its running error bound cannot certify the result (then nothing is
   written). Notation and proof: docs/optics.md, "The fast paths". */
GG_INLINE int refract_fast(ggVec3 v, ggVec3 n, double ni, double nt, ggVec3 *t)
{
    double sump, bound, y, r[3], vc[3], nc[3];
    gg_dd a, vv, nn, ni2, nt2, M, Q, P, D, W, Wi, rho, eta, G1, G2, p;
    int i, neg;
    a = dd_dot3(v.x, v.y, v.z, n.x, n.y, n.z);
    sump = fabs(v.x * n.x) + fabs(v.y * n.y) + fabs(v.z * n.z);
    if (!(fabs(a.hi) > 0x1p-100 * sump)) return 2;
    vv = fd_sum_sq3(v.x, v.y, v.z), nn = fd_sum_sq3(n.x, n.y, n.z);
    ni2 = dd_two_prod(ni, ni), nt2 = dd_two_prod(nt, nt);
    /* D = (nt^2 - ni^2) |v|^2 |n|^2 + ni^2 (v.n)^2 = nt^2 |v|^2 |n|^2 cos^2(theta_t) */
    M = dd_sub(nt2, ni2);
    Q = fd_mul(vv, nn);
    P = dd_sqr(a);
    {
        /* M Q + ni^2 P from the exact products of the high parts */
        gg_dd m = dd_two_prod(M.hi, Q.hi), q = dd_two_prod(ni2.hi, P.hi), s = dd_two_sum(m.hi, q.hi);
        D = dd_fast_two_sum(s.hi, s.lo + ((m.lo + q.lo) + ((M.hi * Q.lo + M.lo * Q.hi) +
                                                            (ni2.hi * P.lo + ni2.lo * P.hi))));
    }
    /* a bound on the error of D (from the magnitudes: docs/optics.md); the
       constant term covers underflow of products of tiny components */
    bound = 0x1p-100 * (40.0 * fabs(M.hi) * Q.hi + ni2.hi * (8.0 * fabs(a.hi) * sump + 20.0 * P.hi) +
                        4.0 * fabs(D.hi)) +
            0x1p-900;
    if (!(fabs(D.hi) > 0x1p36 * bound)) return 2;
    if (D.hi < 0) {
        *t = mirror_fast(v, n, a, nn, fd_rsqrt(vv), 0);
        return 0;
    }
    /* W = |nt| (sqrt(D) + |ni| |v.n|) = nt^2 |v| |n| (cos_t + eta |cos_i|) */
    y = sqrt(D.hi);
    p = dd_two_prod(y, y);
    W = dd_make(y, (((D.hi - p.hi) - p.lo) + D.lo) / (2.0 * y));
    neg = a.hi < 0;
    if (neg) a = dd_neg(a);
    W = fd_mul_d(dd_add_same(W, fd_mul_d(a, fabs(ni))), fabs(nt));
    y = 1.0 / W.hi;
    p = dd_two_prod(W.hi, y);
    Wi = dd_make(y, y * (((1.0 - p.hi) - p.lo) - W.lo * y));
    /* t = G1 v + G2 n: G1 = eta/|v|, G2 = sign(v.n) (nt^2 - ni^2) |v| / W */
    rho = fd_rsqrt(vv);
    y = 1.0 / nt;
    eta.hi = ni * y;
    p = dd_two_prod(eta.hi, nt);
    eta.lo = ((ni - p.hi) - p.lo) * y;
    G1 = fd_mul(eta, rho);
    G2 = fd_mul(fd_mul(M, fd_mul(vv, rho)), Wi);
    if (neg) G2 = dd_neg(G2);
    vc[0] = v.x, vc[1] = v.y, vc[2] = v.z;
    nc[0] = n.x, nc[1] = n.y, nc[2] = n.z;
    for (i = 0; i < 3; i++) {
        gg_dd p1 = dd_two_prod(G1.hi, vc[i]), p2 = dd_two_prod(G2.hi, nc[i]);
        gg_dd sm = dd_two_sum(p1.hi, p2.hi);
        r[i] = sm.hi + (sm.lo + (p1.lo + p2.lo) + (G1.lo * vc[i] + G2.lo * nc[i]));
    }
    *t = v3(r[0], r[1], r[2]);
    return 1;
}

/* Bits of |x|. */
GG_INLINE uint64_t abs_bits(double x)
{
    uint64_t b;
    memcpy(&b, &x, sizeof b);
    return b & ~(1ull << 63);
}

/* The accurate refraction. Returns 1 (transmitted), 0 (total internal
   reflection or tangent v: *t is the mirror direction) or -1 (invalid:
   *t is NaN). */
GG_OPTICS_LINKAGE int GG_REFRACT_NAME(const ggVec3 *vp, const ggVec3 *np, double ni, double nt, ggVec3 *t)
{
    const uint64_t fin = 0x7ff0000000000000ull;
    ggVec3 v = *vp, n = *np;
    uint64_t mv = max_bits(v), mn = max_bits(n), bi = abs_bits(ni), bt = abs_bits(nt);
    uint64_t ei = bi >> 52, et = bt >> 52;
    int ediff = 0;
    /* finite and non-zero: x - 1 wraps for zero */
    if (mv - 1 >= fin - 1 || mn - 1 >= fin - 1 || bi - 1 >= fin - 1 || bt - 1 >= fin - 1) {
        *t = v3nan();
        return -1;
    }
    v = scale_unit(v, mv), n = scale_unit(n, mn);
    /* Indices: one common power of two, unless their ratio is so extreme
       that the smaller would underflow; then each is scaled on its own and
       the ratio's exponent is carried by the tangential part (refract_dd). */
    if (ei >= 1 && ei <= 2045 && et >= 1 && et <= 2045 && ei <= et + 450) {
        double s = pow2_inv(ei > et ? ei : et);
        ni *= s, nt *= s;
    } else {
        int xi = dd_expo(ni), xt = dd_expo(nt), em = xi > xt ? xi : xt;
        if (xi - xt > 450) {
            ediff = xi - xt;
            ni = dd_scale2(ni, -xi), nt = dd_scale2(nt, -xt);
        } else {
            ni = dd_scale2(ni, -em), nt = dd_scale2(nt, -em);
        }
    }
    /* the fast path for 0 < eta <= 4 (and eta >= 2^-200) */
    if (!ediff && (ni > 0) == (nt > 0) && fabs(ni) <= 4.0 * fabs(nt) &&
        fabs(ni) >= 0x1p-200 * fabs(nt)) {
        int rc = refract_fast(v, n, ni, nt, t);
        if (rc != 2) return rc;
    }
    v = v3(flush(v.x), flush(v.y), flush(v.z));
    n = v3(flush(n.x), flush(n.y), flush(n.z));
    return refract_dd(v, n, ni, nt, ediff, t);
}
