/* SPDX-License-Identifier: MIT */
/*
** diff.c -- ggDiff: two renders traced side by side, pixel by pixel, with
** their values and ray trees compared.
*/
#include "debug_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct diff_res {
    ggDiffResult pub;
    gg_dbg_alloc al;
} diff_res;

typedef struct diff_thread {
    ggDiffPixel *worst; /* sorted, worst first */
    int n;
    long value_differ, tree_differ, by_kind[GG_DIFF_COUNT];
    double max_delta;
    /* ggDiffPath: the moved pixels (the first `moves_limit`, row order),
       and the last pixel's matching paths */
    ggDiffMove *moves;
    int nmoves;
    size_t moves_cap;
    long moved;
    uint64_t *cls[2]; /* each side's matching paths, as sorted hashes */
    size_t ncls[2], cls_cap[2];
    ggPathSummary last[2];
    int last_moved;
} diff_thread;

typedef struct diff_job {
    ggDiffResult *res;
    diff_thread *t;
    int limit;
    const ggPathExpr *path; /* ggDiffPath */
    int moves_limit;
    const ggAllocator *alloc;
} diff_job;

/* Whether the floats ggRender stores for a and b differ in any bit. */
static int bits_differ(ggColor a, ggColor b)
{
    float fa[3], fb[3];
    fa[0] = (float)a.r, fa[1] = (float)a.g, fa[2] = (float)a.b;
    fb[0] = (float)b.r, fb[1] = (float)b.g, fb[2] = (float)b.b;
    return memcmp(fa, fb, sizeof fa) != 0;
}

static double delta(ggColor a, ggColor b)
{
    double d = fabs(a.r - b.r), e = fabs(a.g - b.g), f = fabs(a.b - b.b);
    if (gg_dbg_nonfinite(a) || gg_dbg_nonfinite(b)) return INFINITY;
    d = d > e ? d : e;
    return d > f ? d : f;
}

/* Worse first: larger delta, then a tree that differs, then row order. */
static int worse(const ggDiffPixel *p, const ggDiffPixel *q)
{
    if (p->delta != q->delta) return p->delta > q->delta;
    if ((p->first.what != GG_DIFF_SAME) != (q->first.what != GG_DIFF_SAME))
        return p->first.what != GG_DIFF_SAME;
    if (p->y != q->y) return p->y < q->y;
    return p->x < q->x;
}

/* Insert p into a worst-first list of at most limit entries. */
static void keep_worst(ggDiffPixel *list, int *n, int limit, const ggDiffPixel *p)
{
    int i;
    if (limit <= 0 || (*n == limit && !worse(p, &list[*n - 1]))) return;
    i = *n < limit ? (*n)++ : *n - 1;
    while (i > 0 && worse(p, &list[i - 1])) {
        list[i] = list[i - 1];
        i--;
    }
    list[i] = *p;
}

/* A hash of a path's events as text (ggPathFormat: types, scatters and
   labels), FNV-1a. */
static uint64_t path_hash(const ggTrace *tr, const ggLedgerTerm *term)
{
    char buf[1024];
    uint64_t h = 14695981039346656037u;
    size_t k, n = ggPathFormat(tr, term, buf, sizeof buf);
    for (k = 0; k < n && k + 1 < sizeof buf; k++) h = (h ^ (unsigned char)buf[k]) * 1099511628211u;
    return h ^ n;
}

static int by_hash(const void *a, const void *b)
{
    uint64_t p = *(const uint64_t *)a, q = *(const uint64_t *)b;
    return p < q ? -1 : p > q;
}

/* One side of a pixel: its path summary and the matching paths' classes
   (their events' hashes, sorted) into th->cls[side]. */
