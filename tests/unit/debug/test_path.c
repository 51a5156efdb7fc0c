/* SPDX-License-Identifier: MIT */
/*
** test_path.c -- light-path expressions (debug.h): every parser error
** class with its column and code; the matcher's semantics, operator by
** operator and event by event, on a hand-built tree whose paths and
** values are written out here; each path's own text (ggPathFormat) as an
** expression matches that path; on rendered scenes the path classes
** partition the ledger and ggFindPath agrees with ggPathMatch pixel by
** pixel; allocation failures give GG_ERROR_NOMEM and leak nothing.
*/
#include "testutil.h"

#include "scene.h"
#include "trace_int.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static ggPathExpr *parse(const char *text)
{
    ggPathExpr *p = NULL;
    ggError e;
    int rc = ggPathParse(text, NULL, &p, &e);
    if (rc != GG_OK) print_error("%s: %s\n", text, e.message);
    assert_int_equal(rc, GG_OK);
    return p;
}

static void expect_error(const char *text, int code, const char *prefix)
{
    ggPathExpr *p = (ggPathExpr *)1;
    ggError e;
    int rc = ggPathParse(text, NULL, &p, &e);
    if (rc != code || strncmp(e.message, prefix, strlen(prefix)) != 0)
        print_error("'%s': got %d '%s', want %d '%s...'\n", text, rc, rc ? e.message : "", code,
                    prefix);
    assert_int_equal(rc, code);
    assert_null(p);
    assert_memory_equal(e.message, prefix, strlen(prefix));
}

