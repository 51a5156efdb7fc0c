/* SPDX-License-Identifier: MIT */
/*
** pred_eval.c -- evaluating a compiled predicate (pred.c) on a recorded
** pixel, in three-valued logic: a field a ray does not have is unknown,
** and unknown rays count for neither some nor all. Also what a predicate
** needs recorded.
*/
#include "debug_int.h"

#include <math.h>
#include <string.h>

enum { F = 0, T = 1, U = 2 };

/* The ray a quantifier's body is looking at: a node, or one of its
   shadow rays (L not NULL; n is then the node whose hit cast it). */
typedef struct ray_ref {
    const ggTraceNode *n;
    const ggTraceLight *L;
    int index;
} ray_ref;

typedef struct ctx {
    const ggPredicate *p;
    const gg_dbg_pixel *px;
    int nroots;
} ctx;

typedef struct val {
    int known;
    double v;
} val;

static val known(double v)
{
    val r;
    r.known = 1, r.v = v;
    return r;
}
static const val unknown = {0, 0};

static double comp(ggColor c, int k)
{
    double m;
    switch (k) {
    case 0:
        return c.r;
    case 1:
        return c.g;
    case 2:
        return c.b;
    case 3:
        m = c.r > c.g ? c.r : c.g;
        return m > c.b ? m : c.b;
    default:
        m = c.r < c.g ? c.r : c.g;
        return m < c.b ? m : c.b;
    }
}

/* Weight in the pixel of node i's colour: gg_dbg_weights for one node,
   the same products in the same order (so the same bits). */
static ggColor weight_up(const ggTrace *t, int i, double root)
{
    const ggTraceNode *n = ggTraceGetNode(t, (size_t)i);
    ggColor w, wp;
    if (n->parent < 0 || n->parent >= i) {
        w.r = w.g = w.b = root;
        return w;
    }
    wp = weight_up(t, n->parent, root);
    {
        const ggTraceNode *up = ggTraceGetNode(t, (size_t)n->parent);
        w.r = wp.r * up->absorption.r * n->weight.r;
        w.g = wp.g * up->absorption.g * n->weight.g;
        w.b = wp.b * up->absorption.b * n->weight.b;
    }
    return w;
}

static ggColor node_weight(const ctx *c, int i)
{
    if (c->px->w) return c->px->w[i];
    return weight_up(c->px->trace, i, 1.0 / (c->nroots > 0 ? c->nroots : 1));
}

static ggColor light_gave(const ggTraceLight *L)
{
    ggColor c;
    c.r = L->diffuse.r + L->phong.r, c.g = L->diffuse.g + L->phong.g;
    c.b = L->diffuse.b + L->phong.b;
    return c;
}

static long rays_cast(const ggTrace *t)
{
    size_t i, n = ggTraceLightCount(t);
    long k = (long)ggTraceNodeCount(t);
    for (i = 0; i < n; i++) k += ggTraceGetLight(t, i)->verdict != GG_SHADOW_FACING_AWAY;
    return k;
}

/* Fields of the surface a ray hit, or left (shadow rays). */
static val surface_field(int f, const ggTraceNode *n)
{
    if (!n->hit) return unknown;
    switch (f) {
    case PF_OBJECT:
        return known(n->object);
    case PF_MATERIAL:
        return known(n->material);
    case PF_LINE:
        return known(n->line);
    case PF_SHAPE:
        return known(n->shape);
    case PF_FRONT:
        return known(n->front);
    default:
        return known(!n->front); /* PF_BACK */
    }
}

/* The numeric state of the hit (a shadow ray: of the hit it leaves);
   NaN, where a field does not apply, is unknown. */
static val numeric_field(int f, const ggTraceNode *n)
{
    double v = f == PF_PERR         ? n->perr
               : f == PF_OFFSET     ? n->offset
               : f == PF_TIR_MARGIN ? n->tir_margin
                                    : n->edge;
    return n->hit && v == v ? known(v) : unknown;
}

static val shadow_field(int f, const ggTraceLight *L, int k)
{
    if (!L) return unknown;
    switch (f) {
    case PF_LIGHT:
        return known(L->light);
    case PF_VERDICT:
        return known(L->verdict);
    case PF_OCCLUDER:
        return known(L->occluder);
    case PF_TRANSMITTANCE:
        return known(comp(L->transmittance, k));
    case PF_DIFFUSE:
        return known(comp(L->diffuse, k));
    default:
        return known(comp(L->phong, k)); /* PF_PHONG */
    }
}

