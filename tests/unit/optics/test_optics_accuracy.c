/* SPDX-License-Identifier: MIT */
/*
** test_optics_accuracy.c -- ggRefract, ggReflection and the Fresnel
** reflectance against a higher-precision evaluation, on the inputs where
** the textbook formulas fail: grazing incidence, eta close to 1, angles
** within a few ulp of the critical angle, normal incidence, negative
** indices, non-unit vectors.
**
** The reference (tests/common/optics_ref.h) evaluates the textbook formulas in
** about 128-bit arithmetic ("long double-double"), far more precisely
** than the bounds checked, and independently of the library's formulas.
**
** Error unit: an "ulp" is 2^-53, the spacing of doubles in [0.5, 1), in
** which the largest component of a unit vector lies. The error of a
** direction is the largest absolute error of its components in that unit
** (max-norm). The bound asserted here is the one stated in docs/optics.md.
*/
#include "testutil.h"

#include "core.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* The bounds docs/optics.md states. */
#define BOUND_REFRACT  1.0 /* ggRefract, transmitted or mirror direction, units of 2^-53 */
#define BOUND_NEARCRIT 4.0 /* the same when cos(theta_t) < 2^-40 */
#define BOUND_REFLECT  1.0 /* ggReflection, in ulps of |v| */
#define BOUND_FRESNEL  1.0 /* ggFresnelDielectric, in ulps of R itself */

#include "optics_ref.h"

/* The kernels themselves, to test the fast path's certificate on its own. */
#define GG_INC_NAME(f) f##_plain
#define GG_INC_LINK    static
#include "refract.inc.h"
#include "reflect.inc.h"

/* check_case's reference: the textbook one of optics_ref.h, or ref_wide
   (below) for index ratios beyond 2^40. */
static int use_wide_ref;
static void ref_wide(ggVec3 v, ggVec3 n, double ni, double nt, ref_result *r);

/* ------------------------------------------------------------------ */
/* Statistics per category                                             */
/* ------------------------------------------------------------------ */

typedef struct stat {
    const char *name;
    long count, undecided, nearcrit, over;
    double worst_general, worst_nearcrit;
    long tir_wrong, tir_wrong_textbook, tir_band;
    double worst, worst_textbook;
    ggVec3 wv, wn; /* the worst input */
    double wni, wnt;
} stat;

static stat overall;

static stat mkstat(const char *name)
{
    stat s;
    memset(&s, 0, sizeof s);
    s.name = name;
    return s;
}

static void check_case(stat *st, ggVec3 v, ggVec3 n, double ni, double nt)
{
    ref_result r;
    ggVec3 t, tb, vu, nu;
    bool ok, okb;
    double e, eb, lv, ln;
    if (use_wide_ref)
        ref_wide(v, n, ni, nt, &r);
    else
        ref_refract(v, n, ni, nt, &r);
    ok = ggRefract(v, n, ni, nt, &t);
    /* The textbook formula wants unit vectors: give it the best doubles. */
    lv = sqrt(v.x * v.x + v.y * v.y + v.z * v.z), ln = sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
    vu.x = v.x / lv, vu.y = v.y / lv, vu.z = v.z / lv;
    nu.x = n.x / ln, nu.y = n.y / ln, nu.z = n.z / ln;
    okb = ggRefractTextbook(vu, nu, ni, nt, &tb);
    st->count++;
    if (r.tir == -1) {
        /* Exactly tangent: documented as not crossing, t = v/|v|. */
        assert_false(ok);
    } else if (!r.certain) {
        st->undecided++;
        if ((ok ? 0 : 1) != r.tir) return; /* either answer is right */
    } else {
        if ((okb ? 0 : 1) != r.tir) st->tir_wrong_textbook++;
        if ((ok ? 0 : 1) != r.tir) {
            /* docs/optics.md: exact unless |cos^2 theta_t| < 2^-96 */
            if (fabsl(r.cos2) < 0x1p-96L) {
                st->tir_band++;
            } else {
                st->tir_wrong++;
                print_error("%s: TIR decision wrong for v=(%a,%a,%a) n=(%a,%a,%a) ni=%a nt=%a\n",
                            st->name, v.x, v.y, v.z, n.x, n.y, n.z, ni, nt);
            }
            return;
        }
    }
    e = err_ulps(t, r.t);
    if (!(e <= st->worst)) {
        st->worst = e, st->wv = v, st->wn = n, st->wni = ni, st->wnt = nt;
    }
    /* The bound: 1 ulp, or 4 when the transmitted ray is within 2^-40 rad
       of the surface (only inputs within about 2^-80 of the critical
       angle get there). */
    {
        double bound = r.tir == 0 && r.cos2 < 0x1p-80L ? BOUND_NEARCRIT : BOUND_REFRACT;
        if (!(e <= bound)) {
            st->over++;
            print_error("%s: error %.3f ulp > bound %.1f at v=(%a,%a,%a) n=(%a,%a,%a) ni=%a "
                        "nt=%a\n",
                        st->name, e, bound, v.x, v.y, v.z, n.x, n.y, n.z, ni, nt);
        }
        if (r.tir == 0 && r.cos2 < 0x1p-80L) {
            st->nearcrit++;
            if (e > st->worst_nearcrit) st->worst_nearcrit = e;
        } else if (e > st->worst_general) {
            st->worst_general = e;
        }
    }
    if ((okb ? 0 : 1) == (ok ? 0 : 1)) {
        eb = err_ulps(tb, r.t);
        if (!(eb <= st->worst_textbook)) st->worst_textbook = eb;
    }
}

