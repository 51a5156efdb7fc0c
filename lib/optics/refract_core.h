/* SPDX-License-Identifier: MIT */
/*
** refract_core.h -- the body of the accurate refraction (internal),
** included twice: by optics.c as plain code, and by refract_fma.c compiled
** for CPUs with fused multiply-add, where dd.h's TwoProd is one fma instead
** of Dekker's 17-flop product. TwoProd is exact either way (the inputs are
** scaled so that no error term underflows), so both copies return the
** same bits; optics.c picks one at run time. Before including, define
** GG_REFRACT_NAME (the name of the static function to generate).
*/
#ifndef GG_REFRACT_NAME
#error "define GG_REFRACT_NAME before including refract_core.h"
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

static int v3valid(ggVec3 a) { return v3finite(a) && (a.x != 0 || a.y != 0 || a.z != 0); }

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

/* v and n scaled so their largest components are in [1, 2); returns 0 if
   either is zero or not finite. */
static int normalise_pair(ggVec3 *v, ggVec3 *n)
{
    if (!v3valid(*v) || !v3valid(*n)) return 0;
    *v = v3scale2(*v, -dd_expo(v3maxabs(*v)));
    *n = v3scale2(*n, -dd_expo(v3maxabs(*n)));
    *v = v3(flush(v->x), flush(v->y), flush(v->z));
    *n = v3(flush(n->x), flush(n->y), flush(n->z));
    return 1;
}

/* The accurate refraction. Returns 1 (transmitted), 0 (total internal
   reflection or tangent v: *t is the mirror direction) or -1 (invalid:
   *t is NaN). */
static int GG_REFRACT_NAME(ggVec3 v, ggVec3 n, double ni, double nt, ggVec3 *t)
{
    double vc[3], nc[3], sump;
    gg_dd a, vv, nn, k, vt[3], ni2, nt2, A, D, g1, g2;
    int s, i, ediff = 0;

    if (!isfinite(ni) || !isfinite(nt) || ni == 0 || nt == 0 || !normalise_pair(&v, &n)) {
        *t = v3nan();
        return -1;
    }
    /* Indices: one common power of two, unless their ratio is so extreme
       that the smaller would underflow; then each is scaled on its own and
       the ratio's exponent is carried by the tangential part below. */
    {
        int ei = dd_expo(ni), et = dd_expo(nt), em = ei > et ? ei : et;
        if (ei - et > 450) {
            ediff = ei - et;
            ni = dd_scale2(ni, -ei), nt = dd_scale2(nt, -et);
        } else {
            ni = dd_scale2(ni, -em), nt = dd_scale2(nt, -em);
        }
    }
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

