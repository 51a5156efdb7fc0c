/* SPDX-License-Identifier: MIT */
/*
** error.c -- the error of anyone's reflection, refraction or Fresnel
** reflectance against the exact value for the given doubles
** (ggRefractError and friends, include/ggrt/optics.h).
**
** The exact value is evaluated in the 512-bit arithmetic of bigf.h from
** quantities in which nothing cancels that was rounded before:
**   a = v.n,  P = |v|^2 |n|^2,  Q = |v x n|^2 = P - a^2,
**   D = nt^2 P - ni^2 Q = nt^2 |v|^2 |n|^2 cos^2(theta_t),
** each a sum of products of the given doubles (exact when they fit in 512
** bits). Then
**   t_i = (ni/nt) (v_i |n|^2 - a n_i) / (|n|^2 |v|) + sign(a) cos_t n_i/|n|,
**   r_i = (v_i |n|^2 - 2 a n_i) / |n|^2                     (mirror image),
** with cos_t = sqrt(D / (nt^2 P)). docs/optics.md derives the error bound
** stated in optics.h.
*/
#include "core.h"

#include "bigf.h"
#include "vec.h"

#include <math.h>
#include <string.h>

typedef gg_bf bf;
#define B   gg_bf_from
#define ADD gg_bf_add
#define SUB gg_bf_sub
#define MUL gg_bf_mul
#define DIV gg_bf_div

static int finite3(ggVec3 a)
{
    return isfinite(a.x) && isfinite(a.y) && isfinite(a.z);
}
static int nonzero3(ggVec3 a)
{
    return a.x != 0 || a.y != 0 || a.z != 0;
}

/* Sum of three values, largest magnitude first, so that terms which
   cancel meet before a small one is added (exact when it fits). */
static bf sum3(bf a, bf b, bf c)
{
    bf t;
    if (gg_bf_cmpabs(a, b) < 0) t = a, a = b, b = t;
    if (gg_bf_cmpabs(b, c) < 0) t = b, b = c, c = t;
    if (gg_bf_cmpabs(a, b) < 0) t = a, a = b, b = t;
    return ADD(ADD(a, b), c);
}

static bf dot(const double *a, const double *b)
{
    return sum3(MUL(B(a[0]), B(b[0])), MUL(B(a[1]), B(b[1])), MUL(B(a[2]), B(b[2])));
}

/* |a x b|^2 from the exact-or-truncated cross product components. */
static bf cross2(const double *a, const double *b)
{
    bf c[3];
    int i;
    for (i = 0; i < 3; i++) {
        int j = (i + 1) % 3, k = (i + 2) % 3;
        c[i] = SUB(MUL(B(a[j]), B(b[k])), MUL(B(a[k]), B(b[j])));
    }
    return sum3(MUL(c[0], c[0]), MUL(c[1], c[1]), MUL(c[2], c[2]));
}

/* |d| in units of 2^-53 times the smallest power of two >= |r|, or of
   2^-1074 (the spacing of subnormals, the contract's unit where the
   result underflows) if that is larger: a correctly rounded subnormal or
   zero result is at most 1/2 off (0 if d == 0, +inf if only r is). */
static double in_units_of(bf d, bf r)
{
    int ue;
    if (!d.sign) return 0;
    if (!r.sign) return HUGE_VAL;
    ue = gg_bf_ceil_expo(r) - 53;
    return fabs(gg_bf_to_double(gg_bf_scale2(d, -(ue > -1074 ? ue : -1074))));
}

