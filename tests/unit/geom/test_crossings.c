/* SPDX-License-Identifier: MIT */
/*
** test_crossings.c -- gg_geom_occluded with a crossing list (coloured
** shadows): blocked exactly when the plain query with transparent
** primitives skipped is; otherwise the nearest crossing and the list are
** what stepping along the segment with gg_geom_intersect finds, bit for
** bit, in both traversal copies; the inside-sphere shortcut stops at the
** sphere's far side.
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
   in a corner, and long thin transparent triangles, at coordinate scale
   `sc`. */
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
    /* long thin transparent triangles across the corner: spatial splits
       clip them (bvh_build.c), so they are in several leaves but must
       cross once */
    for (i = 0; i < 8; i++) {
        ggVec3 t[3];
        t[0] = rvec(r, -sc, 0.3 * sc);
        t[1] = rvec(r, 0.3 * sc, sc);
        t[2] = V3(t[0].x + 0.01 * sc, t[0].y - 0.01 * sc, t[0].z + 0.01 * sc);
        p = gg_geom_add_triangle(g, t, NULL, 1);
        assert_true(p >= 0);
        gg_geom_set_flags(g, p, GG_PRIM_TRANSPARENT);
    }
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    assert_true(g->nslots > gg_geom_prim_count(g));
    return g;
}

/* The plain any-hit query, without an occluder cache. */
static int occluded(const gg_geom *g, const gg_rayq *q)
{
    uint32_t none = 0;
    return gg_geom_occluded(g, q, &none, NULL);
}

/* A shadow-like segment from o to e. */
static gg_rayq segment(ggVec3 o, ggVec3 e)
{
    gg_rayq q;
    q.o = o, q.d = V3(e.x - o.x, e.y - o.y, e.z - o.z), q.tmin = 0, q.tmax = 1;
    q.ignore_prim = UINT32_MAX, q.skip_flags = 0, q.inside = UINT32_MAX, q.opt = &gg_qopt_default;
    return q;
}

/* Blocked exactly when the plain query with transparent primitives
   skipped is; the occluder cache changes nothing, is kept by a blocked
   segment and emptied by a clear one; the nearest crossing is
   gg_geom_intersect's. */
static void test_blocked(void **state)
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
            ggVec3 o = rvec(&r, -sc, sc),
                   e = (i & 1) ? rvec(&r, 0.15 * sc, 0.45 * sc) : rvec(&r, -sc, sc);
            gg_rayq q = segment(o, e);
            gg_hit h;
            gg_tcol tr, tc;
            int blocked, occ, hit, k;
            /* Sometimes leave a primitive, as a shadow ray from a surface does. */
            q.ignore_prim =
                (i % 3 == 0) ? (uint32_t)(tu_next(&r) % gg_geom_prim_count(g)) : UINT32_MAX;
            q.skip_flags = GG_PRIM_TRANSPARENT;
            occ = occluded(g, &q);
            q.skip_flags = i & 2 ? GG_PRIM_TRANSPARENT : 0; /* ignored with a list */
            {
                uint32_t none = 0;
                blocked = gg_geom_occluded(g, &q, &none, &tr);
            }
            assert_int_equal(blocked, occ);
            /* With the cache, twice: first the one the previous segment
               left, then this segment's own occluder. */
            for (k = 0; k < 2; k++) {
                assert_int_equal(gg_geom_occluded(g, &q, &cache, &tc), occ);
                if (occ) {
                    assert_true(cache > 0);
                    continue;
                }
                assert_int_equal(cache, 0);
                assert_int_equal(tc.has_near, tr.has_near);
                if (tr.has_near) {
                    assert_int_equal(tc.near.prim, tr.near.prim);
                    assert_int_equal(tu_ulps(tc.near.t, tr.near.t), 0);
                }
            }
            if (blocked) {
                nblock++;
                continue;
            }
            q.skip_flags = 0;
            hit = gg_geom_intersect(g, &q, &h);
            assert_int_equal(tr.has_near, hit);
            if (hit) {
                ntr++;
                assert_true(g->pflags[h.prim] & GG_PRIM_TRANSPARENT);
                assert_int_equal(tr.near.prim, h.prim);
                assert_int_equal(tr.near.sub, h.sub);
                assert_int_equal(tu_ulps(tr.near.t, h.t), 0);
                assert_int_equal(tu_ulps(tr.near.b1, h.b1), 0);
                assert_int_equal(tu_ulps(tr.near.b2, h.b2), 0);
            } else
                nfree++;
        }
        print_message("scale %g: %ld blocked, %ld through transparent, %ld free\n", sc, nblock, ntr,
                      nfree);
        assert_true(nblock > n / 20 && ntr > n / 50 && nfree > n / 20);
        gg_geom_free(g);
    }
}

