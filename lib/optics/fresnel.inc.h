/* SPDX-License-Identifier: MIT */
/*
** fresnel.inc.h -- the double-double Fresnel reflectances (internal):
** Rs and Rp of a dielectric and of a conductor as double-words, for
** validated arguments. docs/optics.md ("Fresnel reflectance") derives the
** forms.
**
** Compiled twice: into fresnel.c (plain) and into fresnel_fma.c, built
** with -mfma for CPUs that have it (compiler.h, "Per-ISA code"), where
** dd_two_prod is one fma. TwoProd is exact either way and every other
** operation is the same (-ffp-contract=off), so both return the same bits
** (tests/unit/optics/test_fresnel_fma.c). The includer defines GG_INC_NAME and
** GG_INC_LINK (compiler.h, "Templates"); the functions are
** GG_INC_NAME(fresnel_dielectric) and GG_INC_NAME(fresnel_conductor).
*/
#include "dd.h"

#include <math.h>

#if !defined(GG_INC_NAME) || !defined(GG_INC_LINK)
#error "define GG_INC_NAME and GG_INC_LINK before including fresnel.inc.h"
#endif

/* Scale a and b (>= 0, not both 0) by one power of two so the larger is in
   [1, 2): the reflectances depend only on their ratio. */
static void scale_pair(double *a, double *b)
{
    int e = dd_expo(*a > *b ? *a : *b);
    *a = dd_scale2(*a, -e), *b = dd_scale2(*b, -e);
}

/* nt^2 cos^2(theta_t) = (nt^2 - ni^2) + ni^2 c^2, in double-double: the two
   terms cancel near the critical angle. For c^2 >= 1/2 (about) it is formed as
   nt^2 - ni^2 s^2 instead (s^2 = 1 - c^2 from the exact c^2): at normal
   incidence with ni >> nt the first form would leave nt^2 as the
   difference of two terms near ni^2, and lose it. */
static gg_dd cos_t_sq_nt2(double a, double b, double c, gg_dd *delta)
{
    gg_dd a2 = dd_two_prod(a, a), b2 = dd_two_prod(b, b);
    *delta = dd_sub(b2, a2);
    if (c >= 0.70710678118654752) /* c^2 >= 1/2 */
        return dd_sub(b2, dd_mul(a2, dd_sub(dd_from(1.0), dd_two_prod(c, c))));
    return dd_add(*delta, dd_sqr(dd_two_prod(a, c)));
}

static gg_dd dd_x2(gg_dd a)
{
    return dd_make(2 * a.hi, 2 * a.lo);
}

static gg_dd dd_scale(gg_dd a, int e)
{
    return dd_make(dd_scale2(a.hi, e), dd_scale2(a.lo, e));
}

/* 1 - 4 x for x = xm 2^ex, xm in [1/4, 4) (x < 2^-290): the reflectance
   ((1 - x)/(1 + x))^2 to within 8 x^2. */
static gg_dd one_minus_4x(gg_dd xm, int ex)
{
    if (ex < -1100) return dd_from(1.0);
    return dd_sub(dd_from(1.0), dd_scale(xm, ex + 2));
}

/* The biased exponent field of x >= 0 (0 for a subnormal: then the test
   below may send a ratio up to 2^352 to the general path, which keeps
   ni normal after scaling). */
static uint64_t expo_field(double x)
{
    uint64_t b;
    memcpy(&b, &x, sizeof b);
    return b >> 52;
}

/* Rs and Rp for ni far below nt (a < 2^-300 b, any exponents), where
   scaling the pair together would leave ni (and ni c) subnormal or zero.
   With eta = a/b, cos_t = sqrt(1 - eta^2 s^2) is 1 to within 2^-600, so
     rs = (x - 1)/(x + 1),  x = eta c < 2^-300,
     rp = (w - 1)/(w + 1),  w = c/eta,
   and x and w are formed from the mantissas with their exponents apart,
   so a subnormal c or an index ratio beyond 2^1023 loses nothing. Taking
   cos_t as 1 moves rs and rp by less than eta^2 < 2^-600 (docs/optics.md,
   "Dielectrics", "ni far below nt"). */
