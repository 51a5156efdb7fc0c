/* SPDX-License-Identifier: MIT */
/*
** test_ulp_error.c -- ggRefractError, ggReflectionError and the Fresnel
** error functions against two evaluations independent of their 512-bit
** reference:
**  - exact rational arithmetic: inputs built from Pythagorean triples (and
**    small integers), whose exact refracted or reflected direction, or
**    reflectance, is a known fraction p/q; the error of a double x is then
**    |x q - p| / q, with x q - p formed exactly (an fma product and a
**    TwoSum, all in double);
**  - the 128-bit "long double-double" textbook evaluation of
**    tests/common/optics_ref.h, on random and hard inputs.
** Candidates are the library's own results and those results moved by
** known numbers of units.
*/
#include "testutil.h"

#include "core.h"
#include "vec.h"

#include "optics_ref.h"

#include <math.h>
#include <string.h>

static const int trip[][3] = {{3, 4, 5},    {5, 12, 13},  {8, 15, 17},    {7, 24, 25},
                              {20, 21, 29}, {9, 40, 41},  {12, 35, 37},   {11, 60, 61},
                              {28, 45, 53}, {33, 56, 65}, {119, 120, 169}};
#define NTRIP ((int)(sizeof trip / sizeof trip[0]))

/* |x - p/q| in units of 2^e (q > 0; p, q integers below 2^40, so x q is
   exact as a double-double). */
static double err_frac(double x, double p, double q, int e)
{
    double hi = x * q, lo = fma(x, q, -hi), s = hi - p, bb = s - hi;
    double t = (hi - (s - bb)) + (-p - bb); /* TwoSum(hi, -p) */
    return ldexp(fabs(s + (t + lo)) / q, -e);
}

/* The smallest e with |p| / q <= 2^e (q > 0, p != 0, integers < 2^50). */
static int ceil_expo(double p, double q)
{
    int e = 0;
    p = fabs(p);
    while (p > ldexp(q, e)) e++;
    while (e > -60 && p <= ldexp(q, e - 1)) e--;
    return e;
}

static void expect_close(double got, double want)
{
    double tol = 1e-9 * (want > 1 ? want : 1);
    if (!(fabs(got - want) <= tol)) {
        print_error("error measured %.17g, exact %.17g\n", got, want);
        fail();
    }
}

/* Candidate: c moved by k 2^-60 per component (exact in doubles < 2^-7). */
static ggVec3 nudge(ggVec3 c, int k)
{
    c.x += k * 0x1p-56, c.y -= 2 * k * 0x1p-56, c.z += 3 * k * 0x1p-56;
    return c;
}

/* One refraction with exact answer num[i]/den (unit vector): the library's
   result and nudged ones, measured both ways. */
static void check_refract_rational(ggVec3 v, ggVec3 n, double ni, double nt, const double num[3],
                                   double den, bool tir, double cos2_num, double cos2_den)
{
    ggDirectionError e;
    ggVec3 t;
    int k, i, ue;
    double big = 0;
    bool ok = ggRefract(v, n, ni, nt, &t);
    assert_int_equal(ok, !tir);
    for (i = 0; i < 3; i++)
        if (fabs(num[i]) > big) big = fabs(num[i]);
    ue = ceil_expo(big, den) - 53;
    for (k = -40; k <= 40; k += 8) {
        ggVec3 c = nudge(t, k);
        double cc[3], want = 0;
        cc[0] = c.x, cc[1] = c.y, cc[2] = c.z;
        assert_int_equal(ggRefractError(v, n, ni, nt, c, tir, &e), GG_OK);
        for (i = 0; i < 3; i++) {
            double d = err_frac(cc[i], num[i], den, ue);
            if (d > want) want = d;
        }
        expect_close(e.max_ulp, want);
        assert_true(e.unit == ldexp(1.0, ue));
        assert_int_equal(e.exact_tir, tir);
        assert_true(e.tir_agrees && e.certain && e.finite);
        /* The wrong decision is reported as such. */
        assert_int_equal(ggRefractError(v, n, ni, nt, c, !tir, &e), GG_OK);
        assert_false(e.tir_agrees);
    }
    assert_int_equal(ggRefractError(v, n, ni, nt, t, tir, &e), GG_OK);
    expect_close(e.cos2_t, cos2_num / cos2_den);
}

/* sin_i = a1/c1 (triple i), sin_t = a2/c2 (triple j), tangential direction
   (a', b')/c' (triple m): v = (a1 a', a1 b', -b1 c'), n = (0, 0, 1) times
   s, ni = a2 c1, nt = c2 a1, t = (a2 a'/(c2 c'), a2 b'/(c2 c'), -b2/c2). */
