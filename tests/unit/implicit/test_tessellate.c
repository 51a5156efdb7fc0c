/* SPDX-License-Identifier: MIT */
/*
** test_tessellate.c -- ggImplicitTriangulate and ggSceneObjectTriangulate:
** on a sphere, the example torus and a callback sphere, every vertex on
** the zero set (|f| small against |grad f| times the cell), every normal
** unit and the renderer's gradient, every edge in exactly two triangles
** with opposite directions (closed and consistently oriented), the
** enclosed volume near the exact one; a box that cuts the surface (the
** open edges all on the cut face); near-cubic cells in flat boxes, and a
** tube thinner than a flat box's cells drawn whole; an empty box;
** undefined parts; the limits; every allocation failing in turn; threads; the scene's call.
*/
#include "testutil.h"

#include "implicit.h"
#include "vec.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TORUS "(x^2+y^2+z^2+1-0.35^2)^2 - 4*(x^2+y^2)"

static ggTriangulation *tri(const ggImplicit *imp, int n)
{
    ggTriangulation *t = NULL;
    assert_int_equal(ggImplicitTriangulate(imp, n, 0, NULL, &t), GG_OK);
    assert_non_null(t);
    assert_int_equal(t->resolution, n);
    return t;
}

/* ---- edges ---- */

typedef struct edge {
    uint32_t a, b; /* a < b */
    int dir;       /* +1: the triangle runs a -> b */
} edge;

static int edge_cmp(const void *x, const void *y)
{
    const edge *p = x, *q = y;
    if (p->a != q->a) return p->a < q->a ? -1 : 1;
    if (p->b != q->b) return p->b < q->b ? -1 : 1;
    return p->dir - q->dir;
}

/* Every undirected edge of t: how many are in exactly two triangles with
   opposite directions (*shared), how many in one (*open, each passed to
   on_open), and none in any other way. */
static void edges(const ggTriangulation *t, size_t *shared, size_t *open,
                  void (*on_open)(const ggTriangulation *, uint32_t, uint32_t, void *), void *ud)
{
    edge *e = malloc(sizeof *e * 3 * (t->ntris ? t->ntris : 1));
    size_t i, n = 0;
    assert_non_null(e);
    for (i = 0; i < t->ntris; i++) {
        int k;
        for (k = 0; k < 3; k++) {
            uint32_t a = t->tris[3 * i + k], b = t->tris[3 * i + (k + 1) % 3];
            assert_true(a != b); /* never two corners on one vertex */
            e[n].a = a < b ? a : b, e[n].b = a < b ? b : a, e[n].dir = a < b ? 1 : -1;
            n++;
        }
    }
    qsort(e, n, sizeof *e, edge_cmp);
    *shared = *open = 0;
    for (i = 0; i < n;) {
        size_t j = i;
        while (j < n && e[j].a == e[i].a && e[j].b == e[i].b) j++;
        if (j - i == 2) {
            if (e[i].dir != -1 || e[i + 1].dir != 1)
                print_error("edge %u-%u twice in one direction\n", e[i].a, e[i].b);
            assert_true(e[i].dir == -1 && e[i + 1].dir == 1);
            (*shared)++;
        } else {
            if (j - i != 1) print_error("edge %u-%u in %zu triangles\n", e[i].a, e[i].b, j - i);
            assert_int_equal(j - i, 1);
            (*open)++;
            if (on_open) on_open(t, e[i].a, e[i].b, ud);
        }
        i = j;
    }
    free(e);
}

/* ---- the whole mesh against f ---- */

typedef struct stats {
    double worst_f; /* largest |f| / (|grad f| cell) over the vertices */
    double volume;  /* signed, by the divergence theorem (closed meshes) */
    double facing;  /* share of triangles whose winding agrees with their normals */
} stats;

