/* SPDX-License-Identifier: MIT */
/*
** uv.c -- (u, v) of a point on a shape without a ray (geom.h, "(u, v) at
** a point"): the formulas the surface functions of shape_*.c call for a
** hit, and their point-based forms for ggSceneObjectUV.
*/
#include "geom_int.h"

static double clamp01(double x)
{
    return x < 0 ? 0 : x > 1 ? 1 : x;
}

/* An angle about an axis as a fraction of a turn in [0, 1). */
static double turn(double y, double x)
{
    double phi = atan2(y, x), u;
    if (phi < 0) phi += 2 * GG_PI;
    u = phi / (2 * GG_PI);
    return u >= 1 ? 0 : u;
}

void gg_uv_sphere_dir(ggVec3 n, double uv[2])
{
    uv[0] = turn(n.y, n.x);
    uv[1] = acos(n.z < -1 ? -1 : n.z > 1 ? 1 : n.z) / GG_PI;
}

int gg_uv_sphere(ggVec3 c, double r, ggVec3 p, double uv[2])
{
    ggVec3 d = v3sub(p, c), q;
    double len = v3len(d), m;
    int k;
    if (!v3finite(c) || !(r > 0) || !isfinite(r) || !isfinite(r * r) || !v3finite(p)) return -1;
    /* gg_sphere_surface's direction: the point re-projected onto the
       sphere, (0, 0, r) for the centre itself. */
    q = v3scale(d, r / len);
    if (len > 0 && isfinite(len) && v3finite(q) && v3dot(q, q) > 0) {
        gg_uv_sphere_dir(v3norm(q), uv);
        return 0;
    }
    /* A point so far (or so near) that |d| overflows (or r / |d| does):
       the direction of d scaled by a power of two, exactly; where p - c
       itself overflows, of half of it. The centre itself is the pole. */
    if (!v3finite(d)) d = v3sub(v3scale(p, 0.5), v3scale(c, 0.5));
    m = fmax(fabs(d.x), fmax(fabs(d.y), fabs(d.z)));
    if (!(m > 0)) {
        gg_uv_sphere_dir(v3(0, 0, 1), uv);
        return 0;
    }
    k = ilogb(m);
    d = v3(ldexp(d.x, -k), ldexp(d.y, -k), ldexp(d.z, -k));
    gg_uv_sphere_dir(v3norm(d), uv);
    return 0;
}

int gg_uv_cone_frame(ggVec3 base, double rb, ggVec3 apex, double ra, ggVec3 e[3], double *h)
{
    gg_cone c;
    if (gg_cone_prepare(base, rb, apex, ra, &c)) return -1;
    e[0] = v3(c.k.ex[0], c.k.ex[1], c.k.ex[2]);
    e[1] = v3(c.k.ey[0], c.k.ey[1], c.k.ey[2]);
    e[2] = v3(c.k.ez[0], c.k.ez[1], c.k.ez[2]);
    *h = c.k.h;
    return 0;
}

void gg_uv_cone_local(double x, double y, double z, double h, double uv[2])
{
    uv[0] = turn(y, x);
    uv[1] = (z < 0 ? 0 : z > h ? h : z) / h;
}

int gg_uv_cone(ggVec3 base, double rb, ggVec3 apex, double ra, ggVec3 p, double uv[2])
{
    ggVec3 e[3], w;
    double h, x, y;
    double s = 1;
    if (gg_uv_cone_frame(base, rb, apex, ra, e, &h) || !v3finite(p)) return -1;
    w = v3sub(p, base);
    if (!v3finite(w))
        w = v3sub(v3scale(p, 0.5), v3scale(base, 0.5)), s = 2; /* p - base overflows */
    x = v3dot(w, e[0]), y = v3dot(w, e[1]);
    /* On the axis gg_cone_surface takes the point at angle 0 (x and y
       tested, not x^2 + y^2, which underflows off the axis). */
    if (!(x != 0 || y != 0) || x != x || y != y) x = 1, y = 0;
    gg_uv_cone_local(x, y, s * v3dot(w, e[2]), h, uv);
    return 0;
}

/* The dual basis of (e1, e2) in their plane: a1 . e1 = 1, a1 . e2 = 0
   (gg_rect_prepare's). 0, or -1 when e1 and e2 are parallel. */
static int dual(ggVec3 e1, ggVec3 e2, ggVec3 *a1, ggVec3 *a2)
{
    ggVec3 n = v3cross(e1, e2);
    double nn = v3dot(n, n);
    if (!(nn > 0) || !isfinite(nn)) return -1;
    *a1 = v3scale(v3cross(e2, n), 1 / nn);
    *a2 = v3scale(v3cross(n, e1), 1 / nn);
    return 0;
}

int gg_uv_rect(ggVec3 corner, ggVec3 e1, ggVec3 e2, ggVec3 p, double uv[2])
{
    ggVec3 a1, a2, q;
    if (!v3finite(corner) || !v3finite(e1) || !v3finite(e2) || !v3finite(p) ||
        dual(e1, e2, &a1, &a2))
        return -1;
    q = v3sub(p, corner);
    uv[0] = v3dot(q, a1);
    uv[1] = v3dot(q, a2);
    return 0;
}