static val ray_field(const ctx *c, const gg_pnode *pn, const ray_ref *r)
{
    const ggTraceNode *n = r->n;
    const ggTraceLight *L = r->L;
    int f = pn->field, k = pn->comp;
    switch (f) {
    case PF_KIND:
        return known(L ? GG_PRED_SHADOW : n->kind);
    case PF_DEPTH:
        return known(n->depth);
    case PF_CHANNEL:
        return known(n->channel);
    case PF_MEDIUM:
        return known(n->medium);
    case PF_OBJECT:
    case PF_MATERIAL:
    case PF_LINE:
    case PF_SHAPE:
    case PF_FRONT:
    case PF_BACK:
        return surface_field(f, n);
    case PF_HIT:
        return L ? unknown : known(n->hit);
    case PF_MISS:
        return L ? unknown : known(!n->hit);
    case PF_T:
        if (L) return L->occluder >= 0 ? known(L->t_block) : unknown;
        return n->hit ? known(n->t) : unknown;
    case PF_STOP:
        return L ? unknown : known(n->stop);
    case PF_FRESNEL:
        return L || !n->hit || n->fresnel < 0 ? unknown : known(n->fresnel);
    case PF_WEIGHT: {
        ggColor w = node_weight(c, r->index);
        if (L) w.r *= n->absorption.r, w.g *= n->absorption.g, w.b *= n->absorption.b;
        return known(comp(w, k));
    }
    case PF_COLOR:
        return known(comp(L ? light_gave(L) : n->color, k));
    case PF_ABSORPTION:
        return L ? unknown : known(comp(n->absorption, k));
    case PF_NONFINITE:
        return known(gg_dbg_nonfinite(L ? light_gave(L) : n->color));
    case PF_PERR:
    case PF_OFFSET:
    case PF_TIR_MARGIN:
    case PF_EDGE:
        return numeric_field(f, n);
    case PF_TRIANGLE:
        return n->hit && n->triangle >= 0 ? known((double)n->triangle) : unknown;
    case PF_NODES:
        return L || n->nodes < 0 ? unknown : known((double)n->nodes);
    case PF_PRIMS:
        return L || n->prims < 0 ? unknown : known((double)n->prims);
    default:
        return shadow_field(f, L, k);
    }
}

static val operand(const ctx *c, int i, const ray_ref *r);

static int eval(const ctx *c, int i, const ray_ref *r);

/* Run a quantifier's body over every ray: the number of rays for which
   it is true (some: stops at the first; all: counts the false ones). */
static long over_rays(const ctx *c, int body, int op)
{
    const ggTrace *t = c->px->trace;
    size_t i, n = ggTraceNodeCount(t);
    long count = 0;
    int l;
    for (i = 0; i < n; i++) {
        ray_ref r;
        int v;
        r.n = ggTraceGetNode(t, i), r.L = NULL, r.index = (int)i;
        v = eval(c, body, &r);
        if (op == PN_ALL ? v == F : v == T) {
            if (op != PN_COUNT) return 1;
            count++;
        }
        for (l = 0; r.n->hit && l < r.n->nlights; l++) {
            r.L = ggTraceGetLight(t, (size_t)(r.n->first_light + l));
            if (!r.L) break;
            v = eval(c, body, &r);
            if (op == PN_ALL ? v == F : v == T) {
                if (op != PN_COUNT) return 1;
                count++;
            }
        }
    }
    return count;
}

static val operand(const ctx *c, int i, const ray_ref *r)
{
    const gg_pnode *pn = &c->p->n[i];
    switch (pn->op) {
    case PN_NUM:
        return known(pn->num);
    case PN_COUNT:
        return c->px->trace ? known((double)over_rays(c, pn->a, PN_COUNT)) : unknown;
    default:
        break;
    }
    switch (pn->field) {
    case PF_X:
        return known(c->px->x);
    case PF_Y:
        return known(c->px->y);
    case PF_PIXEL:
        return known(comp(c->px->px, pn->comp));
    case PF_RAYS:
        return c->px->trace ? known((double)rays_cast(c->px->trace)) : unknown;
    default:
        return r ? ray_field(c, pn, r) : unknown;
    }
}

static int compare(double a, double b, int cmp)
{
    switch (cmp) {
    case PC_EQ:
        return a == b;
    case PC_NE:
        return a != b;
    case PC_LT:
        return a < b;
    case PC_LE:
        return a <= b;
    case PC_GT:
        return a > b;
    default:
        return a >= b;
    }
}

