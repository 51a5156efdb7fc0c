/* SPDX-License-Identifier: MIT */
/*
** report_merge.c -- `ggrt merge --reports PART.json... -o REPORT.json`:
** the JSON reports of find, check and diff --tile joined into the report
** one process writes for the whole image (docs/cluster.md). Counts add;
** lists in row order (matches, moves) are joined in tile order and cut
** to the command's limit; lists of the worst pixels are merged in the
** library's own order (lib/debug/check.c, diff.c: the larger measure
** first, then row order), a total order, so the merged list is the one a
** single scan keeps. Values are copied as the tiles wrote them.
*/
#include "render/jdom.h"
#include "render/tile.h"
#include "common/json.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#define REPORT_MAX_BYTES (256L << 20)

typedef struct report {
    const char *path;
    char *text;
    jnode root;
    const jnode *tile;
    int index;
} report;

/* The manifest's fields compared between tiles, and their names in
   messages. */
static const char *const same_keys[] = {"version", "buildId", "sceneHash", "options",
                                        "cut",     "params",  NULL};
static const char *const same_what[] = {"ggrt version",   "ggrt build", "scene (hash)",
                                        "render options", "cut",        "command options"};
/* Report members merged (the others must be equal in every tile, but the
   scene paths, as given, and the options: the manifest compares options
   and options_a without -j, same_b options_b). */
static const char *const merged[] = {
    "window",    "scanned", "matched", "checked",    "value_differ",     "tree_differ",
    "moved",     "stats",   "stats_a", "stats_b",    "first_divergence", "traced",
    "max_delta", "share",   "failed",  "invariants", "matches",          "worst",
    "moves",     "scene",   "scene_a", "scene_b",    "options",          "options_a",
    "options_b", "tile",    NULL};

static int is_merged(const jnode *m)
{
    int k;
    for (k = 0; merged[k]; k++)
        if ((size_t)m->keylen == strlen(merged[k]) &&
            !memcmp(jdom_key(m), merged[k], strlen(merged[k])))
            return 1;
    return 0;
}

static int load(report *r)
{
    char why[200];
    size_t got;
    int k, rc = cli_read_text(r->path, REPORT_MAX_BYTES, &r->text, &got);
    if (rc == CLI_READ_IO || rc == CLI_READ_NOTFILE) {
        cli_error("%s: %s", r->path, rc == CLI_READ_IO ? strerror(errno) : "not a regular file");
        return EXIT_IO;
    }
    if (rc) {
        cli_error("%s: %s", r->path, rc == CLI_READ_LARGE ? "larger than 256 MiB" : "out of memory");
        return EXIT_INPUT;
    }
    why[0] = '\0';
    if (jdom_parse(r->text, &r->root, why, sizeof why) != 0 || r->root.type != 'o' || !r->root.n) {
        cli_error("%s: not a JSON report: %s", r->path,
                  why[0]                ? why
                  : r->root.type != 'o' ? "not an object"
                                        : "an empty object");
        return EXIT_INPUT;
    }
    if (!(r->tile = jdom_get(&r->root, "tile")) || r->tile->type != 'o') {
        cli_error("%s: not a tile's report: no \"tile\" manifest (find, check or diff --tile)",
                  r->path);
        return EXIT_INPUT;
    }
    /* A report of a ggrt from before the build id: which build it is
       cannot be told, so it cannot be trusted to match. */
    if (jdom_get(r->tile, "version") && !jdom_get(r->tile, "buildId")) {
        cli_error("%s: a tile's report of an older ggrt: no \"buildId\" in its manifest (run it "
                  "again with this one)",
                  r->path);
        return EXIT_INPUT;
    }
    for (k = 0; same_keys[k]; k++)
        if (!jdom_get(r->tile, same_keys[k]) || jdom_get(r->tile, same_keys[k])->type != 's') {
            cli_error("%s: the tile manifest has no \"%s\" string", r->path, same_keys[k]);
            return EXIT_INPUT;
        }
    return EXIT_OK;
}

