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
#include <string.h>

/* 3x5 glyphs, one row per 3 bits (top row first). */
static const struct {
    char c;
    unsigned char rows[5];
} glyphs[] = {
    {'0', {7, 5, 5, 5, 7}}, {'1', {2, 6, 2, 2, 7}}, {'2', {7, 1, 7, 4, 7}},
    {'3', {7, 1, 7, 1, 7}}, {'4', {5, 5, 7, 1, 1}}, {'5', {7, 4, 7, 1, 7}},
    {'6', {7, 4, 7, 5, 7}}, {'7', {7, 1, 1, 1, 1}}, {'8', {7, 5, 7, 5, 7}},
    {'9', {7, 5, 7, 1, 7}}, {'.', {0, 0, 0, 0, 2}}, {'-', {0, 0, 7, 0, 0}},
    {'e', {7, 5, 7, 4, 7}}, {'+', {0, 2, 7, 2, 0}}, {'s', {7, 4, 7, 1, 7}},
    {'r', {6, 5, 6, 5, 5}}, {'a', {7, 5, 7, 5, 5}}, {'y', {5, 5, 7, 2, 2}},
    {'d', {6, 5, 5, 5, 6}}, {'p', {7, 5, 7, 4, 4}}, {'t', {7, 2, 2, 2, 2}},
    {'h', {5, 5, 7, 5, 5}}, {'i', {7, 2, 2, 2, 7}}, {'m', {5, 7, 7, 5, 5}},
    {' ', {0, 0, 0, 0, 0}},
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

ggImage *heatmap_image(const float *cost, int w, int h, const char *label, double *vmax)
{
    int legend = 14 + (w >= 200 ? 10 : 6), scale = w >= 200 ? 2 : 1, x, y;
    ggImage *img = ggImageCreate(w, h + legend, NULL);
    double mx = 0;
    char buf[64];
    ggColor white = {1, 1, 1};
    size_t i;
    if (!img) return NULL;
    for (i = 0; i < (size_t)w * h; i++)
        if (isfinite(cost[i]) && cost[i] > mx) mx = cost[i];
    if (vmax) *vmax = mx;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) ggImageSet(img, x, y, ramp(mx > 0 ? cost[(size_t)y * w + x] / mx : 0));
    /* Legend: the ramp from 0 to the maximum, labelled at both ends. */
    for (y = h + 2; y < h + 8; y++)
        for (x = 0; x < w; x++) ggImageSet(img, x, y, ramp((double)x / (w > 1 ? w - 1 : 1)));
    text(img, 1, h + 10, scale, "0", white);
    snprintf(buf, sizeof buf, "%.3g", mx);
    text(img, w - 1 - (int)strlen(buf) * 4 * scale, h + 10, scale, buf, white);
    if ((int)(strlen(label) + 8) * 4 * scale < w)
        text(img, w / 2 - (int)strlen(label) * 2 * scale, h + 10, scale, label, white);
    return img;
}
