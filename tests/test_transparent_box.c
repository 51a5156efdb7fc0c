/* SPDX-License-Identifier: MIT */
/*
** test_transparent_box.c -- the coloured-shadow shortcuts:
** gg_geom_transparent_may_hit never says "no" for a segment that the exact
** query finds a transparent primitive on, and does say "no" for most
** segments far from them (else it would save nothing); gg_geom_shadow_query
** answers exactly what gg_geom_occluded (transparent skipped) and
** gg_geom_intersect answer, bit for bit.
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

static ggVec3 rvec(tu_rng *r, double lo, double hi)
{
    return V3(tu_range(r, lo, hi), tu_range(r, lo, hi), tu_range(r, lo, hi));
}

/* A scene of opaque clutter and a few transparent spheres and triangles
   in a corner, at coordinate scale `sc`. */
static gg_geom *make_scene(tu_rng *r, double sc)
{
    gg_geom *g = gg_geom_create(NULL);
    int i, p;
    assert_non_null(g);
    for (i = 0; i < 200; i++) {
        ggVec3 t[3];
        t[0] = rvec(r, -sc, sc);
        t[1] = V3(t[0].x + 0.1 * sc, t[0].y, t[0].z);
        t[2] = V3(t[0].x, t[0].y + 0.1 * sc, t[0].z + 0.05 * sc);
        assert_true(gg_geom_add_triangle(g, t, NULL, 0) >= 0);
    }
    for (i = 0; i < 4; i++) {
        p = gg_geom_add_sphere(g, rvec(r, 0.2 * sc, 0.4 * sc), 0.05 * sc, 1);
        assert_true(p >= 0);
        gg_geom_set_flags(g, p, GG_PRIM_TRANSPARENT);
    }
    for (i = 0; i < 4; i++) {
        ggVec3 t[3];
        t[0] = rvec(r, 0.2 * sc, 0.4 * sc);
        t[1] = V3(t[0].x - 0.05 * sc, t[0].y + 0.03 * sc, t[0].z);
        t[2] = V3(t[0].x, t[0].y, t[0].z + 0.04 * sc);
        p = gg_geom_add_triangle(g, t, NULL, 1);
        assert_true(p >= 0);
        gg_geom_set_flags(g, p, GG_PRIM_TRANSPARENT);
    }
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    return g;
}

/* Whether the segment hits a transparent primitive: step through its
   hits, nearest first, with the exact query. */
static int hits_transparent(const gg_geom *g, ggVec3 o, ggVec3 d)
{
    gg_rayq q;
    gg_hit h;
    q.o = o, q.d = d, q.tmin = 0, q.tmax = 1, q.ignore_prim = UINT32_MAX, q.skip_flags = 0;
    while (gg_geom_intersect(g, &q, &h)) {
        if (g->pflags[h.prim] & GG_PRIM_TRANSPARENT) return 1;
        q.tmin = h.t;
        if (!(q.tmin < q.tmax)) break;
    }
    return 0;
}

static void test_never_misses(void **state)
{
    static const double scales[] = {1e-6, 1.0, 1e6};
    int si;
    (void)state;
    for (si = 0; si < 3; si++) {
        double sc = scales[si];
        tu_rng r = {11 + (uint64_t)si};
        gg_geom *g = make_scene(&r, sc);
        long i, nhit = 0, nno = 0, n = 20000;
        for (i = 0; i < n; i++) {
            ggVec3 o = rvec(&r, -sc, sc), e;
            ggVec3 d;
            int may = 0;
            /* Half the segments end in the transparent corner. */
            e = (i & 1) ? rvec(&r, 0.15 * sc, 0.45 * sc) : rvec(&r, -sc, sc);
            d = V3(e.x - o.x, e.y - o.y, e.z - o.z);
            may = gg_geom_transparent_may_hit(g, o, d);
            if (hits_transparent(g, o, d)) {
                nhit++;
                assert_int_equal(may, 1);
            }
            if (!may) nno++;
        }
        print_message("scale %g: %ld of %ld segments hit a transparent primitive, %ld skipped\n",
                      sc, nhit, n, nno);
        assert_true(nhit > n / 50);
        assert_true(nno > n / 4);
        gg_geom_free(g);
    }
}

static void test_flags_after_build(void **state)
{
    tu_rng r = {5};
    gg_geom *g = make_scene(&r, 1.0);
    ggVec3 o = V3(-0.9, -0.9, -0.9), d = V3(-0.05, 0, 0);
    (void)state;
    /* Far from the transparent corner: skipped. */
    assert_int_equal(gg_geom_transparent_may_hit(g, o, d), 0);
    /* A primitive made transparent after the build: no shortcut any more. */
    gg_geom_set_flags(g, 0, GG_PRIM_TRANSPARENT);
    assert_int_equal(gg_geom_transparent_may_hit(g, o, d), 1);
    /* NaN and huge inputs say "may". */
    assert_int_equal(gg_geom_transparent_may_hit(g, V3(NAN, 0, 0), d), 1);
    gg_geom_free(g);
}

