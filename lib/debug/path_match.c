/* SPDX-License-Identifier: MIT */
/*
** path_match.c -- running a compiled path expression (path.c) over a
** pixel's paths. A path is a ledger term (ledger.c) read from the eye: the
** events down the tree to the ray that carried it, then the term's own.
** The automaton's state set after each ray's events is kept per ray, in
** the order rays were cast (parents first), so each path costs the
** events of its term only: a pixel costs time linear in its rays.
*/
#include "debug_int.h"

#include <math.h>
#include <string.h>

/* One event of a path. */
typedef struct pev {
    int type, scatter, tir;
    const ggTraceNode *at; /* the surface (hit) of a surface event, else NULL */
    int node;              /* the ray arriving at the event, for predicates */
    const ggTraceLight *L; /* L events */
} pev;

static int label_ok(const gg_path_pat *q, int k, const pev *ev)
{
    switch (q->label_kind[k]) {
    case PL_TIR:
        return ev->tir;
    case PL_MATERIAL:
        return ev->at && ev->at->material == q->label_num[k];
    default:
        if (ev->type == PE_L) return ev->L && ev->L->light == q->label_num[k];
        return ev->at && ev->at->object == q->label_num[k];
    }
}

static int pat_ok(const gg_path_pat *q, const pev *ev)
{
    int k;
    if (!(q->types >> ev->type & 1u) || !(q->scatters >> ev->scatter & 1u)) return 0;
    for (k = 0; k < q->nlabels; k++)
        if (!label_ok(q, k, ev)) return 0;
    return 1;
}

static int class_ok(const ggPathExpr *e, int c, const pev *ev, const gg_dbg_pixel *px)
{
    const gg_path_class *cl = &e->cls[c];
    int k, any = 0;
    for (k = 0; k < cl->count && !any; k++) any = pat_ok(&e->pats[cl->first + k], ev);
    if (any == cl->neg) return 0;
    return !cl->pred || gg_pred_eval_ray(cl->pred, px, ev->node, ev->L);
}

static int empty(const uint64_t *s)
{
    int w;
    uint64_t any = 0;
    for (w = 0; w < GG_PATH_WORDS; w++) any |= s[w];
    return any == 0;
}

/* out = the states after event ev from the states in. */
static void step_raw(const ggPathExpr *e, const uint64_t *in, const pev *ev,
                     const gg_dbg_pixel *px, uint64_t *out)
{
    signed char ok[GG_PATH_MAX_EVENTS];
    int k, w;
    memset(out, 0, sizeof(gg_path_set));
    if (empty(in)) return; /* a dead path stays dead: most rays of a narrow expression */
    memset(ok, -1, (size_t)e->ncls);
    for (k = 0; k < e->nedges; k++) {
        const gg_path_edge *ed = &e->edges[k];
        if (ed->cls < 0 || !(in[ed->from / 64] >> (ed->from % 64) & 1u)) continue;
        if (ok[ed->cls] < 0) ok[ed->cls] = (signed char)class_ok(e, ed->cls, ev, px);
        if (ok[ed->cls])
            for (w = 0; w < GG_PATH_WORDS; w++) out[w] |= e->closure[ed->to][w];
    }
}

/* What a step without predicates reads of an event: the labels only if
   the expression has labels of that kind. */
static void signature(const gg_path_cache *c, const pev *ev, int *sig)
{
    sig[0] = ev->type, sig[1] = ev->scatter, sig[2] = ev->tir;
    sig[3] = c->numbers && ev->at ? ev->at->object : -1;
    sig[4] = c->materials && ev->at ? ev->at->material : -1;
    sig[5] = c->numbers && ev->L ? ev->L->light : -1;
}

