/* SPDX-License-Identifier: MIT */
/*
** test_optics_corners.c -- the optics contract (include/ggrt/optics.h) at
** the corners issue 32 found wrong, each drawn over its whole range and
** checked against the library's 512-bit references (lib/optics/error.c):
**  - ggRefract with a normal part of v from 1 down to 2^-1074 of its
**    tangential part, every eta from 2^-2098 to 2^2098, ni == nt, ni == -nt;
**  - ggRefract with |eta| beyond 2^1028 and a tangential part of v or n
**    more than 1022 binades below the normal one (the 512-bit fallback);
**  - ggFresnelConductor with n == n_outside and k from n down to 2^-1074
**    (k with one, two and 53 significant bits), every cosine exponent;
**  - ggFresnelDielectric (and the conductor with k = 0) with ni below
**    2^-300 nt, subnormal cosines and cosines at Brewster's angle;
**  - the error functions' unit where the exact value underflows;
**  - ggFresnelDielectricPolarized's Rp at and near Brewster's angle, for
**    every index ratio, against a 512-bit Rp formed here with bigf.h.
*/
#include "testutil.h"

#include "bigf.h"

#include <math.h>
#include <stdio.h>

static ggVec3 vec3(double x, double y, double z)
{
    ggVec3 r;
    r.x = x, r.y = y, r.z = z;
    return r;
}

/* A double m 2^e with m drawn in [1, 2), kept finite and non-zero. */
static double draw(tu_rng *r, int e)
{
    double x;
    if (e > 1023) e = 1023;
    x = ldexp(1.0 + tu_uniform(r), e);
    return x != 0 ? x : 0x1p-1074;
}

/* Indices whose ratio covers 2^-2098..2^2098: independent exponents over
   the whole double range, a random sign each; every eighth pair is
   ni == nt, every eighth ni == -nt. */
static void draw_indices(tu_rng *r, long i, double *ni, double *nt)
{
    *ni = draw(r, (int)(tu_uniform(r) * 2098) - 1074);
    *nt = draw(r, (int)(tu_uniform(r) * 2098) - 1074);
    if (tu_uniform(r) < 0.5) *ni = -*ni;
    if (tu_uniform(r) < 0.5) *nt = -*nt;
    if (i % 8 == 0) *nt = *ni;
    if (i % 8 == 1) *nt = -*ni;
    if (i % 8 == 2) *nt = fabs(*nt) * 1.5, *ni = fabs(*nt) / 1.5; /* eta < 1 */
}

static ggVec3 put(int axis, double tang1, double tang2, double normal)
{
    return axis == 0 ? vec3(normal, tang1, tang2) : axis == 1 ? vec3(tang2, normal, tang1)
                                                            : vec3(tang1, tang2, normal);
}

/* The contract on one input, ggRefract against ggRefractError: a
   decision the reference is certain of agrees outside the 2^-96 band,
   and every component is within 1 ulp (4 for a transmitted ray with
   cos^2(theta_t) < 2^-80). Counted into y (the first three failures of
   each kind printed); returns the exact cos^2(theta_t). */
typedef struct tally {
    long cases, wrong, over;
    double worst;
} tally;

static double check_refract(tally *y, ggVec3 v, ggVec3 n, double ni, double nt)
{
    ggDirectionError er;
    ggVec3 t;
    bool ok = ggRefract(v, n, ni, nt, &t);
    double bound;
    assert_int_equal(ggRefractError(v, n, ni, nt, t, !ok, &er), GG_OK);
    y->cases++;
    if (er.certain && !er.tir_agrees && !(fabs(er.cos2_t) < 0x1p-96)) {
        if (y->wrong++ < 3)
            print_message("decision wrong: v=(%a,%a,%a) n=(%a,%a,%a) ni=%a nt=%a: %s\n", v.x, v.y,
                          v.z, n.x, n.y, n.z, ni, nt, ok ? "transmitted" : "TIR");
        return er.cos2_t;
    }
    bound = ok && er.cos2_t < 0x1p-80 ? 4 : 1;
    if (er.max_ulp > y->worst) y->worst = er.max_ulp;
    if (!(er.max_ulp <= bound) && y->over++ < 3)
        print_message("%.3g ulp: v=(%a,%a,%a) n=(%a,%a,%a) ni=%a nt=%a\n", er.max_ulp, v.x, v.y,
                      v.z, n.x, n.y, n.z, ni, nt);
    return er.cos2_t;
}

static void tally_done(const char *what, const tally *y)
{
    print_message("%s: %ld cases, %ld decisions wrong, %ld over the bound, worst %.3f ulp\n", what,
                  y->cases, y->wrong, y->over, y->worst);
    assert_int_equal(y->wrong, 0);
    assert_int_equal(y->over, 0);
}

