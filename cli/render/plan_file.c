/* SPDX-License-Identifier: MIT */
/*
** plan_file.c -- reading a plan file of ggrt plan (tile.h): a JSON
** object read by jdom.c, the reader of merge --reports, so that both take
** the same grammar. Only what ggrt plan writes needs reading, but any
** such object parses (keys in any order, unknown keys skipped).
*/
#include "render/jdom.h"
#include "render/tile.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#define PLAN_MAX_BYTES (1L << 20)

/* The rows as a cut ("plan Y0,...,YN" through tile_cut_parse, the one
   check of a cut). */
static int rows_cut(const double *y, int k, int h, tile_cut *c, char *why, size_t whylen)
{
    char *text = malloc((size_t)k * 12 + 8);
    size_t at = 5;
    int i, rc;
    if (!text) {
        snprintf(why, whylen, "out of memory");
        return -1;
    }
    memcpy(text, "plan ", 5);
    for (i = 0; i < k; i++) {
        if (y[i] != (double)(int)y[i]) {
            snprintf(why, whylen, "rows: %.17g is not a row", y[i]);
            free(text);
            return -1;
        }
        at += (size_t)sprintf(text + at, i ? ",%d" : "%d", (int)y[i]);
    }
    rc = k ? tile_cut_parse(text, h, c, why, whylen) : -1;
    if (!k) snprintf(why, whylen, "rows is empty");
    free(text);
    return rc;
}

/* The numbers of an array of at most max into v; -1 if it is not one. */
static int numbers(const jnode *a, double *v, int max)
{
    int i;
    if (!a || a->type != 'a' || a->n > max) return -1;
    for (i = 0; i < a->n; i++) {
        if (a->kid[i].type != 'n') return -1;
        v[i] = jdom_num(&a->kid[i]);
    }
    return a->n;
}

/* The members a plan needs; unknown ones are skipped. */
static int members(const jnode *o, tile_plan *p, double *rows, int *nrows, char *why, size_t whylen)
{
    static const char *const need[] = {"ggrt_plan", "sceneHash", "options", "size", "rows"};
    const jnode *v;
    double size[2];
    int k;
    for (k = 0; k < 5; k++)
        if (!jdom_get(o, need[k])) return snprintf(why, whylen, "no \"%s\"", need[k]), -1;
    v = jdom_get(o, "ggrt_plan");
    if (v->type != 'n' || jdom_num(v) != 1) return snprintf(why, whylen, "ggrt_plan is not 1"), -1;
    if (jdom_str(jdom_get(o, "sceneHash"), p->hash, sizeof p->hash) != 0)
        return snprintf(why, whylen, "sceneHash is not a hash"), -1;
    if (jdom_str(jdom_get(o, "options"), p->options, sizeof p->options) != 0)
        return snprintf(why, whylen, "options is not a string"), -1;
    /* A plan of a ggrt from before the build id (the others as today's
       writes them): which build it is cannot be told. */
    if (!(v = jdom_get(o, "buildId")))
        return snprintf(why, whylen, "no \"buildId\" (a plan of an older ggrt: make it again)"), -1;
    if (jdom_str(v, p->build, sizeof p->build) != 0)
        return snprintf(why, whylen, "buildId is not a string"), -1;
    if (numbers(jdom_get(o, "size"), size, 2) != 2 || size[0] < 1 || size[1] < 1 ||
        size[0] > GG_IMAGE_MAX_DIM || size[1] > GG_IMAGE_MAX_DIM)
        return snprintf(why, whylen, "size is not [width,height]"), -1;
    p->width = (int)size[0], p->height = (int)size[1];
    if ((*nrows = numbers(jdom_get(o, "rows"), rows, TILE_MAX_PLAN + 1)) < 0)
        return snprintf(why, whylen, "rows is not a list of at most %d rows", TILE_MAX_PLAN + 1),
               -1;
    return 0;
}

/* The same JSON grammar as merge --reports (jdom.c), one object. */
static int parse_plan(const char *text, tile_plan *p, char *why, size_t whylen)
{
    double *rows = malloc((TILE_MAX_PLAN + 1) * sizeof *rows);
    int nrows = 0, rc = -1;
    jnode root;
    if (!rows) return snprintf(why, whylen, "out of memory"), -1;
    if (jdom_parse(text, &root, why, whylen) == 0) {
        if (root.type != 'o')
            snprintf(why, whylen, "not a JSON object");
        else if (members(&root, p, rows, &nrows, why, whylen) == 0)
            rc = rows_cut(rows, nrows, p->height, &p->cut, why, whylen);
    }
    jdom_free(&root);
    free(rows);
    return rc;
}

int tile_plan_read(const char *path, tile_plan *p)
{
    char *text, why[200];
    size_t got;
    int rc;
    memset(p, 0, sizeof *p);
    rc = cli_read_text(path, PLAN_MAX_BYTES, &text, &got);
    if (rc == CLI_READ_IO || rc == CLI_READ_NOTFILE) {
        cli_error("the plan %s: %s", path, rc == CLI_READ_IO ? strerror(errno) : "not a regular file");
        return EXIT_IO;
    }
    if (rc == CLI_READ_NOMEM)
        cli_error("out of memory");
    else if (rc == CLI_READ_LARGE || strlen(text) != got)
        cli_error("%s: not a ggrt plan: %s", path,
                  rc == CLI_READ_LARGE ? "larger than 1 MiB" : "a NUL byte in it");
    else if (parse_plan(text, p, why, sizeof why) != 0)
        cli_error("%s: not a ggrt plan: %s", path, why);
    else {
        free(text);
        return EXIT_OK;
    }
    free(text);
    return EXIT_INPUT;
}

int tile_plan_match(const tile_plan *p, const char *plan_path, const char *hash,
                    const char *options, int w, int h)
{
    if (strcmp(p->build, ggBuildId()) != 0) {
        cli_error("%s is a plan of another ggrt build: its '%s', not '%s' (ggrt --version)",
                  plan_path, p->build, ggBuildId());
        return EXIT_INPUT;
    }
    if (strcmp(p->hash, hash) != 0) {
        cli_error("%s is a plan for another scene: its hash '%s', not '%s'", plan_path, p->hash,
                  hash);
        return EXIT_INPUT;
    }
    if (strcmp(p->options, options) != 0) {
        char d[512];
        cli_render_text_diff(p->options, options, d, sizeof d);
        cli_error("%s is a plan for other render options: %s", plan_path, d);
        return EXIT_INPUT;
    }
    if (p->width != w || p->height != h) {
        cli_error("%s is a plan for a %dx%d image, not %dx%d", plan_path, p->width, p->height, w,
                  h);
        return EXIT_INPUT;
    }
    return EXIT_OK;
}
