/* SPDX-License-Identifier: MIT */
/*
** fuzz_optics.c -- libFuzzer harness for reflection, refraction, Fresnel
** and Beer-Lambert. The input is read as up to 12 little-endian doubles
**   v.x v.y v.z  n.x n.y n.z  ni nt  cos_i k  lambda distance
** (missing ones take the defaults below) and a shaping byte after them
** that can bend v or nt towards the hard cases (eta near 1, near the
** critical angle, grazing, normal incidence), which raw bytes rarely hit.
**
** It asserts the documented properties: invalid input gives false and NaN;
** no FE_INVALID, FE_DIVBYZERO or FE_OVERFLOW on finite input; t unit and
** on the far side; Snell's law; the TIR decision and the 1-ulp bound
** against the 128-bit reference of tests/common/optics_ref.h; bit-identical
** results for -n and for power-of-two scalings; reflection preserves
** length and is an involution; reflectances in [0, 1]; Beer-Lambert
** composes. Over the whole range -- eta from 2^-2098 to 2^2098, normal
** parts of v down to 2^-1074 of the tangential part, subnormal cosines,
** n == n_outside with k down to 2^-1074 -- the decision and the 1-ulp
** bounds are also checked against the library's 512-bit references
** (ggRefractError and friends, lib/optics/error.c). A failed check prints
** what failed and aborts: the harness does, the library never does.
**
** Built by `make fuzz` with clang -fsanitize=fuzzer,address,undefined, and
** with the plain compiler as build/tests/replay_optics, which `make check`
** runs over tests/fuzz/corpus/optics/.
*/
#include "ggrt.h"

#include "optics_ref.h"

#include <fenv.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const uint8_t *g_data;
static size_t g_size;

