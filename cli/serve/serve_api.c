/* SPDX-License-Identifier: MIT */
/*
** serve_api.c -- `ggrt serve`'s routes: the page, and the JSON API that
** the page and scripts use (docs/serve.md).
*/
#if defined(GG_HAVE_MHD)
#include "serve/serve.h"
#include "debug/debug.h"
#include "trace/trace_view.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_SCENE_OBJECTS 20000 /* objects /api/scene describes (as the SVG views) */
/* Mesh triangles /api/scene lists (about 5 MB of JSON): past it every k-th
   is listed and "simplified" says so, for the page to note. */
#define MAX_SCENE_TRIANGLES 60000L
/* Implicit surfaces' triangles /api/scene sends, all of them together
   (about 4 MB of JSON): each of the k implicit objects is triangulated
   with about cli_surface_cells[r]^3 cells, the first r whose triangles fit in
   1/k of it. The grids of the k objects together have at most
   MAX_SURFACE_CELLS cells, so the time f is evaluated in is bounded
   however many there are (100 of 4000-character expressions: 10 s
   without this bound); past 512 objects (8^3 cells each) the boxes are
   drawn. */
#define MAX_SURFACE_TRIANGLES CLI_SURFACE_TRIANGLES
#define MAX_SURFACE_CELLS     (64L * 64 * 64)

typedef struct route {
    const char *path;
    void (*run)(srv_server *s, const srv_req *r, srv_resp *resp);
    const char *params; /* the parameters it takes besides token, space-separated */
} route;

static const route *find_route(const char *path);

int srv_param_allowed(const char *path, const char *key)
{
    const route *rt = find_route(path);
    const char *p;
    size_t n = strlen(key);
    if (!rt) return 1; /* answered 404 anyway */
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
    cam = ggSceneCamera(s->scene);
    ggSceneGetInfo(s->scene, &in);
    fx = ggSceneEffects(s->scene);
    fprintf(f, "{\"ggrt\":\"%s\",\"scene\":", ggVersion());
    json_str(f, s->cfg.scene_path);
    fprintf(f, ",\"width\":%d,\"height\":%d,\"objects\":%d,\"lights\":%d,\"materials\":%d,",
            s->cfg.width, s->cfg.height, ggSceneObjectCount(s->scene), ggSceneLightCount(s->scene),
            ggSceneMaterialCount(s->scene));
    fprintf(f, "\"camera\":{");
    json_vec(f, "from", cam.from), fputc(',', f), json_vec(f, "at", cam.at), fputc(',', f);
    json_vec(f, "up", cam.up);
    fprintf(f, ",\"fov\":");
    json_num(f, cam.fov_deg);
    fprintf(f, "},\"bounds\":{");
    json_vec(f, "lo", in.lo), fputc(',', f), json_vec(f, "hi", in.hi);
    fprintf(f, "},\"primitives\":%zu,\"effects\":[", in.primitives);
    for (e = 1; e < (1u << GG_EFFECT_COUNT); e <<= 1) {
        const char *why = ggSceneEffectReason(s->scene, e);
        if (!(fx & e)) continue;
        fprintf(f, "%s{\"name\":\"%s\",\"reason\":", first ? "" : ",", ggEffectName(e));
        json_str(f, why ? why : "");
        fputc('}', f);
        first = 0;
    }
    fprintf(f, "],");
    json_options(f, "options", &s->cfg.opt);
    fprintf(f,
            ",\"limits\":{\"max_depth\":%d,\"max_samples\":%d,\"trace_bytes\":%d,"
            "\"jobs\":%d,\"job_seconds\":%d,\"uri_bytes\":%d,\"params\":%d,"
            "\"value_bytes\":%d,\"connections\":%d,\"connections_per_address\":%d,"
            "\"threads\":%d,\"timeout_seconds\":%d,\"head_seconds\":%d,"
            "\"head_bytes\":%d,\"expr_bytes\":%d,\"record_bytes\":%d,\"texture_side\":%d}",
            SRV_MAX_DEPTH, SRV_MAX_SAMPLES, SRV_TRACE_BYTES, SRV_MAX_JOBS, s->cfg.job_seconds,
            SRV_MAX_URI, SRV_MAX_PARAMS, SRV_MAX_VALUE, SRV_MAX_CONNECTIONS, SRV_MAX_PER_ADDR,
            SRV_THREADS, SRV_CONN_TIMEOUT, SRV_HEAD_SECONDS, SRV_MEMORY_LIMIT, SRV_MAX_EXPR,
            SRV_RECORD_BYTES, SRV_TEXTURE_SIDE);
    fprintf(f, "}\n");
    srv_body_close(resp, f);
}

