/* SPDX-License-Identifier: MIT */
/*
** pred.c -- the predicate language of ggFind (debug.h): tokenizer and
** recursive-descent parser to a small tree, with type and level checks
** that name the column of the first mistake.
**
** Grammar (lowest precedence first):
**   or      := and ('||' and)*
**   and     := not ('&&' not)*
**   not     := '!' not | primary
**   primary := '(' or ')' | ('some' | 'all') '(' or ')' | operand [cmpop operand]
**   operand := number | name ['.' component] | 'count' '(' or ')'
** A name is a field, or one of the named values of the field on the other
** side of == or !=. Identifiers may contain '-' (facing-away): the
** language has no arithmetic.
*/
#include "debug_int.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef GG_STOP_BUDGET
#define GG_STOP_BUDGET 4
#endif

typedef struct enum_val {
    const char *name;
    int value;
} enum_val;

static const enum_val kinds[] = {{"eye", GG_RAY_EYE},         {"reflect", GG_RAY_REFLECT},
                                 {"refract", GG_RAY_REFRACT}, {"tir", GG_RAY_TIR},
                                 {"shadow", GG_PRED_SHADOW},  {NULL, 0}};
static const enum_val stops[] = {{"none", GG_STOP_NONE},     {"miss", GG_STOP_MISS},
                                 {"depth", GG_STOP_DEPTH},   {"matte", GG_STOP_MATTE},
                                 {"budget", GG_STOP_BUDGET}, {NULL, 0}};
static const enum_val verdicts[] = {
    {"visible", GG_SHADOW_VISIBLE},         {"blocked", GG_SHADOW_BLOCKED},
    {"attenuated", GG_SHADOW_ATTENUATED},   {"facing_away", GG_SHADOW_FACING_AWAY},
    {"facing-away", GG_SHADOW_FACING_AWAY}, {NULL, 0}};
static const enum_val channels[] = {{"rgb", -1}, {"red", 0}, {"green", 1}, {"blue", 2}, {NULL, 0}};

typedef struct field_def {
    const char *name;
    int type;
    const enum_val *vals; /* PT_ENUM; NULL for shape (ggShapeKindName) */
} field_def;

/* Indexed by PF_*. */
static const field_def fields[PF_COUNT] = {
    {"kind", PT_ENUM, kinds},
    {"depth", PT_NUM, NULL},
    {"channel", PT_ENUM, channels},
    {"object", PT_NUM, NULL},
    {"material", PT_NUM, NULL},
    {"line", PT_NUM, NULL},
    {"shape", PT_ENUM, NULL},
    {"front", PT_BOOL, NULL},
    {"back", PT_BOOL, NULL},
    {"hit", PT_BOOL, NULL},
    {"miss", PT_BOOL, NULL},
    {"t", PT_NUM, NULL},
    {"stop", PT_ENUM, stops},
    {"fresnel", PT_NUM, NULL},
    {"weight", PT_COLOR, NULL},
    {"color", PT_COLOR, NULL},
    {"absorption", PT_COLOR, NULL},
    {"nonfinite", PT_BOOL, NULL},
    {"light", PT_NUM, NULL},
    {"verdict", PT_ENUM, verdicts},
    {"occluder", PT_NUM, NULL},
    {"transmittance", PT_COLOR, NULL},
    {"diffuse", PT_COLOR, NULL},
    {"phong", PT_COLOR, NULL},
    {"medium", PT_NUM, NULL},
    {"perr", PT_NUM, NULL},
    {"offset", PT_NUM, NULL},
    {"tir_margin", PT_NUM, NULL},
    {"edge", PT_NUM, NULL},
    {"triangle", PT_NUM, NULL},
    {"nodes", PT_NUM, NULL},
    {"prims", PT_NUM, NULL},
    {"x", PT_NUM, NULL},
    {"y", PT_NUM, NULL},
    {"pixel", PT_COLOR, NULL},
    {"rays", PT_NUM, NULL},
};

