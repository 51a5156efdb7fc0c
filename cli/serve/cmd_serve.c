/* SPDX-License-Identifier: MIT */
/*
** cmd_serve.c -- `ggrt serve SCENE`: the ray debugger in a browser. A
** local HTTP server (GNU libmicrohttpd) with the rendered image, every
** pixel's ray tree on a click, heatmaps, and a JSON API (docs/serve.md).
** Without libmicrohttpd at build time the command only says so.
*/
#include "common/cli.h"

#include <arpa/inet.h>
#include <stdlib.h>
#include <string.h>

static const char about[] =
    "Serve the ray debugger on http://127.0.0.1:PORT/: the rendered image, and for\n"
    "any pixel you click its ray tree (as ggrt trace prints it), its rays drawn in\n"
    "the scene, heatmaps of rays, depth and time, a second set of options to compare\n"
    "against, and a JSON API for scripts (docs/serve.md). Prints the URL to open,\n"
    "with a random token that every request must carry, and serves until Ctrl-C.";

static const char tail[] =
    "The render options are the starting point; the page changes depth, samples and\n"
    "the accuracy knobs per view (depth at most 16, samples at most 64, images at\n"
    "most 4096 a side and 16777216 pixels). --crop is refused: the page shows the\n"
    "whole image. Only SCENE and its textures are read.\n"
    "exit: 0 stopped by Ctrl-C, SIGTERM or SIGHUP, 1 usage, 2 bad scene, 3 scene\n"
    "unreadable or cannot listen";

typedef struct serve_args {
    const char *scene, *host;
    int port, job_seconds;
    cli_render ro;
} serve_args;

static int numeric_host(const char *h)
{
    unsigned char bin[16];
    return inet_pton(AF_INET, h, bin) == 1 || inet_pton(AF_INET6, h, bin) == 1;
}

/* Parse the command line (also where serve is not built in: --help
   works the same). Returns CLI_GO or an exit code. */
static int parse(serve_args *a, int argc, char **argv)
{
    cli_opt mine[] = {
        CLI_OPT_INT(0, "port", &a->port, 0, 65535, "N",
                    "port to listen on (default 8080; 0: any free port)"),
        CLI_OPT_INT(0, "job-seconds", &a->job_seconds, 1, 300, "N",
                    "cancel a render, find, check or diff still\n"
                    "running after N seconds (default and most 300);\n"
                    "it reports failed"),
        CLI_OPT_STRING(0, "host", &a->host, "ADDR",
                       "address to listen on, numeric or localhost\n"
                       "(default 127.0.0.1); any other than loopback is\n"
                       "reachable from other machines"),
        CLI_OPT_END,
    };
    cli_cmd cmd = {.name = "serve",
                   .usage = "SCENE [--port N] [--host ADDR] [options]",
                   .about = about,
                   .tail = tail,
                   .opts = {mine, a->ro.table},
                   .args = &a->scene,
                   .min_args = 1,
                   .max_args = 1,
                   .args_name = "scene"};
    int rc;
    a->port = 8080, a->host = "127.0.0.1", a->job_seconds = 300;
    cli_render_init(&a->ro, CLI_RENDER_ALL);
    if ((rc = cli_parse(&cmd, argc, argv)) != CLI_GO) return rc;
    cli_render_finish(&a->ro);
    if (cli_given(&cmd, "crop"))
        return cli_usage_error(&cmd, "--crop does not apply: the page shows the whole image "
                                     "(serve renders it in bands of its own)");
    if (a->ro.opt.max_depth > 16)
        return cli_usage_error(&cmd, "bad value '%d' for --depth: ggrt serve takes at most 16",
                               a->ro.opt.max_depth);
    if (a->ro.opt.samples > 64)
        return cli_usage_error(&cmd, "bad value '%d' for --samples: ggrt serve takes at most 64",
                               a->ro.opt.samples);
    if (!strcmp(a->host, "localhost")) a->host = "127.0.0.1";
    if (!numeric_host(a->host))
        return cli_usage_error(&cmd,
                               "bad value '%s' for --host: expected a numeric IPv4 or IPv6 "
                               "address, or localhost",
                               a->host);
    return CLI_GO;
}

#if !defined(GG_HAVE_MHD)

int cmd_serve(int argc, char **argv)
{
    serve_args a;
    int rc;
    memset(&a, 0, sizeof a);
    if ((rc = parse(&a, argc, argv)) != CLI_GO) return rc;
    cli_error("not available: this ggrt was built without GNU libmicrohttpd "
              "(install libmicrohttpd-dev, then rebuild)");
    return EXIT_USAGE;
}

#else
#include "serve/serve.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

/* 128 random bits from the kernel, as 32 hex digits. */
static int make_token(char out[33])
{
    unsigned char b[16];
    size_t got = 0;
    int fd = open("/dev/urandom", O_RDONLY), i;
    if (fd < 0) return -1;
    while (got < sizeof b) {
        ssize_t n = read(fd, b + got, sizeof b - got);
        if (n <= 0 && errno != EINTR) break;
        if (n > 0) got += (size_t)n;
    }
    close(fd);
    if (got < sizeof b) return -1;
    for (i = 0; i < 16; i++) snprintf(out + 2 * i, 3, "%02x", b[i]);
    return 0;
}

