/* SPDX-License-Identifier: MIT */
/*
** optics_cases.c -- the hard-case generators of `ggrt optics check`
** (docs/optics.md lists the classes). The first classes of each kind keep
** 1/4 <= |ni/nt| <= 4 and vector components within 2^-480 of their
** vector's largest; the last ones (issue 32) draw every exponent: normal
** parts of v down to 2^-1074 of the tangential part, subnormal
** components and cosines, index ratios over the whole double range,
** ni == nt, and n == n_outside with k down to 2^-1074 and few bits.
*/
#include "optics/optics_cases.h"

#include <math.h>

static const char *const refract_classes[] = {"random",
                                              "grazing",
                                              "grazing exact dot",
                                              "near critical",
                                              "eta near 1",
                                              "normal incidence",
                                              "negative index",
                                              "exactly tangent",
                                              "huge and tiny",
                                              "non-unit",
                                              "extreme eta",
                                              "tiny normal part",
                                              "every exponent",
                                              "any index ratio",
                                              "huge eta, tilted",
                                              "subnormal sine",
                                              NULL};
static const char *const reflect_classes[] = {
    "random",          "grazing",       "grazing exact dot", "normal incidence",
    "exactly tangent", "huge and tiny", "non-unit",          NULL};
static const char *const fresnel_classes[] = {"random",
                                              "grazing",
                                              "near critical",
                                              "eta near 1",
                                              "normal incidence",
                                              "negative index",
                                              "huge and tiny",
                                              "brewster",
                                              "subnormal cosine",
                                              "any index ratio",
                                              NULL};
static const char *const conductor_classes[] = {"random",           "grazing",
                                                "normal incidence", "metals",
                                                "tiny k",           "tiny k near critical",
                                                "huge and tiny",    "matched, tiny k",
                                                "any index ratio",  NULL};

const char *const *oc_classes(int kind)
{
    switch (kind) {
    case OC_REFRACT:
        return refract_classes;
    case OC_REFLECT:
        return reflect_classes;
    case OC_FRESNEL:
        return fresnel_classes;
    default:
        return conductor_classes;
    }
}

uint64_t oc_next(oc_rng *r)
{
    /* xorshift64* (Vigna 2016) */
    r->s ^= r->s >> 12, r->s ^= r->s << 25, r->s ^= r->s >> 27;
    return r->s * 2685821657736338717ULL;
}

static double uni(oc_rng *r)
{
    return (double)(oc_next(r) >> 11) * 0x1p-53;
}
static double range(oc_rng *r, double lo, double hi)
{
    return lo + (hi - lo) * uni(r);
}
static int irange(oc_rng *r, int lo, int hi)
{
    return lo + (int)(oc_next(r) % (uint64_t)(hi - lo + 1));
}

