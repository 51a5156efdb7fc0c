/* SPDX-License-Identifier: MIT */
/*
** expr_ival.c -- interval versions of the elementary functions, and running
** an expression tape on intervals (for root isolation along rays).
**
** Every function returns an enclosure of the true range of the real
** function over its argument, restricted to the function's domain (sqrt of
** [-1, 4] is [0, 2]; of [-2, -1] it is empty). Enclosures may be wider
** than the range, never narrower.
*/
#include "expr.h"

gg_ival gg_ival_div(gg_ival a, gg_ival b)
{
    double q1, q2, q3, q4, lo, hi;
    if (gg_iv_isempty(a) || gg_iv_isempty(b)) return gg_iv_empty();
    /* Division by zero itself: no real quotient, so nothing (an expression
       like z^2/0 is undefined wherever it is evaluated, and its rays are
       pruned at once instead of subdividing to the end of their budget). */
    if (b.lo == 0 && b.hi == 0) return gg_iv_empty();
    if (b.lo > 0 || b.hi < 0) {
        q1 = a.lo / b.lo, q2 = a.lo / b.hi, q3 = a.hi / b.lo, q4 = a.hi / b.hi;
        /* inf / inf: the true quotient can be anything of its sign. */
        if (q1 != q1 || q2 != q2 || q3 != q3 || q4 != q4) return gg_iv_entire();
        lo = q1 < q2 ? q1 : q2;
        lo = lo < q3 ? lo : q3;
        lo = lo < q4 ? lo : q4;
        hi = q1 > q2 ? q1 : q2;
        hi = hi > q3 ? hi : q3;
        hi = hi > q4 ? hi : q4;
        return gg_iv_widen(lo, hi, GG_IV_REL);
    }
    /* b touches 0 at one end only: the quotient is one-sided, which keeps
       blobs like 1/(x^2 + y^2 + z^2) - 1 prunable near their centres. */
    if (b.lo == 0 && b.hi > 0) {
        if (a.lo >= 0) return gg_iv(gg_iv_dn(a.lo / b.hi, GG_IV_REL), INFINITY);
        if (a.hi <= 0) return gg_iv(-INFINITY, gg_iv_up(a.hi / b.hi, GG_IV_REL));
    } else if (b.hi == 0 && b.lo < 0) {
        if (a.lo >= 0) return gg_iv(-INFINITY, gg_iv_up(a.lo / b.lo, GG_IV_REL));
        if (a.hi <= 0) return gg_iv(gg_iv_dn(a.hi / b.lo, GG_IV_REL), INFINITY);
    }
    return gg_iv_entire();
}

gg_ival gg_ival_sqrt(gg_ival a)
{
    double lo;
    if (gg_iv_isempty(a) || a.hi < 0) return gg_iv_empty();
    lo = a.lo > 0 ? gg_iv_dn(sqrt(a.lo), GG_IV_REL) : 0.0;
    return gg_iv(lo > 0 ? lo : 0.0, gg_iv_up(sqrt(a.hi), GG_IV_REL));
}

gg_ival gg_ival_exp(gg_ival a)
{
    double lo;
    if (gg_iv_isempty(a)) return gg_iv_empty();
    lo = gg_iv_dn(exp(a.lo), GG_IV_RELF);
    return gg_iv(lo > 0 ? lo : 0.0, gg_iv_up(exp(a.hi), GG_IV_RELF));
}

gg_ival gg_ival_log(gg_ival a)
{
    if (gg_iv_isempty(a) || a.hi < 0) return gg_iv_empty();
    return gg_iv(a.lo > 0 ? gg_iv_dn(log(a.lo), GG_IV_RELF) : -INFINITY,
                 gg_iv_up(log(a.hi), GG_IV_RELF));
}

/* Beyond this the argument reduction of sin, cos and tan is too coarse
   for locating extrema and poles; answer with the whole range. */
#define TRIG_MAX 1e9

/* Is there an integer k with phase + k*period in [lo, hi]? Computed with a
   margin that covers the rounding of period and of the division, so a
   point just outside may count as inside (wider result, still valid). */
static int hits_phase(double lo, double hi, double phase, double period)
{
    double m = 1e-14 * (1 + (fabs(lo) > fabs(hi) ? fabs(lo) : fabs(hi)));
    double k = ceil((lo - m - phase) / period);
    return phase + k * period <= hi + m;
}

