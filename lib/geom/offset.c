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
** 1e-9 apart are still found (tests/test_offset.c checks both).
*/
#include "geom_int.h"

/* x one double further along the sign of n: gg_next_up(x) for n > 0,
   gg_next_down(x) for n < 0, x itself for n = 0 or NaN. For finite
   nonzero x that is one step of the bit pattern, up when x and n have
   the same sign (away from zero) and down otherwise, computed without a
   branch on those signs: they are a coin toss per hit, and the branches
   of the gg_next_up / gg_next_down pair mispredicted. */
static inline double step_along(double x, double n)
{
    uint64_t u, opposite;
    if (!(fabs(n) > 0)) return x; /* 0 or NaN: one test, rarely true */
    if (!(fabs(x) > 0 && fabs(x) < INFINITY)) return n > 0 ? gg_next_up(x) : gg_next_down(x);
    memcpy(&u, &x, 8);
    opposite = (u >> 63) ^ (uint64_t)(n < 0);
    u += 1 - 2 * opposite;
    memcpy(&x, &u, 8);
    return x;
}

/* x with its sign bit flipped where flip has it (-x, as v3neg does). */
static inline double flip_sign(double x, uint64_t flip)
{
    uint64_t u;
    memcpy(&u, &x, 8);
    u ^= flip;
    memcpy(&x, &u, 8);
    return x;
}

static ggVec3 push(const gg_surf *s, ggVec3 d, double eps, int round_away)
{
    /* ng towards the side d leaves to; which side that is is a coin toss
       too, so no branch either */
    const uint64_t flip = (uint64_t)(v3dot(d, s->ng) < 0) << 63;
    ggVec3 n, p;
    n.x = flip_sign(s->ng.x, flip), n.y = flip_sign(s->ng.y, flip), n.z = flip_sign(s->ng.z, flip);
    p = v3madd(s->p, n, eps);
    if (round_away) {
        /* The sum p + eps n rounds to nearest; step one ulp further so the
           rounding cannot take back part of the push (pbrt 3.9.5). */
        p.x = step_along(p.x, n.x);
        p.y = step_along(p.y, n.y);
        p.z = step_along(p.z, n.z);
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
