/* SPDX-License-Identifier: MIT */
/*
** check.c -- ggCheck: every pixel's ray trees tested against invariants
** a correct Whitted render keeps, with the worst pixels of each.
*/
#include "debug_int.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct check_res {
    ggCheckResult pub;
    gg_dbg_alloc al;
} check_res;

/* One invariant's state in one pixel: its measure and where it is worst. */
typedef struct pix_fail {
    int failed;
    double measure;
    ggCheckPixel at;
} pix_fail;

typedef struct check_thread {
    gg_dbg_buf buf;
    ggCheckItem item[GG_CHECK_COUNT];
    long checked;
    /* The last pixel checked in full (check_pixel): 0 it was left out (no
       path matched), 1 it passed every check, 2 something failed; and
       its paths' share. */
    int last;
    double last_share;
    /* Path checks: the shares of the row this thread is scanning (row
       y), stored into check_job.row_share when it moves on (flush_row). */
    double row_acc;
    int row_y;
    uint64_t *sets;   /* path checks: the automaton's states per ray */
    size_t sets_cap;
    /* Threads' structs lie side by side and each writes its own per
       pixel: the next one's fields start a cache line further on. */
    unsigned char pad[64];
} check_thread;

typedef struct check_job {
    ggCheckOptions co;
    const ggScene *s;
    ggCheckResult *res;
    check_thread *t;
    const ggAllocator *alloc;
    double *children; /* per material: the weight its children get, ks + kt (conductor 1 + kt) */
    /* Path checks: the checked pixels' shares, summed per row of the
       window (one thread scans a row, left to right) and the rows in
       order by merge: the same sum for any number of threads. */
    double *row_share;
    int y0;
} check_job;

GG_API const char *ggCheckName(int check)
{
    static const char *const n[] = {"nonfinite", "negative", "energy", "truncation",
                                    "self-hit",  "near-tir", "grazing"};
    return check >= 0 && check < GG_CHECK_COUNT ? n[check] : "?";
}

GG_API const char *ggSeverityName(int severity)
{
    static const char *const n[] = {"info", "warning", "error"};
    return severity >= 0 && severity < 3 ? n[severity] : "?";
}

GG_API void ggCheckOptionsDefault(ggCheckOptions *co)
{
    if (!co) return;
    memset(co, 0, sizeof *co);
    co->severity[GG_CHECK_NONFINITE] = GG_SEVERITY_ERROR;
    co->severity[GG_CHECK_NEGATIVE] = GG_SEVERITY_ERROR;
    co->severity[GG_CHECK_ENERGY] = GG_SEVERITY_ERROR;
    co->severity[GG_CHECK_TRUNCATION] = GG_SEVERITY_ERROR;
    co->severity[GG_CHECK_SELF_HIT] = GG_SEVERITY_WARNING;
    co->severity[GG_CHECK_NEAR_TIR] = GG_SEVERITY_INFO;
    co->severity[GG_CHECK_GRAZING] = GG_SEVERITY_INFO;
    co->truncation = 0.1;
    co->self_hit = 4;
    co->near_tir = 16;
    co->grazing = 1e-3;
}

static double cmax(ggColor c)
{
    double m = c.r > c.g ? c.r : c.g;
    return m > c.b ? m : c.b;
}

static double cmin(ggColor c)
{
    double m = c.r < c.g ? c.r : c.g;
    return m < c.b ? m : c.b;
}

/* Worse first: larger measure, then row order. */
static int worse(const ggCheckPixel *p, const ggCheckPixel *q)
{
    if (p->value != q->value) return p->value > q->value;
    if (p->y != q->y) return p->y < q->y;
    return p->x < q->x;
}

static void keep_worst(ggCheckItem *it, const ggCheckPixel *p)
{
    int i;
    if (it->nworst == GG_CHECK_WORST && !worse(p, &it->pixels_worst[GG_CHECK_WORST - 1])) return;
    i = it->nworst < GG_CHECK_WORST ? it->nworst++ : GG_CHECK_WORST - 1;
    while (i > 0 && worse(p, &it->pixels_worst[i - 1])) {
        it->pixels_worst[i] = it->pixels_worst[i - 1];
        i--;
    }
    it->pixels_worst[i] = *p;
}

