/* SPDX-License-Identifier: MIT */
/*
** test_implicit.c -- implicit surfaces: hits and normals against closed
** forms (sphere, torus, quartics), central-difference normals, thin parts,
** near misses, rays leaving the surface, domains and poles, callbacks and
** their warnings, threads, API arguments.
*/
#include "testutil.h"

#include "implicit.h"
#include "vec.h"

#include <float.h>
#include <pthread.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static ggVec3 rand_in(tu_rng *r, double lo, double hi)
{
    return v3(tu_range(r, lo, hi), tu_range(r, lo, hi), tu_range(r, lo, hi));
}

static ggVec3 unit_normal(const ggImplicit *imp, ggVec3 p)
{
    return v3norm(ggGradientNormal(imp, p));
}

/* ------------------------------------------------------------------ */
/* Hits against closed forms                                           */
/* ------------------------------------------------------------------ */

/* First t > tmin of the ray against the sphere (c, R), the stable way:
   the discriminant from the distance of the centre to the line
   (Haines et al., Ray Tracing Gems ch. 7). */
static int sphere_hit(ggVec3 c, double R, ggVec3 o, ggVec3 d, double tmin, double *t,
                      double *disc_out)
{
    double a = v3dot(d, d), b, disc, q, t0, t1, cc;
    ggVec3 f = v3sub(o, c), l;
    b = -v3dot(f, d);
    l = v3sub(f, v3scale(d, -b / a));
    disc = a * (R * R - v3dot(l, l));
    *disc_out = disc / (a * R * R);
    if (disc < 0) return 0;
    q = b + (b >= 0 ? 1 : -1) * sqrt(disc);
    cc = v3dot(f, f) - R * R;
    t0 = cc / q, t1 = q / a;
    if (t0 > t1) q = t0, t0 = t1, t1 = q;
    if (t0 > tmin) {
        *t = t0;
        return 1;
    }
    if (t1 > tmin) {
        *t = t1;
        return 1;
    }
    return 0;
}

/* tol: relative to R. Rounding alone moves the surface by about
   eps |c| / R relative to R, which matters for small spheres far out. */
static void check_sphere(const char *src, ggVec3 c, double R, ggVec3 lo, ggVec3 hi, uint64_t seed,
                         int nrays, double tol)
{
    tu_rng r = {seed};
    ggImplicit *imp = tu_implicit(src, lo, hi);
    int i, hits = 0, misses = 0, inside = 0;
    for (i = 0; i < nrays; i++) {
        ggVec3 o, target, d, n, nw;
        double t, tw, disc;
        int h, hw;
        if (i % 10 == 0) { /* some rays start inside */
            o = v3add(c, v3scale(tu_unit(&r), R * tu_range(&r, 0, 0.9)));
            inside++;
        } else {
            o = v3add(c, v3scale(tu_unit(&r), R * tu_range(&r, 2.5, 8)));
        }
        target = v3add(c, v3scale(tu_unit(&r), R * tu_range(&r, 0, 1.3)));
        d = v3scale(v3norm(v3sub(target, o)), i % 2 ? 1 : tu_range(&r, 0.2, 5));
        hw = sphere_hit(c, R, o, d, 0, &tw, &disc);
        if (fabs(disc) < 1e-8) continue; /* tangent within rounding: either answer */
        h = gg_implicit_intersect(imp, o, d, 0, INFINITY, &t);
        if (h != hw) print_error("ray %d: implicit %d analytic %d (disc %g)\n", i, h, hw, disc);
        assert_int_equal(h, hw);
        if (!h) {
            misses++;
            continue;
        }
        hits++;
        assert_close(t * v3len(d) / R, tw * v3len(d) / R, tol);
        n = unit_normal(imp, v3madd(o, d, t));
        nw = v3scale(v3sub(v3madd(o, d, tw), c), 1 / R);
        assert_vec_close(n, nw, tol);
    }
    assert_true(hits > nrays / 3 && misses > nrays / 20 && inside > 0);
    assert_int_equal(ggImplicitWarnings(imp), 0);
    ggImplicitFree(imp);
}

static void test_sphere_matches_analytic(void **state)
{
    (void)state;
    check_sphere("x^2+y^2+z^2-1", v3(0, 0, 0), 1, v3(-2, -2, -2), v3(2, 2, 2), 21, 20000, 1e-12);
    check_sphere("(x-0.3)^2+(y+0.2)^2+(z-0.1)^2-0.49", v3(0.3, -0.2, 0.1), 0.7, v3(-1, -1, -1),
                 v3(1.5, 1, 1), 22, 10000, 1e-12);
    /* Small and far from the origin (|c| / R = 1e5): the root tolerance
       follows the box, the accuracy is what rounding of x - 100 allows. */
    check_sphere("(x-100)^2+(y+50)^2+z^2-1e-6", v3(100, -50, 0), 1e-3, v3(99.99, -50.01, -0.01),
                 v3(100.01, -49.99, 0.01), 23, 5000, 1e-9);
}

static double torus_first_x(double R, double r, double y0, double z0, int *hit)
{
    double s, rho;
    *hit = 0;
    if (fabs(z0) >= r) return 0;
    s = sqrt(r * r - z0 * z0);
    rho = R + s;
    if (rho <= fabs(y0)) return 0;
    *hit = 1;
    return -sqrt(rho * rho - y0 * y0);
}

static ggVec3 torus_normal(double R, ggVec3 p)
{
    double rho = sqrt(p.x * p.x + p.y * p.y);
    return v3norm(v3(p.x - R * p.x / rho, p.y - R * p.y / rho, p.z));
}