static GG_NOINLINE void dielectric_tiny_eta(double c, double a, double b, gg_dd *rs,
                                           gg_dd *rp)
{
    int ec = dd_expo(c), ea = dd_expo(a), eb = dd_expo(b), ew;
    double cm = dd_scale2(c, -ec), am = dd_scale2(a, -ea), bm = dd_scale2(b, -eb);
    gg_dd x = dd_div(dd_two_prod(am, cm), dd_from(bm)), w = dd_div(dd_two_prod(cm, bm), dd_from(am));
    *rs = one_minus_4x(x, ea + ec - eb);
    ew = ec + eb - ea;
    if (ew > 600) {
        /* Rp = 1 - 4 w/(w + 1)^2 = 1 - 4/w to within 2^-1200 */
        *rp = one_minus_4x(dd_div(dd_from(1.0), w), -ew);
    } else if (ew < -600) {
        *rp = one_minus_4x(w, ew);
    } else {
        /* (w - 1)/(w + 1) = (c b - a)/(c b + a) with c b exact: the
           numerator, which vanishes at Brewster's angle, has only its
           one rounding (and cos_t = 1 moves it by less than 2^-490 of
           itself unless c b == a, where Rp < 2^-1200 anyway) */
        gg_dd X = dd_scale(dd_two_prod(cm, bm), ew), A = dd_from(am);
        gg_dd amp = dd_div(dd_sub(X, A), dd_add(X, A));
        *rp = dd_sqr(amp);
    }
}

/* Append x (hi + lo, exact) to the non-overlapping expansion e[0..*m)
   (Shewchuk's Grow-Expansion, twice). */
static void grow2(double *e, int *m, gg_dd x)
{
    double part[2];
    int i, j;
    part[0] = x.hi, part[1] = x.lo;
    for (j = 0; j < 2; j++) {
        double q = part[j];
        for (i = 0; i < *m; i++) {
            gg_dd t = dd_two_sum(q, e[i]);
            q = t.hi, e[i] = t.lo;
        }
        e[(*m)++] = q;
    }
}

/* (h hi + h lo)^2 as three exact products appended to e. */
static void grow_sqr(double *e, int *m, gg_dd h)
{
    grow2(e, m, dd_two_prod(h.hi, h.hi));
    grow2(e, m, dd_two_prod(2.0 * h.hi, h.lo));
    grow2(e, m, dd_two_prod(h.lo, h.lo));
}

/* 2^512 ((ni^2 + nt^2) c^2 - ni^2), a = |ni|, b = |nt| (a >= 2^-353 b,
   b in [1, 2)), to a relative 2^-100: the term that vanishes at
   Brewster's angle, where forming it in double-double leaves only its
   rounding errors (Rp then off by up to 1e3 ulp of itself). Its three
   products are summed exactly (the indices scaled by 2^256 so no part
   underflows), except c^2 a^2 for c < 2^-200, which is below 2^-400 a^2
   and added after the exact sum of the others (which is 0 or above
   2^-110 a^2). */
static GG_NOINLINE gg_dd brewster_term(double a, double b, double c)
{
    double e[16], as = a * 0x1p256, bs = b * 0x1p256;
    int m = 0, i;
    gg_dd r = dd_from(0.0), ca = dd_two_prod(c, as), na = dd_two_prod(as, as);
    grow_sqr(e, &m, dd_two_prod(c, bs));
    grow2(e, &m, dd_make(-na.hi, -na.lo));
    if (c >= 0x1p-200) grow_sqr(e, &m, ca);
    for (i = 0; i < m; i++) r = dd_add(r, dd_from(e[i]));
    return c >= 0x1p-200 ? r : dd_add(r, dd_sqr(ca));
}

/* Dielectric: Rs and Rp as double-words. a = |ni| > 0, b = |nt| > 0, c in
   [0, 1].
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
GG_INC_LINK void GG_INC_NAME(fresnel_dielectric)(double c, double a, double b, gg_dd *rs, gg_dd *rp)
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
    if (expo_field(b) > expo_field(a) + 300) {
        dielectric_tiny_eta(c, a, b, rs, rp);
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
        if (fabs(br.hi) < 0x1p-45 * a2.hi) {
            /* near Brewster's angle: exactly, scaled by 2^512 */
            br = brewster_term(a, b, c);
            amp = dd_div(dd_mul(delta, br), dd_sqr(PQ));
            amp = dd_make(dd_scale2(amp.hi, -512), dd_scale2(amp.lo, -512));
        } else {
            amp = dd_div(dd_mul(delta, br), dd_sqr(PQ));
        }
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

