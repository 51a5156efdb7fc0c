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

int srv_opts_parse(const srv_server *s, const srv_req *r, const char *name, ggRenderOptions *o,
                   char *text, size_t textlen, srv_resp *resp)
{
    const char *v = srv_param_get(r, name);
    const ggRenderOptions *base = &s->cfg.opt;
    ggError err;
    *o = *base;
    if (v && ggRenderOptionsParse(o, v, &err) != GG_OK) {
        srv_error(resp, 400, "%s:%s", name, err.message);
        return -1;
    }
    if (o->width != base->width || o->height != base->height || o->threads != base->threads ||
        o->crop_x0 != base->crop_x0 || o->crop_y0 != base->crop_y0 || o->crop_x1 != base->crop_x1 ||
        o->crop_y1 != base->crop_y1) {
        srv_error(resp, 400, "%s: size, threads and crop are the server's (its command line)",
                  name);
        return -1;
    }
    if (o->max_depth > SRV_MAX_DEPTH || o->samples > SRV_MAX_SAMPLES) {
        srv_error(resp, 400, "%s: depth is at most %d and samples at most %d here", name,
                  SRV_MAX_DEPTH, SRV_MAX_SAMPLES);
        return -1;
    }
    if (text && ggRenderOptionsFormat(o, text, textlen) >= textlen) {
        srv_error(resp, 400, "%s: too long", name);
        return -1;
    }
    return 0;
}

#else
typedef int serve_opts_unused;
#endif