static const char *const comps[] = {"r", "g", "b", "max", "min"};

enum { TK_END, TK_NUM, TK_NAME, TK_OP, TK_LP, TK_RP, TK_DOT, TK_BAD };

typedef struct parser {
    const char *s;
    size_t len, pos;
    int tok;
    size_t tpos, tlen;
    double num;
    int depth;    /* nesting, against GG_PREDICATE_MAX_DEPTH */
    int in_quant; /* inside some/all/count */
    int status;
    ggError *err;
    ggPredicate *p;
    size_t cap;
} parser;

/* ---- errors ---- */

static int fail(parser *ps, size_t pos, int code, const char *fmt, ...) GG_PRINTF(4, 5);

static int fail(parser *ps, size_t pos, int code, const char *fmt, ...)
{
    size_t i;
    int line = 1, col = 1;
    char msg[400];
    va_list ap;
    if (ps->status != GG_OK) return -1; /* keep the first error */
    for (i = 0; i < pos && i < ps->len; i++) {
        if (ps->s[i] == '\n')
            line++, col = 1;
        else if (((unsigned char)ps->s[i] & 0xC0) != 0x80)
            col++; /* count characters */
    }
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    ps->status = gg_error_set(ps->err, code, "%d:%d: %s", line, col, msg);
    return -1;
}

/* The current token as text for messages, shortened. */
static const char *tok_text(const parser *ps, char *buf, size_t n)
{
    size_t k = ps->tlen < n - 3 ? ps->tlen : n - 3;
    if (ps->tok == TK_END) return "the end";
    buf[0] = '\'';
    memcpy(buf + 1, ps->s + ps->tpos, k);
    buf[k + 1] = '\'', buf[k + 2] = '\0';
    return buf;
}

/* ---- tokens ---- */

static int is_name_char(int c, int first)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' ||
           (!first && ((c >= '0' && c <= '9') || c == '-'));
}

static int is_digit(int c)
{
    return c >= '0' && c <= '9';
}

static void next(parser *ps)
{
    const char *s = ps->s;
    size_t n = ps->len, i = ps->pos;
    while (i < n && (s[i] == ' ' || s[i] == '\t' || s[i] == '\n' || s[i] == '\r')) i++;
    ps->tpos = i;
    ps->tlen = 1;
    if (i >= n) {
        ps->tok = TK_END, ps->tlen = 0;
    } else if (is_digit(s[i]) || ((s[i] == '.' || s[i] == '-' || s[i] == '+') && i + 1 < n &&
                                  (is_digit(s[i + 1]) || s[i + 1] == '.'))) {
        size_t k = gg_dbg_number(s + i, n - i, &ps->num);
        ps->tok = k ? TK_NUM : TK_BAD, ps->tlen = k ? k : 1;
    } else if (is_name_char((unsigned char)s[i], 1)) {
        size_t k = 1;
        while (i + k < n && is_name_char((unsigned char)s[i + k], 0)) k++;
        ps->tok = TK_NAME, ps->tlen = k;
    } else if (s[i] == '(' || s[i] == ')' || s[i] == '.') {
        ps->tok = s[i] == '(' ? TK_LP : s[i] == ')' ? TK_RP : TK_DOT;
    } else if (i + 1 < n &&
               (!strncmp(s + i, "&&", 2) || !strncmp(s + i, "||", 2) || !strncmp(s + i, "==", 2) ||
                !strncmp(s + i, "!=", 2) || !strncmp(s + i, "<=", 2) || !strncmp(s + i, ">=", 2))) {
        ps->tok = TK_OP, ps->tlen = 2;
    } else if (s[i] == '!' || s[i] == '<' || s[i] == '>' || s[i] == '=' || s[i] == '&' ||
               s[i] == '|') {
        ps->tok = TK_OP;
    } else {
        ps->tok = TK_BAD;
        while (i + ps->tlen < n && ((unsigned char)s[i + ps->tlen] & 0xC0) == 0x80) ps->tlen++;
    }
    ps->pos = ps->tpos + ps->tlen;
}

