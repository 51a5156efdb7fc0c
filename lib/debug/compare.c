/* SPDX-License-Identifier: MIT */
/*
** compare.c -- ggTraceCompare: where two recorded ray trees first part.
**
** The trees are walked together in the order the rays of the first were
** cast (a ray, its shadow rays, then its children), matching children by
** what they are: the refracted rays by channel, then the mirror ray. A
** channel refracted on one side only, while the other side's mirror ray
** carries a totally internally reflected share, is a TIR decision; any
** other ray present on one side only is a missing child.
*/
#include "debug_int.h"

#include <string.h>

#define MAX_KIDS 8 /* three refracted channels and a mirror ray, with room */

typedef struct kids {
    int refr[3]; /* refracted child per channel slot (-1: none); slot 0 also for all of RGB */
    int mirror;  /* the reflect or tir child, -1 if none */
    int other[MAX_KIDS], nother;
} kids;

static void children(const ggTrace *t, int i, kids *k)
{
    size_t j, n = ggTraceNodeCount(t);
    k->refr[0] = k->refr[1] = k->refr[2] = -1;
    k->mirror = -1, k->nother = 0;
    for (j = (size_t)i + 1; j < n; j++) {
        const ggTraceNode *c = ggTraceGetNode(t, j);
        if (c->parent != i) continue;
        if (c->kind == GG_RAY_REFRACT && k->refr[c->channel < 0 ? 0 : c->channel] < 0)
            k->refr[c->channel < 0 ? 0 : c->channel] = (int)j;
        else if ((c->kind == GG_RAY_REFLECT || c->kind == GG_RAY_TIR) && k->mirror < 0)
            k->mirror = (int)j;
        else if (k->nother < MAX_KIDS)
            k->other[k->nother++] = (int)j;
    }
}

static int set(ggDivergence *d, int what, int na, int nb, int a, int b)
{
    d->what = what, d->node_a = na, d->node_b = nb, d->a = a, d->b = b;
    d->light = -1;
    return 1;
}

/* The node's own hit and its shadow rays. */
static int compare_hit(const ggTraceNode *x, const ggTraceNode *y, int ia, int ib, const ggTrace *a,
                       const ggTrace *b, ggDivergence *d)
{
    int l, nl;
    if (x->hit != y->hit || (x->hit && x->object != y->object))
        return set(d, x->hit != y->hit ? GG_DIFF_HIT : GG_DIFF_OBJECT, ia, ib,
                   x->hit ? x->object : -1, y->hit ? y->object : -1);
    if (!x->hit) return 0;
    if (x->front != y->front) return set(d, GG_DIFF_FACE, ia, ib, x->front, y->front);
    nl = x->nlights > y->nlights ? x->nlights : y->nlights;
    for (l = 0; l < nl; l++) {
        const ggTraceLight *p =
            l < x->nlights ? ggTraceGetLight(a, (size_t)(x->first_light + l)) : NULL;
        const ggTraceLight *q =
            l < y->nlights ? ggTraceGetLight(b, (size_t)(y->first_light + l)) : NULL;
        if (!p || !q || p->verdict != q->verdict) {
            set(d, GG_DIFF_SHADOW, ia, ib, p ? p->verdict : -1, q ? q->verdict : -1);
            d->light = p ? p->light : q->light;
            return 1;
        }
        if (p->occluder != q->occluder) {
            set(d, GG_DIFF_OCCLUDER, ia, ib, p->occluder, q->occluder);
            d->light = p->light;
            return 1;
        }
    }
    return 0;
}

