/* SPDX-License-Identifier: MIT */
/*
** serve_http.c -- `ggrt serve`'s HTTP side on GNU libmicrohttpd: every
** request is checked here before a route sees it, in this order:
**   request target over SRV_MAX_URI bytes        414
**   a %00 (decoded NUL) in the target            400
**   a method other than GET or HEAD              405
**   a request body (Content-Length, chunked)     413
**   a Host header that does not name the server  403 (DNS rebinding)
**   no token (query or Authorization: Bearer)    401
**   a wrong token                                403
**   a parameter over the limits, or repeated     400 / 414
**   an unknown route                             404
**   a parameter the route does not take          400
** Every refusal is a JSON body {"status": N, "error": "..."}.
**
** Slow clients: libmicrohttpd closes a connection idle for
** SRV_CONN_TIMEOUT, caps the connections (SRV_MAX_CONNECTIONS) and those
** of one client address (SRV_MAX_PER_ADDR); its idle timer restarts with
** every byte, so a watchdog here also cuts a connection whose request
** head is not complete SRV_HEAD_SECONDS after it began (a client that
** sends one byte a second), and a kept-alive one that waits longer for
** its next request. A connection is exempt from the watchdog only while
** an authorised request runs: one announcing a body is refused at once
** (no route takes one), so no client holds a connection by dripping a
** body. A request is answered on the handler's second call,
** once the whole request is in: answered on the first, libmicrohttpd
** would close the connection (it cannot know the body was read), and
** HTTP/1.1 keep-alive would never work.
*/
#if defined(GG_HAVE_MHD)
#include "serve/serve.h"

#include <arpa/inet.h>
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <microhttpd.h>
#include <netinet/in.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

/* ---- libmicrohttpd, opened when the server starts ----

   ggrt does not link libmicrohttpd: Debian's is built with TLS, and
   loading it loads GnuTLS and eight more libraries, 5.4 ms of every ggrt
   process's start (`ggrt --version`: 8.8 ms linked, 3.4 ms not), for a
   server that never speaks TLS. `ggrt serve` opens it by its soname
   (GG_MHD_SONAME, which the Makefile reads off the library pkg-config
   names, so the header and the library are one version) and takes the
   nine functions this file calls. */
#ifndef GG_MHD_SONAME
#define GG_MHD_SONAME "libmicrohttpd.so.12"
#endif

static struct {
    struct MHD_Daemon *(*start_daemon_va)(unsigned, uint16_t, MHD_AcceptPolicyCallback, void *,
                                          MHD_AccessHandlerCallback, void *, va_list);
    void (*stop_daemon)(struct MHD_Daemon *);
    const union MHD_ConnectionInfo *(*get_connection_info)(struct MHD_Connection *,
                                                           enum MHD_ConnectionInfoType, ...);
    struct MHD_Response *(*create_response_from_buffer)(size_t, void *,
                                                        enum MHD_ResponseMemoryMode);
    enum MHD_Result (*add_response_header)(struct MHD_Response *, const char *, const char *);
    enum MHD_Result (*queue_response)(struct MHD_Connection *, unsigned, struct MHD_Response *);
    void (*destroy_response)(struct MHD_Response *);
    const char *(*lookup_connection_value)(struct MHD_Connection *, enum MHD_ValueKind,
                                           const char *);
    int (*get_connection_values)(struct MHD_Connection *, enum MHD_ValueKind, MHD_KeyValueIterator,
                                 void *);
} mhd;

static char mhd_error[320];
static pthread_once_t mhd_once = PTHREAD_ONCE_INIT;

