/* SPDX-License-Identifier: MIT */
/*
** test_expr.c -- the expression compiler (accepting, rejecting with line and
** column, limits, folding) and its evaluators: doubles and dual numbers
** against C, intervals against point values and against long doubles.
*/
#include "testutil.h"

#include "expr.h"
#include "vec.h"

#include <float.h>
#include <locale.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static gg_expr *compile_ok(const char *s)
{
    gg_expr *e = NULL;
    ggError err;
    int rc = gg_expr_compile(s, strlen(s), NULL, &e, &err);
    if (rc != GG_OK) print_error("compiling \"%s\": %s\n", s, err.message);
    assert_int_equal(rc, GG_OK);
    assert_non_null(e);
    return e;
}

static ggVec3 rand_in(tu_rng *r, double lo, double hi)
{
    return v3(tu_range(r, lo, hi), tu_range(r, lo, hi), tu_range(r, lo, hi));
}

/* ------------------------------------------------------------------ */
/* Parser                                                              */
/* ------------------------------------------------------------------ */

static void test_parse_accepts(void **state)
{
    static const char *ok[] = {
        "x",
        "1",
        ".5",
        "5.",
        "1e3",
        "1.5E-3",
        "2e+2",
        "-x",
        "+x",
        "--x",
        "x^2",
        "x^-2",
        "2^3^2",
        "-x^2",
        "pi",
        "sqrt(x)",
        "sin(x)*cos(y)+tan(z)",
        "exp(log(abs(x)))",
        "min(x, y)",
        "max(x, y, z, 1)",
        "pow(x, 3)",
        "pow(x, y)",
        "x^y",
        "x^0.5",
        "x ^ 1.5",
        "( ( x ) )",
        " \t\n x \r\n",
        "x*y/z-1",
        "(x^2+y^2+z^2+0.75)^2-4*(x^2+y^2)",
        "1/0",
        "sqrt(-1)",
        "x^0",
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof ok / sizeof ok[0]; i++) gg_expr_free(compile_ok(ok[i]));
}

static void test_parse_rejects_with_columns(void **state)
{
    static const struct {
        const char *src;
        int code;
        const char *msg;
    } bad[] = {
        {"sinn(x)", GG_ERROR_PARSE, "1:1: unknown function 'sinn'"},
        {"x + sinn(y)", GG_ERROR_PARSE, "1:5: unknown function 'sinn'"},
        {"x +\n  sinn(y)", GG_ERROR_PARSE, "2:3: unknown function 'sinn'"},
        {"", GG_ERROR_PARSE, "1:1: empty expression"},
        {"   ", GG_ERROR_PARSE, "1:1: empty expression"},
        {"1 +", GG_ERROR_PARSE,
         "1:4: expected a number, a variable, a function or '(', found end of expression"},
        {"2x", GG_ERROR_PARSE, "1:2: expected an operator or the end, found 'x'"},
        {"(x", GG_ERROR_PARSE,
         "1:3: expected ')' to close the '(' at column 1, found end of expression"},
        {"x)", GG_ERROR_PARSE, "1:2: unmatched ')'"},
        {"1e", GG_ERROR_PARSE, "1:1: malformed exponent in number '1e'"},
        {"x*1e+", GG_ERROR_PARSE, "1:3: malformed exponent in number '1e+'"},
        {"w", GG_ERROR_PARSE,
         "1:1: unknown variable 'w' (the variables are x, y, z and the constant pi)"},
        {"sin x", GG_ERROR_PARSE, "1:1: expected '(' after 'sin'"},
        {"min(x)", GG_ERROR_PARSE, "1:1: min() takes at least 2 arguments, got 1"},
        {"y*sqrt(x, y)", GG_ERROR_PARSE, "1:3: sqrt() takes 1 argument, got 2"},
        {"pow(x)", GG_ERROR_PARSE, "1:1: pow() takes 2 arguments, got 1"},
        {"x # y", GG_ERROR_PARSE, "1:3: unexpected character '#'"},
        {"x\x01", GG_ERROR_PARSE, "1:2: unexpected character '\\x01'"},
        {".", GG_ERROR_PARSE, "1:1: expected digits around '.'"},
        {"1..2", GG_ERROR_PARSE, "1:3: expected an operator or the end, found '.2'"},
        {"x^", GG_ERROR_PARSE,
         "1:3: expected a number, a variable, a function or '(', found end of expression"},
        {"sin()", GG_ERROR_PARSE,
         "1:5: expected a number, a variable, a function or '(', found ')'"},
        {"1e999", GG_ERROR_PARSE, "1:1: number '1e999' is too large for a double"},
        {"x,y", GG_ERROR_PARSE, "1:2: expected an operator or the end, found ','"},
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        gg_expr *e = (gg_expr *)1;
        ggError err;
        int rc = gg_expr_compile(bad[i].src, strlen(bad[i].src), NULL, &e, &err);
        if (rc != bad[i].code || strcmp(err.message, bad[i].msg) != 0)
            print_error("\"%s\": got %d \"%s\"\n", bad[i].src, rc, err.message);
        assert_int_equal(rc, bad[i].code);
        assert_int_equal(err.code, bad[i].code);
        assert_string_equal(err.message, bad[i].msg);
        assert_null(e);
    }
    /* The public constructor reports the same, and leaves *out NULL. */
    {
        ggImplicit *imp = (ggImplicit *)1;
        ggError err;
        assert_int_equal(
            ggImplicitCreateExpr("x + sinn(y)", v3(-1, -1, -1), v3(1, 1, 1), NULL, &imp, &err),
            GG_ERROR_PARSE);
        assert_string_equal(err.message, "1:5: unknown function 'sinn'");
        assert_null(imp);
    }
}

