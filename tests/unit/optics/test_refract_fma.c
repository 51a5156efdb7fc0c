/* SPDX-License-Identifier: MIT */
/*
** test_refract_fma.c -- the fma build of the accurate refraction returns
** the same bits as the plain build (and so does the reflection) (TwoProd is exact either way), on
** ordinary, grazing, near-critical, eta ~ 1, exactly normal, extreme-scale
** and extreme-ratio inputs. The plain build is compiled into this test
** from the same source (refract.inc.h), so the two are compared directly.
** Skipped where the compiler or the CPU has no fma build.
*/
#include "testutil.h"

#include "refract_fma.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define GG_INC_NAME(f) f##_plain
#define GG_INC_LINK    static
#include "refract.inc.h"
#include "reflect.inc.h"

#if GG_ISA_X86
static ggVec3 V3(double x, double y, double z)
{
    ggVec3 v;
    v.x = x, v.y = y, v.z = z;
    return v;
}

static long ncase, ntrans;

static void same(ggVec3 v, ggVec3 n, double ni, double nt)
{
    ggVec3 a, b;
    int ra = refract_plain(v, n, ni, nt, &a), rb = gg_refract_fma(v, n, ni, nt, &b);
    ncase++;
    ntrans += ra == 1;
    if (ra != rb || memcmp(&a, &b, sizeof a) != 0) {
        print_error("v = (%a, %a, %a) n = (%a, %a, %a) ni = %a nt = %a: plain %d (%a %a %a), "
                    "fma %d (%a %a %a)\n",
                    v.x, v.y, v.z, n.x, n.y, n.z, ni, nt, ra, a.x, a.y, a.z, rb, b.x, b.y, b.z);
        fail();
    }
    a = reflect_plain(&v, &n), b = gg_reflect_fma(&v, &n);
    if (memcmp(&a, &b, sizeof a) != 0) {
        print_error("reflection of v = (%a, %a, %a) n = (%a, %a, %a): plain (%a %a %a), fma "
                    "(%a %a %a)\n",
                    v.x, v.y, v.z, n.x, n.y, n.z, a.x, a.y, a.z, b.x, b.y, b.z);
        fail();
    }
}

static void test_same_bits(void **state)
{
    tu_rng r = {2024};
    long i;
    (void)state;
    if (!(gg_cpu_features() & GG_CPU_FMA)) {
        print_message("CPU without fma: nothing to compare\n");
        skip();
    }
    for (i = 0; i < 200000; i++) {
        ggVec3 v = tu_unit(&r), n = tu_unit(&r);
        double ni = tu_range(&r, 0.5, 2.5), nt = tu_range(&r, 0.5, 2.5);
        int kind = (int)(i % 8);
        if (kind == 1) {
            /* grazing: v almost in the surface */
            double c = v.x * n.x + v.y * n.y + v.z * n.z, e = ldexp(1.0, -(int)(tu_next(&r) % 60));
            v = V3(v.x - c * n.x + e * n.x, v.y - c * n.y + e * n.y, v.z - c * n.z + e * n.z);
        } else if (kind == 2) {
            /* eta within a few ulp of 1 */
            nt = ni * (1 + ldexp((double)(int)(tu_next(&r) % 9) - 4, -52));
        } else if (kind == 3) {
            /* near the critical angle: sin(theta_i) ~ nt / ni */
            double s = nt / ni, c;
            if (s < 1) {
                ggVec3 t = tu_unit(&r);
                double tn = t.x * n.x + t.y * n.y + t.z * n.z, tl;
                t = V3(t.x - tn * n.x, t.y - tn * n.y, t.z - tn * n.z);
                tl = sqrt(t.x * t.x + t.y * t.y + t.z * t.z);
                c = sqrt(1 - s * s) * (1 + ldexp(tu_range(&r, -1, 1), -(int)(tu_next(&r) % 50)));
                v = V3(s * t.x / tl - c * n.x, s * t.y / tl - c * n.y, s * t.z / tl - c * n.z);
            }
        } else if (kind == 4) {
            /* exactly normal incidence, scaled */
            v = V3(-3 * n.x, -3 * n.y, -3 * n.z);
        } else if (kind == 5) {
            /* extreme scales of v, n and the indices */
            int ev = (int)(tu_next(&r) % 1200) - 600, en = (int)(tu_next(&r) % 1200) - 600;
            v = V3(ldexp(v.x, ev), ldexp(v.y, ev), ldexp(v.z, ev));
            n = V3(ldexp(n.x, en), ldexp(n.y, en), ldexp(n.z, en));
            ni = ldexp(ni, (int)(tu_next(&r) % 400) - 200);
            nt = ldexp(nt, (int)(tu_next(&r) % 400) - 200);
        } else if (kind == 6) {
            /* tiny components next to large ones */
            v.y = ldexp(v.y, -(int)(tu_next(&r) % 600));
            n.z = ldexp(n.z, -(int)(tu_next(&r) % 600));
        } else if (kind == 7) {
            /* negative indices, huge ratios */
            ni = -ni;
            if (i & 8) nt = ldexp(nt, -(int)(tu_next(&r) % 900));
        }
        same(v, n, ni, nt);
    }
    print_message("%ld cases (%ld transmitted): plain and fma builds agree bit for bit (refraction "
                  "and reflection)\n",
                  ncase, ntrans);
    assert_true(ntrans > ncase / 4);
}
#else
static void test_same_bits(void **state)
{
    (void)state;
    (void)refract_plain, (void)reflect_plain; /* compiled, nothing to compare them with */
    print_message("no fma build on this compiler/target\n");
    skip();
}
#endif

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_same_bits),
    };
    return cmocka_run_group_tests_name("refract_fma", tests, NULL, NULL);
}