static void test_torus_closed_form(void **state)
{
    const double R = 1, r = 0.25;
    tu_rng rng = {31};
    ggImplicit *imp = tu_implicit("(x^2+y^2+z^2+1-0.0625)^2-4*(x^2+y^2)", v3(-1.5, -1.5, -0.5),
                                  v3(1.5, 1.5, 0.5));
    int i, hits = 0, checked = 0;
    double t;
    (void)state;
    /* Along the x axis the four roots are at +-0.75 and +-1.25. */
    assert_true(gg_implicit_intersect(imp, v3(-3, 0, 0), v3(1, 0, 0), 0, INFINITY, &t));
    assert_close(t, 3 - 1.25, 1e-14);
    assert_true(
        gg_implicit_intersect(imp, v3(-3, 0, 0), v3(1, 0, 0), 3 - 1.25 + 1e-9, INFINITY, &t));
    assert_close(t, 3 - 0.75, 1e-14);
    assert_true(gg_implicit_intersect(imp, v3(0, 0, 0), v3(2, 0, 0), 0, INFINITY, &t));
    assert_close(t, 0.375, 1e-14); /* |d| = 2 */
    /* tmax ends the search: just before the root a miss, just after a hit. */
    assert_false(gg_implicit_intersect(imp, v3(0, 0, 0), v3(2, 0, 0), 0, 0.375 - 1e-12, &t));
    assert_true(gg_implicit_intersect(imp, v3(0, 0, 0), v3(2, 0, 0), 0, 0.375 + 1e-12, &t));
    assert_close(t, 0.375, 1e-14);
    /* Rays parallel to x. */
    for (i = 0; i < 5000; i++) {
        double y0 = tu_range(&rng, -1.4, 1.4), z0 = tu_range(&rng, -0.3, 0.3), x1;
        double sc = tu_range(&rng, 0.5, 3);
        int want, h;
        x1 = torus_first_x(R, r, y0, z0, &want);
        if (fabs(fabs(z0) - r) < 1e-6 || fabs(R + sqrt(fmax(0, r * r - z0 * z0)) - fabs(y0)) < 1e-6)
            continue; /* tangent */
        h = gg_implicit_intersect(imp, v3(-3, y0, z0), v3(sc, 0, 0), 0, INFINITY, &t);
        assert_int_equal(h, want);
        checked++;
        if (!h) continue;
        hits++;
        assert_close(t * sc, x1 + 3, 1e-12);
        assert_vec_close(unit_normal(imp, v3(-3 + t * sc, y0, z0)), torus_normal(R, v3(x1, y0, z0)),
                         1e-11);
    }
    /* Rays parallel to z, downwards. */
    for (i = 0; i < 5000; i++) {
        double x0 = tu_range(&rng, -1.4, 1.4), y0 = tu_range(&rng, -1.4, 1.4);
        double rho = sqrt(x0 * x0 + y0 * y0), zt;
        int want = fabs(rho - R) < r, h;
        if (fabs(fabs(rho - R) - r) < 1e-6) continue;
        h = gg_implicit_intersect(imp, v3(x0, y0, 3), v3(0, 0, -1), 0, INFINITY, &t);
        assert_int_equal(h, want);
        checked++;
        if (!h) continue;
        hits++;
        zt = sqrt(r * r - (rho - R) * (rho - R));
        assert_close(t, 3 - zt, 1e-12);
        assert_vec_close(unit_normal(imp, v3(x0, y0, 3 - t)), torus_normal(R, v3(x0, y0, zt)),
                         1e-10);
    }
    /* Any ray in the plane y = 0 meets two circles (x -+ R)^2 + z^2 = r^2. */
    for (i = 0; i < 5000; i++) {
        ggVec3 o = v3(tu_range(&rng, -3, 3), 0, tu_range(&rng, 1, 3)), d;
        double a = tu_range(&rng, 0, 2 * GG_PI), best = INFINITY, tt, disc;
        int k, h;
        if (i % 2) o.z = -o.z;
        d = v3(cos(a), 0, sin(a));
        for (k = -1; k <= 1; k += 2) {
            if (sphere_hit(v3(k * R, 0, 0), r, o, d, 0, &tt, &disc) && tt < best) best = tt;
            if (fabs(disc) < 1e-8) best = NAN;
        }
        if (best != best) continue;
        h = gg_implicit_intersect(imp, o, d, 0, INFINITY, &t);
        assert_int_equal(h, best < INFINITY);
        checked++;
        if (!h) continue;
        hits++;
        assert_close(t, best, 1e-12);
        assert_vec_close(unit_normal(imp, v3madd(o, d, t)), torus_normal(R, v3madd(o, d, best)),
                         1e-11);
    }
    assert_true(hits > 3000 && checked > 12000);
    ggImplicitFree(imp);
}

static void test_quartic_blobs(void **state)
{
    tu_rng rng = {41};
    ggImplicit *cube = tu_implicit("x^4+y^4+z^4-1", v3(-1.2, -1.2, -1.2), v3(1.2, 1.2, 1.2));
    ggImplicit *tangle =
        tu_implicit("x^4-5*x^2+y^4-5*y^2+z^4-5*z^2+11.8", v3(-3, -3, -3), v3(3, 3, 3));
    double t, s;
    int i, hits = 0;
    (void)state;
    /* Rounded cube along the diagonal: 3 s^4 = 1. */
    assert_true(gg_implicit_intersect(cube, v3(-3, -3, -3), v3(1, 1, 1), 0, INFINITY, &t));
    s = pow(1.0 / 3, 0.25);
    assert_close(t, 3 - s, 1e-13);
    assert_vec_close(unit_normal(cube, v3(-s, -s, -s)), v3norm(v3(-1, -1, -1)), 1e-14);
    for (i = 0; i < 5000; i++) {
        double y0 = tu_range(&rng, -1.1, 1.1), z0 = tu_range(&rng, -1.1, 1.1);
        double c = 1 - pow(y0, 4) - pow(z0, 4), x1;
        int h;
        if (fabs(c) < 1e-6) continue;
        h = gg_implicit_intersect(cube, v3(-2, y0, z0), v3(1, 0, 0), 0, INFINITY, &t);
        assert_int_equal(h, c > 0);
        if (!h) continue;
        x1 = -pow(c, 0.25);
        assert_close(t, x1 + 2, 1e-12);
        assert_vec_close(unit_normal(cube, v3(x1, y0, z0)),
                         v3norm(v3(x1 * x1 * x1, y0 * y0 * y0, z0 * z0 * z0)), 1e-12);
        hits++;
    }
    /* Tanglecube: along x, x^2 = (5 +- sqrt(25 - 4C)) / 2; the first hit
       from -x is the larger root's negative square root. */
    for (i = 0; i < 5000; i++) {
        double y0 = tu_range(&rng, -2.5, 2.5), z0 = tu_range(&rng, -2.5, 2.5);
        double C = pow(y0, 4) - 5 * y0 * y0 + pow(z0, 4) - 5 * z0 * z0 + 11.8, disc = 25 - 4 * C;
        double u, x1;
        int want, h;
        if (fabs(disc) < 1e-6) continue;
        u = disc > 0 ? (5 + sqrt(disc)) / 2 : -1;
        want = u > 0 && sqrt(u) < 3;
        if (u > 0 && fabs(sqrt(u) - 3) < 1e-9) continue;
        h = gg_implicit_intersect(tangle, v3(-4, y0, z0), v3(1, 0, 0), 0, INFINITY, &t);
        assert_int_equal(h, want);
        if (!h) continue;
        x1 = -sqrt(u);
        assert_close(t, x1 + 4, 1e-12);
        assert_vec_close(unit_normal(tangle, v3(x1, y0, z0)),
                         v3norm(v3(4 * pow(x1, 3) - 10 * x1, 4 * pow(y0, 3) - 10 * y0,
                                   4 * pow(z0, 3) - 10 * z0)),
                         1e-12);
        hits++;
    }
    assert_true(hits > 4000);
    ggImplicitFree(cube);
    ggImplicitFree(tangle);
}

/* ------------------------------------------------------------------ */
/* Normals by central differences                                      */
/* ------------------------------------------------------------------ */

/* Mean relative error of central differences with step h over points on a
   torus of major radius s, against the exact (dual-number) gradient. */
