/* SPDX-License-Identifier: MIT */
/*
** serve_jobs.c -- `ggrt serve`'s long work: a small cache of jobs (a
** render, a find, a check, a diff), each named by its options, done in
** order by one worker thread.
**
** A job runs as a sequence of bands of rows (crop windows: ggRender
** promises their pixels equal the full render's, and ggFind, ggCheck and
** ggDiff scan the options' crop window). Trace requests run beside the
** bands on the same prepared scene, which nothing writes (scene.h,
** "Threads"); the bands give the progress and the points where a job can
** be cancelled (shutdown, time limit, /api/cancel).
*/
#if defined(GG_HAVE_MHD)
#include "serve/serve.h"

#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define KEYLEN       2048
#define BAND_SECONDS 0.05      /* aim of one band: frequent progress and cancel points */
#define BAND_PIXELS  (1 << 16) /* and at most this many pixels */

typedef struct job {
    int used, readers;
    unsigned long stamp, queued; /* last use (eviction), queue order */
    char key[KEYLEN];
    int state;
    long done, total;
    double t0, seconds;
    double cancel_at; /* when /api/cancel asked (0: not asked, or asked for again since) */
    int abandoned;    /* stopped for that: forgotten, not failed */
    char error[512];
    srv_result res;
} job;

struct srv_jobs {
    pthread_mutex_t mu;
    pthread_cond_t cv;
    pthread_t thread;
    int started, quit;
    unsigned long clock;
    job jobs[SRV_MAX_JOBS];
};

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct band_ctx {
    srv_server *s;
    job *j;
    long before; /* pixels of earlier bands */
    long band;   /* pixels of this band */
} band_ctx;

/* Was job j asked to be cancelled, and not asked for since, for the
   grace period? (Under the lock.) */
static int cancel_due(const job *j, double t)
{
    return j->cancel_at > 0 && t - j->cancel_at >= SRV_CANCEL_GRACE;
}

/* The progress callback of every band: publish the progress, and stop on
   shutdown, past the time limit, or when cancelled (/api/cancel). */
static int band_progress(void *ud, long done, long total)
{
    band_ctx *b = ud;
    struct srv_jobs *J = b->s->jobs;
    double t = now();
    int stop = t - b->j->t0 > b->s->cfg.job_seconds;
    pthread_mutex_lock(&J->mu);
    b->j->done = b->before + (total > 0 ? (long)((double)b->band * done / total) : 0);
    if (cancel_due(b->j, t)) stop = b->j->abandoned = 1;
    stop |= J->quit;
    pthread_mutex_unlock(&J->mu);
    return stop;
}

/* One band of a render: ggRender of the crop window, its rows copied. */
static int band_render(srv_server *s, srv_result *r, const ggRenderOptions *o, int y0, int y1,
                       ggError *err)
{
    ggImage *img = NULL;
    ggRayStats st;
    int rc;
    memset(&st, 0, sizeof st);
    rc = ggRender(s->scene, o, &img, &st, err);
    if (rc == GG_OK) {
        size_t row = (size_t)r->width * 3;
        memcpy(r->px + (size_t)y0 * row, ggImagePixelsConst(img) + (size_t)y0 * row,
               (size_t)(y1 - y0) * row * sizeof(float));
        ggRayStatsAdd(&r->stats, &st);
    }
    ggImageFree(img);
    return rc;
}

/* The band's options: the job's, on rows [y, y + rows), reporting to b. */
static void band_options(const ggRenderOptions *in, ggRenderOptions *o, const srv_result *r, int y,
                         int rows, band_ctx *b)
{
    *o = *in;
    o->width = r->width, o->height = r->height;
    o->crop_x0 = 0, o->crop_x1 = r->width, o->crop_y0 = y, o->crop_y1 = y + rows;
    o->cost_map = r->spec.type == SRV_TYPE_RENDER && r->spec.kind >= 0 ? r->cost : NULL;
    o->cost_kind = r->spec.kind >= 0 ? r->spec.kind : 0;
    o->progress = band_progress, o->progress_ud = b;
}