/* Fill e's error fields: candidate c against the exact direction r. */
static void measure(const bf r[3], ggVec3 cand, ggDirectionError *e)
{
    double c[3], d[3], ss = 0;
    bf big = r[0];
    int i, ue;
    c[0] = cand.x, c[1] = cand.y, c[2] = cand.z;
    for (i = 1; i < 3; i++)
        if (gg_bf_cmpabs(r[i], big) > 0) big = r[i];
    ue = big.sign ? gg_bf_ceil_expo(big) - 53 : -1074;
    if (ue < -1074) ue = -1074; /* the spacing of subnormals, as in_units_of */
    e->unit = ldexp(1.0, ue);
    e->exact = v3(gg_bf_to_double(r[0]), gg_bf_to_double(r[1]), gg_bf_to_double(r[2]));
    e->max_ulp = 0;
    for (i = 0; i < 3; i++) {
        bf diff;
        if (!isfinite(c[i])) {
            e->comp_ulp[i] = d[i] = HUGE_VAL;
            continue;
        }
        diff = SUB(B(c[i]), r[i]);
        /* scaled to the unit before rounding, so it cannot overflow */
        d[i] = fabs(gg_bf_to_double(gg_bf_scale2(diff, -ue)));
        e->comp_ulp[i] = in_units_of(diff, r[i]);
    }
    for (i = 0; i < 3; i++) {
        if (d[i] > e->max_ulp) e->max_ulp = d[i];
        ss += d[i] * d[i];
    }
    e->norm_ulp = isfinite(e->max_ulp) ? sqrt(ss) : HUGE_VAL;
    e->finite = finite3(cand);
}

GG_API int ggReflectionError(ggVec3 v, ggVec3 n, ggVec3 candidate, ggDirectionError *e)
{
    double vc[3], nc[3];
    bf a, nn, r[3];
    int i;
    if (!e) return GG_ERROR_INVALID;
    memset(e, 0, sizeof *e);
    e->critical_rad = NAN;
    if (!finite3(v) || !finite3(n) || !nonzero3(n) || !nonzero3(v)) return GG_ERROR_INVALID;
    vc[0] = v.x, vc[1] = v.y, vc[2] = v.z;
    nc[0] = n.x, nc[1] = n.y, nc[2] = n.z;
    a = dot(vc, nc), nn = dot(nc, nc);
    for (i = 0; i < 3; i++)
        r[i] = DIV(SUB(MUL(B(vc[i]), nn), gg_bf_scale2(MUL(a, B(nc[i])), 1)), nn);
    e->tir_agrees = e->certain = 1;
    e->cos2_t = 1;
    measure(r, candidate, e);
    return GG_OK;
}

/* theta_i - theta_c from sin(theta_i - theta_c) = sin_i cos_c - cos_i sin_c,
   sin_i = sqrt(Q/P), cos_i = |a|/sqrt(P), sin_c = |nt/ni|; |ni| > |nt|. */
static double critical_offset(bf a, bf P, bf Q, bf ni2, bf nt2, double ni, double nt)
{
    bf s, num;
    double x;
    a.sign = a.sign ? 1 : 0;
    num = SUB(MUL(gg_bf_sqrt(Q), gg_bf_sqrt(SUB(ni2, nt2))), MUL(a, B(fabs(nt))));
    s = DIV(num, MUL(gg_bf_sqrt(P), B(fabs(ni))));
    x = gg_bf_to_double(s);
    return asin(x > 1 ? 1 : x < -1 ? -1 : x);
}

/* The exact direction of the branch the candidate chose: transmitted
   (cos_t clamped at 0 if the exact answer is TIR) or mirrored; v/|v| for a
   tangent v. */
static void exact_dir(const double *vc, const double *nc, double ni, double nt, bf a, bf vv, bf nn,
                      bf D, bf nt2P, int tangent, int transmitted, bf r[3])
{
    bf g1, g2, lv = gg_bf_sqrt(vv);
    int i;
    if (tangent) {
        for (i = 0; i < 3; i++) r[i] = DIV(B(vc[i]), lv);
        return;
    }
    if (!transmitted) {
        /* (v_i |n|^2 - 2 a n_i) / (|n|^2 |v|) */
        g1 = DIV(B(1.0), MUL(nn, lv));
        for (i = 0; i < 3; i++)
            r[i] = MUL(SUB(MUL(B(vc[i]), nn), gg_bf_scale2(MUL(a, B(nc[i])), 1)), g1);
        return;
    }
    g1 = DIV(B(ni), MUL(B(nt), MUL(nn, lv)));
    g2 = D.sign > 0 ? gg_bf_sqrt(DIV(D, MUL(nt2P, nn))) : B(0.0);
    if (a.sign < 0) g2 = gg_bf_neg(g2);
    for (i = 0; i < 3; i++)
        r[i] = ADD(MUL(g1, SUB(MUL(B(vc[i]), nn), MUL(a, B(nc[i])))), MUL(g2, B(nc[i])));
}

