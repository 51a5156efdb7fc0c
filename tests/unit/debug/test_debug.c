/* SPDX-License-Identifier: MIT */
/*
** test_debug.c -- the image-level debugger (debug.h): predicate errors
** name their column; ggFind returns exactly the pixels whose full traces
** satisfy the predicate (checked by hand-written tests of the recorded
** trees, not by the predicate evaluator); the ledger adds up to the pixel
** on every example scene; ggCheck finds planted defects and passes clean
** scenes; ggDiff reports nothing for identical options and the textbook
** sphere's divergences on acc-distant.nff; render options as text.
*/
#include "testutil.h"

#include "scene.h"
#include "trace_int.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static ggPredicate *parse(const char *text)
{
    ggPredicate *p = NULL;
    ggError e;
    int rc = ggPredicateParse(text, NULL, &p, &e);
    if (rc != GG_OK) print_error("%s: %s\n", text, e.message);
    assert_int_equal(rc, GG_OK);
    return p;
}

static void small(ggRenderOptions *o, int w, int h, int threads)
{
    ggRenderOptionsDefault(o);
    o->width = w, o->height = h, o->threads = threads;
}

/* ---- predicate errors ---- */

static void expect_error(const char *text, int code, const char *prefix)
{
    ggPredicate *p = (ggPredicate *)1;
    ggError e;
    int rc = ggPredicateParse(text, NULL, &p, &e);
    if (rc != code || strncmp(e.message, prefix, strlen(prefix)) != 0)
        print_error("'%s': got %d '%s', want %d '%s...'\n", text, rc, rc ? e.message : "", code,
                    prefix);
    assert_int_equal(rc, code);
    assert_null(p);
    assert_memory_equal(e.message, prefix, strlen(prefix));
}

static void test_predicate_errors(void **state)
{
    char deep[400];
    int i;
    (void)state;
    expect_error("some(kind == tri)", GG_ERROR_PARSE,
                 "1:14: 'tri' is not a kind (eye, reflect, refract, tir, shadow)");
    expect_error("some(knd == tir)", GG_ERROR_PARSE,
                 "1:6: unknown field 'knd'; did you mean 'kind'?");
    expect_error("kind == tir", GG_ERROR_PARSE, "1:1: 'kind' is a field of a ray");
    expect_error("some(kind == tir", GG_ERROR_PARSE, "1:17: expected ')'");
    expect_error("some(depth = 3)", GG_ERROR_PARSE, "1:12: '=' is not an operator: write ==");
    expect_error("some(depth > 3) junk", GG_ERROR_PARSE, "1:17: unexpected 'junk'");
    expect_error("some(depth > 3) & x > 1", GG_ERROR_PARSE, "1:17: '&' is not an operator");
    expect_error("", GG_ERROR_PARSE, "1:1: empty predicate");
    expect_error("some(front == 1)", GG_ERROR_PARSE, "1:6: 'front' is true or false");
    expect_error("some(kind < tir)", GG_ERROR_PARSE, "1:13: kind values have no order");
    expect_error("some(stop == 3)", GG_ERROR_PARSE, "1:14: stop is compared with a name");
    expect_error("some(some(hit))", GG_ERROR_PARSE, "1:6: some, all and count");
    expect_error("some(depth >)", GG_ERROR_PARSE, "1:13: expected a field, a number or '('");
    expect_error("some(tir)", GG_ERROR_PARSE, "1:6: 'tir' is a value of kind: write kind == tir");
    expect_error("some(color.q > 1)", GG_ERROR_PARSE, "1:12: a colour's component is r, g, b");
    expect_error("some(depth > 2)\n  && some(kind == tri)", GG_ERROR_PARSE,
                 "2:19: 'tri' is not a kind");
    expect_error("x > 1 @", GG_ERROR_PARSE, "1:7: unexpected character '@'");
    /* the limits */
    for (i = 0; i < 70; i++) deep[i] = '(';
    strcpy(deep + 70, "x > 1");
    for (i = 0; i < 70; i++) strcat(deep, ")");
    expect_error(deep, GG_ERROR_LIMIT, "1:");
    {
        char *big = malloc(GG_PREDICATE_MAX_TEXT + 2);
        memset(big, ' ', GG_PREDICATE_MAX_TEXT + 1);
        big[GG_PREDICATE_MAX_TEXT + 1] = '\0';
        expect_error(big, GG_ERROR_LIMIT, "1:4097: predicate longer than");
        free(big);
    }
    {
        ggPredicate *p = NULL;
        assert_int_equal(ggPredicateParse(NULL, NULL, &p, NULL), GG_ERROR_INVALID);
        assert_int_equal(ggPredicateParse("x > 1", NULL, NULL, NULL), GG_ERROR_INVALID);
        ggPredicateFree(NULL);
    }
}

/* ---- find against hand-written tests of the full traces ---- */

/* Each predicate with a direct test of what it says over a recorded
   pixel, written against trace.h alone. */
typedef int (*direct_fn)(const ggTrace *t, ggColor px, int x, int y);

static int d_tir(const ggTrace *t, ggColor px, int x, int y)
{
    size_t i;
    (void)px, (void)x, (void)y;
    for (i = 0; i < ggTraceNodeCount(t); i++)
        if (ggTraceGetNode(t, i)->kind == GG_RAY_TIR) return 1;
    return 0;
}

static int d_blocked_by_2(const ggTrace *t, ggColor px, int x, int y)
{
    size_t i;
    (void)px, (void)x, (void)y;
    for (i = 0; i < ggTraceLightCount(t); i++) {
        const ggTraceLight *L = ggTraceGetLight(t, i);
        if (L->verdict == GG_SHADOW_BLOCKED && L->occluder == 2) return 1;
    }
    return 0;
}

/* some(stop == depth && weight > 0.01): the weight by multiplying down. */
static int d_cut_heavy(const ggTrace *t, ggColor px, int x, int y)
{
    size_t i, n = ggTraceNodeCount(t), roots = 0;
    (void)px, (void)x, (void)y;
    for (i = 0; i < n; i++) roots += ggTraceGetNode(t, i)->parent < 0;
    for (i = 0; i < n; i++) {
        const ggTraceNode *nd = ggTraceGetNode(t, i);
        double w[3];
        int k;
        if (nd->stop != GG_STOP_DEPTH) continue;
        w[0] = w[1] = w[2] = 1.0 / (double)roots;
        for (; nd->parent >= 0; nd = ggTraceGetNode(t, (size_t)nd->parent)) {
            const ggTraceNode *up = ggTraceGetNode(t, (size_t)nd->parent);
            w[0] *= nd->weight.r * up->absorption.r, w[1] *= nd->weight.g * up->absorption.g;
            w[2] *= nd->weight.b * up->absorption.b;
        }
        for (k = 0; k < 3; k++)
            if (w[k] > 0.01 * (1 + 1e-9)) return 1;
    }
    return 0;
}

static int d_refract_to_2_few_tir(const ggTrace *t, ggColor px, int x, int y)
{
    size_t i;
    int found = 0, tir = 0;
    (void)px, (void)x, (void)y;
    for (i = 0; i < ggTraceNodeCount(t); i++) {
        const ggTraceNode *n = ggTraceGetNode(t, i);
        if (n->kind == GG_RAY_REFRACT && n->hit && n->object == 2 && n->front) found = 1;
        tir += n->kind == GG_RAY_TIR;
    }
    return found && tir < 2;
}

static int d_bright_right(const ggTrace *t, ggColor px, int x, int y)
{
    (void)t;
    return (px.r > 0.5 || px.b < 0.2) && x >= 30 && !(y < 10);
}

static int d_many_shadows(const ggTrace *t, ggColor px, int x, int y)
{
    size_t i;
    int k = 0;
    (void)px, (void)x, (void)y;
    for (i = 0; i < ggTraceLightCount(t); i++)
        k += ggTraceGetLight(t, i)->verdict != GG_SHADOW_FACING_AWAY;
    return k >= 3;
}

static int d_all_front_hits(const ggTrace *t, ggColor px, int x, int y)
{
    size_t i;
    (void)px, (void)x, (void)y;
    for (i = 0; i < ggTraceNodeCount(t); i++) {
        const ggTraceNode *n = ggTraceGetNode(t, i);
        if (n->hit && !n->front) return 0;
    }
    return 1;
}

static int d_close_tir_or_edge(const ggTrace *t, ggColor px, int x, int y)
{
    size_t i;
    (void)px, (void)x, (void)y;
    for (i = 0; i < ggTraceNodeCount(t); i++) {
        const ggTraceNode *n = ggTraceGetNode(t, i);
        if (n->hit && n->tir_margin < 0 && n->tir_margin > -3e13) return 1;
        if (n->hit && n->edge < 0.02) return 1;
    }
    return 0;
}