static void test_parse_limits(void **state)
{
    char *s = malloc(GG_EXPR_MAX_LEN + 64);
    gg_expr *e;
    ggError err;
    int i, n;
    (void)state;
    assert_non_null(s);
    /* Length. */
    memset(s, ' ', GG_EXPR_MAX_LEN + 1);
    s[0] = 'x';
    assert_int_equal(gg_expr_compile(s, GG_EXPR_MAX_LEN, NULL, &e, &err), GG_OK);
    gg_expr_free(e);
    assert_int_equal(gg_expr_compile(s, GG_EXPR_MAX_LEN + 1, NULL, &e, &err), GG_ERROR_LIMIT);
    assert_null(e);
    /* Nesting: 63 parentheses inside the top level are fine, 64 are not. */
    for (n = 63; n <= 64; n++) {
        int k = 0;
        for (i = 0; i < n; i++) s[k++] = '(';
        s[k++] = 'x';
        for (i = 0; i < n; i++) s[k++] = ')';
        s[k] = 0;
        assert_int_equal(gg_expr_compile(s, strlen(s), NULL, &e, &err),
                         n == 63 ? GG_OK : GG_ERROR_LIMIT);
        if (n == 64) assert_non_null(strstr(err.message, "nesting deeper than 64"));
        gg_expr_free(e);
    }
    /* Unary chains and powers count too; the depth is not a C stack risk. */
    memset(s, '-', 4000);
    strcpy(s + 4000, "x");
    assert_int_equal(gg_expr_compile(s, strlen(s), NULL, &e, &err), GG_ERROR_LIMIT);
    /* Tape size: 350 distinct sines need more than 1024 instructions. */
    for (i = 0, n = 0; i < 350; i++) n += sprintf(s + n, "%ssin(x+%d)", i ? "+" : "", i + 1);
    assert_true(n < GG_EXPR_MAX_LEN);
    assert_int_equal(gg_expr_compile(s, strlen(s), NULL, &e, &err), GG_ERROR_LIMIT);
    assert_non_null(strstr(err.message, "instructions"));
    assert_null(e);
    free(s);
}

