/* SPDX-License-Identifier: MIT */
/*
** render.c -- camera rays, tiles and threads: ggRender and ggRayColor.
**
** Every pixel's value is a function of its coordinates only (samples sit
** at fixed positions, nothing random, no shared accumulation), so the
** image is bit-identical for any thread count and any crop window.
*/
#include "render.h"
#include "lpe.h"
#include "shade.h"

#include "trace_int.h"
#include "vec.h"

#include <float.h>
#include <math.h>
#include <pthread.h>
#include <string.h>
#include <unistd.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#define TILE 16
/* A tile row's eye rays are one packet (tile_rows). */
typedef char tile_row_fits_packet[TILE <= GG_PACKET_MAX ? 1 : -1];

/* ggRender and ggTracePixel prepare an unprepared scene. Two threads may
   do that at once on one scene (scene.h): the lock makes the second wait
   for the first's preparation and then find the scene prepared. Taken
   once per call; a prepared scene returns from ggScenePrepare at once. */
static pthread_mutex_t prepare_mu = PTHREAD_MUTEX_INITIALIZER;

static int prepare(ggScene *s, ggError *err)
{
    int rc;
    pthread_mutex_lock(&prepare_mu);
    rc = ggScenePrepare(s, err);
    pthread_mutex_unlock(&prepare_mu);
    return rc;
}

GG_API void ggRenderOptionsDefault(ggRenderOptions *opt)
{
    if (opt) memset(opt, 0, sizeof *opt);
}

GG_API int ggRenderOptionsResolve(const ggScene *scene, const ggRenderOptions *opt,
                                  ggRenderOptions *out)
{
    ggRenderOptions o;
    if (!scene || !opt || !out) return GG_ERROR_INVALID;
    o = *opt;
    /* the same choices as resolve() below makes; negative values stay */
    if (o.width == 0) o.width = scene->camera.width;
    if (o.height == 0) o.height = scene->camera.height;
    if (o.max_depth == 0) o.max_depth = scene->depth > 0 ? scene->depth : 5;
    if (o.samples == 0) o.samples = scene->samples > 0 ? scene->samples : 1;
    if (o.ray_budget == 0) o.ray_budget = GG_RAY_BUDGET;
    *out = o;
    return GG_OK;
}

typedef struct resolved {
    int w, h, depth, spp, threads, budget;
    int x0, y0, x1, y1;
    bool corners, spd;
    unsigned force;
    ggAccuracy acc;
} resolved;

typedef struct cam_basis {
    ggVec3 eye, fwd, right, up;
    double tx, ty;
    int w, h;
} cam_basis;

/* The choice knobs hold one of their GG_ACC_* values. */
static int knob_range(const ggAccuracy *a, ggError *err)
{
    const struct {
        const char *name;
        int v, max;
    } k[] = {{"offset", a->offset, GG_ACC_OFFSET_FIXED},
             {"sphere", a->sphere, GG_ACC_SPHERE_TEXTBOOK},
             {"refract", a->refract, GG_ACC_REFRACT_EXACT},
             {"fresnel", a->fresnel, GG_ACC_FRESNEL_EXACT},
             {"texture", a->texture, GG_ACC_TEXTURE_NEAREST},
             {"wavelengths", a->wavelengths, 1},
             {"intersect", a->intersect, GG_ACC_ISECT_FLOAT},
             {"shadows", a->shadows, GG_ACC_SHADOWS_OPAQUE},
             {"phong", a->phong, GG_ACC_PHONG_FAST}};
    size_t i;
    for (i = 0; i < sizeof k / sizeof k[0]; i++)
        if (k[i].v < 0 || k[i].v > k[i].max)
            return gg_error_set(err, GG_ERROR_INVALID, "accuracy knob %s is %d, not 0..%d",
                                k[i].name, k[i].v, k[i].max);
    return GG_OK;
}

static int resolve(const ggScene *s, const ggRenderOptions *o, resolved *r, ggError *err)
{
    ggRenderOptions d;
    long n;
    if (!o) {
        ggRenderOptionsDefault(&d);
        o = &d;
    }
    r->w = o->width > 0 ? o->width : s->camera.width;
    r->h = o->height > 0 ? o->height : s->camera.height;
    /* a negative size is a bad argument, not one over the limit */
    if (o->width < 0 || o->height < 0)
        return gg_error_set(err, GG_ERROR_INVALID,
                            "image width and height must be >= 0 (0: the camera's), got %d and %d",
                            o->width, o->height);
    if (r->w <= 0 || r->h <= 0 || r->w > GG_IMAGE_MAX_DIM || r->h > GG_IMAGE_MAX_DIM ||
        (size_t)r->w * (size_t)r->h > GG_IMAGE_MAX_PIXELS)
        return gg_error_set(err, GG_ERROR_LIMIT,
                            "image size %dx%d exceeds the limit of %lu pixels (%d per side)", r->w,
                            r->h, (unsigned long)GG_IMAGE_MAX_PIXELS, GG_IMAGE_MAX_DIM);
    r->depth = o->max_depth > 0 ? o->max_depth : s->depth > 0 ? s->depth : 5;
    r->spp = o->samples > 0 ? o->samples : s->samples > 0 ? s->samples : 1;
    if (o->max_depth < 0 || r->depth > 64)
        return gg_error_set(err, GG_ERROR_INVALID,
                            "max_depth must be 0 (the scene's) or 1..64, got %d",
                            o->max_depth < 0 ? o->max_depth : r->depth);
    if (o->samples < 0 || r->spp > 4096)
        return gg_error_set(err, GG_ERROR_INVALID,
                            "samples must be 0 (the scene's) or 1..4096, got %d",
                            o->samples < 0 ? o->samples : r->spp);
    if (o->threads < 0)
        return gg_error_set(err, GG_ERROR_INVALID,
                            "threads must be 0 (one per processor) or more, got %d", o->threads);
    r->budget = o->ray_budget > 0 ? o->ray_budget : GG_RAY_BUDGET;
    if (o->ray_budget < 0 || o->ray_budget > GG_RAY_BUDGET_MAX)
        return gg_error_set(err, GG_ERROR_INVALID, "ray budget %d is out of range 1..%d",
                            o->ray_budget, GG_RAY_BUDGET_MAX);
    n = o->threads > 0 ? o->threads : sysconf(_SC_NPROCESSORS_ONLN);
    r->threads = (int)(n < 1 ? 1 : n > 256 ? 256 : n);
    r->x0 = o->crop_x0, r->y0 = o->crop_y0, r->x1 = o->crop_x1, r->y1 = o->crop_y1;
    if (r->x0 == 0 && r->y0 == 0 && r->x1 == 0 && r->y1 == 0) r->x1 = r->w, r->y1 = r->h;
    if (r->x0 >= r->x1 || r->y0 >= r->y1)
        return gg_error_set(err, GG_ERROR_INVALID, "crop window [%d,%d)x[%d,%d) is empty", r->x0,
                            r->x1, r->y0, r->y1);
    if (r->x0 < 0 || r->y0 < 0 || r->x1 > r->w || r->y1 > r->h)
        return gg_error_set(err, GG_ERROR_INVALID,
                            "crop window [%d,%d)x[%d,%d) is not inside the %dx%d image", r->x0,
                            r->x1, r->y0, r->y1, r->w, r->h);
    r->corners = o->pixel_corners;
    r->spd = o->spd_rules;
    r->force = o->force_effects & GG_EFFECT_ALL;
    r->acc = o->accuracy;
    if (!(r->acc.offset_eps >= 0) || !(r->acc.cutoff >= 0) || !(r->acc.gradient_h >= 0) ||
        !(r->acc.implicit_tol >= 0) || !isfinite(r->acc.offset_eps) || !isfinite(r->acc.cutoff) ||
        !isfinite(r->acc.gradient_h) || !isfinite(r->acc.implicit_tol))
        return gg_error_set(err, GG_ERROR_INVALID, "accuracy knobs must be finite and >= 0");
    return knob_range(&r->acc, err);
}