/* ---- conductors ---- */

/* Rs and Rp as double-words. */
typedef struct conductor_r {
    gg_dd rs, rp;
} conductor_r;

/* |x + iy| for double-words, scaled first if the squares could leave the
   range where double-words keep their precision. */
static gg_dd dd_hypot(gg_dd x, gg_dd y)
{
    double m = fabs(x.hi) > fabs(y.hi) ? fabs(x.hi) : fabs(y.hi);
    int e;
    if (m > 0x1p-400 && m < 0x1p400) return dd_sqrt(dd_add_same(dd_sqr(x), dd_sqr(y)));
    if (m == 0) return dd_from(0.0);
    e = dd_expo(m);
    x = dd_scale(x, -e), y = dd_scale(y, -e);
    return dd_scale(dd_sqrt(dd_add_same(dd_sqr(x), dd_sqr(y))), e);
}

/* za = Re Z and m = |Z|^2 = |X + iY| for Z = sqrt(X + iY), the principal
   root (Y >= 0), from the half-angle forms, which do not cancel:
   za = sqrt((m + X)/2) for X >= 0, else za = Y/(2 zb) with
   zb = sqrt((m - X)/2). (Im Z is not needed below.) */
static void complex_sqrt(gg_dd X, gg_dd Y, gg_dd *za, gg_dd *m)
{
    *m = dd_hypot(X, Y);
    *za = dd_from(0.0);
    if (m->hi == 0) return;
    if (X.hi >= 0) {
        *za = dd_sqrt(dd_mul_d(dd_add(*m, X), 0.5));
    } else if (Y.hi != 0) {
        gg_dd zb = dd_sqrt(dd_mul_d(dd_sub(*m, X), 0.5));
        *za = dd_div(Y, dd_x2(zb));
    }
}

/* The unscaled quantities of the forms below, for outside index n1,
   inside n + ik, cosine c. */
typedef struct conductor_in {
    double c, n1;
    gg_dd c2, N1, N1s2, NN, KK, Y; /* c^2, n1^2, n1^2 s^2, n^2, k^2, 2nk */
} conductor_in;

/* Rs and Rp from a scaled pair: with sigma = 2^j,
   A = sigma a (a = n1 c) and T = sigma^2 ((n + ik)^2 - n1^2) = Tr + i Ti.
   docs/optics.md ("Conductors") derives the forms: with s^2 = 1 - c^2,
   Z = n1 cos_t (n + ik) = sqrt(a^2 + (n + ik)^2 - n1^2) (principal root),
     rs = (a^2 - Z^2) / (a + Z)^2 = -((n + ik)^2 - n1^2) / (a + Z)^2,
     |rs| = |T| / Ds,            Ds = |A + sigma Z|^2 = A^2 + 2 A za + m,
     za = Re sigma Z,            m = |sigma Z|^2,
     rp = -((n + ik)^2 - n1^2) Bc / ((n + ik)^2 c + n1 Z)^2,
     Bc = c^2 (n^2 - k^2) - n1^2 s^2 + i 2nk c^2,
     |rp| = |T| |Bc| / Dp,       Dp = C^2 (n^2 + k^2)^2 + 2 C W + n1^2 m,
     W = n1 Re(conj((n + ik)^2) sigma Z) = n1 za (n1^2 s^2 + m sigma^-2),
     C = sigma c.
   X = Re (sigma Z)^2 = A^2 + Tr = sigma^2 (n^2 - k^2 - n1^2 s^2). Only Tr,
   X and Re Bc are differences (of exact products, in double-double);
   every other sum has terms of one sign. Ds and Dp are
   sigma^2 times their unscaled values, so the ratios do not depend on
   sigma: it only keeps a tiny A and T inside the exponent range. */