static int tok_is(const parser *ps, int tok, const char *text)
{
    return ps->tok == tok &&
           (!text || (strlen(text) == ps->tlen && !strncmp(ps->s + ps->tpos, text, ps->tlen)));
}

/* ---- the tree ---- */

static int add(parser *ps, int op)
{
    ggPredicate *p = ps->p;
    gg_pnode *n;
    if (ps->status != GG_OK) return -1;
    if (gg_mem_grow(p->alloc, (void **)&p->n, &ps->cap, (size_t)p->count + 1, sizeof *p->n)) {
        ps->status = gg_error_set(ps->err, GG_ERROR_NOMEM, "predicate: out of memory");
        return -1;
    }
    n = &p->n[p->count];
    memset(n, 0, sizeof *n);
    n->op = op;
    n->a = n->b = n->field = -1;
    return p->count++;
}

static int field_index(const char *s, size_t n)
{
    int i;
    for (i = 0; i < PF_COUNT; i++)
        if (strlen(fields[i].name) == n && !strncmp(fields[i].name, s, n)) return i;
    return -1;
}

/* The value of a named constant of field f, or INT_MIN-like -999 if none. */
#define NO_VALUE (-999)
static int enum_value(int f, const char *s, size_t n)
{
    int i;
    if (f == PF_SHAPE) {
        for (i = 0; i < GG_SHAPE_COUNT; i++)
            if (strlen(ggShapeKindName(i)) == n && !strncmp(ggShapeKindName(i), s, n)) return i;
        return NO_VALUE;
    }
    for (i = 0; fields[f].vals[i].name; i++)
        if (strlen(fields[f].vals[i].name) == n && !strncmp(fields[f].vals[i].name, s, n))
            return fields[f].vals[i].value;
    return NO_VALUE;
}

/* "eye, reflect, ..." for messages. */
static void enum_list(int f, char *buf, size_t n)
{
    size_t k = 0;
    int i;
    buf[0] = '\0';
    for (i = 0;; i++) {
        const char *name = f == PF_SHAPE ? (i < GG_SHAPE_COUNT ? ggShapeKindName(i) : NULL)
                                         : fields[f].vals[i].name;
        if (!name) break;
        if (f == PF_VERDICT && !strcmp(name, "facing-away")) continue;
        k += (size_t)snprintf(buf + k, k < n ? n - k : 0, "%s%s", i ? ", " : "", name);
        if (k >= n) break;
    }
}

static int p_or(parser *ps);

/* An unknown name: a field misspelt, or a named value used alone. */
static int unknown_name(parser *ps, size_t pos, const char *s, size_t n)
{
    const char *names[PF_COUNT];
    int i, best;
    for (i = 0; i < PF_COUNT; i++)
        if (fields[i].type == PT_ENUM && enum_value(i, s, n) != NO_VALUE)
            return fail(ps, pos, GG_ERROR_PARSE, "'%.*s' is a value of %s: write %s == %.*s",
                        (int)n, s, fields[i].name, fields[i].name, (int)n, s);
    for (i = 0; i < PF_COUNT; i++) names[i] = fields[i].name;
    best = gg_dbg_suggest(s, n, names, PF_COUNT);
    if ((n == 4 && !strncmp(s, "some", n)) || (n == 3 && !strncmp(s, "all", n)) ||
        (n == 5 && !strncmp(s, "count", n)))
        return fail(ps, pos, GG_ERROR_PARSE, "'%.*s' needs a ray expression in ( )", (int)n, s);
    if (best >= 0)
        return fail(ps, pos, GG_ERROR_PARSE, "unknown field '%.*s'; did you mean '%s'?", (int)n, s,
                    fields[best].name);
    return fail(ps, pos, GG_ERROR_PARSE, "unknown field '%.*s'", (int)n, s);
}

/* An operand being parsed: a node, plus the name it was written as (a
   name may turn out to be a named value of the other side's field). */
