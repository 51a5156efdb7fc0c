/* SPDX-License-Identifier: MIT */
/*
** fresnel.c -- Fresnel reflectance of dielectric and conducting
** interfaces, Schlick's approximation, Beer-Lambert absorption.
** docs/optics.md derives the forms used here.
*/
#include "core.h"

#include "dd.h"

#include <math.h>

/* |cos_i| clamped to [0, 1]; the caller has checked it is finite. */
static double clamp_cos(double c)
{
    c = fabs(c);
    return c > 1 ? 1 : c;
}

/* Scale a and b (>= 0, not both 0) by one power of two so the larger is in
   [1, 2): the reflectances depend only on their ratio. */
static void scale_pair(double *a, double *b)
{
    int e = dd_expo(*a > *b ? *a : *b);
    *a = dd_scale2(*a, -e), *b = dd_scale2(*b, -e);
}

/* nt^2 cos^2(theta_t) = (nt^2 - ni^2) + ni^2 c^2, in double-double: the two
   terms cancel near the critical angle. */
static gg_dd cos_t_sq_nt2(double a, double b, double c, gg_dd *delta)
{
    *delta = dd_sub(dd_two_prod(b, b), dd_two_prod(a, a));
    return dd_add(*delta, dd_sqr(dd_two_prod(a, c)));
}

/* Dielectric: Rs and Rp as double-words. a = |ni|, b = |nt|, c in [0, 1].
   With q = nt^2 cos_t^2 and delta = nt^2 - ni^2,
     rs = (ni c - nt cos_t)/(ni c + nt cos_t) = -delta / (ni c + sqrt q)^2
   (multiply by the conjugate; docs/optics.md), whose numerator cannot
   cancel: a reflectance of 1e-30 between nearly matched media keeps its
   digits. After scaling, ni c + sqrt q >= 2^-26 (a != b are doubles in
   [2^-52, 2) apart), so the square cannot underflow.
     rp = (nt c - ni cos_t)/(nt c + ni cos_t) = (P - Q)/(P + Q),
   P = nt^2 c, Q = ni sqrt q, both in double-double; when P and Q are close
   the numerator is rewritten as (P^2 - Q^2)/(P + Q) with
   P^2 - Q^2 = delta ((ni^2 + nt^2) c^2 - ni^2), which does not cancel
   (it vanishes only at Brewster's angle, as rp must). Otherwise P and Q
   are scaled together (the index ratio may be extreme). */
static void dielectric_dd(double c, double a, double b, gg_dd *rs, gg_dd *rp)
{
    gg_dd delta, q, sq, A, P, Q, amp;
    double m;
    if (a == b) {
        *rs = *rp = dd_from(0.0);
        return;
    }
    if (c == 0) {
        *rs = *rp = dd_from(1.0);
        return;
    }
    scale_pair(&a, &b);
    q = cos_t_sq_nt2(a, b, c, &delta);
    if (q.hi <= 0) { /* total internal reflection */
        *rs = *rp = dd_from(1.0);
        return;
    }
    sq = dd_sqrt(q);
    A = dd_add(dd_two_prod(a, c), sq);
    amp = dd_div(delta, dd_sqr(A));
    *rs = dd_sqr(amp);
    P = dd_mul_d(dd_two_prod(b, b), c), Q = dd_mul_d(sq, a);
    if (P.hi <= 2 * Q.hi && Q.hi <= 2 * P.hi && P.hi > 0x1p-400) {
        /* P - Q cancels (nearly matched media): use
           P^2 - Q^2 = delta ((ni^2 + nt^2) c^2 - ni^2) instead. */
        gg_dd a2 = dd_two_prod(a, a), PQ = dd_add(P, Q);
        gg_dd br = dd_sub(dd_mul(dd_two_prod(c, c), dd_add(a2, dd_two_prod(b, b))), a2);
        amp = dd_div(dd_mul(delta, br), dd_sqr(PQ));
        *rp = dd_sqr(amp);
        return;
    }
    m = P.hi > Q.hi ? P.hi : Q.hi;
    if (m == 0) {
        *rp = dd_from(1.0);
        return;
    }
    if (m < 0x1p-900) {
        int e = -dd_expo(m);
        P = dd_make(dd_scale2(P.hi, e), dd_scale2(P.lo, e));
        Q = dd_make(dd_scale2(Q.hi, e), dd_scale2(Q.lo, e));
    }
    amp = dd_div(dd_sub(P, Q), dd_add(P, Q));
    *rp = dd_sqr(amp);
}

static int dielectric_args(double cos_i, double ni, double nt)
{
    return isfinite(cos_i) && isfinite(ni) && isfinite(nt) && ni != 0 && nt != 0;
}

GG_API void ggFresnelDielectricPolarized(double cos_i, double ni, double nt, double *rs,
                                         double *rp)
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

/* |p - q|^2 / |p + q|^2 for complex p = (pr, pi), q = (qr, qi), scaled so
   that nothing underflows; `zero` is returned for 0/0. */
static double ratio_sq(double pr, double pi, double qr, double qi, double zero)
{
    double m = fabs(pr), num, den;
    if (fabs(pi) > m) m = fabs(pi);
    if (fabs(qr) > m) m = fabs(qr);
    if (fabs(qi) > m) m = fabs(qi);
    if (m == 0) return zero;
    if (m < 0x1p-500 || m > 0x1p500) {
        int e = -dd_expo(m);
        pr = dd_scale2(pr, e), pi = dd_scale2(pi, e), qr = dd_scale2(qr, e), qi = dd_scale2(qi, e);
    }
    num = (pr - qr) * (pr - qr) + (pi - qi) * (pi - qi);
    den = (pr + qr) * (pr + qr) + (pi + qi) * (pi + qi);
    if (den == 0) return zero;
    return num > den ? 1.0 : num / den;
}