/* diff's options_b, which no manifest field holds, read back as options
   and compared without their threads (-j changes no pixel). 1 if equal,
   0 if not or if one does not parse. */
static int same_b(const jnode *x, const jnode *y)
{
    char tx[1024], ty[1024];
    ggRenderOptions ox, oy;
    ggError err;
    if (!x || !y) return !x && !y;
    if (jdom_str(x, tx, sizeof tx) != 0 || jdom_str(y, ty, sizeof ty) != 0) return 0;
    ggRenderOptionsDefault(&ox), ggRenderOptionsDefault(&oy);
    if (ggRenderOptionsParse(&ox, tx, &err) != GG_OK ||
        ggRenderOptionsParse(&oy, ty, &err) != GG_OK)
        return 0;
    ox.threads = oy.threads = 0;
    ggRenderOptionsFormat(&ox, tx, sizeof tx);
    ggRenderOptionsFormat(&oy, ty, sizeof ty);
    return strcmp(tx, ty) == 0;
}

/* The first member names the kind: ggrt_find, ggrt_check, ggrt_diff. */
static int check_against(const report *r, const report *ref)
{
    const jnode *a = &r->root.kid[0], *b = &ref->root.kid[0];
    int k, i;
    if (a->keylen != b->keylen || memcmp(jdom_key(a), jdom_key(b), a->keylen)) {
        cli_error("%s: a %.*s report, not %.*s as %s", r->path, (int)a->keylen, jdom_key(a),
                  (int)b->keylen, jdom_key(b), ref->path);
        return EXIT_INPUT;
    }
    for (k = 0; same_keys[k]; k++) {
        const jnode *x = jdom_get(r->tile, same_keys[k]), *y = jdom_get(ref->tile, same_keys[k]);
        if (!x || !jdom_same(x, y)) {
            char tx[1024], ty[1024], d[1024];
            /* option texts: only the settings that differ */
            if (x && (!strcmp(same_keys[k], "options") || !strcmp(same_keys[k], "params")) &&
                jdom_str(x, tx, sizeof tx) == 0 && jdom_str(y, ty, sizeof ty) == 0) {
                cli_render_text_diff(tx, ty, d, sizeof d);
                cli_error("%s: different %s from %s: %s", r->path, same_what[k], ref->path, d);
                return EXIT_INPUT;
            }
            cli_error("%s: different %s from %s: %.*s, not %.*s", r->path, same_what[k], ref->path,
                      x ? (int)x->len : 4, x ? x->s : "none", (int)y->len, y->s);
            return EXIT_INPUT;
        }
    }
    if (!same_b(jdom_get(&r->root, "options_b"), jdom_get(&ref->root, "options_b"))) {
        const jnode *x = jdom_get(&r->root, "options_b"), *y = jdom_get(&ref->root, "options_b");
        cli_error("%s: different \"options_b\" from %s: %.*s, not %.*s", r->path, ref->path,
                  x ? (int)x->len : 4, x ? x->s : "none", y ? (int)y->len : 4, y ? y->s : "none");
        return EXIT_INPUT;
    }
    for (i = 0; i < ref->root.n; i++) {
        const jnode *m = &ref->root.kid[i];
        char key[64];
        const jnode *x;
        snprintf(key, sizeof key, "%.*s", (int)m->keylen, jdom_key(m));
        if (is_merged(m)) continue;
        if (!(x = jdom_get(&r->root, key)) || !jdom_same(x, m)) {
            cli_error("%s: different \"%s\" from %s: %.*s, not %.*s", r->path, key, ref->path,
                      x ? (int)x->len : 4, x ? x->s : "none", (int)m->len, m->s);
            return EXIT_INPUT;
        }
    }
    return EXIT_OK;
}