static void mhd_open(void)
{
    /* mhd's members, in order: all function pointers (size checked below) */
    static const char *const names[] = {
        "MHD_start_daemon_va",       "MHD_stop_daemon",
        "MHD_get_connection_info",   "MHD_create_response_from_buffer",
        "MHD_add_response_header",   "MHD_queue_response",
        "MHD_destroy_response",      "MHD_lookup_connection_value",
        "MHD_get_connection_values",
    };
    void *slot[sizeof names / sizeof names[0]];
    typedef char slot_check[sizeof slot == sizeof mhd ? 1 : -1];
    void *lib = dlopen(GG_MHD_SONAME, RTLD_NOW | RTLD_LOCAL);
    size_t i;
    (void)sizeof(slot_check);
    if (!lib) {
        snprintf(mhd_error, sizeof mhd_error,
                 "cannot load GNU libmicrohttpd (%s); install it (Debian: libmicrohttpd12)",
                 dlerror());
        return;
    }
    for (i = 0; i < sizeof names / sizeof names[0]; i++) {
        if (!(slot[i] = dlsym(lib, names[i]))) {
            snprintf(mhd_error, sizeof mhd_error, "%s has no %s", GG_MHD_SONAME, names[i]);
            dlclose(lib);
            return;
        }
    }
    /* Object and function pointers have one size and representation on
       POSIX (dlsym). The library stays open until the process ends. */
    memcpy(&mhd, slot, sizeof mhd);
}

/* 0 once the functions are there, else -1 with the reason in msg. */
static int mhd_load(char *msg, size_t msglen)
{
    pthread_once(&mhd_once, mhd_open);
    if (mhd.start_daemon_va) return 0;
    snprintf(msg, msglen, "%s", mhd_error);
    return -1;
}

static struct MHD_Daemon *mhd_start(unsigned flags, uint16_t port, MHD_AccessHandlerCallback dh,
                                    void *dh_cls, ...)
{
    struct MHD_Daemon *d;
    va_list ap;
    va_start(ap, dh_cls);
    d = mhd.start_daemon_va(flags, port, NULL, NULL, dh, dh_cls, ap);
    va_end(ap);
    return d;
}

typedef struct http_ctx {
    srv_server *srv;
    struct watchdog *watch;
    int port;
    int loopback, wildcard; /* the bound address is loopback / any address */
    unsigned char addr[16]; /* the bound address, binary */
    int family;
} http_ctx;

/* Markers of a request's state between the handler's calls: its target
   was too long, held an encoded NUL, or neither (set by uri_log), and its
   head was seen. */
static int mark_ok, mark_long, mark_nul, mark_head;

/* ---- the watchdog of request heads ---- */

#define WATCH_SLOTS (SRV_MAX_CONNECTIONS + SRV_THREADS * 4)

typedef struct watch_slot {
    int used, fd;
    int busy;     /* a request's head is in: its handler or its response runs */
    double since; /* when the connection began waiting for a request head */
} watch_slot;

typedef struct watchdog {
    pthread_mutex_t mu;
    pthread_cond_t cv;
    pthread_t thread;
    int started, quit;
    long cut; /* connections cut so far (stderr at shutdown) */
    watch_slot slots[WATCH_SLOTS];
} watchdog;

static double mono_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Every half second: shut down the sockets of connections whose request
   head is late. libmicrohttpd then reads the end of the stream and closes
   the connection; it reports NOTIFY_CLOSED (which frees the slot, under
   the same lock) before it closes the descriptor, so the descriptor shut
   down here is never one reused by a newer connection. */
static void *watch_run(void *arg)
{
    watchdog *w = arg;
    pthread_mutex_lock(&w->mu);
    while (!w->quit) {
        struct timespec ts;
        double t = mono_now();
        int i;
        for (i = 0; i < WATCH_SLOTS; i++) {
            watch_slot *sl = &w->slots[i];
            if (sl->used && !sl->busy && sl->since > 0 && t - sl->since > SRV_HEAD_SECONDS) {
                shutdown(sl->fd, SHUT_RDWR);
                sl->since = 0; /* once */
                w->cut++;
            }
        }
        clock_gettime(CLOCK_REALTIME, &ts);
        ts.tv_nsec += 500000000L;
        if (ts.tv_nsec >= 1000000000L) ts.tv_sec++, ts.tv_nsec -= 1000000000L;
        pthread_cond_timedwait(&w->cv, &w->mu, &ts);
    }
    pthread_mutex_unlock(&w->mu);
    return NULL;
}

