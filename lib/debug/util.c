/* SPDX-License-Identifier: MIT */
/*
** util.c -- small helpers of the debug layer.
*/
#include "debug_int.h"

#include <locale.h>
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
    char buf[128];
    const char *dp = localeconv()->decimal_point;
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
    if (i >= sizeof buf) return 0;
    memcpy(buf, s, i);
    buf[i] = '\0';
    /* strtod reads the locale's radix point: give it that one (the library
       must not depend on LC_NUMERIC). */
    if (dp && dp[0] && dp[0] != '.' && dp[1] == 0)
        for (j = 0; j < i; j++)
            if (buf[j] == '.') buf[j] = dp[0];
    *out = strtod(buf, NULL);
    return i;
}

void gg_dbg_alloc_init(gg_dbg_alloc *al, const ggAllocator *a)
{
    if (a)
        al->copy = *a, al->a = &al->copy;
    else
        al->a = NULL;
}

void gg_dbg_stats_add(ggRayStats *a, const ggRayStats *b)
{
    a->eye += b->eye, a->eye_hit += b->eye_hit, a->reflect += b->reflect;
    a->refract += b->refract, a->shadow += b->shadow, a->tir += b->tir;
    a->nonfinite += b->nonfinite, a->budget_cut += b->budget_cut;
    a->implicit_cut += b->implicit_cut;
    if (b->max_depth > a->max_depth) a->max_depth = b->max_depth;
}

void gg_dbg_put(ggImage *img, int x, int y, ggColor c)
{
    float *p = ggImagePixels(img) + 3 * ((size_t)y * (size_t)ggImageWidth(img) + (size_t)x);
    p[0] = (float)c.r, p[1] = (float)c.g, p[2] = (float)c.b;
}