GG_API int ggRefractError(ggVec3 v, ggVec3 n, double ni, double nt, ggVec3 candidate,
                          bool candidate_tir, ggDirectionError *e)
{
    double vc[3], nc[3];
    bf a, vv, nn, P, Q, ni2, nt2, nt2P, D, r[3];
    int tangent;
    if (!e) return GG_ERROR_INVALID;
    memset(e, 0, sizeof *e);
    e->critical_rad = NAN;
    if (!finite3(v) || !finite3(n) || !nonzero3(n) || !nonzero3(v) || !isfinite(ni) ||
        !isfinite(nt) || ni == 0 || nt == 0)
        return GG_ERROR_INVALID;
    vc[0] = v.x, vc[1] = v.y, vc[2] = v.z;
    nc[0] = n.x, nc[1] = n.y, nc[2] = n.z;
    a = dot(vc, nc), vv = dot(vc, vc), nn = dot(nc, nc);
    P = MUL(vv, nn), Q = cross2(vc, nc);
    ni2 = MUL(B(ni), B(ni)), nt2 = MUL(B(nt), B(nt));
    nt2P = MUL(nt2, P);
    D = SUB(nt2P, MUL(ni2, Q));
    tangent = a.sign == 0;
    e->cos2_t = tangent ? 1 : gg_bf_to_double(DIV(D, nt2P));
    e->exact_tir = tangent ? -1 : D.sign < 0;
    /* D's error is below 2^-508 nt^2 P (bigf.h: a few truncations of
       terms no larger than that), and none at all if nothing was rounded. */
    e->certain = tangent || !D.inexact || (D.sign && D.exp > nt2P.exp - 500);
    e->tir_agrees = (e->exact_tir != 0) == (candidate_tir != 0);
    if (!tangent && fabs(ni) > fabs(nt))
        e->critical_rad = critical_offset(a, P, Q, ni2, nt2, ni, nt);
    exact_dir(vc, nc, ni, nt, a, vv, nn, D, nt2P, tangent, !candidate_tir, r);
    measure(r, candidate, e);
    return GG_OK;
}

/* The candidate R against the exact one; (1 - cand) - (1 - R) is the same
   difference, measured in the unit of 1 - R. */
static void measure_r(bf R, double cand, ggReflectanceError *e)
{
    bf C = SUB(B(1.0), R), d;
    e->exact = gg_bf_to_double(R);
    e->complement_exact = gg_bf_to_double(C);
    e->finite = isfinite(cand);
    if (!e->finite) {
        e->ulp = e->complement_ulp = HUGE_VAL;
        return;
    }
    d = SUB(B(cand), R);
    e->ulp = in_units_of(d, R);
    e->complement_ulp = in_units_of(d, C);
}

/* Exact dielectric R for a = |ni|, b = |nt|, c in [0, 1] (a != b, c > 0):
     q = nt^2 cos_t^2 = b^2 - a^2 + a^2 c^2,
     rs = (a^2 - b^2) / (a c + sqrt q)^2,
     rp = (b^2 c - a sqrt q) / (b^2 c + a sqrt q). */
static bf dielectric_exact(double a, double b, double c)
{
    bf a2 = MUL(B(a), B(a)), b2 = MUL(B(b), B(b)), q, sq, ac, rs, rp, pc, pq;
    q = sum3(b2, gg_bf_neg(a2), MUL(a2, MUL(B(c), B(c))));
    if (q.sign <= 0) return B(1.0);
    sq = gg_bf_sqrt(q), ac = MUL(B(a), B(c));
    ac = ADD(ac, sq);
    rs = DIV(SUB(a2, b2), MUL(ac, ac));
    pc = MUL(b2, B(c)), pq = MUL(B(a), sq);
    rp = DIV(SUB(pc, pq), ADD(pc, pq));
    return gg_bf_scale2(ADD(MUL(rs, rs), MUL(rp, rp)), -1);
}

