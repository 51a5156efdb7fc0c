/* SPDX-License-Identifier: MIT */
/*
** tile.c -- ggrt render --tile I/N and --tiles I,J,K/N: the cut, the
** manifest and the rendering of tiles (tile.h).
*/
#include "render/tile.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

void tile_rows(int i, int n, int h, int *y0, int *y1)
{
    *y0 = (int)((long long)i * h / n);
    *y1 = (int)((long long)(i + 1) * h / n);
}

/* "N" after the slash: 1 to GG_IMAGE_MAX_DIM. */
static int parse_n(const char *slash, int *n, char *why, size_t whylen)
{
    long v;
    if (!slash) {
        snprintf(why, whylen, "expected I/N, e.g. 0/8");
        return -1;
    }
    if (cli_parse_long(slash + 1, 1, GG_IMAGE_MAX_DIM, &v, why, whylen) != 0) return -1;
    *n = (int)v;
    return 0;
}

static int parse_index(const char *s, size_t len, int n, long *out, char *why, size_t whylen)
{
    char buf[32];
    if (len == 0 || len >= sizeof buf) {
        snprintf(why, whylen, "expected a tile index");
        return -1;
    }
    memcpy(buf, s, len), buf[len] = '\0';
    if (cli_parse_long(buf, 0, n - 1, out, why, whylen) != 0) {
        snprintf(why, whylen, "tile index '%s' is not in 0..%d", buf, n - 1);
        return -1;
    }
    return 0;
}

int tile_parse_one(void *ud, const char *value, char *why, size_t whylen)
{
    tile_list *tl = ud;
    const char *slash = strchr(value, '/');
    long i;
    if (parse_n(slash, &tl->n, why, whylen) != 0) return -1;
    if (parse_index(value, (size_t)(slash - value), tl->n, &i, why, whylen) != 0) return -1;
    tl->count = 1, tl->idx[0] = (int)i;
    return 0;
}

/* I,J,A-B,.../N: every index once. */
int tile_parse_list(void *ud, const char *value, char *why, size_t whylen)
{
    tile_list *tl = ud;
    const char *slash = strchr(value, '/'), *p = value;
    if (parse_n(slash, &tl->n, why, whylen) != 0) return -1;
    tl->count = 0;
    while (p < slash) {
        const char *end = memchr(p, ',', (size_t)(slash - p)), *dash;
        long a, b, k;
        int j;
        if (!end) end = slash;
        dash = memchr(p, '-', (size_t)(end - p));
        if (parse_index(p, (size_t)((dash ? dash : end) - p), tl->n, &a, why, whylen) != 0 ||
            (dash && parse_index(dash + 1, (size_t)(end - dash - 1), tl->n, &b, why, whylen) != 0))
            return -1;
        if (!dash) b = a;
        for (k = a; k <= b; k++) {
            for (j = 0; j < tl->count; j++)
                if (tl->idx[j] == k) {
                    snprintf(why, whylen, "tile %ld listed twice", k);
                    return -1;
                }
            if (tl->count == TILE_MAX_LIST) {
                snprintf(why, whylen, "more than %d tiles", TILE_MAX_LIST);
                return -1;
            }
            tl->idx[tl->count++] = (int)k;
        }
        p = end + 1;
    }
    if (!tl->count) {
        snprintf(why, whylen, "no tile listed");
        return -1;
    }
    return 0;
}

int tile_path(const char *pattern, int i, char *buf, size_t size)
{
    const char *pct = strstr(pattern, "%d");
    int n;
    if (!pct)
        n = snprintf(buf, size, "%s", pattern);
    else
        n = snprintf(buf, size, "%.*s%d%s", (int)(pct - pattern), pattern, i, pct + 2);
    return n < 0 || (size_t)n >= size ? -1 : 0;
}

int tile_hash_file(const char *path, char *buf, size_t size)
{
    unsigned long long h = 14695981039346656037ull;
    unsigned char chunk[65536];
    size_t got, k;
    FILE *f = fopen(path, "rb");
    if (!f) return -1;
    while ((got = fread(chunk, 1, sizeof chunk, f)) > 0)
        for (k = 0; k < got; k++) h = (h ^ chunk[k]) * 1099511628211ull;
    if (ferror(f)) {
        fclose(f);
        errno = EIO;
        return -1;
    }
    fclose(f);
    snprintf(buf, size, "fnv1a64:%016llx", h);
    return 0;
}

/* What every tile of this render carries but its index. */
typedef struct tile_job {
    const char *scene_path, *out;
    ggRenderOptions opt; /* whole-image size explicit, no crop */
    int w, h, quiet;
    char hash[32], cut[32], options[2048];
} tile_job;

/* Stops a render on SIGINT, SIGTERM or SIGHUP. */
static int cancel_check(void *ud, long done, long total)
{
    (void)ud, (void)done, (void)total;
    return cli_cancelled() != 0;
}

