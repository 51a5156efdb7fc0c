/* SPDX-License-Identifier: MIT */
/*
** options.c -- render options as text (ggRenderOptionsParse and
** ggRenderOptionsFormat): "sphere=textbook depth=8", for ggrt diff's --a
** and --b, the options of a replay command and a server's query strings.
*/
#include "debug_int.h"

#include <locale.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

typedef struct word {
    const char *s;  /* the whole text */
    size_t at, len; /* this setting */
    size_t eq;      /* offset of '=' within it, or len */
} word;

static int fail(const word *w, size_t at, ggError *err, const char *fmt, ...) GG_PRINTF(4, 5);

static int fail(const word *w, size_t at, ggError *err, const char *fmt, ...)
{
    char msg[400];
    size_t i;
    int line = 1, col = 1;
    va_list ap;
    for (i = 0; i < at; i++) {
        if (w->s[i] == '\n')
            line++, col = 1;
        else if (((unsigned char)w->s[i] & 0xC0) != 0x80)
            col++;
    }
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return gg_error_set(err, GG_ERROR_PARSE, "%d:%d: %s", line, col, msg);
}

static int key_is(const word *w, const char *k)
{
    return w->eq == strlen(k) && !strncmp(w->s + w->at, k, w->eq);
}

static int val_is(const word *w, const char *v)
{
    size_t n = w->len - w->eq - 1;
    return w->eq < w->len && n == strlen(v) && !strncmp(w->s + w->at + w->eq + 1, v, n);
}

/* The value of a key=value setting as a number (all of it). */
static int number(const word *w, double lo, double *out, ggError *err)
{
    const char *v = w->s + w->at + w->eq + 1;
    size_t n = w->len - w->eq - 1, k;
    if (w->eq >= w->len || n == 0)
        return fail(w, w->at, err, "%.*s needs a value", (int)w->eq, w->s + w->at);
    k = gg_dbg_number(v, n, out);
    if (k != n || !isfinite(*out) || *out < lo)
        return fail(w, w->at + w->eq + 1, err, "%.*s must be a number >= %g, got '%.*s'",
                    (int)w->eq, w->s + w->at, lo, (int)n, v);
    return GG_OK;
}

/* The value as a whole number in [lo, hi]: one message for every way to
   miss (not a number, a fraction, out of range), naming the range. */
static int integer(const word *w, int lo, int hi, int *out, ggError *err)
{
    const char *v = w->s + w->at + w->eq + 1;
    size_t n = w->len - w->eq - 1;
    double d;
    if (w->eq >= w->len || n == 0)
        return fail(w, w->at, err, "%.*s needs a value", (int)w->eq, w->s + w->at);
    if (gg_dbg_number(v, n, &d) != n || !(d >= lo && d <= hi) || d != floor(d))
        return fail(w, w->at + w->eq + 1, err,
                    "%.*s must be a whole number from %d to %d, got '%.*s'", (int)w->eq,
                    w->s + w->at, lo, hi, (int)n, v);
    *out = (int)d;
    return GG_OK;
}

/* A value out of a list of names: its index, or an error naming them. */
static int choice(const word *w, const char *const *names, int *out, ggError *err)
{
    char list[200];
    size_t k = 0;
    int i;
    for (i = 0; names[i]; i++)
        if (val_is(w, names[i])) {
            *out = i;
            return GG_OK;
        }
    list[0] = '\0';
    for (i = 0; names[i]; i++)
        k += (size_t)snprintf(list + k, k < sizeof list ? sizeof list - k : 0, "%s%s",
                              i ? (names[i + 1] ? ", " : " or ") : "", names[i]);
    return fail(w, w->eq < w->len ? w->at + w->eq + 1 : w->at, err, "%.*s must be %s, got '%.*s'",
                (int)w->eq, w->s + w->at, list, (int)(w->eq < w->len ? w->len - w->eq - 1 : 0),
                w->s + w->at + w->eq + 1);
}

/* size=WxH and crop=X0,Y0,X1,Y1. */
static int numbers(const word *w, int count, int lo, int *out, ggError *err)
{
    const char *v = w->s + w->at + w->eq + 1;
    size_t n = w->eq < w->len ? w->len - w->eq - 1 : 0, i = 0;
    int k;
    for (k = 0; k < count; k++) {
        double d;
        size_t m = gg_dbg_number(v + i, n - i, &d);
        if (!m || d != floor(d) || d < lo || d > 65536 || v[i] == '+' || v[i] == '-') break;
        out[k] = (int)d, i += m;
        if (k + 1 < count) {
            if (i >= n || !strchr(count == 2 ? "xX" : ",", v[i])) break;
            i++;
        }
    }
    if (k < count || i != n)
        return fail(w, w->at + w->eq + 1, err, "%s must be %s, got '%.*s'",
                    count == 2 ? "size" : "crop", count == 2 ? "WxH" : "X0,Y0,X1,Y1", (int)n, v);
    return GG_OK;
}