static stats check(const ggImplicit *imp, const ggTriangulation *t, double tol)
{
    ggVec3 lo, hi;
    double cell;
    size_t i, agree = 0, counted = 0;
    stats st = {0, 0, 0};
    ggImplicitBounds(imp, &lo, &hi);
    cell = fmax(hi.x - lo.x, fmax(hi.y - lo.y, hi.z - lo.z)) / t->resolution;
    for (i = 0; i < 3 * t->ntris; i++) assert_true(t->tris[i] < t->nverts);
    for (i = 0; i < t->nverts; i++) {
        ggVec3 p = t->verts[i], n = t->normals[i], g = ggGradientNormal(imp, p);
        double f = ggImplicitEval(imp, p), r = fabs(f) / (v3len(g) * cell);
        assert_true(p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z &&
                    p.z <= hi.z);
        assert_true(isfinite(f));
        if (r > st.worst_f) st.worst_f = r;
        if (!(r <= tol))
            print_error("vertex %zu (%g %g %g): f = %g, |grad f| = %g, cell %g\n", i, p.x, p.y, p.z,
                        f, v3len(g), cell);
        assert_true(r <= tol);
        assert_true(fabs(v3len(n) - 1) < 1e-12);
        assert_true(v3dot(n, v3norm(g)) > 1 - 1e-12); /* the renderer's normal */
    }
    for (i = 0; i < t->ntris; i++) {
        ggVec3 a = t->verts[t->tris[3 * i]], b = t->verts[t->tris[3 * i + 1]];
        ggVec3 c = t->verts[t->tris[3 * i + 2]];
        ggVec3 fn = v3cross(v3sub(b, a), v3sub(c, a));
        ggVec3 vn = v3add(v3add(t->normals[t->tris[3 * i]], t->normals[t->tris[3 * i + 1]]),
                          t->normals[t->tris[3 * i + 2]]);
        st.volume += v3dot(a, v3cross(b, c)) / 6;
        if (v3len(fn) > 1e-6 * cell * cell) {
            counted++;
            if (v3dot(fn, vn) > 0) agree++;
        }
    }
    st.facing = counted ? (double)agree / counted : 1;
    return st;
}

static void closed_surface(const char *expr, ggVec3 lo, ggVec3 hi, int n, double volume,
                           double vol_tol)
{
    ggImplicit *imp = tu_implicit(expr, lo, hi);
    ggTriangulation *t = tri(imp, n);
    size_t shared, open;
    stats st;
    assert_true(t->ntris > 0);
    st = check(imp, t, 1e-3);
    edges(t, &shared, &open, NULL, NULL);
    print_message("%s at %d: %zu vertices, %zu triangles, %zu edges, worst |f|/(|grad f| cell) "
                  "%.2g, volume %.5f (exact %.5f), winding agrees with normals on %.4f\n",
                  expr, n, t->nverts, t->ntris, shared, st.worst_f, st.volume, volume, st.facing);
    assert_int_equal(open, 0);
    /* Euler: V - E + F = 2 - 2 genus, each edge in two triangles */
    assert_int_equal(3 * t->ntris, 2 * shared);
    assert_true(fabs(st.volume - volume) <= vol_tol * volume);
    assert_true(st.facing > 0.99);
    ggTriangulationFree(t);
    ggImplicitFree(imp);
}

static void test_sphere_closed(void **state)
{
    (void)state;
    closed_surface("x^2+y^2+z^2-1", v3(-1.5, -1.5, -1.5), v3(1.5, 1.5, 1.5), 24, 4 * GG_PI / 3,
                   0.02);
    closed_surface("x^2+y^2+z^2-1", v3(-1.2, -1.3, -1.1), v3(1.4, 1.25, 1.3), 64, 4 * GG_PI / 3,
                   0.005);
    /* a coarse grid is still closed */
    closed_surface("x^2+y^2+z^2-1", v3(-1.5, -1.5, -1.5), v3(1.5, 1.5, 1.5), 4, 4 * GG_PI / 3, 0.6);
}

static void test_torus_closed(void **state)
{
    ggImplicit *imp;
    ggTriangulation *t;
    size_t shared, open;
    (void)state;
    /* examples/scenes/torus.nff: R = 1, r = 0.35, volume 2 pi^2 R r^2 */
    closed_surface(TORUS, v3(-1.4, -1.4, -0.4), v3(1.4, 1.4, 0.4), 64,
                   2 * GG_PI * GG_PI * 0.35 * 0.35, 0.02);
    closed_surface(TORUS, v3(-1.4, -1.4, -0.4), v3(1.4, 1.4, 0.4), 32,
                   2 * GG_PI * GG_PI * 0.35 * 0.35, 0.05);
    /* genus 1: V - E + F = 0 */
    imp = tu_implicit(TORUS, v3(-1.4, -1.4, -0.4), v3(1.4, 1.4, 0.4));
    t = tri(imp, 48);
    edges(t, &shared, &open, NULL, NULL);
    assert_int_equal(open, 0);
    assert_int_equal((long)t->nverts - (long)shared + (long)t->ntris, 0);
    ggTriangulationFree(t);
    ggImplicitFree(imp);
}

