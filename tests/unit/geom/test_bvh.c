/* SPDX-License-Identifier: MIT */
/*
** test_bvh.c -- the BVH answers exactly what testing every primitive
** answers: same primitive, same t to the bit, same occlusion, on random
** scenes of every shape kind and on the SPD scenes.
*/
#include "testutil.h"

#include "bvh_int.h"
#include "geom_leaf.h"
#include "implicit.h"
#include "scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef GG_TEST_SUITE
#define GG_TEST_SUITE "bvh"
#endif

static ggVec3 V3(double x, double y, double z)
{
    ggVec3 v;
    v.x = x, v.y = y, v.z = z;
    return v;
}

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
        case 0:
            id = gg_geom_add_sphere(g, c, s * 0.5, i);
            break;
        case 1:
            p[0] = vadd(c, rvec(r, -s, s)), p[1] = vadd(c, rvec(r, -s, s));
            p[2] = vadd(c, rvec(r, -s, s));
            id = gg_geom_add_triangle(g, p, NULL, i);
            break;
        case 2: {
            /* One draw per statement: the order in which a call's
               arguments are evaluated is unspecified, and the scene must
               not depend on the compiler (this is the order GCC took). */
            double ra = tu_uniform(r) < 0.3 ? 0.2 * s : s * tu_range(r, 0, 0.5);
            ggVec3 apex = vadd(c, rvec(r, -s, s));
            id = gg_geom_add_cone(g, c, s * tu_range(r, 0, 0.5), apex, ra, i);
            break;
        }
        case 3: {
            ggVec3 e2 = rvec(r, -s, s), e1 = rvec(r, -s, s);
            id = gg_geom_add_rect(g, c, e1, e2, i);
            break;
        }
        default:
            id = add_star(g, r, c, s, 3 + (int)(tu_next(r) % 8));
            break;
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
    double u = tu_uniform(r), len;
    q->o = rvec(r, -14, 14);
    len = tu_range(r, 0.1, 3); /* before the direction, as above */
    q->d = vscale(tu_unit(r), len);
    if (u < 0.1) q->d.x = 0;
    if (u < 0.05) q->d.y = 0;
    if (u > 0.95) q->o.x = 10; /* on a plane of the scene box */
    q->tmin = 0;
    q->tmax = tu_uniform(r) < 0.2 ? tu_range(r, 0, 10) : INFINITY;
    q->ignore_prim = UINT32_MAX;
    q->skip_flags = 0;
    q->inside = UINT32_MAX, q->opt = &gg_qopt_default;
}

/* ---- the reference: every element, with a chunk filter ----

   Testing all of gears' 37,000 elements for 1e5 rays takes a minute, so
   the reference skips runs of consecutive slots whose bounding sphere
   (padded far beyond rounding) the ray provably misses or that lie wholly
   behind the current closest hit; everything else is tested element by
   element with the same kernels, in slot order. It shares nothing with
   the BVH but the kernels and gg_leaf_closest's tie rule, and it is
   itself checked against gg_geom_intersect_brute (no filter at all). */

#define CH  16 /* slots per chunk */
#define SCH 16 /* chunks per super-chunk */

typedef struct sphb {
    double c[3], r;
} sphb;

typedef struct ref {
    const gg_geom *g;
    sphb *ch, *sup;
    size_t nch, nsup;
} ref;

