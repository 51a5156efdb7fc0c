/* SPDX-License-Identifier: MIT */
/*
** serve_opts.c -- `ggrt serve`: render options carried in a request's
** query, responses built with stdio, and JSON helpers.
*/
#if defined(GG_HAVE_MHD)
#include "serve.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

const char *srv_param_get(const srv_req *r, const char *key)
{
    int i;
    for (i = 0; i < r->nparams; i++)
        if (!strcmp(r->params[i].key, key)) return r->params[i].value;
    return NULL;
}

int srv_parse_int(const char *s, long lo, long hi, int *out)
{
    char why[96];
    long v;
    if (cli_parse_long(s, lo, hi, &v, why, sizeof why)) return -1;
    *out = (int)v;
    return 0;
}

/* ---- responses ---- */

FILE *srv_body_open(srv_resp *resp, int status, const char *type)
{
    free(resp->body);
    resp->body = NULL;
    resp->len = 0;
    resp->body_static = 0;
    resp->status = status;
    resp->type = type;
    return open_memstream(&resp->body, &resp->len);
}

void srv_body_close(srv_resp *resp, FILE *f)
{
    int bad = !f || ferror(f);
    if (f && fclose(f) != 0) bad = 1;
    if (bad) {
        static char oom[] = "{\"status\":500,\"error\":\"out of memory building the response\"}\n";
        free(resp->body);
        resp->body = oom, resp->len = sizeof oom - 1, resp->body_static = 1;
        resp->status = 500, resp->type = "application/json";
    }
}

void srv_error(srv_resp *resp, int status, const char *fmt, ...)
{
    char msg[768];
    va_list ap;
    FILE *f;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    f = srv_body_open(resp, status, "application/json");
    if (f) {
        fprintf(f, "{\"status\":%d,\"error\":", status);
        srv_json_str(f, msg);
        fprintf(f, "}\n");
    }
    srv_body_close(resp, f);
}

void srv_json_num(FILE *f, double d)
{
    /* JSON has no NaN or infinity: null stands for them (docs/trace-json.md). */
    if (isfinite(d))
        fprintf(f, "%.17g", d);
    else
        fprintf(f, "null");
}

/* Length of the valid UTF-8 sequence at s (RFC 3629: no overlongs, no
   surrogates, at most U+10FFFF), or 0. */
static int utf8_len(const unsigned char *s)
{
    int n, i;
    unsigned c = s[0];
    if (c < 0x80) return 1;
    if (c >= 0xc2 && c <= 0xdf)
        n = 2;
    else if (c >= 0xe0 && c <= 0xef)
        n = 3;
    else if (c >= 0xf0 && c <= 0xf4)
        n = 4;
    else
        return 0;
    for (i = 1; i < n; i++)
        if ((s[i] & 0xc0) != 0x80) return 0;
    if (n == 3 && ((c == 0xe0 && s[1] < 0xa0) || (c == 0xed && s[1] > 0x9f))) return 0;
    if (n == 4 && ((c == 0xf0 && s[1] < 0x90) || (c == 0xf4 && s[1] > 0x8f))) return 0;
    return n;
}

/* A JSON string; bytes that are not UTF-8 (a query can carry any) become
   U+FFFD, so the document always parses. */
void srv_json_str(FILE *f, const char *s)
{
    const unsigned char *p = (const unsigned char *)s;
    fputc('"', f);
    while (*p) {
        int n = utf8_len(p);
        if (!n) {
            fputs("\\ufffd", f);
            p++;
        } else if (*p == '"' || *p == '\\') {
            fprintf(f, "\\%c", *p++);
        } else if (*p < 0x20 || *p == 0x7f) {
            fprintf(f, "\\u%04x", *p++);
        } else {
            fwrite(p, 1, (size_t)n, f);
            p += n;
        }
    }
    fputc('"', f);
}

/* ---- render options ---- */

typedef struct choice {
    const char *name;
    int value;
} choice;

static const choice c_offset[] = {
    {"scaled", GG_ACC_OFFSET_SCALED}, {"fixed", GG_ACC_OFFSET_FIXED}, {0, 0}};
static const choice c_sphere[] = {
    {"stable", GG_ACC_SPHERE_STABLE}, {"textbook", GG_ACC_SPHERE_TEXTBOOK}, {0, 0}};
static const choice c_refract[] = {{"accurate", GG_ACC_REFRACT_ACCURATE},
                                   {"textbook", GG_ACC_REFRACT_TEXTBOOK},
                                   {"exact", GG_ACC_REFRACT_EXACT},
                                   {0, 0}};
static const choice c_fresnel[] = {{"material", 0},
                                   {"none", GG_ACC_FRESNEL_NONE},
                                   {"schlick", GG_ACC_FRESNEL_SCHLICK},
                                   {"exact", GG_ACC_FRESNEL_EXACT},
                                   {0, 0}};
static const choice c_texture[] = {{"material", 0},
                                   {"bilinear", GG_ACC_TEXTURE_BILINEAR},
                                   {"nearest", GG_ACC_TEXTURE_NEAREST},
                                   {0, 0}};
static const choice c_wave[] = {{"rgb", 0}, {"one", 1}, {0, 0}};
static const choice c_bool[] = {{"0", 0}, {"1", 1}, {"false", 0}, {"true", 1}, {0, 0}};

static const char *const option_names[] = {"depth",   "samples",      "spd",        "corners",
                                           "force",   "offset",       "offset_eps", "sphere",
                                           "refract", "fresnel",      "texture",    "wavelengths",
                                           "cutoff",  "implicit_tol", "gradient_h", NULL};

int srv_opts_known(const char *key)
{
    int i;
    if (!strncmp(key, "b.", 2)) key += 2;
    for (i = 0; option_names[i]; i++)
        if (!strcmp(key, option_names[i])) return 1;
    return 0;
}