/* Connected pieces of t (triangles sharing a vertex), by union-find. */
static size_t root(size_t *up, size_t i)
{
    while (up[i] != i) i = up[i] = up[up[i]];
    return i;
}

static size_t pieces(const ggTriangulation *t)
{
    size_t *up = malloc(sizeof *up * (t->nverts ? t->nverts : 1)), i, n = 0;
    assert_non_null(up);
    for (i = 0; i < t->nverts; i++) up[i] = i;
    for (i = 0; i < 3 * t->ntris; i++) up[root(up, t->tris[i])] = root(up, t->tris[i - i % 3]);
    for (i = 0; i < t->nverts; i++) n += root(up, i) == i;
    free(up);
    return n;
}

/* The counts of cells: the resolution along the longest side, as many as
   keep the cells no longer than that along the others, at least one. */
static void test_cell_counts(void **state)
{
    static const struct {
        double lo[3], hi[3];
        int res, n[3];
    } c[] = {
        {{-1.5, -1.5, -1.5}, {1.5, 1.5, 1.5}, 24, {24, 24, 24}},
        {{-1.4, -1.4, -0.4}, {1.4, 1.4, 0.4}, 64, {64, 64, 19}}, /* 18.29 */
        {{0, 0, 0}, {0.5, 2, 1}, 8, {2, 8, 4}},                  /* whole ratios */
        {{-1.05, -1.05, -0.05}, {1.05, 1.05, 0.05}, 132, {132, 132, 7}},
        {{0, 0, 0}, {1, 1e-9, 1}, 256, {256, 1, 256}}, /* all but flat */
        {{0, 0, 0}, {1, 1, 1}, 1, {1, 1, 1}},
    };
    size_t i;
    int a;
    (void)state;
    for (i = 0; i < sizeof c / sizeof c[0]; i++) {
        ggImplicit *imp = tu_implicit("x^2+y^2+z^2-1", v3(c[i].lo[0], c[i].lo[1], c[i].lo[2]),
                                      v3(c[i].hi[0], c[i].hi[1], c[i].hi[2]));
        ggTriangulation *t = tri(imp, c[i].res);
        double longest = 0;
        for (a = 0; a < 3; a++) longest = fmax(longest, c[i].hi[a] - c[i].lo[a]);
        for (a = 0; a < 3; a++) {
            if (t->cells[a] != c[i].n[a])
                print_error("box %zu axis %d: %d cells, expected %d\n", i, a, t->cells[a],
                            c[i].n[a]);
            assert_int_equal(t->cells[a], c[i].n[a]);
            assert_true((c[i].hi[a] - c[i].lo[a]) / t->cells[a] <=
                        longest / c[i].res * (1 + 1e-12));
        }
        ggTriangulationFree(t);
        ggImplicitFree(imp);
    }
}

/* examples/scenes/acc-thin.nff's torus: a tube of radius 0.03 in a box
   2.1 x 2.1 x 0.1. Cells as flat as the box, 48^3 of them, are 0.044
   across: wider than the tube, which they drew in pieces. Near-cubic
   ones at about that count (132 x 132 x 7, 0.016 across) draw one closed
   surface of genus 1. */
static void test_thin_tube(void **state)
{
    ggImplicit *imp = tu_implicit("(x^2+y^2+z^2+1-0.03^2)^2 - 4*(x^2+y^2)", v3(-1.05, -1.05, -0.05),
                                  v3(1.05, 1.05, 0.05));
    ggTriangulation *t = tri(imp, 132);
    size_t shared, open, n;
    stats st = check(imp, t, 1e-3);
    double volume = 2 * GG_PI * GG_PI * 0.03 * 0.03;
    (void)state;
    edges(t, &shared, &open, NULL, NULL);
    n = pieces(t);
    print_message("thin tube at %d x %d x %d cells: %zu triangles, %zu piece(s), volume %.5f "
                  "(exact %.5f)\n",
                  t->cells[0], t->cells[1], t->cells[2], t->ntris, n, st.volume, volume);
    assert_true((long)t->cells[0] * t->cells[1] * t->cells[2] <= 48L * 48 * 48 * 12 / 10);
    assert_int_equal(open, 0);
    assert_int_equal(n, 1);
    assert_int_equal((long)t->nverts - (long)shared + (long)t->ntris, 0);
    assert_true(fabs(st.volume - volume) <= 0.1 * volume);
    ggTriangulationFree(t);
    ggImplicitFree(imp);
}

