/* SPDX-License-Identifier: MIT */
/*
** serve.h -- `ggrt serve`: the parts of the local debugging server. The
** HTTP layer (serve_http.c, the only file that sees libmicrohttpd) checks
** every request and hands it to a route (serve_api.c) as a srv_req; the
** route fills a srv_resp. Renders run on one worker thread (serve_jobs.c).
** docs/serve.md documents the API and every limit below.
*/
#ifndef GG_SERVE_H
#define GG_SERVE_H

#include "common/cli.h"
#include "common/json.h"

#include <pthread.h>
#include <stdio.h>

/* ---- limits (docs/serve.md, "Limits") ---- */
#define SRV_MAX_URI         4096       /* bytes of the request target, query included */
#define SRV_MAX_PARAMS      40         /* query parameters in one request */
#define SRV_MAX_VALUE       1024       /* bytes of one decoded parameter value */
#define SRV_MAX_NAME        64         /* bytes of one decoded parameter name */
#define SRV_MAX_CONNECTIONS 512        /* open connections at once */
#define SRV_MAX_PER_ADDR    16         /* of them from one client address */
#define SRV_THREADS         4          /* threads answering requests */
#define SRV_CONN_TIMEOUT    5          /* seconds a connection may send or take nothing */
#define SRV_HEAD_SECONDS    5          /* seconds a request head may take, or a kept-alive
                                          connection wait for its next request */
#define SRV_MEMORY_LIMIT    (64 << 10) /* bytes per connection for the request head */
#define SRV_MAX_DEPTH       16         /* depth a request may ask for */
#define SRV_MAX_SAMPLES     64         /* samples per pixel a request may ask for */
#define SRV_MAX_SIDE        4096       /* -s: largest side */
#define SRV_MAX_PIXELS      (1L << 24) /* -s: largest width * height */
#define SRV_MAX_JOBS        8          /* renders kept (image + cost map each) */
#define SRV_TRACE_BYTES     (4 << 20)  /* memory one recorded ray tree may use */
#define SRV_RECORD_BYTES    (64 << 20) /* one pixel's trees in a find, check or diff */
#define SRV_RENDER_SECONDS  300        /* a job still running after this is cancelled
                                          (the default and the most of --job-seconds) */
#define SRV_MAX_EXPR        512        /* bytes of a find predicate or path expression */
#define SRV_TEXTURE_SIDE    2048       /* /api/texture: the largest side it sends */
#define SRV_CANCEL_GRACE                                                                           \
    1.0 /* seconds a job asked to be cancelled (/api/cancel)                                       \
           goes on: a request for it meanwhile keeps it */

/* Cost-map kinds a render job can carry, plus the image itself. */
#define SRV_KIND_IMAGE -1

typedef struct srv_param {
    const char *key, *value;
} srv_param;

typedef struct srv_server srv_server;

typedef struct srv_req {
    srv_server *srv;
    const char *path;
    srv_param params[SRV_MAX_PARAMS];
    int nparams;
} srv_req;

typedef struct srv_resp {
    int status;       /* HTTP status */
    const char *type; /* Content-Type (static string) */
    char *body;       /* malloc'ed, or static when body_static */
    size_t len;
    int body_static;
    char extra_name[32], extra_value[128]; /* one optional extra header */
    char extra2_name[32], extra2_value[128];
} srv_resp;

/* A whole number in [lo, hi] (the whole string): 0, else -1. */
int srv_parse_int(const char *s, long lo, long hi, int *out);

/* The value of parameter key, or NULL. */
const char *srv_param_get(const srv_req *r, const char *key);

/* Fill resp with {"status": status, "error": message} (printf format). */
void srv_error(srv_resp *resp, int status, const char *fmt, ...) CLI_PRINTF(3, 4);

/* A response built with stdio: srv_body_open, print to the FILE, then
   srv_body_close (status 500 "out of memory" if the stream failed). */
FILE *srv_body_open(srv_resp *resp, int status, const char *type);
void srv_body_close(srv_resp *resp, FILE *f);

/* ---- render options carried by a request ---- */