/* v = T + N with |N| = 2^-p |T| for every p in 0..1074 (as far as N stays
   representable), T and the normal n at random scales over the exponent
   range, n along a random axis, tilted by a tiny component in half the
   cases. Every decision the reference is certain of must agree, every
   component be within the contract's 1 ulp (4 within 2^-40 rad of the
   surface). */
static void test_refract_tiny_normal_part(void **state)
{
    tu_rng rng = {3232};
    long i = 0, cases = 0, wrong = 0, over = 0;
    int p, rep;
    double worst = 0;
    (void)state;
    for (p = 0; p <= 1074; p++)
        for (rep = 0; rep < 4; rep++, i++) {
            int sv = (int)(tu_uniform(&rng) * 1900) - 900, sn = (int)(tu_uniform(&rng) * 2000) - 1000;
            int axis = (int)(tu_uniform(&rng) * 3), e = sv - p;
            double th = tu_uniform(&rng) * 6.283185307179586, ni, nt, bound;
            double nz = tu_uniform(&rng) < 0.5 ? -1 : 1, vz = tu_uniform(&rng) < 0.5 ? -1 : 1;
            ggVec3 v, n, t;
            ggDirectionError er;
            bool ok;
            if (e < -1074) e = -1074;
            v = put(axis, ldexp(cos(th), sv), ldexp(sin(th), sv), vz * draw(&rng, e));
            n = put(axis, 0, i % 2 ? draw(&rng, sn - 700 - (int)(tu_uniform(&rng) * 300)) : 0,
                    nz * draw(&rng, sn));
            draw_indices(&rng, i, &ni, &nt);
            ok = ggRefract(v, n, ni, nt, &t);
            assert_int_equal(ggRefractError(v, n, ni, nt, t, !ok, &er), GG_OK);
            cases++;
            if (er.certain && !er.tir_agrees) {
                if (wrong++ < 3)
                    print_message("decision wrong: v=(%a,%a,%a) n=(%a,%a,%a) ni=%a nt=%a: %s\n",
                                  v.x, v.y, v.z, n.x, n.y, n.z, ni, nt,
                                  ok ? "transmitted" : "not transmitted");
                continue;
            }
            bound = ok && er.cos2_t < 0x1p-80 ? 4 : 1;
            if (er.max_ulp > worst) worst = er.max_ulp;
            if (!(er.max_ulp <= bound) && over++ < 3)
                print_message("%.3g ulp: v=(%a,%a,%a) n=(%a,%a,%a) ni=%a nt=%a\n", er.max_ulp, v.x,
                              v.y, v.z, n.x, n.y, n.z, ni, nt);
        }
    print_message("tiny normal parts: %ld cases, %ld decisions wrong, %ld over the bound, worst "
                  "%.3f ulp\n",
                  cases, wrong, over, worst);
    assert_int_equal(wrong, 0);
    assert_int_equal(over, 0);
}

/* Every component of v and n at any exponent from 2^-1074 to 2^1023
   (one in six zero), either sign, |ni/nt| within 2^+-400 (where the
   reference's own error stays far below the bound, optics.h), one pair
   in eight with ni == nt. */
static void test_refract_every_exponent(void **state)
{
    tu_rng rng = {3237};
    tally y = {0, 0, 0, 0};
    long i;
    (void)state;
    for (i = 0; i < 6000; i++) {
        double d[6], ni, nt;
        int j, e = (int)(tu_uniform(&rng) * 1298) - 674;
        for (j = 0; j < 6; j++) {
            d[j] = tu_uniform(&rng) < 1.0 / 6 ? 0 : draw(&rng, (int)(tu_uniform(&rng) * 2098) - 1074);
            if (tu_uniform(&rng) < 0.5) d[j] = -d[j];
        }
        if ((d[0] == 0 && d[1] == 0 && d[2] == 0) || (d[3] == 0 && d[4] == 0 && d[5] == 0))
            continue;
        ni = draw(&rng, e), nt = draw(&rng, e - 400 + (int)(tu_uniform(&rng) * 801));
        if (tu_uniform(&rng) < 0.5) nt = -nt;
        if (i % 8 == 0) nt = ni;
        check_refract(&y, vec3(d[0], d[1], d[2]), vec3(d[3], d[4], d[5]), ni, nt);
    }
    tally_done("every exponent", &y);
}

/* One ggRefract answer (ok, t) against an exact one (exact_ok, r,
   cos2): outside the TIR band the decision must agree and each component
   be within the contract's 1 ulp (4 for a transmitted ray with
   cos^2(theta_t) < 2^-80); the first three failures of each kind are
   printed. Inside the band (|cos^2(theta_t)| < 2^-96) either decision
   is right, and its direction is checked. */