static void test_path_errors(void **state)
{
    char *big;
    int i;
    (void)state;
    expect_error("", GG_ERROR_PARSE, "1:1: empty path expression");
    expect_error("  ", GG_ERROR_PARSE, "1:1: empty path expression");
    expect_error("C<TS", GG_ERROR_PARSE, "1:5: expected '>' to close the '<' of column 2, got the end");
    expect_error("C<XS>", GG_ERROR_PARSE, "1:3: 'X' is not an event type (C R T L O B A or .)");
    expect_error("C<RX>", GG_ERROR_PARSE, "1:4: 'X' is not a scatter type (D G S or .)");
    expect_error("C<R S x>", GG_ERROR_PARSE, "1:7: expected '>' to close the '<' of column 2");
    expect_error("C(<TS>", GG_ERROR_PARSE, "1:7: expected ')' to close the '(' of column 2, got the end");
    expect_error("C<TS>)", GG_ERROR_PARSE, "1:6: ')' without a matching '('");
    expect_error("C()", GG_ERROR_PARSE, "1:3: expected an event, got ')'");
    expect_error("C[<TS>", GG_ERROR_PARSE, "1:7: expected ']' to close the '[' of column 2, got the end");
    expect_error("C[ ]", GG_ERROR_PARSE, "1:2: empty set of events [ ]");
    expect_error("C[^]", GG_ERROR_PARSE, "1:2: empty set of events [ ]");
    expect_error("*C", GG_ERROR_PARSE, "1:1: '*' has nothing to repeat");
    expect_error("C|+", GG_ERROR_PARSE, "1:3: '+' has nothing to repeat");
    expect_error("C(?)", GG_ERROR_PARSE, "1:3: '?' has nothing to repeat");
    expect_error("C|{2}", GG_ERROR_PARSE, "1:3: '{' has nothing to repeat");
    expect_error("C|", GG_ERROR_PARSE, "1:3: expected an event, got the end");
    expect_error("|C", GG_ERROR_PARSE, "1:1: expected an event, got '|'");
    expect_error("C>", GG_ERROR_PARSE, "1:2: '>' without a matching '<'");
    expect_error("C]", GG_ERROR_PARSE, "1:2: ']' without a matching '['");
    expect_error("CX", GG_ERROR_PARSE, "1:2: 'X' is not an event");
    expect_error("C #", GG_ERROR_PARSE, "1:3: expected an event, got '#'");
    expect_error("C\n  x", GG_ERROR_PARSE, "2:3: expected an event, got 'x'");
    expect_error("C'foo'", GG_ERROR_PARSE, "1:2: 'foo' is not a label");
    expect_error("C'm'", GG_ERROR_PARSE, "1:2: 'm' is not a label");
    expect_error("C''", GG_ERROR_PARSE, "1:2: '' is not a label");
    expect_error("C'01'", GG_ERROR_PARSE, "1:2: '01' is not a label");
    expect_error("C<RS'm007'>", GG_ERROR_PARSE, "1:5: 'm007' is not a label");
    expect_error("C<TS'tir", GG_ERROR_PARSE, "1:5: no closing quote for this label");
    expect_error("C<TS>{3,1}", GG_ERROR_PARSE, "1:6: {3,1}: the least is more than the most");
    expect_error("C<TS>{x}", GG_ERROR_PARSE, "1:7: expected a count in { }, got 'x'");
    expect_error("C<TS>{2", GG_ERROR_PARSE, "1:8: expected '}' to close the '{' of column 6, got the end");
    expect_error("C<TS>{2,x}", GG_ERROR_PARSE, "1:9: expected a count in { }, got 'x'");
    /* per-event predicates: the predicate language's errors, at the column of the whole text */
    expect_error("C<TS>[objct == 2]", GG_ERROR_PARSE,
                 "1:7: unknown field 'objct'; did you mean 'object'?");
    expect_error("C<TS>[object == 2", GG_ERROR_PARSE, "1:18: expected ']' to close the '[' of column 6, got the end");
    expect_error("C<TS>[object == ]", GG_ERROR_PARSE, "1:17: expected a field, a number or '(', got ']'");
    expect_error("C<TS>[kind == tri]", GG_ERROR_PARSE, "1:15: 'tri' is not a kind");
    expect_error("C<TS>[some(hit)]", GG_ERROR_PARSE, "1:7: some, all and count look at every ray already");
    /* limits */
    expect_error(".{257}", GG_ERROR_LIMIT, "1:3: a count above 256");
    expect_error(".{200}.{100}", GG_ERROR_LIMIT, "1:7: the expression needs more than 256 states");
    expect_error("(.{16}){16}", GG_ERROR_LIMIT, "1:");
    expect_error("C<R'1''2''3''4''5''6''7''8''9'>", GG_ERROR_LIMIT, "1:28: more than 8 labels on one event");
    big = malloc(GG_PATH_MAX_TEXT + 2);
    assert_non_null(big);
    for (i = 0; i < 70; i++) big[i] = '(';
    big[70] = 'C';
    for (i = 71; i < 141; i++) big[i] = ')';
    big[141] = '\0';
    expect_error(big, GG_ERROR_LIMIT, "1:65: nested deeper than 64");
    memset(big, '.', GG_PATH_MAX_TEXT + 1);
    big[GG_PATH_MAX_TEXT + 1] = '\0';
    expect_error(big, GG_ERROR_LIMIT, "1:4097: path expression longer than 4096 bytes");
    /* 300 events: more events than the limit, before any state is made */
    big[300] = '\0';
    expect_error(big, GG_ERROR_LIMIT, "1:257: more than 256 events");
    free(big);
    {
        ggPathExpr *p = (ggPathExpr *)1;
        assert_int_equal(ggPathParse(NULL, NULL, &p, NULL), GG_ERROR_INVALID);
        assert_int_equal(ggPathParse("C", NULL, NULL, NULL), GG_ERROR_INVALID);
    }
    ggPathFree(NULL);
}

/* ---- a hand-built tree ----

   0 eye      hits object 1 (material 1): ambient 0.1, light 0 diffuse 0.2
              and highlight 0.3, light 1 blocked (gives nothing)
   1 reflect  (factor 0.5) of 0, hits object 2 (material 2): emission 0.4
   2 refract  (factor 0.5) of 0, hits object 1 from inside: no terms,
              tir_margin -5
   3 tir      (factor 0.5) of 2, misses: background 0.6
   Paths and values (one tree, absorption 1):
     C<RD'1'>A 0.1   C<RD'1'><L.'0'> 0.2   C<RG'1'><L.'0'> 0.3
     C<RS'1'>O 0.5 * 0.4 = 0.2   C<TS'1'><RS'1''tir'>B 0.25 * 0.6 = 0.15
   the pixel 0.95. */

static ggColor grey(double v)
{
    ggColor c;
    c.r = c.g = c.b = v;
    return c;
}

