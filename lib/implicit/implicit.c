/* SPDX-License-Identifier: MIT */
/*
** implicit.c -- implicit surfaces: the object, its settings, gradients, and
** the root finders along a ray.
**
** Expressions: interval subdivision of the ray segment inside the box. A
** piece [a, b] is dropped when the enclosure of f over it excludes 0 (the
** natural enclosure, tightened by the mean-value forms f(a) + f'[a,b](t-a)
** and f(b) - f'[a,b](b-t), which matter near grazing rays). When the
** enclosure of f' excludes 0 too, f is monotone there: one sign test at the
** ends decides, and a sign change is refined by safeguarded Newton. Pieces
** are visited front to back, so the first root found is the first root.
**
** Callbacks: stepping by |f| / (L |d|), which cannot jump over a root if L
** bounds the gradient, until f changes sign; the last step is then refined.
*/
#include "implicit.h"

#include "expr.h"
#include "vec.h"

#include <string.h>

#define GRID        17     /* samples per axis for estimating a bound */
/* Subdivision depth: the stack grows by one per halving, so 256 (12 KB)
   takes a segment down by 2^-250, a box 1e75 times the tolerance; past
   that a piece that may hold a root raises GG_IMPLICIT_WARN_BUDGET (with
   100, a unit sphere in a box of 1e40 was missed without a word). */
#define STACK       256
#define TOL_DEFAULT 1e-12  /* times the box diagonal */
#define STEP_MIN    1e-9   /* times the box diagonal: smallest Lipschitz step */
#define BUDGET      100000 /* evaluations per ray: callbacks (their cost is unknown) */
/* Expressions: BUDGET_WORK / (n + 16) evaluations of a tape of n
   operations, within [BUDGET_MIN, BUDGET_MAX]. The example scenes' rays
   need at most 138 (torus.nff, acc-thin.nff); a ray that exhausts the
   budget costs about 1 ms (4096 evaluations of x^-1000000000 - 1, 0.22 us
   each) to 2.2 ms (256 of a 1008-operation tape, 8.5 us each), so a 64x48
   render of any expression takes seconds (docs/performance.md). */
#define BUDGET_WORK (1L << 18)
#define BUDGET_MIN  256
#define BUDGET_MAX  4096
#define SLOPE_SLACK 1e-6   /* relative; rounding noise in observed slopes */

struct ggImplicit {
    const ggAllocator *alloc; /* &alloc_copy, or NULL for malloc */
    ggAllocator alloc_copy;   /* the creator's allocator, copied (base.h) */
    gg_expr *expr;
    ggImplicitFn fn;
    ggImplicitGradFn grad;
    void *ud;
    ggVec3 lo, hi;
    double tol;   /* scene units */
    double bound; /* gradient bound, 0 = none yet */
    int method;
    long budget;
    int budget_set;  /* by ggImplicitSetBudget, else default_budget() */
    double normal_h; /* > 0: surface normals by central differences (accuracy study) */
    /* The only state intersection writes (atomically, see note()). */
    unsigned warn;
    uint64_t slope_bits; /* largest slope seen, bits of a double >= 0 */
};

/* ---- atomics (GG_ATOMIC_*, compiler.h) ---- */

static unsigned load_u(const unsigned *p)
{
    return GG_ATOMIC_LOAD(p);
}
static void or_u(unsigned *p, unsigned v)
{
    GG_ATOMIC_OR(p, v);
}
static uint64_t load_u64(const uint64_t *p)
{
    return GG_ATOMIC_LOAD(p);
}
static int cas_u64(uint64_t *p, uint64_t *expect, uint64_t v)
{
    return GG_ATOMIC_CAS(p, expect, v);
}

static uint64_t dbits(double x)
{
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}
static double bitsd(uint64_t u)
{
    double x;
    memcpy(&x, &u, sizeof x);
    return x;
}

/* ---- evaluation ---- */

static double eval(const ggImplicit *imp, ggVec3 p)
{
    return imp->expr ? gg_expr_eval(imp->expr, p) : imp->fn(imp->ud, p);
}

