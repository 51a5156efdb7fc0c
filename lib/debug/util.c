/* SPDX-License-Identifier: MIT */
/*
** util.c -- small helpers of the debug layer.
*/
#include "debug_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int gg_dbg_nonfinite(ggColor c)
{
    return !isfinite(c.r) || !isfinite(c.g) || !isfinite(c.b);
}

static int digit(char c)
{
    return c >= '0' && c <= '9';
}

size_t gg_dbg_number(const char *s, size_t n, double *out)
{
    size_t i = 0, j, digits = 0;
    if (i < n && (s[i] == '+' || s[i] == '-')) i++;
    while (i < n && digit(s[i])) i++, digits++;
    if (i < n && s[i] == '.') {
        i++;
        while (i < n && digit(s[i])) i++, digits++;
    }
    if (!digits) return 0;
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        j = i + 1;
        if (j < n && (s[j] == '+' || s[j] == '-')) j++;
        if (j < n && digit(s[j])) {
            i = j;
            while (i < n && digit(s[i])) i++;
        }
    }
    if (i >= 128) return 0;
    (void)gg_strtod_c(s, i, out);
    return i;
}

void gg_dbg_alloc_init(gg_dbg_alloc *al, const ggAllocator *a)
{
    if (a)
        al->copy = *a, al->a = &al->copy;
    else
        al->a = NULL;
}

void gg_dbg_put(ggImage *img, int x, int y, ggColor c)
{
    float *p = ggImagePixels(img) + 3 * ((size_t)y * (size_t)ggImageWidth(img) + (size_t)x);
    p[0] = (float)c.r, p[1] = (float)c.g, p[2] = (float)c.b;
}

/* The edit distance between a[0..na) and b: insertions, deletions,
   changes and swaps of two neighbours (dpeth is one edit from depth);
   99 past 32 bytes. */
static int distance(const char *a, size_t na, const char *b)
{
    int d[34][34];
    size_t nb = strlen(b), i, j;
    if (na > 32 || nb > 32) return 99;
    for (i = 0; i <= na; i++) d[i][0] = (int)i;
    for (j = 0; j <= nb; j++) d[0][j] = (int)j;
    for (i = 1; i <= na; i++)
        for (j = 1; j <= nb; j++) {
            int c = d[i - 1][j - 1] + (a[i - 1] != b[j - 1]);
            if (d[i - 1][j] + 1 < c) c = d[i - 1][j] + 1;
            if (d[i][j - 1] + 1 < c) c = d[i][j - 1] + 1;
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] &&
                d[i - 2][j - 2] + 1 < c)
                c = d[i - 2][j - 2] + 1;
            d[i][j] = c;
        }
    return d[na][nb];
}

int gg_dbg_suggest(const char *s, size_t n, const char *const *names, size_t count)
{
    int best = -1, bd = (int)(n / 3 + 1), prefixed = -1, nprefixed = 0, d;
    size_t i;
    if (bd > 3) bd = 3;
    for (i = 0; i < count; i++) {
        if (n && !strncmp(names[i], s, n)) prefixed = (int)i, nprefixed++;
        if ((d = distance(s, n, names[i])) < bd) bd = d, best = (int)i;
    }
    return nprefixed == 1 ? prefixed : best;
}