static void test_compile_folds_and_shares(void **state)
{
    gg_expr *e;
    (void)state;
    e = compile_ok("x^2 + x^2"); /* x, x^2, + */
    assert_int_equal(e->n, 3);
    gg_expr_free(e);
    e = compile_ok("x*x"); /* becomes a square */
    assert_int_equal(e->n, 2);
    assert_int_equal(e->ins[1].op, GG_OP_SQR);
    gg_expr_free(e);
    e = compile_ok("2*3 + 4^0.5 - sqrt(16)*pi/pi"); /* all constant: 6 + 2 - 4 */
    assert_int_equal(e->n, 1);
    assert_close(e->ins[0].c, 4.0, 1e-14);
    gg_expr_free(e);
    e = compile_ok("(x^2+y^2+z^2+0.75)^2-4*(x^2+y^2)"); /* x^2 and y^2 once each */
    {
        size_t i, sq = 0;
        for (i = 0; i < e->n; i++) sq += e->ins[i].op == GG_OP_SQR;
        assert_int_equal(sq, 4); /* x^2, y^2, z^2, (...)^2 */
    }
    gg_expr_free(e);
}

static void test_locale_independent_numbers(void **state)
{
    const char *loc = setlocale(LC_NUMERIC, "de_DE.UTF-8");
    gg_expr *e;
    (void)state;
    if (!loc) loc = setlocale(LC_NUMERIC, "fr_FR.UTF-8");
    e = compile_ok("1.25 + x");
    assert_close(gg_expr_eval(e, v3(0, 0, 0)), 1.25, 0);
    gg_expr_free(e);
    setlocale(LC_NUMERIC, "C");
    if (!loc) print_message("(no comma locale installed: checked under \"C\" only)\n");
}

/* ------------------------------------------------------------------ */
/* Evaluators                                                          */
/* ------------------------------------------------------------------ */

typedef struct fcase {
    const char *src;
    double (*f)(ggVec3);
    ggVec3 (*g)(ggVec3); /* NULL: skip gradient check */
} fcase;

static double f_torus(ggVec3 p)
{
    double s = p.x * p.x + p.y * p.y + p.z * p.z + 0.75;
    return s * s - 4 * (p.x * p.x + p.y * p.y);
}
static ggVec3 g_torus(ggVec3 p)
{
    double s = p.x * p.x + p.y * p.y + p.z * p.z + 0.75;
    return v3(4 * s * p.x - 8 * p.x, 4 * s * p.y - 8 * p.y, 4 * s * p.z);
}
static double f_trig(ggVec3 p)
{
    return sin(p.x) * cos(p.y) + tan(p.z / 4);
}
static ggVec3 g_trig(ggVec3 p)
{
    double t = tan(p.z / 4);
    return v3(cos(p.x) * cos(p.y), -sin(p.x) * sin(p.y), (1 + t * t) / 4);
}
static double f_explog(ggVec3 p)
{
    return exp(p.x / 2) * log(1 + p.y * p.y) - sqrt(2 + p.z);
}
static ggVec3 g_explog(ggVec3 p)
{
    return v3(0.5 * exp(p.x / 2) * log(1 + p.y * p.y), exp(p.x / 2) * 2 * p.y / (1 + p.y * p.y),
              -0.5 / sqrt(2 + p.z));
}
static double f_div(ggVec3 p)
{
    return (p.x - 2 * p.y) / (1 + p.z * p.z) - 1 / (3 + p.x);
}
static ggVec3 g_div(ggVec3 p)
{
    double q = 1 + p.z * p.z;
    return v3(1 / q + 1 / ((3 + p.x) * (3 + p.x)), -2 / q, -(p.x - 2 * p.y) * 2 * p.z / (q * q));
}
static double f_pow(ggVec3 p)
{
    return pow(p.x, 3) - pow(p.y, -2) + pow(fabs(p.z), 1.5) + pow(2.0, p.x) - pow(p.z, 4);
}
static ggVec3 g_pow(ggVec3 p)
{
    return v3(3 * p.x * p.x + log(2.0) * pow(2.0, p.x), 2 * pow(p.y, -3),
              1.5 * sqrt(fabs(p.z)) * (p.z < 0 ? -1 : 1) - 4 * pow(p.z, 3));
}
static double f_minmax(ggVec3 p)
{
    return fmin(fmin(p.x, 2 * p.y), p.z - 1) + fmax(fabs(p.x), p.y * p.z) - 2;
}
static double f_unary(ggVec3 p)
{
    return -p.x * p.x + -(p.y - p.z) * 3 + pow(2, pow(1.5, 2));
}
static ggVec3 g_unary(ggVec3 p)
{
    return v3(-2 * p.x, -3, 3);
}
static double f_blob(ggVec3 p)
{
    return 1 / (0.1 + (p.x - 0.5) * (p.x - 0.5) + p.y * p.y + p.z * p.z) +
           1 / (0.1 + (p.x + 0.5) * (p.x + 0.5) + p.y * p.y + p.z * p.z) - 3;
}
static double f_nested(ggVec3 p)
{
    return sqrt(exp(sin(p.x * p.y) + cos(p.z)) + pow(p.x, 2));
}