/* Ray `node` (light record `light`, or -1) has measure m: keep the worst. */
static void note(pix_fail *f, double m, int node, int light, const ggTraceNode *n)
{
    if (f->failed && m <= f->measure) return;
    f->failed = 1, f->measure = m;
    f->at.value = m, f->at.node = node, f->at.light = light;
    f->at.object = n && n->hit ? n->object : -1;
    f->at.material = n && n->hit ? n->material : -1;
    f->at.line = n && n->hit ? n->line : 0;
}

static void ray_fails(pix_fail *f, ggCheckItem *it, double m, int node, int light,
                      const ggTraceNode *n)
{
    it->rays++;
    note(f, m, node, light, n);
}

/* A colour the float image cannot hold (NaN, infinite, or beyond
   FLT_MAX, which rounds to infinity), or a negative one (neg). */
static int bad_color(ggColor c, int neg)
{
    if (neg) return cmin(c) < 0;
    return !(fabs(c.r) <= FLT_MAX && fabs(c.g) <= FLT_MAX && fabs(c.b) <= FLT_MAX);
}

/* The ray where a non-finite (neg = 0) or negative (neg = 1) colour
   starts: the first whose children's colours are all fine. */
static int source_ray(const ggTrace *t, int neg)
{
    size_t i, j, n = ggTraceNodeCount(t);
    for (i = 0; i < n; i++) {
        int kids_bad = 0;
        if (!bad_color(ggTraceGetNode(t, i)->color, neg)) continue;
        for (j = i + 1; j < n && !kids_bad; j++) {
            const ggTraceNode *c = ggTraceGetNode(t, j);
            if (c->parent == (int)i) kids_bad = bad_color(c->color, neg);
        }
        if (!kids_bad) return (int)i;
    }
    return -1;
}

#ifndef GG_STOP_BUDGET
#define GG_STOP_BUDGET 4
#endif

/* Secondary rays (and shadow rays) meeting something within k times the
   error bound of their origin, perr + offset of the hit they leave: the
   measure is that bound over the distance (larger is worse). */
static void self_hits(const check_job *cj, check_thread *th, pix_fail *f, const ggTrace *t, int i)
{
    const ggTraceNode *n = ggTraceGetNode(t, (size_t)i), *p;
    ggCheckItem *it = &th->item[GG_CHECK_SELF_HIT];
    double bound;
    int l;
    if (n->parent >= 0 && n->hit && (p = ggTraceGetNode(t, (size_t)n->parent)) && p->hit) {
        bound = p->perr + p->offset;
        if (bound > 0 && n->t <= cj->co.self_hit * bound)
            ray_fails(&f[GG_CHECK_SELF_HIT], it, n->t > 0 ? bound / n->t : INFINITY, i, -1, n);
    }
    bound = n->perr + n->offset;
    for (l = 0; n->hit && bound > 0 && l < n->nlights; l++) {
        const ggTraceLight *L = ggTraceGetLight(t, (size_t)(n->first_light + l));
        double d;
        if (!L || L->occluder < 0) continue;
        d = L->t_block * sqrt(L->dir.x * L->dir.x + L->dir.y * L->dir.y + L->dir.z * L->dir.z);
        if (d <= cj->co.self_hit * bound)
            ray_fails(&f[GG_CHECK_SELF_HIT], it, d > 0 ? bound / d : INFINITY, i,
                      n->first_light + l, n);
    }
}

/* Whether n is a hit the depth or the budget cut whose material would
   have given children weight: what they lost is truncation. */
static int cut_with_children(const check_job *cj, const ggTraceNode *n)
{
    return n->hit && (n->stop == GG_STOP_DEPTH || n->stop == GG_STOP_BUDGET) &&
           n->material >= 0 && (size_t)n->material < cj->s->nmaterials &&
           cj->children[n->material] > 0;
}

/* The weight node i's children could have carried and did not: the
   material's (ks + kt) less what the children cast carry (a budget stop
   may come after the mirror ray; a depth stop casts none). Children
   follow their parent in a trace. */
static double cut_share(const check_job *cj, const ggTrace *t, int i, const ggTraceNode *n)
{
    double cast = 0;
    size_t j, count = ggTraceNodeCount(t);
    if (n->stop == GG_STOP_BUDGET)
        for (j = (size_t)i + 1; j < count; j++) {
            const ggTraceNode *k = ggTraceGetNode(t, j);
            if (k->parent == i) cast += cmax(k->weight);
        }
    return cast < cj->children[n->material] ? cj->children[n->material] - cast : 0;
}

