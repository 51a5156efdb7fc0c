/* SPDX-License-Identifier: MIT */
/*
** trace_text.c -- a recorded ray tree as an indented tree and as JSON.
*/
#include "trace/trace_view.h"
#include "debug/debug.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_KIDS 64

/* ---- children ----

   Found once per tree: a scan of the later nodes for each node made a tree
   of n rays cost n^2 steps (65536 rays: 8 s as text, 11 s as JSON). The
   counts go to first[p + 1], their running sums make first[p] where p's
   run starts, placing a child advances first[p] to the next run's start,
   and the shift back restores it. */
int trace_kids_make(trace_kids *k, const ggTrace *t)
{
    size_t n = ggTraceNodeCount(t), j;
    k->first = calloc(n + 1, sizeof *k->first);
    k->kid = malloc((n ? n : 1) * sizeof *k->kid);
    if (!k->first || !k->kid) {
        trace_kids_free(k);
        return -1;
    }
    /* a child comes after its parent, as the scan this replaces saw it */
    for (j = 0; j < n; j++) {
        int p = ggTraceGetNode(t, j)->parent;
        if (p >= 0 && (size_t)p < j) k->first[p + 1]++;
    }
    for (j = 0; j < n; j++) k->first[j + 1] += k->first[j];
    for (j = 0; j < n; j++) {
        int p = ggTraceGetNode(t, j)->parent;
        if (p >= 0 && (size_t)p < j) k->kid[k->first[p]++] = (int)j;
    }
    for (j = n; j > 0; j--) k->first[j] = k->first[j - 1];
    k->first[0] = 0;
    return 0;
}

void trace_kids_free(trace_kids *k)
{
    free(k->first), free(k->kid);
    k->first = k->kid = NULL;
}

int trace_children(const trace_kids *k, const ggTrace *t, int i, int *kids, int max)
{
    size_t j, n = ggTraceNodeCount(t);
    int c = 0;
    if (k && k->first) {
        for (j = (size_t)k->first[i]; j < (size_t)k->first[i + 1] && c < max; j++)
            kids[c++] = k->kid[j];
        return c;
    }
    for (j = (size_t)(i + 1); j < n; j++)
        if (ggTraceGetNode(t, j)->parent == i && c < max) kids[c++] = (int)j;
    return c;
}

static const char *medium_name(const ggScene *s, int medium, char *buf, size_t n)
{
    (void)s;
    if (medium < 0) return "outside";
    snprintf(buf, n, "material %d", medium);
    return buf;
}

static void object_name(const trace_view *v, int obj, char *buf, size_t n)
{
    int line = ggSceneObjectLine(v->scene, obj);
    if (line > 0)
        snprintf(buf, n, "%s #%d (%s:%d)", ggShapeKindName(ggSceneObjectKind(v->scene, obj)), obj,
                 v->path, line);
    else
        snprintf(buf, n, "%s #%d", ggShapeKindName(ggSceneObjectKind(v->scene, obj)), obj);
}

/* %.<p>g, with every NaN as "nan" (glibc prints a negative one "-nan";
   the JSON and the page say "nan"). */
static void pnum(FILE *f, int p, double d)
{
    if (isnan(d)) fputs("nan", f);
    else fprintf(f, "%.*g", p, d);
}
static void pcol(FILE *f, ggColor c)
{
    fputc('(', f), pnum(f, 4, c.r), fputc(' ', f), pnum(f, 4, c.g), fputc(' ', f);
    pnum(f, 4, c.b), fputc(')', f);
}
static void pvec(FILE *f, ggVec3 p)
{
    fputc('(', f), pnum(f, 6, p.x), fputs(", ", f), pnum(f, 6, p.y), fputs(", ", f);
    pnum(f, 6, p.z), fputc(')', f);
}

/* ---- a ray's weight in the pixel and its share ----

   A node's colour enters its parent's as parent absorption * factor *
   colour, and the pixel is the mean of its trees: a ray's weight in the
   pixel is 1/trees times the factors and absorptions above it, the same
   products in the same order as the library's (lib/debug/tree.c), so the
   same bits as find's `weight`. Its contribution is weight * colour (0
   where the weight is 0, as the renderer adds nothing there), and its
   share that contribution's r+g+b over the reference's: the pixel when
   every sample is recorded, else the mean of the recorded trees -- the
   ledger's measure (lib/debug/ledger.c), 0 where the reference is 0 or
   not finite. */

static int root_count(const ggTrace *t)
{
    size_t i, n = ggTraceNodeCount(t);
    int k = 0;
    for (i = 0; i < n; i++) k += ggTraceGetNode(t, i)->parent < 0;
    return k > 0 ? k : 1;
}

