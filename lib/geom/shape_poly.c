/* SPDX-License-Identifier: MIT */
/*
** shape_poly.c -- planar polygons: plane, (u, v) frame, and the split
** into triangles (ear clipping) that lets the BVH bound the parts of a
** large concave polygon tightly and keeps shared edges watertight.
*/
#include "shape_poly.h"
#include "shape_tri.h"

#include <string.h>

/* Polygons larger than this stay whole: ear clipping is quadratic. */
#define GG_POLY_MAX_CLIP 4096

typedef struct clip2 {
    const double (*q)[2]; /* projected vertices */
    double sg;            /* +1 or -1: makes counter-clockwise positive */
} clip2;

static double orient(const clip2 *c, int a, int b, int d)
{
    const double *A = c->q[a], *B = c->q[b], *D = c->q[d];
    return c->sg * ((B[0] - A[0]) * (D[1] - A[1]) - (B[1] - A[1]) * (D[0] - A[0]));
}

static int same_pt(const clip2 *c, int a, int b)
{
    return c->q[a][0] == c->q[b][0] && c->q[a][1] == c->q[b][1];
}

/* Is the ear (p, i, n) free of the other remaining vertices? A vertex on
   the ear's boundary blocks it too, unless it coincides with a corner
   (polygons that touch themselves at a vertex). */
static int ear_empty(const clip2 *c, const int *next, int p, int i, int n)
{
    int j;
    /* The diagonal n-p first: most vertices lie beyond it. The corner
       test only for a vertex inside. */
    for (j = next[n]; j != p; j = next[j])
        if (orient(c, n, p, j) >= 0 && orient(c, p, i, j) >= 0 && orient(c, i, n, j) >= 0 &&
            !same_pt(c, j, p) && !same_pt(c, j, i) && !same_pt(c, j, n))
            return 0;
    return 1;
}

/* Squared length of the ear's diagonal p-n; -1 if i is not an ear, -2 if
   its corner is collinear (zero area). */
static double ear_score(const clip2 *c, const int *next, const int *prev, int i)
{
    int p = prev[i], n = next[i];
    double dx, dy, o = orient(c, p, i, n);
    if (o == 0) return -2;
    if (o < 0 || !ear_empty(c, next, p, i, n)) return -1;
    dx = c->q[n][0] - c->q[p][0], dy = c->q[n][1] - c->q[p][1];
    return dx * dx + dy * dy;
}

/* Ear clipping in the projection that drops the normal's dominant axis,
   always cutting the ear with the shortest diagonal: on the SPD gears'
   near-circular 144-gons a plain walk around the outline makes a fan of
   slivers that all span the gear, which a BVH cannot separate; shortest
   diagonals first give compact triangles. Ear status is cached and only
   the two neighbours of a cut are re-examined, so it is O(n^2).
   Writes up to nv - 2 index triples to tri[]; returns their count, or -1
   when the polygon cannot be split exactly (self-intersecting, or a
   numerical dead end): the caller then keeps the polygon whole. The areas
   of the pieces must add up to the polygon's area, which catches the
   cases where clipping "succeeds" on a polygon that overlaps itself. */
static int ear_clip(const clip2 *c, int nv, int *next, int *prev, double *score, int (*tri)[3])
{
    int i, left = nv, nt = 0, first = 0;
    double area = 0, asum = 0, scale = 0;
    for (i = 0; i < nv; i++) {
        next[i] = i + 1 < nv ? i + 1 : 0;
        prev[i] = i > 0 ? i - 1 : nv - 1;
        area += orient(c, 0, i, next[i]);
        if (fabs(c->q[i][0]) > scale) scale = fabs(c->q[i][0]);
        if (fabs(c->q[i][1]) > scale) scale = fabs(c->q[i][1]);
    }
    if (!(area > 0)) return -1;
    for (i = 0; i < nv; i++) score[i] = ear_score(c, next, prev, i);
    while (left > 3) {
        int best = -1, p, n, k;
        double bs = INFINITY;
        /* Collinear (zero-area) corners go first and make no triangle.
           score[] is current for every corner: a cut changes only those
           of its two neighbours, which are scored again below. */
        for (i = first, k = 0; k < left; k++, i = next[i]) {
            if (score[i] == -2) {
                best = i, bs = -1;
                break;
            }
            if (score[i] >= 0 && score[i] < bs) best = i, bs = score[i];
        }
        if (best < 0) return -1;
        p = prev[best], n = next[best];
        if (bs >= 0) {
            tri[nt][0] = p, tri[nt][1] = best, tri[nt][2] = n;
            nt++;
            asum += orient(c, p, best, n);
        }
        next[p] = n, prev[n] = p;
        first = n;
        left--;
        score[p] = ear_score(c, next, prev, p);
        score[n] = ear_score(c, next, prev, n);
    }
    {
        int p = prev[first], n = next[first];
        double o = orient(c, p, first, n);
        if (o < 0) return -1;
        if (o > 0) {
            tri[nt][0] = p, tri[nt][1] = first, tri[nt][2] = n;
            nt++;
            asum += o;
        }
    }
    /* Each orient() carries an error of a few ulps of the largest
       coordinate squared; allow that much per term. */
    if (fabs(asum - area) > 64 * GG_U * nv * scale * scale) return -1;
    return nt;
}

