/* SPDX-License-Identifier: MIT */
/*
** refract.inc.h -- the body of the accurate refraction and the
** four-lane helpers it shares with reflect.inc.h (internal), included
** twice: by optics.c as plain code, and by refract_fma.c compiled for
** CPUs with fused multiply-add, where TwoProd is
** one fma instead of Dekker's 17-flop product. TwoProd is exact either way
** (the inputs are scaled so that no error term underflows), and so is the
** only other use of fma, the remainder of a correctly rounded quotient or
** square root; so both copies return the same bits; optics.c picks one
** at run time. Before including, define GG_INC_NAME and GG_INC_LINK
** (compiler.h, "Templates"); the function is GG_INC_NAME(refract).
**
** The refraction first scales its vectors by powers of two (exact) and then
** tries a fast path: double-double where the result needs it, plain double
** elsewhere, with a running bound on the error. When the bound cannot
** guarantee the documented 1 ulp (near the critical angle, a ray almost in
** the surface, |ni/nt| > 4 or negative), the full double-double
** refract_dd decides. docs/optics.md gives the bound and its proof.
*/
#if !defined(GG_INC_NAME) || !defined(GG_INC_LINK)
#error "define GG_INC_NAME and GG_INC_LINK before including refract.inc.h"
#endif

#include "dd.h"
#include "refract_big.h"
#include "vec.h"

#include <math.h>

static ggVec3 v3scale2(ggVec3 a, int e)
{
    if (e == 0) return a;
    if (e >= -1022 && e <= 1023) return v3scale(a, dd_pow2(e));
    return v3(scalbn(a.x, e), scalbn(a.y, e), scalbn(a.z, e));
}

static ggVec3 v3nan(void)
{
    return v3(NAN, NAN, NAN);
}

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

/* A double as m 2^e with m in [1, 2) (x finite, non-zero). */
static double mant(double x, int *e)
{
    *e = dd_expo(x);
    return dd_scale2(x, -*e);
}

/* Sign (-1, 0, 1) of the exact a.b for any finite doubles: each product
   is kept as the product of two mantissas in [1, 2) with its own exponent
   (products of tiny components would underflow), and the terms are taken
   largest exponent first, in runs whose consecutive exponents are less
   than 300 apart; a run's sum is exact (dot_sign_exact, scaled to its
   first term: its products stay above 2^-600). A term is a multiple of
   2^-104 times 2 to its exponent, so a non-zero run is at least 2^-104
   times its last term's power of two, above everything after it (below
   2^-297 of that): its sign is the sign; a zero run leaves the decision to
   the rest. */
static int dot_sign_wide(ggVec3 a, ggVec3 b)
{
    double am[3], bm[3];
    int ex[3], i, j, e, order[3] = {0, 1, 2}, s = 0;
    am[0] = a.x, am[1] = a.y, am[2] = a.z, bm[0] = b.x, bm[1] = b.y, bm[2] = b.z;
    for (i = 0; i < 3; i++) {
        if (am[i] == 0 || bm[i] == 0) {
            am[i] = bm[i] = 0, ex[i] = -100000;
            continue;
        }
        am[i] = mant(am[i], &ex[i]), bm[i] = mant(bm[i], &e), ex[i] += e;
    }
    for (i = 0; i < 2; i++)
        for (j = 2; j > i; j--)
            if (ex[order[j]] > ex[order[j - 1]]) e = order[j], order[j] = order[j - 1], order[j - 1] = e;
    for (i = 0; i < 3 && s == 0 && am[order[i]] != 0; i = j) {
        double p[3] = {0, 0, 0}, q[3] = {0, 0, 0};
        int top = ex[order[i]];
        for (j = i; j < 3 && am[order[j]] != 0 && (j == i || ex[order[j]] > ex[order[j - 1]] - 300); j++)
            p[j] = am[order[j]], q[j] = dd_scale2(bm[order[j]], ex[order[j]] - top);
        s = dot_sign_exact(v3(p[0], p[1], p[2]), v3(q[0], q[1], q[2]));
    }
    return s;
}

/* True if a and b are exactly parallel (a x b == 0 in exact arithmetic),
   for any finite doubles: each component of a x b is a two-term dot
   product whose sign dot_sign_wide takes exactly. (Comparing the
   products' TwoProd pairs is not exact where a product is near the
   subnormal range: v = (0x1.3333333333333p-1, 0x9ap-1074, 0) and n =
   (0x1.33333333399p-1, 0x9ap-1074, 0), a sine near 2^-1100, gave equal
   pairs, and with eta near 2^1733 a ray that totally reflects went
   straight through; the fuzzer found it.) */
