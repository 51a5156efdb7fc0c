/* SPDX-License-Identifier: MIT */
/*
** plan_file.c -- reading a plan file of ggrt plan (tile.h): a flat JSON
** object whose values are strings, numbers, true, false, null or arrays
** of numbers and strings. Only what ggrt plan writes needs reading, but
** any such object parses (keys in any order, unknown keys skipped).
*/
#include "render/tile.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#define PLAN_MAX_BYTES (1L << 20)

typedef struct jr {
    const char *p;
} jr;

static void ws(jr *r)
{
    while (*r->p == ' ' || *r->p == '\t' || *r->p == '\n' || *r->p == '\r') r->p++;
}

/* A string into buf (NULL: skipped); escapes of ASCII only. */
static int jstr(jr *r, char *buf, size_t size)
{
    size_t n = 0;
    ws(r);
    if (*r->p++ != '"') return -1;
    while (*r->p != '"') {
        int c = (unsigned char)*r->p++;
        if (c < 0x20) return -1;
        if (c == '\\') {
            const char *esc = "\"\\/b\bf\fn\nr\rt\t", *e;
            c = *r->p++;
            if (c == 'u') {
                char hex[5] = {0};
                int k;
                /* byte by byte: never past the text's terminating NUL */
                for (k = 0; k < 4; k++) {
                    if (!r->p[k] || !strchr("0123456789abcdefABCDEF", r->p[k])) return -1;
                    hex[k] = r->p[k];
                }
                c = (int)strtol(hex, NULL, 16), r->p += 4;
                if (c < 1 || c > 0x7f) return -1;
            } else {
                for (e = esc; *e && *e != c; e += 2) continue;
                if (!*e) return -1;
                c = e[1];
            }
        }
        if (buf && n + 1 >= size) return -1;
        if (buf) buf[n++] = (char)c;
    }
    r->p++;
    if (buf) buf[n] = '\0';
    return 0;
}

static int jnum(jr *r, double *d)
{
    char *end;
    ws(r);
    if (!strchr("-0123456789", *r->p) || !*r->p) return -1;
    *d = strtod(r->p, &end);
    r->p = end;
    return 0;
}

/* [n, n, ...] into v[0..max), *count set; more than max is an error. */
static int jnums(jr *r, double *v, int max, int *count)
{
    ws(r);
    *count = 0;
    if (*r->p++ != '[') return -1;
    ws(r);
    if (*r->p == ']') return r->p++, 0;
    for (;;) {
        if (*count == max || jnum(r, &v[*count]) != 0) return -1;
        ++*count;
        ws(r);
        if (*r->p == ']') return r->p++, 0;
        if (*r->p++ != ',') return -1;
    }
}

/* Any value but an object (none is in a plan). */
static int jskip(jr *r)
{
    double d;
    ws(r);
    if (*r->p == '"') return jstr(r, NULL, 0);
    if (!strncmp(r->p, "true", 4) || !strncmp(r->p, "null", 4)) return r->p += 4, 0;
    if (!strncmp(r->p, "false", 5)) return r->p += 5, 0;
    if (*r->p == '[') {
        r->p++;
        ws(r);
        if (*r->p == ']') return r->p++, 0;
        for (;;) {
            if (jskip(r) != 0) return -1;
            ws(r);
            if (*r->p == ']') return r->p++, 0;
            if (*r->p++ != ',') return -1;
        }
    }
    return jnum(r, &d);
}

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

/* One "key": value of the object. */
static int member(jr *r, tile_plan *p, double *rows, int *nrows, int *seen, char *why,
                  size_t whylen)
{
    char key[64];
    double size[2];
    int n;
    if (jstr(r, key, sizeof key) != 0) return snprintf(why, whylen, "expected a key"), -1;
    ws(r);
    if (*r->p++ != ':') return snprintf(why, whylen, "expected ':' after \"%s\"", key), -1;
    if (!strcmp(key, "ggrt_plan")) {
        if (jnum(r, &size[0]) != 0 || size[0] != 1)
            return snprintf(why, whylen, "ggrt_plan is not 1"), -1;
        *seen |= 1;
    } else if (!strcmp(key, "sceneHash")) {
        if (jstr(r, p->hash, sizeof p->hash) != 0)
            return snprintf(why, whylen, "sceneHash is not a hash"), -1;
        *seen |= 2;
    } else if (!strcmp(key, "options")) {
        if (jstr(r, p->options, sizeof p->options) != 0)
            return snprintf(why, whylen, "options is not a string"), -1;
        *seen |= 4;
    } else if (!strcmp(key, "size")) {
        if (jnums(r, size, 2, &n) != 0 || n != 2 || size[0] < 1 || size[1] < 1 ||
            size[0] > GG_IMAGE_MAX_DIM || size[1] > GG_IMAGE_MAX_DIM)
            return snprintf(why, whylen, "size is not [width,height]"), -1;
        p->width = (int)size[0], p->height = (int)size[1];
        *seen |= 8;
    } else if (!strcmp(key, "rows")) {
        if (jnums(r, rows, TILE_MAX_PLAN + 1, nrows) != 0)
            return snprintf(why, whylen, "rows is not a list of at most %d rows",
                            TILE_MAX_PLAN + 1), -1;
        *seen |= 16;
    } else if (jskip(r) != 0) {
        return snprintf(why, whylen, "\"%s\" has a bad value", key), -1;
    }
    return 0;
}

static int parse_plan(const char *text, tile_plan *p, char *why, size_t whylen)
{
    static const char *const need[] = {"ggrt_plan", "sceneHash", "options", "size", "rows"};
    double *rows = malloc((TILE_MAX_PLAN + 1) * sizeof *rows);
    int nrows = 0, seen = 0, k, rc = -1;
    jr r;
    r.p = text;
    ws(&r);
    if (!rows) return snprintf(why, whylen, "out of memory"), -1;
    if (*r.p++ != '{') {
        snprintf(why, whylen, "not a JSON object");
        goto done;
    }
    ws(&r);
    while (*r.p != '}') {
        if (member(&r, p, rows, &nrows, &seen, why, whylen) != 0) goto done;
        ws(&r);
        if (*r.p == ',') r.p++;
        else if (*r.p != '}') {
            snprintf(why, whylen, "expected ',' or '}' at byte %ld", (long)(r.p - text));
            goto done;
        }
    }
    r.p++;
    ws(&r);
    for (k = 0; k < 5; k++)
        if (!(seen & (1 << k))) {
            snprintf(why, whylen, "no \"%s\"", need[k]);
            goto done;
        }
    if (*r.p) snprintf(why, whylen, "text after the object");
    else rc = rows_cut(rows, nrows, p->height, &p->cut, why, whylen);
done:
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
    if (rc == CLI_READ_IO) {
        cli_error("%s: %s", path, strerror(errno));
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
    if (strcmp(p->hash, hash) != 0) {
        cli_error("%s is a plan for another scene: its hash '%s', not '%s'", plan_path, p->hash,
                  hash);
        return EXIT_INPUT;
    }
    if (strcmp(p->options, options) != 0) {
        cli_error("%s is a plan for other render options: '%s', not '%s'", plan_path,
                  p->options, options);
        return EXIT_INPUT;
    }
    if (p->width != w || p->height != h) {
        cli_error("%s is a plan for a %dx%d image, not %dx%d", plan_path, p->width, p->height, w,
                  h);
        return EXIT_INPUT;
    }
    return EXIT_OK;
}