static void slot_points(const gg_geom *g, const gg_slot *s, double lo[3], double hi[3])
{
    const gg_prim *p = &g->prims[s->prim];
    int k;
    for (k = 0; k < 3; k++) lo[k] = INFINITY, hi[k] = -INFINITY;
#define PT(x, y, z)                                                                                \
    do {                                                                                           \
        double v_[3] = {(x), (y), (z)};                                                            \
        for (k = 0; k < 3; k++) lo[k] = fmin(lo[k], v_[k]), hi[k] = fmax(hi[k], v_[k]);            \
    } while (0)
    switch (p->kind) {
    case GG_SHAPE_SPHERE: {
        const gg_sph *sp = &g->sphs[p->data];
        PT(sp->c.x - sp->r, sp->c.y - sp->r, sp->c.z - sp->r);
        PT(sp->c.x + sp->r, sp->c.y + sp->r, sp->c.z + sp->r);
        break;
    }
    case GG_SHAPE_TRIANGLE:
    case GG_SHAPE_POLYGON: {
        const gg_ktri *t = p->kind == GG_SHAPE_TRIANGLE ? &g->tris[p->data].k : &g->pieces[s->sub];
        int j;
        if (p->kind == GG_SHAPE_POLYGON && g->polys[p->data].npiece == 0) {
            const gg_poly *pl = &g->polys[p->data];
            uint32_t i;
            for (i = 0; i < pl->nv; i++) {
                const double *v = g->pverts[pl->vfirst + i];
                PT(v[0], v[1], v[2]);
            }
            break;
        }
        for (j = 0; j < 3; j++) PT(t->v[j][0], t->v[j][1], t->v[j][2]);
        break;
    }
    case GG_SHAPE_CONE: {
        const gg_kcone *c = &g->cones[p->data].k;
        double rmax = fmax(c->rb, g->cones[p->data].ra), e = c->h;
        PT(c->base[0] - rmax, c->base[1] - rmax, c->base[2] - rmax);
        PT(c->base[0] + rmax, c->base[1] + rmax, c->base[2] + rmax);
        PT(c->base[0] + e * c->ez[0] - rmax, c->base[1] + e * c->ez[1] - rmax,
           c->base[2] + e * c->ez[2] - rmax);
        PT(c->base[0] + e * c->ez[0] + rmax, c->base[1] + e * c->ez[1] + rmax,
           c->base[2] + e * c->ez[2] + rmax);
        break;
    }
    case GG_SHAPE_RECT: {
        const gg_rect *r = &g->rects[p->data];
        const double *c = r->k.v[0];
        PT(c[0], c[1], c[2]);
        PT(c[0] + r->e1.x, c[1] + r->e1.y, c[2] + r->e1.z);
        PT(c[0] + r->e2.x, c[1] + r->e2.y, c[2] + r->e2.z);
        PT(c[0] + r->e1.x + r->e2.x, c[1] + r->e1.y + r->e2.y, c[2] + r->e1.z + r->e2.z);
        break;
    }
    default: {
        ggVec3 l, h;
        gg_implicit_bounds(g->imps[p->data], &l, &h);
        PT(l.x, l.y, l.z);
        PT(h.x, h.y, h.z);
        break;
    }
    }
#undef PT
}

/* Bounding sphere of the boxes of slots [a, b), padded by 1e-6 of its
   radius and of the coordinates' size: rounding is ~1e-16 of those. */
static sphb bound(const gg_geom *g, size_t a, size_t b)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    sphb s;
    size_t i;
    int k;
    for (i = a; i < b; i++) {
        double l[3], h[3];
        slot_points(g, &g->slots[i], l, h);
        for (k = 0; k < 3; k++) lo[k] = fmin(lo[k], l[k]), hi[k] = fmax(hi[k], h[k]);
    }
    for (k = 0; k < 3; k++) s.c[k] = 0.5 * (lo[k] + hi[k]);
    s.r = 0.5 * sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                     (hi[2] - lo[2]) * (hi[2] - lo[2]));
    s.r += 1e-6 * (s.r + fabs(s.c[0]) + fabs(s.c[1]) + fabs(s.c[2]));
    return s;
}

static void ref_init(ref *rf, const gg_geom *g)
{
    size_t i;
    rf->g = g;
    rf->nch = (g->nslots + CH - 1) / CH;
    rf->nsup = (rf->nch + SCH - 1) / SCH;
    rf->ch = malloc(sizeof *rf->ch * (rf->nch + 1));
    rf->sup = malloc(sizeof *rf->sup * (rf->nsup + 1));
    assert_non_null(rf->ch);
    assert_non_null(rf->sup);
    for (i = 0; i < rf->nch; i++)
        rf->ch[i] = bound(g, i * CH, (i + 1) * CH < g->nslots ? (i + 1) * CH : g->nslots);
    for (i = 0; i < rf->nsup; i++)
        rf->sup[i] =
            bound(g, i * CH * SCH, (i + 1) * CH * SCH < g->nslots ? (i + 1) * CH * SCH : g->nslots);
}

static void ref_free(ref *rf)
{
    free(rf->ch);
    free(rf->sup);
}

/* Can the ray meet the sphere with t <= tmax? (w x d)^2 <= r^2 d^2 says
   the line passes within r; w.d >= -r |d| that it is not behind; and the
   entry (w.d - r |d|) / d^2 must not lie beyond tmax. Padded by 1e-9. */
