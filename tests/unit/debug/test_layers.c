/* SPDX-License-Identifier: MIT */
/*
** test_layers.c -- path layers (ggPathLayersCompile, lib/render/lpe.h):
** the compiled automaton stepped event by event, with labels, 'tir' and
** its dead state; refusals (predicates with their column, bad counts);
** and on rendered scenes, every layer's pixel equal to what ggPathMatch
** (the recorder's matcher) says the layer's paths carry, and the image
** itself unchanged by the layers.
*/
#include "testutil.h"

#include "lpe.h"
#include "scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static ggPathLayers *compile(const char *text)
{
    ggPathLayers *l = NULL;
    ggError e;
    int rc = ggPathLayersCompile(&text, 1, NULL, &l, &e);
    if (rc != GG_OK) print_error("%s: %s\n", text, e.message);
    assert_int_equal(rc, GG_OK);
    return l;
}

/* Whether the event string ks (kinds, each at class cls) from the start
   ends in an accepting state. */
static int run(const gg_lpe_dfa *d, const int *ks, const int *cls, int n)
{
    unsigned s = d->start;
    int i;
    for (i = 0; i < n; i++) s = gg_lpe_step(d, s, ks[i], cls[i]);
    return d->accept[s];
}

static void test_layers_stepping(void **state)
{
    ggPathLayers *l = compile("C<RS>+<TS>B");
    const gg_lpe_dfa *d = &l->layer[0];
    const int none = gg_lpe_none(d), sf = gg_lpe_surface(d, 3, 1);
    int ks[4] = {GG_LPE_RS, GG_LPE_RS_TIR, GG_LPE_TS, GG_LPE_B}, c[4];
    (void)state;
    c[0] = c[1] = c[2] = sf, c[3] = none;
    assert_int_equal(ggPathLayersCount(l), 1);
    assert_int_equal(d->ncls, 1);
    assert_true(run(d, ks, c, 4));        /* RS RS(tir) TS B: <RS> takes tir too */
    assert_true(run(d, ks + 1, c + 1, 3)); /* RS(tir) TS B */
    assert_false(run(d, ks + 2, c + 2, 2)); /* TS B: no RS */
    ks[3] = GG_LPE_O;
    assert_false(run(d, ks, c, 4)); /* ...O */
    /* a failed event leads to the dead state, which stays dead */
    assert_int_equal(gg_lpe_step(d, d->start, GG_LPE_B, none), 0);
    assert_int_equal(gg_lpe_step(d, 0, GG_LPE_RS, sf), 0);
    ggPathLayersFree(l);

    /* labels: objects, materials, lights, 'tir' */
    l = compile("C<RS'2''tir'><T.'m1'><RD><L'0'>");
    d = &l->layer[0];
    assert_int_equal(d->nnum, 2); /* 2 and 0 */
    assert_int_equal(d->nmat, 1);
    ks[0] = GG_LPE_RS_TIR, ks[1] = GG_LPE_TS, ks[2] = GG_LPE_RD, ks[3] = GG_LPE_L;
    c[0] = gg_lpe_surface(d, 2, 5), c[1] = gg_lpe_surface(d, 7, 1), c[2] = gg_lpe_surface(d, 9, 9);
    c[3] = gg_lpe_light(d, 0);
    assert_true(run(d, ks, c, 4));
    c[3] = gg_lpe_light(d, 1); /* another light */
    assert_false(run(d, ks, c, 4));
    c[3] = gg_lpe_light(d, 0), c[1] = gg_lpe_surface(d, 7, 2); /* another material */
    assert_false(run(d, ks, c, 4));
    c[1] = gg_lpe_surface(d, 7, 1), c[0] = gg_lpe_surface(d, 3, 5); /* another object */
    assert_false(run(d, ks, c, 4));
    c[0] = gg_lpe_surface(d, 2, 5), ks[0] = GG_LPE_RS; /* no tir */
    assert_false(run(d, ks, c, 4));
    ggPathLayersFree(l);
}

static void test_layers_refused(void **state)
{
    const char *two[2] = {"C.*", "C<TS>[object == 2]B"};
    const char *bad[1] = {"C<X>"};
    ggPathLayers *l = (ggPathLayers *)&l;
    ggError e;
    (void)state;
    assert_int_equal(ggPathLayersCompile(two, 2, NULL, &l, &e), GG_ERROR_UNSUPPORTED);
    assert_null(l);
    assert_non_null(strstr(e.message, "layer 2: 1:6: "));
    assert_int_equal(ggPathLayersCompile(bad, 1, NULL, &l, &e), GG_ERROR_PARSE);
    assert_non_null(strstr(e.message, "layer 1: 1:3: "));
    assert_int_equal(ggPathLayersCompile(bad, 0, NULL, &l, &e), GG_ERROR_INVALID);
    assert_int_equal(ggPathLayersCompile(bad, GG_PATH_LAYERS_MAX + 1, NULL, &l, &e),
                     GG_ERROR_INVALID);
    two[0] = "C('0'|'1'|'2'|'3'|'4'|'5'|'6'|'7'|'8')B";
    assert_int_equal(ggPathLayersCompile(two, 1, NULL, &l, &e), GG_ERROR_LIMIT);
    /* the ninth label's quote */
    assert_string_equal(e.message, "layer 1: 1:35: more than 8 distinct numbers or materials");
    /* places on the line ggPathParse would name */
    two[0] = "C\n<TS>[object == 2]B";
    assert_int_equal(ggPathLayersCompile(two, 1, NULL, &l, &e), GG_ERROR_UNSUPPORTED);
    assert_non_null(strstr(e.message, "layer 1: 2:5: "));
    two[0] = "C<RD'm1'> <RD'm2'> <RD'm3'> <RD'm4'> <RD'm5'>\n  <RD'm6'> <RD'm7'> <RD'm8'><RD'm9'>L";
    assert_int_equal(ggPathLayersCompile(two, 1, NULL, &l, &e), GG_ERROR_LIMIT);
    assert_string_equal(e.message, "layer 1: 2:32: more than 8 distinct numbers or materials");
}