static const fcase cases[] = {
    {"(x^2+y^2+z^2+0.75)^2-4*(x^2+y^2)", f_torus, g_torus},
    {"sin(x)*cos(y)+tan(z/4)", f_trig, g_trig},
    {"exp(x/2)*log(1+y^2)-sqrt(2+z)", f_explog, g_explog},
    {"(x-2*y)/(1+z^2)-1/(3+x)", f_div, g_div},
    {"x^3 - y^-2 + abs(z)^1.5 + 2^x - pow(z, 4)", f_pow, g_pow},
    {"min(x, 2*y, z-1) + max(abs(x), y*z) - 2", f_minmax, NULL},
    {"-x^2 + -(y-z)*3 + 2^1.5^2", f_unary, g_unary},
    {"1/(0.1+(x-0.5)^2+y^2+z^2) + 1/(0.1+(x+0.5)^2+y^2+z^2) - 3", f_blob, NULL},
    {"sqrt(exp(sin(x*y)+cos(z)) + x^2)", f_nested, NULL},
};
#define NCASES (sizeof cases / sizeof cases[0])

static void test_eval_matches_c(void **state)
{
    tu_rng r = {11};
    size_t c;
    int i, nan_both = 0;
    (void)state;
    for (c = 0; c < NCASES; c++) {
        gg_expr *e = compile_ok(cases[c].src);
        for (i = 0; i < 300; i++) {
            ggVec3 p = rand_in(&r, -2.5, 2.5);
            double a = gg_expr_eval(e, p), b = cases[c].f(p), ga;
            if (isnan(b)) {
                assert_true(isnan(a));
                nan_both++;
                continue;
            }
            assert_close(a, b, 1e-13);
            /* The dual evaluator's value is the same computation. */
            ga = gg_expr_grad(e, p, NULL);
            assert_close(ga, a, 1e-14);
        }
        gg_expr_free(e);
    }
    assert_true(nan_both > 0); /* sqrt(2+z) for z < -2 */
}

static void test_dual_gradients_exact(void **state)
{
    tu_rng r = {12};
    size_t c;
    int i, checked = 0;
    (void)state;
    for (c = 0; c < NCASES; c++) {
        gg_expr *e;
        if (!cases[c].g) continue;
        e = compile_ok(cases[c].src);
        for (i = 0; i < 300; i++) {
            ggVec3 p = rand_in(&r, -2.5, 2.5), g, want = cases[c].g(p);
            if (!v3finite(want)) continue;
            gg_expr_grad(e, p, &g);
            assert_vec_close(g, want, 1e-12);
            checked++;
        }
        gg_expr_free(e);
    }
    assert_true(checked > 1000);
}

/* Any point value computed in a box lies in the box's enclosure, and along
   a ray segment the derivative lies in the derivative's enclosure. */