static int sph_maybe(const sphb *s, const gg_rpre *r, double dl, double tmax)
{
    double wx = s->c[0] - r->o[0], wy = s->c[1] - r->o[1], wz = s->c[2] - r->o[2];
    double cx = wy * r->d[2] - wz * r->d[1], cy = wz * r->d[0] - wx * r->d[2];
    double cz = wx * r->d[1] - wy * r->d[0], along = wx * r->d[0] + wy * r->d[1] + wz * r->d[2];
    double rr = s->r * dl * (1 + 1e-9);
    if (cx * cx + cy * cy + cz * cz > rr * rr) return 0;
    if (along < -rr) return 0;
    if ((along - rr) * (1 - 1e-9) > tmax * r->a) return 0;
    return 1;
}

static int ref_closest(const ref *rf, const gg_rayq *q, gg_hit *hit)
{
    const gg_geom *g = rf->g;
    gg_rpre r;
    gg_hit best;
    size_t si, ci;
    double dl;
    if (!g->nslots || !gg_rpre_init(&r, q) || !(q->tmax > q->tmin)) return 0;
    dl = sqrt(r.a);
    best.t = gg_next_down(q->tmax);
    best.prim = UINT32_MAX, best.sub = 0, best.b1 = best.b2 = 0;
    for (si = 0; si < rf->nsup; si++) {
        size_t ce = (si + 1) * SCH < rf->nch ? (si + 1) * SCH : rf->nch;
        if (!sph_maybe(&rf->sup[si], &r, dl, best.t)) continue;
        for (ci = si * SCH; ci < ce; ci++) {
            size_t a = ci * CH, b = a + CH < g->nslots ? a + CH : g->nslots;
            if (!sph_maybe(&rf->ch[ci], &r, dl, best.t)) continue;
            gg_leaf_closest(g, &r, (uint32_t)a, (uint32_t)(b - a), &best);
        }
    }
    if (best.prim == UINT32_MAX) return 0;
    *hit = best;
    return 1;
}

/* The plain any-hit query, without an occluder cache. */
static int occluded(const gg_geom *g, const gg_rayq *q)
{
    uint32_t none = 0;
    return gg_geom_occluded(g, q, &none, NULL);
}

/* Any-hit by testing every element, as gg_geom_intersect_brute does for
   the closest hit. */
static int occluded_brute(const gg_geom *g, const gg_rayq *q)
{
    gg_rpre r;
    if (!g->built || !g->nslots || !gg_rpre_init(&r, q) || !(q->tmax > q->tmin)) return 0;
    return gg_leaf_any(g, &r, 0, (uint32_t)g->nslots, gg_next_down(q->tmax)) != 0;
}

static void compare_ref(const gg_geom *g, const ref *rf, const gg_rayq *q, long *nhit)
{
    gg_hit a, b;
    int fa = gg_geom_intersect(g, q, &a), fb = ref_closest(rf, q, &b);
    if (fa != fb || (fa && (a.prim != b.prim || a.t != b.t || a.sub != b.sub || a.b1 != b.b1))) {
        print_error("bvh %d prim %u t %.17g, reference %d prim %u t %.17g\n", fa, fa ? a.prim : 0,
                    fa ? a.t : 0, fb, fb ? b.prim : 0, fb ? b.t : 0);
        fail();
    }
    assert_int_equal(occluded(g, q), fb);
    if (fa) (*nhit)++;
}

static void compare(const gg_geom *g, const gg_rayq *q, long *nhit)
{
    gg_hit a, b;
    int fa = gg_geom_intersect(g, q, &a), fb = gg_geom_intersect_brute(g, q, &b);
    assert_int_equal(fa, fb);
    assert_int_equal(occluded(g, q), fb);
    assert_int_equal(occluded_brute(g, q), fb);
    if (fa) {
        if (a.prim != b.prim || a.t != b.t || a.sub != b.sub || a.b1 != b.b1) {
            print_error("bvh prim %u t %.17g, brute prim %u t %.17g\n", a.prim, a.t, b.prim, b.t);
            fail();
        }
        (*nhit)++;
    }
}

/* Fewer rays under the sanitizers, which check memory, not statistics. */
#if defined(__SANITIZE_ADDRESS__)
#define RAYS(n) ((n) / 10)
#else
#define RAYS(n) (n)
#endif

static void run_random(int n, int kinds, int rays, unsigned seed, long min_hits)
{
    tu_rng r = {seed};
    gg_geom *g = random_scene(&r, n, kinds);
    long nhit = 0;
    int i;
    ref rf;
    ref_init(&rf, g);
    for (i = 0; i < rays; i++) {
        gg_rayq q;
        random_ray(&r, &q);
        /* every 50th ray also against the unfiltered brute force */
        if (i % 50 == 0)
            compare(g, &q, &nhit);
        else
            compare_ref(g, &rf, &q, &nhit);
    }
    ref_free(&rf);
    /* The scene must actually be hit often enough for the comparison to
       prove something. */
    assert_true(nhit >= min_hits);
    gg_geom_free(g);
}