void gg_uv_interp(const double *u0, const double *u1, const double *u2, double b1, double b2,
                  double uv[2])
{
    double b0 = 1 - b1 - b2;
    uv[0] = b0 * u0[0] + b1 * u1[0] + b2 * u2[0];
    uv[1] = b0 * u0[1] + b1 * u1[1] + b2 * u2[1];
}

int gg_uv_triangle(const ggVec3 v[3], const double *tuv, ggVec3 p, double uv[2])
{
    ggVec3 a1, a2, q;
    double b1, b2;
    if (!v3finite(v[0]) || !v3finite(v[1]) || !v3finite(v[2]) || !v3finite(p) ||
        dual(v3sub(v[1], v[0]), v3sub(v[2], v[0]), &a1, &a2))
        return -1;
    q = v3sub(p, v[0]);
    b1 = v3dot(q, a1), b2 = v3dot(q, a2);
    if (tuv) {
        gg_uv_interp(tuv, tuv + 2, tuv + 4, b1, b2, uv);
    } else {
        uv[0] = clamp01(b1);
        uv[1] = clamp01(b2);
    }
    return 0;
}

/* The largest of the fan's cross products (p_i - p_0) x (p_i+1 - p_0),
   each offset times s: a normal of a planar polygon whatever its winding. */
static ggVec3 fan_normal(const ggVec3 *p, int nv, double s)
{
    ggVec3 best = v3(0, 0, 0);
    int i;
    for (i = 1; i + 1 < nv; i++) {
        ggVec3 x = v3cross(v3scale(v3sub(p[i], p[0]), s), v3scale(v3sub(p[i + 1], p[0]), s));
        if (v3maxabs(x) > v3maxabs(best)) best = x;
    }
    return best;
}

/* The plane's normal. Newell's normal, about the centroid c to keep the
   products small: the area-weighted normal of any planar (or nearly
   planar) polygon, concave or not, pointing to the side it runs
   counter-clockwise. The offsets from c are scaled by a power of two s
   (exactly) to near 1, so that the products neither underflow (polygons
   under 2^-511 across had no normal and vanished) nor overflow; the
   normal's bits are those without s. Where the lobes of a self-crossing
   polygon cancel (a bow tie), Newell's sum is 0 or rounding: then the
   fan's largest cross product (the polygon had vanished, and one vertex
   moved by 1e-6 brought both lobes back). */
static ggVec3 plane_normal(const ggVec3 *p, int nv, ggVec3 c)
{
    ggVec3 n = v3(0, 0, 0);
    double m = 0, s, sum = 0;
    int i;
    for (i = 0; i < nv; i++) m = fmax(m, v3maxabs(v3sub(p[i], c)));
    if (!(m > 0) || !isfinite(m)) return n;
    s = ldexp(1, -ilogb(m));
    for (i = 0; i < nv; i++) {
        ggVec3 a = v3scale(v3sub(p[i], c), s), b = v3scale(v3sub(p[i + 1 < nv ? i + 1 : 0], c), s);
        ggVec3 x = v3cross(a, b);
        n = v3add(n, x);
        sum += fabs(x.x) + fabs(x.y) + fabs(x.z);
    }
    return v3maxabs(n) > 0x1p-40 * sum ? n : fan_normal(p, nv, s);
}

int gg_uv_plane_make(const ggVec3 *p, int nv, gg_uv_plane *out)
{
    ggVec3 c = v3(0, 0, 0), n, eu = v3(0, 0, 0);
    double umin = INFINITY, umax = -INFINITY, vmin = INFINITY, vmax = -INFINITY;
    int i;
    memset(out, 0, sizeof *out);
    if (nv < 3) return -1;
    for (i = 0; i < nv; i++) c = v3add(c, p[i]);
    c = v3scale(c, 1.0 / nv);
    n = plane_normal(p, nv, c);
    if (!(v3maxabs(n) > 0) || !v3finite(n)) return -1; /* not |n|^2: it underflows */
    n = v3unit(n);
    for (i = 1; i < nv && v3dot(eu, eu) == 0; i++) {
        eu = v3sub(p[i], p[0]);
        eu = v3sub(eu, v3scale(n, v3dot(eu, n)));
    }
    eu = v3unit(eu);
    if (!(v3dot(eu, eu) > 0)) return -1;
    out->n = n;
    out->eu = eu;
    out->ev = v3cross(n, eu);
    out->p0 = p[0];
    for (i = 0; i < nv; i++) {
        ggVec3 d = v3sub(p[i], p[0]);
        double u = v3dot(d, out->eu), v = v3dot(d, out->ev);
        umin = u < umin ? u : umin, umax = u > umax ? u : umax;
        vmin = v < vmin ? v : vmin, vmax = v > vmax ? v : vmax;
    }
    if (!(umax > umin) || !(vmax > vmin)) return -1;
    out->u0 = umin, out->su = 1 / (umax - umin);
    out->v0 = vmin, out->sv = 1 / (vmax - vmin);
    return 0;
}

void gg_uv_plane_at(const gg_uv_plane *f, ggVec3 p, double uv[2])
{
    ggVec3 d = v3sub(p, f->p0);
    uv[0] = clamp01((v3dot(d, f->eu) - f->u0) * f->su);
    uv[1] = clamp01((v3dot(d, f->ev) - f->v0) * f->sv);
}