static void test_no_transparent(void **state)
{
    gg_geom *g = gg_geom_create(NULL);
    (void)state;
    assert_true(gg_geom_add_sphere(g, V3(0, 0, 0), 1, 0) >= 0);
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    assert_int_equal(gg_geom_transparent_may_hit(g, V3(0, 0, -5), V3(0, 0, 10)), 0);
    gg_geom_free(g);
}

static void test_shadow_query(void **state)
{
    static const double scales[] = {1e-6, 1.0, 1e6};
    int si;
    (void)state;
    for (si = 0; si < 3; si++) {
        double sc = scales[si];
        tu_rng r = {31 + (uint64_t)si};
        gg_geom *g = make_scene(&r, sc);
        long i, n = 20000, nblock = 0, ntr = 0, nfree = 0;
        uint32_t cache = 0;
        for (i = 0; i < n; i++) {
            ggVec3 o = rvec(&r, -sc, sc), e = (i & 1) ? rvec(&r, 0.15 * sc, 0.45 * sc)
                                                       : rvec(&r, -sc, sc);
            gg_rayq q;
            gg_hit h, ht;
            int has = -1, blocked, occ, hit;
            q.o = o, q.d = V3(e.x - o.x, e.y - o.y, e.z - o.z);
            q.tmin = 0, q.tmax = 1;
            /* Sometimes leave a primitive, as a shadow ray from a surface does. */
            q.ignore_prim = (i % 3 == 0) ? (uint32_t)(tu_next(&r) % gg_geom_prim_count(g))
                                          : UINT32_MAX;
            q.skip_flags = GG_PRIM_TRANSPARENT;
            occ = gg_geom_occluded(g, &q);
            blocked = gg_geom_shadow_query(g, &q, &ht, &has);
            assert_int_equal(blocked, occ);
            {
                /* The cached variant, twice: first with the cache the
                   previous ray left, then with this ray's own occluder. */
                gg_hit hc;
                int k, hasc = -1;
                for (k = 0; k < 2; k++) {
                    assert_int_equal(gg_geom_shadow_query_cached(g, &q, &hc, &hasc, &cache), occ);
                    if (occ) {
                        assert_true(cache > 0);
                        continue;
                    }
                    /* a clear segment empties the cache */
                    assert_int_equal(cache, 0);
                    assert_int_equal(hasc, has);
                    if (has) {
                        assert_int_equal(hc.prim, ht.prim);
                        assert_int_equal(tu_ulps(hc.t, ht.t), 0);
                    }
                }
            }
            if (blocked) {
                nblock++;
                continue;
            }
            q.skip_flags = 0;
            hit = gg_geom_intersect(g, &q, &h);
            assert_int_equal(has, hit);
            if (hit) {
                ntr++;
                assert_true(g->pflags[h.prim] & GG_PRIM_TRANSPARENT);
                assert_int_equal(ht.prim, h.prim);
                assert_int_equal(ht.sub, h.sub);
                assert_int_equal(tu_ulps(ht.t, h.t), 0);
                assert_int_equal(tu_ulps(ht.b1, h.b1), 0);
                assert_int_equal(tu_ulps(ht.b2, h.b2), 0);
            } else
                nfree++;
        }
        print_message("scale %g: %ld blocked, %ld through transparent, %ld free\n", sc, nblock,
                      ntr, nfree);
        assert_true(nblock > n / 20 && ntr > n / 50 && nfree > n / 20);
        gg_geom_free(g);
    }
}

/* gg_geom_shadow_query_all against stepping along the segment with the
   closest-hit query (same origin and direction, tmin moved up to each
   hit): the same crossings, in order, bit for bit; complete unless there
   are more than GG_TCOL_CAP; no list when something opaque blocks. Both
   traversal copies (AVX where the CPU has it, and the plain one). */
