/* SPDX-License-Identifier: MIT */
/*
** find.c -- ggFind: the pixels whose ray trees satisfy a predicate.
*/
#include "debug_int.h"

#include <stdlib.h>
#include <string.h>

typedef struct find_res {
    ggFindResult pub; /* first: the public pointer is this struct's */
    gg_dbg_alloc al;
} find_res;

/* What each worker keeps: its first `limit` matches (in row order, as it
   takes rows in order) and its count. */
typedef struct find_thread {
    ggFindMatch *m;
    int n;
    size_t cap;
    int last; /* the predicate's value at the last pixel */
    double last_share; /* path finds: the share at the last pixel */
    long matched;
    gg_dbg_buf buf;
    uint64_t *sets; /* path finds: the automaton's states per ray */
    size_t sets_cap;
    gg_path_cache *cache; /* path finds: the automaton's steps */
} find_thread;

typedef struct find_job {
    const ggPredicate *pred;
    const ggPathExpr *path; /* instead of pred */
    ggFindResult *res;
    int limit;
    find_thread *t;
    const ggAllocator *alloc;
} find_job;

/* Record a match of worker th; the mask and image are the result's. The
   list grows as matches come (a limit can be far above the pixel count). */
static int matched(find_job *fj, find_thread *th, int x, int y, ggColor px, double share)
{
    ggFindResult *r = fj->res;
    r->mask[(size_t)y * r->width + x] = 1;
    th->matched++;
    if (th->n < fj->limit) {
        if (gg_mem_grow(fj->alloc, (void **)&th->m, &th->cap, (size_t)th->n + 1, sizeof *th->m))
            return GG_ERROR_NOMEM;
        th->m[th->n].x = x, th->m[th->n].y = y, th->m[th->n].pixel = px;
        th->m[th->n].share = share;
        th->n++;
    }
    return 0;
}

/* A path find's pixel: weights, then the automaton over its paths. */
static int path_pixel(find_job *fj, find_thread *th, int x, int y, const ggTrace *tr, ggColor px)
{
    gg_dbg_pixel p;
    ggPathSummary sum;
    size_t n = ggTraceNodeCount(tr);
    if (gg_dbg_buf_weights(&th->buf, fj->alloc, tr) ||
        gg_mem_grow(fj->alloc, (void **)&th->sets, &th->sets_cap, (n ? n : 1) * GG_PATH_WORDS,
                    sizeof *th->sets) ||
        (!th->cache && !(th->cache = gg_mem_calloc(fj->alloc, 1, sizeof *th->cache))))
        return GG_ERROR_NOMEM;
    memset(&p, 0, sizeof p);
    p.trace = tr, p.x = x, p.y = y, p.px = px, p.w = th->buf.w;
    gg_path_run(fj->path, &p, th->sets, &sum, th->cache);
    th->last = sum.matched > 0, th->last_share = sum.share;
    return th->last ? matched(fj, th, x, y, px, sum.share) : 0;
}

static int find_pixel(void *ud, int thread, int x, int y, ggTrace *const *recs, const ggColor *px,
                      int same)
{
    find_job *fj = ud;
    find_thread *th = &fj->t[thread];
    gg_dbg_pixel p;
    unsigned needs = fj->path ? fj->path->needs : fj->pred->needs;
    gg_dbg_put(fj->res->image, x, y, px[0]);
    /* The same trees as the last pixel's: the same answer, unless the
       predicate reads x or y. */
    if (same && !(needs & GG_NEED_XY))
        return th->last ? matched(fj, th, x, y, px[0], th->last_share) : 0;
    if (fj->path) return path_pixel(fj, th, x, y, recs[0], px[0]);
    memset(&p, 0, sizeof p);
    p.trace = recs ? recs[0] : NULL, p.x = x, p.y = y, p.px = px[0];
    if (p.trace && (fj->pred->needs & GG_NEED_WEIGHT)) {
        if (gg_dbg_buf_weights(&th->buf, fj->alloc, p.trace)) return GG_ERROR_NOMEM;
        p.w = th->buf.w;
    }
    th->last = gg_pred_eval(fj->pred, &p);
    return th->last ? matched(fj, th, x, y, px[0], 0) : 0;
}

static int by_row(const void *a, const void *b)
{
    const ggFindMatch *p = a, *q = b;
    return p->y != q->y ? (p->y < q->y ? -1 : 1) : p->x < q->x ? -1 : p->x > q->x;
}