/* The crossing list against stepping along the segment with the
   closest-hit query (same origin and direction, tmin moved up to each
   hit): the same crossings, in order, bit for bit; complete unless there
   are more than GG_TCOL_CAP; no list when something opaque blocks. Both
   traversal copies (AVX where the CPU has it, and the plain one). */
static void test_list(void **state)
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
                ggVec3 o = rvec(&r, -sc, sc),
                       e = (i & 1) ? rvec(&r, 0.15 * sc, 0.45 * sc) : rvec(&r, -sc, sc);
                gg_rayq q = segment(o, e);
                gg_hit ref[GG_TCOL_CAP + 1];
                gg_tcol all;
                int blocked, k, nref = 0;
                q.ignore_prim =
                    (i % 3 == 0) ? (uint32_t)(tu_next(&r) % gg_geom_prim_count(g)) : UINT32_MAX;
                q.skip_flags = GG_PRIM_TRANSPARENT;
                blocked = gg_geom_occluded(g, &q, &cache, &all);
                assert_int_equal(blocked, occluded(g, &q));
                if (blocked) {
                    assert_int_equal(all.n, 0);
                    assert_int_equal(all.has_near, 0);
                    continue;
                }
                q.skip_flags = 0;
                while (nref <= GG_TCOL_CAP && gg_geom_intersect(g, &q, &ref[nref])) {
                    q.tmin = ref[nref++].t;
                }
                assert_int_equal(all.complete, nref <= GG_TCOL_CAP);
                assert_int_equal(all.has_near, nref > 0);
                if (nref > 0) {
                    assert_int_equal(all.near.prim, ref[0].prim);
                    assert_int_equal(tu_ulps(all.near.t, ref[0].t), 0);
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
static void test_overflow(void **state)
{
    gg_geom *g = gg_geom_create(NULL);
    gg_rayq q;
    gg_tcol all;
    uint32_t cache = 0;
    int i, path;
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
        q = segment(V3(0.1, 0.1, -0.5), V3(0.1, 0.1, 99.5));
        assert_int_equal(gg_geom_occluded(g, &q, &cache, &all), 0);
        assert_int_equal(all.complete, 0);
        assert_int_equal(all.has_near, 1);
        assert_int_equal(all.near.prim, 0);
        /* a segment crossing only three of them is complete */
        q.d = V3(0, 0, 3);
        assert_int_equal(gg_geom_occluded(g, &q, &cache, &all), 0);
        assert_int_equal(all.complete, 1);
        assert_int_equal(all.n, 3);
        for (i = 0; i < 3; i++) {
            assert_int_equal(all.h[i].prim, (uint32_t)i);
            assert_true(fabs(all.h[i].t - (i + 0.5) / 3) <= 1e-15);
        }
    }
    gg_geom_free(g);
}

/* From inside an isolated transparent sphere, with q.inside naming it:
   the far side is the nearest crossing, the list is marked incomplete and
   nothing beyond is looked at (an opaque wall there is the walk's to
   find); without the hint the wall blocks. A sphere that is not isolated
   gets no shortcut. */