/* The open edges of a sphere cut by the plane z = 0.2 (the box's floor). */
static void on_floor(const ggTriangulation *t, uint32_t a, uint32_t b, void *ud)
{
    size_t *n = ud;
    assert_true(t->verts[a].z == 0.2 && t->verts[b].z == 0.2);
    (*n)++;
}

static void test_box_cuts_surface(void **state)
{
    ggImplicit *imp = tu_implicit("x^2+y^2+z^2-1", v3(-1.5, -1.5, 0.2), v3(1.5, 1.5, 1.5));
    ggTriangulation *t = tri(imp, 40);
    size_t shared, open, floor_edges = 0;
    stats st = check(imp, t, 1e-3);
    (void)state;
    edges(t, &shared, &open, on_floor, &floor_edges);
    print_message("cut sphere: %zu triangles, %zu open edges on the cut, worst %.2g\n", t->ntris,
                  open, st.worst_f);
    assert_true(open > 0);
    assert_int_equal(open, floor_edges);
    assert_true(st.facing > 0.99);
    ggTriangulationFree(t);
    ggImplicitFree(imp);
}

static void test_empty_box(void **state)
{
    static const char *exprs[] = {"x^2+y^2+z^2-1", "1", "-1", "sqrt(-1-x^2)"};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof exprs / sizeof exprs[0]; i++) {
        ggImplicit *imp = tu_implicit(exprs[i], v3(2, 2, 2), v3(3, 3, 3));
        ggTriangulation *t = tri(imp, 16);
        assert_int_equal(t->ntris, 0);
        assert_int_equal(t->nverts, 0);
        assert_null(t->tris);
        assert_null(t->verts);
        assert_null(t->normals);
        ggTriangulationFree(t);
        ggImplicitFree(imp);
    }
}

/* f undefined for x < -0.3 (where the sphere is not): no triangle there,
   and the rest as good as anywhere. */
static void test_undefined_parts(void **state)
{
    ggImplicit *imp =
        tu_implicit("x^2 + y^2 + z^2 - 1 + 0*sqrt(x + 0.3)", v3(-1, -1, -1), v3(1, 1, 1));
    ggTriangulation *t = tri(imp, 32);
    size_t i;
    (void)state;
    assert_true(t->ntris > 100);
    check(imp, t, 1e-3);
    for (i = 0; i < t->nverts; i++) assert_true(t->verts[i].x > -0.3);
    ggTriangulationFree(t);
    ggImplicitFree(imp);
}

static double sphere_fn(void *ud, ggVec3 p)
{
    (void)ud;
    return v3dot(p, p) - 1;
}

static void test_callbacks(void **state)
{
    ggImplicit *imp = NULL;
    ggTriangulation *t;
    size_t shared, open;
    (void)state;
    assert_int_equal(
        ggImplicitCreateFn(sphere_fn, NULL, NULL, v3(-2, -2, -2), v3(2, 2, 2), NULL, &imp, NULL),
        GG_OK);
    t = tri(imp, 20);
    check(imp, t, 1e-3);
    edges(t, &shared, &open, NULL, NULL);
    assert_int_equal(open, 0);
    assert_true(shared > 0);
    ggTriangulationFree(t);
    ggImplicitFree(imp);
}