/* f and, when it is known, the derivative along d (returns 1 then). */
static int eval_d(const ggImplicit *imp, ggVec3 p, ggVec3 d, double *f, double *df)
{
    ggVec3 g;
    if (imp->expr) {
        *f = gg_expr_grad(imp->expr, p, &g);
    } else {
        *f = imp->fn(imp->ud, p);
        if (!imp->grad) return 0;
        g = imp->grad(imp->ud, p);
    }
    *df = v3dot(g, d);
    return 1;
}

static ggVec3 at(ggVec3 o, ggVec3 d, double t)
{
    return v3(o.x + t * d.x, o.y + t * d.y, o.z + t * d.z);
}

static double box_diag(const ggImplicit *imp)
{
    return v3len(v3sub(imp->hi, imp->lo));
}

GG_API double ggImplicitEval(const ggImplicit *imp, ggVec3 p)
{
    return imp ? eval(imp, p) : NAN;
}

GG_API ggVec3 ggGradientCentral(const ggImplicit *imp, ggVec3 p, double h)
{
    double g[3];
    int k;
    if (!imp) return v3(NAN, NAN, NAN);
    if (!(h > 0)) {
        ggVec3 e = v3sub(imp->hi, imp->lo);
        h = cbrt(DBL_EPSILON) * 0.5 * v3maxabs(e);
    }
    for (k = 0; k < 3; k++) {
        ggVec3 pp = p, pm = p;
        double *cp = k == 0 ? &pp.x : k == 1 ? &pp.y : &pp.z;
        double *cm = k == 0 ? &pm.x : k == 1 ? &pm.y : &pm.z;
        *cp += h, *cm -= h;
        /* The step as rounded, so far from the origin the quotient still
           divides by the distance actually between the two samples. */
        g[k] = (eval(imp, pp) - eval(imp, pm)) / (*cp - *cm);
    }
    return v3(g[0], g[1], g[2]);
}

GG_API ggVec3 ggGradientNormal(const ggImplicit *imp, ggVec3 p)
{
    ggVec3 g;
    if (!imp) return v3(NAN, NAN, NAN);
    if (imp->expr) {
        gg_expr_grad(imp->expr, p, &g);
        return g;
    }
    if (imp->grad) return imp->grad(imp->ud, p);
    return ggGradientCentral(imp, p, 0);
}

/* ---- creation and settings ---- */

/* Twice the largest difference quotient between neighbours of a GRID^3
   lattice over the box (and the largest |grad f| there, when known). */
static double estimate_bound(const ggImplicit *imp)
{
    double prev[GRID * GRID], cur[GRID * GRID], best = 0;
    ggVec3 step = v3scale(v3sub(imp->hi, imp->lo), 1.0 / (GRID - 1));
    int i, j, k;
    for (k = 0; k < GRID; k++) {
        for (j = 0; j < GRID; j++) {
            for (i = 0; i < GRID; i++) {
                ggVec3 p =
                    v3(imp->lo.x + i * step.x, imp->lo.y + j * step.y, imp->lo.z + k * step.z);
                double v = eval(imp, p), q[3] = {0, 0, 0};
                cur[j * GRID + i] = v;
                if (i > 0) q[0] = fabs(v - cur[j * GRID + i - 1]) / step.x;
                if (j > 0) q[1] = fabs(v - cur[(j - 1) * GRID + i]) / step.y;
                if (k > 0) q[2] = fabs(v - prev[j * GRID + i]) / step.z;
                if (imp->expr || imp->grad) {
                    ggVec3 g = ggGradientNormal(imp, p);
                    double l = v3len(g);
                    if (isfinite(l) && l > best) best = l;
                }
                for (int a = 0; a < 3; a++)
                    if (isfinite(q[a]) && q[a] > best) best = q[a];
            }
        }
        memcpy(prev, cur, sizeof prev);
    }
    return best > 0 ? 2 * best : 1.0;
}

/* The tolerance and the smallest step are fractions of the diagonal:
   a box whose |hi - lo| overflows (sides past about 1e154) would make
   them infinite, and no ray would ever hit. */
static int check_box(ggVec3 lo, ggVec3 hi)
{
    return v3finite(lo) && v3finite(hi) && lo.x < hi.x && lo.y < hi.y && lo.z < hi.z &&
           isfinite(v3len(v3sub(hi, lo)));
}

