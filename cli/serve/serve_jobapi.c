/* SPDX-License-Identifier: MIT */
/*
** serve_jobapi.c -- `ggrt serve`'s routes over jobs (serve_jobs.c):
** /api/render, /api/image, /api/find, /api/check, /api/diff. A route
** names its job by the canonical text of its options, starts it or finds
** it, and answers 202 with its progress until it is done; the JSON of a
** finished find, check or diff is what the command line prints with
** --format json (cli/debug/debug.c writes both).
*/
#if defined(GG_HAVE_MHD)
#include "serve/serve.h"
#include "debug/debug.h"
#include "common/heatmap.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define KEYLEN     2048
#define FIND_LIMIT 100000 /* matches /api/find may list */
#define DIFF_LIMIT 1000   /* worst pixels /api/diff may list (as ggrt diff --worst) */

static void retry_after(srv_resp *resp, const char *seconds)
{
    snprintf(resp->extra_name, sizeof resp->extra_name, "Retry-After");
    snprintf(resp->extra_value, sizeof resp->extra_value, "%s", seconds);
}

/* Find or start the job; unless it is done (or always_report), fill resp
   with its state: 202 while it runs, 500 when it failed, 503 when no slot
   is free. Returns 1 when it is done. */
static int job_ready(srv_server *s, const char *key, const srv_job_spec *spec, srv_resp *resp,
                     int always_report)
{
    srv_job_view v;
    FILE *f;
    if (srv_jobs_request(s, key, spec, &v)) {
        srv_error(resp, 503, "%s", v.error);
        retry_after(resp, "2");
        return 0;
    }
    if (v.state == SRV_STATE_DONE && !always_report) return 1;
    if (v.state == SRV_STATE_FAILED) {
        srv_error(resp, 500, "failed: %s", v.error);
        return 0;
    }
    f = srv_body_open(resp, v.state == SRV_STATE_DONE ? 200 : 202, "application/json");
    if (f) {
        fprintf(f, "{\"job\":");
        srv_job_json(f, &v);
        fputc(',', f), json_options(f, "options", &spec->opt);
        if (spec->type == SRV_TYPE_DIFF) fputc(',', f), json_options(f, "options_b", &spec->opt_b);
        fprintf(f, "}\n");
    }
    srv_body_close(resp, f);
    if (v.state != SRV_STATE_DONE) retry_after(resp, "1");
    return v.state == SRV_STATE_DONE;
}

static int kind_arg(const srv_req *r, int *kind, srv_resp *resp)
{
    const char *k = srv_param_get(r, "kind");
    if (!k || !strcmp(k, "image"))
        *kind = SRV_KIND_IMAGE;
    else if (!strcmp(k, "rays"))
        *kind = GG_COST_RAYS;
    else if (!strcmp(k, "depth"))
        *kind = GG_COST_DEPTH;
    else if (!strcmp(k, "time"))
        *kind = GG_COST_TIME;
    else {
        srv_error(resp, 400, "kind must be image, rays, depth or time, got '%s'", k);
        return -1;
    }
    return 0;
}

static int format_arg(const srv_req *r, const char *const *allowed, const char **out,
                      srv_resp *resp)
{
    const char *v = srv_param_get(r, "format");
    char list[128] = "";
    int i;
    *out = allowed[0];
    if (!v) return 0;
    for (i = 0; allowed[i]; i++)
        if (!strcmp(v, allowed[i])) {
            *out = allowed[i];
            return 0;
        }
    for (i = 0; allowed[i]; i++)
        snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s",
                 i ? (allowed[i + 1] ? ", " : " or ") : "", allowed[i]);
    srv_error(resp, 400, "format must be %s, got '%s'", list, v);
    return -1;
}