static const char *const sphere_names[] = {"stable", "textbook", NULL};
static const char *const refract_names[] = {"accurate", "textbook", "exact", NULL};
static const char *const fresnel_names[] = {"scene", "none", "schlick", "exact", NULL};
static const char *const texture_names[] = {"scene", "bilinear", "nearest", NULL};
static const char *const wave_names[] = {"rgb", "one", NULL};
static const char *const isect_names[] = {"double", "float", NULL};
static const char *const shadow_names[] = {"colored", "opaque", NULL};
static const char *const phong_names[] = {"exact", "fast", NULL};

static int flag(const word *w, ggRenderOptions *o, ggError *err)
{
    if (w->eq < w->len)
        return fail(w, w->at + w->eq, err, "%.*s takes no value", (int)w->eq, w->s + w->at);
    if (key_is(w, "spd")) {
        o->spd_rules = o->pixel_corners = true;
        if (!o->max_depth) o->max_depth = 5;
    } else if (key_is(w, "spd-rules")) {
        o->spd_rules = true;
    } else if (key_is(w, "corners")) {
        o->pixel_corners = true;
    } else {
        o->force_effects = GG_EFFECT_ALL; /* force-effects */
    }
    return GG_OK;
}

/* offset=scaled|fixed|EPS, implicit-tol=own|T and gradient=exact|H: a
   word, or a number > 0. */
static int word_or_number(const word *w, ggRenderOptions *o, ggError *err)
{
    const char *v = w->s + w->at + w->eq + 1;
    size_t n = w->eq < w->len ? w->len - w->eq - 1 : 0;
    int off = key_is(w, "offset"), tol = key_is(w, "implicit-tol");
    const char *word0 = off ? "scaled" : tol ? "own" : "exact";
    double d;
    if (val_is(w, word0)) {
        if (off)
            o->accuracy.offset = GG_ACC_OFFSET_SCALED, o->accuracy.offset_eps = 0;
        else if (tol)
            o->accuracy.implicit_tol = 0;
        else
            o->accuracy.gradient_h = 0;
        return GG_OK;
    }
    if (off && val_is(w, "fixed")) {
        o->accuracy.offset = GG_ACC_OFFSET_FIXED, o->accuracy.offset_eps = 0;
        return GG_OK;
    }
    if (n == 0 || gg_dbg_number(v, n, &d) != n || !isfinite(d) || !(d > 0))
        return fail(w, w->at + w->eq + (n ? 1 : 0), err,
                    "%.*s must be %s%s or a number > 0, got '%.*s'", (int)w->eq, w->s + w->at,
                    word0, off ? ", fixed" : "", (int)n, v);
    if (off)
        o->accuracy.offset = GG_ACC_OFFSET_FIXED, o->accuracy.offset_eps = d;
    else if (tol)
        o->accuracy.implicit_tol = d;
    else
        o->accuracy.gradient_h = d;
    return GG_OK;
}

/* force-effects=NAME+NAME...: those effects (ggEffectName's names; '+'
   because ',' separates settings). Bare force-effects is all of them. */
static int effects(const word *w, ggRenderOptions *o, ggError *err)
{
    const char *v = w->s + w->at + w->eq + 1;
    const size_t n = w->len - w->eq - 1;
    size_t i = 0;
    unsigned mask = 0;
    while (i <= n) {
        size_t j = i;
        int e;
        while (j < n && v[j] != '+') j++;
        for (e = 0; e < GG_EFFECT_COUNT; e++) {
            const char *name = ggEffectName(1u << e);
            if (strlen(name) == j - i && !strncmp(v + i, name, j - i)) break;
        }
        if (e == GG_EFFECT_COUNT)
            return fail(w, w->at + w->eq + 1 + i, err,
                        "force-effects= takes effect names joined by '+' (shadows+reflection), "
                        "got '%.*s'",
                        (int)(j - i), v + i);
        mask |= 1u << e, i = j + 1;
    }
    o->force_effects = mask;
    return GG_OK;
}

/* Every setting's name, for the message about one that is not. */
static const char *const setting_names[] = {
    "size",    "crop",      "depth",   "samples",      "threads",      "ray-budget",
    "sphere",  "refract",   "fresnel", "texture",      "wavelengths",  "intersect",
    "shadows", "phong",     "offset",  "gradient",     "implicit-tol", "cutoff",
    "spd",     "spd-rules", "corners", "force-effects"};

/* An unknown setting: a command-line option where a NAME=VALUE goes
   (-d 8 for depth=8), or a misspelt name (gg_dbg_suggest). */