/* The budget when none was set: see BUDGET_WORK. The Lipschitz method
   (for comparisons, on expressions) takes many more steps where f
   vanishes to second order, so it keeps the callbacks' budget. */
static long default_budget(const ggImplicit *imp)
{
    long b;
    if (!imp->expr || imp->method == GG_IMPLICIT_LIPSCHITZ) return BUDGET;
    b = BUDGET_WORK / ((long)imp->expr->n + 16);
    return b < BUDGET_MIN ? BUDGET_MIN : b > BUDGET_MAX ? BUDGET_MAX : b;
}

static ggImplicit *new_implicit(ggVec3 lo, ggVec3 hi, const ggAllocator *alloc)
{
    ggImplicit *imp = gg_mem_calloc(alloc, 1, sizeof *imp);
    if (!imp) return NULL;
    if (alloc) imp->alloc_copy = *alloc, imp->alloc = &imp->alloc_copy;
    imp->lo = lo, imp->hi = hi;
    imp->tol = TOL_DEFAULT * v3len(v3sub(hi, lo));
    imp->budget = BUDGET;
    return imp;
}

GG_API int ggImplicitCreateExpr(const char *expr, ggVec3 lo, ggVec3 hi, const ggAllocator *alloc,
                                ggImplicit **out, ggError *err)
{
    ggImplicit *imp;
    gg_expr *e;
    int rc;
    if (!expr || !out) return gg_error_set(err, GG_ERROR_INVALID, "implicit: NULL argument");
    *out = NULL; /* after the NULL checks: base.h rule 1 */
    if (!check_box(lo, hi))
        return gg_error_set(
            err, GG_ERROR_INVALID,
            "implicit: the box needs finite corners with lo < hi on each axis and a "
            "finite diagonal");
    rc = gg_expr_compile(expr, strlen(expr), alloc, &e, err);
    if (rc != GG_OK) return rc;
    imp = new_implicit(lo, hi, alloc);
    if (!imp) {
        gg_expr_free(e);
        return gg_error_set(err, GG_ERROR_NOMEM, "implicit: out of memory");
    }
    imp->expr = e;
    imp->method = GG_IMPLICIT_INTERVAL;
    imp->budget = default_budget(imp);
    *out = imp;
    return GG_OK;
}

GG_API int ggImplicitCreateFn(ggImplicitFn f, ggImplicitGradFn grad, void *ud, ggVec3 lo, ggVec3 hi,
                              const ggAllocator *alloc, ggImplicit **out, ggError *err)
{
    ggImplicit *imp;
    if (!f || !out) return gg_error_set(err, GG_ERROR_INVALID, "implicit: NULL argument");
    *out = NULL; /* after the NULL checks: base.h rule 1 */
    if (!check_box(lo, hi))
        return gg_error_set(
            err, GG_ERROR_INVALID,
            "implicit: the box needs finite corners with lo < hi on each axis and a "
            "finite diagonal");
    imp = new_implicit(lo, hi, alloc);
    if (!imp) return gg_error_set(err, GG_ERROR_NOMEM, "implicit: out of memory");
    imp->fn = f, imp->grad = grad, imp->ud = ud;
    imp->method = GG_IMPLICIT_LIPSCHITZ;
    imp->bound = estimate_bound(imp);
    *out = imp;
    return GG_OK;
}

GG_API void ggImplicitFree(ggImplicit *imp)
{
    if (!imp) return;
    gg_expr_free(imp->expr);
    gg_mem_free(imp->alloc, imp);
}

GG_API int ggImplicitSetTolerance(ggImplicit *imp, double tol)
{
    if (!imp || !(tol > 0) || !isfinite(tol)) return GG_ERROR_INVALID;
    imp->tol = tol;
    return GG_OK;
}

GG_API int ggImplicitSetGradientBound(ggImplicit *imp, double L)
{
    if (!imp || !(L > 0) || !isfinite(L)) return GG_ERROR_INVALID;
    imp->bound = L;
    return GG_OK;
}

GG_API double ggImplicitGradientBound(const ggImplicit *imp)
{
    return imp ? imp->bound : 0;
}