/* The invariants that live at one hit. *cut sums the truncated weight. */
static void check_node(const check_job *cj, check_thread *th, pix_fail *f, const ggTrace *t, int i,
                       double *cut, long *ncut, pix_fail *cut_at)
{
    const ggTraceNode *n = ggTraceGetNode(t, (size_t)i);
    const ggMaterial *m;
    double e, c;
    if (!n->hit || n->material < 0 || (size_t)n->material >= cj->s->nmaterials) return;
    m = &cj->s->materials[n->material];
    e = m->kd * cmax(n->surface) + cj->children[n->material];
    if (e > 1 + 1e-9) {
        ray_fails(&f[GG_CHECK_ENERGY], &th->item[GG_CHECK_ENERGY], e, i, -1, n);
        f[GG_CHECK_ENERGY].at.line = m->line;
    }
    c = fabs(n->d.x * n->ng.x + n->d.y * n->ng.y + n->d.z * n->ng.z);
    if (c < cj->co.grazing)
        ray_fails(&f[GG_CHECK_GRAZING], &th->item[GG_CHECK_GRAZING], c > 0 ? 1 / c : INFINITY, i,
                  -1, n);
    if (fabs(n->tir_margin) < cj->co.near_tir) { /* NaN (no refraction) fails this */
        double k = fabs(n->tir_margin);
        ray_fails(&f[GG_CHECK_NEAR_TIR], &th->item[GG_CHECK_NEAR_TIR], k > 0 ? 1 / k : INFINITY, i,
                  -1, n);
    }
    self_hits(cj, th, f, t, i);
    if (cut_with_children(cj, n)) {
        const ggColor *w = &th->buf.w[i];
        ggColor a;
        double lost;
        a.r = w->r * n->absorption.r, a.g = w->g * n->absorption.g, a.b = w->b * n->absorption.b;
        lost = cmax(a) * cut_share(cj, t, i, n);
        *cut += lost;
        (*ncut)++;
        note(cut_at, lost, i, -1, n);
    }
}

/* The pixel-level invariants: its value not finite, or negative. */
static void check_value(check_thread *th, pix_fail *f, const ggTrace *t, ggColor px)
{
    int src;
    if (gg_dbg_nonfinite(px)) {
        src = source_ray(t, 0);
        ray_fails(&f[GG_CHECK_NONFINITE], &th->item[GG_CHECK_NONFINITE], 1, src, -1,
                  src >= 0 ? ggTraceGetNode(t, (size_t)src) : NULL);
    } else if (cmin(px) < 0) {
        src = source_ray(t, 1);
        ray_fails(&f[GG_CHECK_NEGATIVE], &th->item[GG_CHECK_NEGATIVE], -cmin(px), src, -1,
                  src >= 0 ? ggTraceGetNode(t, (size_t)src) : NULL);
    }
}

/* Thread th's row of shares into cj->row_share (one store a row: rows
   next to each other, scanned by different threads, share cache lines). */
static void flush_row(const check_job *cj, check_thread *th)
{
    if (th->row_acc != 0) cj->row_share[th->row_y - cj->y0] += th->row_acc;
    th->row_acc = 0;
}

/* Whether checking t needs its rays' weights in the pixel: a path check,
   or a ray cut by the depth or the budget that would have had children
   (the truncation check weighs what they lost). */
static int needs_weights(const check_job *cj, const ggTrace *t, size_t n)
{
    size_t i;
    if (cj->co.path) return 1;
    for (i = 0; i < n; i++)
        if (cut_with_children(cj, ggTraceGetNode(t, i))) return 1;
    return 0;
}