static void test_inside_shortcut(void **state)
{
    gg_geom *g = gg_geom_create(NULL);
    ggVec3 t[3];
    gg_rayq q;
    gg_tcol all;
    gg_hit h;
    uint32_t cache = 0;
    int ball, wall, near;
    (void)state;
    ball = gg_geom_add_sphere(g, V3(0, 0, 0), 1, 0);
    gg_geom_set_flags(g, ball, GG_PRIM_TRANSPARENT);
    t[0] = V3(-5, -5, 3), t[1] = V3(5, -5, 3), t[2] = V3(0, 5, 3);
    wall = gg_geom_add_triangle(g, t, NULL, 1);
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    q = segment(V3(0.1, 0.2, 0.3), V3(0.1, 0.2, 10));
    q.skip_flags = GG_PRIM_TRANSPARENT;
    assert_int_equal(gg_geom_occluded(g, &q, &cache, &all), 1);
    assert_true(cache > 0); /* the wall, remembered */
    q.inside = (uint32_t)ball;
    cache = 0;
    assert_int_equal(gg_geom_occluded(g, &q, &cache, &all), 0);
    assert_true(!all.complete && all.has_near && all.near.prim == (uint32_t)ball);
    q.skip_flags = 0, q.inside = UINT32_MAX;
    assert_int_equal(gg_geom_intersect(g, &q, &h), 1);
    assert_true(h.prim == all.near.prim && h.t == all.near.t);
    gg_geom_free(g);
    /* a second sphere inside the ball: not isolated, no shortcut */
    g = gg_geom_create(NULL);
    ball = gg_geom_add_sphere(g, V3(0, 0, 0), 1, 0);
    near = gg_geom_add_sphere(g, V3(0.5, 0, 0), 0.1, 1);
    gg_geom_set_flags(g, ball, GG_PRIM_TRANSPARENT);
    gg_geom_set_flags(g, near, GG_PRIM_TRANSPARENT);
    wall = gg_geom_add_triangle(g, t, NULL, 2);
    assert_true(wall >= 0);
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    q = segment(V3(0.1, 0.2, 0.3), V3(0.1, 0.2, 10));
    q.inside = (uint32_t)ball;
    assert_int_equal(gg_geom_occluded(g, &q, &cache, &all), 1);
    gg_geom_free(g);
}

static ggVec3 from_axes(const double c[3])
{
    return V3(c[0], c[1], c[2]);
}

/* A ray exactly through the edge two triangles share crosses exactly one
   of them, also when that edge is horizontal in the ray's sheared space
   (its ey is exactly 0): gg_tri_owns (lib/geom/shape_tri.h) gives it to
   the triangle that sees it with ex > 0, the top-left rule. Guards that
   rule's `ey > 0` (`ey >= 0` lets both triangles own a horizontal edge,
   so a coloured shadow would cross the pair twice). The edge has constant
   coordinate ky (the axis that is y after the shear) and the ray no
   component along ky from an origin with that coordinate: then both ends
   of the edge shear to y = 0 exactly, whatever the other coordinates.
   Every dominant axis and sign, both kernels (double and float), random
   edges, triangles and rays; each triangle alone (exactly one hits) and
   the transparent pair in a crossing list (one crossing). */
static void test_shared_horizontal_edge_once(void **state)
{
    tu_rng r = {97};
    int i, isect;
    (void)state;
    for (isect = 0; isect < 2; isect++) {
        gg_qopt opt = gg_qopt_default;
        opt.isect = isect ? GG_ISECT_FLOAT : GG_ISECT_DOUBLE;
        for (i = 0; i < 600; i++) {
            int kz = i % 3, neg = (i / 3) % 2;
            int kx = kz == 2 ? 0 : kz + 1, ky = kx == 2 ? 0 : kx + 1, tmp;
            double a[3], b[3], c1[3], c2[3], p[3], o[3], e[3], y0 = tu_range(&r, -4, 4), f;
            ggVec3 tri[2][3];
            gg_geom *g2;
            gg_rayq q;
            gg_tcol all;
            uint32_t cache = 0;
            int k, hits = 0;
            if (neg) tmp = kx, kx = ky, ky = tmp; /* the swap gg_rayq's setup makes */
            /* the shared edge a-b at constant ky, the third vertices on either side */
            a[kx] = tu_range(&r, -6, -1), a[ky] = y0, a[kz] = tu_range(&r, -2, 2);
            b[kx] = tu_range(&r, 1, 6), b[ky] = y0, b[kz] = tu_range(&r, -2, 2);
            c1[kx] = tu_range(&r, -3, 3), c1[ky] = y0 + tu_range(&r, 0.5, 4);
            c1[kz] = tu_range(&r, -2, 2);
            c2[kx] = tu_range(&r, -3, 3), c2[ky] = y0 - tu_range(&r, 0.5, 4);
            c2[kz] = tu_range(&r, -2, 2);
            /* a point inside the edge, and a ray to it along kz (tilted
               along kx only) from an origin at ky = y0 */
            f = tu_range(&r, 0.2, 0.8);
            for (k = 0; k < 3; k++) p[k] = a[k] + f * (b[k] - a[k]);
            p[ky] = y0;
            o[kx] = p[kx] + tu_range(&r, -3, 3), o[ky] = y0;
            o[kz] = p[kz] + (neg ? 20 : -20) + tu_range(&r, -5, 5);
            for (k = 0; k < 3; k++) e[k] = o[k] + 2 * (p[k] - o[k]);
            tri[0][0] = from_axes(a), tri[0][1] = from_axes(b), tri[0][2] = from_axes(c1);
            tri[1][0] = from_axes(b), tri[1][1] = from_axes(a), tri[1][2] = from_axes(c2);
            q = segment(from_axes(o), from_axes(e));
            q.opt = &opt;
            assert_true((ky == 0 ? q.d.x : ky == 1 ? q.d.y : q.d.z) == 0); /* no ky part */
            for (k = 0; k < 2; k++) {
                gg_geom *g = gg_geom_create(NULL);
                gg_hit h;
                assert_true(gg_geom_add_triangle(g, tri[k], NULL, 0) >= 0);
                assert_int_equal(gg_geom_build(g, NULL), GG_OK);
                hits += gg_geom_intersect(g, &q, &h);
                gg_geom_free(g);
            }
            if (hits != 1)
                print_error("kz %d neg %d: the ray through the shared edge hits %d of the two "
                            "triangles\n",
                            kz, neg, hits);
            assert_int_equal(hits, 1);
            g2 = gg_geom_create(NULL);
            for (k = 0; k < 2; k++) {
                int pr = gg_geom_add_triangle(g2, tri[k], NULL, k);
                assert_true(pr >= 0);
                gg_geom_set_flags(g2, pr, GG_PRIM_TRANSPARENT);
            }
            assert_int_equal(gg_geom_build(g2, NULL), GG_OK);
            assert_int_equal(gg_geom_occluded(g2, &q, &cache, &all), 0);
            assert_true(all.complete && all.has_near);
            assert_int_equal(all.n, 1);
            gg_geom_free(g2);
        }
    }
}