/* Run job j band by band; GG_OK or the status with err filled. */
static int run_bands(srv_server *s, job *j, ggError *err)
{
    srv_result *r = &j->res;
    int w = r->width, h = r->height, y = 0, rows = 16, rc = GG_OK;
    band_ctx b;
    b.s = s, b.j = j, b.before = 0;
    /* With rays through the pixel corners, a band [y0, y1) shades corner
       rows y0 to y1: two bands would both shade (and count) the row they
       share. One band then, its progress callback still reporting and
       cancelling, so that the stats are ggrt render's. */
    if (r->spec.opt.pixel_corners || r->spec.opt_b.pixel_corners) rows = h;
    while (y < h && rc == GG_OK) {
        ggRenderOptions o, ob;
        double t;
        if (rows > h - y) rows = h - y;
        band_options(&r->spec.opt, &o, r, y, rows, &b);
        band_options(&r->spec.opt_b, &ob, r, y, rows, &b);
        b.band = (long)rows * w;
        t = now();
        if (r->spec.type == SRV_TYPE_RENDER)
            rc = band_render(s, r, &o, y, y + rows, err);
        else
            rc = srv_band_debug(s, r, &o, &ob, y, y + rows, err);
        t = now() - t;
        y += rows;
        b.before += (long)rows * w;
        /* Next band: about BAND_SECONDS of work in whole tiles of 16 rows,
           growing at most twice (the sky above a scene is cheap, what
           follows may not be) and at most BAND_PIXELS. */
        {
            double want = t > 0 ? rows * BAND_SECONDS / t : 2.0 * rows;
            if (want > 2.0 * rows) want = 2.0 * rows;
            if (want * w > BAND_PIXELS) want = (double)BAND_PIXELS / w;
            rows = want < 16 ? 16 : (int)want / 16 * 16;
        }
    }
    if (rc == GG_OK && r->spec.type != SRV_TYPE_RENDER) srv_debug_finish(r);
    if (rc == GG_ERROR_CANCELLED && now() - j->t0 > s->cfg.job_seconds)
        snprintf(err->message, sizeof err->message,
                 "cancelled: still running after %d s (docs/serve.md, limits)", s->cfg.job_seconds);
    return rc;
}

/* The arrays a job fills, and its predicate. */
static int job_alloc(srv_server *s, srv_result *r, ggError *err)
{
    size_t n = (size_t)r->width * (size_t)r->height;
    int t = r->spec.type;
    r->px = t == SRV_TYPE_RENDER || t == SRV_TYPE_DIFF ? calloc(n * 3, sizeof *r->px) : NULL;
    r->px_b = t == SRV_TYPE_DIFF ? calloc(n * 3, sizeof *r->px_b) : NULL;
    r->cost = t == SRV_TYPE_RENDER && r->spec.kind >= 0 ? calloc(n, sizeof *r->cost) : NULL;
    if (((t == SRV_TYPE_RENDER || t == SRV_TYPE_DIFF) && !r->px) || (t == SRV_TYPE_DIFF && !r->px_b) ||
        (t == SRV_TYPE_RENDER && r->spec.kind >= 0 && !r->cost)) {
        snprintf(err->message, sizeof err->message, "out of memory for a %dx%d job", r->width,
                 r->height);
        return GG_ERROR_NOMEM;
    }
    if (t == SRV_TYPE_FIND && r->spec.lpe) {
        if (!(r->share = calloc(n, sizeof *r->share))) {
            snprintf(err->message, sizeof err->message, "out of memory for a %dx%d job", r->width,
                     r->height);
            return GG_ERROR_NOMEM;
        }
        return ggPathParse(r->where, NULL, &r->lpe, err);
    }
    if (t == SRV_TYPE_FIND) return ggPredicateParse(r->where, NULL, &r->pred, err);
    (void)s;
    return GG_OK;
}

static void run_job(srv_server *s, job *j)
{
    struct srv_jobs *J = s->jobs;
    ggError err;
    int rc;
    err.message[0] = '\0';
    pthread_mutex_lock(&J->mu);
    j->state = SRV_STATE_RUNNING;
    j->t0 = now();
    j->done = 0, j->total = (long)j->res.width * j->res.height;
    pthread_mutex_unlock(&J->mu);
    rc = job_alloc(s, &j->res, &err);
    if (rc == GG_OK) rc = run_bands(s, j, &err);
    ggPredicateFree(j->res.pred), ggPathFree(j->res.lpe);
    j->res.pred = NULL, j->res.lpe = NULL;
    pthread_mutex_lock(&J->mu);
    j->seconds = now() - j->t0;
    if (rc != GG_OK && j->abandoned) {
        /* cancelled: forgotten (a request for it later starts it again) */
        srv_result_free(&j->res);
        memset(j, 0, sizeof *j);
    } else if (rc == GG_OK) {
        j->state = SRV_STATE_DONE;
        j->done = j->total;
    } else {
        j->state = SRV_STATE_FAILED;
        snprintf(j->error, sizeof j->error, "%s", err.message);
        srv_result_free(&j->res);
    }
    pthread_mutex_unlock(&J->mu);
}

