/* SPDX-License-Identifier: MIT */
/*
** trace_debug.c -- `ggrt trace --ledger` (a pixel's colour term by term)
** and `ggrt trace --diff` (two trees of one pixel side by side).
*/
#include "debug/debug.h"
#include "trace/trace_view.h"

#include <string.h>

/* "sphere #2 (glass.nff:29)" */
static void object_name(const trace_view *v, int obj, char *buf, size_t n)
{
    int line = ggSceneObjectLine(v->scene, obj);
    const char *kind = ggShapeKindName(ggSceneObjectKind(v->scene, obj));
    if (line > 0)
        snprintf(buf, n, "%s #%d (%s:%d)", kind, obj, v->path, line);
    else
        snprintf(buf, n, "%s #%d", kind, obj);
}

/* What a term is, in words: "background seen through eye > refract",
   "light 1 diffuse on sphere #2 (f.nff:9) via eye > reflect". */
static void term_text(const trace_view *v, const ggLedgerTerm *t, char *buf, size_t n)
{
    const ggTraceNode *nd = ggTraceGetNode(v->trace, (size_t)t->node);
    char path[400], obj[300];
    dbg_path(path, sizeof path, v->trace, t->node);
    if (t->kind == GG_TERM_BACKGROUND) {
        snprintf(buf, n, "background seen through %s (ray #%d)", path, t->node);
        return;
    }
    object_name(v, nd->object, obj, sizeof obj);
    if (t->kind == GG_TERM_DIFFUSE || t->kind == GG_TERM_PHONG)
        snprintf(buf, n, "light %d %s on %s via %s (ray #%d)", t->light, ggTermName(t->kind), obj,
                 path, t->node);
    else
        snprintf(buf, n, "%s of %s via %s (ray #%d)", ggTermName(t->kind), obj, path, t->node);
}

void trace_print_ledger(FILE *f, const trace_view *v, size_t max)
{
    const ggLedger *l = v->ledger;
    size_t i, shown = max && max < l->count ? max : l->count;
    char text[800], cb[CLI_COLOR_LEN];
    ggColor rest = {0, 0, 0};
    double rest_share = 0;
    fprintf(f, "ledger: %zu term%s that add light, largest share first\n", l->count,
            l->count == 1 ? "" : "s");
    for (i = 0; i < shown; i++) {
        const ggLedgerTerm *t = &l->terms[i];
        term_text(v, t, text, sizeof text);
        fprintf(f, "  %6.2f%%  (%s)  %s\n", 100 * t->share, cli_color(cb, sizeof cb, 6, t->value),
                text);
    }
    for (; i < l->count; i++) {
        rest.r += l->terms[i].value.r, rest.g += l->terms[i].value.g;
        rest.b += l->terms[i].value.b, rest_share += l->terms[i].share;
    }
    if (shown < l->count)
        fprintf(f, "  %6.2f%%  (%s)  %zu more terms (--format json lists them all)\n",
                100 * rest_share, cli_color(cb, sizeof cb, 6, rest), l->count - shown);
    fprintf(f, "sum of the terms %s\n", cli_color(cb, sizeof cb, 9, l->sum));
    fprintf(f, "the pixel        %s\n", cli_color(cb, sizeof cb, 9, l->pixel));
    {
        char bb[CLI_COLOR_LEN];
        ggColor d;
        d.r = l->sum.r - l->pixel.r, d.g = l->sum.g - l->pixel.g, d.b = l->sum.b - l->pixel.b;
        fprintf(f, "difference %s, within the rounding bound %s: %s\n",
                cli_color(cb, sizeof cb, 3, d), cli_color(bb, sizeof bb, 3, l->bound),
                l->holds ? "yes" : "NO");
    }
}

/* ---- two trees side by side ---- */

#define COL 58

typedef struct kids {
    int refr[3], mirror;
} kids;

