/* SPDX-License-Identifier: MIT */
/*
** expr_eval.c -- running an expression tape on doubles and on dual numbers
** (value + gradient, forward-mode automatic differentiation).
*/
#include "expr.h"

/* x^n by repeated squaring for small |n| (faster than pow and within
   |n| ulps, which the interval version allows for), pow beyond. */
static double powi(double x, int n)
{
    unsigned m = n < 0 ? 0u - (unsigned)n : (unsigned)n;
    double r = 1.0, b = x;
    if (m > GG_EXPR_MAX_POWI) return pow(x, (double)n);
    while (m) {
        if (m & 1u) r *= b;
        m >>= 1;
        if (m) b *= b;
    }
    return n < 0 ? 1.0 / r : r;
}

/* x^c for a constant c that is not a small integer. A fractional c is
   defined for x >= 0, as C's pow for those exponents; a whole one (past
   POWI's |c| <= 1e9) for every x, C's pow giving the sign by c's parity
   (every double from 2^53 on is even), as the header promises of integer
   powers. A NaN exponent (folded from a constant like (-0.5)^20.1) is
   undefined everywhere, as in the interval version; C's pow(1, NaN)
   would say 1. */
static double powc(double x, double c)
{
    return c == c && (x >= 0 || c == floor(c)) ? pow(x, c) : NAN;
}

/* x^(c - 1), POWC's derivative's power. From 2^53 on, c - 1 rounds to an
   even number while the true c - 1 is odd (c is even): a negative x then
   gets the odd power's sign, so the gradient of x^c points the right way
   on both sides. */
static double powc_m1(double x, double c)
{
    double e = c - 1;
    if (x < 0 && fabs(c) >= 0x1p53 && c == floor(c)) return -pow(-x, e);
    return powc(x, e);
}

double gg_expr_apply(const gg_expr_ins *in, double a, double b)
{
    switch (in->op) {
    case GG_OP_CONST:
        return in->c;
    case GG_OP_NEG:
        return -a;
    case GG_OP_SQR:
        return a * a;
    /* + 0.0 turns sqrt(-0.0) = -0.0 into +0.0, as for the real function;
       otherwise 1 / sqrt(x * 0) would be -inf, outside the enclosure. */
    case GG_OP_SQRT:
        return sqrt(a) + 0.0;
    case GG_OP_SIN:
        return sin(a);
    case GG_OP_COS:
        return cos(a);
    case GG_OP_TAN:
        return tan(a);
    case GG_OP_EXP:
        return exp(a);
    case GG_OP_LOG:
        return log(a);
    case GG_OP_ABS:
        return fabs(a);
    case GG_OP_POWI:
        return powi(a, in->n);
    case GG_OP_POWC:
        return powc(a, in->c);
    case GG_OP_ADD:
        return a + b;
    case GG_OP_SUB:
        return a - b;
    case GG_OP_MUL:
        return a * b;
    case GG_OP_DIV:
        return a / b;
    /* NaN in, NaN out (fmin would drop it and hide an undefined value). */
    case GG_OP_MIN:
        return a != a || b != b ? NAN : a <= b ? a : b;
    case GG_OP_MAX:
        return a != a || b != b ? NAN : a >= b ? a : b;
    default:
        return NAN; /* X, Y, Z have no operands to fold */
    }
}

double gg_expr_eval(const gg_expr *e, ggVec3 p)
{
    double v[GG_EXPR_MAX_TAPE];
    size_t i;
    for (i = 0; i < e->n; i++) {
        const gg_expr_ins *in = &e->ins[i];
        switch (in->op) {
        case GG_OP_CONST:
            v[i] = in->c;
            break;
        case GG_OP_X:
            v[i] = p.x;
            break;
        case GG_OP_Y:
            v[i] = p.y;
            break;
        case GG_OP_Z:
            v[i] = p.z;
            break;
        case GG_OP_ADD:
            v[i] = v[in->a] + v[in->b];
            break;
        case GG_OP_SUB:
            v[i] = v[in->a] - v[in->b];
            break;
        case GG_OP_MUL:
            v[i] = v[in->a] * v[in->b];
            break;
        case GG_OP_SQR:
            v[i] = v[in->a] * v[in->a];
            break;
        default:
            v[i] = gg_expr_apply(in, v[in->a], v[in->b]);
            break;
        }
    }
    return v[e->n - 1];
}