/* NOTIFY_CONNECTION: a connection starts (a slot, its clock running) or
   is closed (its slot freed). A connection without a slot (none free) is
   left to libmicrohttpd's own idle timeout. */
static void watch_conn(void *cls, struct MHD_Connection *c, void **ctx,
                       enum MHD_ConnectionNotificationCode what)
{
    watchdog *w = cls;
    pthread_mutex_lock(&w->mu);
    if (what == MHD_CONNECTION_NOTIFY_STARTED) {
        const union MHD_ConnectionInfo *ci =
            mhd.get_connection_info(c, MHD_CONNECTION_INFO_CONNECTION_FD);
        int i;
        *ctx = NULL;
        for (i = 0; ci && i < WATCH_SLOTS; i++)
            if (!w->slots[i].used) {
                watch_slot *sl = &w->slots[i];
                sl->used = 1, sl->fd = ci->connect_fd, sl->busy = 0, sl->since = mono_now();
                *ctx = sl;
                break;
            }
    } else if (*ctx) {
        memset(*ctx, 0, sizeof(watch_slot));
        *ctx = NULL;
    }
    pthread_mutex_unlock(&w->mu);
}

/* The connection's head is in (busy 1), or its request is done and it
   waits for the next one (busy 0, the clock restarted). */
static void watch_mark(watchdog *w, struct MHD_Connection *c, int busy)
{
    const union MHD_ConnectionInfo *ci =
        mhd.get_connection_info(c, MHD_CONNECTION_INFO_SOCKET_CONTEXT);
    watch_slot *sl = ci ? ci->socket_context : NULL;
    if (!sl) return;
    pthread_mutex_lock(&w->mu);
    if (sl->used) sl->busy = busy, sl->since = busy ? 0 : mono_now();
    pthread_mutex_unlock(&w->mu);
}

static void *uri_log(void *cls, const char *uri, struct MHD_Connection *c)
{
    (void)cls, (void)c;
    /* libmicrohttpd decodes the path and the parameters into C strings,
       where a %00 would silently cut them: seen here, on the raw target. */
    return strlen(uri) > SRV_MAX_URI ? &mark_long : strstr(uri, "%00") ? &mark_nul : &mark_ok;
}

static void logger(void *cls, const char *fmt, va_list ap)
{
    (void)cls;
    fprintf(stderr, "ggrt serve: ");
    vfprintf(stderr, fmt, ap);
}

/* ---- Host ---- */

/* Does the Host header name this server: the bound address (or localhost
   when bound to loopback; any address literal when bound to all of
   them), and the port? A DNS-rebinding page reaches us under its own
   name, which this refuses. */
/* Is text, all digits, the port number want? strtol with its range
   checked: atoi wrapped 2^32 + port around to port. */
static int port_is(const char *text, int want)
{
    char *end;
    long v;
    if (!*text || strspn(text, "0123456789") != strlen(text)) return 0;
    errno = 0;
    v = strtol(text, &end, 10);
    return errno == 0 && *end == '\0' && v >= 1 && v <= 65535 && v == want;
}

static int host_ok(const http_ctx *h, const char *host)
{
    char name[256];
    const char *port = NULL;
    unsigned char bin[16];
    size_t n;
    int fam = 0, bracketed = host && host[0] == '[';
    if (!host || !*host || strlen(host) >= sizeof name) return 0;
    if (bracketed) {
        const char *e = strchr(host, ']');
        if (!e) return 0;
        n = (size_t)(e - host - 1);
        memcpy(name, host + 1, n), name[n] = '\0';
        if (e[1] == ':')
            port = e + 2;
        else if (e[1])
            return 0;
    } else {
        const char *c = strchr(host, ':');
        n = c ? (size_t)(c - host) : strlen(host);
        memcpy(name, host, n), name[n] = '\0';
        if (c) port = c + 1;
    }
    if (port ? !port_is(port, h->port) : h->port != 80) return 0;
    /* Brackets hold an IPv6 address and nothing else (RFC 3986). */
    if (!bracketed && inet_pton(AF_INET, name, bin) == 1)
        fam = AF_INET;
    else if (inet_pton(AF_INET6, name, bin) == 1)
        fam = AF_INET6;
    else if (bracketed)
        return 0;
    if (!fam) return h->loopback && !strcasecmp(name, "localhost");
    if (h->wildcard) return 1;
    return fam == h->family && !memcmp(bin, h->addr, fam == AF_INET ? 4 : 16);
}

