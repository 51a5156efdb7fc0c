/* SPDX-License-Identifier: MIT */
/*
** paths_out.c -- the matching paths of a pixel (trace --path) or of a
** find (find --path) written out for other tools: JSON lines (one path a
** line) and OBJ polylines (one `l` per path), for Python, Blender and
** MeshLab. The library gives the paths (ggLedgerCreate, ggPathMatch,
** ggPathFormat, ggPathPoints); this file only writes them.
*/
#include "debug/debug.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

int dbg_paths_check(const char *cmd, const char *jsonl, const char *obj)
{
    int rc = 0;
    if (jsonl && (rc = cli_check_output(cmd, jsonl)) != 0) return rc;
    if (obj && (rc = cli_check_output(cmd, obj)) != 0) return rc;
    return 0;
}

int dbg_paths_max_parse(void *ud, const char *value, char *why, size_t whylen)
{
    static const char units[] = "KMG";
    const char *u;
    char *end;
    unsigned long long n;
    int shift = 0;
    if (value[0] < '0' || value[0] > '9') goto bad; /* no sign, no blank */
    errno = 0;
    n = strtoull(value, &end, 10);
    if (*end && !end[1] && (u = strchr(units, *end)) != NULL)
        shift = 10 * (int)(u - units + 1), end++;
    if (errno || *end || n > (1ull << 50) >> shift) goto bad;
    *(uint64_t *)ud = (uint64_t)n << shift;
    return 0;
bad:
    snprintf(why, whylen,
             "a whole number of bytes, with K, M or G (powers of 1024), at most 2^50; 0 for no "
             "limit");
    return -1;
}

int dbg_paths_open(dbg_paths_out *o, const char *cmd, const char *jsonl, const char *obj,
                   uint64_t max)
{
    int rc;
    memset(o, 0, sizeof *o);
    o->cmd = cmd, o->max = max;
    if (jsonl) {
        if ((rc = cli_out_open(&o->jsonl, cmd, jsonl)) != 0) return rc;
        o->have_jsonl = 1;
    }
    if (obj) {
        if ((rc = cli_out_open(&o->obj, cmd, obj)) != 0) {
            dbg_paths_close(o);
            return rc;
        }
        o->have_obj = 1;
        fprintf(o->obj.f, "# ggrt: light paths, one polyline (l) per path, eye to light\n");
    }
    return 0;
}

static void write_jsonl(FILE *f, int x, int y, const char *events, const ggLedgerTerm *t,
                        const ggPathPoint *pts, size_t n)
{
    size_t k;
    fprintf(f, "{\"pixel\":[%d,%d],\"events\":", x, y);
    json_str(f, events);
    fprintf(f, ",\"term\":\"%s\",\"node\":%d,\"light\":%d,\"points\":[", ggTermName(t->kind),
            t->node, t->light);
    for (k = 0; k < n; k++) {
        fprintf(f, "%s[", k ? "," : "");
        json_num(f, pts[k].p.x), fputc(',', f), json_num(f, pts[k].p.y), fputc(',', f);
        json_num(f, pts[k].p.z), fputc(']', f);
    }
    fprintf(f, "],\"weights\":[");
    for (k = 0; k < n; k++) {
        fprintf(f, "%s[", k ? "," : "");
        json_num(f, pts[k].weight.r), fputc(',', f), json_num(f, pts[k].weight.g), fputc(',', f);
        json_num(f, pts[k].weight.b), fputc(']', f);
    }
    fprintf(f, "],\"contribution\":[");
    json_num(f, t->value.r), fputc(',', f), json_num(f, t->value.g), fputc(',', f);
    json_num(f, t->value.b);
    fprintf(f, "],\"share\":");
    json_num(f, t->share);
    fprintf(f, "}\n");
}

