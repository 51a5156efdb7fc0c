/* SPDX-License-Identifier: MIT */
/*
** test_shapes.c -- each shape's hits, normals and (u, v) against closed
** forms computed in long double; the sphere's hard cases (far, tiny,
** translated); watertight triangle meshes and polygons; degenerate input.
*/
#include "testutil.h"

#include "geom_int.h"
#include "shape_tri.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static ggVec3 V(double x, double y, double z)
{
    ggVec3 v;
    v.x = x, v.y = y, v.z = z;
    return v;
}

static ggVec3 rvec(tu_rng *r, double lo, double hi)
{
    return V(tu_range(r, lo, hi), tu_range(r, lo, hi), tu_range(r, lo, hi));
}

static gg_rayq ray(ggVec3 o, ggVec3 d)
{
    gg_rayq q;
    q.o = o, q.d = d, q.tmin = 0, q.tmax = INFINITY;
    q.ignore_prim = UINT32_MAX, q.skip_flags = 0;
    q.inside = UINT32_MAX, q.opt = &gg_qopt_default;
    return q;
}

/* The plain any-hit query, without an occluder cache. */
static int occluded(const gg_geom *g, const gg_rayq *q)
{
    uint32_t none = 0;
    return gg_geom_occluded(g, q, &none, NULL);
}

/* One double ulp of |x|. */
static double ulp(double x)
{
    x = fabs(x);
    return x > 0 ? nextafter(x, INFINITY) - x : 0x1p-1074;
}

/* ---- the sphere's hard cases ---- */

typedef struct sph_case {
    const char *name;
    ggVec3 c;
    double r, dist; /* ray origins at this distance from c */
} sph_case;

typedef struct sph_stats {
    long wrong, band, hits, tbad;
} sph_stats;

/* Rays from `dist` away aimed at points spread over a disc of 1.5 r
   around the centre, with extra rays aimed within a few ulps of the
   silhouette. The long double reference decides hit/miss from the
   distance of the line from the centre; rays within K ulps (of the
   largest quantity involved, |o - c|) of the silhouette are the band
   where either answer is acceptable. A reported t must lie between the
   entry distances of spheres of radius r -+ band (the backward error),
   widened by 4 ulps. */
static sph_stats sphere_case(const sph_case *sc, int mode, int isect, int n, unsigned seed)
{
    gg_geom *g = gg_geom_create(NULL);
    tu_rng r = {seed};
    sph_stats st = {0, 0, 0, 0};
    gg_qopt opt = gg_qopt_default;
    /* float's ulps are 2^29 of double's: so are the band and the slack */
    double fscale = isect == GG_ISECT_FLOAT ? 0x1p29 : 1;
    int i;
    assert_true(gg_geom_add_sphere(g, sc->c, sc->r, 0) == 0);
    opt.sphere = mode; /* travels with each query */
    opt.isect = isect;
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    for (i = 0; i < n; i++) {
        ggVec3 u = tu_unit(&r), w, o, tgt, d;
        gg_rayq q;
        gg_hit h;
        long double fx, fy, fz, dd, fd, proj, lx, ly, lz, dist, band, R;
        double rad;
        int hit;
        o = V(sc->c.x + u.x * sc->dist, sc->c.y + u.y * sc->dist, sc->c.z + u.z * sc->dist);
        /* w: a unit vector perpendicular to u */
        w = fabs(u.x) < 0.9 ? V(0, -u.z, u.y) : V(-u.z, 0, u.x);
        {
            double l = sqrt(w.x * w.x + w.y * w.y + w.z * w.z);
            w = V(w.x / l, w.y / l, w.z / l);
        }
        rad =
            i % 4 == 0 ? sc->r * (1 + tu_range(&r, -8, 8) * 0x1p-52) : tu_range(&r, 0, 1.5) * sc->r;
        tgt = V(sc->c.x + w.x * rad, sc->c.y + w.y * rad, sc->c.z + w.z * rad);
        d = V(tgt.x - o.x, tgt.y - o.y, tgt.z - o.z);
        q = ray(o, d);
        q.opt = &opt;
        hit = gg_geom_intersect(g, &q, &h);

        fx = (long double)o.x - sc->c.x, fy = (long double)o.y - sc->c.y;
        fz = (long double)o.z - sc->c.z;
        dd = (long double)d.x * d.x + (long double)d.y * d.y + (long double)d.z * d.z;
        fd = fx * d.x + fy * d.y + fz * d.z;
        proj = -fd / dd;
        lx = fx + proj * d.x, ly = fy + proj * d.y, lz = fz + proj * d.z;
        dist = sqrtl(lx * lx + ly * ly + lz * lz);
        band = 4 * fscale * (long double)ulp(sc->dist > sc->r ? sc->dist : sc->r);
        R = sc->r;
        if (fabsl(dist - R) <= band) {
            st.band++;
        } else if ((dist < R) != hit) {
            st.wrong++;
        }
        if (hit) {
            long double Rb = R + band, Rs = R - band;
            long double tlo = proj - sqrtl((Rb * Rb - dist * dist) / dd);
            long double thi = dist < Rs ? proj - sqrtl((Rs * Rs - dist * dist) / dd) : proj;
            long double slack = 4 * fscale * (long double)ulp(h.t);
            st.hits++;
            if (!(h.t >= tlo - slack && h.t <= thi + slack)) st.tbad++;
        }
    }
    gg_geom_free(g);
    return st;
}

static const sph_case cases[] = {
    {"unit sphere seen from 1e6", {0, 0, 0}, 1, 1e6},
    {"1e-6 sphere from distance 1", {0.25, -0.5, 0.125}, 1e-6, 1},
    {"unit sphere at (1e5,1e5,1e5)", {1e5, 1e5, 1e5}, 1, 10},
};

static void test_sphere_hard_cases(void **state)
{
    int k;
    (void)state;
    for (k = 0; k < 3; k++) {
        sph_stats st =
            sphere_case(&cases[k], GG_SPHERE_STABLE, GG_ISECT_DOUBLE, 40000, 11 + (unsigned)k);
        print_message("%-30s stable: %ld wrong, %ld in band, %ld hits, %ld t off\n", cases[k].name,
                      st.wrong, st.band, st.hits, st.tbad);
        assert_int_equal(st.wrong, 0);
        assert_int_equal(st.tbad, 0);
        assert_true(st.hits > 10000);
    }
}

