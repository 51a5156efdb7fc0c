/* SPDX-License-Identifier: MIT */
/*
** debug.c -- helpers and JSON of the debugger's commands (debug.h).
*/
#include "debug/debug.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void dbg_progress_begin(dbg_progress_state *p, const char *what, int quiet)
{
    p->what = what;
    cli_bar_begin(&p->bar, what, quiet);
    cli_cancel_begin();
}

int dbg_progress(void *ud, long done, long total)
{
    dbg_progress_state *p = ud;
    return p ? cli_bar_step(&p->bar, done, total) : cli_cancelled() != 0;
}

void dbg_progress_end(dbg_progress_state *p)
{
    int sig;
    cli_bar_end(&p->bar);
    if ((sig = cli_cancelled()) != 0) {
        cli_error_in(p->what, "cancelled by signal %d", sig);
        cli_cancel_exit(sig);
    }
}

/* A predicate's error with a caret under its column. */
int dbg_predicate_error(const char *cmd, const char *text, const ggError *err)
{
    return dbg_expr_error(cmd, "where", text, err);
}

int dbg_expr_error(const char *cmd, const char *option, const char *text, const ggError *err)
{
    int line = 0, col = 0, l;
    const char *p = text, *e;
    cli_error_in(cmd, "--%s:%s", option, err->message);
    if (sscanf(err->message, "%d:%d:", &line, &col) != 2 || line < 1 || col < 1) return EXIT_USAGE;
    for (l = 1; l < line && p; l++) p = (p = strchr(p, '\n')) ? p + 1 : NULL;
    if (!p) return EXIT_USAGE;
    e = strchr(p, '\n');
    fprintf(stderr, "  %.*s\n  %*s^\n", e ? (int)(e - p) : (int)strlen(p), p, col - 1, "");
    return EXIT_USAGE;
}

void dbg_replay(FILE *f, const char *scene, const char *scene_b, const cli_render *ro, int x, int y,
                const char *const *extra)
{
    fprintf(f, "ggrt trace");
    cli_print_file(f, scene);
    if (scene_b) cli_print_file(f, scene_b);
    cli_render_print(f, ro, CLI_RENDER_PIXEL);
    fprintf(f, " --pixel %d,%d", x, y);
    for (; extra && *extra; extra++) cli_print_arg(f, *extra);
}

void dbg_path(char *buf, size_t n, const ggTrace *t, int i)
{
    int chain[80], k = 0;
    size_t at = 0;
    buf[0] = '\0';
    while (i >= 0 && k < 80) {
        const ggTraceNode *nd = ggTraceGetNode(t, (size_t)i);
        if (!nd) break;
        chain[k++] = i;
        i = nd->parent;
    }
    while (k-- > 0 && at < n) {
        const ggTraceNode *nd = ggTraceGetNode(t, (size_t)chain[k]);
        at += (size_t)snprintf(buf + at, n - at, "%s%s", at ? " > " : "", ggRayKindName(nd->kind));
    }
}

int dbg_write_map(const char *cmd, const char *path, const unsigned char *map, int w, int h,
                  const float colour[][3], int ncolours)
{
    ggImage *img;
    ggError err;
    float *p;
    size_t i, n = (size_t)w * (size_t)h;
    int rc;
    if ((rc = cli_check_output(cmd, path)) != 0) return rc;
    if (!(img = ggImageCreate(w, h, NULL))) {
        cli_error_in(cmd, "out of memory for a %dx%d image", w, h);
        return EXIT_INPUT;
    }
    p = ggImagePixels(img);
    for (i = 0; i < n; i++) {
        int v = map[i] < ncolours ? map[i] : ncolours - 1;
        p[3 * i] = colour[v][0], p[3 * i + 1] = colour[v][1], p[3 * i + 2] = colour[v][2];
    }
    cli_cancel_hold();
    rc = ggImageWrite(img, path, &err);
    cli_cancel_release();
    ggImageFree(img);
    return rc == GG_OK ? EXIT_OK : cli_fail(rc, &err, 0);
}