/* step_raw through the cache when there is one that applies. */
static void step(const ggPathExpr *e, const uint64_t *in, const pev *ev, const gg_dbg_pixel *px,
                 uint64_t *out)
{
    gg_path_cache *c = px->cache;
    int sig[6], k;
    uint64_t h;
    gg_path_step *st;
    if (!c || !c->usable) {
        step_raw(e, in, ev, px, out);
        return;
    }
    signature(c, ev, sig);
    h = 1469598103934665603u;
    for (k = 0; k < GG_PATH_WORDS; k++) h = (h ^ in[k]) * 1099511628211u;
    for (k = 0; k < 6; k++) h = (h ^ (uint64_t)(unsigned)sig[k]) * 1099511628211u;
    st = &c->slot[(h >> 20) % GG_PATH_CACHE];
    if (st->valid && !memcmp(st->sig, sig, sizeof sig) && !memcmp(st->in, in, sizeof st->in)) {
        memcpy(out, st->out, sizeof st->out);
        return;
    }
    step_raw(e, in, ev, px, out);
    memcpy(st->in, in, sizeof st->in), memcpy(st->out, out, sizeof st->out);
    memcpy(st->sig, sig, sizeof sig), st->valid = 1;
}

static int accepts(const ggPathExpr *e, const uint64_t *s)
{
    return e->accept >= 0 && (s[e->accept / 64] >> (e->accept % 64) & 1u);
}

/* Whether the last event ev of a path, from the states in, leads to the
   accepting state: step and accepts without building the set, stopping
   at the first edge that does (the term events B O L A end every path). */
static int step_accepts(const ggPathExpr *e, const uint64_t *in, const pev *ev,
                        const gg_dbg_pixel *px)
{
    signed char ok[GG_PATH_MAX_EVENTS];
    int k;
    if (e->accept < 0 || empty(in)) return 0;
    if (px->cache && px->cache->usable) {
        gg_path_set out;
        step(e, in, ev, px, out);
        return accepts(e, out);
    }
    memset(ok, -1, (size_t)e->ncls);
    for (k = 0; k < e->nedges; k++) {
        const gg_path_edge *ed = &e->edges[k];
        if (ed->cls < 0 || !(in[ed->from / 64] >> (ed->from % 64) & 1u) ||
            !accepts(e, e->closure[ed->to]))
            continue;
        if (ok[ed->cls] < 0) ok[ed->cls] = (signed char)class_ok(e, ed->cls, ev, px);
        if (ok[ed->cls]) return 1;
    }
    return 0;
}

static void surface(pev *ev, int type, int scatter, const ggTraceNode *at, int node)
{
    memset(ev, 0, sizeof *ev);
    ev->type = type, ev->scatter = scatter, ev->at = at, ev->node = node;
}

void gg_path_step_event(const ggPathExpr *e, const uint64_t *in, int type, int scatter, int tir,
                        int has_at, long object, long material, long light, uint64_t *out)
{
    ggTraceNode at;
    ggTraceLight L;
    gg_dbg_pixel px;
    pev ev;
    memset(&at, 0, sizeof at), memset(&L, 0, sizeof L), memset(&px, 0, sizeof px);
    at.object = (int)object, at.material = (int)material, L.light = (int)light;
    surface(&ev, type, scatter, has_at ? &at : NULL, -1);
    ev.tir = tir;
    ev.L = type == PE_L ? &L : NULL;
    step_raw(e, in, &ev, &px, out);
}

/* The state set after the events that lead to node i: C for a root, else
   the parent's set and the scattering that cast i. */
static void node_states(const ggPathExpr *e, const gg_dbg_pixel *px, int i, uint64_t *sets)
{
    const ggTraceNode *n = ggTraceGetNode(px->trace, (size_t)i);
    pev ev;
    if (n->parent < 0 || n->parent >= i) {
        surface(&ev, PE_C, PS_NONE, NULL, i);
        step(e, e->closure[0], &ev, px, sets + (size_t)i * GG_PATH_WORDS);
        return;
    }
    surface(&ev, n->kind == GG_RAY_REFRACT ? PE_T : PE_R, PS_S,
            ggTraceGetNode(px->trace, (size_t)n->parent), n->parent);
    ev.tir = n->kind == GG_RAY_TIR;
    step(e, sets + (size_t)n->parent * GG_PATH_WORDS, &ev, px, sets + (size_t)i * GG_PATH_WORDS);
}

/* Whether the path of term (kind, light record L) at node i matches,
   from the node's states s; d and g: the sets after <RD> and <RG> at
   the hit (filled on first use, *have tracks which). */