static void basis(const ggScene *s, int w, int h, cam_basis *b)
{
    const ggCamera *c = &s->camera;
    b->eye = c->from;
    b->fwd = v3norm(v3sub(c->at, c->from));
    /* NFF's up need not be perpendicular to the view: orthogonalise. */
    b->right = v3norm(v3cross(b->fwd, c->up));
    b->up = v3cross(b->right, b->fwd);
    b->tx = tan(c->fov_deg * GG_PI / 360.0);
    b->ty = b->tx * (double)h / (double)w;
    b->w = w, b->h = h;
}

/* Ray through image point (px, py), px in [0, w] from the left, py in
   [0, h] from the top. */
static ggVec3 basis_dir(const cam_basis *b, double px, double py)
{
    double sx = (2.0 * px / b->w - 1.0) * b->tx;
    double sy = (1.0 - 2.0 * py / b->h) * b->ty;
    return v3add(b->fwd, v3add(v3scale(b->right, sx), v3scale(b->up, sy)));
}

GG_API ggRay ggCameraRay(const ggScene *s, const ggRenderOptions *opt, double x, double y)
{
    resolved r;
    cam_basis b;
    ggRay ray;
    ggVec3 d;
    double m;
    memset(&ray, 0, sizeof ray);
    if (!s) return ray;
    if (resolve(s, opt, &r, NULL) != GG_OK) r.w = s->camera.width, r.h = s->camera.height;
    basis(s, r.w > 0 ? r.w : 1, r.h > 0 ? r.h : 1, &b);
    d = basis_dir(&b, x, y);
    /* An infinite or NaN direction has no unit length. */
    if (!v3finite(d) || !((m = v3maxabs(d)) > 0)) return ray;
    /* Far off the image (x = 1e200) the squares in v3norm's length
       overflow: scaled to a largest coordinate of 1 first, d comes out
       unit. Only then: elsewhere d is the one ggRender's rays take, bit
       for bit. */
    if (!(v3len(d) < INFINITY)) d = v3scale(d, 1 / m);
    ray.o = b.eye;
    ray.d = v3norm(d);
    return ray;
}

/* Position of sample k of n inside the pixel: an n = m*m grid when n is a
   square, else a (k + 1/2)/n by radical-inverse pattern. Fixed, so the
   render is reproducible. */
static void sample_pos(int k, int n, double *sx, double *sy)
{
    int m;
    if (n == 1) {
        *sx = *sy = 0.5;
        return;
    }
    m = (int)floor(sqrt((double)n) + 0.5);
    if (m * m == n) {
        *sx = ((k % m) + 0.5) / m;
        *sy = ((k / m) + 0.5) / m;
    } else {
        unsigned b = (unsigned)k, rev = 0;
        int i;
        for (i = 0; i < 32; i++) rev = (rev << 1) | ((b >> i) & 1u);
        *sx = (k + 0.5) / n;
        *sy = (double)rev * 0x1p-32 + 0x1p-33;
    }
}

typedef struct job {
    gg_shade_ctx ctx;
    resolved r;
    cam_basis cam;
    float *px;     /* output pixels (full image) */
    float *corner; /* pixel-corner mode: (cw x ch) RGB */
    int cw, ch;    /* the grid being tiled: pixels, or corners */
    int tiles_x, ntiles;
    pthread_mutex_t mu;
    int next_tile;
    long done, total, reported; /* progress, in pixels of the window */
    long points, points_done;   /* the grid's points (corners in corner mode) */
    double reported_at;         /* gg_time_now of the last progress call */
    int cancelled;
    ggProgressFn progress;
    void *progress_ud;
    float *cost;
    int cost_kind;
    float *ccost; /* pixel-corner mode with a cost map: each corner's cost (cw x ch) */
    const ggPathLayers *layers; /* path layers (n > 0), or NULL */
    float *lmap;                /* their map (ggRenderOptions.layer_map), or NULL */
    double *lsum;               /* gg_render_layer_sums: each layer's r + g + b in double, or NULL */
    unsigned char *lhit;        /* and 1 where it took a non-zero term (set with lsum) */
    ggColor lmiss[GG_LAYERS_MAX];   /* each layer's share of an eye ray's miss */
    uint32_t nmiss[GG_LAYERS_MAX];  /* and its terms (0 or 1) */
    unsigned char nmiss8[GG_LAYERS_MAX]; /* the same, as lhit stores them */
    float fmiss[GG_LAYERS_MAX][3];  /* a one-sample pixel's layers of a miss, as stored */
    double dmiss[GG_LAYERS_MAX];    /* and as lsum stores them */
    float *lcorner;             /* pixel-corner mode: each corner's layers, n RGB */
    ggRayStats stats;
} job;

GG_API void ggRayStatsAdd(ggRayStats *a, const ggRayStats *b)
{
    if (!a || !b) return;
    a->eye += b->eye, a->eye_hit += b->eye_hit, a->reflect += b->reflect;
    a->refract += b->refract, a->shadow += b->shadow, a->tir += b->tir;
    a->nonfinite += b->nonfinite, a->budget_cut += b->budget_cut;
    a->implicit_cut += b->implicit_cut;
    a->shadow_blocked += b->shadow_blocked, a->shadow_attenuated += b->shadow_attenuated;
    if (b->max_depth > a->max_depth) a->max_depth = b->max_depth;
}

static ggColor sample_color(job *j, double px, double py, gg_shade_thread *th)
{
    ggColor c = gg_shade_ray(&j->ctx, j->cam.eye, basis_dir(&j->cam, px, py), 1, th);
    if (!isfinite(c.r) || !isfinite(c.g) || !isfinite(c.b)) th->st.nonfinite++;
    return c;
}

/* Pixel (x, y) in pixel-centre mode: the mean of its samples. With rec,
   sample `which` (or all, if -1) is recorded. */
static ggColor pixel_center(job *j, int x, int y, gg_shade_thread *th, ggTrace *rec, int which)
{
    ggColor acc = rgb(0, 0, 0);
    int k;
    for (k = 0; k < j->r.spp; k++) {
        double sx, sy;
        int recorded = rec && (which < 0 || which == k);
        ggRayStats keep = th->st;
        sample_pos(k, j->r.spp, &sx, &sy);
        if (recorded) {
            j->ctx.rec = rec;
            rec->sample = k;
        }
        acc = cadd(acc, sample_color(j, x + sx, y + sy, th));
        /* When tracing one sample, count only that sample's rays. */
        if (rec && !recorded) th->st = keep;
        /* (only ggTracePixel's job, which no other thread sees, records:
           ggRender's workers share theirs and must not write it) */
        if (recorded) j->ctx.rec = NULL;
    }
    return cscale(acc, 1.0 / j->r.spp);
}

/* Layer l's value v at pixel (x, y) of the map. */
static void put_layer(job *j, int l, int x, int y, ggColor v)
{
    const size_t i = ((size_t)l * (size_t)j->r.h + (size_t)y) * (size_t)j->r.w + (size_t)x;
    if (j->lmap) j->lmap[3 * i] = (float)v.r, j->lmap[3 * i + 1] = (float)v.g, j->lmap[3 * i + 2] = (float)v.b;
    if (j->lsum) j->lsum[i] = v.r + v.g + v.b;
}

/* One sample's layers v (and term counts n) at grid point (gx, gy): a
   pixel centre's value (scaled as put_centre scales the pixel), or a
   corner's (tile_rows and fill_empty_tile). */
static void put_sample_layers(job *j, int gx, int gy, const ggColor *v, const uint32_t *n,
                              double scale)
{
    const int nl = j->layers->n;
    const size_t plane = (size_t)j->r.w * (size_t)j->r.h;
    size_t i;
    int l;
    if (j->corner) {
        float *o = j->lcorner + 3 * (size_t)nl * ((size_t)gy * j->cw + gx);
        for (l = 0; l < nl; l++, o += 3)
            o[0] = (float)v[l].r, o[1] = (float)v[l].g, o[2] = (float)v[l].b;
        return;
    }
    /* put_layer's arithmetic and places, one layer's plane after another */
    i = (size_t)(j->r.y0 + gy) * (size_t)j->r.w + (size_t)(j->r.x0 + gx);
    for (l = 0; l < nl; l++, i += plane) {
        const ggColor a = cscale(cadd(rgb(0, 0, 0), v[l]), scale);
        if (j->lmap) j->lmap[3 * i] = (float)a.r, j->lmap[3 * i + 1] = (float)a.g, j->lmap[3 * i + 2] = (float)a.b;
        if (j->lsum) j->lsum[i] = a.r + a.g + a.b;
        if (j->lhit) j->lhit[i] = n && n[l] != 0;
    }
}