static void write_obj(dbg_paths_out *o, int x, int y, const char *events, const ggPathPoint *pts,
                      size_t n)
{
    FILE *f = o->obj.f;
    size_t k;
    fprintf(f, "o pixel_%d_%d_path_%ld\n# %s\n", x, y, o->paths, events);
    for (k = 0; k < n; k++) fprintf(f, "v %.17g %.17g %.17g\n", pts[k].p.x, pts[k].p.y, pts[k].p.z);
    fprintf(f, "l");
    for (k = 0; k < n; k++) fprintf(f, " %ld", o->vertices + 1 + (long)k);
    fprintf(f, "\n");
    o->vertices += (long)n;
}

/* One matched term: its events, points and weights. */
static int write_term(dbg_paths_out *o, const ggTrace *tr, int x, int y, const ggLedgerTerm *t)
{
    char events[2048];
    ggPathPoint stack[72], *pts = stack;
    size_t n = ggPathPoints(tr, t, stack, sizeof stack / sizeof *stack);
    if (n > sizeof stack / sizeof *stack) {
        if (!(pts = malloc(n * sizeof *pts))) return -1;
        ggPathPoints(tr, t, pts, n);
    }
    ggPathFormat(tr, t, events, sizeof events);
    if (o->have_jsonl) write_jsonl(o->jsonl.f, x, y, events, t, pts, n);
    if (o->have_obj) write_obj(o, x, y, events, pts, n);
    o->paths++;
    if (pts != stack) free(pts);
    return 0;
}

/* Past --paths-max after pixel (x, y): exit 2, nothing to be written. */
static int over_max(const dbg_paths_out *o, int x, int y)
{
    off_t a = o->have_jsonl ? ftello(o->jsonl.f) : 0, b = o->have_obj ? ftello(o->obj.f) : 0;
    uint64_t n = (uint64_t)(a > 0 ? a : 0) + (uint64_t)(b > 0 ? b : 0);
    if (!o->max || n <= o->max) return EXIT_OK;
    cli_error_in(o->cmd,
                 "the paths passed --paths-max (%llu bytes) at pixel %d,%d: %llu bytes, %ld "
                 "paths; nothing is written (narrow --path or the pixels, or raise --paths-max)",
                 (unsigned long long)o->max, x, y, (unsigned long long)n, o->paths);
    return EXIT_INPUT;
}

int dbg_paths_pixel(dbg_paths_out *o, const ggPathExpr *e, const ggTrace *tr, int x, int y,
                    ggColor px)
{
    ggLedger *l = NULL;
    unsigned char *m = NULL;
    ggPathSummary sum;
    ggError err;
    size_t i;
    int rc = ggLedgerCreate(tr, px, NULL, &l, &err);
    if (rc == GG_ERROR_INVALID) return EXIT_OK; /* an empty trace: no paths */
    if (rc == GG_OK && !(m = calloc(l->count ? l->count : 1, 1))) rc = GG_ERROR_NOMEM;
    if (rc == GG_OK) rc = ggPathMatch(e, tr, x, y, px, l, m, &sum);
    for (i = 0; rc == GG_OK && i < l->count; i++)
        if (m[i] && write_term(o, tr, x, y, &l->terms[i]) != 0) rc = GG_ERROR_NOMEM;
    free(m);
    ggLedgerFree(l);
    if (rc != GG_OK) {
        cli_error_in(o->cmd, "out of memory writing the paths");
        return EXIT_INPUT;
    }
    return over_max(o, x, y);
}

int dbg_paths_close(dbg_paths_out *o)
{
    int rc = 0, r2 = 0;
    if (o->have_jsonl) rc = cli_out_close(&o->jsonl, o->cmd);
    if (o->have_obj) r2 = cli_out_close(&o->obj, o->cmd);
    o->have_jsonl = o->have_obj = 0;
    return rc ? rc : r2;
}

void dbg_paths_abandon(dbg_paths_out *o)
{
    if (o->have_jsonl) fclose(o->jsonl.f), remove(o->jsonl.tmp);
    if (o->have_obj) fclose(o->obj.f), remove(o->obj.tmp);
    o->have_jsonl = o->have_obj = 0;
}
