/* SPDX-License-Identifier: MIT */
/*
** serve_debug.c -- `ggrt serve`'s find, check and diff jobs band by band:
** each band is one call of ggFind (ggFindPath), ggCheck or ggDiff (include/ggrt/debug.h)
** on a crop window of rows, merged into the result one call over the whole
** image gives. Counts add; matches come in row order; the worst pixels
** are kept with the library's own order (lib/debug/check.c and diff.c:
** larger measure first, then row order), which is a total order, so the
** merged lists are the ones a single call lists.
*/
#if defined(GG_HAVE_MHD)
#include "serve/serve.h"

#include <stdlib.h>
#include <string.h>

/* Rows [y0, y1) of a w-wide array of `each` bytes a pixel. */
static void copy_rows(void *dst, const void *src, int w, int y0, int y1, size_t each)
{
    size_t row = (size_t)w * each;
    memcpy((char *)dst + (size_t)y0 * row, (const char *)src + (size_t)y0 * row,
           (size_t)(y1 - y0) * row);
}

/* ---- find ---- */

static int band_find(srv_server *s, srv_result *r, const ggRenderOptions *o, int y0, int y1,
                     ggError *err)
{
    ggFindResult *b = NULL, *m = &r->find;
    int left = r->spec.limit - m->nmatches, i, rc;
    if (!m->mask) {
        m->mask = calloc((size_t)r->width * r->height, 1);
        m->matches = r->spec.limit > 0 ? calloc((size_t)r->spec.limit, sizeof *m->matches) : NULL;
        if (!m->mask || (r->spec.limit > 0 && !m->matches)) {
            snprintf(err->message, sizeof err->message, "out of memory for a find");
            return GG_ERROR_NOMEM;
        }
    }
    /* With a path every match of the band is listed: the share map needs them all. */
    rc = r->lpe ? ggFindPath(s->scene, o, r->lpe, r->width * (y1 - y0), &b, err)
                : ggFind(s->scene, o, r->pred, left, &b, err);
    if (rc != GG_OK) return rc;
    m->scanned += b->scanned, m->matched += b->matched;
    for (i = 0; r->lpe && i < b->nmatches; i++)
        r->share[(size_t)b->matches[i].y * r->width + b->matches[i].x] = (float)b->matches[i].share;
    for (i = 0; i < b->nmatches && m->nmatches < r->spec.limit; i++)
        m->matches[m->nmatches++] = b->matches[i];
    copy_rows(m->mask, b->mask, r->width, y0, y1, 1);
    m->traced |= b->traced;
    ggRayStatsAdd(&m->stats, &b->stats);
    ggRayStatsAdd(&r->stats, &b->stats);
    ggFindResultFree(b);
    return GG_OK;
}

/* ---- check ---- */

/* lib/debug/check.c's order of the worst pixels. */
static int check_worse(const ggCheckPixel *p, const ggCheckPixel *q)
{
    if (p->value != q->value) return p->value > q->value;
    if (p->y != q->y) return p->y < q->y;
    return p->x < q->x;
}

static void check_keep(ggCheckItem *it, const ggCheckPixel *p)
{
    int i;
    if (it->nworst == GG_CHECK_WORST && !check_worse(p, &it->pixels_worst[GG_CHECK_WORST - 1]))
        return;
    i = it->nworst < GG_CHECK_WORST ? it->nworst++ : GG_CHECK_WORST - 1;
    while (i > 0 && check_worse(p, &it->pixels_worst[i - 1])) {
        it->pixels_worst[i] = it->pixels_worst[i - 1];
        i--;
    }
    it->pixels_worst[i] = *p;
}

static int band_check(srv_server *s, srv_result *r, const ggRenderOptions *o, ggError *err)
{
    ggCheckResult *b = NULL, *m = &r->check;
    int c, k, rc = ggCheck(s->scene, o, NULL, &b, err);
    long n;
    if (rc != GG_OK) return rc;
    n = m->checked + b->checked;
    m->scanned += b->scanned;
    /* checked and share as one ggCheck over the whole image gives them
       (share: the mean over the checked pixels, 0 without a path) */
    if (n > 0) m->share = (m->share * (double)m->checked + b->share * (double)b->checked) / (double)n;
    m->checked = n;
    m->radiance_bound = b->radiance_bound; /* the scene's, the same in every band */
    for (c = 0; c < GG_CHECK_COUNT; c++) {
        ggCheckItem *it = &m->items[c];
        const ggCheckItem *bi = &b->items[c];
        it->check = bi->check, it->severity = bi->severity;
        it->pixels += bi->pixels, it->rays += bi->rays;
        if (bi->worst > it->worst) it->worst = bi->worst;
        for (k = 0; k < bi->nworst; k++) check_keep(it, &bi->pixels_worst[k]);
    }
    ggRayStatsAdd(&m->stats, &b->stats);
    ggRayStatsAdd(&r->stats, &b->stats);
    ggCheckResultFree(b);
    return GG_OK;
}

