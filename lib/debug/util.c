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
