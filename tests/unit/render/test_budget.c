/* SPDX-License-Identifier: MIT */
/*
** test_budget.c -- the ray budget bounds the ray tree of every eye ray
** (ggRenderOptions.ray_budget): nested glass at depth 64, whose trees
** would grow to 2^63 rays, renders with at most the budget's rays per
** eye ray, says how many it left uncast, and marks where in the trace
** (GG_STOP_BUDGET); a larger budget is what lets more rays through; the
** traced pixel is still the rendered one, bit for bit.
*/
#include "testutil.h"

#include <string.h>

#define SCENE "tests/data/nested-glass.nff"

static ggScene *load(void)
{
    ggScene *s = ggSceneCreate(NULL);
    ggError e;
    assert_non_null(s);
    if (ggSceneLoadFile(s, SCENE, &e) != GG_OK) fail_msg("%s", e.message);
    assert_int_equal(ggScenePrepare(s, &e), GG_OK);
    return s;
}

static ggRayStats render(ggScene *s, int depth, int budget, ggImage **img)
{
    ggRenderOptions o;
    ggRayStats st;
    ggError e;
    ggImage *im = NULL;
    ggRenderOptionsDefault(&o);
    o.max_depth = depth, o.ray_budget = budget, o.threads = 2;
    if (ggRender(s, &o, &im, &st, &e) != GG_OK) fail_msg("%s", e.message);
    if (img)
        *img = im;
    else
        ggImageFree(im);
    return st;
}

/* At depth 12 a full tree has 4094 secondary rays: a budget of 64 holds
   every tree to 64, and one of GG_RAY_BUDGET_MAX lets them all through. */
static void test_bound(void **state)
{
    ggScene *s = load();
    ggRayStats small, big;
    (void)state;
    small = render(s, 12, 64, NULL);
    big = render(s, 12, GG_RAY_BUDGET_MAX, NULL);
    print_message("depth 12: budget 64: %llu secondary rays for %llu eye rays, %llu uncast; "
                  "budget %d: %llu, none uncast\n",
                  (unsigned long long)(small.reflect + small.refract),
                  (unsigned long long)small.eye, (unsigned long long)small.budget_cut,
                  GG_RAY_BUDGET_MAX, (unsigned long long)(big.reflect + big.refract));
    assert_true(small.reflect + small.refract <= 64 * small.eye_hit);
    assert_true(small.budget_cut > 0);
    assert_int_equal(big.budget_cut, 0);
    assert_true(big.reflect + big.refract > 8 * (small.reflect + small.refract));
    assert_int_equal(small.eye, big.eye);
    ggSceneFree(s);
}

/* Depth 64 with the default budget: bounded, and the budget acts. */
static void test_deep_default(void **state)
{
    ggScene *s = load();
    ggRayStats st;
    (void)state;
    st = render(s, 0, 0, NULL); /* the scene's depth 64, the default budget */
    print_message("depth 64: %llu secondary rays for %llu eye rays (budget %d), %llu uncast\n",
                  (unsigned long long)(st.reflect + st.refract), (unsigned long long)st.eye,
                  GG_RAY_BUDGET, (unsigned long long)st.budget_cut);
    assert_true(st.reflect + st.refract <= (uint64_t)GG_RAY_BUDGET * st.eye_hit);
    assert_true(st.budget_cut > 0);
    assert_true(st.max_depth > 12);
    ggSceneFree(s);
}

/* The recorder follows the same budget: the trace of a pixel at the
   centre holds at most budget + 1 rays, marks a budget stop, and its
   colour is the rendered pixel's. */
static void test_trace(void **state)
{
    ggScene *s = load();
    ggRenderOptions o;
    ggTrace *t = ggTraceCreate(NULL);
    ggImage *img;
    ggRayStats st;
    ggColor c;
    ggError e;
    size_t i, stops = 0;
    const float *px;
    (void)state;
    render(s, 0, 100, &img);
    ggRenderOptionsDefault(&o);
    o.ray_budget = 100;
    assert_int_equal(ggTracePixel(s, &o, 16, 12, -1, t, &c, &st, &e), GG_OK);
    for (i = 0; i < ggTraceNodeCount(t); i++) stops += ggTraceGetNode(t, i)->stop == GG_STOP_BUDGET;
    print_message("pixel 16,12: %zu rays recorded, %zu budget stops, %llu rays uncast\n",
                  ggTraceNodeCount(t), stops, (unsigned long long)st.budget_cut);
    assert_true(ggTraceNodeCount(t) <= 101);
    assert_true(stops > 0 && st.budget_cut > 0);
    assert_string_equal(ggStopName(GG_STOP_BUDGET), "budget");
    px = ggImagePixels(img) + 3 * (12 * (size_t)ggImageWidth(img) + 16);
    assert_true((float)c.r == px[0] && (float)c.g == px[1] && (float)c.b == px[2]);
    ggImageFree(img);
    ggTraceFree(t);
    ggSceneFree(s);
}

static void test_invalid(void **state)
{
    ggScene *s = load();
    ggRenderOptions o;
    ggImage *img = NULL;
    ggError e;
    (void)state;
    ggRenderOptionsDefault(&o);
    o.ray_budget = -1;
    assert_int_equal(ggRender(s, &o, &img, NULL, &e), GG_ERROR_INVALID);
    assert_non_null(strstr(e.message, "ray budget"));
    o.ray_budget = GG_RAY_BUDGET_MAX + 1;
    assert_int_equal(ggRender(s, &o, &img, NULL, &e), GG_ERROR_INVALID);
    assert_null(img);
    ggSceneFree(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bound),
        cmocka_unit_test(test_trace),
        cmocka_unit_test(test_invalid),
        cmocka_unit_test(test_deep_default),
    };
    return cmocka_run_group_tests_name("budget", tests, NULL, NULL);
}
