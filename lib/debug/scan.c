/* SPDX-License-Identifier: MIT */
/*
** scan.c -- every pixel of a window traced (and recorded) on worker
** threads, handed to a callback: the engine under ggFind, ggCheck and
** ggDiff. Rows are handed out one at a time, so each worker sees its
** pixels in row order; results that keep "the first N" or "the worst N"
** merge the workers' lists into the same answer for any thread count.
*/
#include "debug_int.h"

#include <pthread.h>
#include <string.h>

typedef struct shared {
    gg_scan *sc;
    pthread_mutex_t mu;
    int next_row;
    long done, total, reported;
    int status; /* first failure */
} shared;

typedef struct worker_arg {
    shared *sh;
    int thread;
} worker_arg;

static void fail(shared *sh, int status)
{
    pthread_mutex_lock(&sh->mu);
    if (sh->status == GG_OK) sh->status = status;
    pthread_mutex_unlock(&sh->mu);
}

/* Take the next row; -1 when done or stopped. Reports progress. */
static int take_row(shared *sh, long finished)
{
    gg_scan *sc = sh->sc;
    int row = -1;
    pthread_mutex_lock(&sh->mu);
    sh->done += finished;
    if (sc->desc.progress && finished > 0 &&
        (sh->done - sh->reported >= sh->total / 200 || sh->done == sh->total)) {
        sh->reported = sh->done;
        if (sc->desc.progress(sc->desc.progress_ud, sh->done, sh->total) && sh->status == GG_OK)
            sh->status = GG_ERROR_CANCELLED;
    }
    if (sh->status == GG_OK && sc->desc.y0 + sh->next_row < sc->desc.y1)
        row = sc->desc.y0 + sh->next_row++;
    pthread_mutex_unlock(&sh->mu);
    return row;
}

/* Pixels are traced in spans of SPAN along a row. A span inside a tile
   whose eye rays all miss (gg_tracer_empty on every tracer, tested once
   per SPAN x SPAN tile before the scan) is traced at its first pixel
   only, and that pixel's trees and value serve the others: they differ
   from what tracing each would record in the rays' origins and
   directions only, which nothing in this layer reads (the predicate
   language, the checks and the tree comparison look at what was hit) --
   but for the traversal cost (nodes, prims), which differs from ray to
   ray: a scan for a predicate that reads it sets every_pixel. */
#define SPAN 16

static int scan_row(shared *sh, int thread, int y, ggTrace *const *recs, ggRayStats *st)
{
    gg_scan *sc = sh->sc;
    ggColor px[2];
    ggRayStats one[2];
    const unsigned char *empty =
        sc->empty ? sc->empty + (size_t)((y - sc->desc.y0) / SPAN) * (size_t)sc->tiles_x : NULL;
    int x, xe, i, rc;
    for (x = sc->desc.x0; x < sc->desc.x1; x = xe) {
        int x1 = x + SPAN < sc->desc.x1 ? x + SPAN : sc->desc.x1;
        int reuse = empty && empty[(x - sc->desc.x0) / SPAN];
        for (xe = x; xe < x1; xe++) {
            if (!reuse || xe == x) {
                for (i = 0; i < sc->ntracers; i++) {
                    memset(&one[i], 0, sizeof one[i]);
                    px[i] = gg_tracer_pixel(sc->tracer[i], xe, y, recs ? recs[i] : NULL, &one[i]);
                    if (recs && gg_tracer_status(recs[i]) != GG_OK) return GG_ERROR_NOMEM;
                }
            }
            for (i = 0; i < sc->ntracers; i++) ggRayStatsAdd(&st[i], &one[i]);
            if ((rc = sc->fn(sc->ud, thread, xe, y, recs, px, reuse && xe != x)) != 0) return rc;
        }
    }
    return GG_OK;
}

/* Which tiles are empty on every tracer (sc->empty; NULL if no memory:
   then every pixel is traced). */