/* ---- JSON ---- */

static void json_window(FILE *f, int w, int h, int x0, int y0, int x1, int y1)
{
    fprintf(f, "\"size\":[%d,%d],\"window\":[%d,%d,%d,%d]", w, h, x0, y0, x1, y1);
}

void json_find(FILE *f, const char *scene, const ggRenderOptions *opt, const char *where,
               const char *path, const ggFindResult *r)
{
    int i;
    fprintf(f, "{\"ggrt_find\":1,\"scene\":");
    json_str(f, scene);
    fputc(',', f), json_options(f, "options", opt);
    fprintf(f, ",\"where\":");
    if (where) json_str(f, where);
    else fprintf(f, "null");
    fprintf(f, ",\"path\":");
    if (path) json_str(f, path);
    else fprintf(f, "null");
    fputc(',', f), json_window(f, r->width, r->height, r->x0, r->y0, r->x1, r->y1);
    fprintf(f, ",\"scanned\":%ld,\"matched\":%ld,\"traced\":%s,", r->scanned, r->matched,
            r->traced ? "true" : "false");
    json_stats(f, "stats", &r->stats);
    fprintf(f, ",\"matches\":[");
    for (i = 0; i < r->nmatches; i++) {
        fprintf(f, "%s{\"pixel\":[%d,%d],", i ? "," : "", r->matches[i].x, r->matches[i].y);
        json_color(f, "color", r->matches[i].pixel);
        if (path) fprintf(f, ",\"share\":"), json_num(f, r->matches[i].share);
        fputc('}', f);
    }
    fprintf(f, "]}\n");
}

static void json_check_pixel(FILE *f, const ggCheckPixel *p)
{
    fprintf(f, "{\"pixel\":[%d,%d],\"value\":", p->x, p->y);
    json_num(f, p->value);
    fprintf(f, ",\"node\":%d,\"light\":%d,\"object\":%d,\"material\":%d,\"line\":%d,\"share\":",
            p->node, p->light, p->object, p->material, p->line);
    json_num(f, p->share);
    fputc('}', f);
}

void json_check(FILE *f, const char *scene, const ggRenderOptions *opt, const ggCheckResult *r)
{
    int c, k;
    fprintf(f, "{\"ggrt_check\":1,\"scene\":");
    json_str(f, scene);
    fputc(',', f), json_options(f, "options", opt);
    fputc(',', f), json_window(f, r->width, r->height, r->x0, r->y0, r->x1, r->y1);
    fprintf(f, ",\"scanned\":%ld,\"checked\":%ld,\"share\":", r->scanned, r->checked);
    json_num(f, r->share);
    fprintf(f, ",\"failed\":%d,\"radiance_bound\":", r->failed);
    json_num(f, r->radiance_bound);
    fputc(',', f), json_stats(f, "stats", &r->stats);
    fprintf(f, ",\"invariants\":[");
    for (c = 0; c < GG_CHECK_COUNT; c++) {
        const ggCheckItem *it = &r->items[c];
        fprintf(f, "%s{\"name\":\"%s\",\"severity\":\"%s\",\"pixels\":%ld,\"rays\":%ld,\"worst\":",
                c ? "," : "", ggCheckName(c), ggSeverityName(it->severity), it->pixels, it->rays);
        json_num(f, it->worst);
        fprintf(f, ",\"worst_pixels\":[");
        for (k = 0; k < it->nworst; k++) {
            if (k) fputc(',', f);
            json_check_pixel(f, &it->pixels_worst[k]);
        }
        fprintf(f, "]}");
    }
    fprintf(f, "]}\n");
}

void json_divergence(FILE *f, const ggDivergence *d)
{
    fprintf(f, "{\"what\":\"%s\",\"node_a\":%d,\"node_b\":%d,\"light\":%d,\"a\":%d,\"b\":%d}",
            ggDiffName(d->what), d->node_a, d->node_b, d->light, d->a, d->b);
}