/* One scene with these options: each layer's pixel against ggPathMatch's
   value of the traced pixel, within 2^-22 of the pixel's terms (float
   layers and pixel, double sums in two orders), and the image against a
   render without layers, bit for bit. */
static void match_scene(const char *path, ggRenderOptions o, const char *const *ex, int n)
{
    ggScene *s = tu_load(path);
    ggPathLayers *l = NULL;
    ggPathExpr *pe[8];
    ggTrace *t = ggTraceCreate(NULL);
    ggImage *plain, *img;
    float *map = calloc((size_t)o.width * o.height * 3, (size_t)n * sizeof(float));
    int x, y, k;
    long lit = 0;
    assert_int_equal(ggRender(s, &o, &plain, NULL, NULL), GG_OK);
    assert_int_equal(ggPathLayersCompile(ex, n, NULL, &l, NULL), GG_OK);
    for (k = 0; k < n; k++) assert_int_equal(ggPathParse(ex[k], NULL, &pe[k], NULL), GG_OK);
    o.layers = l, o.layer_map = map;
    assert_int_equal(ggRender(s, &o, &img, NULL, NULL), GG_OK);
    assert_memory_equal(ggImagePixelsConst(img), ggImagePixelsConst(plain),
                        (size_t)o.width * o.height * 3 * sizeof(float));
    o.layers = NULL, o.layer_map = NULL;
    for (y = 0; y < o.height; y++)
        for (x = 0; x < o.width; x++) {
            ggColor px;
            assert_int_equal(ggTracePixel(s, &o, x, y, -1, t, &px, NULL, NULL), GG_OK);
            for (k = 0; k < n; k++) {
                const float *v = map + 3 * (((size_t)k * o.height + y) * o.width + x);
                ggPathSummary sum;
                double tol;
                assert_int_equal(ggPathMatch(pe[k], t, x, y, px, NULL, NULL, &sum), GG_OK);
                lit += sum.matched > 0 && v[1] > 0;
                tol = 0x1p-22 * (fabs(px.r) + fabs(px.g) + fabs(px.b) + fabs(sum.value.r) +
                                 fabs(sum.value.g) + fabs(sum.value.b));
                if (fabs(v[0] - sum.value.r) > tol || fabs(v[1] - sum.value.g) > tol ||
                    fabs(v[2] - sum.value.b) > tol)
                    fail_msg("%s %s pixel %d,%d: layer %g %g %g, matcher %g %g %g", path, ex[k],
                             x, y, v[0], v[1], v[2], sum.value.r, sum.value.g, sum.value.b);
            }
        }
    assert_true(lit > o.width * o.height / 2); /* not a comparison of zeros */
    for (k = 0; k < n; k++) ggPathFree(pe[k]);
    ggPathLayersFree(l);
    ggImageFree(plain), ggImageFree(img);
    ggTraceFree(t);
    free(map);
    ggSceneFree(s);
}

static void test_layers_match(void **state)
{
    static const char *const ex[] = {
        "C<RD>L", "C<RS>+.*", "C.*<TS>.*", "CB", "C.*<RS'tir'>.*<RG>L", "C<.S'1'>*[BO]",
        "C.*<RD'm0'>A", "C[^T]*<L'0'>"};
    static const char *const scenes[] = {"examples/scenes/glass.nff", "examples/scenes/prism.nff",
                                         "examples/scenes/gold.nff", "tests/data/debug/absorb.nff"};
    ggRenderOptions o;
    size_t k;
    (void)state;
    ggRenderOptionsDefault(&o);
    o.width = 20, o.height = 15;
    for (k = 0; k < sizeof scenes / sizeof *scenes; k++) match_scene(scenes[k], o, ex, 8);
    /* four samples, then corners with the SPD rules */
    o.samples = 4;
    match_scene("examples/scenes/glass.nff", o, ex, 8);
    o.samples = 0, o.pixel_corners = o.spd_rules = true;
    match_scene("examples/scenes/glass.nff", o, ex, 8);
}

/* Each allocation failing in turn gives GG_ERROR_NOMEM, NULL, and no leak. */
static void test_layers_nomem(void **state)
{
    const char *ex[3] = {"C<RS>*<TS>[<RS><TS>]*(<RD>[LA]|<RG>L|O|B)", "C<RD'2'>L", "CB"};
    tu_failer f;
    long k, points = 0;
    (void)state;
    tu_failer_init(&f);
    for (k = 1;; k++) {
        ggPathLayers *l = (ggPathLayers *)&l;
        int rc;
        tu_failer_arm(&f, k);
        rc = ggPathLayersCompile(ex, 3, &f.alloc, &l, NULL);
        if (rc != GG_OK) {
            assert_int_equal(rc, GG_ERROR_NOMEM);
            assert_null(l);
        } else {
            assert_int_equal(ggPathLayersCount(l), 3);
            ggPathLayersFree(l);
        }
        assert_int_equal(f.live, 0);
        if (!f.failed) break;
        points++;
        assert_int_equal(rc, GG_ERROR_NOMEM); /* every failure is reported */
    }
    assert_true(points > 5);
    tu_failer_done(&f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_layers_stepping),
        cmocka_unit_test(test_layers_refused),
        cmocka_unit_test(test_layers_match),
        cmocka_unit_test(test_layers_nomem),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
