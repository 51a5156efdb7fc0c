/* SPDX-License-Identifier: MIT */
/*
** test_frustum.c -- gg_geom_frustum_empty, the renderer's empty-tile test:
** whenever it calls a tile empty, no eye ray through that tile (pixel
** centres, pixel corners, random points inside pixels) hits anything;
** and it does call a good share of tetra's tiles empty (else it would
** save nothing).
*/
#include "testutil.h"

#include "geom_int.h"
#include "scene.h"

#include <stdio.h>

static int ray_hits(const ggScene *s, const ggRenderOptions *o, double x, double y)
{
    ggRay r = ggCameraRay(s, o, x, y);
    gg_rayq q;
    gg_hit h;
    q.o = r.o, q.d = r.d, q.tmin = 0, q.tmax = INFINITY;
    q.ignore_prim = UINT32_MAX, q.skip_flags = 0;
    q.inside = UINT32_MAX, q.opt = &gg_qopt_default;
    return gg_geom_intersect(s->geom, &q, &h);
}

/* Tiles of T x T pixels over a W x W image of the scene; returns the
   share of tiles called empty, after checking each empty one. */
static double check_scene(const char *name, int W, int T, long *rays)
{
    char path[512];
    ggScene *s = ggSceneCreate(NULL);
    ggRenderOptions o;
    ggError e;
    tu_rng r = {5};
    int x0, y0, nt = 0, ne = 0;
    snprintf(path, sizeof path, "%s/%s.nff", tu_spd_dir(), name);
    assert_non_null(s);
    assert_int_equal(ggSceneLoadFile(s, path, &e), GG_OK);
    assert_int_equal(ggScenePrepare(s, &e), GG_OK);
    ggRenderOptionsDefault(&o);
    o.width = o.height = W;
    for (y0 = 0; y0 < W; y0 += T)
        for (x0 = 0; x0 < W; x0 += T) {
            ggVec3 d[4];
            int x, y, k;
            d[0] = ggCameraRay(s, &o, x0, y0).d;
            d[1] = ggCameraRay(s, &o, x0 + T, y0).d;
            d[2] = ggCameraRay(s, &o, x0 + T, y0 + T).d;
            d[3] = ggCameraRay(s, &o, x0, y0 + T).d;
            nt++;
            if (!gg_geom_frustum_empty(s->geom, s->camera.from, d)) continue;
            ne++;
            for (y = y0; y <= y0 + T; y++)
                for (x = x0; x <= x0 + T; x++) {
                    /* the corner (x, y), and inside the tile's pixels the
                       centre and a random point */
                    assert_false(ray_hits(s, &o, x, y));
                    (*rays)++;
                    if (x == x0 + T || y == y0 + T) continue;
                    assert_false(ray_hits(s, &o, x + 0.5, y + 0.5));
                    assert_false(ray_hits(s, &o, x + tu_uniform(&r), y + tu_uniform(&r)));
                    for (k = 0; k < 2; k++) (*rays)++;
                }
        }
    ggSceneFree(s);
    printf("%s: %d of %d %dx%d tiles empty\n", name, ne, nt, T, T);
    return (double)ne / nt;
}

static void test_frustum_empty_tiles(void **state)
{
    long rays = 0;
    (void)state;
    assert_true(check_scene("tetra", 256, 8, &rays) > 0.4);
    assert_true(check_scene("tetra", 256, 16, &rays) > 0.3);
    assert_true(check_scene("mount", 256, 8, &rays) > 0.1);
    assert_true(check_scene("teapot-s12", 256, 8, &rays) > 0.1);
    assert_true(check_scene("tree", 256, 8, &rays) >= 0);
    /* every pixel of these shows something */
    assert_true(check_scene("balls-s4", 128, 8, &rays) == 0);
    assert_true(check_scene("rings", 128, 8, &rays) == 0);
    printf("%ld rays through empty tiles, none hit\n", rays);
}

/* Tiles around a lone small sphere, at scales 1e-6..1e6: a tile whose
   pyramid only grazes the sphere's box is not empty, one a pixel away
   from the box is. */
static void test_frustum_tight(void **state)
{
    static const double scales[] = {1e-6, 1.0, 1e6};
    int si;
    (void)state;
    for (si = 0; si < 3; si++) {
        double sc = scales[si];
        gg_geom *g = gg_geom_create(NULL);
        ggVec3 eye = v3(0, 0, -10 * sc), d[4];
        assert_true(gg_geom_add_sphere(g, v3(0, 0, 0), sc, 0) >= 0);
        assert_int_equal(gg_geom_build(g, NULL), GG_OK);
        /* the box spans x in [-sc, sc] at z in [-sc, sc]: from the eye,
           x/z slopes up to 1/9 */
        d[0] = v3(0.2, 0.2, 1), d[1] = v3(0.3, 0.2, 1), d[2] = v3(0.3, 0.3, 1),
        d[3] = v3(0.2, 0.3, 1);
        assert_int_equal(gg_geom_frustum_empty(g, eye, d), 1);
        d[0] = v3(1.0 / 9, 0, 1), d[1] = v3(0.3, 0, 1), d[2] = v3(0.3, 0.1, 1),
        d[3] = v3(1.0 / 9, 0.1, 1);
        assert_int_equal(gg_geom_frustum_empty(g, eye, d), 0);
        d[0] = v3(-0.05, -0.05, 1), d[1] = v3(0.05, -0.05, 1), d[2] = v3(0.05, 0.05, 1),
        d[3] = v3(-0.05, 0.05, 1);
        assert_int_equal(gg_geom_frustum_empty(g, eye, d), 0);
        /* looking away */
        d[0] = v3(-0.05, -0.05, -1), d[1] = v3(0.05, -0.05, -1), d[2] = v3(0.05, 0.05, -1),
        d[3] = v3(-0.05, 0.05, -1);
        assert_int_equal(gg_geom_frustum_empty(g, eye, d), 1);
        /* degenerate (NaN) directions: no claim */
        d[0].x = NAN;
        assert_int_equal(gg_geom_frustum_empty(g, eye, d), 0);
        gg_geom_free(g);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_frustum_empty_tiles),
        cmocka_unit_test(test_frustum_tight),
    };
    return cmocka_run_group_tests_name("frustum", tests, NULL, NULL);
}