typedef struct operand {
    int node;        /* -1 for a name not (yet) taken as a field */
    int type;        /* PT_* of the node; a colour with or without a component is a number */
    int field;       /* PF_* or -1 */
    size_t pos, len; /* the name, if written as one (len 0 otherwise) */
} operand;

static int name_is(const parser *ps, const char *w)
{
    return ps->tok == TK_NAME && strlen(w) == ps->tlen && !strncmp(ps->s + ps->tpos, w, ps->tlen);
}

/* 'field' as a node, checking that a ray field sits inside a quantifier. */
static int field_node(parser *ps, operand *o, int f, size_t pos)
{
    int n;
    if (f < PF_FIRST_PIXEL && !ps->in_quant)
        return fail(ps, pos, GG_ERROR_PARSE,
                    "'%s' is a field of a ray: use it inside some(...), all(...) or count(...)",
                    fields[f].name);
    if ((n = add(ps, fields[f].type == PT_BOOL ? PN_BOOL : PN_FIELD)) < 0) return -1;
    ps->p->n[n].field = f;
    ps->p->n[n].comp = 3; /* max */
    o->node = n, o->field = f;
    o->type = fields[f].type == PT_COLOR ? PT_NUM : fields[f].type;
    return 0;
}

/* A quantifier's body: some(...), all(...), count(...). */
static int quantified(parser *ps, int op)
{
    size_t at = ps->tpos;
    int n, body;
    next(ps);
    if (!tok_is(ps, TK_LP, NULL)) {
        char b[40];
        return fail(ps, ps->tpos, GG_ERROR_PARSE, "expected '(' after '%s', got %s",
                    op == PN_SOME  ? "some"
                    : op == PN_ALL ? "all"
                                   : "count",
                    tok_text(ps, b, sizeof b));
    }
    if (ps->in_quant)
        return fail(ps, at, GG_ERROR_PARSE,
                    "some, all and count look at every ray already: they do not nest");
    next(ps);
    ps->in_quant = 1;
    body = p_or(ps);
    ps->in_quant = 0;
    if (body < 0) return -1;
    if (!tok_is(ps, TK_RP, NULL)) {
        char b[40];
        return fail(ps, ps->tpos, GG_ERROR_PARSE,
                    "expected ')' to close the '(' of column %d, got %s", (int)(at + 1),
                    tok_text(ps, b, sizeof b));
    }
    next(ps);
    if ((n = add(ps, op)) < 0) return -1;
    ps->p->n[n].a = body;
    return n;
}

static int p_operand(parser *ps, operand *o)
{
    char b[40];
    memset(o, 0, sizeof *o);
    o->node = o->field = -1;
    o->pos = ps->tpos;
    if (ps->tok == TK_NUM) {
        if ((o->node = add(ps, PN_NUM)) < 0) return -1;
        ps->p->n[o->node].num = ps->num;
        o->type = PT_NUM;
        next(ps);
        return 0;
    }
    if (name_is(ps, "count")) {
        if ((o->node = quantified(ps, PN_COUNT)) < 0) return -1;
        o->type = PT_NUM;
        return 0;
    }
    if (ps->tok != TK_NAME)
        return fail(ps, ps->tpos, GG_ERROR_PARSE, "expected a field, a number or '(', got %s",
                    tok_text(ps, b, sizeof b));
    o->len = ps->tlen;
    next(ps);
    if (tok_is(ps, TK_DOT, NULL)) {
        int f = field_index(ps->s + o->pos, o->len), c;
        size_t dot = ps->tpos;
        if (f < 0) return unknown_name(ps, o->pos, ps->s + o->pos, o->len);
        if (fields[f].type != PT_COLOR)
            return fail(ps, dot, GG_ERROR_PARSE, "'%s' is not a colour: it has no components",
                        fields[f].name);
        next(ps);
        for (c = 0; c < 5; c++)
            if (name_is(ps, comps[c])) break;
        if (c == 5)
            return fail(ps, ps->tpos, GG_ERROR_PARSE,
                        "a colour's component is r, g, b, max or min, got %s",
                        tok_text(ps, b, sizeof b));
        if (field_node(ps, o, f, o->pos) < 0) return -1;
        ps->p->n[o->node].comp = c;
        o->len = 0; /* written with a component: not a bare name */
        next(ps);
    }
    return 0;
}