typedef struct judged {
    long wrong, over;
    double worst;
} judged;

static void judge(judged *j, ggVec3 v, ggVec3 n, double ni, double nt, int ok, ggVec3 t,
                  int exact_ok, const gg_bf r[3], double cos2)
{
    double c[3], bound;
    int k;
    if (ok != exact_ok) {
        if (fabs(cos2) < 0x1p-96) return; /* the band: either decision */
        if (j->wrong++ < 3)
            print_message("decision wrong: v=(%a,%a,%a) n=(%a,%a,%a) ni=%a nt=%a: %s\n", v.x, v.y,
                          v.z, n.x, n.y, n.z, ni, nt, ok ? "transmitted" : "TIR");
        return;
    }
    bound = ok && cos2 < 0x1p-80 ? 4 : 1;
    c[0] = t.x, c[1] = t.y, c[2] = t.z;
    for (k = 0; k < 3; k++) {
        double d = fabs(gg_bf_to_double(gg_bf_scale2(gg_bf_sub(gg_bf_from(c[k]), r[k]), 53)));
        if (d > j->worst) j->worst = d;
        if (!(d <= bound)) {
            if (j->over++ < 3)
                print_message("%.3g ulp: v=(%a,%a,%a) n=(%a,%a,%a) ni=%a nt=%a\n", d, v.x, v.y, v.z,
                              n.x, n.y, n.z, ni, nt);
            return;
        }
    }
}

/* The exact answer for the two shapes of test_refract_spread_huge_eta,
   in 512 bits from the geometry (not from the library's formulas):
   a = the tiny tangential component, b = the large normal one (b > 0),
   S = a/h, C = b/h, h = sqrt(a^2 + b^2), m = eta S.
   in_v:  v = (a, 0, -b), n = (0, 0, N):  t = (m, 0, -cos_t),
          mirror (S, 0, C);
   else:  v = (0, 0, -V), n = (0, a, b):  t = (0, m C, -(m S + cos_t C)),
          mirror (0, 2 S C, C^2 - S^2).
   Returns 1 (transmitted) or 0 (total internal reflection); *cos2 is
   cos^2(theta_t) = 1 - m^2. */
static int spread_exact(double a, double b, double ni, double nt, int in_v, gg_bf r[3],
                        double *cos2)
{
    gg_bf A = gg_bf_from(a), Bb = gg_bf_from(b), one = gg_bf_from(1.0), zero = gg_bf_from(0.0);
    gg_bf h = gg_bf_sqrt(gg_bf_add(gg_bf_mul(Bb, Bb), gg_bf_mul(A, A)));
    gg_bf S = gg_bf_div(A, h), C = gg_bf_div(Bb, h);
    gg_bf m = gg_bf_mul(gg_bf_div(gg_bf_from(ni), gg_bf_from(nt)), S);
    gg_bf c2 = gg_bf_sub(one, gg_bf_mul(m, m)), ct;
    *cos2 = gg_bf_to_double(c2);
    r[0] = r[1] = r[2] = zero;
    if (c2.sign < 0) {
        if (in_v) r[0] = S, r[2] = C;
        else
            r[1] = gg_bf_scale2(gg_bf_mul(S, C), 1),
            r[2] = gg_bf_sub(gg_bf_mul(C, C), gg_bf_mul(S, S));
        return 0;
    }
    ct = gg_bf_sqrt(c2);
    if (in_v) r[0] = m, r[2] = gg_bf_neg(ct);
    else
        r[1] = gg_bf_mul(m, C), r[2] = gg_bf_neg(gg_bf_add(gg_bf_mul(m, S), gg_bf_mul(ct, C)));
    return 1;
}

/* |eta| beyond 2^450 with a decisive tangential part more than 1022
   binades below the normal one (as the fuzzer found: the scaling to
   [1, 2) rounded or dropped it, and a ray such a ratio reflects went
   straight through). The tangential part a = 2^-q b, q from 1030 to
   2070, in n (v = -V e_z, n = (0, a, b)) or in v (v = (a, 0, -b),
   n = N e_z); b at any exponent that keeps a representable; ni at any
   exponent, nt (normal or subnormal, either sign) chosen so that
   |eta sin(theta_i)| is 1/4 to 2. Decision and every component against
   spread_exact, within the contract's 1 ulp (4 for a transmitted ray with
   cos^2(theta_t) < 2^-80). (ggRefractError is not the reference here:
   its transmitted direction may be off by 2^-450 |eta| ulp for such
   inputs, optics.h.) */