/* Children present on one side only. */
static int compare_kids(const ggTrace *a, const ggTrace *b, const kids *ka, const kids *kb, int ia,
                        int ib, ggDivergence *d)
{
    int c;
    for (c = 0; c < 3; c++)
        if ((ka->refr[c] < 0) != (kb->refr[c] < 0)) {
            int ma = ka->mirror >= 0 && ggTraceGetNode(a, (size_t)ka->mirror)->kind == GG_RAY_TIR;
            int mb = kb->mirror >= 0 && ggTraceGetNode(b, (size_t)kb->mirror)->kind == GG_RAY_TIR;
            if (ma != mb)
                return set(d, GG_DIFF_TIR, ka->refr[c] >= 0 ? ka->refr[c] : ka->mirror,
                           kb->refr[c] >= 0 ? kb->refr[c] : kb->mirror,
                           ka->refr[c] >= 0 ? GG_RAY_REFRACT : GG_RAY_TIR,
                           kb->refr[c] >= 0 ? GG_RAY_REFRACT : GG_RAY_TIR);
            return set(d, GG_DIFF_CHILD, ka->refr[c], kb->refr[c],
                       ka->refr[c] >= 0 ? GG_RAY_REFRACT : -1,
                       kb->refr[c] >= 0 ? GG_RAY_REFRACT : -1);
        }
    if ((ka->mirror < 0) != (kb->mirror < 0) || ka->nother != kb->nother)
        return set(d, GG_DIFF_CHILD, ka->mirror, kb->mirror,
                   ka->mirror >= 0 ? ggTraceGetNode(a, (size_t)ka->mirror)->kind : -1,
                   kb->mirror >= 0 ? ggTraceGetNode(b, (size_t)kb->mirror)->kind : -1);
    if (ka->mirror >= 0 &&
        ggTraceGetNode(a, (size_t)ka->mirror)->kind != ggTraceGetNode(b, (size_t)kb->mirror)->kind)
        return set(d, GG_DIFF_TIR, ka->mirror, kb->mirror,
                   ggTraceGetNode(a, (size_t)ka->mirror)->kind,
                   ggTraceGetNode(b, (size_t)kb->mirror)->kind);
    (void)ia, (void)ib;
    return 0;
}

static int compare_node(const ggTrace *a, int ia, const ggTrace *b, int ib, ggDivergence *d)
{
    const ggTraceNode *x = ggTraceGetNode(a, (size_t)ia), *y = ggTraceGetNode(b, (size_t)ib);
    kids ka, kb;
    int c;
    if (compare_hit(x, y, ia, ib, a, b, d)) return 1;
    /* A different stop explains the children that follow from it. */
    if (x->stop != y->stop) return set(d, GG_DIFF_STOP, ia, ib, x->stop, y->stop);
    children(a, ia, &ka);
    children(b, ib, &kb);
    if (compare_kids(a, b, &ka, &kb, ia, ib, d)) return 1;
    /* In a's cast order: the refracted rays (by index), then the mirror. */
    for (c = 0; c < 3; c++)
        if (ka.refr[c] >= 0 && (ka.mirror < 0 || ka.refr[c] < ka.mirror) &&
            compare_node(a, ka.refr[c], b, kb.refr[c], d))
            return 1;
    if (ka.mirror >= 0 && compare_node(a, ka.mirror, b, kb.mirror, d)) return 1;
    for (c = 0; c < 3; c++)
        if (ka.refr[c] >= 0 && ka.mirror >= 0 && ka.refr[c] > ka.mirror &&
            compare_node(a, ka.refr[c], b, kb.refr[c], d))
            return 1;
    for (c = 0; c < ka.nother; c++)
        if (compare_node(a, ka.other[c], b, kb.other[c], d)) return 1;
    return 0;
}

static int root(const ggTrace *t, int k)
{
    size_t i, n = ggTraceNodeCount(t);
    for (i = 0; i < n; i++)
        if (ggTraceGetNode(t, i)->parent < 0 && k-- == 0) return (int)i;
    return -1;
}

GG_API const char *ggDiffName(int what)
{
    static const char *const n[] = {"same",   "hit",      "object", "face", "tir",
                                    "shadow", "occluder", "child",  "stop", "samples"};
    return what >= 0 && what < GG_DIFF_COUNT ? n[what] : "?";
}

GG_API int ggTraceCompare(const ggTrace *a, const ggTrace *b, ggDivergence *first)
{
    ggDivergence d;
    int na = a ? gg_dbg_roots(a) : 0, nb = b ? gg_dbg_roots(b) : 0, k, r = 0;
    memset(&d, 0, sizeof d);
    d.node_a = d.node_b = d.light = -1;
    if (na != nb) r = set(&d, GG_DIFF_SAMPLES, -1, -1, na, nb);
    for (k = 0; !r && k < na; k++) r = compare_node(a, root(a, k), b, root(b, k), &d);
    if (first) *first = d;
    return r;
}