static int unknown_setting(const word *w, size_t n, ggError *err)
{
    const char *s = w->s + w->at;
    int best;
    if (n && s[0] == '-')
        return fail(w, w->at, err,
                    "unknown setting '%.*s': settings are NAME=VALUE (depth=8, size=64x48), "
                    "not options",
                    (int)n, s);
    best = gg_dbg_suggest(s, n, setting_names, sizeof setting_names / sizeof setting_names[0]);
    if (best >= 0)
        return fail(w, w->at, err, "unknown setting '%.*s'; did you mean '%s'?", (int)n, s,
                    setting_names[best]);
    return fail(w, w->at, err, "unknown setting '%.*s'", (int)n, s);
}

static int setting(const word *w, ggRenderOptions *o, ggError *err)
{
    ggAccuracy *a = &o->accuracy;
    int v[4], rc = GG_OK;
    double d;
    if (key_is(w, "force-effects") && w->eq < w->len) return effects(w, o, err);
    if (key_is(w, "spd") || key_is(w, "spd-rules") || key_is(w, "corners") ||
        key_is(w, "force-effects"))
        return flag(w, o, err);
    if (w->eq >= w->len) return unknown_setting(w, w->len, err);
    if (key_is(w, "size")) {
        /* 0: that side from the camera, as in ggRenderOptions */
        if ((rc = numbers(w, 2, 0, v, err)) == GG_OK) o->width = v[0], o->height = v[1];
    } else if (key_is(w, "crop")) {
        if ((rc = numbers(w, 4, 0, v, err)) == GG_OK)
            o->crop_x0 = v[0], o->crop_y0 = v[1], o->crop_x1 = v[2], o->crop_y1 = v[3];
    } else if (key_is(w, "depth"))
        rc = integer(w, 1, 64, &o->max_depth, err);
    else if (key_is(w, "samples"))
        rc = integer(w, 1, 4096, &o->samples, err);
    else if (key_is(w, "threads"))
        rc = integer(w, 1, 256, &o->threads, err);
    else if (key_is(w, "ray-budget"))
        rc = integer(w, 1, GG_RAY_BUDGET_MAX, &o->ray_budget, err);
    else if (key_is(w, "sphere"))
        rc = choice(w, sphere_names, &a->sphere, err);
    else if (key_is(w, "refract"))
        rc = choice(w, refract_names, &a->refract, err);
    else if (key_is(w, "fresnel"))
        rc = choice(w, fresnel_names, &a->fresnel, err);
    else if (key_is(w, "texture"))
        rc = choice(w, texture_names, &a->texture, err);
    else if (key_is(w, "wavelengths"))
        rc = choice(w, wave_names, &a->wavelengths, err);
    else if (key_is(w, "intersect"))
        rc = choice(w, isect_names, &a->intersect, err);
    else if (key_is(w, "shadows"))
        rc = choice(w, shadow_names, &a->shadows, err);
    else if (key_is(w, "phong"))
        rc = choice(w, phong_names, &a->phong, err);
    else if (key_is(w, "offset") || key_is(w, "gradient") || key_is(w, "implicit-tol"))
        rc = word_or_number(w, o, err);
    else if (key_is(w, "cutoff")) {
        if ((rc = number(w, 0, &d, err)) == GG_OK && d > 1)
            rc = fail(w, w->at + w->eq + 1, err, "cutoff must be a weight from 0 (off) to 1");
        if (rc == GG_OK) a->cutoff = d > 0 ? d : 0; /* -0 is off, as 0 is */
    } else
        return unknown_setting(w, w->eq, err);
    return rc;
}

GG_API int ggRenderOptionsParse(ggRenderOptions *opt, const char *text, ggError *err)
{
    ggRenderOptions o;
    word w;
    size_t n, i = 0;
    if (!opt || !text)
        return gg_error_set(err, GG_ERROR_INVALID, "ggRenderOptionsParse: NULL argument");
    o = *opt;
    n = strlen(text);
    w.s = text;
    for (;;) {
        size_t j;
        int crop;
        while (i < n && strchr(" \t\r\n,", text[i])) i++;
        if (i >= n) break;
        crop = !strncmp(text + i, "crop=", 5);
        /* crop's value has commas of its own */
        for (j = i; j < n && !strchr(crop ? " \t\r\n" : " \t\r\n,", text[j]); j++) {
        }
        w.at = i, w.len = j - i;
        for (w.eq = 0; w.eq < w.len && text[i + w.eq] != '='; w.eq++) {
        }
        if (setting(&w, &o, err) != GG_OK) return GG_ERROR_PARSE;
        i = j;
    }
    *opt = o;
    return GG_OK;
}

/* ---- formatting ---- */

typedef struct out {
    char *buf;
    size_t size, len;
} out;

static void put(out *o, const char *fmt, ...) GG_PRINTF(2, 3);

