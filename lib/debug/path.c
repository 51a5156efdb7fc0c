/* SPDX-License-Identifier: MIT */
/*
** path.c -- light-path expressions (debug.h): a recursive-descent parser
** of OSL's LPE syntax to a small tree, and Thompson's construction of a
** nondeterministic automaton over path events from it, with the empty
** moves closed in advance (path_match.c runs it).
**
** Grammar (loosest first):
**   alt   := cat ('|' cat)*
**   cat   := rep rep*
**   rep   := atom ('*' | '+' | '?' | '{' n [',' [m]] '}')*
**   atom  := '(' alt ')' | item [ '[' ray-expr ']' ]
**   item  := event | '[' ['^'] event+ ']'
**   event := C R T L O B A | D G S | '.' | "'" label "'"
**          | '<' [type | '.'] [scatter | '.'] ("'" label "'")* '>'
** A '[' after an item opens a predicate when the next character (after
** spaces) is a lower-case letter, a digit, '(' or '!'; otherwise a set.
** Everything is bounded: the text, the nesting, the tree's size, the
** automaton's states and edges (GG_PATH_MAX_*).
*/
#include "debug_int.h"

#include <stdio.h>
#include <string.h>

enum { AX_EV, AX_CAT, AX_ALT, AX_STAR, AX_PLUS, AX_OPT, AX_REP };

#define MAX_NODES (4 * GG_PATH_MAX_STATES)
#define MAX_EDGES (4 * GG_PATH_MAX_STATES)

typedef struct ast {
    int op, a, b, cls, n, m; /* m -1: no upper bound */
    size_t pos;
} ast;

typedef struct lp {
    const char *s;
    size_t len, pos;
    int depth, status;
    ggError *err;
    ggPathExpr *e;
    ast t[MAX_NODES];
    int nt;
    size_t pcap, ccap, ecap;
    size_t limit_pos; /* where a state limit was hit */
} lp;

static const char types_text[] = "CRTLOBA"; /* by PE_* */

static int fail(lp *p, size_t pos, int code, const char *fmt, ...) GG_PRINTF(4, 5);

/* The line and column (from 1; columns count UTF-8 characters) of byte
   pos, as every message about the text gives them. */
static gg_path_place place(const lp *p, size_t pos)
{
    gg_path_place pl;
    size_t i;
    pl.line = 1, pl.col = 1;
    for (i = 0; i < pos && i < p->len; i++) {
        if (p->s[i] == '\n')
            pl.line++, pl.col = 1;
        else if (((unsigned char)p->s[i] & 0xC0) != 0x80)
            pl.col++;
    }
    return pl;
}

static int fail(lp *p, size_t pos, int code, const char *fmt, ...)
{
    gg_path_place pl = place(p, pos);
    int line = pl.line, col = pl.col;
    char msg[300];
    va_list ap;
    if (p->status != GG_OK) return -1;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    p->status = gg_error_set(p->err, code, "%d:%d: %s", line, col, msg);
    return -1;
}

static int nomem(lp *p)
{
    if (p->status == GG_OK)
        p->status = gg_error_set(p->err, GG_ERROR_NOMEM, "path expression: out of memory");
    return -1;
}

/* The next character after spaces (0 at the end); p->pos moves to it. */
static int peek(lp *p)
{
    while (p->pos < p->len && (p->s[p->pos] == ' ' || p->s[p->pos] == '\t' ||
                               p->s[p->pos] == '\n' || p->s[p->pos] == '\r'))
        p->pos++;
    return p->pos < p->len ? (unsigned char)p->s[p->pos] : 0;
}

/* What is at pos, for messages: "'x'" or "the end". */
static const char *what(const lp *p, size_t pos, char *buf)
{
    size_t k = 1;
    if (pos >= p->len) return "the end";
    while (pos + k < p->len && ((unsigned char)p->s[pos + k] & 0xC0) == 0x80 && k < 4) k++;
    snprintf(buf, 12, "'%.*s'", (int)k, p->s + pos);
    return buf;
}