#define CHECK(cond, what)                                                                        \
    do {                                                                                         \
        if (!(cond)) fail_check(what, #cond, __LINE__);                                          \
    } while (0)

static void fail_check(const char *what, const char *cond, int line)
{
    size_t i;
    fprintf(stderr, "fuzz_optics.c:%d: property failed: %s (%s)\ninput (%zu bytes):", line, what,
            cond, g_size);
    for (i = 0; i < g_size; i++) fprintf(stderr, "%s%02x", i % 32 ? "" : "\n  ", g_data[i]);
    fprintf(stderr, "\n");
    abort();
}

static ggVec3 V(double x, double y, double z)
{
    ggVec3 v;
    v.x = x, v.y = y, v.z = z;
    return v;
}
static int finite3(ggVec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }
static int zero3(ggVec3 a) { return a.x == 0 && a.y == 0 && a.z == 0; }
static int nan3(ggVec3 a) { return isnan(a.x) && isnan(a.y) && isnan(a.z); }
static int same(ggVec3 a, ggVec3 b) { return memcmp(&a, &b, sizeof a) == 0; }
static double maxabs3(ggVec3 a)
{
    double m = fabs(a.x);
    if (fabs(a.y) > m) m = fabs(a.y);
    if (fabs(a.z) > m) m = fabs(a.z);
    return m;
}

/* Long double helpers for the checks (wider range: no overflow). */
static ld ldot(ggVec3 a, ggVec3 b) { return (ld)a.x * b.x + (ld)a.y * b.y + (ld)a.z * b.z; }
static ld llen(ggVec3 a) { return sqrtl(ldot(a, a)); }
static ld lcrosslen(ggVec3 a, ggVec3 b)
{
    ld x = (ld)a.y * b.z - (ld)a.z * b.y, y = (ld)a.z * b.x - (ld)a.x * b.z,
       z = (ld)a.x * b.y - (ld)a.y * b.x;
    return sqrtl(x * x + y * y + z * z);
}
static ld ldiff(ggVec3 a, ggVec3 b, ld s) /* max |a - s b| */
{
    ld x = fabsl(a.x - s * b.x), y = fabsl(a.y - s * b.y), z = fabsl(a.z - s * b.z);
    return x > y ? (x > z ? x : z) : (y > z ? y : z);
}

/* Sign of the exact v.n: the six exact long double parts of the products
   summed into a non-overlapping expansion (Shewchuk's Grow-Expansion,
   exact because TwoSum is); its largest non-zero part has the sign. */
static int exact_dot_sign(ggVec3 a, ggVec3 b)
{
    ld terms[6], e[6], q;
    int m = 0, i, j;
    ldd p = two_prod(a.x, b.x);
    terms[0] = p.hi, terms[1] = p.lo;
    p = two_prod(a.y, b.y), terms[2] = p.hi, terms[3] = p.lo;
    p = two_prod(a.z, b.z), terms[4] = p.hi, terms[5] = p.lo;
    for (i = 0; i < 6; i++) {
        q = terms[i];
        for (j = 0; j < m; j++) {
            ldd s = two_sum(q, e[j]);
            q = s.hi, e[j] = s.lo;
        }
        e[m++] = q;
    }
    for (i = m - 1; i >= 0; i--)
        if (e[i] != 0) return e[i] > 0 ? 1 : -1;
    return 0;
}

/* v x n == 0 exactly: the exact products compared pairwise (a double
   product is exact as a long double pair, and that pair is unique). */
static int same_prod(double a, double b, double c, double d)
{
    ldd p = two_prod(a, b), q = two_prod(c, d);
    return p.hi == q.hi && p.lo == q.lo;
}
static int exact_parallel(ggVec3 a, ggVec3 b)
{
    return same_prod(a.y, b.z, a.z, b.y) && same_prod(a.z, b.x, a.x, b.z) &&
           same_prod(a.x, b.y, a.y, b.x);
}

/* "Moderate" inputs, where the accuracy bounds and the geometric checks
   with fixed tolerances apply. */
static int moderate(double x) { return x == 0 || (fabs(x) > 0x1p-500 && fabs(x) < 0x1p500); }
static int moderate3(ggVec3 a) { return moderate(a.x) && moderate(a.y) && moderate(a.z); }
/* No component is below 2^-470 of the largest: ggRefract treats those
   below 2^-480 as zero (documented), which can decide the side of a ray
   that is otherwise exactly tangent. */
static int span_ok(double x, double m) { return x == 0 || fabs(x) >= m * 0x1p-470; }
static int range3(ggVec3 a)
{
    double m = maxabs3(a);
    return span_ok(a.x, m) && span_ok(a.y, m) && span_ok(a.z, m);
}

static const double defaults[12] = {0.3, -0.9, 0.1, 0.0, 1.0, 0.0, 1.0, 1.5, 0.7, 3.0, 0.5, 1.0};

static void check_refract(ggVec3 v, ggVec3 n, double ni, double nt)
{
    const int bad = FE_INVALID | FE_DIVBYZERO | FE_OVERFLOW;
    int finite = finite3(v) && finite3(n) && isfinite(ni) && isfinite(nt);
    int valid = finite && !zero3(v) && !zero3(n) && ni != 0 && nt != 0;
    ggVec3 t, t2, t3, back;
    bool ok, ok2, ok3, okb = false;
    int flags;
    ld lv, ln, ci, eta, sini;

    feclearexcept(FE_ALL_EXCEPT);
    ok = ggRefract(v, n, ni, nt, &t);
    ok2 = ggRefract(v, V(-n.x, -n.y, -n.z), ni, nt, &t2);
    (void)ggRefract(v, n, ni, nt, NULL);
    flags = fetestexcept(bad);
    if (finite) CHECK(flags == 0, "no FP exception on finite input");
    if (!valid) {
        CHECK(!ok && nan3(t), "invalid input gives false and NaN");
        return;
    }
    CHECK(ok == ok2 && same(t, t2), "both normal orientations give identical results");
    CHECK(finite3(t), "finite result");
    CHECK(fabsl(llen(t) - 1) < 0x1p-50L, "unit result");

    /* Powers of two anywhere change nothing (when nothing under/overflows). */
    if (moderate3(v) && moderate3(n) && moderate(ni) && moderate(nt)) {
        ok3 = ggRefract(V(v.x * 0x1p-40, v.y * 0x1p-40, v.z * 0x1p-40),
                        V(n.x * 8, n.y * 8, n.z * 8), ni * 0x1p30, nt * 0x1p30, &t3);
        CHECK(ok3 == ok && same(t3, t), "invariant under power-of-two scaling");
    }

    if (!range3(v) || !range3(n)) return;
    /* v exactly in the surface (exact sign of v.n) */
    {
        if (exact_dot_sign(v, n) == 0) {
            CHECK(!ok, "tangent v does not cross");
            lv = llen(v);
            if (lv > 0 && isfinite(lv)) CHECK(ldiff(t, v, 1 / lv) < 0x1p-52L, "t = v/|v|");
            return;
        }
    }
    lv = llen(v), ln = llen(n);
    if (!(lv > 0 && ln > 0 && isfinite(lv) && isfinite(ln))) return; /* squares underflowed */
    ci = ldot(v, n) / (lv * ln);
    eta = (ld)ni / nt;
    sini = lcrosslen(v, n) / (lv * ln);

    if (ni == nt && ci != 0) CHECK(ok && ldiff(t, v, 1 / lv) < 0x1p-52L, "ni == nt gives v/|v|");
    if (exact_parallel(v, n))
        CHECK(ok && ldiff(t, v, 1 / lv) < 0x1p-52L, "normal incidence gives v/|v|");
    if (!(fabsl(eta) > 1e-6L && fabsl(eta) < 1e6L)) return;
    if (ok) {
        ld ct = ldot(t, n) / ln, st = lcrosslen(t, n) / ln;
        CHECK(fabsl(eta) * sini <= 1 + 1e-12L, "transmitted only below the critical angle");
        CHECK(ct * ci >= -1e-12L, "t continues to the far side");
        CHECK(fabsl(fabsl(eta) * sini - st) <= 1e-12L * (1 + fabsl(eta)), "Snell's law");
        /* coplanar with v and n (w = v x n kept in long double: its
           components may be far below the double range) */
        {
            ld wx = (ld)v.y * n.z - (ld)v.z * n.y, wy = (ld)v.z * n.x - (ld)v.x * n.z,
               wz = (ld)v.x * n.y - (ld)v.y * n.x, lw = sqrtl(wx * wx + wy * wy + wz * wz);
            /* w's own rounding: 2^-63 |v||n| absolute */
            if (lw > 0 && isfinite(lw))
                CHECK(fabsl(t.x * (wx / lw) + t.y * (wy / lw) + t.z * (wz / lw)) <=
                          1e-13L + 0x1p-60L * lv * ln / lw,
                      "t in the plane of v and n");
        }
        /* refracting back returns v, where that is well conditioned */
        if (fabsl(ct) > 1e-3L && fabsl(ci) > 1e-3L) {
            okb = ggRefract(V(-t.x, -t.y, -t.z), n, nt, ni, &back);
            CHECK(okb, "the way back is open");
            /* t's 1 ulp comes back multiplied by up to 1/eta (tangential)
               and 1/(cos_i cos_t) (normal) */
            CHECK(ldiff(back, v, -1 / lv) <=
                      1e-14L * (1 + fabsl(eta) + 1 / fabsl(eta)) / (fabsl(ct) * fabsl(ci)),
                  "refracting back");
        }
    } else {
        ld tn = ldot(t, n) / ln;
        CHECK(fabsl(eta) * sini >= 1 - 1e-12L, "TIR only beyond the critical angle");
        CHECK(fabsl(tn + ci) <= 1e-13L, "the mirror direction flips the normal component");
        CHECK(fabsl(lcrosslen(t, n) / ln - sini) <= 1e-13L, "and keeps the tangential one");
    }

    /* The decision and the bound against the 128-bit reference. */
    /* every eta up to 2^40, where the textbook reference's own cancellation
       (eta 2^-128) stays below 2^-88; tests/unit/optics/test_optics_accuracy.c covers
       the rest with a cross-product reference */
    if (ref_init() && moderate3(v) && moderate3(n) && fabsl(eta) <= 0x1p40L) {
        ref_result r;
        double e, bound;
        ref_refract(v, n, ni, nt, &r);
        /* exact outside the band docs/optics.md exempts: |cos^2 theta_t| < 2^-96 */
        if (r.tir != -1 && fabsl(r.cos2) > 0x1p-96L)
            CHECK((ok ? 0 : 1) == r.tir, "TIR decision is exact");
        if (r.tir != -1 && (ok ? 0 : 1) == r.tir) {
            e = err_ulps(t, r.t);
            bound = r.tir == 0 && r.cos2 < 0x1p-80L ? 4.0 : 1.0;
            if (!(e <= bound)) fprintf(stderr, "error %.3f ulp, bound %.0f\n", e, bound);
            CHECK(e <= bound, "accuracy bound of docs/optics.md");
        }
    }
    /* The textbook variant must not misbehave (no UB) either. */
    (void)ggRefractTextbook(v, n, ni, nt, &t3);
}

static void check_reflect(ggVec3 v, ggVec3 n)
{
    const int bad = FE_INVALID | FE_DIVBYZERO | FE_OVERFLOW;
    ggVec3 r, r2;
    int flags;
    int big = !(maxabs3(v) < 0x1p1000);
    feclearexcept(FE_ALL_EXCEPT);
    r = ggReflection(v, n);
    flags = fetestexcept(bad);
    if (!finite3(v) || !finite3(n) || zero3(n)) {
        CHECK(nan3(r), "invalid reflection gives NaN");
        return;
    }
    if (big) return; /* the exact result may exceed DBL_MAX: overflow is allowed */
    CHECK(flags == 0, "no FP exception in ggReflection");
    CHECK(finite3(r), "finite reflection");
    if (moderate3(v) && moderate3(n)) {
        ld lv = llen(v);
        CHECK(fabsl(llen(r) - lv) <= 0x1p-50L * lv, "|r| = |v|");
        r2 = ggReflection(r, n);
        CHECK(ldiff(r2, v, 1) <= 0x1p-50L * lv, "reflecting twice is the identity");
        CHECK(same(ggReflection(v, V(-n.x, -n.y, -n.z)), r), "orientation of n is irrelevant");
    }
}

static void check_fresnel(double c, double ni, double nt, double k)
{
    const int bad = FE_INVALID | FE_DIVBYZERO | FE_OVERFLOW;
    int finite = isfinite(c) && isfinite(ni) && isfinite(nt) && isfinite(k);
    int valid = isfinite(c) && isfinite(ni) && isfinite(nt) && ni != 0 && nt != 0;
    double R, Rs, rs, rp, Rc, Rc0, cs, cp, tc;
    int flags;
    feclearexcept(FE_ALL_EXCEPT);
    R = ggFresnelDielectric(c, ni, nt);
    ggFresnelDielectricPolarized(c, ni, nt, &rs, &rp);
    Rs = ggFresnelSchlick(c, ni, nt);
    Rc = ggFresnelConductor(c, ni, fabs(nt), fabs(k));
    Rc0 = ggFresnelConductor(c, ni, fabs(nt), 0);
    ggFresnelConductorPolarized(c, ni, fabs(nt), fabs(k), &cs, &cp);
    tc = ggCriticalAngle(ni, nt);
    flags = fetestexcept(bad);
    if (finite) CHECK(flags == 0, "no FP exception in the Fresnel functions");
    CHECK(isnan(tc) == !(isfinite(ni) && isfinite(nt) && ni != 0 && nt != 0),
          "critical angle NaN exactly for invalid indices");
    if (!valid) {
        CHECK(isnan(R) && isnan(rs) && isnan(rp) && isnan(Rs), "invalid gives NaN");
        return;
    }
    CHECK(R >= 0 && R <= 1 && rs >= 0 && rs <= 1 && rp >= 0 && rp <= 1, "R in [0, 1]");
    CHECK(fabs(R - 0.5 * (rs + rp)) <= 0x1p-51, "R is the mean of Rs and Rp");
    CHECK(R == ggFresnelDielectric(-c, -ni, nt), "signs are ignored");
    CHECK(Rs >= 0 && Rs <= 1, "Schlick in [0, 1]");
    CHECK(tc >= 0 && tc <= 1.5707963267948967, "critical angle in [0, pi/2]");
    CHECK(Rc0 >= 0 && Rc0 <= 1, "conductor R in [0, 1]");
    if (isfinite(k)) {
        CHECK(Rc >= 0 && Rc <= 1 && cs >= 0 && cs <= 1 && cp >= 0 && cp <= 1,
              "conductor R in [0, 1]");
    } else {
        CHECK(isnan(Rc) && isnan(cs) && isnan(cp), "conductor with infinite k gives NaN");
    }
    /* k = 0 is the dielectric, where the index ratio is moderate and the
       angle not within 1e-6 of the critical one (R is steep there) */
    if (moderate(ni) && moderate(nt) && fabs(ni / nt) < 1e6 && fabs(ni / nt) > 1e-6) {
        double ac = fabs(c) > 1 ? 1 : fabs(c);
        double s = fabs(ni / nt) * sqrt((1 - ac) * (1 + ac));
        if (fabs(s - 1) > 1e-6) CHECK(fabs(Rc0 - R) <= 1e-12, "conductor with k = 0 is dielectric");
    }
}

/* The exponent spread of a vector's non-zero components. */
static int spread3(ggVec3 a)
{
    double c[3];
    int i, lo = 100000, hi = -100000;
    c[0] = a.x, c[1] = a.y, c[2] = a.z;
    for (i = 0; i < 3; i++)
        if (c[i] != 0) {
            int e = ilogb(c[i]);
            lo = e < lo ? e : lo, hi = e > hi ? e : hi;
        }
    return hi - lo;
}

/* Against the library's 512-bit references, at any exponent: the
   decision wherever the reference is certain, the bound wherever its own
   error is far below it (optics.h: |ni/nt| <= 2^400 or components within
   90 binades of each other, and for the conductor R >= 2^-27 or n ==
   n_outside). */
static void check_exact(ggVec3 v, ggVec3 n, double ni, double nt, double c, double k)
{
    ggDirectionError e;
    ggReflectanceError r;
    ggVec3 t;
    bool ok;
    if (finite3(v) && finite3(n) && !zero3(v) && !zero3(n) && isfinite(ni) && isfinite(nt) &&
        ni != 0 && nt != 0) {
        ok = ggRefract(v, n, ni, nt, &t);
        CHECK(ggRefractError(v, n, ni, nt, t, !ok, &e) == GG_OK, "ggRefractError accepts it");
        /* the contract exempts |cos^2 theta_t| < 2^-96 */
        if (e.certain && !(fabs(e.cos2_t) < 0x1p-96))
            CHECK(e.tir_agrees, "TIR decision agrees with the 512-bit reference");
        if (e.tir_agrees && (ilogb(ni) - ilogb(nt) <= 400 || (spread3(v) < 90 && spread3(n) < 90))) {
            double bound = ok && e.cos2_t < 0x1p-80 ? 4.0 : 1.0;
            if (!(e.max_ulp <= bound)) fprintf(stderr, "error %.3g ulp (512-bit)\n", e.max_ulp);
            CHECK(e.max_ulp <= bound, "1 ulp against the 512-bit reference");
        }
    }
    if (!isfinite(c) || !isfinite(ni) || !isfinite(nt) || ni == 0 || nt == 0) return;
    CHECK(ggFresnelDielectricError(c, ni, nt, ggFresnelDielectric(c, ni, nt), &r) == GG_OK,
          "ggFresnelDielectricError accepts it");
    if (!(r.ulp <= 1)) fprintf(stderr, "dielectric error %.3g ulp\n", r.ulp);
    CHECK(r.ulp <= 1, "dielectric R within 1 ulp of the 512-bit reference");
    k = fabs(k), nt = fabs(nt);
    if (!isfinite(k)) return;
    CHECK(ggFresnelConductorError(c, ni, nt, k, ggFresnelConductor(c, ni, nt, k), &r) == GG_OK,
          "ggFresnelConductorError accepts it");
    if (r.exact >= 0x1p-27 || nt == fabs(ni)) {
        if (!(r.ulp <= 1)) fprintf(stderr, "conductor error %.3g ulp\n", r.ulp);
        CHECK(r.ulp <= 1, "conductor R within 1 ulp of the 512-bit reference");
    }
}

static void check_beer(double k, double lambda, double d)
{
    const int bad = FE_INVALID | FE_DIVBYZERO | FE_OVERFLOW;
    double T, Th, a;
    int flags;
    feclearexcept(FE_ALL_EXCEPT);
    T = ggBeerLambert(k, lambda, d);
    Th = ggBeerLambert(k, lambda, d / 2);
    a = ggAbsorptionCoefficient(k, lambda);
    flags = fetestexcept(bad);
    if (isfinite(k) && isfinite(lambda) && isfinite(d)) CHECK(flags == 0, "no FP exception in BL");
    if (isnan(k) || isnan(lambda) || isnan(d) || k < 0 || !(lambda > 0) || d < 0 || isinf(k) ||
        isinf(lambda)) {
        CHECK(isnan(T), "invalid Beer-Lambert gives NaN");
        return;
    }
    CHECK(T >= 0 && T <= 1, "T in [0, 1]");
    CHECK(a >= 0, "alpha >= 0");
    if (k == 0 || d == 0) CHECK(T == 1, "k = 0 or d = 0 gives exactly 1");
    /* T(d) = T(d/2)^2 where T is not in the underflow range */
    if (Th > 1e-150 && d / 2 * 2 == d) CHECK(fabs(T - Th * Th) <= 1e-13 * T, "T composes");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    double d[12];
    size_t i, nd = size / 8 < 12 ? size / 8 : 12;
    unsigned shape = size > nd * 8 ? data[nd * 8] : 0;
    ggVec3 v, n;
    double ni, nt;
    g_data = data, g_size = size;
    (void)ref_init(); /* also needed for the exact products in the checks */
    memcpy(d, defaults, sizeof d);
    for (i = 0; i < nd; i++) memcpy(&d[i], data + 8 * i, 8);
    v = V(d[0], d[1], d[2]), n = V(d[3], d[4], d[5]), ni = d[6], nt = d[7];

    /* Shaping: rebuild v or nt from the other inputs to reach hard cases.
       The low bits of d[8] become the perturbation. */
    if (finite3(n) && !zero3(n) && moderate3(n) && isfinite(ni) && isfinite(nt) && ni != 0 &&
        nt != 0 && moderate(ni) && moderate(nt)) {
        double ln = sqrt(n.x * n.x + n.y * n.y + n.z * n.z), s, c, small;
        ggVec3 u = V(n.y - n.z, n.z - n.x, n.x - n.y); /* orthogonal to n */
        double lu = sqrt(u.x * u.x + u.y * u.y + u.z * u.z);
        uint64_t bits;
        memcpy(&bits, &d[8], 8);
        small = ldexp((double)(bits & 0xffff) - 32768.0, -(int)(40 + (bits >> 16) % 80));
        if (lu == 0) u = V(n.y, -n.x, 0), lu = sqrt(n.x * n.x + n.y * n.y);
        if (lu > 0 && ln > 0) {
            switch (shape % 10) {
            case 1: /* eta near 1 */
                nt = ni * (1 + ldexp((double)((int)(bits % 33) - 16), -52));
                break;
            case 2: /* near the critical angle */
                if (fabs(nt) < fabs(ni)) {
                    s = fabs(nt / ni) * (1 + small);
                    if (s < 1) {
                        c = sqrt((1 - s) * (1 + s));
                        v = V(-c * n.x / ln + s * u.x / lu, -c * n.y / ln + s * u.y / lu,
                              -c * n.z / ln + s * u.z / lu);
                    }
                }
                break;
            case 3: /* grazing */
                v = V(u.x / lu - small * n.x / ln, u.y / lu - small * n.y / ln,
                      u.z / lu - small * n.z / ln);
                break;
            case 4: /* normal incidence, and 1 + tiny off it */
                v = V(-n.x + small * u.x, -n.y + small * u.y, -n.z + small * u.z);
                break;
            case 5: /* exactly matched */
                nt = ni;
                break;
            default: break;
            }
        }
    }
    /* Every exponent: these need no moderate inputs. */
    if (shape % 10 >= 6 && isfinite(ni) && isfinite(nt) && ni != 0 && nt != 0) {
        uint64_t bits;
        int p;
        memcpy(&bits, &d[8], 8);
        p = (int)(bits % 1075);
        switch (shape % 10) {
        case 6: { /* a normal part 2^-p of the tangential part, n along z */
            int sv = ilogb(fabs(v.x) > fabs(v.y) ? v.x : v.y);
            if (isfinite(v.x) && isfinite(v.y) && (v.x != 0 || v.y != 0)) {
                v.z = ldexp(v.z < 0 ? -1.5 : 1.5, sv - p < -1074 ? -1074 : sv - p);
                n = V(0, 0, n.z != 0 && isfinite(n.z) ? n.z : 1);
            }
            break;
        }
        case 7: /* eta anywhere in 2^-2098 ... 2^2098 */
            ni = ldexp(1 + fabs(ni) / (1 + fabs(ni)), (int)((bits >> 11) % 2098) - 1074);
            nt = ldexp(1 + fabs(nt) / (1 + fabs(nt)), (int)((bits >> 22) % 2098) - 1074);
            if (ni == 0) ni = 0x1p-1074;
            if (nt == 0) nt = 0x1p-1074;
            break;
        case 8: /* a subnormal cosine */
            d[8] = ldexp(1 + (double)(bits & 0xfffff) * 0x1p-20, -1023 - (int)((bits >> 20) % 52));
            break;
        default: /* n == n_outside with k down to 2^-1074 */
            nt = fabs(ni);
            d[9] = ldexp(nt, -(int)((bits >> 11) % 2100));
            if (d[9] == 0) d[9] = 0x1p-1074;
            break;
        }
    }
    check_exact(v, n, ni, nt, d[8], d[9]);
    check_refract(v, n, ni, nt);
    check_reflect(v, n);
    check_fresnel(d[8], ni, nt, d[9]);
    check_beer(d[9], d[10], d[11]);
    return 0;
}
