/* SPDX-License-Identifier: MIT */
/*
** serve_opts.c -- `ggrt serve`: render options carried in a request's
** query and responses built with stdio.
*/
#if defined(GG_HAVE_MHD)
#include "serve/serve.h"

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
        json_str(f, msg);
        fprintf(f, "}\n");
    }
    srv_body_close(resp, f);
}

/* ---- render options ---- */

int srv_opts_text(const srv_server *s, const char *v, ggRenderOptions *o, char *msg, size_t len)
{
    const ggRenderOptions *base = &s->cfg.opt;
    ggError err;
    *o = *base;
    if (v && ggRenderOptionsParse(o, v, &err) != GG_OK) {
        snprintf(msg, len, "%s", err.message);
        return -1;
    }
    if (o->width != base->width || o->height != base->height || o->threads != base->threads ||
        o->crop_x0 != base->crop_x0 || o->crop_y0 != base->crop_y0 || o->crop_x1 != base->crop_x1 ||
        o->crop_y1 != base->crop_y1) {
        snprintf(msg, len, "size, threads and crop are the server's (its command line)");
        return -1;
    }
    if (o->max_depth > SRV_MAX_DEPTH || o->samples > SRV_MAX_SAMPLES) {
        snprintf(msg, len, "depth is at most %d and samples at most %d here", SRV_MAX_DEPTH,
                 SRV_MAX_SAMPLES);
        return -1;
    }
    return 0;
}

int srv_opts_parse(const srv_server *s, const srv_req *r, const char *name, ggRenderOptions *o,
                   char *text, size_t textlen, srv_resp *resp)
{
    char msg[sizeof(((ggError *)0)->message)];
    if (srv_opts_text(s, srv_param_get(r, name), o, msg, sizeof msg)) {
        /* "opts:1:17: ..." where the text is at fault, "opts: ..." else */
        srv_error(resp, 400, "%s:%s%s", name, msg[0] >= '0' && msg[0] <= '9' ? "" : " ", msg);
        return -1;
    }
    if (text && ggRenderOptionsFormat(o, text, textlen) >= textlen) {
        srv_error(resp, 400, "%s: too long", name);
        return -1;
    }
    return 0;
}

/* The most bytes one pixel's recorded trees can take under o, as a find,
   check or diff records them (each tracing thread holds one pixel's, a
   diff two): every eye ray of the pixel, each with at most 1 + the ray
   budget rays -- fewer when the depth is set: at most 4 children a hit
   (a reflection and three dispersed refractions) -- each ray a node and
   a light record per light. An upper bound, not an estimate: the library
   records with the scene's allocator, so the server cannot meter it as
   /api/trace meters its own tree. */
static double record_bytes(const srv_server *s, const ggRenderOptions *o)
{
    double eyes = (double)(o->samples > 0 ? o->samples : 1) * (o->pixel_corners ? 4 : 1);
    double cap = o->ray_budget > 0 ? o->ray_budget : GG_RAY_BUDGET, rays = 0, level = 1;
    int d;
    for (d = 1; o->max_depth > 0 && d < o->max_depth && rays < cap; d++) rays += level *= 4;
    if (o->max_depth <= 0 || rays > cap) rays = cap;
    return eyes * (1 + rays) *
           ((double)sizeof(ggTraceNode) +
            (double)ggSceneLightCount(s->scene) * (double)sizeof(ggTraceLight));
}

int srv_opts_recordable(const srv_server *s, const ggRenderOptions *o, const char *name,
                        srv_resp *resp)
{
    double need = record_bytes(s, o);
    if (need <= SRV_RECORD_BYTES) return 0;
    srv_error(resp, 413,
              "%s: the ray trees of one pixel could take %.0f MiB here, over the %d MiB a find, "
              "check or diff may record per pixel: lower samples, depth or ray-budget",
              name, need / (1 << 20), SRV_RECORD_BYTES >> 20);
    return -1;
}

#else
typedef int serve_opts_unused;
#endif
