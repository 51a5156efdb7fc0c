/* SPDX-License-Identifier: MIT */
/*
** serve_jobs.c -- `ggrt serve`'s renders: a small cache of render jobs,
** one per (options, cost-map kind), done in order by one worker thread.
**
** A render runs as a sequence of crop bands (ggRender promises that a crop
** window's pixels equal the full render's), each under the library lock:
** between two bands a trace request gets the scene, so a click is answered
** while a long render runs, and the bands give the progress and the points
** where a render can be cancelled (shutdown, time limit).
*/
#if defined(GG_HAVE_MHD)
#include "serve.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

#define KEYLEN       512
#define BAND_SECONDS 0.05     /* aim of one band: short enough for a trace to wait for */
#define BAND_PIXELS  (1 << 16) /* and at most this many pixels */

typedef struct job {
    int used;
    unsigned long stamp, queued; /* last use (eviction), queue order */
    char key[KEYLEN];
    int kind; /* SRV_KIND_IMAGE or GG_COST_* */
    ggRenderOptions opt;
    int state;
    long done, total;
    double t0, seconds;
    float *px, *cost;
    ggRayStats stats;
    char error[512];
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

static void add_stats(ggRayStats *a, const ggRayStats *b)
{
    a->eye += b->eye, a->eye_hit += b->eye_hit, a->reflect += b->reflect;
    a->refract += b->refract, a->shadow += b->shadow, a->tir += b->tir;
    a->nonfinite += b->nonfinite;
    if (b->max_depth > a->max_depth) a->max_depth = b->max_depth;
}

typedef struct band_ctx {
    srv_server *s;
    job *j;
    long before; /* pixels of earlier bands */
    long band;   /* pixels of this band */
} band_ctx;

/* ggRender's progress callback: publish the progress, and stop on
   shutdown or past the time limit. */
static int band_progress(void *ud, long done, long total)
{
    band_ctx *b = ud;
    struct srv_jobs *J = b->s->jobs;
    int stop = now() - b->j->t0 > SRV_RENDER_SECONDS;
    pthread_mutex_lock(&J->mu);
    b->j->done = b->before + (total > 0 ? (long)((double)b->band * done / total) : 0);
    stop |= J->quit;
    pthread_mutex_unlock(&J->mu);
    return stop;
}

/* Render job j in bands; returns GG_OK or the status with err filled. */
static int render_bands(srv_server *s, job *j, ggError *err)
{
    int w = s->cfg.width, h = s->cfg.height, y = 0, rows = 16, rc = GG_OK;
    band_ctx b;
    b.s = s, b.j = j, b.before = 0;
    while (y < h && rc == GG_OK) {
        ggRenderOptions o = j->opt;
        ggImage *img = NULL;
        ggRayStats st;
        double t;
        if (rows > h - y) rows = h - y;
        o.width = w, o.height = h;
        o.crop_x0 = 0, o.crop_x1 = w, o.crop_y0 = y, o.crop_y1 = y + rows;
        o.cost_map = j->kind >= 0 ? j->cost : NULL;
        o.cost_kind = j->kind >= 0 ? j->kind : 0;
        o.progress = band_progress, o.progress_ud = &b;
        b.band = (long)rows * w;
        memset(&st, 0, sizeof st);
        t = now();
        srv_lib_lock(s);
        rc = ggRender(s->scene, &o, &img, &st, err);
        srv_lib_unlock(s);
        t = now() - t;
        if (rc == GG_OK) {
            const float *src = ggImagePixelsConst(img) + (size_t)y * w * 3;
            memcpy(j->px + (size_t)y * w * 3, src, (size_t)rows * w * 3 * sizeof(float));
            add_stats(&j->stats, &st);
        }
        ggImageFree(img);
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
    if (rc == GG_ERROR_CANCELLED && now() - j->t0 > SRV_RENDER_SECONDS)
        snprintf(err->message, sizeof err->message,
                 "render cancelled: still running after %d s (docs/serve.md, limits)",
                 SRV_RENDER_SECONDS);
    return rc;
}

static job *next_queued(struct srv_jobs *J)
{
    job *best = NULL;
    int i;
    for (i = 0; i < SRV_MAX_JOBS; i++) {
        job *j = &J->jobs[i];
        if (j->used && j->state == SRV_JOB_QUEUED && (!best || j->queued < best->queued)) best = j;
    }
    return best;
}

static void run_job(srv_server *s, job *j)
{
    struct srv_jobs *J = s->jobs;
    size_t n = (size_t)s->cfg.width * (size_t)s->cfg.height;
    float *px = malloc(n * 3 * sizeof *px), *cost = NULL;
    ggError err;
    int rc;
    err.message[0] = '\0';
    if (px && j->kind >= 0) cost = calloc(n, sizeof *cost);
    pthread_mutex_lock(&J->mu);
    j->px = px, j->cost = cost;
    j->state = SRV_JOB_RUNNING;
    j->t0 = now();
    j->done = 0, j->total = (long)n;
    pthread_mutex_unlock(&J->mu);
    if (!px || (j->kind >= 0 && !cost)) {
        rc = GG_ERROR_NOMEM;
        snprintf(err.message, sizeof err.message, "out of memory for a %dx%d render", s->cfg.width,
                 s->cfg.height);
    } else {
        rc = render_bands(s, j, &err);
    }
    pthread_mutex_lock(&J->mu);
    j->seconds = now() - j->t0;
    if (rc == GG_OK) {
        j->state = SRV_JOB_DONE;
        j->done = j->total;
    } else {
        j->state = SRV_JOB_FAILED;
        snprintf(j->error, sizeof j->error, "%s", err.message);
        free(j->px), free(j->cost);
        j->px = j->cost = NULL;
    }
    pthread_mutex_unlock(&J->mu);
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
    if (!J) goto nomem;
    if (pthread_mutex_init(&J->mu, NULL) != 0) goto nomem;
    if (pthread_cond_init(&J->cv, NULL) != 0) {
        pthread_mutex_destroy(&J->mu);
        goto nomem;
    }
    s->jobs = J;
    if (pthread_create(&J->thread, NULL, worker, s) != 0) {
        pthread_cond_destroy(&J->cv);
        pthread_mutex_destroy(&J->mu);
        free(J);
        s->jobs = NULL;
        snprintf(err->message, sizeof err->message, "cannot start the render thread");
        return GG_ERROR_NOMEM;
    }
    J->started = 1;
    return GG_OK;
nomem:
    free(J);
    snprintf(err->message, sizeof err->message, "out of memory");
    return GG_ERROR_NOMEM;
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
    for (i = 0; i < SRV_MAX_JOBS; i++) free(J->jobs[i].px), free(J->jobs[i].cost);
    pthread_cond_destroy(&J->cv);
    pthread_mutex_destroy(&J->mu);
    free(J);
    s->jobs = NULL;
}

static void view_of(const job *j, srv_job_view *v)
{
    v->state = j->state;
    v->done = j->done, v->total = j->total;
    v->seconds = j->state >= SRV_JOB_DONE      ? j->seconds
                 : j->state == SRV_JOB_RUNNING ? now() - j->t0
                                               : 0;
    v->stats = j->stats;
    snprintf(v->error, sizeof v->error, "%s", j->error);
}

static job *find(struct srv_jobs *J, const char *key, int kind)
{
    int i;
    for (i = 0; i < SRV_MAX_JOBS; i++)
        if (J->jobs[i].used && J->jobs[i].kind == kind && !strcmp(J->jobs[i].key, key))
            return &J->jobs[i];
    return NULL;
}

/* A slot for a new job: a free one, else the least recently used finished
   job (its pixels are freed). NULL when every slot is queued or running. */
static job *slot(struct srv_jobs *J)
{
    job *lru = NULL;
    int i;
    for (i = 0; i < SRV_MAX_JOBS; i++) {
        job *j = &J->jobs[i];
        if (!j->used) return j;
        if (j->state >= SRV_JOB_DONE && (!lru || j->stamp < lru->stamp)) lru = j;
    }
    if (lru) {
        free(lru->px), free(lru->cost);
        memset(lru, 0, sizeof *lru);
    }
    return lru;
}

int srv_jobs_request(srv_server *s, const char *key, const ggRenderOptions *opt, int kind,
                     srv_job_view *view)
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
        pthread_mutex_unlock(&J->mu);
        snprintf(view->error, sizeof view->error, "the server is stopping");
        return -1;
    }
    j = find(J, key, kind);
    if (!j && (j = slot(J)) != NULL) {
        j->used = 1;
        snprintf(j->key, sizeof j->key, "%s", key);
        j->kind = kind;
        j->opt = *opt;
        j->state = SRV_JOB_QUEUED;
        j->queued = ++J->clock;
        j->total = (long)s->cfg.width * s->cfg.height;
        pthread_cond_signal(&J->cv);
    }
    if (j) {
        j->stamp = ++J->clock;
        view_of(j, view);
    } else {
        snprintf(view->error, sizeof view->error,
                 "all %d render slots are queued or running; retry when one is done", SRV_MAX_JOBS);
        rc = -1;
    }
    pthread_mutex_unlock(&J->mu);
    return rc;
}

