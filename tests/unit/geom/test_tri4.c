/* SPDX-License-Identifier: MIT */
/*
** test_tri4.c -- the 4-wide triangle test of the AVX traversal (bvh_avx.c)
** gives the scalar kernel's bits: lane by lane on random triangles and on
** rays exactly through shared edges and vertices, and as whole queries
** (closest hit, any hit with its cache, shadow query) against the plain
** traversal on the same BVH and on a BVH built without the blocks (the
** AVX copy's single-ray walks run on the 8-wide tree, gg_bvh_wide: the
** queries check those too, and same_wide_tree that it holds exactly the
** 4-wide tree's leaves with the same boxes). Every build of the AVX copy
** the CPU runs (AVX, AVX2, AVX-512) is checked; the AVX-512 lane tests
** are TAP skips on a CPU without it. Skipped where the compiler or the
** CPU has no AVX copy.
*/
#include "testutil.h"

#include "bvh_int.h"
#include "scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#if GG_HAVE_BVH_AVX

static ggVec3 V3(double x, double y, double z)
{
    ggVec3 v;
    v.x = x, v.y = y, v.z = z;
    return v;
}

/* A random small dyadic number (k / 8, |k| <= 64): sums, differences and
   products of a few of them are exact, so edge functions of rays through
   vertices and edge midpoints come out exactly 0. */
static double dy(tu_rng *r)
{
    return (double)((int)(tu_next(r) % 129) - 64) / 8;
}

/* A direction whose shear constants are exact: the dominant component a
   power of two, the others small dyadic numbers below it. */
static ggVec3 dyadic_dir(tu_rng *r)
{
    double c[3];
    int k = (int)(tu_next(r) % 3), i;
    for (i = 0; i < 3; i++) c[i] = (double)((int)(tu_next(r) % 7) - 3) / 4;
    c[k] = tu_next(r) & 1 ? 1 : -1;
    return V3(c[0], c[1], c[2]);
}

static gg_tleaf *tleaf_new(void)
{
    void *p = NULL;
    assert_int_equal(posix_memalign(&p, 64, sizeof(gg_tleaf)), 0);
    return p;
}

static void tleaf_fill(gg_tleaf *L, const gg_ktri *t, int n)
{
    int k, ax, v;
    for (k = 0; k < 4; k++)
        for (ax = 0; ax < 3; ax++)
            for (v = 0; v < 3; v++) L->v[ax][v][k] = k < n ? t[k].v[v][ax] : NAN;
}

static void set_tri(gg_ktri *t, ggVec3 a, ggVec3 b, ggVec3 c)
{
    t->v[0][0] = a.x, t->v[0][1] = a.y, t->v[0][2] = a.z;
    t->v[1][0] = b.x, t->v[1][1] = b.y, t->v[1][2] = b.z;
    t->v[2][0] = c.x, t->v[2][1] = c.y, t->v[2][2] = c.z;
}

static ggVec3 vert(const gg_ktri *t, int v)
{
    return V3(t->v[v][0], t->v[v][1], t->v[v][2]);
}

static long nlane, nhit, nzero, nzero_hit;

/* A build of the 4-wide test (gg_bvh_tri4_avx, _avx2, _avx512). */
typedef unsigned (*tri4_fn)(const gg_tleaf *L, const gg_rpre *r, double tmax, double t[4],
                            double b1[4], double b2[4], unsigned *zero);

/* Which build the lane tests check against the scalar kernel: the AVX
   one (and its AVX2 build beside it where the CPU has AVX2), or the
   AVX-512 one (test_lanes_*_avx512). */
static tri4_fn lane_fn;

/* The AVX2 build of the same source: the same lanes, the same bits. */
static void same_as_avx2(const gg_tleaf *L, const gg_rpre *r, double tmax, int n, unsigned hit,
                         unsigned zero, const double *tt, const double *b1, const double *b2)
{
    double t2[4], c1[4], c2[4];
    unsigned z2, h2 = gg_bvh_tri4_avx2(L, r, tmax, t2, c1, c2, &z2);
    int k;
    assert_int_equal(h2, hit);
    assert_int_equal(z2, zero);
    for (k = 0; k < n; k++)
        if (hit >> k & 1) {
            assert_memory_equal(&t2[k], &tt[k], sizeof tt[k]);
            assert_memory_equal(&c1[k], &b1[k], sizeof b1[k]);
            assert_memory_equal(&c2[k], &b2[k], sizeof b2[k]);
        }
}

