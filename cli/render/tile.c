/* SPDX-License-Identifier: MIT */
/*
** tile.c -- ggrt render --tile I/N and --tiles I,J,K/N: the cut, the
** manifest and the rendering of tiles (tile.h).
*/
#include "render/tile.h"
#include "render/warn.h"

#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

void tile_rows(int i, int n, int h, int *y0, int *y1)
{
    *y0 = (int)((long long)i * h / n);
    *y1 = (int)((long long)(i + 1) * h / n);
}

/* "N" after the slash: 1 to GG_IMAGE_MAX_DIM; none (n 0): a plan's. */
static int parse_n(const char *slash, int *n, char *why, size_t whylen)
{
    char inner[64];
    long v;
    if (!slash) {
        *n = 0;
        return 0;
    }
    /* The range in the message, as every option's own says it. */
    if (cli_parse_long(slash + 1, 1, GG_IMAGE_MAX_DIM, &v, inner, sizeof inner) != 0) {
        snprintf(why, whylen, "N, the number of tiles: expected a whole number from 1 to %d (%s)",
                 GG_IMAGE_MAX_DIM, inner);
        return -1;
    }
    *n = (int)v;
    return 0;
}

static int parse_index(const char *s, size_t len, int n, long *out, char *why, size_t whylen)
{
    char buf[32];
    if (n == 0) n = GG_IMAGE_MAX_DIM;
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
    if (!slash) slash = value + strlen(value);
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
    if (!slash) slash = value + strlen(value);
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
        if (b < a) {
            snprintf(why, whylen, "range %ld-%ld runs backwards: give %ld-%ld", a, b, b, a);
            return -1;
        }
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
    if (slash > value && slash[-1] == ',') {
        snprintf(why, whylen, "expected a tile index after the last ','");
        return -1;
    }
    if (!tl->count) {
        snprintf(why, whylen, "no tile listed");
        return -1;
    }
    return 0;
}

int tile_list_check(tile_list *tl, int n, char *why, size_t whylen)
{
    int k;
    for (k = 0; k < tl->count; k++)
        if (tl->idx[k] >= n) {
            snprintf(why, whylen, "tile index '%d' is not in 0..%d", tl->idx[k], n - 1);
            return -1;
        }
    tl->n = n;
    return 0;
}

void tile_cut_rows(const tile_cut *c, int i, int h, int *y0, int *y1)
{
    if (!c->y) {
        tile_rows(i, c->n, h, y0, y1);
        return;
    }
    *y0 = c->y[i], *y1 = c->y[i + 1];
}

int tile_cut_format(const tile_cut *c, char *buf, size_t size)
{
    size_t at;
    int k, n;
    if (!c->y) {
        n = snprintf(buf, size, "rows %d", c->n);
        return n < 0 || (size_t)n >= size ? -1 : 0;
    }
    n = snprintf(buf, size, "plan ");
    for (at = (size_t)n, k = 0; k <= c->n; k++) {
        if (at >= size) return -1;
        n = snprintf(buf + at, size - at, k ? ",%d" : "%d", c->y[k]);
        if (n < 0 || (size_t)n >= size - at) return -1;
        at += (size_t)n;
    }
    return 0;
}

void tile_cut_free(tile_cut *c)
{
    free(c->y);
    c->y = NULL;
}

long tile_number(const char *p, const char **end)
{
    long v = 0;
    if (*p < '0' || *p > '9') return -1;
    for (; *p >= '0' && *p <= '9'; p++) v = v > (INT_MAX - 9) / 10 ? INT_MAX : 10 * v + (*p - '0');
    *end = p;
    return v;
}

/* "Y0,Y1,...,YN": 0, strictly increasing, h. */
static int parse_plan_cut(const char *p, int h, tile_cut *c, char *why, size_t whylen)
{
    int k = 0, cap = 0;
    c->y = NULL;
    for (;;) {
        const char *end = p;
        long v = tile_number(p, &end);
        if (v < 0 || (*end && *end != ',') || v < (k ? c->y[k - 1] + 1 : 0) || v > h ||
            (k == 0 && v != 0) || k > TILE_MAX_PLAN) {
            snprintf(why, whylen, "its row %d is not a boundary of rows 0..%d", k, h);
            return -1;
        }
        if (k == cap) {
            int *y = realloc(c->y, (size_t)(cap = cap ? 2 * cap : 16) * sizeof *y);
            if (!y) {
                snprintf(why, whylen, "out of memory");
                return -1;
            }
            c->y = y;
        }
        c->y[k++] = (int)v;
        if (!*end) break;
        p = end + 1;
    }
    if (k < 2 || c->y[k - 1] != h) {
        snprintf(why, whylen, "it does not end at row %d", h);
        return -1;
    }
    c->n = k - 1;
    return 0;
}