/* One side's tree and its children, found once (trace_kids). */
typedef struct side {
    const ggTrace *t;
    trace_kids kids;
} side;

/* A node has a mirror ray and up to three refracted channels; the rest
   of 64 is room. */
static void children(const side *s, int i, kids *k)
{
    int all[64], n, j;
    k->refr[0] = k->refr[1] = k->refr[2] = k->mirror = -1;
    if (i < 0) return;
    n = trace_children(&s->kids, s->t, i, all, 64);
    for (j = 0; j < n; j++) {
        const ggTraceNode *c = ggTraceGetNode(s->t, (size_t)all[j]);
        if (c->kind == GG_RAY_REFRACT)
            k->refr[c->channel < 0 ? 0 : c->channel] = all[j];
        else
            k->mirror = all[j];
    }
}

/* One ray in a column: "refract #1 hit #2 front  v v (0.56 0.65 0.84)". */
static void cell(char *buf, size_t n, const ggTrace *t, int i, int indent)
{
    const ggTraceNode *nd;
    size_t k;
    int l;
    if (i < 0) {
        snprintf(buf, n, "%*s(no such ray)", 2 * indent, "");
        return;
    }
    nd = ggTraceGetNode(t, (size_t)i);
    k = (size_t)snprintf(buf, n, "%*s%s #%d ", 2 * indent, "", ggRayKindName(nd->kind), i);
    if (k < n && nd->hit)
        k += (size_t)snprintf(buf + k, n - k, "hit #%d %s", nd->object,
                              nd->front ? "front" : "back");
    else if (k < n)
        k += (size_t)snprintf(buf + k, n - k, "miss");
    for (l = 0; nd->hit && l < nd->nlights && k < n; l++) {
        const ggTraceLight *L = ggTraceGetLight(t, (size_t)(nd->first_light + l));
        static const char v[] = "vbaf"; /* visible blocked attenuated facing-away */
        k += (size_t)snprintf(buf + k, n - k, "%s%c", l ? "" : " L:", v[L->verdict & 3]);
    }
    if (k < n) {
        char cb[CLI_COLOR_LEN];
        snprintf(buf + k, n - k, " (%s)", cli_color(cb, sizeof cb, 4, nd->color));
    }
}

static void rows(FILE *f, const side *a, int ia, const side *b, int ib, int indent,
                 const ggDivergence *d)
{
    char ca[256], cb[256];
    kids ka, kb;
    int c, mark = (ia >= 0 && ia == d->node_a) || (ib >= 0 && ib == d->node_b);
    cell(ca, sizeof ca, a->t, ia, indent);
    cell(cb, sizeof cb, b->t, ib, indent);
    fprintf(f, "%s %-*.*s | %-.*s\n", mark ? ">>" : "  ", COL, COL, ca, COL, cb);
    children(a, ia, &ka);
    children(b, ib, &kb);
    for (c = 0; c < 3; c++)
        if (ka.refr[c] >= 0 || kb.refr[c] >= 0)
            rows(f, a, ka.refr[c], b, kb.refr[c], indent + 1, d);
    if (ka.mirror >= 0 || kb.mirror >= 0) rows(f, a, ka.mirror, b, kb.mirror, indent + 1, d);
}