static int add_node(ggTrace *t, int parent, int kind, int object)
{
    int k = gg_trace_add_node(t);
    ggTraceNode *n;
    assert_true(k >= 0);
    n = &t->nodes[k];
    n->parent = parent, n->kind = kind, n->channel = -1;
    n->depth = parent < 0 ? 1 : t->nodes[parent].depth + 1;
    n->hit = object >= 0, n->object = object, n->material = object;
    n->medium = -1, n->fresnel = -1, n->triangle = -1;
    n->perr = n->offset = n->tir_margin = n->edge = NAN;
    n->nodes = n->prims = -1;
    n->absorption = grey(1), n->weight = grey(parent < 0 ? 1 : 0.5);
    n->stop = object >= 0 ? GG_STOP_NONE : GG_STOP_MISS;
    return k;
}

static void add_light(ggTrace *t, int node, int light, int verdict, double diffuse, double phong)
{
    int k = gg_trace_add_light(t);
    ggTraceLight *L;
    assert_true(k >= 0);
    L = &t->lights[k];
    L->light = light, L->verdict = verdict, L->occluder = verdict == GG_SHADOW_BLOCKED ? 2 : -1;
    L->t_block = 1, L->transmittance = grey(verdict == GG_SHADOW_BLOCKED ? 0 : 1);
    L->diffuse = grey(diffuse), L->phong = grey(phong);
    if (t->nodes[node].nlights++ == 0) t->nodes[node].first_light = k;
}

static ggTrace *hand_tree(void)
{
    ggTrace *t = ggTraceCreate(NULL);
    assert_non_null(t);
    add_node(t, -1, GG_RAY_EYE, 1);
    t->nodes[0].ambient = grey(0.1);
    add_light(t, 0, 0, GG_SHADOW_VISIBLE, 0.2, 0.3);
    add_light(t, 0, 1, GG_SHADOW_BLOCKED, 0, 0);
    add_node(t, 0, GG_RAY_REFLECT, 2);
    t->nodes[1].emission = grey(0.4);
    add_node(t, 0, GG_RAY_REFRACT, 1);
    t->nodes[2].front = false, t->nodes[2].tir_margin = -5;
    add_node(t, 2, GG_RAY_TIR, -1);
    t->nodes[3].color = grey(0.6);
    return t;
}

typedef struct want {
    const char *expr;
    long matched;
    double value; /* per channel */
} want;