static void test_refract_rational(void **state)
{
    int i, j, m, f;
    (void)state;
    for (i = 0; i < NTRIP; i++)
        for (j = 0; j < NTRIP; j++)
            for (m = 0; m < 3; m++)
                for (f = 0; f < 4; f++) {
                    double a1 = trip[i][f & 1], b1 = trip[i][1 - (f & 1)], c1 = trip[i][2];
                    double a2 = trip[j][0], b2 = trip[j][1], c2 = trip[j][2];
                    double ap = trip[m][0], bp = trip[m][1], cp = trip[m][2], num[3];
                    double s = f & 2 ? -3 : 0.25;
                    ggVec3 v = {a1 * ap, a1 * bp, -b1 * cp}, n = {0, 0, s};
                    num[0] = a2 * ap, num[1] = a2 * bp, num[2] = -b2 * cp;
                    check_refract_rational(v, n, a2 * c1, c2 * a1, num, c2 * cp, false, b2 * b2,
                                           c2 * c2);
                    /* Negative index: the tangential part flips. */
                    num[0] = -num[0], num[1] = -num[1];
                    check_refract_rational(v, n, a2 * c1, -c2 * a1, num, c2 * cp, false, b2 * b2,
                                           c2 * c2);
                }
}

/* Exactly critical (ni = c1, nt = a1: t along the surface, cos2 = 0 with
   no rounding), and one ulp of ni either side; total internal reflection
   with the exact mirror direction (a1 a', a1 b', b1 c') / (c1 c'). */
static void test_refract_critical(void **state)
{
    int i, m;
    ggDirectionError e;
    (void)state;
    for (i = 0; i < NTRIP; i++)
        for (m = 0; m < 3; m++) {
            double a1 = trip[i][0], b1 = trip[i][1], c1 = trip[i][2];
            double ap = trip[m][0], bp = trip[m][1], cp = trip[m][2];
            ggVec3 v = {a1 * ap, a1 * bp, -b1 * cp}, n = {0, 0, 1}, t = {0, 0, 1};
            double num[3] = {ap, bp, 0}, mir[3] = {a1 * ap, a1 * bp, b1 * cp};
            check_refract_rational(v, n, c1, a1, num, cp, false, 0, 1);
            assert_int_equal(ggRefractError(v, n, c1, a1, v3(ap / cp, bp / cp, 0), false, &e),
                             GG_OK);
            assert_true(e.cos2_t == 0 && e.certain && e.exact_tir == 0);
            assert_true(fabs(e.critical_rad) < 1e-100);
            assert_int_equal(ggRefractError(v, n, nextafter(c1, 1e9), a1, t, true, &e), GG_OK);
            assert_true(e.cos2_t < 0 && e.certain && e.exact_tir == 1 && e.critical_rad > 0);
            assert_int_equal(ggRefractError(v, n, nextafter(c1, 0), a1, t, false, &e), GG_OK);
            assert_true(e.cos2_t > 0 && e.certain && e.exact_tir == 0 && e.critical_rad < 0);
            /* Well beyond: TIR, the mirror image. */
            check_refract_rational(v, n, 2 * c1, a1, mir, c1 * cp, true, -3, 1);
        }
}

/* Reflection of small integer vectors: r_i = (v_i n.n - 2 (v.n) n_i) / n.n. */
static void test_reflect_rational(void **state)
{
    tu_rng rng = {777};
    int it, i, k;
    (void)state;
    for (it = 0; it < 2000; it++) {
        double vc[3], nc[3], num[3], a = 0, nn = 0, big = 0;
        ggVec3 v, n, r;
        ggDirectionError e;
        int ue;
        for (i = 0; i < 3; i++) {
            vc[i] = (double)(tu_next(&rng) % 2001) - 1000;
            nc[i] = (double)(tu_next(&rng) % 201) - 100;
            a += vc[i] * nc[i], nn += nc[i] * nc[i];
        }
        if (nn == 0 || (vc[0] == 0 && vc[1] == 0 && vc[2] == 0)) continue;
        for (i = 0; i < 3; i++) {
            num[i] = vc[i] * nn - 2 * a * nc[i];
            if (fabs(num[i]) > big) big = fabs(num[i]);
        }
        ue = ceil_expo(big, nn) - 53;
        v = v3(vc[0], vc[1], vc[2]), n = v3(nc[0], nc[1], nc[2]);
        r = ggReflection(v, n);
        for (k = -3; k <= 3; k++) {
            ggVec3 c = v3(r.x + k * ldexp(1.0, ue + 2), r.y, r.z - k * ldexp(1.0, ue));
            double cc[3] = {c.x, c.y, c.z}, want = 0;
            assert_int_equal(ggReflectionError(v, n, c, &e), GG_OK);
            for (i = 0; i < 3; i++) {
                double d = err_frac(cc[i], num[i], nn, ue);
                if (d > want) want = d;
            }
            expect_close(e.max_ulp, want);
        }
    }
}