static int side_paths(diff_job *dj, diff_thread *th, int side, int x, int y, const ggTrace *tr,
                      ggColor px)
{
    ggLedger *l = NULL;
    unsigned char *m = NULL;
    size_t i;
    int rc = ggLedgerCreate(tr, px, dj->alloc, &l, NULL);
    th->ncls[side] = 0;
    if (rc == GG_ERROR_INVALID) /* an empty trace: no paths */
        return ggPathMatch(dj->path, tr, x, y, px, NULL, NULL, &th->last[side]);
    if (rc == GG_OK && !(m = gg_mem_calloc(dj->alloc, l->count ? l->count : 1, 1)))
        rc = GG_ERROR_NOMEM;
    if (rc == GG_OK) rc = ggPathMatch(dj->path, tr, x, y, px, l, m, &th->last[side]);
    if (rc == GG_OK && gg_mem_grow(dj->alloc, (void **)&th->cls[side], &th->cls_cap[side],
                                   l->count ? l->count : 1, sizeof *th->cls[side]))
        rc = GG_ERROR_NOMEM;
    for (i = 0; rc == GG_OK && i < l->count; i++)
        if (m[i]) th->cls[side][th->ncls[side]++] = path_hash(tr, &l->terms[i]);
    if (rc == GG_OK) qsort(th->cls[side], th->ncls[side], sizeof *th->cls[side], by_hash);
    gg_mem_free(dj->alloc, m);
    ggLedgerFree(l);
    return rc;
}

/* ggDiffPath's part of a pixel: both sides' matching paths, and a move
   when they differ as classes. same: the pixel is the last one's. */
static int path_pixel(diff_job *dj, diff_thread *th, int x, int y, ggTrace *const *recs,
                      const ggColor *px, int same, const ggDivergence *first)
{
    ggDiffMove *m;
    int i;
    if (!same || (dj->path->needs & GG_NEED_XY)) {
        for (i = 0; i < 2; i++)
            if (side_paths(dj, th, i, x, y, recs[i], px[i]) != GG_OK) return GG_ERROR_NOMEM;
        th->last_moved = th->ncls[0] != th->ncls[1] ||
                         (th->ncls[0] && memcmp(th->cls[0], th->cls[1],
                                                th->ncls[0] * sizeof *th->cls[0]) != 0);
    }
    if (!th->last_moved) return 0;
    th->moved++;
    if (th->nmoves >= dj->moves_limit) return 0;
    if (gg_mem_grow(dj->alloc, (void **)&th->moves, &th->moves_cap, (size_t)th->nmoves + 1,
                    sizeof *th->moves))
        return GG_ERROR_NOMEM;
    m = &th->moves[th->nmoves++];
    m->x = x, m->y = y, m->first = *first;
    m->share_a = th->last[0].share, m->share_b = th->last[1].share;
    m->matched_a = th->last[0].matched, m->matched_b = th->last[1].matched;
    return 0;
}

static int diff_pixel(void *ud, int thread, int x, int y, ggTrace *const *recs, const ggColor *px,
                      int same)
{
    diff_job *dj = ud;
    diff_thread *th = &dj->t[thread];
    ggDiffResult *r = dj->res;
    ggDiffPixel p;
    int vd = bits_differ(px[0], px[1]), td;
    memset(&p, 0, sizeof p);
    td = ggTraceCompare(recs[0], recs[1], &p.first);
    if (dj->path && path_pixel(dj, th, x, y, recs, px, same, &p.first) != 0)
        return GG_ERROR_NOMEM;
    gg_dbg_put(r->image_a, x, y, px[0]);
    gg_dbg_put(r->image_b, x, y, px[1]);
    r->map[(size_t)y * r->width + x] = (unsigned char)(td ? 2 : vd ? 1 : 0);
    if (!vd && !td) return 0;
    p.x = x, p.y = y, p.a = px[0], p.b = px[1];
    p.delta = vd ? delta(px[0], px[1]) : 0;
    th->value_differ += vd, th->tree_differ += td;
    if (td) th->by_kind[p.first.what]++;
    if (p.delta > th->max_delta) th->max_delta = p.delta;
    keep_worst(th->worst, &th->n, dj->limit, &p);
    return 0;
}

static int by_row(const void *a, const void *b)
{
    const ggDiffMove *p = a, *q = b;
    return p->y != q->y ? (p->y < q->y ? -1 : 1) : p->x < q->x ? -1 : p->x > q->x;
}

/* The workers' moved pixels into the result: the first moves_limit in
   row order (each worker's are its first, in row order). */