static void test_shadow_query_all(void **state)
{
    static const double scales[] = {1e-6, 1.0, 1e6};
    int si, path;
    (void)state;
    for (path = 0; path < 2; path++)
        for (si = 0; si < 3; si++) {
            double sc = scales[si];
            tu_rng r = {71 + (uint64_t)si};
            gg_geom *g = make_scene(&r, sc);
            long i, n = 20000, nlist = 0, nmulti = 0, nover = 0;
            uint32_t cache = 0;
            if (path == 1) g->trav_avx = 0;
            for (i = 0; i < n; i++) {
                ggVec3 o = rvec(&r, -sc, sc), e = (i & 1) ? rvec(&r, 0.15 * sc, 0.45 * sc)
                                                           : rvec(&r, -sc, sc);
                gg_rayq q;
                gg_hit ht, ref[GG_TCOL_CAP + 1];
                gg_tcol all;
                int has = -1, blocked, k, nref = 0;
                q.o = o, q.d = V3(e.x - o.x, e.y - o.y, e.z - o.z);
                q.tmin = 0, q.tmax = 1;
                q.ignore_prim = (i % 3 == 0) ? (uint32_t)(tu_next(&r) % gg_geom_prim_count(g))
                                              : UINT32_MAX;
                q.skip_flags = GG_PRIM_TRANSPARENT;
                blocked = gg_geom_shadow_query_all(g, &q, &ht, &has, &cache, &all);
                assert_int_equal(blocked, gg_geom_occluded(g, &q));
                if (blocked) {
                    assert_int_equal(all.n, 0);
                    continue;
                }
                q.skip_flags = 0;
                while (nref <= GG_TCOL_CAP && gg_geom_intersect(g, &q, &ref[nref])) {
                    q.tmin = ref[nref++].t;
                }
                assert_int_equal(all.complete, nref <= GG_TCOL_CAP);
                assert_int_equal(has, nref > 0);
                if (nref > 0) {
                    assert_int_equal(ht.prim, ref[0].prim);
                    assert_int_equal(tu_ulps(ht.t, ref[0].t), 0);
                }
                if (!all.complete) {
                    nover++;
                    continue;
                }
                assert_int_equal(all.n, nref);
                for (k = 0; k < nref; k++) {
                    assert_int_equal(all.h[k].prim, ref[k].prim);
                    assert_int_equal(all.h[k].sub, ref[k].sub);
                    assert_int_equal(tu_ulps(all.h[k].t, ref[k].t), 0);
                    assert_int_equal(tu_ulps(all.h[k].b1, ref[k].b1), 0);
                    assert_int_equal(tu_ulps(all.h[k].b2, ref[k].b2), 0);
                }
                nlist += nref > 0;
                nmulti += nref > 1;
            }
            print_message("scale %g, %s: %ld lists, %ld with several crossings, %ld over %d\n", sc,
                          path ? "plain" : "default", nlist, nmulti, nover, GG_TCOL_CAP);
            assert_true(nlist > n / 50 && nmulti > n / 200);
            gg_geom_free(g);
        }
}

/* More crossings than the list holds: a stack of parallel transparent
   triangles. */
static void test_shadow_query_all_overflow(void **state)
{
    gg_geom *g = gg_geom_create(NULL);
    gg_rayq q;
    gg_hit ht;
    gg_tcol all;
    int i, path, has = 0;
    (void)state;
    assert_non_null(g);
    for (i = 0; i < GG_TCOL_CAP + 3; i++) {
        ggVec3 t[3];
        int p;
        t[0] = V3(-1, -1, i), t[1] = V3(1, -1, i), t[2] = V3(0, 1, i);
        p = gg_geom_add_triangle(g, t, NULL, 0);
        assert_true(p >= 0);
        gg_geom_set_flags(g, p, GG_PRIM_TRANSPARENT);
    }
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    /* both traversal copies (the stack makes leaves of triangles, which
       the AVX copy tests four at a time) */
    for (path = 0; path < 2; path++) {
        if (path == 1) g->trav_avx = 0;
        q.o = V3(0.1, 0.1, -0.5), q.d = V3(0, 0, 100), q.tmin = 0, q.tmax = 1;
        q.ignore_prim = UINT32_MAX, q.skip_flags = 0;
        assert_int_equal(gg_geom_shadow_query_all(g, &q, &ht, &has, NULL, &all), 0);
        assert_int_equal(all.complete, 0);
        assert_int_equal(has, 1);
        assert_int_equal(ht.prim, 0);
        /* a segment crossing only three of them is complete */
        q.d = V3(0, 0, 3);
        assert_int_equal(gg_geom_shadow_query_all(g, &q, &ht, &has, NULL, &all), 0);
        assert_int_equal(all.complete, 1);
        assert_int_equal(all.n, 3);
        for (i = 0; i < 3; i++) {
            assert_int_equal(all.h[i].prim, (uint32_t)i);
            assert_true(fabs(all.h[i].t - (i + 0.5) / 3) <= 1e-15);
        }
    }
    gg_geom_free(g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shadow_query),
        cmocka_unit_test(test_shadow_query_all),
        cmocka_unit_test(test_shadow_query_all_overflow),
        cmocka_unit_test(test_never_misses),
        cmocka_unit_test(test_flags_after_build),
        cmocka_unit_test(test_no_transparent),
    };
    return cmocka_run_group_tests_name("transparent_box", tests, NULL, NULL);
}