static void report(stat *st)
{
    print_message("  %-21s %6ld cases  worst %5.3f ulp (%5.3f where cos_t < 2^-40, %ld cases)  "
                  "TIR wrong %ld (+%ld in the 2^-96 band)  textbook: worst %9.3g ulp, TIR wrong "
                  "%ld\n",
                  st->name, st->count, st->worst_general, st->worst_nearcrit, st->nearcrit,
                  st->tir_wrong, st->tir_band, st->worst_textbook, st->tir_wrong_textbook);
    if (!(st->worst <= overall.worst)) {
        overall.worst = st->worst, overall.wv = st->wv, overall.wn = st->wn;
        overall.wni = st->wni, overall.wnt = st->wnt, overall.name = st->name;
    }
    overall.count += st->count;
    if (st->worst_textbook > overall.worst_textbook) overall.worst_textbook = st->worst_textbook;
    assert_int_equal(st->tir_wrong, 0);
    assert_int_equal(st->over, 0);
}

/* ------------------------------------------------------------------ */
/* Input generators                                                    */
/* ------------------------------------------------------------------ */

/* A unit vector orthogonal to unit n. */
static ggVec3 ortho(tu_rng *r, ggVec3 n)
{
    ggVec3 a = tu_unit(r), b;
    double d = a.x * n.x + a.y * n.y + a.z * n.z, l;
    b.x = a.x - d * n.x, b.y = a.y - d * n.y, b.z = a.z - d * n.z;
    l = sqrt(b.x * b.x + b.y * b.y + b.z * b.z);
    b.x /= l, b.y /= l, b.z /= l;
    return b;
}

/* Direction travelling towards a surface with normal n (or -n, at
   random) at incidence cosine c: -c n' + sqrt(1 - c^2) u. */
static ggVec3 incoming(tu_rng *r, ggVec3 n, double c)
{
    ggVec3 u = ortho(r, n), v;
    double s = sqrt((1 - c) * (1 + c)), sign = (tu_next(r) & 1) ? 1 : -1;
    v.x = -sign * c * n.x + s * u.x;
    v.y = -sign * c * n.y + s * u.y;
    v.z = -sign * c * n.z + s * u.z;
    return v;
}

static double rand_index(tu_rng *r)
{
    return tu_range(r, 1.0, 2.5);
}

/* Optionally flip index signs (metamaterials) and scale the vectors by
   non-powers of two (only directions matter). */
static void perturb(tu_rng *r, ggVec3 *v, ggVec3 *n, double *ni, double *nt)
{
    uint64_t b = tu_next(r);
    if ((b & 7) == 0) *nt = -*nt;
    if ((b & 0x38) == 0) *ni = -*ni, *nt = -*nt;
    if ((b & 0x1c0) == 0) {
        double s = tu_range(r, 0.1, 10.0);
        v->x *= s, v->y *= s, v->z *= s;
    }
    if ((b & 0xe00) == 0) {
        double s = tu_range(r, 0.1, 10.0);
        n->x *= s, n->y *= s, n->z *= s;
    }
}