static void test_path_semantics(void **state)
{
    static const want w[] = {
        {"C.*", 5, 0.95},
        {"C<RD>A", 1, 0.1},
        {"C<RD>L", 1, 0.2},
        {"C<RG>L", 1, 0.3},
        {"C<RS>O", 1, 0.2},
        {"C<TS><RS'tir'>B", 1, 0.15},
        {"C<TS><RS>B", 1, 0.15},
        {"C<TS><TS>B", 0, 0},
        {"C<RD>.", 2, 0.3},
        {"C.*L", 2, 0.5},
        {".*B", 1, 0.15},
        {"CO", 0, 0},
        {"C", 0, 0},
        {"B", 0, 0},
        {"C<RS>.*", 1, 0.2},
        {".*'tir'.*", 1, 0.15},
        {"'tir'", 0, 0},
        {"C[^<TS>]*", 4, 0.8},
        {"C[^<TS><RS>]*", 3, 0.6},
        {"C<.S>+B", 1, 0.15},
        {"C<.S>*B", 1, 0.15},
        {"C<.S>{2}B", 1, 0.15},
        {"C<.S>{3}B", 0, 0},
        {"C<.S>{1,2}B", 1, 0.15},
        {"C<.S>{3,}B", 0, 0},
        {"C<.S>{0,}B", 1, 0.15},
        {"C<.S>{0,1}B", 0, 0},
        {"C(<RD>|<RG>)L", 2, 0.5},
        {"C<RD>L|C<RG>L|CO", 2, 0.5},
        {"C<R.'m1'>L", 2, 0.5},
        {"C<R.'m2'>L", 0, 0},
        {"C<RD'2'>L", 0, 0},
        {"C.<L.'0'>", 2, 0.5},
        {"C.<L'1'>", 0, 0},
        {"C.?.?B", 1, 0.15},
        {"C.B", 0, 0},
        {"C<RS>?O", 1, 0.2},
        {"(C)((<RS>))(O)", 1, 0.2},
        {".*'m2'.*", 1, 0.2},
        {"C<O'2'>", 0, 0},
        {"C<RS><O.'2'>", 1, 0.2},
        {"C[<RD><RG>]L", 2, 0.5},
        {"C[<RD><RG>][L A]", 3, 0.6},
        {"C D [L A]", 2, 0.3},
        {"C G L", 1, 0.3},
        {"C <R> ? S* .", 5, 0.95},
        {"C<>.", 4, 0.8},
        {"C T R B", 1, 0.15},
        /* the type left out: <S> is <.S> (refused until an audit) */
        {"C<S>O", 1, 0.2},
        {"C<D>A", 1, 0.1},
        {"C<G>L", 1, 0.3},
        {"C[<D><G>]L", 2, 0.5},
        {"C<TS><S'tir'>B", 1, 0.15},
        {"C<TS><S'tir'>O", 0, 0},
        /* predicates: on the ray arriving at the event (L: the shadow ray) */
        {"C<RS>[object == 1]O", 1, 0.2},
        {"C<RS>[object == 2]O", 0, 0},
        {"C<RS>[object == 1 && kind == eye]O", 1, 0.2},
        {"C<RD>L[light == 0]", 1, 0.2},
        {"C<RD>L[light == 1]", 0, 0},
        {"C<RG>L[verdict == visible]", 1, 0.3},
        {"C[kind == eye]<RD>A", 1, 0.1},
        {"C[kind == refract].*", 0, 0},
        {"C<TS><RS>[tir_margin < 0]B", 1, 0.15},
        {"C<TS><RS>[tir_margin > 0]B", 0, 0},
        {"C<TS><RS>[!(tir_margin > 0)]B", 1, 0.15},
        {"C<RS>[tir_margin < 0]O", 0, 0}, /* unknown (NaN) is not true */
        {"C<RS>[!(tir_margin < 0)]O", 0, 0},
        {"C.B[kind == tir && weight == 0.25]", 0, 0},
        {"C..B[kind == tir && weight == 0.25]", 1, 0.15},
        {"C<TS>[pixel > 0.9].*", 1, 0.15},
        {"[^<TS>][^B]+", 4, 0.8},
    };
    ggTrace *t = hand_tree();
    size_t i;
    (void)state;
    for (i = 0; i < sizeof w / sizeof w[0]; i++) {
        ggPathExpr *e = parse(w[i].expr);
        ggPathSummary s;
        assert_int_equal(ggPathMatch(e, t, 0, 0, grey(0.95), NULL, NULL, &s), GG_OK);
        if (s.matched != w[i].matched || fabs(s.value.g - w[i].value) > 1e-12)
            print_error("%s: matched %ld (want %ld), value %.17g (want %g)\n", w[i].expr,
                        s.matched, w[i].matched, s.value.g, w[i].value);
        assert_int_equal(s.paths, 5);
        assert_int_equal(s.matched, w[i].matched);
        assert_true(fabs(s.value.r - w[i].value) <= 1e-12);
        assert_true(fabs(s.share - w[i].value / 0.95) <= 1e-12);
        ggPathFree(e);
    }
    ggTraceFree(t);
}

/* Each term's own text, as an expression, matches that term and every
   term of the same text (a text without 'tir' matches a TIR event too,
   so others may match); the flags agree with the summary. */
static void check_formats(const ggTrace *t, ggColor px)
{
    ggLedger *l;
    size_t i, j;
    char text[600], other[600];
    unsigned char *m;
    assert_int_equal(ggLedgerCreate(t, px, NULL, &l, NULL), GG_OK);
    m = calloc(l->count + 1, 1);
    assert_non_null(m);
    for (i = 0; i < l->count; i++) {
        ggPathExpr *e;
        ggPathSummary s;
        long same = 0, k = 0;
        assert_true(ggPathFormat(t, &l->terms[i], text, sizeof text) < sizeof text);
        e = parse(text);
        assert_int_equal(ggPathMatch(e, t, 0, 0, px, l, m, &s), GG_OK);
        assert_int_equal(s.paths, (long)l->count);
        assert_int_equal(m[i], 1);
        for (j = 0; j < l->count; j++) {
            ggPathFormat(t, &l->terms[j], other, sizeof other);
            same += !strcmp(text, other);
            k += m[j];
            if (!strcmp(text, other)) assert_int_equal(m[j], 1);
        }
        assert_true(s.matched >= same);
        assert_int_equal(k, s.matched);
        ggPathFree(e);
    }
    free(m);
    ggLedgerFree(l);
}