static double central_error(const ggImplicit *imp, double s, double h)
{
    tu_rng r = {51};
    double sum = 0;
    int i;
    for (i = 0; i < 64; i++) {
        double phi = tu_range(&r, 0, 2 * GG_PI), th = tu_range(&r, 0, 2 * GG_PI);
        double rho = s + 0.25 * s * cos(th);
        ggVec3 p = v3(rho * cos(phi), rho * sin(phi), 0.25 * s * sin(th));
        ggVec3 g = ggGradientNormal(imp, p), c = ggGradientCentral(imp, p, h);
        sum += v3len(v3sub(c, g)) / v3len(g);
    }
    return sum / 64;
}

static void test_central_difference_error_curve(void **state)
{
    static const double scales[] = {1, 1000, 1e-3};
    size_t k;
    (void)state;
    for (k = 0; k < sizeof scales / sizeof scales[0]; k++) {
        double s = scales[k], best = INFINITY, hbest = 0, e_lo, e_hi, h0;
        char src[200];
        ggImplicit *imp;
        int i;
        snprintf(src, sizeof src, "(x^2+y^2+z^2+%.17g-%.17g)^2-4*%.17g*(x^2+y^2)", s * s,
                 s * s / 16, s * s);
        imp = tu_implicit(src, v3(-1.5 * s, -1.5 * s, -0.5 * s), v3(1.5 * s, 1.5 * s, 0.5 * s));
        /* h from 1e-10 s to 1e-1 s, 5 steps per decade. */
        for (i = 0; i <= 45; i++) {
            double h = s * pow(10, -10 + i / 5.0), e = central_error(imp, s, h);
            if (e < best) best = e, hbest = h;
        }
        e_lo = central_error(imp, s, s * 1e-10);
        e_hi = central_error(imp, s, s * 1e-1);
        h0 = cbrt(DBL_EPSILON) * s;
        print_message("scale %g: error min %.2e at h = %.2e (eps^(1/3) s = %.2e, ratio %.2f); "
                      "%.2e at 1e-10 s, %.2e at 0.1 s\n",
                      s, best, hbest, h0, hbest / h0, e_lo, e_hi);
        assert_true(hbest > h0 / 10 && hbest < h0 * 10);
        assert_true(best < 1e-9);
        assert_true(e_lo > 100 * best && e_hi > 100 * best); /* a real U, not a slope */
        /* The default step is near the optimum. */
        assert_true(central_error(imp, s, 0) < 30 * best);
        ggImplicitFree(imp);
    }
}

/* ------------------------------------------------------------------ */
/* Thin parts, near misses, rays leaving the surface                   */
/* ------------------------------------------------------------------ */

/* acc: accuracy relative to r. The quartic form loses precision as the
   tube thins: rounding of f (terms ~4) against |grad f| ~ 8r moves the
   surface by about eps / (2 r^2) relative to r. */
static void check_thin_torus(ggImplicit *imp, double R, double r, double acc, uint64_t seed)
{
    tu_rng rng = {seed};
    int i;
    double t;
    for (i = 0; i < 4000; i++) {
        /* Parallel to z through the tube's cross-section. */
        /* |u| < 0.9 keeps the ray away from grazing, where the error in t
           grows as 1 / sqrt(1 - u^2). */
        double phi = tu_range(&rng, 0, 2 * GG_PI), u = tu_range(&rng, -0.9, 0.9);
        double rho = R + u * r, zt = r * sqrt(1 - u * u);
        ggVec3 o = v3(rho * cos(phi), rho * sin(phi), 1), p, c, d;
        assert_true(gg_implicit_intersect(imp, o, v3(0, 0, -1), 0, INFINITY, &t));
        assert_close((1 - t) / r, zt / r, acc);
        /* Any direction through a point of the centre circle. */
        c = v3(R * cos(phi), R * sin(phi), 0);
        d = tu_unit(&rng);
        o = v3madd(c, d, -tu_range(&rng, 0.05, 1));
        if (!gg_implicit_intersect(imp, o, d, 0, INFINITY, &t))
            print_error("missed: o (%.17g %.17g %.17g) d (%.17g %.17g %.17g) warn %u\n", o.x, o.y,
                        o.z, d.x, d.y, d.z, ggImplicitWarnings(imp));
        assert_true(gg_implicit_intersect(imp, o, d, 0, INFINITY, &t));
        p = v3madd(o, d, t);
        /* On the tube: distance r from the centre circle. */
        {
            double pr = sqrt(p.x * p.x + p.y * p.y);
            assert_close(sqrt((pr - R) * (pr - R) + p.z * p.z) / r, 1.0, 10 * acc);
        }
        /* Just outside the tube (by 100 times the accuracy), parallel to z:
           a miss. */
        o = v3((R + r * (1 + 100 * acc)) * cos(phi), (R + r * (1 + 100 * acc)) * sin(phi), 1);
        assert_false(gg_implicit_intersect(imp, o, v3(0, 0, -1), 0, INFINITY, &t));
    }
}

static void test_thin_parts_not_missed(void **state)
{
    ggImplicit *imp;
    tu_rng rng = {61};
    double t;
    int i;
    (void)state;
    imp =
        tu_implicit("(x^2+y^2+z^2+1-1e-6)^2-4*(x^2+y^2)", v3(-1.1, -1.1, -0.1), v3(1.1, 1.1, 0.1));
    check_thin_torus(imp, 1, 1e-3, 1e-9, 62);
    ggImplicitFree(imp);
    imp =
        tu_implicit("(x^2+y^2+z^2+1-1e-12)^2-4*(x^2+y^2)", v3(-1.1, -1.1, -0.1), v3(1.1, 1.1, 0.1));
    check_thin_torus(imp, 1, 1e-6, 1e-3, 63);
    ggImplicitFree(imp);
    /* A slab 2e-7 thick, crossed at every angle down to near-grazing. */
    imp = tu_implicit("abs(x-0.3)-1e-7", v3(-1, -1, -1), v3(1, 1, 1));
    for (i = 0; i < 4000; i++) {
        ggVec3 o = v3(-0.9, tu_range(&rng, -0.5, 0.5), tu_range(&rng, -0.5, 0.5));
        ggVec3 d = v3norm(v3(pow(10, tu_range(&rng, -3, 0)), tu_range(&rng, -0.3, 0.3),
                             tu_range(&rng, -0.3, 0.3)));
        double want = (0.3 - 1e-7 + 0.9) / d.x;
        ggVec3 p = v3madd(o, d, want);
        if (fabs(p.y) > 0.99 || fabs(p.z) > 0.99) continue;
        assert_true(gg_implicit_intersect(imp, o, d, 0, INFINITY, &t));
        assert_close(t, want, 1e-12);
    }
    ggImplicitFree(imp);
}