static int merge_moves(diff_job *dj, int threads)
{
    ggDiffResult *r = dj->res;
    int i, k, total = 0;
    for (i = 0; i < threads; i++) total += dj->t[i].nmoves, r->moved += dj->t[i].moved;
    if (total == 0) return GG_OK;
    if (!(r->moves = gg_mem_calloc(dj->alloc, (size_t)total, sizeof *r->moves)))
        return GG_ERROR_NOMEM;
    for (i = 0, k = 0; i < threads; i++) {
        if (dj->t[i].nmoves == 0) continue;
        memcpy(r->moves + k, dj->t[i].moves, (size_t)dj->t[i].nmoves * sizeof *r->moves);
        k += dj->t[i].nmoves;
    }
    qsort(r->moves, (size_t)total, sizeof *r->moves, by_row);
    r->nmoves = total < dj->moves_limit ? total : dj->moves_limit;
    return GG_OK;
}

static void merge(diff_job *dj, int threads)
{
    ggDiffResult *r = dj->res;
    int i, k, c;
    for (i = 0; i < threads; i++) {
        const diff_thread *th = &dj->t[i];
        r->value_differ += th->value_differ, r->tree_differ += th->tree_differ;
        for (c = 0; c < GG_DIFF_COUNT; c++) r->first_by_kind[c] += th->by_kind[c];
        if (th->max_delta > r->max_delta) r->max_delta = th->max_delta;
        for (k = 0; k < th->n; k++) keep_worst(r->worst, &r->nworst, dj->limit, &th->worst[k]);
    }
}

GG_API void ggDiffResultFree(ggDiffResult *r)
{
    const ggAllocator *a;
    if (!r) return;
    a = ((diff_res *)r)->al.a;
    gg_mem_free(a, r->worst);
    gg_mem_free(a, r->moves);
    gg_mem_free(a, r->map);
    ggImageFree(r->image_a);
    ggImageFree(r->image_b);
    gg_mem_free(a, r);
}

static int diff_alloc(ggScene *s, const gg_scan *sc, diff_job *dj, ggDiffResult **out)
{
    diff_res *dr = gg_mem_calloc(s->alloc, 1, sizeof *dr);
    ggDiffResult *r;
    size_t lim, pixels = (size_t)sc->desc.width * (size_t)sc->desc.height;
    int i;
    /* No more can be listed than there are pixels: a worst of INT_MAX
       must not ask for INT_MAX entries per thread. */
    if ((size_t)dj->limit > pixels) dj->limit = (int)pixels;
    lim = dj->limit > 0 ? (size_t)dj->limit : 1;
    if (!dr) return GG_ERROR_NOMEM;
    gg_dbg_alloc_init(&dr->al, s->alloc);
    r = *out = &dr->pub;
    dj->res = r, dj->alloc = dr->al.a;
    r->width = sc->desc.width, r->height = sc->desc.height;
    r->x0 = sc->desc.x0, r->y0 = sc->desc.y0, r->x1 = sc->desc.x1, r->y1 = sc->desc.y1;
    r->map = gg_mem_calloc(dj->alloc, (size_t)r->width * (size_t)r->height, 1);
    r->worst = gg_mem_calloc(dj->alloc, lim, sizeof *r->worst);
    r->image_a = ggImageCreate(r->width, r->height, dj->alloc);
    r->image_b = ggImageCreate(r->width, r->height, dj->alloc);
    dj->t = gg_mem_calloc(dj->alloc, (size_t)sc->threads, sizeof *dj->t);
    if (!r->map || !r->worst || !r->image_a || !r->image_b || !dj->t) return GG_ERROR_NOMEM;
    for (i = 0; i < sc->threads; i++)
        if (!(dj->t[i].worst = gg_mem_calloc(dj->alloc, lim, sizeof *dj->t[i].worst)))
            return GG_ERROR_NOMEM;
    return GG_OK;
}

static int diff_setup(ggScene *sa, const ggRenderOptions *oa, ggScene *sb,
                      const ggRenderOptions *ob, gg_tracer **ta, gg_tracer **tb, ggError *err)
{
    gg_tracer_desc da, db;
    int rc;
    if ((rc = gg_tracer_create(sa, oa, ta, err)) != GG_OK) return rc;
    if ((rc = gg_tracer_create(sb, ob, tb, err)) != GG_OK) return rc;
    gg_tracer_info(*ta, &da);
    gg_tracer_info(*tb, &db);
    if (da.width != db.width || da.height != db.height)
        return gg_error_set(err, GG_ERROR_INVALID, "the images differ in size (%dx%d, %dx%d)",
                            da.width, da.height, db.width, db.height);
    return GG_OK;
}