GG_API int ggImplicitSetMethod(ggImplicit *imp, int method)
{
    if (!imp || (method != GG_IMPLICIT_INTERVAL && method != GG_IMPLICIT_LIPSCHITZ))
        return GG_ERROR_INVALID;
    if (method == GG_IMPLICIT_INTERVAL && !imp->expr) return GG_ERROR_UNSUPPORTED;
    if (method == GG_IMPLICIT_LIPSCHITZ && imp->bound == 0) imp->bound = estimate_bound(imp);
    imp->method = method;
    if (!imp->budget_set) imp->budget = default_budget(imp);
    return GG_OK;
}

GG_API int ggImplicitSetBudget(ggImplicit *imp, long max_evals)
{
    if (!imp || max_evals < 16) return GG_ERROR_INVALID;
    imp->budget = max_evals;
    imp->budget_set = 1;
    return GG_OK;
}

GG_API int ggImplicitSetNormalStep(ggImplicit *imp, double h)
{
    if (!imp || !(h >= 0) || !isfinite(h)) return GG_ERROR_INVALID;
    imp->normal_h = h;
    return GG_OK;
}

ggVec3 gg_implicit_normal_step(const ggImplicit *imp, ggVec3 p, double h)
{
    if (!(h > 0)) h = imp->normal_h;
    return h > 0 ? ggGradientCentral(imp, p, h) : ggGradientNormal(imp, p);
}

void gg_implicit_bounds(const ggImplicit *imp, ggVec3 *lo, ggVec3 *hi)
{
    if (lo) *lo = imp->lo;
    if (hi) *hi = imp->hi;
}

double gg_implicit_tolerance(const ggImplicit *imp)
{
    return imp->tol;
}

GG_API void ggImplicitBounds(const ggImplicit *imp, ggVec3 *lo, ggVec3 *hi)
{
    if (imp) gg_implicit_bounds(imp, lo, hi);
}

GG_API unsigned ggImplicitWarnings(const ggImplicit *imp)
{
    return imp ? load_u(&imp->warn) : 0;
}

GG_API double ggImplicitMaxSlope(const ggImplicit *imp)
{
    return imp ? bitsd(load_u64(&imp->slope_bits)) : 0;
}

GG_API void ggImplicitClearWarnings(ggImplicit *imp)
{
    if (!imp) return;
    imp->warn = 0;
    imp->slope_bits = 0;
}

void gg_implicit_note(const ggImplicit *cimp, const gg_implicit_status *st)
{
    /* The object is never const itself (it is allocated); only these two
       fields change after creation. */
    ggImplicit *imp = (ggImplicit *)cimp;
    uint64_t old, want;
    if (st->warn) or_u(&imp->warn, st->warn);
    if (!(st->max_slope > 0)) return;
    want = dbits(st->max_slope); /* non-negative doubles order like their bits */
    old = load_u64(&imp->slope_bits);
    while (old < want && !cas_u64(&imp->slope_bits, &old, want)) {
    }
}

/* ---- refining a bracket ---- */

/* Root of f(o + t d) in [a, b], where fa = f(a), fb = f(b) (point values)
   have opposite signs or one is 0 (else it returns 0). Newton safeguarded by bisection when the
   derivative is known, else the Illinois variant of regula falsi. Stops
   when a Newton step or the bracket is below tol; the answer is then
   corrected by that last Newton step, so it is usually accurate to
   rounding. Also returns 0 if f turns NaN inside the bracket. */
