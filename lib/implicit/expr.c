/* SPDX-License-Identifier: MIT */
/*
** expr.c -- tokenizer and recursive-descent compiler of expressions in x,
** y, z to the tape described in expr.h.
**
** Grammar (lowest precedence first; ^ binds tighter than unary minus and
** to the right, as in mathematics: -x^2 = -(x^2), 2^3^2 = 2^9):
**   expr    := term (('+' | '-') term)*
**   term    := unary (('*' | '/') unary)*
**   unary   := ('-' | '+') unary | power
**   power   := primary ('^' unary)?
**   primary := number | x | y | z | pi | name '(' expr (',' expr)* ')' | '(' expr ')'
** Numbers: digits with an optional fraction and exponent (1, 1.5, .5, 2e-3).
**
** Code is emitted while parsing. Each emit first folds constants, then
** looks for an identical instruction to share; a final pass drops what the
** result does not use. x^n with a constant integer n becomes POWI (exact
** for negative x), other constant exponents POWC (x >= 0), and a
** non-constant exponent x^e becomes exp(e * log(x)), defined for x > 0.
*/
#include "expr.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Instructions the parser may create before dead code is dropped. Every
   source byte yields at most three, so this cannot be reached within
   GG_EXPR_MAX_LEN, but it keeps slot numbers inside unsigned short. */
#define WORK_MAX (4 * GG_EXPR_MAX_LEN)

enum { TK_END, TK_NUM, TK_NAME, TK_PUNCT };

typedef struct parser {
    const char *s;
    size_t len, pos;
    int tok;     /* current token */
    size_t tpos; /* its first byte */
    size_t tlen; /* its length */
    double num;  /* TK_NUM value */
    int depth;
    int status; /* first error, GG_OK until then */
    ggError *err;
    const ggAllocator *alloc;
    gg_expr_ins *ins;
    size_t n, cap;
} parser;

static const struct {
    const char *name;
    int op;
    int arity; /* -2: two or more */
} funcs[] = {
    {"sqrt", GG_OP_SQRT, 1}, {"sin", GG_OP_SIN, 1}, {"cos", GG_OP_COS, 1}, {"tan", GG_OP_TAN, 1},
    {"exp", GG_OP_EXP, 1},   {"log", GG_OP_LOG, 1}, {"abs", GG_OP_ABS, 1}, {"min", GG_OP_MIN, -2},
    {"max", GG_OP_MAX, -2},  {"pow", -1, 2},
};

/* ---- errors ---- */

static int fail(parser *p, size_t pos, int code, const char *fmt, ...) GG_PRINTF(4, 5);

static int fail(parser *p, size_t pos, int code, const char *fmt, ...)
{
    size_t i;
    int line = 1, col = 1;
    char msg[400];
    va_list ap;
    if (p->status != GG_OK) return -1; /* keep the first error */
    for (i = 0; i < pos && i < p->len; i++) {
        if (p->s[i] == '\n')
            line++, col = 1;
        else
            col++;
    }
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    p->status = gg_error_set(p->err, code, "%d:%d: %s", line, col, msg);
    return -1;
}

/* The current token as text for a message: "'sinn'", "'#'", "end of
   expression"; bytes that are not printable ASCII come out as \xNN. */
static void describe(const parser *p, char *buf, size_t size)
{
    size_t i, o = 0, n = p->tlen > 24 ? 24 : p->tlen;
    if (p->tok == TK_END) {
        snprintf(buf, size, "end of expression");
        return;
    }
    buf[o++] = '\'';
    for (i = 0; i < n && o + 6 < size; i++) {
        unsigned char ch = (unsigned char)p->s[p->tpos + i];
        if (ch >= 32 && ch < 127 && ch != '\'')
            buf[o++] = (char)ch;
        else
            o += (size_t)snprintf(buf + o, size - o, "\\x%02X", ch);
    }
    if (n < p->tlen && o + 4 < size) buf[o++] = '.', buf[o++] = '.', buf[o++] = '.';
    buf[o++] = '\'';
    buf[o] = 0;
}

/* ---- tokenizer ---- */

static int is_digit(int c)
{
    return c >= '0' && c <= '9';
}
static int is_alpha(int c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
}

