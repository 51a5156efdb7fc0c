/* SPDX-License-Identifier: MIT */
/*
** tessellate.c -- triangles of an implicit surface's zero set
** (ggImplicitTriangulate): marching tetrahedra over a grid in the box.
**
** The cells are as near cubes as whole counts allow (a flat box gets
** few layers, not flat cells: at the same count of cells a thin tube in
** a flat box is crossed by grid edges where flat cells would step over
** it). The grid is walked one layer of cells at a time (z from lo to
** hi), so besides the result only two layers of samples and of edge
** vertices are kept. Each cell is cut into the six Freudenthal-Kuhn tetrahedra: for
** each order (a, b, c) of the axes, the corners 0, e_a, e_a + e_b and
** e_a + e_b + e_c. Every edge of those tetrahedra runs from a grid point
** p to p + (a sum of distinct unit steps), so it is named by p and a
** 3-bit mask of the steps (1 .. 7), and neighbouring cells cut their
** shared faces the same way: a vertex made once per edge and looked up by
** that name makes the mesh closed.
*/
#include "implicit.h"

#include "vec.h"

#include <math.h>
#include <string.h>

#define REFINE 6 /* Illinois steps per edge vertex */
#define NONE   UINT32_MAX

typedef struct tri_res {
    ggTriangulation pub; /* first: the public pointer is this struct's */
    const ggAllocator *alloc;
    ggAllocator alloc_copy;
} tri_res;

typedef struct tess {
    const ggImplicit *imp;
    int n[3];    /* cells along x, y, z */
    size_t side; /* n[0] + 1: grid points in a row of a layer */
    ggVec3 lo, hi;
    double *val[2];   /* f at the grid points of two z layers, side (n[1] + 1) each */
    uint32_t *eid[2]; /* vertex of edge (point, mask): [point * 8 + mask] */
    size_t vcap, tcap, max_tris;
    tri_res *r;
} tess;

static double coord(double lo, double hi, int i, int n)
{
    return i == n ? hi : lo + (hi - lo) * i / n;
}

static ggVec3 grid_point(const tess *t, int i, int j, int k)
{
    return v3(coord(t->lo.x, t->hi.x, i, t->n[0]), coord(t->lo.y, t->hi.y, j, t->n[1]),
              coord(t->lo.z, t->hi.z, k, t->n[2]));
}

static ggVec3 lerp(ggVec3 a, ggVec3 b, double s)
{
    return v3(a.x + s * (b.x - a.x), a.y + s * (b.y - a.y), a.z + s * (b.z - a.z));
}

/* The zero of f on [a, b] where f(a) = fa < 0 <= fb = f(b): linear
   interpolation refined by the Illinois method (false position that
   halves the value kept at an end twice in a row). Stops at an exact 0
   or a NaN (keeping the bracket it had). */
static ggVec3 edge_root(const ggImplicit *imp, ggVec3 a, ggVec3 b, double fa, double fb)
{
    double s0 = 0, s1 = 1, f0 = fa, f1 = fb, s, f;
    int k, side = 0;
    for (k = 0; k < REFINE; k++) {
        s = s0 + (s1 - s0) * (f0 / (f0 - f1));
        if (!(s > s0 && s < s1)) break;
        f = ggImplicitEval(imp, lerp(a, b, s));
        if (f == 0) return lerp(a, b, s);
        if (isnan(f)) break;
        if (f < 0) {
            s0 = s, f0 = f;
            if (side < 0) f1 /= 2;
            side = -1;
        } else {
            s1 = s, f1 = f;
            if (side > 0) f0 /= 2;
            side = 1;
        }
    }
    s = s0 + (s1 - s0) * (f0 / (f0 - f1));
    if (isnan(s)) s = 0.5 * (s0 + s1); /* both ends infinite */
    return lerp(a, b, s < s0 ? s0 : s > s1 ? s1 : s);
}

/* The vertex on the edge from grid point (i, j, k) along mask m (k is
   the cell layer's z, kz = 0 or 1 which of its two layers the point is
   on), made when first asked for. NONE when out of memory. */
static uint32_t edge_vertex(tess *t, int i, int j, int k, int kz, int m)
{
    ggTriangulation *r = &t->r->pub;
    size_t at = ((size_t)j * t->side + (size_t)i) * 8 + (size_t)m;
    uint32_t *slot = &t->eid[(k + kz) & 1][at];
    int i1 = i + (m & 1), j1 = j + (m >> 1 & 1), kz1 = kz + (m >> 2);
    double fa = t->val[(k + kz) & 1][(size_t)j * t->side + (size_t)i];
    double fb = t->val[(k + kz1) & 1][(size_t)j1 * t->side + (size_t)i1];
    ggVec3 a = grid_point(t, i, j, k + kz), b = grid_point(t, i1, j1, k + kz1), p, g, sw;
    double gl;
    if (*slot != NONE) return *slot;
    if (r->nverts == t->vcap) {
        size_t cap = t->vcap;
        if (gg_mem_grow(t->r->alloc, (void **)&r->verts, &cap, r->nverts + 1, sizeof *r->verts))
            return NONE;
        cap = t->vcap;
        if (gg_mem_grow(t->r->alloc, (void **)&r->normals, &cap, r->nverts + 1, sizeof *r->normals))
            return NONE;
        t->vcap = cap;
    }
    if (fa >= 0) { /* a the f < 0 end */
        double tmp = fa;
        fa = fb, fb = tmp;
        sw = a, a = b, b = sw;
    }
    p = edge_root(t->imp, a, b, fa, fb);
    g = ggGradientNormal(t->imp, p);
    gl = v3len(g);
    if (!(gl > 0) || !isfinite(gl)) g = v3sub(b, a), gl = v3len(g);
    r->verts[r->nverts] = p;
    r->normals[r->nverts] = v3scale(g, 1 / gl);
    *slot = (uint32_t)r->nverts;
    return (uint32_t)r->nverts++;
}