/* Take a still-bare name as a field. */
static int as_field(parser *ps, operand *o)
{
    int f;
    if (o->node >= 0) return 0;
    f = field_index(ps->s + o->pos, o->len);
    if (f < 0) return unknown_name(ps, o->pos, ps->s + o->pos, o->len);
    return field_node(ps, o, f, o->pos);
}

/* Take name operand o as a named value of field f (the other side). */
static int as_value(parser *ps, operand *o, int f, int cmp)
{
    int v = enum_value(f, ps->s + o->pos, o->len);
    char list[200];
    if (v == NO_VALUE) {
        enum_list(f, list, sizeof list);
        return fail(ps, o->pos, GG_ERROR_PARSE, "'%.*s' is not a %s (%s)", (int)o->len,
                    ps->s + o->pos, fields[f].name, list);
    }
    if (cmp != PC_EQ && cmp != PC_NE)
        return fail(ps, o->pos, GG_ERROR_PARSE,
                    "%s values have no order: use == or !=", fields[f].name);
    if ((o->node = add(ps, PN_NUM)) < 0) return -1;
    ps->p->n[o->node].num = v;
    o->type = PT_ENUM, o->field = f;
    return 0;
}

static int cmp_op(const parser *ps)
{
    static const char *const ops[] = {"==", "!=", "<", "<=", ">", ">="};
    int i;
    if (ps->tok != TK_OP) return -1;
    for (i = 0; i < 6; i++)
        if (tok_is(ps, TK_OP, ops[i])) return i;
    return -1;
}

/* Whether operand o is a bare name that field f (an enum) has as a value. */
static int names_value(const parser *ps, const operand *o, int f)
{
    return o->len > 0 && f >= 0 && fields[f].type == PT_ENUM &&
           enum_value(f, ps->s + o->pos, o->len) != NO_VALUE;
}

/* l op r, with the names resolved and the types checked. */
static int comparison(parser *ps, operand *l, int cmp, size_t op_pos, operand *r)
{
    int n, lf = l->len ? field_index(ps->s + l->pos, l->len) : l->field;
    int rf = r->len ? field_index(ps->s + r->pos, r->len) : r->field;
    /* A name beside a field with named values is one of those values
       (stop == depth: the stop reason, not the field depth). */
    if (l->node < 0 && rf >= 0 && fields[rf].type == PT_ENUM && names_value(ps, l, rf)) {
        if (as_field(ps, r) < 0 || as_value(ps, l, rf, cmp) < 0) return -1;
    } else if (r->node < 0 && lf >= 0 && fields[lf].type == PT_ENUM &&
               (names_value(ps, r, lf) || field_index(ps->s + r->pos, r->len) < 0)) {
        if (as_field(ps, l) < 0 || as_value(ps, r, lf, cmp) < 0) return -1;
    } else if (as_field(ps, l) < 0 || as_field(ps, r) < 0) {
        return -1;
    }
    if (l->type == PT_BOOL || r->type == PT_BOOL) {
        const operand *b = l->type == PT_BOOL ? l : r;
        return fail(ps, b->pos, GG_ERROR_PARSE,
                    "'%s' is true or false: write it alone or with ! instead of comparing it",
                    fields[b->field].name);
    }
    if (l->type != r->type || (l->type == PT_ENUM && l->field != r->field)) {
        const operand *e = l->type == PT_ENUM ? l : r, *o = e == l ? r : l;
        char list[200];
        enum_list(e->field, list, sizeof list);
        return fail(ps, o->pos, GG_ERROR_PARSE, "%s is compared with a name (%s)",
                    fields[e->field].name, list);
    }
    if (l->type == PT_ENUM && cmp != PC_EQ && cmp != PC_NE)
        return fail(ps, op_pos, GG_ERROR_PARSE,
                    "%s values have no order: use == or !=", fields[l->field].name);
    if ((n = add(ps, PN_CMP)) < 0) return -1;
    ps->p->n[n].a = l->node, ps->p->n[n].b = r->node, ps->p->n[n].cmp = cmp;
    return n;
}