/* ---- /api/scene: shapes for the page's 3D view ---- */

/* ---- texture coordinates for the 3D view (textured objects only) ---- */

/* A texture coordinate in single precision, as the vertices are sent. */
static void uv_num(FILE *f, double x)
{
    fprintf(f, "%.7g", isfinite(x) ? x : 0.0);
}

/* ',"uv":[u,v,...]': the (u, v) ggSceneObjectUV gives the n points p of
   object i (part k: a fan triangle); nothing if it has none (a shape the
   renderer never hits: the page draws it plain). */
static void uv_json(FILE *f, const ggScene *sc, int i, const ggVec3 *p, int n)
{
    /* A triangle object of more than 3 vertices is the fan (0, k+1, k+2)
       with its own (u, v) per triangle: 3 corners each. */
    long k, parts = ggSceneObjectKind(sc, i) == GG_SHAPE_TRIANGLE && n > 3 ? n - 2 : 1;
    int j, per = parts > 1 ? 3 : n;
    double *uv = malloc(sizeof *uv * 2 * (size_t)(parts > 1 ? 3 * parts : n));
    if (!uv) return;
    for (k = 0; k < parts; k++) {
        ggVec3 c[3];
        const ggVec3 *q = p;
        if (per == 3 && parts > 1) c[0] = p[0], c[1] = p[k + 1], c[2] = p[k + 2], q = c;
        if (ggSceneObjectUV(sc, i, k, q, (size_t)per, uv + 6 * k * (parts > 1)) != GG_OK) {
            free(uv);
            return;
        }
    }
    fprintf(f, ",\"uv\":[");
    for (j = 0; j < 2 * (int)(parts > 1 ? 3 * parts : n); j++) {
        if (j) fputc(',', f);
        uv_num(f, uv[j]);
    }
    fputc(']', f);
    free(uv);
}

/* What the 3D view needs to texture object i like the renderer: the
   (u, v) at the corners it draws (planar kinds), the frame u is measured
   in (spheres, cones: the page computes (u, v) per pixel, as they are
   curved), or the one (u, v) of an implicit surface. */
static void shape_uv_json(FILE *f, const ggScene *sc, int i, const ggShapeDesc *d)
{
    ggVec3 q[4];
    if (ggSceneMaterial(sc, d->material).texture < 0) return;
    switch (d->kind) {
    case GG_SHAPE_SPHERE:
    case GG_SHAPE_CONE:
        fputc(',', f), json_vec(f, "e1", d->e1), fputc(',', f), json_vec(f, "e2", d->e2);
        break;
    case GG_SHAPE_RECT: /* corner, + e1, + e1 + e2, + e2 */
        q[0] = d->base;
        q[1] = (ggVec3){d->base.x + d->e1.x, d->base.y + d->e1.y, d->base.z + d->e1.z};
        q[2] = (ggVec3){q[1].x + d->e2.x, q[1].y + d->e2.y, q[1].z + d->e2.z};
        q[3] = (ggVec3){d->base.x + d->e2.x, d->base.y + d->e2.y, d->base.z + d->e2.z};
        uv_json(f, sc, i, q, 4);
        break;
    case GG_SHAPE_IMPLICIT:
        q[0] = d->base;
        uv_json(f, sc, i, q, 1);
        break;
    case GG_SHAPE_MESH: /* in "meshes" */
        break;
    default:
        if (d->verts && d->nverts >= 3) uv_json(f, sc, i, d->verts, d->nverts);
    }
}

/* The resolution (cells along the longest side) that gives a box about
   n^3 of ggImplicitTriangulate's near-cubic cells: n / cbrt of the box's
   volume over the longest side's cube, each side counted as at least one
   cell. So a flat box gets cells as fine as its count allows, not n
   along each side (acc-thin.nff's torus, 2.1 x 2.1 x 0.1: 132). */
static int surface_resolution(const ggShapeDesc *d, int n)
{
    double e[3], l, v = 1, r;
    int a;
    e[0] = d->apex.x - d->base.x, e[1] = d->apex.y - d->base.y, e[2] = d->apex.z - d->base.z;
    l = fmax(e[0], fmax(e[1], e[2]));
    if (!(l > 0) || !isfinite(l)) return n;
    for (a = 0; a < 3; a++) v *= fmax(e[a] / l, 1.0 / n);
    r = floor(n / cbrt(v) + 0.5);
    return r > GG_TRIANGULATE_MAX_RESOLUTION ? GG_TRIANGULATE_MAX_RESOLUTION : (int)r;
}

/* ',"surface":{...}' for implicit object i (shape d), one of n: its
   triangles with the most cells of cli_surface_cells (n times them within
   MAX_SURFACE_CELLS) that give at most 1/n of MAX_SURFACE_TRIANGLES
   (positions, unit normals -- the renderer's gradient -- and corner
   indices; docs/serve.md); nothing when none fits or the grid sees no
   sign change (the page then draws the box). */
