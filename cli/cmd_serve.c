/* SPDX-License-Identifier: MIT */
/*
** cmd_serve.c -- `ggrt serve SCENE`: the ray debugger in a browser. A
** local HTTP server (GNU libmicrohttpd) with the rendered image, every
** pixel's ray tree on a click, heatmaps, and a JSON API (docs/serve.md).
** Without libmicrohttpd at build time the command only says so.
*/
#include "cli.h"

#include <stdlib.h>
#include <string.h>

static void help(FILE *f)
{
    fprintf(f, "usage: ggrt serve SCENE [--port N] [--host ADDR] [-s WxH] [render options]\n"
               "\n"
               "Serve the ray debugger on http://127.0.0.1:PORT/: the rendered image, and for\n"
               "any pixel you click its ray tree (as ggrt trace prints it), its rays drawn in the\n"
               "scene, heatmaps of rays, depth and time, a second set of options to compare\n"
               "against, and a JSON API for scripts (docs/serve.md). Prints the URL to open,\n"
               "with a random token that every request must carry; serves until Ctrl-C.\n"
               "\n"
               "options:\n"
               "      --port N          port to listen on (default 8080; 0: any free port)\n"
               "      --host ADDR       numeric address to listen on (default 127.0.0.1); any\n"
               "                        other than loopback is reachable from other machines\n"
               "  -s, --size WxH        image size (default: the scene's resolution; at most\n"
               "                        4096 a side and 16777216 pixels)\n"
               "  -d, --depth N         ray-tree depth, 1..16 (default: scene, else 5)\n"
               "  -n, --samples N       samples per pixel, 1..64 (default: scene, else 1)\n"
               "  -j, --threads N       render threads (default: all processors)\n"
               "      --spd, --corners, --force-effects   as for ggrt render\n"
               "  -h, --help            this text\n"
               "\n"
               "The page can change depth, samples and the accuracy knobs per view; every\n"
               "option above is the starting point. Only SCENE and its textures are read.\n"
               "exit: 0 stopped by Ctrl-C or SIGTERM, 1 usage, 2 bad scene, 3 cannot listen\n");
}

#if !defined(GG_SERVE)

int cmd_serve(int argc, char **argv)
{
    int i;
    for (i = 1; i < argc; i++)
        if (cli_is_help(argv[i])) {
            help(stdout);
            printf("\nThis ggrt was built without GNU libmicrohttpd: serve is not available.\n");
            return EXIT_OK;
        }
    fprintf(stderr, "ggrt serve: not available: this ggrt was built without GNU libmicrohttpd "
                    "(install libmicrohttpd-dev, then rebuild)\n");
    return EXIT_USAGE;
}

#else
#include "serve.h"

#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

void srv_lib_lock(srv_server *s)
{
    pthread_mutex_lock(&s->lib);
}
void srv_lib_unlock(srv_server *s)
{
    pthread_mutex_unlock(&s->lib);
}

