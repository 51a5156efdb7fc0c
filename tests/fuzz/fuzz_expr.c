/* SPDX-License-Identifier: MIT */
/*
** fuzz_expr.c -- libFuzzer harness for the expression compiler and its
** evaluators: arbitrary bytes are compiled; what compiles is evaluated on
** doubles, dual numbers and intervals, and a surface made from it is hit by
** a few rays. Never a crash, a leak or an endless loop, and these
** properties hold (abort() otherwise, which the fuzzer and the replayer
** report):
**   - an error is GG_ERROR_PARSE or GG_ERROR_LIMIT with a "line:col: " message;
**   - the dual evaluator's value is the plain value, bit for bit;
**   - every point value lies in the interval enclosure of a box around the
**     point, and of a ray segment through it -- when every intermediate
**     value is finite. Enclosures are of the real function: at a pole the
**     IEEE result is +-inf by the sign of a zero, and exp(-inf) = 0 can
**     make that finite again, outside a one-sided enclosure like
**     1 / [0, 1] = [1, inf].
*/
#include "expr.h"
#include "implicit.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check(int ok)
{
    if (!ok) abort();
}

static int inside(gg_ival f, double v)
{
    return f.lo <= v && v <= f.hi;
}

/* Is every slot of the tape finite at p? */
static int real_path(const gg_expr *e, ggVec3 p)
{
    double v[GG_EXPR_MAX_TAPE];
    size_t i;
    for (i = 0; i < e->n; i++) {
        const gg_expr_ins *in = &e->ins[i];
        if (in->op == GG_OP_X)
            v[i] = p.x;
        else if (in->op == GG_OP_Y)
            v[i] = p.y;
        else if (in->op == GG_OP_Z)
            v[i] = p.z;
        else
            v[i] = gg_expr_apply(in, in->op == GG_OP_CONST ? 0 : v[in->a],
                                 in->op >= GG_OP_ADD ? v[in->b] : 0);
        if (!isfinite(v[i])) return 0;
    }
    return 1;
}

static void probe(const gg_expr *e, ggVec3 p, double w)
{
    gg_ival box[3], f, df;
    ggVec3 g, q, o = {p.x - 1, p.y - 0.5, p.z - 0.25}, d = {1, 0.5, 0.25};
    double v = gg_expr_eval(e, p), vd = gg_expr_grad(e, p, &g);
    int partial = 0;
    check(memcmp(&v, &vd, sizeof v) == 0 || (v != v && vd != vd));
    if (!real_path(e, p)) return;
    box[0] = gg_iv(p.x - w, p.x + w);
    box[1] = gg_iv(p.y, p.y + w);
    box[2] = gg_iv(p.z - w, p.z);
    check(inside(gg_expr_ival(e, box), v));
    box[0] = gg_iv(p.x, p.x), box[1] = gg_iv(p.y, p.y), box[2] = gg_iv(p.z, p.z);
    check(inside(gg_expr_ival(e, box), v));
    /* The point at t = 1 on the ray, as the root finder computes it. */
    f = gg_expr_ival_ray(e, o, d, gg_iv(1 - w, 1 + w), &df, &partial);
    q.x = o.x + 1 * d.x, q.y = o.y + 1 * d.y, q.z = o.z + 1 * d.z;
    if (real_path(e, q)) check(inside(f, gg_expr_eval(e, q)));
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    gg_expr *e = NULL;
    ggError err;
    char *text;
    int rc = gg_expr_compile((const char *)data, size, NULL, &e, &err);
    if (rc != GG_OK) {
        check(e == NULL);
        check(rc == GG_ERROR_PARSE || rc == GG_ERROR_LIMIT);
        check(err.message[0] >= '1' && err.message[0] <= '9' && strchr(err.message, ':'));
        return 0;
    }
    check(e != NULL && e->n >= 1 && e->n <= GG_EXPR_MAX_TAPE);
    {
        static const double pts[][3] = {
            {0.5, -0.25, 2}, {0, 0, 0}, {-1e-3, 3, -7.5}, {1e8, -1e-8, 0.125}};
        size_t i;
        for (i = 0; i < sizeof pts / sizeof pts[0]; i++) {
            ggVec3 p = {pts[i][0], pts[i][1], pts[i][2]};
            probe(e, p, 0.5);
            probe(e, p, 1e-9);
        }
    }
    gg_expr_free(e);
    /* The public path on the same text, with rays (bounded work). */
    text = malloc(size + 1);
    if (!text) return 0;
    memcpy(text, data, size);
    text[size] = 0;
    if (strlen(text) == size) {
        ggImplicit *imp = NULL;
        ggVec3 lo = {-2, -2, -2}, hi = {2, 2, 2};
        check(ggImplicitCreateExpr(text, lo, hi, NULL, &imp, NULL) == GG_OK);
        if (ggImplicitSetBudget(imp, 2000) == GG_OK) {
            ggVec3 o1 = {-3, 0.1, 0.2}, d1 = {1, 0, 0}, o2 = {0.3, 0.3, 0.3}, d2 = {-1, 2, -0.5};
            double t = -1;
            if (gg_implicit_intersect(imp, o1, d1, 0, 1e30, &t)) check(t > 0 && t < 1e30);
            if (gg_implicit_intersect(imp, o2, d2, 0, 1e30, &t)) check(t > 0 && t < 1e30);
            (void)ggGradientNormal(imp, o2);
            (void)ggGradientCentral(imp, o2, 1e-6);
        }
        ggImplicitFree(imp);
    }
    free(text);
    return 0;
}