static int d_eye_no_prims(const ggTrace *t, ggColor px, int x, int y)
{
    size_t i;
    (void)px, (void)x, (void)y;
    for (i = 0; i < ggTraceNodeCount(t); i++) {
        const ggTraceNode *n = ggTraceGetNode(t, i);
        if (n->kind == GG_RAY_EYE && n->prims == 0) return 1;
    }
    return 0;
}

static const struct {
    const char *scene, *where;
    direct_fn direct;
} finds[] = {
    {"examples/scenes/glass.nff", "some(kind == tir)", d_tir},
    {"examples/scenes/default.nff", "some(verdict == blocked && occluder == 2)", d_blocked_by_2},
    {"examples/scenes/glass.nff", "some(stop == depth && weight > 0.01)", d_cut_heavy},
    {"examples/scenes/glass.nff",
     "some(kind == refract && object == 2 && front) && count(kind == tir) < 2",
     d_refract_to_2_few_tir},
    {"examples/scenes/default.nff", "(pixel.r > 0.5 || pixel.b < 0.2) && x >= 30 && !(y < 10)",
     d_bright_right},
    {"examples/scenes/default.nff", "count(kind == shadow && verdict != facing_away) >= 3",
     d_many_shadows},
    {"examples/scenes/glass.nff", "all(!hit || front)", d_all_front_hits},
    {"examples/scenes/glass.nff", "some(tir_margin < 0 && tir_margin > -3e13) || some(edge < 0.02)",
     d_close_tir_or_edge},
    /* the sky: eye rays that miss every box, beside ones that enter the
       floor's (each pixel's own ray, no neighbour's tree) */
    {"examples/scenes/glass.nff", "some(kind == eye && prims == 0)", d_eye_no_prims},
};

static void test_find_matches_full_traces(void **state)
{
    size_t f;
    (void)state;
    for (f = 0; f < sizeof finds / sizeof finds[0]; f++) {
        ggScene *s = tu_load(finds[f].scene);
        ggPredicate *p = parse(finds[f].where);
        ggTrace *t = ggTraceCreate(NULL);
        ggRenderOptions o;
        ggFindResult *r = NULL;
        ggError e;
        long expected = 0;
        int x, y, listed = 0, threads;
        for (threads = 1; threads <= 3; threads += 2) {
            small(&o, 64, 48, threads);
            assert_int_equal(ggFind(s, &o, p, 1000000, &r, &e), GG_OK);
            expected = 0, listed = 0;
            for (y = 0; y < 48; y++)
                for (x = 0; x < 64; x++) {
                    ggColor px;
                    int want, got = r->mask[y * 64 + x];
                    assert_int_equal(ggTracePixel(s, &o, x, y, -1, t, &px, NULL, &e), GG_OK);
                    want = finds[f].direct(t, px, x, y);
                    if (want != got)
                        print_error("%s '%s' %d,%d: find says %d, the trace %d\n", finds[f].scene,
                                    finds[f].where, x, y, got, want);
                    assert_int_equal(want, got);
                    assert_int_equal(ggPredicateMatch(p, t, x, y, px), want);
                    if (want) {
                        /* listed in row order, with the traced value */
                        assert_true(listed < r->nmatches);
                        assert_int_equal(r->matches[listed].x, x);
                        assert_int_equal(r->matches[listed].y, y);
                        assert_true(r->matches[listed].pixel.r == px.r);
                        listed++;
                        expected++;
                    }
                    {
                        ggColor img = ggImageGet(r->image, x, y);
                        assert_true(img.r == px.r && img.g == px.g && img.b == px.b);
                    }
                }
            assert_int_equal(r->matched, expected);
            assert_int_equal(r->nmatches, listed);
            assert_int_equal(r->scanned, 64 * 48);
            ggFindResultFree(r);
        }
        /* Nothing vacuous: each predicate matches somewhere and not everywhere. */
        if (!(expected > 0 && expected < 64 * 48))
            print_error("'%s': %ld\n", finds[f].where, expected);
        assert_true(expected > 0 && expected < 64 * 48);
        ggTraceFree(t);
        ggPredicateFree(p);
        ggSceneFree(s);
    }
}

/* A limit keeps the first matches in row order; a crop window scans only it. */
static void test_find_limit_and_crop(void **state)
{
    ggScene *s = tu_load("examples/scenes/glass.nff");
    ggPredicate *p = parse("some(kind == tir)");
    ggRenderOptions o;
    ggFindResult *all = NULL, *few = NULL, *crop = NULL;
    int i, x, y;
    (void)state;
    small(&o, 80, 60, 2);
    assert_int_equal(ggFind(s, &o, p, 100000, &all, NULL), GG_OK);
    assert_int_equal(ggFind(s, &o, p, 5, &few, NULL), GG_OK);
    assert_int_equal(few->matched, all->matched);
    assert_int_equal(few->nmatches, 5);
    for (i = 0; i < 5; i++)
        assert_memory_equal(&few->matches[i], &all->matches[i], sizeof *few->matches);
    /* a negative limit fails with *out NULL (debug.h: NULL on failure) */
    crop = (ggFindResult *)&crop;
    assert_int_equal(ggFind(s, &o, p, -5, &crop, NULL), GG_ERROR_INVALID);
    assert_null(crop);
    o.crop_x0 = 20, o.crop_y0 = 10, o.crop_x1 = 50, o.crop_y1 = 40;
    assert_int_equal(ggFind(s, &o, p, 0, &crop, NULL), GG_OK);
    assert_int_equal(crop->scanned, 30 * 30);
    assert_int_equal(crop->nmatches, 0);
    for (y = 0; y < 60; y++)
        for (x = 0; x < 80; x++) {
            int in = x >= 20 && x < 50 && y >= 10 && y < 40;
            assert_int_equal(crop->mask[y * 80 + x], in ? all->mask[y * 80 + x] : 0);
        }
    ggFindResultFree(all), ggFindResultFree(few), ggFindResultFree(crop);
    ggFindResultFree(NULL);
    ggPredicateFree(p);
    ggSceneFree(s);
}

/* ---- the ledger ---- */

static const char *const example_scenes[] = {
    "examples/scenes/default.nff",     "examples/scenes/glass.nff",
    "examples/scenes/water.nff",       "examples/scenes/gold.nff",
    "examples/scenes/prism.nff",       "examples/scenes/torus.nff",
    "examples/scenes/texture.nff",     "examples/scenes/acc-corridor.nff",
    "examples/scenes/acc-distant.nff", "examples/scenes/acc-far.nff",
    "examples/scenes/acc-grazing.nff", "examples/scenes/acc-texture.nff",
    "examples/scenes/acc-thin.nff",    "tests/data/debug/absorb.nff",
};

/* Every pixel of every example scene and of a ball of absorbing glass
   (and four samples, and the SPD's corner rule): the terms add up to the
   traced pixel within the bound. */
static void test_ledger_sums_to_pixel(void **state)
{
    size_t k;
    int mode;
    (void)state;
    for (k = 0; k < sizeof example_scenes / sizeof example_scenes[0]; k++)
        for (mode = 0; mode < 3; mode++) {
            ggScene *s = tu_load(example_scenes[k]);
            ggTrace *t = ggTraceCreate(NULL);
            ggRenderOptions o;
            int x, y, w = mode ? 24 : 48, h = mode ? 18 : 36;
            small(&o, w, h, 1);
            if (mode == 1) o.samples = 4;
            if (mode == 2) o.pixel_corners = o.spd_rules = true;
            for (y = 0; y < h; y++)
                for (x = 0; x < w; x++) {
                    ggColor px;
                    ggLedger *l = NULL;
                    double share = 0, prev = INFINITY;
                    size_t i;
                    assert_int_equal(ggTracePixel(s, &o, x, y, -1, t, &px, NULL, NULL), GG_OK);
                    assert_int_equal(ggLedgerCreate(t, px, NULL, &l, NULL), GG_OK);
                    if (!l->holds || !(fabs(l->sum.r - px.r) <= l->bound.r &&
                                       fabs(l->sum.g - px.g) <= l->bound.g &&
                                       fabs(l->sum.b - px.b) <= l->bound.b))
                        print_error("%s mode %d %d,%d: sum %.9g %.9g %.9g, pixel %.9g %.9g %.9g\n",
                                    example_scenes[k], mode, x, y, l->sum.r, l->sum.g, l->sum.b,
                                    px.r, px.g, px.b);
                    assert_true(l->holds);
                    assert_true(fabs(l->sum.g - px.g) <= l->bound.g);
                    /* The bound is a rounding bound: tiny next to the pixel. */
                    assert_true(l->bound.r <= 1e-6 * (1 + fabs(px.r) * 10));
                    for (i = 0; i < l->count; i++) {
                        assert_true(l->terms[i].share <= prev);
                        prev = l->terms[i].share;
                        share += l->terms[i].share;
                    }
                    if (px.r + px.g + px.b > 0) assert_true(fabs(share - 1) < 1e-6);
                    ggLedgerFree(l);
                }
            ggTraceFree(t);
            ggSceneFree(s);
        }
}