/* The tile's index and its band against the cut and the report's window. */
static int check_band(report *r, const tile_cut *cut, int w, int h)
{
    const jnode *idx = jdom_get(r->tile, "index"), *win = jdom_get(&r->root, "window");
    double v = jdom_num(idx);
    int y0, y1;
    if (!idx || idx->type != 'n' || v != (int)v || v < 0 || v >= cut->n) {
        cli_error("%s: tile index is not in 0..%d", r->path, cut->n - 1);
        return EXIT_INPUT;
    }
    r->index = (int)v;
    tile_cut_rows(cut, r->index, h, &y0, &y1);
    if (!win || win->type != 'a' || win->n != 4 || jdom_num(&win->kid[0]) != 0 ||
        jdom_num(&win->kid[1]) != y0 || jdom_num(&win->kid[2]) != w ||
        jdom_num(&win->kid[3]) != y1) {
        cli_error("%s: window is not tile %d of the cut (rows %d..%d)", r->path, r->index, y0,
                  y1 - 1);
        return EXIT_INPUT;
    }
    return EXIT_OK;
}

/* Every report's manifest, then coverage: each tile once, none missing.
   On success *order lists the reports by tile index. */
static int check_reports(report *r, int nr, tile_cut *cut, int *w, int *h, report ***order)
{
    const jnode *size = jdom_get(&r[0].root, "size"), *cutn = jdom_get(r[0].tile, "cut");
    char text[TILE_MAX_PLAN * 8 + 16], why[160];
    int i, k, rc = EXIT_OK;
    if (!size || size->type != 'a' || size->n != 2 || jdom_str(cutn, text, sizeof text) != 0) {
        cli_error("%s: no size or cut", r[0].path);
        return EXIT_INPUT;
    }
    if (jdom_num(&size->kid[0]) < 1 || jdom_num(&size->kid[0]) > GG_IMAGE_MAX_DIM ||
        jdom_num(&size->kid[1]) < 1 || jdom_num(&size->kid[1]) > GG_IMAGE_MAX_DIM) {
        cli_error("%s: size is not [width,height]", r[0].path);
        return EXIT_INPUT;
    }
    *w = (int)jdom_num(&size->kid[0]), *h = (int)jdom_num(&size->kid[1]);
    if (tile_cut_parse(text, *h, cut, why, sizeof why) != 0) {
        cli_error("%s: bad cut '%.40s': %s", r[0].path, text, why);
        return EXIT_INPUT;
    }
    for (i = 0; i < nr && rc == EXIT_OK; i++)
        if ((rc = i ? check_against(&r[i], &r[0]) : EXIT_OK) == EXIT_OK)
            rc = check_band(&r[i], cut, *w, *h);
    if (rc != EXIT_OK) return rc;
    if (!(*order = calloc((size_t)cut->n, sizeof **order))) {
        cli_error("out of memory");
        return EXIT_INPUT;
    }
    for (i = 0; i < nr && rc == EXIT_OK; i++) {
        if ((*order)[r[i].index] && tile_same_file(r[i].path, (*order)[r[i].index]->path)) {
            cli_error("%s: given twice (tile %d)", r[i].path, r[i].index);
            rc = EXIT_INPUT;
        } else if ((*order)[r[i].index]) {
            cli_error("%s: tile %d again (also in %s)", r[i].path, r[i].index,
                      (*order)[r[i].index]->path);
            rc = EXIT_INPUT;
        }
        (*order)[r[i].index] = &r[i];
    }
    for (k = 0; k < cut->n && rc == EXIT_OK; k++)
        if (!(*order)[k]) {
            int y0, y1;
            tile_cut_rows(cut, k, *h, &y0, &y1);
            cli_error("tile %d of %d (rows %d..%d) is missing", k, cut->n, y0, y1 - 1);
            rc = EXIT_INPUT;
        }
    return rc;
}

/* ---- merging ---- */

typedef struct merge {
    report **t; /* by tile index */
    int n, w, h;
    long limit, worst; /* from the params: matches and moves listed, worst pixels */
} merge;

static const jnode *top(const merge *m, int i, const char *key)
{
    return jdom_get(&m->t[i]->root, key);
}

static void key_out(FILE *f, const jnode *member, int first)
{
    fprintf(f, "%s\"%.*s\":", first ? "" : ",", (int)member->keylen, jdom_key(member));
}

