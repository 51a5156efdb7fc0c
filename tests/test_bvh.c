/*
** test_bvh.c -- the BVH answers exactly what testing every primitive
** answers: same primitive, same t to the bit, same occlusion, on random
** scenes of every shape kind and on the SPD scenes.
*/
#include "testutil.h"

#include "geom_int.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef GG_TEST_SUITE
#define GG_TEST_SUITE "bvh"
#endif

static ggVec3 rvec(tu_rng *r, double lo, double hi)
{
    ggVec3 v;
    v.x = tu_range(r, lo, hi), v.y = tu_range(r, lo, hi), v.z = tu_range(r, lo, hi);
    return v;
}

static ggVec3 vadd(ggVec3 a, ggVec3 b)
{
    a.x += b.x, a.y += b.y, a.z += b.z;
    return a;
}

static ggVec3 vscale(ggVec3 a, double s)
{
    a.x *= s, a.y *= s, a.z *= s;
    return a;
}

/* A star-shaped concave polygon with k points in a random plane. */
static int add_star(gg_geom *g, tu_rng *r, ggVec3 c, double size, int k)
{
    ggVec3 v[64], a = tu_unit(r), b = tu_unit(r), u, w;
    double la;
    int i;
    /* u, w: orthonormal pair spanning the plane of a and b */
    u = a;
    la = a.x * b.x + a.y * b.y + a.z * b.z;
    w = vadd(b, vscale(a, -la));
    w = vscale(w, 1 / sqrt(w.x * w.x + w.y * w.y + w.z * w.z));
    for (i = 0; i < 2 * k; i++) {
        double ang = GG_PI * i / k, rad = (i & 1 ? 0.4 : 1.0) * size;
        v[i] = vadd(c, vadd(vscale(u, rad * cos(ang)), vscale(w, rad * sin(ang))));
    }
    return gg_geom_add_polygon(g, v, 2 * k, 0);
}

/* n primitives of mixed kinds in [-10, 10]^3, sizes spread over two
   decades so that boxes overlap in every way. */
static gg_geom *random_scene(tu_rng *r, int n, int kinds)
{
    gg_geom *g = gg_geom_create(NULL);
    int i;
    assert_non_null(g);
    for (i = 0; i < n; i++) {
        ggVec3 c = rvec(r, -10, 10), p[3];
        double s = 0.05 * pow(10, tu_range(r, 0, 2)) * (20.0 / cbrt((double)n));
        int kind = (int)(tu_next(r) % (uint64_t)kinds), id = -1;
        switch (kind) {
        case 0: id = gg_geom_add_sphere(g, c, s * 0.5, i); break;
        case 1:
            p[0] = vadd(c, rvec(r, -s, s)), p[1] = vadd(c, rvec(r, -s, s));
            p[2] = vadd(c, rvec(r, -s, s));
            id = gg_geom_add_triangle(g, p, NULL, i);
            break;
        case 2:
            id = gg_geom_add_cone(g, c, s * tu_range(r, 0, 0.5), vadd(c, rvec(r, -s, s)),
                                  tu_uniform(r) < 0.3 ? 0.2 * s : s * tu_range(r, 0, 0.5), i);
            break;
        case 3: id = gg_geom_add_rect(g, c, rvec(r, -s, s), rvec(r, -s, s), i); break;
        default: id = add_star(g, r, c, s, 3 + (int)(tu_next(r) % 8)); break;
        }
        assert_true(id >= 0);
    }
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    return g;
}

/* Rays from inside and outside the scene, some axis-aligned (zero
   direction components), some starting exactly on a box plane. */
static void random_ray(tu_rng *r, gg_rayq *q)
{
    double u = tu_uniform(r);
    q->o = rvec(r, -14, 14);
    q->d = vscale(tu_unit(r), tu_range(r, 0.1, 3));
    if (u < 0.1) q->d.x = 0;
    if (u < 0.05) q->d.y = 0;
    if (u > 0.95) q->o.x = 10; /* on a plane of the scene box */
    q->tmin = 0;
    q->tmax = tu_uniform(r) < 0.2 ? tu_range(r, 0, 10) : INFINITY;
    q->ignore_prim = UINT32_MAX;
    q->skip_flags = 0;
}

