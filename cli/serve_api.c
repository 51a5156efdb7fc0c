/* SPDX-License-Identifier: MIT */
/*
** serve_api.c -- `ggrt serve`'s routes: the page, and the JSON API that
** the page and scripts use (docs/serve.md).
*/
#if defined(GG_HAVE_MHD)
#include "serve.h"
#include "heatmap.h"
#include "trace_out.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_SCENE_OBJECTS 20000 /* objects /api/scene describes (as the SVG views) */

typedef struct route {
    const char *path;
    void (*run)(srv_server *s, const srv_req *r, srv_resp *resp);
    const char *params; /* accepted parameters besides token and (opts) the render options */
    int opts;           /* 1: the render options; 2: also the second set (b.*) */
} route;

static const route *find_route(const char *path);

int srv_param_allowed(const char *path, const char *key)
{
    const route *rt = find_route(path);
    const char *p;
    size_t n = strlen(key);
    if (!rt) return 1; /* answered 404 anyway */
    if (rt->opts && srv_opts_known(key) && (rt->opts == 2 || strncmp(key, "b.", 2))) return 1;
    for (p = rt->params; *p;) {
        const char *e = strchr(p, ' ');
        size_t l = e ? (size_t)(e - p) : strlen(p);
        if (l == n && !strncmp(p, key, n)) return 1;
        p += l + (e != NULL);
    }
    return 0;
}

/* ---- the page ---- */

static const srv_asset *asset(const char *path)
{
    int i;
    for (i = 0; i < srv_nassets; i++)
        if (!strcmp(srv_assets[i].path, path)) return &srv_assets[i];
    return NULL;
}

/* index.html names the token in its script and style links (a page's
   sub-resources carry no Authorization header): "@TOKEN@" becomes it. */
static void page(srv_server *s, const srv_req *r, srv_resp *resp)
{
    const srv_asset *a = asset(!strcmp(r->path, "/") ? "/index.html" : r->path);
    FILE *f;
    size_t i;
    if (!a) {
        srv_error(resp, 404, "no such page: %s", r->path);
        return;
    }
    if (strcmp(a->path, "/index.html")) {
        resp->status = 200, resp->type = a->type;
        resp->body = (char *)a->data, resp->len = a->len, resp->body_static = 1;
        return;
    }
    f = srv_body_open(resp, 200, a->type);
    if (f)
        for (i = 0; i < a->len; i++) {
            if (a->data[i] == '@' && i + 7 <= a->len && !memcmp(a->data + i, "@TOKEN@", 7)) {
                fputs(s->token, f);
                i += 6;
            } else {
                fputc(a->data[i], f);
            }
        }
    srv_body_close(resp, f);
}

/* ---- /api/info ---- */

static void vec(FILE *f, const char *k, ggVec3 v)
{
    fprintf(f, "\"%s\":[", k);
    srv_json_num(f, v.x), fputc(',', f), srv_json_num(f, v.y), fputc(',', f), srv_json_num(f, v.z);
    fputc(']', f);
}