/* A render job's spec and name from the request. */
static int render_spec(srv_server *s, const srv_req *r, srv_job_spec *sp, char *key, srv_resp *resp)
{
    char text[512];
    memset(sp, 0, sizeof *sp);
    sp->type = SRV_TYPE_RENDER;
    if (kind_arg(r, &sp->kind, resp) ||
        srv_opts_parse(s, r, "opts", &sp->opt, text, sizeof text, resp))
        return -1;
    snprintf(key, KEYLEN, "render %d|%s", sp->kind, text);
    return 0;
}

void srv_api_render(srv_server *s, const srv_req *r, srv_resp *resp)
{
    char key[KEYLEN];
    srv_job_spec sp;
    if (render_spec(s, r, &sp, key, resp) == 0) job_ready(s, key, &sp, resp, 1);
}

/* Raw floats, little-endian whatever the host (docs/serve.md). */
static void send_floats(srv_server *s, const float *src, size_t n, srv_resp *resp)
{
    const uint16_t one = 1;
    float *v = malloc(n * sizeof *v);
    if (!v) {
        srv_error(resp, 500, "out of memory");
        return;
    }
    memcpy(v, src, n * sizeof *v);
    if (*(const unsigned char *)&one != 1) {
        unsigned char *b = (unsigned char *)v, t;
        size_t i;
        for (i = 0; i < n * 4; i += 4) {
            t = b[i], b[i] = b[i + 3], b[i + 3] = t;
            t = b[i + 1], b[i + 1] = b[i + 2], b[i + 2] = t;
        }
    }
    resp->status = 200, resp->type = "application/octet-stream";
    resp->body = (char *)v, resp->len = n * sizeof *v;
    snprintf(resp->extra_name, sizeof resp->extra_name, "X-GGRT-Size");
    snprintf(resp->extra_value, sizeof resp->extra_value, "%dx%d", s->cfg.width, s->cfg.height);
}

static void send_bytes(srv_server *s, const unsigned char *src, size_t n, srv_resp *resp)
{
    char *v = malloc(n ? n : 1);
    if (!v) {
        srv_error(resp, 500, "out of memory");
        return;
    }
    memcpy(v, src, n);
    resp->status = 200, resp->type = "application/octet-stream";
    resp->body = v, resp->len = n;
    snprintf(resp->extra_name, sizeof resp->extra_name, "X-GGRT-Size");
    snprintf(resp->extra_value, sizeof resp->extra_value, "%dx%d", s->cfg.width, s->cfg.height);
}

/* A cost or difference map as ggrt render --heatmap draws it (legend
   under the image; robust: a time map's scale, heatmap.h), or the image
   itself when label is NULL. */
static void send_png(srv_server *s, const float *v, const char *label, int robust, srv_resp *resp)
{
    int w = s->cfg.width, h = s->cfg.height;
    unsigned char *png;
    if (label) {
        heatmap_range r = {0, 0, 0, 0};
        ggImage *map = heatmap_image(v, w, h, label, robust, &r);
        png = map ? srv_png(ggImagePixelsConst(map), ggImageWidth(map), ggImageHeight(map),
                            &resp->len)
                  : NULL;
        ggImageFree(map);
        snprintf(resp->extra_name, sizeof resp->extra_name, "X-GGRT-Max");
        snprintf(resp->extra_value, sizeof resp->extra_value, "%.9g", r.max);
        snprintf(resp->extra2_name, sizeof resp->extra2_name, "X-GGRT-Top");
        snprintf(resp->extra2_value, sizeof resp->extra2_value, "%.9g", r.top);
    } else {
        png = srv_png(v, w, h, &resp->len);
    }
    if (!png) {
        resp->extra_name[0] = resp->extra2_name[0] = '\0';
        srv_error(resp, 500, "out of memory");
        return;
    }
    resp->status = 200, resp->type = "image/png", resp->body = (char *)png;
}

