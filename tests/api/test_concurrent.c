/* SPDX-License-Identifier: MIT */
/*
** test_concurrent.c -- rendering reads the scene and never writes it:
** prepared scenes rendered, traced and queried from several threads at
** once, each call with options of its own (accuracy knobs that the
** geometry answers by among them), give exactly the images, pixels and
** ray counts of the same calls made one after another; two threads
** rendering one unprepared scene prepare it once; a render's accuracy
** knobs leave the scene's own settings as they were. make check runs this
** suite under ThreadSanitizer as well (tests/run-tests.sh, build/tsan).
*/
#include "testutil.h"

#include "implicit.h"
#include "scene.h"

#include <pthread.h>
#include <stdio.h>
#include <string.h>

static const char *const scenes[] = {
    "examples/scenes/glass.nff", "examples/scenes/torus.nff", "examples/scenes/prism.nff",
    "examples/scenes/texture.nff", "examples/scenes/acc-distant.nff",
};
#define NSCENE ((int)(sizeof scenes / sizeof scenes[0]))
#define NOPT   10
#define NJOB   (NSCENE * NOPT)
#define NTHR   4

/* Option set k: every choice that could be shared by mistake differs
   from its neighbours' (the geometry's among them: sphere mode, implicit
   tolerance, gradient step). */
static ggRenderOptions options(int k)
{
    ggRenderOptions o;
    ggRenderOptionsDefault(&o);
    o.width = 40, o.height = 30;
    o.threads = 1 + k % 2;
    switch (k) {
    case 1: o.accuracy.sphere = GG_ACC_SPHERE_TEXTBOOK; break;
    case 2: o.accuracy.implicit_tol = 1e-3, o.accuracy.gradient_h = 1e-2; break;
    case 3: o.max_depth = 2, o.samples = 4, o.accuracy.intersect = GG_ACC_ISECT_FLOAT; break;
    case 4: o.spd_rules = o.pixel_corners = true; break;
    case 5: o.accuracy.offset = GG_ACC_OFFSET_FIXED, o.accuracy.offset_eps = 1e-4; break;
    case 6: o.accuracy.refract = GG_ACC_REFRACT_TEXTBOOK, o.accuracy.wavelengths = 1; break;
    case 7: o.accuracy.fresnel = GG_ACC_FRESNEL_SCHLICK, o.accuracy.texture = 2; break;
    case 8: o.ray_budget = 3, o.crop_x0 = 5, o.crop_y0 = 4, o.crop_x1 = 33, o.crop_y1 = 25; break;
    case 9: o.accuracy.cutoff = 0.05, o.force_effects = GG_EFFECT_ALL; break;
    default: break;
    }
    return o;
}

/* What one job computes: the image, its stats, one traced pixel and the
   colour of one ray (ggRayColor), with their stats. */
typedef struct result {
    ggImage *img;
    ggRayStats st, tst, cst;
    ggColor traced, ray;
    size_t nodes;
    int rc;
} result;

static ggScene *shared[NSCENE];
static result seq[NJOB], par[NJOB];

static void run_job(int j, result *out)
{
    ggScene *s = shared[j / NOPT];
    ggRenderOptions o = options(j % NOPT);
    ggTrace *t = ggTraceCreate(NULL);
    ggError e;
    ggRay ray = ggCameraRay(s, &o, 21.5, 13.5);
    memset(out, 0, sizeof *out);
    out->rc = t ? ggRender(s, &o, &out->img, &out->st, &e) : GG_ERROR_NOMEM;
    if (out->rc == GG_OK) out->rc = ggTracePixel(s, &o, 21, 13, -1, t, &out->traced, &out->tst, &e);
    out->nodes = ggTraceNodeCount(t);
    out->ray = ggRayColor(s, &o, ray, 1, &out->cst);
    ggTraceFree(t);
}

static int same_stats(const ggRayStats *a, const ggRayStats *b)
{
    return memcmp(a, b, sizeof *a) == 0;
}