/* ---- diff ---- */

/* lib/debug/diff.c's order of the worst pixels. */
static int diff_worse(const ggDiffPixel *p, const ggDiffPixel *q)
{
    if (p->delta != q->delta) return p->delta > q->delta;
    if ((p->first.what != GG_DIFF_SAME) != (q->first.what != GG_DIFF_SAME))
        return p->first.what != GG_DIFF_SAME;
    if (p->y != q->y) return p->y < q->y;
    return p->x < q->x;
}

static void diff_keep(ggDiffResult *m, int limit, const ggDiffPixel *p)
{
    int i;
    if (limit <= 0 || (m->nworst == limit && !diff_worse(p, &m->worst[m->nworst - 1]))) return;
    i = m->nworst < limit ? m->nworst++ : m->nworst - 1;
    while (i > 0 && diff_worse(p, &m->worst[i - 1])) {
        m->worst[i] = m->worst[i - 1];
        i--;
    }
    m->worst[i] = *p;
}

static int band_diff(srv_server *s, srv_result *r, const ggRenderOptions *o,
                     const ggRenderOptions *ob, int y0, int y1, ggError *err)
{
    ggDiffResult *b = NULL, *m = &r->diff;
    int i, rc;
    if (!m->map) {
        m->map = calloc((size_t)r->width * r->height, 1);
        m->worst = r->spec.limit > 0 ? calloc((size_t)r->spec.limit, sizeof *m->worst) : NULL;
        if (!m->map || (r->spec.limit > 0 && !m->worst)) {
            snprintf(err->message, sizeof err->message, "out of memory for a diff");
            return GG_ERROR_NOMEM;
        }
    }
    rc = ggDiff(s->scene, o, s->scene, ob, r->spec.limit, &b, err);
    if (rc != GG_OK) return rc;
    m->scanned += b->scanned;
    m->value_differ += b->value_differ, m->tree_differ += b->tree_differ;
    for (i = 0; i < GG_DIFF_COUNT; i++) m->first_by_kind[i] += b->first_by_kind[i];
    if (b->max_delta > m->max_delta) m->max_delta = b->max_delta;
    for (i = 0; i < b->nworst; i++) diff_keep(m, r->spec.limit, &b->worst[i]);
    copy_rows(m->map, b->map, r->width, y0, y1, 1);
    copy_rows(r->px, ggImagePixelsConst(b->image_a), r->width, y0, y1, 3 * sizeof(float));
    copy_rows(r->px_b, ggImagePixelsConst(b->image_b), r->width, y0, y1, 3 * sizeof(float));
    ggRayStatsAdd(&m->stats_a, &b->stats_a);
    ggRayStatsAdd(&m->stats_b, &b->stats_b);
    ggRayStatsAdd(&r->stats, &b->stats_a);
    ggDiffResultFree(b);
    return GG_OK;
}

int srv_band_debug(srv_server *s, srv_result *r, const ggRenderOptions *o,
                   const ggRenderOptions *ob, int y0, int y1, ggError *err)
{
    switch (r->spec.type) {
    case SRV_TYPE_FIND:
        return band_find(s, r, o, y0, y1, err);
    case SRV_TYPE_CHECK:
        return band_check(s, r, o, err);
    default:
        return band_diff(s, r, o, ob, y0, y1, err);
    }
}

void srv_debug_finish(srv_result *r)
{
    int c;
    ggFindResult *f = &r->find;
    ggCheckResult *k = &r->check;
    ggDiffResult *d = &r->diff;
    f->width = k->width = d->width = r->width;
    f->height = k->height = d->height = r->height;
    f->x0 = k->x0 = d->x0 = 0, f->y0 = k->y0 = d->y0 = 0;
    f->x1 = k->x1 = d->x1 = r->width, f->y1 = k->y1 = d->y1 = r->height;
    k->failed = 0;
    for (c = 0; c < GG_CHECK_COUNT; c++)
        if (k->items[c].severity == GG_SEVERITY_ERROR && k->items[c].pixels > 0) k->failed++;
}

void srv_result_free(srv_result *r)
{
    free(r->where), free(r->px), free(r->px_b), free(r->cost), free(r->share);
    free(r->find.mask), free(r->find.matches);
    free(r->diff.map), free(r->diff.worst);
    ggPredicateFree(r->pred), ggPathFree(r->lpe);
    r->where = NULL, r->px = r->px_b = r->cost = r->share = NULL;
    r->find.mask = NULL, r->find.matches = NULL;
    r->diff.map = NULL, r->diff.worst = NULL;
    r->pred = NULL, r->lpe = NULL;
}

#else
typedef int serve_debug_unused;
#endif
