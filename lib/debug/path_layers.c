/* SPDX-License-Identifier: MIT */
/*
** path_layers.c -- path expressions compiled for the shading's layer copy
** (ggPathLayersCompile, debug.h; lib/render/lpe.h runs them). Each
** expression's automaton (path.c) becomes a deterministic one by subset
** construction: its states are the state sets the matcher
** (gg_path_step_event, path_match.c) reaches from the start over every
** event the shading can meet, an event being its kind and the classes of
** its labels (lpe.h). Predicates would need what only the recorder keeps
** for some fields and a pixel's trees for others: a layer refuses them.
*/
#include "debug_int.h"
#include "lpe.h"

#include <string.h>

/* The most states one layer's automaton may have. */
#define GG_LPE_MAX_STATES 4096

/* An event kind's type, scatter, tir flag and what labels it carries
   (1: a surface's, 2: a light's), by GG_LPE_*. */
static const struct {
    int type, scatter, tir, labels;
} kinds[GG_LPE_KINDS] = {
    {PE_C, PS_NONE, 0, 0}, {PE_R, PS_S, 0, 1}, {PE_R, PS_S, 1, 1}, {PE_T, PS_S, 0, 1},
    {PE_R, PS_D, 0, 1},    {PE_R, PS_G, 0, 1}, {PE_L, PS_NONE, 0, 2}, {PE_A, PS_NONE, 0, 0},
    {PE_O, PS_NONE, 0, 1}, {PE_B, PS_NONE, 0, 0}};

/* Slots of the table from a state's set to its number: a power of two
   at least twice the most states, so that probes stay short. */
#define GG_LPE_SLOTS (2 * GG_LPE_MAX_STATES)

typedef struct builder {
    const ggPathExpr *e;
    gg_lpe_dfa *d;
    gg_path_set *sets; /* each DFA state's set */
    size_t cap, ncap;
    int n, rc;
    uint16_t *next;
    uint16_t *slot; /* GG_LPE_SLOTS: a state's number + 1, or 0 for none */
} builder;

static int add_label(long *list, int *n, long v, gg_path_place at, int layer, ggError *err)
{
    int k;
    for (k = 0; k < *n; k++)
        if (list[k] == v) return GG_OK;
    if (*n >= GG_LPE_LABELS)
        return gg_error_set(err, GG_ERROR_LIMIT,
                            "layer %d: %d:%d: more than %d distinct numbers or materials",
                            layer + 1, at.line, at.col, GG_LPE_LABELS);
    list[(*n)++] = v;
    return GG_OK;
}

/* The labels e names, and its refusal of predicates. */
static int labels(const ggPathExpr *e, gg_lpe_dfa *d, int layer, ggError *err)
{
    int c, k, rc;
    for (c = 0; c < e->ncls; c++)
        if (e->cls[c].pred)
            return gg_error_set(err, GG_ERROR_UNSUPPORTED,
                                "layer %d: %d:%d: a path layer takes no predicate [...]: the "
                                "shading does not keep what predicates read",
                                layer + 1, e->cls[c].pred_at.line, e->cls[c].pred_at.col);
    for (c = 0; c < e->npats; c++)
        for (k = 0; k < e->pats[c].nlabels; k++) {
            const int kind = e->pats[c].label_kind[k];
            const gg_path_place at = e->pats[c].label_at[k];
            if (kind == PL_NUMBER)
                rc = add_label(d->num, &d->nnum, e->pats[c].label_num[k], at, layer, err);
            else if (kind == PL_MATERIAL)
                rc = add_label(d->mat, &d->nmat, e->pats[c].label_num[k], at, layer, err);
            else
                rc = GG_OK;
            if (rc != GG_OK) return rc;
        }
    d->ncls = (d->nnum + 1) * (d->nmat + 1);
    d->nsym = GG_LPE_KINDS * d->ncls;
    return GG_OK;
}

static size_t set_hash(const uint64_t *s)
{
    uint64_t h = 0x9E3779B97F4A7C15u;
    int w;
    for (w = 0; w < GG_PATH_WORDS; w++) {
        h ^= s[w];
        h *= 0xBF58476D1CE4E5B9u;
        h ^= h >> 31;
    }
    return (size_t)(h & (GG_LPE_SLOTS - 1));
}

/* The DFA state of set s, added if new; -1 on a limit or no memory. A
   table finds it: a scan of every state, for each of up to 4096 states
   times 810 symbols, took seconds on an expression that ends refused. */