static void api_info(srv_server *s, const srv_req *r, srv_resp *resp)
{
    FILE *f = srv_body_open(resp, 200, "application/json");
    ggCamera cam;
    ggSceneInfo in;
    unsigned fx, e;
    int first = 1;
    (void)r;
    if (!f) {
        srv_body_close(resp, f);
        return;
    }
    srv_lib_lock(s);
    cam = ggSceneCamera(s->scene);
    ggSceneGetInfo(s->scene, &in);
    fx = ggSceneEffects(s->scene);
    fprintf(f, "{\"ggrt\":\"%s\",\"scene\":", ggVersion());
    srv_json_str(f, s->cfg.scene_path);
    fprintf(f, ",\"width\":%d,\"height\":%d,\"objects\":%d,\"lights\":%d,\"materials\":%d,",
            s->cfg.width, s->cfg.height, ggSceneObjectCount(s->scene), ggSceneLightCount(s->scene),
            ggSceneMaterialCount(s->scene));
    fprintf(f, "\"camera\":{");
    vec(f, "from", cam.from), fputc(',', f), vec(f, "at", cam.at), fputc(',', f);
    vec(f, "up", cam.up);
    fprintf(f, ",\"fov\":");
    srv_json_num(f, cam.fov_deg);
    fprintf(f, "},\"bounds\":{");
    vec(f, "lo", in.lo), fputc(',', f), vec(f, "hi", in.hi);
    fprintf(f, "},\"primitives\":%zu,\"effects\":[", in.primitives);
    for (e = 1; e < (1u << GG_EFFECT_COUNT); e <<= 1) {
        const char *why = ggSceneEffectReason(s->scene, e);
        if (!(fx & e)) continue;
        fprintf(f, "%s{\"name\":\"%s\",\"reason\":", first ? "" : ",", ggEffectName(e));
        srv_json_str(f, why ? why : "");
        fputc('}', f);
        first = 0;
    }
    srv_lib_unlock(s);
    fprintf(f, "],\"options\":");
    srv_opts_json(f, &s->cfg.opt);
    fprintf(f,
            ",\"limits\":{\"max_depth\":%d,\"max_samples\":%d,\"trace_bytes\":%d,"
            "\"render_jobs\":%d,\"render_seconds\":%d,\"uri_bytes\":%d,\"params\":%d,"
            "\"value_bytes\":%d,\"connections\":%d,\"threads\":%d,\"timeout_seconds\":%d,"
            "\"head_bytes\":%d,\"expr_bytes\":%d}",
            SRV_MAX_DEPTH, SRV_MAX_SAMPLES, SRV_TRACE_BYTES, SRV_MAX_JOBS, SRV_RENDER_SECONDS,
            SRV_MAX_URI, SRV_MAX_PARAMS, SRV_MAX_VALUE, SRV_MAX_CONNECTIONS, SRV_THREADS,
            SRV_CONN_TIMEOUT, SRV_MEMORY_LIMIT, SRV_MAX_EXPR);
    fprintf(f, ",\"features\":{\"find\":false,\"check\":false,\"ledger\":false}}\n");
    srv_body_close(resp, f);
}

/* ---- /api/scene: shapes for the page's 3D view ---- */

static void shape_json(FILE *f, const ggShapeDesc *d)
{
    int i;
    fprintf(f, "{\"kind\":\"%s\",\"material\":%d,\"line\":%d,", ggShapeKindName(d->kind),
            d->material, d->line);
    switch (d->kind) {
    case GG_SHAPE_SPHERE:
        vec(f, "center", d->base);
        fprintf(f, ",\"radius\":");
        srv_json_num(f, d->radius);
        break;
    case GG_SHAPE_CONE:
        vec(f, "base", d->base), fputc(',', f), vec(f, "apex", d->apex);
        fprintf(f, ",\"radius\":");
        srv_json_num(f, d->radius);
        fprintf(f, ",\"radius2\":");
        srv_json_num(f, d->radius2);
        break;
    case GG_SHAPE_RECT:
        vec(f, "corner", d->base), fputc(',', f), vec(f, "e1", d->e1), fputc(',', f);
        vec(f, "e2", d->e2);
        break;
    case GG_SHAPE_IMPLICIT:
        vec(f, "lo", d->base), fputc(',', f), vec(f, "hi", d->apex);
        break;
    default:
        fprintf(f, "\"verts\":[");
        for (i = 0; i < d->nverts && d->verts; i++) {
            fputc(i ? ',' : '[', f);
            srv_json_num(f, d->verts[i].x), fputc(',', f), srv_json_num(f, d->verts[i].y);
            fputc(',', f), srv_json_num(f, d->verts[i].z), fputc(']', f);
            if (i + 1 < d->nverts) fputc(',', f);
        }
        fputc(']', f);
    }
    fputc('}', f);
}