/* ---- token ---- */

static int same_token(const char *a, const char *b)
{
    size_t i, n = strlen(b);
    unsigned char d = 0;
    if (strlen(a) != n) return 0;
    for (i = 0; i < n; i++) d |= (unsigned char)(a[i] ^ b[i]);
    return d == 0;
}

/* ---- parameters ---- */

typedef struct collect {
    srv_req *req;
    int status; /* 0, or the refusal */
    char msg[256];
} collect;

static enum MHD_Result take_param(void *cls, enum MHD_ValueKind kind, const char *key,
                                  const char *value)
{
    collect *c = cls;
    int i;
    (void)kind;
    if (!value) value = "";
    if (!strcmp(key, "token")) return MHD_YES;
    if (c->req->nparams >= SRV_MAX_PARAMS) {
        c->status = 400;
        snprintf(c->msg, sizeof c->msg, "more than %d query parameters", SRV_MAX_PARAMS);
        return MHD_NO;
    }
    if (strlen(key) > SRV_MAX_NAME) {
        c->status = 414;
        snprintf(c->msg, sizeof c->msg, "parameter name '%.*s...' is longer than %d bytes",
                 SRV_MAX_NAME, key, SRV_MAX_NAME);
        return MHD_NO;
    }
    if (strlen(value) > SRV_MAX_VALUE) {
        c->status = 414;
        snprintf(c->msg, sizeof c->msg, "parameter '%s' is longer than %d bytes", key,
                 SRV_MAX_VALUE);
        return MHD_NO;
    }
    for (i = 0; i < c->req->nparams; i++)
        if (!strcmp(c->req->params[i].key, key)) {
            c->status = 400;
            snprintf(c->msg, sizeof c->msg, "parameter '%s' given twice", key);
            return MHD_NO;
        }
    c->req->params[c->req->nparams].key = key;
    c->req->params[c->req->nparams].value = value;
    c->req->nparams++;
    return MHD_YES;
}

/* ---- responses ---- */

static enum MHD_Result respond(struct MHD_Connection *conn, srv_resp *r)
{
    struct MHD_Response *m;
    enum MHD_Result ok;
    m = mhd.create_response_from_buffer(
        r->len, r->body, r->body_static ? MHD_RESPMEM_PERSISTENT : MHD_RESPMEM_MUST_FREE);
    if (!m) {
        if (!r->body_static) free(r->body);
        return MHD_NO;
    }
    mhd.add_response_header(m, "Content-Type", r->type ? r->type : "application/json");
    mhd.add_response_header(m, "Cache-Control", "no-store");
    mhd.add_response_header(m, "X-Content-Type-Options", "nosniff");
    mhd.add_response_header(m, "Referrer-Policy", "no-referrer");
    mhd.add_response_header(m, "X-Frame-Options", "DENY");
    mhd.add_response_header(m, "Content-Security-Policy",
                            "default-src 'none'; script-src 'self'; style-src 'self'; "
                            "img-src 'self' blob: data:; connect-src 'self'; "
                            "frame-ancestors 'none'; base-uri 'none'; form-action 'none'");
    if (r->extra_name[0]) mhd.add_response_header(m, r->extra_name, r->extra_value);
    if (r->extra2_name[0]) mhd.add_response_header(m, r->extra2_name, r->extra2_value);
    ok = mhd.queue_response(conn, (unsigned)r->status, m);
    mhd.destroy_response(m);
    return ok;
}

