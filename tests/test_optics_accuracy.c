/*
** test_optics_accuracy.c -- ggRefract, ggReflection and the Fresnel
** reflectance against a higher-precision evaluation, on the inputs where
** the textbook formulas fail: grazing incidence, eta close to 1, angles
** within a few ulp of the critical angle, normal incidence, negative
** indices, non-unit vectors.
**
** The reference is "long double-double": pairs of x86 80-bit long doubles
** (64-bit significands) combined with the same error-free transformations
** as lib/dd.h, about 128 bits. It evaluates the TEXTBOOK formula
**   t = eta v + (eta c - sqrt(1 - eta^2 (1 - c^2))) N
** on the exactly normalised inputs; with 128 bits the cancellations that
** ruin that formula in double cost at most 2^-64 (at exactly the critical
** angle, where the sqrt turns a 2^-128 error into 2^-64), i.e. 0.002 of
** the ulp unit below. So the reference is independent of the library's
** formula, and far more precise than the bound it checks.
**
** Error unit: an "ulp" is 2^-53, the spacing of doubles in [0.5, 1), in
** which the largest component of a unit vector lies. The error of a
** direction is the largest absolute error of its components in that unit
** (max-norm). The bound asserted here is the one stated in docs/optics.md.
*/
#include "testutil.h"

#include "internal.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* The bounds docs/optics.md states (in units of 2^-53). */
#define BOUND_REFRACT 2.0  /* ggRefract, transmitted or mirror direction */
#define BOUND_REFLECT 1.0  /* ggReflection, relative to |v| */
#define BOUND_FRESNEL 4.0  /* ggFresnelDielectric, in ulps of R itself */

/* ------------------------------------------------------------------ */
/* Long double-double                                                  */
/* ------------------------------------------------------------------ */

typedef long double ld;
typedef struct ldd {
    ld hi, lo;
} ldd;

static ld split_const; /* 2^ceil(p/2) + 1 */

static ldd mk(ld hi, ld lo)
{
    ldd r;
    r.hi = hi, r.lo = lo;
    return r;
}
static ldd two_sum(ld a, ld b)
{
    volatile ld s = a + b; /* volatile: keep each rounding */
    ld bb = s - a;
    return mk(s, (a - (s - bb)) + (b - bb));
}
static ldd fast_two_sum(ld a, ld b)
{
    volatile ld s = a + b;
    return mk(s, b - (s - a));
}
static ldd two_prod(ld a, ld b)
{
    volatile ld p = a * b, ta = split_const * a, tb = split_const * b;
    ld ah = ta - (ta - a), al = a - ah, bh = tb - (tb - b), bl = b - bh;
    return mk(p, ((ah * bh - p) + ah * bl + al * bh) + al * bl);
}
static ldd L(ld a) { return mk(a, 0); }
static ldd add(ldd x, ldd y)
{
    ldd s = two_sum(x.hi, y.hi), t = two_sum(x.lo, y.lo), v;
    ld c = s.lo + t.hi, w;
    v = fast_two_sum(s.hi, c);
    w = t.lo + v.lo;
    return fast_two_sum(v.hi, w);
}
static ldd neg(ldd x) { return mk(-x.hi, -x.lo); }
static ldd sub(ldd x, ldd y) { return add(x, neg(y)); }
static ldd mul(ldd x, ldd y)
{
    ldd c = two_prod(x.hi, y.hi);
    return fast_two_sum(c.hi, c.lo + (x.hi * y.lo + x.lo * y.hi));
}
static ldd dvd(ldd x, ldd y)
{
    ld q1 = x.hi / y.hi, q2;
    ldd r = sub(x, mul(y, L(q1)));
    q2 = r.hi / y.hi;
    r = sub(r, mul(y, L(q2)));
    return add(fast_two_sum(q1, q2), L(r.hi / y.hi));
}
static ldd sqrt_ldd(ldd x)
{
    ld s;
    ldd r;
    if (x.hi <= 0) return L(0);
    s = sqrtl(x.hi);
    r = sub(x, two_prod(s, s));
    return fast_two_sum(s, r.hi / (2 * s));
}
static int sgn(ldd x) { return x.hi > 0 ? 1 : x.hi < 0 ? -1 : 0; }

/* Is long double really wider than double here (not the case under
   valgrind, or with -mlong-double-64, or on AArch64 Apple)? */
static int ld_is_wider(void)
{
    volatile ld one = 1, tiny = 0x1p-63L;
    return LDBL_MANT_DIG >= 64 && (one + tiny) - one == tiny;
}

/* ------------------------------------------------------------------ */
/* The reference                                                       */
/* ------------------------------------------------------------------ */

typedef struct ref_result {
    int tir;     /* 1 total internal reflection, 0 transmitted, -1 tangent v */
    int certain; /* the decision is outside the reference's own error band */
    ldd t[3];    /* transmitted or mirror direction, unit */
} ref_result;

