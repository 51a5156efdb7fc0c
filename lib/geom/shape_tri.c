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

void gg_tri_set_normal(gg_tri *t)
{
    ggVec3 a = v3(t->k.v[0][0], t->k.v[0][1], t->k.v[0][2]);
    ggVec3 b = v3(t->k.v[1][0], t->k.v[1][1], t->k.v[1][2]);
    ggVec3 c = v3(t->k.v[2][0], t->k.v[2][1], t->k.v[2][2]);
    ggVec3 ng = v3unit(v3cross(v3sub(b, a), v3sub(c, a)));
    t->ng = t->flip ? v3neg(ng) : ng;
}

/* (u, v) = the barycentric weights of vertices 1 and 2. */
void gg_tri_surface(const gg_tri *t, const ggVec3 *n, const gg_rayq *q, const gg_hit *h,
                    gg_surf *out, unsigned what)
{
    const ggVec3 ng = t->ng;
    (void)q;
    out->p = gg_tri_point(&t->k, h->b1, h->b2, &out->perr);
    out->ng = ng;
    out->ns = ng;
    if (n) {
        double b0 = 1 - h->b1 - h->b2;
        ggVec3 ns = v3add(v3add(v3scale(n[0], b0), v3scale(n[1], h->b1)), v3scale(n[2], h->b2));
        ns = v3norm(ns);
        if (v3dot(ns, ng) > 0) out->ns = ns;
    }
    out->u = what & GG_SURF_UV ? clamp01(h->b1) : 0;
    out->v = what & GG_SURF_UV ? clamp01(h->b2) : 0;
}

/* gg_tri_kernel_f: see shape_tri.h. */
int gg_tri_kernel_f(const gg_ktri *tr, const gg_rpre *r, double tmax, double *t, double *b1,
                    double *b2)
{
    const int kx = r->kx, ky = r->ky, kz = r->kz;
    const double *A = tr->v[0], *B = tr->v[1], *C = tr->v[2];
    const float ox = gg_flt(r->o[kx]), oy = gg_flt(r->o[ky]), oz = gg_flt(r->o[kz]);
    const float sx = gg_flt(r->sx), sy = gg_flt(r->sy), sz = gg_flt(r->sz);
    float Az = gg_flt(A[kz]) - oz, Bz = gg_flt(B[kz]) - oz, Cz = gg_flt(C[kz]) - oz;
    float ax = gg_flt(A[kx]) - ox - sx * Az, ay = gg_flt(A[ky]) - oy - sy * Az;
    float bx = gg_flt(B[kx]) - ox - sx * Bz, by = gg_flt(B[ky]) - oy - sy * Bz;
    float cx = gg_flt(C[kx]) - ox - sx * Cz, cy = gg_flt(C[ky]) - oy - sy * Cz;
    float U = cx * by - cy * bx, V = ax * cy - ay * cx, W = bx * ay - by * ax;
    float det, T, rcp, tt;
    if (((U < 0) | (V < 0) | (W < 0)) & ((U > 0) | (V > 0) | (W > 0))) return 0;
    if (GG_UNLIKELY(U == 0 || V == 0 || W == 0)) {
        double Ud = (double)cx * by - (double)cy * bx, Vd = (double)ax * cy - (double)ay * cx;
        double Wd = (double)bx * ay - (double)by * ax, detd, Td, ttd;
        if (((Ud < 0) | (Vd < 0) | (Wd < 0)) & ((Ud > 0) | (Vd > 0) | (Wd > 0))) return 0;
        detd = Ud + Vd + Wd;
        if (detd == 0 || !gg_tri_zero_edge(Ud, Vd, Wd, ax, ay, bx, by, cx, cy)) return 0;
        Td = (double)sz * (Ud * Az + Vd * Bz + Wd * Cz);
        ttd = Td / detd;
        if (!(ttd > r->tmin && ttd <= tmax)) return 0;
        *t = ttd;
        *b1 = Vd / detd;
        *b2 = Wd / detd;
        return 1;
    }
    det = U + V + W;
    if (det == 0) return 0;
    T = sz * (U * Az + V * Bz + W * Cz);
    rcp = 1.0f / det;
    tt = T * rcp;
    if (!(tt > r->tmin && tt <= tmax)) return 0;
    *t = tt;
    *b1 = V * rcp;
    *b2 = W * rcp;
    return 1;
}
