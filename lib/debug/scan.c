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

static int scan_row(shared *sh, int thread, int y, ggTrace *const *recs, ggRayStats *st)
{
    gg_scan *sc = sh->sc;
    ggColor px[2];
    int x, i, rc;
    for (x = sc->desc.x0; x < sc->desc.x1; x++) {
        for (i = 0; i < sc->ntracers; i++) {
            px[i] = gg_tracer_pixel(sc->tracer[i], x, y, recs ? recs[i] : NULL, &st[i]);
            if (recs && gg_tracer_status(recs[i]) != GG_OK) return GG_ERROR_NOMEM;
        }
        if ((rc = sc->fn(sc->ud, thread, x, y, recs, px)) != 0) return rc;
    }
    return GG_OK;
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
    for (i = 0; i < sc->ntracers; i++) gg_dbg_stats_add(&sc->stats[i], &st[i]);
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
    for (i = 0; i < sc->threads && i < 256; i++) args[i].sh = &sh, args[i].thread = i;
    for (i = 1; i < sc->threads && i < 256; i++) {
        if (pthread_create(&th[started], NULL, worker, &args[i]) != 0) break;
        started++;
    }
    worker(&args[0]); /* the calling thread works too */
    for (i = 0; i < started; i++) pthread_join(th[i], NULL);
    pthread_mutex_destroy(&sh.mu);
    if (sh.status == GG_ERROR_NOMEM)
        return gg_error_set(err, GG_ERROR_NOMEM, "out of memory recording ray trees");
    if (sh.status == GG_ERROR_CANCELLED)
        return gg_error_set(err, GG_ERROR_CANCELLED, "cancelled by the progress callback");
    if (sh.status != GG_OK) return gg_error_set(err, sh.status, "%s", ggStatusString(sh.status));
    return GG_OK;
}