static void test_interval_enclosures(void **state)
{
    tu_rng r = {13};
    size_t c;
    int i, k, tested = 0;
    static const char *extra[] = {
        "sin(x*3) - cos(y*7) + tan(z)",
        "sqrt(x) + log(y) + x^0.3",
        "1/x + y/(z*z)",
        "x^5 - y^4 + z^-3",
        "exp(x*4) - exp(-y*5)",
        "abs(x-y) - min(x, z) * max(y, 1/z)",
        "tan(x*2) * sin(10*y)",
        "cos(1000*x) + sin(12345*y)",
    };
    (void)state;
    for (c = 0; c < NCASES + sizeof extra / sizeof extra[0]; c++) {
        gg_expr *e = compile_ok(c < NCASES ? cases[c].src : extra[c - NCASES]);
        for (i = 0; i < 400; i++) {
            ggVec3 ctr = rand_in(&r, -3, 3), o, d;
            double w = pow(10, tu_range(&r, -12, 0.5));
            gg_ival box[3], F, D;
            int partial = 0;
            box[0] = gg_iv(ctr.x - w * tu_uniform(&r), ctr.x + w * tu_uniform(&r));
            box[1] = gg_iv(ctr.y - w * tu_uniform(&r), ctr.y + w * tu_uniform(&r));
            box[2] = gg_iv(ctr.z - w * tu_uniform(&r), ctr.z + w * tu_uniform(&r));
            F = gg_expr_ival(e, box);
            for (k = 0; k < 8; k++) {
                ggVec3 p =
                    v3(tu_range(&r, box[0].lo, box[0].hi), tu_range(&r, box[1].lo, box[1].hi),
                       tu_range(&r, box[2].lo, box[2].hi));
                double v = gg_expr_eval(e, p);
                if (k == 0) p = v3(box[0].lo, box[1].hi, box[2].lo), v = gg_expr_eval(e, p);
                if (isnan(v)) continue;
                if (!(F.lo <= v && v <= F.hi))
                    print_error("%s at (%.17g %.17g %.17g) = %.17g not in [%.17g, %.17g]\n",
                                e == NULL ? "" : (c < NCASES ? cases[c].src : extra[c - NCASES]),
                                p.x, p.y, p.z, v, F.lo, F.hi);
                assert_true(F.lo <= v && v <= F.hi);
                tested++;
            }
            /* Along a ray segment. */
            o = rand_in(&r, -3, 3);
            d = v3scale(tu_unit(&r), tu_range(&r, 0.1, 3));
            {
                double ta = tu_range(&r, -1, 1), tb = ta + w;
                F = gg_expr_ival_ray(e, o, d, gg_iv(ta, tb), &D, &partial);
                for (k = 0; k < 8; k++) {
                    double t = k == 0 ? ta : k == 1 ? tb : tu_range(&r, ta, tb), v, dv, slack;
                    ggVec3 g, p = v3(o.x + t * d.x, o.y + t * d.y, o.z + t * d.z);
                    v = gg_expr_grad(e, p, &g);
                    /* The test's own dot product rounds differently from
                       the propagated derivative: allow for that. */
                    dv = v3dot(g, d);
                    slack = 4 * DBL_EPSILON * (fabs(g.x * d.x) + fabs(g.y * d.y) + fabs(g.z * d.z));
                    if (isnan(v)) continue;
                    assert_true(F.lo <= v && v <= F.hi);
                    if (!isnan(dv)) assert_true(D.lo - slack <= dv && dv <= D.hi + slack);
                    tested++;
                }
            }
        }
        gg_expr_free(e);
    }
    assert_true(tested > 30000);
}

/* The tape on long doubles (64-bit significand on x86-64): close enough to
   the real value to see a bound that rounding moved inward. Arithmetic and
   sqrt only (correctly rounded in both precisions). */
static long double eval_long(const gg_expr *e, ggVec3 p)
{
    long double v[GG_EXPR_MAX_TAPE];
    size_t i;
    for (i = 0; i < e->n; i++) {
        const gg_expr_ins *in = &e->ins[i];
        long double a = i ? v[in->a] : 0, b = i ? v[in->b] : 0;
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
        case GG_OP_NEG:
            v[i] = -a;
            break;
        case GG_OP_SQR:
            v[i] = a * a;
            break;
        case GG_OP_SQRT:
            v[i] = sqrtl(a);
            break;
        case GG_OP_ADD:
            v[i] = a + b;
            break;
        case GG_OP_SUB:
            v[i] = a - b;
            break;
        case GG_OP_MUL:
            v[i] = a * b;
            break;
        case GG_OP_DIV:
            v[i] = a / b;
            break;
        default:
            fail_msg("op %d not in eval_long", in->op);
        }
    }
    return v[e->n - 1];
}

/* Enclosures of single points hold the (nearly) real value: this is what
   outward rounding is for; the double result alone is always inside. */
