/* SPDX-License-Identifier: MIT */
/*
** aov.c -- ggrt render --aov NAME=LPE and --aov-png DIR (aov.h).
*/
#include "render/aov.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int aov_parse_one(void *ud, const char *value, char *why, size_t whylen)
{
    aov_list *l = ud;
    const char *eq = strchr(value, '=');
    size_t n = eq ? (size_t)(eq - value) : 0, k;
    int i;
    if (l->n >= GG_PATH_LAYERS_MAX) {
        snprintf(why, whylen, "at most %d layers", GG_PATH_LAYERS_MAX);
        return 1;
    }
    /* one message for every way NAME=LPE can be wrong, the way named after it */
    for (k = 0; eq && k < n; k++)
        if (!((value[k] >= 'a' && value[k] <= 'z') || (value[k] >= 'A' && value[k] <= 'Z') ||
              (value[k] >= '0' && value[k] <= '9') || value[k] == '_' || value[k] == '-'))
            break;
    if (!eq || n == 0 || n > GG_EXR_LAYER_NAME || !eq[1] || k < n) {
        snprintf(why, whylen, "expected NAME=LPE, NAME 1 to %d letters, digits, '_' or '-' (%s)",
                 GG_EXR_LAYER_NAME,
                 !eq      ? "no '='"
                 : !n     ? "no NAME"
                 : !eq[1] ? "no LPE"
                 : k < n  ? "NAME has another character"
                          : "NAME is longer");
        return 1;
    }
    memcpy(l->name[l->n], value, n);
    l->name[l->n][n] = '\0';
    for (i = 0; i < l->n; i++)
        if (!strcmp(l->name[i], l->name[l->n])) {
            snprintf(why, whylen, "layer '%s' given twice", l->name[i]);
            return 1;
        }
    l->arg[l->n] = value, l->expr[l->n] = eq + 1;
    l->n++;
    return 0;
}

/* A compile error "layer K: L:C: msg" as a column of the --aov argument,
   in the form of --path's and --where's ("--aov:1:6: ...", then the
   argument and a caret: several --aov are told apart by it). */
static int aov_error(const aov_list *l, const ggError *err)
{
    int k = 0, line = 0, col = 0, off = 0;
    if (sscanf(err->message, "layer %d: %d:%d: %n", &k, &line, &col, &off) == 3 && off > 0 &&
        k >= 1 && k <= l->n && line == 1 && col >= 1) {
        const char *arg = l->arg[k - 1];
        int at = col + (int)(l->expr[k - 1] - arg);
        cli_error("--aov:1:%d: %s", at, err->message + off);
        if (!strchr(arg, '\n')) fprintf(stderr, "  %s\n  %*s^\n", arg, at - 1, "");
    } else {
        cli_error("--aov: %s", err->message);
    }
    return err->code == GG_ERROR_NOMEM ? EXIT_INPUT : EXIT_USAGE;
}

/* Everything the layers take after the render, allocated before it: an
   --aov render that cannot fit fails at once, not after rendering. */
static int layers_alloc(aov_list *l, int w, int h)
{
    size_t layer = (size_t)w * (size_t)h * 3 * sizeof(float);
    l->map = calloc((size_t)l->n, layer);
    /* --aov-png converts one layer at a time into one image */
    if (l->map && l->png_dir) l->scratch = ggImageCreate(w, h, NULL);
    if (!l->map || (l->png_dir && !l->scratch)) {
        double mib = (double)(l->n + (l->png_dir != NULL)) * (double)layer / (1 << 20);
        free(l->map);
        l->map = NULL;
        cli_error("out of memory for the path layers: %d layer%s of %dx%d need %.0f MiB%s", l->n,
                  l->n == 1 ? "" : "s", w, h, mib,
                  l->png_dir ? " with --aov-png's conversion" : "");
        return EXIT_INPUT;
    }
    return EXIT_OK;
}

int aov_prepare(aov_list *l, ggRenderOptions *opt, int w, int h)
{
    ggError err;
    int rc = ggPathLayersCompile(l->expr, l->n, NULL, &l->layers, &err);
    if (rc != GG_OK) return aov_error(l, &err);
    if (w <= 0 || h <= 0 || w > GG_IMAGE_MAX_DIM || h > GG_IMAGE_MAX_DIM ||
        (size_t)w * (size_t)h > GG_IMAGE_MAX_PIXELS)
        return EXIT_OK; /* ggRender refuses the size */
    if ((rc = layers_alloc(l, w, h)) != EXIT_OK) return rc;
    l->w = w, l->h = h;
    opt->layers = l->layers, opt->layer_map = l->map;
    return EXIT_OK;
}

