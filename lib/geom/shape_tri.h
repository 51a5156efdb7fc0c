/* SPDX-License-Identifier: MIT */
/*
** shape_tri.h -- watertight ray/triangle intersection kernel (internal,
** inlined into the traversal loops).
*/
#ifndef GG_SHAPE_TRI_H
#define GG_SHAPE_TRI_H

#include "geom_int.h"

/* Whether a triangle whose edge function is exactly zero owns that edge
   (the ray passes exactly through it in ray space). (ex, ey) is the edge
   vector times the sign of the triangle's orientation; a neighbour that
   shares the edge sees exactly the negated vector, so exactly one of the
   two owns it -- the "top-left" rule of rasterisers. At a vertex the same
   rule leaves exactly one triangle of the fan. */
static inline int gg_tri_owns(double ex, double ey)
{
    return ey > 0 || (ey == 0 && ex > 0);
}

/* The tail of the triangle tests once the edge functions U, V, W (in
   double) are known, at least one of them exactly 0: the ray passes
   through an edge or vertex in ray space, and gg_tri_owns settles which
   triangle has it. (ax, ay) .. (cx, cy) are the sheared vertices, in
   whatever precision the edge functions came from. */
static inline int gg_tri_zero_edge(double U, double V, double W, double ax, double ay, double bx,
                                   double by, double cx, double cy)
{
    double s = U + V + W > 0 ? 1.0 : -1.0;
    if (U == 0 && !gg_tri_owns(s * (cx - bx), s * (cy - by))) return 0;
    if (V == 0 && !gg_tri_owns(s * (ax - cx), s * (ay - cy))) return 0;
    if (W == 0 && !gg_tri_owns(s * (bx - ax), s * (by - ay))) return 0;
    return 1;
}

/* The watertight test of gg_tri_kernel in single precision
   (GG_ISECT_FLOAT), as Woop, Benthin and Wald give it: the vertices,
   origin and shear are rounded to float and everything is computed in
   float. The edge functions then still have the exact sign of those of
   the float operands, or are 0 (rounding is monotonic: fl(a b) >= fl(c d)
   when a b >= c d); where one is 0 all three are recomputed in double
   from the same float operands, where each product is exact (24 + 24
   bits) and the difference is rounded once: exact signs, exact zeros.
   Neighbours round shared vertices alike, so the test stays watertight.
   t and the barycentrics carry float's 24 bits. */
int gg_tri_kernel_f(const gg_ktri *tr, const gg_rpre *r, double tmax, double *t, double *b1,
                    double *b2);

/* Woop, Benthin and Wald, "Watertight Ray/Triangle Intersection", JCGT
   2013, in double precision. The vertices are translated to the ray origin
   and sheared so that the ray becomes the +z axis; the 2D edge functions
   U, V, W of the origin then decide inside/outside. Two triangles sharing
   an edge compute bit-identical edge functions for it (same vertices, same
   operations, reversed order gives the exact negation), so no ray slips
   between them; ties are settled by gg_tri_owns. Returns 1 with t in
   (r->tmin, tmax] and the barycentrics of vertices 1 and 2. */
GG_INLINE int gg_tri_kernel(const gg_ktri *tr, const gg_rpre *r, double tmax, double *t, double *b1,
                            double *b2)
{
    const int kx = r->kx, ky = r->ky, kz = r->kz;
    const double *A = tr->v[0], *B = tr->v[1], *C = tr->v[2];
    double Az = A[kz] - r->o[kz], Bz = B[kz] - r->o[kz], Cz = C[kz] - r->o[kz];
    double ax = A[kx] - r->o[kx] - r->sx * Az, ay = A[ky] - r->o[ky] - r->sy * Az;
    double bx = B[kx] - r->o[kx] - r->sx * Bz, by = B[ky] - r->o[ky] - r->sy * Bz;
    double cx = C[kx] - r->o[kx] - r->sx * Cz, cy = C[ky] - r->o[ky] - r->sy * Cz;
    double U = cx * by - cy * bx, V = ax * cy - ay * cx, W = bx * ay - by * ax;
    double det, T, rcp, tt;
    /* Bitwise, not short-circuit: one unpredictable branch instead of six. */
    if (((U < 0) | (V < 0) | (W < 0)) & ((U > 0) | (V > 0) | (W > 0))) return 0;
    det = U + V + W;
    if (det == 0) return 0;
    if (GG_UNLIKELY(U == 0 || V == 0 || W == 0) &&
        !gg_tri_zero_edge(U, V, W, ax, ay, bx, by, cx, cy))
        return 0;
    T = r->sz * (U * Az + V * Bz + W * Cz);
    rcp = 1.0 / det;
    tt = T * rcp;
    if (!(tt > r->tmin && tt <= tmax)) return 0;
    *t = tt;
    *b1 = V * rcp;
    *b2 = W * rcp;
    return 1;
}

#endif