/* put_sample_layers' values at a pixel centre when only the float map
   is wanted (ggRender), into pixel i of a row's layers (tile_rows_fx). */
static void row_layers(const job *j, float (*lrow)[3 * TILE], int i, const ggColor *v, double scale)
{
    int l;
    for (l = 0; l < j->layers->n; l++) {
        const ggColor a = cscale(cadd(rgb(0, 0, 0), v[l]), scale);
        float *o = &lrow[l][3 * i];
        o[0] = (float)a.r, o[1] = (float)a.g, o[2] = (float)a.b;
    }
}

/* The lines of the layer map that the n pixels from grid point (gx, gy)
   on will be written to, asked for before the row is traced. */
static void prefetch_layer_row(const job *j, int gx, int gy, int n)
{
    const size_t plane3 = 3 * (size_t)j->r.w * (size_t)j->r.h;
    const char *o = (const char *)(j->lmap + 3 * ((size_t)(j->r.y0 + gy) * (size_t)j->r.w +
                                                  (size_t)(j->r.x0 + gx)));
    const size_t bytes = 3 * sizeof(float) * (size_t)n;
    size_t k;
    int l;
    for (l = 0; l < j->layers->n; l++, o += plane3 * sizeof(float)) {
        for (k = 0; k < bytes; k += 64) GG_PREFETCH_W(o + k);
        GG_PREFETCH_W(o + bytes - 1);
    }
}

/* What an eye ray's miss gives each layer: the background if the layer
   takes CB (the layer copy's trace_fx on a miss: weight 1, no
   absorption outside every medium). */
static void miss_layers(job *j)
{
    const ggColor bg = gg_shade_eye_miss(&j->ctx);
    int l;
    for (l = 0; l < j->layers->n; l++) {
        const gg_lpe_dfa *d = &j->layers->layer[l];
        const int on = d->accept[gg_lpe_step(d, d->start, GG_LPE_B, gg_lpe_none(d))];
        const ggColor a = cscale(cadd(rgb(0, 0, 0), on ? bg : rgb(0, 0, 0)), 1.0 / j->r.spp);
        j->lmiss[l] = on ? bg : rgb(0, 0, 0);
        j->nmiss[l] = on && (bg.r != 0 || bg.g != 0 || bg.b != 0);
        j->nmiss8[l] = (unsigned char)j->nmiss[l];
        j->fmiss[l][0] = (float)a.r, j->fmiss[l][1] = (float)a.g, j->fmiss[l][2] = (float)a.b;
        j->dmiss[l] = a.r + a.g + a.b;
    }
}

/* A miss's layers (as stored, j->fmiss) into pixel i of a row's layers. */
static void row_miss_layers(const job *j, float (*lrow)[3 * TILE], int i)
{
    int l;
    for (l = 0; l < j->layers->n; l++) {
        float *o = &lrow[l][3 * i];
        o[0] = j->fmiss[l][0], o[1] = j->fmiss[l][1], o[2] = j->fmiss[l][2];
    }
}

/* The n pixels from grid point (gx, gy) on of each layer l, copied from
   its row p[l]: a row of an empty tile (f repeated) or tile_rows_fx's. */
static void fill_layer_row(job *j, int gx, int gy, int n, const float (*p)[3 * TILE])
{
    const size_t plane = (size_t)j->r.w * (size_t)j->r.h;
    const size_t i = (size_t)(j->r.y0 + gy) * (size_t)j->r.w + (size_t)(j->r.x0 + gx);
    int l;
    for (l = 0; l < j->layers->n; l++)
        memcpy(j->lmap + 3 * (i + (size_t)l * plane), p[l], 3 * sizeof(float) * (size_t)n);
}

/* The same for the layer sums: d and hit h (as stored) at n pixels. */
static void fill_sums(job *j, int gx, int gy, int n, const double *d, const unsigned char *h)
{
    const size_t plane = (size_t)j->r.w * (size_t)j->r.h;
    const size_t i = (size_t)(j->r.y0 + gy) * (size_t)j->r.w + (size_t)(j->r.x0 + gx);
    int l, k;
    for (l = 0; l < j->layers->n; l++) {
        const size_t at = i + (size_t)l * plane;
        for (k = 0; k < n; k++) j->lsum[at + k] = d[l], j->lhit[at + k] = h[l];
    }
}

/* pixel_center with path layers: the same pixel (returned), and each
   layer's share of it, the mean of its samples' shares, into the map. */
static ggColor pixel_layers(job *j, int x, int y, gg_shade_thread *th)
{
    const int nl = j->layers->n;
    ggColor acc = rgb(0, 0, 0), lacc[GG_LAYERS_MAX];
    int k, l;
    for (l = 0; l < nl; l++) lacc[l] = rgb(0, 0, 0);
    if (th->aov_n)
        for (l = 0; l < nl; l++) th->aov_n[l] = 0;
    for (k = 0; k < j->r.spp; k++) {
        double sx, sy;
        sample_pos(k, j->r.spp, &sx, &sy);
        for (l = 0; l < nl; l++) th->aov[l] = rgb(0, 0, 0);
        acc = cadd(acc, sample_color(j, x + sx, y + sy, th));
        for (l = 0; l < nl; l++) lacc[l] = cadd(lacc[l], th->aov[l]);
    }
    for (l = 0; l < nl; l++) put_layer(j, l, x, y, cscale(lacc[l], 1.0 / j->r.spp));
    if (j->lhit)
        for (l = 0; l < nl; l++)
            j->lhit[((size_t)l * (size_t)j->r.h + (size_t)y) * (size_t)j->r.w + (size_t)x] =
                th->aov_n[l] != 0;
    return cscale(acc, 1.0 / j->r.spp);
}

/* A pixel corner's colour with path layers: as sample_color, and each
   layer's share of it into j->lcorner at corner index i. */
static ggColor corner_layers(job *j, double px, double py, size_t i, gg_shade_thread *th)
{
    const int nl = j->layers->n;
    float *o = j->lcorner + 3 * (size_t)nl * i;
    ggColor c;
    int l;
    for (l = 0; l < nl; l++) th->aov[l] = rgb(0, 0, 0);
    c = sample_color(j, px, py, th);
    for (l = 0; l < nl; l++, o += 3)
        o[0] = (float)th->aov[l].r, o[1] = (float)th->aov[l].g, o[2] = (float)th->aov[l].b;
    return c;
}

/* The reads of shading a packet's hits started ahead of it
   (gg_geom_prefetch_hit), each step once: before the first lane (at =
   -1) step 0 of every hit and step 1 of the first two; before shading
   lane at, step 2 of the next hit lane and step 1 of the one after it.
   On large meshes these records are misses, each a chain of two or
   three. Below PREFETCH_PRIMS primitives (every SPD scene; their records
   are at most a few MB, in cache) the hints only cost: mount rendered
   2-4% slower with them. */
#define PREFETCH_PRIMS 65536
static void prefetch_hits(const gg_geom *g, const gg_hit *h, uint32_t hit, int at)
{
    uint32_t m;
    int k;
    if (at < 0) {
        for (m = hit; m; m &= m - 1) gg_geom_prefetch_hit(g, h[GG_CTZ(m)].prim, 0);
        for (k = 0, m = hit; m && k < 2; k++, m &= m - 1)
            gg_geom_prefetch_hit(g, h[GG_CTZ(m)].prim, 1);
        return;
    }
    m = hit >> at >> 1; /* the lanes after at */
    if (!m) return;
    gg_geom_prefetch_hit(g, h[at + 1 + GG_CTZ(m)].prim, 2);
    m &= m - 1;
    if (m) gg_geom_prefetch_hit(g, h[at + 1 + GG_CTZ(m)].prim, 1);
}

/* A pixel-centre pixel from its one sample's colour c, as pixel_center
   and render_tile make it; returns 1 when c is not finite (counted). */
static GG_NOINLINE int put_centre(float *o, const ggColor *c, double scale)
{
    ggColor a = cscale(cadd(rgb(0, 0, 0), *c), scale);
    o[0] = (float)a.r, o[1] = (float)a.g, o[2] = (float)a.b;
    return !isfinite(c->r) || !isfinite(c->g) || !isfinite(c->b);
}