/* Do two edges that are not neighbours in the outline touch or cross?
   Ear clipping assumes a simple polygon; a pentagram, say, would be
   "clipped" into triangles that cover its centre twice (the area check
   cannot see that: a fan's signed areas always add up). Quadratic, so
   only done up to GG_POLY_MAX_SIMPLE vertices; larger polygons rely on
   the clipping and area checks. */
#define GG_POLY_MAX_SIMPLE 512
static int self_intersects(const clip2 *c, int nv)
{
    int i, j;
    if (nv > GG_POLY_MAX_SIMPLE) return 0;
    for (i = 0; i < nv; i++) {
        int i1 = i + 1 < nv ? i + 1 : 0;
        for (j = i + 2; j < nv; j++) {
            int j1 = j + 1 < nv ? j + 1 : 0;
            double a, b, d, e;
            if (j1 == i) continue; /* neighbours share a vertex */
            a = orient(c, i, i1, j), b = orient(c, i, i1, j1);
            if (!((a <= 0 && b >= 0) || (a >= 0 && b <= 0))) continue; /* most pairs */
            d = orient(c, j, j1, i), e = orient(c, j, j1, i1);
            if ((d <= 0 && e >= 0) || (d >= 0 && e <= 0)) {
                /* collinear and disjoint is not a contact */
                if (a == 0 && b == 0) {
                    int k;
                    double lo1, hi1, lo2, hi2;
                    k = fabs(c->q[i1][0] - c->q[i][0]) >= fabs(c->q[i1][1] - c->q[i][1]) ? 0 : 1;
                    lo1 = fmin(c->q[i][k], c->q[i1][k]), hi1 = fmax(c->q[i][k], c->q[i1][k]);
                    lo2 = fmin(c->q[j][k], c->q[j1][k]), hi2 = fmax(c->q[j][k], c->q[j1][k]);
                    if (hi1 < lo2 || hi2 < lo1) continue;
                }
                return 1;
            }
        }
    }
    return 0;
}

static int triangulate(gg_geom *g, const ggVec3 *p, int nv, ggVec3 nrm, gg_poly *out)
{
    int ax, X, Y, i, nt, ok = -1;
    double(*q)[2] = gg_mem_calloc(g->alloc, (size_t)nv, sizeof *q);
    int *next = gg_mem_calloc(g->alloc, (size_t)nv, sizeof *next);
    int *prev = gg_mem_calloc(g->alloc, (size_t)nv, sizeof *prev);
    double *score = gg_mem_calloc(g->alloc, (size_t)nv, sizeof *score);
    int(*tri)[3] = gg_mem_calloc(g->alloc, (size_t)nv, sizeof *tri);
    clip2 c;
    double an[3] = {fabs(nrm.x), fabs(nrm.y), fabs(nrm.z)}, nn[3] = {nrm.x, nrm.y, nrm.z};
    if (!q || !next || !prev || !score || !tri) goto done;
    ax = an[0] > an[1] ? (an[0] > an[2] ? 0 : 2) : (an[1] > an[2] ? 1 : 2);
    X = (ax + 1) % 3, Y = (ax + 2) % 3;
    for (i = 0; i < nv; i++) {
        /* Relative to vertex 0: smaller products, same topology. */
        q[i][0] = v3get(p[i], X) - v3get(p[0], X);
        q[i][1] = v3get(p[i], Y) - v3get(p[0], Y);
    }
    c.q = (const double(*)[2])q;
    c.sg = nn[ax] > 0 ? 1 : -1;
    nt = self_intersects(&c, nv) ? -1 : ear_clip(&c, nv, next, prev, score, tri);
    if (nt <= 0) {
        ok = 0; /* keep it whole */
        goto done;
    }
    if (gg_mem_grow(g->alloc, (void **)&g->pieces, &g->cap_pieces, g->npieces + (size_t)nt,
                    sizeof *g->pieces))
        goto done;
    out->piece_first = (uint32_t)g->npieces;
    out->npiece = (uint32_t)nt;
    for (i = 0; i < nt; i++) {
        gg_ktri *k = &g->pieces[g->npieces + (size_t)i];
        int j;
        for (j = 0; j < 3; j++) {
            ggVec3 v = p[tri[i][j]];
            k->v[j][0] = v.x, k->v[j][1] = v.y, k->v[j][2] = v.z;
        }
    }
    g->npieces += (size_t)nt;
    ok = 0;
done:
    gg_mem_free(g->alloc, q);
    gg_mem_free(g->alloc, next);
    gg_mem_free(g->alloc, prev);
    gg_mem_free(g->alloc, score);
    gg_mem_free(g->alloc, tri);
    return ok;
}