static void compare(const gg_geom *g, const gg_rayq *q, long *nhit)
{
    gg_hit a, b;
    int fa = gg_geom_intersect(g, q, &a), fb = gg_geom_intersect_brute(g, q, &b);
    assert_int_equal(fa, fb);
    assert_int_equal(gg_geom_occluded(g, q), fb);
    if (fa) {
        if (a.prim != b.prim || a.t != b.t || a.sub != b.sub || a.b1 != b.b1) {
            print_error("bvh prim %u t %.17g, brute prim %u t %.17g\n", a.prim, a.t, b.prim, b.t);
            fail();
        }
        (*nhit)++;
    }
}

static void run_random(int n, int kinds, int rays, unsigned seed, long min_hits)
{
    tu_rng r = {seed};
    gg_geom *g = random_scene(&r, n, kinds);
    long nhit = 0;
    int i;
    for (i = 0; i < rays; i++) {
        gg_rayq q;
        random_ray(&r, &q);
        compare(g, &q, &nhit);
    }
    /* The scene must actually be hit often enough for the comparison to
       prove something. */
    assert_true(nhit >= min_hits);
    gg_geom_free(g);
}

static void test_random_mixed(void **state)
{
    (void)state;
    run_random(1000, 5, 100000, 1, 20000);
}

static void test_random_small_scenes(void **state)
{
    int n;
    (void)state;
    /* Root is a leaf, a node with empty lanes, a two-level tree... */
    for (n = 1; n <= 40; n++) run_random(n, 5, 500, 100 + (unsigned)n, n > 20 ? 5 : 0);
}

static void test_ignore_and_skip(void **state)
{
    tu_rng r = {7};
    gg_geom *g = random_scene(&r, 500, 5);
    int i, skipped = 0;
    (void)state;
    for (i = 0; i < 500; i += 3) gg_geom_set_flags(g, i, GG_PRIM_TRANSPARENT);
    for (i = 0; i < 20000; i++) {
        gg_rayq q;
        gg_hit a, b;
        int fa, fb;
        random_ray(&r, &q);
        q.skip_flags = i & 1 ? GG_PRIM_TRANSPARENT : 0;
        fa = gg_geom_intersect_brute(g, &q, &a);
        if (fa && (i & 2)) q.ignore_prim = a.prim; /* skip the first hit */
        fa = gg_geom_intersect(g, &q, &a);
        fb = gg_geom_intersect_brute(g, &q, &b);
        assert_int_equal(fa, fb);
        assert_int_equal(gg_geom_occluded(g, &q), fb);
        if (fa) {
            assert_int_equal(a.prim, b.prim);
            assert_true(a.t == b.t);
            assert_true(a.prim != q.ignore_prim);
            if (q.skip_flags) assert_true(a.prim % 3 != 0);
            skipped += q.ignore_prim != UINT32_MAX;
        }
    }
    assert_true(skipped > 100);
    gg_geom_free(g);
}

/* Many primitives with the same centroid (the SAH finds no split): the
   build must still terminate with small leaves and stay exact. */
static void test_coincident(void **state)
{
    gg_geom *g = gg_geom_create(NULL);
    tu_rng r = {3};
    ggVec3 c = {0, 0, 0};
    gg_bvh_stats st;
    long nhit = 0;
    int i;
    (void)state;
    for (i = 0; i < 1000; i++) assert_true(gg_geom_add_sphere(g, c, 1 + i * 1e-3, i) >= 0);
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    gg_geom_bvh_stats(g, &st);
    assert_true(st.max_depth < 80);
    assert_true(st.leaves >= 1000 / 4);
    for (i = 0; i < 2000; i++) {
        gg_rayq q;
        random_ray(&r, &q);
        if (i & 1) q.d = vscale(q.o, -tu_range(&r, 0.5, 2)); /* aimed at the cluster */
        compare(g, &q, &nhit);
    }
    assert_true(nhit > 500);
    gg_geom_free(g);
}

static void test_empty(void **state)
{
    gg_geom *g = gg_geom_create(NULL);
    gg_rayq q = {{0, 0, 0}, {1, 0, 0}, 0, INFINITY, UINT32_MAX, 0};
    gg_hit h;
    (void)state;
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    assert_int_equal(gg_geom_intersect(g, &q, &h), 0);
    assert_int_equal(gg_geom_occluded(g, &q), 0);
    gg_geom_free(g);
    gg_geom_free(NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_mixed),     cmocka_unit_test(test_random_small_scenes),
        cmocka_unit_test(test_ignore_and_skip),  cmocka_unit_test(test_coincident),
        cmocka_unit_test(test_empty),
    };
    return cmocka_run_group_tests_name(GG_TEST_SUITE, tests, NULL, NULL);
}
