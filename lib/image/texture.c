/* SPDX-License-Identifier: MIT */
/*
** texture.c -- texture sampling: the bilinear blend and the nearest texel
** exactly as ggrt/image.h states them, and a procedural checkerboard.
*/
#include "image.h"

#include <math.h>

/* Bring a coordinate into [0,1]; NaN comes back as NaN. [0,1] itself is
   left alone under both modes so that u = 1 stays the last texel. */
static double wrap_coord(double u, int wrap)
{
    if (u >= 0.0 && u <= 1.0) return u;
    if (wrap == GG_WRAP_REPEAT) return u - floor(u); /* inf - inf = NaN: black */
    if (u < 0.0) return 0.0;
    if (u > 1.0) return 1.0;
    return u; /* NaN */
}

/* The "clamped at 1.0" of ggTextureBilinear (ggrt/image.h); a NaN blend (from non-finite texels) reads 0
   rather than poisoning whatever the colour is multiplied into. */
static double clamp1(double c)
{
    if (c <= 1.0) return c;
    return c > 1.0 ? 1.0 : 0.0;
}

GG_API ggColor ggTextureBilinear(const ggImage *img, double u, double v, int wrap)
{
    ggColor c = {0.0, 0.0, 0.0};
    const float *c00, *c01, *c10, *c11;
    double di, dj, up, vp, w00, w01, w10, w11;
    int i, j, i1, j1, w, h;
    if (!img) return c;
    u = wrap_coord(u, wrap);
    v = wrap_coord(v, wrap);
    if (isnan(u) || isnan(v)) return c;
    w = img->width;
    h = img->height;
    di = (w - 1) * u;
    dj = (h - 1) * v;
    i = (int)di;
    j = (int)dj;
    /* (w-1) u <= w-1 for u <= 1, so these only guard against surprises. */
    if (i > w - 1) i = w - 1;
    if (j > h - 1) j = h - 1;
    up = di - i;
    vp = dj - j;
    /* At u = 1 (or a 1-pixel-wide image) i + 1 would be one past the last
       column; its weight u_p is 0 there, so clamping changes nothing. */
    i1 = i + 1 < w ? i + 1 : w - 1;
    j1 = j + 1 < h ? j + 1 : h - 1;
    c00 = img->px + 3 * ((size_t)j * (size_t)w + (size_t)i);
    c01 = img->px + 3 * ((size_t)j1 * (size_t)w + (size_t)i);
    c10 = img->px + 3 * ((size_t)j * (size_t)w + (size_t)i1);
    c11 = img->px + 3 * ((size_t)j1 * (size_t)w + (size_t)i1);
    w00 = (1.0 - up) * (1.0 - vp);
    w01 = (1.0 - up) * vp;
    w10 = up * (1.0 - vp);
    w11 = up * vp;
    c.r = clamp1(c00[0] * w00 + c01[0] * w01 + c10[0] * w10 + c11[0] * w11);
    c.g = clamp1(c00[1] * w00 + c01[1] * w01 + c10[1] * w10 + c11[1] * w11);
    c.b = clamp1(c00[2] * w00 + c01[2] * w01 + c10[2] * w10 + c11[2] * w11);
    return c;
}

GG_API ggColor ggTextureNearest(const ggImage *img, double u, double v, int wrap)
{
    ggColor c = {0.0, 0.0, 0.0};
    const float *p;
    int i, j;
    if (!img) return c;
    u = wrap_coord(u, wrap);
    v = wrap_coord(v, wrap);
    if (isnan(u) || isnan(v)) return c;
    i = (int)floor((img->width - 1) * u + 0.5);
    j = (int)floor((img->height - 1) * v + 0.5);
    if (i > img->width - 1) i = img->width - 1;
    if (j > img->height - 1) j = img->height - 1;
    p = img->px + 3 * ((size_t)j * (size_t)img->width + (size_t)i);
    c.r = clamp1(p[0]);
    c.g = clamp1(p[1]);
    c.b = clamp1(p[2]);
    return c;
}

GG_API ggColor ggTextureChecker(double u, double v, double n, ggColor a, ggColor b)
{
    ggColor black = {0.0, 0.0, 0.0};
    double su, sv;
    if (!isfinite(u) || !isfinite(v)) return black;
    if (!(n > 0.0) || !isfinite(n)) return a;
    su = floor((u - floor(u)) * n);
    sv = floor((v - floor(v)) * n);
    /* The usual small n: integer parity. A huge n keeps doubles: the
       parity of each, which fmod gets exactly (0 from 2^53 on), not of
       their sum, which rounds past 2^53 and overflows near DBL_MAX. */
    if (su + sv < 1e9) return (((long)su + (long)sv) & 1) == 0 ? a : b;
    return fmod(su, 2.0) == fmod(sv, 2.0) ? a : b;
}