static int add_tri(tess *t, uint32_t a, uint32_t b, uint32_t c)
{
    ggTriangulation *r = &t->r->pub;
    if (a == NONE || b == NONE || c == NONE) return GG_ERROR_NOMEM;
    if (t->max_tris && r->ntris >= t->max_tris) return GG_ERROR_LIMIT;
    if (gg_mem_grow(t->r->alloc, (void **)&r->tris, &t->tcap, 3 * (r->ntris + 1), sizeof *r->tris))
        return GG_ERROR_NOMEM;
    r->tris[3 * r->ntris] = a, r->tris[3 * r->ntris + 1] = b, r->tris[3 * r->ntris + 2] = c;
    r->ntris++;
    return GG_OK;
}

/* Cell corner c (bit 0: +x, 1: +y, 2: +z) of cell (i, j, k) as a point. */
static ggVec3 corner(const tess *t, int i, int j, int k, int c)
{
    return grid_point(t, i + (c & 1), j + (c >> 1 & 1), k + (c >> 2));
}

/* The vertex on the edge between cell corners c and d. */
static uint32_t cut(tess *t, int i, int j, int k, int c, int d)
{
    int lo = c < d ? c : d, hi = c < d ? d : c; /* lo's bits are a subset of hi's */
    return edge_vertex(t, i + (lo & 1), j + (lo >> 1 & 1), k, lo >> 2, hi ^ lo);
}

static ggVec3 mid(ggVec3 a, ggVec3 b)
{
    return lerp(a, b, 0.5);
}

/* Does the triangle of the midpoints of edges (p, q), (p, r), (p, s)...
   face the wrong way? The triangles' orientation is decided on the
   midpoints of the cut edges (never degenerate in a tetrahedron of the
   grid), not on the vertices, which may coincide. out: a point on the
   f >= 0 side, in: one on the f < 0 side. */
static int flip(ggVec3 m0, ggVec3 m1, ggVec3 m2, ggVec3 in, ggVec3 out)
{
    return v3dot(v3cross(v3sub(m1, m0), v3sub(m2, m0)), v3sub(out, in)) < 0;
}

/* The triangles of tetrahedron c[0..3] (cell corners) of cell (i, j, k). */
static int tet(tess *t, int i, int j, int k, const int c[4])
{
    double f[4];
    int neg[4], pos[4], nn = 0, np = 0, q, rc;
    for (q = 0; q < 4; q++) {
        int cz = c[q] >> 2;
        size_t at = (size_t)(j + (c[q] >> 1 & 1)) * t->side + (size_t)(i + (c[q] & 1));
        f[q] = t->val[(k + cz) & 1][at];
        if (isnan(f[q])) return GG_OK;
        if (f[q] < 0)
            neg[nn++] = c[q];
        else
            pos[np++] = c[q];
    }
    if (!nn || !np) return GG_OK;
    if (nn == 1 || np == 1) {
        /* one corner o alone on its side: a triangle across its three edges */
        int o = nn == 1 ? neg[0] : pos[0], *rest = nn == 1 ? pos : neg, w;
        ggVec3 po = corner(t, i, j, k, o), m[3];
        uint32_t v[3];
        for (w = 0; w < 3; w++) m[w] = mid(po, corner(t, i, j, k, rest[w]));
        for (w = 0; w < 3; w++) v[w] = cut(t, i, j, k, o, rest[w]);
        /* the normal must point from the f < 0 side to the other */
        if (nn == 1 ? flip(m[0], m[1], m[2], po, m[0]) : flip(m[0], m[1], m[2], m[0], po))
            return add_tri(t, v[0], v[2], v[1]);
        return add_tri(t, v[0], v[1], v[2]);
    }
    {
        /* two and two: the quad (a c, a d, b d, b c), a b inside, c d outside */
        int a = neg[0], b = neg[1], cc = pos[0], d = pos[1];
        ggVec3 pa = corner(t, i, j, k, a), pb = corner(t, i, j, k, b);
        ggVec3 pc = corner(t, i, j, k, cc), pd = corner(t, i, j, k, d);
        ggVec3 mac = mid(pa, pc), mad = mid(pa, pd), mbd = mid(pb, pd);
        uint32_t vac = cut(t, i, j, k, a, cc), vad = cut(t, i, j, k, a, d);
        uint32_t vbd = cut(t, i, j, k, b, d), vbc = cut(t, i, j, k, b, cc);
        if (flip(mac, mad, mbd, mid(pa, pb), mid(pc, pd))) {
            if ((rc = add_tri(t, vac, vbd, vad))) return rc;
            return add_tri(t, vac, vbc, vbd);
        }
        if ((rc = add_tri(t, vac, vad, vbd))) return rc;
        return add_tri(t, vac, vbd, vbc);
    }
}