static int p_primary(parser *ps)
{
    operand l, r;
    size_t lpos = ps->tpos, op_pos;
    int cmp;
    char b[40];
    if (tok_is(ps, TK_LP, NULL)) {
        int n;
        next(ps);
        if ((n = p_or(ps)) < 0) return -1;
        if (!tok_is(ps, TK_RP, NULL))
            return fail(ps, ps->tpos, GG_ERROR_PARSE,
                        "expected ')' to close the '(' of column %d, got %s", (int)(lpos + 1),
                        tok_text(ps, b, sizeof b));
        next(ps);
        return n;
    }
    if (name_is(ps, "some") || name_is(ps, "all")) {
        int op = name_is(ps, "some") ? PN_SOME : PN_ALL;
        return quantified(ps, op);
    }
    if (p_operand(ps, &l) < 0) return -1;
    if ((cmp = cmp_op(ps)) < 0) {
        if (tok_is(ps, TK_OP, "="))
            return fail(ps, ps->tpos, GG_ERROR_PARSE, "'=' is not an operator: write ==");
        if (as_field(ps, &l) < 0) return -1;
        if (l.type == PT_BOOL) return l.node;
        return fail(ps, ps->tpos, GG_ERROR_PARSE, "expected %s after '%.*s', got %s",
                    l.type == PT_ENUM ? "== or !=" : "a comparison (==, !=, <, <=, >, >=)",
                    (int)(ps->tpos - lpos), ps->s + lpos, tok_text(ps, b, sizeof b));
    }
    op_pos = ps->tpos;
    next(ps);
    if (p_operand(ps, &r) < 0) return -1;
    return comparison(ps, &l, cmp, op_pos, &r);
}

static int p_not(parser *ps)
{
    int n, a;
    if (++ps->depth > GG_PREDICATE_MAX_DEPTH)
        return fail(ps, ps->tpos, GG_ERROR_LIMIT, "nested deeper than %d", GG_PREDICATE_MAX_DEPTH);
    if (tok_is(ps, TK_OP, "!")) {
        next(ps);
        if ((a = p_not(ps)) < 0 || (n = add(ps, PN_NOT)) < 0) return -1;
        ps->p->n[n].a = a;
    } else {
        n = p_primary(ps);
    }
    ps->depth--;
    return n;
}

static int p_binary(parser *ps, int op)
{
    const char *text = op == PN_OR ? "||" : "&&";
    int l = op == PN_OR ? p_binary(ps, PN_AND) : p_not(ps);
    while (l >= 0 && tok_is(ps, TK_OP, text)) {
        int r, n;
        next(ps);
        r = op == PN_OR ? p_binary(ps, PN_AND) : p_not(ps);
        if (r < 0 || (n = add(ps, op)) < 0) return -1;
        ps->p->n[n].a = l, ps->p->n[n].b = r;
        l = n;
    }
    return l;
}

static int p_or(parser *ps)
{
    int n;
    if (++ps->depth > GG_PREDICATE_MAX_DEPTH)
        return fail(ps, ps->tpos, GG_ERROR_LIMIT, "nested deeper than %d", GG_PREDICATE_MAX_DEPTH);
    n = p_binary(ps, PN_OR);
    ps->depth--;
    return n;
}

GG_API void ggPredicateFree(ggPredicate *p)
{
    if (!p) return;
    gg_mem_free(p->alloc, p->n);
    gg_mem_free(p->alloc, p);
}