/* Forget a queued job that was cancelled (under the lock). */
static void drop_queued(job *j)
{
    srv_result_free(&j->res);
    memset(j, 0, sizeof *j);
}

/* The next job to run: the oldest queued one, those not asked to be
   cancelled first; one cancelled past its grace is forgotten. */
static job *next_queued(struct srv_jobs *J)
{
    job *best = NULL;
    double t = now();
    int i;
    for (i = 0; i < SRV_MAX_JOBS; i++) {
        job *j = &J->jobs[i];
        if (!j->used || j->state != SRV_STATE_QUEUED) continue;
        if (cancel_due(j, t)) {
            drop_queued(j);
            continue;
        }
        if (!best || (j->cancel_at > 0) < (best->cancel_at > 0) ||
            ((j->cancel_at > 0) == (best->cancel_at > 0) && j->queued < best->queued))
            best = j;
    }
    return best;
}

static void *worker(void *arg)
{
    srv_server *s = arg;
    struct srv_jobs *J = s->jobs;
    for (;;) {
        job *j = NULL;
        int quit;
        pthread_mutex_lock(&J->mu);
        while (!J->quit && !(j = next_queued(J))) pthread_cond_wait(&J->cv, &J->mu);
        quit = J->quit;
        pthread_mutex_unlock(&J->mu);
        if (quit) return NULL;
        run_job(s, j);
    }
}

int srv_jobs_start(srv_server *s, ggError *err)
{
    struct srv_jobs *J = calloc(1, sizeof *J);
    if (!J || pthread_mutex_init(&J->mu, NULL) != 0) {
        free(J);
        snprintf(err->message, sizeof err->message, "out of memory");
        return GG_ERROR_NOMEM;
    }
    if (pthread_cond_init(&J->cv, NULL) != 0) {
        pthread_mutex_destroy(&J->mu);
        free(J);
        snprintf(err->message, sizeof err->message, "out of memory");
        return GG_ERROR_NOMEM;
    }
    s->jobs = J;
    if (pthread_create(&J->thread, NULL, worker, s) != 0) {
        pthread_cond_destroy(&J->cv);
        pthread_mutex_destroy(&J->mu);
        free(J);
        s->jobs = NULL;
        snprintf(err->message, sizeof err->message, "cannot start the worker thread");
        return GG_ERROR_NOMEM;
    }
    J->started = 1;
    return GG_OK;
}

void srv_jobs_cancel(srv_server *s)
{
    struct srv_jobs *J = s->jobs;
    if (!J) return;
    pthread_mutex_lock(&J->mu);
    J->quit = 1;
    pthread_cond_broadcast(&J->cv);
    pthread_mutex_unlock(&J->mu);
}

void srv_jobs_stop(srv_server *s)
{
    struct srv_jobs *J = s->jobs;
    int i;
    if (!J) return;
    srv_jobs_cancel(s);
    if (J->started) pthread_join(J->thread, NULL);
    for (i = 0; i < SRV_MAX_JOBS; i++) srv_result_free(&J->jobs[i].res);
    pthread_cond_destroy(&J->cv);
    pthread_mutex_destroy(&J->mu);
    free(J);
    s->jobs = NULL;
}

/* What job j computes, for a page to say what a queued job waits for:
   "render", "heatmap of rays", "find WHERE", "find path LPE", "check",
   "diff", with the canonical options of its key. */