void srv_api_image(srv_server *s, const srv_req *r, srv_resp *resp)
{
    static const char *const formats[] = {"png", "f32", NULL};
    static const char *const label[] = {"rays", "depth", "time s"};
    const char *fmt;
    char key[KEYLEN];
    srv_job_spec sp;
    const srv_result *res;
    size_t n = (size_t)s->cfg.width * s->cfg.height;
    if (format_arg(r, formats, &fmt, resp) || render_spec(s, r, &sp, key, resp)) return;
    if (!job_ready(s, key, &sp, resp, 0)) return;
    if (!(res = srv_jobs_acquire(s, key))) {
        srv_error(resp, 503, "the render was replaced by newer ones; ask again");
        return;
    }
    if (!strcmp(fmt, "f32"))
        send_floats(s, sp.kind >= 0 ? res->cost : res->px, sp.kind >= 0 ? n : 3 * n, resp);
    else
        send_png(s, sp.kind >= 0 ? res->cost : res->px, sp.kind >= 0 ? label[sp.kind] : NULL,
                 sp.kind >= 0 && !strcmp(label[sp.kind], "time s"), resp);
    srv_jobs_release(s, res);
}

/* ---- find ---- */

static int limit_arg(const srv_req *r, int dflt, int hi, int *out, srv_resp *resp)
{
    const char *v = srv_param_get(r, "limit");
    *out = dflt;
    if (v && srv_parse_int(v, 0, hi, out)) {
        srv_error(resp, 400, "limit must be a whole number from 0 to %d, got '%s'", hi, v);
        return -1;
    }
    return 0;
}

/* The find's expression: where (a predicate) or path (a light-path
   expression), exactly one, checked; sp->where and sp->lpe receive it. */
static int find_expr(const srv_req *r, srv_job_spec *sp, srv_resp *resp)
{
    const char *where = srv_param_get(r, "where"), *path = srv_param_get(r, "path");
    const char *name = path ? "path" : "where", *v = path ? path : where;
    ggPredicate *pred = NULL;
    ggPathExpr *lpe = NULL;
    ggError err;
    int rc;
    if (!where == !path) {
        srv_error(resp, 400, "%s", where ? "give where or path, not both"
                                         : "missing parameter where (a predicate) or path (a "
                                           "light-path expression), docs/debugging.md");
        return -1;
    }
    if (strlen(v) > SRV_MAX_EXPR || !ggUTF8Valid(v, strlen(v))) {
        srv_error(resp, 400, "%s: at most %d bytes of UTF-8", name, SRV_MAX_EXPR);
        return -1;
    }
    rc = path ? ggPathParse(v, NULL, &lpe, &err) : ggPredicateParse(v, NULL, &pred, &err);
    ggPathFree(lpe), ggPredicateFree(pred);
    if (rc != GG_OK) {
        srv_error(resp, 400, "%s:%s", name, err.message);
        return -1;
    }
    sp->where = v, sp->lpe = path != NULL;
    return 0;
}

/* A finished find in the format asked for: the JSON of ggrt find
   --format json, the mask, or (with a path) the share map as floats or
   as a heatmap PNG with its legend. */
static void find_body(srv_server *s, const char *fmt, const srv_job_spec *sp, const srv_result *res,
                      srv_resp *resp)
{
    size_t n = (size_t)s->cfg.width * s->cfg.height;
    FILE *f;
    if (!strcmp(fmt, "mask")) {
        send_bytes(s, res->find.mask, n, resp);
    } else if (!strcmp(fmt, "share")) {
        send_floats(s, res->share, n, resp);
    } else if (!strcmp(fmt, "png")) {
        send_png(s, res->share, "share", 0, resp);
    } else {
        f = srv_body_open(resp, 200, "application/json");
        if (f)
            json_find(f, s->cfg.scene_path, &sp->opt, sp->lpe ? NULL : sp->where,
                      sp->lpe ? sp->where : NULL, &res->find);
        srv_body_close(resp, f);
    }
}