static void test_refract_accuracy(void **state)
{
    tu_rng rng = {12345};
    stat random = mkstat("random"), grazing = mkstat("grazing"), matched = mkstat("eta near 1"),
         critical = mkstat("near critical"), exactcrit = mkstat("exactly critical"),
         normal = mkstat("normal incidence"), negative = mkstat("negative index"),
         nearcrit = mkstat("2^-100 from critical");
    long i;
    int j;
    (void)state;
    if (!ref_init()) {
        print_message("long double is not wider than double here: no reference\n");
        skip();
    }

    for (i = 0; i < 40000; i++) {
        ggVec3 n = tu_unit(&rng), v = incoming(&rng, n, tu_uniform(&rng));
        double ni = rand_index(&rng), nt = rand_index(&rng);
        perturb(&rng, &v, &n, &ni, &nt);
        check_case(&random, v, n, ni, nt);
    }
    /* Grazing: cos_i = 10^-1 ... 10^-17, and eta from 1/2.5 to 2.5,
       including exactly 1 and 1 +- a few ulp. */
    for (i = 0; i < 20000; i++) {
        ggVec3 n = tu_unit(&rng);
        double c = pow(10.0, -tu_range(&rng, 1, 17)), ni = rand_index(&rng), nt;
        ggVec3 v = incoming(&rng, n, c);
        switch (i % 4) {
        case 0: nt = ni; break;
        case 1: nt = ni * (1 + (double)(tu_next(&rng) % 9 - 4) * 0x1p-52); break;
        case 2: nt = ni * (1 + tu_range(&rng, -1e-8, 1e-8)); break;
        default: nt = rand_index(&rng); break;
        }
        perturb(&rng, &v, &n, &ni, &nt);
        check_case(&grazing, v, n, ni, nt);
    }
    /* Index-matched or nearly: eta = 1 + k 2^-52 ... 1 +- 1e-6, any angle. */
    for (i = 0; i < 20000; i++) {
        ggVec3 n = tu_unit(&rng), v = incoming(&rng, n, tu_uniform(&rng));
        double ni = rand_index(&rng), nt;
        if (i % 2)
            nt = ni * (1 + (double)((int)(tu_next(&rng) % 65) - 32) * 0x1p-53);
        else
            nt = ni * (1 + tu_range(&rng, -1e-6, 1e-6));
        perturb(&rng, &v, &n, &ni, &nt);
        check_case(&matched, v, n, ni, nt);
    }
    /* Near critical: sin_i = (nt/ni)(1 + d), d from +-2^-52 to +-1e-3. */
    for (i = 0; i < 40000; i++) {
        ggVec3 n = tu_unit(&rng);
        double ni = rand_index(&rng), nt = tu_range(&rng, 1.0, ni), d, s, c;
        ggVec3 v;
        if (nt >= ni) nt = 1.0, ni = 1.5;
        d = (i % 2 ? 1 : -1) * pow(2.0, -tu_range(&rng, 10, 54));
        s = nt / ni * (1 + d);
        if (s > 1) s = 1;
        c = sqrt((1 - s) * (1 + s));
        v = incoming(&rng, n, c);
        perturb(&rng, &v, &n, &ni, &nt);
        check_case(&critical, v, n, ni, nt);
    }
    /* Exactly critical, in exact arithmetic: Pythagorean triples,
       sin_i = p/q exactly, ni/nt = q/p, and 1-ulp perturbations of each
       input, in every axis permutation and scale. */
    {
        static const int trip[][3] = {{3, 4, 5}, {5, 12, 13}, {8, 15, 17}, {7, 24, 25},
                                      {20, 21, 29}, {119, 120, 169}, {696, 697, 985}};
        for (i = 0; i < (long)(sizeof trip / sizeof trip[0]); i++) {
            for (j = 0; j < 64; j++) {
                double p = trip[i][j & 1], q = trip[i][1 - (j & 1)], h = trip[i][2];
                double comp[3], nrm[3], ni = h, nt = p, sc = ldexp(1.0, (j % 7) - 3);
                ggVec3 v, n;
                int ax = j % 3, ay = (j + 1) % 3, az = (j + 2) % 3;
                comp[ax] = p * sc, comp[ay] = -q * sc, comp[az] = 0;
                nrm[0] = nrm[1] = nrm[2] = 0, nrm[ay] = (j & 8) ? 1 : -1;
                if ((j >> 4) == 1) comp[ax] = nextafter(comp[ax], 0);
                if ((j >> 4) == 2) comp[ax] = nextafter(comp[ax], 1e9);
                if ((j >> 4) == 3) nt = nextafter(nt, 1e9);
                v.x = comp[0], v.y = comp[1], v.z = comp[2];
                n.x = nrm[0], n.y = nrm[1], n.z = nrm[2];
                check_case(&exactcrit, v, n, ni, nt);
                check_case(&exactcrit, v, n, -ni, -nt);
            }
        }
    }
    /* Within 2^-100 of the critical angle: integer triples (p, q, h) with
       p^2 + q^2 - h^2 = +-1, found by walks of Berggren's matrices (which
       preserve x^2 + y^2 - z^2) from (1, 0, 0) and (0, 0, 1). With
       v = (p, -q, 0), n = (0, 1, 0), ni = h, nt = p, cos^2(theta_t) =
       1 - (h/p)^2 p^2/(p^2+q^2) = +-1/(p^2+q^2): as close to the critical
       angle as double inputs can be, on either side. */
    for (i = 0; i < 4000; i++) {
        double x = (i % 2) ? 1 : 0, y = 0, z = (i % 2) ? 0 : 1, nx, ny, nz;
        int steps = 0;
        while (z < 0x1p40 || (i % 3 == 0 && z < 0x1p50)) {
            /* Mostly B keeps p and q of similar size (eta near sqrt 2). */
            int m = (int)(tu_next(&rng) % 8);
            double sa = m == 0 ? -1 : 1, sb = m == 1 ? -1 : 1;
            nx = sa * x + 2 * sb * y + 2 * z;
            ny = 2 * sa * x + sb * y + 2 * z;
            nz = 2 * sa * x + 2 * sb * y + 3 * z;
            x = fabs(nx), y = fabs(ny), z = nz;
            if (++steps > 200) break;
        }
        if (x == 0 || y == 0 || x * 4 < z) continue; /* keep eta = h/p <= 4 */
        {
            ggVec3 v, n = {0, 1, 0};
            double ni = z, nt = x;
            v.x = x, v.y = -y, v.z = 0;
            if (i & 4) n.y = -1;
            if (i & 8) ni = -ni, nt = -nt;
            check_case(&nearcrit, v, n, ni, nt);
        }
    }
    /* Normal and near-normal incidence (cos_i = 1 - 10^-k). */
    for (i = 0; i < 10000; i++) {
        ggVec3 n = tu_unit(&rng), v;
        double ni = rand_index(&rng), nt = rand_index(&rng), s = (i % 2) ? 1 : -1;
        if (i % 3 == 0) {
            v.x = s * n.x, v.y = s * n.y, v.z = s * n.z;
        } else {
            v = incoming(&rng, n, 1 - pow(10.0, -tu_range(&rng, 1, 17)));
        }
        perturb(&rng, &v, &n, &ni, &nt);
        check_case(&normal, v, n, ni, nt);
    }
    /* Negative nt (metamaterial), any angle. */
    for (i = 0; i < 10000; i++) {
        ggVec3 n = tu_unit(&rng), v = incoming(&rng, n, tu_uniform(&rng));
        check_case(&negative, v, n, rand_index(&rng), -rand_index(&rng));
    }

    print_message("ggRefract against a 128-bit reference (error in units of 2^-53; bound %.0f, "
                  "%.0f where cos_t < 2^-40):\n",
                  BOUND_REFRACT, BOUND_NEARCRIT);
    report(&random);
    report(&grazing);
    report(&matched);
    report(&critical);
    report(&exactcrit);
    report(&nearcrit);
    report(&normal);
    report(&negative);
    print_message("  worst case over %ld inputs: %.3f ulp in '%s' at\n"
                  "    v=(%a, %a, %a) n=(%a, %a, %a) ni=%a nt=%a\n"
                  "  textbook formula worst: %.4g ulp\n",
                  overall.count, overall.worst, overall.name, overall.wv.x,
                  overall.wv.y, overall.wv.z, overall.wn.x, overall.wn.y, overall.wn.z,
                  overall.wni, overall.wnt, overall.worst_textbook);
    /* The test must be able to tell the formulas apart: the textbook one
       fails the bound by orders of magnitude on these inputs. */
    assert_true(overall.worst_textbook > 1000 * BOUND_REFRACT);
}