static void test_interval_real_enclosure(void **state)
{
    static const char *srcs[] = {"(x^2+y^2+z^2+0.9375)^2-4*(x^2+y^2)",
                                 "x*y - z/(x+3.1) + sqrt(x*x+1) - 0.1*z", "x/3 + y/7 - z*z/11"};
    tu_rng r = {14};
    size_t c;
    int i, outside_rounded = 0;
    (void)state;
    if (sizeof(long double) <= sizeof(double)) skip();
    for (c = 0; c < sizeof srcs / sizeof srcs[0]; c++) {
        gg_expr *e = compile_ok(srcs[c]);
        for (i = 0; i < 3000; i++) {
            ggVec3 p = rand_in(&r, -2, 2), o = rand_in(&r, -2, 2), d;
            gg_ival box[3], F;
            long double exact = eval_long(e, p);
            double v = gg_expr_eval(e, p), t;
            box[0] = gg_iv(p.x, p.x), box[1] = gg_iv(p.y, p.y), box[2] = gg_iv(p.z, p.z);
            F = gg_expr_ival(e, box);
            assert_true(F.lo <= exact && exact <= F.hi);
            outside_rounded += (long double)v != exact;
            /* The same for a point of a ray, with o + t d itself rounded. */
            d = v3sub(p, o);
            t = tu_range(&r, 0.5, 1.5);
            {
                gg_ival dg;
                int partial = 0;
                ggVec3 q;
                long double qx = (long double)o.x + (long double)t * d.x;
                long double qy = (long double)o.y + (long double)t * d.y;
                long double qz = (long double)o.z + (long double)t * d.z;
                F = gg_expr_ival_ray(e, o, d, gg_iv(t, t), &dg, &partial);
                /* Evaluate at the exactly computed point: round it only
                   where double holds it exactly, else skip. */
                q = v3((double)qx, (double)qy, (double)qz);
                if ((long double)q.x == qx && (long double)q.y == qy && (long double)q.z == qz) {
                    exact = eval_long(e, q);
                    assert_true(F.lo <= exact && exact <= F.hi);
                }
            }
        }
        gg_expr_free(e);
    }
    /* The test has teeth: the double results are mostly not the real ones. */
    assert_true(outside_rounded > 1000);
}

static void test_interval_functions(void **state)
{
    gg_ival a;
    (void)state;
    /* Extrema inside the argument are found. */
    a = gg_ival_sin(gg_iv(1, 2)); /* pi/2 inside */
    assert_true(a.hi == 1 && a.lo <= sin(1) && a.lo > sin(1) - 1e-14);
    a = gg_ival_cos(gg_iv(3, 3.5)); /* pi inside */
    assert_true(a.lo == -1 && a.hi >= cos(3.5) && a.hi < cos(3.5) + 1e-14);
    a = gg_ival_sin(gg_iv(0.1, 0.2)); /* monotone: tight */
    assert_true(a.lo <= sin(0.1) && a.lo > sin(0.1) - 1e-15 && a.hi < 0.2);
    /* Poles and zero divisors give unbounded (never wrong) results. */
    a = gg_ival_tan(gg_iv(1.5, 1.6));
    assert_true(a.lo == -INFINITY && a.hi == INFINITY);
    a = gg_ival_div(gg_iv(1, 2), gg_iv(-1, 1));
    assert_true(a.lo == -INFINITY && a.hi == INFINITY);
    a = gg_ival_div(gg_iv(1, 2), gg_iv(0, 4)); /* one-sided */
    assert_true(a.lo <= 0.25 && a.lo > 0.2499999 && a.hi == INFINITY);
    /* Division by zero itself has no real value at all. */
    assert_true(gg_iv_isempty(gg_ival_div(gg_iv(1, 2), gg_iv(0, 0))));
    assert_true(gg_iv_isempty(gg_ival_div(gg_iv(-1, 2), gg_iv(-0.0, 0))));
    /* Domains. */
    assert_true(gg_iv_isempty(gg_ival_sqrt(gg_iv(-2, -1))));
    a = gg_ival_sqrt(gg_iv(-1, 4));
    assert_true(a.lo == 0 && a.hi >= 2 && a.hi < 2 + 1e-14);
    a = gg_ival_log(gg_iv(0, 1));
    assert_true(a.lo == -INFINITY && a.hi >= 0);
    /* Even powers of intervals straddling 0 start at 0 (not at -4). */
    a = gg_ival_powi(gg_iv(-2, 1), 2);
    assert_true(a.lo == 0 && a.hi >= 4);
    a = gg_iv_sqr(gg_iv(-2, 1));
    assert_true(a.lo == 0 && a.hi >= 4);
    a = gg_ival_powi(gg_iv(-2, 1), 3);
    assert_true(a.lo <= -8 && a.hi >= 1 && a.hi < 1.0000001);
    /* 0 * inf is 0 for intervals over the reals. */
    a = gg_iv_mul(gg_iv(0, 0), gg_iv_entire());
    assert_true(a.lo <= 0 && a.hi >= 0 && isfinite(a.lo) && isfinite(a.hi));
    /* Outward rounding: 0.1 + 0.2 is enclosed although it rounds up. */
    a = gg_iv_add(gg_iv(0.1, 0.1), gg_iv(0.2, 0.2));
    assert_true(a.lo < 0.1 + 0.2 && a.hi >= 0.1 + 0.2 && a.lo < 0.3 && a.hi > 0.3);
}