/* Every lane of the block against the scalar kernel for ray q. */
static void same_lanes(const gg_tleaf *L, const gg_ktri *t, int n, const gg_rayq *q)
{
    gg_rpre r;
    double tt[4], b1[4], b2[4], tmax = q->tmax;
    unsigned zero, hit;
    int k;
    if (!gg_rpre_init(&r, q)) return;
    hit = lane_fn(L, &r, tmax, tt, b1, b2, &zero);
    if (lane_fn == gg_bvh_tri4_avx && (gg_cpu_features() & GG_CPU_AVX2))
        same_as_avx2(L, &r, tmax, n, hit, zero, tt, b1, b2);
    assert_int_equal((hit | zero) >> n, 0); /* padding lanes never report */
    assert_int_equal(hit & zero, 0);
    for (k = 0; k < n; k++) {
        double st = 0, s1 = 0, s2 = 0;
        int sh = gg_tri_kernel(&t[k], &r, tmax, &st, &s1, &s2);
        nlane++;
        nhit += sh;
        if (zero >> k & 1) {
            /* left to the scalar kernel: the traversal asks it, as here */
            nzero++;
            nzero_hit += sh;
            continue;
        }
        if ((int)(hit >> k & 1) != sh) {
            print_error("lane %d: 4-wide %u, scalar %d; o (%a %a %a) d (%a %a %a)\n", k,
                        hit >> k & 1, sh, q->o.x, q->o.y, q->o.z, q->d.x, q->d.y, q->d.z);
            fail();
        }
        if (sh) {
            assert_memory_equal(&tt[k], &st, sizeof st);
            assert_memory_equal(&b1[k], &s1, sizeof s1);
            assert_memory_equal(&b2[k], &s2, sizeof s2);
        }
    }
}

static void lanes_random(tri4_fn fn)
{
    gg_geom *g = gg_geom_create(NULL);
    gg_tleaf *L = tleaf_new();
    tu_rng r = {77};
    long it;
    lane_fn = fn;
    nlane = nhit = 0;
    for (it = 0; it < 20000; it++) {
        gg_ktri t[4];
        int n = 1 + (int)(tu_next(&r) % 4), k, j;
        ggVec3 c = V3(tu_range(&r, -5, 5), tu_range(&r, -5, 5), tu_range(&r, -5, 5));
        double s = pow(10, tu_range(&r, -3, 3));
        for (k = 0; k < n; k++) {
            ggVec3 p[3];
            for (j = 0; j < 3; j++) {
                ggVec3 u = tu_unit(&r);
                p[j] = V3(c.x + s * u.x, c.y + s * u.y, c.z + s * u.z);
            }
            set_tri(&t[k], p[0], p[1], p[2]);
        }
        tleaf_fill(L, t, n);
        for (j = 0; j < 8; j++) {
            gg_rayq q;
            ggVec3 a = tu_unit(&r);
            q.o = V3(c.x + 3 * s * a.x, c.y + 3 * s * a.y, c.z + 3 * s * a.z);
            /* towards a random point of a random lane's triangle, or anywhere */
            if (j < 6) {
                const gg_ktri *tk = &t[tu_next(&r) % (uint64_t)n];
                double w1 = tu_uniform(&r), w2 = tu_uniform(&r) * (1 - w1);
                ggVec3 A = vert(tk, 0), B = vert(tk, 1), C = vert(tk, 2);
                ggVec3 p = V3(A.x + w1 * (B.x - A.x) + w2 * (C.x - A.x),
                              A.y + w1 * (B.y - A.y) + w2 * (C.y - A.y),
                              A.z + w1 * (B.z - A.z) + w2 * (C.z - A.z));
                q.d = V3(p.x - q.o.x, p.y - q.o.y, p.z - q.o.z);
            } else {
                q.d = tu_unit(&r);
            }
            q.tmin = j == 7 ? tu_range(&r, 0, 1) : 0;
            q.tmax = j == 5 ? tu_range(&r, 0, 2) : DBL_MAX;
            q.ignore_prim = UINT32_MAX, q.skip_flags = 0;
            q.inside = UINT32_MAX, q.opt = &gg_qopt_default;
            same_lanes(L, t, n, &q);
        }
    }
    print_message("random: %ld lanes, %ld hit\n", nlane, nhit);
    assert_true(nhit > nlane / 10 && nhit < nlane);
    free(L);
    gg_geom_free(g);
}