/* The stable formula in float (GG_ISECT_FLOAT) meets the same measure
   with float's ulps where the coordinates are of the size of |o - c|;
   at (1e5, 1e5, 1e5), seen from 10 away, the rounding of o and c to
   float (an ulp of 0.008) is far outside that band, and it fails. */
static void test_sphere_float(void **state)
{
    int k;
    (void)state;
    for (k = 0; k < 3; k++) {
        sph_stats st =
            sphere_case(&cases[k], GG_SPHERE_STABLE, GG_ISECT_FLOAT, 40000, 41 + (unsigned)k);
        print_message("%-30s float: %ld wrong, %ld in band, %ld hits, %ld t off\n", cases[k].name,
                      st.wrong, st.band, st.hits, st.tbad);
        if (k < 2) {
            assert_int_equal(st.wrong, 0);
            assert_int_equal(st.tbad, 0);
            assert_true(st.hits > 10000);
        } else {
            assert_true(st.wrong + st.tbad > 10000);
        }
    }
}

/* The same measure exposes the textbook formula on the far sphere: the
   test is able to fail. */
static void test_sphere_textbook_fails(void **state)
{
    sph_stats st = sphere_case(&cases[0], GG_SPHERE_TEXTBOOK, GG_ISECT_DOUBLE, 40000, 11);
    (void)state;
    print_message("%-30s textbook: %ld wrong, %ld t off\n", cases[0].name, st.wrong, st.tbad);
    assert_true(st.wrong + st.tbad > 100);
}

static void test_sphere_surface(void **state)
{
    gg_geom *g = gg_geom_create(NULL);
    tu_rng r = {5};
    ggVec3 c = V(3, -2, 7);
    int i;
    (void)state;
    gg_geom_add_sphere(g, c, 2, 0);
    gg_geom_build(g, NULL);
    for (i = 0; i < 2000; i++) {
        ggVec3 u = tu_unit(&r), o = V(c.x + 10 * u.x, c.y + 10 * u.y, c.z + 10 * u.z);
        ggVec3 d = V(c.x + tu_range(&r, -1, 1) - o.x, c.y + tu_range(&r, -1, 1) - o.y,
                     c.z + tu_range(&r, -1, 1) - o.z);
        gg_rayq q = ray(o, d);
        gg_hit h;
        gg_surf s;
        double rr, back;
        assert_true(gg_geom_intersect(g, &q, &h));
        gg_geom_surface(g, &q, &h, &s, GG_SURF_UV);
        rr = sqrt((s.p.x - c.x) * (s.p.x - c.x) + (s.p.y - c.y) * (s.p.y - c.y) +
                  (s.p.z - c.z) * (s.p.z - c.z));
        assert_true(fabs(rr - 2) <= 8 * ulp(10));
        assert_close(s.ng.x * s.ng.x + s.ng.y * s.ng.y + s.ng.z * s.ng.z, 1, 1e-15);
        /* outward, and the ray arrives against it */
        assert_true(s.ng.x * (s.p.x - c.x) + s.ng.y * (s.p.y - c.y) + s.ng.z * (s.p.z - c.z) > 0);
        assert_true(s.ng.x * d.x + s.ng.y * d.y + s.ng.z * d.z < 0);
        assert_true(s.u >= 0 && s.u < 1 && s.v >= 0 && s.v <= 1);
        /* (u, v) -> point */
        back = cos(s.v * GG_PI);
        assert_close(back, s.ng.z, 1e-12);
        assert_close(atan2(s.ng.y, s.ng.x), atan2(sin(2 * GG_PI * s.u), cos(2 * GG_PI * s.u)),
                     1e-9);
        assert_true(s.perr > 0 && s.perr < 1e-13);
        {
            /* without (u, v): the same point and normals */
            gg_surf s2;
            gg_geom_surface(g, &q, &h, &s2, 0);
            assert_true(s2.p.x == s.p.x && s2.p.y == s.p.y && s2.p.z == s.p.z);
            assert_true(s2.ng.x == s.ng.x && s2.ns.z == s.ns.z && s2.perr == s.perr);
            assert_true(s2.u == 0 && s2.v == 0);
        }
    }
    gg_geom_free(g);
}

/* A negative tmin (geom.h: "a negative tmin works") asks for the
   closest hit behind the origin too, so the kernel must return the
   smaller root first whatever the sign of b = (o - c).d. The stable form
   makes t0 = c/q the larger root when b >= 0 (the ray leaving the
   centre), which only the swap puts in order: a ray from (0, 0, 5) along
   +z, away from the unit sphere, has roots -6 and -4, and from the centre
   -1 and 1. Guards the t0 > t1 swap of gg_sphere_kernel (dropping it
   returns -4 and 1). Both formulas, several distances and directions. */
static void test_sphere_negative_tmin(void **state)
{
    static const int modes[2] = {GG_SPHERE_STABLE, GG_SPHERE_TEXTBOOK};
    static const ggVec3 dirs[3] = {{0, 0, 1}, {0, 0.6, 0.8}, {-1, 0, 0}};
    int m, k, j;
    (void)state;
    for (m = 0; m < 2; m++) {
        gg_geom *g = gg_geom_create(NULL);
        gg_qopt opt = gg_qopt_default;
        opt.sphere = modes[m];
        assert_true(gg_geom_add_sphere(g, V(0, 0, 0), 1, 0) == 0);
        assert_int_equal(gg_geom_build(g, NULL), GG_OK);
        for (k = 0; k < 3; k++) {
            ggVec3 d = dirs[k];
            for (j = 0; j < 4; j++) {
                /* origin s along d: behind it (s > 1) both roots are
                   negative, -s - 1 and -s + 1; at the centre -1 and 1 */
                double s = j == 0 ? 0 : j == 1 ? 5 : j == 2 ? 1.5 : 64;
                gg_rayq q = ray(V(s * d.x, s * d.y, s * d.z), d);
                gg_hit h;
                q.opt = &opt;
                q.tmin = -100;
                assert_true(gg_geom_intersect(g, &q, &h));
                assert_close(h.t, -s - 1, 4 * 0x1p-53);
                /* above the nearer root: the farther one */
                q.tmin = -s - 0.5;
                assert_true(gg_geom_intersect(g, &q, &h));
                assert_close(h.t, -s + 1, 4 * 0x1p-53);
            }
        }
        gg_geom_free(g);
    }
}

