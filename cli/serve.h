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

#include "cli.h"

#include <pthread.h>
#include <stdio.h>

/* ---- limits (docs/serve.md, "Limits") ---- */
#define SRV_MAX_URI         4096       /* bytes of the request target, query included */
#define SRV_MAX_PARAMS      40         /* query parameters in one request */
#define SRV_MAX_VALUE       1024       /* bytes of one decoded parameter value */
#define SRV_MAX_CONNECTIONS 64         /* open connections at once */
#define SRV_THREADS         4          /* threads answering requests */
#define SRV_CONN_TIMEOUT    30         /* seconds an idle connection is kept */
#define SRV_MEMORY_LIMIT    (64 << 10) /* bytes per connection for the request head */
#define SRV_MAX_DEPTH       16         /* depth a request may ask for */
#define SRV_MAX_SAMPLES     64         /* samples per pixel a request may ask for */
#define SRV_MAX_SIDE        4096       /* -s: largest side */
#define SRV_MAX_PIXELS      (1L << 24) /* -s: largest width * height */
#define SRV_MAX_JOBS        8          /* renders kept (image + cost map each) */
#define SRV_TRACE_BYTES     (4 << 20)  /* memory one recorded ray tree may use */
#define SRV_RENDER_SECONDS  300        /* a render still running after this is cancelled */
#define SRV_MAX_EXPR        512        /* bytes of a find predicate */

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
void srv_error(srv_resp *resp, int status, const char *fmt, ...)
#ifdef __GNUC__
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* A response built with stdio: srv_body_open, print to the FILE, then
   srv_body_close (status 500 "out of memory" if the stream failed). */
FILE *srv_body_open(srv_resp *resp, int status, const char *type);
void srv_body_close(srv_resp *resp, FILE *f);

/* JSON helpers. */
void srv_json_str(FILE *f, const char *s);
void srv_json_num(FILE *f, double d);

/* ---- render options carried by a request ---- */

/* Parse the render options of a request over the server's own (prefix ""
   for the main set, "b." for the second set of diff mode). key receives a
   canonical text of the result that names a render job. Returns 0, or -1
   with resp filled (400). */
int srv_opts_parse(const srv_server *s, const srv_req *r, const char *prefix, ggRenderOptions *o,
                   char *key, size_t keylen, srv_resp *resp);
/* Is key one of the option parameter names (with prefix "" or "b.")? */
int srv_opts_known(const char *key);
/* The options as a JSON object. */
void srv_opts_json(FILE *f, const ggRenderOptions *o);

/* ---- the server ---- */

typedef struct srv_config {
    const char *scene_path;
    ggRenderOptions opt; /* the command line's render options */
    int width, height;   /* the image size (from -s or the camera) */
    const char *host;    /* numeric address to bind */
    int port;            /* 0: any free port */
} srv_config;

struct srv_server {
    srv_config cfg;
    ggScene *scene;
    char token[33];
    /* Library calls on the scene are serialised: a render of one scene
       with different options is not safe against another (the geometry's
       accuracy knobs are set per call, lib/render/render.c
       apply_geometry_knobs). A ticket lock, first come first served: a
       trace that arrives during a render band runs before the next band
       (a plain mutex let the render thread take it back at once). */
    pthread_mutex_t lib;
    pthread_cond_t lib_turn;
    unsigned long lib_next, lib_serving;
    struct srv_jobs *jobs;
};

/* Library lock around every call that reads or sets the scene. */
void srv_lib_lock(srv_server *s);
void srv_lib_unlock(srv_server *s);

/* Route a checked request. */
void srv_route(srv_server *s, const srv_req *r, srv_resp *resp);
/* Is key a parameter that route path accepts (besides token)? */
int srv_param_allowed(const char *path, const char *key);

/* ---- render jobs (serve_jobs.c) ---- */

typedef struct srv_job_view {
    int state; /* SRV_JOB_* */
    long done, total;
    double seconds;
    ggRayStats stats;
    char error[512];
} srv_job_view;

#define SRV_JOB_QUEUED  0
#define SRV_JOB_RUNNING 1
#define SRV_JOB_DONE    2
#define SRV_JOB_FAILED  3

int srv_jobs_start(srv_server *s, ggError *err);
/* Cancel the running render and stop taking jobs (shutdown, first step). */
void srv_jobs_cancel(srv_server *s);
/* Join the worker and free every job. */
void srv_jobs_stop(srv_server *s);
/* Find or queue the render of (key, opt) with a cost map of cost_kind
   (GG_COST_*). Fills *view. Returns 0, or -1 when the queue is full of
   running work (view->error says so). */
int srv_jobs_request(srv_server *s, const char *key, const ggRenderOptions *opt, int cost_kind,
                     srv_job_view *view);
/* Copy a finished job's pixels (3 floats each) or cost map (1 float each)
   into a new malloc'ed array; NULL if not finished or out of memory. */
float *srv_jobs_copy(srv_server *s, const char *key, int cost_kind, int want_cost);
/* The state of a job as JSON ({"state": ..., "done": ...}). */
void srv_job_json(FILE *f, const srv_job_view *v);

/* ---- pictures ---- */

/* An 8-bit sRGB PNG of w x h RGB floats, encoded as ggImageWritePNG
   encodes (clamp to [0,1], NaN to 0, sRGB, rounded in linear space
   against the level midpoints), stored without compression. Returns a
   malloc'ed buffer and its size, or NULL if out of memory. */
unsigned char *srv_png(const float *rgb, int w, int h, size_t *len);

/* ---- HTTP (serve_http.c) ---- */
typedef struct srv_http srv_http;
/* Listen on cfg.host:cfg.port and answer requests from SRV_THREADS
   threads; *port receives the port bound. NULL with msg filled on failure. */
srv_http *srv_http_start(srv_server *s, int *port, char *msg, size_t msglen);
/* Stop listening, finish the requests under way, free. NULL is a no-op. */
void srv_http_stop(srv_http *h);

/* ---- the page (generated from cli/web/ by cli/web/embed.sh) ---- */
typedef struct srv_asset {
    const char *path, *type;
    const unsigned char *data;
    size_t len;
} srv_asset;
extern const srv_asset srv_assets[];
extern const int srv_nassets;

#endif