static void test_no_false_hits(void **state)
{
    static const double margins[] = {1e-4, 1e-7, 1e-9, 1e-11};
    ggImplicit *sph = tu_implicit("x^2+y^2+z^2-1", v3(-2, -2, -2), v3(2, 2, 2));
    ggImplicit *tor = tu_implicit("(x^2+y^2+z^2+1-0.0625)^2-4*(x^2+y^2)", v3(-1.5, -1.5, -0.5),
                                  v3(1.5, 1.5, 0.5));
    tu_rng rng = {71};
    size_t m;
    int i;
    double t;
    (void)state;
    for (m = 0; m < sizeof margins / sizeof margins[0]; m++) {
        for (i = 0; i < 500; i++) {
            /* A line whose closest approach to the centre is 1 +- margin. */
            ggVec3 n = tu_unit(&rng), d = v3norm(v3cross(n, tu_unit(&rng)));
            ggVec3 po = v3scale(n, 1 + margins[m]), pi = v3scale(n, 1 - margins[m]);
            double back = tu_range(&rng, 2, 4);
            assert_false(gg_implicit_intersect(sph, v3madd(po, d, -back), d, 0, INFINITY, &t));
            assert_true(gg_implicit_intersect(sph, v3madd(pi, d, -back), d, 0, INFINITY, &t));
            assert_true(t < back);
            /* Torus: parallel to z, just outside / inside the outer rim. */
            {
                double phi = tu_range(&rng, 0, 2 * GG_PI), ro = 1.25 * (1 + margins[m]);
                double ri = 1.25 * (1 - margins[m]);
                assert_false(gg_implicit_intersect(tor, v3(ro * cos(phi), ro * sin(phi), 1),
                                                   v3(0, 0, -1), 0, INFINITY, &t));
                assert_true(gg_implicit_intersect(tor, v3(ri * cos(phi), ri * sin(phi), 1),
                                                  v3(0, 0, -1), 0, INFINITY, &t));
            }
        }
    }
    ggImplicitFree(sph);
    ggImplicitFree(tor);
}

/* Leaving a hit point, pushed off by a few ulps along the normal to the
   side the new ray goes to: no re-hit of the same spot. */
static void check_leaving(ggImplicit *imp, int convex, double scale, uint64_t seed)
{
    tu_rng rng = {seed};
    ggVec3 lo, hi, ctr;
    int i, n = 0, rehits = 0;
    gg_implicit_bounds(imp, &lo, &hi);
    ctr = v3scale(v3add(lo, hi), 0.5);
    for (i = 0; i < 6000; i++) {
        ggVec3 o = v3add(ctr, v3scale(tu_unit(&rng), 3 * scale)), p, nrm, d, u, w, o2;
        ggVec3 aim = v3add(ctr, v3scale(tu_unit(&rng), 0.8 * scale));
        double t, t2, eps, cosang;
        int inward = i % 3 == 0, h;
        if (!gg_implicit_intersect(imp, o, v3sub(aim, o), 0, INFINITY, &t)) continue;
        p = v3madd(o, v3sub(aim, o), t);
        nrm = unit_normal(imp, p);
        if (v3dot(nrm, v3sub(aim, o)) > 0) nrm = v3neg(nrm); /* face the incoming ray */
        /* A direction in the hemisphere the new ray goes to, often grazing. */
        u = v3norm(v3cross(nrm, fabs(nrm.x) < 0.9 ? v3(1, 0, 0) : v3(0, 1, 0)));
        w = v3cross(nrm, u);
        cosang = i % 2 ? pow(10, tu_range(&rng, -6, 0)) : tu_uniform(&rng);
        {
            double a = tu_range(&rng, 0, 2 * GG_PI), s = sqrt(1 - cosang * cosang);
            d = v3add(v3scale(nrm, cosang), v3add(v3scale(u, s * cos(a)), v3scale(w, s * sin(a))));
        }
        if (inward) d = v3neg(d), nrm = v3neg(nrm);
        eps = 64 * DBL_EPSILON * v3maxabs(p) + 64 * DBL_EPSILON * scale;
        o2 = v3madd(p, nrm, eps);
        h = gg_implicit_intersect(imp, o2, d, 0, INFINITY, &t2);
        n++;
        /* A genuine second hit of a saddle region needs t > ~cos r / 2
           (normal curvature at most 1 / r = 4 / scale); the same spot
           found again would be at t ~ 0. */
        if (h && t2 < 1e-3 * cosang * scale) {
            rehits++;
            print_error("re-hit at t = %g leaving (%g %g %g), cos %g, %s\n", t2, p.x, p.y, p.z,
                        cosang, inward ? "inward" : "outward");
        }
        if (convex && !inward && h) {
            print_error("outward ray from a convex surface hit at t = %g (cos %g)\n", t2, cosang);
            rehits++;
        }
        if (convex && inward && cosang > 1e-3) {
            /* Through the inside to the far side: a chord, not a re-hit. */
            assert_true(h);
            assert_true(t2 > 1e-3 * scale);
        }
    }
    assert_true(n > 3000);
    assert_int_equal(rehits, 0);
}

/* Without any offset: a ray from a hit point as computed (within rounding
   of the surface, on either side) does not find that surface at t ~ 0. */
static void test_origin_on_surface(void **state)
{
    ggImplicit *imp =
        tu_implicit("(x-0.1)^2+(y+0.2)^2+(z-0.3)^2-0.64", v3(-1.5, -1.5, -1.5), v3(1.5, 1.5, 1.5));
    tu_rng rng = {95};
    int i, n = 0;
    (void)state;
    /* Points on the sphere, rounded to doubles, and directions around them. */
    for (i = 0; i < 20000; i++) {
        ggVec3 c = v3(0.1, -0.2, 0.3), p, nrm, d;
        double t2, cosang;
        int inward = i % 2, h;
        nrm = tu_unit(&rng);
        p = v3madd(c, nrm, 0.8);
        cosang = i % 4 < 2 ? pow(10, tu_range(&rng, -3, 0)) : tu_uniform(&rng);
        {
            ggVec3 u = v3norm(v3cross(nrm, fabs(nrm.x) < 0.9 ? v3(1, 0, 0) : v3(0, 1, 0)));
            ggVec3 w = v3cross(nrm, u);
            double a = tu_range(&rng, 0, 2 * GG_PI), s = sqrt(1 - cosang * cosang);
            d = v3add(v3scale(nrm, cosang), v3add(v3scale(u, s * cos(a)), v3scale(w, s * sin(a))));
        }
        if (inward) d = v3neg(d);
        h = gg_implicit_intersect(imp, p, d, 0, INFINITY, &t2);
        n++;
        if (!inward) {
            if (h) print_error("outward from the surface, hit at t = %g\n", t2);
            assert_false(h);
        } else {
            /* The chord to the far side: 2 * 0.8 * cos. */
            if (!h)
                print_error("inward miss: p (%.17g, %.17g, %.17g) d (%.17g, %.17g, %.17g) cos %g\n",
                            p.x, p.y, p.z, d.x, d.y, d.z, cosang);
            assert_true(h);
            assert_close(t2, 1.6 * cosang, 1e-9);
        }
    }
    assert_true(n == 20000);
    ggImplicitFree(imp);
}