/* Against the long double-double textbook reference: the measured errors
   of ggRefract's and the textbook formula's results agree with the
   reference's to 2^-9 ulp (its own error is below 2^-11 ulp). */
static void compare_ldd(ggVec3 v, ggVec3 n, double ni, double nt, long *count)
{
    ref_result r;
    ggDirectionError e;
    ggVec3 t;
    bool ok;
    ref_refract(v, n, ni, nt, &r);
    if (!r.certain || r.tir == -1) return;
    ok = ggRefract(v, n, ni, nt, &t);
    assert_int_equal(ggRefractError(v, n, ni, nt, t, !ok, &e), GG_OK);
    assert_int_equal(e.exact_tir, r.tir);
    assert_true(e.tir_agrees == ((ok ? 0 : 1) == r.tir));
    if (!e.tir_agrees) return;
    if (!(fabs(e.max_ulp - err_ulps(t, r.t)) <= 0x1p-9)) {
        print_error("v=(%a,%a,%a) n=(%a,%a,%a) ni=%a nt=%a: %.6f vs %.6f\n", v.x, v.y, v.z, n.x,
                    n.y, n.z, ni, nt, e.max_ulp, err_ulps(t, r.t));
        fail();
    }
    /* A candidate a few units off. */
    t = nudge(t, 64);
    assert_int_equal(ggRefractError(v, n, ni, nt, t, !ok, &e), GG_OK);
    assert_true(fabs(e.max_ulp - err_ulps(t, r.t)) <= 0x1p-9);
    (*count)++;
}

static ggVec3 incoming(tu_rng *r, ggVec3 n, double c)
{
    ggVec3 a = tu_unit(r), u;
    double d = a.x * n.x + a.y * n.y + a.z * n.z, l, s = sqrt((1 - c) * (1 + c));
    u = v3(a.x - d * n.x, a.y - d * n.y, a.z - d * n.z);
    l = sqrt(u.x * u.x + u.y * u.y + u.z * u.z);
    return v3(-c * n.x + s * u.x / l, -c * n.y + s * u.y / l, -c * n.z + s * u.z / l);
}

static void test_refract_vs_ldd(void **state)
{
    tu_rng rng = {4242};
    long i, count = 0;
    (void)state;
    if (!ref_init()) {
        print_message("long double is not wider than double here: no reference\n");
        skip();
    }
    for (i = 0; i < 3000; i++) {
        ggVec3 n = tu_unit(&rng);
        double ni = tu_range(&rng, 1, 2.5), nt = tu_range(&rng, 1, 2.5), c, s;
        switch (i % 4) {
        case 0:
            c = tu_uniform(&rng);
            break;
        case 1:
            c = pow(2.0, -tu_range(&rng, 1, 50));
            break;
        case 2:
            nt = ni * (1 + tu_range(&rng, -1e-9, 1e-9)), c = tu_uniform(&rng);
            break;
        default:
            if (nt > ni) s = nt, nt = ni, ni = s;
            s = nt / ni * (1 + (i % 8 < 4 ? 1 : -1) * pow(2.0, -tu_range(&rng, 12, 40)));
            c = s >= 1 ? 0.5 : sqrt((1 - s) * (1 + s));
            break;
        }
        compare_ldd(incoming(&rng, n, c), n, ni, nt, &count);
    }
    assert_true(count > 2500);
}

/* Normal incidence: R = ((ni - nt)/(ni + nt))^2 and, for a conductor,
   ((n - n1)^2 + k^2) / ((n + n1)^2 + k^2), with integer indices. */