int tile_cut_parse(const char *text, int h, tile_cut *c, char *why, size_t whylen)
{
    const char *end = text;
    long v;
    c->y = NULL;
    if (strncmp(text, "plan ", 5) == 0) {
        if (parse_plan_cut(text + 5, h, c, why, whylen) == 0) return 0;
        tile_cut_free(c);
        return -1;
    }
    v = strncmp(text, "rows ", 5) == 0 ? tile_number(text + 5, &end) : 0;
    if (v < 1 || v > h || *end) {
        snprintf(why, whylen, "not a cut of %d rows", h);
        return -1;
    }
    c->n = (int)v;
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

int tile_same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    if (!strcmp(a, b)) return 1;
    return stat(a, &sa) == 0 && stat(b, &sb) == 0 && sa.st_dev == sb.st_dev &&
           sa.st_ino == sb.st_ino;
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
    const cli_render *ro; /* as given, for the warnings (tile_render) */
    ggRenderOptions opt;  /* whole-image size explicit, no crop */
    int w, h, quiet;
    tile_cut cut;
    char hash[32], cutname[TILE_MAX_PLAN * 8 + 16], options[2048];
} tile_job;

/* Render tile i's band and write it with the manifest. */
static int render_one(ggScene *scene, const tile_job *j, const tile_list *tl, int i)
{
    ggRenderOptions o = j->opt;
    ggImage *img = NULL, *band = NULL;
    ggEXRAttr attrs[7];
    ggEXRHeader hd;
    ggRayStats st;
    ggError err;
    char path[CLI_PATH_MAX], idx[16], what[48];
    int y0, y1, rc;
    double t0 = cli_now();
    cli_bar bar;
    tile_cut_rows(&j->cut, i, j->h, &y0, &y1);
    if (tile_path(j->out, i, path, sizeof path) != 0) {
        cli_error("output path too long: '%s'", j->out);
        return EXIT_USAGE;
    }
    if ((rc = cli_check_output("render", path)) != 0) return rc;
    o.crop_x0 = 0, o.crop_x1 = j->w, o.crop_y0 = y0, o.crop_y1 = y1;
    snprintf(what, sizeof what, "tile %d/%d", i, tl->n);
    cli_bar_begin(&bar, what, j->quiet);
    o.progress = cli_bar_step, o.progress_ud = &bar;
    rc = ggRender(scene, &o, &img, &st, &err);
    cli_bar_end(&bar);
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
    attrs[4].name = TILE_A_CUT, attrs[4].value = j->cutname;
    attrs[5].name = TILE_A_TILE, attrs[5].value = idx;
    attrs[6].name = TILE_A_BUILD, attrs[6].value = ggBuildId();
    memset(&hd, 0, sizeof hd);
    hd.display_width = j->w, hd.display_height = j->h;
    hd.data_x = 0, hd.data_y = y0;
    hd.attr_count = 7, hd.attrs = attrs;
    cli_cancel_hold();
    rc = ggImageWriteEXRHeader(band, &hd, path, &err);
    if (rc == GG_OK) cli_cancel_after_write(path);
    cli_cancel_release();
    if (rc != GG_OK) {
        ggImageFree(band);
        return cli_fail(rc, &err, 0);
    }
    if (!j->quiet) {
        printf("tile %d/%d: rows %d..%d -> %s (%.3fs)\n", i, tl->n, y0, y1 - 1, path,
               cli_now() - t0);
        fflush(stdout); /* before this tile's warnings, on stderr */
    }
    /* As a whole render warns, each tile after its line. */
    snprintf(what, sizeof what, "tile %d/%d: ", i, tl->n);
    render_warn_pixels(band, 0, y0, j->scene_path, j->ro, what);
    render_warn_stats(&st, j->ro, what);
    ggImageFree(band);
    return EXIT_OK;
}

int tile_options(const ggScene *scene, const ggRenderOptions *opt, int *w, int *h, char *buf,
                 size_t size)
{
    ggRenderOptions f;
    /* the settings the render takes: -d 5 is the default depth, not another */
    if (ggRenderOptionsResolve(scene, opt, &f) != GG_OK) return -1;
    *w = f.width, *h = f.height;
    f.threads = 0, f.crop_x0 = f.crop_y0 = f.crop_x1 = f.crop_y1 = 0;
    f.cost_map = NULL, f.progress = NULL, f.progress_ud = NULL;
    return ggRenderOptionsFormat(&f, buf, size) >= size ? -1 : 0;
}