/* A pixel corner from its colour c, as render_tile stores sample_color's;
   returns 1 when c is not finite (sample_color's count). */
static GG_NOINLINE int put_corner(float *o, const ggColor *c)
{
    o[0] = (float)c->r, o[1] = (float)c->g, o[2] = (float)c->b;
    return !isfinite(c->r) || !isfinite(c->g) || !isfinite(c->b);
}

/* A row's unit eye directions, as basis_dir and gg_shade_dir compute
   them: d = fwd + (right * sx + up * sy) with right * sx of column i in
   c[0..2][i] and v = up * sy, then d / |d|. Bit i of the result is set
   where |d| is finite and > 0 (gg_shade_dir's test of d). All TILE
   columns are computed; the caller uses its own. SSE2's add, multiply,
   divide and square root round exactly as the scalar ones do. */
static uint32_t row_dirs(const cam_basis *b, double c[3][TILE], const double v[3], gg_rayq q[TILE])
{
    uint32_t ok = 0;
    int i;
#if defined(__SSE2__)
    const __m128d fx = _mm_set1_pd(b->fwd.x), fy = _mm_set1_pd(b->fwd.y);
    const __m128d fz = _mm_set1_pd(b->fwd.z), vx = _mm_set1_pd(v[0]);
    const __m128d vy = _mm_set1_pd(v[1]), vz = _mm_set1_pd(v[2]);
    const __m128d zero = _mm_setzero_pd(), big = _mm_set1_pd(DBL_MAX), one = _mm_set1_pd(1.0);
    for (i = 0; i < TILE; i += 2) {
        __m128d dx = _mm_add_pd(fx, _mm_add_pd(_mm_loadu_pd(&c[0][i]), vx));
        __m128d dy = _mm_add_pd(fy, _mm_add_pd(_mm_loadu_pd(&c[1][i]), vy));
        __m128d dz = _mm_add_pd(fz, _mm_add_pd(_mm_loadu_pd(&c[2][i]), vz));
        __m128d len = _mm_sqrt_pd(
            _mm_add_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy)), _mm_mul_pd(dz, dz)));
        __m128d inv = _mm_div_pd(one, len);
        /* len > 0 and finite; NaN fails both */
        __m128d good = _mm_and_pd(_mm_cmpgt_pd(len, zero), _mm_cmple_pd(len, big));
        ok |= (uint32_t)_mm_movemask_pd(good) << i;
        dx = _mm_mul_pd(dx, inv), dy = _mm_mul_pd(dy, inv), dz = _mm_mul_pd(dz, inv);
        _mm_storel_pd(&q[i].d.x, dx), _mm_storeh_pd(&q[i + 1].d.x, dx);
        _mm_storel_pd(&q[i].d.y, dy), _mm_storeh_pd(&q[i + 1].d.y, dy);
        _mm_storel_pd(&q[i].d.z, dz), _mm_storeh_pd(&q[i + 1].d.z, dz);
    }
#else
    for (i = 0; i < TILE; i++) {
        double dx = b->fwd.x + (c[0][i] + v[0]), dy = b->fwd.y + (c[1][i] + v[1]);
        double dz = b->fwd.z + (c[2][i] + v[2]);
        double len = sqrt(dx * dx + dy * dy + dz * dz), inv = 1.0 / len;
        ok |= (uint32_t)(len > 0 && len <= DBL_MAX) << i;
        q[i].d.x = dx * inv, q[i].d.y = dy * inv, q[i].d.z = dz * inv;
    }
#endif
    return ok;
}

/* A tile of many samples per pixel, or of deep trees, can take long: 16
   by 16 pixels of 256 samples through nested glass took 20 s, a bar
   that stood at 0 and a cancel that waited for the tile. Every
   POLL_RAYS rays, the per-pixel loop of render_tile and the rows (or,
   with a raised ray budget, the pixels) of tile_rows_fx ask poll_tile; it calls the progress
   callback (with the pixels this thread has done in the tile) at most every POLL_SECONDS, and says
   whether the render is cancelled. */
#define POLL_RAYS    (1u << 15)
#define POLL_SECONDS 0.1

static uint64_t rays_cast(const ggRayStats *st)
{
    return st->eye + st->reflect + st->refract + st->shadow;
}

static int poll_tile(job *j, long px_done)
{
    int stop;
    pthread_mutex_lock(&j->mu);
    if (j->progress && !j->cancelled) {
        double now = gg_time_now();
        long done = j->done + (long)((double)px_done / (double)j->points * (double)j->total);
        if (done > j->reported && done < j->total && now - j->reported_at >= POLL_SECONDS) {
            j->reported = done, j->reported_at = now;
            if (j->progress(j->progress_ud, done, j->total)) j->cancelled = 1;
        }
    }
    stop = j->cancelled;
    pthread_mutex_unlock(&j->mu);
    return stop;
}

/* render_tile for one sample at each pixel centre (pixel_center,
   sample_color, basis_dir, gg_shade_dir and gg_shade_ray_unit), or at each
   pixel corner (sample_color ...), step by step,
   the same operations in the same order, with what does not change along
   a row or a column hoisted out: a column's right * sx is computed once a
   tile, a row's up * sy once a row. A row's unit directions come first,
   then its rays, so the divisions and square roots run in parallel rather
   than each at the head of its ray's chain. The eye rays of a row are cast
   here as one packet (gg_geom_intersect_packet: the same hits as one at a
   time), then the hits are shaded left to right as before; every miss is
   the same pixel value. On a large geometry the hits' records are
   started ahead of shading them (prefetch_hits). */