/* The ledger of glass.nff's pixel 110,100: the background through the
   glass, refracted in, reflected totally and refracted out. */
static void test_ledger_glass_pixel(void **state)
{
    ggScene *s = tu_load("examples/scenes/glass.nff");
    ggTrace *t = ggTraceCreate(NULL);
    ggLedger *l = NULL;
    ggColor px;
    const ggLedgerTerm *first;
    (void)state;
    assert_int_equal(ggTracePixel(s, NULL, 110, 100, -1, t, &px, NULL, NULL), GG_OK);
    assert_int_equal(ggLedgerCreate(t, px, NULL, &l, NULL), GG_OK);
    assert_true(l->count >= 2);
    first = &l->terms[0];
    assert_int_equal(first->kind, GG_TERM_BACKGROUND);
    assert_true(first->share > 0.5);
    assert_int_equal(ggTraceGetNode(t, (size_t)first->node)->kind, GG_RAY_REFRACT);
    assert_int_equal(
        ggTraceGetNode(t, (size_t)ggTraceGetNode(t, (size_t)first->node)->parent)->kind,
        GG_RAY_TIR);
    assert_true(l->holds);
    ggLedgerFree(l);
    assert_int_equal(ggLedgerCreate(NULL, px, NULL, &l, NULL), GG_ERROR_INVALID);
    ggLedgerFree(NULL);
    ggTraceFree(t);
    ggSceneFree(s);
}

/* The Phong term of pixel (x, y) under opt, from its ledger (0 if none). */
static ggColor phong_term(ggScene *s, const ggRenderOptions *o, int x, int y)
{
    ggTrace *t = ggTraceCreate(NULL);
    ggLedger *l = NULL;
    ggColor px, v = {0, 0, 0};
    size_t i;
    assert_int_equal(ggTracePixel(s, o, x, y, -1, t, &px, NULL, NULL), GG_OK);
    assert_int_equal(ggLedgerCreate(t, px, NULL, &l, NULL), GG_OK);
    for (i = 0; i < l->count; i++)
        if (l->terms[i].kind == GG_TERM_PHONG) v = l->terms[i].value;
    ggLedgerFree(l);
    ggTraceFree(t);
    return v;
}

/* phong=fast (render.h): a whole shine by repeated squaring, within
   (shine - 1) 2^-53 of pow and, at shine 4095 (twelve bits, the first
   square's rounding doubled eleven times), not equal to it everywhere;
   a shine that is not whole takes pow either way. The highlight of a
   sphere lit from the eye, around the image centre. */
static void test_phong_fast(void **state)
{
    static const char *const nff[2] = {
        "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 30\nhither 0.01\nresolution 41 41\n"
        "b 0 0 0\nl 0 0 5\nf 1 1 1 0.5 0.5 4095 0 1\ns 0 0 0 1\n",
        "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 30\nhither 0.01\nresolution 41 41\n"
        "b 0 0 0\nl 0 0 5\nf 1 1 1 0.5 0.5 4095.5 0 1\ns 0 0 0 1\n"};
    const double bound = (4094 + 4) * 0x1p-53;
    int k, x, y, differ[2] = {0, 0}, seen[2] = {0, 0};
    (void)state;
    for (k = 0; k < 2; k++) {
        ggScene *s = ggSceneCreate(NULL);
        ggRenderOptions exact, fast;
        assert_int_equal(ggSceneLoadString(s, nff[k], strlen(nff[k]), "phong.nff", NULL), GG_OK);
        assert_int_equal(ggScenePrepare(s, NULL), GG_OK);
        ggRenderOptionsDefault(&exact);
        ggRenderOptionsDefault(&fast);
        fast.accuracy.phong = GG_ACC_PHONG_FAST;
        for (y = 16; y <= 24; y++)
            for (x = 16; x <= 24; x++) {
                ggColor a = phong_term(s, &exact, x, y), b = phong_term(s, &fast, x, y);
                if (a.r == 0) continue;
                seen[k]++;
                if (fabs(b.r - a.r) > bound * a.r || fabs(b.g - a.g) > bound * a.g ||
                    fabs(b.b - a.b) > bound * a.b)
                    fail_msg("pixel %d,%d: fast %.17g against pow %.17g", x, y, b.r, a.r);
                differ[k] += b.r != a.r;
            }
        ggSceneFree(s);
    }
    assert_true(seen[0] > 10 && seen[1] > 10);
    assert_true(differ[0] > 0);
    assert_int_equal(differ[1], 0);
}

/* ---- check ---- */

static ggCheckResult *check(ggScene *s, int w, int h, int depth)
{
    ggRenderOptions o;
    ggCheckResult *r = NULL;
    ggError e;
    small(&o, w, h, 2);
    o.max_depth = depth;
    assert_int_equal(ggCheck(s, &o, NULL, &r, &e), GG_OK);
    return r;
}

/* NaN in a prepared scene's data, where no loader would let it in: the
   checker must still see it (the red sphere's diffuse colour, green). */
static ggScene *nan_scene(void)
{
    ggScene *s = tu_load("examples/scenes/default.nff");
    s->mfast[s->objects[3].material].kd_color.g = NAN;
    return s;
}

static void test_check_planted_defects(void **state)
{
    ggScene *s;
    ggCheckResult *r;
    const ggCheckItem *it;
    (void)state;
    /* kd + ks + kt > 1, named with the material's line */
    s = tu_load("tests/data/debug/energy.nff");
    r = check(s, 40, 30, 0);
    it = &r->items[GG_CHECK_ENERGY];
    assert_true(it->pixels > 0);
    assert_int_equal(it->severity, GG_SEVERITY_ERROR);
    assert_true(fabs(it->worst - 1.1) < 1e-9);
    assert_int_equal(it->pixels_worst[0].line, 14);
    assert_int_equal(it->pixels_worst[0].material, 1);
    assert_int_equal(r->failed, 1);
    ggCheckResultFree(r);
    ggSceneFree(s);
    /* an SPD scene's glass: kd 0.1 + ks 0.1 + kt 0.9, line 10 of mount.nff */
    {
        char path[512];
        snprintf(path, sizeof path, "%s/mount.nff", tu_spd_dir());
        s = tu_load(path);
        r = check(s, 48, 48, 0);
        it = &r->items[GG_CHECK_ENERGY];
        assert_true(it->pixels > 0);
        assert_true(fabs(it->worst - 1.1) < 1e-9);
        assert_int_equal(it->pixels_worst[0].line, 10);
        ggCheckResultFree(r);
        ggSceneFree(s);
    }
    /* NaN, and where it starts */
    s = nan_scene();
    r = check(s, 32, 24, 0);
    it = &r->items[GG_CHECK_NONFINITE];
    assert_true(it->pixels > 0);
    assert_true(it->rays == it->pixels);
    assert_int_equal(r->failed, 1);
    {
        /* the first NaN ray hits the floor and its children are finite */
        ggTrace *t = ggTraceCreate(NULL);
        ggRenderOptions o;
        const ggCheckPixel *p = &it->pixels_worst[0];
        const ggTraceNode *n;
        ggColor px;
        size_t j;
        small(&o, 32, 24, 1);
        assert_int_equal(ggTracePixel(s, &o, p->x, p->y, -1, t, &px, NULL, NULL), GG_OK);
        assert_true(isnan(px.g));
        n = ggTraceGetNode(t, (size_t)p->node);
        assert_true(isnan(n->color.g) && n->hit && n->object == 3 && p->object == 3);
        for (j = 0; j < ggTraceNodeCount(t); j++)
            if (ggTraceGetNode(t, j)->parent == p->node)
                assert_false(isnan(ggTraceGetNode(t, j)->color.g));
        ggTraceFree(t);
    }
    ggCheckResultFree(r);
    ggSceneFree(s);
    /* values too large for the image's floats: infinite pixels */
    s = tu_load("tests/data/debug/overflow.nff");
    r = check(s, 40, 30, 0);
    it = &r->items[GG_CHECK_NONFINITE];
    assert_true(it->pixels > 0);
    assert_int_equal(it->pixels_worst[0].node, 0);
    assert_int_equal(it->pixels_worst[0].object, 1);
    ggCheckResultFree(r);
    ggSceneFree(s);
    /* cut by the depth limit; passes once the depth suffices */
    s = tu_load("tests/data/debug/cut.nff");
    r = check(s, 40, 30, 0);
    it = &r->items[GG_CHECK_TRUNCATION];
    assert_true(it->pixels > 500);
    assert_true(it->worst > 0.8);
    assert_true(isfinite(r->radiance_bound) && r->radiance_bound > 1);
    assert_int_equal(r->failed, 1);
    ggCheckResultFree(r);
    r = check(s, 40, 30, 64);
    assert_int_equal(r->items[GG_CHECK_TRUNCATION].pixels, 0);
    assert_int_equal(r->failed, 0);
    ggCheckResultFree(r);
    ggSceneFree(s);
    /* cut by the ray budget after some children were cast: only the
       children not cast count (it said 7.07 here, more than a pixel's
       whole weight; every material conserves energy, so at most 1) */
    s = tu_load("tests/data/nested-glass.nff");
    r = check(s, 64, 48, 0);
    it = &r->items[GG_CHECK_TRUNCATION];
    assert_true(it->pixels > 0);
    assert_true(it->worst > 0.1 && it->worst <= 1);
    ggCheckResultFree(r);
    ggSceneFree(s);
}

