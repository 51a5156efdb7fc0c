/* SPDX-License-Identifier: MIT */
/*
** bench_implicit.c -- implicit surfaces: hit throughput on the eye rays of
** a 512 x 512 view of a torus and of a sphere, per way of giving f
** (expression with interval arithmetic or Lipschitz stepping, C callback),
** and the cost of a normal: exact dual numbers against central differences.
** Single-threaded.   make bench-implicit
*/
#include "implicit.h"
#include "vec.h"

#include <stdio.h>
#include <stdlib.h>

#define W 512
#define H 512

/* ---- callbacks ---- */

static double cb_torus(void *ud, ggVec3 p) /* quartic, R = 1, r = 0.25 */
{
    double s = p.x * p.x + p.y * p.y + p.z * p.z + 0.9375;
    (void)ud;
    return s * s - 4 * (p.x * p.x + p.y * p.y);
}
static ggVec3 cb_torus_grad(void *ud, ggVec3 p)
{
    double s = p.x * p.x + p.y * p.y + p.z * p.z + 0.9375;
    (void)ud;
    return v3(4 * s * p.x - 8 * p.x, 4 * s * p.y - 8 * p.y, 4 * s * p.z);
}
static double cb_torus_sdf(void *ud, ggVec3 p) /* signed distance: |grad| = 1 */
{
    double q = sqrt(p.x * p.x + p.y * p.y) - 1;
    (void)ud;
    return sqrt(q * q + p.z * p.z) - 0.25;
}
static double cb_sphere(void *ud, ggVec3 p)
{
    (void)ud;
    return p.x * p.x + p.y * p.y + p.z * p.z - 1;
}
static ggVec3 cb_sphere_grad(void *ud, ggVec3 p)
{
    (void)ud;
    return v3(2 * p.x, 2 * p.y, 2 * p.z);
}

/* Eye rays of a pinhole camera at `eye` looking at the origin, 40 degree
   field of view, one per pixel centre. */
static void eye_ray(ggVec3 eye, int i, int j, ggVec3 *d)
{
    ggVec3 fwd = v3norm(v3neg(eye)), right = v3norm(v3cross(fwd, v3(0, 0, 1)));
    ggVec3 up = v3cross(right, fwd);
    double s = tan(20 * GG_PI / 180), u = ((i + 0.5) / W * 2 - 1) * s,
           v = (1 - (j + 0.5) / H * 2) * s;
    *d = v3norm(v3add(fwd, v3add(v3scale(right, u), v3scale(up, v))));
}

typedef struct result {
    double seconds, evals_per_ray, t_sum;
    long hits;
} result;

static result trace(const ggImplicit *imp, ggVec3 eye)
{
    result r = {0, 0, 0, 0};
    double t0 = gg_time_now(), evals = 0;
    int i, j;
    for (j = 0; j < H; j++) {
        for (i = 0; i < W; i++) {
            ggVec3 d;
            double t;
            gg_implicit_status st;
            eye_ray(eye, i, j, &d);
            if (gg_implicit_intersect_status(imp, eye, d, 0, INFINITY, &t, &st)) {
                ggVec3 n = ggGradientNormal(imp, v3madd(eye, d, t)); /* shading needs it */
                r.hits++;
                r.t_sum += t + 0 * n.x;
            }
            evals += (double)st.evals;
            gg_implicit_note(imp, &st);
        }
    }
    r.seconds = gg_time_now() - t0;
    r.evals_per_ray = evals / (W * H);
    return r;
}

static void row(const char *shape, const char *how, const ggImplicit *imp, ggVec3 eye,
                const result *ref)
{
    result r = trace(imp, eye);
    printf("%-7s %-34s %7.3f s %7.2f Mray/s %7ld hits %8.1f evals/ray  warn %u", shape, how,
           r.seconds, W * H / r.seconds * 1e-6, r.hits, r.evals_per_ray, ggImplicitWarnings(imp));
    if (ref && ref->hits)
        printf("  mean t vs expr %+.1e", r.t_sum / (double)r.hits - ref->t_sum / (double)ref->hits);
    printf("\n");
}

static ggImplicit *expr(const char *s, ggVec3 lo, ggVec3 hi)
{
    ggImplicit *imp = NULL;
    ggError err;
    if (ggImplicitCreateExpr(s, lo, hi, NULL, &imp, &err) != GG_OK) {
        fprintf(stderr, "bench_implicit: %s\n", err.message);
        exit(1);
    }
    return imp;
}

static ggImplicit *fn(ggImplicitFn f, ggImplicitGradFn g, ggVec3 lo, ggVec3 hi, double L)
{
    ggImplicit *imp = NULL;
    if (ggImplicitCreateFn(f, g, NULL, lo, hi, NULL, &imp, NULL) != GG_OK) exit(1);
    if (L > 0) ggImplicitSetGradientBound(imp, L);
    return imp;
}