static void test_leaving_rays_do_not_rehit(void **state)
{
    static const double scales[] = {1e-6, 1, 1e6};
    size_t k;
    (void)state;
    for (k = 0; k < sizeof scales / sizeof scales[0]; k++) {
        double s = scales[k];
        char src[256];
        ggImplicit *imp;
        snprintf(src, sizeof src, "(x-%.17g)^2+(y-%.17g)^2+(z+%.17g)^2-%.17g", 3 * s, s, 2 * s,
                 s * s);
        imp = tu_implicit(src, v3(1.5 * s, -0.5 * s, -3.5 * s), v3(4.5 * s, 2.5 * s, -0.5 * s));
        check_leaving(imp, 1, s, 81 + k);
        ggImplicitFree(imp);
        snprintf(src, sizeof src, "(x^2+y^2+z^2+%.17g-%.17g)^2-4*%.17g*(x^2+y^2)", s * s,
                 s * s / 16, s * s);
        imp = tu_implicit(src, v3(-1.5 * s, -1.5 * s, -0.5 * s), v3(1.5 * s, 1.5 * s, 0.5 * s));
        check_leaving(imp, 0, s, 91 + k);
        ggImplicitFree(imp);
    }
}

/* ------------------------------------------------------------------ */
/* Domains, poles, callbacks, warnings                                 */
/* ------------------------------------------------------------------ */

static void test_domains_and_poles(void **state)
{
    ggImplicit *imp;
    double t;
    (void)state;
    /* sqrt is undefined for x < 0: the root at x = 0.25 is still found. */
    imp = tu_implicit("sqrt(x) - 0.5", v3(-1, -1, -1), v3(1, 1, 1));
    assert_true(gg_implicit_intersect(imp, v3(-2, 0, 0), v3(1, 0, 0), 0, INFINITY, &t));
    assert_close(t, 2.25, 1e-13);
    ggImplicitFree(imp);
    /* 1/x - 1 flips sign at the pole x = 0: not a root. */
    imp = tu_implicit("1/x - 1", v3(-2, -1, -1), v3(2, 1, 1));
    assert_true(gg_implicit_intersect(imp, v3(-3, 0, 0), v3(1, 0, 0), 0, INFINITY, &t));
    assert_close(t, 4, 1e-13);
    ggImplicitFree(imp);
    /* tan(x) - 2 between poles: roots atan(2) + k pi only. */
    imp = tu_implicit("tan(x) - 2", v3(-1, -1, -1), v3(5, 1, 1));
    assert_true(gg_implicit_intersect(imp, v3(-1, 0, 0), v3(1, 0, 0), 0, INFINITY, &t));
    assert_close(t, 1 + atan(2.0), 1e-13);
    assert_true(
        gg_implicit_intersect(imp, v3(-1, 0, 0), v3(1, 0, 0), 1 + atan(2.0) + 0.1, INFINITY, &t));
    assert_close(t, 1 + atan(2.0) + GG_PI, 1e-13);
    ggImplicitFree(imp);
    /* A surface defined nowhere. */
    imp = tu_implicit("sqrt(-1-x^2)", v3(-1, -1, -1), v3(1, 1, 1));
    assert_false(gg_implicit_intersect(imp, v3(-2, 0, 0), v3(1, 0, 0), 0, INFINITY, &t));
    ggImplicitFree(imp);
    /* x - x + 1 never vanishes; interval arithmetic alone cannot see that
       (X - X contains 0), the derivative enclosure does, quickly. */
    imp = tu_implicit("x - x + 1e-3", v3(-1, -1, -1), v3(1, 1, 1));
    {
        gg_implicit_status st;
        assert_false(gg_implicit_intersect_status(imp, v3(-2, 0.1, 0), v3(1, 0.01, 0), 0, INFINITY,
                                                  &t, &st));
        assert_true(st.evals < 100);
    }
    ggImplicitFree(imp);
}

/* "a^n with a constant integer n is defined for every a" (implicit.h),
   however large n: small ones are multiplied out, those past 1e9 go to
   pow, which must then take negative bases too (x^2000000000 was NaN at
   x = -1 and its surface missed on that side). Whole exponents from 2 to
   1e300, both signs, both parities: the value at -x is +-(value at x),
   finite where that is, and the surface |x|^n + y^2 + z^2 = 2 is hit from
   both sides at the same distance. */
static void test_whole_powers_everywhere(void **state)
{
    static const double ns[] = {2,          3,          999999999,  1000000000, 1000000001,
                                1000000002, 2000000000, 4294967297, 1e10,       9007199254740991.0,
                                0x1p53,     1e17,       1e300};
    static const double xs[] = {0.5, 0.999, 1, 1.0001, 2};
    size_t i, j;
    int sgn, hits = 0, even = 0;
    (void)state;
    for (i = 0; i < sizeof ns / sizeof ns[0]; i++)
        for (sgn = 1; sgn >= -1; sgn -= 2) {
            double n = sgn * ns[i], odd = fabs(n) < 0x1p53 && fmod(n, 2) != 0;
            char expr[96], surf[128];
            ggImplicit *imp;
            double t1 = 0, t2 = 0;
            int h1, h2;
            snprintf(expr, sizeof expr, "x^%.17g", n);
            imp = tu_implicit(expr, v3(-3, -3, -3), v3(3, 3, 3));
            for (j = 0; j < sizeof xs / sizeof xs[0]; j++) {
                double fp = ggImplicitEval(imp, v3(xs[j], 0, 0));
                double fm = ggImplicitEval(imp, v3(-xs[j], 0, 0));
                if (!(fm == (odd ? -fp : fp)))
                    print_error("%s at +-%g: %g and %g\n", expr, xs[j], fp, fm);
                assert_true(fm == (odd ? -fp : fp));
                assert_true(isfinite(fp) == isfinite(fm));
            }
            ggImplicitFree(imp);
            if (n < 0 || odd) continue;
            /* x^n + y^2 + z^2 - 2: |x| = 1 at y = 1, z = 0. From 2^53 on f
               jumps from -1 to inf within an ulp of |x| = 1, a step the root
               finder does not see: on neither side then. */
            snprintf(surf, sizeof surf, "x^%.17g + y^2 + z^2 - 2", n);
            imp = tu_implicit(surf, v3(-3, -3, -3), v3(3, 3, 3));
            h1 = gg_implicit_intersect(imp, v3(-2.5, 1, 0), v3(1, 0, 0), 0, INFINITY, &t1);
            h2 = gg_implicit_intersect(imp, v3(2.5, 1, 0), v3(-1, 0, 0), 0, INFINITY, &t2);
            if (h1 != h2 || (h1 && fabs(t1 - t2) > 1e-9) || (n <= 1e10 && !h1))
                print_error("%s: hit %d at %.17g from -x, %d at %.17g from +x\n", surf, h1, t1, h2,
                            t2);
            assert_int_equal(h1, h2);
            assert_true(!h1 || fabs(t1 - t2) <= 1e-9);
            assert_true(h1 || n > 1e10);
            hits += h1, even++;
            ggImplicitFree(imp);
        }
    print_message("whole powers: %d of %d even surfaces hit, each from both sides alike\n", hits,
                  even);
}