/* ggDiffPath's moved pixels: ,"moved":N,"moves":[...] */
static void json_moves(FILE *f, const ggDiffResult *r)
{
    int i;
    fprintf(f, ",\"moved\":%ld,\"moves\":[", r->moved);
    for (i = 0; i < r->nmoves; i++) {
        const ggDiffMove *m = &r->moves[i];
        fprintf(f, "%s{\"pixel\":[%d,%d],\"share_a\":", i ? "," : "", m->x, m->y);
        json_num(f, m->share_a);
        fprintf(f, ",\"share_b\":");
        json_num(f, m->share_b);
        fprintf(f, ",\"matched_a\":%ld,\"matched_b\":%ld,\"first\":", m->matched_a,
                m->matched_b);
        json_divergence(f, &m->first);
        fputc('}', f);
    }
    fputc(']', f);
}

void json_diff(FILE *f, const char *scene_a, const char *scene_b, const ggRenderOptions *oa,
               const ggRenderOptions *ob, const ggDiffResult *r)
{
    int i;
    fprintf(f, "{\"ggrt_diff\":1,\"scene_a\":");
    json_str(f, scene_a);
    fprintf(f, ",\"scene_b\":");
    json_str(f, scene_b);
    fputc(',', f), json_options(f, "options_a", oa);
    fputc(',', f), json_options(f, "options_b", ob);
    fputc(',', f), json_window(f, r->width, r->height, r->x0, r->y0, r->x1, r->y1);
    fprintf(f,
            ",\"scanned\":%ld,\"value_differ\":%ld,\"tree_differ\":%ld,\"max_delta\":", r->scanned,
            r->value_differ, r->tree_differ);
    json_num(f, r->max_delta);
    fprintf(f, ",\"first_divergence\":{");
    for (i = 1; i < GG_DIFF_COUNT; i++)
        fprintf(f, "%s\"%s\":%ld", i > 1 ? "," : "", ggDiffName(i), r->first_by_kind[i]);
    fprintf(f, "},");
    json_stats(f, "stats_a", &r->stats_a);
    fputc(',', f), json_stats(f, "stats_b", &r->stats_b);
    fprintf(f, ",\"worst\":[");
    for (i = 0; i < r->nworst; i++) {
        const ggDiffPixel *p = &r->worst[i];
        fprintf(f, "%s{\"pixel\":[%d,%d],", i ? "," : "", p->x, p->y);
        json_color(f, "a", p->a);
        fputc(',', f), json_color(f, "b", p->b);
        fprintf(f, ",\"delta\":");
        json_num(f, p->delta);
        fprintf(f, ",\"first\":");
        json_divergence(f, &p->first);
        fputc('}', f);
    }
    fprintf(f, "]");
    if (r->by_path) json_moves(f, r);
    fprintf(f, "}\n");
}

void json_ledger(FILE *f, const ggTrace *t, const ggLedger *l)
{
    size_t i;
    char path[512];
    fprintf(f, "{");
    json_color_text(f, "sum", l->sum);
    fputc(',', f), json_color_text(f, "pixel", l->pixel);
    fputc(',', f), json_color_text(f, "bound", l->bound);
    fprintf(f, ",\"holds\":%s,\"terms\":[", l->holds ? "true" : "false");
    for (i = 0; i < l->count; i++) {
        const ggLedgerTerm *term = &l->terms[i];
        const ggTraceNode *n = ggTraceGetNode(t, (size_t)term->node);
        fprintf(f, "%s{\"kind\":\"%s\",\"node\":%d,\"light\":%d,\"object\":%d,", i ? "," : "",
                ggTermName(term->kind), term->node, term->light, n && n->hit ? n->object : -1);
        dbg_path(path, sizeof path, t, term->node);
        fprintf(f, "\"path\":");
        json_str(f, path);
        fputc(',', f), json_color_text(f, "value", term->value);
        fprintf(f, ",\"share\":");
        json_num_text(f, term->share);
        fputc('}', f);
    }
    fprintf(f, "]}");
}

