/* SPDX-License-Identifier: MIT */
/*
** test_packet.c -- gg_geom_intersect_packet answers every lane exactly as
** gg_geom_intersect answers its ray (hit or not, primitive, sub, t, b1,
** b2 and the surface's point and normals, bit for bit), in every copy of
** the traversal this build has: the plain one, the AVX one where the CPU
** runs it, and (test_packet_scalar) the portable C one. Rays: coherent
** packets from one point (rows of a pinhole camera, bundles about a
** direction, some wide enough to cross an axis), incoherent ones, and
** lanes a packet must leave to the single-ray path (another origin, tmin
** > 0, zero or NaN directions, the inside hint), on random scenes of every
** shape kind and on the SPD scenes through their cameras.
*/
#include "testutil.h"

#include "bvh_int.h"
#include "scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef GG_TEST_SUITE
#define GG_TEST_SUITE "packet"
#endif

#define NL GG_PACKET_MAX

static ggVec3 V3(double x, double y, double z)
{
    ggVec3 v;
    v.x = x, v.y = y, v.z = z;
    return v;
}

static ggVec3 add(ggVec3 a, ggVec3 b)
{
    return V3(a.x + b.x, a.y + b.y, a.z + b.z);
}

static ggVec3 scale(ggVec3 a, double s)
{
    return V3(a.x * s, a.y * s, a.z * s);
}