static void test_random_mixed(void **state)
{
    (void)state;
    run_random(3000, 5, RAYS(100000), 1, RAYS(20000));
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
    ref rf;
    (void)state;
    for (i = 0; i < 500; i += 3) gg_geom_set_flags(g, i, GG_PRIM_TRANSPARENT);
    ref_init(&rf, g);
    for (i = 0; i < RAYS(20000); i++) {
        gg_rayq q;
        gg_hit a, b;
        int fa, fb;
        random_ray(&r, &q);
        q.skip_flags = i & 1 ? GG_PRIM_TRANSPARENT : 0;
        fa = ref_closest(&rf, &q, &a);
        if (fa && (i & 2)) q.ignore_prim = a.prim; /* skip the first hit */
        fa = gg_geom_intersect(g, &q, &a);
        fb = i % 50 ? ref_closest(&rf, &q, &b) : gg_geom_intersect_brute(g, &q, &b);
        assert_int_equal(fa, fb);
        assert_int_equal(occluded(g, &q), fb);
        if (fa) {
            assert_int_equal(a.prim, b.prim);
            assert_true(a.t == b.t);
            assert_true(a.prim != q.ignore_prim);
            if (q.skip_flags) assert_true(a.prim % 3 != 0);
            skipped += q.ignore_prim != UINT32_MAX;
        }
    }
    assert_true(skipped > RAYS(20000) / 200);
    ref_free(&rf);
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
    gg_rayq q = {{0, 0, 0},  {1, 0, 0},        0,   INFINITY, UINT32_MAX, 0,
                 UINT32_MAX, &gg_qopt_default, NULL};
    gg_hit h;
    (void)state;
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    assert_int_equal(gg_geom_intersect(g, &q, &h), 0);
    assert_int_equal(occluded(g, &q), 0);
    gg_geom_free(g);
    gg_geom_free(NULL);
}

/* The occluder cache changes nothing but speed: same answers as
   gg_geom_occluded, with a cache that follows coherent rays. */
static void test_occluded_cached(void **state)
{
    tu_rng r = {9};
    gg_geom *g = random_scene(&r, 60, 5);
    uint32_t cache = 0;
    int i, occl = 0;
    ggVec3 light = V3(3, 4, 30);
    (void)state;
    for (i = 0; i < 20000; i++) {
        gg_rayq q;
        /* shadow-like rays: from a wandering point towards one light */
        q.o = V3(-10 + 20 * (i % 200) / 200.0, -10 + 20 * (i / 200) / 100.0, tu_range(&r, -2, 2));
        q.d = V3(light.x - q.o.x, light.y - q.o.y, light.z - q.o.z);
        q.tmin = 0, q.tmax = 1, q.ignore_prim = UINT32_MAX, q.skip_flags = 0;
        q.inside = UINT32_MAX, q.opt = &gg_qopt_default;
        if (i % 7 == 0) cache = (uint32_t)(tu_next(&r) % (g->nslots + 5)); /* junk is harmless */
        assert_int_equal(gg_geom_occluded(g, &q, &cache, NULL), occluded(g, &q));
        /* an occluder is remembered, a clear segment empties the cache */
        assert_int_equal(cache != 0, occluded(g, &q));
        occl += occluded(g, &q);
    }
    print_message("%d of 20000 shadow rays occluded\n", occl);
    assert_true(occl > 1000 && occl < 19000);
    gg_geom_free(g);
}

/* A ray with a component that is not finite (NaN, +-inf) in its origin or
   direction hits nothing, in every query: the ray set-up tests the origin
   itself and lets d . d (then infinite or NaN) turn the direction away.
   The same ray with the component finite does hit, so the queries would
   see the scene. */