static void test_path_format(void **state)
{
    ggTrace *t = hand_tree();
    ggLedger *l;
    char buf[200];
    size_t i;
    int seen = 0;
    (void)state;
    assert_int_equal(ggLedgerCreate(t, grey(0.95), NULL, &l, NULL), GG_OK);
    assert_int_equal(l->count, 5);
    for (i = 0; i < l->count; i++) {
        ggPathFormat(t, &l->terms[i], buf, sizeof buf);
        if (l->terms[i].kind == GG_TERM_BACKGROUND)
            assert_string_equal(buf, "C<TS'1'><RS'1''tir'>B"), seen |= 1;
        if (l->terms[i].kind == GG_TERM_EMISSION) assert_string_equal(buf, "C<RS'1'><O.'2'>"), seen |= 2;
        if (l->terms[i].kind == GG_TERM_PHONG) assert_string_equal(buf, "C<RG'1'><L.'0'>"), seen |= 4;
        if (l->terms[i].kind == GG_TERM_AMBIENT) assert_string_equal(buf, "C<RD'1'>A"), seen |= 8;
    }
    assert_int_equal(seen, 15);
    /* the length it needs, however small the buffer */
    assert_int_equal(ggPathFormat(t, &l->terms[0], buf, 3), ggPathFormat(t, &l->terms[0], NULL, 0));
    assert_true(strlen(buf) == 2);
    assert_int_equal(ggPathFormat(NULL, &l->terms[0], buf, sizeof buf), 0);
    check_formats(t, grey(0.95));
    ggLedgerFree(l);
    ggTraceFree(t);
}

/* On rendered pixels: the classes by last event partition the paths and
   the value; "C.*" carries the whole ledger; each term's text matches it. */
static void test_path_partition(void **state)
{
    static const char *const scenes[] = {"examples/scenes/glass.nff", "examples/scenes/prism.nff",
                                         "examples/scenes/gold.nff"};
    static const char *const parts[] = {"C.*B", "C.*O", "C.*<RD>A", "C.*<RD>L", "C.*<RG>L"};
    ggPathExpr *all = parse("C.*"), *pe[5];
    ggTrace *t = ggTraceCreate(NULL);
    ggRenderOptions o;
    size_t k, p;
    int x, y;
    (void)state;
    for (p = 0; p < 5; p++) pe[p] = parse(parts[p]);
    ggRenderOptionsDefault(&o);
    o.width = 16, o.height = 12;
    for (k = 0; k < 3; k++) {
        ggScene *s = tu_load(scenes[k]);
        for (y = 0; y < o.height; y++)
            for (x = 0; x < o.width; x++) {
                ggColor px;
                ggPathSummary sa, sp;
                ggLedger *l;
                long n = 0;
                double v = 0;
                assert_int_equal(ggTracePixel(s, &o, x, y, -1, t, &px, NULL, NULL), GG_OK);
                assert_int_equal(ggPathMatch(all, t, x, y, px, NULL, NULL, &sa), GG_OK);
                assert_int_equal(ggLedgerCreate(t, px, NULL, &l, NULL), GG_OK);
                assert_int_equal(sa.paths, (long)l->count);
                assert_int_equal(sa.matched, (long)l->count);
                assert_true(fabs(sa.value.g - l->sum.g) <= l->bound.g + 1e-15);
                for (p = 0; p < 5; p++) {
                    assert_int_equal(ggPathMatch(pe[p], t, x, y, px, NULL, NULL, &sp), GG_OK);
                    n += sp.matched, v += sp.value.g;
                }
                assert_int_equal(n, sa.matched);
                assert_true(fabs(v - sa.value.g) <= l->bound.g + 1e-15);
                if ((x + y) % 5 == 0) check_formats(t, px);
                ggLedgerFree(l);
            }
        ggSceneFree(s);
    }
    for (p = 0; p < 5; p++) ggPathFree(pe[p]);
    ggPathFree(all);
    ggTraceFree(t);
}

