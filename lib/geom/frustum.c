/* SPDX-License-Identifier: MIT */
/*
** frustum.c -- whether a bundle of rays from one point can meet anything:
** the test behind the renderer's empty tiles.
**
** A tile of eye rays leaves from the eye through a rectangle of the image
** plane: every ray lies in the pyramid spanned by the four corner
** directions. The pyramid is tested against the BVH's boxes, top down;
** if no leaf box reaches into it, no ray of the tile can hit anything and
** the renderer writes the background without tracing them (tetra: about
** two thirds of the pixels, and half of the eye rays' time).
**
** Conservative by construction: a box is dropped only if its corner
** farthest into the pyramid lies outside one of its four planes by more
** than a margin, 2^-30 of the magnitudes involved, far above the
** rounding of the planes (a few ulp of the directions), of the renderer's
** directions (which differ from the exact ones through the tile's
** rectangle by a few ulp) and of this test itself. Any NaN (a degenerate
** camera) keeps the box in.
*/
#include "bvh_int.h"

static ggVec3 cross(ggVec3 a, ggVec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

/* Whether box lane i of node nd lies wholly outside one of the planes
   (normals n[k] pointing into the pyramid, through eye e): the four
   sides, and the plane through the eye across the middle direction (each
   side alone keeps a box behind the eye that straddles its plane). */
static int box_out(const gg_bnode *nd, int i, const ggVec3 n[5], ggVec3 e)
{
    const double lo[3] = {nd->b[0][i], nd->b[1][i], nd->b[2][i]};
    const double hi[3] = {nd->b[3][i], nd->b[4][i], nd->b[5][i]};
    int k;
    for (k = 0; k < 5; k++) {
        /* the corner farthest along n[k], relative to the eye */
        double px = (n[k].x > 0 ? hi[0] : lo[0]) - e.x;
        double py = (n[k].y > 0 ? hi[1] : lo[1]) - e.y;
        double pz = (n[k].z > 0 ? hi[2] : lo[2]) - e.z;
        double s = n[k].x * px + n[k].y * py + n[k].z * pz;
        double m = (fabs(n[k].x) + fabs(n[k].y) + fabs(n[k].z)) *
                   (fabs(px) + fabs(py) + fabs(pz) + fabs(e.x) + fabs(e.y) + fabs(e.z)) * 0x1p-30;
        if (s < -m) return 1;
    }
    return 0;
}

int gg_geom_frustum_empty(const gg_geom *g, ggVec3 eye, const ggVec3 d[4])
{
    ggVec3 n[5], mid = v3add(v3add(d[0], d[1]), v3add(d[2], d[3]));
    uint32_t stack[GG_STACK];
    int sp = 0, k, i;
    if (!g->built || !g->nslots || !g->nodes) return 1;
    for (k = 0; k < 4; k++) {
        n[k] = cross(d[k], d[(k + 1) & 3]);
        /* inwards: towards the middle direction (NaN stays NaN) */
        if (v3dot(n[k], mid) < 0) n[k] = v3neg(n[k]);
        if (!(v3dot(n[k], mid) > 0)) return 0; /* degenerate: no claim */
        /* every ray of the pyramid goes forwards along mid */
        if (!(v3dot(d[k], mid) > 0)) return 0;
    }
    n[4] = mid;
    stack[sp++] = 0;
    while (sp > 0) {
        const gg_bnode *nd = &g->nodes[stack[--sp]];
        for (i = 0; i < 4; i++) {
            if (!(nd->b[0][i] <= nd->b[3][i])) continue; /* unused lane */
            if (box_out(nd, i, n, eye)) continue;
            if (nd->child[i] & GG_LEAF) return 0;
            if (sp == GG_STACK) return 0;
            stack[sp++] = nd->child[i];
        }
    }
    return 1;
}