/* Fans of triangles around a shared vertex and strips sharing edges, on a
   dyadic grid, and rays along exact directions through their vertices
   and edge midpoints: the edge functions are then exactly 0 and the
   lanes go to the scalar kernel (which keeps exactly one triangle). */
static void lanes_edges(tri4_fn fn)
{
    gg_geom *g = gg_geom_create(NULL);
    gg_tleaf *L = tleaf_new();
    tu_rng r = {78};
    long it;
    lane_fn = fn;
    nlane = nhit = nzero = nzero_hit = 0;
    for (it = 0; it < 20000; it++) {
        gg_ktri t[4];
        ggVec3 c = V3(dy(&r), dy(&r), dy(&r)), p[5];
        int n = 2 + (int)(tu_next(&r) % 3), k, j, fan = (int)(tu_next(&r) & 1);
        for (k = 0; k < 5; k++) p[k] = V3(dy(&r), dy(&r), dy(&r));
        for (k = 0; k < n; k++) {
            if (fan)
                set_tri(&t[k], c, p[k], p[k + 1]); /* shares c and an edge with the next */
            else if (k & 1)
                set_tri(&t[k], p[k + 1], p[k], c); /* strip: c p0 p1 / p2 p1 c / ... */
            else
                set_tri(&t[k], c, p[k], p[k + 1]);
            if (k == 3 && fan) set_tri(&t[k], c, p[4], p[0]);
        }
        tleaf_fill(L, t, n);
        for (j = 0; j < 8; j++) {
            gg_rayq q;
            const gg_ktri *tk = &t[tu_next(&r) % (uint64_t)n];
            int v0 = (int)(tu_next(&r) % 3), v1 = (v0 + 1) % 3;
            ggVec3 A = vert(tk, v0), B = vert(tk, v1);
            /* a vertex, or the midpoint of an edge (exact on the grid) */
            ggVec3 aim = j & 1 ? A : V3(0.5 * (A.x + B.x), 0.5 * (A.y + B.y), 0.5 * (A.z + B.z));
            double back = (double)(1 + tu_next(&r) % 16);
            q.d = dyadic_dir(&r);
            q.o = V3(aim.x - back * q.d.x, aim.y - back * q.d.y, aim.z - back * q.d.z);
            q.tmin = 0;
            q.tmax = DBL_MAX;
            q.ignore_prim = UINT32_MAX, q.skip_flags = 0;
            q.inside = UINT32_MAX, q.opt = &gg_qopt_default;
            same_lanes(L, t, n, &q);
        }
    }
    print_message("edges: %ld lanes, %ld hit, %ld to the scalar kernel (%ld of them hit)\n", nlane,
                  nhit, nzero, nzero_hit);
    assert_true(nzero > nlane / 20);
    assert_true(nzero_hit > 0 && nzero_hit < nzero);
    free(L);
    gg_geom_free(g);
}

static void test_lanes_random(void **state)
{
    (void)state;
    lanes_random(gg_bvh_tri4_avx);
}

static void test_lanes_edges(void **state)
{
    (void)state;
    lanes_edges(gg_bvh_tri4_avx);
}

/* The AVX-512 build (mask registers in place of movemask): the same
   lanes against the scalar kernel; a TAP skip where the CPU has no
   AVX-512 (the AVX and AVX2 builds are still tested above). */
static void test_lanes_random_avx512(void **state)
{
    (void)state;
    if (!(gg_cpu_features() & GG_CPU_AVX512)) {
        print_message("the CPU cannot run AVX-512; skipped\n");
        skip();
    }
    lanes_random(gg_bvh_tri4_avx512);
}

