/* SPDX-License-Identifier: MIT */
/*
** test_kernels.c -- the counting copy of the AVX traversal and the kernel
** loops behind `ggrt bench limit` (ggRenderCountKernels, ggKernelLoop;
** bvh_avx.c built with GG_TRAV_COUNT and GG_TRAV_KLOOP): the counting copy
** answers every query as the scene's own copy does, counts what it is
** asked and what it tests (exact counts where they are known: one node
** test for a ray that misses the root, one closest query per query, the
** hits the render shades), and puts the scene's copy back; the loops run
** only on data the scene has. TAP skips where the scene's queries take
** the plain traversal (no AVX: no counting copy).
*/
#include "testutil.h"

#include "geom.h"
#include "geom_int.h"
#include "scene.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* A matte scene (no secondary rays) of 2 * 12 * 12 triangles, three
   spheres and a cylinder, with two lights. */
static ggScene *make_scene(void)
{
    static char text[65536];
    size_t n = 0;
    int i, j;
    ggScene *s = ggSceneCreate(NULL);
    n += (size_t)snprintf(text + n, sizeof text - n,
                          "v\nfrom 0 -6 8\nat 0 0 0\nup 0 0 1\nangle 45\nhither 0.01\n"
                          "resolution 48 48\nb 0.1 0.1 0.1\nl 4 -4 9\nl -5 -3 6\n"
                          "f 0.8 0.6 0.4 0.9 0 0 0 1\n");
    for (i = 0; i < 12; i++)
        for (j = 0; j < 12; j++) {
            double x = -3 + 0.5 * i, y = -3 + 0.5 * j, z = 0.05 * ((i * 7 + j * 3) % 5);
            n += (size_t)snprintf(text + n, sizeof text - n,
                                  "p 3\n%g %g %g\n%g %g %g\n%g %g %g\n"
                                  "p 3\n%g %g %g\n%g %g %g\n%g %g %g\n",
                                  x, y, z, x + 0.5, y, z, x, y + 0.5, z, x + 0.5, y, z, x + 0.5,
                                  y + 0.5, z, x, y + 0.5, z);
        }
    n += (size_t)snprintf(text + n, sizeof text - n,
                          "s 0 0 1 0.7\ns 1.5 1 0.8 0.5\ns -1.6 0.5 0.6 0.4\n"
                          "c\n1.5 -1.5 0 0.3\n1.5 -1.5 1.5 0.3\n");
    assert_non_null(s);
    assert_int_equal(ggSceneLoadString(s, text, n, "kernels", NULL), GG_OK);
    assert_int_equal(ggScenePrepare(s, NULL), GG_OK);
    return s;
}

/* Whether the scene's queries take an AVX copy (else a TAP skip). */
static int has_counting(ggScene *s)
{
    gg_kcount kc;
    if (gg_geom_count_begin(s->geom, &kc)) {
        print_message("the scene's queries take the plain traversal; skipped\n");
        return 0;
    }
    gg_geom_count_end(s->geom);
    return 1;
}

static ggVec3 V3(double x, double y, double z)
{
    ggVec3 v;
    v.x = x, v.y = y, v.z = z;
    return v;
}

/* Closest and any hit of random rays from around the scene, and a packet
   of eye rays: the same answers from both copies; the counting copy
   counts one query per query and one hit per hit. */
static void test_same_answers(void **state)
{
    ggScene *s = make_scene();
    gg_geom *g;
    gg_kcount kc;
    tu_rng rng;
    int i, own, nhit = 0;
    (void)state;
    if (!has_counting(s)) {
        ggSceneFree(s);
        skip();
    }
    g = s->geom;
    own = g->trav_avx;
    rng.s = 35;
    memset(&kc, 0, sizeof kc);
    for (i = 0; i < 2000; i++) {
        ggVec3 o = V3(tu_uniform(&rng) * 8 - 4, tu_uniform(&rng) * 8 - 4, tu_uniform(&rng) * 4);
        gg_rayq q = gg_rayq_make(o, tu_unit(&rng), 0, i % 3 ? INFINITY : 2.0, NULL);
        gg_hit a, b;
        uint32_t ca = 0, cb = 0;
        int ha = gg_geom_intersect(g, &q, &a), oa = gg_geom_occluded(g, &q, &ca, NULL), hb, ob;
        assert_int_equal(gg_geom_count_begin(g, &kc), 0);
        hb = gg_geom_intersect(g, &q, &b);
        ob = gg_geom_occluded(g, &q, &cb, NULL);
        gg_geom_count_end(g);
        assert_int_equal(g->trav_avx, own);
        assert_int_equal(ha, hb);
        assert_int_equal(oa, ob);
        assert_int_equal(ca, cb);
        if (ha) {
            nhit++;
            assert_true(a.t == b.t && a.prim == b.prim && a.sub == b.sub);
            assert_true(a.b1 == b.b1 && a.b2 == b.b2);
        }
    }
    assert_true(nhit > 200);
    assert_true(kc.closest == 2000 && kc.any == 2000 && kc.hits == (uint64_t)nhit);
    assert_true(kc.box8 >= 2000 && kc.tri4 > 0 && kc.sphere > 0 && kc.other > 0);
    assert_true(kc.packets == 0 && kc.pbox4 == 0 && kc.plane == 0);
    {
        /* a row of 16 eye rays, one packet walk */
        gg_rayq q[GG_PACKET_MAX];
        gg_hit ha[GG_PACKET_MAX], hb[GG_PACKET_MAX];
        unsigned ma, mb;
        for (i = 0; i < GG_PACKET_MAX; i++)
            q[i] = gg_rayq_make(V3(0, -6, 8), V3(0.02 + 0.03 * i, 0.6, -0.74), 0, INFINITY, NULL);
        ma = gg_geom_intersect_packet(g, q, 0xffff, ha);
        memset(&kc, 0, sizeof kc);
        assert_int_equal(gg_geom_count_begin(g, &kc), 0);
        mb = gg_geom_intersect_packet(g, q, 0xffff, hb);
        gg_geom_count_end(g);
        assert_int_equal(ma, mb);
        for (i = 0; i < GG_PACKET_MAX; i++)
            if (ma >> i & 1) assert_true(ha[i].t == hb[i].t && ha[i].prim == hb[i].prim);
        assert_true(kc.packets == 1 && kc.pbox4 > 0 && kc.plane > 0);
        assert_int_equal(kc.hits, (uint64_t)__builtin_popcount(ma));
    }
    ggSceneFree(s);
}