/* ggReflection: r = v - 2 (v.n)/(n.n) n, error relative to |v|. */
static void test_reflect_accuracy(void **state)
{
    tu_rng rng = {777};
    long i;
    double worst = 0;
    ggVec3 wv = {0, 0, 0}, wn = {0, 0, 0};
    (void)state;
    if (!ref_init()) {
        print_message("long double is not wider than double here: no reference\n");
        skip();
    }
    for (i = 0; i < 100000; i++) {
        ggVec3 n = tu_unit(&rng), v, r;
        ldd vc[3], nc[3], a = L(0), nn = L(0), k, ref[3];
        double lv, e;
        int j;
        /* all angles, with grazing and normal incidence overrepresented */
        double c = i % 3 == 0 ? pow(10.0, -tu_range(&rng, 0, 17)) : tu_uniform(&rng);
        if (i % 3 == 1) c = 1 - pow(10.0, -tu_range(&rng, 1, 17));
        v = incoming(&rng, n, c);
        {
            double sv = tu_range(&rng, 0.1, 10), sn = tu_range(&rng, 0.1, 10);
            /* a quarter over the whole exponent range (short of subnormal
               results), across the bounds of the unscaled fast path */
            if (i % 4 == 3) {
                sv = ldexp(sv, (int)(tu_next(&rng) % 2001) - 1000);
                sn = ldexp(sn, (int)(tu_next(&rng) % 2001) - 1000);
            }
            v.x *= sv, v.y *= sv, v.z *= sv, n.x *= sn, n.y *= sn, n.z *= sn;
        }
        r = ggReflection(v, n);
        vc[0] = L(v.x), vc[1] = L(v.y), vc[2] = L(v.z);
        nc[0] = L(n.x), nc[1] = L(n.y), nc[2] = L(n.z);
        for (j = 0; j < 3; j++) a = add(a, mul(vc[j], nc[j])), nn = add(nn, mul(nc[j], nc[j]));
        k = dvd(add(a, a), nn);
        for (j = 0; j < 3; j++) ref[j] = sub(vc[j], mul(k, nc[j]));
        /* in ulps of |v|: a correctly rounded component is within 0.5 */
        lv = ldexp(1.0, ilogbl(sqrtl((ld)v.x * v.x + (ld)v.y * v.y + (ld)v.z * v.z)) + 1);
        e = err_ulps(r, ref) / lv;
        if (e > worst) worst = e, wv = v, wn = n;
    }
    print_message("ggReflection: worst %.3f ulp(|v|) over 100000 inputs (bound %.1f) at\n"
                  "    v=(%a, %a, %a) n=(%a, %a, %a)\n",
                  worst, BOUND_REFLECT, wv.x, wv.y, wv.z, wn.x, wn.y, wn.z);
    assert_true(worst <= BOUND_REFLECT);
}