void trace_print_diff(FILE *f, const trace_view *a, const trace_view *b, const char *name_a,
                      const char *name_b)
{
    ggDivergence d;
    char text[800], cb[CLI_COLOR_LEN];
    size_t i, j, na = ggTraceNodeCount(a->trace), nb = ggTraceNodeCount(b->trace);
    int differ = ggTraceCompare(a->trace, b->trace, &d);
    side sa, sb;
    fprintf(f, "pixel %d,%d", a->x, a->y);
    if (a->sample >= 0) fprintf(f, ", sample %d", a->sample);
    fprintf(f, "\na: %s\n   colour %s\n", name_a, cli_color(cb, sizeof cb, 9, a->pixel));
    fprintf(f, "b: %s\n   colour %s\n", name_b, cli_color(cb, sizeof cb, 9, b->pixel));
    dbg_divergence_text(text, sizeof text, a->trace, b->trace, &d);
    fprintf(f, "%s%s\n\n", differ ? "first divergence (>>): " : "", text);
    fprintf(f, "   %-*s | %s\n", COL, "a", "b");
    /* without memory for an index, trace_children scans */
    sa.t = a->trace, sb.t = b->trace;
    (void)trace_kids_make(&sa.kids, a->trace), (void)trace_kids_make(&sb.kids, b->trace);
    for (i = 0, j = 0; i < na || j < nb;) {
        /* the roots in order, sample by sample */
        while (i < na && ggTraceGetNode(a->trace, i)->parent >= 0) i++;
        while (j < nb && ggTraceGetNode(b->trace, j)->parent >= 0) j++;
        if (i >= na && j >= nb) break;
        rows(f, &sa, i < na ? (int)i : -1, &sb, j < nb ? (int)j : -1, 0, &d);
        i++, j++;
    }
    trace_kids_free(&sa.kids), trace_kids_free(&sb.kids);
    fprintf(f, "\nL: the shadow ray of each light: v visible, b blocked, a attenuated, f facing "
               "away\n");
}

/* ---- the paths an expression matches ---- */

void trace_print_paths(FILE *f, const trace_view *v, const char *expr, const unsigned char *matched,
                       const ggPathSummary *sum)
{
    const ggLedger *l = v->ledger;
    size_t i;
    char text[800], events[600], cb[CLI_COLOR_LEN];
    fprintf(f, "pixel %d,%d of %s\ncolour %s\n", v->x, v->y, v->path,
            cli_color(cb, sizeof cb, 9, v->pixel));
    fprintf(f, "paths matching %s: %ld of %ld, carrying %s (%.2f%% of the pixel)\n", expr,
            sum->matched, sum->paths, cli_color(cb, sizeof cb, 6, sum->value), 100 * sum->share);
    for (i = 0; i < l->count; i++) {
        const ggLedgerTerm *t = &l->terms[i];
        if (!matched[i]) continue;
        ggPathFormat(v->trace, t, events, sizeof events);
        term_text(v, t, text, sizeof text);
        fprintf(f, "  %6.2f%%  (%s)  %s\n           %s\n", 100 * t->share,
                cli_color(cb, sizeof cb, 6, t->value), events, text);
    }
}

void trace_print_paths_json(FILE *f, const trace_view *v, const char *expr,
                            const unsigned char *matched, const ggPathSummary *sum)
{
    const ggLedger *l = v->ledger;
    size_t i;
    int first = 1;
    char events[600];
    fprintf(f, "{\"ggrt_paths\":1,\"scene\":");
    json_str(f, v->path);
    fprintf(f, ",\"pixel\":[%d,%d],", v->x, v->y);
    json_color(f, "color", v->pixel);
    fprintf(f, ",\"expression\":");
    json_str(f, expr);
    fprintf(f, ",\"paths\":%ld,\"matched\":%ld,", sum->paths, sum->matched);
    json_color(f, "value", sum->value);
    fprintf(f, ",\"share\":");
    json_num(f, sum->share);
    fprintf(f, ",\"terms\":[");
    for (i = 0; i < l->count; i++) {
        const ggLedgerTerm *t = &l->terms[i];
        if (!matched[i]) continue;
        ggPathFormat(v->trace, t, events, sizeof events);
        fprintf(f, "%s{\"kind\":\"%s\",\"node\":%d,\"light\":%d,\"events\":", first ? "" : ",",
                ggTermName(t->kind), t->node, t->light);
        json_str(f, events);
        fputc(',', f), json_color(f, "value", t->value);
        fprintf(f, ",\"share\":");
        json_num(f, t->share);
        fputc('}', f);
        first = 0;
    }
    fprintf(f, "]}\n");
}