static void put(out *o, const char *fmt, ...)
{
    va_list ap;
    int k;
    va_start(ap, fmt);
    k = vsnprintf(o->len < o->size ? o->buf + o->len : NULL,
                  o->len < o->size ? o->size - o->len : 0, fmt, ap);
    va_end(ap);
    if (k > 0) o->len += (size_t)k;
}

/* The shortest of %.15g, %.16g, %.17g that reads back as d, with '.' as
   the radix point whatever the locale. */
static void put_num(out *o, const char *key, double d)
{
    char b[64];
    const char *dp = localeconv()->decimal_point;
    int p;
    double back = 0;
    for (p = 15; p <= 17; p++) {
        char *c;
        snprintf(b, sizeof b, "%.*g", p, d);
        if (dp && dp[0] && dp[0] != '.' && dp[1] == 0)
            for (c = b; *c; c++)
                if (*c == dp[0]) *c = '.';
        if (gg_dbg_number(b, strlen(b), &back) == strlen(b) && back == d) break;
    }
    put(o, "%s%s=%s", o->len ? " " : "", key, b);
}

static void put_name(out *o, const char *key, int v, const char *const *names, int count)
{
    if (v > 0 && v < count) put(o, "%s%s=%s", o->len ? " " : "", key, names[v]);
}

/* Bare force-effects reads back as all of them: a subset is named. */
static void put_effects(out *o, unsigned fx)
{
    int e;
    const char *sep = "=";
    if (!fx) return;
    put(o, "%sforce-effects", o->len ? " " : "");
    if (fx == GG_EFFECT_ALL) return;
    for (e = 0; e < GG_EFFECT_COUNT; e++)
        if (fx & (1u << e)) put(o, "%s%s", sep, ggEffectName(1u << e)), sep = "+";
}

GG_API size_t ggRenderOptionsFormat(const ggRenderOptions *opt, char *buf, size_t size)
{
    out o;
    const ggAccuracy *a;
    o.buf = buf, o.size = buf ? size : 0, o.len = 0; /* NULL buf: only the length */
    if (buf && size) buf[0] = '\0';
    if (!opt) return 0;
    a = &opt->accuracy;
    if (opt->width > 0 || opt->height > 0) put(&o, "size=%dx%d", opt->width, opt->height);
    if (opt->max_depth) put(&o, "%sdepth=%d", o.len ? " " : "", opt->max_depth);
    if (opt->samples) put(&o, "%ssamples=%d", o.len ? " " : "", opt->samples);
    if (opt->threads) put(&o, "%sthreads=%d", o.len ? " " : "", opt->threads);
    if (opt->ray_budget) put(&o, "%sray-budget=%d", o.len ? " " : "", opt->ray_budget);
    if (opt->crop_x0 || opt->crop_y0 || opt->crop_x1 || opt->crop_y1)
        put(&o, "%scrop=%d,%d,%d,%d", o.len ? " " : "", opt->crop_x0, opt->crop_y0, opt->crop_x1,
            opt->crop_y1);
    /* "spd" also sets an unset depth to 5: only with a depth, which is
       already written before it, does it read back as these options */
    if (opt->spd_rules && opt->pixel_corners && opt->max_depth) {
        put(&o, "%sspd", o.len ? " " : "");
    } else {
        if (opt->spd_rules) put(&o, "%sspd-rules", o.len ? " " : "");
        if (opt->pixel_corners) put(&o, "%scorners", o.len ? " " : "");
    }
    put_effects(&o, opt->force_effects & GG_EFFECT_ALL);
    /* fixed with no epsilon of its own (1e-6) reads back as itself */
    if (a->offset == GG_ACC_OFFSET_FIXED && a->offset_eps > 0)
        put_num(&o, "offset", a->offset_eps);
    else if (a->offset == GG_ACC_OFFSET_FIXED)
        put(&o, "%soffset=fixed", o.len ? " " : "");
    put_name(&o, "sphere", a->sphere, sphere_names, 2);
    put_name(&o, "refract", a->refract, refract_names, 3);
    put_name(&o, "fresnel", a->fresnel, fresnel_names, 4);
    put_name(&o, "texture", a->texture, texture_names, 3);
    put_name(&o, "wavelengths", a->wavelengths, wave_names, 2);
    put_name(&o, "intersect", a->intersect, isect_names, 2);
    put_name(&o, "shadows", a->shadows, shadow_names, 2);
    put_name(&o, "phong", a->phong, phong_names, 2);
    if (a->cutoff > 0) put_num(&o, "cutoff", a->cutoff);
    if (a->implicit_tol > 0) put_num(&o, "implicit-tol", a->implicit_tol);
    if (a->gradient_h > 0) put_num(&o, "gradient", a->gradient_h);
    return o.len;
}