static void api_scene(srv_server *s, const srv_req *r, srv_resp *resp)
{
    FILE *f = srv_body_open(resp, 200, "application/json");
    int i, n, m;
    (void)r;
    if (!f) {
        srv_body_close(resp, f);
        return;
    }
    srv_lib_lock(s);
    n = ggSceneObjectCount(s->scene), m = ggSceneMaterialCount(s->scene);
    fprintf(f, "{\"objects\":%d,\"truncated\":%s,\"materials\":[", n,
            n > MAX_SCENE_OBJECTS ? "true" : "false");
    for (i = 0; i < m; i++) {
        ggMaterial mt = ggSceneMaterial(s->scene, i);
        fprintf(f, "%s{\"color\":[", i ? "," : "");
        srv_json_num(f, mt.color.r), fputc(',', f), srv_json_num(f, mt.color.g), fputc(',', f);
        srv_json_num(f, mt.color.b);
        fprintf(f, "],\"kd\":");
        srv_json_num(f, mt.kd);
        fprintf(f, ",\"ks\":");
        srv_json_num(f, mt.ks);
        fprintf(f, ",\"kt\":");
        srv_json_num(f, mt.kt);
        fprintf(f, ",\"ior\":");
        srv_json_num(f, mt.ior);
        fprintf(f, ",\"line\":%d}", mt.line);
    }
    fprintf(f, "],\"shapes\":[");
    for (i = 0; i < n && i < MAX_SCENE_OBJECTS; i++) {
        ggShapeDesc d;
        if (i) fputc(',', f);
        if (ggSceneObjectShape(s->scene, i, &d) == GG_OK)
            shape_json(f, &d);
        else
            fprintf(f, "null");
    }
    srv_lib_unlock(s);
    fprintf(f, "]}\n");
    srv_body_close(resp, f);
}

/* ---- /api/trace ---- */

/* A ggAllocator that refuses to hold more than SRV_TRACE_BYTES: the bound
   on one recorded tree (the recorder then reports GG_ERROR_NOMEM). */
typedef struct budget {
    size_t used, limit;
    int refused; /* an allocation went over the limit */
} budget;

static void *b_malloc(void *ud, size_t n)
{
    budget *b = ud;
    size_t *p;
    if (n > b->limit - b->used) {
        b->refused = 1;
        return NULL;
    }
    if (!(p = malloc(n + sizeof(size_t) * 2))) return NULL;
    b->used += n, p[0] = n;
    return p + 2;
}
static void b_free(void *ud, void *ptr)
{
    budget *b = ud;
    size_t *p = ptr;
    if (!p) return;
    b->used -= p[-2];
    free(p - 2);
}
static void *b_realloc(void *ud, void *ptr, size_t n)
{
    budget *b = ud;
    size_t *p = ptr, old = p ? p[-2] : 0;
    if (!p) return b_malloc(ud, n);
    if (n > old && n - old > b->limit - b->used) {
        b->refused = 1;
        return NULL;
    }
    if (!(p = realloc(p - 2, n + sizeof(size_t) * 2))) return NULL;
    b->used = b->used - old + n, p[0] = n;
    return p + 2;
}

static int pixel_arg(const srv_server *s, const srv_req *r, const char *name, int limit, int *out,
                     srv_resp *resp)
{
    const char *v = srv_param_get(r, name);
    if (!v) {
        srv_error(resp, 400, "missing parameter %s", name);
        return -1;
    }
    if (srv_parse_int(v, -(1L << 30), 1L << 30, out)) {
        srv_error(resp, 400, "%s must be a whole number, got '%s'", name, v);
        return -1;
    }
    if (*out < 0 || *out >= limit) {
        srv_error(resp, 400, "pixel %s=%d is outside the %dx%d image", name, *out, s->cfg.width,
                  s->cfg.height);
        return -1;
    }
    return 0;
}