static int node(lp *p, int op, int a, int b, size_t pos)
{
    ast *n;
    if (p->status != GG_OK) return -1;
    if (p->nt >= MAX_NODES)
        return fail(p, pos, GG_ERROR_LIMIT, "the expression has more than %d parts", MAX_NODES);
    n = &p->t[p->nt];
    memset(n, 0, sizeof *n);
    n->op = op, n->a = a, n->b = b, n->cls = -1, n->pos = pos;
    return p->nt++;
}

/* ---- events ---- */

static int new_pat(lp *p, size_t pos)
{
    ggPathExpr *e = p->e;
    gg_path_pat *q;
    if (e->npats >= GG_PATH_MAX_EVENTS)
        return fail(p, pos, GG_ERROR_LIMIT, "more than %d events", GG_PATH_MAX_EVENTS);
    if (gg_mem_grow(e->alloc, (void **)&e->pats, &p->pcap, (size_t)e->npats + 1, sizeof *e->pats))
        return nomem(p);
    q = &e->pats[e->npats];
    memset(q, 0, sizeof *q);
    q->types = (1u << PE_NTYPES) - 1, q->scatters = 0xFu;
    return e->npats++;
}

/* A 'label' at p->pos (the quote) into pattern q. */
static int label(lp *p, int q)
{
    size_t open = p->pos, i = open + 1, n;
    gg_path_pat *pt;
    const char *s;
    while (i < p->len && p->s[i] != '\'') i++;
    if (i >= p->len)
        return fail(p, open, GG_ERROR_PARSE, "no closing quote for this label");
    s = p->s + open + 1, n = i - open - 1;
    p->pos = i + 1;
    pt = &p->e->pats[q];
    if (pt->nlabels < GG_PATH_MAX_LABELS) pt->label_at[pt->nlabels] = place(p, open);
    if (pt->nlabels >= GG_PATH_MAX_LABELS)
        return fail(p, open, GG_ERROR_LIMIT, "more than %d labels on one event",
                    GG_PATH_MAX_LABELS);
    if (n == 3 && !strncmp(s, "tir", 3)) {
        pt->label_kind[pt->nlabels] = PL_TIR;
    } else {
        size_t k = n > 0 && s[0] == 'm' ? 1 : 0, j;
        long v = 0;
        for (j = k; j < n && j < k + 9 && s[j] >= '0' && s[j] <= '9'; j++) v = 10 * v + (s[j] - '0');
        /* '01' is no number ggrt prints: refused, not read as 1 */
        if (j == k || j != n || (s[k] == '0' && n > k + 1))
            return fail(p, open, GG_ERROR_PARSE,
                        "'%.*s' is not a label: 'N' (an object, or a light's number on L), "
                        "'mN' (a material) or 'tir'",
                        (int)(n > 40 ? 40 : n), s);
        pt->label_kind[pt->nlabels] = k ? PL_MATERIAL : PL_NUMBER;
        pt->label_num[pt->nlabels] = v;
    }
    pt->nlabels++;
    return 0;
}

static int type_of(int c)
{
    const char *t = c ? strchr(types_text, c) : NULL;
    return t ? (int)(t - types_text) : -1;
}

static int scatter_of(int c)
{
    return c == 'D' ? PS_D : c == 'G' ? PS_G : c == 'S' ? PS_S : -1;
}