static int refine(const ggImplicit *imp, ggVec3 o, ggVec3 d, double a, double b, double fa,
                  double fb, double tol, double *t, gg_implicit_status *st)
{
    double x, f, df = 0, dxold;
    int it, side = 0;
    if (fa == 0 || fb == 0) {
        *t = fa == 0 ? a : b;
        return 1;
    }
    if (fa != fa || fb != fb || (fa < 0) == (fb < 0)) return 0;
    x = a + 0.5 * (b - a);
    dxold = b - a;
    for (it = 0; it < 200; it++) {
        int have;
        double xn, step;
        st->evals++;
        have = eval_d(imp, at(o, d, x), d, &f, &df);
        if (f == 0) break;
        if (f != f) return 0;
        if ((f < 0) == (fa < 0)) {
            a = x, fa = f;
            if (side == 1) fb *= 0.5; /* Illinois: an end kept twice loses weight */
            side = 1;
        } else {
            b = x, fb = f;
            if (side == -1) fa *= 0.5;
            side = -1;
        }
        if (!have) {
            xn = a - fa * (b - a) / (fb - fa);
            if (!(xn >= a && xn <= b)) xn = a + 0.5 * (b - a);
            x = xn;
            if (b - a <= tol) break;
            continue;
        }
        step = f / df;
        xn = x - step;
        /* Converged: one more Newton step squares the error. Tested before
           the bracket check, since xn may round onto the end just set. */
        if (fabs(step) <= tol || b - a <= tol) {
            if (xn >= a && xn <= b) x = xn;
            break;
        }
        if (!(xn > a && xn < b) || fabs(2 * step) > dxold) {
            dxold = 0.5 * (b - a);
            xn = a + dxold;
        } else {
            dxold = fabs(step);
        }
        x = xn;
    }
    *t = x;
    return 1;
}

/* ---- interval method ---- */

typedef struct node {
    double a, b;
    gg_ival fa, fb; /* enclosures of f at a and at b */
} node;

static gg_ival ival_at(const gg_expr *e, ggVec3 o, ggVec3 d, double t)
{
    gg_ival x[3];
    x[0] = gg_iv_affine_pt(o.x, t, d.x);
    x[1] = gg_iv_affine_pt(o.y, t, d.y);
    x[2] = gg_iv_affine_pt(o.z, t, d.z);
    return gg_expr_ival(e, x);
}

/* 1 or -1 when the sign is certain, 0 when the enclosure holds 0, 2 when
   f is undefined there. */
static int isign(gg_ival f)
{
    if (gg_iv_isempty(f)) return 2;
    return f.lo > 0 ? 1 : f.hi < 0 ? -1 : 0;
}

static int excludes0(gg_ival f)
{
    return gg_iv_isempty(f) || f.lo > 0 || f.hi < 0;
}

/* The search over [t0, t1], the part of (tmin, tmax) in the box; roots
   are accepted strictly inside (tmin, tmax). */
static int search_interval(const ggImplicit *imp, ggVec3 o, ggVec3 d, double t0, double t1,
                           int from_origin, double tmin, double tmax, double tol, double *t,
                           gg_implicit_status *st)
{
    const gg_expr *e = imp->expr;
    node stack[STACK];
    int sp = 1;
    stack[0].a = t0, stack[0].b = t1;
    stack[0].fa = ival_at(e, o, d, t0);
    stack[0].fb = ival_at(e, o, d, t1);
    st->evals += 2;
    while (sp > 0) {
        node nd = stack[--sp];
        gg_ival f, df;
        int sa, sb, mono, leaf, partial = 0;
        double m;
        if (st->evals >= imp->budget) {
            st->warn |= GG_IMPLICIT_WARN_BUDGET;
            return 0;
        }
        st->evals++;
        f = gg_expr_ival_ray(e, o, d, gg_iv(nd.a, nd.b), &df, &partial);
        if (excludes0(f)) continue;
        /* Mean-value forms from both ends; without them a ray passing 1e-9
           from the surface would subdivide down to ~1e-9. They need f
           continuous on the piece: no domain gap, no pole (the enclosure
           of f would be unbounded). */
        if (!partial && gg_iv_finite(f) && !gg_iv_isempty(df)) {
            gg_ival span = gg_iv(0, gg_iv_up(nd.b - nd.a, GG_IV_REL)), slope = gg_iv_mul(df, span);
            if (!gg_iv_isempty(nd.fa)) f = gg_iv_meet(f, gg_iv_add(nd.fa, slope));
            if (!gg_iv_isempty(nd.fb)) f = gg_iv_meet(f, gg_iv_sub(nd.fb, slope));
            if (excludes0(f)) continue;
        }
        sa = isign(nd.fa), sb = isign(nd.fb);
        /* A pole inside (f unbounded) can come with a one-sided f' (as for
           1/x - 1 at 0): no shortcut then, only subdivision. */
        mono = !partial && gg_iv_finite(f) && !gg_iv_isempty(df) && (df.lo > 0 || df.hi < 0);
        m = nd.a + 0.5 * (nd.b - nd.a);
        leaf = nd.b - nd.a <= tol || !(m > nd.a && m < nd.b);
        if (!leaf && !mono && sp + 2 > STACK) leaf = 1, st->warn |= GG_IMPLICIT_WARN_BUDGET;
        if (mono || leaf) {
            double r, pa, pb;
            /* Undefined at an end, or a pole (not a root) inside. */
            if (sa == 2 || sb == 2 || !gg_iv_finite(f)) continue;
            /* f(t0) = 0 within rounding: the surface the ray leaves. */
            if (sa == 0 && nd.a == t0 && from_origin) continue;
            if (sa * sb > 0)
                continue; /* certain signs, equal: no root (mono) or none seen (leaf) */
            /* An end whose enclosure holds 0 may still be no root: the
               enclosure of a point is wider than the rounding of its value.
               Decide on point values: they are the same numbers for the
               neighbouring piece, so a sign change between them is never
               lost, only found in one piece or the other. */
            pa = eval(imp, at(o, d, nd.a));
            pb = eval(imp, at(o, d, nd.b));
            st->evals += 2;
            if (pa == pa && pb == pb && (pa == 0 || pb == 0 || (pa < 0) != (pb < 0)) &&
                refine(imp, o, d, nd.a, nd.b, pa, pb, tol, &r, st) && r > tmin && r < tmax) {
                *t = r;
                return 1;
            }
            continue;
        }
        st->evals++;
        stack[sp].a = m, stack[sp].b = nd.b;
        stack[sp].fa = ival_at(e, o, d, m), stack[sp].fb = nd.fb;
        stack[sp + 1].a = nd.a, stack[sp + 1].b = m;
        stack[sp + 1].fa = nd.fa, stack[sp + 1].fb = stack[sp].fa;
        sp += 2;
    }
    return 0;
}