static void scan_number(parser *p)
{
    const char *s = p->s;
    size_t i = p->pos, digits = 0;
    while (i < p->len && is_digit(s[i])) i++, digits++;
    if (i < p->len && s[i] == '.') {
        i++;
        while (i < p->len && is_digit(s[i])) i++, digits++;
    }
    if (digits == 0) {
        p->tlen = 1;
        fail(p, p->pos, GG_ERROR_PARSE, "expected digits around '.'");
        return;
    }
    if (i < p->len && (s[i] == 'e' || s[i] == 'E')) {
        size_t j = i + 1;
        if (j < p->len && (s[j] == '+' || s[j] == '-')) j++;
        if (j >= p->len || !is_digit(s[j])) {
            fail(p, p->pos, GG_ERROR_PARSE, "malformed exponent in number '%.*s'",
                 (int)(j - p->pos > 32 ? 32 : j - p->pos), s + p->pos);
            return;
        }
        while (j < p->len && is_digit(s[j])) j++;
        i = j;
    }
    p->tlen = i - p->pos;
    if (p->tlen >= 128) {
        fail(p, p->pos, GG_ERROR_LIMIT, "number longer than 127 characters");
        return;
    }
    (void)gg_strtod_c(s + p->pos, p->tlen, &p->num); /* checked above */
    if (isinf(p->num)) {
        fail(p, p->pos, GG_ERROR_PARSE, "number '%.*s' is too large for a double",
             (int)(p->tlen > 32 ? 32 : p->tlen), s + p->pos);
        return;
    }
    p->tok = TK_NUM;
    p->pos = i;
}

static void next(parser *p)
{
    const char *s = p->s;
    while (p->pos < p->len &&
           (s[p->pos] == ' ' || s[p->pos] == '\t' || s[p->pos] == '\n' || s[p->pos] == '\r'))
        p->pos++;
    p->tpos = p->pos;
    p->tlen = 0;
    if (p->status != GG_OK || p->pos >= p->len) {
        p->tok = TK_END;
        return;
    }
    if (is_digit(s[p->pos]) || s[p->pos] == '.') {
        scan_number(p);
        if (p->status != GG_OK) p->tok = TK_END;
        return;
    }
    if (is_alpha(s[p->pos])) {
        while (p->pos < p->len && (is_alpha(s[p->pos]) || is_digit(s[p->pos]))) p->pos++;
        p->tok = TK_NAME;
        p->tlen = p->pos - p->tpos;
        return;
    }
    p->tlen = 1;
    if (strchr("+-*/^(),", s[p->pos]) && s[p->pos] != 0) {
        p->tok = TK_PUNCT;
        p->pos++;
        return;
    }
    {
        char what[64];
        p->tok = TK_PUNCT;
        describe(p, what, sizeof what);
        fail(p, p->tpos, GG_ERROR_PARSE, "unexpected character %s", what);
        p->tok = TK_END;
    }
}

static int is_punct(const parser *p, char c)
{
    return p->tok == TK_PUNCT && p->s[p->tpos] == c;
}

static int name_is(const parser *p, const char *name)
{
    return p->tok == TK_NAME && strlen(name) == p->tlen &&
           memcmp(p->s + p->tpos, name, p->tlen) == 0;
}

/* ---- code emission ---- */

static int is_const(const parser *p, int slot)
{
    return p->ins[slot].op == GG_OP_CONST;
}

static int same_ins(const gg_expr_ins *x, const gg_expr_ins *y)
{
    return x->op == y->op && x->a == y->a && x->b == y->b && x->n == y->n &&
           memcmp(&x->c, &y->c, sizeof x->c) == 0;
}

static int is_binary(int op)
{
    return op >= GG_OP_ADD;
}
static int is_leaf(int op)
{
    return op <= GG_OP_Z;
}