/* ggFindPath: the pixels where ggPathMatch finds a match, with its share. */
static void test_find_path(void **state)
{
    static const char *const exprs[] = {"C<TS>+B", "C<TS>.*<RS'tir'>.*", "C<RD>L", "C.*[^B]",
                                        "C<TS>[tir_margin < 1e18]<TS>.*", "C.*<RS>[tir_margin < 1e6].*"};
    ggScene *s = tu_load("examples/scenes/glass.nff");
    ggTrace *t = ggTraceCreate(NULL);
    ggRenderOptions o;
    size_t k;
    (void)state;
    ggRenderOptionsDefault(&o);
    o.width = 24, o.height = 18, o.threads = 2;
    for (k = 0; k < sizeof exprs / sizeof exprs[0]; k++) {
        ggPathExpr *e = parse(exprs[k]);
        ggFindResult *r;
        long count = 0;
        int x, y, m = 0;
        assert_int_equal(ggFindPath(s, &o, e, 1000, &r, NULL), GG_OK);
        /* without predicates the layer copy answers (no trees recorded) */
        assert_int_equal(r->traced, k >= 4);
        for (y = 0; y < o.height; y++)
            for (x = 0; x < o.width; x++) {
                ggColor px;
                ggPathSummary sum;
                assert_int_equal(ggTracePixel(s, &o, x, y, -1, t, &px, NULL, NULL), GG_OK);
                assert_int_equal(ggPathMatch(e, t, x, y, px, NULL, NULL, &sum), GG_OK);
                assert_int_equal(r->mask[y * o.width + x], sum.matched > 0);
                if (sum.matched == 0) continue;
                count++;
                assert_true(m < r->nmatches);
                assert_int_equal(r->matches[m].x, x);
                assert_int_equal(r->matches[m].y, y);
                assert_true(r->matches[m].share == sum.share);
                m++;
            }
        assert_int_equal(r->matched, count);
        assert_true(count > 0);
        ggFindResultFree(r);
        ggPathFree(e);
    }
    assert_int_equal(ggFindPath(s, &o, NULL, 0, NULL, NULL), GG_ERROR_INVALID);
    ggTraceFree(t);
    ggSceneFree(s);
}

/* The matching paths' texts of one pixel, sorted (a class as a multiset). */
static size_t classes(const ggPathExpr *e, const ggTrace *t, int x, int y, ggColor px,
                      char (*out)[256], size_t max)
{
    ggLedger *l;
    unsigned char m[4096];
    ggPathSummary sum;
    size_t i, n = 0;
    if (ggLedgerCreate(t, px, NULL, &l, NULL) != GG_OK) return 0;
    assert_true(l->count <= sizeof m);
    assert_int_equal(ggPathMatch(e, t, x, y, px, l, m, &sum), GG_OK);
    for (i = 0; i < l->count; i++)
        if (m[i]) {
            assert_true(n < max);
            ggPathFormat(t, &l->terms[i], out[n++], 256);
        }
    qsort(out, n, sizeof *out, (int (*)(const void *, const void *))strcmp);
    ggLedgerFree(l);
    return n;
}

static int same_classes(char (*a)[256], char (*b)[256], size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        if (strcmp(a[i], b[i]) != 0) return 0;
    return 1;
}

/* ggDiffPath: the moved pixels are those whose matching paths' texts
   differ between the sides, in row order, with ggTraceCompare's first
   divergence; a diff of a render with itself moves nothing. */