static void test_check_clean_scenes(void **state)
{
    static const char *const clean[] = {"examples/scenes/default.nff", "examples/scenes/water.nff",
                                        "examples/scenes/texture.nff", "examples/scenes/torus.nff",
                                        "examples/scenes/acc-distant.nff"};
    size_t k;
    int c;
    (void)state;
    for (k = 0; k < sizeof clean / sizeof clean[0]; k++) {
        ggScene *s = tu_load(clean[k]);
        ggCheckResult *r = check(s, 64, 48, 0);
        for (c = 0; c < GG_CHECK_COUNT; c++)
            if (r->items[c].severity == GG_SEVERITY_ERROR && r->items[c].pixels)
                print_error("%s: %s fails in %ld pixels\n", clean[k], ggCheckName(c),
                            r->items[c].pixels);
        assert_int_equal(r->failed, 0);
        assert_int_equal(r->scanned, 64 * 48);
        ggCheckResultFree(r);
        ggSceneFree(s);
    }
}

/* The shadow verdicts against the transmittance the trace records, on
   every pixel of every example, SPD and test-data scene at 32x24:
   visible exactly when all of the light got through, attenuated when
   some but not all did, blocked when none did and an occluder is
   named. A transparent object that takes nothing (glass.nff's kt = 1
   spheres) leaves the light visible and is named as the object
   crossed; a light that only an absorbing medium dims is attenuated
   with no occluder. A render of the scene counts the same blocked and
   attenuated shadow rays (ggRayStats) as the traces' verdicts, on 2
   threads (the occluder caches then differ from the traces'). */
typedef struct verdict_counts {
    long seen[4], crossed_visible, medium_only;
} verdict_counts;

static void check_verdicts(const char *path, void *ud)
{
    verdict_counts *vc = ud;
    ggScene *s = tu_load(path);
    ggTrace *t = ggTraceCreate(NULL);
    ggRenderOptions o;
    ggRayStats st;
    ggImage *img = NULL;
    ggError e;
    long here[4] = {0};
    int x, y;
    size_t i;
    small(&o, 32, 24, 1);
    for (y = 0; y < 24; y++)
        for (x = 0; x < 32; x++) {
            ggColor px;
            assert_int_equal(ggTracePixel(s, &o, x, y, -1, t, &px, NULL, &e), GG_OK);
            for (i = 0; i < ggTraceLightCount(t); i++) {
                const ggTraceLight *L = ggTraceGetLight(t, i);
                ggColor a = L->transmittance;
                int all = a.r == 1 && a.g == 1 && a.b == 1, none = a.r == 0 && a.g == 0 && a.b == 0;
                int ok = L->verdict == GG_SHADOW_VISIBLE      ? all
                         : L->verdict == GG_SHADOW_ATTENUATED ? !all
                         : L->verdict == GG_SHADOW_BLOCKED    ? none && L->occluder >= 0
                                                              : L->occluder < 0;
                if (!ok)
                    print_error(
                        "%s %d,%d light %d: %s with transmittance (%g %g %g), occluder %d\n", path,
                        x, y, L->light, ggShadowName(L->verdict), a.r, a.g, a.b, L->occluder);
                assert_true(ok);
                vc->seen[L->verdict]++;
                here[L->verdict]++;
                vc->crossed_visible += L->verdict == GG_SHADOW_VISIBLE && L->occluder >= 0;
                vc->medium_only += L->verdict == GG_SHADOW_ATTENUATED && L->occluder < 0;
            }
        }
    o.threads = 2;
    assert_int_equal(ggRender(s, &o, &img, &st, &e), GG_OK);
    if (st.shadow_blocked != (uint64_t)here[GG_SHADOW_BLOCKED] ||
        st.shadow_attenuated != (uint64_t)here[GG_SHADOW_ATTENUATED])
        print_error("%s: the render counts %llu blocked, %llu attenuated; the traces %ld, %ld\n",
                    path, (unsigned long long)st.shadow_blocked,
                    (unsigned long long)st.shadow_attenuated, here[GG_SHADOW_BLOCKED],
                    here[GG_SHADOW_ATTENUATED]);
    assert_true(st.shadow_blocked == (uint64_t)here[GG_SHADOW_BLOCKED]);
    assert_true(st.shadow_attenuated == (uint64_t)here[GG_SHADOW_ATTENUATED]);
    ggImageFree(img);
    ggTraceFree(t);
    ggSceneFree(s);
}

static void test_shadow_verdicts(void **state)
{
    verdict_counts vc = {{0}, 0, 0};
    int v;
    (void)state;
    assert_true(tu_each_file("examples/scenes", ".nff", check_verdicts, &vc) >= 10);
    assert_true(tu_each_file(tu_spd_dir(), ".nff", check_verdicts, &vc) >= 7);
    assert_true(tu_each_file("tests/data", ".nff", check_verdicts, &vc) >= 1);
    assert_true(tu_each_file("tests/data/debug", ".nff", check_verdicts, &vc) >= 1);
    /* every verdict occurs, and so do a lossless crossing and a light
       that only the medium around it dims (tests/data/light-in-glass.nff) */
    for (v = 0; v < 4; v++) assert_true(vc.seen[v] > 0);
    assert_true(vc.crossed_visible > 0);
    assert_true(vc.medium_only > 0);
}

/* The same answers on 1 and 3 threads. */
static void test_check_threads(void **state)
{
    ggScene *s = tu_load("examples/scenes/glass.nff");
    ggCheckResult *a = check(s, 60, 40, 0), *b;
    ggRenderOptions o;
    (void)state;
    small(&o, 60, 40, 3);
    assert_int_equal(ggCheck(s, &o, NULL, &b, NULL), GG_OK);
    assert_memory_equal(a->items, b->items, sizeof a->items);
    assert_true(a->items[GG_CHECK_TRUNCATION].pixels > 0); /* glass.nff at depth 5 is cut */
    ggCheckResultFree(a), ggCheckResultFree(b);
    ggCheckResultFree(NULL);
    ggSceneFree(s);
}

/* A failing background: every miss fails the nonfinite check, those in
   spans of misses too, whose trees scan.c traces once (check.c reuses a
   passed verdict along the span, not a failed one). The count equals the
   NaN pixels of ggRender's image. */
static void test_check_failing_misses(void **state)
{
    ggScene *s = tu_load("examples/scenes/spd/tetra.nff"); /* mostly sky */
    ggCheckResult *r;
    ggImage *img = NULL;
    ggRenderOptions o;
    const float *px;
    long nan = 0, i;
    (void)state;
    s->background.g = NAN;
    small(&o, 64, 48, 2);
    assert_int_equal(ggRender(s, &o, &img, NULL, NULL), GG_OK);
    px = ggImagePixelsConst(img);
    for (i = 0; i < 64 * 48; i++) nan += px[3 * i] != px[3 * i] || px[3 * i + 1] != px[3 * i + 1];
    assert_true(nan > 16 * 16); /* at least one whole tile of sky */
    assert_int_equal(ggCheck(s, &o, NULL, &r, NULL), GG_OK);
    assert_int_equal(r->items[GG_CHECK_NONFINITE].pixels, nan);
    ggCheckResultFree(r);
    ggImageFree(img);
    ggSceneFree(s);
}