/* The dielectric Fresnel reflectance, from the amplitude coefficients in
   their textbook form, in 128-bit arithmetic. */
static ld ref_fresnel(double c, double ni, double nt)
{
    ldd a = L(fabs(ni)), b = L(fabs(nt)), C = L(fabs(c)), eta = dvd(a, b), k, ct, rs, rp;
    k = sub(L(1), mul(mul(eta, eta), mul(sub(L(1), C), add(L(1), C))));
    if (k.hi <= 0) return 1;
    ct = sqrt_ldd(k);
    rs = dvd(sub(mul(a, C), mul(b, ct)), add(mul(a, C), mul(b, ct)));
    rp = dvd(sub(mul(b, C), mul(a, ct)), add(mul(b, C), mul(a, ct)));
    rs = add(mul(rs, rs), mul(rp, rp));
    return (rs.hi + rs.lo) / 2;
}

static void test_fresnel_accuracy(void **state)
{
    tu_rng rng = {4242};
    long i;
    double worst = 0, wc = 0, wni = 0, wnt = 0, worst_textbook = 0;
    (void)state;
    if (!ref_init()) {
        print_message("long double is not wider than double here: no reference\n");
        skip();
    }
    for (i = 0; i < 100000; i++) {
        double ni = tu_range(&rng, 1, 3), nt = tu_range(&rng, 1, 3), c = tu_uniform(&rng), R;
        ld ref, ulp;
        double e;
        switch (i % 5) {
        case 0: c = pow(10.0, -tu_range(&rng, 0, 17)); break;       /* grazing */
        case 1: nt = ni * (1 + tu_range(&rng, -1e-6, 1e-6)); break; /* nearly matched */
        case 2: nt = ni * (1 + (double)((int)(tu_next(&rng) % 17) - 8) * 0x1p-52); break;
        case 3: /* near the critical angle */
            if (nt > ni) {
                double x = ni;
                ni = nt, nt = x;
            }
            c = sqrt(1 - (nt / ni) * (nt / ni)) * (1 + tu_range(&rng, -1e-6, 1e-6));
            if (c > 1) c = 1;
            break;
        default: break;
        }
        R = ggFresnelDielectric(c, ni, nt);
        ref = ref_fresnel(c, ni, nt);
        if (ref == 0) {
            assert_true(R == 0);
            continue;
        }
        ulp = ldexpl(1.0L, ilogbl(ref) - 52);
        e = (double)(fabsl((ld)R - ref) / ulp);
        if (e > worst) worst = e, wc = c, wni = ni, wnt = nt;
        /* the plain formula, for comparison */
        {
            double st2 = (ni / nt) * (ni / nt) * (1 - c * c), ct, rs, rp, Rt;
            if (st2 < 1) {
                ct = sqrt(1 - st2);
                rs = (ni * c - nt * ct) / (ni * c + nt * ct);
                rp = (nt * c - ni * ct) / (nt * c + ni * ct);
                Rt = 0.5 * (rs * rs + rp * rp);
                e = (double)(fabsl((ld)Rt - ref) / ulp);
                if (e > worst_textbook) worst_textbook = e;
            }
        }
    }
    print_message("ggFresnelDielectric: worst %.3f ulp of R over 100000 inputs (bound %.1f; the "
                  "textbook formula: %.3g ulp) at\n    cos_i=%a ni=%a nt=%a\n",
                  worst, BOUND_FRESNEL, worst_textbook, wc, wni, wnt);
    assert_true(worst <= BOUND_FRESNEL);
}

