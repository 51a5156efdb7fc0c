/* SPDX-License-Identifier: MIT */
/*
** json.c -- the CLI's one JSON writer (json.h).
*/
#include "common/json.h"

#include <math.h>
#include <string.h>

void json_num(FILE *f, double d)
{
    if (isfinite(d))
        fprintf(f, "%.17g", d);
    else
        fprintf(f, "null");
}

void json_num_text(FILE *f, double d)
{
    if (isfinite(d))
        fprintf(f, "%.17g", d);
    else
        fprintf(f, "\"%s\"", isnan(d) ? "nan" : d > 0 ? "inf" : "-inf");
}

void json_num_opt(FILE *f, double d)
{
    if (isnan(d))
        fprintf(f, "null");
    else
        json_num_text(f, d);
}

void json_str(FILE *f, const char *s)
{
    const unsigned char *p = (const unsigned char *)s, *end = p + strlen(s);
    fputc('"', f);
    while (*p) {
        int n = ggUTF8Length((const char *)p, (size_t)(end - p));
        if (!n)
            fprintf(f, "\\\\x%02X", *p++); /* the text \xHH, as in the library's messages */
        else if (*p == '"' || *p == '\\')
            fprintf(f, "\\%c", *p++);
        else if (*p < 0x20 || *p == 0x7f)
            fprintf(f, "\\u%04x", *p++);
        else {
            fwrite(p, 1, (size_t)n, f);
            p += (size_t)n;
        }
    }
    fputc('"', f);
}

static void triple(FILE *f, const char *key, double a, double b, double c,
                   void (*num)(FILE *, double))
{
    if (key) fprintf(f, "\"%s\":", key);
    fputc('[', f);
    num(f, a), fputc(',', f), num(f, b), fputc(',', f), num(f, c);
    fputc(']', f);
}

void json_color(FILE *f, const char *key, ggColor c)
{
    triple(f, key, c.r, c.g, c.b, json_num);
}

void json_color_text(FILE *f, const char *key, ggColor c)
{
    triple(f, key, c.r, c.g, c.b, json_num_text);
}

void json_vec(FILE *f, const char *key, ggVec3 v)
{
    triple(f, key, v.x, v.y, v.z, json_num);
}

void json_vec_text(FILE *f, const char *key, ggVec3 v)
{
    triple(f, key, v.x, v.y, v.z, json_num_text);
}

void json_options(FILE *f, const char *key, const ggRenderOptions *opt)
{
    char buf[1024];
    ggRenderOptionsFormat(opt, buf, sizeof buf);
    fprintf(f, "\"%s\":", key);
    json_str(f, buf);
}

void json_stats(FILE *f, const char *key, const ggRayStats *st)
{
    fprintf(f,
            "\"%s\":{\"eye\":%llu,\"reflect\":%llu,\"refract\":%llu,\"shadow\":%llu,\"tir\":%llu,"
            "\"shadow_blocked\":%llu,\"shadow_attenuated\":%llu}",
            key, (unsigned long long)st->eye, (unsigned long long)st->reflect,
            (unsigned long long)st->refract, (unsigned long long)st->shadow,
            (unsigned long long)st->tir, (unsigned long long)st->shadow_blocked,
            (unsigned long long)st->shadow_attenuated);
}