/* ---- triangles ---- */

static void test_triangle_basics(void **state)
{
    gg_geom *g = gg_geom_create(NULL);
    ggVec3 p[3] = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
    ggVec3 n[3] = {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
    ggVec3 flipped[3] = {{0, 0, -1}, {0, 0, -1}, {0, 0, -1}};
    gg_rayq q = ray(V(0.5, 0.25, 3), V(0, 0, -1));
    gg_hit h;
    gg_surf s;
    (void)state;
    assert_int_equal(gg_geom_add_triangle(g, p, n, 7), 0);
    assert_int_equal(gg_geom_add_triangle(g, p, flipped, 8), 1);
    p[0].z = p[1].z = p[2].z = -1;
    assert_int_equal(gg_geom_add_triangle(g, p, NULL, 9), 2);
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    assert_int_equal(gg_geom_prim_kind(g, 0), GG_SHAPE_TRIANGLE);
    assert_int_equal(gg_geom_prim_object(g, 1), 8);
    assert_true(gg_geom_intersect(g, &q, &h));
    assert_true(h.prim == 0 || h.prim == 1); /* same plane: the lower index wins */
    assert_int_equal(h.prim, 0);
    assert_true(h.t == 3);
    assert_close(h.b1, 0.25, 1e-15);
    assert_close(h.b2, 0.125, 1e-15);
    gg_geom_surface(g, &q, &h, &s, GG_SURF_UV);
    assert_vec_close(s.p, V(0.5, 0.25, 0), 1e-15);
    assert_vec_close(s.ng, V(0, 0, 1), 1e-15);
    /* ns = normalize(0.625 (0,0,1) + 0.25 (1,0,1) + 0.125 (0,1,1)), normals unit first */
    {
        double a = 1 / sqrt(2.0);
        ggVec3 e = V(0.25 * a, 0.125 * a, 0.625 + 0.375 * a);
        double l = sqrt(e.x * e.x + e.y * e.y + e.z * e.z);
        assert_vec_close(s.ns, V(e.x / l, e.y / l, e.z / l), 1e-14);
    }
    assert_close(s.u, 0.25, 1e-15);
    assert_close(s.v, 0.125, 1e-15);
    /* Vertex normals facing -z flip ng, so ns and ng agree. */
    q.ignore_prim = 0;
    assert_true(gg_geom_intersect(g, &q, &h));
    assert_int_equal(h.prim, 1);
    gg_geom_surface(g, &q, &h, &s, GG_SURF_UV);
    assert_vec_close(s.ng, V(0, 0, -1), 1e-15);
    assert_vec_close(s.ns, V(0, 0, -1), 1e-15);
    /* tmax is exclusive, tmin too */
    q.ignore_prim = UINT32_MAX;
    q.tmax = 3;
    assert_true(gg_geom_intersect(g, &q, &h) == 0);
    q.tmax = 4.5;
    q.tmin = 3;
    assert_true(gg_geom_intersect(g, &q, &h));
    assert_int_equal(h.prim, 2);
    gg_geom_free(g);
}

/* A subdivided octahedron pushed onto the unit sphere: vertices shared by
   index, so neighbouring triangles use bit-identical coordinates. */
typedef struct mesh {
    ggVec3 v[4096];
    int nv;
    int t[8192][3];
    int nt;
} mesh;

static int midpoint(mesh *m, int a, int b, int (*cache)[3], int *nc)
{
    int i;
    ggVec3 p;
    double l;
    for (i = 0; i < *nc; i++)
        if ((cache[i][0] == a && cache[i][1] == b) || (cache[i][0] == b && cache[i][1] == a))
            return cache[i][2];
    p = V((m->v[a].x + m->v[b].x) / 2, (m->v[a].y + m->v[b].y) / 2, (m->v[a].z + m->v[b].z) / 2);
    l = sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
    m->v[m->nv] = V(p.x / l, p.y / l, p.z / l);
    cache[*nc][0] = a, cache[*nc][1] = b, cache[*nc][2] = m->nv;
    (*nc)++;
    return m->nv++;
}

static void make_sphere_mesh(mesh *m, int levels)
{
    static const int oct[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                  {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    static int cache[12288][3];
    int i, l;
    m->nv = 6;
    m->v[0] = V(1, 0, 0), m->v[1] = V(-1, 0, 0), m->v[2] = V(0, 1, 0);
    m->v[3] = V(0, -1, 0), m->v[4] = V(0, 0, 1), m->v[5] = V(0, 0, -1);
    m->nt = 8;
    for (i = 0; i < 8; i++) m->t[i][0] = oct[i][0], m->t[i][1] = oct[i][1], m->t[i][2] = oct[i][2];
    for (l = 0; l < levels; l++) {
        int nt = m->nt, nc = 0;
        for (i = 0; i < nt; i++) {
            int a = m->t[i][0], b = m->t[i][1], c = m->t[i][2];
            int ab = midpoint(m, a, b, cache, &nc), bc = midpoint(m, b, c, cache, &nc);
            int ca = midpoint(m, c, a, cache, &nc);
            m->t[i][0] = a, m->t[i][1] = ab, m->t[i][2] = ca;
            m->t[m->nt][0] = ab, m->t[m->nt][1] = b, m->t[m->nt][2] = bc, m->nt++;
            m->t[m->nt][0] = ca, m->t[m->nt][1] = bc, m->t[m->nt][2] = c, m->nt++;
            m->t[m->nt][0] = ab, m->t[m->nt][1] = bc, m->t[m->nt][2] = ca, m->nt++;
        }
    }
}

/* Rays from outside aimed exactly at vertices, at points on shared edges
   and inside triangles of a closed convex mesh: each must be hit by
   exactly one triangle on the way in and one on the way out (counted by
   running the kernel on every triangle), and the BVH must find a hit.
   opt: the query's options (the precision); ttol: how far past the
   aimed-at point (t = 1) the entry may come out. */
static void watertight_run(const mesh *m, ggVec3 shift, double scale, unsigned seed,
                           const gg_qopt *opt, double ttol)
{
    gg_geom *g = gg_geom_create(NULL);
    tu_rng r = {seed};
    int i, k, ties = 0;
    ggVec3 *v = malloc(sizeof *v * (size_t)m->nv);
    assert_non_null(v);
    for (i = 0; i < m->nv; i++)
        v[i] = V(m->v[i].x * scale + shift.x, m->v[i].y * scale + shift.y,
                 m->v[i].z * scale + shift.z);
    for (i = 0; i < m->nt; i++) {
        ggVec3 p[3];
        p[0] = v[m->t[i][0]], p[1] = v[m->t[i][1]], p[2] = v[m->t[i][2]];
        assert_true(gg_geom_add_triangle(g, p, NULL, i) >= 0);
    }
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    for (k = 0; k < 3000; k++) {
        int tri = (int)(tu_next(&r) % (uint64_t)m->nt), kind = k % 3, j, nin = 0, nout = 0;
        ggVec3 a = v[m->t[tri][0]], b = v[m->t[tri][1]], c = v[m->t[tri][2]], tgt, o, d, u;
        gg_rayq q;
        gg_rpre rp;
        gg_hit h;
        double s = tu_uniform(&r);
        if (kind == 0)
            tgt = a; /* a shared vertex */
        else if (kind == 1)
            tgt = V(a.x + s * (b.x - a.x), a.y + s * (b.y - a.y), a.z + s * (b.z - a.z));
        else
            tgt = V((a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3, (a.z + b.z + c.z) / 3);
        /* from the outside, within 60 degrees of the outward direction */
        do {
            u = tu_unit(&r);
        } while (u.x * m->v[m->t[tri][0]].x + u.y * m->v[m->t[tri][0]].y +
                     u.z * m->v[m->t[tri][0]].z <
                 0.5);
        o = V(tgt.x + 3 * scale * u.x, tgt.y + 3 * scale * u.y, tgt.z + 3 * scale * u.z);
        d = V(tgt.x - o.x, tgt.y - o.y, tgt.z - o.z);
        q = ray(o, d);
        q.opt = opt;
        assert_true(gg_rpre_init(&rp, &q));
        /* every triangle record once (a clipped one has more than one slot) */
        for (j = 0; j < (int)(g->ntri + g->npieces + g->nmtri); j++) {
            double t, b1, b2;
            if (gg_tri_kernel(&g->ltri[j], &rp, INFINITY, &t, &b1, &b2)) {
                /* entering at the aimed-at point (t = 1), or leaving */
                if (t < 1 + ttol)
                    nin++;
                else
                    nout++;
                if (nin > 1) print_error("t %.17g tri %d\n", t, j);
            }
        }
        if (nin != 1 || nout != 1)
            print_error("ray %d (kind %d): %d triangles hit entering, %d leaving\n", k, kind, nin,
                        nout);
        assert_int_equal(nin, 1);
        assert_int_equal(nout, 1);
        assert_true(gg_geom_intersect(g, &q, &h));
        assert_true(h.t < 1 + ttol);
        ties += kind == 0;
    }
    assert_true(ties > 500);
    free(v);
    gg_geom_free(g);
}

static void test_watertight_mesh(void **state)
{
    static mesh m;
    (void)state;
    make_sphere_mesh(&m, 4); /* 2048 triangles */
    watertight_run(&m, V(0, 0, 0), 1, 21, &gg_qopt_default, 1e-6);
    watertight_run(&m, V(1e5, -3e4, 7e4), 1, 22, &gg_qopt_default, 1e-6);
    watertight_run(&m, V(0.5, 0.25, 0), 1e-4, 23, &gg_qopt_default, 1e-6);
    watertight_run(&m, V(0, 0, 0), 1e4, 24, &gg_qopt_default, 1e-6);
}

/* The single-precision triangle test (GG_ISECT_FLOAT) is watertight too:
   vertices rounded alike give neighbours exactly negated edge functions,
   and the zeros are settled in exact double arithmetic. Far from the
   origin the rounded mesh is still closed (t is then only float's). */
static void test_watertight_mesh_float(void **state)
{
    static mesh m;
    gg_qopt fl = gg_qopt_default;
    (void)state;
    fl.isect = GG_ISECT_FLOAT;
    make_sphere_mesh(&m, 4);
    watertight_run(&m, V(0, 0, 0), 1, 31, &fl, 1e-5);
    /* a float ulp of 0.5 is 2e-4 of the ray's length here */
    watertight_run(&m, V(0.5, 0.25, 0), 1e-4, 32, &fl, 1e-2);
    watertight_run(&m, V(0, 0, 0), 1e4, 33, &fl, 1e-5);
    watertight_run(&m, V(300, -100, 200), 1, 34, &fl, 1e-3);
}

/* ---- cones ---- */

/* Nearest root along the ray of the cone, in long double, or -1. */
static long double cone_ref(ggVec3 b, double rb, ggVec3 a, double ra, ggVec3 o, ggVec3 d)
{
    long double ax = (long double)a.x - b.x, ay = (long double)a.y - b.y,
                az = (long double)a.z - b.z;
    long double h = sqrtl(ax * ax + ay * ay + az * az), k = (ra - rb) / h, best = -1;
    long double wx = (long double)o.x - b.x, wy = (long double)o.y - b.y,
                wz = (long double)o.z - b.z;
    long double fz, dz, A, B, C, disc, t[2];
    int i;
    ax /= h, ay /= h, az /= h;
    fz = wx * ax + wy * ay + wz * az;
    dz = d.x * ax + d.y * ay + d.z * az;
    /* |w + t d|^2 - (z)^2 = (rb + k z)^2 with z = fz + t dz */
    A = (long double)d.x * d.x + (long double)d.y * d.y + (long double)d.z * d.z - dz * dz -
        k * k * dz * dz;
    B = wx * d.x + wy * d.y + wz * d.z - fz * dz - k * dz * (rb + k * fz);
    C = wx * wx + wy * wy + wz * wz - fz * fz - (rb + k * fz) * (rb + k * fz);
    disc = B * B - A * C;
    if (disc < 0 || A == 0) return -1;
    t[0] = (-B - sqrtl(disc)) / A, t[1] = (-B + sqrtl(disc)) / A;
    if (t[0] > t[1]) {
        long double x = t[0];
        t[0] = t[1], t[1] = x;
    }
    for (i = 0; i < 2; i++) {
        long double z = fz + t[i] * dz;
        if (t[i] > 0 && z >= 0 && z <= h) {
            best = t[i];
            break;
        }
    }
    return best;
}

static void test_cone(void **state)
{
    tu_rng r = {31};
    int trial, i, hits = 0;
    (void)state;
    for (trial = 0; trial < 40; trial++) {
        gg_geom *g = gg_geom_create(NULL);
        ggVec3 b = V(tu_range(&r, -5, 5), tu_range(&r, -5, 5), tu_range(&r, -5, 5));
        ggVec3 ax = tu_unit(&r), a;
        double h = tu_range(&r, 0.5, 3), rb = tu_range(&r, 0.1, 1);
        double ra = trial % 3 == 0 ? rb : trial % 3 == 1 ? 0 : tu_range(&r, 0.1, 1);
        a = V(b.x + h * ax.x, b.y + h * ax.y, b.z + h * ax.z);
        assert_int_equal(gg_geom_add_cone(g, b, rb, a, ra, 0), 0);
        assert_int_equal(gg_geom_build(g, NULL), GG_OK);
        for (i = 0; i < 500; i++) {
            ggVec3 o =
                V(b.x + tu_range(&r, -4, 4), b.y + tu_range(&r, -4, 4), b.z + tu_range(&r, -4, 4));
            double s = tu_uniform(&r);
            ggVec3 tgt = V(b.x + s * (a.x - b.x) + tu_range(&r, -1, 1),
                           b.y + s * (a.y - b.y) + tu_range(&r, -1, 1),
                           b.z + s * (a.z - b.z) + tu_range(&r, -1, 1));
            ggVec3 d = V(tgt.x - o.x, tgt.y - o.y, tgt.z - o.z);
            gg_rayq q = ray(o, d);
            gg_hit hh;
            long double tr = cone_ref(b, rb, a, ra, o, d);
            int hit = gg_geom_intersect(g, &q, &hh);
            if (tr > 0) {
                /* Grazing the rim or a silhouette is allowed either way. */
                if (!hit) continue;
                hits++;
                assert_close(hh.t, (double)tr, 1e-9);
                {
                    gg_surf sf;
                    double z, rr, rad;
                    ggVec3 w, n = V((a.x - b.x) / h, (a.y - b.y) / h, (a.z - b.z) / h);
                    gg_geom_surface(g, &q, &hh, &sf, GG_SURF_UV);
                    w = V(sf.p.x - b.x, sf.p.y - b.y, sf.p.z - b.z);
                    z = w.x * n.x + w.y * n.y + w.z * n.z;
                    rr = sqrt(w.x * w.x + w.y * w.y + w.z * w.z - z * z);
                    rad = rb + (ra - rb) * z / h;
                    assert_close(rr, rad, 1e-12);
                    assert_close(sf.v, z / h, 1e-12);
                    assert_true(sf.u >= 0 && sf.u < 1);
                    /* outward: away from the axis */
                    assert_true(sf.ng.x * (w.x - z * n.x) + sf.ng.y * (w.y - z * n.y) +
                                    sf.ng.z * (w.z - z * n.z) >=
                                0);
                    assert_close(sf.ng.x * sf.ng.x + sf.ng.y * sf.ng.y + sf.ng.z * sf.ng.z, 1,
                                 1e-14);
                }
            } else {
                assert_false(hit);
            }
        }
        /* open: straight down the axis from outside sees nothing (a cone
           with a zero radius would be hit at its tip) */
        if (ra > 0) {
            ggVec3 o = V(b.x - 10 * ax.x, b.y - 10 * ax.y, b.z - 10 * ax.z);
            gg_rayq q = ray(o, ax);
            gg_hit hh;
            assert_false(gg_geom_intersect(g, &q, &hh));
        }
        gg_geom_free(g);
    }
    assert_true(hits > 3000);
}

/* A long cylinder is split into height slices (separate BVH elements):
   rays aimed exactly at slice boundaries still hit once, at the right t,
   and the hit reports the cylinder. */
static void test_cone_slices(void **state)
{
    gg_geom *g = gg_geom_create(NULL);
    ggVec3 b = V(1, 2, 3), ax = V(0.6, 0, 0.8);
    double h = 24, r = 1;
    int i, k;
    (void)state;
    assert_int_equal(gg_geom_add_cone(g, b, r, V(b.x + h * ax.x, b.y, b.z + h * ax.z), r, 9), 0);
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    assert_int_equal((int)g->nslots, 8);
    for (k = 0; k <= 8; k++)
        for (i = 0; i < 16; i++) {
            double z = h * k / 8, ang = 2 * GG_PI * i / 16;
            /* the point at height z, angle ang; the ray comes in radially */
            ggVec3 n = V(-ax.z * cos(ang), sin(ang), ax.x * cos(ang));
            ggVec3 p =
                V(b.x + z * ax.x + r * n.x, b.y + z * ax.y + r * n.y, b.z + z * ax.z + r * n.z);
            gg_rayq q = ray(V(p.x + 5 * n.x, p.y + 5 * n.y, p.z + 5 * n.z), V(-n.x, -n.y, -n.z));
            gg_hit h1, h2;
            int f1 = gg_geom_intersect(g, &q, &h1), f2 = gg_geom_intersect_brute(g, &q, &h2);
            assert_int_equal(f1, f2);
            if (k > 0 && k < 8) assert_true(f1); /* the rims themselves may go either way */
            if (!f1) continue;
            assert_int_equal(h1.prim, 0);
            assert_true(h1.t == h2.t && h1.sub == h2.sub);
            /* at a rim the near point may round off the open end: then the
               far side (t = 7) is the right answer */
            if (k > 0 && k < 8) assert_close(h1.t, 5, 1e-12);
        }
    gg_geom_free(g);
}

/* ---- rectangles ---- */

static void test_rect(void **state)
{
    gg_geom *g = gg_geom_create(NULL);
    ggVec3 c = V(1, 2, 3), e1 = V(2, 0, 0), e2 = V(1, 3, 0); /* a parallelogram */
    tu_rng r = {41};
    int i;
    (void)state;
    assert_int_equal(gg_geom_add_rect(g, c, e1, e2, 4), 0);
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    assert_int_equal(gg_geom_prim_kind(g, 0), GG_SHAPE_RECT);
    for (i = 0; i < 5000; i++) {
        double s = tu_range(&r, -0.2, 1.2), t = tu_range(&r, -0.2, 1.2);
        ggVec3 p = V(c.x + s * e1.x + t * e2.x, c.y + s * e1.y + t * e2.y, c.z);
        ggVec3 o = V(p.x + tu_range(&r, -1, 1), p.y + tu_range(&r, -1, 1), 5);
        gg_rayq q = ray(o, V(p.x - o.x, p.y - o.y, p.z - o.z));
        gg_hit h;
        gg_surf sf;
        int in = s >= 0 && s <= 1 && t >= 0 && t <= 1, hit = gg_geom_intersect(g, &q, &h);
        if (fabs(s) < 1e-9 || fabs(s - 1) < 1e-9 || fabs(t) < 1e-9 || fabs(t - 1) < 1e-9) continue;
        assert_int_equal(hit, in);
        if (!hit) continue;
        gg_geom_surface(g, &q, &h, &sf, GG_SURF_UV);
        assert_close(sf.u, s, 1e-12);
        assert_close(sf.v, t, 1e-12);
        assert_vec_close(sf.p, p, 1e-13);
        assert_vec_close(sf.ng, V(0, 0, 1), 1e-15);
    }
    /* Just inside each corner, (s, t) stays in [0, 1]^2. */
    for (i = 0; i < 4; i++) {
        double s = i & 1 ? 1 - 0x1p-40 : 0x1p-40, t = i & 2 ? 1 - 0x1p-40 : 0x1p-40;
        gg_rayq q = ray(V(c.x + s * e1.x + t * e2.x, c.y + s * e1.y + t * e2.y, 5), V(0, 0, -1));
        gg_hit h;
        assert_true(gg_geom_intersect(g, &q, &h));
        assert_true(h.b1 >= 0 && h.b1 <= 1 && h.b2 >= 0 && h.b2 <= 1);
        assert_close(h.b1, s, 1e-12);
        assert_close(h.b2, t, 1e-12);
    }
    gg_geom_free(g);
}

/* Two rectangles side by side in one plane, sharing an edge (the
   second's corner is the first's c + e1, its e2 the first's), leave no
   crack: a ray aimed at a point of
   the shared edge hits one of them. Random parallelograms in random
   planes, rays from either side. An audit's harness let 208,427 of
   2,000,000 such rays through when each rectangle tested s and t on its
   own dual basis; rectangles now test their corners as polygons do. */
static void test_rect_shared_edge(void **state)
{
    tu_rng r = {43};
    int i, misses = 0;
    (void)state;
    for (i = 0; i < 400; i++) {
        ggVec3 c = rvec(&r, -2, 2), e1 = rvec(&r, -1, 1), e2 = rvec(&r, -1, 1), f1, c2;
        double a = tu_range(&r, 0.2, 2), b = tu_range(&r, -1, 1);
        gg_geom *g = gg_geom_create(NULL);
        int k;
        /* the second in the first's plane, beyond the shared edge */
        f1 = V(a * e1.x + b * e2.x, a * e1.y + b * e2.y, a * e1.z + b * e2.z);
        c2 = V(c.x + e1.x, c.y + e1.y, c.z + e1.z);
        if (gg_geom_add_rect(g, c, e1, e2, 0) < 0 || gg_geom_add_rect(g, c2, f1, e2, 1) < 0) {
            gg_geom_free(g);
            continue;
        }
        assert_int_equal(gg_geom_build(g, NULL), GG_OK);
        for (k = 0; k < 50; k++) {
            double f = tu_uniform(&r);
            ggVec3 p = V(c2.x + f * e2.x, c2.y + f * e2.y, c2.z + f * e2.z);
            ggVec3 o = rvec(&r, -8, 8);
            gg_rayq q = ray(o, V(p.x - o.x, p.y - o.y, p.z - o.z));
            gg_hit h;
            misses += !gg_geom_intersect(g, &q, &h);
        }
        gg_geom_free(g);
    }
    if (misses) print_error("%d of 20000 rays aimed at a shared edge missed both\n", misses);
    assert_int_equal(misses, 0);
}

/* ---- polygons ---- */

/* A gear outline like SPD gears' 144-gons: nt teeth on a circle. */
static int gear(ggVec3 *p, int nt, double r0, double r1, double z)
{
    int i, n = 0;
    for (i = 0; i < nt; i++) {
        double a = 2 * GG_PI * i / nt, da = 2 * GG_PI / nt;
        p[n++] = V(r0 * cos(a), r0 * sin(a), z);
        p[n++] = V(r1 * cos(a + 0.2 * da), r1 * sin(a + 0.2 * da), z);
        p[n++] = V(r1 * cos(a + 0.45 * da), r1 * sin(a + 0.45 * da), z);
        p[n++] = V(r0 * cos(a + 0.65 * da), r0 * sin(a + 0.65 * da), z);
    }
    return n;
}

/* Even-odd point-in-polygon in the xy plane, long double. */
static int inside_xy(const ggVec3 *p, int n, double x, double y)
{
    int i, j, in = 0;
    for (i = 0, j = n - 1; i < n; j = i++) {
        if ((p[i].y > y) != (p[j].y > y)) {
            long double xc = p[j].x + (long double)(y - p[j].y) * (p[i].x - p[j].x) /
                                          ((long double)p[i].y - p[j].y);
            if (x < xc) in = !in;
        }
    }
    return in;
}

static void polygon_run(int mode, int expect_pieces)
{
    gg_geom *g = gg_geom_create(NULL);
    ggVec3 p[144];
    tu_rng r = {51};
    int n = gear(p, 36, 0.234, 0.258, 1), i, hits = 0;
    g->poly_mode = mode;
    assert_int_equal(gg_geom_add_polygon(g, p, n, 3), 0);
    assert_int_equal(gg_geom_prim_kind(g, 0), GG_SHAPE_POLYGON);
    assert_int_equal(g->polys[0].npiece, (uint32_t)expect_pieces);
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    for (i = 0; i < 20000; i++) {
        double x = tu_range(&r, -0.27, 0.27), y = tu_range(&r, -0.27, 0.27);
        ggVec3 o = V(x + tu_range(&r, -0.1, 0.1), y + tu_range(&r, -0.1, 0.1), 2);
        gg_rayq q = ray(o, V(x - o.x, y - o.y, -1));
        gg_hit h;
        gg_surf sf;
        int in = inside_xy(p, n, x, y), hit = gg_geom_intersect(g, &q, &h), j;
        double dmin = 1;
        /* skip points within 1e-9 of an edge */
        for (j = 0; j < n; j++) {
            ggVec3 a = p[j], b = p[(j + 1) % n];
            double ex = b.x - a.x, ey = b.y - a.y, l = sqrt(ex * ex + ey * ey);
            double s = ((x - a.x) * ex + (y - a.y) * ey) / (l * l), dx, dy, dd;
            s = s < 0 ? 0 : s > 1 ? 1 : s;
            dx = x - a.x - s * ex, dy = y - a.y - s * ey;
            dd = sqrt(dx * dx + dy * dy);
            if (dd < dmin) dmin = dd;
        }
        if (dmin < 1e-9) continue;
        assert_int_equal(hit, in);
        if (!hit) continue;
        hits++;
        assert_close(h.t, 1, 1e-15);
        gg_geom_surface(g, &q, &h, &sf, GG_SURF_UV);
        assert_vec_close(sf.p, V(x, y, 1), 1e-15);
        assert_vec_close(sf.ng, V(0, 0, 1), 1e-15); /* counter-clockwise seen from +z */
        assert_true(sf.u >= 0 && sf.u <= 1 && sf.v >= 0 && sf.v <= 1);
    }
    assert_true(hits > 5000);
    gg_geom_free(g);
}

static void test_polygon_gear(void **state)
{
    (void)state;
    polygon_run(GG_POLY_TRIANGULATE, 142);
    polygon_run(GG_POLY_CROSSING, 0);
}

static int vertex_index(const ggVec3 *p, int n, const double *v)
{
    int i;
    for (i = 0; i < n; i++)
        if (p[i].x == v[0] && p[i].y == v[1] && p[i].z == v[2]) return i;
    return -1;
}

/* Triangulated pieces tile the polygon: the areas add up, and rays aimed
   exactly at points of the diagonals that pieces share hit exactly one
   piece. */
static void test_polygon_pieces_watertight(void **state)
{
    gg_geom *g = gg_geom_create(NULL);
    ggVec3 p[144];
    tu_rng r = {61};
    int n = gear(p, 36, 0.234, 0.258, 0.5), i, k, tested = 0;
    double area = 0, parea = 0;
    gg_rpre rp;
    (void)state;
    assert_int_equal(gg_geom_add_polygon(g, p, n, 0), 0);
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    for (i = 0; i < n; i++) area += p[i].x * p[(i + 1) % n].y - p[(i + 1) % n].x * p[i].y;
    for (i = 0; i < (int)g->npieces; i++) {
        const gg_ktri *pc = &g->pieces[i];
        const double(*v)[3] = (const double(*)[3])pc->v;
        double o =
            (v[1][0] - v[0][0]) * (v[2][1] - v[0][1]) - (v[1][1] - v[0][1]) * (v[2][0] - v[0][0]);
        assert_true(o > 0);
        parea += o;
    }
    assert_close(parea, area, 1e-13);
    for (k = 0; k < 5000; k++) {
        const double(*v)[3] = (const double(*)[3])g->pieces[tu_next(&r) % g->npieces].v;
        double s = tu_uniform(&r);
        int j = (int)(tu_next(&r) % 3), c = 0;
        ggVec3 a = V(v[j][0], v[j][1], v[j][2]),
               b = V(v[(j + 1) % 3][0], v[(j + 1) % 3][1], v[(j + 1) % 3][2]);
        ggVec3 tgt = V(a.x + s * (b.x - a.x), a.y + s * (b.y - a.y), a.z);
        ggVec3 o = V(tgt.x + tu_range(&r, -1, 1), tgt.y + tu_range(&r, -1, 1), 2);
        gg_rayq q = ray(o, V(tgt.x - o.x, tgt.y - o.y, tgt.z - o.z));
        int ia = vertex_index(p, n, v[j]), ib = vertex_index(p, n, v[(j + 1) % 3]);
        /* only diagonals: an edge of the outline has one piece on one side */
        assert_true(ia >= 0 && ib >= 0);
        if ((ia + 1) % n == ib || (ib + 1) % n == ia) continue;
        tested++;
        assert_true(gg_rpre_init(&rp, &q));
        for (i = 0; i < (int)(g->ntri + g->npieces + g->nmtri); i++) {
            double t, b1, b2;
            c += gg_tri_kernel(&g->ltri[i], &rp, INFINITY, &t, &b1, &b2);
        }
        assert_int_equal(c, 1);
    }
    assert_true(tested > 1000);
    gg_geom_free(g);
}

/* A self-intersecting pentagram cannot be split: it stays whole, and the
   crossing test gives the even-odd answer (its centre is out). */
static void test_polygon_pentagram(void **state)
{
    gg_geom *g = gg_geom_create(NULL);
    ggVec3 p[5];
    gg_rayq q;
    gg_hit h;
    int i;
    (void)state;
    for (i = 0; i < 5; i++) p[i] = V(cos(i * 4 * GG_PI / 5), sin(i * 4 * GG_PI / 5), 0);
    assert_int_equal(gg_geom_add_polygon(g, p, 5, 0), 0);
    assert_int_equal(g->polys[0].npiece, 0);
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    q = ray(V(0.8, 0.01, 1), V(0, 0, -1)); /* a tip */
    assert_true(gg_geom_intersect(g, &q, &h));
    q = ray(V(0.01, 0.02, 1), V(0, 0, -1)); /* the centre, covered twice */
    assert_false(gg_geom_intersect(g, &q, &h));
    q = ray(V(0.9, 0.5, 1), V(0, 0, -1)); /* between tips */
    assert_false(gg_geom_intersect(g, &q, &h));
    gg_geom_free(g);
}

/* A bow tie whose two lobes have equal and opposite areas: Newell's
   normal sums to 0, yet the polygon is planar and has a plane. Both lobes
   are hit (even-odd), as they are when one vertex moves by 1e-6 and the
   sum is not 0; in any plane, tilted and at every size from 2^-520 to
   2^500 (the polygon had vanished, gg_uv_plane_make refusing it). */
static void test_polygon_bow_tie(void **state)
{
    static const int exps[] = {-520, -300, 0, 300, 500};
    static const double corner[4][2] = {{-1, -1}, {1, 1}, {1, -1}, {-1, 1}};
    size_t e;
    int tilt;
    (void)state;
    for (e = 0; e < sizeof exps / sizeof *exps; e++)
        for (tilt = 0; tilt < 2; tilt++) {
            const double S = ldexp(1, exps[e]), c = tilt ? 0.6 : 1, sn = tilt ? 0.8 : 0;
            gg_geom *g = gg_geom_create(NULL);
            ggVec3 p[4];
            gg_rayq q;
            gg_hit h;
            int i, side;
            /* the bow tie in the plane spanned by x and (0, c, sn) */
            for (i = 0; i < 4; i++)
                p[i] = V(corner[i][0] * S, corner[i][1] * S * c, corner[i][1] * S * sn);
            assert_int_equal(gg_geom_add_polygon(g, p, 4, 0), 0);
            assert_int_equal(gg_geom_build(g, NULL), GG_OK);
            for (side = -1; side <= 1; side += 2) {
                /* the middle of the left and right lobes, and above the crossing */
                double y = 0.125 * S;
                q = ray(V(side * 0.5 * S, y * c, y * sn + 4 * S), V(0, 0, -1));
                if (!gg_geom_intersect(g, &q, &h))
                    fail_msg("2^%d, tilt %d: the %s lobe is not hit", exps[e], tilt,
                             side < 0 ? "left" : "right");
                assert_close(h.t / S, 4, 1e-12);
                q = ray(V(0, (side * 0.5 * S) * c, (side * 0.5 * S) * sn + 4 * S), V(0, 0, -1));
                assert_false(gg_geom_intersect(g, &q, &h));
            }
            gg_geom_free(g);
        }
}

static void test_degenerate(void **state)
{
    gg_geom *g = gg_geom_create(NULL);
    ggVec3 line[4] = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}};
    ggVec3 tri[3] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    ggVec3 o = V(0, 0, 0), x = V(1, 0, 0);
    (void)state;
    assert_int_equal(gg_geom_add_sphere(g, o, 0, 0), -1);
    assert_int_equal(gg_geom_add_sphere(g, o, -1, 0), -1);
    assert_int_equal(gg_geom_add_sphere(g, V(NAN, 0, 0), 1, 0), -1);
    assert_int_equal(gg_geom_add_sphere(g, o, INFINITY, 0), -1);
    assert_int_equal(gg_geom_add_triangle(g, tri, NULL, 0), -1);
    assert_int_equal(gg_geom_add_polygon(g, line, 4, 0), -1);
    assert_int_equal(gg_geom_add_polygon(g, line, 2, 0), -1);
    assert_int_equal(gg_geom_add_cone(g, o, 1, o, 1, 0), -1);
    assert_int_equal(gg_geom_add_cone(g, o, 0, x, 0, 0), -1);
    assert_int_equal(gg_geom_add_cone(g, o, -1, x, 1, 0), -1);
    assert_int_equal(gg_geom_add_rect(g, o, x, V(2, 0, 0), 0), -1);
    assert_int_equal(gg_geom_add_implicit(g, NULL, 0), -1);
    assert_int_equal((int)gg_geom_prim_count(g), 0);
    /* a valid one still gets index 0 */
    assert_int_equal(gg_geom_add_sphere(g, o, 1, 5), 0);
    assert_int_equal(gg_geom_prim_object(g, 0), 5);
    assert_int_equal(gg_geom_prim_object(g, 9), -1);
    assert_int_equal(gg_geom_prim_kind(g, 9), -1);
    /* rays that can hit nothing */
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    {
        gg_rayq q = ray(V(0, 0, 5), V(0, 0, 0));
        gg_hit h;
        assert_false(gg_geom_intersect(g, &q, &h));
        q.d = V(0, 0, NAN);
        assert_false(gg_geom_intersect(g, &q, &h));
        q.d = V(0, 0, -1), q.tmin = NAN;
        assert_false(gg_geom_intersect(g, &q, &h));
        assert_false(occluded(g, &q));
        q.tmin = 0;
        assert_true(gg_geom_intersect(g, &q, &h));
        /* an origin beyond float range still works (brute-force fallback) */
        q.o = V(0, 0, 1e200), q.d = V(0, 0, -1);
        assert_true(gg_geom_intersect(g, &q, &h));
        assert_true(occluded(g, &q));
        /* negative tmin too */
        q.o = V(0, 0, 5), q.tmin = -10;
        assert_true(gg_geom_intersect(g, &q, &h));
        assert_close(h.t, 4, 1e-15);
    }
    gg_geom_free(g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere_hard_cases),
        cmocka_unit_test(test_sphere_textbook_fails),
        cmocka_unit_test(test_sphere_float),
        cmocka_unit_test(test_sphere_surface),
        cmocka_unit_test(test_sphere_negative_tmin),
        cmocka_unit_test(test_triangle_basics),
        cmocka_unit_test(test_watertight_mesh),
        cmocka_unit_test(test_watertight_mesh_float),
        cmocka_unit_test(test_cone),
        cmocka_unit_test(test_cone_slices),
        cmocka_unit_test(test_rect),
        cmocka_unit_test(test_rect_shared_edge),
        cmocka_unit_test(test_polygon_gear),
        cmocka_unit_test(test_polygon_pieces_watertight),
        cmocka_unit_test(test_polygon_pentagram),
        cmocka_unit_test(test_polygon_bow_tie),
        cmocka_unit_test(test_degenerate),
    };
    return cmocka_run_group_tests_name("shapes", tests, NULL, NULL);
}
