/* SPDX-License-Identifier: MIT */
/*
** bigf.c -- the 512-bit floating-point type of bigf.h: schoolbook limb
** arithmetic, truncating; division and square root by Newton's iteration.
*/
#include "bigf.h"

#include <math.h>
#include <string.h>

#define L GG_BF_LIMBS
#define W (L + 2) /* working width of a sum: two guard limbs */

static gg_bf zero(int inexact)
{
    gg_bf r;
    memset(&r, 0, sizeof r);
    r.inexact = inexact;
    return r;
}

/* r = sign * 0.w * 2^exp (nw limbs, most significant first), normalised
   and truncated to L limbs. */
static gg_bf normalise(const uint32_t *w, int nw, int exp, int sign, int inexact)
{
    gg_bf r;
    int k = 0, lz = 0, i;
    while (k < nw && w[k] == 0) k++;
    if (k == nw) return zero(inexact);
    while (!(w[k] & (0x80000000u >> lz))) lz++;
    r.sign = sign, r.exp = exp - 32 * k - lz, r.inexact = inexact;
    for (i = 0; i < L; i++) {
        uint32_t hi = k + i < nw ? w[k + i] : 0, lo = k + i + 1 < nw ? w[k + i + 1] : 0;
        r.m[i] = lz ? (hi << lz) | (lo >> (32 - lz)) : hi;
    }
    /* Bits beyond the L kept limbs. */
    if (k + L < nw && lz && (w[k + L] << lz)) r.inexact = 1;
    if (k + L < nw && !lz && w[k + L]) r.inexact = 1;
    for (i = k + L + 1; i < nw; i++)
        if (w[i]) r.inexact = 1;
    return r;
}

gg_bf gg_bf_from(double x)
{
    gg_bf r = zero(0);
    int e;
    uint64_t m;
    if (x == 0) return r;
    m = (uint64_t)ldexp(fabs(frexp(x, &e)), 53); /* exact: 53 bits */
    r.sign = x < 0 ? -1 : 1, r.exp = e;
    r.m[0] = (uint32_t)(m >> 21), r.m[1] = (uint32_t)((m & 0x1fffff) << 11);
    return r;
}

double gg_bf_to_double(gg_bf a)
{
    uint64_t m;
    int i, sticky;
    if (a.sign == 0) return 0.0;
    m = ((uint64_t)a.m[0] << 21) | (a.m[1] >> 11);
    sticky = (a.m[1] & 0x3ff) != 0;
    for (i = 2; i < L; i++) sticky |= a.m[i] != 0;
    if (((a.m[1] >> 10) & 1) && (sticky || (m & 1))) m++;
    return a.sign * ldexp((double)m, a.exp - 53);
}

gg_bf gg_bf_neg(gg_bf a)
{
    a.sign = -a.sign;
    return a;
}

gg_bf gg_bf_scale2(gg_bf a, int e)
{
    if (a.sign) a.exp += e;
    return a;
}

int gg_bf_cmpabs(gg_bf a, gg_bf b)
{
    int i;
    if (!a.sign || !b.sign) return !!a.sign - !!b.sign;
    if (a.exp != b.exp) return a.exp > b.exp ? 1 : -1;
    for (i = 0; i < L; i++)
        if (a.m[i] != b.m[i]) return a.m[i] > b.m[i] ? 1 : -1;
    return 0;
}

int gg_bf_ceil_expo(gg_bf a)
{
    int i;
    if (a.m[0] != 0x80000000u) return a.exp;
    for (i = 1; i < L; i++)
        if (a.m[i]) return a.exp;
    return a.exp - 1;
}

/* b's mantissa shifted right by d bits into W limbs; returns whether bits
   fell off the end. */
static int shift_into(uint32_t *w, const gg_bf *b, long d)
{
    int q = (int)(d / 32), s = (int)(d % 32), i, lost = 0;
    for (i = 0; i < W; i++) {
        int j = i - q;
        uint32_t v = 0;
        if (j >= 0 && j < L) v = b->m[j] >> s;
        if (s && j - 1 >= 0 && j - 1 < L) v |= b->m[j - 1] << (32 - s);
        w[i] = v;
    }
    /* Source bit positions >= 32 W are lost. */
    for (i = 0; i < L; i++) {
        long first = 32L * i + d, end = first + 32;
        if (end <= 32L * W) continue;
        if (first >= 32L * W)
            lost |= b->m[i] != 0;
        else
            lost |= (b->m[i] & ((1u << (end - 32L * W)) - 1)) != 0;
    }
    return lost;
}