GG_INLINE void tile_rows_fx(job *j, int gx0, int gy0, int gx1, int gy1, gg_shade_thread *th,
                            const int layers)
{
    const cam_basis *b = &j->cam;
    const gg_geom *geom = j->ctx.s->geom;
    const int pf = gg_geom_prim_count(geom) >= PREFETCH_PRIMS;
    const int n = gx1 - gx0, corner = j->corner != NULL;
    const double scale = 1.0 / j->r.spp, half = corner ? 0 : 0.5;
    /* gg_shade_dir's test of the origin: no ray at all from a non-finite eye. */
    const uint32_t eye_ok = v3finite(b->eye) ? ~0u : 0u;
    double c[3][TILE]; /* right * sx of the tile's columns */
    gg_rayq q[TILE];   /* a row's eye rays */
    gg_hit h[TILE];    /* and their hits */
    const ggColor black = {0, 0, 0}, bg = gg_shade_eye_miss(&j->ctx);
    const uint32_t cols = (1u << n) - 1;
    float miss[3];
    /* Only the float map wanted (ggRender): a row's layers are gathered
       here and stored with one copy per layer (fill_layer_row). */
    const int direct = layers && !corner && !j->lsum;
    float lrow[GG_LAYERS_MAX][3 * TILE];
    uint64_t eye = 0, nonfinite = 0, miss_bad, poll_at = rays_cast(&th->st) + POLL_RAYS;
    /* A row's trees are bounded by the ray budget: with the default, poll
       once a row; with more, after each pixel (a tree can take seconds) */
    const int deep = j->ctx.budget > GG_RAY_BUDGET;
    int i, gy;
    miss_bad = (uint64_t)(corner ? put_corner(miss, &bg) : put_centre(miss, &bg, scale));
    for (i = 0; i < TILE; i++) {
        q[i] = gg_rayq_make(b->eye, b->eye, 0, INFINITY, &j->ctx.qopt);
        q[i].implicit_cut = &th->st.implicit_cut;
    }
    for (i = 0; i < TILE; i++) {
        double px = j->r.x0 + gx0 + i + half;
        double sx = (2.0 * px / b->w - 1.0) * b->tx;
        c[0][i] = b->right.x * sx, c[1][i] = b->right.y * sx, c[2][i] = b->right.z * sx;
    }
    for (gy = gy0; gy < gy1; gy++) {
        const int y = j->r.y0 + gy;
        const double py = y + half;
        const double sy = (1.0 - 2.0 * py / b->h) * b->ty;
        const double v[3] = {b->up.x * sy, b->up.y * sy, b->up.z * sy};
        float *o = corner ? j->corner + 3 * ((size_t)gy * j->cw + gx0)
                          : j->px + 3 * ((size_t)y * j->r.w + (j->r.x0 + gx0));
        const uint32_t ok = row_dirs(b, c, v, q) & eye_ok & cols;
        uint32_t hit;
        if (direct) prefetch_layer_row(j, gx0, gy, n);
        hit = gg_geom_intersect_packet(geom, q, ok, h);
        eye += (uint64_t)n;
        if (pf) prefetch_hits(geom, h, hit, -1);
        for (i = 0; i < n; i++, o += 3) {
            if (!((ok >> i) & 1u)) {
                nonfinite += corner ? put_corner(o, &black) : put_centre(o, &black, scale);
                eye--; /* no ray cast: take it back from the row's n */
                if (direct) {
                    int l;
                    for (l = 0; l < j->layers->n; l++)
                        lrow[l][3 * i] = lrow[l][3 * i + 1] = lrow[l][3 * i + 2] = 0;
                } else if (layers) {
                    ggColor none[GG_LAYERS_MAX];
                    int l;
                    for (l = 0; l < j->layers->n; l++) none[l] = black;
                    put_sample_layers(j, gx0 + i, gy, none, NULL, scale);
                }
                continue;
            }
            if ((hit >> i) & 1u) {
                ggColor col;
                int l;
                for (l = 0; layers && l < j->layers->n; l++) {
                    th->aov[l] = black;
                    if (th->aov_n) th->aov_n[l] = 0;
                }
                if (pf) prefetch_hits(geom, h, hit, i);
                col = gg_shade_eye_hit(&j->ctx, &q[i], &h[i], th);
                nonfinite += corner ? put_corner(o, &col) : put_centre(o, &col, scale);
                if (direct)
                    row_layers(j, lrow, i, th->aov, scale);
                else if (layers)
                    put_sample_layers(j, gx0 + i, gy, th->aov, th->aov_n, scale);
                if (deep && rays_cast(&th->st) >= poll_at) {
                    if (poll_tile(j, (long)(gy - gy0) * n + i + 1)) goto cancelled;
                    poll_at = rays_cast(&th->st) + POLL_RAYS;
                }
            } else {
                o[0] = miss[0], o[1] = miss[1], o[2] = miss[2];
                nonfinite += miss_bad;
                if (direct)
                    row_miss_layers(j, lrow, i);
                else if (layers && !corner)
                    fill_sums(j, gx0 + i, gy, 1, j->dmiss, j->nmiss8);
                else if (layers)
                    put_sample_layers(j, gx0 + i, gy, j->lmiss, j->nmiss, scale);
            }
        }
        if (direct) fill_layer_row(j, gx0, gy, n, (const float(*)[3 * TILE])lrow);
        if (rays_cast(&th->st) >= poll_at) {
            if (poll_tile(j, (long)(gy - gy0 + 1) * n)) break;
            poll_at = rays_cast(&th->st) + POLL_RAYS;
        }
    }
cancelled: /* (the image is not used then) */
    th->st.eye += eye;
    th->st.nonfinite += nonfinite;
    if (eye > 0 && th->st.max_depth < 1) th->st.max_depth = 1;
}

static void tile_rows(job *j, int gx0, int gy0, int gx1, int gy1, gg_shade_thread *th)
{
    tile_rows_fx(j, gx0, gy0, gx1, gy1, th, 0);
}

/* tile_rows with path layers: a copy of its own, the other unchanged. */
static GG_NOINLINE void tile_rows_layers(job *j, int gx0, int gy0, int gx1, int gy1,
                                         gg_shade_thread *th)
{
    tile_rows_fx(j, gx0, gy0, gx1, gy1, th, 1);
}

/* Whether no eye ray of tile [gx0, gx1) x [gy0, gy1) can hit anything:
   its samples all lie in the image rectangle from (x0 + gx0, y0 + gy0)
   to (x0 + gx1, y0 + gy1) (pixel centres, points inside pixels, and in
   corner mode the grid points), so in the pyramid of its four corners. */
static int tile_empty(const job *j, int gx0, int gy0, int gx1, int gy1)
{
    double xa = j->r.x0 + gx0, xb = j->r.x0 + gx1, ya = j->r.y0 + gy0, yb = j->r.y0 + gy1;
    ggVec3 d[4];
    d[0] = basis_dir(&j->cam, xa, ya), d[1] = basis_dir(&j->cam, xb, ya);
    d[2] = basis_dir(&j->cam, xb, yb), d[3] = basis_dir(&j->cam, xa, yb);
    return gg_geom_frustum_empty(j->ctx.s->geom, j->cam.eye, d);
}

/* fill_empty_tile's layers: n misses a pixel (one a corner), summed and
   scaled as pixel_layers sums them. */
static void empty_tile_layers(job *j, int gx0, int gy0, int gx1, int gy1, int n)
{
    ggColor v[GG_LAYERS_MAX];
    uint32_t c[GG_LAYERS_MAX];
    int l, k, gx, gy;
    float f[GG_LAYERS_MAX][3];
    double d[GG_LAYERS_MAX];
    unsigned char h[GG_LAYERS_MAX];
    for (l = 0; l < j->layers->n; l++) {
        ggColor acc = rgb(0, 0, 0), a;
        for (k = 0; k < n; k++) acc = cadd(acc, j->lmiss[l]);
        v[l] = acc, c[l] = (uint32_t)n * j->nmiss[l];
        a = cscale(cadd(rgb(0, 0, 0), acc), 1.0 / j->r.spp);
        f[l][0] = (float)a.r, f[l][1] = (float)a.g, f[l][2] = (float)a.b;
        d[l] = a.r + a.g + a.b, h[l] = c[l] != 0;
    }
    if (!j->corner && !j->lsum) {
        float p[GG_LAYERS_MAX][3 * TILE];
        for (l = 0; l < j->layers->n; l++)
            for (k = 0; k < 3 * TILE; k++) p[l][k] = f[l][k % 3];
        for (gy = gy0; gy < gy1 && gy < gy0 + 2; gy++) prefetch_layer_row(j, gx0, gy, gx1 - gx0);
        for (gy = gy0; gy < gy1; gy++) {
            if (gy + 2 < gy1) prefetch_layer_row(j, gx0, gy + 2, gx1 - gx0);
            fill_layer_row(j, gx0, gy, gx1 - gx0, (const float(*)[3 * TILE])p);
        }
        return;
    }
    for (gy = gy0; !j->corner && gy < gy1; gy++) fill_sums(j, gx0, gy, gx1 - gx0, d, h);
    if (!j->corner) return;
    for (gy = gy0; gy < gy1; gy++)
        for (gx = gx0; gx < gx1; gx++) put_sample_layers(j, gx, gy, v, c, 1.0 / j->r.spp);
}

/* An empty tile: every sample is a miss. The same values and counts as
   tracing them (gg_shade_ray_unit and trace_fx on a miss: one eye ray,
   depth 1, the background), without the rays. */
static void fill_empty_tile(job *j, int gx0, int gy0, int gx1, int gy1, gg_shade_thread *th)
{
    ggRayStats *st = &th->st;
    const ggColor bg = gg_shade_eye_miss(&j->ctx);
    const int bad = !isfinite(bg.r) || !isfinite(bg.g) || !isfinite(bg.b);
    const int n = j->corner ? 1 : j->r.spp;
    const uint64_t rays = (uint64_t)n * (uint64_t)(gx1 - gx0) * (uint64_t)(gy1 - gy0);
    ggColor acc = rgb(0, 0, 0);
    float v[3];
    int gx, gy, k;
    /* Every pixel of the tile gets the same value, so it is computed
       once: the background in corner mode, else n samples of it summed
       and scaled by 1/spp, as a pixel of n misses adds up. */
    if (j->corner) {
        acc = bg;
    } else {
        for (k = 0; k < n; k++) acc = cadd(acc, bg);
        acc = cscale(acc, 1.0 / j->r.spp);
    }
    v[0] = (float)acc.r, v[1] = (float)acc.g, v[2] = (float)acc.b;
    if (st->max_depth < 1) st->max_depth = 1;
    st->eye += rays;
    if (bad) st->nonfinite += rays;
    for (gy = gy0; gy < gy1; gy++) {
        float *o = j->corner ? j->corner + 3 * ((size_t)gy * j->cw + gx0)
                             : j->px + 3 * ((size_t)(j->r.y0 + gy) * j->r.w + (j->r.x0 + gx0));
        for (gx = gx0; gx < gx1; gx++, o += 3) o[0] = v[0], o[1] = v[1], o[2] = v[2];
    }
    if (j->layers) empty_tile_layers(j, gx0, gy0, gx1, gy1, n);
}