/* The weight of node n whose parent has weight wp (NULL: a root), in a
   tree of `roots` trees (root_count). */
static ggColor node_weight(const ggTrace *t, int roots, const ggTraceNode *n, const ggColor *wp)
{
    ggColor w;
    if (!wp || n->parent < 0) {
        w.r = w.g = w.b = 1.0 / roots;
    } else {
        const ggTraceNode *up = ggTraceGetNode(t, (size_t)n->parent);
        w.r = wp->r * up->absorption.r * n->weight.r;
        w.g = wp->g * up->absorption.g * n->weight.g;
        w.b = wp->b * up->absorption.b * n->weight.b;
    }
    return w;
}

static double part(double w, double c) { return w == 0 ? 0 : w * c; }

/* r+g+b of the reference the shares are of. */
static double share_base(const trace_view *v)
{
    size_t i, n = ggTraceNodeCount(v->trace);
    double s = 0;
    if (v->sample < 0) return (double)v->pixel.r + v->pixel.g + v->pixel.b;
    for (i = 0; i < n; i++) {
        const ggTraceNode *r = ggTraceGetNode(v->trace, i);
        if (r->parent < 0) s += r->color.r + r->color.g + r->color.b;
    }
    return s / root_count(v->trace);
}

static ggColor contribution(ggColor w, ggColor c)
{
    ggColor o;
    o.r = part(w.r, c.r), o.g = part(w.g, c.g), o.b = part(w.b, c.b);
    return o;
}

static double share_of(ggColor c, double base)
{
    return base != 0 && isfinite(base) ? (c.r + c.g + c.b) / base : 0;
}

/* The ray's traversal cost, when recorded. */
static void print_cost(FILE *f, const ggTraceNode *n)
{
    if (n->nodes >= 0) fprintf(f, ", traversal %ld nodes %ld prims", n->nodes, n->prims);
}

/* The hit's numeric state on one line: error bound, offset, TIR margin
   and edge distance where they apply, and the traversal's cost. */
static void print_numeric(FILE *f, const char *body, const ggTraceNode *n)
{
    fprintf(f, "\n%s    numeric: perr %.2g, offset %.2g", body, n->perr, n->offset);
    if (isfinite(n->tir_margin)) fprintf(f, ", tir margin %+.3g", n->tir_margin);
    if (isfinite(n->edge)) fprintf(f, ", edge %.3g", n->edge);
    print_cost(f, n);
}

typedef struct glyphs {
    const char *tee, *last, *pipe, *blank;
} glyphs;

/* What every node of a tree is printed with, worked out once per tree
   (each is a pass over the nodes). */
typedef struct tree {
    const trace_view *v;
    const glyphs *g; /* text only */
    trace_kids kids;
    double base; /* share_base */
    int roots;   /* root_count */
} tree;

static void tree_begin(tree *t, const trace_view *v, const glyphs *g)
{
    t->v = v, t->g = g, t->base = share_base(v), t->roots = root_count(v->trace);
    (void)trace_kids_make(&t->kids, v->trace); /* without memory, trace_children scans */
}

/* One light of a hit: its verdict, what blocked or dimmed it, its terms. */
static void print_light(FILE *f, const trace_view *v, const char *body, const ggTraceLight *L)
{
    char name[256];
    fprintf(f, "%s    light %d: %s", body, L->light, ggShadowName(L->verdict));
    if (L->occluder >= 0) {
        /* a visible light's occluder is a transparent object it crossed
           without losing anything */
        object_name(v, L->occluder, name, sizeof name);
        fprintf(f, " %s %s at t %.4g", L->verdict == GG_SHADOW_VISIBLE ? "through" : "by", name,
                L->t_block);
    }
    if (L->verdict == GG_SHADOW_ATTENUATED) {
        fprintf(f, ", transmittance ");
        pcol(f, L->transmittance);
    }
    if (L->verdict == GG_SHADOW_VISIBLE || L->verdict == GG_SHADOW_ATTENUATED) {
        fprintf(f, "  diffuse ");
        pcol(f, L->diffuse);
        if (L->phong.r != 0 || L->phong.g != 0 || L->phong.b != 0) {
            fprintf(f, " phong ");
            pcol(f, L->phong);
        }
    }
    fprintf(f, "\n");
}

/* A node's hit: where, the surface, the material, the lights, Fresnel,
   why it stops. */