static int emit(parser *p, int op, int a, int b, int n, double c)
{
    gg_expr_ins in;
    size_t i;
    if (p->status != GG_OK || a < 0 || b < 0) return -1;
    /* Sharing and folding need a canonical form. */
    if ((op == GG_OP_ADD || op == GG_OP_MUL || op == GG_OP_MIN || op == GG_OP_MAX) && a > b) {
        int t = a;
        a = b, b = t;
    }
    if (op == GG_OP_MUL && a == b) op = GG_OP_SQR;
    memset(&in, 0, sizeof in);
    in.op = (unsigned char)op;
    in.a = (unsigned short)(is_leaf(op) ? 0 : a);
    in.b = (unsigned short)(is_binary(op) ? b : 0);
    in.n = op == GG_OP_POWI ? n : 0;
    in.c = op == GG_OP_CONST || op == GG_OP_POWC ? c : 0.0;
    if (!is_leaf(op) && is_const(p, a) && (!is_binary(op) || is_const(p, b))) {
        double v = gg_expr_apply(&in, p->ins[a].c, is_binary(op) ? p->ins[b].c : 0.0);
        return emit(p, GG_OP_CONST, 0, 0, 0, v);
    }
    for (i = 0; i < p->n; i++)
        if (same_ins(&p->ins[i], &in)) return (int)i;
    if (p->n >= WORK_MAX)
        return fail(p, p->tpos, GG_ERROR_LIMIT, "expression too complex to compile");
    if (gg_mem_grow(p->alloc, (void **)&p->ins, &p->cap, p->n + 1, sizeof *p->ins) != 0)
        return fail(p, p->tpos, GG_ERROR_NOMEM, "out of memory compiling the expression");
    p->ins[p->n] = in;
    return (int)p->n++;
}

static int emit_const(parser *p, double c)
{
    return emit(p, GG_OP_CONST, 0, 0, 0, c);
}

/* base ^ ex */
static int emit_pow(parser *p, int base, int ex)
{
    double c, r;
    if (base < 0 || ex < 0) return -1;
    if (!is_const(p, ex)) /* x^e = exp(e log x) */
        return emit(p, GG_OP_EXP, emit(p, GG_OP_MUL, ex, emit(p, GG_OP_LOG, base, 0, 0, 0), 0, 0),
                    0, 0, 0);
    c = p->ins[ex].c;
    r = floor(c);
    if (c == 0) return emit_const(p, 1.0); /* as pow(x, 0) = 1 for every x */
    if (c == 1) return base;
    if (c == 2) return emit(p, GG_OP_SQR, base, 0, 0, 0);
    if (c == 0.5) return emit(p, GG_OP_SQRT, base, 0, 0, 0);
    if (r == c && fabs(c) <= 1e9) return emit(p, GG_OP_POWI, base, 0, (int)c, 0);
    return emit(p, GG_OP_POWC, base, 0, 0, c);
}

/* ---- parser ---- */

static int p_expr(parser *p);
static int p_unary(parser *p);

static int deeper(parser *p)
{
    if (++p->depth > GG_EXPR_MAX_DEPTH)
        return fail(p, p->tpos, GG_ERROR_LIMIT, "nesting deeper than %d levels", GG_EXPR_MAX_DEPTH);
    return 0;
}

static int expect_close(parser *p, size_t open_pos)
{
    char what[64];
    if (is_punct(p, ')')) {
        next(p);
        return 0;
    }
    describe(p, what, sizeof what);
    return fail(p, p->tpos, GG_ERROR_PARSE, "expected ')' to close the '(' at column %d, found %s",
                (int)open_pos + 1, what);
}