static void api_trace(srv_server *s, const srv_req *r, srv_resp *resp)
{
    const char *fmt = srv_param_get(r, "format"), *sv = srv_param_get(r, "sample");
    char key[512];
    ggRenderOptions o;
    ggAllocator al;
    budget b;
    ggTrace *tr;
    ggError err;
    trace_view view;
    int x, y, sample = -1, rc;
    FILE *f;
    if (!fmt) fmt = "json";
    if (strcmp(fmt, "json") && strcmp(fmt, "text") && strcmp(fmt, "svg")) {
        srv_error(resp, 400, "format must be json, text or svg, got '%s'", fmt);
        return;
    }
    if (pixel_arg(s, r, "x", s->cfg.width, &x, resp) ||
        pixel_arg(s, r, "y", s->cfg.height, &y, resp))
        return;
    if (sv && srv_parse_int(sv, -1, 4095, &sample)) {
        srv_error(resp, 400, "sample must be -1 (all) or a sample index, got '%s'", sv);
        return;
    }
    if (srv_opts_parse(s, r, "", &o, key, sizeof key, resp)) return;
    b.used = 0, b.limit = SRV_TRACE_BYTES, b.refused = 0;
    al.malloc = b_malloc, al.realloc = b_realloc, al.free = b_free, al.ud = &b;
    if (!(tr = ggTraceCreate(&al))) {
        srv_error(resp, 500, "out of memory");
        return;
    }
    memset(&view.stats, 0, sizeof view.stats);
    err.message[0] = '\0';
    srv_lib_lock(s);
    rc = ggTracePixel(s->scene, &o, x, y, sample, tr, &view.pixel, &view.stats, &err);
    if (rc == GG_OK) {
        view.scene = s->scene, view.trace = tr, view.opt = &o, view.path = s->cfg.scene_path;
        view.x = x, view.y = y, view.sample = sample;
        f = srv_body_open(resp, 200,
                          !strcmp(fmt, "json")   ? "application/json"
                          : !strcmp(fmt, "text") ? "text/plain; charset=utf-8"
                                                 : "image/svg+xml");
        if (f) {
            if (!strcmp(fmt, "json"))
                trace_print_json(f, &view);
            else if (!strcmp(fmt, "text"))
                trace_print_text(f, &view, 1);
            else
                trace_write_svg_views(f, &view, 0);
        }
        srv_body_close(resp, f);
    }
    srv_lib_unlock(s);
    if (rc == GG_ERROR_NOMEM && b.refused)
        srv_error(resp, 413,
                  "the ray tree of pixel %d,%d needs more than %d MiB (%zu rays recorded): ask "
                  "for one sample (sample=K) or a smaller depth",
                  x, y, SRV_TRACE_BYTES >> 20, ggTraceNodeCount(tr));
    else if (rc != GG_OK)
        srv_error(resp, rc == GG_ERROR_INVALID ? 400 : 500, "%s", err.message);
    ggTraceFree(tr);
}

/* ---- /api/render and /api/image ---- */

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

/* Find or start the job; fill resp with its state unless it is done.
   Returns 1 when done (resp untouched), 0 otherwise. */
static int job_ready(srv_server *s, const char *key, const ggRenderOptions *o, int kind,
                     srv_resp *resp, int always_report)
{
    srv_job_view v;
    FILE *f;
    if (srv_jobs_request(s, key, o, kind, &v)) {
        srv_error(resp, 503, "%s", v.error);
        snprintf(resp->extra_name, sizeof resp->extra_name, "Retry-After");
        snprintf(resp->extra_value, sizeof resp->extra_value, "2");
        return 0;
    }
    if (v.state == SRV_JOB_DONE && !always_report) return 1;
    if (v.state == SRV_JOB_FAILED) {
        srv_error(resp, 500, "render failed: %s", v.error);
        return 0;
    }
    f = srv_body_open(resp, v.state == SRV_JOB_DONE ? 200 : 202, "application/json");
    if (f) {
        fprintf(f, "{\"render\":");
        srv_job_json(f, &v);
        fprintf(f, ",\"options\":");
        srv_opts_json(f, o);
        fprintf(f, "}\n");
    }
    srv_body_close(resp, f);
    if (v.state != SRV_JOB_DONE) {
        snprintf(resp->extra_name, sizeof resp->extra_name, "Retry-After");
        snprintf(resp->extra_value, sizeof resp->extra_value, "1");
    }
    return v.state == SRV_JOB_DONE;
}

static void api_render(srv_server *s, const srv_req *r, srv_resp *resp)
{
    char key[512];
    ggRenderOptions o;
    int kind;
    if (kind_arg(r, &kind, resp) || srv_opts_parse(s, r, "", &o, key, sizeof key, resp)) return;
    job_ready(s, key, &o, kind, resp, 1);
}