/* Random bytes and mutations of good expressions: an error code or a
   working expression, never a crash (ASan and UBSan watch in make check). */
static void test_malformed_never_crash(void **state)
{
    static const char alphabet[] = "xyz0123456789.e+-*/^(),pisqrtncoabmlgw #\n";
    tu_rng rng = {131};
    char buf[80];
    int i, ok = 0, bad = 0;
    (void)state;
    for (i = 0; i < 20000; i++) {
        size_t n = (size_t)(tu_next(&rng) % 40), k;
        gg_expr *e;
        ggError err;
        int rc;
        if (i % 2) {
            const char *base = cases[tu_next(&rng) % NCASES].src;
            n = strlen(base);
            memcpy(buf, base, n);
            for (k = 0; k < 1 + (size_t)(i / 2) % 3; k++)
                buf[tu_next(&rng) % n] = alphabet[tu_next(&rng) % (sizeof alphabet - 1)];
        } else {
            for (k = 0; k < n; k++)
                buf[k] = i % 4 ? alphabet[tu_next(&rng) % (sizeof alphabet - 1)]
                               : (char)(tu_next(&rng) % 256);
        }
        rc = gg_expr_compile(buf, n, NULL, &e, &err);
        if (rc == GG_OK) {
            ggVec3 g;
            gg_ival box[3] = {{-1, 1}, {-1, 1}, {-1, 1}}, dg;
            int partial = 0;
            ok++;
            gg_expr_eval(e, v3(0.5, -0.25, 2));
            gg_expr_grad(e, v3(0.5, -0.25, 2), &g);
            gg_expr_ival(e, box);
            gg_expr_ival_ray(e, v3(0, 0, 0), v3(1, 2, 3), gg_iv(0, 1), &dg, &partial);
            gg_expr_free(e);
        } else {
            assert_true(rc == GG_ERROR_PARSE || rc == GG_ERROR_LIMIT);
            assert_null(e);
            /* Every message starts with line:column. */
            assert_true(err.message[0] >= '1' && err.message[0] <= '9' &&
                        strchr(err.message, ':') != NULL);
            bad++;
        }
    }
    print_message("%d compiled, %d rejected\n", ok, bad);
    assert_true(ok > 500 && bad > 5000);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parse_accepts),
        cmocka_unit_test(test_parse_rejects_with_columns),
        cmocka_unit_test(test_parse_limits),
        cmocka_unit_test(test_compile_folds_and_shares),
        cmocka_unit_test(test_locale_independent_numbers),
        cmocka_unit_test(test_eval_matches_c),
        cmocka_unit_test(test_dual_gradients_exact),
        cmocka_unit_test(test_interval_enclosures),
        cmocka_unit_test(test_interval_real_enclosure),
        cmocka_unit_test(test_interval_functions),
        cmocka_unit_test(test_malformed_never_crash),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