static long long sum_top(const merge *m, const char *key)
{
    long long s = 0;
    int i;
    for (i = 0; i < m->n; i++) s += (long long)jdom_num(top(m, i, key));
    return s;
}

/* An object of counts, member by member. */
static void sums_out(FILE *f, const merge *m, const char *key)
{
    const jnode *o = top(m, 0, key);
    int j, i;
    fputc('{', f);
    for (j = 0; o && j < o->n; j++) {
        char k[64];
        long long s = 0;
        snprintf(k, sizeof k, "%.*s", (int)o->kid[j].keylen, jdom_key(&o->kid[j]));
        for (i = 0; i < m->n; i++) s += (long long)jdom_num(jdom_get(top(m, i, key), k));
        key_out(f, &o->kid[j], j == 0);
        fprintf(f, "%lld", s);
    }
    fputc('}', f);
}

/* The largest value of a member of parents[i], as written. */
static void max_out(FILE *f, const jnode *const *parents, int n, const char *key)
{
    const jnode *best = jdom_get(parents[0], key);
    int i;
    for (i = 1; i < n; i++) {
        const jnode *v = jdom_get(parents[i], key);
        if (jdom_num(v) > jdom_num(best)) best = v;
    }
    if (best) jdom_write(f, best);
}

/* ---- ranked lists: the worst pixels ---- */

static int pixel_y(const jnode *e)
{
    const jnode *p = jdom_get(e, "pixel");
    return p && p->n == 2 ? (int)jdom_num(&p->kid[1]) : 0;
}

static int pixel_x(const jnode *e)
{
    const jnode *p = jdom_get(e, "pixel");
    return p && p->n == 2 ? (int)jdom_num(&p->kid[0]) : 0;
}

static int row_order(const jnode *a, const jnode *b)
{
    if (pixel_y(a) != pixel_y(b)) return pixel_y(a) < pixel_y(b) ? -1 : 1;
    return pixel_x(a) < pixel_x(b) ? -1 : pixel_x(a) > pixel_x(b);
}

/* lib/debug/check.c: larger value first, then row order. */
static int check_order(const void *pa, const void *pb)
{
    const jnode *a = *(const jnode *const *)pa, *b = *(const jnode *const *)pb;
    double va = jdom_num(jdom_get(a, "value")), vb = jdom_num(jdom_get(b, "value"));
    if (va != vb) return va > vb ? -1 : 1;
    return row_order(a, b);
}

static int diverged(const jnode *e)
{
    char what[32] = "";
    jdom_str(jdom_get(jdom_get(e, "first"), "what"), what, sizeof what);
    return strcmp(what, "same") != 0;
}

/* lib/debug/diff.c: larger delta first, a divergent tree before a same
   one, then row order. */
static int diff_order(const void *pa, const void *pb)
{
    const jnode *a = *(const jnode *const *)pa, *b = *(const jnode *const *)pb;
    double da = jdom_num(jdom_get(a, "delta")), db = jdom_num(jdom_get(b, "delta"));
    if (da != db) return da > db ? -1 : 1;
    if (diverged(a) != diverged(b)) return diverged(a) ? -1 : 1;
    return row_order(a, b);
}

/* The arrays lists[0..n) joined, in order (sorted by cmp, or as they come
   when cmp is NULL), the first keep of them written. */
static int list_out(FILE *f, const jnode *const *lists, int n, long keep,
                    int (*cmp)(const void *, const void *))
{
    const jnode **all;
    long total = 0, k, i;
    int t;
    for (t = 0; t < n; t++) total += lists[t] ? lists[t]->n : 0;
    if (!(all = malloc((size_t)(total ? total : 1) * sizeof *all))) return -1;
    for (t = 0, k = 0; t < n; t++)
        for (i = 0; lists[t] && i < lists[t]->n; i++) all[k++] = &lists[t]->kid[i];
    if (cmp) qsort(all, (size_t)total, sizeof *all, cmp);
    fputc('[', f);
    for (k = 0; k < total && k < keep; k++) {
        if (k) fputc(',', f);
        jdom_write(f, all[k]);
    }
    fputc(']', f);
    free(all);
    return 0;
}