static void test_refract_spread_huge_eta(void **state)
{
    tu_rng rng = {3238};
    long i, cases = 0, tir = 0;
    judged jd = {0, 0, 0};
    (void)state;
    for (i = 0; i < 4000; i++) {
        int q = 1030 + (int)(tu_uniform(&rng) * 1041), in_v = (int)(i % 2), exact_ok;
        int E = q - 1074 + (int)(tu_uniform(&rng) * (2097 - q));
        int ei = q - 1060 + (int)(tu_uniform(&rng) * (2083 - q));
        double am = (1 + tu_uniform(&rng)) * (tu_uniform(&rng) < 0.5 ? -1 : 1);
        double bm = 1 + tu_uniform(&rng), mt = 0.25 + 1.75 * tu_uniform(&rng);
        double nim = (1 + tu_uniform(&rng)) * (tu_uniform(&rng) < 0.5 ? -1 : 1);
        double a = ldexp(am, E - q), b = ldexp(bm, E), ni = ldexp(nim, ei), nt, cos2;
        ggVec3 v, n, t;
        gg_bf r[3];
        bool ok;
        /* eta S = (nim/ntm) 2^q (am/bm) 2^-q = mt */
        nt = ldexp(fabs(nim * am / bm) / mt, ei - q);
        if (nt == 0) continue;
        if (tu_uniform(&rng) < 0.5) nt = -nt;
        if (in_v)
            v = vec3(a, 0, -b), n = vec3(0, 0, draw(&rng, (int)(tu_uniform(&rng) * 2000) - 1000));
        else
            v = vec3(0, 0, -draw(&rng, (int)(tu_uniform(&rng) * 2000) - 1000)), n = vec3(0, a, b);
        ok = ggRefract(v, n, ni, nt, &t);
        exact_ok = spread_exact(a, b, ni, nt, in_v, r, &cos2);
        cases++, tir += !exact_ok;
        judge(&jd, v, n, ni, nt, ok, t, exact_ok, r, cos2);
    }
    print_message("huge eta, spread components: %ld cases (%ld TIR), %ld decisions wrong, %ld "
                  "over the bound, worst %.3f ulp\n",
                  cases, tir, jd.wrong, jd.over, jd.worst);
    assert_int_equal(jd.wrong, 0);
    assert_int_equal(jd.over, 0);
}

/* sin^2(theta_i) of v and n, |v x n|^2 / (|v|^2 |n|^2), in 512 bits. */
static gg_bf sin2_exact(ggVec3 v, ggVec3 n)
{
    double a[3] = {v.x, v.y, v.z}, b[3] = {n.x, n.y, n.z};
    gg_bf w2 = gg_bf_from(0.0), vv = gg_bf_from(0.0), nn = gg_bf_from(0.0);
    int i;
    for (i = 0; i < 3; i++) {
        int j = (i + 1) % 3, k = (i + 2) % 3;
        gg_bf w = gg_bf_sub(gg_bf_mul(gg_bf_from(a[j]), gg_bf_from(b[k])),
                            gg_bf_mul(gg_bf_from(a[k]), gg_bf_from(b[j])));
        w2 = gg_bf_add(w2, gg_bf_mul(w, w));
        vv = gg_bf_add(vv, gg_bf_mul(gg_bf_from(a[i]), gg_bf_from(a[i])));
        nn = gg_bf_add(nn, gg_bf_mul(gg_bf_from(b[i]), gg_bf_from(b[i])));
    }
    return gg_bf_div(w2, gg_bf_mul(vv, nn));
}

/* The exact refraction or mirror direction of v at n in 512 bits, from
   the geometry: the tangential part as n x (v x n) / |n|^2, which keeps
   its relative precision however small sin(theta_i) is (v - (v.n/n.n) n
   would not). Returns 1 (transmitted) or 0 (TIR); *cos2 is
   cos^2(theta_t). */