GG_API int ggFresnelDielectricError(double cos_i, double ni, double nt, double candidate,
                                    ggReflectanceError *e)
{
    double a, b, c;
    bf R;
    if (!e) return GG_ERROR_INVALID;
    memset(e, 0, sizeof *e);
    if (!isfinite(cos_i) || !isfinite(ni) || !isfinite(nt) || ni == 0 || nt == 0)
        return GG_ERROR_INVALID;
    a = fabs(ni), b = fabs(nt), c = fabs(cos_i) > 1 ? 1 : fabs(cos_i);
    R = a == b ? B(0.0) : c == 0 ? B(1.0) : dielectric_exact(a, b, c);
    measure_r(R, candidate, e);
    return GG_OK;
}

/* |p - q|^2 / |p + q|^2 for complex p and q. */
static bf ratio_sq(bf pr, bf pi, bf qr, bf qi)
{
    bf dr = SUB(pr, qr), di = SUB(pi, qi), sr = ADD(pr, qr), si = ADD(pi, qi);
    bf num = ADD(MUL(dr, dr), MUL(di, di)), den = ADD(MUL(sr, sr), MUL(si, si));
    return den.sign ? DIV(num, den) : B(1.0);
}

/* Exact conductor R: Z = n1 cos_t (n + ik) = sqrt(X + iY) with
   X = n^2 - k^2 - n1^2 (1 - c^2), Y = 2 n k (principal root, from the
   half-angle forms), Rs = |n1 c - Z|^2/|n1 c + Z|^2 and
   Rp = |(n + ik)^2 c - n1 Z|^2 / |(n + ik)^2 c + n1 Z|^2. */
static bf conductor_exact(double c, double n1, double n, double k)
{
    bf nn = MUL(B(n), B(n)), kk = MUL(B(k), B(k)), Y = gg_bf_scale2(MUL(B(n), B(k)), 1);
    bf n12 = MUL(B(n1), B(n1)), X, m, za, zb, rs, rp, ec;
    /* X = n^2 - k^2 - n1^2 s^2 with s^2 = 1 - c^2 exact for c^2 >= 1/2;
       below, 1 - c^2 could round to 1 (c < 2^-256) and lose n1^2 c^2, all
       that is left of X when n == n1 and k is tiny, so then
       X = (n^2 - n1^2) - k^2 + n1^2 c^2. The first difference is exact
       unless n and n1 are 230 binades apart, where X + iY is within
       2^-500 (relative) of (n + ik)^2 or of -n1^2 s^2 either way. */
    if (c * c >= 0.5)
        X = sum3(nn, gg_bf_neg(kk), gg_bf_neg(MUL(n12, SUB(B(1.0), MUL(B(c), B(c))))));
    else
        X = sum3(SUB(nn, n12), gg_bf_neg(kk), MUL(n12, MUL(B(c), B(c))));
    m = gg_bf_sqrt(ADD(MUL(X, X), MUL(Y, Y)));
    if (!m.sign) {
        za = zb = B(0.0);
    } else if (X.sign >= 0) {
        za = gg_bf_sqrt(gg_bf_scale2(ADD(m, X), -1));
        zb = DIV(Y, gg_bf_scale2(za, 1));
    } else {
        zb = gg_bf_sqrt(gg_bf_scale2(SUB(m, X), -1));
        za = DIV(Y, gg_bf_scale2(zb, 1));
    }
    ec = MUL(B(n1), B(c));
    rs = ratio_sq(ec, B(0.0), za, zb);
    rp = ratio_sq(MUL(SUB(nn, kk), B(c)), MUL(Y, B(c)), MUL(B(n1), za), MUL(B(n1), zb));
    return gg_bf_scale2(ADD(rs, rp), -1);
}

GG_API int ggFresnelConductorError(double cos_i, double n_outside, double n, double k,
                                   double candidate, ggReflectanceError *e)
{
    double c, n1;
    if (!e) return GG_ERROR_INVALID;
    memset(e, 0, sizeof *e);
    if (!isfinite(cos_i) || !isfinite(n_outside) || !isfinite(n) || !isfinite(k) ||
        n_outside == 0 || n < 0 || k < 0 || (n == 0 && k == 0))
        return GG_ERROR_INVALID;
    c = fabs(cos_i) > 1 ? 1 : fabs(cos_i);
    n1 = fabs(n_outside);
    measure_r(k == 0 && n == n1 ? B(0.0) : conductor_exact(c, n1, n, k), candidate, e);
    return GG_OK;
}