static void surface_json(FILE *f, const ggScene *sc, int i, const ggShapeDesc *d, int n)
{
    ggTriangulation *t = NULL;
    size_t k, r;
    size_t budget = (size_t)(MAX_SURFACE_TRIANGLES / n);
    int rc = GG_ERROR_LIMIT;
    for (r = 0; r < CLI_SURFACE_STEPS && rc == GG_ERROR_LIMIT; r++) {
        long c = cli_surface_cells[r];
        if (n * c * c * c > MAX_SURFACE_CELLS) continue;
        rc = ggSceneObjectTriangulate(sc, i, surface_resolution(d, cli_surface_cells[r]),
                                      budget ? budget : 1, &t);
    }
    if (rc != GG_OK || !t->ntris) {
        ggTriangulationFree(t);
        return;
    }
    fprintf(f, ",\"surface\":{\"resolution\":%d,\"cells\":[%d,%d,%d],\"triangles\":%zu,\"verts\":[",
            t->resolution, t->cells[0], t->cells[1], t->cells[2], t->ntris);
    for (k = 0; k < t->nverts; k++) /* single precision is plenty for a picture */
        fprintf(f, "%s%.7g,%.7g,%.7g", k ? "," : "", t->verts[k].x, t->verts[k].y, t->verts[k].z);
    fprintf(f, "],\"normals\":[");
    for (k = 0; k < t->nverts; k++)
        fprintf(f, "%s%.4g,%.4g,%.4g", k ? "," : "", t->normals[k].x, t->normals[k].y,
                t->normals[k].z);
    fprintf(f, "],\"tris\":[");
    for (k = 0; k < 3 * t->ntris; k++) fprintf(f, "%s%u", k ? "," : "", (unsigned)t->tris[k]);
    fprintf(f, "]}");
    ggTriangulationFree(t);
}

/* Object obj (shape d) as JSON; `implicit`: how many implicit objects
   share the surfaces' budgets. */
static void shape_json(FILE *f, const ggScene *sc, int obj, const ggShapeDesc *d, int implicit)
{
    int i;
    fprintf(f, "{\"kind\":\"%s\",\"material\":%d,\"line\":%d,", ggShapeKindName(d->kind),
            d->material, d->line);
    switch (d->kind) {
    case GG_SHAPE_SPHERE:
        json_vec(f, "center", d->base);
        fprintf(f, ",\"radius\":");
        json_num(f, d->radius);
        break;
    case GG_SHAPE_CONE:
        json_vec(f, "base", d->base), fputc(',', f), json_vec(f, "apex", d->apex);
        fprintf(f, ",\"radius\":");
        json_num(f, d->radius);
        fprintf(f, ",\"radius2\":");
        json_num(f, d->radius2);
        break;
    case GG_SHAPE_RECT:
        json_vec(f, "corner", d->base), fputc(',', f), json_vec(f, "e1", d->e1), fputc(',', f);
        json_vec(f, "e2", d->e2);
        break;
    case GG_SHAPE_IMPLICIT: /* its box, and its surface as triangles */
        json_vec(f, "lo", d->base), fputc(',', f), json_vec(f, "hi", d->apex);
        surface_json(f, sc, obj, d, implicit);
        break;
    case GG_SHAPE_MESH: /* the box of the mesh's part */
        json_vec(f, "lo", d->base), fputc(',', f), json_vec(f, "hi", d->apex);
        break;
    default:
        fprintf(f, "\"verts\":[");
        for (i = 0; i < d->nverts && d->verts; i++) {
            fputs(i ? ",[" : "[", f);
            json_num(f, d->verts[i].x), fputc(',', f), json_num(f, d->verts[i].y);
            fputc(',', f), json_num(f, d->verts[i].z), fputc(']', f);
        }
        fputc(']', f);
    }
    shape_uv_json(f, sc, obj, d);
    fputc('}', f);
}

/* "meshes": each mesh part's triangles (9 numbers each: the corners) for
   the 3D view to shade; one in `stride` when the scene has too many. */