static void conductor_core(const conductor_in *in, gg_dd NpK, int j, gg_dd A, gg_dd X, gg_dd Tr,
                           gg_dd Ti, conductor_r *r)
{
    gg_dd za, m, E2, Ds, W, e, Dp, Br, Bi, B2;
    double C = dd_scale2(in->c, j);
    complex_sqrt(X, Ti, &za, &m);
    Ds = dd_add_same(dd_add_same(dd_sqr(A), dd_x2(dd_mul(A, za))), m);
    W = dd_mul_d(dd_mul(za, dd_add_same(in->N1s2, dd_scale(m, -2 * j))), in->n1);
    e = dd_mul_d(NpK, C);
    Dp = dd_add_same(dd_sqr(e), dd_add_same(dd_x2(dd_mul_d(W, C)), dd_mul(in->N1, m)));
    Br = dd_sub(dd_sub(dd_mul(in->c2, in->NN), in->N1s2), dd_mul(in->c2, in->KK));
    Bi = dd_mul(in->c2, in->Y);
    /* Ds >= max(A^2, m), m = |A^2 + T|, is above 2^-310 (A^2 or |T| is
       above 2^-302, see conductor_general); |T| is above 2^-54 unless
       n == n1. */
    if (Dp.hi > 0x1p-400 && (fabs(Tr.hi) > 0x1p-400 || fabs(Ti.hi) > 0x1p-400) &&
        (fabs(Br.hi) > 0x1p-400 || fabs(Bi.hi) > 0x1p-400)) {
        E2 = dd_add_same(dd_sqr(Tr), dd_sqr(Ti));
        B2 = dd_add_same(dd_sqr(Br), dd_sqr(Bi));
        r->rs = dd_div(E2, dd_sqr(Ds));
        r->rp = dd_div(dd_mul(E2, B2), dd_sqr(Dp));
    } else {
        /* |T| or |Bc| and Dp tiny (n == n1 with a tiny k, or n1 far below
           |n + ik|): as ratios first, so that no square underflows */
        gg_dd E = dd_hypot(Tr, Ti), q = dd_div(E, Ds);
        r->rs = dd_sqr(q);
        q = dd_div(dd_mul(E, dd_hypot(Br, Bi)), Dp);
        r->rp = dd_sqr(q);
    }
}

/* Outside index n1, inside n + ik (k > 0), scaled together so that the
   largest is in [1, 2) and n1 and |n + ik| are both above 2^-302; cosine
   c in (0, 1]. (n + ik)^2 - n1^2 = (n^2 - k^2 - n1^2) + 2ink is at least
   2^-54 unless n == n1, where it is k (2in - k): then a tiny k with a tiny
   c (a and Z both below 2^-480) is scaled up by sigma^2, chosen to bring
   the larger of a^2 and |T| near 1. */
static void conductor_general(double c, double n1, double n, double k, double kraw, int e,
                              conductor_r *r)
{
    conductor_in in;
    gg_dd A, X, Tr, Ti;
    int j = 0;
    in.c = c, in.n1 = n1;
    in.c2 = dd_two_prod(c, c), in.N1 = dd_two_prod(n1, n1);
    in.N1s2 = dd_mul(in.N1, dd_sub(dd_from(1.0), in.c2));
    in.NN = dd_two_prod(n, n), in.KK = dd_two_prod(k, k), in.Y = dd_x2(dd_two_prod(n, k));
    if (n == n1) {
        /* k = kraw 2^-e = km 2^ke is used only scaled by sigma (k sigma
           and k sigma^2, sigma = 2^j), so no k down to 2^-1074 n loses a
           bit; where the scaled k is subnormal its k^2 and 2nk terms in
           conductor_core are below 2^-1000 of the terms they are added
           to. */
        int ea, et, h, ke = dd_expo(kraw);
        double kj, k2, km = dd_scale2(kraw, -ke);
        ke -= e;
        ea = dd_expo(c) + dd_expo(n1), et = dd_expo(km) + ke + dd_expo(n > k ? n : k) + 1;
        h = 2 * ea > et ? 2 * ea : et;
        if (h < -300) j = -(h / 2);
        kj = dd_scale2(km, ke + j), k2 = dd_scale2(km, ke + 2 * j);
        A = dd_two_prod(n1, dd_scale2(c, j));
        Tr = dd_neg(dd_two_prod(kj, kj)), Ti = dd_x2(dd_two_prod(n, k2));
        X = dd_add(dd_sqr(A), Tr);
    } else {
        /* X from n^2 - k^2 - n1^2 s^2: A^2 + Tr would cancel when |n + ik|
           is much below n1 near normal incidence. */
        A = dd_two_prod(n1, c);
        Tr = dd_sub(dd_sub(in.NN, in.N1), in.KK), Ti = in.Y;
        /* as in cos_t_sq_nt2, whichever of n^2 - n1^2 s^2 and
           (n^2 - n1^2) + a^2 cancels less */
        X = in.c2.hi >= 0.5 ? dd_sub(in.NN, in.N1s2) : dd_add(dd_sub(in.NN, in.N1), dd_sqr(A));
        X = dd_sub(X, in.KK);
    }
    conductor_core(&in, dd_add_same(in.NN, in.KK), j, A, X, Tr, Ti, r);
}