/* The attribute listing the layers. */
static char *layer_list(const aov_list *l)
{
    size_t n = 1;
    char *s;
    int k;
    for (k = 0; k < l->n; k++) n += strlen(l->arg[k]) + 1;
    if (!(s = malloc(n))) return NULL;
    s[0] = '\0';
    for (k = 0; k < l->n; k++) strcat(strcat(s, l->arg[k]), k + 1 < l->n ? "\n" : "");
    return s;
}

/* err says what (and, for I/O, why: errno). */
static int set_err(ggError *err, int code, const char *what)
{
    err->code = code;
    if (code == GG_ERROR_IO)
        snprintf(err->message, sizeof err->message, "%.400s: %s", what, strerror(errno));
    else
        snprintf(err->message, sizeof err->message, "%s", what);
    return code;
}

/* DIR/NAME.png of layer k; 0, or -1 when it does not fit in n bytes. */
static int layer_path(const aov_list *l, int k, char *buf, size_t n)
{
    int len = snprintf(buf, n, "%s/%s.png", l->png_dir, l->name[k]);
    return len < 0 || (size_t)len >= n ? -1 : 0;
}

int aov_check_pngs(const aov_list *l, const char *out, const char *scene)
{
    struct stat st;
    int k, rc;
    if (stat(l->png_dir, &st) != 0) {
        if (errno != ENOENT) {
            cli_error("cannot write into '%s': %s", l->png_dir, strerror(errno));
            return EXIT_IO;
        }
        /* created when the layers are written: only its parent must be
           there, not a whole missing path (mkdir makes one level) */
        return cli_check_output("render", l->png_dir);
    }
    if (!S_ISDIR(st.st_mode)) {
        cli_error("refusing to write into '%s' (--aov-png DIR): it is not a directory", l->png_dir);
        return EXIT_IO;
    }
    for (k = 0; k < l->n; k++) {
        char path[4096];
        if (layer_path(l, k, path, sizeof path) != 0) {
            cli_error("'%s/%s.png': file name too long", l->png_dir, l->name[k]);
            return EXIT_IO;
        }
        if (cli_same_file(path, out)) {
            cli_error("-o '%s' and --aov-png's '%s' are the same file: one would overwrite the "
                      "other",
                      out, path);
            cli_usage_hint();
            return EXIT_USAGE;
        }
        if (cli_same_file(path, scene)) {
            cli_error("--aov-png's '%s' is the input '%s': writing it would destroy it", path,
                      scene);
            cli_usage_hint();
            return EXIT_USAGE;
        }
        if ((rc = cli_check_output("render", path)) != 0) return rc;
    }
    return 0;
}

int aov_check_not_read(const aov_list *l, const ggScene *s)
{
    int k, rc;
    for (k = 0; l->png_dir && k < l->n; k++) {
        char path[4096];
        const char *opt = "--aov-png's", *p = path;
        if (layer_path(l, k, path, sizeof path) != 0) continue; /* aov_check_pngs said so */
        if ((rc = cli_check_not_read("render", s, &opt, &p, 1)) != 0) return rc;
    }
    return 0;
}

/* DIR/NAME.png's temporary name, beside it until every file is written. */
static int layer_temp(const aov_list *l, int k, char *buf, size_t n)
{
    int len = snprintf(buf, n, "%s/%s.png.tmp%ld", l->png_dir, l->name[k], (long)getpid());
    return len < 0 || (size_t)len >= n ? -1 : 0;
}

/* The first `done` layers' temporary files removed (a failure). */
static void drop_temps(const aov_list *l, int done)
{
    char tmp[4096];
    int k;
    for (k = 0; k < done; k++)
        if (layer_temp(l, k, tmp, sizeof tmp) == 0) remove(tmp);
}

/* err's message names the temporary file tmp: name layer k's file. */
static void rename_in_message(ggError *err, const char *tmp, const aov_list *l, int k)
{
    char path[4096], rest[sizeof err->message];
    size_t n = strlen(tmp), pn, rn;
    if (!err || strncmp(err->message, tmp, n) != 0 || layer_path(l, k, path, sizeof path) != 0)
        return;
    rn = strlen(err->message + n), pn = strlen(path);
    if (pn + rn >= sizeof err->message) return;
    memcpy(rest, err->message + n, rn + 1);
    memcpy(err->message, path, pn);
    memcpy(err->message + pn, rest, rn + 1);
}

