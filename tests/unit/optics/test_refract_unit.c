/* SPDX-License-Identifier: MIT */
/*
** test_refract_unit.c -- the renderer's refraction (lib/optics/refract_unit.h)
** against the exact ggRefract: the plain-double path it takes where the
** problem is well conditioned stays within its documented 2^-45, and
** every total-internal-reflection decision is ggRefract's.
*/
#include "testutil.h"

#include "refract_unit.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define BOUND 0x1p-45 /* lib/optics/refract_unit.h */

static ggVec3 V(double x, double y, double z)
{
    ggVec3 v;
    v.x = x, v.y = y, v.z = z;
    return v;
}
static double dot(ggVec3 a, ggVec3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
static ggVec3 unit(ggVec3 a)
{
    double l = sqrt(dot(a, a));
    return V(a.x / l, a.y / l, a.z / l);
}
static double maxdiff(ggVec3 a, ggVec3 b)
{
    double x = fabs(a.x - b.x), y = fabs(a.y - b.y), z = fabs(a.z - b.z);
    return x > y ? (x > z ? x : z) : (y > z ? y : z);
}

/* Unit direction towards the surface with unit normal n at incidence
   cosine c (rounded, as the renderer's directions are). */
static ggVec3 incoming(tu_rng *r, ggVec3 n, double c)
{
    ggVec3 a = tu_unit(r), u;
    double d = dot(a, n), s = sqrt((1 - c) * (1 + c));
    u = unit(V(a.x - d * n.x, a.y - d * n.y, a.z - d * n.z));
    return unit(V(-c * n.x + s * u.x, -c * n.y + s * u.y, -c * n.z + s * u.z));
}

/* Whether gg_refract_unit takes its plain-double path (its own test). */
static int fast_path(ggVec3 v, ggVec3 n, double ni, double nt)
{
    double c = fabs(dot(v, n)), eta = ni / nt;
    return eta > 0.5 && eta < 2 && c >= 0x1p-40 && eta * eta * ((1 - c) * (1 + c)) <= 1 - 0.0625;
}

/* Random unit inputs over the whole range of incidence, indices of real
   interfaces (air, water, glass, diamond, both ways) and random ones,
   and cosines crowded at the ends (grazing, normal) and around the
   critical angle. */
static void test_refract_unit_bound(void **state)
{
    static const double idx[] = {1.0, 1.0000001, 1.333, 1.5, 1.7, 2.42, 1.99, 0.51};
    tu_rng r = {20261122};
    double worst = 0;
    long fast = 0, exact = 0, tir = 0, i;
    (void)state;
    for (i = 0; i < 400000; i++) {
        ggVec3 n = tu_unit(&r), v, ta, tb;
        double ni, nt, c;
        bool oka, okb;
        int kind = (int)(i % 5);
        if (i % 2) {
            ni = idx[tu_next(&r) % 8], nt = idx[tu_next(&r) % 8];
        } else {
            ni = tu_range(&r, 1, 3), nt = tu_range(&r, 1, 3);
        }
        if (kind == 0)
            c = tu_uniform(&r);
        else if (kind == 1)
            c = ldexp(tu_uniform(&r), -(int)(tu_next(&r) % 50)); /* grazing */
        else if (kind == 2)
            c = 1 - ldexp(tu_uniform(&r), -(int)(tu_next(&r) % 50)); /* normal */
        else {
            /* around the critical angle (or an arbitrary one if none) */
            double e = ni / nt, cc = e > 1 ? sqrt(1 - 1 / (e * e)) : tu_uniform(&r);
            c = cc + tu_range(&r, -1, 1) * ldexp(1, -(int)(tu_next(&r) % 40));
            if (!(c > 0 && c <= 1)) c = cc;
        }
        v = incoming(&r, n, c);
        if (i % 3 == 0) n = V(-n.x, -n.y, -n.z); /* normal on the far side */
        oka = gg_refract_unit(v, n, ni, nt, &ta);
        okb = ggRefract(v, n, ni, nt, &tb);
        /* TIR decisions are ggRefract's, always. */
        assert_int_equal(oka, okb);
        if (!okb) {
            tir++;
            continue;
        }
        if (fast_path(v, n, ni, nt)) {
            double d = maxdiff(ta, tb);
            fast++;
            if (d > worst) worst = d;
            if (!(d <= BOUND)) {
                print_error("v (%a %a %a) n (%a %a %a) ni %a nt %a: off by %g > 2^-45\n", v.x, v.y,
                            v.z, n.x, n.y, n.z, ni, nt, d);
                fail();
            }
        } else {
            /* the exact path: ggRefract's bits */
            exact++;
            assert_memory_equal(&ta, &tb, sizeof ta);
        }
    }
    printf("refract_unit: %ld plain-double, %ld exact, %ld TIR; worst plain-double error %.3g "
           "(2^%.1f, bound 2^-45)\n",
           fast, exact, tir, worst, worst > 0 ? log2(worst) : -INFINITY);
    /* both paths and TIR must have been exercised for the above to mean anything */
    assert_true(fast > 100000 && exact > 10000 && tir > 10000);
}

/* Invalid input goes to ggRefract and gets its answers (NaN, or the
   mirror direction). */
static void test_refract_unit_invalid(void **state)
{
    static const double bad[][2] = {{0, 1}, {1, 0}, {-1.5, 1}, {1, -1.5}, {NAN, 1}, {1, INFINITY}};
    ggVec3 v = unit(V(1, -2, 0.5)), n = V(0, 1, 0), ta, tb;
    size_t i;
    (void)state;
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        bool oka = gg_refract_unit(v, n, bad[i][0], bad[i][1], &ta);
        bool okb = ggRefract(v, n, bad[i][0], bad[i][1], &tb);
        assert_int_equal(oka, okb);
        assert_memory_equal(&ta, &tb, sizeof ta);
    }
    {
        bool oka = gg_refract_unit(V(NAN, 0, 0), n, 1, 1.5, &ta);
        bool okb = ggRefract(V(NAN, 0, 0), n, 1, 1.5, &tb);
        assert_int_equal(oka, okb);
        assert_true(isnan(ta.x) && isnan(tb.x));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_refract_unit_bound),
        cmocka_unit_test(test_refract_unit_invalid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