static void test_diff_path(void **state)
{
    static const char *const exprs[] = {"C<RS>+.*", "C<RD>L", "C.*B"};
    static char ca[64][256], cb[64][256];
    ggScene *s = tu_load("examples/scenes/acc-distant.nff");
    ggTrace *ta = ggTraceCreate(NULL), *tb = ggTraceCreate(NULL);
    ggRenderOptions oa, ob;
    size_t k;
    (void)state;
    ggRenderOptionsDefault(&oa);
    oa.width = 32, oa.height = 24, oa.threads = 2;
    ob = oa;
    assert_int_equal(ggRenderOptionsParse(&ob, "sphere=textbook", NULL), GG_OK);
    for (k = 0; k < sizeof exprs / sizeof exprs[0]; k++) {
        ggPathExpr *e = parse(exprs[k]);
        ggDiffResult *r, *same;
        long count = 0;
        int x, y, m = 0;
        assert_int_equal(ggDiffPath(s, &oa, s, &ob, e, 0, 1000, &r, NULL), GG_OK);
        for (y = 0; y < oa.height; y++)
            for (x = 0; x < oa.width; x++) {
                ggColor pa, pb;
                ggDivergence d;
                size_t na, nb;
                assert_int_equal(ggTracePixel(s, &oa, x, y, -1, ta, &pa, NULL, NULL), GG_OK);
                assert_int_equal(ggTracePixel(s, &ob, x, y, -1, tb, &pb, NULL, NULL), GG_OK);
                na = classes(e, ta, x, y, pa, ca, 64), nb = classes(e, tb, x, y, pb, cb, 64);
                if (na == nb && same_classes(ca, cb, na)) continue;
                count++;
                assert_true(m < r->nmoves);
                assert_int_equal(r->moves[m].x, x);
                assert_int_equal(r->moves[m].y, y);
                ggTraceCompare(ta, tb, &d);
                assert_int_equal(r->moves[m].first.what, d.what);
                assert_int_equal(r->moves[m].first.node_a, d.node_a);
                m++;
            }
        assert_int_equal(r->moved, count);
        assert_int_equal(r->nmoves, m);
        assert_true(count > 0);
        ggDiffResultFree(r);
        assert_int_equal(ggDiffPath(s, &oa, s, &oa, e, 0, 10, &same, NULL), GG_OK);
        assert_int_equal(same->by_path, 1);
        assert_int_equal(same->moved, 0);
        assert_int_equal(same->nmoves, 0);
        ggDiffResultFree(same);
        ggPathFree(e);
    }
    assert_int_equal(ggDiffPath(s, &oa, s, &ob, NULL, 0, 0, NULL, NULL), GG_ERROR_INVALID);
    ggTraceFree(ta), ggTraceFree(tb);
    ggSceneFree(s);
}

/* ggCheck with a path: only the pixels find --path finds are checked. */
static void test_check_path(void **state)
{
    ggScene *s = tu_load("examples/scenes/glass.nff");
    ggRenderOptions o;
    ggCheckOptions co;
    ggCheckResult *r;
    ggFindResult *f;
    ggPathExpr *tir = parse("C.*<RS'tir'>.*"), *all = parse("C.*"), *none = parse("C<TS>{9}.*");
    (void)state;
    ggRenderOptionsDefault(&o);
    o.width = 24, o.height = 18, o.threads = 2;
    ggCheckOptionsDefault(&co);
    assert_null(co.path);
    co.path = tir;
    assert_int_equal(ggCheck(s, &o, &co, &r, NULL), GG_OK);
    assert_int_equal(ggFindPath(s, &o, tir, 0, &f, NULL), GG_OK);
    assert_int_equal(r->scanned, 432);
    assert_int_equal(r->checked, f->matched);
    assert_true(r->checked > 0 && r->share > 0 && r->share < 1);
    ggFindResultFree(f);
    ggCheckResultFree(r);
    co.path = all;
    assert_int_equal(ggCheck(s, &o, &co, &r, NULL), GG_OK);
    assert_int_equal(r->checked, 432);
    assert_true(fabs(r->share - 1) < 1e-6);
    ggCheckResultFree(r);
    co.path = none;
    assert_int_equal(ggCheck(s, &o, &co, &r, NULL), GG_OK);
    assert_int_equal(r->checked, 0);
    assert_int_equal(r->failed, 0);
    ggCheckResultFree(r);
    /* The share is the same number, to the bit, for any thread count
       (the pixels' shares are summed per row, the rows in order: summed
       per thread, 1 and 3 threads differed in the last digits here). */
    {
        ggPathExpr *glass = parse("C.*<TS>.*");
        double share[3];
        int k;
        co.path = glass;
        o.width = 64, o.height = 48;
        for (k = 0; k < 3; k++) {
            o.threads = k + 1;
            assert_int_equal(ggCheck(s, &o, &co, &r, NULL), GG_OK);
            share[k] = r->share;
            ggCheckResultFree(r);
        }
        assert_true(share[0] > 0 && share[0] < 1);
        assert_memory_equal(&share[0], &share[1], sizeof share[0]);
        assert_memory_equal(&share[0], &share[2], sizeof share[0]);
        ggPathFree(glass);
    }
    ggPathFree(tir), ggPathFree(all), ggPathFree(none);
    ggSceneFree(s);
}

/* ggPathPoints: the eye, every hit of the chain, then the light or a
   point on the leaving ray; weights start at 1 / samples. */