static ggVec3 cross(ggVec3 a, ggVec3 b)
{
    return V3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

static ggVec3 unit(ggVec3 a)
{
    return scale(a, 1 / sqrt(a.x * a.x + a.y * a.y + a.z * a.z));
}

static void same_bits(const void *a, const void *b, size_t n)
{
    assert_memory_equal(a, b, n);
}

static long nlanes, nhits;

/* Fills the stack below the caller with all-ones bytes (a NaN as a float)
   so that a value the packet code reads without setting is a NaN on every
   compiler, not only where clang's ASan frame happened to leave one (a
   lane's tmin, set only for the lanes a packet takes, once made the packet
   bound NaN and every lane miss). */
static void *(*volatile paint_fill)(void *, int, size_t) = memset; /* not optimised away */
static void paint_stack(void)
{
    unsigned char buf[1 << 14];
    paint_fill(buf, 0xff, sizeof buf);
}

/* One packet on g's current copy against the single-ray query per lane.
   Lanes outside `lanes` must be left untouched. */
static void same_packet(const gg_geom *g, const gg_rayq *q, unsigned lanes)
{
    gg_hit hp[NL], hs, untouched;
    unsigned got;
    int l;
    memset(hp, 0xa5, sizeof hp);
    memset(&untouched, 0xa5, sizeof untouched);
    paint_stack();
    got = gg_geom_intersect_packet(g, q, lanes, hp);
    assert_int_equal(got & ~lanes, 0);
    for (l = 0; l < NL; l++) {
        int hit;
        if (!(lanes >> l & 1)) {
            same_bits(&hp[l], &untouched, sizeof untouched);
            continue;
        }
        nlanes++;
        hit = gg_geom_intersect(g, &q[l], &hs);
        assert_int_equal((int)(got >> l & 1), hit);
        if (!hit) {
            same_bits(&hp[l], &untouched, sizeof untouched);
            continue;
        }
        nhits++;
        assert_int_equal(hp[l].prim, hs.prim);
        assert_int_equal(hp[l].sub, hs.sub);
        same_bits(&hp[l].t, &hs.t, sizeof hs.t);
        same_bits(&hp[l].b1, &hs.b1, sizeof hs.b1);
        same_bits(&hp[l].b2, &hs.b2, sizeof hs.b2);
        {
            gg_surf sa, sb;
            gg_geom_surface(g, &q[l], &hp[l], &sa, GG_SURF_UV);
            gg_geom_surface(g, &q[l], &hs, &sb, GG_SURF_UV);
            same_bits(&sa.p, &sb.p, sizeof sa.p);
            same_bits(&sa.ng, &sb.ng, sizeof sa.ng);
            same_bits(&sa.ns, &sb.ns, sizeof sa.ns);
        }
    }
}

/* The packet on every copy of the traversal g can take: the plain one,
   and below the copy g's build chose (2: the AVX2 build) the others. */
static void same_all_copies(gg_geom *g, const gg_rayq *q, unsigned lanes)
{
    int avx = g->trav_avx, lv;
    for (lv = 0; lv <= avx; lv++) {
        g->trav_avx = lv;
        same_packet(g, q, lanes);
    }
    g->trav_avx = avx;
}

/* ---- random scenes ---- */

static ggVec3 rvec(tu_rng *r, double lo, double hi)
{
    double x = tu_range(r, lo, hi), y = tu_range(r, lo, hi), z = tu_range(r, lo, hi);
    return V3(x, y, z);
}

/* n primitives of every kind in [-10, 10]^3, a fifth of them transparent
   (so the skip flags matter). One draw per statement: argument order is
   unspecified. */
static gg_geom *random_scene(tu_rng *r, int n, int avx)
{
    gg_geom *g = gg_geom_create(NULL);
    int i;
    assert_non_null(g);
    gg_geom_set_cpu(g, avx ? GG_CPU_ALL : 0);
    for (i = 0; i < n; i++) {
        ggVec3 c = rvec(r, -10, 10), p[4], e1, e2;
        double s = 0.1 * pow(10, tu_range(r, 0, 1.5)), rb, ra;
        int id = -1, k;
        switch (tu_next(r) % 6) {
        case 0:
            id = gg_geom_add_sphere(g, c, s * 0.5, i);
            break;
        case 1:
        case 2: /* triangles twice as often: the AVX blocks */
            for (k = 0; k < 3; k++) p[k] = add(c, rvec(r, -s, s));
            id = gg_geom_add_triangle(g, p, NULL, i);
            break;
        case 3:
            rb = s * tu_range(r, 0.05, 0.5);
            ra = s * tu_range(r, 0, 0.5);
            e1 = add(c, rvec(r, -s, s));
            id = gg_geom_add_cone(g, c, rb, e1, ra, i);
            break;
        case 4:
            e2 = rvec(r, -s, s);
            e1 = rvec(r, -s, s);
            id = gg_geom_add_rect(g, c, e1, e2, i);
            break;
        default:
            e1 = rvec(r, -s, s);
            e2 = rvec(r, -s, s);
            p[0] = c, p[1] = add(c, e1), p[3] = add(c, e2);
            p[2] = add(add(c, scale(e1, 0.7)), scale(e2, 1.3));
            id = gg_geom_add_polygon(g, p, 4, i);
            break;
        }
        if (id == GG_GEOM_DEGENERATE) continue;
        assert_true(id >= 0);
        if (tu_next(r) % 5 == 0) gg_geom_set_flags(g, id, GG_PRIM_TRANSPARENT);
    }
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    return g;
}

/* Lane l of a packet from o about direction c: a row (spread along one
   direction, as a tile row of eye rays), a cone, or any direction. */
static ggVec3 lane_dir(tu_rng *r, int kind, ggVec3 c, ggVec3 u, double spread, int l)
{
    switch (kind) {
    case 0:
        return add(c, scale(u, spread * (l - NL / 2)));
    case 1:
        return add(c, scale(rvec(r, -1, 1), spread));
    default:
        return tu_unit(r);
    }
}

/* Something a packet must leave to the single-ray path, or a change of
   bounds or options that stays in the packet, now and then. */
static void perturb(tu_rng *r, gg_rayq *q, size_t nprim)
{
    switch (tu_next(r) % 24) {
    case 0:
        q->o.x = nextafter(q->o.x, INFINITY); /* another origin */
        break;
    case 1:
        q->tmin = tu_range(r, 0, 5);
        break;
    case 2:
        q->d.y = 0; /* 1/d infinite */
        break;
    case 3:
        q->d = V3(0, 0, 0);
        break;
    case 4:
        q->d.z = NAN;
        break;
    case 5:
        q->inside = (uint32_t)(tu_next(r) % nprim);
        break;
    case 6:
        q->tmax = q->tmin;
        break;
    case 7:
        q->tmin = -1;
        break;
    case 8:
    case 9:
        q->ignore_prim = (uint32_t)(tu_next(r) % nprim);
        break;
    case 10:
    case 11:
        q->skip_flags = GG_PRIM_TRANSPARENT;
        break;
    case 12:
    case 13:
        q->tmax = tu_range(r, 0, 30);
        break;
    case 14:
        q->d = scale(q->d, 1e-30); /* 1/d beyond float */
        break;
    default:
        break;
    }
}

/* A packet of rays from o; returns the lanes to ask for. */
static unsigned random_packet(tu_rng *r, gg_rayq q[NL], ggVec3 o, size_t nprim)
{
    int kind = (int)(tu_next(r) % 3), l, perturbed = tu_next(r) % 3 == 0;
    ggVec3 c = tu_unit(r), u = unit(cross(c, tu_unit(r)));
    double spread = pow(10, tu_range(r, -4, 0));
    unsigned lanes = tu_next(r) % 4 ? (1u << NL) - 1 : (unsigned)(tu_next(r) & 0xffff);
    for (l = 0; l < NL; l++) {
        q[l] = gg_rayq_make(o, lane_dir(r, kind, c, u, spread, l), 0, INFINITY, NULL);
        if (perturbed) perturb(r, &q[l], nprim);
    }
    return lanes;
}

static void test_random_scenes(void **state)
{
    tu_rng r = {141};
    int s;
    (void)state;
    nlanes = nhits = 0;
    for (s = 0; s < 6; s++) {
        int avx = (s & 1) && (gg_cpu_features() & GG_CPU_AVX);
        gg_geom *g = random_scene(&r, s < 2 ? 40 : 1500, avx);
        size_t nprim = gg_geom_prim_count(g);
        long i;
        for (i = 0; i < 3000; i++) {
            gg_rayq q[NL];
            /* from inside the scene, or from outside looking at it */
            ggVec3 o = i % 2 ? rvec(&r, -10, 10) : scale(tu_unit(&r), 25);
            unsigned lanes = random_packet(&r, q, o, nprim);
            if (i % 2 == 0 && q[0].d.x * o.x + q[0].d.y * o.y + q[0].d.z * o.z > 0)
                for (int l = 0; l < NL; l++) q[l].d = scale(q[l].d, -1);
            same_all_copies(g, q, lanes);
        }
        gg_geom_free(g);
    }
    print_message("random scenes: %ld lanes, %ld hits, the same as one ray at a time\n", nlanes,
                  nhits);
    assert_true(nhits > nlanes / 5);
}

/* ---- the SPD scenes through their cameras ---- */

/* The eye rays of pixel row y, columns x0 .. x0 + 15, at w x h, as the
   renderer's tile loop makes them (unit directions from the eye). */
static void camera_row(const ggCamera *c, int w, int h, int x0, int y, gg_rayq q[NL])
{
    ggVec3 fwd = unit(add(c->at, scale(c->from, -1)));
    ggVec3 right = unit(cross(fwd, c->up)), up = cross(right, fwd);
    double tx = tan(c->fov_deg * GG_PI / 360.0), ty = tx * h / w;
    double sy = (1.0 - 2.0 * (y + 0.5) / h) * ty;
    int l;
    for (l = 0; l < NL; l++) {
        double sx = (2.0 * (x0 + l + 0.5) / w - 1.0) * tx;
        ggVec3 d = add(fwd, add(scale(right, sx), scale(up, sy)));
        q[l] = gg_rayq_make(c->from, unit(d), 0, INFINITY, NULL);
    }
}

static void test_spd_scenes(void **state)
{
    static const char *names[] = {"balls-s4", "gears", "rings",     "tetra",
                                  "mount",    "tree",  "teapot-s12"};
    const int w = 128, h = 128;
    int k;
    (void)state;
    for (k = 0; k < 7; k++) {
        char path[512];
        ggScene *sc = ggSceneCreate(NULL);
        ggError err;
        tu_rng r = {150 + (unsigned)k};
        ggVec3 lo, hi;
        int x, y, i;
        nlanes = nhits = 0;
        snprintf(path, sizeof path, "%s/%s.nff", tu_spd_dir(), names[k]);
        assert_int_equal(ggSceneLoadFile(sc, path, &err), GG_OK);
        assert_int_equal(ggScenePrepare(sc, &err), GG_OK);
        for (y = 0; y < h; y++)
            for (x = 0; x < w; x += NL) {
                gg_rayq q[NL];
                camera_row(&sc->camera, w, h, x, y, q);
                same_all_copies(sc->geom, q, (1u << NL) - 1);
            }
        gg_geom_bounds(sc->geom, &lo, &hi);
        for (i = 0; i < 1000; i++) {
            gg_rayq q[NL];
            ggVec3 o = V3(lo.x + (hi.x - lo.x) * tu_range(&r, -0.25, 1.25),
                          lo.y + (hi.y - lo.y) * tu_range(&r, -0.25, 1.25),
                          lo.z + (hi.z - lo.z) * tu_range(&r, -0.25, 1.25));
            unsigned lanes = random_packet(&r, q, o, gg_geom_prim_count(sc->geom));
            same_all_copies(sc->geom, q, lanes);
        }
        print_message("%-10s %ld lanes, %ld hits, the same as one ray at a time\n", names[k],
                      nlanes, nhits);
        assert_true(nhits > 1000);
        ggSceneFree(sc);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_scenes),
        cmocka_unit_test(test_spd_scenes),
    };
    return cmocka_run_group_tests_name(GG_TEST_SUITE, tests, NULL, NULL);
}
