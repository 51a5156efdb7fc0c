/* SPDX-License-Identifier: MIT */
/*
** heatmap.c -- turn a per-pixel cost map into a picture with a legend: a
** colour ramp from cheap (dark blue) to expensive (yellow), and below the
** image a bar with the scale's ends written in a tiny built-in font (no
** font library needed).
*/
#include "common/heatmap.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* 3x5 glyphs, one row per 3 bits (top row first). */
static const struct {
    char c;
    unsigned char rows[5];
} glyphs[] = {
    {'0', {7, 5, 5, 5, 7}}, {'1', {2, 6, 2, 2, 7}}, {'2', {7, 1, 7, 4, 7}}, {'3', {7, 1, 7, 1, 7}},
    {'4', {5, 5, 7, 1, 1}}, {'5', {7, 4, 7, 1, 7}}, {'6', {7, 4, 7, 5, 7}}, {'7', {7, 1, 1, 1, 1}},
    {'8', {7, 5, 7, 5, 7}}, {'9', {7, 5, 7, 1, 7}}, {'.', {0, 0, 0, 0, 2}}, {'-', {0, 0, 7, 0, 0}},
    {'e', {7, 5, 7, 4, 7}}, {'+', {0, 2, 7, 2, 0}}, {'s', {0, 3, 6, 3, 6}}, /* not 5 */
    {'r', {6, 5, 6, 5, 5}}, {'a', {7, 5, 7, 5, 5}}, {'y', {5, 5, 7, 2, 2}}, {'d', {6, 5, 5, 5, 6}},
    {'p', {7, 5, 7, 4, 4}}, {'t', {7, 2, 2, 2, 2}}, {'h', {5, 5, 7, 5, 5}}, {'i', {7, 2, 2, 2, 7}},
    {'m', {5, 7, 7, 5, 5}}, {' ', {0, 0, 0, 0, 0}},
};

static void put(ggImage *img, int x, int y, ggColor c)
{
    if (x >= 0 && y >= 0 && x < ggImageWidth(img) && y < ggImageHeight(img)) ggImageSet(img, x, y, c);
}

/* Text at (x, y) scaled by s; returns the x after it. */
static int text(ggImage *img, int x, int y, int s, const char *str, ggColor c)
{
    for (; *str; str++) {
        size_t g;
        int r, b, i, j;
        for (g = 0; g < sizeof glyphs / sizeof glyphs[0] && glyphs[g].c != *str; g++) continue;
        if (g < sizeof glyphs / sizeof glyphs[0])
            for (r = 0; r < 5; r++)
                for (b = 0; b < 3; b++)
                    if (glyphs[g].rows[r] & (4 >> b))
                        for (i = 0; i < s; i++)
                            for (j = 0; j < s; j++) put(img, x + b * s + i, y + r * s + j, c);
        x += 4 * s;
    }
    return x;
}

/* A blue-to-yellow ramp through purple and orange, readable in print. */
static ggColor ramp(double t)
{
    static const double k[5][3] = {
        {0.02, 0.02, 0.20}, {0.30, 0.05, 0.55}, {0.75, 0.15, 0.40}, {0.98, 0.50, 0.10}, {1.0, 0.95, 0.45}};
    double f;
    int i;
    ggColor c;
    if (!(t > 0)) t = 0;
    if (t > 1) t = 1;
    f = t * 4;
    i = (int)f;
    if (i > 3) i = 3;
    f -= i;
    c.r = k[i][0] + (k[i + 1][0] - k[i][0]) * f;
    c.g = k[i][1] + (k[i + 1][1] - k[i][1]) * f;
    c.b = k[i][2] + (k[i + 1][2] - k[i][2]) * f;
    /* The ramp is given in display terms; the PNG writer encodes sRGB. */
    c.r = ggSRGBToLinear(c.r), c.g = ggSRGBToLinear(c.g), c.b = ggSRGBToLinear(c.b);
    return c;
}

/* Bins of positive values by binary exponent and 16 steps of mantissa:
   a quantile to within 1/16 of itself, in one pass and fixed memory. */
