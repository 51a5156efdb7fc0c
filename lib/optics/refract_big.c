/* SPDX-License-Identifier: MIT */
/*
** refract_big.c -- ggRefract's fallback for the inputs its double-double
** path cannot represent: an index ratio beyond 2^450 with a component of
** v or n more than 1022 binades below its vector's largest, which the
** scaling to [1, 2) would round or lose (and which such a ratio can make
** decisive: a tangential part of 2^-1640 with |eta| = 2^1660 is total
** internal reflection). Evaluated in the 512-bit arithmetic of bigf.h
** (an int exponent: nothing under- or overflows) from the cross products,
** which keep a tiny tangential part to its own relative precision:
**   w = v x n,  P = |v|^2 |n|^2,  Q = |w|^2,  D = nt^2 P - ni^2 Q,
**   TIR iff D < 0; else
**   t = (ni/nt) (n x w) / (|n|^2 |v|) + sign(v.n) sqrt(D / (nt^2 P)) n / |n|,
**   mirror r = (v |n|^2 - 2 (v.n) n) / (|n|^2 |v|).
** docs/optics.md ("Index ratios beyond 2^450 with spread components")
** gives the error bound.
*/
#include "refract_big.h"

#include "bigf.h"

typedef gg_bf bf;

static bf prod(double a, double b)
{
    return gg_bf_mul(gg_bf_from(a), gg_bf_from(b));
}

/* a + b + c, largest magnitude first (exact when it fits in 512 bits). */
static bf sum3(bf a, bf b, bf c)
{
    bf x;
    if (gg_bf_cmpabs(a, b) < 0) x = a, a = b, b = x;
    if (gg_bf_cmpabs(b, c) < 0) x = b, b = c, c = x;
    if (gg_bf_cmpabs(a, b) < 0) x = a, a = b, b = x;
    return gg_bf_add(gg_bf_add(a, b), c);
}

int gg_optics_refract_big(const double v[3], const double n[3], double ni, double nt, int s,
                          double t[3])
{
    bf w[3], sq[3], vv, nn, P, Q, D, nt2P, lv, g1, g2;
    int i;
    for (i = 0; i < 3; i++) {
        int j = (i + 1) % 3, k = (i + 2) % 3;
        w[i] = gg_bf_sub(prod(v[j], n[k]), prod(v[k], n[j]));
    }
    vv = sum3(prod(v[0], v[0]), prod(v[1], v[1]), prod(v[2], v[2]));
    nn = sum3(prod(n[0], n[0]), prod(n[1], n[1]), prod(n[2], n[2]));
    for (i = 0; i < 3; i++) sq[i] = gg_bf_mul(w[i], w[i]);
    P = gg_bf_mul(vv, nn), Q = sum3(sq[0], sq[1], sq[2]);
    nt2P = gg_bf_mul(prod(nt, nt), P);
    D = gg_bf_sub(nt2P, gg_bf_mul(prod(ni, ni), Q));
    lv = gg_bf_sqrt(vv);
    if (D.sign < 0) {
        bf a = sum3(prod(v[0], n[0]), prod(v[1], n[1]), prod(v[2], n[2]));
        g1 = gg_bf_div(gg_bf_from(1.0), gg_bf_mul(nn, lv));
        a = gg_bf_scale2(a, 1);
        for (i = 0; i < 3; i++) {
            bf r = gg_bf_sub(gg_bf_mul(gg_bf_from(v[i]), nn), gg_bf_mul(a, gg_bf_from(n[i])));
            t[i] = gg_bf_to_double(gg_bf_mul(r, g1));
        }
        return 0;
    }
    /* n x w = v |n|^2 - n (v.n) = |n|^2 vt */
    g1 = gg_bf_div(gg_bf_from(ni), gg_bf_mul(gg_bf_from(nt), gg_bf_mul(nn, lv)));
    g2 = D.sign > 0 ? gg_bf_sqrt(gg_bf_div(D, gg_bf_mul(nt2P, nn))) : gg_bf_from(0.0);
    if (s < 0) g2 = gg_bf_neg(g2);
    for (i = 0; i < 3; i++) {
        int j = (i + 1) % 3, k = (i + 2) % 3;
        bf vt = gg_bf_sub(gg_bf_mul(gg_bf_from(n[j]), w[k]), gg_bf_mul(gg_bf_from(n[k]), w[j]));
        t[i] = gg_bf_to_double(gg_bf_add(gg_bf_mul(g1, vt), gg_bf_mul(g2, gg_bf_from(n[i]))));
    }
    return 1;
}