/* Rs and Rp for outside index n1 and inside n + i k (all scaled together,
   the largest in [1, 2)), cosine c. With eta~ = (n + i k)/n1,
     z  = sqrt(eta~^2 - sin^2)            (principal root, Re z >= 0)
     Rs = |c - z|^2 / |c + z|^2,   Rp = |eta~^2 c - z|^2 / |eta~^2 c + z|^2.
   Multiplying through by n1 (and n1^2 for Rp) leaves Z = n1 z =
   sqrt(X + i Y), X = n^2 - k^2 - n1^2 sin^2, Y = 2 n k. X is the small
   difference of large terms near the critical angle when k is small, so
   it is formed in double-double from exact squares; the square root is
   then taken without cancellation (the half-angle forms). */
static void conductor_general(double c, double n1, double n, double k, double *rs, double *rp)
{
    gg_dd s2 = dd_sub(dd_from(1.0), dd_two_prod(c, c));
    gg_dd X = dd_sub(dd_sub(dd_two_prod(n, n), dd_two_prod(k, k)),
                     dd_mul(dd_two_prod(n1, n1), s2));
    double Y = 2 * n * k, m = hypot(X.hi, Y), za, zb;
    if (m == 0) {
        za = zb = 0;
    } else if (X.hi >= 0) {
        /* sqrt(m + X) sqrt(1/2): halving first could underflow to 0. */
        za = sqrt(m + X.hi) * 0.70710678118654752440;
        zb = Y / (2 * za);
    } else {
        zb = sqrt(m - X.hi) * 0.70710678118654752440;
        za = Y / (2 * zb);
    }
    /* With eta~ tending to 0 both ratios tend to 1 (the outside medium
       is infinitely denser): the 0/0 value. */
    *rs = ratio_sq(c * n1, 0, za, zb, 1.0);
    *rp = ratio_sq((n - k) * (n + k) * c, Y * c, n1 * za, n1 * zb, 1.0);
}

/* |eta~| = H 2^G with G > 300: then sin^2 is negligible next to eta~^2
   (relative 2^-600), z = eta~, and with u = eta~/|eta~|,
     Rs = |w - u|^2/|w + u|^2,  w = c / |eta~|;
     Rp = |L u - 1|^2/|L u + 1|^2, L = c |eta~|. */
static void conductor_huge(double c, double ur, double ui, double H, int G, double *rs,
                           double *rp)
{
    double w = dd_scale2(c / H, -G), L;
    *rs = ratio_sq(w, 0, ur, ui, 1.0);
    if (c == 0 || dd_expo(c) + G > 900) {
        /* Grazing, or L > 2^898: Rp = 1 - O(1/L), 1 when rounded. */
        *rp = 1.0;
        return;
    }
    L = dd_scale2(c * H, G);
    if (L > 0x1p500)
        *rp = ratio_sq(ur, ui, 1 / L, 0, 1.0);
    else
        *rp = ratio_sq(L * ur, L * ui, 1, 0, 1.0);
}

static int conductor(double cos_i, double n1, double n, double k, double *rs, double *rp)
{
    double c, nm, km, n1m, H;
    int e1, em, G;
    if (!isfinite(cos_i) || !isfinite(n1) || !isfinite(n) || !isfinite(k) || n1 == 0 || n < 0 ||
        k < 0 || (n == 0 && k == 0)) {
        *rs = *rp = NAN;
        return 0;
    }
    c = clamp_cos(cos_i);
    n1 = fabs(n1);
    if (k == 0 && n == n1) {
        *rs = *rp = 0;
        return 1;
    }
    /* eta~ = (n + i k)/n1 = (nm + i km)/n1m 2^G with nm, km, n1m in [1, 2). */
    e1 = dd_expo(n1), em = dd_expo(n > k ? n : k);
    G = em - e1;
    if (G > 300) {
        n1m = dd_scale2(n1, -e1), nm = dd_scale2(n, -em), km = dd_scale2(k, -em);
        H = hypot(nm, km);
        conductor_huge(c, nm / H, km / H, H / n1m, G, rs, rp);
    } else {
        /* One common scale. |eta~| < 2^302; tiny ones may underflow, which
           only pushes R towards its limit 1. */
        int e = e1 > em ? e1 : em;
        conductor_general(c, dd_scale2(n1, -e), dd_scale2(n, -e), dd_scale2(k, -e), rs, rp);
    }
    return 1;
}

GG_API void ggFresnelConductorPolarized(double cos_i, double n_outside, double n, double k,
                                        double *rs, double *rp)
{
    double s, p;
    conductor(cos_i, n_outside, n, k, &s, &p);
    if (rs) *rs = s;
    if (rp) *rp = p;
}

GG_API double ggFresnelConductor(double cos_i, double n_outside, double n, double k)
{
    double s, p;
    if (!conductor(cos_i, n_outside, n, k, &s, &p)) return NAN;
    return 0.5 * (s + p);
}

/* ------------------------------------------------------------------ */
/* Beer-Lambert                                                        */
/* ------------------------------------------------------------------ */

#define FOUR_PI 12.566370614359172954

GG_API double ggAbsorptionCoefficient(double k, double lambda)
{
    if (!isfinite(k) || !isfinite(lambda) || k < 0 || !(lambda > 0)) return NAN;
    if (k == 0) return 0;
    /* 4 pi k / lambda < 2^(ek - el + 5): overflow only past 2^1018. */
    if (dd_expo(k) - dd_expo(lambda) > 1018) return INFINITY;
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