/* ---- diff ---- */

static void test_diff_identical(void **state)
{
    ggScene *s = tu_load("examples/scenes/glass.nff");
    ggRenderOptions o;
    ggDiffResult *r = NULL;
    int i;
    (void)state;
    small(&o, 64, 48, 2);
    assert_int_equal(ggDiff(s, &o, s, &o, 10, &r, NULL), GG_OK);
    assert_int_equal(r->value_differ, 0);
    assert_int_equal(r->tree_differ, 0);
    assert_int_equal(r->nworst, 0);
    for (i = 0; i < 64 * 48; i++) assert_int_equal(r->map[i], 0);
    ggDiffResultFree(r);
    ggSceneFree(s);
}

/* Which objects each ray hit and each light's verdict: the trees'
   identity as ggTraceCompare should see it, hand-written. */
static unsigned long long signature(const ggTrace *t)
{
    unsigned long long h = 1469598103934665603ull;
    size_t i;
    int l;
    for (i = 0; i < ggTraceNodeCount(t); i++) {
        const ggTraceNode *n = ggTraceGetNode(t, i);
        h = (h ^ (unsigned long long)(n->hit ? n->object * 2 + n->front + 1 : 0)) *
            1099511628211ull;
        h = (h ^ (unsigned long long)(n->kind * 8 + n->stop)) * 1099511628211ull;
        h = (h ^ (unsigned long long)(n->parent + 1)) * 1099511628211ull;
        for (l = 0; n->hit && l < n->nlights; l++) {
            const ggTraceLight *L = ggTraceGetLight(t, (size_t)(n->first_light + l));
            h = (h ^ (unsigned long long)(L->verdict * 1000 + L->occluder + 1)) * 1099511628211ull;
        }
    }
    return h;
}

static void test_diff_textbook_sphere(void **state)
{
    ggScene *a = tu_load("examples/scenes/acc-distant.nff"),
            *b = tu_load("examples/scenes/acc-distant.nff");
    ggRenderOptions oa, ob;
    ggDiffResult *r = NULL;
    ggTrace *ta = ggTraceCreate(NULL), *tb = ggTraceCreate(NULL);
    long trees = 0, values = 0;
    int x, y, i;
    (void)state;
    small(&oa, 80, 60, 2);
    ob = oa;
    assert_int_equal(ggRenderOptionsParse(&ob, "sphere=textbook", NULL), GG_OK);
    assert_int_equal(ob.accuracy.sphere, GG_ACC_SPHERE_TEXTBOOK);
    /* the knobs travel with the options (scene.h): one scene object
       serves both sphere modes at once, and gives what two copies give */
    {
        ggDiffResult *one = NULL;
        assert_int_equal(ggDiff(a, &oa, a, &ob, 5, &one, NULL), GG_OK);
        assert_int_equal(ggDiff(a, &oa, b, &ob, 5, &r, NULL), GG_OK);
        assert_int_equal(one->tree_differ, r->tree_differ);
        assert_int_equal(one->value_differ, r->value_differ);
        assert_memory_equal(one->map, r->map, 80 * 60);
        for (i = 0; i < 5; i++) {
            assert_int_equal(one->worst[i].x, r->worst[i].x);
            assert_int_equal(one->worst[i].y, r->worst[i].y);
            assert_true(one->worst[i].delta == r->worst[i].delta);
            assert_int_equal(one->worst[i].first.what, r->worst[i].first.what);
        }
        ggDiffResultFree(one);
        /* any count up to INT_MAX: at most every differing pixel is
           listed (a worst of INT_MAX asked for INT_MAX entries a thread) */
        assert_int_equal(ggDiff(a, &oa, a, &ob, INT_MAX, &one, NULL), GG_OK);
        assert_int_equal(one->nworst, one->value_differ);
        for (i = 0; i < 5; i++) assert_true(one->worst[i].delta == r->worst[i].delta);
        ggDiffResultFree(one);
        /* a negative count fails with *out NULL, as every failure after
           the NULL checks (debug.h) */
        one = (ggDiffResult *)&one;
        assert_int_equal(ggDiff(a, &oa, a, &ob, -1, &one, NULL), GG_ERROR_INVALID);
        assert_null(one);
    }
    for (y = 0; y < 60; y++)
        for (x = 0; x < 80; x++) {
            ggColor pa, pb;
            int td, vd;
            assert_int_equal(ggTracePixel(a, &oa, x, y, -1, ta, &pa, NULL, NULL), GG_OK);
            assert_int_equal(ggTracePixel(b, &ob, x, y, -1, tb, &pb, NULL, NULL), GG_OK);
            td = signature(ta) != signature(tb);
            vd = pa.r != pb.r || pa.g != pb.g || pa.b != pb.b;
            assert_int_equal(r->map[y * 80 + x], td ? 2 : vd ? 1 : 0);
            trees += td, values += vd;
        }
    assert_int_equal(r->tree_differ, trees);
    assert_int_equal(r->value_differ, values);
    /* the textbook quadratic loses silhouettes: eye rays that hit or miss */
    assert_true(trees > 0 && r->first_by_kind[GG_DIFF_HIT] > 0);
    assert_true(r->nworst == 5 && r->worst[0].delta > 0.5);
    for (i = 1; i < r->nworst; i++) assert_true(r->worst[i].delta <= r->worst[i - 1].delta);
    {
        /* the worst: its first divergence is an eye ray's hit */
        const ggDiffPixel *p = &r->worst[0];
        ggDivergence d;
        ggColor pa, pb;
        assert_int_equal(ggTracePixel(a, &oa, p->x, p->y, -1, ta, &pa, NULL, NULL), GG_OK);
        assert_int_equal(ggTracePixel(b, &ob, p->x, p->y, -1, tb, &pb, NULL, NULL), GG_OK);
        assert_int_equal(ggTraceCompare(ta, tb, &d), 1);
        assert_memory_equal(&d, &p->first, sizeof d);
        assert_true(d.what == GG_DIFF_HIT || d.what == GG_DIFF_OBJECT);
        assert_int_equal(ggTraceCompare(ta, ta, &d), 0);
        assert_int_equal(d.what, GG_DIFF_SAME);
    }
    ggDiffResultFree(r);
    ggDiffResultFree(NULL);
    ggTraceFree(ta), ggTraceFree(tb);
    ggSceneFree(a), ggSceneFree(b);
}

/* A depth limit cuts the glass pixel: the first divergence is its stop. */
static void test_compare_depth(void **state)
{
    ggScene *s = tu_load("examples/scenes/glass.nff");
    ggRenderOptions o3;
    ggTrace *a = ggTraceCreate(NULL), *b = ggTraceCreate(NULL);
    ggDivergence d;
    ggColor pa, pb;
    (void)state;
    ggRenderOptionsDefault(&o3);
    o3.max_depth = 3;
    assert_int_equal(ggTracePixel(s, NULL, 110, 100, -1, a, &pa, NULL, NULL), GG_OK);
    assert_int_equal(ggTracePixel(s, &o3, 110, 100, -1, b, &pb, NULL, NULL), GG_OK);
    assert_int_equal(ggTraceCompare(a, b, &d), 1);
    assert_int_equal(d.what, GG_DIFF_STOP);
    assert_int_equal(d.a, GG_STOP_NONE);
    assert_int_equal(d.b, GG_STOP_DEPTH);
    assert_int_equal(ggTraceGetNode(a, (size_t)d.node_a)->depth, 3);
    ggTraceFree(a), ggTraceFree(b);
    ggSceneFree(s);
}

/* Each kind of difference, planted in a copy of a real tree. */
static void copy_trace(ggTrace *dst, const ggTrace *src)
{
    size_t i;
    int k;
    gg_trace_clear(dst);
    for (i = 0; i < src->nnodes; i++) {
        assert_true((k = gg_trace_add_node(dst)) >= 0); /* may move dst->nodes */
        dst->nodes[k] = src->nodes[i];
    }
    for (i = 0; i < src->nlights; i++) {
        assert_true((k = gg_trace_add_light(dst)) >= 0);
        dst->lights[k] = src->lights[i];
    }
}

static void expect_divergence(const ggTrace *a, const ggTrace *b, int what, int node_a)
{
    ggDivergence d;
    assert_int_equal(ggTraceCompare(a, b, &d), 1);
    if (d.what != what || d.node_a != node_a)
        print_error("want %s at #%d, got %s at #%d\n", ggDiffName(what), node_a, ggDiffName(d.what),
                    d.node_a);
    assert_int_equal(d.what, what);
    assert_int_equal(d.node_a, node_a);
}