static void print_hit(FILE *f, const trace_view *v, const char *body, const ggTraceNode *n)
{
    ggMaterial m = ggSceneMaterial(v->scene, n->material);
    char name[256];
    int l;
    object_name(v, n->object, name, sizeof name);
    fprintf(f, "%shit %s at t %.6g, %s face\n", body, name, n->t, n->front ? "front" : "back");
    if (cli_face_text(v->scene, n->object, n->triangle, name, sizeof name))
        fprintf(f, "%s    %s\n", body, name);
    fprintf(f, "%s    p ", body);
    pvec(f, n->p);
    fprintf(f, "  uv (%.4g, %.4g)\n%s    ng ", n->u, n->v, body);
    pvec(f, n->ng);
    fprintf(f, "  ns ");
    pvec(f, n->ns);
    if (!v->hide_numeric) print_numeric(f, body, n);
    fprintf(f, "\n%s    material %d: kd %g ks %g kt %g ior %g, surface colour ", body, n->material,
            m.kd, m.ks, m.kt, m.ior);
    pcol(f, n->surface);
    fprintf(f, "\n%s    ambient ", body);
    pcol(f, n->ambient);
    if (n->emission.r != 0 || n->emission.g != 0 || n->emission.b != 0) {
        fprintf(f, "  emission ");
        pcol(f, n->emission);
    }
    fprintf(f, "\n");
    for (l = 0; l < n->nlights; l++)
        print_light(f, v, body, ggTraceGetLight(v->trace, (size_t)(n->first_light + l)));
    if (n->fresnel >= 0)
        fprintf(f, "%s    fresnel R %.6g, T %.6g (n %g -> %g)\n", body, n->fresnel, 1 - n->fresnel,
                n->n_medium, n->n_other);
    if (n->stop != GG_STOP_NONE)
        fprintf(f, "%s    stops: %s\n", body,
                n->stop == GG_STOP_DEPTH    ? "depth limit reached"
                : n->stop == GG_STOP_MATTE  ? "no ks or kt: no secondary rays"
                : n->stop == GG_STOP_BUDGET ? "the eye ray's ray budget is used up"
                                            : ggStopName(n->stop));
}

static void print_node(FILE *f, const tree *t, int i, const ggColor *wp, const char *prefix,
                       const char *branch, const char *cont)
{
    const trace_view *v = t->v;
    const glyphs *g = t->g;
    const ggTraceNode *n = ggTraceGetNode(v->trace, (size_t)i);
    ggColor w = node_weight(v->trace, t->roots, n, wp);
    int kids[MAX_KIDS], nk = trace_children(&t->kids, v->trace, i, kids, MAX_KIDS), k;
    char body[512], next[512], med[64];
    const char *chan[] = {"red", "green", "blue"};

    /* Header: kind, weight in the pixel, share of it, factor. */
    fprintf(f, "%s%s%s", prefix, branch, ggRayKindName(n->kind));
    if (n->channel >= 0) fprintf(f, " [%s]", chan[n->channel]);
    fprintf(f, " #%d depth %d  weight ", i, n->depth);
    pcol(f, w);
    fprintf(f, "  share ");
    pnum(f, 3, 100 * share_of(contribution(w, n->color), t->base));
    fputc('%', f);
    if (n->parent >= 0) {
        fprintf(f, "  factor ");
        pcol(f, n->weight);
    }
    fprintf(f, "\n");
    snprintf(body, sizeof body, "%s%s%s", prefix, cont, nk ? g->pipe : g->blank);
    fprintf(f, "%sray o ", body);
    pvec(f, n->o);
    fprintf(f, " d ");
    pvec(f, n->d);
    fprintf(f, " in %s (n %.6g)\n", medium_name(v->scene, n->medium, med, sizeof med),
            n->n_medium);
    if (!n->hit) {
        fprintf(f, "%smissed: background", body);
        if (!v->hide_numeric) print_cost(f, n);
        fputc('\n', f);
    } else
        print_hit(f, v, body, n);
    if (n->absorption.r != 1 || n->absorption.g != 1 || n->absorption.b != 1) {
        fprintf(f, "%sabsorption over the segment ", body);
        pcol(f, n->absorption);
        fprintf(f, "\n");
    }
    fprintf(f, "%sreturns ", body);
    pcol(f, n->color);
    fprintf(f, "\n");
    snprintf(next, sizeof next, "%s%s", prefix, cont);
    for (k = 0; k < nk; k++) {
        int last = k == nk - 1;
        print_node(f, t, kids[k], &w, next, last ? g->last : g->tee, last ? "   " : g->pipe);
    }
}