static void mesh_json(FILE *f, const ggScene *sc, int n)
{
    long total = 0, stride, shown = 0, k;
    int i, c, first = 1;
    ggVec3 v[3];
    for (i = 0; i < n && i < MAX_SCENE_OBJECTS; i++) total += ggSceneObjectTriangleCount(sc, i);
    stride = (total + MAX_SCENE_TRIANGLES - 1) / MAX_SCENE_TRIANGLES;
    fprintf(f, ",\"meshes\":[");
    for (i = 0; i < n && i < MAX_SCENE_OBJECTS; i++) {
        long nt = ggSceneObjectTriangleCount(sc, i), t;
        int textured = ggSceneMaterial(sc, ggSceneObjectMaterial(sc, i)).texture >= 0;
        if (!nt) continue;
        fprintf(f, "%s{\"object\":%d,\"triangles\":%ld,\"verts\":[", first ? "" : ",", i, nt);
        first = 0;
        for (k = 0; k < nt; k += stride) {
            if (ggSceneObjectTriangle(sc, i, k, v, NULL) != GG_OK) continue;
            for (c = 0; c < 3; c++) /* single precision is plenty for a picture */
                fprintf(f, "%s%.7g,%.7g,%.7g", k || c ? "," : "", v[c].x, v[c].y, v[c].z);
            shown++;
        }
        fputc(']', f);
        /* A textured part: the (u, v) of each listed triangle's corners, 6
           numbers a triangle, as the renderer interpolates them. */
        if (textured) fputs(",\"uv\":[", f);
        for (k = 0; textured && k < nt; k += stride) {
            double uv[6] = {0, 0, 0, 0, 0, 0};
            if (ggSceneObjectTriangle(sc, i, k, v, &t) != GG_OK) continue;
            ggSceneObjectUV(sc, i, t, v, 3, uv);
            for (c = 0; c < 6; c++) {
                if (k || c) fputc(',', f);
                uv_num(f, uv[c]);
            }
        }
        fputs(textured ? "]}" : "}", f);
    }
    fprintf(f, "],\"triangles\":%ld,\"triangles_shown\":%ld,\"simplified\":%s", total, shown,
            shown < total ? "true" : "false");
}

/* "lights": where each light is, for the 3D view. */
static void lights_json(FILE *f, const ggScene *sc)
{
    int i, n = ggSceneLightCount(sc);
    fprintf(f, ",\"lights\":[");
    for (i = 0; i < n; i++) {
        ggVec3 p;
        ggColor c;
        if (ggSceneGetLight(sc, i, &p, &c) != GG_OK) continue;
        fprintf(f, "%s{", i ? "," : "");
        json_vec(f, "position", p);
        fputc('}', f);
    }
    fputc(']', f);
}

/* ',"textures":[...]' when the scene has any: each image's size, wrap
   and filter (its texels: /api/texture), each checker's squares and
   colours (ggSceneGetTexture). */
static void textures_json(FILE *f, const ggScene *sc)
{
    int i, n = ggSceneTextureCount(sc);
    if (!n) return;
    fprintf(f, ",\"textures\":[");
    for (i = 0; i < n; i++) {
        ggTextureInfo t;
        if (i) fputc(',', f);
        if (ggSceneGetTexture(sc, i, &t) != GG_OK) {
            fprintf(f, "null");
        } else if (t.image) {
            fprintf(f,
                    "{\"kind\":\"image\",\"width\":%d,\"height\":%d,\"wrap\":\"%s\","
                    "\"filter\":\"%s\"}",
                    ggImageWidth(t.image), ggImageHeight(t.image),
                    t.wrap == GG_WRAP_REPEAT ? "repeat" : "clamp",
                    t.nearest ? "nearest" : "bilinear");
        } else {
            fprintf(f, "{\"kind\":\"checker\",\"n\":");
            json_num(f, t.checker_n);
            fputc(',', f), json_color(f, "a", t.checker_a), fputc(',', f);
            json_color(f, "b", t.checker_b), fputc('}', f);
        }
    }
    fputc(']', f);
}

/* ---- /api/texture: an image texture as PNG ---- */

/* The texels as /api/texture sends them: the image itself, or, past
   SRV_TEXTURE_SIDE on a side, reduced by the smallest whole factor k
   that fits: each texel the mean of a k x k block (fewer at the right and
   bottom edges), in linear light. NULL if out of memory. */
static float *texture_texels(const ggImage *img, int *w, int *h, int *k)
{
    int W = ggImageWidth(img), H = ggImageHeight(img), x, y, i, j, c;
    const float *src = ggImagePixelsConst(img);
    float *out;
    *k = 1;
    while ((W + *k - 1) / *k > SRV_TEXTURE_SIDE || (H + *k - 1) / *k > SRV_TEXTURE_SIDE) (*k)++;
    *w = (W + *k - 1) / *k, *h = (H + *k - 1) / *k;
    if (!(out = malloc(sizeof *out * 3 * (size_t)*w * (size_t)*h))) return NULL;
    for (y = 0; y < *h; y++)
        for (x = 0; x < *w; x++) {
            double sum[3] = {0, 0, 0};
            int m = 0;
            for (j = y * *k; j < (y + 1) * *k && j < H; j++)
                for (i = x * *k; i < (x + 1) * *k && i < W; i++, m++)
                    for (c = 0; c < 3; c++) sum[c] += src[3 * ((size_t)j * W + i) + c];
            for (c = 0; c < 3; c++) out[3 * ((size_t)y * *w + x) + c] = (float)(sum[c] / m);
        }
    return out;
}