static int check_pixel(void *ud, int thread, int x, int y, ggTrace *const *recs, const ggColor *px,
                       int same)
{
    check_job *cj = ud;
    check_thread *th = &cj->t[thread];
    const ggTrace *t = recs[0];
    pix_fail f[GG_CHECK_COUNT], cut_at;
    ggPathSummary sum;
    size_t i, n = ggTraceNodeCount(t);
    double cut = 0;
    long ncut = 0;
    int c;
    memset(&sum, 0, sizeof sum);
    if (y != th->row_y) flush_row(cj, th), th->row_y = y;
    /* The last pixel's trees and value (a span of misses, scan.c): the
       same verdict, which only needs recording again where it failed. */
    if (same && th->last != 2) {
        if (th->last == 0) return 0;
        th->checked++;
        th->row_acc += th->last_share;
        return 0;
    }
    th->last = 0;
    if (needs_weights(cj, t, n) && gg_dbg_buf_weights(&th->buf, cj->alloc, t))
        return GG_ERROR_NOMEM;
    if (cj->co.path) {
        gg_dbg_pixel p;
        if (gg_mem_grow(cj->alloc, (void **)&th->sets, &th->sets_cap,
                        (n ? n : 1) * GG_PATH_WORDS, sizeof *th->sets))
            return GG_ERROR_NOMEM;
        memset(&p, 0, sizeof p);
        p.trace = t, p.x = x, p.y = y, p.px = px[0], p.w = th->buf.w;
        gg_path_run(cj->co.path, &p, th->sets, &sum, NULL);
        if (sum.matched == 0) return 0;
        th->row_acc += sum.share;
    }
    th->checked++;
    th->last = 1, th->last_share = sum.share;
    memset(f, 0, sizeof f);
    memset(&cut_at, 0, sizeof cut_at);
    check_value(th, f, t, px[0]);
    for (i = 0; i < n; i++) check_node(cj, th, f, t, (int)i, &cut, &ncut, &cut_at);
    if (cut > cj->co.truncation) {
        th->item[GG_CHECK_TRUNCATION].rays += ncut;
        f[GG_CHECK_TRUNCATION] = cut_at;
        f[GG_CHECK_TRUNCATION].measure = f[GG_CHECK_TRUNCATION].at.value = cut;
    }
    for (c = 0; c < GG_CHECK_COUNT; c++) {
        ggCheckItem *it = &th->item[c];
        if (!f[c].failed) continue;
        th->last = 2;
        it->pixels++;
        if (f[c].measure > it->worst) it->worst = f[c].measure;
        f[c].at.x = x, f[c].at.y = y, f[c].at.share = sum.share;
        keep_worst(it, &f[c].at);
    }
    return 0;
}

/* ---- the radiance bound ---- */

/* The largest channel a texture can give (colour times texel). */
static double texture_max(const ggScene *s, const ggMaterial *m)
{
    const gg_texture *t;
    double v = 0;
    if (m->texture < 0 || (size_t)m->texture >= s->ntextures) return cmax(m->color);
    t = &s->textures[m->texture];
    if (!t->img) {
        v = cmax(t->checker_a) > cmax(t->checker_b) ? cmax(t->checker_a) : cmax(t->checker_b);
    } else {
        const float *p = ggImagePixelsConst(t->img);
        size_t i, k = 3 * (size_t)ggImageWidth(t->img) * (size_t)ggImageHeight(t->img);
        for (i = 0; i < k; i++)
            if (p[i] > v || p[i] != p[i]) v = p[i] != p[i] ? INFINITY : p[i];
    }
    return v * cmax(m->color);
}

/* Any ray's colour is at most L, by induction on the depth left: a miss
   is the background; a hit returns at most its own terms D (emission,
   ambient, and per light a diffuse term and a highlight of at most the
   light's colour) plus g L, g the weight its children get (absorption and
   shadow transmittance only lower that). So L = max(background, D / (1 -
   g)) over the materials with g < 1 holds for all of them when every
   other material passes light on without adding any (g = 1, D = 0:
   clear glass, perfect mirrors); else there is no finite bound. */
static double radiance_bound(const check_job *cj)
{
    const ggScene *s = cj->s;
    double lights = 0, L = cmax(s->background), amb = cmax(s->ambient);
    size_t i;
    for (i = 0; i < s->nlights; i++) lights += cmax(s->light_colors[i]);
    for (i = 0; i < s->nmaterials; i++) {
        const ggMaterial *m = &s->materials[i];
        double d = cmax(m->ke) + m->kd * texture_max(s, m) * (amb + lights) + m->ks * lights;
        double g = cj->children[i];
        if (m->kt > 1 || !isfinite(d)) return INFINITY; /* shadows could amplify */
        if (g < 1) {
            if (d / (1 - g) > L) L = d / (1 - g);
        } else if (g > 1 + 1e-12 || d > 0) {
            return INFINITY;
        }
    }
    return L;
}

/* ---- ggCheck ---- */

GG_API void ggCheckResultFree(ggCheckResult *r)
{
    if (r) gg_mem_free(((check_res *)r)->al.a, r);
}

