/* SPDX-License-Identifier: MIT */
/*
** shape_rect.c -- parametric rectangles corner + s e1 + t e2 (the
** intersection kernel is in shape_rect.h).
*/
#include "shape_rect.h"

/* The dual basis of edges whose |e1 x e2|^2 leaves the normal range
   (edges below about 2^-242: it went subnormal, 1 / |n|^2 infinite, and
   the rectangle was never hit): from the edges scaled by 2^-k (exact) to
   a largest component in [1, 2), the a_i scaled back by 2^-k; n is then
   the scaled edges' cross product (the kernel uses only its direction). */
static int dual_scaled(ggVec3 e1, ggVec3 e2, ggVec3 *n, ggVec3 *a1, ggVec3 *a2)
{
    double m = fmax(v3maxabs(e1), v3maxabs(e2)), nn;
    int k;
    if (!(m > 0)) return -1;
    k = ilogb(m);
    e1 = v3(ldexp(e1.x, -k), ldexp(e1.y, -k), ldexp(e1.z, -k));
    e2 = v3(ldexp(e2.x, -k), ldexp(e2.y, -k), ldexp(e2.z, -k));
    *n = v3cross(e1, e2), nn = v3dot(*n, *n);
    if (!(nn > 0) || !isfinite(nn)) return -1;
    *a1 = v3scale(v3cross(e2, *n), ldexp(1 / nn, -k));
    *a2 = v3scale(v3cross(*n, e1), ldexp(1 / nn, -k));
    return v3finite(*a1) && v3finite(*a2) ? 0 : -1;
}

/* The corners c, c + e1, (c + e1) + e2, c + e2: the kernel's edges, the
   bounds' box. -1 if one is not finite. */
static int set_corners(gg_krect *k, ggVec3 c, ggVec3 e1, ggVec3 e2)
{
    ggVec3 p[4];
    int i;
    p[0] = c, p[1] = v3add(c, e1), p[2] = v3add(p[1], e2), p[3] = v3add(c, e2);
    for (i = 0; i < 4; i++) {
        if (!v3finite(p[i])) return -1;
        k->v[i][0] = p[i].x, k->v[i][1] = p[i].y, k->v[i][2] = p[i].z;
    }
    return 0;
}

int gg_rect_prepare(ggVec3 corner, ggVec3 e1, ggVec3 e2, gg_rect *out)
{
    ggVec3 n = v3cross(e1, e2), a1, a2;
    double nn = v3dot(n, n);
    if (!v3finite(corner) || !v3finite(e1) || !v3finite(e2)) return -1;
    if (nn >= GG_VEC_SQ_MIN && isfinite(nn)) {
        /* Dual basis: a1 = (e2 x n) / |n|^2 gives a1.e1 = 1, a1.e2 = 0. */
        a1 = v3scale(v3cross(e2, n), 1 / nn);
        a2 = v3scale(v3cross(n, e1), 1 / nn);
    } else if (dual_scaled(e1, e2, &n, &a1, &a2)) {
        return -1;
    }
    if (set_corners(&out->k, corner, e1, e2)) return -1;
    out->k.n[0] = n.x, out->k.n[1] = n.y, out->k.n[2] = n.z;
    out->k.a1[0] = a1.x, out->k.a1[1] = a1.y, out->k.a1[2] = a1.z;
    out->k.a2[0] = a2.x, out->k.a2[1] = a2.y, out->k.a2[2] = a2.z;
    out->e1 = e1;
    out->e2 = e2;
    return 0;
}

void gg_rect_bounds(const gg_rect *r, double lo[3], double hi[3])
{
    int i, k;
    for (k = 0; k < 3; k++) lo[k] = INFINITY, hi[k] = -INFINITY;
    for (i = 0; i < 4; i++)
        for (k = 0; k < 3; k++) {
            double v = r->k.v[i][k];
            double pad = fabs(v) * 0x1p-48;
            lo[k] = v - pad < lo[k] ? v - pad : lo[k];
            hi[k] = v + pad > hi[k] ? v + pad : hi[k];
        }
}

/* (u, v) = (s, t) in [0,1]^2; ng = unit e1 x e2. */
void gg_rect_surface(const gg_rect *r, const gg_rayq *q, const gg_hit *h, gg_surf *out)
{
    ggVec3 c = v3(r->k.v[0][0], r->k.v[0][1], r->k.v[0][2]);
    ggVec3 a = v3scale(r->e1, h->b1), b = v3scale(r->e2, h->b2);
    ggVec3 n = v3unit(v3(r->k.n[0], r->k.n[1], r->k.n[2]));
    (void)q;
    /* From (s, t), not from o + t d: the point lies on the plane to a few
       ulps of the corner and edges whatever the ray's length. */
    out->p = v3add(c, v3add(a, b));
    out->perr = gg_gamma(4) * (v3maxabs(c) + v3maxabs(a) + v3maxabs(b));
    out->ng = n;
    out->ns = n;
    out->u = h->b1;
    out->v = h->b2;
}