static void test_compare_kinds(void **state)
{
    ggScene *s = tu_load("examples/scenes/glass.nff");
    ggTrace *a = ggTraceCreate(NULL), *b = ggTraceCreate(NULL);
    ggColor px;
    int l1;
    (void)state;
    /* 0 eye, 1 refract, 2 tir, 3 refract (miss), 4 reflect, 5 tir (depth), 6 reflect (miss) */
    assert_int_equal(ggTracePixel(s, NULL, 110, 100, -1, a, &px, NULL, NULL), GG_OK);
    assert_int_equal(a->nnodes, 7);
    assert_int_equal(a->nodes[5].stop, GG_STOP_DEPTH);
    l1 = a->nodes[1].first_light;
    copy_trace(b, a);
    assert_int_equal(ggTraceCompare(a, b, NULL), 0);
    b->nodes[6].hit = true, b->nodes[6].object = 0;
    expect_divergence(a, b, GG_DIFF_HIT, 6);
    copy_trace(b, a);
    b->nodes[1].object = 1;
    expect_divergence(a, b, GG_DIFF_OBJECT, 1);
    copy_trace(b, a);
    b->nodes[2].front = !b->nodes[2].front;
    expect_divergence(a, b, GG_DIFF_FACE, 2);
    copy_trace(b, a);
    b->lights[l1 + 1].verdict = GG_SHADOW_BLOCKED;
    expect_divergence(a, b, GG_DIFF_SHADOW, 1);
    copy_trace(b, a);
    b->lights[l1].occluder = 0;
    expect_divergence(a, b, GG_DIFF_OCCLUDER, 1);
    copy_trace(b, a);
    b->nodes[5].stop = GG_STOP_MATTE;
    expect_divergence(a, b, GG_DIFF_STOP, 5);
    copy_trace(b, a);
    b->nodes[4].kind = GG_RAY_TIR;
    expect_divergence(a, b, GG_DIFF_TIR, 4);
    copy_trace(b, a);
    b->nodes[2].kind = GG_RAY_REFRACT; /* ray 1 refracts in b instead of reflecting totally */
    expect_divergence(a, b, GG_DIFF_TIR, 2);
    copy_trace(b, a);
    b->nodes[3].parent = 99; /* ray 2 has no refracted child in b */
    expect_divergence(a, b, GG_DIFF_CHILD, 3);
    copy_trace(b, a);
    b->nodes[3].parent = -1; /* a second tree */
    expect_divergence(a, b, GG_DIFF_SAMPLES, -1);
    ggTraceFree(a), ggTraceFree(b);
    ggSceneFree(s);
}

/* ---- the numeric state of each hit ---- */

static void test_numeric_state(void **state)
{
    ggScene *s = tu_load("examples/scenes/glass.nff");
    ggTrace *t = ggTraceCreate(NULL);
    ggRenderOptions o;
    ggColor px;
    size_t i;
    int x, y, decided = 0;
    (void)state;
    /* 110,100: 0 enters the glass (refracts), 1 is reflected totally at the bubble */
    assert_int_equal(ggTracePixel(s, NULL, 110, 100, -1, t, &px, NULL, NULL), GG_OK);
    assert_true(ggTraceGetNode(t, 0)->tir_margin > 1e10);
    assert_true(ggTraceGetNode(t, 1)->tir_margin < -1e10);
    assert_true(isnan(ggTraceGetNode(t, 0)->edge)); /* a sphere */
    for (i = 0; i < ggTraceNodeCount(t); i++) {
        const ggTraceNode *n = ggTraceGetNode(t, i);
        if (!n->hit) {
            assert_true(isnan(n->perr) && isnan(n->offset) && isnan(n->tir_margin));
            continue;
        }
        /* the scaled offset pushes by 8 error bounds (lib/geom/offset.c) */
        assert_true(n->perr > 0 && n->perr < 1e-14);
        assert_true(n->offset >= 7.9 * n->perr && n->offset <= 8 * sqrt(3.0) * n->perr * 1.01);
    }
    /* Over an image: where the margin is clear, it agrees with the decision. */
    small(&o, 64, 48, 1);
    for (y = 0; y < 48; y++)
        for (x = 0; x < 64; x++) {
            assert_int_equal(ggTracePixel(s, &o, x, y, -1, t, &px, NULL, NULL), GG_OK);
            for (i = 0; i < ggTraceNodeCount(t); i++) {
                const ggTraceNode *n = ggTraceGetNode(t, i);
                size_t j;
                int refr = 0, tir = 0;
                if (!isfinite(n->tir_margin) || fabs(n->tir_margin) < 16) continue;
                for (j = i + 1; j < ggTraceNodeCount(t); j++)
                    if (ggTraceGetNode(t, j)->parent == (int)i) {
                        refr |= ggTraceGetNode(t, j)->kind == GG_RAY_REFRACT;
                        tir |= ggTraceGetNode(t, j)->kind == GG_RAY_TIR;
                    }
                if (n->stop == GG_STOP_DEPTH) continue;
                assert_int_equal(n->tir_margin > 0, refr);
                assert_int_equal(n->tir_margin < 0, tir);
                decided++;
            }
            /* the floor is a rectangle: an edge distance in [0, 1/2] */
            if (ggTraceGetNode(t, 0)->hit && ggTraceGetNode(t, 0)->object == 0) {
                double e = ggTraceGetNode(t, 0)->edge;
                assert_true(e >= 0 && e <= 0.5);
            }
        }
    assert_true(decided > 100);
    ggSceneFree(s);
    /* triangles: the smallest barycentric coordinate; a fixed offset is what it says */
    {
        char path[512];
        ggTraceNode n0;
        snprintf(path, sizeof path, "%s/tetra.nff", tu_spd_dir());
        s = tu_load(path);
        small(&o, 64, 64, 1);
        assert_int_equal(ggRenderOptionsParse(&o, "offset=1e-6", NULL), GG_OK);
        assert_int_equal(ggTracePixel(s, &o, 32, 40, -1, t, &px, NULL, NULL), GG_OK);
        n0 = *ggTraceGetNode(t, 0);
        assert_true(n0.hit && n0.shape == GG_SHAPE_TRIANGLE);
        assert_true(n0.edge >= 0 && n0.edge <= 1.0 / 3);
        assert_true(fabs(n0.offset - 1e-6) < 1e-12);
        /* the edge distance is the smallest barycentric coordinate of p,
           here from the triangle's own vertices */
        for (y = 8; y < 64; y += 8)
            for (x = 4; x < 64; x += 6) {
                ggShapeDesc d;
                ggVec3 a, b, c, q;
                double ab, bc, ca, all, m;
                const ggTraceNode *n;
                assert_int_equal(ggTracePixel(s, &o, x, y, -1, t, &px, NULL, NULL), GG_OK);
                n = ggTraceGetNode(t, 0);
                if (!n->hit) continue;
                assert_int_equal(ggSceneObjectShape(s, n->object, &d), GG_OK);
                a = d.verts[0], b = d.verts[1], c = d.verts[2], q = n->p;
#define TRI_AREA(p1, p2, p3)                                                                       \
    sqrt(pow((p2.y - p1.y) * (p3.z - p1.z) - (p2.z - p1.z) * (p3.y - p1.y), 2) +                   \
         pow((p2.z - p1.z) * (p3.x - p1.x) - (p2.x - p1.x) * (p3.z - p1.z), 2) +                   \
         pow((p2.x - p1.x) * (p3.y - p1.y) - (p2.y - p1.y) * (p3.x - p1.x), 2))
                all = TRI_AREA(a, b, c);
                ab = TRI_AREA(q, a, b) / all, bc = TRI_AREA(q, b, c) / all,
                ca = TRI_AREA(q, c, a) / all;
#undef TRI_AREA
                m = ab < bc ? ab : bc;
                m = m < ca ? m : ca;
                if (fabs(m - n->edge) > 1e-6)
                    print_error("%d,%d: edge %g, barycentric %g\n", x, y, n->edge, m);
                assert_true(fabs(m - n->edge) <= 1e-6);
            }
        ggSceneFree(s);
    }
    ggTraceFree(t);
}

/* Each ray's traversal cost: within the BVH's size, a hit has a tested
   primitive, and the BVH prunes (balls-s3: 821 primitives). */