void dbg_divergence_text(char *buf, size_t n, const ggTrace *ta, const ggTrace *tb,
                         const ggDivergence *d)
{
    char path[400];
    const char *va, *vb;
    int node = d->node_a >= 0 ? d->node_a : d->node_b;
    const ggTrace *t = d->node_a >= 0 ? ta : tb;
    size_t k;
    if (d->what == GG_DIFF_SAME) {
        snprintf(buf, n, "the trees agree");
        return;
    }
    if (d->what == GG_DIFF_SAMPLES) {
        snprintf(buf, n, "a has %d samples, b %d", d->a, d->b);
        return;
    }
    /* TIR and CHILD name the child that differs; say where its parent is. */
    if ((d->what == GG_DIFF_TIR || d->what == GG_DIFF_CHILD) && node >= 0 &&
        ggTraceGetNode(t, (size_t)node)->parent >= 0)
        node = ggTraceGetNode(t, (size_t)node)->parent;
    dbg_path(path, sizeof path, t, node);
    k = (size_t)snprintf(buf, n, "ray #%d (%s): ", node, path);
    if (k >= n) return;
    buf += k, n -= k;
    switch (d->what) {
    case GG_DIFF_HIT:
        if (d->a >= 0)
            snprintf(buf, n, "a hits object #%d, b leaves the scene", d->a);
        else
            snprintf(buf, n, "a leaves the scene, b hits object #%d", d->b);
        break;
    case GG_DIFF_OBJECT:
        snprintf(buf, n, "a hits object #%d, b object #%d", d->a, d->b);
        break;
    case GG_DIFF_FACE:
        snprintf(buf, n, "a hits the %s face, b the %s", d->a ? "front" : "back",
                 d->b ? "front" : "back");
        break;
    case GG_DIFF_TIR:
        snprintf(buf, n, "%s",
                 d->a == GG_RAY_REFRACT || d->b == GG_RAY_TIR
                     ? "a refracts, b reflects totally (TIR)"
                     : "a reflects totally (TIR), b refracts");
        break;
    case GG_DIFF_SHADOW:
        va = d->a >= 0 ? ggShadowName(d->a) : "no shadow ray";
        vb = d->b >= 0 ? ggShadowName(d->b) : "no shadow ray";
        snprintf(buf, n, "light %d is %s in a, %s in b", d->light, va, vb);
        break;
    case GG_DIFF_OCCLUDER:
        snprintf(buf, n, "light %d is stopped by object #%d in a, #%d in b", d->light, d->a, d->b);
        break;
    case GG_DIFF_CHILD:
        snprintf(buf, n, "a %s%s ray, b %s%s", d->a >= 0 ? "casts a " : "casts no such",
                 d->a >= 0 ? ggRayKindName(d->a) : "", d->b >= 0 ? "casts a " : "none",
                 d->b >= 0 ? ggRayKindName(d->b) : "");
        break;
    default: {
        static const char *const why[] = {"goes on", "leaves the scene", "stops at the depth limit",
                                          "stops (matte)", "stops (ray budget)"};
        snprintf(buf, n, "a %s, b %s", d->a >= 0 && d->a < 5 ? why[d->a] : ggStopName(d->a),
                 d->b >= 0 && d->b < 5 ? why[d->b] : ggStopName(d->b));
        break;
    }
    }
}

void dbg_warn_same_sides(int nscenes, const ggRenderOptions *oa, const ggRenderOptions *ob)
{
    char ta[512], tb[512];
    if (nscenes > 1) return;
    ggRenderOptionsFormat(oa, ta, sizeof ta);
    ggRenderOptionsFormat(ob, tb, sizeof tb);
    if (strcmp(ta, tb)) return;
    cli_warn("both sides render with the same options (%s%s%s), so nothing can differ: "
             "--a and --b set one side each; -a (--accuracy) sets both",
             *ta ? "'" : "the defaults", ta, *ta ? "'" : "");
}