static double cb_sphere(void *ud, ggVec3 p)
{
    (*(int *)ud)++;
    return p.x * p.x + p.y * p.y + p.z * p.z - 1;
}
static double cb_sphere_plain(void *ud, ggVec3 p)
{
    (void)ud;
    return p.x * p.x + p.y * p.y + p.z * p.z - 1;
}
static ggVec3 cb_sphere_grad(void *ud, ggVec3 p)
{
    (void)ud;
    return v3(2 * p.x, 2 * p.y, 2 * p.z);
}
/* Signed distance to the torus R = 1, tube radius *ud: |grad f| = 1. */
static double cb_torus(void *ud, ggVec3 p)
{
    double rho = sqrt(p.x * p.x + p.y * p.y) - 1;
    return sqrt(rho * rho + p.z * p.z) - *(double *)ud;
}

static void test_callbacks(void **state)
{
    tu_rng rng = {101};
    int calls = 0, i, pass, hits = 0;
    ggImplicit *imp;
    double t, tw, disc;
    (void)state;
    for (pass = 0; pass < 2; pass++) {
        assert_int_equal(ggImplicitCreateFn(cb_sphere, pass ? cb_sphere_grad : NULL, &calls,
                                            v3(-2, -2, -2), v3(2, 2, 2), NULL, &imp, NULL),
                         GG_OK);
        /* The estimate: |grad f| reaches 2 sqrt(12) at the corners; with
           the gradient known the bound is twice that, from differences
           along the axes it is 2 * 3.75 (from x = 1.75 to 2). */
        assert_true(ggImplicitGradientBound(imp) > 2 * sqrt(12.0) &&
                    ggImplicitGradientBound(imp) < 14);
        assert_true(calls >= 17 * 17 * 17);
        for (i = 0; i < 3000; i++) {
            ggVec3 o = v3scale(tu_unit(&rng), tu_range(&rng, 2.5, 6));
            ggVec3 d = v3sub(v3scale(tu_unit(&rng), tu_range(&rng, 0, 1.3)), o);
            int h, want = sphere_hit(v3(0, 0, 0), 1, o, d, 0, &tw, &disc);
            if (fabs(disc) < 1e-8) continue;
            h = gg_implicit_intersect(imp, o, d, 0, INFINITY, &t);
            assert_int_equal(h, want);
            if (!h) continue;
            hits++;
            assert_close(t, tw, 1e-12);
            assert_vec_close(unit_normal(imp, v3madd(o, d, t)), v3norm(v3madd(o, d, tw)),
                             pass ? 1e-12 : 1e-9);
        }
        /* An honest bound raises no warning; the slopes seen stay below it. */
        assert_int_equal(ggImplicitWarnings(imp), 0);
        assert_true(ggImplicitMaxSlope(imp) > 1 && ggImplicitMaxSlope(imp) < 2 * sqrt(12.0));
        /* A bound 100 times too small is noticed. */
        assert_int_equal(ggImplicitSetGradientBound(imp, 0.07), GG_OK);
        for (i = 0; i < 50; i++) {
            ggVec3 o = v3scale(tu_unit(&rng), 5);
            gg_implicit_intersect(imp, o, v3neg(o), 0, INFINITY, &t);
        }
        assert_true(ggImplicitWarnings(imp) & GG_IMPLICIT_WARN_GRADIENT);
        assert_true(ggImplicitMaxSlope(imp) > 1);
        ggImplicitClearWarnings(imp);
        assert_int_equal(ggImplicitWarnings(imp), 0);
        assert_true(ggImplicitMaxSlope(imp) == 0);
        ggImplicitFree(imp);
    }
    assert_true(hits > 2000);
}

/* Stepping by |f| / L suits distance-like callbacks. (The quartic form of
   a thin torus behaves like distance^2, and like distance^4 along a ray
   tangent to the tube's centre circle: |f| / L steps then crawl, which is
   what the interval method on expressions is for.) */
static void test_callback_thin_torus(void **state)
{
    double r = 1e-3;
    ggImplicit *imp;
    (void)state;
    assert_int_equal(ggImplicitCreateFn(cb_torus, NULL, &r, v3(-1.1, -1.1, -0.1), v3(1.1, 1.1, 0.1),
                                        NULL, &imp, NULL),
                     GG_OK);
    assert_int_equal(ggImplicitSetGradientBound(imp, 1), GG_OK);
    check_thin_torus(imp, 1, 1e-3, 1e-9, 111);
    assert_int_equal(ggImplicitWarnings(imp), 0);
    ggImplicitFree(imp);
}

static void test_lipschitz_method_on_expressions(void **state)
{
    tu_rng rng = {121};
    ggImplicit *a = tu_implicit("(x^2+y^2+z^2+1-0.0625)^2-4*(x^2+y^2)", v3(-1.5, -1.5, -0.5),
                                v3(1.5, 1.5, 0.5));
    ggImplicit *b = tu_implicit("(x^2+y^2+z^2+1-0.0625)^2-4*(x^2+y^2)", v3(-1.5, -1.5, -0.5),
                                v3(1.5, 1.5, 0.5));
    int i, same = 0;
    (void)state;
    assert_int_equal(ggImplicitSetMethod(b, GG_IMPLICIT_LIPSCHITZ), GG_OK);
    assert_true(ggImplicitGradientBound(b) > 0);
    for (i = 0; i < 3000; i++) {
        ggVec3 o = v3scale(tu_unit(&rng), 3), d = v3sub(rand_in(&rng, -1.3, 1.3), o);
        double ta, tb;
        int ha = gg_implicit_intersect(a, o, d, 0, INFINITY, &ta);
        int hb = gg_implicit_intersect(b, o, d, 0, INFINITY, &tb);
        assert_int_equal(ha, hb);
        if (ha) assert_close(ta, tb, 1e-10);
        same += ha;
    }
    assert_true(same > 500);
    assert_int_equal(ggImplicitWarnings(b), 0);
    ggImplicitFree(a);
    ggImplicitFree(b);
}

/* Several threads on the same objects: the same hits as one thread, and
   the warnings (written atomically) seen from any of them. */
typedef struct job {
    const ggImplicit *imp;
    uint64_t seed;
    int n;
    double *t; /* n results, NAN for a miss */
} job;

static void *run_job(void *arg)
{
    job *j = arg;
    tu_rng r;
    int i;
    r.s = j->seed;
    for (i = 0; i < j->n; i++) {
        ggVec3 o = v3scale(tu_unit(&r), 3), d = v3sub(rand_in(&r, -1, 1), o);
        double t;
        j->t[i] = gg_implicit_intersect(j->imp, o, d, 0, INFINITY, &t) ? t : NAN;
    }
    return NULL;
}