/* A transparent cylinder or cone is cut into up to 8 slices along its
   axis (gg_cone_slice), all with the same surface: a shadow segment
   through the axis at a slice boundary crosses the surface twice, once
   per wall, not once per slice that holds the boundary. Random frames,
   radii and boundaries; the boundaries at z = i/8 of a length-1 axis,
   exact in binary. */
static void test_cone_slice_boundary_once(void **state)
{
    tu_rng r = {113};
    int i;
    (void)state;
    for (i = 0; i < 400; i++) {
        ggVec3 base = rvec(&r, -3, 3), ax = rvec(&r, -1, 1), side, p, o, e;
        double len, rb = tu_range(&r, 0.01, 0.04), ra = i & 1 ? rb : tu_range(&r, 0.01, 0.04);
        double z = (double)(1 + i % 7) / 8;
        gg_geom *g = gg_geom_create(NULL);
        gg_rayq q;
        gg_tcol all;
        uint32_t cache = 0;
        int pr;
        len = sqrt(ax.x * ax.x + ax.y * ax.y + ax.z * ax.z);
        ax = V3(ax.x / len, ax.y / len, ax.z / len);
        /* a direction across the axis */
        side = fabs(ax.x) < 0.5 ? V3(0, ax.z, -ax.y) : V3(ax.y, -ax.x, 0);
        p = V3(base.x + z * ax.x, base.y + z * ax.y, base.z + z * ax.z);
        o = V3(p.x - side.x, p.y - side.y, p.z - side.z);
        e = V3(p.x + side.x, p.y + side.y, p.z + side.z);
        pr = gg_geom_add_cone(g, base, rb, V3(base.x + ax.x, base.y + ax.y, base.z + ax.z), ra, 0);
        assert_true(pr >= 0);
        gg_geom_set_flags(g, pr, GG_PRIM_TRANSPARENT);
        assert_int_equal(gg_geom_build(g, NULL), GG_OK);
        q = segment(o, e);
        assert_int_equal(gg_geom_occluded(g, &q, &cache, &all), 0);
        if (!(all.complete && all.n == 2))
            print_error("segment %d (z = %g): %d crossings, complete %d\n", i, z, (int)all.n,
                        (int)all.complete);
        assert_true(all.complete);
        assert_int_equal(all.n, 2);
        gg_geom_free(g);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_blocked),
        cmocka_unit_test(test_list),
        cmocka_unit_test(test_overflow),
        cmocka_unit_test(test_inside_shortcut),
        cmocka_unit_test(test_shared_horizontal_edge_once),
        cmocka_unit_test(test_cone_slice_boundary_once),
    };
    return cmocka_run_group_tests_name("crossings", tests, NULL, NULL);
}