/* sin (phase 0) or cos (phase pi/2, cos x = sin(x + pi/2)). */
static gg_ival sincos(gg_ival a, int is_cos)
{
    double fa, fb, lo, hi, top;
    if (gg_iv_isempty(a)) return gg_iv_empty();
    if (!(a.hi - a.lo < 6.0) || fabs(a.lo) > TRIG_MAX || fabs(a.hi) > TRIG_MAX) return gg_iv(-1, 1);
    fa = is_cos ? cos(a.lo) : sin(a.lo);
    fb = is_cos ? cos(a.hi) : sin(a.hi);
    lo = gg_iv_dn(fa < fb ? fa : fb, GG_IV_RELF);
    hi = gg_iv_up(fa > fb ? fa : fb, GG_IV_RELF);
    top = is_cos ? 0 : GG_PI / 2; /* where the maximum 1 is reached */
    if (hits_phase(a.lo, a.hi, top, 2 * GG_PI)) hi = 1;
    if (hits_phase(a.lo, a.hi, top + GG_PI, 2 * GG_PI)) lo = -1;
    return gg_iv(lo < -1 ? -1 : lo, hi > 1 ? 1 : hi);
}

gg_ival gg_ival_sin(gg_ival a)
{
    return sincos(a, 0);
}
gg_ival gg_ival_cos(gg_ival a)
{
    return sincos(a, 1);
}

gg_ival gg_ival_tan(gg_ival a)
{
    if (gg_iv_isempty(a)) return gg_iv_empty();
    if (!(a.hi - a.lo < 3.0) || fabs(a.lo) > TRIG_MAX || fabs(a.hi) > TRIG_MAX ||
        hits_phase(a.lo, a.hi, GG_PI / 2, GG_PI))
        return gg_iv_entire();
    return gg_iv_widen(tan(a.lo), tan(a.hi), GG_IV_RELF);
}

gg_ival gg_ival_abs(gg_ival a)
{
    if (gg_iv_isempty(a)) return a;
    if (a.lo >= 0) return a;
    if (a.hi <= 0) return gg_iv_neg(a);
    return gg_iv(0, -a.lo > a.hi ? -a.lo : a.hi);
}

gg_ival gg_ival_min(gg_ival a, gg_ival b)
{
    if (gg_iv_isempty(a) || gg_iv_isempty(b)) return gg_iv_empty();
    return gg_iv(a.lo < b.lo ? a.lo : b.lo, a.hi < b.hi ? a.hi : b.hi);
}

gg_ival gg_ival_max(gg_ival a, gg_ival b)
{
    if (gg_iv_isempty(a) || gg_iv_isempty(b)) return gg_iv_empty();
    return gg_iv(a.lo > b.lo ? a.lo : b.lo, a.hi > b.hi ? a.hi : b.hi);
}

/* pow() on an endpoint; the point evaluator uses repeated squaring, whose
   error grows with |n| (relatively, and absolutely when the products are
   subnormal), so widen by that much. */
static double pw_dn(double x, int n)
{
    double m = n < 0 ? -(double)n : n;
    return gg_iv_dn(pow(x, n), GG_IV_RELF + 0x1p-52 * m) - m * GG_IV_TINY;
}
static double pw_up(double x, int n)
{
    double m = n < 0 ? -(double)n : n;
    return gg_iv_up(pow(x, n), GG_IV_RELF + 0x1p-52 * m) + m * GG_IV_TINY;
}

static double nonneg(double x)
{
    return x > 0 ? x : 0.0;
}

gg_ival gg_ival_powi(gg_ival a, int n)
{
    if (gg_iv_isempty(a)) return a;
    if (n < 0) {
        gg_ival p = gg_ival_powi(a, n == -1 ? 1 : -n);
        return gg_ival_div(gg_iv(1, 1), n == -1 ? a : p);
    }
    if (n == 0) return gg_iv(1, 1);
    if (n == 1) return a;
    /* The absolute widening of pw_dn must not take the lower end below 0
       where x^n >= 0 (n even, or x >= 0; so does repeated squaring): for
       x^-1000000000 over [0.5, 0.9], x^n underflows to [0, 0] and a lower
       end of -5e-315 made 1 / x^n the whole line, so no piece of the box
       was ever pruned (every ray ran out of its budget). */
    if (a.lo >= 0) return gg_iv(nonneg(pw_dn(a.lo, n)), pw_up(a.hi, n)); /* increasing */
    if (n % 2) return gg_iv(pw_dn(a.lo, n), pw_up(a.hi, n));             /* odd, increasing */
    if (a.hi <= 0) return gg_iv(nonneg(pw_dn(a.hi, n)), pw_up(a.lo, n)); /* even, decreasing */
    return gg_iv(0, pw_up(-a.lo > a.hi ? a.lo : a.hi, n));
}

/* -(-x)^e for x < 0, x^e otherwise: an odd power e > 0 (whatever the
   double e's own parity). */
static double odd_pow(double x, double e)
{
    return x < 0 ? -pow(-x, e) : pow(x, e);
}