/* ------------------------------------------------------------------ */
/* Every eta: a reference without cancellation at any index ratio      */
/* ------------------------------------------------------------------ */

/* The textbook reference above cancels eta v against eta c N: its error
   grows like eta 2^-128, too much beyond eta = 2^40. This one builds the
   tangential part from cross products, vt = n x (v x n) / |n|^2 (each
   component from exact products, 128-bit relative), and
   cos^2(theta_t) = 1 - eta^2 |v x n|^2 / (|v|^2 |n|^2), so its error stays
   near 2^-127 of |t| for every eta the doubles allow. */
static void ref_wide(ggVec3 v, ggVec3 n, double ni, double nt, ref_result *r)
{
    ldd vc[3] = {L(v.x), L(v.y), L(v.z)}, nc[3] = {L(n.x), L(n.y), L(n.z)}, w[3], vt[3];
    ldd vv = L(0), nn = L(0), a = L(0), ww = L(0), lv, ln, eta, k;
    int i, s;
    for (i = 0; i < 3; i++) {
        vv = add(vv, mul(vc[i], vc[i])), nn = add(nn, mul(nc[i], nc[i]));
        a = add(a, mul(vc[i], nc[i]));
    }
    for (i = 0; i < 3; i++) {
        int j = (i + 1) % 3, l = (i + 2) % 3;
        w[i] = sub(mul(vc[j], nc[l]), mul(vc[l], nc[j]));
        ww = add(ww, mul(w[i], w[i]));
    }
    for (i = 0; i < 3; i++) {
        int j = (i + 1) % 3, l = (i + 2) % 3;
        vt[i] = dvd(sub(mul(nc[j], w[l]), mul(nc[l], w[j])), nn);
    }
    lv = sqrt_ldd(vv), ln = sqrt_ldd(nn);
    s = sgn(a);
    if (s == 0) {
        r->tir = -1, r->certain = 1, r->cos2 = 0;
        for (i = 0; i < 3; i++) r->t[i] = dvd(vc[i], lv);
        return;
    }
    eta = dvd(L(ni), L(nt));
    k = sub(L(1), mul(mul(eta, eta), dvd(ww, mul(vv, nn))));
    r->certain = fabsl(k.hi) > 0x1p-118L;
    r->cos2 = k.hi;
    if (k.hi < 0) {
        ldd k2 = dvd(add(a, a), nn);
        r->tir = 1;
        for (i = 0; i < 3; i++) r->t[i] = dvd(sub(vc[i], mul(k2, nc[i])), lv);
    } else {
        ldd g = mul(L(s), dvd(sqrt_ldd(k), ln)), e = dvd(eta, lv);
        r->tir = 0;
        for (i = 0; i < 3; i++) r->t[i] = add(mul(e, vt[i]), mul(g, nc[i]));
    }
}

/* A random finite double with exponent in [lo, hi]. */
static double rand_scaled(tu_rng *r, int lo, int hi)
{
    return ldexp(tu_range(r, 1.0, 2.0), lo + (int)(tu_next(r) % (uint64_t)(hi - lo + 1)));
}

/* eta anywhere in the double range: random directions and index ratios
   from 2^-2098 to 2^2098; near-normal incidence with sin_i ~ 1/eta (axis
   normals, so the tiny tangential part is exact), where only huge ratios
   transmit; tiny eta, where every ray transmits almost along n; and
   critical angles of huge ratios, cos^2(theta_t) as small as 2^-1000. */