#define HBIN_SUB 16
#define HBIN_EXP 2200 /* exponents -1100 .. 1099 (frexp gives -1073 .. 1024) */

static size_t hbin(double v)
{
    int e;
    double m = frexp(v, &e); /* v = m 2^e, m in [0.5, 1) */
    return (size_t)(e + 1100) * HBIN_SUB + (size_t)((m - 0.5) * 2 * HBIN_SUB);
}

/* Every value of bin b is below this. */
static double hbin_top(size_t b)
{
    return ldexp(0.5 + (double)(b % HBIN_SUB + 1) / (2 * HBIN_SUB), (int)(b / HBIN_SUB) - 1100);
}

/* The scale of a cost map as heatmap.h's heatmap_range describes it. */
static void scale_of(const float *cost, size_t n, int robust, heatmap_range *r)
{
    size_t *bins = robust ? calloc((size_t)HBIN_EXP * HBIN_SUB, sizeof *bins) : NULL;
    size_t i, npos = 0, want, sum = 0, b;
    double q = 0;
    r->max = 0, r->top = 0, r->above = 0;
    for (i = 0; i < n; i++)
        if (isfinite(cost[i]) && cost[i] > r->max) r->max = cost[i];
    r->top = r->max;
    if (!robust || !bins) { /* the scale is the largest value: still a true one */
        free(bins);
        return;
    }
    for (i = 0; i < n; i++)
        if (isfinite(cost[i]) && cost[i] > 0) bins[hbin(cost[i])]++, npos++;
    want = npos - npos / 1000; /* the 99.9th percentile's rank */
    for (b = 0; npos && b < (size_t)HBIN_EXP * HBIN_SUB; b++)
        if ((sum += bins[b]) >= want) break;
    free(bins);
    if (!npos || !(r->max > HEATMAP_OUTLIER * hbin_top(b))) return;
    for (i = 0; i < n; i++) /* the largest value of that bin: the quantile when values repeat */
        if (isfinite(cost[i]) && cost[i] > 0 && hbin(cost[i]) == b && cost[i] > q) q = cost[i];
    r->top = q;
    for (i = 0; i < n; i++)
        if (isfinite(cost[i]) && cost[i] > q) r->above++;
}

/* The map's pixels: cost over the ramp from 0 to mx. Returns img. */
static ggImage *img_fill(ggImage *img, const float *cost, int w, int h, double mx)
{
    int x, y;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++)
            ggImageSet(img, x, y, ramp(mx > 0 ? cost[(size_t)y * w + x] / mx : 0));
    return img;
}

ggImage *heatmap_image(const float *cost, int w, int h, const char *label, int robust,
                       heatmap_range *range)
{
    int legend = 14 + (w >= 200 ? 10 : 6), scale = w >= 200 ? 2 : 1, x, y;
    ggImage *img;
    heatmap_range r;
    double mx;
    char buf[64];
    ggColor white = {1, 1, 1};
    if ((uint64_t)w * (uint64_t)(h + legend) > GG_IMAGE_MAX_PIXELS || h + legend > GG_IMAGE_MAX_DIM)
        legend = 0;
    if (!(img = ggImageCreate(w, h + legend, NULL))) return NULL;
    scale_of(cost, (size_t)w * h, robust, &r);
    r.legend = legend;
    if (range) *range = r;
    if (!legend) return img_fill(img, cost, w, h, r.top);
    mx = r.top;
    img_fill(img, cost, w, h, mx);
    /* Legend: the ramp from 0 to the top of the scale, labelled at both
       ends ("+": larger values take the top colour). */
    for (y = h + 2; y < h + 8; y++)
        for (x = 0; x < w; x++) ggImageSet(img, x, y, ramp((double)x / (w > 1 ? w - 1 : 1)));
    text(img, 1, h + 10, scale, "0", white);
    snprintf(buf, sizeof buf, "%.3g%s", mx, r.above ? "+" : "");
    text(img, w - 1 - (int)strlen(buf) * 4 * scale, h + 10, scale, buf, white);
    if ((int)(strlen(label) + 8) * 4 * scale < w)
        text(img, w / 2 - (int)strlen(label) * 2 * scale, h + 10, scale, label, white);
    return img;
}