void trace_print_text(FILE *f, const trace_view *v, int utf8)
{
    static const glyphs uni = {"\xe2\x94\x9c\xe2\x94\x80 ", "\xe2\x94\x94\xe2\x94\x80 ",
                               "\xe2\x94\x82  ", "   "};
    static const glyphs asc = {"+- ", "`- ", "|  ", "   "};
    size_t i, n = ggTraceNodeCount(v->trace);
    tree t;
    fprintf(f, "pixel %d,%d of %s", v->x, v->y, v->path);
    if (v->sample >= 0) fprintf(f, ", sample %d", v->sample);
    fprintf(f, "\ncolour ");
    pnum(f, 9, v->pixel.r), fputc(' ', f), pnum(f, 9, v->pixel.g), fputc(' ', f);
    pnum(f, 9, v->pixel.b), fputc('\n', f);
    fprintf(f,
            "rays: eye %llu, reflect %llu (tir %llu of them), refract %llu, shadow %llu "
            "(blocked %llu, attenuated %llu)\n\n",
            (unsigned long long)v->stats.eye, (unsigned long long)v->stats.reflect,
            (unsigned long long)v->stats.tir, (unsigned long long)v->stats.refract,
            (unsigned long long)v->stats.shadow, (unsigned long long)v->stats.shadow_blocked,
            (unsigned long long)v->stats.shadow_attenuated);
    if (v->stats.budget_cut)
        fprintf(f, "ray budget used up: %llu rays not cast (--ray-budget raises it)\n\n",
                (unsigned long long)v->stats.budget_cut);
    tree_begin(&t, v, utf8 ? &uni : &asc);
    for (i = 0; i < n; i++)
        if (ggTraceGetNode(v->trace, i)->parent < 0) {
            const ggTraceNode *r = ggTraceGetNode(v->trace, i);
            fprintf(f, "sample %d\n", r->sample);
            print_node(f, &t, (int)i, NULL, "", "", "");
            fprintf(f, "\n");
        }
    trace_kids_free(&t.kids);
}

/* ---- JSON ---- */

/* Numbers as json_num_text: JSON has no NaN or infinity, the strings
   "inf", "-inf" and "nan" stand for them (docs/trace-json.md, version 2);
   json_num_opt for a number that may not apply (NaN, the library's
   "none", as null). */

/* Mesh hits: "face": {"triangle", "index", "line", "mesh", "group",
   "material_name"}; null for other shapes. */
static void json_face(FILE *f, const ggScene *s, const ggTraceNode *n)
{
    ggFaceInfo fi;
    fprintf(f, ",\"face\":");
    if (n->triangle < 0 || ggSceneGetFaceInfo(s, n->object, n->triangle, &fi) != GG_OK) {
        fprintf(f, "null");
        return;
    }
    fprintf(f, "{\"triangle\":%ld,\"index\":%ld,\"line\":%d,\"mesh\":", n->triangle, fi.face,
            fi.line);
    json_str(f, fi.mesh_name);
    fprintf(f, ",\"group\":");
    json_str(f, fi.group);
    fprintf(f, ",\"material_name\":");
    json_str(f, fi.material_name);
    fputc('}', f);
}