static void test_refract_every_eta(void **state)
{
    tu_rng rng = {4242};
    stat any = mkstat("any eta"), big = mkstat("huge eta, near normal"),
         tiny = mkstat("tiny eta"), crit = mkstat("huge eta, critical"),
         sub = mkstat("subnormal components");
    long i;
    (void)state;
    if (!ref_init()) {
        print_message("long double is not wider than double here: no reference\n");
        skip();
    }
    use_wide_ref = 1;
    for (i = 0; i < 20000; i++) {
        ggVec3 n = tu_unit(&rng), v = incoming(&rng, n, tu_uniform(&rng));
        double ni = rand_scaled(&rng, -1074, 1023), nt = rand_scaled(&rng, -1074, 1023);
        if (i % 3 == 0) ni = nt * tu_range(&rng, 4, 64); /* just above the old range */
        if (i % 3 == 1) nt = ni * tu_range(&rng, 4, 64);
        perturb(&rng, &v, &n, &ni, &nt);
        check_case(&any, v, n, ni, nt);
    }
    for (i = 0; i < 20000; i++) {
        int e = 1 + (int)(tu_next(&rng) % 1060), ax = (int)(i % 3);
        double comp[3], nrm[3] = {0, 0, 0}, ni = ldexp(tu_range(&rng, 1, 2), e), nt = 1.0;
        ggVec3 v, n;
        /* sin_i ~ x / eta, x in (0, 2): transmitted below x ~ 1 */
        comp[ax] = ldexp(tu_range(&rng, 0.01, 2.0), -e) * (tu_next(&rng) & 1 ? 1 : -1);
        comp[(ax + 1) % 3] = -1, comp[(ax + 2) % 3] = i % 2 ? 0 : comp[ax] * 0.5;
        nrm[(ax + 1) % 3] = (i & 4) ? 1 : -1;
        v.x = comp[0], v.y = comp[1], v.z = comp[2];
        n.x = nrm[0], n.y = nrm[1], n.z = nrm[2];
        if (i & 8) ni = -ni, nt = -nt;
        if (i & 16) ni = ldexp(ni, -1000), nt = ldexp(nt, -1000);
        check_case(&big, v, n, ni, nt);
    }
    for (i = 0; i < 10000; i++) {
        ggVec3 n = tu_unit(&rng), v = incoming(&rng, n, tu_uniform(&rng));
        double nt = rand_scaled(&rng, 0, 1023), ni = nt * ldexp(1.0, -2 - (int)(tu_next(&rng) % 2000));
        if (ni == 0) ni = 0x1p-1074;
        perturb(&rng, &v, &n, &ni, &nt);
        check_case(&tiny, v, n, ni, nt);
    }
    /* v = (x, -1, 0), n = (0, 1, 0): sin_i = x / sqrt(1 + x^2); with ni = 1,
       nt = x (1 + k 2^-53): critical within a few ulp, cos^2 ~ x^2 or
       -k 2^-52. */
    for (i = 0; i < 4000; i++) {
        double x = ldexp(tu_range(&rng, 1, 2), -1 - (int)(tu_next(&rng) % 1000));
        double k = (double)((int)(tu_next(&rng) % 9) - 4), nt = x * (1 + k * 0x1p-53);
        ggVec3 v = {x, -1, 0}, n = {0, 1, 0};
        check_case(&crit, v, n, 1.0, nt);
    }
    /* A normal with a subnormal component: n = (x, +-m, 0), v = (0, -w, 0),
       sin_i about x, ni = 1, nt = x / r (eta about r / x, up to 2^1074):
       found by the fuzzer (tests/fuzz/corpus/optics/huge-eta-subnormal-normal)
       when k n_x underflowed in the double-double path. */
    for (i = 0; i < 2000; i++) {
        double x = ldexp(tu_range(&rng, 1, 2), -1023 - (int)(tu_next(&rng) % 50));
        double r = tu_range(&rng, 0.01, 2.0);
        ggVec3 v = {0, -1, 0}, n = {x, (i & 1) ? 1 : -1, 0};
        v.y = -tu_range(&rng, 1, 2), n.y *= tu_range(&rng, 0.5, 1); /* k = v.n/n.n inexact */
        if (i & 2) v.z = ldexp(x, -(int)(tu_next(&rng) % 4));
        check_case(&sub, v, n, 1.0, x / r);
    }
    use_wide_ref = 0;
    print_message("ggRefract for every eta against the cross-product reference (bound %.0f, %.0f "
                  "where cos_t < 2^-40):\n",
                  BOUND_REFRACT, BOUND_NEARCRIT);
    report(&any);
    report(&big);
    report(&tiny);
    report(&crit);
    report(&sub);
    assert_true(big.count > 0 && crit.nearcrit > 0);
}

/* ------------------------------------------------------------------ */
/* The fast path's certificate                                         */
/* ------------------------------------------------------------------ */

/* refract_fast (lib/optics/refract.inc.h, compiled into this test) on the
   scaled inputs, against the 128-bit reference and against refract_dd on
   the same inputs: whenever it certifies a result, that result is within
   the bound; it must decline (return 2) within 2^-60 of the critical
   angle, where the double-double discriminant cannot give cos_t to the
   precision the 1-ulp bound needs; and it must cover nearly all random
   inputs (otherwise the speed claimed in docs/optics.md is not there). */
static int fast_on(ggVec3 v, ggVec3 n, double ni, double nt, ggVec3 *t, ggVec3 *tdd, int *rdd)
{
    gg_v4 V = scale_unit(v, max_bits(v)), N = scale_unit(n, max_bits(n));
    int e = dd_expo(fabs(ni)) > dd_expo(fabs(nt)) ? dd_expo(fabs(ni)) : dd_expo(fabs(nt)), rc;
    ni = dd_scale2(ni, -e), nt = dd_scale2(nt, -e);
    *rdd = refract_dd(v3(flush(V[0]), flush(V[1]), flush(V[2])),
                      v3(flush(N[0]), flush(N[1]), flush(N[2])), ni, nt, 0, &v, &n, tdd);
    if (!((ni > 0) == (nt > 0) && fabs(ni) <= 4 * fabs(nt))) return 2;
    rc = refract_fast(V, N, ni, nt, t);
    return rc;
}