static int term_matches(const ggPathExpr *e, const gg_dbg_pixel *px, int i, int kind,
                        const ggTraceLight *L, const uint64_t *s, uint64_t *d, uint64_t *g,
                        int *have)
{
    const ggTraceNode *n = ggTraceGetNode(px->trace, (size_t)i);
    pev ev;
    if (kind == GG_TERM_BACKGROUND || kind == GG_TERM_EMISSION) {
        surface(&ev, kind == GG_TERM_BACKGROUND ? PE_B : PE_O, PS_NONE,
                kind == GG_TERM_EMISSION ? n : NULL, i);
        return step_accepts(e, s, &ev, px);
    }
    if (kind == GG_TERM_PHONG && !(*have & 2)) {
        surface(&ev, PE_R, PS_G, n, i);
        step(e, s, &ev, px, g), *have |= 2;
    } else if (kind != GG_TERM_PHONG && !(*have & 1)) {
        surface(&ev, PE_R, PS_D, n, i);
        step(e, s, &ev, px, d), *have |= 1;
    }
    surface(&ev, kind == GG_TERM_AMBIENT ? PE_A : PE_L, PS_NONE, NULL, i);
    ev.L = kind == GG_TERM_AMBIENT ? NULL : L;
    return step_accepts(e, kind == GG_TERM_PHONG ? g : d, &ev, px);
}

/* a * b per channel, a weight of exactly 0 keeping out even an infinite
   term (as ledger.c). */
static ggColor cmul3(ggColor a, ggColor b)
{
    ggColor c;
    c.r = a.r == 0 ? 0 : a.r * b.r, c.g = a.g == 0 ? 0 : a.g * b.g;
    c.b = a.b == 0 ? 0 : a.b * b.b;
    return c;
}

static int nonzero(ggColor c)
{
    return c.r != 0 || c.g != 0 || c.b != 0;
}

/* One term (if not zero) into the summary. */
static void tally(ggPathSummary *sum, int match, ggColor a, ggColor term)
{
    ggColor v;
    if (!nonzero(term)) return;
    sum->paths++;
    if (!match) return;
    v = cmul3(a, term);
    sum->matched++;
    sum->value.r += v.r, sum->value.g += v.g, sum->value.b += v.b;
}

/* The terms of node i (as ledger.c's node_terms) into sum. */
static void node_paths(const ggPathExpr *e, const gg_dbg_pixel *px, int i, const uint64_t *s,
                       ggPathSummary *sum)
{
    const ggTraceNode *n = ggTraceGetNode(px->trace, (size_t)i);
    ggColor a = cmul3(px->w[i], n->absorption);
    gg_path_set d, g;
    int have = 0, l;
    if (!n->hit) {
        if (nonzero(n->color))
            tally(sum, term_matches(e, px, i, GG_TERM_BACKGROUND, NULL, s, d, g, &have), px->w[i],
                  n->color);
        return;
    }
    if (nonzero(n->ambient))
        tally(sum, term_matches(e, px, i, GG_TERM_AMBIENT, NULL, s, d, g, &have), a, n->ambient);
    if (nonzero(n->emission))
        tally(sum, term_matches(e, px, i, GG_TERM_EMISSION, NULL, s, d, g, &have), a, n->emission);
    for (l = 0; l < n->nlights; l++) {
        const ggTraceLight *L = ggTraceGetLight(px->trace, (size_t)(n->first_light + l));
        if (!L) break;
        if (nonzero(L->diffuse))
            tally(sum, term_matches(e, px, i, GG_TERM_DIFFUSE, L, s, d, g, &have), a, L->diffuse);
        if (nonzero(L->phong))
            tally(sum, term_matches(e, px, i, GG_TERM_PHONG, L, s, d, g, &have), a, L->phong);
    }
}

