/* SPDX-License-Identifier: MIT */
/*
** test_optics.c -- properties of reflection, refraction, Fresnel and
** Beer-Lambert (docs/optics.md). Each test asserts a physical or
** documented property that a wrong formula would break.
*/
#include "testutil.h"

#include "core.h"

#include <float.h>
#include <fenv.h>
#include <math.h>
#include <string.h>

#include "optics_ref.h"

#define U 0x1p-53 /* the ulp unit of docs/optics.md */

static ggVec3 V(double x, double y, double z)
{
    ggVec3 v;
    v.x = x, v.y = y, v.z = z;
    return v;
}
static double dot(ggVec3 a, ggVec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static double len(ggVec3 a) { return sqrt(dot(a, a)); }
static ggVec3 scale(ggVec3 a, double s) { return V(a.x * s, a.y * s, a.z * s); }
static ggVec3 unit(ggVec3 a) { return scale(a, 1 / len(a)); }
static ggVec3 cross(ggVec3 a, ggVec3 b)
{
    return V(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static double maxdiff(ggVec3 a, ggVec3 b)
{
    double x = fabs(a.x - b.x), y = fabs(a.y - b.y), z = fabs(a.z - b.z);
    return x > y ? (x > z ? x : z) : (y > z ? y : z);
}
static int same_bits(ggVec3 a, ggVec3 b) { return memcmp(&a, &b, sizeof a) == 0; }

/* max |a_i - b_i| <= tol, printing both vectors (hex, to reproduce) if not */
#define assert_within(a, b, tol) tu_within((a), (b), (tol), #a, #b, __FILE__, __LINE__)
static void tu_within(ggVec3 a, ggVec3 b, double tol, const char *sa, const char *sb,
                      const char *file, int line)
{
    if (!(maxdiff(a, b) <= tol)) {
        print_error("%s = (%a, %a, %a)\n%s = (%a, %a, %a)\ndiffer by %.3g > %.3g\n", sa, a.x, a.y,
                    a.z, sb, b.x, b.y, b.z, maxdiff(a, b), tol);
        _fail(file, line);
    }
}

/* Direction towards the surface with normal n at incidence cosine c. */
static ggVec3 incoming(tu_rng *r, ggVec3 n, double c)
{
    ggVec3 a = tu_unit(r), u;
    double d = dot(a, n), s = sqrt((1 - c) * (1 + c));
    u = unit(V(a.x - d * n.x, a.y - d * n.y, a.z - d * n.z));
    return unit(V(-c * n.x + s * u.x, -c * n.y + s * u.y, -c * n.z + s * u.z));
}

/* ------------------------------------------------------------------ */
/* Reflection                                                          */
/* ------------------------------------------------------------------ */

static void test_reflect_length_and_twice(void **state)
{
    tu_rng r = {1};
    int i;
    (void)state;
    for (i = 0; i < 20000; i++) {
        ggVec3 v = scale(tu_unit(&r), tu_range(&r, 0.01, 100)), n = tu_unit(&r), r1, r2;
        if (i % 3 == 0) n = scale(n, tu_range(&r, 0.1, 10)); /* non-unit n is allowed */
        r1 = ggReflection(v, n);
        r2 = ggReflection(r1, n);
        /* |r| = |v| */
        assert_close(len(r1), len(v), 4 * U);
        /* the mirror image: same tangential part, opposite normal part */
        assert_close(dot(r1, n), -dot(v, n), 4 * U * len(v) * len(n));
        /* twice is the identity */
        assert_true(maxdiff(r2, v) <= 4 * U * len(v));
    }
    /* v = (1,-1,0) on the floor y = 0 bounces to (1,1,0), exactly. */
    {
        ggVec3 r1 = ggReflection(V(1, -1, 0), V(0, 1, 0));
        assert_true(same_bits(r1, V(1, 1, 0)));
        r1 = ggReflection(V(1, -1, 0), V(0, -7, 0));
        assert_true(same_bits(r1, V(1, 1, 0)));
    }
}

/* Inputs inside the unscaled fast path (components below 2^300, |v| and
   |n| above 2^-300) and outside it (scaled into [1, 2) first) give the
   same bits: scaling v by 2^a scales r by 2^a, scaling n changes nothing,
   while no product of components underflows (components here are at
   least 2^-20 of their vector's length). */
static void test_reflect_power_of_two_scaling(void **state)
{
    static const int ex[] = {-900, -601, -600, -302, -301, -300, -299, -298, -150, 0,
                             150,  298,  299,  300,  301,  302,  600,  601,  900};
    const int nex = (int)(sizeof ex / sizeof ex[0]);
    tu_rng r = {15};
    int i, a, b;
    (void)state;
    for (i = 0; i < 400; i++) {
        ggVec3 v = scale(tu_unit(&r), tu_range(&r, 0.5, 2)),
               n = scale(tu_unit(&r), tu_range(&r, 0.5, 2));
        ggVec3 r0;
        if (!(fabs(v.x) > 0x1p-20 && fabs(v.y) > 0x1p-20 && fabs(v.z) > 0x1p-20 &&
              fabs(n.x) > 0x1p-20 && fabs(n.y) > 0x1p-20 && fabs(n.z) > 0x1p-20))
            continue;
        r0 = ggReflection(v, n);
        for (a = 0; a < nex; a++)
            for (b = 0; b < nex; b++) {
                double sa = ldexp(1, ex[a]);
                ggVec3 r1 = ggReflection(scale(v, sa), scale(n, ldexp(1, ex[b])));
                assert_true(same_bits(r1, scale(r0, sa)));
            }
    }
}

static void test_reflect_invalid(void **state)
{
    ggVec3 r;
    (void)state;
    r = ggReflection(V(1, 0, 0), V(0, 0, 0));
    assert_true(isnan(r.x) && isnan(r.y) && isnan(r.z));
    r = ggReflection(V(NAN, 0, 0), V(0, 0, 1));
    assert_true(isnan(r.x) && isnan(r.y) && isnan(r.z));
    r = ggReflection(V(1, 0, 0), V(INFINITY, 0, 1));
    assert_true(isnan(r.x));
    r = ggReflection(V(0, 0, 0), V(0, 0, 1));
    assert_true(r.x == 0 && r.y == 0 && r.z == 0);
}

/* ------------------------------------------------------------------ */
/* Refraction                                                          */
/* ------------------------------------------------------------------ */

static void test_refract_matched_is_identity(void **state)
{
    tu_rng r = {2};
    int i;
    (void)state;
    for (i = 0; i < 20000; i++) {
        ggVec3 n = tu_unit(&r), v = incoming(&r, n, tu_uniform(&r) * (i % 2 ? 1 : 1e-9)), t;
        double idx = tu_range(&r, 1, 3) * (i % 5 == 0 ? -1 : 1);
        if (i % 4 == 0) n = scale(n, -1);
        assert_true(ggRefract(v, n, idx, idx, &t));
        /* t is v/|v| correctly rounded: within 0.5 ulp of it, and the
           test's unit() is within 1.5 ulp; v itself is unit within a few
           ulp only, as generated. */
        assert_within(t, unit(v), 2 * U);
        assert_within(t, v, 2 * U + fabs(len(v) - 1));
    }
    /* Exactly representable directions come back bit for bit, even at
       cos_i = 2^-60 where the textbook 1 - (1 - c^2) rounds to 0. */
    {
        ggVec3 t, v = V(1, -0x1p-60, 0), n = V(0, 1, 0);
        assert_true(ggRefract(V(0.6, -0.8, 0), V(0, 1, 0), 1.33, 1.33, &t));
        assert_true(same_bits(t, V(0.6, -0.8, 0)) || maxdiff(t, V(0.6, -0.8, 0)) <= U);
        assert_true(ggRefract(v, n, 1.5, 1.5, &t));
        assert_true(same_bits(t, v));
        assert_true(ggRefractTextbook(v, n, 1.5, 1.5, &t));
        assert_true(t.y == 0); /* the textbook formula loses the normal component */
    }
}

static void test_refract_normal_incidence(void **state)
{
    tu_rng r = {3};
    int i;
    (void)state;
    for (i = 0; i < 20000; i++) {
        ggVec3 n = tu_unit(&r), v = scale(n, i % 2 ? -1 : 1), t;
        double ni = tu_range(&r, 1, 3), nt = tu_range(&r, 1, 3) * (i % 3 == 0 ? -1 : 1);
        assert_true(ggRefract(v, n, ni, nt, &t));
        assert_true(maxdiff(t, v) <= 2 * U);
    }
    /* Axis-aligned: exact, for any indices including huge ratios. */
    {
        ggVec3 t;
        assert_true(ggRefract(V(0, 0, -1), V(0, 0, 1), 1, 1.5, &t));
        assert_true(same_bits(t, V(0, 0, -1)));
        assert_true(ggRefract(V(0, 0, -3), V(0, 0, 0.5), 2.4, -1, &t));
        assert_true(same_bits(t, V(0, 0, -1)));
        assert_true(ggRefract(V(0, 2, 0), V(0, 1, 0), 1e300, 1e-300, &t));
        assert_true(same_bits(t, V(0, 1, 0)));
    }
}

/* Snell's law as a residual, coplanarity, unit length, side. */
static void test_refract_snell_plane_side(void **state)
{
    tu_rng r = {4};
    int i, transmitted = 0;
    (void)state;
    for (i = 0; i < 50000; i++) {
        ggVec3 n = tu_unit(&r), v = incoming(&r, n, tu_uniform(&r)), t, w;
        double ni = tu_range(&r, 1, 2.5), nt = tu_range(&r, 1, 2.5), si, st;
        if (i % 2) n = scale(n, -1);
        if (!ggRefract(v, n, ni, nt, &t)) continue;
        transmitted++;
        assert_close(len(t), 1.0, 4 * U);
        w = cross(v, n);
        si = len(w) / len(v) / len(n);
        st = len(cross(t, n)) / len(n);
        /* ni sin_i = nt sin_t */
        assert_true(fabs(ni * si - nt * st) <= 8 * U * (ni + nt));
        /* t in the plane of v and n */
        assert_true(fabs(dot(t, w)) <= 8 * U * len(v) * len(n)); /* w's own error */
        /* t continues to the far side */
        assert_true(dot(t, n) * dot(v, n) >= 0);
    }
    assert_true(transmitted > 30000);
}

static void test_refract_back_returns_v(void **state)
{
    tu_rng r = {5};
    int i, checked = 0;
    (void)state;
    for (i = 0; i < 50000; i++) {
        ggVec3 n = tu_unit(&r), v = incoming(&r, n, tu_range(&r, 0.01, 1)), t, back;
        double ni = tu_range(&r, 1, 2.5), nt = tu_range(&r, 1, 2.5) * (i % 4 ? 1 : -1);
        double ct, ci = fabs(dot(v, n));
        if (!ggRefract(v, n, ni, nt, &t)) continue;
        ct = fabs(dot(t, n));
        if (ct < 0.01) continue; /* the inverse is ill-conditioned at grazing */
        assert_true(ggRefract(scale(t, -1), n, nt, ni, &back));
        /* 0.5 ulp in t (and in v's own length), amplified by at most about
           1/(cos_i cos_t) on the way back. */
        assert_within(back, scale(v, -1), 4 * U / (ct * ci) + fabs(len(v) - 1));
        checked++;
    }
    assert_true(checked > 30000);
}

static void test_refract_both_orientations(void **state)
{
    tu_rng r = {6};
    int i;
    (void)state;
    for (i = 0; i < 50000; i++) {
        ggVec3 n = scale(tu_unit(&r), tu_range(&r, 0.1, 3)), t1, t2;
        ggVec3 v = incoming(&r, unit(n), pow(tu_uniform(&r), 1 + i % 7));
        double ni = tu_range(&r, 0.5, 3), nt = tu_range(&r, 0.5, 3) * (i % 5 ? 1 : -1);
        bool a = ggRefract(v, n, ni, nt, &t1), b = ggRefract(v, scale(n, -1), ni, nt, &t2);
        assert_true(a == b);
        assert_true(same_bits(t1, t2));
        /* and powers of two in any argument change nothing either */
        b = ggRefract(scale(v, 0x1p-300), scale(n, 8), ni * 0x1p500, nt * 0x1p500, &t2);
        assert_true(a == b);
        assert_true(same_bits(t1, t2));
    }
}

/* TIR exactly beyond the critical angle: sin_i = 3/5 with ni/nt = 5/3 is
   exactly critical in exact arithmetic; one ulp either side decides. */
static void test_refract_tir_threshold(void **state)
{
    ggVec3 t;
    double below = nextafter(3.0, 0), above = nextafter(3.0, 4);
    (void)state;
    assert_true(ggRefract(V(3, -4, 0), V(0, 1, 0), 5, 3, &t));
    assert_true(same_bits(t, V(1, 0, 0))); /* along the surface */
    assert_true(ggRefract(V(below, -4, 0), V(0, 1, 0), 5, 3, &t));
    assert_true(t.y < 0 && t.y > -1e-7);
    assert_false(ggRefract(V(above, -4, 0), V(0, 1, 0), 5, 3, &t));
    /* The mirror direction. */
    assert_true(maxdiff(t, unit(V(above, 4, 0))) <= U);
    /* Same with the index perturbed instead of the direction. */
    assert_false(ggRefract(V(3, -4, 0), V(0, 1, 0), nextafter(5.0, 6), 3, &t));
    assert_true(ggRefract(V(3, -4, 0), V(0, 1, 0), 5, nextafter(3.0, 4), &t));
    /* The textbook formula gets it wrong: 0.6 and 0.8 are inexact. */
    {
        int i, wrong = 0;
        for (i = 1; i < 200; i++) {
            ggVec3 v = V(3 * i, -4 * i, 0);
            bool ok = ggRefractTextbook(unit(v), V(0, 1, 0), 5, 3, &t);
            assert_true(ggRefract(v, V(0, 1, 0), 5, 3, NULL));
            wrong += !ok;
        }
        print_message("textbook formula calls exactly critical rays TIR in %d of 199 cases\n",
                      wrong);
    }
    /* ggCriticalAngle agrees with the decision, either side of it. */
    {
        tu_rng r = {7};
        int i;
        for (i = 0; i < 10000; i++) {
            double ni = tu_range(&r, 1.01, 3), nt = tu_range(&r, 1, ni - 0.005);
            double tc = ggCriticalAngle(ni, nt), d = tu_range(&r, 1e-9, 0.1);
            ggVec3 n = V(0, 0, 1), v1 = V(sin(tc - d), 0, -cos(tc - d)),
                   v2 = V(sin(tc + d), 0, -cos(tc + d));
            assert_true(ggRefract(v1, n, ni, nt, NULL));
            assert_false(ggRefract(v2, n, ni, nt, NULL));
        }
        assert_close(ggCriticalAngle(1.5, 1.0), asin(1 / 1.5), 2 * U);
        assert_close(ggCriticalAngle(-1.5, 1.0), asin(1 / 1.5), 2 * U);
        assert_true(ggCriticalAngle(1.0, 1.5) == GG_PI / 2);
        assert_true(ggCriticalAngle(1.5, 1.5) == GG_PI / 2);
        assert_true(isnan(ggCriticalAngle(0, 1)) && isnan(ggCriticalAngle(1, NAN)));
        /* Near-equal indices: the angle is close to 90 degrees, and
           accurate (asin(1 - 1e-12) would lose half the digits). */
        {
            double ni = 1 + 1e-12, e = ni - 1; /* exact */
            /* cos(theta_c) = sqrt(2e + e^2)/(1 + e) */
            assert_close(ggCriticalAngle(ni, 1), GG_PI / 2 - asin(sqrt(2 * e + e * e) / ni),
                         4 * U);
        }
    }
}

/* ggCriticalAngle for |ni| a few ulps above |nt|, where the angle is
   within about 1e-7 rad of pi/2 and its cosine sqrt(ni^2 - nt^2)/ni comes
   from a difference of squares that cancels to the last bits: the header
   promises the result is "accurate also when nt is close to ni", which
   needs ni^2 - nt^2 formed without rounding, as (ni - nt)(ni + nt) is
   (Sterbenz). Checked against atan2 of the exact difference (the squares
   as exact long double-double pairs, tests/common/optics_ref.h), within
   2 ulps of the result, for nt over the whole double range (subnormal to
   2^1022), either sign, 1 to 16 ulps apart, and for ratios ni/nt up to
   2^900. Guards the (a - b)(a + b) of lib/optics/optics.c: a*a - b*b
   rounds both squares and is ~2e-9 rad off at ni = nt + 1 ulp. */
static void test_critical_angle_near_equal(void **state)
{
    tu_rng r = {17};
    int i;
    (void)state;
    if (!ref_init()) {
        print_message("long double is no wider than double here: skipped\n");
        skip();
    }
    for (i = 0; i < 40000; i++) {
        double nt, ni, got, want, ulp_w;
        ldd d;
        ld a, b;
        int k;
        if (i % 2 == 0) {
            /* ni 1..16 ulps above nt */
            nt = ldexp(1 + tu_uniform(&r), (int)(tu_uniform(&r) * 2097) - 1074);
            if (nt == 0) nt = 0x1p-1074;
            ni = nt;
            for (k = 1 + (int)(tu_uniform(&r) * 16); k > 0; k--) ni = nextafter(ni, INFINITY);
        } else {
            /* any ratio up to 2^900 (nt stays above 2^-1022) */
            ni = ldexp(1 + tu_uniform(&r), (int)(tu_uniform(&r) * 1100) - 120);
            nt = ni * ldexp(1 + tu_uniform(&r), -(int)(tu_uniform(&r) * 900) - 1);
        }
        if (i % 3 == 1) ni = -ni;
        if (i % 5 == 2) nt = -nt;
        a = fabsl((ld)ni), b = fabsl((ld)nt);
        d = sub(two_prod(a, a), two_prod(b, b)); /* a^2 - b^2, exact to 2^-120 */
        want = (double)atan2l(b, sqrtl(d.hi + d.lo));
        got = ggCriticalAngle(ni, nt);
        ulp_w = ldexp(1, ilogb(want) - 52);
        if (!(fabs(got - want) <= 2 * ulp_w)) {
            print_error("ggCriticalAngle(%a, %a) = %a, exact %a: %.3g ulp\n", ni, nt, got, want,
                        fabs(got - want) / ulp_w);
            fail();
        }
    }
    /* the audit's case: 1.333 and the next double above it */
    {
        double ni = nextafter(1.333, 2);
        ldd d = sub(two_prod(ni, ni), two_prod(1.333, 1.333));
        assert_close(ggCriticalAngle(ni, 1.333), (double)atan2l(1.333L, sqrtl(d.hi + d.lo)), 2 * U);
    }
}

/* A negative nt bends the ray to the same side of the normal. */
static void test_refract_negative_index(void **state)
{
    tu_rng r = {8};
    int i;
    (void)state;
    for (i = 0; i < 20000; i++) {
        ggVec3 n = tu_unit(&r), v = incoming(&r, n, tu_range(&r, 0.05, 1)), tp, tm, vt, tt;
        double ni = tu_range(&r, 1, 2), nt = tu_range(&r, ni, 3);
        assert_true(ggRefract(v, n, ni, nt, &tp));
        assert_true(ggRefract(v, n, ni, -nt, &tm));
        /* same normal component, opposite tangential component */
        assert_close(dot(tm, n), dot(tp, n), 4 * U);
        vt = V(v.x - dot(v, n) * n.x, v.y - dot(v, n) * n.y, v.z - dot(v, n) * n.z);
        tt = V(tm.x - dot(tm, n) * n.x, tm.y - dot(tm, n) * n.y, tm.z - dot(tm, n) * n.z);
        assert_true(dot(vt, tt) <= 0);
        assert_within(tt, scale(vt, -ni / nt / len(v)), 16 * U); /* the test's own vt, tt */
        /* both negative: an ordinary interface */
        assert_true(ggRefract(v, n, -ni, -nt, &tm));
        assert_true(same_bits(tm, tp));
    }
}

static void test_refract_invalid_and_tangent(void **state)
{
    ggVec3 t;
    const double bad[] = {0.0, NAN, INFINITY, -INFINITY};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        assert_false(ggRefract(V(0, 0, -1), V(0, 0, 1), bad[i], 1.5, &t));
        assert_true(isnan(t.x) && isnan(t.y) && isnan(t.z));
        assert_false(ggRefract(V(0, 0, -1), V(0, 0, 1), 1, bad[i], &t));
        assert_true(isnan(t.x));
        assert_false(ggRefract(V(bad[i], 0, -1), V(0, 0, 1), 1, 1.5, &t) && bad[i] != 0);
    }
    assert_false(ggRefract(V(0, 0, 0), V(0, 0, 1), 1, 1.5, &t));
    assert_true(isnan(t.x));
    assert_false(ggRefract(V(0, 0, -1), V(0, 0, 0), 1, 1.5, &t));
    assert_true(isnan(t.y));
    assert_true(ggRefract(V(0, 0, -1), V(0, 0, 1), 1, 1.5, NULL)); /* t may be NULL */
    assert_false(ggRefract(V(0.9, 0, -0.1), V(0, 0, 1), 1.5, 1, NULL));
    /* v exactly in the surface: does not cross; t = v/|v|. */
    assert_false(ggRefract(V(2, 0, 0), V(0, 0, 1), 1, 1.5, &t));
    assert_true(same_bits(t, V(1, 0, 0)));
    assert_false(ggRefract(V(1, 1, 0), V(1, -1, 0), 1, 1.5, &t));
    /* correctly rounded 1/sqrt(2) */
    assert_true(same_bits(t, V(0x1.6a09e667f3bcdp-1, 0x1.6a09e667f3bcdp-1, 0)));
    /* The exact sign of v.n decides the side, also when v.n is 2^-104 and
       the products in it are 1: (1+2^-52)^2 - (1+2^-51) 1 = 2^-104. */
    {
        double a = 1 + 0x1p-52, c = 1 + 0x1p-51;
        assert_true(ggRefract(V(a, c, 0), V(a, -1, 0), 1, 1.5, &t));
        assert_true(dot(t, V(a, -1, 0)) > 0.5); /* v.n > 0: t goes along n */
        assert_true(ggRefract(V(c, a, 0), V(1, -a, 0), 1, 1.5, &t));
        assert_true(dot(t, V(1, -a, 0)) < -0.5);
    }
}

/* Valid finite input never raises invalid, divide-by-zero or overflow. */
static void test_no_fp_exceptions(void **state)
{
    tu_rng r = {9};
    int i, raised = 0;
    const int bad = FE_INVALID | FE_DIVBYZERO | FE_OVERFLOW;
    (void)state;
    for (i = 0; i < 50000; i++) {
        /* Unit vectors first, then scaled over the whole exponent range;
           everything derived is computed before the flags are cleared. */
        ggVec3 nu = tu_unit(&r), vu = incoming(&r, nu, pow(tu_uniform(&r), 1 + i % 9)), t;
        ggVec3 n = scale(nu, ldexp(1, (int)(tu_next(&r) % 2000) - 1000));
        ggVec3 v = scale(vu, ldexp(tu_range(&r, 0.5, 1), (int)(tu_next(&r) % 2000) - 1000));
        double ni = ldexp(tu_range(&r, 0.5, 1), (int)(tu_next(&r) % 2100) - 1050);
        double nt = ldexp(tu_range(&r, 0.5, 1), (int)(tu_next(&r) % 2100) - 1050);
        double c = tu_uniform(&r), k = ldexp(tu_uniform(&r), (int)(tu_next(&r) % 200) - 100);
        double rs, rp, ct = c * 1e-300;
        if (i % 7 == 0) nt = ni * (1 + 0x1p-52);
        feclearexcept(FE_ALL_EXCEPT);
        (void)ggRefract(v, n, ni, nt, &t);
        (void)ggRefract(v, n, nt, ni, &t);
        (void)ggRefractTextbook(vu, nu, 1.0, 1.5, &t);
        (void)ggReflection(v, n);
        (void)ggFresnelDielectric(c, ni, nt);
        ggFresnelDielectricPolarized(ct, ni, nt, &rs, &rp);
        (void)ggFresnelConductor(c, ni, nt, k);
        (void)ggFresnelConductor(c, ni, k, nt);
        (void)ggFresnelConductor(ct, k, nt, ni);
        (void)ggFresnelSchlick(c, ni, nt);
        (void)ggCriticalAngle(ni, nt);
        (void)ggBeerLambert(k, ni, nt);
        (void)ggAbsorptionCoefficient(k, nt);
        if (fetestexcept(bad)) {
            if (raised++ < 5)
                print_error("FP exception %#x: v=(%a,%a,%a) n=(%a,%a,%a) ni=%a nt=%a c=%a k=%a\n",
                            fetestexcept(bad), v.x, v.y, v.z, n.x, n.y, n.z, ni, nt, c, k);
        }
    }
    /* Invalid finite input is quiet too. */
    feclearexcept(FE_ALL_EXCEPT);
    (void)ggRefract(V(0, 0, 0), V(0, 0, 1), 1, 1.5, NULL);
    (void)ggRefract(V(1, 0, 0), V(0, 0, 0), 0, 1.5, NULL);
    (void)ggFresnelDielectric(0.5, 0, 1);
    (void)ggBeerLambert(-1, 1, 1);
    if (fetestexcept(bad)) raised++;
    assert_int_equal(raised, 0);
}

/* ------------------------------------------------------------------ */
/* Fresnel                                                             */
/* ------------------------------------------------------------------ */

/* Transmittances from the transmission amplitude coefficients, computed
   here independently of the library (Hecht, Optics, 4.4):
     ts = 2 ni ci / (ni ci + nt ct),  tp = 2 ni ci / (nt ci + ni ct),
     T  = (nt ct) / (ni ci) t^2. */
static void transmittance(double ci, double ni, double nt, double *Ts, double *Tp)
{
    double st = ni / nt * sqrt(1 - ci * ci), ct = sqrt(1 - st * st);
    double ts = 2 * ni * ci / (ni * ci + nt * ct), tp = 2 * ni * ci / (nt * ci + ni * ct);
    *Ts = nt * ct / (ni * ci) * ts * ts;
    *Tp = nt * ct / (ni * ci) * tp * tp;
}

static void test_fresnel_dielectric(void **state)
{
    tu_rng r = {10};
    int i;
    (void)state;
    /* normal incidence */
    for (i = 0; i < 1000; i++) {
        double a = tu_range(&r, 1, 4), b = tu_range(&r, 1, 4), r0 = (a - b) / (a + b);
        assert_close(ggFresnelDielectric(1, a, b), r0 * r0, 4 * U);
        assert_close(ggFresnelDielectric(-1, a, b), r0 * r0, 4 * U);
    }
    assert_close(ggFresnelDielectric(1, 1, 1.5), 0.04, 4 * U);
    /* grazing and TIR: R = 1 */
    assert_true(ggFresnelDielectric(0, 1, 1.5) == 1);
    assert_true(ggFresnelDielectric(0, 1.5, 1) == 1);
    assert_true(ggFresnelDielectric(cos(0.8), 1.5, 1) == 1); /* 45.8 > 41.8 degrees */
    assert_true(ggFresnelDielectric(cos(0.7), 1.5, 1) < 1);
    /* matched */
    assert_true(ggFresnelDielectric(0.3, 1.33, 1.33) == 0);
    /* R + T = 1 per polarisation, and reciprocity */
    for (i = 0; i < 20000; i++) {
        double ni = tu_range(&r, 1, 3), nt = tu_range(&r, 1, 3), ci = tu_range(&r, 0.01, 1);
        double rs, rp, Ts, Tp, st, ct;
        ggFresnelDielectricPolarized(ci, ni, nt, &rs, &rp);
        assert_true(rs >= 0 && rs <= 1 && rp >= 0 && rp <= 1);
        st = ni / nt * sqrt(1 - ci * ci);
        if (st >= 0.999) continue; /* TIR or too close for the test's own formula */
        ct = sqrt(1 - st * st);
        transmittance(ci, ni, nt, &Ts, &Tp);
        /* the test's own ct has a relative error of about U/ct^2, which
           the reflectance inherits */
        assert_close(rs + Ts, 1.0, 64 * U / (ct * ct * ci));
        assert_close(rp + Tp, 1.0, 64 * U / (ct * ct * ci));
        /* the same interface seen from the other side, along the
           transmitted ray, reflects the same fraction */
        assert_close(ggFresnelDielectric(ct, nt, ni), 0.5 * (rs + rp), 64 * U / (ct * ct * ci));
        assert_close(ggFresnelDielectric(ci, ni, nt), 0.5 * (rs + rp), 2 * U);
    }
    /* Brewster: rp = 0 at tan(theta) = nt/ni */
    {
        double rs, rp;
        ggFresnelDielectricPolarized(cos(atan(1.5)), 1, 1.5, &rs, &rp);
        assert_true(rp < 1e-30 && rs > 0.1);
    }
    /* Nearly matched: R ~ (d/2)^2 keeps its relative accuracy. */
    {
        double d = 1e-10, want = (d / (2 + d)) * (d / (2 + d));
        assert_close(ggFresnelDielectric(1, 1, 1 + d) / want, 1.0, 1e-6);
    }
    /* Negative indices reflect as |n| */
    assert_true(ggFresnelDielectric(0.6, 1, -1.5) == ggFresnelDielectric(0.6, 1, 1.5));
    assert_true(ggFresnelDielectric(0.6, -1, -1) == 0); /* perfect lens, no reflection */
    /* Invalid */
    assert_true(isnan(ggFresnelDielectric(NAN, 1, 1.5)));
    assert_true(isnan(ggFresnelDielectric(0.5, 0, 1.5)));
    assert_true(isnan(ggFresnelDielectric(0.5, 1, INFINITY)));
    assert_true(ggFresnelDielectric(1.5, 1, 1.5) == ggFresnelDielectric(1, 1, 1.5));
}

static void test_fresnel_schlick(void **state)
{
    int i;
    (void)state;
    assert_close(ggFresnelSchlick(1, 1, 1.5), 0.04, 4 * U);
    assert_true(ggFresnelSchlick(0, 1, 1.5) == 1);
    assert_true(ggFresnelSchlick(cos(0.8), 1.5, 1) == 1);
    for (i = 0; i <= 100; i++) {
        double c = i / 100.0;
        /* air-glass: within 0.06 of the exact value everywhere */
        assert_true(fabs(ggFresnelSchlick(c, 1, 1.5) - ggFresnelDielectric(c, 1, 1.5)) < 0.06);
    }
    assert_true(isnan(ggFresnelSchlick(0.5, 0, 1)));
}

/* Johnson & Christy, Phys. Rev. B 6, 4370 (1972), Table 1, and Rakic,
   Appl. Opt. 34, 4755 (1995), as tabulated by refractiveindex.info. */
static void test_fresnel_conductor(void **state)
{
    static const struct {
        const char *name;
        double lambda_um, n, k, dn, dk; /* published, with half a unit in the last digit */
        double published_r, tol;        /* measured normal-incidence reflectance */
    } metal[] = {
        /* Gold at 659.5 nm (J&C): evaporated films reflect about 96%.
           Silver at 548.6 nm (J&C): about 98%. Aluminium at 563.6 nm
           (Rakic): about 91.5% (91.6% is the figure usually quoted at
           550 nm). Film preparation changes measured values by about a
           percent, hence the tolerance of 0.01. */
        {"gold", 0.6595, 0.14, 3.697, 0.005, 0.0005, 0.96, 0.01},
        {"silver", 0.5486, 0.06, 3.586, 0.005, 0.0005, 0.98, 0.01},
        {"aluminium", 0.56357, 1.0728, 6.7839, 0.00005, 0.00005, 0.916, 0.01},
    };
    size_t i;
    tu_rng r = {11};
    int j;
    (void)state;
    for (i = 0; i < sizeof metal / sizeof metal[0]; i++) {
        double n = metal[i].n, k = metal[i].k, R = ggFresnelConductor(1, 1, n, k);
        /* the closed form at normal incidence, evaluated here */
        double closed = ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
        /* how much R moves within the rounding of the published n, k */
        double sens = fabs(ggFresnelConductor(1, 1, n + metal[i].dn, k) - R) +
                      fabs(ggFresnelConductor(1, 1, n, k + metal[i].dk) - R);
        print_message("%-9s %.4f um  n=%g k=%g  R=%.5f (closed form %.5f, published %.3f)\n",
                      metal[i].name, metal[i].lambda_um, n, k, R, closed, metal[i].published_r);
        assert_close(R, closed, 8 * U);
        assert_true(fabs(R - metal[i].published_r) <= metal[i].tol + sens);
        /* polarisations agree at normal incidence, and R rises to 1 at
           grazing after a dip in Rp (the pseudo-Brewster angle) */
        {
            double rs, rp, rpmin = 1;
            ggFresnelConductorPolarized(1, 1, n, k, &rs, &rp);
            assert_close(rs, rp, 8 * U);
            assert_true(ggFresnelConductor(0, 1, n, k) == 1);
            for (j = 1; j < 1000; j++) {
                ggFresnelConductorPolarized(j / 1000.0, 1, n, k, &rs, &rp);
                assert_true(rs >= rp - 1e-15 && rs <= 1 && rp >= 0);
                if (rp < rpmin) rpmin = rp;
            }
            assert_true(rpmin < R - 0.01);
        }
    }
    /* k = 0: the dielectric result, through the complex arithmetic */
    for (j = 0; j < 20000; j++) {
        double n1 = tu_range(&r, 1, 2), n = tu_range(&r, 0.2, 4), c = tu_uniform(&r);
        double rs1, rp1, rs2, rp2;
        ggFresnelDielectricPolarized(c, n1, n, &rs1, &rp1);
        ggFresnelConductorPolarized(c, n1, n, 0, &rs2, &rp2);
        assert_true(fabs(rs1 - rs2) <= 1e-14 && fabs(rp1 - rp2) <= 1e-14);
        /* a tiny k is a small perturbation (away from the critical angle,
           where absorption rounds off the corner of R at 1) */
        if (n > n1)
            assert_true(fabs(ggFresnelConductor(c, n1, n, 1e-9) - ggFresnelDielectric(c, n1, n)) <
                        1e-7);
    }
    /* the ratio is what matters */
    assert_close(ggFresnelConductor(0.5, 1.33, 0.2, 3), ggFresnelConductor(0.5, 1, 0.2 / 1.33,
                                                                            3 / 1.33),
                 1e-15);
    /* invalid */
    assert_true(isnan(ggFresnelConductor(0.5, 1, -0.1, 3)));
    assert_true(isnan(ggFresnelConductor(0.5, 1, 0.1, -3)));
    assert_true(isnan(ggFresnelConductor(0.5, 1, 0, 0)));
    assert_true(isnan(ggFresnelConductor(0.5, 0, 1, 1)));
    assert_true(isnan(ggFresnelConductor(NAN, 1, 1, 1)));
    /* extreme: a perfect conductor reflects everything at normal incidence */
    assert_true(ggFresnelConductor(1, 1, 1e300, 1e300) == 1);
}

/* ------------------------------------------------------------------ */
/* Beer-Lambert                                                        */
/* ------------------------------------------------------------------ */

static void test_beer_lambert(void **state)
{
    tu_rng r = {12};
    int i;
    (void)state;
    for (i = 0; i < 10000; i++) {
        double k = ldexp(tu_uniform(&r), -(int)(tu_next(&r) % 30)), lambda = tu_range(&r, 0.3, 1);
        double d1 = tu_range(&r, 0, 3), d2 = tu_range(&r, 0, 3);
        double t1 = ggBeerLambert(k, lambda, d1), t2 = ggBeerLambert(k, lambda, d2);
        /* composes over distances */
        assert_close(ggBeerLambert(k, lambda, d1 + d2), t1 * t2, 8 * U);
        /* alpha = 4 pi k / lambda */
        assert_close(ggBeerLambert(k, lambda, d1), exp(-4 * GG_PI * k / lambda * d1), 8 * U);
        assert_close(ggAbsorptionCoefficient(k, lambda), 4 * GG_PI * k / lambda, 4 * U);
        assert_true(t1 >= 0 && t1 <= 1);
        /* k = 0 and d = 0 give exactly 1 */
        assert_true(ggBeerLambert(0, lambda, d1) == 1.0);
        assert_true(ggBeerLambert(k, lambda, 0) == 1.0);
    }
    /* water (Pope and Fry 1997): 0.34 per metre at 650 nm */
    {
        double k = 0.34 * 650e-9 / (4 * GG_PI);
        assert_close(ggBeerLambert(k, 650e-9, 1.0), exp(-0.34), 4 * U);
    }
    assert_true(ggBeerLambert(0, 1, INFINITY) == 1.0);
    assert_true(ggBeerLambert(1e-9, 1, INFINITY) == 0.0);
    assert_true(ggBeerLambert(1, 1e-300, 1e300) == 0.0);
    assert_true(isnan(ggBeerLambert(-1, 1, 1)));
    assert_true(isnan(ggBeerLambert(1, 0, 1)));
    assert_true(isnan(ggBeerLambert(1, 1, -1)));
    assert_true(isnan(ggBeerLambert(NAN, 1, 1)));
    assert_true(isnan(ggAbsorptionCoefficient(1, -1)));
    assert_true(isinf(ggAbsorptionCoefficient(1e300, 1e-300)));
    /* Near overflow, against long double (whose exponent does not
       overflow here): finite wherever 4 pi k / lambda is below DBL_MAX
       (an audit found +inf for k = 2^1019, lambda = 1), +inf beyond. */
    for (i = 0; i < 20000; i++) {
        int e = 1010 + (int)(tu_next(&r) % 16), el = -(int)(tu_next(&r) % 40);
        double k = ldexp(tu_range(&r, 1, 2), e + el < 1023 ? e + el : 1023);
        double lambda = ldexp(tu_range(&r, 1, 2), el), a = ggAbsorptionCoefficient(k, lambda);
        long double x = 4 * (long double)GG_PI * ((long double)k / lambda);
        if (x < (long double)DBL_MAX * (1 - 0x1p-50))
            assert_true(isfinite(a) && fabsl(a - x) <= 4 * U * x);
        else if (x > (long double)DBL_MAX * (1 + 0x1p-50))
            assert_true(isinf(a));
    }
    {
        ggColor k = {1e-7, 0, -1}, l = {1, 1, 1}, t = ggBeerLambertColor(k, l, 1);
        assert_true(t.r < 1 && t.g == 1 && isnan(t.b));
    }
}

/* The textbook formula is a valid refraction on benign input. */
static void test_textbook_agrees_on_benign_input(void **state)
{
    tu_rng r = {13};
    int i;
    (void)state;
    for (i = 0; i < 10000; i++) {
        ggVec3 n = tu_unit(&r), v = incoming(&r, n, tu_range(&r, 0.2, 1)), t1, t2;
        double ni = tu_range(&r, 1, 1.2), nt = tu_range(&r, 1.3, 2.5);
        assert_true(ggRefract(v, n, ni, nt, &t1));
        assert_true(ggRefractTextbook(v, n, ni, nt, &t2));
        assert_true(maxdiff(t1, t2) < 1e-13);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reflect_length_and_twice),
        cmocka_unit_test(test_reflect_power_of_two_scaling),
        cmocka_unit_test(test_reflect_invalid),
        cmocka_unit_test(test_refract_matched_is_identity),
        cmocka_unit_test(test_refract_normal_incidence),
        cmocka_unit_test(test_refract_snell_plane_side),
        cmocka_unit_test(test_refract_back_returns_v),
        cmocka_unit_test(test_refract_both_orientations),
        cmocka_unit_test(test_refract_tir_threshold),
        cmocka_unit_test(test_critical_angle_near_equal),
        cmocka_unit_test(test_refract_negative_index),
        cmocka_unit_test(test_refract_invalid_and_tangent),
        cmocka_unit_test(test_no_fp_exceptions),
        cmocka_unit_test(test_fresnel_dielectric),
        cmocka_unit_test(test_fresnel_schlick),
        cmocka_unit_test(test_fresnel_conductor),
        cmocka_unit_test(test_beer_lambert),
        cmocka_unit_test(test_textbook_agrees_on_benign_input),
    };
    return cmocka_run_group_tests_name("optics", tests, NULL, NULL);
}