/* x^e over a for an odd e (increasing for e > 0; 1 / x^-e for e < 0). */
static gg_ival ival_odd_pow(gg_ival a, double e)
{
    if (e < 0) return gg_ival_div(gg_iv(1, 1), ival_odd_pow(a, -e));
    return gg_iv(gg_iv_dn(odd_pow(a.lo, e), GG_IV_RELF), gg_iv_up(odd_pow(a.hi, e), GG_IV_RELF));
}

gg_ival gg_ival_powc(gg_ival a, double c)
{
    double lo;
    if (!gg_iv_isempty(a) && a.lo < 0 && c == floor(c)) {
        /* a whole exponent past POWI's range, defined below 0 too: even,
           |x|^c; odd, as odd powers are */
        if (fabs(c) >= 0x1p53 || fmod(c, 2) == 0) return gg_ival_powc(gg_ival_abs(a), c);
        return ival_odd_pow(a, c);
    }
    if (gg_iv_isempty(a) || a.hi < 0 || c != c) return gg_iv_empty();
    lo = a.lo > 0 ? a.lo : 0;
    if (c > 0) {
        double l = gg_iv_dn(pow(lo, c), GG_IV_RELF);
        return gg_iv(l > 0 ? l : 0, gg_iv_up(pow(a.hi, c), GG_IV_RELF));
    } else {
        double l = gg_iv_dn(pow(a.hi, c), GG_IV_RELF);
        return gg_iv(l > 0 ? l : 0, lo > 0 ? gg_iv_up(pow(lo, c), GG_IV_RELF) : INFINITY);
    }
}

static gg_ival apply(const gg_expr_ins *in, gg_ival a, gg_ival b)
{
    switch (in->op) {
    case GG_OP_CONST:
        return gg_iv(in->c, in->c);
    case GG_OP_NEG:
        return gg_iv_neg(a);
    case GG_OP_SQR:
        return gg_iv_sqr(a);
    case GG_OP_SQRT:
        return gg_ival_sqrt(a);
    case GG_OP_SIN:
        return gg_ival_sin(a);
    case GG_OP_COS:
        return gg_ival_cos(a);
    case GG_OP_TAN:
        return gg_ival_tan(a);
    case GG_OP_EXP:
        return gg_ival_exp(a);
    case GG_OP_LOG:
        return gg_ival_log(a);
    case GG_OP_ABS:
        return gg_ival_abs(a);
    case GG_OP_POWI:
        return gg_ival_powi(a, in->n);
    case GG_OP_POWC:
        return gg_ival_powc(a, in->c);
    case GG_OP_ADD:
        return gg_iv_add(a, b);
    case GG_OP_SUB:
        return gg_iv_sub(a, b);
    case GG_OP_MUL:
        return gg_iv_mul(a, b);
    case GG_OP_DIV:
        return gg_ival_div(a, b);
    case GG_OP_MIN:
        return gg_ival_min(a, b);
    case GG_OP_MAX:
        return gg_ival_max(a, b);
    default:
        return gg_iv_entire();
    }
}

gg_ival gg_expr_ival(const gg_expr *e, const gg_ival x[3])
{
    gg_ival v[GG_EXPR_MAX_TAPE];
    size_t i;
    for (i = 0; i < e->n; i++) {
        const gg_expr_ins *in = &e->ins[i];
        /* The arithmetic inline, the rest through apply(). */
        switch (in->op) {
        case GG_OP_CONST:
            v[i] = gg_iv(in->c, in->c);
            break;
        case GG_OP_X:
        case GG_OP_Y:
        case GG_OP_Z:
            v[i] = x[in->op - GG_OP_X];
            break;
        case GG_OP_SQR:
            v[i] = gg_iv_sqr(v[in->a]);
            break;
        case GG_OP_ADD:
            v[i] = gg_iv_add(v[in->a], v[in->b]);
            break;
        case GG_OP_SUB:
            v[i] = gg_iv_sub(v[in->a], v[in->b]);
            break;
        case GG_OP_MUL:
            v[i] = gg_iv_mul(v[in->a], v[in->b]);
            break;
        default:
            v[i] = apply(in, v[in->a], v[in->b]);
            break;
        }
    }
    return v[e->n - 1];
}

/* An interval with its derivative enclosure along the ray. */
typedef struct idual {
    gg_ival v, d;
} idual;

static idual id(gg_ival v, gg_ival d)
{
    idual r;
    r.v = v, r.d = d;
    return r;
}