static int load(srv_server *s)
{
    ggCamera cam;
    int rc;
    if (!(s->scene = cli_load_scene(s->cfg.scene_path, NULL, NULL, 0, &rc))) return rc;
    cam = ggSceneCamera(s->scene);
    s->cfg.width = s->cfg.opt.width > 0 ? s->cfg.opt.width : cam.width;
    s->cfg.height = s->cfg.opt.height > 0 ? s->cfg.opt.height : cam.height;
    if (s->cfg.width < 1 || s->cfg.height < 1 || s->cfg.width > SRV_MAX_SIDE ||
        s->cfg.height > SRV_MAX_SIDE || (long)s->cfg.width * s->cfg.height > SRV_MAX_PIXELS) {
        cli_error("a %dx%d image is over the limits (4096 a side, 16777216 pixels); "
                  "choose one with -s WxH",
                  s->cfg.width, s->cfg.height);
        return EXIT_USAGE;
    }
    return EXIT_OK;
}

/* Block the stop signals in every thread (the threads started later
   inherit the mask) so that the main thread alone takes them, in
   sigwait. */
static void block_signals(sigset_t *set)
{
    sigemptyset(set);
    sigaddset(set, SIGINT);
    sigaddset(set, SIGTERM);
    sigaddset(set, SIGHUP);
    pthread_sigmask(SIG_BLOCK, set, NULL);
    signal(SIGPIPE, SIG_IGN);
}

/* The server's own render starts at once: the page shows it first. */
static void queue_first_render(srv_server *s)
{
    srv_job_spec sp;
    srv_job_view v;
    char text[1024], key[2048];
    memset(&sp, 0, sizeof sp);
    sp.type = SRV_TYPE_RENDER, sp.kind = SRV_KIND_IMAGE, sp.opt = s->cfg.opt;
    ggRenderOptionsFormat(&sp.opt, text, sizeof text);
    snprintf(key, sizeof key, "render %d|%s", SRV_KIND_IMAGE, text);
    srv_jobs_request(s, key, &sp, &v);
}

static int serve(srv_server *s)
{
    sigset_t set;
    srv_http *http;
    ggError err;
    char msg[256];
    int port, sig = 0, v6 = strchr(s->cfg.host, ':') != NULL;
    block_signals(&set);
    if (srv_jobs_start(s, &err) != GG_OK) {
        cli_error("%s", err.message);
        return EXIT_IO;
    }
    queue_first_render(s);
    http = srv_http_start(s, &port, msg, sizeof msg);
    if (!http) {
        cli_error("%s", msg);
        srv_jobs_stop(s);
        return EXIT_IO;
    }
    fprintf(stderr, "ggrt serve: %s, %dx%d, %d objects, %d lights\n", s->cfg.scene_path,
            s->cfg.width, s->cfg.height, ggSceneObjectCount(s->scene), ggSceneLightCount(s->scene));
    if (strncmp(s->cfg.host, "127.", 4) && strcmp(s->cfg.host, "::1"))
        cli_warn("listening on %s, which other machines can reach; anyone with the URL can use "
                 "this server",
                 s->cfg.host);
    errno = 0;
    printf("http://%s%s%s:%d/?token=%s\n", v6 ? "[" : "", s->cfg.host, v6 ? "]" : "", port,
           s->token);
    /* The URL carries the token, the only way in: a server nobody can
       reach is not started. */
    if (fflush(stdout) != 0 || ferror(stdout)) {
        cli_error("cannot print the URL (it carries the token): %s", strerror(errno ? errno : EIO));
        srv_http_stop(http);
        srv_jobs_stop(s);
        return EXIT_IO;
    }
    fprintf(stderr, "ggrt serve: open the URL above; Ctrl-C stops\n");
    while (sigwait(&set, &sig) != 0) continue;
    fprintf(stderr, "ggrt serve: %s: stopping\n", sig == SIGINT ? "interrupt" : "signal");
    srv_jobs_cancel(s);
    srv_http_stop(http);
    srv_jobs_stop(s);
    return EXIT_OK;
}

int cmd_serve(int argc, char **argv)
{
    serve_args a;
    srv_server s;
    int rc;
    memset(&a, 0, sizeof a);
    if ((rc = parse(&a, argc, argv)) != CLI_GO) return rc;
    memset(&s, 0, sizeof s);
    s.cfg.scene_path = a.scene, s.cfg.host = a.host, s.cfg.port = a.port;
    s.cfg.job_seconds = a.job_seconds;
    s.cfg.opt = a.ro.opt;
    if (make_token(s.token)) {
        cli_error("cannot read /dev/urandom for the token");
        return EXIT_IO;
    }
    if (pthread_mutex_init(&s.scene_mu, NULL) != 0) {
        cli_error("cannot make a mutex");
        return EXIT_IO;
    }
    if ((rc = load(&s)) == EXIT_OK) rc = serve(&s);
    ggSceneFree(s.scene);
    free(s.scene_json); /* after serve() has stopped the server: no response holds it */
    pthread_mutex_destroy(&s.scene_mu);
    return rc;
}

#endif