float *srv_jobs_copy(srv_server *s, const char *key, int kind, int want_cost)
{
    struct srv_jobs *J = s->jobs;
    size_t n = (size_t)s->cfg.width * (size_t)s->cfg.height * (want_cost ? 1 : 3);
    float *out = NULL;
    job *j;
    pthread_mutex_lock(&J->mu);
    j = find(J, key, kind);
    if (j && j->state == SRV_JOB_DONE && (want_cost ? j->cost : j->px)) {
        out = malloc(n * sizeof *out);
        if (out) memcpy(out, want_cost ? j->cost : j->px, n * sizeof *out);
    }
    pthread_mutex_unlock(&J->mu);
    return out;
}

void srv_job_json(FILE *f, const srv_job_view *v)
{
    static const char *const names[] = {"queued", "running", "done", "failed"};
    fprintf(f, "{\"state\":\"%s\",\"done\":%ld,\"total\":%ld,\"seconds\":", names[v->state],
            v->done, v->total);
    srv_json_num(f, v->seconds);
    if (v->state == SRV_JOB_DONE)
        fprintf(f,
                ",\"stats\":{\"eye\":%llu,\"eye_hit\":%llu,\"reflect\":%llu,\"refract\":%llu,"
                "\"shadow\":%llu,\"tir\":%llu,\"nonfinite\":%llu,\"max_depth\":%llu}",
                (unsigned long long)v->stats.eye, (unsigned long long)v->stats.eye_hit,
                (unsigned long long)v->stats.reflect, (unsigned long long)v->stats.refract,
                (unsigned long long)v->stats.shadow, (unsigned long long)v->stats.tir,
                (unsigned long long)v->stats.nonfinite, (unsigned long long)v->stats.max_depth);
    if (v->state == SRV_JOB_FAILED) {
        fprintf(f, ",\"error\":");
        srv_json_str(f, v->error);
    }
    fputc('}', f);
}

#else
typedef int serve_jobs_unused; /* ISO C wants a declaration in every file */
#endif