/* |eta~| = (n + ik)/n1 = H 2^G, G > 300, u = eta~/|eta~| = (ur, ui): then
   sin^2 is negligible next to eta~^2 (relative 2^-600) and z = eta~, so
   with w = c/|eta~| and L = c |eta~|
     Rs = |w - u|^2 / |w + u|^2,   1 - Rs = 4 w ur / (1 + 2 w ur + w^2),
     Rp = |L u - 1|^2 / |L u + 1|^2 = ((L - 1)^2 + 2 L ui^2/(1 + ur)) / Dp,
     1 - Rp = 4 L ur / Dp,   Dp = L^2 + 2 L ur + 1.
   c > 0; H as a double-word. */
static void conductor_huge(double c, gg_dd ur, gg_dd ui, gg_dd H, int G, conductor_r *r)
{
    gg_dd w = dd_scale(dd_div(dd_from(c), H), -G), L, one = dd_from(1.0), Dp, N;
    gg_dd wu = dd_mul(w, ur), tp;
    r->rs =
        dd_sub(one, dd_div(dd_mul_d(wu, 4), dd_add_same(one, dd_add_same(dd_x2(wu), dd_sqr(w)))));
    if (dd_expo(c) + G > 900) {
        /* L > 2^898: 1 - Rp = 4 ur / L, to 2^-898 relative (c 2^600 first:
           H c could underflow to 0 for a subnormal c). */
        tp = dd_scale(dd_div(dd_mul_d(ur, 4), dd_mul_d(H, dd_scale2(c, 600))), 600 - G);
    } else {
        L = dd_mul_d(H, dd_scale2(c, G)); /* c 2^G first: c may be subnormal */
        if (L.hi > 0x1p400) {
            tp = dd_div(dd_mul_d(ur, 4), L);
        } else {
            Dp = dd_add_same(dd_add_same(dd_sqr(L), dd_x2(dd_mul(L, ur))), one);
            N = dd_add_same(dd_sqr(dd_sub(L, one)),
                            dd_div(dd_x2(dd_mul(L, dd_sqr(ui))), dd_add_same(one, ur)));
            r->rp = dd_div(N, Dp);
            return;
        }
    }
    r->rp = dd_sub(one, tp);
}

/* Rs, Rp (and the complements) for valid arguments; 0 if they are not. */
/* Rs and Rp of a conductor for valid arguments: c = |cos_i| clamped to
   [0, 1], n1 = |n_outside| > 0, n >= 0, k >= 0, not both 0. */
GG_INC_LINK void GG_INC_NAME(fresnel_conductor)(double c, double n1, double n, double k, gg_dd *rs,
                                                gg_dd *rp)
{
    conductor_r r;
    int e1, em, G;
    if (k == 0) {
        /* A dielectric: exactly ggFresnelDielectric's values. */
        GG_INC_NAME(fresnel_dielectric)(c, n1, n, rs, rp);
        return;
    }
    r.rs = r.rp = dd_from(1.0);
    if (c > 0) {
        /* eta~ = (n + ik)/n1 = (nm + i km)/n1m 2^G with n1m and the larger
           of nm, km in [1, 2). */
        e1 = dd_expo(n1), em = dd_expo(n > k ? n : k);
        G = em - e1;
        if (G > 300) {
            double n1m = dd_scale2(n1, -e1), nm = dd_scale2(n, -em), km = dd_scale2(k, -em);
            gg_dd h = dd_hypot(dd_from(nm), dd_from(km));
            conductor_huge(c, dd_div(dd_from(nm), h), dd_div(dd_from(km), h),
                           dd_div(h, dd_from(n1m)), G, &r);
        } else if (G >= -300) {
            int e = e1 > em ? e1 : em;
            conductor_general(c, dd_scale2(n1, -e), dd_scale2(n, -e), dd_scale2(k, -e), k, e, &r);
        }
        /* else |eta~| < 2^-299: R = 1 - O(|eta~|), 1 when rounded. */
    }
    *rs = r.rs, *rp = r.rp;
}