/* ---- Lipschitz method ---- */

static int search_lipschitz(const ggImplicit *imp, ggVec3 o, ggVec3 d, double t0, double t1,
                            int from_origin, double tmin, double tmax, double tol, double *t,
                            gg_implicit_status *st)
{
    double dl = v3len(d), lt = imp->bound * dl; /* bound on |df/dt| */
    double hmin = STEP_MIN * box_diag(imp) / dl, h, ta = t0, fa, smax = (t1 - t0) / 16;
    int forced = 0;
    if (hmin < tol) hmin = tol;
    h = hmin;
    fa = eval(imp, at(o, d, ta));
    st->evals++;
    if (fa == 0 && !from_origin && ta > tmin && ta < tmax) {
        *t = ta;
        return 1;
    }
    while (ta < t1) {
        double step, tb, fb, slope, r;
        if (st->evals >= imp->budget) {
            st->warn |= GG_IMPLICIT_WARN_BUDGET;
            return 0;
        }
        step = fa == fa ? fabs(fa) / lt : (t1 - t0) / 1024; /* NaN: no information */
        if (!(step >= h)) {
            /* Too close to the surface to prove anything by stepping: take
               the smallest step, and grow it when crawling along. */
            step = h;
            if (++forced > 16) h *= 2;
        } else {
            forced = 0;
            h = hmin;
        }
        /* At least 16 samples per segment, so that a bound far too small
           (steps across the whole box) is still caught in the act. */
        if (step > smax) step = smax;
        tb = ta + step;
        if (!(tb < t1)) tb = t1;
        if (!(tb > ta)) tb = nextafter(ta, INFINITY);
        fb = eval(imp, at(o, d, tb));
        st->evals++;
        /* Over a step of a few ulps (the last one, clipped to t1) the
           quotient is rounding noise: judge slopes over hmin or more only,
           allowing for the rounding of f itself. */
        if (tb - ta >= hmin) {
            slope = (fabs(fb - fa) - 8 * DBL_EPSILON * (fabs(fa) + fabs(fb))) / ((tb - ta) * dl);
            if (slope > st->max_slope) st->max_slope = slope;
            if (slope > imp->bound * (1 + SLOPE_SLACK)) st->warn |= GG_IMPLICIT_WARN_GRADIENT;
        }
        if (fa == fa && fb == fb && (fb == 0 || (fa < 0) != (fb < 0)) &&
            !(fa == 0 && from_origin && ta == t0)) {
            if (refine(imp, o, d, ta, tb, fa, fb, tol, &r, st) && r > tmin && r < tmax) {
                *t = r;
                return 1;
            }
        }
        ta = tb, fa = fb;
    }
    return 0;
}