static int refract_exact(ggVec3 v, ggVec3 n, double ni, double nt, gg_bf r[3], double *cos2)
{
    gg_bf a[3] = {gg_bf_from(v.x), gg_bf_from(v.y), gg_bf_from(v.z)};
    gg_bf b[3] = {gg_bf_from(n.x), gg_bf_from(n.y), gg_bf_from(n.z)}, w[3], vt[3];
    gg_bf vv = gg_bf_from(0.0), nn = gg_bf_from(0.0), vn = gg_bf_from(0.0), lv, ln, eta, ct, c2;
    int i, side;
    for (i = 0; i < 3; i++) {
        int j = (i + 1) % 3, k = (i + 2) % 3;
        w[i] = gg_bf_sub(gg_bf_mul(a[j], b[k]), gg_bf_mul(a[k], b[j]));
        vv = gg_bf_add(vv, gg_bf_mul(a[i], a[i]));
        nn = gg_bf_add(nn, gg_bf_mul(b[i], b[i]));
        vn = gg_bf_add(vn, gg_bf_mul(a[i], b[i]));
    }
    for (i = 0; i < 3; i++) {
        int j = (i + 1) % 3, k = (i + 2) % 3;
        vt[i] = gg_bf_div(gg_bf_sub(gg_bf_mul(b[j], w[k]), gg_bf_mul(b[k], w[j])), nn);
    }
    lv = gg_bf_sqrt(vv), ln = gg_bf_sqrt(nn);
    side = vn.sign; /* v along n: it leaves on n's side */
    eta = gg_bf_div(gg_bf_from(ni), gg_bf_from(nt));
    c2 = gg_bf_sub(gg_bf_from(1.0),
                   gg_bf_div(gg_bf_mul(gg_bf_mul(eta, eta), gg_bf_div(gg_bf_mul(vt[0], vt[0]), vv)),
                             gg_bf_from(1.0)));
    c2 = gg_bf_sub(c2, gg_bf_div(gg_bf_mul(gg_bf_mul(eta, eta), gg_bf_add(gg_bf_mul(vt[1], vt[1]),
                                                                          gg_bf_mul(vt[2], vt[2]))),
                                 vv));
    *cos2 = gg_bf_to_double(c2);
    if (c2.sign < 0) {
        /* the mirror: (v - 2 (v.n/n.n) n) / |v| = (2 vt - v) / |v| */
        for (i = 0; i < 3; i++) r[i] = gg_bf_div(gg_bf_sub(gg_bf_scale2(vt[i], 1), a[i]), lv);
        return 0;
    }
    /* t = eta vt / |v| + sign(v.n) cos_t n / |n| (a negative eta bends
       the ray to the same side of the normal) */
    ct = gg_bf_sqrt(c2);
    for (i = 0; i < 3; i++) {
        gg_bf tn = gg_bf_div(gg_bf_mul(ct, b[i]), ln);
        r[i] = gg_bf_add(gg_bf_div(gg_bf_mul(eta, vt[i]), lv), side < 0 ? gg_bf_neg(tn) : tn);
    }
    return 1;
}

/* v and n parallel but for a cross product below the subnormal range:
   they share a component s of any exponent down to 2^-1074 and differ
   in the other by k units in the last place (k up to 2^20), so v x n is
   s (x - x'), as small as 2^-1126. Every eta from 2^-2098 to 2^2098 is
   drawn so that eta^2 sin^2(theta_i) is 1/16 to 4: the decision and
   every component of *t against refract_exact, within the contract's
   1 ulp (4 for a transmitted ray with cos^2(theta_t) < 2^-80), wherever
   |cos^2(theta_t)| >= 2^-96. (A test of the TwoProd pairs for parallel
   vectors called such v and n parallel: a ray eta 2^1733 times denser
   totally reflects went through, and one that crosses came out along n,
   2.1e10 ulp off; the fuzzer found it,
   tests/fuzz/corpus/optics/found_near_parallel_subnormal_cross.) */
static void test_refract_near_parallel_subnormal(void **state)
{
    tu_rng rng = {5521};
    long i, cases = 0, tir = 0;
    judged jd = {0, 0, 0};
    (void)state;
    for (i = 0; i < 20000; i++) {
        int ex = (int)(tu_uniform(&rng) * 200) - 100, es = -1074 + (int)(tu_uniform(&rng) * 120);
        double x = ldexp(1 + tu_uniform(&rng), ex), sm = 1 + tu_uniform(&rng), s;
        double k = floor(1 + tu_uniform(&rng) * (i % 3 == 0 ? 4 : 0x1p20)), x2, ni, nt, cos2;
        gg_bf sin2, r[3];
        ggVec3 v, n, t;
        int exact_ok, ok, ei;
        s = ldexp(sm, es);
        if (s == 0) s = 0x1p-1074;
        x2 = x + k * ldexp(1, ex - 52);
        v = vec3(x, s, 0), n = vec3(x2, s, 0);
        if (i % 2) v = vec3(0, x, -s), n = vec3(0, -x2, s); /* the other side, other axes */
        sin2 = sin2_exact(v, n);
        if (sin2.sign == 0) continue; /* k >= 1: never */
        /* eta = m / sin, m^2 in [1/16, 4]: ni at any exponent, nt from it */
        ei = (int)(tu_uniform(&rng) * 2000) - 1000;
        ni = ldexp(1 + tu_uniform(&rng), ei);
        {
            double m = 0.25 + 1.75 * tu_uniform(&rng);
            gg_bf nt_bf = gg_bf_div(gg_bf_mul(gg_bf_from(ni), gg_bf_sqrt(sin2)), gg_bf_from(m));
            nt = gg_bf_to_double(nt_bf);
        }
        if (!(nt != 0 && isfinite(nt))) continue;
        if (tu_uniform(&rng) < 0.5) nt = -nt;
        ok = ggRefract(v, n, ni, nt, &t);
        exact_ok = refract_exact(v, n, ni, nt, r, &cos2);
        cases++, tir += !exact_ok;
        judge(&jd, v, n, ni, nt, ok, t, exact_ok, r, cos2);
    }
    print_message("near-parallel v and n, a subnormal cross product: %ld cases (%ld TIR), %ld "
                  "decisions wrong, %ld over the bound, worst %.3f ulp\n",
                  cases, tir, jd.wrong, jd.over, jd.worst);
    assert_true(cases > 8000 && tir > 1000 && cases - tir > 1000);
    assert_int_equal(jd.wrong, 0);
    assert_int_equal(jd.over, 0);
}