/* <type scatter 'label'...> at p->pos. */
static int bracket(lp *p, int q)
{
    size_t open = p->pos;
    gg_path_pat *pt = &p->e->pats[q];
    int c, k;
    char b[12];
    p->pos++;
    c = peek(p);
    if (c == '.' || (k = type_of(c)) >= 0) {
        if (c != '.') pt->types = 1u << k;
        p->pos++;
        c = peek(p);
        if (c == '.' || (k = scatter_of(c)) >= 0) {
            if (c != '.') pt->scatters = 1u << k;
            p->pos++;
        } else if (c >= 'A' && c <= 'Z') {
            return fail(p, p->pos, GG_ERROR_PARSE, "'%c' is not a scatter type (D G S or .)", c);
        }
    } else if ((k = scatter_of(c)) >= 0) {
        /* the type left out (the grammar makes both optional): the
           letters of the two never overlap, so <S> is <.S> */
        pt->scatters = 1u << k;
        p->pos++;
    } else if (c >= 'A' && c <= 'Z') {
        return fail(p, p->pos, GG_ERROR_PARSE,
                    "'%c' is not an event type (C R T L O B A or .)", c);
    }
    while ((c = peek(p)) == '\'')
        if (label(p, q) < 0) return -1;
    if (c != '>')
        return fail(p, p->pos, GG_ERROR_PARSE, "expected '>' to close the '<' of column %d, got %s",
                    (int)open + 1, what(p, p->pos, b));
    p->pos++;
    return 0;
}

/* One event into a new pattern; returns its index. */
static int event(lp *p)
{
    int c = peek(p), q, k;
    char b[12];
    size_t at = p->pos;
    if (c == '<' || c == '\'' || c == '.' || type_of(c) >= 0 || scatter_of(c) >= 0) {
        if ((q = new_pat(p, at)) < 0) return -1;
        if (c == '<') return bracket(p, q) < 0 ? -1 : q;
        if (c == '\'') return label(p, q) < 0 ? -1 : q;
        p->pos++;
        if ((k = type_of(c)) >= 0) p->e->pats[q].types = 1u << k;
        if ((k = scatter_of(c)) >= 0) p->e->pats[q].scatters = 1u << k;
        return q;
    }
    if (c == 0) return fail(p, at, GG_ERROR_PARSE, "expected an event, got the end");
    if (c == '*' || c == '+' || c == '?' || c == '{')
        return fail(p, at, GG_ERROR_PARSE, "'%c' has nothing to repeat", c);
    if (c == '>') return fail(p, at, GG_ERROR_PARSE, "'>' without a matching '<'");
    if (c == ']') return fail(p, at, GG_ERROR_PARSE, "']' without a matching '['");
    if (c >= 'A' && c <= 'Z')
        return fail(p, at, GG_ERROR_PARSE,
                    "'%c' is not an event (C R T L O B A, D G S, ., 'label', <...>)", c);
    return fail(p, at, GG_ERROR_PARSE, "expected an event, got %s", what(p, at, b));
}

static int new_class(lp *p, size_t pos)
{
    ggPathExpr *e = p->e;
    if (e->ncls >= GG_PATH_MAX_EVENTS)
        return fail(p, pos, GG_ERROR_LIMIT, "more than %d events", GG_PATH_MAX_EVENTS);
    if (gg_mem_grow(e->alloc, (void **)&e->cls, &p->ccap, (size_t)e->ncls + 1, sizeof *e->cls))
        return nomem(p);
    memset(&e->cls[e->ncls], 0, sizeof *e->cls);
    e->cls[e->ncls].first = e->npats;
    return e->ncls++;
}

/* [e e ...] or [^e e ...] at p->pos. */
static int set(lp *p, int c)
{
    size_t open = p->pos;
    int ch;
    char b[12];
    p->pos++;
    if (peek(p) == '^') p->e->cls[c].neg = 1, p->pos++;
    while ((ch = peek(p)) != ']') {
        if (ch == 0)
            return fail(p, p->pos, GG_ERROR_PARSE,
                        "expected ']' to close the '[' of column %d, got %s", (int)open + 1,
                        what(p, p->pos, b));
        if (event(p) < 0) return -1;
        p->e->cls[c].count++;
    }
    if (p->e->cls[c].count == 0) return fail(p, open, GG_ERROR_PARSE, "empty set of events [ ]");
    p->pos++;
    return 0;
}