static int p_call(parser *p)
{
    char name[40];
    size_t npos = p->tpos, k;
    int f = -1, args[2], nargs = 0, v = -1;
    snprintf(name, sizeof name, "%.*s", (int)(p->tlen > 32 ? 32 : p->tlen), p->s + p->tpos);
    for (k = 0; k < sizeof funcs / sizeof funcs[0]; k++)
        if (name_is(p, funcs[k].name)) f = (int)k;
    if (f < 0) return fail(p, npos, GG_ERROR_PARSE, "unknown function '%s'", name);
    next(p); /* name */
    {
        size_t open = p->tpos;
        next(p); /* ( */
        if (deeper(p) < 0) return -1;
        for (;;) {
            int a = p_expr(p);
            if (a < 0) return -1;
            if (nargs < 2) args[nargs] = a;
            if (funcs[f].arity == -2 && nargs >= 1) /* min/max fold as they come */
                args[0] = v = emit(p, funcs[f].op, args[0], a, 0, 0);
            nargs++;
            if (!is_punct(p, ',')) break;
            next(p);
        }
        p->depth--;
        if (expect_close(p, open) < 0) return -1;
    }
    if (funcs[f].arity == -2) {
        if (nargs < 2)
            return fail(p, npos, GG_ERROR_PARSE, "%s() takes at least 2 arguments, got %d", name,
                        nargs);
        return v;
    }
    if (nargs != funcs[f].arity)
        return fail(p, npos, GG_ERROR_PARSE, "%s() takes %d argument%s, got %d", name,
                    funcs[f].arity, funcs[f].arity == 1 ? "" : "s", nargs);
    if (funcs[f].op < 0) return emit_pow(p, args[0], args[1]);
    return emit(p, funcs[f].op, args[0], 0, 0, 0);
}

static int p_primary(parser *p)
{
    char what[64];
    if (p->tok == TK_NUM) {
        int r = emit_const(p, p->num);
        next(p);
        return r;
    }
    if (p->tok == TK_NAME) {
        int r;
        size_t save = p->pos;
        /* A name is a call when '(' follows it. */
        while (save < p->len && (p->s[save] == ' ' || p->s[save] == '\t' || p->s[save] == '\n' ||
                                 p->s[save] == '\r'))
            save++;
        if (save < p->len && p->s[save] == '(') return p_call(p);
        if (name_is(p, "x"))
            r = emit(p, GG_OP_X, 0, 0, 0, 0);
        else if (name_is(p, "y"))
            r = emit(p, GG_OP_Y, 0, 0, 0, 0);
        else if (name_is(p, "z"))
            r = emit(p, GG_OP_Z, 0, 0, 0, 0);
        else if (name_is(p, "pi"))
            r = emit_const(p, GG_PI);
        else {
            size_t k;
            describe(p, what, sizeof what);
            for (k = 0; k < sizeof funcs / sizeof funcs[0]; k++)
                if (name_is(p, funcs[k].name))
                    return fail(p, p->tpos, GG_ERROR_PARSE, "expected '(' after %s", what);
            return fail(p, p->tpos, GG_ERROR_PARSE,
                        "unknown variable %s (the variables are x, y, z and the constant pi)",
                        what);
        }
        next(p);
        return r;
    }
    if (is_punct(p, '(')) {
        size_t open = p->tpos;
        int r;
        next(p);
        r = p_expr(p);
        if (r < 0) return -1;
        return expect_close(p, open) < 0 ? -1 : r;
    }
    describe(p, what, sizeof what);
    return fail(p, p->tpos, GG_ERROR_PARSE,
                "expected a number, a variable, a function or '(', found %s", what);
}

static int p_power(parser *p)
{
    int base = p_primary(p), ex;
    if (base < 0 || !is_punct(p, '^')) return base;
    next(p);
    if (deeper(p) < 0) return -1;
    ex = p_unary(p);
    p->depth--;
    return emit_pow(p, base, ex);
}

static int p_unary(parser *p)
{
    if (is_punct(p, '-') || is_punct(p, '+')) {
        int neg = is_punct(p, '-'), a;
        next(p);
        if (deeper(p) < 0) return -1;
        a = p_unary(p);
        p->depth--;
        return neg ? emit(p, GG_OP_NEG, a, 0, 0, 0) : a;
    }
    return p_power(p);
}

static int p_term(parser *p)
{
    int a = p_unary(p);
    while (a >= 0 && (is_punct(p, '*') || is_punct(p, '/'))) {
        int op = is_punct(p, '*') ? GG_OP_MUL : GG_OP_DIV;
        next(p);
        a = emit(p, op, a, p_unary(p), 0, 0);
    }
    return a;
}

static int p_expr(parser *p)
{
    int a;
    if (deeper(p) < 0) return -1;
    a = p_term(p);
    while (a >= 0 && (is_punct(p, '+') || is_punct(p, '-'))) {
        int op = is_punct(p, '+') ? GG_OP_ADD : GG_OP_SUB;
        next(p);
        a = emit(p, op, a, p_term(p), 0, 0);
    }
    p->depth--;
    return a;
}