/* eta up to 2^62 with v within 2^-p of a tilted normal (every component
   of n and v non-zero, so v - (v.n / n.n) n is not exact in any
   precision): the case generators above put such normals on an axis,
   where it is, and missed that a tangential part formed with an error of
   2^-106 |v| is 2^-106 / sin(theta_i) of itself, which eta then
   multiplies (an audit found 197,597 ulp). p from 1 to 62; ni = x /
   sin(theta_i) with x from 1/4 to 1 (transmitted, down to the critical
   angle), or the double nearest 1 / sin(theta_i) (|cos^2(theta_t)| below
   about 2^-51, a few in 2^6 inside [2^-96, 2^-58]); indices scaled by a
   power of two and signed at random. Decisions and components against
   ggRefractError, within the contract. */
static void test_refract_huge_eta_tilted(void **state)
{
    tu_rng rng = {3241};
    tally y = {0, 0, 0, 0};
    long i, band = 0;
    (void)state;
    for (i = 0; i < 24000; i++) {
        int p = 1 + (int)(tu_uniform(&rng) * 62), e = (int)(tu_uniform(&rng) * 1200) - 600;
        ggVec3 n = tu_unit(&rng), d = tu_unit(&rng), v;
        double s = ldexp(tu_range(&rng, 1, 2), -p), rs, ni, nt, c2;
        v.x = -n.x + s * d.x, v.y = -n.y + s * d.y, v.z = -n.z + s * d.z;
        if (v.x * v.y * v.z * n.x * n.y * n.z == 0) continue;
        rs = 1 / sqrt(gg_bf_to_double(sin2_exact(v, n)));
        if (!isfinite(rs)) continue;
        ni = i % 2 ? rs : rs * tu_range(&rng, 0.25, 1.0);
        nt = ldexp(tu_uniform(&rng) < 0.5 ? -1.0 : 1.0, e);
        ni = ldexp(tu_uniform(&rng) < 0.5 ? -ni : ni, e);
        if (i % 2) { /* nearer the critical angle: one of ni's neighbours */
            gg_bf m =
                gg_bf_sub(gg_bf_from(1.0),
                          gg_bf_mul(gg_bf_mul(gg_bf_from(rs), gg_bf_from(rs)), sin2_exact(v, n)));
            if (fabs(gg_bf_to_double(m)) > 0x1p-58)
                ni = nextafter(ni, tu_uniform(&rng) < 0.5 ? 0 : 2 * ni);
        }
        c2 = fabs(check_refract(&y, v, n, ni, nt));
        band += c2 >= 0x1p-96 && c2 <= 0x1p-58;
    }
    print_message("huge eta, tilted normal: %ld with |cos^2 t| in [2^-96, 2^-58]\n", band);
    assert_true(band >= 20);
    tally_done("huge eta, tilted normal", &y);
}

/* n == n_outside over the exponent range, k from n down to 2^-1074 with
   one, two or 53 significant bits, cosines from 1 down to 2^-1074. */