/* Whether the '[' at p->pos opens a predicate rather than a set. */
static int opens_predicate(lp *p)
{
    size_t save = p->pos;
    int c;
    p->pos++;
    c = peek(p);
    p->pos = save;
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '(' || c == '!';
}

/* An item and its predicate, as an event node. */
static int item(lp *p)
{
    size_t at = p->pos;
    int c = new_class(p, at), n;
    if (c < 0) return -1;
    if (peek(p) == '[' && !opens_predicate(p)) {
        if (set(p, c) < 0) return -1;
    } else {
        if (event(p) < 0) return -1;
        p->e->cls[c].count = 1;
    }
    if (peek(p) == '[' && opens_predicate(p)) {
        size_t end;
        int rc;
        p->e->cls[c].pred_at = place(p, p->pos);
        rc = gg_pred_parse_ray(p->s, p->len, p->pos + 1, p->e->alloc, &p->e->cls[c].pred,
                                   &end, p->err);
        if (rc != GG_OK) {
            p->status = rc;
            return -1;
        }
        p->e->needs |= p->e->cls[c].pred->needs;
        p->pos = end;
    }
    if ((n = node(p, AX_EV, -1, -1, at)) >= 0) p->t[n].cls = c;
    return n;
}

static int p_alt(lp *p);

static int atom(lp *p)
{
    size_t open = p->pos;
    int n;
    char b[12];
    if (peek(p) != '(') return item(p);
    if (++p->depth > GG_PATH_MAX_DEPTH)
        return fail(p, open, GG_ERROR_LIMIT, "nested deeper than %d", GG_PATH_MAX_DEPTH);
    p->pos++;
    if ((n = p_alt(p)) < 0) return -1;
    if (peek(p) != ')')
        return fail(p, p->pos, GG_ERROR_PARSE, "expected ')' to close the '(' of column %d, got %s",
                    (int)open + 1, what(p, p->pos, b));
    p->pos++;
    p->depth--;
    return n;
}

/* A count in { }: digits at p->pos, at most GG_PATH_MAX_STATES. */
static int count(lp *p, int *out)
{
    size_t at = p->pos;
    long v = 0;
    char b[12];
    peek(p);
    at = p->pos;
    if (p->pos >= p->len || p->s[p->pos] < '0' || p->s[p->pos] > '9')
        return fail(p, at, GG_ERROR_PARSE, "expected a count in { }, got %s", what(p, at, b));
    while (p->pos < p->len && p->s[p->pos] >= '0' && p->s[p->pos] <= '9') {
        v = 10 * v + (p->s[p->pos++] - '0');
        if (v > GG_PATH_MAX_STATES)
            return fail(p, at, GG_ERROR_LIMIT, "a count above %d", GG_PATH_MAX_STATES);
    }
    *out = (int)v;
    return 0;
}

/* {n}, {n,}, {n,m} after node a. */
static int braces(lp *p, int a)
{
    size_t open = p->pos;
    int n, m, r;
    char b[12];
    p->pos++;
    if (count(p, &n) < 0) return -1;
    m = n;
    if (peek(p) == ',') {
        p->pos++;
        if (peek(p) == '}')
            m = -1;
        else if (count(p, &m) < 0)
            return -1;
    }
    if (peek(p) != '}')
        return fail(p, p->pos, GG_ERROR_PARSE, "expected '}' to close the '{' of column %d, got %s",
                    (int)open + 1, what(p, p->pos, b));
    if (m >= 0 && m < n)
        return fail(p, open, GG_ERROR_PARSE, "{%d,%d}: the least is more than the most", n, m);
    p->pos++;
    if ((r = node(p, AX_REP, a, -1, open)) < 0) return -1;
    p->t[r].n = n, p->t[r].m = m;
    return r;
}