static const char *choice_name(const choice *c, int v)
{
    for (; c->name; c++)
        if (c->value == v) return c->name;
    return "?";
}

typedef struct popt {
    const srv_req *r;
    const char *prefix;
    srv_resp *resp;
    int bad;
} popt;

static const char *get(popt *p, const char *name, char *full, size_t n)
{
    snprintf(full, n, "%s%s", p->prefix, name);
    return srv_param_get(p->r, full);
}

static void opt_choice(popt *p, const char *name, const choice *c, int *out)
{
    char full[64], list[128] = "";
    const char *v = get(p, name, full, sizeof full);
    const choice *k;
    if (!v || p->bad) return;
    for (k = c; k->name; k++)
        if (!strcmp(v, k->name)) {
            *out = k->value;
            return;
        }
    for (k = c; k->name; k++) {
        if (c == c_bool && k > c + 1) break;
        snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", k == c ? "" : ", ",
                 k->name);
    }
    srv_error(p->resp, 400, "%s must be one of %s, got '%s'", full, list, v);
    p->bad = 1;
}

static void opt_int(popt *p, const char *name, int lo, int hi, int *out)
{
    char full[64];
    const char *v = get(p, name, full, sizeof full);
    if (!v || p->bad) return;
    if (srv_parse_int(v, lo, hi, out)) {
        srv_error(p->resp, 400, "%s must be a whole number from %d to %d, got '%s'", full, lo, hi,
                  v);
        p->bad = 1;
    }
}

static void opt_num(popt *p, const char *name, double *out)
{
    char full[64], why[96];
    const char *v = get(p, name, full, sizeof full);
    if (!v || p->bad) return;
    if (cli_parse_num(v, 0, 1e6, out, why, sizeof why)) {
        srv_error(p->resp, 400, "%s must be a number from 0 to 1e6, got '%s'", full, v);
        p->bad = 1;
    }
}

int srv_opts_parse(const srv_server *s, const srv_req *r, const char *prefix, ggRenderOptions *o,
                   char *key, size_t keylen, srv_resp *resp)
{
    popt p;
    int spd = s->cfg.opt.spd_rules, corners = s->cfg.opt.pixel_corners,
        force = s->cfg.opt.force_effects != 0;
    ggAccuracy *a = &o->accuracy;
    *o = s->cfg.opt;
    p.r = r, p.prefix = prefix, p.resp = resp, p.bad = 0;
    opt_int(&p, "depth", 0, SRV_MAX_DEPTH, &o->max_depth);
    opt_int(&p, "samples", 0, SRV_MAX_SAMPLES, &o->samples);
    opt_choice(&p, "spd", c_bool, &spd);
    opt_choice(&p, "corners", c_bool, &corners);
    opt_choice(&p, "force", c_bool, &force);
    opt_choice(&p, "offset", c_offset, &a->offset);
    opt_num(&p, "offset_eps", &a->offset_eps);
    opt_choice(&p, "sphere", c_sphere, &a->sphere);
    opt_choice(&p, "refract", c_refract, &a->refract);
    opt_choice(&p, "fresnel", c_fresnel, &a->fresnel);
    opt_choice(&p, "texture", c_texture, &a->texture);
    opt_choice(&p, "wavelengths", c_wave, &a->wavelengths);
    opt_num(&p, "cutoff", &a->cutoff);
    opt_num(&p, "implicit_tol", &a->implicit_tol);
    opt_num(&p, "gradient_h", &a->gradient_h);
    if (p.bad) return -1;
    /* As ggrt trace --spd: SPD rules imply pixel corners and depth 5. */
    o->spd_rules = spd != 0;
    o->pixel_corners = corners != 0 || spd != 0;
    if (spd && !o->max_depth) o->max_depth = 5;
    o->force_effects = force ? GG_EFFECT_ALL : 0;
    o->width = s->cfg.width, o->height = s->cfg.height;
    snprintf(key, keylen, "d%d n%d spd%d c%d f%u o%d e%a s%d r%d F%d t%d w%d k%a i%a g%a",
             o->max_depth, o->samples, o->spd_rules, o->pixel_corners, o->force_effects, a->offset,
             a->offset_eps, a->sphere, a->refract, a->fresnel, a->texture, a->wavelengths,
             a->cutoff, a->implicit_tol, a->gradient_h);
    return 0;
}

void srv_opts_json(FILE *f, const ggRenderOptions *o)
{
    const ggAccuracy *a = &o->accuracy;
    fprintf(f, "{\"depth\":%d,\"samples\":%d,\"spd\":%s,\"corners\":%s,\"force\":%s,", o->max_depth,
            o->samples, o->spd_rules ? "true" : "false", o->pixel_corners ? "true" : "false",
            o->force_effects ? "true" : "false");
    fprintf(f, "\"offset\":\"%s\",\"offset_eps\":", choice_name(c_offset, a->offset));
    srv_json_num(f, a->offset_eps);
    fprintf(f,
            ",\"sphere\":\"%s\",\"refract\":\"%s\",\"fresnel\":\"%s\",\"texture\":\"%s\","
            "\"wavelengths\":\"%s\",\"cutoff\":",
            choice_name(c_sphere, a->sphere), choice_name(c_refract, a->refract),
            choice_name(c_fresnel, a->fresnel), choice_name(c_texture, a->texture),
            choice_name(c_wave, a->wavelengths));
    srv_json_num(f, a->cutoff);
    fprintf(f, ",\"implicit_tol\":");
    srv_json_num(f, a->implicit_tol);
    fprintf(f, ",\"gradient_h\":");
    srv_json_num(f, a->gradient_h);
    fputc('}', f);
}

#else
typedef int serve_opts_unused;
#endif