static int parse_args(int argc, char **argv, srv_config *c)
{
    int i;
    ggRenderOptionsDefault(&c->opt);
    c->host = "127.0.0.1", c->port = 8080, c->scene_path = NULL;
    for (i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--spd")) {
            c->opt.spd_rules = true, c->opt.pixel_corners = true;
            continue;
        } else if (!strcmp(a, "--corners")) {
            c->opt.pixel_corners = true;
            continue;
        } else if (!strcmp(a, "--force-effects")) {
            c->opt.force_effects = GG_EFFECT_ALL;
            continue;
        } else if (a[0] != '-' || !a[1]) {
            if (c->scene_path) {
                fprintf(stderr, "ggrt serve: more than one scene given ('%s')\n", a);
                return EXIT_USAGE;
            }
            c->scene_path = a;
            continue;
        }
        if (!v) {
            fprintf(stderr, "ggrt serve: %s needs a value (see ggrt serve --help)\n", a);
            return EXIT_USAGE;
        }
        i++;
        if (!strcmp(a, "--port")) {
            if (cli_parse_int(v, 0, 65535, &c->port)) goto bad;
        } else if (!strcmp(a, "--host")) {
            unsigned char bin[16];
            c->host = !strcmp(v, "localhost") ? "127.0.0.1" : v;
            if (inet_pton(AF_INET, c->host, bin) != 1 && inet_pton(AF_INET6, c->host, bin) != 1) {
                fprintf(stderr,
                        "ggrt serve: --host needs a numeric IPv4 or IPv6 address, got '%s'\n", v);
                return EXIT_USAGE;
            }
        } else if (!strcmp(a, "-s") || !strcmp(a, "--size")) {
            char w[16], *x = strchr(v, 'x');
            if (!x || (size_t)(x - v) >= sizeof w) goto bad;
            memcpy(w, v, (size_t)(x - v)), w[x - v] = '\0';
            if (cli_parse_int(w, 1, SRV_MAX_SIDE, &c->opt.width) ||
                cli_parse_int(x + 1, 1, SRV_MAX_SIDE, &c->opt.height))
                goto bad;
        } else if (!strcmp(a, "-d") || !strcmp(a, "--depth")) {
            if (cli_parse_int(v, 1, SRV_MAX_DEPTH, &c->opt.max_depth)) goto bad;
        } else if (!strcmp(a, "-n") || !strcmp(a, "--samples")) {
            if (cli_parse_int(v, 1, SRV_MAX_SAMPLES, &c->opt.samples)) goto bad;
        } else if (!strcmp(a, "-j") || !strcmp(a, "--threads")) {
            if (cli_parse_int(v, 1, 256, &c->opt.threads)) goto bad;
        } else {
            fprintf(stderr, "ggrt serve: unknown option '%s' (see ggrt serve --help)\n", a);
            return EXIT_USAGE;
        }
        continue;
    bad:
        fprintf(stderr, "ggrt serve: bad value '%s' for %s\n", v, a);
        return EXIT_USAGE;
    }
    if (c->opt.spd_rules && !c->opt.max_depth) c->opt.max_depth = 5;
    if (!c->scene_path) {
        fprintf(stderr, "ggrt serve: need a scene (see ggrt serve --help)\n");
        return EXIT_USAGE;
    }
    return EXIT_OK;
}

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
    ggError err;
    ggCamera cam;
    int rc;
    s->scene = ggSceneCreate(NULL);
    if (!s->scene) {
        fprintf(stderr, "ggrt serve: out of memory\n");
        return EXIT_INPUT;
    }
    rc = ggSceneLoadFile(s->scene, s->cfg.scene_path, &err);
    if (rc == GG_OK) rc = ggScenePrepare(s->scene, &err);
    if (rc != GG_OK) {
        fprintf(stderr, "ggrt: %s\n", err.message);
        return cli_exit_code(rc);
    }
    cam = ggSceneCamera(s->scene);
    s->cfg.width = s->cfg.opt.width ? s->cfg.opt.width : cam.width;
    s->cfg.height = s->cfg.opt.height ? s->cfg.opt.height : cam.height;
    if (s->cfg.width < 1 || s->cfg.height < 1 || s->cfg.width > SRV_MAX_SIDE ||
        s->cfg.height > SRV_MAX_SIDE || (long)s->cfg.width * s->cfg.height > SRV_MAX_PIXELS) {
        fprintf(stderr,
                "ggrt serve: a %dx%d image is over the limits (4096 a side, 16777216 pixels); "
                "choose one with -s WxH\n",
                s->cfg.width, s->cfg.height);
        return EXIT_USAGE;
    }
    s->cfg.opt.width = s->cfg.width, s->cfg.opt.height = s->cfg.height;
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

static void queue_first_render(srv_server *s)
{
    srv_req r;
    srv_resp resp;
    srv_job_view v;
    ggRenderOptions o;
    char key[512];
    memset(&r, 0, sizeof r);
    memset(&resp, 0, sizeof resp);
    r.srv = s, r.path = "/api/render";
    if (srv_opts_parse(s, &r, "", &o, key, sizeof key, &resp) == 0)
        srv_jobs_request(s, key, &o, SRV_KIND_IMAGE, &v);
    if (!resp.body_static) free(resp.body);
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
        fprintf(stderr, "ggrt serve: %s\n", err.message);
        return EXIT_IO;
    }
    queue_first_render(s);
    http = srv_http_start(s, &port, msg, sizeof msg);
    if (!http) {
        fprintf(stderr, "ggrt serve: %s\n", msg);
        srv_jobs_stop(s);
        return EXIT_IO;
    }
    fprintf(stderr, "ggrt serve: %s, %dx%d, %d objects, %d lights\n", s->cfg.scene_path,
            s->cfg.width, s->cfg.height, ggSceneObjectCount(s->scene), ggSceneLightCount(s->scene));
    if (strncmp(s->cfg.host, "127.", 4) && strcmp(s->cfg.host, "::1"))
        fprintf(stderr,
                "ggrt serve: warning: listening on %s, which other machines can reach; "
                "anyone with the URL can use this server\n",
                s->cfg.host);
    printf("http://%s%s%s:%d/?token=%s\n", v6 ? "[" : "", s->cfg.host, v6 ? "]" : "", port,
           s->token);
    fflush(stdout);
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
    srv_server s;
    int i, rc;
    for (i = 1; i < argc; i++)
        if (cli_is_help(argv[i])) {
            help(stdout);
            return EXIT_OK;
        }
    memset(&s, 0, sizeof s);
    if ((rc = parse_args(argc, argv, &s.cfg)) != EXIT_OK) return rc;
    if (make_token(s.token)) {
        fprintf(stderr, "ggrt serve: cannot read /dev/urandom for the token\n");
        return EXIT_IO;
    }
    if ((rc = load(&s)) == EXIT_OK) {
        if (pthread_mutex_init(&s.lib, NULL) != 0) {
            fprintf(stderr, "ggrt serve: cannot create a mutex\n");
            rc = EXIT_IO;
        } else {
            rc = serve(&s);
            pthread_mutex_destroy(&s.lib);
        }
    }
    ggSceneFree(s.scene);
    return rc;
}

#endif