static void api_texture(srv_server *s, const srv_req *r, srv_resp *resp)
{
    const char *v = srv_param_get(r, "index");
    int i, n = ggSceneTextureCount(s->scene), w, h, k;
    ggTextureInfo t;
    float *texels;
    unsigned char *png;
    if (!v) {
        srv_error(resp, 400, "missing parameter index");
        return;
    }
    if (srv_parse_int(v, 0, 1L << 30, &i)) {
        srv_error(resp, 400, "index must be a whole number >= 0, got '%s'", v);
        return;
    }
    if (i >= n || ggSceneGetTexture(s->scene, i, &t) != GG_OK) {
        srv_error(resp, 404, "no texture %d: the scene has %d (/api/scene lists them)", i, n);
        return;
    }
    if (!t.image) {
        srv_error(resp, 404,
                  "texture %d is a procedural checker: it has no image (/api/scene gives its "
                  "squares and colours)",
                  i);
        return;
    }
    texels = texture_texels(t.image, &w, &h, &k);
    png = texels ? srv_png(texels, w, h, &resp->len) : NULL;
    free(texels);
    if (!png) {
        srv_error(resp, 500, "out of memory");
        return;
    }
    resp->status = 200, resp->type = "image/png", resp->body = (char *)png;
    if (k > 1) {
        snprintf(resp->extra_name, sizeof resp->extra_name, "X-GGRT-Reduced");
        snprintf(resp->extra_value, sizeof resp->extra_value, "%d", k);
    }
}

static void scene_body(srv_server *s, srv_resp *resp)
{
    FILE *f = srv_body_open(resp, 200, "application/json");
    int i, n, m, implicit = 0;
    if (!f) {
        srv_body_close(resp, f);
        return;
    }
    n = ggSceneObjectCount(s->scene), m = ggSceneMaterialCount(s->scene);
    for (i = 0; i < n && i < MAX_SCENE_OBJECTS; i++)
        implicit += ggSceneObjectKind(s->scene, i) == GG_SHAPE_IMPLICIT;
    fprintf(f, "{\"objects\":%d,\"truncated\":%s,\"materials\":[", n,
            n > MAX_SCENE_OBJECTS ? "true" : "false");
    for (i = 0; i < m; i++) {
        ggMaterial mt = ggSceneMaterial(s->scene, i);
        fprintf(f, "%s{", i ? "," : "");
        if (mt.texture >= 0) fprintf(f, "\"texture\":%d,", mt.texture);
        json_color(f, "color", mt.color);
        fprintf(f, ",\"kd\":");
        json_num(f, mt.kd);
        fprintf(f, ",\"ks\":");
        json_num(f, mt.ks);
        fprintf(f, ",\"kt\":");
        json_num(f, mt.kt);
        fprintf(f, ",\"ior\":");
        json_num(f, mt.ior);
        fprintf(f, ",\"line\":%d}", mt.line);
    }
    fprintf(f, "],\"shapes\":[");
    for (i = 0; i < n && i < MAX_SCENE_OBJECTS; i++) {
        ggShapeDesc d;
        if (i) fputc(',', f);
        if (ggSceneObjectShape(s->scene, i, &d) == GG_OK)
            shape_json(f, s->scene, i, &d, implicit);
        else
            fprintf(f, "null");
    }
    fputc(']', f);
    mesh_json(f, s->scene, n);
    lights_json(f, s->scene);
    textures_json(f, s->scene);
    fprintf(f, "}\n");
    srv_body_close(resp, f);
}

/* The scene is only read while served, so its description is the same
   bytes every time: built by the first request (the implicit surfaces'
   triangles take about 0.15 s, a large mesh's list longer) and sent from
   memory after. A request that comes while it is being built waits for
   it. A failed build (out of memory) is not kept. */