/* The workers' lists into the result: the first `limit` in row order. */
static int merge(find_job *fj, int threads)
{
    ggFindResult *r = fj->res;
    int i, k, total = 0;
    for (i = 0; i < threads; i++) total += fj->t[i].n, r->matched += fj->t[i].matched;
    if (total == 0) return GG_OK;
    r->matches = gg_mem_calloc(fj->alloc, (size_t)total, sizeof *r->matches);
    if (!r->matches) return GG_ERROR_NOMEM;
    for (i = 0, k = 0; i < threads; i++) {
        if (fj->t[i].n == 0) continue; /* its list may be NULL */
        memcpy(r->matches + k, fj->t[i].m, (size_t)fj->t[i].n * sizeof *r->matches);
        k += fj->t[i].n;
    }
    qsort(r->matches, (size_t)total, sizeof *r->matches, by_row);
    r->nmatches = total < fj->limit ? total : fj->limit;
    return GG_OK;
}

/* A predicate that reads only pixel values: one plain render serves. */
static int find_by_render(ggScene *s, const ggRenderOptions *opt, find_job *fj, ggError *err)
{
    ggFindResult *r = fj->res;
    find_thread *th = &fj->t[0];
    ggImage *img = NULL;
    int x, y, rc = ggRender(s, opt, &img, &r->stats, err);
    if (rc != GG_OK) return rc;
    ggImageFree(r->image);
    r->image = img;
    for (y = r->y0; y < r->y1; y++)
        for (x = r->x0; x < r->x1; x++) {
            gg_dbg_pixel p;
            memset(&p, 0, sizeof p);
            p.x = x, p.y = y, p.px = ggImageGet(img, x, y);
            if (gg_pred_eval(fj->pred, &p) && matched(fj, th, x, y, p.px, 0) != 0)
                return gg_error_set(err, GG_ERROR_NOMEM, "out of memory for the find result");
        }
    return GG_OK;
}

/* A path find without predicates (l: its one layer, freed here), one
   sample per pixel at its centre: a
   render whose layer copy carries the expression's automaton gives each
   pixel's matching terms: whether there is a non-zero one, and their
   sum's r + g + b in ggPathMatch's order (gg_render_layer_sums), so the
   same matches and shares as tracing every pixel, without the recorder. */
static int find_by_layers(ggScene *s, const ggRenderOptions *opt, find_job *fj, ggPathLayers *l,
                          ggError *err)
{
    ggFindResult *r = fj->res;
    const size_t n = (size_t)r->width * (size_t)r->height;
    ggImage *img = NULL;
    double *sum = gg_mem_alloc(fj->alloc, n * sizeof *sum);
    unsigned char *hit = gg_mem_calloc(fj->alloc, n, 1);
    int x, y, rc = sum && hit ? GG_OK
                              : gg_error_set(err, GG_ERROR_NOMEM, "out of memory for a path find");
    if (rc == GG_OK) rc = gg_render_layer_sums(s, opt, l, sum, hit, &img, &r->stats, err);
    if (rc == GG_OK) r->image = img;
    for (y = r->y0; rc == GG_OK && y < r->y1; y++) {
        const unsigned char *h = hit + (size_t)y * r->width;
        for (x = r->x0; rc == GG_OK && x < r->x1; x++) {
            const size_t i = (size_t)y * r->width + x;
            ggColor px;
            double pt;
            if (!h[x]) continue;
            px = ggImageGet(img, x, y), pt = px.r + px.g + px.b;
            /* the share as path_match.c's gg_path_run computes it */
            if (matched(fj, &fj->t[0], x, y, px, pt != 0 && pt == pt && pt - pt == 0 ? sum[i] / pt : 0))
                rc = gg_error_set(err, GG_ERROR_NOMEM, "out of memory for the find result");
        }
    }
    ggPathLayersFree(l);
    gg_mem_free(fj->alloc, sum), gg_mem_free(fj->alloc, hit);
    return rc;
}

GG_API void ggFindResultFree(ggFindResult *r)
{
    const ggAllocator *a;
    if (!r) return;
    a = ((find_res *)r)->al.a;
    gg_mem_free(a, r->matches);
    gg_mem_free(a, r->mask);
    ggImageFree(r->image);
    gg_mem_free(a, r);
}

/* A result for the tracer's image and window (with an image of its own
   when `image`: else a render's is put there), and the workers' lists. */
static int find_alloc(ggScene *s, const gg_scan *sc, find_job *fj, ggFindResult **out, int image)
{
    find_res *fr = gg_mem_calloc(s->alloc, 1, sizeof *fr);
    ggFindResult *r;
    if (!fr) return GG_ERROR_NOMEM;
    gg_dbg_alloc_init(&fr->al, s->alloc);
    r = *out = &fr->pub;
    fj->res = r, fj->alloc = fr->al.a;
    r->width = sc->desc.width, r->height = sc->desc.height;
    r->x0 = sc->desc.x0, r->y0 = sc->desc.y0, r->x1 = sc->desc.x1, r->y1 = sc->desc.y1;
    r->mask = gg_mem_calloc(fj->alloc, (size_t)r->width * (size_t)r->height, 1);
    if (image) r->image = ggImageCreate(r->width, r->height, fj->alloc);
    fj->t = gg_mem_calloc(fj->alloc, (size_t)sc->threads, sizeof *fj->t);
    if (!r->mask || (image && !r->image) || !fj->t) return GG_ERROR_NOMEM;
    return GG_OK;
}