/* The render options of parameter `name` ("opts", or "b" for the second
   set of a diff): its text (ggRenderOptionsParse's grammar, as ggrt
   diff's --a and --b) applied over the server's options. The size,
   threads and crop stay the server's; depth and samples are at most
   SRV_MAX_DEPTH and SRV_MAX_SAMPLES. text (may be NULL) receives the
   canonical form (ggRenderOptionsFormat), which names the job. Returns 0,
   or -1 with resp filled (400). */
int srv_opts_parse(const srv_server *s, const srv_req *r, const char *name, ggRenderOptions *o,
                   char *text, size_t textlen, srv_resp *resp);
/* The same checks of a text v (NULL: none given), for /api/parse: 0, or
   -1 with the reason in msg ("L:C: ..." where the text does not parse). */
int srv_opts_text(const srv_server *s, const char *v, ggRenderOptions *o, char *msg, size_t len);

/* May a find, check or diff record pixels under o (parameter name)? The
   bound on one pixel's trees (SRV_RECORD_BYTES) keeps a request from
   making the library record gigabytes: 0, or -1 with resp filled (413). */
int srv_opts_recordable(const srv_server *s, const ggRenderOptions *o, const char *name,
                        srv_resp *resp);

/* ---- the server ---- */

typedef struct srv_config {
    const char *scene_path;
    ggRenderOptions opt; /* the command line's render options */
    int width, height;   /* the image size (from -s or the camera) */
    const char *host;    /* numeric address to bind */
    int port;            /* 0: any free port */
    int job_seconds;     /* a job running longer is cancelled (--job-seconds) */
} srv_config;

struct srv_server {
    srv_config cfg;
    ggScene *scene; /* loaded and prepared before the first request, only
                       read after: any number of requests and the job worker
                       call the library on it at once (scene.h, "Threads") */
    char token[33];
    struct srv_jobs *jobs;
    /* /api/scene's body, built by the first request (the scene does not
       change while served) and kept until the server stops */
    pthread_mutex_t scene_mu;
    char *scene_json;
    size_t scene_json_len;
};

/* Pixel coordinate parameter `name` (required), in [0, limit): 0, or -1
   with resp filled (400). */
int srv_pixel_arg(const srv_server *s, const srv_req *r, const char *name, int limit, int *out,
                  srv_resp *resp);

/* The routes of the jobs (serve_jobapi.c). */
void srv_api_render(srv_server *s, const srv_req *r, srv_resp *resp);
void srv_api_image(srv_server *s, const srv_req *r, srv_resp *resp);
void srv_api_find(srv_server *s, const srv_req *r, srv_resp *resp);
void srv_api_check(srv_server *s, const srv_req *r, srv_resp *resp);
void srv_api_diff(srv_server *s, const srv_req *r, srv_resp *resp);
void srv_api_cancel(srv_server *s, const srv_req *r, srv_resp *resp);

/* Route a checked request. */
void srv_route(srv_server *s, const srv_req *r, srv_resp *resp);
/* Is key a parameter that route path accepts (besides token)? */
int srv_param_allowed(const char *path, const char *key);

/* ---- jobs: renders, find, check, diff (serve_jobs.c, serve_debug.c) ---- */

/* What a job computes (srv_job_spec.type). */
enum srv_job_type {
    SRV_TYPE_RENDER, /* the image, or a cost map (kind) */
    SRV_TYPE_FIND,   /* ggFind, or ggFindPath (spec.lpe) */
    SRV_TYPE_CHECK,  /* ggCheck */
    SRV_TYPE_DIFF    /* ggDiff of options A and B */
};

typedef struct srv_job_spec {
    int type;              /* enum srv_job_type: SRV_TYPE_* */
    int kind;              /* render: SRV_KIND_IMAGE or GG_COST_* */
    ggRenderOptions opt;   /* the options (A) */
    ggRenderOptions opt_b; /* diff: B */
    const char *where;     /* find: the predicate or path expression (copied) */
    int lpe;               /* find: where is a light-path expression (ggFindPath) */
    int limit;             /* find: matches listed; diff: worst pixels listed */
} srv_job_spec;

/* A job's results, merged over its bands; read-only once done. The
   find, check and diff results are the library's structs with the
   window of the whole image, as one call over the whole image would fill
   them (their image members are NULL: px, px_b hold the pictures). */