/* The clock of a timed cost map (GG_COST_TIME, GG_COST_CPU), else 0. */
static double cost_clock(const job *j)
{
    if (!j->cost) return 0;
    return j->cost_kind == GG_COST_CPU ? gg_time_cpu()
           : j->cost_kind == GG_COST_TIME ? gg_time_now()
                                          : 0;
}

/* The cost of grid point (gx, gy): a pixel's own, or in corner mode the
   corner's, which fold_corner_costs gives to the pixels that own them. */
static void put_cost(job *j, int gx, int gy, double v)
{
    if (j->corner)
        j->ccost[(size_t)gy * j->cw + gx] = (float)v;
    else
        j->cost[(size_t)(j->r.y0 + gy) * j->r.w + (j->r.x0 + gx)] = (float)v;
}

/* An empty tile's cost map: what fill_empty_tile stands for at each grid
   point (n eye rays that miss, depth 1) or its share of the seconds
   secs the tile took. Cost maps measure the render as it runs, so that
   ggrt plan sees background as the cheap thing it is. */
static void empty_tile_cost(job *j, int gx0, int gy0, int gx1, int gy1, double secs)
{
    const int n = j->corner ? 1 : j->r.spp;
    const double per = secs / ((double)(gx1 - gx0) * (double)(gy1 - gy0));
    const double v = j->cost_kind == GG_COST_TIME || j->cost_kind == GG_COST_CPU ? per
                     : j->cost_kind == GG_COST_DEPTH                         ? 1.0
                                                                             : (double)n;
    int gx, gy;
    for (gy = gy0; gy < gy1; gy++)
        for (gx = gx0; gx < gx1; gx++) put_cost(j, gx, gy, v);
}

/* Corner mode's cost map: pixel (x, y) owns the corner at its top left,
   and a pixel on the image's right or bottom edge the corners beyond it
   too, so that the map adds up to the render's rays (and seconds) with
   every corner counted once. The depth is the deepest of the corners
   owned. A crop's corners right of or below it belong to pixels outside
   it, so tiles' maps add up to the whole image's. */
static void fold_corner_costs(job *j)
{
    const size_t cw = (size_t)j->cw;
    int x, y;
    for (y = j->r.y0; y < j->r.y1; y++)
        for (x = j->r.x0; x < j->r.x1; x++) {
            const float *c = j->ccost + (size_t)(y - j->r.y0) * cw + (size_t)(x - j->r.x0);
            const int right = x == j->r.w - 1, bottom = y == j->r.h - 1;
            float own[4];
            double v = 0;
            int n = 0, k;
            own[n++] = c[0];
            if (right) own[n++] = c[1];
            if (bottom) own[n++] = c[cw];
            if (right && bottom) own[n++] = c[cw + 1];
            for (k = 0; k < n; k++)
                v = j->cost_kind == GG_COST_DEPTH ? (own[k] > v ? own[k] : v) : v + own[k];
            j->cost[(size_t)y * j->r.w + x] = (float)v;
        }
}

static void render_tile(job *j, int t, gg_shade_thread *th)
{
    ggRayStats *st = &th->st;
    /* Tiles go out column by column: two threads then work on tiles one
       above the other, whose rows share no cache line of the image or
       the layer map, where side by side they shared the line at their
       boundary in every row (16 pixels of 12 bytes are 3 lines only if
       the buffer is 64-byte aligned, which the caller's map need not
       be): 10% of spd/tetra's render with four layers. */
    const int tiles_y = j->ntiles / j->tiles_x;
    int gx0 = (t / tiles_y) * TILE, gy0 = (t % tiles_y) * TILE;
    int gx1 = gx0 + TILE < j->cw ? gx0 + TILE : j->cw;
    int gy1 = gy0 + TILE < j->ch ? gy0 + TILE : j->ch;
    int gx, gy;
    uint64_t poll_at;
    if (tile_empty(j, gx0, gy0, gx1, gy1)) {
        double t0 = cost_clock(j);
        fill_empty_tile(j, gx0, gy0, gx1, gy1, th);
        if (j->cost) empty_tile_cost(j, gx0, gy0, gx1, gy1, cost_clock(j) - t0);
        return;
    }
    if (!j->cost && !j->ctx.rec && (j->corner || j->r.spp == 1)) {
        if (j->layers)
            tile_rows_layers(j, gx0, gy0, gx1, gy1, th);
        else
            tile_rows(j, gx0, gy0, gx1, gy1, th);
        return;
    }
    poll_at = rays_cast(st) + POLL_RAYS;
    for (gy = gy0; gy < gy1; gy++)
        for (gx = gx0; gx < gx1; gx++) {
            ggRayStats before = *st;
            if (rays_cast(st) >= poll_at) {
                if (poll_tile(j, (long)(gy - gy0) * (gx1 - gx0) + (gx - gx0))) return;
                poll_at = rays_cast(st) + POLL_RAYS;
            }
            double t0 = cost_clock(j);
            if (j->cost) st->max_depth = 0;
            if (j->corner) {
                /* Corner (x0 + gx, y0 + gy) of the pixel grid. */
                ggColor c = j->layers ? corner_layers(j, j->r.x0 + gx, j->r.y0 + gy,
                                                      (size_t)gy * j->cw + gx, th)
                                      : sample_color(j, j->r.x0 + gx, j->r.y0 + gy, th);
                float *o = j->corner + 3 * ((size_t)gy * j->cw + gx);
                o[0] = (float)c.r, o[1] = (float)c.g, o[2] = (float)c.b;
            } else {
                int x = j->r.x0 + gx, y = j->r.y0 + gy;
                ggColor acc =
                    j->layers ? pixel_layers(j, x, y, th) : pixel_center(j, x, y, th, NULL, -1);
                float *o = j->px + 3 * ((size_t)y * j->r.w + x);
                o[0] = (float)acc.r, o[1] = (float)acc.g, o[2] = (float)acc.b;
            }
            if (j->cost) {
                double v =
                    j->cost_kind == GG_COST_TIME || j->cost_kind == GG_COST_CPU
                        ? cost_clock(j) - t0
                    : j->cost_kind == GG_COST_DEPTH
                        ? (double)st->max_depth
                        : (double)(st->eye + st->reflect + st->refract + st->shadow - before.eye -
                                   before.reflect - before.refract - before.shadow);
                put_cost(j, gx, gy, v);
                if (before.max_depth > st->max_depth) st->max_depth = before.max_depth;
            }
        }
}

/* Points of the grid in tile t: edge tiles are cut by the grid. */
static long tile_points(const job *j, int t)
{
    const int tiles_y = j->ntiles / j->tiles_x;
    const int gx0 = (t / tiles_y) * TILE, gy0 = (t % tiles_y) * TILE;
    const int w = j->cw - gx0 < TILE ? j->cw - gx0 : TILE;
    const int h = j->ch - gy0 < TILE ? j->ch - gy0 : TILE;
    return (long)w * h;
}

static void *worker(void *arg)
{
    job *j = arg;
    gg_shade_thread th;
    ggColor aov[GG_LAYERS_MAX];
    uint32_t aov_n[GG_LAYERS_MAX];
    memset(&th, 0, sizeof th);
    th.aov = aov;
    if (j->lhit) th.aov_n = aov_n;
    for (;;) {
        int t;
        long tile_px;
        pthread_mutex_lock(&j->mu);
        t = j->cancelled ? j->ntiles : j->next_tile++;
        pthread_mutex_unlock(&j->mu);
        if (t >= j->ntiles) break;
        render_tile(j, t, &th);
        tile_px = tile_points(j, t);
        pthread_mutex_lock(&j->mu);
        /* the grid's points as the window's pixels (render.h: progress is
           in pixels; a corner grid has a row and a column more) */
        j->points_done += tile_px;
        j->done = (long)((double)j->points_done / (double)j->points * (double)j->total);
        if (j->points_done == j->points) j->done = j->total;
        /* Report about every 1/200 of the work: enough for a smooth bar,
           few enough not to matter. */
        if (j->progress && (j->done - j->reported >= j->total / 200 || j->done == j->total)) {
            j->reported = j->done;
            if (j->progress(j->progress_ud, j->done, j->total)) j->cancelled = 1;
        }
        pthread_mutex_unlock(&j->mu);
    }
    pthread_mutex_lock(&j->mu);
    ggRayStatsAdd(&j->stats, &th.st);
    pthread_mutex_unlock(&j->mu);
    return NULL;
}

