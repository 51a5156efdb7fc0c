/* SPDX-License-Identifier: MIT */
/*
** aov_sum.c -- `ggrt check --aov-sum LAYERS.exr [SCENE]`: do the path
** layers of a `ggrt render --aov` file add up to its image, pixel by
** pixel, within rounding (docs/debugging.md, "Path layers")? A pixel
** whose layers add up to less is a gap (light no layer claims), one
** whose layers add up to more an overlap (light two layers claim). With
** the scene (SCENE, or the one the file names), the worst pixel of each
** is traced and the largest path no layer matches (or two match) named.
*/
#include "debug/debug.h"
#include "render/aov.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

typedef struct aov_file {
    const char *path;
    int n, w, h;
    char *list; /* the AOV_ATTR text, split in place */
    const char *name[GG_PATH_LAYERS_MAX], *expr[GG_PATH_LAYERS_MAX];
    char scene[4096], options[2048];
    ggImage *img, *layer[GG_PATH_LAYERS_MAX];
} aov_file;

/* What the comparison found, for gaps (sign 1) or overlaps (sign -1). */
typedef struct aov_side {
    long pixels;
    double light;      /* sum over those pixels of |image - layers| (r + g + b) */
    int wx, wy;        /* the worst pixel */
    double worst;      /* its |image - layers| (r + g + b) */
} aov_side;

static void file_free(aov_file *f)
{
    int k;
    ggImageFree(f->img);
    for (k = 0; k < f->n; k++) ggImageFree(f->layer[k]);
    free(f->list);
}

/* The layer list "NAME=LPE\n..." into f->name, f->expr. */
static int split_list(aov_file *f, const char *text)
{
    char *p;
    if (!(f->list = malloc(strlen(text) + 1))) return -1;
    strcpy(f->list, text);
    for (p = f->list; p && *p && f->n < GG_PATH_LAYERS_MAX;) {
        char *nl = strchr(p, '\n'), *eq = strchr(p, '=');
        if (nl) *nl = '\0';
        if (!eq || (nl && eq > nl)) return -1;
        *eq = '\0';
        f->name[f->n] = p, f->expr[f->n] = eq + 1;
        f->n++;
        p = nl ? nl + 1 : NULL;
    }
    return f->n > 0 ? 0 : -1;
}

static int read_file(aov_file *f)
{
    ggEXRHeader h;
    ggError err;
    const char *v;
    int k, rc = ggImageReadEXRHeader(f->path, &h, &err);
    if (rc != GG_OK) return cli_fail(rc, &err, 0);
    v = ggEXRHeaderGet(&h, AOV_ATTR);
    if (!v || split_list(f, v) != 0) {
        ggEXRHeaderFree(&h);
        cli_error("%s: no path layers (the " AOV_ATTR " attribute of ggrt render --aov)",
                  f->path);
        return EXIT_INPUT;
    }
    if ((v = ggEXRHeaderGet(&h, AOV_ATTR_SCENE))) snprintf(f->scene, sizeof f->scene, "%s", v);
    if ((v = ggEXRHeaderGet(&h, AOV_ATTR_OPTIONS)))
        snprintf(f->options, sizeof f->options, "%s", v);
    ggEXRHeaderFree(&h);
    if ((rc = ggImageReadEXRLayer(f->path, NULL, NULL, &f->img, &err)) != GG_OK)
        return cli_fail(rc, &err, 0);
    f->w = ggImageWidth(f->img), f->h = ggImageHeight(f->img);
    for (k = 0; k < f->n; k++) {
        if ((rc = ggImageReadEXRLayer(f->path, f->name[k], NULL, &f->layer[k], &err)) != GG_OK)
            return cli_fail(rc, &err, 0);
        if (ggImageWidth(f->layer[k]) != f->w || ggImageHeight(f->layer[k]) != f->h) {
            cli_error("%s: layer %s is not %dx%d", f->path, f->name[k], f->w, f->h);
            return EXIT_INPUT;
        }
    }
    return EXIT_OK;
}

static void note(aov_side *s, double d, int x, int y)
{
    s->pixels++;
    s->light += d;
    if (d > s->worst) s->worst = d, s->wx = x, s->wy = y;
}

