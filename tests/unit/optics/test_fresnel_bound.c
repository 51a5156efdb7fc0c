/* SPDX-License-Identifier: MIT */
/*
** test_fresnel_bound.c -- ggFresnelConductor, ggFresnelConductorPolarized
** and ggFresnelDielectric within the 1-ulp bound optics.h states, against
** the 512-bit reference of ggFresnelConductorError and
** ggFresnelDielectricError (whose own correctness test_ulp_error.c checks
** against independent evaluations).
**
** The classes are those of `ggrt optics check --kind conductor`
** (docs/optics.md, "ggrt optics check") and the edges of the bound: indices
** equal to the last bit with a tiny k at grazing incidence (where the
** reflectance is a ratio of two tiny numbers), index ratios beyond 2^300
** either way, subnormal cosines, all indices scaled by 2^+-900, k = 0 (the
** dielectric). The unit is the reference's: 2^-53 times the smallest power
** of two at or above R. A reflectance below 2^-1022 is subnormal, and then
** only within 2^-1074 (optics.h).
*/
#include "testutil.h"

#include "core.h"

#include <fenv.h>
#include <float.h>
#include <math.h>
#include <stdio.h>

#define NCLASS 12
#define CASES  600

static const char *const class_name[NCLASS] = {
    "random",        "grazing",        "normal incidence", "metals",
    "tiny k",        "nearly matched", "matched, tiny c",  "tiny k near critical",
    "extreme ratio", "huge and tiny",  "subnormal cos",    "k = 0"};

static int irange(tu_rng *r, int lo, int hi)
{
    return lo + (int)(tu_next(r) % (uint64_t)(hi - lo + 1));
}

/* One conductor input of class cls: cosine c, outside n1, inside n + ik. */
static void make_case(int cls, tu_rng *r, double *c, double *n1, double *n, double *k)
{
    static const double metal[][2] = {{0.14, 3.70}, {0.06, 3.59}, {0.96, 6.69},
                                      {1.10, 2.58}, {2.90, 3.10}, {0.27, 2.78}};
    double s;
    *n1 = tu_range(r, 1, 1.6), *n = tu_range(r, 0.05, 3), *k = tu_range(r, 0, 8);
    *c = tu_uniform(r);
    switch (cls) {
    case 1:
        *c = ldexp(1.0, -irange(r, 1, 60));
        break;
    case 2:
        *c = 1 - irange(r, 0, 8) * 0x1p-53;
        break;
    case 3: {
        int m = irange(r, 0, 5);
        *n1 = 1, *n = metal[m][0], *k = metal[m][1];
        break;
    }
    case 4:
        *k = ldexp(1.0, -irange(r, 10, 60));
        break;
    case 5:
        *n = *n1 * (1 + irange(r, -64, 64) * 0x1p-52), *k = ldexp(*n1, -irange(r, 20, 70));
        if (irange(r, 0, 1)) *c = ldexp(1.0, -irange(r, 1, 40));
        break;
    case 6:
        /* a^2 = (n1 c)^2 and |(n + ik)^2 - n1^2| = 2 n1 k comparable, or not */
        *n = *n1, *c = ldexp(tu_range(r, 1, 2), -irange(r, 1, 500));
        *k = ldexp(*n1 * *c * *c, -irange(r, -20, 60));
        if (irange(r, 0, 2) == 0) /* |T| = 2 n1 k far below a^2: R near 2^-1000 */
            *c = ldexp(1.0, -irange(r, 1, 60)), *k = ldexp(*n1, -irange(r, 400, 640));
        if (*k == 0) *k = 0x1p-1074;
        break;
    case 7:
        if (*n > *n1) s = *n, *n = *n1, *n1 = s;
        s = *n / *n1 * (1 + (irange(r, 0, 1) ? 1 : -1) * ldexp(1.0, -irange(r, 10, 50)));
        *c = s >= 1 ? 0.5 : sqrt((1 - s) * (1 + s));
        *k = ldexp(1.0, -irange(r, 20, 60));
        break;
    case 8:
        s = ldexp(1.0, (irange(r, 0, 1) ? 1 : -1) * irange(r, 250, 1000));
        *n1 *= s;
        if (irange(r, 0, 2) == 1) *c = ldexp(tu_range(r, 1, 2), -irange(r, 1, 1000));
        if (irange(r, 0, 2) == 2) *c = 1 - irange(r, 0, 8) * 0x1p-53;
        break;
    case 9:
        make_case(irange(r, 0, 7), r, c, n1, n, k);
        s = ldexp(1.0, irange(r, -900, 900));
        *n1 *= s, *n *= s, *k *= s;
        break;
    case 10:
        *c = ldexp(tu_range(r, 1, 2), -irange(r, 1023, 1070));
        break;
    case 11:
        make_case(irange(r, 0, 9), r, c, n1, n, k);
        *k = 0;
        break;
    default:
        break;
    }
    if (*n == 0 && *k == 0) *k = 1;
}

/* The error of R in the reference's ulps, 0 for a subnormal R within
   2^-1074 (the most a subnormal double can carry). */
static double err_of(double got, const ggReflectanceError *e)
{
    if (fabs(e->exact) < 0x1p-1022 && fabs(got - e->exact) <= 0x1p-1074) return 0;
    return e->ulp;
}

