/* SPDX-License-Identifier: MIT */
/*
** expr.h -- expressions f(x, y, z) compiled to a tape (internal).
**
** gg_expr_compile parses the text (expr.c) into a straight-line program in
** SSA form: instruction i computes slot i from earlier slots, the last slot
** is f. Constants are folded and repeated subexpressions shared, so x^2
** written twice is computed once. The tape is then run four ways:
**   plain doubles                    (expr_eval.c)
**   dual numbers: value + gradient   (expr_eval.c)  exact normals N = grad f
**   intervals                        (expr_ival.c)  rigorous enclosures
**   intervals along a ray + d/dt     (expr_ival.c)  root isolation
** A compiled expression is immutable, so every evaluator is thread-safe;
** each keeps its slots on the stack (at most GG_EXPR_MAX_TAPE of them).
*/
#ifndef GG_EXPR_H
#define GG_EXPR_H

#include "core.h"
#include "ival.h"

/* Hard limits; beyond them gg_expr_compile returns GG_ERROR_LIMIT. */
#define GG_EXPR_MAX_LEN   GG_IMPLICIT_MAX_EXPR  /* bytes of source text */
#define GG_EXPR_MAX_TAPE  GG_IMPLICIT_MAX_TAPE  /* instructions after folding, sharing */
#define GG_EXPR_MAX_DEPTH GG_IMPLICIT_MAX_DEPTH /* nesting of (), calls, unary signs, ^ */
#define GG_EXPR_MAX_POWI  64                    /* |n| up to which x^n is repeated squaring */

enum {
    GG_OP_CONST, /* c */
    GG_OP_X,
    GG_OP_Y,
    GG_OP_Z,
    GG_OP_NEG, /* unary */
    GG_OP_SQR,
    GG_OP_SQRT,
    GG_OP_SIN,
    GG_OP_COS,
    GG_OP_TAN,
    GG_OP_EXP,
    GG_OP_LOG,
    GG_OP_ABS,
    GG_OP_POWI, /* a^n, n integer, |n| >= 2 or n = -1 */
    GG_OP_POWC, /* a^c, c a constant: not an integer, or one past POWI's 1e9 */
    GG_OP_ADD,  /* binary */
    GG_OP_SUB,
    GG_OP_MUL,
    GG_OP_DIV,
    GG_OP_MIN,
    GG_OP_MAX,
    GG_OP_COUNT
};

typedef struct gg_expr_ins {
    unsigned char op;
    unsigned short a, b; /* operand slots */
    int n;               /* POWI exponent */
    double c;            /* CONST value, POWC exponent */
} gg_expr_ins;

typedef struct gg_expr {
    const ggAllocator *alloc; /* &alloc_copy, or NULL for malloc */
    ggAllocator alloc_copy;
    size_t n; /* instructions; slot n - 1 is the result */
    gg_expr_ins *ins;
} gg_expr;

/* Compile src[0..len) (need not be NUL-terminated; a NUL byte is an
   error). On failure *out is NULL and err gets "line:col: message" with
   1-based line and column (in bytes). Returns GG_OK, GG_ERROR_PARSE,
   GG_ERROR_LIMIT, GG_ERROR_NOMEM or GG_ERROR_INVALID (NULL arguments). */
int gg_expr_compile(const char *src, size_t len, const ggAllocator *alloc, gg_expr **out,
                    ggError *err);
void gg_expr_free(gg_expr *e);

/* The point operation of one instruction (also used to fold constants). */
double gg_expr_apply(const gg_expr_ins *ins, double a, double b);

/* f(p). NaN where f is undefined (sqrt of a negative number...). */
double gg_expr_eval(const gg_expr *e, ggVec3 p);
/* f(p) and, in *grad, its exact gradient (forward-mode dual numbers). */
double gg_expr_grad(const gg_expr *e, ggVec3 p, ggVec3 *grad);

/* Enclosure of f over the box x[0] x x[1] x x[2]. */
gg_ival gg_expr_ival(const gg_expr *e, const gg_ival x[3]);
/* Enclosure of g(t) = f(o + t d) for t in T and, in *dg, of g'(t) =
   grad f . d there. dg is the generalised (Clarke) derivative at the kinks
   of abs, min and max, so 0 outside *dg still proves g strictly monotone
   on T -- provided g is defined on all of T: *partial is set to 1 when some
   sqrt, log or non-integer power met arguments below 0 (g may then have
   gaps, where neither monotonicity nor the mean value theorem holds), and
   left alone otherwise. */
gg_ival gg_expr_ival_ray(const gg_expr *e, ggVec3 o, ggVec3 d, gg_ival t, gg_ival *dg,
                         int *partial);

#endif