/* ns per normal at n points on the torus. */
static double normal_ns(const ggImplicit *imp, int central, double h)
{
    const int n = 400000;
    double t0 = gg_time_now(), sink = 0;
    int k;
    for (k = 0; k < n; k++) {
        double a = k * 0.000123, b = k * 0.0371, rho = 1 + 0.25 * cos(b);
        ggVec3 p = v3(rho * cos(a), rho * sin(a), 0.25 * sin(b)), g;
        g = central ? ggGradientCentral(imp, p, h) : ggGradientNormal(imp, p);
        sink += g.x;
    }
    return (gg_time_now() - t0) / n * 1e9 + 0 * sink;
}

/* Mean angle (radians) between the normal and the exact one. */
static double normal_err(const ggImplicit *imp, const ggImplicit *exact, double h)
{
    double sum = 0;
    int k;
    for (k = 0; k < 2000; k++) {
        double a = k * 0.0123, b = k * 0.371, rho = 1 + 0.25 * cos(b);
        ggVec3 p = v3(rho * cos(a), rho * sin(a), 0.25 * sin(b));
        ggVec3 g = v3norm(ggGradientCentral(imp, p, h)), e = v3norm(ggGradientNormal(exact, p));
        sum += v3len(v3cross(g, e));
    }
    return sum / 2000;
}

int main(void)
{
    const char *torus = "(x^2+y^2+z^2+0.9375)^2-4*(x^2+y^2)";
    ggVec3 tlo = v3(-1.25, -1.25, -0.25), thi = v3(1.25, 1.25, 0.25);
    ggVec3 slo = v3(-1, -1, -1), shi = v3(1, 1, 1);
    ggVec3 eye_t = v3(0, -3.2, 2.2), eye_s = v3(0.3, -2.8, 1.1);
    ggImplicit *a, *b;
    result ref;
    printf("implicit surfaces, %d x %d eye rays (1 ray per pixel), single thread; a hit also\n"
           "computes its normal. Boxes are tight: torus R = 1, r = 0.25; unit sphere.\n\n",
           W, H);

    a = expr(torus, tlo, thi);
    ref = trace(a, eye_t);
    row("torus", "expr, interval (default)", a, eye_t, NULL);
    b = expr(torus, tlo, thi);
    ggImplicitSetMethod(b, GG_IMPLICIT_LIPSCHITZ);
    row("torus", "expr, Lipschitz (estimated L)", b, eye_t, &ref);
    ggImplicitFree(b);
    b = fn(cb_torus, cb_torus_grad, tlo, thi, 0);
    row("torus", "callback + grad, estimated L", b, eye_t, &ref);
    printf("        (estimated L = %.2f, largest slope seen %.2f)\n", ggImplicitGradientBound(b),
           ggImplicitMaxSlope(b));
    ggImplicitFree(b);
    b = fn(cb_torus, NULL, tlo, thi, 0);
    row("torus", "callback, no grad, estimated L", b, eye_t, &ref);
    ggImplicitFree(b);
    b = fn(cb_torus_sdf, NULL, tlo, thi, 1.0);
    row("torus", "callback, signed distance, L = 1", b, eye_t, &ref);
    ggImplicitFree(b);

    {
        ggImplicit *s = expr("x^2+y^2+z^2-1", slo, shi);
        result sref = trace(s, eye_s);
        row("sphere", "expr, interval (default)", s, eye_s, NULL);
        b = fn(cb_sphere, cb_sphere_grad, slo, shi, 2 * sqrt(3.0));
        row("sphere", "callback + grad, L = 2 sqrt 3", b, eye_s, &sref);
        ggImplicitFree(b);
        b = fn(cb_sphere, NULL, slo, shi, 2 * sqrt(3.0));
        row("sphere", "callback, no grad, L = 2 sqrt 3", b, eye_s, &sref);
        ggImplicitFree(b);
        ggImplicitFree(s);
    }

    printf("\nnormals on the torus (ns per normal; error = mean angle to the exact normal, rad)\n");
    b = fn(cb_torus, NULL, tlo, thi, 1);
    {
        ggImplicit *g = fn(cb_torus, cb_torus_grad, tlo, thi, 1);
        printf("  expr, dual numbers (exact)          %7.1f ns\n", normal_ns(a, 0, 0));
        printf("  callback gradient (exact)           %7.1f ns\n", normal_ns(g, 0, 0));
        printf("  expr, central differences, default h %6.1f ns  error %.1e\n", normal_ns(a, 1, 0),
               normal_err(a, a, 0));
        printf("  callback, central differences, def. h %5.1f ns  error %.1e\n", normal_ns(b, 1, 0),
               normal_err(b, a, 0));
        {
            static const double hs[] = {1e-9, 1e-7, 1e-5, 1e-3};
            size_t k;
            for (k = 0; k < sizeof hs / sizeof hs[0]; k++)
                printf("  callback, central differences, h=%.0e    error %.1e\n", hs[k],
                       normal_err(b, a, hs[k]));
        }
        ggImplicitFree(g);
    }
    ggImplicitFree(b);
    ggImplicitFree(a);
    return 0;
}