void gg_path_run(const ggPathExpr *e, const gg_dbg_pixel *pixel, uint64_t *sets,
                 ggPathSummary *sum, gg_path_cache *cache)
{
    gg_dbg_pixel q = *pixel, *px = &q;
    size_t i, n = ggTraceNodeCount(px->trace);
    double pt = px->px.r + px->px.g + px->px.b, vt;
    int c, k;
    memset(sum, 0, sizeof *sum);
    if (cache && cache->e != e) { /* first use with e: forget other expressions' steps */
        memset(cache->slot, 0, sizeof cache->slot);
        cache->e = e, cache->usable = 1;
        for (c = 0; c < e->ncls; c++)
            if (e->cls[c].pred) cache->usable = 0;
        cache->numbers = cache->materials = 0;
        for (c = 0; c < e->npats; c++)
            for (k = 0; k < e->pats[c].nlabels; k++) {
                cache->numbers |= e->pats[c].label_kind[k] == PL_NUMBER;
                cache->materials |= e->pats[c].label_kind[k] == PL_MATERIAL;
            }
    }
    q.cache = cache;
    for (i = 0; i < n; i++) {
        node_states(e, px, (int)i, sets);
        node_paths(e, px, (int)i, sets + i * GG_PATH_WORDS, sum);
    }
    vt = sum->value.r + sum->value.g + sum->value.b;
    sum->share = pt != 0 && pt == pt && pt - pt == 0 ? vt / pt : 0;
}

/* The light record of term t at its node, or NULL. */
static const ggTraceLight *term_light(const ggTrace *tr, const ggLedgerTerm *t)
{
    const ggTraceNode *n = ggTraceGetNode(tr, (size_t)t->node);
    int l;
    for (l = 0; n && n->hit && l < n->nlights; l++) {
        const ggTraceLight *L = ggTraceGetLight(tr, (size_t)(n->first_light + l));
        if (L && L->light == t->light) return L;
    }
    return NULL;
}

GG_API int ggPathMatch(const ggPathExpr *e, const ggTrace *tr, int x, int y, ggColor pixel,
                       const ggLedger *ledger, unsigned char *matched, ggPathSummary *sum)
{
    size_t n, i;
    uint64_t *sets;
    ggColor *w;
    gg_dbg_pixel px;
    if (!e || !tr || !sum || (matched && !ledger)) return GG_ERROR_INVALID;
    memset(sum, 0, sizeof *sum); /* after the NULL checks: base.h rule 1 */
    n = ggTraceNodeCount(tr);
    sets = gg_mem_calloc(e->alloc, n ? n : 1, sizeof(gg_path_set));
    w = gg_mem_calloc(e->alloc, n ? n : 1, sizeof *w);
    if (!sets || !w) {
        gg_mem_free(e->alloc, sets), gg_mem_free(e->alloc, w);
        return GG_ERROR_NOMEM;
    }
    gg_dbg_weights(tr, w);
    memset(&px, 0, sizeof px);
    px.trace = tr, px.x = x, px.y = y, px.px = pixel, px.w = w;
    gg_path_run(e, &px, sets, sum, NULL);
    for (i = 0; matched && i < ledger->count; i++) {
        const ggLedgerTerm *t = &ledger->terms[i];
        gg_path_set d, g;
        int have = 0;
        matched[i] = t->node >= 0 && (size_t)t->node < n &&
                     term_matches(e, &px, t->node, t->kind, term_light(tr, t),
                                  sets + (size_t)t->node * GG_PATH_WORDS, d, g, &have);
    }
    gg_mem_free(e->alloc, sets), gg_mem_free(e->alloc, w);
    return GG_OK;
}

/* The longest chain of rays ggPathPoints follows (the depth limit is 64). */
#define GG_PATH_CHAIN 256

/* ---- a path as text ---- */

typedef struct sbuf {
    char *b;
    size_t size, len;
} sbuf;

static void put(sbuf *s, const char *fmt, ...) GG_PRINTF(2, 3);

static void put(sbuf *s, const char *fmt, ...)
{
    va_list ap;
    int k;
    va_start(ap, fmt);
    k = vsnprintf(s->len < s->size ? s->b + s->len : NULL, s->len < s->size ? s->size - s->len : 0,
                  fmt, ap);
    va_end(ap);
    if (k > 0) s->len += (size_t)k;
}