/* Raw floats, little-endian whatever the host (docs/serve.md). */
static void send_floats(srv_server *s, float *v, size_t n, srv_resp *resp)
{
    const uint16_t one = 1;
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

static void api_image(srv_server *s, const srv_req *r, srv_resp *resp)
{
    static const char *const label[] = {"rays", "depth", "time s"};
    const char *fmt = srv_param_get(r, "format");
    char key[512];
    ggRenderOptions o;
    int kind, w = s->cfg.width, h = s->cfg.height;
    float *v;
    unsigned char *png;
    if (!fmt) fmt = "png";
    if (strcmp(fmt, "png") && strcmp(fmt, "f32")) {
        srv_error(resp, 400, "format must be png or f32, got '%s'", fmt);
        return;
    }
    if (kind_arg(r, &kind, resp) || srv_opts_parse(s, r, "", &o, key, sizeof key, resp)) return;
    if (!job_ready(s, key, &o, kind, resp, 0)) return;
    v = srv_jobs_copy(s, key, kind, kind >= 0);
    if (!v) {
        srv_error(resp, 503, "the render was evicted; ask again");
        return;
    }
    if (!strcmp(fmt, "f32")) {
        send_floats(s, v, (size_t)w * h * (kind >= 0 ? 1 : 3), resp);
        return;
    }
    if (kind >= 0) {
        double vmax = 0;
        ggImage *map = heatmap_image(v, w, h, label[kind], &vmax);
        free(v);
        if (!map) {
            srv_error(resp, 500, "out of memory");
            return;
        }
        png = srv_png(ggImagePixelsConst(map), ggImageWidth(map), ggImageHeight(map), &resp->len);
        ggImageFree(map);
        snprintf(resp->extra_name, sizeof resp->extra_name, "X-GGRT-Max");
        snprintf(resp->extra_value, sizeof resp->extra_value, "%.9g", vmax);
    } else {
        png = srv_png(v, w, h, &resp->len);
        free(v);
    }
    if (!png) {
        srv_error(resp, 500, "out of memory");
        return;
    }
    resp->status = 200, resp->type = "image/png", resp->body = (char *)png;
}

/* ---- /api/diff: one set of options against another ---- */

/* Per-pixel divergence: the largest channel difference |a - b|; a NaN on
   one side only counts as infinite. */
static float *divergence(const float *a, const float *b, size_t n, size_t *differ, size_t *worst)
{
    float *d = malloc(n * sizeof *d), top = -1;
    size_t i;
    int k;
    if (!d) return NULL;
    *differ = 0, *worst = 0;
    for (i = 0; i < n; i++) {
        float m = 0;
        for (k = 0; k < 3; k++) {
            float x = a[3 * i + k], y = b[3 * i + k], e;
            if (isnan(x) != isnan(y))
                e = INFINITY;
            else
                e = isnan(x) ? 0 : fabsf(x - y);
            if (e > m) m = e;
        }
        d[i] = m;
        if (m > 0) ++*differ;
        if (m > top) top = m, *worst = i;
    }
    return d;
}

static void diff_json(srv_server *s, FILE *f, const float *pa, const float *pb, size_t differ,
                      size_t worst, const ggRenderOptions *oa, const ggRenderOptions *ob)
{
    int w = s->cfg.width, h = s->cfg.height;
    ggImage *ia = ggImageCreate(w, h, NULL), *ib = ggImageCreate(w, h, NULL);
    ggImageDiff d;
    size_t n = (size_t)w * h * 3;
    memset(&d, 0, sizeof d);
    if (ia && ib) {
        memcpy(ggImagePixels(ia), pa, n * sizeof *pa);
        memcpy(ggImagePixels(ib), pb, n * sizeof *pb);
        ggImageCompare(ia, ib, GG_COMPARE_LINEAR, &d);
    }
    ggImageFree(ia), ggImageFree(ib);
    fprintf(f, "{\"state\":\"done\",\"a\":");
    srv_opts_json(f, oa);
    fprintf(f, ",\"b\":");
    srv_opts_json(f, ob);
    fprintf(f, ",\"pixels\":%zu,\"pixels_differ\":%zu,\"worst\":[%d,%d],\"rmse\":", n / 3, differ,
            (int)(worst % (size_t)w), (int)(worst / (size_t)w));
    srv_json_num(f, d.rmse);
    fprintf(f, ",\"max_abs\":");
    srv_json_num(f, d.max_abs);
    fprintf(f, ",\"psnr\":");
    srv_json_num(f, d.psnr);
    fprintf(f, ",\"pixels_over\":%zu,\"nan_channels\":%zu}\n", d.pixels_over, d.nan_channels);
}

static void api_diff(srv_server *s, const srv_req *r, srv_resp *resp)
{
    const char *fmt = srv_param_get(r, "format");
    char ka[512], kb[512];
    ggRenderOptions oa, ob;
    srv_job_view va, vb;
    float *pa = NULL, *pb = NULL, *d = NULL;
    size_t n = (size_t)s->cfg.width * s->cfg.height, differ, worst;
    FILE *f;
    if (!fmt) fmt = "json";
    if (strcmp(fmt, "json") && strcmp(fmt, "png") && strcmp(fmt, "f32")) {
        srv_error(resp, 400, "format must be json, png or f32, got '%s'", fmt);
        return;
    }
    if (srv_opts_parse(s, r, "", &oa, ka, sizeof ka, resp) ||
        srv_opts_parse(s, r, "b.", &ob, kb, sizeof kb, resp))
        return;
    if (srv_jobs_request(s, ka, &oa, SRV_KIND_IMAGE, &va) ||
        srv_jobs_request(s, kb, &ob, SRV_KIND_IMAGE, &vb)) {
        srv_error(resp, 503, "%s", va.error[0] ? va.error : vb.error);
        return;
    }
    if (va.state == SRV_JOB_FAILED || vb.state == SRV_JOB_FAILED) {
        srv_error(resp, 500, "render failed: %s", va.error[0] ? va.error : vb.error);
        return;
    }
    if (va.state != SRV_JOB_DONE || vb.state != SRV_JOB_DONE) {
        f = srv_body_open(resp, 202, "application/json");
        if (f) {
            fprintf(f, "{\"state\":\"rendering\",\"a\":");
            srv_job_json(f, &va);
            fprintf(f, ",\"b\":");
            srv_job_json(f, &vb);
            fprintf(f, "}\n");
        }
        srv_body_close(resp, f);
        snprintf(resp->extra_name, sizeof resp->extra_name, "Retry-After");
        snprintf(resp->extra_value, sizeof resp->extra_value, "1");
        return;
    }
    pa = srv_jobs_copy(s, ka, SRV_KIND_IMAGE, 0);
    pb = srv_jobs_copy(s, kb, SRV_KIND_IMAGE, 0);
    if (pa && pb) d = divergence(pa, pb, n, &differ, &worst);
    if (!d) {
        srv_error(resp, pa && pb ? 500 : 503,
                  pa && pb ? "out of memory" : "a render was evicted; ask again");
    } else if (!strcmp(fmt, "f32")) {
        send_floats(s, d, n, resp);
        d = NULL;
    } else if (!strcmp(fmt, "png")) {
        double vmax = 0;
        ggImage *map = heatmap_image(d, s->cfg.width, s->cfg.height, "", &vmax);
        unsigned char *png = map ? srv_png(ggImagePixelsConst(map), ggImageWidth(map),
                                           ggImageHeight(map), &resp->len)
                                 : NULL;
        ggImageFree(map);
        if (!png) {
            srv_error(resp, 500, "out of memory");
        } else {
            resp->status = 200, resp->type = "image/png", resp->body = (char *)png;
            snprintf(resp->extra_name, sizeof resp->extra_name, "X-GGRT-Max");
            snprintf(resp->extra_value, sizeof resp->extra_value, "%.9g", vmax);
        }
    } else {
        f = srv_body_open(resp, 200, "application/json");
        if (f) diff_json(s, f, pa, pb, differ, worst, &oa, &ob);
        srv_body_close(resp, f);
    }
    free(pa), free(pb), free(d);
}

/* ---- the table ---- */

static const route routes[] = {
    {"/", page, "", 0},
    {"/app.js", page, "", 0},
    {"/app.css", page, "", 0},
    {"/api/info", api_info, "", 0},
    {"/api/scene", api_scene, "", 0},
    {"/api/render", api_render, "kind", 1},
    {"/api/image", api_image, "kind format", 1},
    {"/api/trace", api_trace, "x y sample format", 1},
    {"/api/diff", api_diff, "format", 2},
};

static const route *find_route(const char *path)
{
    size_t i;
    for (i = 0; i < sizeof routes / sizeof routes[0]; i++)
        if (!strcmp(routes[i].path, path)) return &routes[i];
    return NULL;
}

void srv_route(srv_server *s, const srv_req *r, srv_resp *resp)
{
    const route *rt = find_route(r->path);
    if (!rt) {
        srv_error(resp, 404, "no such route: %s (docs/serve.md lists them)", r->path);
        return;
    }
    rt->run(s, r, resp);
}

#else
typedef int serve_api_unused;
#endif