static void find_empty_tiles(gg_scan *sc)
{
    int tx, ty, i, w = sc->desc.x1 - sc->desc.x0, h = sc->desc.y1 - sc->desc.y0;
    sc->tiles_x = (w + SPAN - 1) / SPAN;
    sc->empty = gg_mem_calloc(sc->alloc, (size_t)sc->tiles_x * (size_t)((h + SPAN - 1) / SPAN), 1);
    for (ty = 0; sc->empty && ty * SPAN < h; ty++)
        for (tx = 0; tx * SPAN < w; tx++) {
            int x0 = sc->desc.x0 + tx * SPAN, y0 = sc->desc.y0 + ty * SPAN, e = 1;
            int x1 = x0 + SPAN < sc->desc.x1 ? x0 + SPAN : sc->desc.x1;
            int y1 = y0 + SPAN < sc->desc.y1 ? y0 + SPAN : sc->desc.y1;
            for (i = 0; i < sc->ntracers && e; i++)
                e = gg_tracer_empty(sc->tracer[i], x0, y0, x1, y1);
            sc->empty[(size_t)ty * sc->tiles_x + tx] = (unsigned char)e;
        }
}

static void *worker(void *arg)
{
    worker_arg *wa = arg;
    shared *sh = wa->sh;
    gg_scan *sc = sh->sc;
    ggTrace *recs[2] = {NULL, NULL};
    ggRayStats st[2];
    int i, y, rc = GG_OK;
    long finished = 0;
    memset(st, 0, sizeof st);
    for (i = 0; sc->record && i < sc->ntracers; i++)
        if (!(recs[i] = ggTraceCreate(sc->alloc))) rc = GG_ERROR_NOMEM;
    while (rc == GG_OK && (y = take_row(sh, finished)) >= 0) {
        rc = scan_row(sh, wa->thread, y, sc->record ? recs : NULL, st);
        finished = sc->desc.x1 - sc->desc.x0;
    }
    if (rc != GG_OK) fail(sh, rc);
    for (i = 0; i < sc->ntracers; i++) ggTraceFree(recs[i]);
    pthread_mutex_lock(&sh->mu);
    for (i = 0; i < sc->ntracers; i++) ggRayStatsAdd(&sc->stats[i], &st[i]);
    pthread_mutex_unlock(&sh->mu);
    return NULL;
}

void gg_scan_init(gg_scan *sc)
{
    int rows;
    gg_tracer_info(sc->tracer[0], &sc->desc);
    rows = sc->desc.y1 - sc->desc.y0;
    sc->threads = sc->desc.threads < rows ? sc->desc.threads : rows;
    if (sc->threads < 1) sc->threads = 1;
    memset(sc->stats, 0, sizeof sc->stats);
}

int gg_scan_run(gg_scan *sc, ggError *err)
{
    shared sh;
    worker_arg args[256];
    pthread_t th[256];
    int i, started = 0;
    memset(&sh, 0, sizeof sh);
    sh.sc = sc;
    sh.total = (long)(sc->desc.x1 - sc->desc.x0) * (sc->desc.y1 - sc->desc.y0);
    sh.status = GG_OK;
    if (pthread_mutex_init(&sh.mu, NULL) != 0)
        return gg_error_set(err, GG_ERROR_NOMEM, "cannot create a mutex");
    if (!sc->every_pixel) find_empty_tiles(sc);
    for (i = 0; i < sc->threads && i < 256; i++) args[i].sh = &sh, args[i].thread = i;
    for (i = 1; i < sc->threads && i < 256; i++) {
        if (pthread_create(&th[started], NULL, worker, &args[i]) != 0) break;
        started++;
    }
    worker(&args[0]); /* the calling thread works too */
    for (i = 0; i < started; i++) pthread_join(th[i], NULL);
    pthread_mutex_destroy(&sh.mu);
    gg_mem_free(sc->alloc, sc->empty);
    sc->empty = NULL;
    if (sh.status == GG_ERROR_NOMEM)
        return gg_error_set(err, GG_ERROR_NOMEM, "out of memory recording ray trees");
    if (sh.status == GG_ERROR_CANCELLED)
        return gg_error_set(err, GG_ERROR_CANCELLED, "cancelled by the progress callback");
    if (sh.status != GG_OK) return gg_error_set(err, sh.status, "%s", ggStatusString(sh.status));
    return GG_OK;
}