static int rep(lp *p)
{
    int a = atom(p), c;
    while (a >= 0 && ((c = peek(p)) == '*' || c == '+' || c == '?' || c == '{')) {
        if (c == '{') {
            a = braces(p, a);
        } else {
            a = node(p, c == '*' ? AX_STAR : c == '+' ? AX_PLUS : AX_OPT, a, -1, p->pos);
            p->pos++;
        }
    }
    return a;
}

static int p_cat(lp *p)
{
    int l = rep(p), c;
    while (l >= 0 && (c = peek(p)) != 0 && c != '|' && c != ')') {
        int r = rep(p);
        if (r < 0) return -1;
        l = node(p, AX_CAT, l, r, p->t[r].pos);
    }
    return l;
}

static int p_alt(lp *p)
{
    int l = p_cat(p);
    while (l >= 0 && peek(p) == '|') {
        size_t at = p->pos;
        int r;
        p->pos++;
        if ((r = p_cat(p)) < 0) return -1;
        l = node(p, AX_ALT, l, r, at);
    }
    return l;
}

/* ---- the automaton ---- */

static int state(lp *p, size_t pos)
{
    if (p->e->nstates >= GG_PATH_MAX_STATES)
        return fail(p, pos, GG_ERROR_LIMIT, "the expression needs more than %d states",
                    GG_PATH_MAX_STATES);
    return p->e->nstates++;
}

static int edge(lp *p, int from, int cls, int to, size_t pos)
{
    ggPathExpr *e = p->e;
    if (from < 0 || to < 0) return -1;
    if (e->nedges >= MAX_EDGES)
        return fail(p, pos, GG_ERROR_LIMIT, "the expression needs more than %d moves", MAX_EDGES);
    if (gg_mem_grow(e->alloc, (void **)&e->edges, &p->ecap, (size_t)e->nedges + 1,
                    sizeof *e->edges))
        return nomem(p);
    e->edges[e->nedges].from = from, e->edges[e->nedges].cls = cls, e->edges[e->nedges].to = to;
    e->nedges++;
    return 0;
}

static int compile(lp *p, int i, int s);

/* a* from s: a fresh state that loops through a. */
static int star(lp *p, int a, int s, size_t pos)
{
    int in = state(p, pos), end;
    if (in < 0 || edge(p, s, -1, in, pos) < 0) return -1;
    if ((end = compile(p, a, in)) < 0 || edge(p, end, -1, in, pos) < 0) return -1;
    return in;
}

/* a? from s. */
static int optional(lp *p, int a, int s, size_t pos)
{
    int in = state(p, pos), out, end;
    if (in < 0 || edge(p, s, -1, in, pos) < 0) return -1;
    if ((end = compile(p, a, in)) < 0 || (out = state(p, pos)) < 0) return -1;
    if (edge(p, end, -1, out, pos) < 0 || edge(p, s, -1, out, pos) < 0) return -1;
    return out;
}

/* Node i from state s; returns its end state, -1 on a limit. */
static int compile(lp *p, int i, int s)
{
    const ast *n = &p->t[i];
    int e, a, b, k;
    if (s < 0 || p->status != GG_OK) return -1;
    switch (n->op) {
    case AX_EV:
        e = state(p, n->pos);
        return edge(p, s, n->cls, e, n->pos) < 0 ? -1 : e;
    case AX_CAT:
        return compile(p, n->b, compile(p, n->a, s));
    case AX_ALT:
        a = state(p, n->pos), b = state(p, n->pos);
        if (a < 0 || b < 0 || edge(p, s, -1, a, n->pos) < 0 || edge(p, s, -1, b, n->pos) < 0)
            return -1;
        a = compile(p, n->a, a), b = compile(p, n->b, b);
        e = state(p, n->pos);
        return edge(p, a, -1, e, n->pos) < 0 || edge(p, b, -1, e, n->pos) < 0 ? -1 : e;
    case AX_STAR:
        return star(p, n->a, s, n->pos);
    case AX_PLUS:
        return star(p, n->a, compile(p, n->a, s), n->pos);
    case AX_OPT:
        return optional(p, n->a, s, n->pos);
    default: /* AX_REP */
        for (k = 0; k < n->n && s >= 0; k++) s = compile(p, n->a, s);
        if (n->m < 0) return star(p, n->a, s, n->pos);
        for (k = n->n; k < n->m && s >= 0; k++) s = optional(p, n->a, s, n->pos);
        return s;
    }
}