static void test_traversal_cost(void **state)
{
    char path[512];
    ggScene *s;
    ggSceneInfo in;
    ggTrace *t = ggTraceCreate(NULL);
    ggRenderOptions o;
    ggColor px;
    long eye = 0, eye_prims = 0, rays = 0;
    size_t i;
    int x, y;
    (void)state;
    snprintf(path, sizeof path, "%s/balls-s3.nff", tu_spd_dir());
    s = tu_load(path);
    assert_int_equal(ggSceneGetInfo(s, &in), GG_OK);
    small(&o, 48, 48, 1);
    for (y = 0; y < 48; y++)
        for (x = 0; x < 48; x++) {
            assert_int_equal(ggTracePixel(s, &o, x, y, -1, t, &px, NULL, NULL), GG_OK);
            for (i = 0; i < ggTraceNodeCount(t); i++) {
                const ggTraceNode *n = ggTraceGetNode(t, i);
                assert_true(n->nodes >= 0 && (size_t)n->nodes <= in.bvh_nodes);
                /* + 1: the isolated-sphere hint tests its sphere first */
                assert_true(n->prims >= 0 && (size_t)n->prims <= in.primitives + 1);
                if (n->hit) assert_true(n->prims >= 1 && n->nodes >= 1);
                if (n->kind == GG_RAY_EYE) eye++, eye_prims += n->prims;
                rays++;
            }
        }
    assert_int_equal(eye, 48 * 48);
    assert_true(rays > eye);
    /* an eye ray tests under 2% of the primitives */
    if (!(eye_prims * 50 < eye * (long)in.primitives))
        print_error("%ld primitives tested by %ld eye rays\n", eye_prims, eye);
    assert_true(eye_prims * 50 < eye * (long)in.primitives);
    ggSceneFree(s);
    ggTraceFree(t);
}

/* self-hit and near-tir see the recorded state: with thresholds that take
   everything they count every secondary hit and every refraction. */
static void test_check_numeric(void **state)
{
    ggScene *s = tu_load("examples/scenes/glass.nff");
    ggRenderOptions o;
    ggCheckOptions co;
    ggCheckResult *r = NULL;
    ggTrace *t = ggTraceCreate(NULL);
    long second = 0, refr = 0;
    int x, y;
    size_t i;
    (void)state;
    small(&o, 40, 30, 2);
    ggCheckOptionsDefault(&co);
    co.self_hit = co.near_tir = 1e300;
    assert_int_equal(ggCheck(s, &o, &co, &r, NULL), GG_OK);
    for (y = 0; y < 30; y++)
        for (x = 0; x < 40; x++) {
            ggColor px;
            assert_int_equal(ggTracePixel(s, &o, x, y, -1, t, &px, NULL, NULL), GG_OK);
            for (i = 0; i < ggTraceNodeCount(t); i++) {
                const ggTraceNode *n = ggTraceGetNode(t, i);
                int l;
                second += n->hit && n->parent >= 0 && ggTraceGetNode(t, (size_t)n->parent)->hit;
                refr += isfinite(n->tir_margin);
                for (l = 0; n->hit && l < n->nlights; l++)
                    second += ggTraceGetLight(t, (size_t)(n->first_light + l))->occluder >= 0;
            }
        }
    assert_int_equal(r->items[GG_CHECK_SELF_HIT].rays, second);
    assert_int_equal(r->items[GG_CHECK_NEAR_TIR].rays, refr);
    assert_true(second > 0 && refr > 0);
    ggCheckResultFree(r);
    ggSceneFree(s);
    ggTraceFree(t);
    /* far from the origin a fixed offset of 1e-12 is no offset at all */
    s = tu_load("examples/scenes/acc-far.nff");
    small(&o, 64, 48, 2);
    assert_int_equal(ggCheck(s, &o, NULL, &r, NULL), GG_OK);
    assert_int_equal(r->items[GG_CHECK_SELF_HIT].pixels, 0);
    ggCheckResultFree(r);
    assert_int_equal(ggRenderOptionsParse(&o, "offset=1e-12", NULL), GG_OK);
    assert_int_equal(ggCheck(s, &o, NULL, &r, NULL), GG_OK);
    assert_true(r->items[GG_CHECK_SELF_HIT].pixels > 10);
    assert_int_equal(r->items[GG_CHECK_SELF_HIT].severity, GG_SEVERITY_WARNING);
    ggCheckResultFree(r);
    ggSceneFree(s);
}

/* ---- render options as text ---- */

/* Each setting, misspelt by a letter, is suggested; none is unknown. */
static void unknown_settings_suggest(void)
{
    static const char *const names[] = {
        "size",    "crop",      "depth",   "samples",      "threads",      "ray-budget",
        "sphere",  "refract",   "fresnel", "texture",      "wavelengths",  "intersect",
        "shadows", "phong",     "offset",  "gradient",     "implicit-tol", "cutoff",
        "spd",     "spd-rules", "corners", "force-effects"};
    ggRenderOptions o;
    ggError e;
    char text[64], want[128];
    size_t i;
    for (i = 0; i < sizeof names / sizeof names[0]; i++) {
        ggRenderOptionsDefault(&o);
        snprintf(text, sizeof text, "%s=?", names[i]);
        if (ggRenderOptionsParse(&o, text, &e) != GG_OK) assert_null(strstr(e.message, "unknown"));
        snprintf(text, sizeof text, "%sq=1", names[i]);
        assert_int_equal(ggRenderOptionsParse(&o, text, &e), GG_ERROR_PARSE);
        snprintf(want, sizeof want, "1:1: unknown setting '%sq'; did you mean '%s'?", names[i],
                 names[i]);
        assert_string_equal(e.message, want);
    }
}

/* Every combination of the SPD flags, a depth or none, and a ray budget
   or none reads back as itself ("spd" alone would also set the depth),
   and so does the fixed offset with no epsilon of its own. */
static void round_trips(void)
{
    static const int depth[] = {0, 5, 7}, budget[] = {0, 1, GG_RAY_BUDGET_MAX};
    ggRenderOptions o, p;
    char buf[512];
    int k;
    for (k = 0; k < 36; k++) {
        ggRenderOptionsDefault(&o);
        o.spd_rules = k & 1, o.pixel_corners = k >> 1 & 1;
        o.max_depth = depth[k / 4 % 3], o.ray_budget = budget[k / 12];
        ggRenderOptionsFormat(&o, buf, sizeof buf);
        ggRenderOptionsDefault(&p);
        assert_int_equal(ggRenderOptionsParse(&p, buf, NULL), GG_OK);
        if (memcmp(&o, &p, sizeof o)) fail_msg("'%s' does not read back as its options", buf);
    }
    /* the fixed offset with its default epsilon (0: 1e-6) */
    ggRenderOptionsDefault(&o);
    o.accuracy.offset = GG_ACC_OFFSET_FIXED;
    ggRenderOptionsFormat(&o, buf, sizeof buf);
    assert_string_equal(buf, "offset=fixed");
}

/* A small deterministic generator for the random round trips. */
static unsigned long rt_state = 1;
static int rt_int(int lo, int hi)
{
    rt_state = rt_state * 6364136223846793005ul + 1442695040888963407ul;
    return lo + (int)((rt_state >> 33) % (unsigned long)(hi - lo + 1));
}
/* 0 half the time, else a number in (0, hi] with all 53 bits random */
static double rt_num(double hi)
{
    double d;
    if (rt_int(0, 1)) return 0;
    d = ldexp((double)rt_int(1, 1 << 26) * 134217728.0 + rt_int(0, (1 << 27) - 1), -53);
    return d * hi > 0 ? d * hi : hi;
}

/* Options drawn at random from the ranges ggRenderOptionsParse accepts,
   every field at once: each formats to text that reads back as them
   (a size with one side 0, a subset of force_effects: both once lost). */