static void test_threads(void **state)
{
    enum { N = 3000, THREADS = 4 };
    static double serial[N], par[THREADS][N];
    ggImplicit *objs[2];
    int k, i;
    (void)state;
    objs[0] =
        tu_implicit("(x^2+y^2+z^2+0.9375)^2-4*(x^2+y^2)", v3(-1.5, -1.5, -0.5), v3(1.5, 1.5, 0.5));
    assert_int_equal(ggImplicitCreateFn(cb_sphere_plain, cb_sphere_grad, NULL, v3(-2, -2, -2),
                                        v3(2, 2, 2), NULL, &objs[1], NULL),
                     GG_OK);
    /* Too small a bound: every thread raises the warning. */
    assert_int_equal(ggImplicitSetGradientBound(objs[1], 0.5), GG_OK);
    for (k = 0; k < 2; k++) {
        job js = {objs[k], 200 + (uint64_t)k, N, serial}, jp[THREADS];
        pthread_t th[THREADS];
        run_job(&js);
        ggImplicitClearWarnings(objs[k]);
        for (i = 0; i < THREADS; i++) {
            jp[i] = js;
            jp[i].t = par[i];
            assert_int_equal(pthread_create(&th[i], NULL, run_job, &jp[i]), 0);
        }
        for (i = 0; i < THREADS; i++) assert_int_equal(pthread_join(th[i], NULL), 0);
        for (i = 0; i < THREADS; i++)
            assert_memory_equal(serial, par[i], sizeof serial); /* bit for bit, NaN for misses */
        assert_int_equal(ggImplicitWarnings(objs[k]), k == 1 ? GG_IMPLICIT_WARN_GRADIENT : 0);
        if (k == 1) assert_true(ggImplicitMaxSlope(objs[k]) > 0.5);
    }
    assert_true(gg_implicit_tolerance(objs[0]) > 0 && gg_implicit_tolerance(objs[0]) < 1e-11);
    ggImplicitFree(objs[0]);
    ggImplicitFree(objs[1]);
}

static void test_budget_warning(void **state)
{
    /* Never 0, but near x = 0 neither the enclosure of s - s (s oscillating
       without end) nor that of its derivative can show it: far more than
       16 evaluations. */
    ggImplicit *imp = tu_implicit("sin(1/x) - sin(1/x) + 1e-3", v3(-1, -1, -1), v3(1, 1, 1));
    double t;
    (void)state;
    assert_int_equal(ggImplicitSetBudget(imp, 16), GG_OK);
    assert_int_equal(ggImplicitWarnings(imp), 0);
    assert_false(gg_implicit_intersect(imp, v3(-2, 0.013, 0.3), v3(1, 0.001, 0), 0, INFINITY, &t));
    assert_true(ggImplicitWarnings(imp) & GG_IMPLICIT_WARN_BUDGET);
    ggImplicitFree(imp);
}

/* An expression divided by zero is undefined everywhere: no hit, found
   without subdividing the ray to the end of its budget (the fuzz finding
   tests/fuzz/corpus/nff/slow-divide-by-zero.nff took 47 s for a 4x3 image). */
static void test_divide_by_zero_pruned(void **state)
{
    ggImplicit *imp = tu_implicit("x^4+y^2+z^2/0", v3(-1.1, -0.1, -1.1), v3(1, 1.1, 1.1));
    double t;
    (void)state;
    assert_false(gg_implicit_intersect(imp, v3(-2, 0.05, 0.3), v3(1, 0, 0.01), 0, INFINITY, &t));
    assert_false(gg_implicit_intersect(imp, v3(0.2, 0.5, -3), v3(0, 0, 1), 0, INFINITY, &t));
    assert_int_equal(ggImplicitWarnings(imp), 0);
    ggImplicitFree(imp);
}

/* A 64x48 render (one thread) of scene text with one implicit surface:
   its statistics and wall-clock seconds. */
static ggRayStats render_implicit(const char *expr, const char *view, double *secs)
{
    char text[512];
    ggScene *s = ggSceneCreate(NULL);
    ggRenderOptions o;
    ggRayStats st;
    ggImage *img = NULL;
    ggError err;
    double t0;
    snprintf(text, sizeof text,
             "v from %s at 0 0 0 up 0 0 1 angle 40 resolution 64 48\nl 3 -3 5\n"
             "f 0.9 0.3 0.2 0.7 0.3 40 0 0\nimplicit \"%s\" -1.4 -1.4 -1.4 1.4 1.4 1.4\n",
             view, expr);
    assert_int_equal(ggSceneLoadString(s, text, strlen(text), "t.nff", &err), GG_OK);
    ggRenderOptionsDefault(&o);
    o.threads = 1;
    t0 = gg_time_now();
    assert_int_equal(ggRender(s, &o, &img, &st, &err), GG_OK);
    *secs = gg_time_now() - t0;
    ggImageFree(img);
    ggSceneFree(s);
    return st;
}

/* x^-1000000000 - 1 rendered for minutes, every ray using its
   100000 evaluations (x^n underflowing to [0, 0] was widened below 0, so
   1 / x^n was the whole line). Rays that do run out are counted in
   ggRayStats.implicit_cut, with the default budget of an expression (at
   most 4096 evaluations) keeping them cheap. */
static void test_bounded_time(void **state)
{
    double secs, wild_secs;
    ggRayStats st = render_implicit("x^-1000000000 - 1", "0 -4 2", &secs), wild;
    (void)state;
    print_message("x^-1000000000 - 1: %llu of 3072 eye rays hit, %llu tests out of budget, "
                  "%.2f s\n",
                  (unsigned long long)st.eye_hit, (unsigned long long)st.implicit_cut, secs);
    assert_true(st.eye_hit > 1000); /* the planes |x| = 1 are there */
    assert_int_equal(st.implicit_cut, 0);
    /* no root, and no enclosure near x = 0 can show it */
    wild = render_implicit("sin(1/x) - sin(1/x) + 1e-3", "3 -3 0.3", &wild_secs);
    print_message("sin(1/x) - sin(1/x) + 1e-3: %llu tests out of budget, %.2f s\n",
                  (unsigned long long)wild.implicit_cut, wild_secs);
    assert_int_equal(wild.eye_hit, 0);
    assert_true(wild.implicit_cut > 1000);
    assert_true(wild.implicit_cut <= wild.eye + wild.shadow);
}