static void test_conductor_matched_tiny_k(void **state)
{
    tu_rng rng = {3233};
    static const int ce[] = {0, -1, -27, -300, -537, -1000, -1060, -1074};
    long cases = 0, over = 0;
    int en, d, b, ci;
    double worst = 0;
    (void)state;
    for (en = -1022; en <= 1023; en += 73)
        for (d = 0; d <= 2100; d += 37)
            for (b = 0; b < 3; b++)
                for (ci = 0; ci < 8; ci++) {
                    double n = draw(&rng, en), k, c, R;
                    int ek = en - d;
                    ggReflectanceError er;
                    if (ek < -1074) ek = -1074;
                    k = b == 0 ? ldexp(1.0, ek) : b == 1 ? ldexp(1.5, ek) : draw(&rng, ek);
                    if (k == 0) k = 0x1p-1074;
                    c = ci == 0 ? 1.0 : draw(&rng, ce[ci]);
                    if (c > 1) c = 1;
                    R = ggFresnelConductor(c, n, n, k);
                    assert_int_equal(ggFresnelConductorError(c, n, n, k, R, &er), GG_OK);
                    cases++;
                    if (er.ulp > worst) worst = er.ulp;
                    if (!(er.ulp <= 1) && over++ < 3)
                        print_message("%.3g ulp: c=%a n=%a k=%a R=%.17g exact %.17g\n", er.ulp, c,
                                      n, k, R, er.exact);
                }
    print_message("n == n_outside, tiny k: %ld cases, %ld over 1 ulp, worst %.3f ulp\n", cases,
                  over, worst);
    assert_int_equal(over, 0);
}

/* ni below 2^-300 nt over the whole range (ratios up to 2^2097), with
   subnormal cosines, cosines at and next to Brewster's angle (c = ni/nt)
   and random ones; the conductor with k = 0 must agree. */
static void test_dielectric_extreme_ratio(void **state)
{
    tu_rng rng = {3234};
    long cases = 0, over = 0;
    int ea, eb, j;
    double worst = 0;
    (void)state;
    for (ea = -1074; ea <= 720; ea += 41)
        for (eb = ea + 300; eb <= 1023; eb += 43)
            for (j = 0; j < 6; j++) {
                double ni = draw(&rng, ea), nt = draw(&rng, eb), c, R, Rc;
                ggReflectanceError er;
                if (j == 0) c = ldexp(1.0 + tu_uniform(&rng), -1023 - (int)(tu_uniform(&rng) * 52));
                else if (j == 1) c = 0x1p-1074;
                else if (j == 2) c = ni / nt;
                else if (j == 3) c = ni / nt * (1 + ldexp(tu_uniform(&rng) - 0.5, -30));
                else if (j == 4) c = draw(&rng, -(int)(tu_uniform(&rng) * 1074));
                else c = tu_uniform(&rng);
                if (c == 0) c = 0x1p-1074;
                if (c > 1) c = 1;
                R = ggFresnelDielectric(c, ni, nt);
                Rc = ggFresnelConductor(c, ni, nt, 0);
                assert_int_equal(ggFresnelDielectricError(c, ni, nt, R, &er), GG_OK);
                cases++;
                if (er.ulp > worst) worst = er.ulp;
                if ((!(er.ulp <= 1) || Rc != R) && over++ < 3)
                    print_message("%.3g ulp: c=%a ni=%a nt=%a R=%.17g exact %.17g conductor %.17g\n",
                                  er.ulp, c, ni, nt, R, er.exact, Rc);
            }
    print_message("ni < 2^-300 nt: %ld cases, %ld over 1 ulp (or conductor differing), worst "
                  "%.3f ulp\n",
                  cases, over, worst);
    assert_int_equal(over, 0);
}

/* The unit where the exact value underflows: the correctly rounded exact
   value (subnormal or 0) is at most 1/2 ulp off, for reflectances from
   normal down to 2^-2000 (n == n_outside, normal incidence,
   R = k^2 / (4 n^2 + k^2)) and for subnormal components of a refracted
   direction. */
static void test_error_unit_at_underflow(void **state)
{
    tu_rng rng = {3235};
    int d;
    long cases = 0;
    (void)state;
    for (d = 500; d <= 1100; d++) {
        double n = draw(&rng, (int)(tu_uniform(&rng) * 200) - 100), k = ldexp(n, -d), cand;
        ggReflectanceError er, ec;
        assert_int_equal(ggFresnelConductorError(1.0, n, n, k, 0.5, &er), GG_OK);
        cand = er.exact; /* R rounded to nearest */
        assert_int_equal(ggFresnelConductorError(1.0, n, n, k, cand, &ec), GG_OK);
        if (!(ec.ulp <= 0.5))
            fail_msg("k = n 2^-%d: the rounded exact R %a is %.3g ulp off", d, cand, ec.ulp);
        assert_int_equal(ggFresnelConductorError(1.0, n, n, k, ggFresnelConductor(1.0, n, n, k),
                                                 &ec),
                         GG_OK);
        if (!(ec.ulp <= 1)) fail_msg("k = n 2^-%d: ggFresnelConductor is %.3g ulp off", d, ec.ulp);
        cases++;
    }
    for (d = 1022; d <= 1074; d++) {
        /* t has a subnormal component: ni == nt, v = (1, 2^-d m, 0) */
        ggVec3 v = vec3(1, draw(&rng, -d), 0), n = vec3(1, 0, 0);
        ggDirectionError er, ec;
        int i;
        assert_int_equal(ggRefractError(v, n, 1.5, 1.5, v, false, &er), GG_OK);
        assert_int_equal(ggRefractError(v, n, 1.5, 1.5, er.exact, false, &ec), GG_OK);
        for (i = 0; i < 3; i++)
            if (!(ec.comp_ulp[i] <= 0.5))
                fail_msg("v.y = %a: rounded exact component %d is %.3g ulp off", v.y, i,
                         ec.comp_ulp[i]);
        cases++;
    }
    print_message("underflowing references: %ld cases, each within 1/2 ulp\n", cases);
}