static void test_lanes_edges_avx512(void **state)
{
    (void)state;
    if (!(gg_cpu_features() & GG_CPU_AVX512)) {
        print_message("the CPU cannot run AVX-512; skipped\n");
        skip();
    }
    lanes_edges(gg_bvh_tri4_avx512);
}

/* ---- whole queries: AVX copy against the plain one ---- */

static void same_hit(int ha, const gg_hit *a, int hb, const gg_hit *b)
{
    assert_int_equal(ha, hb);
    if (!ha) return;
    assert_int_equal(a->prim, b->prim);
    assert_int_equal(a->sub, b->sub);
    assert_memory_equal(&a->t, &b->t, sizeof a->t);
    assert_memory_equal(&a->b1, &b->b1, sizeof a->b1);
    assert_memory_equal(&a->b2, &b->b2, sizeof a->b2);
}

/* Every query of q on g (built with blocks) with copy lv of the AVX
   traversal (g->trav_avx: 1 the AVX copy, 2 its AVX2 build, 3 its
   AVX-512 build) and the plain
   one, and on g2 (the same scene built without the blocks, so with the
   plain cost model). cache[0..2] are the occluder caches of the three.
   Returns whether q hit anything. */
static int same_queries_at(gg_geom *g, const gg_geom *g2, const gg_rayq *q, uint32_t cache[3],
                           int lv)
{
    gg_hit h[3];
    gg_tcol tr[3];
    int r[3], s[3], sh[3], k, i;
    uint32_t oc[3];
    gg_rayq qs = *q;
    qs.skip_flags = GG_PRIM_TRANSPARENT;
    for (k = 0; k < 3; k++) {
        gg_geom *gk = k < 2 ? g : (gg_geom *)g2;
        g->trav_avx = k == 0 ? lv : 0;
        oc[k] = cache[k];
        r[k] = gg_geom_intersect(gk, q, &h[k]);
        s[k] = gg_geom_occluded(gk, q, &oc[k], NULL);
        sh[k] = gg_geom_occluded(gk, &qs, &cache[k], &tr[k]);
    }
    g->trav_avx = lv;
    for (k = 1; k < 3; k++) {
        same_hit(r[0], &h[0], r[k], &h[k]);
        assert_int_equal(s[0], s[k]);
        assert_int_equal(sh[0], sh[k]);
        assert_int_equal(tr[0].has_near, tr[k].has_near);
        if (!sh[0]) {
            same_hit(tr[0].has_near, &tr[0].near, tr[k].has_near, &tr[k].near);
            assert_int_equal(tr[0].complete, tr[k].complete);
            assert_int_equal(tr[0].n, tr[k].n);
            for (i = 0; i < tr[0].n && tr[0].complete; i++)
                same_hit(1, &tr[0].h[i], 1, &tr[k].h[i]);
        }
        if (k == 1) {
            /* An occluder exactly when there is one (g2's build, made
               without blocks, may order the slots differently). The AVX
               copy's walks visit the 8-wide tree in another order
               and may name another one; it blocks too if the plain copy,
               asked with it cached, keeps it. */
            uint32_t c = oc[0];
            gg_tcol again; /* (tr[2] is g2's answer, compared next) */
            assert_int_equal(oc[0] != 0, oc[k] != 0);
            assert_int_equal(cache[0] != 0, cache[k] != 0);
            g->trav_avx = 0;
            if (c) assert_true(gg_geom_occluded(g, q, &c, NULL) && c == oc[0]);
            c = cache[0];
            if (c) assert_true(gg_geom_occluded(g, &qs, &c, &again) && c == cache[0]);
            g->trav_avx = lv;
        }
    }
    return r[0];
}

/* same_queries_at for every copy g's build may take: the one it chose
   (the AVX-512 build where the CPU has AVX-512, else the AVX2 build
   where it has AVX2) and each below it down to the AVX copy. */