/* Each state's closure under empty moves (states reachable by them). */
static void close_states(ggPathExpr *e)
{
    int s, changed, k;
    memset(e->closure, 0, sizeof e->closure);
    for (s = 0; s < e->nstates; s++) e->closure[s][s / 64] |= (uint64_t)1 << (s % 64);
    do {
        changed = 0;
        for (k = 0; k < e->nedges; k++) {
            const gg_path_edge *ed = &e->edges[k];
            int w;
            if (ed->cls >= 0) continue;
            for (w = 0; w < GG_PATH_WORDS; w++) {
                uint64_t before = e->closure[ed->from][w];
                e->closure[ed->from][w] |= e->closure[ed->to][w];
                changed |= e->closure[ed->from][w] != before;
            }
        }
    } while (changed);
}

GG_API void ggPathFree(ggPathExpr *e)
{
    int i;
    if (!e) return;
    for (i = 0; i < e->ncls; i++) ggPredicateFree(e->cls[i].pred);
    gg_mem_free(e->alloc, e->pats);
    gg_mem_free(e->alloc, e->cls);
    gg_mem_free(e->alloc, e->edges);
    gg_mem_free(e->alloc, e);
}

/* Parse and compile into p->e; the status. */
static int build(lp *p)
{
    int root, start;
    char b[12];
    if (peek(p) == 0) return fail(p, 0, GG_ERROR_PARSE, "empty path expression"), p->status;
    if ((root = p_alt(p)) < 0) return p->status;
    if (peek(p) != 0) {
        int c = peek(p);
        if (c == ')') return fail(p, p->pos, GG_ERROR_PARSE, "')' without a matching '('"), p->status;
        return fail(p, p->pos, GG_ERROR_PARSE, "unexpected %s", what(p, p->pos, b)), p->status;
    }
    if ((start = state(p, 0)) < 0) return p->status;
    p->e->accept = compile(p, root, start);
    if (p->status == GG_OK) close_states(p->e);
    return p->status;
}

GG_API int ggPathParse(const char *text, const ggAllocator *alloc, ggPathExpr **out, ggError *err)
{
    lp *p;
    ggPathExpr *e;
    size_t n;
    int rc;
    if (!text || !out) return gg_error_set(err, GG_ERROR_INVALID, "ggPathParse: NULL argument");
    *out = NULL; /* after the NULL checks: base.h rule 1 */
    n = strlen(text);
    if (n > GG_PATH_MAX_TEXT)
        return gg_error_set(err, GG_ERROR_LIMIT, "1:%d: path expression longer than %d bytes",
                            GG_PATH_MAX_TEXT + 1, GG_PATH_MAX_TEXT);
    e = gg_mem_calloc(alloc, 1, sizeof *e);
    p = gg_mem_calloc(alloc, 1, sizeof *p);
    if (!e || !p) {
        gg_mem_free(alloc, e), gg_mem_free(alloc, p);
        return gg_error_set(err, GG_ERROR_NOMEM, "path expression: out of memory");
    }
    if (alloc) e->alloc_copy = *alloc, e->alloc = &e->alloc_copy;
    p->s = text, p->len = n, p->err = err, p->e = e, p->status = GG_OK;
    rc = build(p);
    gg_mem_free(alloc, p);
    if (rc != GG_OK) {
        ggPathFree(e);
        return rc;
    }
    *out = e;
    return GG_OK;
}