static enum MHD_Result refuse(struct MHD_Connection *conn, int status, const char *fmt, ...)
{
    srv_resp r;
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    memset(&r, 0, sizeof r);
    srv_error(&r, status, "%s", msg);
    if (status == 401) {
        snprintf(r.extra_name, sizeof r.extra_name, "WWW-Authenticate");
        snprintf(r.extra_value, sizeof r.extra_value, "Bearer realm=\"ggrt serve\"");
    }
    if (status == 405) {
        snprintf(r.extra_name, sizeof r.extra_name, "Allow");
        snprintf(r.extra_value, sizeof r.extra_value, "GET, HEAD");
    }
    return respond(conn, &r);
}

static const char *bearer(struct MHD_Connection *conn)
{
    const char *a = mhd.lookup_connection_value(conn, MHD_HEADER_KIND, "Authorization");
    if (!a || strncasecmp(a, "Bearer ", 7)) return NULL;
    a += 7;
    while (*a == ' ') a++;
    return a;
}

/* Does the request announce a body (a Content-Length other than 0, or
   any Transfer-Encoding)? */
static int has_body(struct MHD_Connection *conn)
{
    const char *cl = mhd.lookup_connection_value(conn, MHD_HEADER_KIND, "Content-Length");
    const char *te = mhd.lookup_connection_value(conn, MHD_HEADER_KIND, "Transfer-Encoding");
    return te || (cl && strspn(cl, "0") != strlen(cl));
}

static enum MHD_Result handle(void *cls, struct MHD_Connection *conn, const char *url,
                              const char *method, const char *version, const char *upload,
                              size_t *upload_size, void **con_cls)
{
    http_ctx *h = cls;
    srv_req req;
    srv_resp resp;
    collect col;
    const char *tok;
    int i;
    (void)version, (void)upload;
    /* Refused at once, on the first call: libmicrohttpd then closes the
       connection, which is what a request with a body we never read
       needs. */
    if (*con_cls == &mark_long) {
        *upload_size = 0;
        return refuse(conn, 414, "request target longer than %d bytes", SRV_MAX_URI);
    }
    if (*con_cls == &mark_nul) {
        *upload_size = 0;
        return refuse(conn, 400, "a NUL byte (%%00) in the request target");
    }
    if (strcmp(method, "GET") && strcmp(method, "HEAD")) {
        *upload_size = 0;
        return refuse(conn, 405, "method %s not allowed: the API is read-only (GET)", method);
    }
    /* No route takes a body, and reading one would let a client that
       drips it byte by byte hold the connection (and a thread's
       attention) without ever sending the Host or the token. */
    if (*con_cls != &mark_head && has_body(conn)) {
        *upload_size = 0;
        return refuse(conn, 413, "a request body is refused: the API takes none (GET)");
    }
    /* Answered on the second call, with the whole request in: the
       connection can then be kept alive. */
    if (*con_cls != &mark_head) {
        *con_cls = &mark_head;
        return MHD_YES;
    }
    if (*upload_size) {
        *upload_size = 0;
        return MHD_YES;
    }
    if (!host_ok(h, mhd.lookup_connection_value(conn, MHD_HEADER_KIND, "Host")))
        return refuse(conn, 403, "Host header does not name this server");
    /* An empty ?token= counts as none: it must not hide a good Bearer
       header (a page's link may carry one left empty). */
    tok = mhd.lookup_connection_value(conn, MHD_GET_ARGUMENT_KIND, "token");
    if (!tok || !*tok) tok = bearer(conn);
    if (!tok || !*tok)
        return refuse(conn, 401,
                      "missing token: add ?token=... as printed by ggrt serve, "
                      "or an Authorization: Bearer header");
    if (!same_token(tok, h->srv->token)) return refuse(conn, 403, "wrong token");
    /* Complete and authorised: only now is the connection kept from the
       watchdog while the route runs (a trace or a check may take a
       while). */
    watch_mark(h->watch, conn, 1);
    memset(&req, 0, sizeof req);
    req.srv = h->srv, req.path = url;
    col.req = &req, col.status = 0, col.msg[0] = '\0';
    mhd.get_connection_values(conn, MHD_GET_ARGUMENT_KIND, take_param, &col);
    if (col.status) return refuse(conn, col.status, "%s", col.msg);
    for (i = 0; i < req.nparams; i++)
        if (!srv_param_allowed(url, req.params[i].key))
            return refuse(conn, 400, "unknown parameter '%.64s' for %.64s (docs/serve.md)",
                          req.params[i].key, url);
    memset(&resp, 0, sizeof resp);
    srv_route(h->srv, &req, &resp);
    return respond(conn, &resp);
}