static int same_queries(gg_geom *g, const gg_geom *g2, const gg_rayq *q, uint32_t cache[3])
{
    const unsigned f = gg_cpu_features();
    const int top = g->trav_avx;
    int r = same_queries_at(g, g2, q, cache, top), lv;
    assert_int_equal(top, f & GG_CPU_AVX512 ? 3 : f & GG_CPU_AVX2 ? 2 : 1);
    for (lv = top - 1; lv >= 1; lv--) assert_int_equal(same_queries_at(g, g2, q, cache, lv), r);
    g->trav_avx = top;
    return r;
}

/* A height field of 2 * n * n triangles on a dyadic grid (shared edges
   and vertices everywhere), every third row transparent. */
static gg_geom *grid(int n, int avx, double (*h)[65])
{
    gg_geom *g = gg_geom_create(NULL);
    int i, j;
    gg_geom_set_cpu(g, avx ? GG_CPU_ALL : 0);
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++) {
            ggVec3 a = V3(i, j, h[i][j]), b = V3(i + 1, j, h[i + 1][j]);
            ggVec3 c = V3(i + 1, j + 1, h[i + 1][j + 1]), d = V3(i, j + 1, h[i][j + 1]);
            ggVec3 t1[3], t2[3];
            int p;
            t1[0] = a, t1[1] = b, t1[2] = c;
            t2[0] = a, t2[1] = c, t2[2] = d;
            p = gg_geom_add_triangle(g, t1, NULL, 0);
            assert_true(p >= 0);
            if (i % 3 == 1) gg_geom_set_flags(g, p, GG_PRIM_TRANSPARENT);
            p = gg_geom_add_triangle(g, t2, NULL, 0);
            assert_true(p >= 0);
            if (i % 3 == 1) gg_geom_set_flags(g, p, GG_PRIM_TRANSPARENT);
        }
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    return g;
}

static void test_grid_queries(void **state)
{
    static double h[65][65];
    tu_rng r = {79};
    gg_geom *g, *g2;
    uint32_t cache[3] = {0, 0, 0};
    long i, j, n = 0;
    (void)state;
    for (i = 0; i <= 64; i++)
        for (j = 0; j <= 64; j++) h[i][j] = (double)(tu_next(&r) % 9) / 4;
    g = grid(64, 1, h), g2 = grid(64, 0, h);
    assert_true(g->trav_avx && g->ntleaves > 0);
    assert_true(!g2->trav_avx && g2->ntleaves == 0);
    for (i = 0; i < 200000; i++) {
        gg_rayq q;
        /* through a grid vertex or an edge midpoint, exact directions,
           or a random ray */
        double x = (double)(tu_next(&r) % 129) / 2, y = (double)(tu_next(&r) % 129) / 2;
        double z = x == (int)x && y == (int)y ? h[(int)x][(int)y] : 1;
        double back = (double)(1 + tu_next(&r) % 8);
        if (i % 4 == 3) {
            q.o = V3(tu_range(&r, -8, 72), tu_range(&r, -8, 72), tu_range(&r, -4, 8));
            q.d = tu_unit(&r);
        } else {
            q.d = dyadic_dir(&r);
            q.o = V3(x - back * q.d.x, y - back * q.d.y, z - back * q.d.z);
        }
        q.tmin = 0;
        q.tmax = i % 5 == 0 ? back : INFINITY;
        q.ignore_prim = i % 7 == 0 ? (uint32_t)(tu_next(&r) % 8192) : UINT32_MAX;
        q.skip_flags = i % 11 == 0 ? GG_PRIM_TRANSPARENT : 0;
        q.inside = UINT32_MAX, q.opt = &gg_qopt_default;
        n += same_queries(g, g2, &q, cache);
    }
    print_message("grid: %ld of 200000 rays hit, same answers\n", n);
    assert_true(n > 50000);
    gg_geom_free(g);
    gg_geom_free(g2);
}

/* A height field of triangles under a layer of small spheres: rays from
   above pass sphere leaves before they reach a triangle block, so the
   closest-hit traversal's deferred set-up of the 4-wide test (bvh_avx.c)
   must be made on the first block it meets, whatever came before. */
/* A leaf reference with the box its parent holds for it. */
typedef struct leafbox {
    uint32_t ref;
    float b[6];
} leafbox;

static int leafbox_cmp(const void *a, const void *b)
{
    uint32_t x = ((const leafbox *)a)->ref, y = ((const leafbox *)b)->ref;
    return x < y ? -1 : x > y;
}

