/* SPDX-License-Identifier: MIT */
/*
** offset.c -- where a secondary ray starts.
**
** Method: a per-hit error bound, not an ulp count. Every shape computes
** its hit point in a way whose distance from the true surface is bounded
** by a few roundings of the magnitudes involved (pbrt's error analysis,
** Pharr, Jakob, Humphreys 3rd ed. 3.9): spheres and cones re-project onto
** the surface, triangles and rectangles rebuild the point from their
** parameters, so the bound does not grow with the distance the ray
** travelled. gg_geom_surface stores it in gg_surf.perr (a bound on each
** component's absolute error). The origin is pushed along ng by
** GG_OFFSET_K * perr to the side the new ray goes to.
**
** Why not Waechter and Binder's integer-ulp offset (Ray Tracing Gems ch. 6):
** it scales with |p| only. A point near the world origin on a triangle
** whose vertices are at 1e6 carries an error of ~1e-10 (the vertices'
** rounding) but |p| ~ 0 gives an offset of ~1e-300: the new ray re-hits.
** The bound here scales with what the point was computed from.
**
** Why K = 8: perr bounds the error per component; along a unit normal the
** bound is at most sqrt(3) perr; the re-intersection test at the new
** origin has errors of the same order (a few roundings of the same
** magnitudes), which must not flip the sign of the tiny distance back to
** the surface. 8 covers both with a factor of ~2 to spare; the offsets
** stay ~1e-14 relative, far below anything visible, and nested surfaces
** 1e-9 apart are still found (tests/unit/geom/test_offset.c checks both).
*/
#include "geom_int.h"

static ggVec3 push(const gg_surf *s, ggVec3 d, double eps, int round_away)
{
    ggVec3 n = s->ng, p;
    if (v3dot(d, n) < 0) n = v3neg(n);
    p = v3madd(s->p, n, eps);
    if (round_away) {
        /* The sum p + eps n rounds to nearest; step one ulp further so the
           rounding cannot take back part of the push (pbrt 3.9.5). */
        if (n.x > 0) p.x = gg_next_up(p.x);
        if (n.x < 0) p.x = gg_next_down(p.x);
        if (n.y > 0) p.y = gg_next_up(p.y);
        if (n.y < 0) p.y = gg_next_down(p.y);
        if (n.z > 0) p.z = gg_next_up(p.z);
        if (n.z < 0) p.z = gg_next_down(p.z);
    }
    return p;
}

ggVec3 gg_offset_origin(const gg_surf *s, ggVec3 d)
{
    return push(s, d, GG_OFFSET_K * s->perr, 1);
}

ggVec3 gg_offset_origin_fixed(const gg_surf *s, ggVec3 d, double eps)
{
    return push(s, d, eps, 0);
}

/* A hit near the target carries the rounding of the coordinates it is
   computed from, a few units of 2^-53 (|o| + |target|) in space, which
   is that over |target - o| in t; K of them, as at the origin. */
double gg_offset_end(ggVec3 o, ggVec3 target)
{
    double len = v3maxabs(v3sub(target, o)), t;
    if (!(len > 0)) return 0.5;
    t = 1 - GG_OFFSET_K * 0x1p-53 * (v3maxabs(o) + v3maxabs(target)) / len;
    return t > 0.5 ? t : 0.5;
}