static int same_image(const ggImage *a, const ggImage *b)
{
    size_t n = (size_t)ggImageWidth(a) * ggImageHeight(a) * 3;
    return a && b && ggImageWidth(a) == ggImageWidth(b) && ggImageHeight(a) == ggImageHeight(b) &&
           memcmp(ggImagePixelsConst(a), ggImagePixelsConst(b), n * sizeof(float)) == 0;
}

static int same_result(const result *a, const result *b)
{
    return a->rc == GG_OK && b->rc == GG_OK && same_image(a->img, b->img) &&
           same_stats(&a->st, &b->st) && same_stats(&a->tst, &b->tst) &&
           same_stats(&a->cst, &b->cst) && a->nodes == b->nodes &&
           memcmp(&a->traced, &b->traced, sizeof a->traced) == 0 &&
           memcmp(&a->ray, &b->ray, sizeof a->ray) == 0;
}

/* The workers take jobs from a shared counter, in an order that mixes
   scenes and options, so calls with different options overlap on each
   scene. */
static pthread_mutex_t next_mu = PTHREAD_MUTEX_INITIALIZER;
static int next_job;

static void *worker(void *arg)
{
    (void)arg;
    for (;;) {
        int k, j;
        pthread_mutex_lock(&next_mu);
        k = next_job++;
        pthread_mutex_unlock(&next_mu);
        if (k >= NJOB) return NULL;
        j = (k * 7) % NJOB; /* 7 is prime to NJOB = 50 */
        run_job(j, &par[j]);
    }
}

static void test_concurrent_equals_sequential(void **state)
{
    pthread_t th[NTHR];
    int i, j, bad = 0;
    ggError e;
    (void)state;
    for (i = 0; i < NSCENE; i++) {
        shared[i] = ggSceneCreate(NULL);
        assert_non_null(shared[i]);
        if (ggSceneLoadFile(shared[i], scenes[i], &e) != GG_OK) fail_msg("%s", e.message);
        assert_int_equal(ggScenePrepare(shared[i], &e), GG_OK);
    }
    for (j = 0; j < NJOB; j++) run_job(j, &seq[j]);
    next_job = 0;
    for (i = 0; i < NTHR; i++) assert_int_equal(pthread_create(&th[i], NULL, worker, NULL), 0);
    for (i = 0; i < NTHR; i++) pthread_join(th[i], NULL);
    for (j = 0; j < NJOB; j++) {
        if (!same_result(&seq[j], &par[j])) {
            print_error("%s, option set %d: concurrent result differs\n", scenes[j / NOPT],
                        j % NOPT);
            bad++;
        }
    }
    /* The knobs the geometry answers by do change these images (so a
       render that took another's would be seen): the textbook sphere on
       the distant sphere, the implicit tolerance and normal step on the
       torus. */
    assert_false(same_image(seq[4 * NOPT + 1].img, seq[4 * NOPT].img));
    assert_false(same_image(seq[1 * NOPT + 2].img, seq[1 * NOPT].img));
    print_message("%d jobs (%d scenes x %d option sets: render, trace, ray colour) on %d threads: "
                  "%d differ from the sequential run\n",
                  NJOB, NSCENE, NOPT, NTHR, bad);
    assert_int_equal(bad, 0);
    for (j = 0; j < NJOB; j++) ggImageFree(seq[j].img), ggImageFree(par[j].img);
    for (i = 0; i < NSCENE; i++) ggSceneFree(shared[i]);
}

/* Two threads render one unprepared scene at once, with different
   options: it is prepared once, and each image is the one a prepared
   copy gives. */
typedef struct unprep {
    ggScene *s;
    ggRenderOptions o;
    ggImage *img;
    int rc;
} unprep;

static void *render_unprepared(void *arg)
{
    unprep *u = arg;
    ggError e;
    u->rc = ggRender(u->s, &u->o, &u->img, NULL, &e);
    return NULL;
}