static void run_tiles(job *j, int cw, int ch)
{
    pthread_t th[256];
    int i, started = 0;
    j->cw = cw, j->ch = ch;
    j->tiles_x = (cw + TILE - 1) / TILE;
    j->ntiles = j->tiles_x * ((ch + TILE - 1) / TILE);
    j->next_tile = 0;
    j->done = 0, j->reported = 0, j->points_done = 0, j->reported_at = gg_time_now();
    j->points = (long)cw * ch;
    j->total = (long)(j->r.x1 - j->r.x0) * (j->r.y1 - j->r.y0);
    for (i = 1; i < j->r.threads && i < j->ntiles; i++) {
        if (pthread_create(&th[started], NULL, worker, j) != 0) break;
        started++;
    }
    worker(j); /* the calling thread works too */
    for (i = 0; i < started; i++) pthread_join(th[i], NULL);
}

/* Pixel-corner mode: each pixel the mean of its four corners, and so each
   of its layers. */
static void average_corners(job *j, int cw)
{
    const int nl = j->layers ? j->layers->n : 0;
    int x, y, k, l;
    for (y = j->r.y0; y < j->r.y1 && !j->cancelled; y++)
        for (x = j->r.x0; x < j->r.x1; x++) {
            const size_t i = (size_t)(y - j->r.y0) * cw + (x - j->r.x0);
            const float *c00 = j->corner + 3 * i;
            const float *c10 = c00 + 3, *c01 = c00 + 3 * (size_t)cw, *c11 = c01 + 3;
            float *o = j->px + 3 * ((size_t)y * j->r.w + x);
            for (k = 0; k < 3; k++)
                o[k] = (float)(((double)c00[k] + c10[k] + c01[k] + c11[k]) * 0.25);
            for (l = 0; l < nl; l++) {
                const size_t row = 3 * (size_t)nl * (size_t)cw, at = 3 * ((size_t)nl * i + l);
                const float *d00 = j->lcorner + at, *d10 = d00 + 3 * nl, *d01 = d00 + row;
                const float *d11 = d01 + 3 * nl;
                ggColor v;
                v.r = ((double)d00[0] + d10[0] + d01[0] + d11[0]) * 0.25;
                v.g = ((double)d00[1] + d10[1] + d01[1] + d11[1]) * 0.25;
                v.b = ((double)d00[2] + d10[2] + d01[2] + d11[2]) * 0.25;
                put_layer(j, l, x, y, v);
            }
        }
}

/* The options' path layers into the job (and its shading). */
static int set_layers(job *j, const ggRenderOptions *opt, ggError *err)
{
    if (!opt || (!opt->layers && !opt->layer_map)) return GG_OK;
    if (!opt->layers || !opt->layer_map)
        return gg_error_set(err, GG_ERROR_INVALID,
                            "ggRender: path layers need both layers and layer_map");
    if (opt->layers->n < 0 || opt->layers->n > GG_LAYERS_MAX)
        return gg_error_set(err, GG_ERROR_INVALID, "ggRender: %d path layers (0..%d)",
                            opt->layers->n, GG_LAYERS_MAX);
    if (opt->layers->n == 0) return GG_OK;
    j->layers = opt->layers;
    j->lmap = opt->layer_map;
    return GG_OK;
}

static int render_job(job *j, ggScene *s, const ggRenderOptions *opt, ggImage **out,
                      ggRayStats *stats, ggError *err);

GG_API int ggRender(ggScene *s, const ggRenderOptions *opt, ggImage **out, ggRayStats *stats,
                    ggError *err)
{
    job j;
    int rc;
    /* A NULL handle or output leaves every output as it was (base.h rule
       1); past that, statistics are this call's alone, also on failure. */
    if (!s || !out) return gg_error_set(err, GG_ERROR_INVALID, "ggRender: NULL argument");
    if (stats) memset(stats, 0, sizeof *stats);
    *out = NULL;
    memset(&j, 0, sizeof j);
    if ((rc = set_layers(&j, opt, err)) != GG_OK) return rc;
    return render_job(&j, s, opt, out, stats, err);
}

int gg_render_layer_sums(ggScene *s, const ggRenderOptions *opt, const ggPathLayers *l,
                         double *sums, unsigned char *hits, ggImage **out, ggRayStats *stats,
                         ggError *err)
{
    job j;
    if (stats) memset(stats, 0, sizeof *stats);
    *out = NULL;
    memset(&j, 0, sizeof j);
    j.layers = l, j.lsum = sums, j.lhit = hits;
    return render_job(&j, s, opt, out, stats, err);
}

/* ggRender with the job's layers set. */
static int render_job(job *j0, ggScene *s, const ggRenderOptions *opt, ggImage **out,
                      ggRayStats *stats, ggError *err)
{
    job j = *j0;
    ggImage *img;
    int rc;
    if ((rc = resolve(s, opt, &j.r, err)) != GG_OK) return rc;
    if (j.lsum && (j.r.spp != 1 || j.r.corners))
        return gg_error_set(err, GG_ERROR_UNSUPPORTED,
                            "layer sums: one sample per pixel at its centre only");
    if ((rc = prepare(s, err)) != GG_OK) return rc;
    img = ggImageCreate(j.r.w, j.r.h, s->alloc);
    if (!img)
        return gg_error_set(err, GG_ERROR_NOMEM, "out of memory for a %dx%d image", j.r.w, j.r.h);
    gg_shade_init(&j.ctx, s, j.r.depth, j.r.force, j.r.spd, &j.r.acc);
    gg_shade_set_layers(&j.ctx, j.layers);
    if (j.layers) miss_layers(&j);
    j.ctx.budget = (uint32_t)j.r.budget;
    if (j.r.spp > 1) j.ctx.fx |= GG_EFFECT_SUPERSAMPLING;
    basis(s, j.r.w, j.r.h, &j.cam);
    j.px = ggImagePixels(img);
    if (opt) {
        j.progress = opt->progress, j.progress_ud = opt->progress_ud;
        j.cost = opt->cost_map, j.cost_kind = opt->cost_kind;
    }
    if (pthread_mutex_init(&j.mu, NULL) != 0) {
        ggImageFree(img);
        return gg_error_set(err, GG_ERROR_NOMEM, "cannot create a mutex");
    }
    if (j.r.corners) {
        /* SPD sampling: rays through the (w+1) x (h+1) pixel corners, each
           pixel the mean of its four corners. Corners are shaded once. */
        int cw = j.r.x1 - j.r.x0 + 1, ch = j.r.y1 - j.r.y0 + 1;
        const size_t nl = j.layers ? (size_t)j.layers->n : 0;
        j.corner = gg_mem_calloc(s->alloc, (size_t)cw * (size_t)ch, 3 * sizeof(float));
        if (nl) j.lcorner = gg_mem_calloc(s->alloc, (size_t)cw * (size_t)ch, 3 * nl * sizeof(float));
        if (j.cost) j.ccost = gg_mem_calloc(s->alloc, (size_t)cw * (size_t)ch, sizeof(float));
        if (!j.corner || (nl && !j.lcorner) || (j.cost && !j.ccost)) {
            gg_mem_free(s->alloc, j.corner), gg_mem_free(s->alloc, j.lcorner);
            gg_mem_free(s->alloc, j.ccost);
            pthread_mutex_destroy(&j.mu);
            ggImageFree(img);
            return gg_error_set(err, GG_ERROR_NOMEM, "out of memory for pixel corners");
        }
        run_tiles(&j, cw, ch);
        average_corners(&j, cw);
        if (j.cost) fold_corner_costs(&j);
        gg_mem_free(s->alloc, j.corner), gg_mem_free(s->alloc, j.lcorner);
        gg_mem_free(s->alloc, j.ccost);
    } else {
        run_tiles(&j, j.r.x1 - j.r.x0, j.r.y1 - j.r.y0);
    }
    pthread_mutex_destroy(&j.mu);
    if (stats) *stats = j.stats;
    if (j.cancelled) {
        ggImageFree(img);
        return gg_error_set(err, GG_ERROR_CANCELLED, "render cancelled by the progress callback");
    }
    *out = img;
    return GG_OK;
}