/* The exact Rp for a = |ni|, b = |nt|, c (transmitted):
   rp = (b^2 c - a sqrt q)/(b^2 c + a sqrt q), q = b^2 - a^2 + a^2 c^2. */
static gg_bf exact_rp(double a, double b, double c)
{
    gg_bf a2 = gg_bf_mul(gg_bf_from(a), gg_bf_from(a)), b2 = gg_bf_mul(gg_bf_from(b), gg_bf_from(b));
    gg_bf q = gg_bf_add(gg_bf_sub(b2, a2), gg_bf_mul(a2, gg_bf_mul(gg_bf_from(c), gg_bf_from(c))));
    gg_bf pc = gg_bf_mul(b2, gg_bf_from(c)), pq = gg_bf_mul(gg_bf_from(a), gg_bf_sqrt(q));
    gg_bf rp = gg_bf_div(gg_bf_sub(pc, pq), gg_bf_add(pc, pq));
    return gg_bf_mul(rp, rp);
}

/* Rp at Brewster's angle (c = ni/hypot(ni, nt), or ni/nt for tiny
   ratios) and up to 2^-52 (relative) off it, for ni < nt with every
   ratio from 1 + 2^-20 to 2^2097: within 1 ulp of Rp (2^-53 times the
   smallest power of two >= Rp, or 2^-1074). */
static void test_rp_brewster(void **state)
{
    tu_rng rng = {3236};
    long cases = 0, over = 0;
    int i;
    double worst = 0;
    (void)state;
    for (i = 0; i < 20000; i++) {
        int ea = (int)(tu_uniform(&rng) * 2097) - 1074, eb;
        double ni, nt, c, rs, rp, u;
        gg_bf R, d;
        eb = i % 2 ? ea + (int)(tu_uniform(&rng) * 40) : ea + (int)(tu_uniform(&rng) * 2097);
        ni = draw(&rng, ea), nt = draw(&rng, eb > 1023 ? 1023 : eb);
        if (!(ni < nt)) continue;
        c = ni / nt > 0x1p-500 ? ni / hypot(ni, nt) : ni / nt;
        c *= 1 + ldexp(tu_uniform(&rng) - 0.5, -(int)(tu_uniform(&rng) * 53));
        if (!(c > 0 && c <= 1)) continue;
        ggFresnelDielectricPolarized(c, ni, nt, &rs, &rp);
        R = exact_rp(ni, nt, c);
        d = gg_bf_sub(gg_bf_from(rp), R);
        u = 0;
        if (d.sign) {
            int ue = R.sign ? gg_bf_ceil_expo(R) - 53 : -1074;
            u = fabs(gg_bf_to_double(gg_bf_scale2(d, -(ue > -1074 ? ue : -1074))));
        }
        cases++;
        if (u > worst) worst = u;
        if (!(u <= 1) && over++ < 3)
            print_message("Rp %.3g ulp off: c=%a ni=%a nt=%a Rp=%a\n", u, c, ni, nt, rp);
    }
    print_message("Rp near Brewster: %ld cases, %ld over 1 ulp of Rp, worst %.3f ulp\n", cases,
                  over, worst);
    assert_int_equal(over, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_refract_tiny_normal_part),
        cmocka_unit_test(test_refract_every_exponent),
        cmocka_unit_test(test_refract_spread_huge_eta),
        cmocka_unit_test(test_refract_near_parallel_subnormal),
        cmocka_unit_test(test_refract_huge_eta_tilted),
        cmocka_unit_test(test_conductor_matched_tiny_k),
        cmocka_unit_test(test_dielectric_extreme_ratio),
        cmocka_unit_test(test_error_unit_at_underflow),
        cmocka_unit_test(test_rp_brewster),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
