/* SPDX-License-Identifier: MIT */
/*
** textbook_refract.c -- the textbook formulas, as most renderers write
** them, built into a shared library for `ggrt optics check` to measure:
**
**   make build/libtextbook_refract.so
**   ggrt optics check --lib build/libtextbook_refract.so --symbol textbook_refract
**
** textbook_refract has ggRefract's signature (and normalises v and n
** first, since ggRefract accepts any lengths); textbook_reflect
** ggReflection's; textbook_fresnel ggFresnelDielectric's. The check shows
** where they lose digits: at grazing incidence and near the critical
** angle, where 1 - eta^2 (1 - c^2) cancels. Not part of libggrt.
*/
#include <ggrt.h>

#include <math.h>

bool textbook_refract(ggVec3 v, ggVec3 n, double ni, double nt, ggVec3 *t);
ggVec3 textbook_reflect(ggVec3 v, ggVec3 n);
double textbook_fresnel(double cos_i, double ni, double nt);

static ggVec3 vec(double x, double y, double z)
{
    ggVec3 a;
    a.x = x, a.y = y, a.z = z;
    return a;
}

static ggVec3 normalise(ggVec3 a)
{
    double l = sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
    return vec(a.x / l, a.y / l, a.z / l);
}

/* c = -v.n (n turned to face v), k = 1 - eta^2 (1 - c^2); TIR if k < 0,
   else t = eta v + (eta c - sqrt k) n. */
bool textbook_refract(ggVec3 v, ggVec3 n, double ni, double nt, ggVec3 *t)
{
    double eta = ni / nt, c, k;
    v = normalise(v), n = normalise(n);
    c = -(v.x * n.x + v.y * n.y + v.z * n.z);
    if (c < 0) n = vec(-n.x, -n.y, -n.z), c = -c;
    k = 1 - eta * eta * (1 - c * c);
    if (k < 0) {
        *t = vec(v.x + 2 * c * n.x, v.y + 2 * c * n.y, v.z + 2 * c * n.z);
        return false;
    }
    c = eta * c - sqrt(k);
    *t = vec(eta * v.x + c * n.x, eta * v.y + c * n.y, eta * v.z + c * n.z);
    return true;
}

/* r = v - 2 (v.n) n / (n.n) */
ggVec3 textbook_reflect(ggVec3 v, ggVec3 n)
{
    double s = 2 * (v.x * n.x + v.y * n.y + v.z * n.z) / (n.x * n.x + n.y * n.y + n.z * n.z);
    return vec(v.x - s * n.x, v.y - s * n.y, v.z - s * n.z);
}

/* (Rs + Rp)/2 with cos_t = sqrt(1 - eta^2 (1 - c^2)). */
double textbook_fresnel(double cos_i, double ni, double nt)
{
    double c = fabs(cos_i) > 1 ? 1 : fabs(cos_i), eta = ni / nt, k, ct, rs, rp;
    k = 1 - eta * eta * (1 - c * c);
    if (k < 0) return 1;
    ct = sqrt(k);
    rs = (ni * c - nt * ct) / (ni * c + nt * ct);
    rp = (nt * c - ni * ct) / (nt * c + ni * ct);
    return (rs * rs + rp * rp) / 2;
}