static void job_what(const job *j, char *out, size_t len)
{
    static const char *const kinds[] = {"rays", "depth", "time"};
    const srv_job_spec *sp = &j->res.spec;
    const char *opts = strchr(j->key, '|');
    char head[160];
    opts = opts ? opts + 1 : "";
    switch (sp->type) {
    case SRV_TYPE_RENDER:
        if (sp->kind >= 0 && sp->kind <= 2)
            snprintf(head, sizeof head, "heatmap of %s", kinds[sp->kind]);
        else
            snprintf(head, sizeof head, "render");
        break;
    case SRV_TYPE_FIND:
        snprintf(head, sizeof head, "find %s%.100s", sp->lpe ? "path " : "",
                 sp->where ? sp->where : "");
        /* the key goes on with |WHERE after the options */
        break;
    case SRV_TYPE_CHECK:
        snprintf(head, sizeof head, "check");
        break;
    default:
        snprintf(head, sizeof head, "diff");
        break;
    }
    if (sp->type == SRV_TYPE_FIND) {
        const char *e = strchr(opts, '|');
        snprintf(out, len, "%s (options %.*s)", head, e ? (int)(e - opts) : (int)strlen(opts),
                 opts);
    } else {
        snprintf(out, len, "%s (options %s)", head, opts);
    }
}

static void view_of(const struct srv_jobs *J, const job *j, srv_job_view *v)
{
    int i;
    v->id = j->queued;
    v->state = j->state;
    v->ahead = 0;
    v->running[0] = '\0';
    if (j->state == SRV_STATE_QUEUED)
        for (i = 0; i < SRV_MAX_JOBS; i++) {
            const job *o = &J->jobs[i];
            if (!o->used || o == j) continue;
            if (o->state == SRV_STATE_RUNNING) {
                v->ahead++;
                job_what(o, v->running, sizeof v->running);
                v->running_done = o->done, v->running_total = o->total;
            } else if (o->state == SRV_STATE_QUEUED && o->queued < j->queued &&
                       !(o->cancel_at > 0 && j->cancel_at <= 0)) {
                v->ahead++;
            }
        }
    v->done = j->done, v->total = j->total;
    v->seconds = j->state >= SRV_STATE_DONE      ? j->seconds
                 : j->state == SRV_STATE_RUNNING ? now() - j->t0
                                               : 0;
    v->stats = j->res.stats;
    snprintf(v->error, sizeof v->error, "%s", j->error);
}

static job *find(struct srv_jobs *J, const char *key)
{
    int i;
    for (i = 0; i < SRV_MAX_JOBS; i++)
        if (J->jobs[i].used && !strcmp(J->jobs[i].key, key)) return &J->jobs[i];
    return NULL;
}

/* A slot for a new job: a free one, else the least recently used finished
   job nobody reads (its results are freed). NULL when there is none. */
static job *slot(struct srv_jobs *J)
{
    job *lru = NULL;
    int i;
    for (i = 0; i < SRV_MAX_JOBS; i++) {
        job *j = &J->jobs[i];
        if (!j->used) return j;
        if (j->state == SRV_STATE_QUEUED && cancel_due(j, now())) {
            drop_queued(j);
            return j;
        }
        if (j->state >= SRV_STATE_DONE && !j->readers && (!lru || j->stamp < lru->stamp)) lru = j;
    }
    if (lru) {
        srv_result_free(&lru->res);
        memset(lru, 0, sizeof *lru);
    }
    return lru;
}

static int fill_job(srv_server *s, job *j, const char *key, const srv_job_spec *spec)
{
    memset(j, 0, sizeof *j);
    snprintf(j->key, sizeof j->key, "%s", key);
    j->res.spec = *spec;
    j->res.width = s->cfg.width, j->res.height = s->cfg.height;
    if (spec->where && !(j->res.where = strdup(spec->where))) return -1;
    j->res.spec.where = j->res.where;
    j->used = 1;
    j->state = SRV_STATE_QUEUED;
    j->total = (long)s->cfg.width * s->cfg.height;
    return 0;
}