static void json_node(FILE *f, const tree *t, int i, const ggColor *wp)
{
    const trace_view *v = t->v;
    const ggTraceNode *n = ggTraceGetNode(v->trace, (size_t)i);
    ggColor w = node_weight(v->trace, t->roots, n, wp), c = contribution(w, n->color);
    int kids[MAX_KIDS], nk = trace_children(&t->kids, v->trace, i, kids, MAX_KIDS), k, l;
    fprintf(f, "{\"id\":%d,\"kind\":\"%s\",\"depth\":%d,\"sample\":%d,\"channel\":", i,
            ggRayKindName(n->kind), n->depth, n->sample);
    if (n->channel >= 0) fprintf(f, "\"%c\"", "rgb"[n->channel]);
    else fprintf(f, "null");
    fputc(',', f), json_vec_text(f, "origin", n->o), fputc(',', f), json_vec_text(f, "direction", n->d);
    fprintf(f, ",\"medium\":%d,\"n_medium\":", n->medium);
    json_num_text(f, n->n_medium);
    fputc(',', f), json_color_text(f, "weight", w);
    fputc(',', f), json_color_text(f, "factor", n->weight);
    fputc(',', f), json_color_text(f, "contribution", c);
    fprintf(f, ",\"share\":");
    json_num_text(f, share_of(c, t->base));
    fputc(',', f), json_color_text(f, "absorption", n->absorption);
    fprintf(f, ",\"stop\":\"%s\",", ggStopName(n->stop));
    json_color_text(f, "color", n->color);
    if (n->nodes >= 0)
        fprintf(f, ",\"traversal\":{\"nodes\":%ld,\"prims\":%ld}", n->nodes, n->prims);
    else
        fprintf(f, ",\"traversal\":null");
    fprintf(f, ",\"hit\":");
    if (!n->hit) {
        fprintf(f, "null");
    } else {
        fprintf(f, "{\"object\":%d,\"shape\":\"%s\",\"line\":%d,\"material\":%d,\"t\":", n->object,
                ggShapeKindName(n->shape), n->line, n->material);
        json_num_text(f, n->t);
        json_face(f, v->scene, n);
        fputc(',', f), json_vec_text(f, "point", n->p), fputc(',', f), json_vec_text(f, "ng", n->ng);
        fputc(',', f), json_vec_text(f, "ns", n->ns);
        fprintf(f, ",\"numeric\":{\"perr\":");
        json_num_text(f, n->perr);
        fprintf(f, ",\"offset\":");
        json_num_text(f, n->offset);
        fprintf(f, ",\"tir_margin\":");
        json_num_opt(f, n->tir_margin);
        fprintf(f, ",\"edge\":");
        json_num_opt(f, n->edge);
        fputc('}', f);
        fprintf(f, ",\"front\":%s,\"uv\":[", n->front ? "true" : "false");
        json_num_text(f, n->u), fputc(',', f), json_num_text(f, n->v);
        fprintf(f, "],\"n_other\":");
        json_num_text(f, n->n_other);
        fputc(',', f), json_color_text(f, "surface", n->surface);
        fputc(',', f), json_color_text(f, "emission", n->emission);
        fputc(',', f), json_color_text(f, "ambient", n->ambient);
        fprintf(f, ",\"fresnel\":");
        if (n->fresnel >= 0) json_num_text(f, n->fresnel);
        else fprintf(f, "null");
        fputc(',', f), json_color_text(f, "reflect_factor", n->reflect_weight);
        fputc(',', f), json_color_text(f, "refract_factor", n->refract_weight);
        fprintf(f, ",\"lights\":[");
        for (l = 0; l < n->nlights; l++) {
            const ggTraceLight *L = ggTraceGetLight(v->trace, (size_t)(n->first_light + l));
            if (l) fputc(',', f);
            fprintf(f, "{\"light\":%d,\"verdict\":\"%s\",\"occluder\":", L->light,
                    ggShadowName(L->verdict));
            if (L->occluder >= 0) fprintf(f, "%d", L->occluder);
            else fprintf(f, "null");
            if (L->verdict != GG_SHADOW_FACING_AWAY) {
                fputc(',', f), json_vec_text(f, "origin", L->origin);
                fputc(',', f), json_vec_text(f, "direction", L->dir);
                fprintf(f, ",\"t_block\":");
                json_num_text(f, L->t_block);
            }
            fputc(',', f), json_color_text(f, "transmittance", L->transmittance);
            fputc(',', f), json_color_text(f, "diffuse", L->diffuse);
            fputc(',', f), json_color_text(f, "phong", L->phong);
            fputc('}', f);
        }
        fprintf(f, "]}");
    }
    fprintf(f, ",\"children\":[");
    for (k = 0; k < nk; k++) {
        if (k) fputc(',', f);
        json_node(f, t, kids[k], &w);
    }
    fprintf(f, "]}");
}

void trace_print_json(FILE *f, const trace_view *v)
{
    size_t i, n = ggTraceNodeCount(v->trace);
    int first = 1;
    tree t;
    fprintf(f, "{\"ggrt_trace\":2,\"version\":2,\"scene\":");
    json_str(f, v->path);
    fprintf(f, ",\"pixel\":[%d,%d],\"sample\":", v->x, v->y);
    if (v->sample >= 0) fprintf(f, "%d", v->sample);
    else fprintf(f, "null");
    fputc(',', f);
    json_color_text(f, "color", v->pixel);
    fputc(',', f), json_stats(f, "stats", &v->stats);
    fprintf(f, ",\"roots\":[");
    tree_begin(&t, v, NULL);
    for (i = 0; i < n; i++)
        if (ggTraceGetNode(v->trace, i)->parent < 0) {
            if (!first) fputc(',', f);
            first = 0;
            json_node(f, &t, (int)i, NULL);
        }
    trace_kids_free(&t.kids);
    fprintf(f, "]");
    if (v->ledger) {
        fprintf(f, ",\"ledger\":");
        json_ledger(f, v->trace, v->ledger);
    }
    fprintf(f, "}\n");
}
