/* SPDX-License-Identifier: MIT */
/*
** ledger.c -- a pixel's colour term by term: every emission, ambient,
** diffuse, Phong and background term of its trees, times the weights and
** absorptions of the rays that carried it, and a bound on how far their
** sum may lie from the rendered value.
**
** The bound. The renderer computes each node's colour as its absorption
** times the sum, in order, of its local terms and of weight * colour of
** its children, and the pixel as the mean of the trees, rounded to float
** (lib/render/shade.c, render.c). In exact arithmetic that is the sum of
** the ledger's terms. With u = 2^-53 and gamma(k) = k u / (1 - k u)
** (Higham, Accuracy and Stability of Numerical Algorithms, 2nd ed.,
** sec. 3.1 and 4.2), each term reaches the renderer's sum through at most
** one product by a weight and one by an absorption per level and one
** rounded addition per other summand of each sum on its way: in all at
** most N + M + 2d + S + 1 roundings for N non-zero terms, M rays, depth d
** and S trees (adding an exact zero rounds nothing). The ledger's own
** products (2 per level, 2 more) and its sum (N - 1 additions) add
** 2d + N + 1. A float pixel, or a float corner of the SPD's corner
** sampling, is within 2^-24 of its double. So
**   |sum - pixel| <= 2^-24 (|pixel| + sum |t|) + gamma(2N + M + 4d + S + 2) sum |t|
** per channel, which ggLedgerCreate states as `bound`.
*/
#include "debug_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct ledger_res {
    ggLedger pub;
    gg_dbg_alloc al;
    size_t cap;
} ledger_res;

GG_API const char *ggTermName(int kind)
{
    static const char *const n[] = {"emission", "ambient", "diffuse", "phong", "background"};
    return kind >= 0 && kind < 5 ? n[kind] : "?";
}

/* a * b per channel, where a weight of exactly 0 keeps out even an
   infinite term: the renderer does not add a child whose weight is 0. */
static ggColor cmul3(ggColor a, ggColor b)
{
    ggColor c;
    c.r = a.r == 0 ? 0 : a.r * b.r, c.g = a.g == 0 ? 0 : a.g * b.g;
    c.b = a.b == 0 ? 0 : a.b * b.b;
    return c;
}

static int is_zero(ggColor c)
{
    return c.r == 0 && c.g == 0 && c.b == 0;
}

static int add_term(ledger_res *lr, int kind, int node, int light, ggColor a, ggColor term)
{
    ggLedger *l = &lr->pub;
    ggLedgerTerm *t;
    if (is_zero(term)) return 0;
    if (gg_mem_grow(lr->al.a, (void **)&l->terms, &lr->cap, l->count + 1, sizeof *l->terms))
        return -1;
    t = &l->terms[l->count++];
    t->kind = kind, t->node = node, t->light = light;
    t->value = cmul3(a, term);
    t->share = 0;
    return 0;
}

/* The terms of node i, whose colour weighs w in the pixel. */
static int node_terms(ledger_res *lr, const ggTrace *tr, int i, ggColor w)
{
    const ggTraceNode *n = ggTraceGetNode(tr, (size_t)i);
    ggColor a = cmul3(w, n->absorption);
    int l;
    if (!n->hit) return add_term(lr, GG_TERM_BACKGROUND, i, -1, w, n->color);
    if (add_term(lr, GG_TERM_AMBIENT, i, -1, a, n->ambient) ||
        add_term(lr, GG_TERM_EMISSION, i, -1, a, n->emission))
        return -1;
    for (l = 0; l < n->nlights; l++) {
        const ggTraceLight *L = ggTraceGetLight(tr, (size_t)(n->first_light + l));
        if (!L) break;
        if (add_term(lr, GG_TERM_DIFFUSE, i, L->light, a, L->diffuse) ||
            add_term(lr, GG_TERM_PHONG, i, L->light, a, L->phong))
            return -1;
    }
    return 0;
}