/* A top-level list of every tile. */
static int top_list(FILE *f, const merge *m, const char *key, long keep,
                    int (*cmp)(const void *, const void *))
{
    const jnode **lists = malloc((size_t)m->n * sizeof *lists);
    int i, rc;
    if (!lists) return -1;
    for (i = 0; i < m->n; i++) lists[i] = top(m, i, key);
    rc = list_out(f, lists, m->n, keep, cmp);
    free(lists);
    return rc;
}

/* check's invariants, item by item; *failed counts the error-class ones
   with pixels. */
static int invariants_out(FILE *f, const merge *m, int *failed)
{
    const jnode *a0 = top(m, 0, "invariants");
    const jnode **items = malloc((size_t)m->n * sizeof *items), **wl = malloc((size_t)m->n * sizeof *wl);
    int j, i, k, rc = 0;
    if (!items || !wl) rc = -1;
    fputc('[', f);
    for (j = 0; rc == 0 && a0 && j < a0->n; j++) {
        const jnode *e0 = &a0->kid[j];
        long long pixels = 0;
        for (i = 0; i < m->n; i++) {
            const jnode *a = top(m, i, "invariants");
            items[i] = a && a->n == a0->n ? &a->kid[j] : e0;
            wl[i] = jdom_get(items[i], "worst_pixels");
            pixels += (long long)jdom_num(jdom_get(items[i], "pixels"));
        }
        fputs(j ? ",{" : "{", f);
        for (k = 0; k < e0->n; k++) {
            const jnode *mk = &e0->kid[k];
            char key[32];
            snprintf(key, sizeof key, "%.*s", (int)mk->keylen, jdom_key(mk));
            key_out(f, mk, k == 0);
            if (!strcmp(key, "pixels") || !strcmp(key, "rays")) {
                long long s = 0;
                for (i = 0; i < m->n; i++) s += (long long)jdom_num(jdom_get(items[i], key));
                fprintf(f, "%lld", s);
            } else if (!strcmp(key, "worst")) {
                max_out(f, items, m->n, key);
            } else if (!strcmp(key, "worst_pixels")) {
                rc = list_out(f, wl, m->n, GG_CHECK_WORST, check_order);
            } else {
                jdom_write(f, mk);
            }
        }
        fputc('}', f);
        {
            char sev[16] = "";
            jdom_str(jdom_get(e0, "severity"), sev, sizeof sev);
            if (!strcmp(sev, "error") && pixels > 0) ++*failed;
        }
    }
    fputc(']', f);
    free(items), free(wl);
    return rc;
}

/* check's share: the mean over the checked pixels, as ggrt serve's bands
   sum it. */
static double share_of(const merge *m)
{
    double share = 0;
    long long checked = 0;
    int i;
    for (i = 0; i < m->n; i++) {
        long long c = (long long)jdom_num(top(m, i, "checked"));
        if (checked + c > 0)
            share = (share * (double)checked + jdom_num(top(m, i, "share")) * (double)c) /
                    (double)(checked + c);
        checked += c;
    }
    return share;
}

static long param(const merge *m, const char *name, long dflt)
{
    char text[256], *p;
    size_t n = strlen(name);
    if (jdom_str(jdom_get(m->t[0]->tile, "params"), text, sizeof text) != 0) return dflt;
    for (p = text; (p = strstr(p, name)) != NULL; p += n)
        if ((p == text || p[-1] == ' ') && p[n] == '=') return strtol(p + n + 1, NULL, 10);
    return dflt;
}

