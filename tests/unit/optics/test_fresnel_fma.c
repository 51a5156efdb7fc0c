/* SPDX-License-Identifier: MIT */
/*
** test_fresnel_fma.c -- the fma build of the Fresnel reflectances
** (fresnel_fma.c) gives the same results as the plain build -- Rs, Rp and
** R = (Rs + Rp)/2 rounded as fresnel.c rounds them, bit for bit above
** 2^-960 and within 1 ulp below (the error terms of a double-word there
** fall below 2^-1022, where Veltkamp's product drops bits that the fma
** keeps) -- on
** ordinary, grazing, normal, nearly and exactly matched, tiny-k,
** extreme-ratio and extreme-scale inputs. The plain build is compiled into
** this test from the same source (fresnel.inc.h), so the two are compared
** directly. Skipped where the compiler or the CPU has no fma build.
*/
#include "testutil.h"

#include "fresnel_fma.h"

#include <math.h>
#include <string.h>

#define GG_INC_NAME(f) f##_plain
#define GG_INC_LINK    static
#include "fresnel.inc.h"

#if GG_ISA_X86
static int expo(tu_rng *r, int lo, int hi)
{
    return lo + (int)(tu_next(r) % (uint64_t)(hi - lo + 1));
}

static double pick_cos(tu_rng *r)
{
    switch (tu_next(r) % 5) {
    case 0:
        return ldexp(1.0, -expo(r, 1, 60));
    case 1:
        return 1 - expo(r, 0, 8) * 0x1p-53;
    case 2:
        return ldexp(tu_range(r, 1, 2), -expo(r, 1, 1073));
    default:
        return tu_uniform(r);
    }
}

/* What fresnel.c returns from Rs and Rp: the three doubles. */
static void rounded(gg_dd rs, gg_dd rp, double out[3])
{
    gg_dd r = dd_mul_d(dd_add(rs, rp), 0.5);
    out[0] = rs.hi, out[1] = rp.hi, out[2] = r.hi;
}

static void same(gg_dd ps, gg_dd pp, gg_dd fs, gg_dd fp, const char *what, double c, double n1,
                 double n, double k)
{
    double a[3], b[3];
    int i, ok = 1;
    rounded(ps, pp, a), rounded(fs, fp, b);
    for (i = 0; i < 3; i++)
        ok &= a[i] == b[i] || (fabs(a[i]) < 0x1p-960 && tu_ulps(a[i], b[i]) <= 1);
    if (!ok) {
        print_error("%s at c=%a n1=%a n=%a k=%a: plain Rs %a Rp %a R %a, fma Rs %a Rp %a R %a\n",
                    what, c, n1, n, k, a[0], a[1], a[2], b[0], b[1], b[2]);
        fail();
    }
}

static void test_same_bits(void **state)
{
    tu_rng rng = {31337};
    int i;
    (void)state;
    if (!(gg_cpu_features() & GG_CPU_FMA)) {
        print_message("no fma on this CPU: nothing to compare\n");
        skip();
    }
    for (i = 0; i < 40000; i++) {
        double c = pick_cos(&rng), n1 = tu_range(&rng, 1, 1.6), n = tu_range(&rng, 0.05, 3);
        double k = tu_range(&rng, 0, 8), s;
        gg_dd ps, pp, fs, fp;
        switch (i % 6) {
        case 0:
            n = n1 * (1 + expo(&rng, -64, 64) * 0x1p-52);
            break;
        case 1:
            n = n1;
            break;
        case 2:
            n1 = ldexp(n1, expo(&rng, -1000, 1000));
            break;
        default:
            break;
        }
        if (i % 5 == 0) k = 0;
        if (i % 5 == 1) k = ldexp(n1, -expo(&rng, 10, 1000));
        s = ldexp(1.0, expo(&rng, -900, 900));
        n1 *= s, n *= s, k *= s;
        if (!(n1 > 0) || !isfinite(n1) || !isfinite(n) || !isfinite(k) || (n == 0 && k == 0))
            continue;
        fresnel_conductor_plain(c, n1, n, k, &ps, &pp);
        gg_fresnel_conductor_fma(c, n1, n, k, &fs, &fp);
        same(ps, pp, fs, fp, "conductor", c, n1, n, k);
        if (n > 0) {
            fresnel_dielectric_plain(c, n1, n, &ps, &pp);
            gg_fresnel_dielectric_fma(c, n1, n, &fs, &fp);
            same(ps, pp, fs, fp, "dielectric", c, n1, n, 0);
        }
    }
}
#else
static void test_same_bits(void **state)
{
    (void)state;
    (void)fresnel_conductor_plain; /* compiled, nothing to compare it with */
    print_message("no fma build on this target\n");
    skip();
}
#endif

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_same_bits),
    };
    return cmocka_run_group_tests_name("fresnel_fma", tests, NULL, NULL);
}