GG_API int ggPredicateParse(const char *text, const ggAllocator *alloc, ggPredicate **out,
                            ggError *err)
{
    parser ps;
    ggPredicate *p;
    char b[40];
    size_t n;
    if (!text || !out)
        return gg_error_set(err, GG_ERROR_INVALID, "ggPredicateParse: NULL argument");
    *out = NULL; /* after the NULL checks: base.h rule 1 */
    n = strlen(text);
    if (n > GG_PREDICATE_MAX_TEXT)
        return gg_error_set(err, GG_ERROR_LIMIT, "1:%d: predicate longer than %d bytes",
                            GG_PREDICATE_MAX_TEXT + 1, GG_PREDICATE_MAX_TEXT);
    p = gg_mem_calloc(alloc, 1, sizeof *p);
    if (!p) return gg_error_set(err, GG_ERROR_NOMEM, "predicate: out of memory");
    if (alloc) p->alloc_copy = *alloc, p->alloc = &p->alloc_copy;
    memset(&ps, 0, sizeof ps);
    ps.s = text, ps.len = n, ps.err = err, ps.p = p, ps.status = GG_OK;
    next(&ps);
    if (ps.tok == TK_END)
        fail(&ps, 0, GG_ERROR_PARSE, "empty predicate");
    else if ((p->root = p_or(&ps)) >= 0 && ps.tok != TK_END) {
        if (tok_is(&ps, TK_OP, "&") || tok_is(&ps, TK_OP, "|"))
            fail(&ps, ps.tpos, GG_ERROR_PARSE, "'%c' is not an operator: write %s", ps.s[ps.tpos],
                 ps.s[ps.tpos] == '&' ? "&&" : "||");
        else if (tok_is(&ps, TK_RP, NULL))
            fail(&ps, ps.tpos, GG_ERROR_PARSE, "')' without a matching '('");
        else
            fail(&ps, ps.tpos, GG_ERROR_PARSE,
                 ps.tok == TK_BAD ? "unexpected character %s"
                                  : "unexpected %s after a complete predicate",
                 tok_text(&ps, b, sizeof b));
    }
    if (ps.status != GG_OK) {
        ggPredicateFree(p);
        return ps.status;
    }
    p->needs = gg_pred_analyse(p);
    *out = p;
    return GG_OK;
}

/* A ray expression (the body of some(...)) inside a path expression,
   from byte `start` of text up to the ']' that closes the '[' at start - 1:
   errors count columns in the whole text. */
int gg_pred_parse_ray(const char *text, size_t len, size_t start, const ggAllocator *alloc,
                      ggPredicate **out, size_t *end, ggError *err)
{
    parser ps;
    ggPredicate *p;
    char b[40];
    *out = NULL;
    p = gg_mem_calloc(alloc, 1, sizeof *p);
    if (!p) return gg_error_set(err, GG_ERROR_NOMEM, "path expression: out of memory");
    if (alloc) p->alloc_copy = *alloc, p->alloc = &p->alloc_copy;
    memset(&ps, 0, sizeof ps);
    ps.s = text, ps.len = len, ps.pos = start, ps.err = err, ps.p = p, ps.status = GG_OK;
    ps.in_quant = 1;
    next(&ps);
    if (ps.tok == TK_BAD && text[ps.tpos] == ']')
        fail(&ps, ps.tpos, GG_ERROR_PARSE, "empty predicate in [ ]");
    else if ((p->root = p_or(&ps)) >= 0 && !(ps.tok == TK_BAD && text[ps.tpos] == ']'))
        fail(&ps, ps.tpos, GG_ERROR_PARSE, "expected ']' to close the '[' of column %d, got %s",
             (int)start, tok_text(&ps, b, sizeof b));
    if (ps.status != GG_OK) {
        ggPredicateFree(p);
        return ps.status;
    }
    p->needs = gg_pred_analyse(p);
    *end = ps.tpos + 1;
    *out = p;
    return GG_OK;
}