static int state_of(builder *b, const uint64_t *s, int layer, ggError *err)
{
    const ggAllocator *a = b->e->alloc;
    size_t h = set_hash(s);
    while (b->slot[h]) {
        const int i = b->slot[h] - 1;
        if (!memcmp(b->sets[i], s, sizeof(gg_path_set))) return i;
        h = (h + 1) & (GG_LPE_SLOTS - 1);
    }
    if (b->n >= GG_LPE_MAX_STATES) {
        b->rc = gg_error_set(err, GG_ERROR_LIMIT, "layer %d: the automaton needs more than %d states",
                             layer + 1, GG_LPE_MAX_STATES);
        return -1;
    }
    if (gg_mem_grow(a, (void **)&b->sets, &b->cap, (size_t)b->n + 1, sizeof(gg_path_set)) ||
        gg_mem_grow(a, (void **)&b->next, &b->ncap, ((size_t)b->n + 1) * (size_t)b->d->nsym,
                    sizeof *b->next)) {
        b->rc = gg_error_set(err, GG_ERROR_NOMEM, "path layers: out of memory");
        return -1;
    }
    memcpy(b->sets[b->n], s, sizeof(gg_path_set));
    b->slot[h] = (uint16_t)(b->n + 1);
    return b->n++;
}

/* Every transition of DFA state i. */
static int expand(builder *b, int i, int layer, ggError *err)
{
    const gg_lpe_dfa *d = b->d;
    int k, u, m, to;
    for (k = 0; k < GG_LPE_KINDS; k++)
        for (u = 0; u <= d->nnum; u++)
            for (m = 0; m <= d->nmat; m++) {
                const long num = u < d->nnum ? d->num[u] : -1, mat = m < d->nmat ? d->mat[m] : -1;
                gg_path_set in, out;
                memcpy(in, b->sets[i], sizeof in);
                gg_path_step_event(b->e, in, kinds[k].type, kinds[k].scatter, kinds[k].tir,
                                   kinds[k].labels == 1, num, mat, num, out);
                if ((to = state_of(b, out, layer, err)) < 0) return -1;
                b->next[(size_t)i * (size_t)d->nsym + (size_t)(k * d->ncls + u * (d->nmat + 1) + m)] =
                    (uint16_t)to;
            }
    return 0;
}

/* d->term (lpe.h) from d's next and accept: which terms that end a path
   at a hit each (state, class) accepts; then d->quiet, the states that
   accept none of them whatever the class (the shading skips such a layer
   at a hit). */
static void terms(gg_lpe_dfa *d)
{
    const int none = gg_lpe_none(d);
    int s, cls, u;
    for (s = 0; s < d->nstates; s++)
        for (cls = 0; cls < d->ncls; cls++) {
            const unsigned sd = gg_lpe_step(d, (unsigned)s, GG_LPE_RD, cls);
            const unsigned sg = gg_lpe_step(d, (unsigned)s, GG_LPE_RG, cls);
            uint32_t t = 0;
            for (u = 0; u <= d->nnum; u++) {
                const int lc = u * (d->nmat + 1) + d->nmat;
                if (d->accept[gg_lpe_step(d, sd, GG_LPE_L, lc)]) t |= 1u << (GG_LPE_T_RDL + u);
                if (d->accept[gg_lpe_step(d, sg, GG_LPE_L, lc)]) t |= 1u << (GG_LPE_T_RGL + u);
            }
            if (d->accept[gg_lpe_step(d, sd, GG_LPE_A, none)]) t |= GG_LPE_T_A;
            if (d->accept[gg_lpe_step(d, (unsigned)s, GG_LPE_O, cls)]) t |= GG_LPE_T_O;
            if (d->accept[gg_lpe_step(d, (unsigned)s, GG_LPE_B, none)]) t |= GG_LPE_T_B;
            d->term[(size_t)s * (size_t)d->ncls + (size_t)cls] = t;
        }
    for (s = 0; s < d->nstates; s++) {
        d->quiet[s] = 1;
        for (cls = 0; cls < d->ncls; cls++)
            if (d->term[(size_t)s * (size_t)d->ncls + (size_t)cls] & ~GG_LPE_T_B) d->quiet[s] = 0;
    }
}