static void layer_values(tess *t, int k)
{
    double *v = t->val[k & 1];
    int i, j;
    for (j = 0; j <= t->n[1]; j++)
        for (i = 0; i <= t->n[0]; i++)
            v[(size_t)j * t->side + (size_t)i] = ggImplicitEval(t->imp, grid_point(t, i, j, k));
    memset(t->eid[k & 1], 0xff, sizeof(uint32_t) * 8 * t->side * ((size_t)t->n[1] + 1));
}

static int march(tess *t)
{
    /* the six orders of the axes (a, b, c): corners 0, a, a|b, 7 */
    static const int order[6][3] = {{1, 2, 4}, {1, 4, 2}, {2, 1, 4},
                                    {2, 4, 1}, {4, 1, 2}, {4, 2, 1}};
    int i, j, k, o, rc;
    layer_values(t, 0);
    for (k = 0; k < t->n[2]; k++) {
        layer_values(t, k + 1);
        for (j = 0; j < t->n[1]; j++)
            for (i = 0; i < t->n[0]; i++)
                for (o = 0; o < 6; o++) {
                    int c[4];
                    c[0] = 0, c[1] = order[o][0], c[2] = c[1] | order[o][1], c[3] = 7;
                    if ((rc = tet(t, i, j, k, c))) return rc;
                }
    }
    return GG_OK;
}

GG_API void ggTriangulationFree(ggTriangulation *t)
{
    const ggAllocator *a;
    if (!t) return;
    a = ((tri_res *)t)->alloc;
    gg_mem_free(a, t->verts);
    gg_mem_free(a, t->normals);
    gg_mem_free(a, t->tris);
    gg_mem_free(a, t);
}

/* Cells along each axis: `resolution` along the box's longest side,
   ceil(resolution side / longest) (at least 1) along the others. */
static void cell_counts(ggVec3 lo, ggVec3 hi, int resolution, int n[3])
{
    double e[3], l;
    int a;
    e[0] = hi.x - lo.x, e[1] = hi.y - lo.y, e[2] = hi.z - lo.z;
    l = fmax(e[0], fmax(e[1], e[2]));
    for (a = 0; a < 3; a++) {
        double c = l > 0 ? ceil(resolution * (e[a] / l)) : resolution;
        n[a] = !(c >= 1) ? 1 : c > resolution ? resolution : (int)c;
    }
}

GG_API int ggImplicitTriangulate(const ggImplicit *imp, int resolution, size_t max_triangles,
                                 const ggAllocator *alloc, ggTriangulation **out)
{
    tess t;
    tri_res *r;
    size_t layer;
    int rc = GG_OK, q;
    if (!imp || !out) return GG_ERROR_INVALID;
    *out = NULL;
    if (resolution < 1) return GG_ERROR_INVALID;
    if (resolution > GG_TRIANGULATE_MAX_RESOLUTION) return GG_ERROR_LIMIT;
    r = gg_mem_calloc(alloc, 1, sizeof *r);
    if (!r) return GG_ERROR_NOMEM;
    if (alloc) r->alloc_copy = *alloc, r->alloc = &r->alloc_copy;
    memset(&t, 0, sizeof t);
    t.imp = imp, t.r = r;
    t.max_tris = max_triangles;
    gg_implicit_bounds(imp, &t.lo, &t.hi);
    cell_counts(t.lo, t.hi, resolution, t.n);
    r->pub.resolution = resolution;
    for (q = 0; q < 3; q++) r->pub.cells[q] = t.n[q];
    t.side = (size_t)t.n[0] + 1;
    layer = t.side * ((size_t)t.n[1] + 1);
    for (q = 0; q < 2 && rc == GG_OK; q++) {
        t.val[q] = gg_mem_calloc(r->alloc, layer, sizeof *t.val[q]);
        t.eid[q] = gg_mem_calloc(r->alloc, 8 * layer, sizeof *t.eid[q]);
        if (!t.val[q] || !t.eid[q]) rc = GG_ERROR_NOMEM;
    }
    if (rc == GG_OK) rc = march(&t);
    for (q = 0; q < 2; q++) gg_mem_free(r->alloc, t.val[q]), gg_mem_free(r->alloc, t.eid[q]);
    if (rc != GG_OK) {
        ggTriangulationFree(&r->pub);
        return rc;
    }
    *out = &r->pub;
    return GG_OK;
}