static void test_conductor_bound(void **state)
{
    tu_rng rng = {20261202};
    int cls, i;
    double all = 0;
    (void)state;
    for (cls = 0; cls < NCLASS; cls++) {
        double worst = 0, wc = 0, wn1 = 0, wn = 0, wk = 0;
        for (i = 0; i < CASES; i++) {
            double c, n1, n, k, R, rs, rp, u;
            ggReflectanceError e;
            make_case(cls, &rng, &c, &n1, &n, &k);
            R = ggFresnelConductor(c, n1, n, k);
            assert_int_equal(ggFresnelConductorError(c, n1, n, k, R, &e), GG_OK);
            u = err_of(R, &e);
            if (!(u < worst)) worst = u, wc = c, wn1 = n1, wn = n, wk = k;
            ggFresnelConductorPolarized(c, n1, n, k, &rs, &rp);
            assert_true(rs >= 0 && rs <= 1 && rp >= 0 && rp <= 1);
            if (k == 0) {
                /* the dielectric's bits, and its own bound */
                assert_true(R == ggFresnelDielectric(c, n1, n));
                assert_int_equal(ggFresnelDielectricError(c, n1, n, R, &e), GG_OK);
                assert_true(err_of(R, &e) <= 1);
            }
        }
        print_message("  %-22s worst %.3f ulp at c=%a n1=%a n=%a k=%a\n", class_name[cls], worst,
                      wc, wn1, wn, wk);
        if (worst > all) all = worst;
    }
    assert_true(all <= 1.0);
}

/* The limits optics.h states: 1 at grazing incidence, the normal-incidence
   closed form, and an index ratio beyond the double range's square root. */
static void test_conductor_limits(void **state)
{
    ggReflectanceError e;
    int i;
    (void)state;
    assert_true(ggFresnelConductor(0, 1, 0.2, 3) == 1);
    assert_true(ggFresnelConductor(0, 1, 1, 0x1p-1074) == 1);
    /* n == n1, k = 2^-1074: R about (k / (2 n))^2, far below the doubles */
    assert_true(ggFresnelConductor(1, 1, 1, 0x1p-1074) == 0);
    /* |eta| = 2^-1000: R = 1 - 4 n/n1 (1 + ...) rounds to 1 */
    assert_true(ggFresnelConductor(1, 0x1p500, 0x1p-500, 0x1p-500) == 1);
    assert_int_equal(ggFresnelConductorError(0.5, 1, 0x1p1000, 0x1p999,
                                             ggFresnelConductor(0.5, 1, 0x1p1000, 0x1p999), &e),
                     GG_OK);
    assert_true(e.ulp <= 1);
    /* equal indices, k = 2^-590 n at c = 2^-42: R = 1.6 2^-1018, whose
       (n + ik)^2 - n1^2 squared would underflow */
    assert_int_equal(
        ggFresnelConductorError(0x1.bf9914b345f28p-42, 0x1.59df43839d174p+44, 0x1.59df43839d174p+44,
                                0x1.503ff43b18a66p-546,
                                ggFresnelConductor(0x1.bf9914b345f28p-42, 0x1.59df43839d174p+44,
                                                   0x1.59df43839d174p+44, 0x1.503ff43b18a66p-546),
                                &e),
        GG_OK);
    assert_true(e.exact > 0x1p-1022 && e.ulp <= 1);
    /* Normal incidence out of a far denser dielectric: R = 1 - 4 nt/ni (1 +
       ...) needs nt^2 cos_t^2 = nt^2 exactly, not as ni^2 c^2 - (ni^2 - nt^2). */
    for (i = 20; i <= 70; i++) {
        double ni = ldexp(1.3, i), R = ggFresnelDielectric(1, ni, 1.7);
        assert_int_equal(ggFresnelDielectricError(1, ni, 1.7, R, &e), GG_OK);
        assert_true(e.ulp <= 1);
        assert_true(ggFresnelConductor(1, ni, 1.7, 0) == R);
    }
}

/* No FE_INVALID, FE_DIVBYZERO or FE_OVERFLOW for finite arguments
   (optics.h), and R in [0, 1], at the corners of the range: every
   combination of extreme cosines, outside indices and n, k. */
static void test_no_fp_exceptions(void **state)
{
    static const double cs[] = {0x1p-1074, 0x1p-1060, 0x1p-600, 1e-300, 0.5, 1};
    static const double n1s[] = {0x1p-1074, 0x1p-1000, 1, 0x1p1000, DBL_MAX};
    static const double ns[] = {0, 0x1p-1074, 1e-300, 0.3, 1, 1e300, DBL_MAX};
    int a, b, i, j;
    (void)state;
    for (a = 0; a < 6; a++)
        for (b = 0; b < 5; b++)
            for (i = 0; i < 7; i++)
                for (j = 0; j < 7; j++) {
                    double R, rs, rp, D = 0;
                    if (ns[i] == 0 && ns[j] == 0) continue;
                    feclearexcept(FE_ALL_EXCEPT);
                    R = ggFresnelConductor(cs[a], n1s[b], ns[i], ns[j]);
                    ggFresnelConductorPolarized(cs[a], n1s[b], ns[i], ns[j], &rs, &rp);
                    if (ns[i] > 0) D = ggFresnelDielectric(cs[a], n1s[b], ns[i]);
                    if (fetestexcept(FE_INVALID | FE_DIVBYZERO | FE_OVERFLOW) ||
                        !(R >= 0 && R <= 1) || !(D >= 0 && D <= 1)) {
                        print_error("c=%a n1=%a n=%a k=%a: R %a, D %a, exceptions %#x\n", cs[a],
                                    n1s[b], ns[i], ns[j], R, D, fetestexcept(FE_ALL_EXCEPT));
                        fail();
                    }
                }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_conductor_bound),
        cmocka_unit_test(test_conductor_limits),
        cmocka_unit_test(test_no_fp_exceptions),
    };
    return cmocka_run_group_tests_name("fresnel_bound", tests, NULL, NULL);
}