/* Expression e as layer `layer` into d. */
static int compile_layer(const ggPathExpr *e, gg_lpe_dfa *d, int layer, ggError *err)
{
    builder b;
    gg_path_set none;
    int i, rc = labels(e, d, layer, err);
    if (rc != GG_OK) return rc;
    memset(&b, 0, sizeof b);
    b.e = e, b.d = d;
    memset(none, 0, sizeof none);
    if (!(b.slot = gg_mem_calloc(e->alloc, GG_LPE_SLOTS, sizeof *b.slot)))
        return gg_error_set(err, GG_ERROR_NOMEM, "path layers: out of memory");
    /* state 0: dead; 1: the start, before C */
    if (state_of(&b, none, layer, err) < 0 || state_of(&b, e->closure[0], layer, err) < 0) rc = -1;
    for (i = 0; rc == 0 && i < b.n; i++) rc = expand(&b, i, layer, err);
    if (rc == 0 && !(d->accept = gg_mem_calloc(e->alloc, (size_t)b.n, 2)))
        rc = b.rc = gg_error_set(err, GG_ERROR_NOMEM, "path layers: out of memory");
    if (rc == 0) {
        d->quiet = d->accept + b.n;
        for (i = 0; i < b.n; i++)
            d->accept[i] = e->accept >= 0 && (b.sets[i][e->accept / 64] >> (e->accept % 64) & 1u);
        d->nstates = b.n, d->next = b.next, b.next = NULL;
        d->start = (uint16_t)gg_lpe_step(d, 1, GG_LPE_C, gg_lpe_none(d));
        if (!(d->term = gg_mem_calloc(e->alloc, (size_t)b.n * (size_t)d->ncls, sizeof *d->term)))
            rc = b.rc = gg_error_set(err, GG_ERROR_NOMEM, "path layers: out of memory");
        else
            terms(d);
    }
    gg_mem_free(e->alloc, b.sets), gg_mem_free(e->alloc, b.next), gg_mem_free(e->alloc, b.slot);
    return rc == 0 ? GG_OK : b.rc;
}

GG_API void ggPathLayersFree(ggPathLayers *layers)
{
    int l;
    if (!layers) return;
    for (l = 0; l < layers->n; l++) {
        gg_mem_free(layers->alloc, layers->layer[l].next);
        gg_mem_free(layers->alloc, layers->layer[l].accept);
        gg_mem_free(layers->alloc, layers->layer[l].term);
    }
    gg_mem_free(layers->alloc, layers);
}

GG_API int ggPathLayersCount(const ggPathLayers *layers)
{
    return layers ? layers->n : 0;
}

int gg_path_layers_of(const ggPathExpr *e, ggPathLayers **out, ggError *err)
{
    ggPathLayers *P;
    int rc;
    *out = NULL;
    if (!(P = gg_mem_calloc(e->alloc, 1, sizeof *P)))
        return gg_error_set(err, GG_ERROR_NOMEM, "path layers: out of memory");
    if (e->alloc) P->alloc_copy = *e->alloc, P->alloc = &P->alloc_copy;
    P->n = 1;
    if ((rc = compile_layer(e, &P->layer[0], 0, err)) != GG_OK) {
        ggPathLayersFree(P);
        return rc;
    }
    P->live = P->layer[0].start ? 1u : 0u;
    P->start[0] = P->layer[0].start;
    *out = P;
    return GG_OK;
}

GG_API int ggPathLayersCompile(const char *const *exprs, int n, const ggAllocator *alloc,
                               ggPathLayers **out, ggError *err)
{
    ggPathLayers *P;
    int l, rc = GG_OK;
    if (!exprs || !out)
        return gg_error_set(err, GG_ERROR_INVALID, "ggPathLayersCompile: NULL argument");
    *out = NULL; /* after the NULL checks: base.h rule 1 */
    if (n < 1 || n > GG_LAYERS_MAX)
        return gg_error_set(err, GG_ERROR_INVALID, "ggPathLayersCompile: %d layers (1..%d)", n,
                            GG_LAYERS_MAX);
    if (!(P = gg_mem_calloc(alloc, 1, sizeof *P)))
        return gg_error_set(err, GG_ERROR_NOMEM, "path layers: out of memory");
    if (alloc) P->alloc_copy = *alloc, P->alloc = &P->alloc_copy;
    for (l = 0; l < n && rc == GG_OK; l++) {
        ggPathExpr *e = NULL;
        ggError pe;
        if (!exprs[l]) {
            rc = gg_error_set(err, GG_ERROR_INVALID, "ggPathLayersCompile: layer %d is NULL",
                              l + 1);
            break;
        }
        rc = ggPathParse(exprs[l], P->alloc, &e, &pe);
        if (rc != GG_OK) {
            gg_error_set(err, rc, "layer %d: %s", l + 1, pe.message);
            break;
        }
        P->n = l + 1;
        rc = compile_layer(e, &P->layer[l], l, err);
        ggPathFree(e);
    }
    if (rc != GG_OK) {
        ggPathLayersFree(P);
        return rc;
    }
    for (l = 0; l < n; l++) {
        P->start[l] = P->layer[l].start;
        if (P->layer[l].start) P->live |= 1u << l;
    }
    *out = P;
    return GG_OK;
}