static int parallel_exact(ggVec3 a, ggVec3 b)
{
    return dot_sign_wide(v3(a.y, -a.z, 0), v3(b.z, b.y, 0)) == 0 &&
           dot_sign_wide(v3(a.z, -a.x, 0), v3(b.x, b.z, 0)) == 0 &&
           dot_sign_wide(v3(a.x, -a.y, 0), v3(b.y, b.x, 0)) == 0;
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
static double flush(double x)
{
    return fabs(x) < 0x1p-480 ? 0.0 : x;
}

/* The tangential part of v, n x (v x n) / |n|^2 = v - (v.n / n.n) n, for
   4 < |eta| <= 2^400. Formed as v - k n it carries an error of about
   2^-106 |v| in every direction, 2^-106 / sin(theta_i) of itself: eta
   multiplies that into t, and near the critical angle (sin(theta_i)
   about 1/eta) into the discriminant (an audit found 197,597 ulp and
   wrong decisions at eta = 2^52, test_refract_huge_eta_tilted). Here
   each component of w = v x n is a difference of two exact products
   (relative error 3u^2, none when v and n are parallel), and n x w has
   no cancellation relative to |n| |w| = |n|^2 |vt|: vt within about
   2^-102 of itself. The components, flushed (0 or at least 2^-480 of
   their vector's largest, which is in [1, 2)), give exact products, and
   w is scaled by 2^600 before the second product so that none of its
   terms underflow. */
static void tangent_cross(const double vc[3], const double nc[3], gg_dd nn, gg_dd vt[3])
{
    gg_dd w[3];
    int i;
    for (i = 0; i < 3; i++) {
        int j = (i + 1) % 3, k = (i + 2) % 3;
        w[i] = dd_sub(dd_two_prod(vc[j], nc[k]), dd_two_prod(vc[k], nc[j]));
        w[i] = dd_make(dd_scale2(w[i].hi, 600), dd_scale2(w[i].lo, 600));
    }
    for (i = 0; i < 3; i++) {
        int j = (i + 1) % 3, k = (i + 2) % 3;
        gg_dd x = dd_div(dd_sub(dd_mul_d(w[k], nc[j]), dd_mul_d(w[j], nc[k])), nn);
        vt[i] = dd_make(dd_scale2(x.hi, -600), dd_scale2(x.lo, -600));
    }
}

/* vt projected again along n: the error of vt is about 2^-104 |v| along n
   (from k's rounding), and t takes eta times it into its normal
   component. Each pass shrinks it by about 2^-104, until it is below
   2^-100 |vt| (so eta times it is below 2^-100 wherever the ray is
   transmitted). */
static void reproject(gg_dd vt[3], const double nc[3], gg_dd nn)
{
    int pass, i;
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

/* g1 vt_i + g2 n_i, rounded once: the exact products of the high parts
   are summed with TwoSum and everything else (at most 2^-104 of the
   terms, and |t| = 1) in double. */
static ggVec3 assemble(gg_dd g1, const gg_dd vt[3], gg_dd g2, const double nc[3])
{
    double r[3];
    int i;
    for (i = 0; i < 3; i++) {
        gg_dd p = dd_two_prod(g1.hi, vt[i].hi), q = dd_two_prod(g2.hi, nc[i]);
        gg_dd sum = dd_two_sum(p.hi, q.hi);
        double lo = sum.lo + (p.lo + q.lo) + (g1.hi * vt[i].lo + g1.lo * vt[i].hi) + g2.lo * nc[i];
        r[i] = sum.hi + lo;
    }
    return v3(r[0], r[1], r[2]);
}

/* Mirror direction (v - 2k n) / |v|. */
static ggVec3 mirror_dd(const double vc[3], const double nc[3], gg_dd k, gg_dd vv)
{
    double r[3];
    gg_dd k2 = dd_make(2.0 * k.hi, 2.0 * k.lo), rv = dd_rsqrt(vv);
    int i;
    for (i = 0; i < 3; i++) r[i] = dd_mul(dd_sub(dd_from(vc[i]), dd_mul_d(k2, nc[i])), rv).hi;
    return v3(r[0], r[1], r[2]);
}

/* The double-double refraction of normalised inputs (the fallback of the
   fast path below; tests/unit/optics/test_optics_accuracy.c compares the two):
   ediff is the exponent of |ni/nt| carried separately when it exceeds
   450; vp and np are the caller's vectors before scaling and flushing,
   from which the side v comes from is decided exactly. Returns 1
   (transmitted) or 0 (total internal reflection or tangent v: *t is the
   mirror direction). */
static GG_NOINLINE int refract_dd(ggVec3 v, ggVec3 n, double ni, double nt, int ediff,
                                  const ggVec3 *vp, const ggVec3 *np, ggVec3 *t)
{
    double vc[3], nc[3], sump;
    gg_dd a, vv, nn, k, vt[3], ni2, nt2, A, D, g1, g2;
    int s, i, sc;

    vc[0] = v.x, vc[1] = v.y, vc[2] = v.z;
    nc[0] = n.x, nc[1] = n.y, nc[2] = n.z;

    /* Which side v comes from. Dot2's error is below gamma_3^2 sum|v_i n_i|
       (about 9u^2 = 2^-102.8; dd.h, dd_dot3), and the components flushed
       (or lost to underflow by the scaling) change v.n by less than
       2^-476; only inside those bands is the exact sign worked out, from
       the caller's doubles. There a (below 2^-470) may even have the wrong
       sign: it is then taken as 0 (v grazing the surface, with the
       exact side s), which moves t by less than 2^-17 ulp and keeps the
       decision exact (docs/optics.md, "Grazing incidence below the
       flush"). */
    a = dd_dot3(v.x, v.y, v.z, n.x, n.y, n.z);
    sump = fabs(v.x * n.x) + fabs(v.y * n.y) + fabs(v.z * n.z);
    if (fabs(a.hi) > 0x1p-100 * sump && fabs(a.hi) > 0x1p-470) {
        s = a.hi > 0 ? 1 : -1;
    } else {
        s = dot_sign_wide(*vp, *np);
        if (s != (a.hi > 0) - (a.hi < 0)) a = dd_from(0.0);
    }

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
    /* For eta > 2^450 vt is formed scaled by 2^sc (exact): a component of
       n below 2^-1022 would otherwise make k n_i subnormal and lose the
       relative precision that eta multiplies. */
    sc = ediff ? 600 : 0;
    if (!ediff && fabs(ni) > 4 * fabs(nt) && fabs(ni) <= 0x1p400 * fabs(nt)) {
        tangent_cross(vc, nc, nn, vt);
    } else {
        /* Up to |eta| = 4, eta times v - k n's error stays below 2^-104
           (and keeps the bits the fast path gives, test_fast_certificate).
           Beyond 2^400 the components are not flushed, so the products of
           tangent_cross could underflow; transmission there needs
           sin(theta_i) < 2^-400, which only components hundreds of binades
           apart give, and k n_i then errs along n, which reproject takes
           out (test_refract_spread_huge_eta). */
        for (i = 0; i < 3; i++)
            vt[i] = dd_add_d(dd_neg(dd_mul_d(k, dd_scale2(nc[i], sc))), dd_scale2(vc[i], sc));
        /* Exactly normal incidence: vt above is only rounding noise (at
           most 2^-104 |v|), which a huge eta would magnify. */
        if (fabs(vt[0].hi) + fabs(vt[1].hi) + fabs(vt[2].hi) < dd_scale2(0x1p-90, sc) &&
            parallel_exact(v, n))
            vt[0] = vt[1] = vt[2] = dd_from(0.0);
        if (ediff || fabs(ni) > 0x1p30 * fabs(nt)) reproject(vt, nc, nn);
    }

    if (ediff) {
        /* eta > 2^450: transmission needs sin(theta_i) < 1/eta. With
           |v| < 2 sqrt(3) and |vt| >= m / sqrt(3), m >= 2^(4 - ediff)
           means eta sin(theta_i) > 1. Otherwise multiply vt by 2^ediff
           (exact) so the formulas below see eta in (1/2, 2). */
        double m = fabs(vt[0].hi) + fabs(vt[1].hi) + fabs(vt[2].hi);
        if (m != 0 && dd_expo(m) >= 4 - ediff + sc) goto tir;
        for (i = 0; i < 3; i++)
            vt[i].hi = dd_scale2(vt[i].hi, ediff - sc), vt[i].lo = dd_scale2(vt[i].lo, ediff - sc);
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
    *t = assemble(g1, vt, g2, nc);
    return 1;

tir:
    *t = mirror_dd(vc, nc, k, vv);
    return 0;
}

/* ------------------------------------------------------------------ */
/* Fast paths                                                          */
/* ------------------------------------------------------------------ */

/* Four-lane double vectors (GNU C vector extensions, GCC and clang): the
   three components of a vector, or three dot products side by side, go
   through the same error-free transformations at once. Lanes are
   independent IEEE operations, so the fma build (256-bit AVX, TwoProd one
   fma) and the plain build (SSE2 pairs, Dekker's product) agree bit for
   bit. The fourth lane repeats the third (so it raises no exception the
   third does not; a zero there makes GCC emit a VEX movq that valgrind
   3.19 cannot run). */
#if defined(GG_DD_FMA)
#include <immintrin.h>
#elif defined(__SSE2__)
#include <emmintrin.h>
#endif
/* Every function taking or returning these is inlined (GG_INLINE): no
   call crosses the ABI that GCC and clang warn about for the plain build. */
GG_PSABI_OFF
typedef double gg_v4 GG_VECTOR_SIZE(32);
typedef struct gg_v4dd {
    gg_v4 hi, lo;
} gg_v4dd;

typedef uint64_t gg_v4u GG_VECTOR_SIZE(32);
GG_INLINE gg_v4u v4bits(uint64_t x)
{
    gg_v4u r = {x, x, x, x};
    return r;
}

GG_INLINE gg_v4 v4splat(double x)
{
    gg_v4 r = {x, x, x, x};
    return r;
}

/* a * b = hi + lo exactly, lane by lane (barring underflow of lo). */
GG_INLINE gg_v4dd v4_two_prod(gg_v4 a, gg_v4 b)
{
    gg_v4dd r;
    r.hi = a * b;
#if defined(GG_DD_FMA)
    r.lo = (gg_v4)_mm256_fmsub_pd((__m256d)a, (__m256d)b, (__m256d)r.hi);
#else
    {
        const gg_v4 split = v4splat(134217729.0); /* 2^27 + 1 */
        gg_v4 ta = split * a, tb = split * b;
        gg_v4 ah = ta - (ta - a), al = a - ah, bh = tb - (tb - b), bl = b - bh;
        r.lo = ((ah * bh - r.hi) + ah * bl + al * bh) + al * bl;
    }
#endif
    return r;
}

/* a + b = hi + lo exactly, lane by lane. */
GG_INLINE gg_v4dd v4_two_sum(gg_v4 a, gg_v4 b)
{
    gg_v4dd r;
    gg_v4 bb;
    r.hi = a + b, bb = r.hi - a;
    r.lo = (a - (r.hi - bb)) + (b - bb);
    return r;
}

/* 1/sqrt(x) for a double-word x > 0: one Newton step from the double
   estimate y = x^(-1/2) (1 + d), |d| < 2.5u. 1 - m.hi is exact (Sterbenz:
   m = x y^2 is within 6u of 1), so the step's error is the truncation
   1.5 d^2, half of dd_mul's 7u^2 (dd.h) and two roundings of about 2.5u^2
   each: relative error below 20u^2. */
GG_INLINE gg_dd fd_rsqrt(gg_dd x)
{
    double y = 1.0 / sqrt(x.hi);
    gg_dd m = dd_mul(x, dd_two_prod(y, y));
    return dd_fast_two_sum(y, 0.5 * y * ((1.0 - m.hi) - m.lo));
}

/* The bits of |x|, and of the largest |component| (NaN and infinities
   compare largest, so the exponent field is 2047 if any component is not
   finite). */
GG_INLINE uint64_t abs_bits(double x)
{
    uint64_t b;
    memcpy(&b, &x, sizeof b);
    return b & ~(1ull << 63);
}
GG_INLINE uint64_t max_bits(ggVec3 a)
{
    uint64_t x = abs_bits(a.x), y = abs_bits(a.y), z = abs_bits(a.z);
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

/* a as a vector, scaled so its largest component is in [1, 2), given m =
   max_bits(a) (finite, non-zero): the same numbers as
   v3scale2(a, -dd_expo(max)). */
GG_INLINE gg_v4 scale_unit(ggVec3 a, uint64_t m)
{
    uint64_t e = m >> 52;
    gg_v4 r = {a.x, a.y, a.z, a.z};
    if (e >= 1 && e <= 2045) return r * v4splat(pow2_inv(e));
    a = v3scale2(a, -dd_expo(v3maxabs(a)));
    r[0] = a.x, r[1] = a.y, r[2] = a.z, r[3] = a.z;
    return r;
}

/* v.n, v.v and n.n in lanes 0, 1, 2, each hi + lo with |lo| <= u |hi|
   (Dot2 of Ogita, Rump and Oishi: error below 3u^2 times the sum of the
   |products|; for the sums of squares a relative error below 3u^2). *sump
   gets |v_x n_x| + |v_y n_y| + |v_z n_z|. */
GG_INLINE gg_v4dd v4_dots(gg_v4 V, gg_v4 N, double *sump)
{
    gg_v4 l1 = {V[0], V[0], N[0], N[0]}, r1 = {N[0], V[0], N[0], N[0]};
    gg_v4 l2 = {V[1], V[1], N[1], N[1]}, r2 = {N[1], V[1], N[1], N[1]};
    gg_v4 l3 = {V[2], V[2], N[2], N[2]}, r3 = {N[2], V[2], N[2], N[2]};
    gg_v4dd p1 = v4_two_prod(l1, r1), p2 = v4_two_prod(l2, r2), p3 = v4_two_prod(l3, r3);
    gg_v4dd s = v4_two_sum(p1.hi, p2.hi), t = v4_two_sum(s.hi, p3.hi);
    gg_v4 lo = ((p1.lo + p2.lo) + (p3.lo + s.lo)) + t.lo;
    *sump = fabs(p1.hi[0]) + fabs(p2.hi[0]) + fabs(p3.hi[0]);
    return v4_two_sum(t.hi, lo);
}

GG_INLINE gg_dd lane(gg_v4dd x, int i)
{
    return dd_make(x.hi[i], x.lo[i]);
}

/* (V - 2 (a/nn) N) rho, each component rounded once, for scaled V and N
   and a double-word rho (rho == NULL: 1, the reflection); a = v.n and nn
   = n.n as double-words. Error: docs/optics.md, "The fast paths". */
GG_INLINE ggVec3 mirror_fast(gg_v4 V, gg_v4 N, gg_dd a, gg_dd nn, const gg_dd *rho)
{
    double y = 1.0 / nn.hi, q = a.hi * y, rem;
    gg_dd p = dd_two_prod(q, nn.hi);
    gg_v4dd pk, s;
    gg_v4 lo, R;
    /* k = 2 a / nn as q + kl; a.hi - p.hi is exact (Sterbenz) */
    rem = (((a.hi - p.hi) - p.lo) + a.lo) - q * nn.lo;
    pk = v4_two_prod(v4splat(2.0 * q), N);
    s = v4_two_sum(V, -pk.hi);
    lo = (s.lo - pk.lo) - v4splat(2.0 * rem * y) * N;
    if (!rho) {
        R = s.hi + lo;
    } else {
        gg_v4dd m = v4_two_prod(s.hi, v4splat(rho->hi));
        R = m.hi + (m.lo + (s.hi * v4splat(rho->lo) + lo * v4splat(rho->hi)));
    }
    return v3(R[0], R[1], R[2]);
}

/* The square root of x >= 0. In the fma build without the errno check
   libm's sqrt carries (a compare and a branch); the same correctly
   rounded result either way. */
#if defined(GG_DD_FMA)
GG_INLINE double fsqrt(double x)
{
    return _mm_cvtsd_f64(_mm_sqrt_pd(_mm_set1_pd(x)));
}
#else
GG_INLINE double fsqrt(double x)
{
    return sqrt(x);
}
#endif

/* Two-lane double vectors: two square roots or two quotients of the fast
   refraction side by side (lanes are independent IEEE operations, as for
   gg_v4). */
typedef double gg_v2 GG_VECTOR_SIZE(16);
typedef uint64_t gg_v2u GG_VECTOR_SIZE(16);
typedef struct gg_v2dd {
    gg_v2 hi, lo;
} gg_v2dd;

GG_INLINE gg_v2u v2bits(uint64_t x)
{
    gg_v2u r = {x, x};
    return r;
}

GG_INLINE gg_v2 v2sqrt(gg_v2 x)
{
#if defined(__SSE2__)
    return (gg_v2)_mm_sqrt_pd((__m128d)x);
#else
    gg_v2 r = {sqrt(x[0]), sqrt(x[1])};
    return r;
#endif
}

/* x - a b, lane by lane, where that value is a double (the remainder of a
   correctly rounded quotient or square root): one fma in the fma build,
   Dekker's exact product and two subtractions in the plain one, the same
   exact result. */
GG_INLINE gg_v2 v2_exact_rem(gg_v2 x, gg_v2 a, gg_v2 b)
{
#if defined(GG_DD_FMA)
    return (gg_v2)_mm_fnmadd_pd((__m128d)a, (__m128d)b, (__m128d)x);
#else
    const gg_v2 split = {134217729.0, 134217729.0}; /* 2^27 + 1 */
    gg_v2 p = a * b, ta = split * a, tb = split * b;
    gg_v2 ah = ta - (ta - a), al = a - ah, bh = tb - (tb - b), bl = b - bh;
    return (x - p) - (((ah * bh - p) + ah * bl + al * bh) + al * bl);
#endif
}

/* Double-word operations for the fast refraction, without the final
   renormalisation (Fast2Sum) of dd.h's: operands and results are pairs
   hi + lo with |lo| <= 11u |hi| (u = 2^-53), which is all the error
   bounds of docs/optics.md ("The fast paths") assume. No fma (the builds
   agree bit for bit). */
/* x y: relative error below 3u^2 + |x.lo y.lo| / |x y|. */
GG_INLINE gg_dd w_mul(gg_dd x, gg_dd y)
{
    gg_dd c = dd_two_prod(x.hi, y.hi);
    return dd_make(c.hi, x.hi * y.lo + (x.lo * y.hi + c.lo));
}
/* x y for a double y: relative error below 2u^2. */
GG_INLINE gg_dd w_mul_d(gg_dd x, double y)
{
    gg_dd c = dd_two_prod(x.hi, y);
    return dd_make(c.hi, x.lo * y + c.lo);
}
/* The fast refraction of scaled v and n (largest components in [1, 2))
   and indices both in [2^-100, 2^101) or scaled so that the larger is in
   [1, 2) (scale_indices), with ni/nt in [2^-200, 4] (checked here). Every
   operation below commutes with a common power-of-two scaling of the
   indices (nothing over- or underflows and the bound is homogeneous in
   them), so both give the same bits. Returns 1 or 0 as refract_dd, or 2 when its running
   error bound cannot certify the result (then nothing is written). Notation and proof:
   docs/optics.md, "The fast paths". */
GG_INLINE int refract_fast(gg_v4 V, gg_v4 N, double ni, double nt, ggVec3 *t)
{
    double sump, sq, bound, eta, ani, ant;
    gg_dd a, vv, nn, Q, dn, sn, M, ni2, P, D, W, G1, G2;
    gg_v4dd d, p1, p2, sm;
    gg_v4 R;
    eta = ni / nt;
    if (!(eta >= 0x1p-200 && eta <= 4.0)) return 2;
    ani = fabs(ni), ant = fabs(nt);
    d = v4_dots(V, N, &sump);
    a = lane(d, 0), vv = lane(d, 1), nn = lane(d, 2);
    Q = w_mul(vv, nn);
    sq = fsqrt(Q.hi);
    /* the side v comes from is certain: Dot2's error is below 2^-102 |v||n| */
    if (!(fabs(a.hi) > 0x1p-100 * sq)) return 2;
    /* D = (nt - ni)(nt + ni) |v|^2 |n|^2 + ni^2 (v.n)^2 = nt^2 |v|^2 |n|^2 cos^2(theta_t) */
    dn = dd_two_sum(nt, -ni), sn = dd_two_sum(nt, ni);
    M = w_mul(dn, sn);
    ni2 = dd_two_prod(ni, ni);
    P = dd_two_prod(a.hi, a.hi);
    P.lo += 2.0 * a.hi * a.lo;
    {
        gg_dd m = dd_two_prod(M.hi, Q.hi), q = dd_two_prod(ni2.hi, P.hi),
              s = dd_two_sum(m.hi, q.hi);
        double lo = s.lo + (m.lo + q.lo);
        lo = M.hi * Q.lo + (M.lo * Q.hi + lo);
        lo = ni2.hi * P.lo + (ni2.lo * P.hi + lo);
        D = dd_fast_two_sum(s.hi, lo);
    }
    /* a bound on the error of D (docs/optics.md); the last term covers
       underflow in products of tiny components */
    bound = 0x1p-99 * (fabs(M.hi) * Q.hi + ni2.hi * (fabs(a.hi) * sq + 0x1p-501));
    if (D.hi < 0) {
        gg_dd rho;
        if (!(-D.hi > 2.0 * bound)) return 2;
        rho = fd_rsqrt(vv);
        *t = mirror_fast(V, N, a, nn, &rho);
        return 0;
    }
    /* relative error of D below 2^-52: then the Fast2Sum above was exact
       and sqrt(D) is one Newton step from the double square root. With
       ni == nt (M == 0) G2 is 0 whatever D (and D > 2^-603 > 0). */
    if (!(D.hi > 0x1p52 * bound) && M.hi != 0) return 2;
    /* G1 = eta / |v| = ni / (nt |v|), G2 = sign(v.n) M |v| / W with
       W = |nt| (sqrt(D) + |ni| |v.n|) = nt^2 |v| |n| (cos_t + eta |cos_i|);
       sqrt(D) and |v| side by side, then G2 and G1 */
    {
        gg_v2 x = {D.hi, vv.hi}, xl = {D.lo, vv.lo}, y, num, den, denl, q;
        gg_dd S, lv, X;
        y = v2sqrt(x);
        xl = (v2_exact_rem(x, y, y) + xl) / (y + y);
        S = dd_make(y[0], xl[0]), lv = dd_make(y[1], xl[1]);
        /* |v.n| |ni| and W carrying the sign of v.n (so G2 does) */
        a = w_mul_d(a, copysign(ani, a.hi));
        {
            gg_dd s = dd_two_sum(S.hi, a.hi);
            W = w_mul_d(dd_make(s.hi, s.lo + (S.lo + a.lo)), copysign(ant, d.hi[0]));
        }
        X = w_mul(M, lv);
        G1 = w_mul_d(lv, nt);
        num[0] = X.hi, num[1] = ni, den[0] = W.hi, den[1] = G1.hi, denl[0] = W.lo, denl[1] = G1.lo;
        q = num / den;
        xl[0] = X.lo, xl[1] = 0.0;
        xl = ((v2_exact_rem(num, q, den) + xl) - q * denl) / den;
        G2 = dd_make(q[0], xl[0]), G1 = dd_make(q[1], xl[1]);
    }
    /* The error of D reaches t through sqrt(D), at most |G2 n_i| rho / 2
       <= |G2| rho (rho = bound / D, |n_i| < 2): certified when below 2^-60. */
    if (!(bound * fabs(G2.hi) <= 0x1p-60 * D.hi)) return 2;
    p1 = v4_two_prod(v4splat(G1.hi), V), p2 = v4_two_prod(v4splat(G2.hi), N);
    sm = v4_two_sum(p1.hi, p2.hi);
    R = sm.hi + (v4splat(G1.lo) * V + (v4splat(G2.lo) * N + (sm.lo + (p1.lo + p2.lo))));
    *t = v3(R[0], R[1], R[2]);
    return 1;
}

/* The exponent fields of a vector's components (and of a pair of
   indices), as doubles: powers of two, 0 or +infinity, never NaN, so the
   maxima and compares below raise no exception. */
GG_INLINE gg_v4 v4_expo(gg_v4 r)
{
    return (gg_v4)((gg_v4u)r & v4bits(0x7ff0000000000000ull));
}
GG_INLINE double max3(gg_v4 e)
{
    double m = e[0] > e[1] ? e[0] : e[1];
    return m > e[2] ? m : e[2];
}
/* All four lanes of a comparison true. */
GG_INLINE int v4_all(gg_v4u m)
{
#if defined(GG_DD_FMA)
    return _mm256_movemask_pd((__m256d)m) == 15;
#else
    return (int)(m[0] & m[1] & m[2] & m[3] & 1);
#endif
}

/* v and n scaled so their largest components are in [1, 2) (as
   scale_unit), when those components are normal numbers below 2^1023;
   else 0 (zero, NaN, infinite, or extreme: the full path decides). */
GG_INLINE int load_units(const ggVec3 *a, const ggVec3 *b, gg_v4 *A, gg_v4 *B)
{
    const gg_v2 lo = {0x1p-1022, 0x1p-1022}, hi = {0x1p1022, 0x1p1022}, one = {1.0, 1.0};
    gg_v4 ra = {a->x, a->y, a->z, a->z}, rb = {b->x, b->y, b->z, b->z};
    gg_v2 m = {max3(v4_expo(ra)), max3(v4_expo(rb))}, sc;
    gg_v2u in = (gg_v2u)(m >= lo) & (gg_v2u)(m <= hi);
    if (!(in[0] & in[1])) return 0;
    sc = one / m;
    *A = ra * v4splat(sc[0]), *B = rb * v4splat(sc[1]);
    return 1;
}

/* The indices scaled by one power of two, the larger into [1, 2) (as
   refract_full does), when both are normal and their exponents at most
   201 apart; else 0. (2^-201 m may underflow to 0: hence the test of mn
   against 2^-1022 first.) */
GG_INLINE int scale_indices(double *ni, double *nt)
{
    gg_v4 x = {*ni, *nt, *nt, *nt}, e = v4_expo(x);
    double m = e[0] > e[1] ? e[0] : e[1], mn = e[0] > e[1] ? e[1] : e[0], sc;
    if (!(m <= 0x1p1022 && mn >= 0x1p-1022 && mn >= 0x1p-201 * m)) return 0;
    sc = 1.0 / m;
    *ni *= sc, *nt *= sc;
    return 1;
}

/* True if the scaling of a to [1, 2) (A = scale_unit(a)) rounded one of
   its components: only one more than 1022 binades below the largest,
   which became subnormal or zero, can have been (a scaled normal number
   is exact); that one is scaled back and compared. */
static GG_NOINLINE int scaling_rounded(const ggVec3 *a, const gg_v4 *A)
{
    double c[3];
    int i;
    c[0] = a->x, c[1] = a->y, c[2] = a->z;
    for (i = 0; i < 3; i++)
        if (fabs((*A)[i]) < 0x1p-1022 && c[i] != 0 &&
            dd_scale2((*A)[i], dd_expo(v3maxabs(*a))) != c[i])
            return 1;
    return 0;
}

/* A non-zero component of v or n that the scaling made subnormal or zero
   (so scaling_rounded may be true): one comparison of exponent fields. */
GG_INLINE int scaled_to_subnormal(const ggVec3 *v, gg_v4 V, const ggVec3 *n, gg_v4 N)
{
    const gg_v4 zero = {0, 0, 0, 0};
    gg_v4 rv = {v->x, v->y, v->z, v->z}, rn = {n->x, n->y, n->z, n->z};
    gg_v4u m = ((gg_v4u)(v4_expo(V) == zero) & (gg_v4u)(rv != zero)) |
               ((gg_v4u)(v4_expo(N) == zero) & (gg_v4u)(rn != zero));
    return (m[0] | m[1] | m[2]) != 0;
}

/* gg_optics_refract_big on the caller's doubles (v not in the surface). */
static GG_NOINLINE int refract_wide(const ggVec3 *vp, const ggVec3 *np, double ni, double nt,
                                    ggVec3 *t)
{
    double vc[3], nc[3], r[3];
    int s = dot_sign_wide(*vp, *np), rc;
    if (s == 0) {
        gg_dd vd[3];
        ggVec3 v = v3scale2(*vp, -dd_expo(v3maxabs(*vp)));
        vd[0] = dd_from(v.x), vd[1] = dd_from(v.y), vd[2] = dd_from(v.z);
        *t = dd_scale_vec(dd_rsqrt(dd_sum_sq3(v.x, v.y, v.z)), vd);
        return 0;
    }
    vc[0] = vp->x, vc[1] = vp->y, vc[2] = vp->z, nc[0] = np->x, nc[1] = np->y, nc[2] = np->z;
    rc = gg_optics_refract_big(vc, nc, ni, nt, s, r);
    *t = v3(r[0], r[1], r[2]);
    return rc;
}

/* Everything the fast path declines: validation, scaling, refract_dd. */
static GG_NOINLINE int refract_full(const ggVec3 *vp, const ggVec3 *np, double ni, double nt,
                                    ggVec3 *t)
{
    const uint64_t fin = 0x7ff0000000000000ull;
    uint64_t mv = max_bits(*vp), mn = max_bits(*np), bi = abs_bits(ni), bt = abs_bits(nt);
    uint64_t ei = bi >> 52, et = bt >> 52;
    int ediff = 0, same = ni == nt, rc;
    const double ni0 = ni, nt0 = nt;
    gg_v4 V, N;
    ggVec3 v, n;
    /* finite and non-zero: x - 1 wraps around for zero */
    if (mv - 1 >= fin - 1 || mn - 1 >= fin - 1 || bi - 1 >= fin - 1 || bt - 1 >= fin - 1) {
        *t = v3nan();
        return -1;
    }
    V = scale_unit(*vp, mv), N = scale_unit(*np, mn);
    /* Indices: one common power of two, unless their ratio is so extreme
       that the smaller would underflow; then each is scaled on its own and
       the ratio's exponent is carried by the tangential part (refract_dd). */
    if (ei >= 1 && ei <= 2045 && et >= 1 && et <= 2045 && ei <= et + 450) {
        double s = pow2_inv(ei > et ? ei : et);
        ni *= s, nt *= s;
    } else {
        int xi = dd_expo(ni), xt = dd_expo(nt), em = xi > xt ? xi : xt;
        if (xi - xt > 450) {
            /* such a ratio can make a component the scaling would round
               decisive: then the 512-bit path */
            if (scaled_to_subnormal(vp, V, np, N) &&
                (scaling_rounded(vp, &V) || scaling_rounded(np, &N)))
                return refract_wide(vp, np, ni, nt, t);
            ediff = xi - xt;
            ni = dd_scale2(ni, -xi), nt = dd_scale2(nt, -xt);
        } else {
            ni = dd_scale2(ni, -em), nt = dd_scale2(nt, -em);
        }
    }
    v = v3(V[0], V[1], V[2]), n = v3(N[0], N[1], N[2]);
    if (same) {
        /* t = v/|v| from the unflushed v, on whichever side v is */
        gg_dd vd[3];
        vd[0] = dd_from(v.x), vd[1] = dd_from(v.y), vd[2] = dd_from(v.z);
        *t = dd_scale_vec(dd_rsqrt(dd_sum_sq3(v.x, v.y, v.z)), vd);
        return dot_sign_wide(*vp, *np) != 0;
    }
    if (!ediff && fabs(ni) <= 0x1p400 * fabs(nt)) {
        /* eta * 2^-480 < 2^-80: the flush moves t by less than 2^-80 */
        v = v3(flush(v.x), flush(v.y), flush(v.z));
        n = v3(flush(n.x), flush(n.y), flush(n.z));
    }
    rc = refract_dd(v, n, ni, nt, ediff, vp, np, t);
    /* |eta| > 2^450 lets a ray through only for sin(theta_i) < 2^-446:
       components hundreds of binades apart, whose tangential part the
       double-double terms may carry to a few ulp only (v and n sharing a
       component near 2^-1000 and differing by an ulp in another: 4.8 ulp
       off). The 512-bit path answers those (its decision is this one
       outside the TIR band). */
    if (ediff && rc == 1) return refract_wide(vp, np, ni0, nt0, t);
    return rc;
}

/* The fast path for inputs that are not in the common ranges (the
   vectors' largest components or the indices outside [2^-100, 2^101)),
   then the full path. */
static GG_NOINLINE int refract_entry(const ggVec3 *vp, const ggVec3 *np, double ni, double nt,
                                     ggVec3 *t)
{
    gg_v4 V, N;
    double si = ni, st = nt;
    if (load_units(vp, np, &V, &N) && scale_indices(&si, &st)) {
        int rc = refract_fast(V, N, si, st, t);
        if (rc != 2) return rc;
    }
    return refract_full(vp, np, ni, nt, t);
}

/* The accurate refraction, ggRefract's contract (include/ggrt/optics.h):
   true when transmitted; *t (if t is not NULL) the transmitted or mirror
   direction, NaN for invalid input. The common case -- the largest
   components of v and n and both indices in [2^-100, 2^101) -- is checked
   with one comparison of four exponents and goes to the fast path with
   the indices as given. */
GG_INC_LINK bool GG_INC_NAME(refract)(ggVec3 v, ggVec3 n, double ni, double nt, ggVec3 *t)
{
    const gg_v4 lo = {0x1p-100, 0x1p-100, 0x1p-100, 0x1p-100};
    const gg_v4 hi = {0x1p100, 0x1p100, 0x1p100, 0x1p100};
    gg_v4 rv = {v.x, v.y, v.z, v.z}, rn = {n.x, n.y, n.z, n.z}, x = {ni, nt, ni, nt}, e;
    ggVec3 tmp;
    if (!t) t = &tmp;
    e = v4_expo(x);
    e[0] = max3(v4_expo(rv)), e[1] = max3(v4_expo(rn));
    if (v4_all((gg_v4u)(e >= lo) & (gg_v4u)(e <= hi))) {
        int rc = refract_fast(rv * v4splat(1.0 / e[0]), rn * v4splat(1.0 / e[1]), ni, nt, t);
        if (rc != 2) return rc == 1;
        return refract_full(&v, &n, ni, nt, t) == 1;
    }
    return refract_entry(&v, &n, ni, nt, t) == 1;
}