void srv_api_find(srv_server *s, const srv_req *r, srv_resp *resp)
{
    static const char *const formats[] = {"json", "mask", "share", "png", NULL};
    const char *fmt;
    char text[512], key[KEYLEN];
    srv_job_spec sp;
    const srv_result *res;
    memset(&sp, 0, sizeof sp);
    if (find_expr(r, &sp, resp) || format_arg(r, formats, &fmt, resp) ||
        limit_arg(r, 20, FIND_LIMIT, &sp.limit, resp) ||
        srv_opts_parse(s, r, "opts", &sp.opt, text, sizeof text, resp) ||
        srv_opts_recordable(s, &sp.opt, "opts", resp))
        return;
    /* 0 lists them all, as ggrt find --limit 0 does, up to the server's
       most (docs/serve.md) */
    if (sp.limit == 0) sp.limit = FIND_LIMIT;
    if (!sp.lpe && (!strcmp(fmt, "share") || !strcmp(fmt, "png"))) {
        srv_error(resp, 400, "format %s is the share of a path: give path, not where", fmt);
        return;
    }
    sp.type = SRV_TYPE_FIND;
    snprintf(key, sizeof key, "find%s %d|%s|%s", sp.lpe ? "path" : "", sp.limit, text, sp.where);
    if (!job_ready(s, key, &sp, resp, 0)) return;
    if (!(res = srv_jobs_acquire(s, key))) {
        srv_error(resp, 503, "the find was replaced by newer jobs; ask again");
        return;
    }
    find_body(s, fmt, &sp, res, resp);
    srv_jobs_release(s, res);
}

/* ---- check ---- */

/* The invariants at one pixel: one ggCheck of a 1x1 window, at once. */
static void check_pixel(srv_server *s, const srv_req *r, ggRenderOptions *o, srv_resp *resp)
{
    ggCheckResult *res = NULL;
    ggError err;
    FILE *f;
    int x, y, rc;
    if (srv_pixel_arg(s, r, "x", s->cfg.width, &x, resp) ||
        srv_pixel_arg(s, r, "y", s->cfg.height, &y, resp))
        return;
    o->crop_x0 = x, o->crop_y0 = y, o->crop_x1 = x + 1, o->crop_y1 = y + 1;
    rc = ggCheck(s->scene, o, NULL, &res, &err);
    if (rc != GG_OK) {
        srv_error(resp, 500, "%s", err.message);
        return;
    }
    f = srv_body_open(resp, 200, "application/json");
    if (f) json_check(f, s->cfg.scene_path, o, res);
    srv_body_close(resp, f);
    ggCheckResultFree(res);
}

void srv_api_check(srv_server *s, const srv_req *r, srv_resp *resp)
{
    static const char *const formats[] = {"json", NULL};
    const char *fmt;
    char text[512], key[KEYLEN];
    srv_job_spec sp;
    const srv_result *res;
    FILE *f;
    memset(&sp, 0, sizeof sp);
    if (format_arg(r, formats, &fmt, resp) ||
        srv_opts_parse(s, r, "opts", &sp.opt, text, sizeof text, resp) ||
        srv_opts_recordable(s, &sp.opt, "opts", resp))
        return;
    if (srv_param_get(r, "x") || srv_param_get(r, "y")) {
        check_pixel(s, r, &sp.opt, resp);
        return;
    }
    sp.type = SRV_TYPE_CHECK;
    snprintf(key, sizeof key, "check|%s", text);
    if (!job_ready(s, key, &sp, resp, 0)) return;
    if (!(res = srv_jobs_acquire(s, key))) {
        srv_error(resp, 503, "the check was replaced by newer jobs; ask again");
        return;
    }
    f = srv_body_open(resp, 200, "application/json");
    if (f) json_check(f, s->cfg.scene_path, &sp.opt, &res->check);
    srv_body_close(resp, f);
    srv_jobs_release(s, res);
}

/* ---- diff ---- */

/* Per pixel, the largest channel difference |a - b|; a NaN on one side
   only counts as infinite. */
static float *divergence(const float *a, const float *b, size_t n)
{
    float *d = malloc(n * sizeof *d);
    size_t i;
    int k;
    if (!d) return NULL;
    for (i = 0; i < n; i++) {
        float m = 0;
        for (k = 0; k < 3; k++) {
            float x = a[3 * i + k], y = b[3 * i + k], e;
            /* in double, as ggDiff's delta, then stored as float */
            e = isnan(x) != isnan(y) ? INFINITY : isnan(x) ? 0 : (float)fabs((double)x - y);
            if (e > m) m = e;
        }
        d[i] = m;
    }
    return d;
}