static void test_limits(void **state)
{
    ggImplicit *imp = tu_implicit("x^2+y^2+z^2-1", v3(-1.5, -1.5, -1.5), v3(1.5, 1.5, 1.5));
    ggTriangulation *t = (ggTriangulation *)&t, *u;
    size_t all;
    (void)state;
    assert_int_equal(ggImplicitTriangulate(imp, 0, 0, NULL, &t), GG_ERROR_INVALID);
    assert_null(t);
    t = (ggTriangulation *)&t;
    assert_int_equal(ggImplicitTriangulate(imp, -5, 0, NULL, &t), GG_ERROR_INVALID);
    assert_null(t);
    t = (ggTriangulation *)&t;
    assert_int_equal(ggImplicitTriangulate(imp, GG_TRIANGULATE_MAX_RESOLUTION + 1, 0, NULL, &t),
                     GG_ERROR_LIMIT);
    assert_null(t);
    assert_int_equal(ggImplicitTriangulate(imp, 8, 0, NULL, NULL), GG_ERROR_INVALID);
    /* the smallest grids: one cell (corners all outside: nothing), two */
    t = tri(imp, 1);
    assert_int_equal(t->ntris, 0);
    ggTriangulationFree(t);
    t = tri(imp, 2);
    assert_true(t->ntris > 0);
    ggTriangulationFree(t);
    /* the largest: closed, 12 n^3 bounds it */
    t = tri(imp, GG_TRIANGULATE_MAX_RESOLUTION);
    assert_true(t->ntris > 0 && t->ntris <= 12.0 * 256 * 256 * 256);
    ggTriangulationFree(t);
    /* max_triangles: exactly enough passes, one fewer is GG_ERROR_LIMIT */
    t = tri(imp, 16);
    all = t->ntris;
    assert_int_equal(ggImplicitTriangulate(imp, 16, all, NULL, &u), GG_OK);
    assert_int_equal(u->ntris, all);
    /* the same call gives the same bytes */
    assert_int_equal(u->nverts, t->nverts);
    assert_memory_equal(u->verts, t->verts, sizeof *t->verts * t->nverts);
    assert_memory_equal(u->normals, t->normals, sizeof *t->normals * t->nverts);
    assert_memory_equal(u->tris, t->tris, sizeof *t->tris * 3 * t->ntris);
    ggTriangulationFree(u);
    u = (ggTriangulation *)&u;
    assert_int_equal(ggImplicitTriangulate(imp, 16, all - 1, NULL, &u), GG_ERROR_LIMIT);
    assert_null(u);
    ggTriangulationFree(t);
    ggImplicitFree(imp);
}

/* ---- allocation failure ---- */

static void test_nomem(void **state)
{
    tu_failer f;
    ggImplicit *imp = tu_implicit(TORUS, v3(-1.4, -1.4, -0.4), v3(1.4, 1.4, 0.4));
    ggTriangulation *ref = tri(imp, 12), *t;
    long k, total;
    (void)state;
    tu_failer_init(&f);
    assert_int_equal(ggImplicitTriangulate(imp, 12, 0, &f.alloc, &t), GG_OK);
    total = f.count;
    ggTriangulationFree(t);
    assert_int_equal(f.live, 0);
    for (k = 1; k <= total; k++) {
        tu_failer_arm(&f, k);
        t = (ggTriangulation *)&t;
        assert_int_equal(ggImplicitTriangulate(imp, 12, 0, &f.alloc, &t), GG_ERROR_NOMEM);
        assert_null(t);
        assert_int_equal(f.live, 0);
    }
    tu_failer_arm(&f, total + 1);
    assert_int_equal(ggImplicitTriangulate(imp, 12, 0, &f.alloc, &t), GG_OK);
    assert_false(f.failed);
    assert_int_equal(t->ntris, ref->ntris);
    assert_memory_equal(t->tris, ref->tris, sizeof *t->tris * 3 * t->ntris);
    assert_memory_equal(t->verts, ref->verts, sizeof *t->verts * t->nverts);
    ggTriangulationFree(t);
    assert_int_equal(f.live, 0);
    print_message("allocation failure: each of %ld allocations failed once\n", total);
    tu_failer_done(&f);
    ggTriangulationFree(ref);
    ggImplicitFree(imp);
}

/* ---- threads ---- */

typedef struct job {
    const ggImplicit *imp;
    ggTriangulation *t;
    int rc;
} job;

static void *run(void *p)
{
    job *j = p;
    j->rc = ggImplicitTriangulate(j->imp, 40, 0, NULL, &j->t);
    return NULL;
}