static void random_round_trips(void)
{
    ggRenderOptions o, p;
    ggAccuracy *a = &o.accuracy;
    char buf[1024];
    ggError e;
    int k;
    for (k = 0; k < 20000; k++) {
        ggRenderOptionsDefault(&o);
        o.width = rt_int(0, 3) ? rt_int(0, 65536) : 0;
        o.height = rt_int(0, 3) ? rt_int(0, 65536) : 0;
        o.max_depth = rt_int(0, 1) ? rt_int(0, 64) : 0;
        o.samples = rt_int(0, 1) ? rt_int(0, 4096) : 0;
        o.threads = rt_int(0, 1) ? rt_int(0, 256) : 0;
        o.ray_budget = rt_int(0, 1) ? rt_int(0, GG_RAY_BUDGET_MAX) : 0;
        if (rt_int(0, 1))
            o.crop_x0 = rt_int(0, 65536), o.crop_y0 = rt_int(0, 65536),
            o.crop_x1 = rt_int(0, 65536), o.crop_y1 = rt_int(0, 65536);
        o.spd_rules = rt_int(0, 1), o.pixel_corners = rt_int(0, 1);
        o.force_effects = rt_int(0, 1) ? (unsigned)rt_int(0, GG_EFFECT_ALL) : 0;
        a->offset = rt_int(0, 1) ? GG_ACC_OFFSET_FIXED : GG_ACC_OFFSET_SCALED;
        a->offset_eps = a->offset == GG_ACC_OFFSET_FIXED ? rt_num(1e3) : 0;
        a->sphere = rt_int(0, 1), a->refract = rt_int(0, 2), a->fresnel = rt_int(0, 3);
        a->texture = rt_int(0, 2), a->wavelengths = rt_int(0, 1), a->intersect = rt_int(0, 1);
        a->shadows = rt_int(0, 1), a->phong = rt_int(0, 1);
        a->cutoff = rt_num(1), a->implicit_tol = rt_num(1e-2), a->gradient_h = rt_num(1e2);
        assert_true(ggRenderOptionsFormat(&o, buf, sizeof buf) < sizeof buf);
        ggRenderOptionsDefault(&p);
        if (ggRenderOptionsParse(&p, buf, &e) != GG_OK) fail_msg("'%s': %s", buf, e.message);
        if (memcmp(&o, &p, sizeof o)) fail_msg("'%s' does not read back as its options", buf);
    }
    /* the two the audit found, spelled out */
    ggRenderOptionsDefault(&o), o.width = 5;
    ggRenderOptionsFormat(&o, buf, sizeof buf);
    assert_string_equal(buf, "size=5x0");
    ggRenderOptionsDefault(&o), o.force_effects = GG_EFFECT_REFRACTION | GG_EFFECT_SHADOWS;
    ggRenderOptionsFormat(&o, buf, sizeof buf);
    assert_string_equal(buf, "force-effects=shadows+refraction");
    o.force_effects = GG_EFFECT_ALL;
    ggRenderOptionsFormat(&o, buf, sizeof buf);
    assert_string_equal(buf, "force-effects");
    ggRenderOptionsDefault(&p);
    assert_int_equal(ggRenderOptionsParse(&p, "force-effects=phong+bogus", &e), GG_ERROR_PARSE);
    assert_string_equal(e.message, "1:21: force-effects= takes effect names joined by '+' "
                                   "(shadows+reflection), got 'bogus'");
    assert_int_equal(ggRenderOptionsParse(&p, "force-effects=", &e), GG_ERROR_PARSE);
    assert_int_equal(p.force_effects, 0);
}

static void test_options_text(void **state)
{
    ggRenderOptions o, p;
    ggError e;
    char buf[512];
    (void)state;
    ggRenderOptionsDefault(&o);
    assert_int_equal(ggRenderOptionsParse(&o, "", &e), GG_OK);
    assert_int_equal(ggRenderOptionsFormat(&o, buf, sizeof buf), 0);
    assert_int_equal(ggRenderOptionsParse(&o,
                                          "size=64x48 depth=8,samples=4 crop=1,2,30,40 spd "
                                          "sphere=textbook refract=exact fresnel=schlick "
                                          "texture=nearest wavelengths=one cutoff=0.001 "
                                          "implicit-tol=1e-7 gradient=1e-5 offset=1e-6 "
                                          "intersect=float shadows=opaque phong=fast",
                                          &e),
                     GG_OK);
    assert_int_equal(o.width, 64);
    assert_int_equal(o.accuracy.intersect, GG_ACC_ISECT_FLOAT);
    assert_int_equal(o.accuracy.shadows, GG_ACC_SHADOWS_OPAQUE);
    assert_int_equal(o.accuracy.phong, GG_ACC_PHONG_FAST);
    assert_int_equal(o.max_depth, 8);
    assert_int_equal(o.crop_y1, 40);
    assert_true(o.spd_rules && o.pixel_corners);
    assert_int_equal(o.accuracy.refract, GG_ACC_REFRACT_EXACT);
    assert_int_equal(o.accuracy.offset, GG_ACC_OFFSET_FIXED);
    assert_true(o.accuracy.offset_eps == 1e-6 && o.accuracy.cutoff == 0.001);
    ggRenderOptionsFormat(&o, buf, sizeof buf);
    ggRenderOptionsDefault(&p);
    assert_int_equal(ggRenderOptionsParse(&p, buf, &e), GG_OK);
    assert_memory_equal(&o, &p, sizeof o); /* a round trip */
    round_trips();
    random_round_trips();
    /* errors name the column and leave the options alone */
    p = o;
    assert_int_equal(ggRenderOptionsParse(&p, "depth=3 sphere=fast", &e), GG_ERROR_PARSE);
    assert_string_equal(e.message, "1:16: sphere must be stable or textbook, got 'fast'");
    assert_memory_equal(&o, &p, sizeof o);
    assert_int_equal(ggRenderOptionsParse(&p, "depht=3", &e), GG_ERROR_PARSE);
    assert_string_equal(e.message, "1:1: unknown setting 'depht'; did you mean 'depth'?");
    /* the command line's rule (cli_suggest): a start names the one
       setting it starts, a swap is one edit, a short word gets no guess
       two edits away */
    assert_int_equal(ggRenderOptionsParse(&p, "ray=3", &e), GG_ERROR_PARSE);
    assert_string_equal(e.message, "1:1: unknown setting 'ray'; did you mean 'ray-budget'?");
    assert_int_equal(ggRenderOptionsParse(&p, "dpeth=3", &e), GG_ERROR_PARSE);
    assert_string_equal(e.message, "1:1: unknown setting 'dpeth'; did you mean 'depth'?");
    assert_int_equal(ggRenderOptionsParse(&p, "sz=3", &e), GG_ERROR_PARSE);
    assert_string_equal(e.message, "1:1: unknown setting 'sz'");
    assert_int_equal(ggRenderOptionsParse(&p, "frobnicate=3", &e), GG_ERROR_PARSE);
    assert_string_equal(e.message, "1:1: unknown setting 'frobnicate'");
    assert_int_equal(ggRenderOptionsParse(&p, "depth=3 -d 8", &e), GG_ERROR_PARSE);
    assert_string_equal(e.message, "1:9: unknown setting '-d': settings are NAME=VALUE (depth=8, "
                                   "size=64x48), not options");
    unknown_settings_suggest();
    assert_int_equal(ggRenderOptionsParse(&p, "depth=3x", &e), GG_ERROR_PARSE);
    assert_int_equal(ggRenderOptionsParse(&p, "depth=65", &e), GG_ERROR_PARSE);
    assert_int_equal(ggRenderOptionsParse(&p, "size=64x", &e), GG_ERROR_PARSE);
    assert_int_equal(ggRenderOptionsParse(&p, "cutoff=2", &e), GG_ERROR_PARSE);
    assert_int_equal(ggRenderOptionsParse(&p, "spd=1", &e), GG_ERROR_PARSE);
    assert_int_equal(ggRenderOptionsParse(&p, "ray-budget=0", &e), GG_ERROR_PARSE);
    assert_int_equal(ggRenderOptionsParse(&p, "ray-budget=16777217", &e), GG_ERROR_PARSE);
    assert_int_equal(ggRenderOptionsParse(NULL, "", &e), GG_ERROR_INVALID);
    /* a short buffer: snprintf's contract */
    assert_true(ggRenderOptionsFormat(&o, buf, 4) > 4);
    assert_int_equal(strlen(buf), 3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_predicate_errors),
        cmocka_unit_test(test_find_matches_full_traces),
        cmocka_unit_test(test_find_limit_and_crop),
        cmocka_unit_test(test_ledger_sums_to_pixel),
        cmocka_unit_test(test_ledger_glass_pixel),
        cmocka_unit_test(test_phong_fast),
        cmocka_unit_test(test_check_planted_defects),
        cmocka_unit_test(test_check_clean_scenes),
        cmocka_unit_test(test_check_threads),
        cmocka_unit_test(test_shadow_verdicts),
        cmocka_unit_test(test_check_failing_misses),
        cmocka_unit_test(test_diff_identical),
        cmocka_unit_test(test_diff_textbook_sphere),
        cmocka_unit_test(test_compare_depth),
        cmocka_unit_test(test_compare_kinds),
        cmocka_unit_test(test_numeric_state),
        cmocka_unit_test(test_traversal_cost),
        cmocka_unit_test(test_check_numeric),
        cmocka_unit_test(test_options_text),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