/* Render tile i's band and write it with the manifest. */
static int render_one(ggScene *scene, const tile_job *j, const tile_list *tl, int i)
{
    ggRenderOptions o = j->opt;
    ggImage *img = NULL, *band = NULL;
    ggEXRAttr attrs[6];
    ggEXRHeader hd;
    ggError err;
    char path[1024], idx[16];
    int y0, y1, rc;
    double t0 = cli_now();
    tile_rows(i, tl->n, j->h, &y0, &y1);
    if (tile_path(j->out, i, path, sizeof path) != 0) {
        cli_error("output path too long: '%s'", j->out);
        return EXIT_USAGE;
    }
    if ((rc = cli_check_output("render", path)) != 0) return rc;
    o.crop_x0 = 0, o.crop_x1 = j->w, o.crop_y0 = y0, o.crop_y1 = y1;
    o.progress = cancel_check, o.progress_ud = NULL;
    rc = ggRender(scene, &o, &img, NULL, &err);
    if (cli_cancelled()) {
        ggImageFree(img);
        cli_error("cancelled by signal %d; %s not written", cli_cancelled(), path);
        cli_cancel_exit(cli_cancelled());
    }
    if (rc != GG_OK) return cli_fail(rc, &err, 1);
    rc = ggImageCrop(img, 0, y0, j->w, y1 - y0, &band);
    ggImageFree(img);
    if (rc != GG_OK) return cli_fail(rc, &err, 0);
    snprintf(idx, sizeof idx, "%d", i);
    attrs[0].name = TILE_A_VERSION, attrs[0].value = ggVersion();
    attrs[1].name = TILE_A_HASH, attrs[1].value = j->hash;
    attrs[2].name = TILE_A_SCENE, attrs[2].value = j->scene_path;
    attrs[3].name = TILE_A_OPTIONS, attrs[3].value = j->options;
    attrs[4].name = TILE_A_CUT, attrs[4].value = j->cut;
    attrs[5].name = TILE_A_TILE, attrs[5].value = idx;
    memset(&hd, 0, sizeof hd);
    hd.display_width = j->w, hd.display_height = j->h;
    hd.data_x = 0, hd.data_y = y0;
    hd.attr_count = 6, hd.attrs = attrs;
    cli_cancel_hold();
    rc = ggImageWriteEXRHeader(band, &hd, path, &err);
    cli_cancel_release();
    ggImageFree(band);
    if (rc != GG_OK) return cli_fail(rc, &err, 0);
    if (!j->quiet)
        printf("tile %d/%d: rows %d..%d -> %s (%.3fs)\n", i, tl->n, y0, y1 - 1, path,
               cli_now() - t0);
    return EXIT_OK;
}

/* The manifest's options: the size explicit, neither crop nor threads
   (which do not change a pixel). */
static int job_init(tile_job *j, ggScene *scene, const char *scene_path,
                    const ggRenderOptions *opt, const tile_list *tl, const char *out, int quiet)
{
    ggCamera cam = ggSceneCamera(scene);
    ggRenderOptions f;
    size_t need;
    j->scene_path = scene_path, j->out = out, j->quiet = quiet, j->opt = *opt;
    j->w = opt->width ? opt->width : cam.width;
    j->h = opt->height ? opt->height : cam.height;
    j->opt.width = j->w, j->opt.height = j->h;
    if (j->h < tl->n) {
        cli_error("%d tiles of %d rows: at most one tile per row", tl->n, j->h);
        return EXIT_USAGE;
    }
    if (tile_hash_file(scene_path, j->hash, sizeof j->hash) != 0) {
        cli_error("%s: cannot read to hash it: %s", scene_path, strerror(errno));
        return EXIT_IO;
    }
    snprintf(j->cut, sizeof j->cut, "rows %d", tl->n);
    f = j->opt;
    f.threads = 0, f.crop_x0 = f.crop_y0 = f.crop_x1 = f.crop_y1 = 0;
    need = ggRenderOptionsFormat(&f, j->options, sizeof j->options);
    if (need >= sizeof j->options) {
        cli_error("render options too long for a tile manifest");
        return EXIT_USAGE;
    }
    return EXIT_OK;
}

int tile_render(ggScene *scene, const char *scene_path, const ggRenderOptions *opt,
                const tile_list *tl, const char *out, int quiet)
{
    tile_job *j = malloc(sizeof *j);
    int k, rc;
    if (!j) {
        cli_error("out of memory");
        return EXIT_INPUT;
    }
    rc = job_init(j, scene, scene_path, opt, tl, out, quiet);
    cli_cancel_begin();
    for (k = 0; k < tl->count && rc == EXIT_OK; k++) {
        rc = render_one(scene, j, tl, tl->idx[k]);
        if (rc == EXIT_OK && cli_cancelled()) cli_cancel_exit(cli_cancelled());
    }
    free(j);
    return rc;
}