int gg_poly_prepare(gg_geom *g, const ggVec3 *p, int nv, gg_poly *out)
{
    int i;
    memset(out, 0, sizeof *out);
    if (gg_uv_plane_make(p, nv, &out->f)) return GG_GEOM_DEGENERATE;
    if (gg_mem_grow(g->alloc, (void **)&g->pverts, &g->cap_pverts, g->npverts + (size_t)nv,
                    sizeof *g->pverts))
        return GG_GEOM_NOMEM;
    out->vfirst = (uint32_t)g->npverts;
    out->nv = (uint32_t)nv;
    for (i = 0; i < nv; i++) {
        g->pverts[g->npverts + (size_t)i][0] = p[i].x;
        g->pverts[g->npverts + (size_t)i][1] = p[i].y;
        g->pverts[g->npverts + (size_t)i][2] = p[i].z;
    }
    out->piece_first = (uint32_t)g->npieces;
    if (g->poly_mode == GG_POLY_TRIANGULATE && nv <= GG_POLY_MAX_CLIP) {
        if (triangulate(g, p, nv, out->f.n, out)) return GG_GEOM_NOMEM;
    }
    g->npverts += (size_t)nv;
    return 0;
}

void gg_poly_bounds(const gg_geom *g, const gg_poly *pl, double lo[3], double hi[3])
{
    uint32_t i;
    int k;
    for (k = 0; k < 3; k++) lo[k] = INFINITY, hi[k] = -INFINITY;
    for (i = 0; i < pl->nv; i++) {
        const double *v = g->pverts[pl->vfirst + i];
        for (k = 0; k < 3; k++) {
            lo[k] = v[k] < lo[k] ? v[k] : lo[k];
            hi[k] = v[k] > hi[k] ? v[k] : hi[k];
        }
    }
}

/* ng = the Newell normal (front = counter-clockwise side). (u, v) = the
   point's coordinates in the plane frame (eu along the first edge, ev =
   n x eu), scaled so the polygon's bounding rectangle in that frame is
   [0,1]^2. */
void gg_poly_surface(const gg_geom *g, const gg_poly *pl, const gg_rayq *q, const gg_hit *h,
                     gg_surf *out, unsigned what)
{
    double uv[2];
    if (pl->npiece) {
        out->p = gg_tri_point(&g->pieces[h->sub], h->b1, h->b2, &out->perr);
    } else {
        /* Project o + t d onto the plane: the distance along the normal
           then has an error of a few ulps of |p| and |p0|, not of t. */
        ggVec3 p = v3madd(q->o, q->d, h->t);
        p = v3sub(p, v3scale(pl->f.n, v3dot(v3sub(p, pl->f.p0), pl->f.n)));
        out->p = p;
        out->perr = gg_gamma(8) * (v3maxabs(p) + v3maxabs(pl->f.p0));
    }
    out->ng = pl->f.n;
    out->ns = pl->f.n;
    out->u = out->v = 0;
    if (what & GG_SURF_UV) {
        gg_uv_plane_at(&pl->f, out->p, uv);
        out->u = uv[0], out->v = uv[1];
    }
}