static int eval(const ctx *c, int i, const ray_ref *r)
{
    const gg_pnode *pn = &c->p->n[i];
    int a, b;
    val x, y;
    switch (pn->op) {
    case PN_OR:
        if ((a = eval(c, pn->a, r)) == T) return T;
        b = eval(c, pn->b, r);
        return b == T ? T : a == U || b == U ? U : F;
    case PN_AND:
        if ((a = eval(c, pn->a, r)) == F) return F;
        b = eval(c, pn->b, r);
        return b == F ? F : a == U || b == U ? U : T;
    case PN_NOT:
        a = eval(c, pn->a, r);
        return a == U ? U : a == T ? F : T;
    case PN_SOME:
        return c->px->trace && over_rays(c, pn->a, PN_SOME) ? T : F;
    case PN_ALL:
        return c->px->trace && !over_rays(c, pn->a, PN_ALL) ? T : F;
    case PN_BOOL:
        x = operand(c, i, r);
        return !x.known ? U : x.v != 0 ? T : F;
    default: /* PN_CMP */
        x = operand(c, pn->a, r), y = operand(c, pn->b, r);
        if (!x.known || !y.known) return U;
        return compare(x.v, y.v, pn->cmp) ? T : F;
    }
}

int gg_pred_eval(const ggPredicate *p, const gg_dbg_pixel *px)
{
    ctx c;
    c.p = p, c.px = px;
    c.nroots = px->trace ? gg_dbg_roots(px->trace) : 0;
    return eval(&c, p->root, NULL) == T;
}

GG_API int ggPredicateMatch(const ggPredicate *p, const ggTrace *trace, int x, int y, ggColor pixel)
{
    gg_dbg_pixel px;
    if (!p || !trace) return 0;
    memset(&px, 0, sizeof px);
    px.trace = trace, px.x = x, px.y = y, px.px = pixel;
    return gg_pred_eval(p, &px);
}

/* ---- what a predicate needs recorded ---- */

enum { A = 3 }; /* abstract value: could be anything */

static int lacks_on_shadow(int f)
{
    return f == PF_HIT || f == PF_MISS || f == PF_STOP || f == PF_FRESNEL || f == PF_ABSORPTION;
}

/* The body's value on a shadow ray whose data is not known. */
static int on_shadow(const ggPredicate *p, int i)
{
    const gg_pnode *pn = &p->n[i];
    int a, b;
    switch (pn->op) {
    case PN_NOT:
        a = on_shadow(p, pn->a);
        return a == T ? F : a == F ? T : a;
    case PN_AND:
    case PN_OR:
        a = on_shadow(p, pn->a), b = on_shadow(p, pn->b);
        if (pn->op == PN_AND ? (a == F || b == F) : (a == T || b == T))
            return pn->op == PN_AND ? F : T;
        if (a == A || b == A) return A;
        if (a == b) return a;
        return U;
    case PN_BOOL:
        return lacks_on_shadow(pn->field) ? U : A;
    case PN_CMP: {
        const gg_pnode *l = &p->n[pn->a], *r = &p->n[pn->b];
        const gg_pnode *f = l->op == PN_FIELD ? l : r, *k = f == l ? r : l;
        if ((l->op == PN_FIELD && lacks_on_shadow(l->field)) ||
            (r->op == PN_FIELD && lacks_on_shadow(r->field)))
            return U;
        if (f->op == PN_FIELD && f->field == PF_KIND && k->op == PN_NUM &&
            (pn->cmp == PC_EQ || pn->cmp == PC_NE))
            return ((k->num == GG_PRED_SHADOW) == (pn->cmp == PC_EQ)) ? T : F;
        return A;
    }
    default:
        return A;
    }
}

static unsigned needs_of(const ggPredicate *p, int i)
{
    const gg_pnode *pn = &p->n[i];
    unsigned m = 0;
    int v;
    if (pn->a >= 0) m |= needs_of(p, pn->a);
    if (pn->b >= 0) m |= needs_of(p, pn->b);
    switch (pn->op) {
    case PN_SOME:
    case PN_COUNT:
    case PN_ALL:
        m |= GG_NEED_TREE;
        v = on_shadow(p, pn->a);
        if (v == A || v == (pn->op == PN_ALL ? F : T)) m |= GG_NEED_LIGHTS;
        break;
    case PN_FIELD:
    case PN_BOOL:
        if (pn->field == PF_WEIGHT) m |= GG_NEED_WEIGHT;
        if (pn->field == PF_RAYS) m |= GG_NEED_TREE | GG_NEED_LIGHTS;
        if (pn->field == PF_X || pn->field == PF_Y) m |= GG_NEED_XY;
        if (pn->field == PF_NODES || pn->field == PF_PRIMS) m |= GG_NEED_COST;
        break;
    default:
        break;
    }
    return m;
}

unsigned gg_pred_analyse(const ggPredicate *p)
{
    return needs_of(p, p->root);
}

int gg_pred_eval_ray(const ggPredicate *p, const gg_dbg_pixel *px, int node, const ggTraceLight *L)
{
    ctx c;
    ray_ref r;
    c.p = p, c.px = px;
    c.nroots = gg_dbg_roots(px->trace);
    r.n = ggTraceGetNode(px->trace, (size_t)node), r.L = L, r.index = node;
    return r.n && eval(&c, p->root, &r) == T;
}