static void diff_job_free(diff_job *dj, int threads)
{
    int i;
    for (i = 0; dj->t && i < threads; i++) {
        gg_mem_free(dj->alloc, dj->t[i].worst);
        gg_mem_free(dj->alloc, dj->t[i].moves);
        gg_mem_free(dj->alloc, dj->t[i].cls[0]);
        gg_mem_free(dj->alloc, dj->t[i].cls[1]);
    }
    gg_mem_free(dj->alloc, dj->t);
}

/* ggDiff and ggDiffPath (dj->path set); dj->limit and moves_limit set. */
static int diff_run(ggScene *sa, const ggRenderOptions *oa, ggScene *sb,
                    const ggRenderOptions *ob, diff_job *dj, ggDiffResult **out, ggError *err)
{
    gg_tracer *ta = NULL, *tb = NULL;
    gg_scan sc;
    ggDiffResult *r = NULL;
    int rc;
    memset(&sc, 0, sizeof sc);
    if ((rc = diff_setup(sa, oa, sb, ob, &ta, &tb, err)) == GG_OK) {
        sc.tracer[0] = ta, sc.tracer[1] = tb, sc.ntracers = 2, sc.record = 1;
        gg_scan_init(&sc);
        if ((rc = diff_alloc(sa, &sc, dj, &r)) != GG_OK)
            rc = gg_error_set(err, rc, "out of memory for the diff result");
    }
    if (rc == GG_OK) {
        sc.fn = diff_pixel, sc.ud = dj, sc.alloc = dj->alloc;
        if ((rc = gg_scan_run(&sc, err)) == GG_OK) {
            r->stats_a = sc.stats[0], r->stats_b = sc.stats[1];
            r->scanned = (long)(r->x1 - r->x0) * (r->y1 - r->y0);
            merge(dj, sc.threads);
            r->by_path = dj->path != NULL;
            if (dj->path && merge_moves(dj, sc.threads) != GG_OK)
                rc = gg_error_set(err, GG_ERROR_NOMEM, "out of memory for the diff result");
        }
    }
    diff_job_free(dj, sc.threads);
    gg_tracer_free(ta);
    gg_tracer_free(tb);
    if (rc != GG_OK) {
        ggDiffResultFree(r);
        return rc;
    }
    *out = r;
    return GG_OK;
}

GG_API int ggDiff(ggScene *sa, const ggRenderOptions *oa, ggScene *sb, const ggRenderOptions *ob,
                  int worst, ggDiffResult **out, ggError *err)
{
    diff_job dj;
    if (!sa || !sb || !out) return gg_error_set(err, GG_ERROR_INVALID, "ggDiff: NULL argument");
    *out = NULL; /* after the NULL checks: base.h rule 1 */
    if (worst < 0) return gg_error_set(err, GG_ERROR_INVALID, "ggDiff: negative count");
    memset(&dj, 0, sizeof dj);
    dj.limit = worst;
    return diff_run(sa, oa, sb, ob, &dj, out, err);
}

GG_API int ggDiffPath(ggScene *sa, const ggRenderOptions *oa, ggScene *sb,
                      const ggRenderOptions *ob, const ggPathExpr *expr, int worst, int limit,
                      ggDiffResult **out, ggError *err)
{
    diff_job dj;
    if (!sa || !sb || !expr || !out)
        return gg_error_set(err, GG_ERROR_INVALID, "ggDiffPath: NULL argument");
    *out = NULL; /* after the NULL checks: base.h rule 1 */
    if (worst < 0 || limit < 0)
        return gg_error_set(err, GG_ERROR_INVALID, "ggDiffPath: negative count");
    memset(&dj, 0, sizeof dj);
    dj.limit = worst, dj.path = expr, dj.moves_limit = limit;
    return diff_run(sa, oa, sb, ob, &dj, out, err);
}