/* Derivative of one unary function at enclosure a (value r = f(a)). */
static gg_ival dunary(const gg_expr_ins *in, gg_ival a, gg_ival r)
{
    switch (in->op) {
    case GG_OP_SQR:
        return gg_iv_scale(a, 2);
    case GG_OP_SQRT:
        return gg_ival_div(gg_iv(0.5, 0.5), r);
    case GG_OP_SIN:
        return gg_ival_cos(a);
    case GG_OP_COS:
        return gg_iv_neg(gg_ival_sin(a));
    case GG_OP_TAN:
        return gg_iv_add(gg_iv(1, 1), gg_iv_sqr(r));
    case GG_OP_EXP:
        return r;
    case GG_OP_LOG:
        return gg_ival_div(gg_iv(1, 1), a);
    case GG_OP_POWI:
        return gg_iv_scale(gg_ival_powi(a, in->n - 1), in->n);
    case GG_OP_POWC: /* past 2^53 c - 1 rounds to an even number; it is odd */
        if (a.lo < 0 && fabs(in->c) >= 0x1p53 && in->c == floor(in->c))
            return gg_iv_scale(ival_odd_pow(a, in->c - 1), in->c);
        return gg_iv_scale(gg_ival_powc(a, in->c - 1), in->c);
    default:
        return gg_iv_entire();
    }
}

gg_ival gg_expr_ival_ray(const gg_expr *e, ggVec3 o, ggVec3 d, gg_ival t, gg_ival *dg, int *partial)
{
    idual v[GG_EXPR_MAX_TAPE];
    size_t i;
    for (i = 0; i < e->n; i++) {
        const gg_expr_ins *in = &e->ins[i];
        idual a, b, r;
        switch (in->op) {
        case GG_OP_CONST:
            r = id(gg_iv(in->c, in->c), gg_iv(0, 0));
            break;
        case GG_OP_X:
            r = id(gg_iv_affine(o.x, t, d.x), gg_iv(d.x, d.x));
            break;
        case GG_OP_Y:
            r = id(gg_iv_affine(o.y, t, d.y), gg_iv(d.y, d.y));
            break;
        case GG_OP_Z:
            r = id(gg_iv_affine(o.z, t, d.z), gg_iv(d.z, d.z));
            break;
        default:
            a = v[in->a], b = v[in->b];
            switch (in->op) {
            case GG_OP_NEG:
                r = id(gg_iv_neg(a.v), gg_iv_neg(a.d));
                break;
            case GG_OP_SQR:
                r = id(gg_iv_sqr(a.v), gg_iv_scale(gg_iv_mul(a.v, a.d), 2));
                break;
            case GG_OP_ADD:
                r = id(gg_iv_add(a.v, b.v), gg_iv_add(a.d, b.d));
                break;
            case GG_OP_SUB:
                r = id(gg_iv_sub(a.v, b.v), gg_iv_sub(a.d, b.d));
                break;
            case GG_OP_MUL:
                r = id(gg_iv_mul(a.v, b.v), gg_iv_add(gg_iv_mul(a.d, b.v), gg_iv_mul(a.v, b.d)));
                break;
            case GG_OP_DIV:
                r.v = gg_ival_div(a.v, b.v);
                r.d = gg_ival_div(gg_iv_sub(a.d, gg_iv_mul(r.v, b.d)), b.v);
                break;
            /* Clarke derivative at the kinks: the hull of the one-sided
               ones (for abs, of d and -d). */
            case GG_OP_ABS:
                if (a.v.lo >= 0)
                    r = a;
                else if (a.v.hi <= 0)
                    r = id(gg_iv_neg(a.v), gg_iv_neg(a.d));
                else
                    r = id(gg_ival_abs(a.v), gg_iv_hull(a.d, gg_iv_neg(a.d)));
                break;
            case GG_OP_MIN:
            case GG_OP_MAX: {
                int mn = in->op == GG_OP_MIN;
                if (gg_iv_isempty(a.v) || gg_iv_isempty(b.v))
                    r = id(gg_iv_empty(), gg_iv_empty());
                else if (mn ? a.v.hi < b.v.lo : a.v.lo > b.v.hi)
                    r = a;
                else if (mn ? b.v.hi < a.v.lo : b.v.lo > a.v.hi)
                    r = b;
                else
                    r = id(mn ? gg_ival_min(a.v, b.v) : gg_ival_max(a.v, b.v),
                           gg_iv_hull(a.d, b.d));
                break;
            }
            default:
                if (a.v.lo < 0 &&
                    (in->op == GG_OP_SQRT || in->op == GG_OP_LOG || in->op == GG_OP_POWC))
                    *partial = 1;
                r.v = apply(in, a.v, b.v);
                r.d = gg_iv_mul(dunary(in, a.v, r.v), a.d);
                break;
            }
        }
        v[i] = r;
    }
    *dg = v[e->n - 1].d;
    return v[e->n - 1].v;
}