GG_API ggColor ggRayColor(const ggScene *s, const ggRenderOptions *opt, ggRay ray, int depth,
                          ggRayStats *stats)
{
    gg_shade_ctx ctx;
    resolved r;
    gg_shade_thread th;
    if (!s) return rgb(0, 0, 0); /* stats as they were (base.h rule 1) */
    if (stats) memset(stats, 0, sizeof *stats);
    if (!s->prepared || resolve(s, opt, &r, NULL) != GG_OK) return rgb(0, 0, 0);
    gg_shade_init(&ctx, s, r.depth, r.force, r.spd, &r.acc);
    ctx.budget = (uint32_t)r.budget;
    memset(&th, 0, sizeof th);
    {
        int k; /* d of any finite size (base.h): only its direction counts */
        ggColor c = gg_shade_ray(&ctx, ray.o, v3tame(ray.d, &k), depth > 0 ? depth : 1, &th);
        if (stats) *stats = th.st;
        return c;
    }
}

/* A job set up for tracing single pixels: ggTracePixel and gg_tracer. */
static int trace_setup(job *j, ggScene *s, const ggRenderOptions *opt, ggError *err)
{
    memset(j, 0, sizeof *j);
#ifdef GG_NO_RECORDER
    (void)s, (void)opt;
    return gg_error_set(err, GG_ERROR_UNSUPPORTED, "this libggrt was built without the recorder");
#else
    int rc;
    if ((rc = resolve(s, opt, &j->r, err)) != GG_OK) return rc;
    if ((rc = prepare(s, err)) != GG_OK) return rc;
    gg_shade_init(&j->ctx, s, j->r.depth, j->r.force, j->r.spd, &j->r.acc);
    j->ctx.budget = (uint32_t)j->r.budget;
    if (j->r.spp > 1) j->ctx.fx |= GG_EFFECT_SUPERSAMPLING;
    basis(s, j->r.w, j->r.h, &j->cam);
    return GG_OK;
#endif
}

/* c rounded to the floats ggRender stores. Through a volatile: GCC 12.2's
   SLP vectorizer (-O2) drops the (double)(float) round trip of the two
   lanes it pairs, r and g, which C99 6.3.1.5 and 5.2.4.2.2 require (compare
   its output with -fno-tree-slp-vectorize, or with clang's). */
static ggColor as_stored(ggColor c)
{
    volatile float f[3];
    f[0] = (float)c.r, f[1] = (float)c.g, f[2] = (float)c.b;
    return rgb(f[0], f[1], f[2]);
}

/* Pixel (x, y) of a set-up job, as ggRender writes it, recording sample
   `sample` (-1: all) into rec when rec is not NULL. j0 is only read: the
   recorder goes into a copy of its context, so threads may share j0. */
static ggColor trace_one(const job *j0, int x, int y, int sample, ggTrace *rec,
                         gg_shade_thread *local)
{
    job j = *j0;
    ggColor c;
    int k;
    if (rec) gg_trace_clear(rec);
    if (j.r.corners) {
        /* The four corners, stored as floats and averaged as ggRender does. */
        float cf[4][3];
        for (k = 0; k < 4; k++) {
            ggColor cc;
            int recorded = rec && (sample < 0 || sample == k);
            ggRayStats keep = local->st;
            if (recorded) {
                j.ctx.rec = rec;
                rec->sample = k;
            }
            cc = sample_color(&j, x + (k & 1), y + (k >> 1), local);
            if (rec && !recorded) local->st = keep;
            j.ctx.rec = NULL;
            cf[k][0] = (float)cc.r, cf[k][1] = (float)cc.g, cf[k][2] = (float)cc.b;
        }
        c.r = ((double)cf[0][0] + cf[1][0] + cf[2][0] + cf[3][0]) * 0.25;
        c.g = ((double)cf[0][1] + cf[1][1] + cf[2][1] + cf[3][1]) * 0.25;
        c.b = ((double)cf[0][2] + cf[1][2] + cf[2][2] + cf[3][2]) * 0.25;
    } else {
        c = pixel_center(&j, x, y, local, rec, sample);
    }
    return as_stored(c);
}

GG_API int ggTracePixel(ggScene *s, const ggRenderOptions *opt, int x, int y, int sample,
                        ggTrace *rec, ggColor *pixel, ggRayStats *stats, ggError *err)
{
    job j;
    gg_shade_thread local;
    int rc;
    if (!s || !rec || !pixel) /* stats as they were (base.h rule 1) */
        return gg_error_set(err, GG_ERROR_INVALID, "ggTracePixel: NULL argument");
    if (stats) memset(stats, 0, sizeof *stats);
    /* cleared first, so that a failure leaves no earlier call's rays */
    gg_trace_clear(rec);
    memset(&local, 0, sizeof local);
    if ((rc = resolve(s, opt, &j.r, err)) != GG_OK) return rc;
    if (x < 0 || y < 0 || x >= j.r.w || y >= j.r.h)
        return gg_error_set(err, GG_ERROR_INVALID, "pixel %d,%d is outside the %dx%d image", x, y,
                            j.r.w, j.r.h);
    if (sample < -1 || sample >= (j.r.corners ? 4 : j.r.spp))
        return gg_error_set(err, GG_ERROR_INVALID, "sample %d does not exist (the pixel has %d)",
                            sample, j.r.corners ? 4 : j.r.spp);
    if ((rc = trace_setup(&j, s, opt, err)) != GG_OK) return rc;
    *pixel = trace_one(&j, x, y, sample, rec, &local);
    if (stats) *stats = local.st;
    if (rec->status != GG_OK) {
        rc = rec->status;
        gg_trace_clear(rec); /* not a partial tree: the trace is empty on failure */
        return gg_error_set(err, rc, "out of memory recording the ray tree");
    }
    return GG_OK;
}

/* ---- gg_tracer (render.h) ---- */

struct gg_tracer {
    job j;
    const ggAllocator *alloc;
};

int gg_tracer_create(ggScene *s, const ggRenderOptions *opt, gg_tracer **out, ggError *err)
{
    gg_tracer *t;
    int rc;
    *out = NULL;
    t = gg_mem_calloc(s->alloc, 1, sizeof *t);
    if (!t) return gg_error_set(err, GG_ERROR_NOMEM, "out of memory");
    t->alloc = s->alloc;
    if ((rc = trace_setup(&t->j, s, opt, err)) != GG_OK) {
        gg_mem_free(s->alloc, t);
        return rc;
    }
    if (opt) t->j.progress = opt->progress, t->j.progress_ud = opt->progress_ud;
    *out = t;
    return GG_OK;
}

void gg_tracer_free(gg_tracer *t)
{
    if (t) gg_mem_free(t->alloc, t);
}

void gg_tracer_info(const gg_tracer *t, gg_tracer_desc *d)
{
    const resolved *r = &t->j.r;
    d->width = r->w, d->height = r->h;
    d->x0 = r->x0, d->y0 = r->y0, d->x1 = r->x1, d->y1 = r->y1;
    d->samples = r->corners ? 4 : r->spp;
    d->max_depth = r->depth;
    d->threads = r->threads;
    d->progress = t->j.progress, d->progress_ud = t->j.progress_ud;
}

ggColor gg_tracer_pixel(const gg_tracer *t, int x, int y, ggTrace *rec, ggRayStats *st)
{
    gg_shade_thread local;
    ggColor c;
    memset(&local, 0, sizeof local);
    c = trace_one(&t->j, x, y, -1, rec, &local);
    if (st) ggRayStatsAdd(st, &local.st);
    return c;
}

int gg_tracer_status(const ggTrace *rec)
{
    return rec->status;
}

int gg_tracer_empty(const gg_tracer *t, int x0, int y0, int x1, int y1)
{
    const resolved *r = &t->j.r;
    return tile_empty(&t->j, x0 - r->x0, y0 - r->y0, x1 - r->x0, y1 - r->y0);
}