static void find_job_free(find_job *fj, int threads)
{
    int i;
    for (i = 0; fj->t && i < threads; i++) {
        gg_mem_free(fj->alloc, fj->t[i].m);
        gg_mem_free(fj->alloc, fj->t[i].buf.w);
        gg_mem_free(fj->alloc, fj->t[i].sets);
        gg_mem_free(fj->alloc, fj->t[i].cache);
    }
    gg_mem_free(fj->alloc, fj->t);
}

/* ggFind and ggFindPath: fj->pred or fj->path set. */
static int find_run(ggScene *s, const ggRenderOptions *opt, find_job *fj, unsigned needs,
                    ggFindResult **out, ggError *err)
{
    gg_tracer *tr = NULL;
    gg_scan sc;
    ggFindResult *r = NULL;
    ggPathLayers *l = NULL;
    int rc;
    if ((rc = gg_tracer_create(s, opt, &tr, err)) != GG_OK) return rc;
    memset(&sc, 0, sizeof sc);
    sc.tracer[0] = tr, sc.ntracers = 1;
    sc.record = (needs & GG_NEED_TREE) != 0;
    /* A render through pixel corners shares each corner's rays between
       four pixels (and a crop casts its edge's corners again), so its
       counts are no pixel's own: a tile's would not add up to the whole
       image's. Each pixel is traced then, as the traced predicates are. */
    if (opt && opt->pixel_corners) sc.record = 1;
    sc.every_pixel = (needs & GG_NEED_COST) != 0;
    gg_scan_init(&sc);
    if (sc.record && fj->path && sc.desc.samples == 1 &&
        gg_path_layers_of(fj->path, &l, NULL) != GG_OK)
        l = NULL;
    /* a render's image goes into the result: none of its own then */
    rc = find_alloc(s, &sc, fj, &r, sc.record && !l);
    if (rc != GG_OK) {
        ggPathLayersFree(l);
        rc = gg_error_set(err, rc, "out of memory for the find result");
    } else if (!sc.record) {
        rc = find_by_render(s, opt, fj, err);
    } else if (l) {
        rc = find_by_layers(s, opt, fj, l, err);
    } else {
        sc.fn = find_pixel, sc.ud = fj, sc.alloc = fj->alloc;
        r->traced = 1;
        if ((rc = gg_scan_run(&sc, err)) == GG_OK) r->stats = sc.stats[0];
    }
    /* r is NULL when find_alloc failed before making it */
    if (r) r->scanned = rc == GG_OK ? (long)(r->x1 - r->x0) * (r->y1 - r->y0) : 0;
    if (rc == GG_OK && merge(fj, sc.threads) != GG_OK)
        rc = gg_error_set(err, GG_ERROR_NOMEM, "out of memory for the find result");
    find_job_free(fj, sc.threads);
    gg_tracer_free(tr);
    if (rc != GG_OK) {
        ggFindResultFree(r);
        return rc;
    }
    *out = r;
    return GG_OK;
}

GG_API int ggFind(ggScene *s, const ggRenderOptions *opt, const ggPredicate *pred, int limit,
                  ggFindResult **out, ggError *err)
{
    find_job fj;
    if (!s || !pred || !out) return gg_error_set(err, GG_ERROR_INVALID, "ggFind: NULL argument");
    *out = NULL; /* after the NULL checks: base.h rule 1 */
    if (limit < 0) return gg_error_set(err, GG_ERROR_INVALID, "ggFind: negative limit");
    memset(&fj, 0, sizeof fj);
    fj.pred = pred, fj.limit = limit;
    return find_run(s, opt, &fj, pred->needs, out, err);
}

GG_API int ggFindPath(ggScene *s, const ggRenderOptions *opt, const ggPathExpr *path, int limit,
                      ggFindResult **out, ggError *err)
{
    find_job fj;
    if (!s || !path || !out)
        return gg_error_set(err, GG_ERROR_INVALID, "ggFindPath: NULL argument");
    *out = NULL; /* after the NULL checks: base.h rule 1 */
    if (limit < 0) return gg_error_set(err, GG_ERROR_INVALID, "ggFindPath: negative limit");
    memset(&fj, 0, sizeof fj);
    fj.path = path, fj.limit = limit;
    return find_run(s, opt, &fj, path->needs | GG_NEED_TREE | GG_NEED_LIGHTS | GG_NEED_WEIGHT,
                    out, err);
}