/* The events down to node i (not its own term). */
static void events_to(sbuf *s, const ggTrace *tr, int i, int depth)
{
    const ggTraceNode *n = ggTraceGetNode(tr, (size_t)i);
    const ggTraceNode *up;
    if (n->parent < 0 || n->parent >= i || depth > 100000) {
        put(s, "C");
        return;
    }
    events_to(s, tr, n->parent, depth + 1);
    up = ggTraceGetNode(tr, (size_t)n->parent);
    put(s, "<%cS'%d'%s>", n->kind == GG_RAY_REFRACT ? 'T' : 'R', up->object,
        n->kind == GG_RAY_TIR ? "'tir'" : "");
}

GG_API size_t ggPathFormat(const ggTrace *tr, const ggLedgerTerm *t, char *buf, size_t size)
{
    sbuf s;
    const ggTraceNode *n;
    if (buf && size) buf[0] = '\0';
    if (!tr || !t || t->node < 0 || !(n = ggTraceGetNode(tr, (size_t)t->node))) return 0;
    s.b = buf, s.size = buf ? size : 0, s.len = 0;
    events_to(&s, tr, t->node, 0);
    switch (t->kind) {
    case GG_TERM_BACKGROUND:
        put(&s, "B");
        break;
    case GG_TERM_EMISSION:
        put(&s, "<O.'%d'>", n->object);
        break;
    case GG_TERM_AMBIENT:
        put(&s, "<RD'%d'>A", n->object);
        break;
    default:
        put(&s, "<R%c'%d'><L.'%d'>", t->kind == GG_TERM_PHONG ? 'G' : 'D', n->object, t->light);
        break;
    }
    return s.len;
}

/* ---- a path as points ---- */

static void point(ggPathPoint *pts, size_t max, size_t *k, ggVec3 p, ggColor w)
{
    if (*k < max) pts[*k].p = p, pts[*k].weight = w;
    ++*k;
}

static double dist(ggVec3 a, ggVec3 b)
{
    double x = a.x - b.x, y = a.y - b.y, z = a.z - b.z;
    return sqrt(x * x + y * y + z * z);
}

GG_API size_t ggPathPoints(const ggTrace *tr, const ggLedgerTerm *t, ggPathPoint *pts, size_t max)
{
    int chain[GG_PATH_CHAIN], depth = 0, i, roots;
    const ggTraceNode *n, *last = NULL;
    ggColor w;
    ggVec3 prev;
    double len = 0, r;
    size_t k = 0;
    if (!tr || !t || t->node < 0 || !(n = ggTraceGetNode(tr, (size_t)t->node))) return 0;
    if (!pts) max = 0;
    for (i = t->node; i >= 0 && depth < GG_PATH_CHAIN; depth++) {
        chain[depth] = i;
        n = ggTraceGetNode(tr, (size_t)i);
        i = n->parent < i ? n->parent : -1;
    }
    roots = gg_dbg_roots(tr);
    r = 1.0 / (roots > 0 ? roots : 1);
    w.r = w.g = w.b = r;
    for (i = depth - 1; i >= 0; i--) {
        n = ggTraceGetNode(tr, (size_t)chain[i]);
        if (!last) {
            point(pts, max, &k, n->o, w), prev = n->o;
        } else {
            w.r *= last->absorption.r * n->weight.r, w.g *= last->absorption.g * n->weight.g;
            w.b *= last->absorption.b * n->weight.b;
        }
        if (n->hit) point(pts, max, &k, n->p, w), len += dist(prev, n->p), prev = n->p;
        last = n;
    }
    if (t->kind == GG_TERM_BACKGROUND) {
        double s = len > 1 ? len : 1;
        ggVec3 q;
        q.x = last->o.x + s * last->d.x, q.y = last->o.y + s * last->d.y;
        q.z = last->o.z + s * last->d.z;
        point(pts, max, &k, q, w);
    } else if (t->kind == GG_TERM_DIFFUSE || t->kind == GG_TERM_PHONG) {
        const ggTraceLight *L = term_light(tr, t);
        ggVec3 q;
        if (L) {
            q.x = L->origin.x + L->dir.x, q.y = L->origin.y + L->dir.y;
            q.z = L->origin.z + L->dir.z;
            point(pts, max, &k, q, w);
        }
    }
    return k;
}