gg_bf gg_bf_add(gg_bf a, gg_bf b)
{
    uint32_t wa[W + 1], wb[W];
    int i, lost, inexact = a.inexact | b.inexact;
    long d;
    if (!b.sign) return a.inexact = inexact, a;
    if (!a.sign) return b.inexact = inexact, b;
    if (gg_bf_cmpabs(a, b) < 0) {
        gg_bf t = a;
        a = b, b = t;
    }
    d = (long)a.exp - b.exp;
    if (d >= 32L * W) return a.inexact = 1, a;
    lost = shift_into(wb, &b, d);
    wa[0] = 0;
    for (i = 0; i < W; i++) wa[i + 1] = i < L ? a.m[i] : 0;
    if (a.sign == b.sign) {
        uint64_t c = 0;
        for (i = W - 1; i >= 0; i--) {
            c += (uint64_t)wa[i + 1] + wb[i];
            wa[i + 1] = (uint32_t)c, c >>= 32;
        }
        wa[0] = (uint32_t)c;
    } else {
        int64_t br = 0;
        for (i = W - 1; i >= 0; i--) {
            int64_t t = (int64_t)wa[i + 1] - wb[i] - br;
            br = t < 0, wa[i + 1] = (uint32_t)(t + (br ? 4294967296LL : 0));
        }
    }
    return normalise(wa, W + 1, a.exp + 32, a.sign, inexact | lost);
}

gg_bf gg_bf_sub(gg_bf a, gg_bf b)
{
    return gg_bf_add(a, gg_bf_neg(b));
}

gg_bf gg_bf_mul(gg_bf a, gg_bf b)
{
    uint32_t p[2 * L];
    int i, j;
    if (!a.sign || !b.sign) return zero(a.inexact | b.inexact);
    memset(p, 0, sizeof p);
    for (i = L - 1; i >= 0; i--) {
        uint64_t c = 0;
        for (j = L - 1; j >= 0; j--) {
            c += (uint64_t)a.m[i] * b.m[j] + p[i + j + 1];
            p[i + j + 1] = (uint32_t)c, c >>= 32;
        }
        p[i] = (uint32_t)c;
    }
    return normalise(p, 2 * L, a.exp + b.exp, a.sign * b.sign, a.inexact | b.inexact);
}

/* 1/b for b != 0: x <- x + x (1 - b x) from a double estimate; each step
   doubles the correct bits (53, 106, 212, 424, then the precision). */
static gg_bf recip(gg_bf b)
{
    gg_bf f = b, x, one = gg_bf_from(1.0);
    int i;
    f.exp = 0, f.sign = 1;
    x = gg_bf_from(1.0 / gg_bf_to_double(f));
    for (i = 0; i < 4; i++) x = gg_bf_add(x, gg_bf_mul(x, gg_bf_sub(one, gg_bf_mul(f, x))));
    x = gg_bf_scale2(x, -b.exp);
    x.sign = b.sign;
    return x;
}

gg_bf gg_bf_div(gg_bf a, gg_bf b)
{
    gg_bf x = recip(b), q = gg_bf_mul(a, x);
    /* One correction with the residual a - b q. */
    q = gg_bf_add(q, gg_bf_mul(gg_bf_sub(a, gg_bf_mul(b, q)), x));
    q.inexact = 1;
    return q;
}

gg_bf gg_bf_sqrt(gg_bf a)
{
    gg_bf f = a, y, s, one = gg_bf_from(1.0);
    int i, e = a.exp;
    if (a.sign <= 0) return zero(a.inexact);
    /* a = f 2^e with e even, f in [1/4, 1). */
    if (e & 1) e++;
    f.exp = a.exp - e;
    y = gg_bf_scale2(gg_bf_from(1.0 / sqrt(gg_bf_to_double(f))), -e / 2);
    /* 1/sqrt(a): y <- y + y (1 - a y^2) / 2. */
    for (i = 0; i < 4; i++)
        y = gg_bf_add(
            y, gg_bf_scale2(gg_bf_mul(y, gg_bf_sub(one, gg_bf_mul(a, gg_bf_mul(y, y)))), -1));
    s = gg_bf_mul(a, y);
    s = gg_bf_add(s, gg_bf_scale2(gg_bf_mul(y, gg_bf_sub(a, gg_bf_mul(s, s))), -1));
    s.inexact = 1;
    return s;
}