static void test_threads(void **state)
{
    ggImplicit *imp = tu_implicit(TORUS, v3(-1.4, -1.4, -0.4), v3(1.4, 1.4, 0.4));
    ggTriangulation *ref = tri(imp, 40);
    job j[4];
    pthread_t th[4];
    int i;
    (void)state;
    for (i = 0; i < 4; i++) {
        j[i].imp = imp, j[i].t = NULL;
        assert_int_equal(pthread_create(&th[i], NULL, run, &j[i]), 0);
    }
    for (i = 0; i < 4; i++) {
        pthread_join(th[i], NULL);
        assert_int_equal(j[i].rc, GG_OK);
        assert_int_equal(j[i].t->ntris, ref->ntris);
        assert_memory_equal(j[i].t->tris, ref->tris, sizeof *ref->tris * 3 * ref->ntris);
        assert_memory_equal(j[i].t->verts, ref->verts, sizeof *ref->verts * ref->nverts);
        ggTriangulationFree(j[i].t);
    }
    ggTriangulationFree(ref);
    ggImplicitFree(imp);
}

/* ---- the scene's call ---- */

static void test_scene(void **state)
{
    static const char text[] = "v from 0 -5 3 at 0 0 0 up 0 0 1 angle 40 resolution 8 6\n"
                               "l 2 3 4\nf 1 0.5 0.5 0.8 0.2 20 0 0\ns 3 0 0 0.5\n"
                               "implicit \"" TORUS "\" -1.4 -1.4 -0.4 1.4 1.4 0.4\n";
    tu_failer f;
    ggScene *s;
    ggImplicit *imp = tu_implicit(TORUS, v3(-1.4, -1.4, -0.4), v3(1.4, 1.4, 0.4));
    ggTriangulation *ref = tri(imp, 32), *t = (ggTriangulation *)&t, *u;
    (void)state;
    tu_failer_init(&f);
    s = ggSceneCreate(&f.alloc);
    assert_non_null(s);
    assert_int_equal(ggSceneLoadString(s, text, sizeof text - 1, "t.nff", NULL), GG_OK);
    assert_int_equal(ggSceneObjectKind(s, 1), GG_SHAPE_IMPLICIT);
    /* another kind, out of range, a bad resolution */
    assert_int_equal(ggSceneObjectTriangulate(s, 0, 32, 0, &t), GG_ERROR_UNSUPPORTED);
    assert_null(t);
    t = (ggTriangulation *)&t;
    assert_int_equal(ggSceneObjectTriangulate(s, 2, 32, 0, &t), GG_ERROR_INVALID);
    assert_null(t);
    assert_int_equal(ggSceneObjectTriangulate(s, -1, 32, 0, &t), GG_ERROR_INVALID);
    assert_int_equal(ggSceneObjectTriangulate(s, 1, 0, 0, &t), GG_ERROR_INVALID);
    assert_int_equal(ggSceneObjectTriangulate(s, 1, 257, 0, &t), GG_ERROR_LIMIT);
    /* unprepared, then prepared: the same mesh as the surface's own */
    assert_int_equal(ggSceneObjectTriangulate(s, 1, 32, 0, &t), GG_OK);
    assert_int_equal(ggScenePrepare(s, NULL), GG_OK);
    assert_int_equal(ggSceneObjectTriangulate(s, 1, 32, 0, &u), GG_OK);
    assert_int_equal(t->ntris, ref->ntris);
    assert_int_equal(u->ntris, ref->ntris);
    assert_memory_equal(t->verts, ref->verts, sizeof *t->verts * t->nverts);
    assert_memory_equal(u->tris, ref->tris, sizeof *t->tris * 3 * t->ntris);
    /* made with the scene's allocator, and outlives the scene */
    ggSceneFree(s);
    assert_true(f.live > 0);
    ggTriangulationFree(t);
    ggTriangulationFree(u);
    assert_int_equal(f.live, 0);
    tu_failer_done(&f);
    ggTriangulationFree(ref);
    ggImplicitFree(imp);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere_closed),    cmocka_unit_test(test_torus_closed),
        cmocka_unit_test(test_cell_counts),      cmocka_unit_test(test_thin_tube),
        cmocka_unit_test(test_box_cuts_surface), cmocka_unit_test(test_empty_box),
        cmocka_unit_test(test_undefined_parts),  cmocka_unit_test(test_callbacks),
        cmocka_unit_test(test_limits),           cmocka_unit_test(test_nomem),
        cmocka_unit_test(test_threads),          cmocka_unit_test(test_scene),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