static void diff_body(srv_server *s, const char *fmt, const srv_job_spec *sp, const srv_result *res,
                      srv_resp *resp)
{
    size_t n = (size_t)s->cfg.width * s->cfg.height;
    float *d;
    FILE *f;
    if (!strcmp(fmt, "map")) {
        send_bytes(s, res->diff.map, n, resp);
    } else if (!strcmp(fmt, "json")) {
        f = srv_body_open(resp, 200, "application/json");
        if (f) json_diff(f, s->cfg.scene_path, s->cfg.scene_path, &sp->opt, &sp->opt_b, &res->diff);
        srv_body_close(resp, f);
    } else if (!(d = divergence(res->px, res->px_b, n))) {
        srv_error(resp, 500, "out of memory");
    } else {
        if (!strcmp(fmt, "f32"))
            send_floats(s, d, n, resp);
        else
            send_png(s, d, "", 0, resp);
        free(d);
    }
}

void srv_api_diff(srv_server *s, const srv_req *r, srv_resp *resp)
{
    static const char *const formats[] = {"json", "map", "f32", "png", NULL};
    const char *fmt;
    char ta[512], tb[512], key[KEYLEN];
    srv_job_spec sp;
    const srv_result *res;
    memset(&sp, 0, sizeof sp);
    if (format_arg(r, formats, &fmt, resp) || limit_arg(r, 10, DIFF_LIMIT, &sp.limit, resp) ||
        srv_opts_parse(s, r, "opts", &sp.opt, ta, sizeof ta, resp) ||
        srv_opts_parse(s, r, "b", &sp.opt_b, tb, sizeof tb, resp) ||
        srv_opts_recordable(s, &sp.opt, "opts", resp) ||
        srv_opts_recordable(s, &sp.opt_b, "b", resp))
        return;
    sp.type = SRV_TYPE_DIFF;
    snprintf(key, sizeof key, "diff %d|%s|%s", sp.limit, ta, tb);
    if (!job_ready(s, key, &sp, resp, 0)) return;
    if (!(res = srv_jobs_acquire(s, key))) {
        srv_error(resp, 503, "the diff was replaced by newer jobs; ask again");
        return;
    }
    diff_body(s, fmt, &sp, res, resp);
    srv_jobs_release(s, res);
}

/* ---- cancel ---- */

/* Ask to cancel the job numbered id (the "id" of its job JSON): a queued
   or running job stops SRV_CANCEL_GRACE seconds later unless it is asked
   for again meanwhile (another page may want it), and is forgotten. */
void srv_api_cancel(srv_server *s, const srv_req *r, srv_resp *resp)
{
    const char *v = srv_param_get(r, "id");
    srv_job_view view;
    unsigned long id = 0;
    FILE *f;
    int i;
    for (i = 0; v && v[i] >= '0' && v[i] <= '9' && i < 18; i++)
        id = id * 10 + (unsigned long)(v[i] - '0');
    if (!v || !v[0] || v[i] || !id) {
        srv_error(resp, 400, "id must be a job's number (the \"id\" of its job), got '%s'",
                  v ? v : "nothing");
        return;
    }
    if (srv_jobs_cancel_id(s, id, &view)) {
        srv_error(resp, 404, "no job %lu: done and replaced, cancelled, or never started", id);
        return;
    }
    f = srv_body_open(resp, 200, "application/json");
    if (f) {
        fprintf(f, "{\"cancelling\":%s,\"job\":", view.state < SRV_STATE_DONE ? "true" : "false");
        srv_job_json(f, &view);
        fprintf(f, "}\n");
    }
    srv_body_close(resp, f);
}

#else
typedef int serve_jobapi_unused;
#endif