/* The used lanes' leaves of wide node w, recursively; returns the number
   of wide nodes reached. */
static size_t wide_leaves(const gg_geom *g, uint32_t w, leafbox *out, size_t *n)
{
    size_t nodes = 1;
    int i, k;
    for (i = 0; i < 8; i++) {
        const gg_wnode *nd = &g->wnodes[w];
        uint32_t c = nd->child[i];
        if (nd->b[0][i] == INFINITY) { /* unused: inverted box, no child */
            assert_true(nd->b[3][i] == -INFINITY && c == GG_LEAF);
            continue;
        }
        if (!(c & GG_LEAF)) {
            assert_true(c < g->nwnodes);
            nodes += wide_leaves(g, c, out, n);
            continue;
        }
        out[*n].ref = c;
        for (k = 0; k < 6; k++) out[*n].b[k] = nd->b[k][i];
        ++*n;
    }
    return nodes;
}

/* The 8-wide tree holds every leaf of the 4-wide one once, with the same
   box, and every wide node is reached once. */
static void same_wide_tree(const gg_geom *g)
{
    size_t n4 = 0, n8 = 0, i;
    leafbox *a = calloc(4 * g->nnodes, sizeof *a), *b = calloc(4 * g->nnodes, sizeof *b);
    int c, k;
    /* at most one wide node per inner binary node, of which a 4-wide node holds <= 3 */
    assert_true(a && b && g->wnodes && g->nwnodes > 0 && g->nwnodes <= 3 * g->nnodes);
    for (i = 0; i < g->nnodes; i++)
        for (c = 0; c < 4; c++) {
            const gg_bnode *nd = &g->nodes[i];
            if (!(nd->child[c] & GG_LEAF) || nd->b[0][c] == INFINITY) continue;
            a[n4].ref = nd->child[c];
            for (k = 0; k < 6; k++) a[n4].b[k] = nd->b[k][c];
            n4++;
        }
    assert_int_equal(wide_leaves(g, 0, b, &n8), g->nwnodes);
    assert_int_equal(n4, n8);
    qsort(a, n4, sizeof *a, leafbox_cmp);
    qsort(b, n8, sizeof *b, leafbox_cmp);
    assert_memory_equal(a, b, n4 * sizeof *a);
    free(a);
    free(b);
}

static gg_geom *mixed(int n, int avx, double (*h)[65], tu_rng *r)
{
    gg_geom *g = grid(n, avx, h);
    int i;
    for (i = 0; i < n * n / 2; i++) {
        ggVec3 c = V3(tu_range(r, 0, n), tu_range(r, 0, n), tu_range(r, 3, 5));
        assert_true(gg_geom_add_sphere(g, c, tu_range(r, 0.05, 0.4), -1) >= 0);
    }
    assert_int_equal(gg_geom_build(g, NULL), GG_OK);
    return g;
}

static void test_mixed_queries(void **state)
{
    static double h[65][65];
    tu_rng r = {81}, r1 = {82}, r2 = {82};
    gg_geom *g, *g2;
    uint32_t cache[3] = {0, 0, 0};
    long i, j, n = 0, nsph = 0, ntri = 0;
    (void)state;
    for (i = 0; i <= 32; i++)
        for (j = 0; j <= 32; j++) h[i][j] = (double)(tu_next(&r) % 9) / 4;
    g = mixed(32, 1, h, &r1), g2 = mixed(32, 0, h, &r2);
    assert_true(g->trav_avx && g->ntleaves > 0);
    same_wide_tree(g);
    assert_true(g2->wnodes == NULL);
    for (i = 0; i < 100000; i++) {
        gg_rayq q;
        gg_hit hh;
        q.o = V3(tu_range(&r, -2, 34), tu_range(&r, -2, 34), tu_range(&r, 6, 9));
        q.d = V3(tu_range(&r, -0.3, 0.3), tu_range(&r, -0.3, 0.3), -1);
        q.tmin = 0;
        q.tmax = i % 5 == 0 ? tu_range(&r, 3, 9) : INFINITY;
        q.ignore_prim = UINT32_MAX;
        q.skip_flags = i % 11 == 0 ? GG_PRIM_TRANSPARENT : 0;
        q.inside = UINT32_MAX, q.opt = &gg_qopt_default;
        n += same_queries(g, g2, &q, cache);
        if (gg_geom_intersect(g, &q, &hh))
            gg_geom_prim_kind(g, hh.prim) == GG_SHAPE_SPHERE ? nsph++ : ntri++;
    }
    print_message("mixed: %ld of 100000 rays hit (%ld spheres, %ld triangles), same answers\n", n,
                  nsph, ntri);
    assert_true(nsph > 5000 && ntri > 20000);
    gg_geom_free(g);
    gg_geom_free(g2);
}