static void test_fresnel_rational(void **state)
{
    int ni, nt, k;
    ggReflectanceError e;
    (void)state;
    for (ni = 1; ni <= 9; ni++)
        for (nt = 1; nt <= 9; nt++) {
            double num = (ni - nt) * (ni - nt), den = (ni + nt) * (ni + nt);
            double r = ggFresnelDielectric(1, ni, nt);
            for (k = -2; k <= 2; k++) {
                double c = r + k * 0x1p-60, want;
                assert_int_equal(ggFresnelDielectricError(1, ni, -nt, c, &e), GG_OK);
                want = num == 0 ? (c == 0 ? 0 : HUGE_VAL)
                                : err_frac(c, num, den, ceil_expo(num, den) - 53);
                if (isinf(want))
                    assert_true(isinf(e.ulp));
                else
                    expect_close(e.ulp, want);
                expect_close(e.complement_ulp,
                             err_frac(c, num, den, ceil_expo(den - num, den) - 53));
            }
            for (k = 0; k <= 6; k++) {
                double num2 = (nt - ni) * (nt - ni) + k * k, den2 = (nt + ni) * (nt + ni) + k * k;
                double c = ggFresnelConductor(1, ni, nt, k);
                if (num2 == 0) continue;
                assert_int_equal(ggFresnelConductorError(-1, ni, nt, k, c, &e), GG_OK);
                expect_close(e.ulp, err_frac(c, num2, den2, ceil_expo(num2, den2) - 53));
            }
        }
}

/* The conductor's complex evaluation with k = 0 against the dielectric's
   conjugate form (two different formulas), and invalid arguments. */
static void test_fresnel_consistency(void **state)
{
    tu_rng rng = {99};
    ggReflectanceError d, c;
    ggDirectionError de;
    int i;
    (void)state;
    for (i = 0; i < 2000; i++) {
        double cs = tu_uniform(&rng), n1 = tu_range(&rng, 1, 2.5), n2 = tu_range(&rng, 1, 2.5);
        double cand = ggFresnelDielectric(cs, n1, n2);
        assert_int_equal(ggFresnelDielectricError(cs, n1, n2, cand, &d), GG_OK);
        assert_int_equal(ggFresnelConductorError(cs, n1, n2, 0, cand, &c), GG_OK);
        assert_true(fabs(d.exact - c.exact) <= 0x1p-60 * d.exact);
        assert_true(fabs(d.ulp - c.ulp) <= 1e-6);
    }
    assert_int_equal(ggFresnelDielectricError(NAN, 1, 1.5, 0, &d), GG_ERROR_INVALID);
    assert_int_equal(ggFresnelDielectricError(1, 0, 1.5, 0, &d), GG_ERROR_INVALID);
    assert_int_equal(ggFresnelConductorError(1, 1, -1, 1, 0, &c), GG_ERROR_INVALID);
    assert_int_equal(ggFresnelConductorError(1, 1, 0, 0, 0, &c), GG_ERROR_INVALID);
    assert_int_equal(ggFresnelConductorError(1, 1, 1, 1, 0, NULL), GG_ERROR_INVALID);
    assert_int_equal(ggRefractError(v3(0, 0, 0), v3(0, 0, 1), 1, 1.5, v3(0, 0, 1), 0, &de),
                     GG_ERROR_INVALID);
    assert_int_equal(ggRefractError(v3(0, 1, 0), v3(0, 0, 1), 1, 0, v3(0, 0, 1), 0, &de),
                     GG_ERROR_INVALID);
    assert_int_equal(ggReflectionError(v3(0, 1, 0), v3(0, 0, INFINITY), v3(0, 0, 1), &de),
                     GG_ERROR_INVALID);
    /* Tangent v: not transmitted, exact result v/|v|; non-finite candidate. */
    assert_int_equal(ggRefractError(v3(3, 4, 0), v3(0, 0, 1), 1, 1.5, v3(0.6, 0.8, 0), 1, &de),
                     GG_OK);
    assert_true(de.exact_tir == -1 && de.tir_agrees && de.max_ulp < 0.6);
    assert_int_equal(ggRefractError(v3(3, 4, -1), v3(0, 0, 1), 1, 1.5, v3(NAN, 0, 0), 0, &de),
                     GG_OK);
    assert_true(isinf(de.max_ulp) && !de.finite);
}

/* Conductor R in long double-double: the textbook complex evaluation
   Z = sqrt(X + iY) (half-angle forms), Rs = |a - Z|^2 / |a + Z|^2,
   Rp = |e c - n1 Z|^2 / |e c + n1 Z|^2 with a = n1 c, e = (n + ik)^2, except
   that X = (n^2 - n1^2) + n1^2 c^2 - k^2 is summed from exact products, so a
   tiny cosine keeps its a^2 (1 - c^2 would round to 1). Its cancellations
   (a - Z, e c - n1 Z) cost the bits R is below its terms: about 128 - 60
   on the inputs of test_conductor_vs_ldd. */