static int by_share(const void *pa, const void *pb)
{
    const ggLedgerTerm *a = pa, *b = pb;
    if (a->share != b->share) return a->share > b->share ? -1 : 1;
    if (a->node != b->node) return a->node < b->node ? -1 : 1;
    if (a->kind != b->kind) return a->kind < b->kind ? -1 : 1;
    return a->light < b->light ? -1 : a->light > b->light;
}

static double gamma_k(double k)
{
    return k * 0x1p-53 / (1 - k * 0x1p-53);
}

/* Sum, shares and the bound of the module comment. */
static void totals(ggLedger *l, const ggTrace *tr, ggColor px)
{
    size_t i, n = ggTraceNodeCount(tr);
    double pt = px.r + px.g + px.b, g;
    ggColor abs_sum = {0, 0, 0};
    int depth = 0;
    for (i = 0; i < n; i++)
        if (ggTraceGetNode(tr, i)->depth > depth) depth = ggTraceGetNode(tr, i)->depth;
    l->sum.r = l->sum.g = l->sum.b = 0;
    for (i = 0; i < l->count; i++) {
        ggColor v = l->terms[i].value;
        l->sum.r += v.r, l->sum.g += v.g, l->sum.b += v.b;
        abs_sum.r += fabs(v.r), abs_sum.g += fabs(v.g), abs_sum.b += fabs(v.b);
        l->terms[i].share = pt != 0 && isfinite(pt) ? (v.r + v.g + v.b) / pt : 0;
    }
    g = gamma_k(2.0 * (double)l->count + (double)n + 4.0 * depth + gg_dbg_roots(tr) + 2);
    /* (1 + 2^-20): the bound's own rounding, generously. */
    l->bound.r = (0x1p-24 * (fabs(px.r) + abs_sum.r) + g * abs_sum.r) * (1 + 0x1p-20);
    l->bound.g = (0x1p-24 * (fabs(px.g) + abs_sum.g) + g * abs_sum.g) * (1 + 0x1p-20);
    l->bound.b = (0x1p-24 * (fabs(px.b) + abs_sum.b) + g * abs_sum.b) * (1 + 0x1p-20);
    l->pixel = px;
    l->holds = fabs(l->sum.r - px.r) <= l->bound.r && fabs(l->sum.g - px.g) <= l->bound.g &&
               fabs(l->sum.b - px.b) <= l->bound.b;
    if (l->count) qsort(l->terms, l->count, sizeof *l->terms, by_share);
}

GG_API void ggLedgerFree(ggLedger *l)
{
    const ggAllocator *a;
    if (!l) return;
    a = ((ledger_res *)l)->al.a;
    gg_mem_free(a, l->terms);
    gg_mem_free(a, l);
}

GG_API int ggLedgerCreate(const ggTrace *tr, ggColor px, const ggAllocator *alloc, ggLedger **out,
                          ggError *err)
{
    ledger_res *lr;
    ggColor *w;
    size_t i, n;
    if (!tr || !out) return gg_error_set(err, GG_ERROR_INVALID, "ggLedgerCreate: NULL argument");
    *out = NULL; /* after the NULL checks: base.h rule 1 */
    if ((n = ggTraceNodeCount(tr)) == 0)
        return gg_error_set(err, GG_ERROR_INVALID, "ggLedgerCreate: the trace is empty");
    lr = gg_mem_calloc(alloc, 1, sizeof *lr);
    w = gg_mem_calloc(alloc, n, sizeof *w);
    if (!lr || !w) {
        gg_mem_free(alloc, lr), gg_mem_free(alloc, w);
        return gg_error_set(err, GG_ERROR_NOMEM, "ledger: out of memory");
    }
    gg_dbg_alloc_init(&lr->al, alloc);
    gg_dbg_weights(tr, w);
    for (i = 0; i < n; i++)
        if (node_terms(lr, tr, (int)i, w[i])) {
            gg_mem_free(alloc, w);
            ggLedgerFree(&lr->pub);
            return gg_error_set(err, GG_ERROR_NOMEM, "ledger: out of memory");
        }
    gg_mem_free(alloc, w);
    totals(&lr->pub, tr, px);
    *out = &lr->pub;
    return GG_OK;
}