/* ---- intersection ---- */

/* Clip o + t d, t in [*t0, *t1], to the box; 0 if nothing is left. */
static int clip(const ggImplicit *imp, ggVec3 o, ggVec3 d, double *t0, double *t1)
{
    int k;
    for (k = 0; k < 3; k++) {
        double ok = v3get(o, k), dk = v3get(d, k), lo = v3get(imp->lo, k), hi = v3get(imp->hi, k);
        if (dk == 0) {
            if (ok < lo || ok > hi) return 0;
        } else {
            double ta = (lo - ok) / dk, tb = (hi - ok) / dk;
            if (ta > tb) {
                double s = ta;
                ta = tb, tb = s;
            }
            if (ta > *t0) *t0 = ta;
            if (tb < *t1) *t1 = tb;
        }
    }
    return *t0 <= *t1;
}

/* gg_implicit_intersect_status with the tolerance in scene units (> 0),
   or the surface's own. */
static int intersect_status(const ggImplicit *imp, ggVec3 o, ggVec3 d, double tmin, double tmax,
                            double tol_scene, double *t, gg_implicit_status *st)
{
    double t0 = tmin, t1 = tmax, dl = v3len(d), tol;
    int from_origin;
    st->warn = 0, st->max_slope = 0, st->evals = 0;
    if (!imp || !t || !v3finite(o) || !v3finite(d) || !(dl > 0) || !(tmin < tmax)) return 0;
    if (!clip(imp, o, d, &t0, &t1)) return 0;
    /* The search starts at the ray origin rather than at a face of the box. */
    from_origin = t0 == tmin;
    tol = (tol_scene > 0 ? tol_scene : imp->tol) / dl;
    if (imp->method == GG_IMPLICIT_INTERVAL && imp->expr)
        return search_interval(imp, o, d, t0, t1, from_origin, tmin, tmax, tol, t, st);
    return search_lipschitz(imp, o, d, t0, t1, from_origin, tmin, tmax, tol, t, st);
}

int gg_implicit_intersect_status(const ggImplicit *imp, ggVec3 o, ggVec3 d, double tmin,
                                 double tmax, double *t, gg_implicit_status *st)
{
    return intersect_status(imp, o, d, tmin, tmax, 0, t, st);
}

int gg_implicit_intersect_warn(const ggImplicit *imp, ggVec3 o, ggVec3 d, double tmin, double tmax,
                               double tol, double *t, unsigned *warn)
{
    gg_implicit_status st;
    int hit = intersect_status(imp, o, d, tmin, tmax, tol, t, &st);
    if (imp && (st.warn || st.max_slope > 0)) gg_implicit_note(imp, &st);
    *warn = st.warn;
    return hit;
}

int gg_implicit_intersect_tol(const ggImplicit *imp, ggVec3 o, ggVec3 d, double tmin, double tmax,
                              double tol, double *t)
{
    unsigned warn;
    return gg_implicit_intersect_warn(imp, o, d, tmin, tmax, tol, t, &warn);
}

int gg_implicit_intersect(const ggImplicit *imp, ggVec3 o, ggVec3 d, double tmin, double tmax,
                          double *t)
{
    return gg_implicit_intersect_tol(imp, o, d, tmin, tmax, 0, t);
}

GG_API int ggImplicitIntersect(const ggImplicit *imp, ggRay ray, double tmin, double tmax,
                               double *t)
{
    int k, hit;
    ray.d = v3tame(ray.d, &k); /* d of any finite size; t scaled with it */
    hit = gg_implicit_intersect(imp, ray.o, ray.d, ldexp(tmin, -k), ldexp(tmax, -k), t);
    if (hit && t) *t = ldexp(*t, k);
    return hit;
}