static void api_scene(srv_server *s, const srv_req *r, srv_resp *resp)
{
    (void)r;
    pthread_mutex_lock(&s->scene_mu);
    if (!s->scene_json) {
        scene_body(s, resp);
        if (resp->status == 200 && !resp->body_static) {
            s->scene_json = resp->body, s->scene_json_len = resp->len;
            resp->body = NULL;
        }
    }
    if (s->scene_json) {
        resp->status = 200, resp->type = "application/json";
        resp->body = s->scene_json, resp->len = s->scene_json_len, resp->body_static = 1;
    }
    pthread_mutex_unlock(&s->scene_mu);
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

int srv_pixel_arg(const srv_server *s, const srv_req *r, const char *name, int limit, int *out,
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

/* The tree (and, with every sample recorded, its ledger, as ggrt trace
   prints it) in the format asked for; with a path expression instead,
   the ledger terms it matches (ggrt trace --path). */
static void trace_body(srv_resp *resp, const char *fmt, trace_view *v, const ggAllocator *al,
                       const ggPathExpr *lpe, const char *path)
{
    ggLedger *ledger = NULL;
    unsigned char *matched = NULL;
    ggPathSummary sum;
    ggError err;
    FILE *f;
    if (v->sample < 0 && ggLedgerCreate(v->trace, v->pixel, al, &ledger, &err) != GG_OK) {
        srv_error(resp, 500, "%s", err.message);
        return;
    }
    v->ledger = ledger;
    if (lpe && (!(matched = calloc(ledger->count ? ledger->count : 1, 1)) ||
                ggPathMatch(lpe, v->trace, v->x, v->y, v->pixel, ledger, matched, &sum) != GG_OK)) {
        srv_error(resp, 500, "out of memory");
        free(matched), ggLedgerFree(ledger);
        return;
    }
    f = srv_body_open(resp, 200,
                      !strcmp(fmt, "json")   ? "application/json"
                      : !strcmp(fmt, "text") ? "text/plain; charset=utf-8"
                                             : "image/svg+xml");
    if (f && lpe) {
        if (!strcmp(fmt, "json"))
            trace_print_paths_json(f, v, path, matched, &sum);
        else
            trace_print_paths(f, v, path, matched, &sum);
    } else if (f) {
        if (!strcmp(fmt, "json"))
            trace_print_json(f, v);
        else if (!strcmp(fmt, "text"))
            trace_print_text(f, v, 1);
        else
            trace_write_svg_views(f, v, 0, NULL, NULL, NULL);
    }
    srv_body_close(resp, f);
    free(matched);
    ggLedgerFree(ledger);
}

/* /api/trace's parameter path (may be absent: *out NULL): 0, or -1 with
   resp filled (400). A path needs every sample's tree and the json or
   text format. */
static int trace_path_arg(const srv_req *r, const char *fmt, int sample, ggPathExpr **out,
                          srv_resp *resp)
{
    const char *v = srv_param_get(r, "path");
    ggError err;
    *out = NULL;
    if (!v) return 0;
    if (strlen(v) > SRV_MAX_EXPR || !ggUTF8Valid(v, strlen(v))) {
        srv_error(resp, 400, "path: at most %d bytes of UTF-8", SRV_MAX_EXPR);
        return -1;
    }
    if (sample >= 0 || !strcmp(fmt, "svg")) {
        srv_error(resp, 400, "path takes every sample (no sample=K) and format json or text");
        return -1;
    }
    if (ggPathParse(v, NULL, out, &err) != GG_OK) {
        srv_error(resp, 400, "path:%s", err.message);
        return -1;
    }
    return 0;
}

/* 413: a recorded tree went over SRV_TRACE_BYTES (its arrays double as
   they grow, so the rays that fit depend on the lights: docs/serve.md,
   limits). Not how far it got: a failed ggTracePixel leaves the trace
   empty. */
static void too_large(srv_resp *resp, int x, int y, const char *advice)
{
    srv_error(resp, 413,
              "the ray tree of pixel %d,%d does not fit in the %d MiB a trace may record: %s", x, y,
              SRV_TRACE_BYTES >> 20, advice);
}

static void api_trace(srv_server *s, const srv_req *r, srv_resp *resp)
{
    const char *fmt = srv_param_get(r, "format"), *sv = srv_param_get(r, "sample");
    ggRenderOptions o;
    ggAllocator al;
    budget b;
    ggTrace *tr;
    ggPathExpr *lpe = NULL;
    ggError err;
    trace_view view;
    int x, y, sample = -1, rc;
    if (!fmt) fmt = "json";
    if (strcmp(fmt, "json") && strcmp(fmt, "text") && strcmp(fmt, "svg")) {
        srv_error(resp, 400, "format must be json, text or svg, got '%s'", fmt);
        return;
    }
    if (srv_pixel_arg(s, r, "x", s->cfg.width, &x, resp) ||
        srv_pixel_arg(s, r, "y", s->cfg.height, &y, resp))
        return;
    if (sv && srv_parse_int(sv, -1, 4095, &sample)) {
        srv_error(resp, 400, "sample must be -1 (all) or a sample index, got '%s'", sv);
        return;
    }
    if (srv_opts_parse(s, r, "opts", &o, NULL, 0, resp) ||
        trace_path_arg(r, fmt, sample, &lpe, resp))
        return;
    b.used = 0, b.limit = SRV_TRACE_BYTES, b.refused = 0;
    al.malloc = b_malloc, al.realloc = b_realloc, al.free = b_free, al.ud = &b;
    if (!(tr = ggTraceCreate(&al))) {
        srv_error(resp, 500, "out of memory");
        ggPathFree(lpe);
        return;
    }
    memset(&view, 0, sizeof view);
    err.message[0] = '\0';
    rc = ggTracePixel(s->scene, &o, x, y, sample, tr, &view.pixel, &view.stats, &err);
    if (rc == GG_OK) {
        view.scene = s->scene, view.trace = tr, view.opt = &o, view.path = s->cfg.scene_path;
        view.x = x, view.y = y, view.sample = sample;
        trace_body(resp, fmt, &view, &al, lpe, srv_param_get(r, "path"));
    }
    if ((rc == GG_ERROR_NOMEM || resp->status == 500) && b.refused)
        too_large(resp, x, y, "ask for one sample (sample=K) or a smaller depth");
    else if (rc != GG_OK)
        srv_error(resp, rc == GG_ERROR_INVALID ? 400 : 500, "%s", err.message);
    ggTraceFree(tr);
    ggPathFree(lpe);
}

/* ---- /api/compare: one pixel's trees under options A and B ---- */

typedef struct side {
    budget b;
    ggAllocator al;
    ggTrace *tr;
    trace_view v;
} side;

static int trace_side(srv_server *s, ggScene *sc, const ggRenderOptions *o, int x, int y, side *d,
                      ggError *err)
{
    int rc;
    d->b.used = 0, d->b.limit = SRV_TRACE_BYTES, d->b.refused = 0;
    d->al.malloc = b_malloc, d->al.realloc = b_realloc, d->al.free = b_free, d->al.ud = &d->b;
    memset(&d->v, 0, sizeof d->v);
    if (!(d->tr = ggTraceCreate(&d->al))) {
        snprintf(err->message, sizeof err->message, "out of memory");
        return GG_ERROR_NOMEM;
    }
    rc = ggTracePixel(sc, o, x, y, -1, d->tr, &d->v.pixel, &d->v.stats, err);
    d->v.scene = sc, d->v.trace = d->tr, d->v.opt = o, d->v.path = s->cfg.scene_path;
    d->v.x = x, d->v.y = y, d->v.sample = -1;
    return rc;
}

static void compare_body(srv_resp *resp, const char *fmt, side *a, side *b, const char *ta,
                         const char *tb)
{
    ggDivergence d;
    char text[800], na[600], nb[600];
    int differ = ggTraceCompare(a->tr, b->tr, &d);
    FILE *f = srv_body_open(
        resp, 200, !strcmp(fmt, "json") ? "application/json" : "text/plain; charset=utf-8");
    if (f && !strcmp(fmt, "text")) {
        snprintf(na, sizeof na, "%s '%s'", a->v.path, ta);
        snprintf(nb, sizeof nb, "%s '%s'", b->v.path, tb);
        trace_print_diff(f, &a->v, &b->v, na, nb);
    } else if (f) {
        dbg_divergence_text(text, sizeof text, a->tr, b->tr, &d);
        fprintf(f, "{\"pixel\":[%d,%d],", a->v.x, a->v.y);
        json_options(f, "options_a", a->v.opt), fputc(',', f);
        json_options(f, "options_b", b->v.opt);
        fprintf(f, ",\"differ\":%s,\"first\":", differ ? "true" : "false");
        json_divergence(f, &d);
        fprintf(f, ",\"text\":");
        json_str(f, text);
        fprintf(f, "}\n");
    }
    srv_body_close(resp, f);
}

static void api_compare(srv_server *s, const srv_req *r, srv_resp *resp)
{
    const char *fmt = srv_param_get(r, "format");
    char ta[512], tb[512];
    ggRenderOptions oa, ob;
    side a, b;
    ggError err;
    int x, y, rc;
    if (!fmt) fmt = "json";
    if (strcmp(fmt, "json") && strcmp(fmt, "text")) {
        srv_error(resp, 400, "format must be json or text, got '%s'", fmt);
        return;
    }
    if (srv_pixel_arg(s, r, "x", s->cfg.width, &x, resp) ||
        srv_pixel_arg(s, r, "y", s->cfg.height, &y, resp) ||
        srv_opts_parse(s, r, "opts", &oa, ta, sizeof ta, resp) ||
        srv_opts_parse(s, r, "b", &ob, tb, sizeof tb, resp))
        return;
    a.tr = b.tr = NULL;
    err.message[0] = '\0';
    rc = trace_side(s, s->scene, &oa, x, y, &a, &err);
    /* One scene serves both sides: every knob travels with the options
       (scene.h, "Threads"). */
    if (rc == GG_OK) rc = trace_side(s, s->scene, &ob, x, y, &b, &err);
    /* The names as ggrt trace --diff prints them: the texts as given. */
    if (rc == GG_OK)
        compare_body(resp, fmt, &a, &b, srv_param_get(r, "opts") ? srv_param_get(r, "opts") : "",
                     srv_param_get(r, "b") ? srv_param_get(r, "b") : "");
    if (rc != GG_OK && (a.b.refused || (b.tr && b.b.refused)))
        too_large(resp, x, y, "ask for fewer samples or a smaller depth (opts, b)");
    else if (rc != GG_OK)
        srv_error(resp, rc == GG_ERROR_INVALID ? 400 : 500, "%s", err.message);
    ggTraceFree(a.tr), ggTraceFree(b.tr);
}

/* ---- /api/parse: is a predicate or an option text well formed? ---- */

/* "L:C: message" -> line and column. */
static void where_of(const char *msg, int *line, int *col)
{
    if (sscanf(msg, "%d:%d:", line, col) != 2) *line = *col = 0;
}

static void parse_answer(FILE *f, const char *what, int ok, const char *msg)
{
    int line = 0, col = 0;
    fprintf(f, "\"%s\":{\"valid\":%s", what, ok ? "true" : "false");
    if (!ok) {
        where_of(msg, &line, &col);
        fprintf(f, ",\"error\":");
        json_str(f, msg);
        fprintf(f, ",\"line\":%d,\"column\":%d", line, col);
    }
    fputc('}', f);
}

/* 200 whether the texts parse or not (a page checks them as they are
   typed); each one given gets {"valid": ..., "error", "line", "column"}. */
/* Does text (parameter name: where or path) parse? As parse_answer. */
static void parse_expr(FILE *f, const char *name, const char *text)
{
    ggPredicate *p = NULL;
    ggPathExpr *e = NULL;
    ggError err;
    int sized = strlen(text) <= SRV_MAX_EXPR && ggUTF8Valid(text, strlen(text)), ok = 0;
    if (sized)
        ok = (!strcmp(name, "path") ? ggPathParse(text, NULL, &e, &err)
                                    : ggPredicateParse(text, NULL, &p, &err)) == GG_OK;
    else
        snprintf(err.message, sizeof err.message, "1:1: at most %d bytes of UTF-8", SRV_MAX_EXPR);
    ggPredicateFree(p), ggPathFree(e);
    parse_answer(f, name, ok, err.message);
}

/* 200 whether the texts parse or not (a page checks them as they are
   typed); each one given gets {"valid": ..., "error", "line", "column"}. */
static void api_parse(srv_server *s, const srv_req *r, srv_resp *resp)
{
    const char *names[] = {"where", "path", "opts", "b"};
    FILE *f = srv_body_open(resp, 200, "application/json");
    char msg[sizeof(((ggError *)0)->message)];
    int i, first = 1;
    if (!f) {
        srv_body_close(resp, f);
        return;
    }
    fputc('{', f);
    for (i = 0; i < 4; i++) {
        const char *v = srv_param_get(r, names[i]);
        ggRenderOptions o;
        if (!v) continue;
        if (!first) fputc(',', f);
        if (i < 2)
            parse_expr(f, names[i], v);
        else /* valid exactly where the other routes take it: the server's limits too */
            parse_answer(f, names[i], srv_opts_text(s, v, &o, msg, sizeof msg) == 0, msg);
        first = 0;
    }
    fprintf(f, "}\n");
    srv_body_close(resp, f);
}

/* ---- the table ---- */

static const route routes[] = {
    {"/", page, ""},
    {"/app.js", page, ""},
    {"/app.css", page, ""},
    {"/view3d.js", page, ""},
    {"/links.js", page, ""},
    {"/export.js", page, ""},
    {"/api/info", api_info, ""},
    {"/api/scene", api_scene, ""},
    {"/api/texture", api_texture, "index"},
    {"/api/trace", api_trace, "opts x y sample format path"},
    {"/api/compare", api_compare, "opts b x y format"},
    {"/api/parse", api_parse, "where path opts b"},
    {"/api/render", srv_api_render, "opts kind"},
    {"/api/image", srv_api_image, "opts kind format"},
    {"/api/find", srv_api_find, "opts where path limit format"},
    {"/api/check", srv_api_check, "opts x y format"},
    {"/api/diff", srv_api_diff, "opts b limit format"},
    {"/api/cancel", srv_api_cancel, "id"},
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
