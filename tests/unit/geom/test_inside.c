/* SPDX-License-Identifier: MIT */
/*
** test_inside.c -- the gg_rayq.inside hint (gg_geom_inside_hit): for a
** ray starting inside an isolated sphere it answers exactly what the
** brute-force query answers (same primitive, same t to the bit), and it
** declines (-1) whenever the sphere has a neighbour inside or touching it,
** or the origin is outside; gg_geom_intersect with the hint answers what it
** answers without.
*/
#include "testutil.h"

#include "geom_int.h"

#include <math.h>

static ggVec3 V3(double x, double y, double z)
{
    ggVec3 v;
    v.x = x, v.y = y, v.z = z;
    return v;
}

/* A terrain-like sheet of triangles under three spheres: A and B close
   (a gap of 1e-6 r between them), C crossed by a triangle. */
static gg_geom *make_scene(int *a, int *b, int *c)
{
    gg_geom *g = gg_geom_create(NULL);
    int i, j;
    assert_non_null(g);
    for (i = 0; i < 20; i++)
        for (j = 0; j < 20; j++) {
            ggVec3 t[3];
            double x = -2 + 0.2 * i, y = -2 + 0.2 * j;
            t[0] = V3(x, y, 0.01 * ((i * 7 + j * 3) % 5));
            t[1] = V3(x + 0.2, y, 0.01 * ((i * 3 + j) % 5));
            t[2] = V3(x, y + 0.2, 0.02);
            assert_true(gg_geom_add_triangle(g, t, NULL, 0) >= 0);
        }
    *a = gg_geom_add_sphere(g, V3(0, 0, 1), 0.25, 1);
    *b = gg_geom_add_sphere(g, V3(0.5 + 0.25e-6, 0, 1), 0.25, 2);
    *c = gg_geom_add_sphere(g, V3(1, 1, 0.1), 0.2, 3);
    assert_true(*a >= 0 && *b >= 0 && *c >= 0);
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    return g;
}

static void check_rays(const gg_geom *g, int prim, ggVec3 c, double rad, int expect_fast)
{
    tu_rng r = {0x1234 + (uint64_t)prim};
    int k, fast = 0;
    for (k = 0; k < 20000; k++) {
        gg_rayq q;
        gg_hit h1, h2;
        int got, ref;
        /* Origins near the surface, some just outside it, as offset
           origins are. */
        double s = k % 4 == 0 ? 1 + 1e-12 : tu_range(&r, 0.0, 1.0);
        {
            ggVec3 u = tu_unit(&r);
            double f = s * rad;
            q.o = V3(c.x + f * u.x, c.y + f * u.y, c.z + f * u.z);
        }
        q.d = tu_unit(&r);
        q.tmin = 0, q.tmax = k % 8 == 1 ? 0.1 * rad : INFINITY;
        q.ignore_prim = UINT32_MAX, q.skip_flags = 0;
        q.inside = UINT32_MAX, q.opt = &gg_qopt_default;
        ref = gg_geom_intersect_brute(g, &q, &h2);
        q.inside = (uint32_t)prim;
        assert_int_equal(gg_geom_intersect(g, &q, &h1), ref);
        if (ref) assert_true(h1.prim == h2.prim && h1.t == h2.t && h1.sub == h2.sub);
        got = gg_geom_inside_hit(g, &q, 0, &h1);
        if (got < 0) continue;
        fast++;
        assert_int_equal(got, 1);
        assert_int_equal(ref, 1);
        assert_int_equal(h1.prim, h2.prim);
        assert_true(h1.t == h2.t);
        assert_int_equal(h1.sub, h2.sub);
    }
    if (expect_fast)
        assert_true(fast > 10000);
    else
        assert_int_equal(fast, 0);
}

static void test_isolated_exact(void **state)
{
    int a, b, c;
    gg_geom *g = make_scene(&a, &b, &c);
    (void)state;
    check_rays(g, a, V3(0, 0, 1), 0.25, 1);
    check_rays(g, b, V3(0.5 + 0.25e-6, 0, 1), 0.25, 1);
    gg_geom_free(g);
}

static void test_declines(void **state)
{
    int a, b, c;
    gg_geom *g = make_scene(&a, &b, &c);
    gg_rayq q;
    gg_hit h;
    ggVec3 t[3];
    (void)state;
    /* C is cut by the sheet: never answered alone. */
    check_rays(g, c, V3(1, 1, 0.1), 0.2, 0);
    /* Origin outside A. */
    q.o = V3(0, 0, 1.3), q.d = V3(0, 0, -1), q.tmin = 0, q.tmax = INFINITY;
    q.ignore_prim = UINT32_MAX, q.skip_flags = 0;
    q.inside = (uint32_t)a, q.opt = &gg_qopt_default;
    assert_int_equal(gg_geom_inside_hit(g, &q, 0, &h), -1);
    /* Not a sphere. */
    q.o = V3(0, 0, 1);
    q.inside = 0;
    assert_int_equal(gg_geom_inside_hit(g, &q, 0, &h), -1);
    /* A ignored, or skipped by its flags. */
    q.inside = (uint32_t)a;
    assert_int_equal(gg_geom_inside_hit(g, &q, 0, &h), 1);
    gg_geom_set_flags(g, a, GG_PRIM_TRANSPARENT);
    assert_int_equal(gg_geom_inside_hit(g, &q, GG_PRIM_TRANSPARENT, &h), -1);
    q.ignore_prim = (uint32_t)a;
    assert_int_equal(gg_geom_inside_hit(g, &q, 0, &h), -1);
    gg_geom_free(g);
    /* A triangle added inside A: A no longer isolated after the rebuild. */
    g = make_scene(&a, &b, &c);
    t[0] = V3(0, 0, 1), t[1] = V3(0.05, 0, 1), t[2] = V3(0, 0.05, 1.01);
    assert_true(gg_geom_add_triangle(g, t, NULL, 4) >= 0);
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    check_rays(g, a, V3(0, 0, 1), 0.25, 0);
    gg_geom_free(g);
}

/* Two spheres that overlap: neither is isolated. */
static void test_overlap(void **state)
{
    gg_geom *g = gg_geom_create(NULL);
    int a, b;
    (void)state;
    assert_non_null(g);
    a = gg_geom_add_sphere(g, V3(0, 0, 0), 1, 0);
    b = gg_geom_add_sphere(g, V3(1.99, 0, 0), 1, 1);
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    check_rays(g, a, V3(0, 0, 0), 1, 0);
    check_rays(g, b, V3(1.99, 0, 0), 1, 0);
    gg_geom_free(g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_isolated_exact),
        cmocka_unit_test(test_declines),
        cmocka_unit_test(test_overlap),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