/* ---- start and stop ---- */

struct srv_http {
    struct MHD_Daemon *d;
    http_ctx ctx;
    watchdog watch;
};

/* NOTIFY_COMPLETED: a request is done; its connection waits for the
   next one. */
static void request_done(void *cls, struct MHD_Connection *c, void **con_cls,
                         enum MHD_RequestTerminationCode why)
{
    (void)con_cls, (void)why;
    watch_mark(cls, c, 0);
}

static int watch_start(watchdog *w)
{
    if (pthread_mutex_init(&w->mu, NULL) != 0) return -1;
    if (pthread_cond_init(&w->cv, NULL) != 0) {
        pthread_mutex_destroy(&w->mu);
        return -1;
    }
    if (pthread_create(&w->thread, NULL, watch_run, w) != 0) {
        pthread_cond_destroy(&w->cv);
        pthread_mutex_destroy(&w->mu);
        return -1;
    }
    w->started = 1;
    return 0;
}

static void watch_stop(watchdog *w)
{
    if (!w->started) return;
    pthread_mutex_lock(&w->mu);
    w->quit = 1;
    pthread_cond_signal(&w->cv);
    pthread_mutex_unlock(&w->mu);
    pthread_join(w->thread, NULL);
    w->started = 0;
}

static int parse_addr(const char *host, struct sockaddr_storage *ss, http_ctx *h)
{
    struct sockaddr_in *a4 = (struct sockaddr_in *)ss;
    struct sockaddr_in6 *a6 = (struct sockaddr_in6 *)ss;
    memset(ss, 0, sizeof *ss);
    if (inet_pton(AF_INET, host, &a4->sin_addr) == 1) {
        a4->sin_family = AF_INET;
        h->family = AF_INET;
        memcpy(h->addr, &a4->sin_addr, 4);
        h->loopback = h->addr[0] == 127;
        h->wildcard = a4->sin_addr.s_addr == htonl(INADDR_ANY);
        return 0;
    }
    if (inet_pton(AF_INET6, host, &a6->sin6_addr) == 1) {
        a6->sin6_family = AF_INET6;
        h->family = AF_INET6;
        memcpy(h->addr, &a6->sin6_addr, 16);
        h->loopback = IN6_IS_ADDR_LOOPBACK(&a6->sin6_addr);
        h->wildcard = IN6_IS_ADDR_UNSPECIFIED(&a6->sin6_addr);
        return 0;
    }
    return -1;
}

/* A listening socket on ss (non-blocking, as the daemon's pool of
   threads accepts on it), and the port it got (--port 0: any free one):
   known before the daemon starts, so no request runs before it is set. */
static int listen_on(struct sockaddr_storage *ss, int family, int *port)
{
    socklen_t len = family == AF_INET6 ? sizeof(struct sockaddr_in6) : sizeof(struct sockaddr_in);
    int fd = socket(family, SOCK_STREAM, 0), one = 1, e;
    if (fd < 0) return -1;
    if (setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one) != 0 ||
        bind(fd, (struct sockaddr *)ss, len) != 0 || listen(fd, SOMAXCONN) != 0 ||
        getsockname(fd, (struct sockaddr *)ss, &len) != 0 ||
        fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK) != 0) {
        e = errno; /* (close may change it: the caller says why) */
        close(fd);
        errno = e;
        return -1;
    }
    *port = ntohs(family == AF_INET6 ? ((struct sockaddr_in6 *)ss)->sin6_port
                                     : ((struct sockaddr_in *)ss)->sin_port);
    return fd;
}

