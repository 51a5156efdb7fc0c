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
} diff_thread;

typedef struct diff_job {
    ggDiffResult *res;
    diff_thread *t;
    int limit;
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

static int diff_pixel(void *ud, int thread, int x, int y, ggTrace *const *recs, const ggColor *px,
                      int same)
{
    diff_job *dj = ud;
    diff_thread *th = &dj->t[thread];
    ggDiffResult *r = dj->res;
    ggDiffPixel p;
    int vd = bits_differ(px[0], px[1]), td;
    (void)same;
    memset(&p, 0, sizeof p);
    td = ggTraceCompare(recs[0], recs[1], &p.first);
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
    gg_mem_free(a, r->map);
    ggImageFree(r->image_a);
    ggImageFree(r->image_b);
    gg_mem_free(a, r);
}

static int diff_alloc(ggScene *s, const gg_scan *sc, diff_job *dj, ggDiffResult **out)
{
    diff_res *dr = gg_mem_calloc(s->alloc, 1, sizeof *dr);
    ggDiffResult *r;
    size_t lim = dj->limit > 0 ? (size_t)dj->limit : 1;
    int i;
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

GG_API int ggDiff(ggScene *sa, const ggRenderOptions *oa, ggScene *sb, const ggRenderOptions *ob,
                  int worst, ggDiffResult **out, ggError *err)
{
    gg_tracer *ta = NULL, *tb = NULL;
    gg_scan sc;
    diff_job dj;
    ggDiffResult *r = NULL;
    int rc, i;
    if (out) *out = NULL;
    if (!sa || !sb || !out || worst < 0)
        return gg_error_set(err, GG_ERROR_INVALID, "ggDiff: NULL argument or negative count");
    memset(&sc, 0, sizeof sc);
    memset(&dj, 0, sizeof dj);
    if ((rc = diff_setup(sa, oa, sb, ob, &ta, &tb, err)) == GG_OK) {
        sc.tracer[0] = ta, sc.tracer[1] = tb, sc.ntracers = 2, sc.record = 1;
        gg_scan_init(&sc);
        dj.limit = worst;
        if ((rc = diff_alloc(sa, &sc, &dj, &r)) != GG_OK)
            rc = gg_error_set(err, rc, "out of memory for the diff result");
    }
    if (rc == GG_OK) {
        sc.fn = diff_pixel, sc.ud = &dj, sc.alloc = dj.alloc;
        if ((rc = gg_scan_run(&sc, err)) == GG_OK) {
            r->stats_a = sc.stats[0], r->stats_b = sc.stats[1];
            r->scanned = (long)(r->x1 - r->x0) * (r->y1 - r->y0);
            merge(&dj, sc.threads);
        }
    }
    for (i = 0; dj.t && i < sc.threads; i++) gg_mem_free(dj.alloc, dj.t[i].worst);
    gg_mem_free(dj.alloc, dj.t);
    gg_tracer_free(ta);
    gg_tracer_free(tb);
    if (rc != GG_OK) {
        ggDiffResultFree(r);
        return rc;
    }
    *out = r;
    return GG_OK;
}