/* The SPD scenes that are mostly triangles, rays from the scene box. */
static void test_spd_queries(void **state)
{
    static const char *names[] = {"tetra", "gears", "teapot-s12", "mount"};
    int k;
    (void)state;
    for (k = 0; k < 4; k++) {
        char path[512];
        ggScene *sc = ggSceneCreate(NULL), *sc2 = ggSceneCreate(NULL);
        ggError err;
        gg_geom *g;
        ggVec3 lo, hi;
        tu_rng r = {80 + (unsigned)k};
        uint32_t cache[3] = {0, 0, 0};
        long i, n = 0;
        snprintf(path, sizeof path, "%s/%s.nff", tu_spd_dir(), names[k]);
        assert_int_equal(ggSceneLoadFile(sc, path, &err), GG_OK);
        assert_int_equal(ggScenePrepare(sc, &err), GG_OK);
        assert_int_equal(ggSceneLoadFile(sc2, path, &err), GG_OK);
        assert_int_equal(ggScenePrepare(sc2, &err), GG_OK);
        /* the same scene built again for the plain code only */
        gg_geom_set_cpu(sc2->geom, 0);
        assert_int_equal(gg_geom_build(sc2->geom, &err), GG_OK);
        g = sc->geom;
        assert_true(g->trav_avx && g->ntleaves > 0);
        assert_true(!sc2->geom->trav_avx && sc2->geom->ntleaves == 0);
        same_wide_tree(g);
        gg_geom_bounds(g, &lo, &hi);
        for (i = 0; i < 30000; i++) {
            gg_rayq q;
            q.o = V3(lo.x + (hi.x - lo.x) * tu_range(&r, -0.25, 1.25),
                     lo.y + (hi.y - lo.y) * tu_range(&r, -0.25, 1.25),
                     lo.z + (hi.z - lo.z) * tu_range(&r, -0.25, 1.25));
            q.d = tu_unit(&r);
            q.tmin = 0;
            q.tmax = i % 4 == 0 ? tu_range(&r, 0, hi.x - lo.x) : INFINITY;
            q.ignore_prim =
                i % 3 == 0 ? (uint32_t)(tu_next(&r) % gg_geom_prim_count(g)) : UINT32_MAX;
            q.skip_flags = 0, q.inside = UINT32_MAX, q.opt = &gg_qopt_default;
            n += same_queries(g, sc2->geom, &q, cache);
        }
        print_message("%-10s %zu triangle blocks, %zu wide nodes for %zu: %ld of 30000 rays hit, "
                      "same answers\n",
                      names[k], g->ntleaves, g->nwnodes, g->nnodes, n);
        assert_true(n > 1000);
        ggSceneFree(sc);
        ggSceneFree(sc2);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lanes_random),        cmocka_unit_test(test_lanes_edges),
        cmocka_unit_test(test_lanes_random_avx512), cmocka_unit_test(test_lanes_edges_avx512),
        cmocka_unit_test(test_mixed_queries),       cmocka_unit_test(test_grid_queries),
        cmocka_unit_test(test_spd_queries),
    };
    if (!(gg_cpu_features() & GG_CPU_AVX)) {
        printf("tri4: the CPU cannot run AVX; skipped\n");
        return 0;
    }
    return cmocka_run_group_tests_name("tri4", tests, NULL, NULL);
}

#else

#include <stdio.h>

int main(void)
{
    printf("tri4: no AVX copy of the traversal in this build; skipped\n");
    return 0;
}

#endif