/* Dual number: value and gradient with respect to (x, y, z). */
typedef struct dual {
    double v, x, y, z;
} dual;

static dual dscale(dual a, double v, double s)
{
    dual r;
    r.v = v, r.x = a.x * s, r.y = a.y * s, r.z = a.z * s;
    return r;
}

double gg_expr_grad(const gg_expr *e, ggVec3 p, ggVec3 *grad)
{
    dual v[GG_EXPR_MAX_TAPE];
    size_t i;
    for (i = 0; i < e->n; i++) {
        const gg_expr_ins *in = &e->ins[i];
        dual a, b, r;
        double t;
        /* Leaves have no operands: slot 0 may not be written yet. */
        if (in->op > GG_OP_Z) a = v[in->a], b = v[in->b];
        switch (in->op) {
        case GG_OP_CONST:
            r.v = in->c, r.x = r.y = r.z = 0;
            break;
        case GG_OP_X:
            r.v = p.x, r.x = 1, r.y = r.z = 0;
            break;
        case GG_OP_Y:
            r.v = p.y, r.y = 1, r.x = r.z = 0;
            break;
        case GG_OP_Z:
            r.v = p.z, r.z = 1, r.x = r.y = 0;
            break;
        case GG_OP_NEG:
            r = dscale(a, -a.v, -1);
            break;
        case GG_OP_ADD:
            r.v = a.v + b.v, r.x = a.x + b.x, r.y = a.y + b.y, r.z = a.z + b.z;
            break;
        case GG_OP_SUB:
            r.v = a.v - b.v, r.x = a.x - b.x, r.y = a.y - b.y, r.z = a.z - b.z;
            break;
        case GG_OP_MUL:
            r.v = a.v * b.v;
            r.x = a.x * b.v + a.v * b.x;
            r.y = a.y * b.v + a.v * b.y;
            r.z = a.z * b.v + a.v * b.z;
            break;
        case GG_OP_DIV:
            r.v = a.v / b.v;
            /* (a' - q b') / b */
            r.x = (a.x - r.v * b.x) / b.v;
            r.y = (a.y - r.v * b.y) / b.v;
            r.z = (a.z - r.v * b.z) / b.v;
            break;
        case GG_OP_SQR:
            r = dscale(a, a.v * a.v, 2 * a.v);
            break;
        case GG_OP_SQRT:
            t = sqrt(a.v) + 0.0, r = dscale(a, t, 0.5 / t);
            break;
        case GG_OP_SIN:
            r = dscale(a, sin(a.v), cos(a.v));
            break;
        case GG_OP_COS:
            r = dscale(a, cos(a.v), -sin(a.v));
            break;
        case GG_OP_TAN:
            t = tan(a.v), r = dscale(a, t, 1 + t * t);
            break;
        case GG_OP_EXP:
            t = exp(a.v), r = dscale(a, t, t);
            break;
        case GG_OP_LOG:
            r = dscale(a, log(a.v), 1 / a.v);
            break;
        /* At a kink (abs at 0, min/max at a tie) any one-sided derivative
           is as good as another: take the first operand's side. */
        case GG_OP_ABS:
            r = dscale(a, fabs(a.v), a.v < 0 ? -1 : 1);
            break;
        case GG_OP_POWI:
            r = dscale(a, powi(a.v, in->n), in->n * powi(a.v, in->n - 1));
            break;
        case GG_OP_POWC:
            r = dscale(a, powc(a.v, in->c), in->c * powc_m1(a.v, in->c));
            break;
        case GG_OP_MIN:
            r = a.v <= b.v ? a : b;
            if (a.v != a.v || b.v != b.v) r.v = NAN;
            break;
        case GG_OP_MAX:
            r = a.v >= b.v ? a : b;
            if (a.v != a.v || b.v != b.v) r.v = NAN;
            break;
        default:
            r.v = r.x = r.y = r.z = NAN;
            break;
        }
        v[i] = r;
    }
    if (grad) grad->x = v[e->n - 1].x, grad->y = v[e->n - 1].y, grad->z = v[e->n - 1].z;
    return v[e->n - 1].v;
}