srv_http *srv_http_start(srv_server *s, int *port, char *msg, size_t msglen)
{
    srv_http *h;
    struct sockaddr_storage ss;
    int fd, listen_errno;
    unsigned flags = MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_AUTO | MHD_USE_ERROR_LOG;
    if (mhd_load(msg, msglen)) return NULL;
    if (!(h = calloc(1, sizeof *h))) {
        snprintf(msg, msglen, "out of memory");
        return NULL;
    }
    h->ctx.srv = s;
    h->ctx.watch = &h->watch;
    if (parse_addr(s->cfg.host, &ss, &h->ctx)) {
        snprintf(msg, msglen, "--host '%s' is not a numeric IPv4 or IPv6 address", s->cfg.host);
        free(h);
        return NULL;
    }
    if (h->ctx.family == AF_INET6) {
        flags |= MHD_USE_IPv6;
        ((struct sockaddr_in6 *)&ss)->sin6_port = htons((uint16_t)s->cfg.port);
    } else {
        ((struct sockaddr_in *)&ss)->sin_port = htons((uint16_t)s->cfg.port);
    }
    /* The logger first: options before it would log through MHD's own. */
    errno = 0;
    fd = listen_on(&ss, h->ctx.family, &h->ctx.port);
    listen_errno = fd < 0 ? errno : 0;
    if (fd >= 0 && watch_start(&h->watch) != 0) {
        close(fd);
        snprintf(msg, msglen, "cannot start the connection watchdog thread");
        free(h);
        return NULL;
    }
    /* clang-format off */
    if (fd >= 0)
        h->d = mhd_start(flags, (uint16_t)h->ctx.port, handle, &h->ctx,
                                MHD_OPTION_EXTERNAL_LOGGER, logger, NULL,
                                MHD_OPTION_LISTEN_SOCKET, fd,
                                MHD_OPTION_THREAD_POOL_SIZE, (unsigned)SRV_THREADS,
                                MHD_OPTION_CONNECTION_LIMIT, (unsigned)SRV_MAX_CONNECTIONS,
                                MHD_OPTION_PER_IP_CONNECTION_LIMIT, (unsigned)SRV_MAX_PER_ADDR,
                                MHD_OPTION_CONNECTION_TIMEOUT, (unsigned)SRV_CONN_TIMEOUT,
                                MHD_OPTION_CONNECTION_MEMORY_LIMIT, (size_t)SRV_MEMORY_LIMIT,
                                MHD_OPTION_NOTIFY_CONNECTION, watch_conn, &h->watch,
                                MHD_OPTION_NOTIFY_COMPLETED, request_done, &h->watch,
                                MHD_OPTION_URI_LOG_CALLBACK, uri_log, NULL, MHD_OPTION_END);
    /* clang-format on */
    if (!h->d) {
        /* Why: a port in use, a privileged one, an address not here. */
        if (listen_errno)
            snprintf(msg, msglen, "cannot listen on %s port %d: %s%s", s->cfg.host, s->cfg.port,
                     strerror(listen_errno),
                     listen_errno == EADDRINUSE && s->cfg.port ? " (--port 0 takes a free one)"
                                                               : "");
        else
            snprintf(msg, msglen, "cannot start the HTTP server on %s port %d", s->cfg.host,
                     s->cfg.port);
        if (fd >= 0) close(fd);
        watch_stop(&h->watch);
        if (fd >= 0) pthread_cond_destroy(&h->watch.cv), pthread_mutex_destroy(&h->watch.mu);
        free(h);
        return NULL;
    }
    *port = h->ctx.port;
    return h;
}

void srv_http_stop(srv_http *h)
{
    if (!h) return;
    /* The watchdog first: it must not shut down a socket of a daemon
       that is closing them all. */
    watch_stop(&h->watch);
    mhd.stop_daemon(h->d);
    pthread_cond_destroy(&h->watch.cv);
    pthread_mutex_destroy(&h->watch.mu);
    free(h);
}

#else
typedef int serve_http_unused;
#endif
