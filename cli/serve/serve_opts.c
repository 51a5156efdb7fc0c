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

/* The settings whose values the server bounds below the library's. */
static const struct {
    const char *key;
    int max;
} srv_limits[] = {{"depth", SRV_MAX_DEPTH}, {"samples", SRV_MAX_SAMPLES}};

/* "LINE:COL: key must be a whole number from 1 to MAX here, got 'V'" for
   the value of v at offset at, LINE:COL as ggRenderOptionsParse counts
   them (lines, UTF-8 characters). */
static void limit_message(const char *v, size_t at, size_t n, int k, char *msg, size_t len)
{
    size_t i;
    int line = 1, col = 1;
    for (i = 0; i < at; i++) {
        if (v[i] == '\n')
            line++, col = 1;
        else if (((unsigned char)v[i] & 0xC0) != 0x80)
            col++;
    }
    snprintf(msg, len, "%d:%d: %s must be a whole number from 1 to %d here, got '%.*s'", line, col,
             srv_limits[k].key, srv_limits[k].max, (int)n, v + at);
}

/* The words of v setting depth or samples, as ggRenderOptionsParse splits
   them: at[k] receives the offset of the last one's value (0: none). With
   check, a value the library itself refuses that is a number >= 1 (not
   whole, or over the library's bound: depth=99) is reported with the
   server's bound, which is lower, rather than the library's; an error of
   an earlier setting still comes first. Returns -1 with msg filled then. */
static int scan_limits(const srv_server *s, const char *v, int check, size_t at[2], char *msg,
                       size_t len)
{
    size_t n = strlen(v), i = 0;
    at[0] = at[1] = 0;
    for (;;) {
        size_t j, eq;
        int k, crop;
        while (i < n && strchr(" \t\r\n,", v[i])) i++;
        if (i >= n) break;
        crop = !strncmp(v + i, "crop=", 5);
        for (j = i; j < n && !strchr(crop ? " \t\r\n" : " \t\r\n,", v[j]); j++) {
        }
        for (eq = i; eq < j && v[eq] != '='; eq++) {
        }
        for (k = 0; k < 2 && eq < j; k++) {
            size_t kl = strlen(srv_limits[k].key), vn = j - eq - 1;
            char num[64], *end;
            double d;
            if (eq - i != kl || strncmp(v + i, srv_limits[k].key, kl)) continue;
            at[k] = eq + 1;
            if (!check || vn == 0 || vn >= sizeof num) continue;
            memcpy(num, v + eq + 1, vn);
            num[vn] = 0;
            if (strspn(num, "0123456789.eE+-") != vn) continue;
            d = strtod(num, &end);
            if (*end || !isfinite(d) || d < 1 || (d == floor(d) && d <= srv_limits[k].max))
                continue;
            {
                /* The library's verdict on the text up to this word, and
                   through it: an earlier error is its own; this word
                   refused is the server's bound. */
                ggRenderOptions o = s->cfg.opt;
                ggError err;
                char *head = strndup(v, j);
                int before, through;
                if (!head) {
                    snprintf(msg, len, "out of memory");
                    return -1;
                }
                through = ggRenderOptionsParse(&o, head, &err) != GG_OK;
                head[i] = 0;
                o = s->cfg.opt;
                before = ggRenderOptionsParse(&o, head, &err) != GG_OK;
                free(head);
                if (before) {
                    snprintf(msg, len, "%s", err.message);
                    return -1;
                }
                if (through) {
                    limit_message(v, eq + 1, vn, k, msg, len);
                    return -1;
                }
            }
        }
        i = j;
    }
    return 0;
}

int srv_opts_text(const srv_server *s, const char *v, ggRenderOptions *o, char *msg, size_t len)
{
    const ggRenderOptions *base = &s->cfg.opt;
    ggError err;
    size_t at[2] = {0, 0};
    *o = *base;
    if (v && scan_limits(s, v, 1, at, msg, len)) return -1;
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
        /* the last word that set it (the earlier of the two when both
           are over), named with the server's bound */
        int k = o->max_depth > SRV_MAX_DEPTH ? 0 : 1;
        if (k == 0 && o->samples > SRV_MAX_SAMPLES && at[1] && at[1] < at[0]) k = 1;
        if (at[k]) {
            size_t n = strcspn(v + at[k], " \t\r\n,");
            limit_message(v, at[k], n, k, msg, len);
        } else {
            snprintf(msg, len, "depth is at most %d and samples at most %d here", SRV_MAX_DEPTH,
                     SRV_MAX_SAMPLES);
        }
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

int srv_opts_recordable(const srv_server *s, const ggRenderOptions *o, const char *name,
                        srv_resp *resp)
{
    double need = cli_record_bytes(s->scene, o); /* (common/scene.c) */
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
