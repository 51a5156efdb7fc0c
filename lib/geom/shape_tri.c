/* SPDX-License-Identifier: MIT */
/*
** shape_tri.c -- triangle bounds and surface (the watertight intersection
** kernel is in shape_tri.h).
*/
#include "shape_tri.h"

void gg_tri_bounds(const gg_ktri *t, double lo[3], double hi[3])
{
    int k;
    for (k = 0; k < 3; k++) {
        double a = t->v[0][k], b = t->v[1][k], c = t->v[2][k];
        lo[k] = a < b ? (a < c ? a : c) : (b < c ? b : c);
        hi[k] = a > b ? (a > c ? a : c) : (b > c ? b : c);
    }
}

ggVec3 gg_tri_point(const gg_ktri *t, double b1, double b2, double *perr)
{
    double b0 = 1 - b1 - b2, e = 0;
    double p[3];
    int k;
    /* The barycentric sum stays on the triangle's plane whatever the error
       of b1, b2 (the weights sum to 1); its error is gamma(7) times the sum
       of the absolute terms (pbrt, 3.9.4), independent of the ray. */
    for (k = 0; k < 3; k++) {
        double a0 = b0 * t->v[0][k], a1 = b1 * t->v[1][k], a2 = b2 * t->v[2][k];
        double s = fabs(a0) + fabs(a1) + fabs(a2);
        p[k] = a0 + a1 + a2;
        if (s > e) e = s;
    }
    *perr = gg_gamma(7) * e;
    return v3(p[0], p[1], p[2]);
}

static double clamp01(double x)
{
    return x < 0 ? 0 : x > 1 ? 1 : x;
}

/* (u, v) = the barycentric weights of vertices 1 and 2. */
void gg_tri_surface(const gg_tri *t, const gg_rayq *q, const gg_hit *h, gg_surf *out, unsigned what)
{
    ggVec3 a = v3(t->k.v[0][0], t->k.v[0][1], t->k.v[0][2]);
    ggVec3 b = v3(t->k.v[1][0], t->k.v[1][1], t->k.v[1][2]);
    ggVec3 c = v3(t->k.v[2][0], t->k.v[2][1], t->k.v[2][2]);
    ggVec3 ng = v3norm(v3cross(v3sub(b, a), v3sub(c, a)));
    (void)q;
    out->p = gg_tri_point(&t->k, h->b1, h->b2, &out->perr);
    if (t->flip) ng = v3neg(ng);
    out->ng = ng;
    out->ns = ng;
    if (t->has_n) {
        double b0 = 1 - h->b1 - h->b2;
        ggVec3 ns =
            v3add(v3add(v3scale(t->n[0], b0), v3scale(t->n[1], h->b1)), v3scale(t->n[2], h->b2));
        ns = v3norm(ns);
        if (v3dot(ns, ng) > 0) out->ns = ns;
    }
    out->u = what & GG_SURF_UV ? clamp01(h->b1) : 0;
    out->v = what & GG_SURF_UV ? clamp01(h->b2) : 0;
}