static void test_nonfinite_rays(void **state)
{
    gg_geom *g = gg_geom_create(NULL);
    const double bad[] = {NAN, INFINITY, -INFINITY, 1e300};
    uint32_t cache = 0;
    int k, b, nhit = 0;
    (void)state;
    assert_true(gg_geom_add_sphere(g, V3(0, 0, 0), 1, 0) >= 0);
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    for (k = 0; k < 6; k++)
        for (b = -1; b < 4; b++) {
            double c[6] = {0.25, 0.25, 10, 0, 0, -1};
            gg_rayq q;
            gg_hit h;
            gg_tcol all;
            int expect;
            /* 1e300 overflows d . d (as an origin it is only far away) */
            if (b == 3 && k < 3) continue;
            if (b >= 0) c[k] = bad[b];
            expect = b < 0;
            q.o = V3(c[0], c[1], c[2]), q.d = V3(c[3], c[4], c[5]);
            q.tmin = 0, q.tmax = INFINITY, q.ignore_prim = UINT32_MAX, q.skip_flags = 0;
            q.inside = UINT32_MAX, q.opt = &gg_qopt_default;
            assert_int_equal(gg_geom_intersect(g, &q, &h), expect);
            assert_int_equal(occluded(g, &q), expect);
            assert_int_equal(gg_geom_occluded(g, &q, &cache, NULL), expect);
            /* the sphere is opaque: it blocks a coloured shadow ray too */
            assert_int_equal(gg_geom_occluded(g, &q, &cache, &all), expect);
            if (!expect) assert_true(all.complete && all.n == 0 && !all.has_near);
            q.inside = 0; /* a hint changes no answer */
            assert_int_equal(gg_geom_intersect(g, &q, &h), expect);
            assert_int_equal(gg_geom_occluded(g, &q, &cache, &all), expect);
            nhit += expect;
        }
    assert_int_equal(nhit, 6);
    gg_geom_free(g);
}

/* The float rounding helpers of the traversal: f_down(x) < x and f_up(x)
   > x, one float ulp past the nearest float on the safe side, and the
   constant the traversal takes for f_down of a tmin of +-0 (bvh_trav.inc.h,
   f_down_tmin). */
static void test_float_bounds(void **state)
{
    tu_rng r = {31};
    int i;
    (void)state;
    assert_true(f_down(0.0) == -0x1p-149f && signbit(f_down(0.0)));
    assert_true(f_down(-0.0) == -0x1p-149f);
    assert_true(f_up(0.0) == 0x1p-149f);
    for (i = 0; i < 100000; i++) {
        double e = tu_range(&r, -140, 120), x = tu_range(&r, -1, 1) * pow(2, e);
        float lo = f_down(x), hi = f_up(x);
        assert_true((double)lo < x && (double)hi > x);
        assert_true(f_next_up(lo) <= (float)x && f_next_down(hi) >= (float)x);
    }
}