static void test_api_arguments(void **state)
{
    ggImplicit *imp = NULL;
    ggError err;
    ggVec3 lo, hi;
    double t;
    int calls = 0;
    (void)state;
    assert_int_equal(ggImplicitCreateExpr(NULL, v3(0, 0, 0), v3(1, 1, 1), NULL, &imp, &err),
                     GG_ERROR_INVALID);
    assert_int_equal(ggImplicitCreateExpr("x", v3(0, 0, 0), v3(1, 1, 1), NULL, NULL, &err),
                     GG_ERROR_INVALID);
    assert_int_equal(ggImplicitCreateExpr("x", v3(0, 0, 0), v3(1, 0, 1), NULL, &imp, &err),
                     GG_ERROR_INVALID);
    assert_int_equal(ggImplicitCreateExpr("x", v3(0, 0, 0), v3(1, INFINITY, 1), NULL, &imp, &err),
                     GG_ERROR_INVALID);
    /* a box whose diagonal overflows: its tolerance would be infinite and
       nothing ever hit (one of +-1e308 was accepted) */
    assert_int_equal(ggImplicitCreateExpr("x^2+y^2+z^2-1", v3(-1e308, -1e308, -1e308),
                                          v3(1e308, 1e308, 1e308), NULL, &imp, &err),
                     GG_ERROR_INVALID);
    assert_int_equal(ggImplicitCreateFn(cb_sphere_plain, NULL, NULL, v3(-1e155, -1, -1),
                                        v3(1e155, 1, 1), NULL, &imp, &err),
                     GG_ERROR_INVALID);
    {
        /* a unit sphere in a box of 1e60 (scenes allow 1e64): the default
           tolerance (1e-12 of the diagonal) is larger than the sphere; with
           1e-12 it is found, 2^190 times smaller than the segment (the
           subdivision stopped at 2^-99 and missed it without a word). In a
           box of 1e150 it is past the depth: a miss that says so. */
        ggRay r = {{-3, 0.1, 0.2}, {1, 0, 0}};
        double side[2] = {1e60, 1e150};
        int b;
        for (b = 0; b < 2; b++) {
            assert_int_equal(ggImplicitCreateExpr("x^2+y^2+z^2-1", v3(-side[b], -side[b], -side[b]),
                                                  v3(side[b], side[b], side[b]), NULL, &imp, &err),
                             GG_OK);
            assert_int_equal(ggImplicitSetTolerance(imp, 1e-12), GG_OK);
            assert_int_equal(ggImplicitIntersect(imp, r, 0, INFINITY, &t), b == 0);
            if (b == 0) assert_true(fabs(t - (3 - sqrt(1 - 0.05))) < 1e-9);
            assert_int_equal(ggImplicitWarnings(imp), b == 0 ? 0u : GG_IMPLICIT_WARN_BUDGET);
            if (b == 0) ggImplicitFree(imp);
        }
    }
    ggImplicitFree(imp);
    imp = NULL;
    assert_int_equal(
        ggImplicitCreateFn(NULL, NULL, NULL, v3(0, 0, 0), v3(1, 1, 1), NULL, &imp, &err),
        GG_ERROR_INVALID);
    assert_null(imp);
    assert_int_equal(
        ggImplicitCreateFn(cb_sphere, NULL, &calls, v3(0, 0, 0), v3(1, 1, 1), NULL, &imp, &err),
        GG_OK);
    assert_int_equal(ggImplicitSetMethod(imp, GG_IMPLICIT_INTERVAL), GG_ERROR_UNSUPPORTED);
    assert_int_equal(ggImplicitSetMethod(imp, 7), GG_ERROR_INVALID);
    assert_int_equal(ggImplicitSetTolerance(imp, 0), GG_ERROR_INVALID);
    assert_int_equal(ggImplicitSetTolerance(imp, NAN), GG_ERROR_INVALID);
    assert_int_equal(ggImplicitSetTolerance(imp, 1e-9), GG_OK);
    assert_int_equal(ggImplicitSetGradientBound(imp, -1), GG_ERROR_INVALID);
    assert_int_equal(ggImplicitSetGradientBound(imp, INFINITY), GG_ERROR_INVALID);
    assert_int_equal(ggImplicitSetBudget(imp, 3), GG_ERROR_INVALID);
    ggImplicitBounds(imp, &lo, &hi);
    assert_true(lo.x == 0 && hi.z == 1);
    /* Degenerate rays are misses, not crashes. */
    assert_false(gg_implicit_intersect(imp, v3(0.5, 0.5, -1), v3(0, 0, 0), 0, INFINITY, &t));
    assert_false(gg_implicit_intersect(imp, v3(NAN, 0.5, -1), v3(0, 0, 1), 0, INFINITY, &t));
    assert_false(gg_implicit_intersect(imp, v3(0.5, 0.5, -1), v3(0, 0, 1), 5, 1, &t));
    {
        ggRay ray;
        ray.o = v3(0.5, 0.5, -1), ray.d = v3(0, 0, 1);
        assert_true(ggImplicitIntersect(imp, ray, 0, INFINITY, &t)); /* z = sqrt(0.5) */
        assert_close(t, 1 + sqrt(0.5), 1e-9);
        /* Axis-parallel ray outside the box's slab: clipped away. */
        ray.o = v3(1.5, 0.5, -1);
        assert_false(ggImplicitIntersect(imp, ray, 0, INFINITY, &t));
    }
    ggImplicitFree(imp);
    ggImplicitFree(NULL);
    assert_true(isnan(ggImplicitEval(NULL, v3(0, 0, 0))));
}

static int live_allocs;
static void *c_malloc(void *ud, size_t n)
{
    (void)ud;
    live_allocs++;
    return malloc(n);
}
static void *c_realloc(void *ud, void *p, size_t n)
{
    (void)ud;
    if (!p) live_allocs++;
    return realloc(p, n);
}
static void c_free(void *ud, void *p)
{
    (void)ud;
    if (p) live_allocs--;
    free(p);
}

static void test_allocator_and_no_leaks(void **state)
{
    ggAllocator a = {c_malloc, c_realloc, c_free, NULL};
    static const char *srcs[] = {"x^2+y^2+z^2-1", "sinn(x)", "(x", "1e999", "min(x)"};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof srcs / sizeof srcs[0]; i++) {
        ggImplicit *imp = NULL;
        int rc = ggImplicitCreateExpr(srcs[i], v3(-1, -1, -1), v3(1, 1, 1), &a, &imp, NULL);
        assert_int_equal(rc, i == 0 ? GG_OK : GG_ERROR_PARSE);
        if (i == 0) assert_true(live_allocs > 0);
        ggImplicitFree(imp);
        assert_int_equal(live_allocs, 0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere_matches_analytic),
        cmocka_unit_test(test_torus_closed_form),
        cmocka_unit_test(test_quartic_blobs),
        cmocka_unit_test(test_central_difference_error_curve),
        cmocka_unit_test(test_thin_parts_not_missed),
        cmocka_unit_test(test_no_false_hits),
        cmocka_unit_test(test_origin_on_surface),
        cmocka_unit_test(test_leaving_rays_do_not_rehit),
        cmocka_unit_test(test_domains_and_poles),
        cmocka_unit_test(test_whole_powers_everywhere),
        cmocka_unit_test(test_callbacks),
        cmocka_unit_test(test_callback_thin_torus),
        cmocka_unit_test(test_lipschitz_method_on_expressions),
        cmocka_unit_test(test_threads),
        cmocka_unit_test(test_budget_warning),
        cmocka_unit_test(test_divide_by_zero_pruned),
        cmocka_unit_test(test_bounded_time),
        cmocka_unit_test(test_api_arguments),
        cmocka_unit_test(test_allocator_and_no_leaks),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