int srv_jobs_request(srv_server *s, const char *key, const srv_job_spec *spec, srv_job_view *view)
{
    struct srv_jobs *J = s->jobs;
    job *j;
    int rc = 0;
    memset(view, 0, sizeof *view);
    if (strlen(key) >= KEYLEN) {
        snprintf(view->error, sizeof view->error, "options too long");
        return -1;
    }
    pthread_mutex_lock(&J->mu);
    if (J->quit) {
        snprintf(view->error, sizeof view->error, "the server is stopping");
        rc = -1;
    } else if (!(j = find(J, key)) && (j = slot(J)) != NULL) {
        if (fill_job(s, j, key, spec)) {
            memset(j, 0, sizeof *j);
            j = NULL;
            snprintf(view->error, sizeof view->error, "out of memory");
            rc = -1;
        } else {
            j->queued = ++J->clock;
            pthread_cond_signal(&J->cv);
        }
    }
    if (!rc && j) {
        j->stamp = ++J->clock;
        j->cancel_at = 0; /* wanted again: a pending cancel is off */
        view_of(J, j, view);
        /* A failure is this request's answer, not the job's for good:
           the slot is freed (run_job freed the results) so that the next
           request runs the job again. */
        if (j->state == SRV_STATE_FAILED) memset(j, 0, sizeof *j);
    } else if (!rc) {
        snprintf(view->error, sizeof view->error,
                 "all %d job slots are queued, running or being read; retry when one is done",
                 SRV_MAX_JOBS);
        rc = -1;
    }
    pthread_mutex_unlock(&J->mu);
    return rc;
}

int srv_jobs_cancel_id(srv_server *s, unsigned long id, srv_job_view *view)
{
    struct srv_jobs *J = s->jobs;
    int i, rc = -1;
    memset(view, 0, sizeof *view);
    pthread_mutex_lock(&J->mu);
    for (i = 0; i < SRV_MAX_JOBS && id; i++) {
        job *j = &J->jobs[i];
        if (!j->used || j->queued != id) continue;
        view_of(J, j, view);
        if (j->state < SRV_STATE_DONE && !(j->cancel_at > 0)) j->cancel_at = now();
        rc = 0;
        break;
    }
    pthread_mutex_unlock(&J->mu);
    return rc;
}

const srv_result *srv_jobs_acquire(srv_server *s, const char *key)
{
    struct srv_jobs *J = s->jobs;
    const srv_result *r = NULL;
    job *j;
    pthread_mutex_lock(&J->mu);
    j = find(J, key);
    if (j && j->state == SRV_STATE_DONE) {
        j->readers++;
        r = &j->res;
    }
    pthread_mutex_unlock(&J->mu);
    return r;
}

void srv_jobs_release(srv_server *s, const srv_result *r)
{
    struct srv_jobs *J = s->jobs;
    job *j;
    if (!r) return;
    j = (job *)((const char *)r - offsetof(job, res));
    pthread_mutex_lock(&J->mu);
    j->readers--;
    pthread_mutex_unlock(&J->mu);
}

void srv_job_json(FILE *f, const srv_job_view *v)
{
    static const char *const names[] = {"queued", "running", "done", "failed"};
    fprintf(f, "{\"id\":%lu,\"state\":\"%s\",\"done\":%ld,\"total\":%ld,\"seconds\":", v->id,
            names[v->state], v->done, v->total);
    json_num(f, v->seconds);
    if (v->state == SRV_STATE_QUEUED) {
        fprintf(f, ",\"ahead\":%d", v->ahead);
        if (v->running[0]) {
            fprintf(f, ",\"running\":{\"what\":");
            json_str(f, v->running);
            fprintf(f, ",\"done\":%ld,\"total\":%ld}", v->running_done, v->running_total);
        }
    }
    if (v->state == SRV_STATE_DONE)
        fprintf(f,
                ",\"stats\":{\"eye\":%llu,\"eye_hit\":%llu,\"reflect\":%llu,\"refract\":%llu,"
                "\"shadow\":%llu,\"shadow_blocked\":%llu,\"shadow_attenuated\":%llu,"
                "\"tir\":%llu,\"nonfinite\":%llu,\"max_depth\":%llu}",
                (unsigned long long)v->stats.eye, (unsigned long long)v->stats.eye_hit,
                (unsigned long long)v->stats.reflect, (unsigned long long)v->stats.refract,
                (unsigned long long)v->stats.shadow, (unsigned long long)v->stats.shadow_blocked,
                (unsigned long long)v->stats.shadow_attenuated, (unsigned long long)v->stats.tir,
                (unsigned long long)v->stats.nonfinite, (unsigned long long)v->stats.max_depth);
    if (v->state == SRV_STATE_FAILED) {
        fprintf(f, ",\"error\":");
        json_str(f, v->error);
    }
    fputc('}', f);
}

#else
typedef int serve_jobs_unused; /* ISO C wants a declaration in every file */
#endif