static void test_unprepared(void **state)
{
    ggScene *s = ggSceneCreate(NULL), *ref = ggSceneCreate(NULL);
    unprep u[2];
    pthread_t th[2];
    ggError e;
    int i;
    (void)state;
    assert_int_equal(ggSceneLoadFile(s, "examples/scenes/torus.nff", &e), GG_OK);
    assert_int_equal(ggSceneLoadFile(ref, "examples/scenes/torus.nff", &e), GG_OK);
    for (i = 0; i < 2; i++) {
        u[i].s = s, u[i].o = options(2 * i), u[i].img = NULL;
        assert_int_equal(pthread_create(&th[i], NULL, render_unprepared, &u[i]), 0);
    }
    for (i = 0; i < 2; i++) pthread_join(th[i], NULL);
    for (i = 0; i < 2; i++) {
        ggImage *img = NULL;
        ggRenderOptions o = options(2 * i);
        assert_int_equal(u[i].rc, GG_OK);
        assert_int_equal(ggRender(ref, &o, &img, NULL, &e), GG_OK);
        assert_true(same_image(u[i].img, img));
        ggImageFree(img), ggImageFree(u[i].img);
    }
    ggSceneFree(s), ggSceneFree(ref);
}

/* A render's accuracy knobs stay with the render: a tolerance and a
   normal step set on the surface itself are there after a render that
   overrode them, and the next default render equals the first. */
static void test_knobs_stay_with_the_render(void **state)
{
    ggScene *s = ggSceneCreate(NULL);
    ggImplicit *imp = NULL;
    ggRenderOptions o;
    ggImage *a = NULL, *b = NULL, *c = NULL;
    ggMaterial m;
    ggCamera cam;
    ggError e;
    int mi;
    (void)state;
    memset(&cam, 0, sizeof cam);
    cam.from.y = -4, cam.up.z = 1, cam.fov_deg = 40, cam.width = 32, cam.height = 24;
    ggSceneSetCamera(s, &cam);
    m = ggMaterialDefault();
    mi = ggSceneAddMaterial(s, &m);
    assert_int_equal(ggImplicitCreateExpr("x^2 + y^2 + z^2 - 1", (ggVec3){-1.5, -1.5, -1.5},
                                          (ggVec3){1.5, 1.5, 1.5}, NULL, &imp, &e),
                     GG_OK);
    assert_int_equal(ggImplicitSetTolerance(imp, 1e-4), GG_OK);
    assert_int_equal(ggImplicitSetNormalStep(imp, 1e-3), GG_OK);
    assert_true(ggSceneAddImplicit(s, mi, imp) >= 0);
    assert_true(ggSceneAddLight(s, (ggVec3){3, -3, 3}, (ggColor){1, 1, 1}) >= 0);
    ggRenderOptionsDefault(&o);
    assert_int_equal(ggRender(s, &o, &a, NULL, &e), GG_OK);
    o.accuracy.implicit_tol = 1e-9, o.accuracy.gradient_h = 1e-6;
    o.accuracy.sphere = GG_ACC_SPHERE_TEXTBOOK;
    assert_int_equal(ggRender(s, &o, &b, NULL, &e), GG_OK);
    assert_true(gg_implicit_tolerance(imp) == 1e-4);
    ggRenderOptionsDefault(&o);
    assert_int_equal(ggRender(s, &o, &c, NULL, &e), GG_OK);
    assert_true(same_image(a, c));
    assert_false(same_image(a, b)); /* the knobs did reach the second render */
    ggImageFree(a), ggImageFree(b), ggImageFree(c);
    ggSceneFree(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_concurrent_equals_sequential),
        cmocka_unit_test(test_unprepared),
        cmocka_unit_test(test_knobs_stay_with_the_render),
    };
    return cmocka_run_group_tests_name("concurrent", tests, NULL, NULL);
}