typedef struct srv_result {
    srv_job_spec spec;
    char *where; /* the spec's copy */
    int width, height;
    float *px, *px_b; /* render, find: the image; diff: both images */
    float *cost;      /* render with a kind: the cost map */
    ggRayStats stats;
    ggFindResult find; /* matches and mask owned here */
    ggCheckResult check;
    ggDiffResult diff; /* worst and map owned here */
    float *share;      /* find with a path: each pixel's share (0 where none matched) */
    ggPredicate *pred; /* find, while it runs */
    ggPathExpr *lpe;   /* find with a path, while it runs */
} srv_result;

typedef struct srv_job_view {
    unsigned long id; /* the job's number, for /api/cancel */
    int state;        /* enum srv_job_state: SRV_STATE_* */
    long done, total;
    /* queued: the jobs that run before it, and the one running now */
    int ahead;
    char running[256]; /* what it is ("" if none), as job_what */
    long running_done, running_total;
    double seconds;
    ggRayStats stats;
    char error[512];
} srv_job_view;

/* Where a job is (srv_job_view.state); the order is used (>= DONE: over). */
enum srv_job_state { SRV_STATE_QUEUED, SRV_STATE_RUNNING, SRV_STATE_DONE, SRV_STATE_FAILED };

int srv_jobs_start(srv_server *s, ggError *err);
/* Cancel the running job and stop taking jobs (shutdown, first step). */
void srv_jobs_cancel(srv_server *s);
/* Join the worker and free every job. */
void srv_jobs_stop(srv_server *s);
/* Find the job named key, or queue one for spec. Fills *view. Returns 0,
   or -1 when every slot is queued, running or being read (view->error
   says so). A job that failed (or was cancelled) is reported once, to
   this request, and forgotten: the next request for it runs it again. */
int srv_jobs_request(srv_server *s, const char *key, const srv_job_spec *spec, srv_job_view *view);
/* Ask to cancel job id (srv_job_view.id): a queued or running job stops
   SRV_CANCEL_GRACE seconds later unless a request for it comes first (a
   job may be shared by several pages), and is then forgotten. Returns 0
   with *view filled (its state before), or -1 when there is no such job. */
int srv_jobs_cancel_id(srv_server *s, unsigned long id, srv_job_view *view);
/* A finished job's results, kept from eviction until srv_jobs_release;
   NULL if the job is not done. */
const srv_result *srv_jobs_acquire(srv_server *s, const char *key);
void srv_jobs_release(srv_server *s, const srv_result *r);
/* The state of a job as JSON ({"state": ..., "done": ...}). */
void srv_job_json(FILE *f, const srv_job_view *v);

/* One band of rows [y0, y1) of a find, check or diff job (serve_debug.c):
   run the library's call on that crop window (o and ob carry it and the
   progress callback) and merge its result into r. */
int srv_band_debug(srv_server *s, srv_result *r, const ggRenderOptions *o,
                   const ggRenderOptions *ob, int y0, int y1, ggError *err);
/* After the last band: the totals one call would give. */
void srv_debug_finish(srv_result *r);
/* Free what a result owns (not r). */
void srv_result_free(srv_result *r);

/* ---- pictures ---- */

/* An 8-bit sRGB PNG of w x h RGB floats, the bytes ggImageWritePNG
   writes (ggLinearToSRGB8), stored without compression. Returns a
   malloc'ed buffer and its size, or NULL if out of memory. */
unsigned char *srv_png(const float *rgb, int w, int h, size_t *len);

/* ---- HTTP (serve_http.c) ---- */
typedef struct srv_http srv_http;
/* Listen on cfg.host:cfg.port and answer requests from SRV_THREADS
   threads; *port receives the port bound. NULL with msg filled on failure. */
srv_http *srv_http_start(srv_server *s, int *port, char *msg, size_t msglen);
/* Stop listening, finish the requests under way, free. NULL is a no-op. */
void srv_http_stop(srv_http *h);

/* ---- the page (generated from cli/serve/web/ by cli/serve/web/embed.sh) ---- */
typedef struct srv_asset {
    const char *path, *type;
    const unsigned char *data;
    size_t len;
} srv_asset;
extern const srv_asset srv_assets[];
extern const int srv_nassets;

#endif