static int check_alloc(ggScene *s, const gg_scan *sc, check_job *cj, ggCheckResult **out)
{
    check_res *cr = gg_mem_calloc(s->alloc, 1, sizeof *cr);
    ggCheckResult *r;
    size_t i;
    if (!cr) return GG_ERROR_NOMEM;
    gg_dbg_alloc_init(&cr->al, s->alloc);
    r = *out = &cr->pub;
    cj->res = r, cj->alloc = cr->al.a, cj->s = s;
    r->width = sc->desc.width, r->height = sc->desc.height;
    r->x0 = sc->desc.x0, r->y0 = sc->desc.y0, r->x1 = sc->desc.x1, r->y1 = sc->desc.y1;
    cj->t = gg_mem_calloc(cj->alloc, (size_t)sc->threads, sizeof *cj->t);
    cj->children = gg_mem_calloc(cj->alloc, s->nmaterials ? s->nmaterials : 1, sizeof(double));
    cj->row_share =
        gg_mem_calloc(cj->alloc, (size_t)(sc->desc.y1 - sc->desc.y0) + 1, sizeof(double));
    cj->y0 = sc->desc.y0;
    if (!cj->t || !cj->children || !cj->row_share) return GG_ERROR_NOMEM;
    for (i = 0; i < s->nmaterials; i++) {
        const ggMaterial *m = &s->materials[i];
        cj->children[i] = (m->fresnel == GG_FRESNEL_CONDUCTOR ? 1 : m->ks) + m->kt;
    }
    return GG_OK;
}

static void merge(check_job *cj, int threads)
{
    ggCheckResult *r = cj->res;
    int i, c, k;
    double share = 0;
    for (i = 0; i < threads; i++) r->checked += cj->t[i].checked, flush_row(cj, &cj->t[i]);
    for (k = 0; k < r->y1 - r->y0; k++) share += cj->row_share[k];
    if (cj->co.path && r->checked > 0) r->share = share / (double)r->checked;
    for (c = 0; c < GG_CHECK_COUNT; c++) {
        ggCheckItem *it = &r->items[c];
        it->check = c, it->severity = cj->co.severity[c];
        for (i = 0; i < threads; i++) {
            const ggCheckItem *ti = &cj->t[i].item[c];
            it->pixels += ti->pixels, it->rays += ti->rays;
            if (ti->worst > it->worst) it->worst = ti->worst;
            for (k = 0; k < ti->nworst; k++) keep_worst(it, &ti->pixels_worst[k]);
        }
        if (it->severity == GG_SEVERITY_ERROR && it->pixels > 0) r->failed++;
    }
}

GG_API int ggCheck(ggScene *s, const ggRenderOptions *opt, const ggCheckOptions *co,
                   ggCheckResult **out, ggError *err)
{
    gg_tracer *tr = NULL;
    gg_scan sc;
    check_job cj;
    ggCheckResult *r = NULL;
    int rc, i;
    if (!s || !out) return gg_error_set(err, GG_ERROR_INVALID, "ggCheck: NULL argument");
    *out = NULL; /* after the NULL checks: base.h rule 1 */
    memset(&cj, 0, sizeof cj);
    memset(&sc, 0, sizeof sc);
    if (co)
        cj.co = *co;
    else
        ggCheckOptionsDefault(&cj.co);
    if ((rc = gg_tracer_create(s, opt, &tr, err)) != GG_OK) return rc;
    sc.tracer[0] = tr, sc.ntracers = 1, sc.record = 1;
    gg_scan_init(&sc);
    if ((rc = check_alloc(s, &sc, &cj, &r)) != GG_OK) {
        rc = gg_error_set(err, rc, "out of memory for the check result");
    } else {
        sc.fn = check_pixel, sc.ud = &cj, sc.alloc = cj.alloc;
        if ((rc = gg_scan_run(&sc, err)) == GG_OK) {
            r->stats = sc.stats[0];
            r->scanned = (long)(r->x1 - r->x0) * (r->y1 - r->y0);
            r->radiance_bound = radiance_bound(&cj);
            merge(&cj, sc.threads);
        }
    }
    for (i = 0; cj.t && i < sc.threads; i++) {
        gg_mem_free(cj.alloc, cj.t[i].buf.w);
        gg_mem_free(cj.alloc, cj.t[i].sets);
    }
    gg_mem_free(cj.alloc, cj.t);
    gg_mem_free(cj.alloc, cj.children);
    gg_mem_free(cj.alloc, cj.row_share);
    gg_tracer_free(tr);
    if (rc != GG_OK) {
        ggCheckResultFree(r);
        return rc;
    }
    *out = r;
    return GG_OK;
}