static void ref_refract(ggVec3 v, ggVec3 n, double ni, double nt, ref_result *r)
{
    ldd vc[3] = {L(v.x), L(v.y), L(v.z)}, nc[3] = {L(n.x), L(n.y), L(n.z)};
    ldd vv = L(0), nn = L(0), c = L(0), lv, ln, eta, k, sin2;
    int i, s;
    for (i = 0; i < 3; i++) {
        vv = add(vv, mul(vc[i], vc[i]));
        nn = add(nn, mul(nc[i], nc[i]));
    }
    lv = sqrt_ldd(vv), ln = sqrt_ldd(nn);
    for (i = 0; i < 3; i++) vc[i] = dvd(vc[i], lv), nc[i] = dvd(nc[i], ln);
    for (i = 0; i < 3; i++) c = add(c, mul(vc[i], nc[i])); /* signed cos */
    s = sgn(c);
    if (s == 0) {
        r->tir = -1, r->certain = 1;
        for (i = 0; i < 3; i++) r->t[i] = vc[i];
        return;
    }
    eta = dvd(L(ni), L(nt));
    sin2 = mul(sub(L(1), c), add(L(1), c));
    k = sub(L(1), mul(mul(eta, eta), sin2)); /* cos^2 of the transmitted angle */
    r->certain = fabsl(k.hi) > 0x1p-118L;
    if (k.hi < 0) {
        ldd c2 = add(c, c);
        r->tir = 1;
        for (i = 0; i < 3; i++) r->t[i] = sub(vc[i], mul(c2, nc[i]));
    } else {
        /* N = -s nc faces v; t = eta v + (eta |c| - cos_t) N. */
        ldd coef = mul(L(-s), sub(mul(eta, s > 0 ? c : neg(c)), sqrt_ldd(k)));
        r->tir = 0;
        for (i = 0; i < 3; i++) r->t[i] = add(mul(eta, vc[i]), mul(coef, nc[i]));
    }
}

/* Error of t in units of 2^-53, max over components. */
static double err_ulps(ggVec3 t, const ldd ref[3])
{
    ld d[3];
    int i;
    double m = 0;
    d[0] = ((ld)t.x - ref[0].hi) - ref[0].lo;
    d[1] = ((ld)t.y - ref[1].hi) - ref[1].lo;
    d[2] = ((ld)t.z - ref[2].hi) - ref[2].lo;
    for (i = 0; i < 3; i++) {
        double e = (double)(fabsl(d[i]) * 0x1p53L);
        if (!(e <= m)) m = e; /* NaN propagates */
    }
    return m;
}

/* ------------------------------------------------------------------ */
/* Statistics per category                                             */
/* ------------------------------------------------------------------ */

typedef struct stat {
    const char *name;
    long count, undecided;
    long tir_wrong, tir_wrong_textbook;
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
        if ((ok ? 0 : 1) != r.tir) st->tir_wrong++;
        if ((okb ? 0 : 1) != r.tir) st->tir_wrong_textbook++;
        if ((ok ? 0 : 1) != r.tir) {
            print_error("%s: TIR decision wrong for v=(%a,%a,%a) n=(%a,%a,%a) ni=%a nt=%a\n",
                        st->name, v.x, v.y, v.z, n.x, n.y, n.z, ni, nt);
            return;
        }
    }
    e = err_ulps(t, r.t);
    if (!(e <= st->worst)) {
        st->worst = e, st->wv = v, st->wn = n, st->wni = ni, st->wnt = nt;
    }
    if ((okb ? 0 : 1) == (ok ? 0 : 1)) {
        eb = err_ulps(tb, r.t);
        if (!(eb <= st->worst_textbook)) st->worst_textbook = eb;
    }
}

static void report(stat *st)
{
    print_message("  %-22s %7ld cases  worst %6.3f ulp (textbook %10.4g)  TIR wrong %ld "
                  "(textbook %ld)  undecidable %ld\n",
                  st->name, st->count, st->worst, st->worst_textbook, st->tir_wrong,
                  st->tir_wrong_textbook, st->undecided);
    if (!(st->worst <= overall.worst)) {
        overall.worst = st->worst, overall.wv = st->wv, overall.wn = st->wn;
        overall.wni = st->wni, overall.wnt = st->wnt, overall.name = st->name;
    }
    overall.count += st->count;
    if (st->worst_textbook > overall.worst_textbook) overall.worst_textbook = st->worst_textbook;
    assert_int_equal(st->tir_wrong, 0);
    if (!(st->worst <= BOUND_REFRACT)) {
        print_error("%s: error %.3f ulp > bound %.1f at v=(%a,%a,%a) n=(%a,%a,%a) ni=%a nt=%a\n",
                    st->name, st->worst, BOUND_REFRACT, st->wv.x, st->wv.y, st->wv.z, st->wn.x,
                    st->wn.y, st->wn.z, st->wni, st->wnt);
        fail();
    }
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
    if (!ld_is_wider()) skip();
    split_const = ldexpl(1.0L, (LDBL_MANT_DIG + 1) / 2) + 1;

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

    print_message("ggRefract against a 128-bit reference (error in units of 2^-53):\n");
    report(&random);
    report(&grazing);
    report(&matched);
    report(&critical);
    report(&exactcrit);
    report(&nearcrit);
    report(&normal);
    report(&negative);
    print_message("  worst case over %ld inputs: %.3f ulp (bound %.1f) in '%s' at\n"
                  "    v=(%a, %a, %a) n=(%a, %a, %a) ni=%a nt=%a\n"
                  "  textbook formula worst: %.4g ulp\n",
                  overall.count, overall.worst, BOUND_REFRACT, overall.name, overall.wv.x,
                  overall.wv.y, overall.wv.z, overall.wn.x, overall.wn.y, overall.wn.z,
                  overall.wni, overall.wnt, overall.worst_textbook);
    /* The test must be able to tell the formulas apart: the textbook one
       fails the bound by orders of magnitude on these inputs. */
    assert_true(overall.worst_textbook > 1000 * BOUND_REFRACT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_refract_accuracy),
    };
    return cmocka_run_group_tests_name("optics_accuracy", tests, NULL, NULL);
}