/* One member of the merged report. */
static int member_out(FILE *f, const merge *m, const jnode *mk, int failed, double share)
{
    int dummy = 0;
    char key[64];
    long limit = param(m, "limit", 0);
    snprintf(key, sizeof key, "%.*s", (int)mk->keylen, jdom_key(mk));
    if (!strcmp(key, "window"))
        fprintf(f, "[0,0,%d,%d]", m->w, m->h);
    else if (!strcmp(key, "scanned") || !strcmp(key, "matched") || !strcmp(key, "checked") ||
             !strcmp(key, "value_differ") || !strcmp(key, "tree_differ") || !strcmp(key, "moved"))
        fprintf(f, "%lld", sum_top(m, key));
    else if (!strcmp(key, "stats") || !strcmp(key, "stats_a") || !strcmp(key, "stats_b") ||
             !strcmp(key, "first_divergence"))
        sums_out(f, m, key);
    else if (!strcmp(key, "traced")) {
        int i, any = 0;
        for (i = 0; i < m->n; i++) any |= top(m, i, key) && top(m, i, key)->type == 't';
        fputs(any ? "true" : "false", f);
    } else if (!strcmp(key, "max_delta")) {
        const jnode **roots = malloc((size_t)m->n * sizeof *roots);
        int i;
        if (!roots) return -1;
        for (i = 0; i < m->n; i++) roots[i] = &m->t[i]->root;
        max_out(f, roots, m->n, key);
        free(roots);
    } else if (!strcmp(key, "share"))
        json_num(f, share);
    else if (!strcmp(key, "failed"))
        fprintf(f, "%d", failed);
    else if (!strcmp(key, "invariants"))
        return invariants_out(f, m, &dummy);
    else if (!strcmp(key, "matches") || !strcmp(key, "moves"))
        return top_list(f, m, key, limit > 0 ? limit : 1L << 30, NULL);
    else if (!strcmp(key, "worst"))
        return top_list(f, m, key, param(m, "worst", 10), diff_order);
    else
        jdom_write(f, mk);
    return 0;
}

/* The merged report: the first tile's members in its order. "failed"
   comes before "invariants" in check's report, so the invariants are
   merged once into /dev/null first to count it (not a temporary file:
   a full or read-only /tmp made that fail as "out of memory"). */
static int write_merged(FILE *f, const merge *m)
{
    const jnode *r0 = &m->t[0]->root;
    int i, failed = 0, rc = 0, first = 1;
    double share = share_of(m);
    if (top(m, 0, "invariants")) {
        FILE *scratch = fopen("/dev/null", "w");
        if (!scratch) return -1;
        rc = invariants_out(scratch, m, &failed);
        fclose(scratch);
    }
    fputc('{', f);
    for (i = 0; rc == 0 && i < r0->n; i++) {
        const jnode *mk = &r0->kid[i];
        if (mk->keylen == 4 && !memcmp(jdom_key(mk), "tile", 4)) continue;
        key_out(f, mk, first);
        first = 0;
        rc = member_out(f, m, mk, failed, share);
    }
    fputs("}\n", f);
    return rc;
}

int merge_reports(const char **files, int nfiles, const char *out, int quiet)
{
    report *r = calloc((size_t)nfiles, sizeof *r), **order = NULL;
    tile_cut cut = {0, NULL};
    merge m;
    cli_out o;
    int i, rc = r ? EXIT_OK : EXIT_INPUT;
    if (!r) cli_error("out of memory");
    for (i = 0; r && i < nfiles && rc == EXIT_OK; i++) {
        r[i].path = files[i];
        rc = load(&r[i]);
    }
    if (rc == EXIT_OK) rc = check_reports(r, nfiles, &cut, &m.w, &m.h, &order);
    if (rc == EXIT_OK && (rc = cli_out_open(&o, "merge", out)) == EXIT_OK) {
        m.t = order, m.n = cut.n;
        if (write_merged(o.f, &m) != 0) {
            cli_error("out of memory");
            fclose(o.f);
            remove(o.tmp);
            rc = EXIT_INPUT;
        } else {
            rc = cli_out_close(&o, "merge");
        }
    }
    if (rc == EXIT_OK && !quiet)
        printf("%d reports of %d tiles -> %s, %dx%d\n", nfiles, cut.n, out, m.w, m.h);
    for (i = 0; r && i < nfiles; i++) {
        jdom_free(&r[i].root);
        free(r[i].text);
    }
    tile_cut_free(&cut);
    free(order);
    free(r);
    return rc;
}