static void test_path_points(void **state)
{
    ggScene *s = tu_load("examples/scenes/glass.nff");
    ggTrace *t = ggTraceCreate(NULL);
    ggRenderOptions o;
    int x, y, seen_l = 0, seen_b = 0;
    (void)state;
    ggRenderOptionsDefault(&o);
    o.width = 12, o.height = 9;
    for (y = 0; y < o.height; y++)
        for (x = 0; x < o.width; x++) {
            ggColor px;
            ggLedger *l;
            size_t i;
            assert_int_equal(ggTracePixel(s, &o, x, y, -1, t, &px, NULL, NULL), GG_OK);
            assert_int_equal(ggLedgerCreate(t, px, NULL, &l, NULL), GG_OK);
            for (i = 0; i < l->count; i++) {
                const ggLedgerTerm *term = &l->terms[i];
                ggPathPoint pts[80];
                size_t n = ggPathPoints(t, term, pts, 80), hits = 0, k = 0;
                int j = term->node, chain[80], depth = 0;
                assert_true(n >= 2 && n <= 80);
                assert_int_equal(ggPathPoints(t, term, NULL, 0), n);
                while (j >= 0) chain[depth++] = j, j = ggTraceGetNode(t, (size_t)j)->parent;
                assert_true(pts[0].p.x == ggTraceGetNode(t, (size_t)chain[depth - 1])->o.x);
                assert_true(pts[0].weight.g == 1);
                for (j = depth - 1; j >= 0; j--) {
                    const ggTraceNode *nd = ggTraceGetNode(t, (size_t)chain[j]);
                    if (!nd->hit) continue;
                    hits++, k++;
                    assert_true(pts[k].p.x == nd->p.x && pts[k].p.z == nd->p.z);
                }
                if (term->kind == GG_TERM_DIFFUSE || term->kind == GG_TERM_PHONG)
                    seen_l++, assert_int_equal(n, hits + 2);
                else if (term->kind == GG_TERM_BACKGROUND)
                    seen_b++, assert_int_equal(n, hits + 2);
                else
                    assert_int_equal(n, hits + 1);
            }
            ggLedgerFree(l);
        }
    assert_true(seen_l > 0 && seen_b > 0);
    assert_int_equal(ggPathPoints(NULL, NULL, NULL, 0), 0);
    ggTraceFree(t);
    ggSceneFree(s);
}

/* ---- allocation failures ---- */

/* Each allocation of the parse failing in turn, then the match's own. */
static void test_path_nomem(void **state)
{
    const char *text = "C(<TS>[object == 1]|[^<RS'tir'> B])*<RD>L{1,3}";
    ggTrace *t = hand_tree();
    tu_failer f;
    long k, points = 0;
    ggPathExpr *e;
    ggPathSummary s;
    (void)state;
    tu_failer_init(&f);
    for (k = 1;; k++) {
        int rc;
        e = (ggPathExpr *)1;
        tu_failer_arm(&f, k);
        rc = ggPathParse(text, &f.alloc, &e, NULL);
        if (!f.failed) { /* k is past the parse's allocations */
            assert_int_equal(rc, GG_OK);
            break;
        }
        points++;
        assert_int_equal(rc, GG_ERROR_NOMEM);
        assert_null(e);
        assert_int_equal(f.live, 0);
    }
    assert_true(points > 3);
    tu_failer_arm(&f, 1); /* the match's own memory fails */
    assert_int_equal(ggPathMatch(e, t, 0, 0, grey(0.95), NULL, NULL, &s), GG_ERROR_NOMEM);
    assert_true(f.failed);
    assert_int_equal(s.matched, 0);
    tu_failer_arm(&f, 0);
    assert_int_equal(ggPathMatch(e, t, 0, 0, grey(0.95), NULL, NULL, &s), GG_OK);
    ggPathFree(e);
    assert_int_equal(f.live, 0);
    tu_failer_done(&f);
    ggTraceFree(t);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_path_errors),    cmocka_unit_test(test_path_semantics),
        cmocka_unit_test(test_path_format),    cmocka_unit_test(test_path_partition),
        cmocka_unit_test(test_find_path),      cmocka_unit_test(test_path_nomem),
        cmocka_unit_test(test_diff_path),      cmocka_unit_test(test_check_path),
        cmocka_unit_test(test_path_points),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