/* Each layer into its temporary file, through the one image allocated
   before the render (aov_prepare): on any failure none is left. */
static int write_pngs(const aov_list *l, ggError *err)
{
    size_t layer = (size_t)l->w * (size_t)l->h * 3;
    int k, rc = GG_OK;
    if (mkdir(l->png_dir, 0777) != 0 && errno != EEXIST)
        return set_err(err, GG_ERROR_IO, l->png_dir);
    for (k = 0; k < l->n && rc == GG_OK; k++) {
        char tmp[4096];
        memcpy(ggImagePixels(l->scratch), l->map + (size_t)k * layer, layer * sizeof(float));
        if (layer_temp(l, k, tmp, sizeof tmp) != 0)
            rc = set_err(err, GG_ERROR_INVALID, "an --aov-png file name is too long");
        else if ((rc = ggImageWritePNG(l->scratch, tmp, err)) != GG_OK)
            rename_in_message(err, tmp, l, k);
    }
    if (rc != GG_OK) drop_temps(l, k);
    return rc;
}

/* The written layers renamed into place, once -o is written too. */
static int place_pngs(const aov_list *l, ggError *err)
{
    int k;
    for (k = 0; k < l->n; k++) {
        char tmp[4096], path[4096];
        if (layer_temp(l, k, tmp, sizeof tmp) != 0 || layer_path(l, k, path, sizeof path) != 0 ||
            rename(tmp, path) != 0) {
            drop_temps(l, l->n);
            return set_err(err, GG_ERROR_IO, path);
        }
    }
    return GG_OK;
}

/* -o: an EXR with the layers as channels, written from the map in place
   (and the attributes that say how they were made), or the image alone. */
static int write_out(const aov_list *l, const ggImage *img, const char *out, const char *scene,
                     const ggRenderOptions *opt, const char *list, ggError *err)
{
    const char *names[GG_PATH_LAYERS_MAX];
    ggEXRAttr attr[3];
    ggEXRHeader h;
    ggRenderOptions f = *opt;
    char options[2048];
    int k;
    if (cli_image_kind(out) != CLI_IMAGE_EXR) return ggImageWrite(img, out, err);
    for (k = 0; k < l->n; k++) names[k] = l->name[k];
    memset(&h, 0, sizeof h);
    h.display_width = ggImageWidth(img), h.display_height = ggImageHeight(img);
    f.width = h.display_width, f.height = h.display_height, f.threads = 0;
    attr[0].name = AOV_ATTR, attr[0].value = list;
    attr[1].name = AOV_ATTR_SCENE, attr[1].value = scene;
    attr[2].name = AOV_ATTR_OPTIONS, attr[2].value = options;
    h.attrs = attr, h.attr_count = 3;
    if (ggRenderOptionsFormat(&f, options, sizeof options) >= sizeof options) h.attr_count = 2;
    return ggImageWriteEXRLayerMap(img, l->map, names, l->n, &h, out, err);
}

int aov_write(const aov_list *l, const ggImage *img, const char *out, const char *scene,
              const ggRenderOptions *opt, ggError *err)
{
    int rc;
    char *list = layer_list(l);
    /* The layer PNGs first, under temporary names, renamed into place
       only once -o is written: a failure in either leaves neither (a
       layer that failed to write used to leave -o written). */
    if (!list || !l->map || (l->png_dir && !l->scratch))
        rc = set_err(err, GG_ERROR_NOMEM, "out of memory for the path layers");
    else if (l->png_dir && (rc = write_pngs(l, err)) != GG_OK)
        ; /* nothing written; err says why */
    else if ((rc = write_out(l, img, out, scene, opt, list, err)) != GG_OK) {
        if (l->png_dir) drop_temps(l, l->n);
    } else if (l->png_dir) {
        rc = place_pngs(l, err);
    }
    free(list);
    return rc;
}

void aov_print_pixel(const aov_list *l, int x, int y)
{
    int k;
    for (k = 0; k < l->n && l->map; k++) {
        const float *v = l->map + 3 * (((size_t)k * l->h + y) * l->w + x);
        ggColor c;
        char cb[CLI_COLOR_LEN];
        c.r = v[0], c.g = v[1], c.b = v[2];
        printf("layer %s %d,%d %s\n", l->name[k], x, y, cli_color(cb, sizeof cb, 9, c));
    }
}

void aov_free(aov_list *l)
{
    ggPathLayersFree(l->layers);
    free(l->map);
    ggImageFree(l->scratch);
    l->layers = NULL, l->map = NULL, l->scratch = NULL;
}