/* Keep what `root` needs, in order; root becomes the last slot. Returns
   the new length, 0 when out of memory. */
static size_t drop_dead(const ggAllocator *alloc, gg_expr_ins *ins, size_t root)
{
    unsigned short *map = gg_mem_alloc(alloc, (root + 1) * sizeof *map);
    size_t i, n = 0;
    if (!map) return 0;
    /* map[i] = 1 marks slot i as used, then becomes its new index + 1. */
    memset(map, 0, (root + 1) * sizeof *map);
    map[root] = 1;
    for (i = root + 1; i-- > 0;) {
        if (!map[i]) continue;
        if (!is_leaf(ins[i].op)) map[ins[i].a] = 1;
        if (is_binary(ins[i].op)) map[ins[i].b] = 1;
    }
    for (i = 0; i <= root; i++) {
        if (!map[i]) continue;
        ins[n] = ins[i];
        if (!is_leaf(ins[n].op)) ins[n].a = (unsigned short)(map[ins[i].a] - 1);
        if (is_binary(ins[n].op)) ins[n].b = (unsigned short)(map[ins[i].b] - 1);
        map[i] = (unsigned short)++n;
    }
    gg_mem_free(alloc, map);
    return n;
}

int gg_expr_compile(const char *src, size_t len, const ggAllocator *alloc, gg_expr **out,
                    ggError *err)
{
    parser p;
    gg_expr *e;
    size_t i;
    int root;
    if (!src || !out) return gg_error_set(err, GG_ERROR_INVALID, "expression: NULL argument");
    *out = NULL; /* after the NULL checks: base.h rule 1 */
    if (len > GG_EXPR_MAX_LEN)
        return gg_error_set(err, GG_ERROR_LIMIT, "1:%d: expression longer than %d characters",
                            GG_EXPR_MAX_LEN + 1, GG_EXPR_MAX_LEN);
    for (i = 0; i < len; i++)
        if (src[i] == 0)
            return gg_error_set(err, GG_ERROR_PARSE, "1:%d: NUL byte in expression", (int)i + 1);
    memset(&p, 0, sizeof p);
    p.s = src;
    p.len = len;
    p.err = err;
    p.alloc = alloc;
    next(&p);
    if (p.status == GG_OK && p.tok == TK_END) {
        fail(&p, 0, GG_ERROR_PARSE, "empty expression");
        return p.status;
    }
    root = p_expr(&p);
    if (root >= 0 && p.tok != TK_END) {
        char what[64];
        describe(&p, what, sizeof what);
        if (is_punct(&p, ')'))
            fail(&p, p.tpos, GG_ERROR_PARSE, "unmatched ')'");
        else
            fail(&p, p.tpos, GG_ERROR_PARSE, "expected an operator or the end, found %s", what);
    }
    if (p.status == GG_OK) {
        p.n = drop_dead(alloc, p.ins, (size_t)root);
        if (p.n == 0)
            fail(&p, 0, GG_ERROR_NOMEM, "out of memory compiling the expression");
        else if (p.n > GG_EXPR_MAX_TAPE)
            fail(&p, 0, GG_ERROR_LIMIT, "expression needs %lu instructions, more than %d",
                 (unsigned long)p.n, GG_EXPR_MAX_TAPE);
    }
    if (p.status != GG_OK) {
        gg_mem_free(alloc, p.ins);
        return p.status;
    }
    e = gg_mem_alloc(alloc, sizeof *e);
    if (!e) {
        gg_mem_free(alloc, p.ins);
        return gg_error_set(err, GG_ERROR_NOMEM, "expression: out of memory");
    }
    e->alloc = NULL;
    if (alloc) e->alloc_copy = *alloc, e->alloc = &e->alloc_copy;
    e->n = p.n;
    e->ins = p.ins;
    *out = e;
    return GG_OK;
}

void gg_expr_free(gg_expr *e)
{
    if (!e) return;
    gg_mem_free(e->alloc, e->ins);
    gg_mem_free(e->alloc, e);
}
