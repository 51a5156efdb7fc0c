/* SPDX-License-Identifier: MIT */
/*
** test_offset.c -- secondary rays never find the surface they leave, at
** any scale and far from the origin, with grazing directions; nested
** surfaces 1e-9 apart are still found; the fixed-epsilon variant.
*/
#include "testutil.h"

#include "geom_int.h"
#include "implicit.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static ggVec3 V(double x, double y, double z)
{
    ggVec3 v;
    v.x = x, v.y = y, v.z = z;
    return v;
}
static ggVec3 add(ggVec3 a, ggVec3 b)
{
    return V(a.x + b.x, a.y + b.y, a.z + b.z);
}
static ggVec3 sub(ggVec3 a, ggVec3 b)
{
    return V(a.x - b.x, a.y - b.y, a.z - b.z);
}
static ggVec3 mul(ggVec3 a, double s)
{
    return V(a.x * s, a.y * s, a.z * s);
}
static double dot(ggVec3 a, ggVec3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
static ggVec3 cross(ggVec3 a, ggVec3 b)
{
    return V(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static ggVec3 unit(ggVec3 a)
{
    return mul(a, 1 / sqrt(dot(a, a)));
}

static gg_rayq ray(ggVec3 o, ggVec3 d)
{
    gg_rayq q;
    q.o = o, q.d = d, q.tmin = 0, q.tmax = INFINITY;
    q.ignore_prim = UINT32_MAX, q.skip_flags = 0;
    q.inside = UINT32_MAX, q.opt = &gg_qopt_default;
    return q;
}

enum { S_SPHERE, S_TRI, S_CYL, S_CONE, S_RECT, S_POLY, S_IMPLICIT, S_COUNT };
static const char *names[S_COUNT] = {"sphere", "triangle", "cylinder", "cone",
                                     "rect",   "polygon",  "implicit"};

typedef struct shape {
    int kind;
    ggVec3 c, axis;  /* centre / base, unit axis for cones */
    double r, r2, h; /* radius, apex radius, height */
    ggImplicit *imp; /* S_IMPLICIT: the sphere as (x - cx)^2 + ... - r^2 */
} shape;

/* The implicit sphere of radius r about t, in the box t +- 1.5 r. */
static ggImplicit *implicit_sphere(ggVec3 t, double r)
{
    char f[256];
    ggImplicit *imp;
    ggError e;
    snprintf(f, sizeof f, "(x - %.17g)^2 + (y - %.17g)^2 + (z - %.17g)^2 - %.17g", t.x, t.y, t.z,
             r * r);
    if (ggImplicitCreateExpr(f, sub(t, V(1.5 * r, 1.5 * r, 1.5 * r)),
                             add(t, V(1.5 * r, 1.5 * r, 1.5 * r)), NULL, &imp, &e) != GG_OK)
        fail_msg("%s: %s", f, e.message);
    return imp;
}

/* One shape of the kind, of size ~scale, centred at t. */
static shape make(gg_geom *g, int kind, double scale, ggVec3 t, tu_rng *r)
{
    shape s;
    ggVec3 a = tu_unit(r), b = unit(cross(a, tu_unit(r))), c = cross(a, b);
    int id = -1;
    s.kind = kind, s.c = t, s.axis = a, s.r = scale, s.r2 = scale, s.h = 2 * scale, s.imp = NULL;
    /* long enough to be split into 4 height slices (gg_cone_slices) */
    if (kind == S_CYL || kind == S_CONE) s.h = 12 * scale;
    switch (kind) {
    case S_SPHERE:
        id = gg_geom_add_sphere(g, t, scale, 0);
        break;
    case S_TRI: {
        ggVec3 p[3];
        p[0] = add(t, mul(b, scale)), p[1] = add(t, mul(c, scale));
        p[2] = sub(t, mul(add(b, c), 0.7 * scale));
        id = gg_geom_add_triangle(g, p, NULL, 0);
        break;
    }
    case S_CYL:
    case S_CONE:
        s.r2 = kind == S_CYL ? scale : 0.3 * scale;
        id = gg_geom_add_cone(g, t, s.r, add(t, mul(a, s.h)), s.r2, 0);
        break;
    case S_RECT:
        id = gg_geom_add_rect(g, t, mul(b, scale), mul(add(c, mul(b, 0.3)), scale), 0);
        break;
    case S_IMPLICIT:
        s.imp = implicit_sphere(t, scale);
        id = gg_geom_add_implicit(g, s.imp, 0);
        break;
    default: {
        ggVec3 p[12];
        int i;
        for (i = 0; i < 12; i++) {
            double ang = 2 * GG_PI * i / 12, rad = (i & 1 ? 0.5 : 1) * scale;
            p[i] = add(t, add(mul(b, rad * cos(ang)), mul(c, rad * sin(ang))));
        }
        id = gg_geom_add_polygon(g, p, 12, 0);
        break;
    }
    }
    assert_int_equal(id, 0);
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    return s;
}

/* The first root ahead (t > 0) of the ray o + t d against the shape's
   full quadric, in long double (o - c is exact there), restricted to the
   shape's extent; -1 if none. Planar shapes have none: a ray leaving one
   can only find it again by mistake. o is the spawned origin, so this is
   the exact answer to the very query the library was asked -- for an
   inward ray that is the exit through the far side, which near grazing
   incidence comes within sqrt(2 r offset) of the start. */
static long double first_root(const shape *s, ggVec3 o, ggVec3 d)
{
    long double fx = (long double)o.x - s->c.x, fy = (long double)o.y - s->c.y;
    long double fz = (long double)o.z - s->c.z, A, B, C, disc, t[2];
    long double fzz = 0, dz = 0;
    int i;
    if (s->kind == S_SPHERE || s->kind == S_IMPLICIT) {
        A = (long double)d.x * d.x + (long double)d.y * d.y + (long double)d.z * d.z;
        B = fx * d.x + fy * d.y + fz * d.z;
        C = fx * fx + fy * fy + fz * fz - (long double)s->r * s->r;
    } else if (s->kind == S_CYL || s->kind == S_CONE) {
        long double k = ((long double)s->r2 - s->r) / s->h, w, kd;
        fzz = fx * s->axis.x + fy * s->axis.y + fz * s->axis.z;
        dz = d.x * s->axis.x + d.y * s->axis.y + d.z * s->axis.z;
        w = s->r + k * fzz, kd = k * dz;
        A = (long double)d.x * d.x + (long double)d.y * d.y + (long double)d.z * d.z - dz * dz -
            kd * kd;
        B = fx * d.x + fy * d.y + fz * d.z - fzz * dz - w * kd;
        C = fx * fx + fy * fy + fz * fz - fzz * fzz - w * w;
    } else {
        return -1;
    }
    disc = B * B - A * C;
    if (disc < 0 || A == 0) return -1;
    t[0] = (-B - sqrtl(disc)) / A, t[1] = (-B + sqrtl(disc)) / A;
    for (i = 0; i < 2; i++) {
        long double z = fzz + t[i] * dz;
        if (t[i] <= 0) continue;
        if ((s->kind == S_CYL || s->kind == S_CONE) && (z < 0 || z > s->h)) continue;
        return t[i];
    }
    return -1;
}

/* A point on the shape, hit by a primary ray from outside. */
static int primary(const gg_geom *g, const shape *s, double scale, tu_rng *r, gg_rayq *q,
                   gg_surf *sf)
{
    ggVec3 tgt =
        add(s->c, mul(V(tu_range(r, -1, 1), tu_range(r, -1, 1), tu_range(r, -1, 1)), 0.8 * scale));
    ggVec3 o = add(tgt, mul(tu_unit(r), 4 * scale));
    gg_hit h;
    if (s->kind == S_CYL || s->kind == S_CONE) tgt = add(tgt, mul(s->axis, tu_range(r, 0, s->h)));
    *q = ray(o, sub(tgt, o));
    if (!gg_geom_intersect(g, q, &h)) return 0;
    gg_geom_surface(g, q, &h, sf, GG_SURF_UV);
    return 1;
}

typedef struct counts {
    long rays, rehit, lost, grazing;
} counts;

static void leave(int kind, double scale, ggVec3 t, int n, tu_rng *r, counts *ct)
{
    gg_geom *g = gg_geom_create(NULL);
    shape s = make(g, kind, scale, t, r);
    int i = 0, tries = 0;
    while (i < n && tries < 20 * n) {
        gg_rayq q, q2;
        gg_surf sf;
        gg_hit h2;
        ggVec3 d, tg;
        double u = tu_uniform(r), side = tu_uniform(r) < 0.5 ? -1 : 1;
        long double tref;
        int hit;
        tries++;
        if (!primary(g, &s, scale, r, &q, &sf)) continue;
        tg = unit(cross(sf.ng, tu_unit(r)));
        if (u < 0.5) {
            d = tu_unit(r);
        } else {
            /* grazing: 1e-1 down to 1e-15 off the tangent plane, either side */
            double e = pow(10, -tu_range(r, 1, 15));
            d = add(mul(tg, sqrt(1 - e * e)), mul(sf.ng, side * e));
            ct->grazing++;
        }
        q2 = ray(gg_offset_origin(&sf, d), d);
        hit = gg_geom_intersect(g, &q2, &h2);
        tref = first_root(&s, q2.o, d);
        if (dot(d, sf.ng) >= 0 && tref > 0) {
            /* pushed outward, yet the exact ray meets the shape: the
               offset did not get off the surface */
            if (ct->rehit < 5) print_error("%s: outward origin not off the surface\n", names[kind]);
            ct->rehit++;
        } else if (hit) {
            /* The only acceptable hit is the exact one, the far side of a
               curved shape seen from inside; a re-hit would be at t ~ 0.
               (Near grazing the exit is ill-conditioned: allow 2x.) */
            if (!(tref > 0 && h2.t >= 0.5 * tref && h2.t <= 2 * tref)) {
                if (ct->rehit < 5)
                    print_error("%s scale %g at (%g,%g,%g): re-hit at t %.3g (expected %.3Lg), "
                                "d.ng %.3g, perr %.3g\n",
                                names[kind], scale, t.x, t.y, t.z, h2.t, tref, dot(d, sf.ng),
                                sf.perr);
                ct->rehit++;
            }
        } else if (tref > 0) {
            /* the far side, seen from inside, missed */
            if (ct->lost < 5)
                print_error("%s scale %g: far side at t %.3Lg lost\n", names[kind], scale, tref);
            ct->lost++;
        }
        i++;
        ct->rays++;
    }
    if (i != n)
        print_error("%s scale %g at (%g,%g,%g): %d primary hits in %d tries\n", names[kind], scale,
                    t.x, t.y, t.z, i, tries);
    assert_int_equal(i, n);
    gg_geom_free(g);
    ggImplicitFree(s.imp);
}

/* Scales 1e-6 .. 1e6, at the origin and translated by up to 1e5 per
   axis, seven shape kinds: 6 * 7 * 2 * 12000 > 1e6 secondary rays, and
   the implicit sphere's. */
static void test_no_rehits(void **state)
{
    static const double scales[] = {1e-6, 1e-4, 1e-2, 1, 1e2, 1e4, 1e6};
    tu_rng r = {71};
    counts all = {0, 0, 0, 0};
    int kind, si, tr;
    (void)state;
    for (kind = 0; kind < S_COUNT; kind++) {
        counts ct = {0, 0, 0, 0};
        for (si = 0; si < 7; si++)
            for (tr = 0; tr < 2; tr++) {
                ggVec3 t = tr ? V(tu_range(&r, -1e5, 1e5), tu_range(&r, -1e5, 1e5),
                                  tu_range(&r, -1e5, 1e5))
                              : V(0, 0, 0);
                /* (an implicit surface's root finding is the slow one:
                   a quarter of the rays, 42,000) */
                leave(kind, scales[si], t, kind == S_IMPLICIT ? 3000 : 12000, &r, &ct);
            }
        print_message("%-9s %ld rays (%ld grazing): %ld re-hits, %ld far sides lost\n", names[kind],
                      ct.rays, ct.grazing, ct.rehit, ct.lost);
        all.rays += ct.rays, all.rehit += ct.rehit, all.lost += ct.lost;
    }
    assert_true(all.rays >= 1000000);
    assert_int_equal(all.rehit, 0);
    assert_int_equal(all.lost, 0);
}

/* No single fixed epsilon works everywhere, which is the point of the
   scaled offset (and shows the tests above can fail): the naive 1e-6 of
   GG_ACC_OFFSET_FIXED jumps over an inner sphere 1e-13 below the outer one at
   scale 1e-4, while an epsilon small enough for that (1e-14) re-hits a
   unit sphere translated to 1e5, where the hit point's error is ~1e-11. */
static void test_fixed_epsilon_fails(void **state)
{
    gg_geom *g = gg_geom_create(NULL);
    tu_rng r = {73};
    shape s = make(g, S_SPHERE, 1, V(1e5, 1e5, 1e5), &r);
    int i, rehit = 0, skipped = 0;
    (void)state;
    for (i = 0; i < 2000; i++) {
        gg_rayq q, q2;
        gg_surf sf;
        gg_hit h;
        ggVec3 d;
        if (!primary(g, &s, 1, &r, &q, &sf)) continue;
        d = unit(add(sf.ng, mul(tu_unit(&r), 0.9)));
        if (dot(d, sf.ng) <= 0) continue;
        q2 = ray(gg_offset_origin_fixed(&sf, d, 1e-14), d);
        rehit += gg_geom_intersect(g, &q2, &h);
    }
    gg_geom_free(g);
    g = gg_geom_create(NULL);
    gg_geom_add_sphere(g, V(0, 0, 0), 1e-4 * (1 + 1e-9), 0);
    gg_geom_add_sphere(g, V(0, 0, 0), 1e-4, 1);
    gg_geom_build(g, NULL);
    for (i = 0; i < 2000; i++) {
        ggVec3 o = mul(tu_unit(&r), 3e-4), tgt = mul(tu_unit(&r), 0.5e-4);
        gg_rayq q = ray(o, sub(tgt, o));
        gg_hit h;
        gg_surf sf;
        assert_true(gg_geom_intersect(g, &q, &h));
        assert_int_equal(h.prim, 0);
        gg_geom_surface(g, &q, &h, &sf, GG_SURF_UV);
        q.o = gg_offset_origin_fixed(&sf, q.d, 1e-6);
        /* the inner sphere's entry, right behind the outer one */
        skipped += !gg_geom_intersect(g, &q, &h) || h.prim != 1 || h.t * sqrt(dot(q.d, q.d)) > 1e-8;
    }
    gg_geom_free(g);
    print_message("fixed 1e-14 at 1e5: %d re-hits; fixed 1e-6 at 1e-4: %d inner spheres skipped"
                  " (of 2000 each)\n",
                  rehit, skipped);
    assert_true(rehit > 100);
    assert_true(skipped > 1000);
}

/* Spheres of radius R and R (1 + 1e-9), same centre: a ray crossing both
   finds all four surfaces in order (outer, inner, inner, outer), each
   spawned from the previous hit; and a ray leaving the inner sphere
   outward finds the outer one. Skipped where the gap is below 50 ulps of
   the position (a scale of 1e-4 translated by 1e5 has a gap of 1e-13
   against an ulp of 1.5e-11: doubles cannot tell the spheres apart). */
static void test_nested_spheres(void **state)
{
    static const double scales[] = {1e-4, 1, 1e4};
    tu_rng r = {81};
    int si, tr, i, runs = 0;
    (void)state;
    for (si = 0; si < 3; si++)
        for (tr = 0; tr < 2; tr++) {
            double R = scales[si];
            ggVec3 c = tr ? V(1e5, -1e5, 1e5) : V(0, 0, 0);
            gg_geom *g;
            if (R * 1e-9 < 50 * 1.5e-11 * (tr ? 1 : 0)) continue;
            g = gg_geom_create(NULL);
            assert_int_equal(gg_geom_add_sphere(g, c, R * (1 + 1e-9), 0), 0);
            assert_int_equal(gg_geom_add_sphere(g, c, R, 1), 1);
            assert_int_equal(gg_geom_build(g, NULL), GG_OK);
            runs++;
            for (i = 0; i < 3000; i++) {
                static const uint32_t order[4] = {0, 1, 1, 0};
                ggVec3 o = add(c, mul(tu_unit(&r), 3 * R));
                ggVec3 tgt = add(c, mul(V(tu_range(&r, -0.5, 0.5), tu_range(&r, -0.5, 0.5),
                                          tu_range(&r, -0.5, 0.5)),
                                        R));
                gg_rayq q = ray(o, sub(tgt, o));
                gg_hit h;
                gg_surf sf;
                int k;
                for (k = 0; k < 4; k++) {
                    if (!gg_geom_intersect(g, &q, &h) || h.prim != order[k]) {
                        print_error("scale %g%s: surface %d of 4 is prim %d, not %u\n", R,
                                    tr ? " translated" : "", k,
                                    gg_geom_intersect(g, &q, &h) ? (int)h.prim : -1, order[k]);
                        fail();
                    }
                    gg_geom_surface(g, &q, &h, &sf, GG_SURF_UV);
                    q.o = gg_offset_origin(&sf, q.d);
                    if (k == 1) {
                        /* from the inner sphere back out: the outer one */
                        gg_rayq back = ray(gg_offset_origin(&sf, mul(q.d, -1)), mul(q.d, -1));
                        gg_hit hb;
                        assert_true(gg_geom_intersect(g, &back, &hb));
                        assert_int_equal(hb.prim, 0);
                    }
                }
                assert_false(gg_geom_intersect(g, &q, &h));
            }
            gg_geom_free(g);
        }
    assert_int_equal(runs, 5);
}

static void test_offset_basics(void **state)
{
    gg_surf s;
    ggVec3 p;
    (void)state;
    s.p = V(1, 2, 3), s.ng = V(0, 0, 1), s.ns = s.ng, s.u = s.v = 0, s.perr = 1e-10;
    p = gg_offset_origin(&s, V(0, 1, 1));
    assert_true(p.z > 3 + GG_OFFSET_K * 1e-10 * 0.999 && p.x == 1 && p.y == 2);
    p = gg_offset_origin(&s, V(0, 1, -1));
    assert_true(p.z < 3 - GG_OFFSET_K * 1e-10 * 0.999);
    p = gg_offset_origin(&s, V(1, 0, 0)); /* tangent: the ng side */
    assert_true(p.z > 3);
    p = gg_offset_origin_fixed(&s, V(0, 0, -1), 1e-6);
    assert_close(p.z, 3 - 1e-6, 1e-15);
    p = gg_offset_origin_fixed(&s, V(0, 0, 1), 0.25);
    assert_true(p.z == 3.25);
    /* the scaled offset follows the error bound, not a constant */
    s.perr = 0;
    p = gg_offset_origin(&s, V(0, 0, 1));
    assert_true(p.z == nextafter(3, 4)); /* still at least one ulp off */
}

/* The last step of the scaled offset, one ulp further along the normal,
   against nextafter: random points of every magnitude and sign (zeros,
   subnormals, the largest doubles, infinities) and normals with zero
   components. */
static double ref_step(double x, double n)
{
    if (n > 0) return nextafter(x, INFINITY);
    if (n < 0) return nextafter(x, -INFINITY);
    return x;
}

static void test_offset_ulp_step(void **state)
{
    static const double special[] = {
        0.0,      -0.0, 0x1p-1074, -0x1p-1074,           0x1p-1022, -0x1p-1022, DBL_MAX,
        -DBL_MAX, 1.0,  -1.0,      0x1.fffffffffffffp-1, INFINITY,  -INFINITY};
    tu_rng r = {77};
    int i, k;
    (void)state;
    for (i = 0; i < 200000; i++) {
        gg_surf s;
        ggVec3 d, n, p, q;
        double c[3], m[3];
        for (k = 0; k < 3; k++) {
            if (tu_next(&r) % 4 == 0)
                c[k] = special[tu_next(&r) % (sizeof special / sizeof special[0])];
            else
                c[k] = ldexp(tu_range(&r, -1, 1), (int)(tu_next(&r) % 2100) - 1074);
            m[k] = tu_next(&r) % 5 == 0 ? 0.0 : tu_range(&r, -1, 1);
        }
        s.p = V(c[0], c[1], c[2]);
        s.ng = V(m[0], m[1], m[2]);
        s.ns = s.ng, s.u = s.v = 0;
        s.perr = tu_next(&r) % 3 == 0 ? 0.0 : ldexp(1, -(int)(tu_next(&r) % 60));
        d = tu_unit(&r);
        p = gg_offset_origin(&s, d);
        n = d.x * m[0] + d.y * m[1] + d.z * m[2] < 0 ? V(-m[0], -m[1], -m[2]) : s.ng;
        q = V(c[0] + n.x * (GG_OFFSET_K * s.perr), c[1] + n.y * (GG_OFFSET_K * s.perr),
              c[2] + n.z * (GG_OFFSET_K * s.perr));
        q = V(ref_step(q.x, n.x), ref_step(q.y, n.y), ref_step(q.z, n.z));
        assert_memory_equal(&p, &q, sizeof p);
    }
}

/* An implicit surface's offset follows its root tolerance, not the size
   of its box: a ball of radius 0.005 resting on the plane y = -1, written
   as f = y + 1 in a box 2e6 wide, shadows the plane just beside where it
   touches. The offset was 1e-9 of the box (8 * 0.002 along the normal:
   above the ball's top), and the contact shadow was lost. */
static void test_implicit_offset_follows_tolerance(void **state)
{
    gg_geom *g = gg_geom_create(NULL);
    ggImplicit *imp;
    ggError e;
    int i, blocked = 0;
    (void)state;
    assert_int_equal(
        ggImplicitCreateExpr("y + 1", V(-1e6, -2, -1e6), V(1e6, 0, 1e6), NULL, &imp, &e), GG_OK);
    assert_int_equal(gg_geom_add_implicit(g, imp, 0), 0);
    assert_true(gg_geom_add_sphere(g, V(0, -0.995, 0), 0.005, 1) >= 0);
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    for (i = 0; i < 8; i++) {
        /* plane points under the ball, 0.001 to 0.0045 from the contact */
        double x = 0.001 + 0.0005 * i, gap = 0.005 - sqrt(0.005 * 0.005 - x * x);
        /* straight down from the gap between the ball and the plane */
        gg_rayq q = ray(V(x, -1 + 0.5 * gap, 0), V(0, -1, 0)), sh;
        gg_hit h;
        gg_surf sf;
        uint32_t cache = 0;
        assert_true(gg_geom_intersect(g, &q, &h));
        assert_int_equal(h.prim, 0);
        gg_geom_surface(g, &q, &h, &sf, 0);
        sh = ray(gg_offset_origin(&sf, V(0, 1, 0)), V(0, 13, 0));
        sh.tmax = 1;
        blocked += gg_geom_occluded(g, &sh, &cache, NULL);
        if (i == 0)
            print_message("perr %.3g at the plane, tolerance %.3g\n", sf.perr,
                          gg_implicit_tolerance(imp));
    }
    assert_int_equal(blocked, 8);
    gg_geom_free(g);
    ggImplicitFree(imp);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_offset_basics),
        cmocka_unit_test(test_offset_ulp_step),
        cmocka_unit_test(test_no_rehits),
        cmocka_unit_test(test_fixed_epsilon_fails),
        cmocka_unit_test(test_nested_spheres),
        cmocka_unit_test(test_implicit_offset_follows_tolerance),
    };
    return cmocka_run_group_tests_name("offset", tests, NULL, NULL);
}