/* The cut: equal bands, or the plan's (which must be for this scene and
   these options, and have the list's N if it gives one). */
static int job_cut(tile_job *j, tile_list *tl, const char *plan_path)
{
    tile_plan p;
    char why[160];
    int rc;
    if (!plan_path) {
        j->cut.n = tl->n, j->cut.y = NULL;
        return EXIT_OK;
    }
    if ((rc = tile_plan_read(plan_path, &p)) != EXIT_OK) return rc;
    if ((rc = tile_plan_match(&p, plan_path, j->hash, j->options, j->w, j->h)) != EXIT_OK) {
        tile_cut_free(&p.cut);
        return rc;
    }
    if (tl->n && tl->n != p.cut.n) {
        cli_error("%s cuts %d tiles, not %d: give --tile I (or I/%d)", plan_path, p.cut.n, tl->n,
                  p.cut.n);
        cli_usage_hint();
        tile_cut_free(&p.cut);
        return EXIT_USAGE;
    }
    if (tile_list_check(tl, p.cut.n, why, sizeof why) != 0) {
        cli_error("%s: %s", plan_path, why);
        cli_usage_hint();
        tile_cut_free(&p.cut);
        return EXIT_USAGE;
    }
    j->cut = p.cut;
    return EXIT_OK;
}

/* The manifest: hash, options, cut. */
static int job_init(tile_job *j, ggScene *scene, const char *scene_path,
                    const ggRenderOptions *opt, tile_list *tl, const char *out, int quiet,
                    const char *plan_path)
{
    int rc;
    j->scene_path = scene_path, j->out = out, j->quiet = quiet, j->opt = *opt;
    j->cut.y = NULL;
    if (tile_options(scene, opt, &j->w, &j->h, j->options, sizeof j->options) != 0) {
        cli_error("render options too long for a tile manifest");
        return EXIT_USAGE;
    }
    j->opt.width = j->w, j->opt.height = j->h;
    if (!plan_path && j->h < tl->n) {
        cli_error("%d tiles of %d rows: at most one tile per row", tl->n, j->h);
        cli_usage_hint();
        return EXIT_USAGE;
    }
    if (tile_hash_file(scene_path, j->hash, sizeof j->hash) != 0) {
        cli_error("%s: cannot read to hash it: %s", scene_path, strerror(errno));
        return EXIT_IO;
    }
    if ((rc = job_cut(j, tl, plan_path)) != EXIT_OK) return rc;
    tile_cut_format(&j->cut, j->cutname, sizeof j->cutname);
    return EXIT_OK;
}

int tile_render(ggScene *scene, const char *scene_path, const cli_render *ro, tile_list *tl,
                const char *out, int quiet, const char *plan_path)
{
    tile_job *j = malloc(sizeof *j);
    int k, rc;
    if (!j) {
        cli_error("out of memory");
        return EXIT_INPUT;
    }
    j->ro = ro;
    rc = job_init(j, scene, scene_path, &ro->opt, tl, out, quiet, plan_path);
    cli_cancel_begin();
    for (k = 0; k < tl->count && rc == EXIT_OK; k++) {
        rc = render_one(scene, j, tl, tl->idx[k]);
        if (rc == EXIT_OK && cli_cancelled()) cli_cancel_exit(cli_cancelled());
    }
    tile_cut_free(&j->cut);
    free(j);
    return rc;
}

int tile_band_init(tile_band *b, ggScene *scene, const char *scene_path,
                   const ggRenderOptions *opt, tile_list *tl, const char *plan_path)
{
    tile_job *j = malloc(sizeof *j);
    int rc;
    if (!j) {
        cli_error("out of memory");
        return EXIT_INPUT;
    }
    rc = job_init(j, scene, scene_path, opt, tl, "", 1, plan_path);
    if (rc == EXIT_OK) {
        b->index = tl->idx[0], b->n = j->cut.n, b->w = j->w, b->h = j->h;
        tile_cut_rows(&j->cut, b->index, j->h, &b->y0, &b->y1);
        memcpy(b->hash, j->hash, sizeof b->hash);
        memcpy(b->options, j->options, sizeof b->options);
        memcpy(b->cut, j->cutname, sizeof b->cut);
    }
    tile_cut_free(&j->cut);
    free(j);
    return rc;
}