/* Compare every pixel: gap and overlap; *total the image's light, *bad
   the pixels that are not finite (not compared), *ratio the largest
   |image - layers| over its bound (0/0 counting 0). */
static void compare(const aov_file *f, aov_side *gap, aov_side *over, double *total, long *bad,
                    double *ratio)
{
    int x, y, k, c;
    memset(gap, 0, sizeof *gap), memset(over, 0, sizeof *over);
    *total = 0, *bad = 0, *ratio = 0;
    for (y = 0; y < f->h; y++)
        for (x = 0; x < f->w; x++) {
            const ggColor p = ggImageGet(f->img, x, y);
            const double pv[3] = {p.r, p.g, p.b};
            double sum[3] = {0, 0, 0}, mag[3], miss = 0, extra = 0;
            int out = 0, finite = isfinite(p.r) && isfinite(p.g) && isfinite(p.b);
            for (c = 0; c < 3; c++) mag[c] = fabs(pv[c]);
            for (k = 0; k < f->n; k++) {
                const ggColor l = ggImageGet(f->layer[k], x, y);
                const double lv[3] = {l.r, l.g, l.b};
                for (c = 0; c < 3; c++) sum[c] += lv[c], mag[c] += fabs(lv[c]);
                finite = finite && isfinite(l.r) && isfinite(l.g) && isfinite(l.b);
            }
            if (!finite) {
                ++*bad;
                continue;
            }
            *total += pv[0] + pv[1] + pv[2];
            for (c = 0; c < 3; c++) {
                const double d = pv[c] - sum[c], bound = 0x1p-22 * mag[c];
                if (d != 0 && fabs(d) / bound > *ratio) *ratio = fabs(d) / bound;
                if (fabs(d) <= bound) continue;
                out = 1;
                if (d > 0) miss += d;
                else extra -= d;
            }
            if (!out) continue;
            if (miss > 0) note(gap, miss, x, y);
            if (extra > 0) note(over, extra, x, y);
        }
}

/* The worst pixel's largest path that no layer (want 0) or more than one
   layer (want 2) matches, from its traced terms. */
static void example(const aov_file *f, ggScene *scene, const ggRenderOptions *opt, int x, int y,
                    int want)
{
    ggTrace *tr = ggTraceCreate(NULL);
    ggLedger *led = NULL;
    unsigned char *m[GG_PATH_LAYERS_MAX];
    ggColor px;
    ggError err;
    size_t i, best = (size_t)-1;
    int k, ok = tr && ggTracePixel(scene, opt, x, y, -1, tr, &px, NULL, &err) == GG_OK &&
                    ggLedgerCreate(tr, px, NULL, &led, &err) == GG_OK;
    memset(m, 0, sizeof m);
    for (k = 0; ok && k < f->n; k++) {
        ggPathExpr *e = NULL;
        ggPathSummary s;
        ok = (m[k] = calloc(led->count + 1, 1)) && ggPathParse(f->expr[k], NULL, &e, &err) == GG_OK &&
             ggPathMatch(e, tr, x, y, px, led, m[k], &s) == GG_OK;
        ggPathFree(e);
    }
    for (i = 0; ok && i < led->count; i++) {
        int hits = 0;
        for (k = 0; k < f->n; k++) hits += m[k][i];
        if ((want == 0 ? hits == 0 : hits > 1) &&
            (best == (size_t)-1 || fabs(led->terms[i].share) > fabs(led->terms[best].share)))
            best = i;
    }
    if (ok && best != (size_t)-1) {
        char path[512];
        const ggLedgerTerm *t = &led->terms[best];
        ggPathFormat(tr, t, path, sizeof path);
        char cb[CLI_COLOR_LEN];
        printf("  %s: %s, %s (%.2f%% of the pixel)",
               want ? "a path two layers match" : "a path no layer matches", path,
               cli_color(cb, sizeof cb, 4, t->value), 100 * t->share);
        if (want)
            for (k = 0; k < f->n; k++)
                if (m[k][best]) printf(" [%s]", f->name[k]);
        printf("\n");
    } else if (!ok) {
        printf("  (could not trace pixel %d,%d of the scene to name a path)\n", x, y);
    }
    for (k = 0; k < f->n; k++) free(m[k]);
    ggLedgerFree(led);
    ggTraceFree(tr);
}