/* Adding after a build and building again; statistics; bounds. */
static void test_rebuild_stats_bounds(void **state)
{
    gg_geom *g = gg_geom_create(NULL);
    gg_bvh_stats st;
    ggVec3 lo, hi, p[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    gg_rayq q;
    gg_hit h;
    (void)state;
    assert_int_equal(gg_geom_add_sphere(g, V3(0, 0, 0), 1, 0), 0);
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    gg_geom_bounds(g, &lo, &hi);
    assert_true(lo.x <= -1 && lo.x > -1 - 1e-12 && hi.z >= 1 && hi.z < 1 + 1e-12);
    q.o = V3(0.25, 0.25, 10), q.d = V3(0, 0, -1), q.tmin = 0, q.tmax = INFINITY;
    q.ignore_prim = UINT32_MAX, q.skip_flags = 0;
    q.inside = UINT32_MAX, q.opt = &gg_qopt_default;
    assert_true(gg_geom_intersect(g, &q, &h));
    assert_close(h.t, 10 - sqrt(1 - 0.125), 1e-15);
    /* a new primitive in front: unbuilt queries find nothing, rebuilt ones find it */
    p[0].z = p[1].z = p[2].z = 5;
    assert_int_equal(gg_geom_add_triangle(g, p, NULL, 1), 1);
    assert_false(gg_geom_intersect(g, &q, &h));
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    assert_true(gg_geom_intersect(g, &q, &h));
    assert_int_equal(h.prim, 1);
    gg_geom_bounds(g, &lo, &hi);
    assert_true(hi.z >= 5);
    gg_geom_bvh_stats(g, &st);
    assert_true(st.nodes >= 1 && st.leaves >= 1 && st.max_depth >= 1);
    assert_true(st.bytes >= 128 + 2 * sizeof(gg_slot));
    assert_true(st.build_seconds >= 0);
    gg_geom_free(g);
}

/* Every allocation goes through the allocator; a failing allocator gives
   -1 or GG_ERROR_NOMEM, never a crash, and leaks nothing (ASan). */
static long live, budget;
static void *a_malloc(void *ud, size_t n)
{
    (void)ud;
    if (budget-- <= 0) return NULL;
    live++;
    return malloc(n);
}
static void *a_realloc(void *ud, void *p, size_t n)
{
    void *q;
    (void)ud;
    if (budget-- <= 0) return NULL;
    q = realloc(p, n);
    if (q && !p) live++;
    return q;
}
static void a_free(void *ud, void *p)
{
    (void)ud;
    if (p) live--;
    free(p);
}

static void test_allocator(void **state)
{
    ggAllocator al = {a_malloc, a_realloc, a_free, NULL};
    size_t sizes[3] = {50, 8, 60};
    long b;
    int ok_builds = 0, was = gg_bvh_set_threads(2);
    (void)state;
    /* with two build threads for the 120 primitives (small limits) */
    gg_bvh_set_build_sizes(sizes);
    for (b = 0; b < 400; b += 3) {
        tu_rng r = {17};
        gg_geom *g;
        ggError err;
        int i;
        live = 0, budget = b;
        g = gg_geom_create(&al);
        if (!g) {
            assert_int_equal(live, 0);
            continue;
        }
        for (i = 0; i < 60; i++) {
            ggVec3 c = rvec(&r, -5, 5), st[8];
            int k;
            for (k = 0; k < 8; k++)
                st[k] = V3(c.x + cos(k * GG_PI / 4) * (k & 1 ? 0.5 : 1),
                           c.y + sin(k * GG_PI / 4) * (k & 1 ? 0.5 : 1), c.z);
            gg_geom_add_sphere(g, c, 0.3, i);
            gg_geom_add_polygon(g, st, 8, i);
        }
        if (gg_geom_build(g, &err) == GG_OK) {
            gg_rayq q;
            gg_hit h;
            ok_builds++;
            q.o = V3(0, 0, 20), q.d = V3(0.01, 0.02, -1), q.tmin = 0, q.tmax = INFINITY;
            q.ignore_prim = UINT32_MAX, q.skip_flags = 0;
            q.inside = UINT32_MAX, q.opt = &gg_qopt_default;
            assert_int_equal(gg_geom_intersect(g, &q, &h), gg_geom_intersect_brute(g, &q, &h));
        } else {
            assert_int_equal(err.code, GG_ERROR_NOMEM);
        }
        gg_geom_free(g);
        assert_int_equal(live, 0);
    }
    gg_bvh_set_build_sizes(sizes);
    gg_bvh_set_threads(was);
    assert_true(ok_builds > 0);
}

/* ---- threaded builds ---- */

/* The tree does not depend on the number of threads: the same nodes,
   slots and triangle blocks byte for byte with 1 to 4 build threads,
   each handed many small subtrees and binning the large nodes together
   (small limits), and answers that are brute force's. */
static void test_threaded_build(void **state)
{
    size_t sizes[3] = {500, 40, 700}, keep[3];
    gg_geom *one;
    int t, was = gg_bvh_set_threads(1), i;
    (void)state;
    gg_bvh_set_build_sizes(sizes);
    {
        tu_rng r = {23};
        one = random_scene(&r, 4000, 5);
    }
    assert_true(one->nnodes > 100 && (one->ntleaves > 10 || !gg_bvh_avx_wanted(one)));
    for (t = 2; t <= 4; t++) {
        tu_rng r = {23};
        gg_geom *g;
        long nhit = 0;
        gg_bvh_set_threads(t);
        g = random_scene(&r, 4000, 5);
        assert_int_equal(g->nnodes, one->nnodes);
        assert_int_equal(g->nslots, one->nslots);
        assert_int_equal(g->ntleaves, one->ntleaves);
        assert_int_equal(memcmp(g->nodes, one->nodes, g->nnodes * sizeof *g->nodes), 0);
        assert_int_equal(memcmp(g->slots, one->slots, g->nslots * sizeof *g->slots), 0);
        if (g->ntleaves) /* none in the scalar suite */
            assert_int_equal(memcmp(g->tleaves, one->tleaves, g->ntleaves * sizeof *g->tleaves), 0);
        for (i = 0; i < RAYS(5000); i++) {
            gg_rayq q;
            random_ray(&r, &q);
            compare(g, &q, &nhit);
        }
        assert_true(nhit > RAYS(500));
        gg_geom_free(g);
    }
    gg_geom_free(one);
    memcpy(keep, sizes, sizeof keep);
    gg_bvh_set_build_sizes(keep);
    gg_bvh_set_threads(was);
}

/* ---- SPD scenes ---- */

/* Load an SPD scene through the library's NFF loader; the scene owns
   the gg_geom the renderer traces. */
static ggScene *load_spd(const char *name)
{
    char path[512];
    ggScene *sc = ggSceneCreate(NULL);
    ggError err;
    assert_non_null(sc);
    snprintf(path, sizeof path, "%s/%s.nff", tu_spd_dir(), name);
    if (ggSceneLoadFile(sc, path, &err) != GG_OK) {
        snprintf(path, sizeof path, "examples/scenes/spd/%s.nff", name);
        if (ggSceneLoadFile(sc, path, &err) != GG_OK) {
            print_error("%s\n", err.message);
            fail();
        }
    }
    if (ggScenePrepare(sc, &err) != GG_OK) {
        print_error("%s\n", err.message);
        fail();
    }
    return sc;
}

static void test_spd_scenes(void **state)
{
    static const char *names[] = {"balls-s4",   "gears", "mount", "rings",
                                  "teapot-s12", "tetra", "tree"};
    int k;
    (void)state;
    for (k = 0; k < 7; k++) {
        ggScene *sc = load_spd(names[k]);
        const gg_geom *g = sc->geom;
        ref rf;
        tu_rng r = {1000 + (unsigned)k};
        ggVec3 lo, hi, c;
        long nhit = 0;
        int i, npoly = 0, whole = 0;
        for (i = 0; i < (int)g->npoly; i++) npoly++, whole += g->polys[i].npiece == 0;
        ref_init(&rf, g);
        gg_geom_bounds(g, &lo, &hi);
        c = vscale(vadd(lo, hi), 0.5);
        for (i = 0; i < RAYS(100000); i++) {
            gg_rayq q;
            /* origins in the scene box grown by half, random directions
               (drawn z, y, x: one order for every compiler) */
            double fz = tu_range(&r, -0.75, 0.75), fy = tu_range(&r, -0.75, 0.75);
            double fx = tu_range(&r, -0.75, 0.75);
            q.o = V3(c.x + (hi.x - lo.x) * fx, c.y + (hi.y - lo.y) * fy, c.z + (hi.z - lo.z) * fz);
            q.d = tu_unit(&r);
            q.tmin = 0;
            q.tmax = i % 4 == 0 ? tu_range(&r, 0, hi.x - lo.x) : INFINITY;
            q.ignore_prim = UINT32_MAX, q.skip_flags = 0;
            q.inside = UINT32_MAX, q.opt = &gg_qopt_default;
            if (i % 500 == 0)
                compare(g, &q, &nhit);
            else
                compare_ref(g, &rf, &q, &nhit);
        }
        print_message("%-10s %6zu prims, %6zu elements, %d polygons (%d kept whole): %ld of %d "
                      "rays hit, BVH = reference\n",
                      names[k], gg_geom_prim_count(g), g->nslots, npoly, whole, nhit, RAYS(100000));
        assert_int_equal(whole, 0); /* every SPD polygon splits into triangles */
        assert_true(nhit > RAYS(100000) / 20);
        ref_free(&rf);
        ggSceneFree(sc);
    }
}

/* gg_next_down_tmax (the traversals' tmax) is gg_next_down bit for bit:
   the special values, their neighbours, and random doubles of both
   signs (random bit patterns, so NaNs and subnormals too). */
static void test_next_down_tmax(void **state)
{
    const double sp[] = {0.0,       -0.0,       INFINITY, -INFINITY, NAN,     -NAN,
                         1.0,       -1.0,       DBL_MAX,  -DBL_MAX,  DBL_MIN, -DBL_MIN,
                         0x1p-1074, -0x1p-1074, 1e300,    1e-300};
    tu_rng rng = {14};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof sp / sizeof sp[0] + 100000; i++) {
        double x = 0, a, b;
        uint64_t u;
        if (i < sizeof sp / sizeof sp[0]) {
            x = sp[i];
        } else {
            u = tu_next(&rng);
            memcpy(&x, &u, 8);
        }
        a = gg_next_down_tmax(x), b = gg_next_down(x);
        assert_memory_equal(&a, &b, sizeof a);
    }
}