static ldd ldd_conductor(double c, double n1, double n, double k)
{
    ldd nn = two_prod(n, n), kk = two_prod(k, k), n12 = two_prod(n1, n1), a = two_prod(n1, c);
    ldd X = sub(add(sub(nn, n12), mul(n12, two_prod(c, c))), kk), Y = mul(L(2), two_prod(n, k));
    ldd m = sqrt_ldd(add(mul(X, X), mul(Y, Y))), za, zb, er, ei, qa, qb, d1, d2, s1, s2, rs, rp;
    if (sgn(X) >= 0) {
        za = sqrt_ldd(mul(L(0.5), add(m, X)));
        zb = za.hi > 0 ? dvd(Y, mul(L(2), za)) : L(0);
    } else {
        zb = sqrt_ldd(mul(L(0.5), sub(m, X)));
        za = dvd(Y, mul(L(2), zb));
    }
    d1 = sub(a, za), s1 = add(a, za);
    rs = dvd(add(mul(d1, d1), mul(zb, zb)), add(mul(s1, s1), mul(zb, zb)));
    er = mul(sub(nn, kk), L(c)), ei = mul(Y, L(c)), qa = mul(L(n1), za), qb = mul(L(n1), zb);
    d1 = sub(er, qa), d2 = sub(ei, qb), s1 = add(er, qa), s2 = add(ei, qb);
    rp = dvd(add(mul(d1, d1), mul(d2, d2)), add(mul(s1, s1), mul(s2, s2)));
    return mul(L(0.5), add(rs, rp));
}

/* |x - r| in units of 2^-53 times the smallest power of two >= r > 0. */
static double ldd_units(double x, ldd r)
{
    int e;
    ld f = frexpl(r.hi, &e);
    ldd d = sub(L(x), r);
    if (f == 0.5L && r.lo <= 0) e--;
    return (double)fabsl(ldexpl(d.hi + d.lo, 53 - e));
}

/* The conductor reference (and so ggrt optics check --kind conductor)
   against ldd_conductor: metals at every angle, random media, tiny k
   between nearly matched indices, equal indices with a tiny k at cosines
   down to 2^-500 (where a reference that forms 1 - c^2 loses everything),
   and index ratios of 2^+-200; the library's R and candidates moved by a
   few units. */
static void test_conductor_vs_ldd(void **state)
{
    static const double metal[][2] = {{0.14, 3.70}, {0.06, 3.59}, {0.96, 6.69}, {2.90, 3.10}};
    tu_rng rng = {777};
    int i, j;
    (void)state;
    if (!ref_init()) {
        print_message("long double is not wider than double here: no reference\n");
        skip();
    }
    for (i = 0; i < 1200; i++) {
        double c = tu_uniform(&rng), n1 = tu_range(&rng, 1, 1.6), n = tu_range(&rng, 0.05, 3);
        double k = tu_range(&rng, 0, 8), R;
        ggReflectanceError e;
        ldd ref;
        switch (i % 6) {
        case 0:
            n1 = 1, n = metal[i / 6 % 4][0], k = metal[i / 6 % 4][1];
            break;
        case 1:
            n = n1 * (1 + (double)(int)(tu_next(&rng) % 129 - 64) * 0x1p-52);
            k = ldexp(n1, -(int)(tu_next(&rng) % 30) - 10);
            break;
        case 2:
            n = n1, c = ldexp(tu_range(&rng, 1, 2), -(int)(tu_next(&rng) % 500) - 1);
            k = ldexp(n1 * c * c, -(int)(tu_next(&rng) % 40));
            break;
        case 3:
            n1 = ldexp(n1, tu_next(&rng) % 2 ? 200 : -200);
            break;
        case 4:
            c = ldexp(1.0, -(int)(tu_next(&rng) % 60) - 1);
            break;
        default:
            break;
        }
        R = ggFresnelConductor(c, n1, n, k);
        ref = ldd_conductor(c, n1, n, k);
        for (j = -3; j <= 5; j += 4) {
            int ex;
            double cand = R + j * ldexp(1.0, (frexp(R, &ex), ex - 53));
            assert_int_equal(ggFresnelConductorError(c, n1, n, k, cand, &e), GG_OK);
            if (!(fabs(e.ulp - ldd_units(cand, ref)) <= 0x1p-6)) {
                print_error("c=%a n1=%a n=%a k=%a cand=%a: %.17g ulp, long double-double %.17g\n",
                            c, n1, n, k, cand, e.ulp, ldd_units(cand, ref));
                fail();
            }
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_refract_rational), cmocka_unit_test(test_refract_critical),
        cmocka_unit_test(test_reflect_rational), cmocka_unit_test(test_refract_vs_ldd),
        cmocka_unit_test(test_fresnel_rational), cmocka_unit_test(test_fresnel_consistency),
        cmocka_unit_test(test_conductor_vs_ldd),
    };
    return cmocka_run_group_tests_name("ulp_error", tests, NULL, NULL);
}