static ggVec3 V(double x, double y, double z)
{
    ggVec3 a;
    a.x = x, a.y = y, a.z = z;
    return a;
}
static double dot(ggVec3 a, ggVec3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
static ggVec3 scale(ggVec3 a, double s)
{
    return V(a.x * s, a.y * s, a.z * s);
}

static ggVec3 unit(oc_rng *r)
{
    ggVec3 a;
    double l;
    do {
        a = V(range(r, -1, 1), range(r, -1, 1), range(r, -1, 1));
        l = dot(a, a);
    } while (l > 1 || l < 0x1p-20);
    return scale(a, 1 / sqrt(l));
}

/* Unit v travelling towards the surface of unit normal n (or -n, at
   random) at incidence cosine c: -c n' + sqrt(1 - c^2) u, u _|_ n. */
static ggVec3 incoming(oc_rng *r, ggVec3 n, double c)
{
    ggVec3 a = unit(r), u;
    double d = dot(a, n), s = sqrt((1 - c) * (1 + c)), sg = (oc_next(r) & 1) ? 1 : -1;
    u = V(a.x - d * n.x, a.y - d * n.y, a.z - d * n.z);
    u = scale(u, 1 / sqrt(dot(u, u)));
    return V(-sg * c * n.x + s * u.x, -sg * c * n.y + s * u.y, -sg * c * n.z + s * u.z);
}

static double index1(oc_rng *r)
{
    return range(r, 1.0, 2.5);
}

/* m 2^e, m in [1, 2) (one bit when few is 1, two when 2), with e in
   [lo, hi] clamped to the doubles: never 0 or infinite. */
static double any_exp(oc_rng *r, int lo, int hi, int few)
{
    int e = irange(r, lo, hi);
    double x = ldexp(few == 1 ? 1.0 : few == 2 ? 1.5 : range(r, 1, 2), e < -1074 ? -1074 : e);
    if (x == 0) x = 0x1p-1074;
    return isfinite(x) ? x : 0x1.fffffffffffffp1023;
}

/* Indices whose ratio covers the whole range (2^-2097 to 2^2097), either
   sign; one pair in four with ni == nt, one in eight ni == -nt. */
static void any_indices(oc_rng *r, oc_case *c)
{
    int w = irange(r, 0, 7);
    c->ni = any_exp(r, -1074, 1023, 0), c->nt = any_exp(r, -1074, 1023, 0);
    if (oc_next(r) & 1) c->ni = -c->ni;
    if (oc_next(r) & 1) c->nt = -c->nt;
    if (w < 2) c->nt = c->ni;
    if (w == 2) c->nt = -c->ni;
}

/* v = T + N, |N| = 2^-p |T| for p in 1..1074: the normal part of v from
   1/2 down to 2^-1074 of its tangential part, n along an axis (either
   sign), both at any scale. */
static void tiny_normal(oc_rng *r, oc_case *c)
{
    double t = range(r, 0, 6.283185307179586), comp[3], nc[3] = {0, 0, 0};
    int ax = irange(r, 0, 2), sg = (oc_next(r) & 1) ? 1 : -1, sv = irange(r, -1000, 1000);
    comp[(ax + 1) % 3] = ldexp(cos(t), sv), comp[(ax + 2) % 3] = ldexp(sin(t), sv);
    comp[ax] = -sg * any_exp(r, sv - 1074, sv - 1, 0);
    nc[ax] = sg * any_exp(r, -1000, 1000, 0);
    c->v = V(comp[0], comp[1], comp[2]), c->n = V(nc[0], nc[1], nc[2]);
    any_indices(r, c);
}

/* Every component of v and n at any exponent (some zero, some
   subnormal), |ni/nt| within 2^+-400 (beyond, the reference's own error
   when the tangential part is rounded could reach the bound: optics.h). */
static void every_exponent(oc_rng *r, oc_case *c)
{
    double d[6];
    int i, e;
    do {
        for (i = 0; i < 6; i++) {
            d[i] = irange(r, 0, 5) == 0 ? 0 : any_exp(r, -1074, 1023, 0);
            if (oc_next(r) & 1) d[i] = -d[i];
        }
    } while ((d[0] == 0 && d[1] == 0 && d[2] == 0) || (d[3] == 0 && d[4] == 0 && d[5] == 0));
    c->v = V(d[0], d[1], d[2]), c->n = V(d[3], d[4], d[5]);
    e = irange(r, -674, 623);
    c->ni = any_exp(r, e, e, 0), c->nt = any_exp(r, e - 400, e + 400, 0);
    if (oc_next(r) & 1) c->nt = -c->nt;
    if (irange(r, 0, 7) == 0) c->nt = c->ni;
}

/* An axis normal (permuted, either sign, power-of-two length) and v with
   v.n = -2^-k times it, exactly: grazing with an exact dot product. */
static void grazing_exact(oc_rng *r, oc_case *c)
{
    double t = range(r, 0, 6.283185307179586), s = ldexp(1.0, irange(r, -4, 4));
    double comp[3], nc[3] = {0, 0, 0};
    int ax = irange(r, 0, 2), sg = (oc_next(r) & 1) ? 1 : -1;
    comp[(ax + 1) % 3] = cos(t), comp[(ax + 2) % 3] = sin(t);
    comp[ax] = -sg * ldexp(1.0, -irange(r, 1, 60));
    nc[ax] = sg * s;
    c->v = V(comp[0], comp[1], comp[2]), c->n = V(nc[0], nc[1], nc[2]);
}

/* v.n == 0 exactly: n = (a, b, c0), v = (-b, a, 0) permuted. */
static void tangent(oc_rng *r, oc_case *c)
{
    double a = range(r, -1, 1), b = range(r, -1, 1), z = range(r, -1, 1);
    double vc[3], nc[3];
    int p = irange(r, 0, 2);
    nc[p] = a, nc[(p + 1) % 3] = b, nc[(p + 2) % 3] = z;
    vc[p] = -b, vc[(p + 1) % 3] = a, vc[(p + 2) % 3] = 0;
    if (oc_next(r) & 1) vc[(p + 2) % 3] = z, nc[(p + 2) % 3] = 0;
    c->v = V(vc[0], vc[1], vc[2]), c->n = V(nc[0], nc[1], nc[2]);
}

/* Within +-2000 ulp of the critical angle asin(nt/ni). */
static void near_critical(oc_rng *r, oc_case *c)
{
    double th;
    c->ni = range(r, 1.2, 2.5), c->nt = range(r, 1.0, c->ni / 1.1);
    th = asin(c->nt / c->ni);
    th += irange(r, -2000, 2000) * (nextafter(th, 4) - th);
    c->n = unit(r), c->v = incoming(r, c->n, cos(th));
}

/* |eta| = 2^+-(2 ... 900): into a much denser medium, or out of one with
   sin_i below 1/|eta| (transmitted) or within 2^-40 of it. */
static void extreme_eta(oc_rng *r, oc_case *c)
{
    double e = ldexp(range(r, 1, 2), irange(r, 2, 900)), s, cs;
    ggVec3 u, a = unit(r);
    c->nt = index1(r), c->n = unit(r);
    if (oc_next(r) & 1) {
        c->ni = c->nt / e;
        c->v = incoming(r, c->n, uni(r));
        return;
    }
    c->ni = c->nt * e;
    s = (oc_next(r) & 1) ? uni(r) / e : (1 + irange(r, -1000, 1000) * 0x1p-40) / e;
    cs = dot(a, c->n);
    u = V(a.x - cs * c->n.x, a.y - cs * c->n.y, a.z - cs * c->n.z);
    u = scale(u, 1 / sqrt(dot(u, u)));
    cs = sqrt((1 - s) * (1 + s));
    c->v = V(-cs * c->n.x + s * u.x, -cs * c->n.y + s * u.y, -cs * c->n.z + s * u.z);
}

/* a b - c d with the products' rounding errors (fma) added back: within
   about 2^-104 of max(|a b|, |c d|), however much the difference cancels */
static double diff_prod(double a, double b, double c, double d)
{
    double p = a * b, q = c * d;
    return (p - q) + (fma(a, b, -p) - fma(c, d, -q));
}

/* v within 2^-p of a normal off every axis (p from 1 to 62), ni = x /
   sin(theta_i) (so eta up to 2^62): x from 1/4 to 1.05, or 1 +- 2^-q
   with q up to 45, which puts cos^2(theta_t) within about 2^-(q-1) of
   0 on either side. sin(theta_i) comes from v x n with compensated
   products, so x holds to about 2^-44. Forming v - (v.n/n.n) n loses
   2^-106 / sin(theta_i) of the tangential part in every direction,
   which eta multiplies; "extreme eta" rarely draws such rays, and an
   audit found ggRefract 197,597 ulp off and deciding TIR wrongly there
   (cos^2(theta_t) near 2^-44 and 2^-62). */
static void huge_eta_tilted(oc_rng *r, oc_case *c)
{
    ggVec3 d = unit(r), v, n, w;
    double s = ldexp(range(r, 1, 2), -irange(r, 1, 62)), sn, x;
    n = c->n = unit(r);
    v = c->v = V(-n.x + s * d.x, -n.y + s * d.y, -n.z + s * d.z);
    w = V(diff_prod(v.y, n.z, v.z, n.y), diff_prod(v.z, n.x, v.x, n.z),
          diff_prod(v.x, n.y, v.y, n.x));
    sn = sqrt(dot(w, w) / (dot(v, v) * dot(n, n)));
    x = (oc_next(r) & 1) ? range(r, 0.25, 1.05)
                         : 1 + ((oc_next(r) & 1) ? 1 : -1) * ldexp(1.0, -irange(r, 1, 45));
    c->nt = index1(r);
    c->ni = sn > 0 && isfinite(c->nt * x / sn) ? c->nt * x / sn : c->nt * 0x1p62;
}

/* v and n parallel but for a cross product below the subnormal range:
   they share a component s = sm 2^es down to 2^-1074 and their other
   components x = xm 2^ex and x' differ by k units in the last place, so
   sin(theta_i) is about (sm k / xm^2) 2^(es - ex - 52), as small as
   2^-1126; nt is set from it so that eta sin(theta_i) is 1/4 to 2 (eta up
   to 2^2098). A fuzzer found ggRefract calling such v and n parallel
   and letting through a ray that totally reflects. */
static void subnormal_sine(oc_rng *r, oc_case *c)
{
    int ex = irange(r, -60, 60), es = irange(r, -1074, -960), e;
    double xm = range(r, 1, 2), sm = range(r, 1, 2), k = (double)irange(r, 1, 1 << 20);
    double x = ldexp(xm, ex), s = ldexp(sm, es), m = range(r, 0.25, 2), im = range(r, 1, 2);
    if (s == 0) s = 0x1p-1074, sm = 1, es = -1074;
    sm = s / ldexp(1.0, es); /* the mantissa s kept after rounding to a subnormal */
    c->v = V(x, s, 0), c->n = V(x + k * ldexp(1.0, ex - 52), s, 0);
    if (oc_next(r) & 1) c->v = V(0, -c->v.x, c->v.y), c->n = V(0, -c->n.x, c->n.y);
    /* ni = im 2^ei with nt = im (sm k / xm^2) / m 2^(ei + es - ex - 52) normal */
    e = irange(r, -1000, 0) - ex;
    c->ni = ldexp(im, ex + 52 - es + e);
    c->nt = ldexp(im * sm * k / (xm * xm * m), e);
    if (!isfinite(c->ni)) c->ni = 0x1.fffffffffffffp1023;
    if (oc_next(r) & 1) c->nt = -c->nt;
}

static void refract_case(int cls, oc_rng *r, oc_case *c)
{
    double k;
    c->ni = index1(r), c->nt = index1(r), c->n = unit(r);
    switch (cls) {
    case 0:
        c->v = incoming(r, c->n, uni(r));
        break;
    case 1:
        c->v = incoming(r, c->n, ldexp(1.0, -irange(r, 1, 60)));
        if (oc_next(r) & 1) c->nt = c->ni;
        break;
    case 2:
        grazing_exact(r, c);
        break;
    case 3:
        near_critical(r, c);
        break;
    case 4:
        c->nt = c->ni * (1 + irange(r, -64, 64) * 0x1p-52);
        c->v = incoming(r, c->n, (oc_next(r) & 1) ? uni(r) : ldexp(1.0, -irange(r, 1, 50)));
        break;
    case 5:
        c->ni = range(r, 1, 4), c->nt = range(r, 1, 4);
        if (oc_next(r) & 1) k = c->ni, c->ni = c->nt, c->nt = k;
        c->v = (oc_next(r) & 1) ? scale(c->n, -range(r, 0.5, 2))
                                : incoming(r, c->n, 1 - ldexp(1.0, -irange(r, 20, 60)));
        break;
    case 6:
        refract_case(irange(r, 0, 4), r, c);
        if (oc_next(r) & 1)
            c->ni = -c->ni;
        else
            c->nt = -c->nt;
        break;
    case 7:
        tangent(r, c);
        break;
    case 8:
        refract_case(irange(r, 0, 5), r, c);
        k = ldexp(1.0, irange(r, -900, 900));
        c->v = scale(c->v, ldexp(1.0, irange(r, -900, 900)));
        c->n = scale(c->n, ldexp(1.0, irange(r, -900, 900)));
        c->ni *= k, c->nt *= k;
        break;
    case 9:
        refract_case(irange(r, 0, 5), r, c);
        c->v = scale(c->v, exp(range(r, -7, 7)));
        c->n = scale(c->n, exp(range(r, -7, 7)));
        break;
    case 10:
        extreme_eta(r, c);
        break;
    case 11:
        tiny_normal(r, c);
        break;
    case 12:
        every_exponent(r, c);
        break;
    case 14:
        huge_eta_tilted(r, c);
        break;
    case 15:
        subnormal_sine(r, c);
        break;
    default:
        c->v = incoming(r, c->n, (oc_next(r) & 1) ? uni(r) : 1 - ldexp(uni(r), -irange(r, 1, 60)));
        any_indices(r, c);
        break;
    }
}

static void reflect_case(int cls, oc_rng *r, oc_case *c)
{
    /* random, grazing, grazing exact dot, normal, tangent, huge/tiny, non-unit */
    static const int map[] = {0, 1, 2, 5, 7, 8, 9};
    refract_case(map[cls], r, c);
}

/* Reflectance cases: c->c = cos_i, c->ni, c->nt (and c->k). */
static void fresnel_case(int cls, oc_rng *r, oc_case *c)
{
    oc_case d;
    c->ni = index1(r), c->nt = index1(r), c->c = uni(r), c->k = 0;
    switch (cls) {
    case 0:
        break;
    case 1:
        c->c = ldexp(1.0, -irange(r, 1, 60));
        break;
    case 2:
        near_critical(r, &d);
        c->ni = d.ni, c->nt = d.nt, c->c = fabs(dot(d.v, d.n)) / sqrt(dot(d.v, d.v));
        break;
    case 3:
        c->nt = c->ni * (1 + irange(r, -64, 64) * 0x1p-52);
        break;
    case 4:
        c->c = 1 - irange(r, 0, 8) * 0x1p-53;
        break;
    case 5:
        fresnel_case(irange(r, 0, 4), r, c);
        if (oc_next(r) & 1)
            c->ni = -c->ni;
        else
            c->nt = -c->nt;
        break;
    case 6: {
        double s = ldexp(1.0, irange(r, -1000, 1000));
        fresnel_case(irange(r, 0, 4), r, c);
        c->ni *= s, c->nt *= s;
        break;
    }
    case 7: /* Brewster's angle, where rp = 0: cos = ni / hypot(ni, nt) */
        c->c = c->ni / hypot(c->ni, c->nt) * (1 + irange(r, -1000, 1000) * 0x1p-53);
        break;
    case 8:
        any_indices(r, c);
        c->c = any_exp(r, -1074, -1023, 0);
        break;
    default: /* any ratio; a third at Brewster's angle of tiny ni/nt */
        any_indices(r, c);
        c->c = irange(r, 0, 2) == 0 ? uni(r) : any_exp(r, -1074, 0, 0);
        if (irange(r, 0, 2) == 0 && fabs(c->ni) < fabs(c->nt))
            c->c = fabs(c->ni / c->nt) * (1 + irange(r, -1000, 1000) * 0x1p-40);
        if (c->c > 1 || c->c == 0) c->c = uni(r);
        break;
    }
}

static void conductor_case(int cls, oc_rng *r, oc_case *c)
{
    static const double metal[][2] = {{0.14, 3.70}, {0.06, 3.59}, {0.96, 6.69},
                                      {1.10, 2.58}, {2.90, 3.10}, {0.27, 2.78}};
    c->ni = range(r, 1, 1.6), c->nt = range(r, 0.05, 3), c->k = range(r, 0, 8), c->c = uni(r);
    switch (cls) {
    case 0:
        break;
    case 1:
        c->c = ldexp(1.0, -irange(r, 1, 60));
        break;
    case 2:
        c->c = 1 - irange(r, 0, 8) * 0x1p-53;
        break;
    case 3: {
        int m = irange(r, 0, 5);
        c->ni = 1, c->nt = metal[m][0], c->k = metal[m][1];
        break;
    }
    case 4:
        c->k = ldexp(1.0, -irange(r, 10, 60));
        break;
    case 5: {
        oc_case d;
        near_critical(r, &d);
        c->ni = d.ni, c->nt = d.nt, c->c = fabs(dot(d.v, d.n)) / sqrt(dot(d.v, d.v));
        c->k = ldexp(1.0, -irange(r, 20, 60));
        break;
    }
    case 6: {
        double s = ldexp(1.0, irange(r, -900, 900));
        conductor_case(irange(r, 0, 3), r, c);
        c->ni *= s, c->nt *= s, c->k *= s;
        break;
    }
    case 7: { /* n == n_outside, k = n 2^-(0 ... 2100), 1, 2 or 53 bits */
        int e = irange(r, -1022, 1023);
        c->ni = c->nt = any_exp(r, e, e, 0);
        c->k = any_exp(r, e - 2100, e, irange(r, 0, 2));
        c->c = irange(r, 0, 3) == 0 ? 1 : any_exp(r, -1074, -1, 0);
        break;
    }
    default: /* n_outside, n, k and the cosine at any exponent */
        c->ni = any_exp(r, -1074, 1023, 0), c->nt = any_exp(r, -1074, 1023, 0);
        c->k = irange(r, 0, 3) == 0 ? 0 : any_exp(r, -1074, 1023, irange(r, 0, 2));
        if (oc_next(r) & 1) c->ni = -c->ni;
        c->c = irange(r, 0, 3) == 0 ? uni(r) : any_exp(r, -1074, -1, 0);
        break;
    }
}

void oc_make(int kind, int cls, oc_rng *r, oc_case *c)
{
    c->c = c->k = 0;
    switch (kind) {
    case OC_REFRACT:
        refract_case(cls, r, c);
        break;
    case OC_REFLECT:
        reflect_case(cls, r, c);
        break;
    case OC_FRESNEL:
        fresnel_case(cls, r, c);
        break;
    default:
        conductor_case(cls, r, c);
        break;
    }
}