static void report(const aov_file *f, const aov_side *s, double total, const char *what,
                   ggScene *scene, const ggRenderOptions *opt, int want)
{
    ggColor p;
    char cb[CLI_COLOR_LEN];
    double pt;
    int k;
    printf("%-8s %ld pixels", what, s->pixels);
    if (!s->pixels) {
        printf("\n");
        return;
    }
    p = ggImageGet(f->img, s->wx, s->wy);
    pt = p.r + p.g + p.b;
    printf(", %.4g%% of the image's light (r+g+b %.6g); worst %d,%d: %.4g (%.2f%% of the pixel)\n",
           total > 0 ? 100 * s->light / total : 0.0, s->light, s->wx, s->wy, s->worst,
           pt > 0 ? 100 * s->worst / pt : 0.0);
    printf("  image %s; layers:", cli_color(cb, sizeof cb, 6, p));
    for (k = 0; k < f->n; k++) {
        ggColor l = ggImageGet(f->layer[k], s->wx, s->wy);
        printf(" %s %s%s", f->name[k], cli_color(cb, sizeof cb, 6, l), k + 1 < f->n ? "," : "\n");
    }
    if (scene) example(f, scene, opt, s->wx, s->wy, want);
}

/* The scene and options to trace with: SCENE or the file's, and the
   file's options (NULL scene when neither loads: no example then). */
static ggScene *trace_scene(const aov_file *f, const char *scene_arg, ggRenderOptions *opt)
{
    const char *path = scene_arg ? scene_arg : f->scene[0] ? f->scene : NULL;
    ggError err;
    int rc;
    ggRenderOptionsDefault(opt);
    if (!path || ggRenderOptionsParse(opt, f->options, &err) != GG_OK) return NULL;
    return cli_load_scene(path, NULL, NULL, 0, &rc);
}

int aov_sum_check(const char *exr, const char *scene_arg)
{
    aov_file f;
    aov_side gap, over;
    ggRenderOptions opt;
    ggScene *scene = NULL;
    double total, ratio;
    long bad;
    int k, rc, failed;
    memset(&f, 0, sizeof f);
    f.path = exr;
    /* A SCENE named is checked now, whether or not a gap will need it: a
       typo must not pass unnoticed because the layers happen to add up. */
    if (scene_arg) {
        struct stat st;
        if (stat(scene_arg, &st) != 0) {
            cli_error("%s: %s", scene_arg, strerror(errno));
            return EXIT_IO;
        }
        if (!S_ISREG(st.st_mode)) {
            cli_error("%s: not a regular file", scene_arg);
            return EXIT_IO;
        }
    }
    if ((rc = read_file(&f)) != EXIT_OK) {
        file_free(&f);
        return rc;
    }
    compare(&f, &gap, &over, &total, &bad, &ratio);
    printf("%s: %dx%d, %d layers:", exr, f.w, f.h, f.n);
    for (k = 0; k < f.n; k++) printf(" %s=%s", f.name[k], f.expr[k]);
    printf("\nbound: |image - sum of layers| <= 2^-22 (|image| + sum |layer|) per channel; the "
           "largest difference is %.3g of it\n",
           ratio);
    if (bad) printf("%ld pixels not finite (not compared)\n", bad);
    if (gap.pixels || over.pixels) scene = trace_scene(&f, scene_arg, &opt);
    report(&f, &gap, total, "gap:", scene, &opt, 0);
    report(&f, &over, total, "overlap:", scene, &opt, 2);
    /* No pixel compared is no evidence: a check that could not look fails. */
    failed = gap.pixels || over.pixels || bad == (long)f.w * f.h;
    if (gap.pixels || over.pixels)
        printf("\nFAIL: the layers %s%s%s the image\n", gap.pixels ? "miss light of" : "",
               gap.pixels && over.pixels ? " and " : "", over.pixels ? "count light twice in" : "");
    else if (failed)
        printf("\nFAIL: no pixel is finite in the image and all its layers: nothing could be "
               "compared\n");
    else
        printf("\nok: the layers add up to the image in all %ld pixels\n",
               (long)f.w * f.h - bad);
    ggSceneFree(scene);
    file_free(&f);
    return failed ? EXIT_CHECK : EXIT_OK;
}