static void test_fast_certificate(void **state)
{
    tu_rng rng = {31337};
    long i, certified[4] = {0, 0, 0, 0}, total[4] = {0, 0, 0, 0}, declined_crit = 0;
    double worst = 0, worst_dd = 0;
    static const char *cls[4] = {"random", "grazing, eta ~ 1", "near critical", "normal"};
    (void)state;
    if (!ref_init()) {
        print_message("long double is not wider than double here: no reference\n");
        skip();
    }
    for (i = 0; i < 80000; i++) {
        int k = (int)(i % 4), rc, rdd;
        ggVec3 n = tu_unit(&rng), v, t, tdd;
        double ni = rand_index(&rng), nt = rand_index(&rng), c = tu_uniform(&rng), s;
        ref_result r;
        if (k == 1) {
            c = pow(2.0, -tu_range(&rng, 1, 70));
            nt = ni * (1 + (double)((int)(tu_next(&rng) % 9) - 4) * 0x1p-52);
        } else if (k == 2) {
            if (nt > ni) s = nt, nt = ni, ni = s;
            if (nt == ni) ni = nt * 1.5;
            s = nt / ni * (1 + (i % 8 < 4 ? 1 : -1) * pow(2.0, -tu_range(&rng, 20, 53)));
            c = sqrt((1 - s) * (1 + s));
        } else if (k == 3) {
            c = 1 - pow(10.0, -tu_range(&rng, 1, 17));
        }
        v = incoming(&rng, n, c);
        rc = fast_on(v, n, ni, nt, &t, &tdd, &rdd);
        total[k]++;
        if (rc == 2) continue;
        certified[k]++;
        ref_refract(v, n, ni, nt, &r);
        assert_int_equal(rc, rdd); /* the same decision as the full path */
        if (r.certain && r.tir != -1) {
            double e = err_ulps(t, r.t), d;
            ggVec3 diff = v3sub(t, tdd);
            assert_int_equal(rc == 1 ? 0 : 1, r.tir);
            if (e > worst) worst = e;
            d = 0x1p53 * v3maxabs(diff);
            if (d > worst_dd) worst_dd = d;
            if (!(e <= BOUND_REFRACT))
                print_error("fast path %.3f ulp at v=(%a,%a,%a) n=(%a,%a,%a) ni=%a nt=%a\n", e,
                            v.x, v.y, v.z, n.x, n.y, n.z, ni, nt);
            assert_true(e <= BOUND_REFRACT);
        }
    }
    /* Within 2^-45 (relative) of the critical angle, on the transmitted
       side: cos^2(theta_t) about 2^-44, where the discriminant's bound (about 2^-94 of its terms)
       leaves cos_t less precise than the 1-ulp bound needs: the fast path
       must decline (docs/optics.md, "The fast paths"). */
    for (i = 0; i < 2000; i++) {
        ggVec3 n = tu_unit(&rng), v, t, tdd;
        double ni = 1.5, nt = 1.0, s = nt / ni * (1 - ldexp(0.5 + 0.5 * tu_uniform(&rng), -45));
        int rdd;
        v = incoming(&rng, n, sqrt((1 - s) * (1 + s)));
        if (fast_on(v, n, ni, nt, &t, &tdd, &rdd) == 2) declined_crit++;
    }
    print_message("fast path certified:");
    for (i = 0; i < 4; i++) print_message(" %s %ld/%ld", cls[i], certified[i], total[i]);
    print_message("\n  worst certified error %.3f ulp (bound %.0f), largest difference from the "
                  "double-double path %.3f ulp; declined %ld of 2000 transmitted rays within "
                  "2^-45 of critical\n",
                  worst, BOUND_REFRACT, worst_dd, declined_crit);
    assert_true(worst <= BOUND_REFRACT);
    assert_true(certified[0] >= total[0] * 99 / 100);
    assert_true(certified[1] >= total[1] * 9 / 10);
    assert_int_equal(declined_crit, 2000);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_refract_accuracy),
        cmocka_unit_test(test_refract_every_eta),
        cmocka_unit_test(test_fast_certificate),
        cmocka_unit_test(test_reflect_accuracy),
        cmocka_unit_test(test_fresnel_accuracy),
    };
    (void)refract_plain, (void)reflect_plain;
    return cmocka_run_group_tests_name("optics_accuracy", tests, NULL, NULL);
}