/* The traversal this binary runs: test_bvh_scalar's own build of the
   geometry has the portable one, the library the fastest the CPU runs. */
static void test_traversal(void **state)
{
    gg_geom *g = gg_geom_create(NULL);
    ggVec3 p[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    gg_bvh_stats st;
#ifdef GG_TEST_TRAVERSAL
    const char *plain = GG_TEST_TRAVERSAL, *want = plain;
#else
#ifdef __SSE2__
    const char *plain = "sse2";
#else
    const char *plain = "c";
#endif
    const char *want = !GG_HAVE_BVH_AVX || !(gg_cpu_features() & GG_CPU_AVX) ? plain
                       : gg_cpu_features() & GG_CPU_AVX512                   ? "avx512"
                       : gg_cpu_features() & GG_CPU_AVX2                     ? "avx2"
                                                                             : "avx";
#endif
    (void)state;
    assert_true(gg_geom_add_triangle(g, p, NULL, 0) >= 0);
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    gg_geom_bvh_stats(g, &st);
    assert_string_equal(st.traversal, want);
    /* AVX2 allowed, AVX-512 not: the AVX2 build on an AVX-512 CPU */
    gg_geom_set_cpu(g, GG_CPU_ALL & ~GG_CPU_AVX512);
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    gg_geom_bvh_stats(g, &st);
    assert_string_equal(st.traversal, strcmp(want, "avx512") ? want : "avx2");
    /* AVX allowed, AVX2 not: the AVX copy's own build */
    gg_geom_set_cpu(g, GG_CPU_AVX);
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    gg_geom_bvh_stats(g, &st);
    assert_string_equal(st.traversal, strcmp(want, plain) ? "avx" : plain);
    gg_geom_set_cpu(g, 0);
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    gg_geom_bvh_stats(g, &st);
    assert_string_equal(st.traversal, plain);
    gg_geom_free(g);
}

/* The kernel table (core.h, gg_cpu_kernels): filled once, each entry
   the best copy the CPU's features allow; and a geometry's traversal
   copy (g->trav_avx, its index into the table's copies) that entry as
   each of the 16 masks of gg_geom_set_cpu restricts it: the AVX copy only
   with GG_CPU_AVX, its AVX2 build only with GG_CPU_AVX2 too, its AVX-512
   build only with GG_CPU_AVX512 as well. */
static void test_kernel_table(void **state)
{
    const gg_kernel_table *k = gg_cpu_kernels();
    const unsigned f = gg_cpu_features();
    const int fma = f & GG_CPU_FMA ? GG_KERNEL_FMA : GG_KERNEL_PLAIN;
#ifdef GG_TEST_TRAVERSAL
    const int have = 0; /* the portable build of the geometry */
#else
    const int have = GG_HAVE_BVH_AVX;
#endif
    ggVec3 p[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    unsigned mask;
    (void)state;
    assert_ptr_equal(k, gg_cpu_kernels());
    assert_int_equal(k->refract, fma);
    assert_int_equal(k->reflect, fma);
    assert_int_equal(k->fresnel, fma);
    assert_int_equal(k->trav, f & GG_CPU_AVX512 ? GG_KERNEL_AVX512
                              : f & GG_CPU_AVX2 ? GG_KERNEL_AVX2
                              : f & GG_CPU_AVX  ? GG_KERNEL_AVX
                                                : GG_KERNEL_PLAIN);
    for (mask = 0; mask <= GG_CPU_ALL; mask++) {
        gg_geom *g = gg_geom_create(NULL);
        int want = !have || !(mask & GG_CPU_AVX)                            ? GG_KERNEL_PLAIN
                   : k->trav >= GG_KERNEL_AVX2 && !(mask & GG_CPU_AVX2)     ? GG_KERNEL_AVX
                   : k->trav == GG_KERNEL_AVX512 && !(mask & GG_CPU_AVX512) ? GG_KERNEL_AVX2
                                                                            : k->trav;
        assert_true(gg_geom_add_triangle(g, p, NULL, 0) >= 0);
        gg_geom_set_cpu(g, mask);
        assert_int_equal(gg_geom_build(g, NULL), GG_OK);
        assert_int_equal(g->trav_avx, want);
        gg_geom_free(g);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_mixed),
        cmocka_unit_test(test_random_small_scenes),
        cmocka_unit_test(test_ignore_and_skip),
        cmocka_unit_test(test_coincident),
        cmocka_unit_test(test_empty),
        cmocka_unit_test(test_occluded_cached),
        cmocka_unit_test(test_nonfinite_rays),
        cmocka_unit_test(test_float_bounds),
        cmocka_unit_test(test_rebuild_stats_bounds),
        cmocka_unit_test(test_allocator),
        cmocka_unit_test(test_threaded_build),
        cmocka_unit_test(test_spd_scenes),
        cmocka_unit_test(test_traversal),
        cmocka_unit_test(test_kernel_table),
        cmocka_unit_test(test_next_down_tmax),
    };
    return cmocka_run_group_tests_name(GG_TEST_SUITE, tests, NULL, NULL);
}