/* A ray that misses the root's boxes: one node test, nothing else. */
static void test_miss_counts_one_node(void **state)
{
    ggScene *s = make_scene();
    gg_kcount kc;
    gg_rayq q = gg_rayq_make(V3(0, 0, 20), V3(0, 0, 1), 0, INFINITY, NULL);
    gg_hit h;
    (void)state;
    if (!has_counting(s)) {
        ggSceneFree(s);
        skip();
    }
    memset(&kc, 0, sizeof kc);
    assert_int_equal(gg_geom_count_begin(s->geom, &kc), 0);
    assert_int_equal(gg_geom_count_begin(s->geom, &kc), -1); /* not twice */
    assert_false(gg_geom_intersect(s->geom, &q, &h));
    gg_geom_count_end(s->geom);
    assert_true(kc.closest == 1 && kc.box8 == 1 && kc.hits == 0);
    assert_true(kc.tri4 + kc.tri + kc.sphere + kc.other == 0);
    ggSceneFree(s);
}

/* The counted render: the hits it counts are the eye rays' hits (a matte
   scene shades nothing else), the same twice, and the scene renders the
   same image after it. */
static void test_render_counts(void **state)
{
    ggScene *s = make_scene();
    ggRenderOptions o;
    ggKernelCounts c1, c2;
    ggRayStats st;
    ggImage *a = NULL, *b = NULL;
    (void)state;
    if (!has_counting(s)) {
        ggSceneFree(s);
        skip();
    }
    ggRenderOptionsDefault(&o);
    o.threads = 2;
    assert_int_equal(ggRender(s, &o, &a, &st, NULL), GG_OK);
    assert_int_equal(ggRenderCountKernels(s, &o, &c1, NULL), GG_OK);
    assert_int_equal(ggRenderCountKernels(s, &o, &c2, NULL), GG_OK);
    assert_memory_equal(&c1, &c2, sizeof c1);
    assert_true(st.eye_hit > 0 && st.shadow > 0);
    assert_int_equal(c1.hits, st.eye_hit);
    assert_true(c1.packets > 0 && c1.node > 0 && c1.any > 0);
    assert_int_equal(ggRender(s, &o, &b, NULL, NULL), GG_OK);
    {
        ggImageDiff d;
        assert_int_equal(ggImageCompare(a, b, GG_COMPARE_LINEAR, &d), GG_OK);
        assert_true(d.max_abs == 0 && d.nan_channels == 0);
    }
    o.accuracy.intersect = GG_ACC_ISECT_FLOAT;
    assert_int_equal(ggRenderCountKernels(s, &o, &c1, NULL), GG_ERROR_UNSUPPORTED);
    ggImageFree(a);
    ggImageFree(b);
    ggSceneFree(s);
}

/* The loops run on the scene's data, and only where it has some. */
static void test_kernel_loops(void **state)
{
    ggScene *s = make_scene(), *t = ggSceneCreate(NULL);
    const char tri_only[] = "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 0.1\n"
                            "resolution 8 8\nl 0 0 5\nf 1 1 1 1 0 0 0 1\n"
                            "p 3\n-1 -1 0\n1 -1 0\n0 1 0\np 3\n-1 1 0\n1 1 0\n0 -1 0.1\n";
    int k;
    (void)state;
    if (!has_counting(s)) {
        ggSceneFree(s);
        ggSceneFree(t);
        skip();
    }
    assert_true(ggKernelLoop(t, NULL, GG_KERNEL_NODE, 10) < 0); /* not prepared */
    for (k = 0; k < GG_KERNEL_KINDS; k++)
        if (!(ggKernelLoop(s, NULL, k, 100) >= 0)) fail_msg("kernel %d: no loop", k);
    assert_int_equal(ggSceneLoadString(t, tri_only, sizeof tri_only - 1, "t", NULL), GG_OK);
    assert_int_equal(ggScenePrepare(t, NULL), GG_OK);
    assert_true(ggKernelLoop(t, NULL, GG_KERNEL_SPHERE, 10) < 0);
    assert_true(ggKernelLoop(t, NULL, GG_KERNEL_OTHER, 10) < 0);
    assert_true(ggKernelLoop(t, NULL, GG_KERNEL_TRI, 10) >= 0);
    /* aimed at the element: the triangle test finds it every time */
    assert_true(ggKernelLoop(t, NULL, GG_KERNEL_TRI, 10) >= 10);
    ggSceneFree(s);
    ggSceneFree(t);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_same_answers),
        cmocka_unit_test(test_miss_counts_one_node),
        cmocka_unit_test(test_render_counts),
        cmocka_unit_test(test_kernel_loops),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
