/* SPDX-License-Identifier: MIT */
/*
** shade.c -- rayColor: the lecture notes' pseudocode made right.
**
**   colour = ke + kd C ambient + sum over lights of (kd C (N.L) + ks (R.V)^shine) light
**            + ks' reflection + kt' refraction
**
** where ks' and kt' are ks and kt, or Fresnel-weighted, and the direct term
** is ADDED (the notes' draft assigned it). Recursion stops at the depth
** limit; on total internal reflection the transmitted share reflects.
**
** The body is written once (shade_hit) and compiled twice with the effect
** set as a compile-time constant: the basic path for opaque scenes, where
** every refraction/absorption/dispersion branch is dead code, and the
** full path. Which one runs is decided per render from the scene's effect
** set, so an opaque diffuse scene never pays for refraction.
*/
#include "shade.h"
#include "refract_unit.h"

#include "trace_int.h"
#include "vec.h"

#include <math.h>
#include <string.h>

#define FX_BASIC                                                                                 \
    (GG_EFFECT_SHADOWS | GG_EFFECT_REFLECTION | GG_EFFECT_PHONG | GG_EFFECT_EMISSION |           \
     GG_EFFECT_TEXTURES | GG_EFFECT_IMPLICIT | GG_EFFECT_SUPERSAMPLING)
#define FX_FULL GG_EFFECT_ALL
/* Not an effect: the path that also records the ray tree (trace.h). */
#define FX_RECORD (1u << 30)
#define FX_REC    (FX_FULL | FX_RECORD)

/* Shadow rays through transparent occluders give up after this many
   surfaces (the light is then taken as blocked). */
#define GG_MAX_SHADOW_STEPS 64

#if defined(__GNUC__)
#define GG_INLINE static inline __attribute__((always_inline))
#else
#define GG_INLINE static inline
#endif

/* A ray in flight. channel < 0 carries all of R, G, B; 0..2 carries one
   wavelength after a dispersive surface split the ray. */
typedef struct ray_state {
    ggVec3 o, d;        /* d is unit length */
    uint32_t from_prim; /* the primitive the ray leaves (UINT32_MAX for eye rays) */
    uint32_t inside;    /* a sphere the ray starts inside of, or UINT32_MAX (a hint) */
    int depth;
    int channel;
    gg_media media;
    double weight; /* this ray's weight in the pixel (largest channel) */
    int kind;   /* GG_RAY_*, recorded only */
    int parent; /* parent node, recorded only */
} ray_state;

/* known: the ray's closest hit when the caller has already asked the
   geometry (eye rays from the renderer's tile loop), else NULL. */
static ggColor trace_basic(const gg_shade_ctx *c, const ray_state *r, gg_shade_thread *th,
                           const gg_hit *known);
static ggColor trace_full(const gg_shade_ctx *c, const ray_state *r, gg_shade_thread *th,
                          const gg_hit *known);

/* The same path's recursion: FX is a compile-time constant everywhere.
   GG_NO_RECORDER builds the library without the recording path, only to
   measure what having it costs (make bench-trace). */
#ifdef GG_NO_RECORDER
#define TRACE_CHILD(FX, c, r, th)                                                               \
    ((FX) == FX_BASIC ? trace_basic(c, r, th, NULL) : trace_full(c, r, th, NULL))
#else
static ggColor trace_rec(const gg_shade_ctx *c, const ray_state *r, gg_shade_thread *th,
                         const gg_hit *known);
#define TRACE_CHILD(FX, c, r, th)                                                               \
    ((FX) == FX_BASIC   ? trace_basic(c, r, th, NULL)                                           \
     : (FX) == FX_FULL ? trace_full(c, r, th, NULL)                                             \
                       : trace_rec(c, r, th, NULL))
#endif

void gg_shade_init(gg_shade_ctx *ctx, const ggScene *s, int max_depth, unsigned force,
                   bool spd_rules, const ggAccuracy *acc)
{
    ctx->s = s;
    ctx->max_depth = max_depth;
    ctx->fx = s->effects | force;
    ctx->spd_rules = spd_rules;
    if (acc) ctx->acc = *acc;
    else memset(&ctx->acc, 0, sizeof ctx->acc);
    /* A Fresnel override on a transmitter needs the Fresnel code. */
    if (ctx->acc.fresnel >= GG_ACC_FRESNEL_SCHLICK && (s->effects & GG_EFFECT_REFRACTION))
        ctx->fx |= GG_EFFECT_FRESNEL;
    ctx->rec = NULL;
}

/* Origin of a ray leaving sf in direction d, as the offset knob says. The
   fixed variant is the textbook one: one epsilon and nothing else (it also
   drops the skip of the planar primitive a ray leaves, see leave_prim). */
static ggVec3 spawn(const gg_shade_ctx *c, const gg_surf *sf, ggVec3 d)
{
    if (c->acc.offset == GG_ACC_OFFSET_FIXED)
        return gg_offset_origin_fixed(sf, d, c->acc.offset_eps > 0 ? c->acc.offset_eps : 1e-6);
    return gg_offset_origin(sf, d, GG_OFFSET_SCALED);
}

/* The Fresnel mode in force for a material (the knob overrides dielectrics). */
static int fresnel_mode(const gg_shade_ctx *c, const ggMaterial *m)
{
    if (m->fresnel == GG_FRESNEL_CONDUCTOR || c->acc.fresnel == 0) return m->fresnel;
    return c->acc.fresnel == GG_ACC_FRESNEL_NONE      ? GG_FRESNEL_NONE
           : c->acc.fresnel == GG_ACC_FRESNEL_SCHLICK ? GG_FRESNEL_SCHLICK
                                                      : GG_FRESNEL_EXACT;
}

static double media_index(const ggScene *s, const gg_media *m, int channel)
{
    const gg_mat_fast *f;
    if (m->n == 0) return 1.0;
    f = &s->mfast[m->mat[m->n - 1]];
    return channel == 0 ? f->n_r : channel == 2 ? f->n_b : f->n_g;
}

static double mat_index(const ggScene *s, int mat, int channel)
{
    const gg_mat_fast *f = &s->mfast[mat];
    return channel == 0 ? f->n_r : channel == 2 ? f->n_b : channel == 1 ? f->n_g
                                                                         : s->materials[mat].ior;
}

/* Remove material mat from the stack (the innermost occurrence). */
static void media_exit(gg_media *m, int mat)
{
    int i, j;
    for (i = m->n - 1; i >= 0; i--)
        if (m->mat[i] == mat) {
            for (j = i; j + 1 < m->n; j++) m->mat[j] = m->mat[j + 1];
            m->n--;
            return;
        }
}

static int media_has(const gg_media *m, int mat)
{
    int i;
    for (i = 0; i < m->n; i++)
        if (m->mat[i] == mat) return 1;
    return 0;
}

static void media_enter(gg_media *m, int mat)
{
    if (m->n < GG_MAX_MEDIA) m->mat[m->n++] = mat;
}

/* Beer-Lambert over `dist` in the innermost medium. */
static ggColor media_transmittance(const ggScene *s, const gg_media *m, double dist)
{
    ggColor a;
    if (m->n == 0) return rgb(1, 1, 1);
    a = s->mfast[m->mat[m->n - 1]].alpha;
    if (cis0(a)) return rgb(1, 1, 1);
    /* exp(-0 * inf) must be 1, not NaN: test the coefficient first. */
    return rgb(a.r > 0 ? exp(-a.r * dist) : 1, a.g > 0 ? exp(-a.g * dist) : 1,
               a.b > 0 ? exp(-a.b * dist) : 1);
}

static gg_rayq make_q(ggVec3 o, ggVec3 d, double tmax, uint32_t ignore, unsigned skip)
{
    gg_rayq q;
    q.o = o, q.d = d, q.tmin = 0, q.tmax = tmax, q.ignore_prim = ignore, q.skip_flags = skip;
    return q;
}

/* r = v - 2 n (v.n) for unit n, in plain double: the hot-path twin of
   ggReflection, which spends double-double arithmetic to be exact for any
   input. With unit vectors the plain formula is within a few ulp. */
static inline ggVec3 reflect(ggVec3 v, ggVec3 n) { return v3madd(v, n, -2 * v3dot(v, n)); }

static uint32_t leave_prim(const ggScene *s, uint32_t prim)
{
    int k = gg_geom_prim_kind(s->geom, prim);
    return k == GG_SHAPE_TRIANGLE || k == GG_SHAPE_POLYGON || k == GG_SHAPE_RECT ? prim
                                                                                 : UINT32_MAX;
}

/* Light arriving at the shadow origin from a light at parameter 1 along d
   (d = light - o), through transparent occluders: kt per surface crossed
   and absorption inside. Returns black if an opaque surface blocks.
   *first_obj receives the first object crossed (-1 if none) and *t_first
   where (parameter of the original ray). all (if not NULL): the caller
   has found nothing opaque on the segment, and these are its transparent
   crossings (gg_geom_shadow_query_all). */
static ggColor shadow_walk(const gg_shade_ctx *c, ggVec3 o, ggVec3 d, uint32_t from,
                           const gg_media *start, int *first_obj, double *t_first, int pre,
                           const gg_hit *pre_hit, const gg_tcol *all)
{
    const ggScene *s = c->s;
    const ggVec3 light = v3add(o, d);
    gg_media m = *start;
    ggColor tr = rgb(1, 1, 1);
    double len = v3len(d);
    gg_rayq q = make_q(o, d, 1.0, from, 0);
    gg_hit h;
    uint32_t in_sphere = UINT32_MAX; /* a sphere the current segment starts inside of */
    int step;
    *first_obj = -1;
    *t_first = 1;
    /* Nothing transparent near the segment: the walk's first query would
       miss (what blocks opaquely was ruled out by the caller). */
    if (pre < 0 && !gg_geom_transparent_may_hit(s->geom, o, d))
        return media_transmittance(s, &m, len);
    /* Every crossing known, nothing opaque: no query, no hit point, no
       offset origin is needed, only kt and the media between crossings.
       The stepwise walk below asks again from just past each surface: for
       lists that overflowed or met an implicit surface, for walks that
       start inside a sphere, and for the fixed-epsilon knob, whose re-hits
       are part of what the accuracy study shows. */
    if (all && all->complete && c->acc.offset != GG_ACC_OFFSET_FIXED) {
        double prev = 0;
        int i;
        for (i = 0; i < all->n; i++) {
            const gg_hit *hi = &all->h[i];
            int obj = gg_geom_prim_object(s->geom, hi->prim), mat = s->objects[obj].material;
            if (*first_obj < 0) *first_obj = obj, *t_first = hi->t;
            tr = cmul(tr, media_transmittance(s, &m, (hi->t - prev) * len));
            tr = cscale(tr, s->materials[mat].kt);
            if (!media_has(&m, mat)) media_enter(&m, mat);
            else media_exit(&m, mat);
            if (cmaxc(tr) <= 0) return tr;
            prev = hi->t;
        }
        return cmul(tr, media_transmittance(s, &m, (1 - prev) * len));
    }
    for (step = 0; step < GG_MAX_SHADOW_STEPS; step++) {
        int obj, mat, found;
        gg_surf sf;
        /* The first query may come answered (pre >= 0: gg_geom_shadow_query
           found the nearest hit, pre = 1, or none, pre = 0). */
        if (step == 0 && pre >= 0) {
            found = pre;
            if (found) h = *pre_hit;
        } else {
            found = -1;
            if (in_sphere != UINT32_MAX)
                found = gg_geom_intersect_inside(s->geom, &q, in_sphere, &h);
            if (found < 0) found = gg_geom_intersect(s->geom, &q, &h);
        }
        if (!found) return cmul(tr, media_transmittance(s, &m, len));
        obj = gg_geom_prim_object(s->geom, h.prim);
        mat = s->objects[obj].material;
        if (*first_obj < 0) *first_obj = obj, *t_first = h.t;
        if (s->materials[mat].kt <= 0) {
            *first_obj = obj, *t_first = h.t;
            return rgb(0, 0, 0);
        }
        tr = cmul(tr, media_transmittance(s, &m, h.t * len));
        tr = cscale(tr, s->materials[mat].kt);
        gg_geom_surface_ex(s->geom, &q, &h, &sf, 0u);
        if (!media_has(&m, mat)) media_enter(&m, mat);
        else media_exit(&m, mat);
        if (cmaxc(tr) <= 0) return tr;
        /* Go on from just past this surface towards the light. */
        q.o = spawn(c, &sf, q.d);
        q.d = v3sub(light, q.o);
        len = v3len(q.d);
        q.ignore_prim = c->acc.offset == GG_ACC_OFFSET_FIXED ? UINT32_MAX : leave_prim(s, h.prim);
        /* Crossed into a sphere: the next surface may well be its far side
           (gg_geom_intersect_inside checks that nothing else can be). */
        in_sphere = q.ignore_prim == UINT32_MAX && v3dot(q.d, sf.ng) < 0 ? h.prim : UINT32_MAX;
    }
    return rgb(0, 0, 0);
}

#define CH_ADD(col, ch, x)                                                                       \
    do {                                                                                         \
        if ((ch) == 0) (col).r += (x);                                                           \
        else if ((ch) == 1) (col).g += (x);                                                      \
        else (col).b += (x);                                                                     \
    } while (0)

/* Weight of a child in one channel only (a dispersed ray). */
static ggColor channel_weight(int ch, double w)
{
    return rgb(ch == 0 ? w : 0, ch == 1 ? w : 0, ch == 2 ? w : 0);
}

/* The body of rayColor at a hit, specialised by FX at compile time. node
   is this ray's record (FX_RECORD only). */
GG_INLINE ggColor shade_hit(const gg_shade_ctx *c, const ray_state *r, const gg_rayq *q,
                            const gg_hit *h, gg_shade_thread *th, int node, const unsigned FX)
{
    const ggScene *s = c->s;
    const int32_t obj = gg_geom_prim_object(s->geom, h->prim);
    const int mi = s->objects[obj].material;
    const ggMaterial *m = &s->materials[mi];
    const gg_mat_fast *mf = &s->mfast[mi];
    /* Rays leaving a planar primitive cannot meet it again: skip it
       outright. Curved ones (a sphere's far side, a torus shadowing
       itself) must stay in; the origin offset keeps them robust. */
    const uint32_t leave = c->acc.offset == GG_ACC_OFFSET_FIXED ? UINT32_MAX : leave_prim(s, h->prim);
    ggTrace *rec = c->rec;
    gg_surf sf;
    ggVec3 ng, ns, v = r->d, o_out;
    ggColor col, kdc;
    int front;
    size_t li;

    /* (u, v) costs an atan2 on curved shapes: only for textures and the
       recorder. */
    gg_geom_surface_ex(s->geom, q, h, &sf,
                       ((FX & FX_RECORD) || (mf->flags & GG_MF_TEXTURE)) ? GG_SURF_UV : 0u);
    /* Normals facing the incoming ray: surfaces are two-sided. */
    front = v3dot(v, sf.ng) < 0;
    ng = front ? sf.ng : v3neg(sf.ng);
    ns = front ? sf.ns : v3neg(sf.ns);
    /* The offset depends only on the side a new ray leaves to: shadow and
       mirror rays all leave on the incoming side, so share one origin. */
    o_out = spawn(c, &sf, ng);

    kdc = mf->kd_color;
    if ((FX & GG_EFFECT_TEXTURES) && (mf->flags & GG_MF_TEXTURE))
        kdc = cscale(gg_scene_surface_color(s, mi, sf.u, sf.v, c->acc.texture), m->kd);

    /* Emission and ambient. */
    col = cmul(kdc, s->ambient);
    if ((FX & GG_EFFECT_EMISSION) && (mf->flags & GG_MF_EMIT)) col = cadd(col, m->ke);

    if ((FX & FX_RECORD) && node >= 0) {
        ggTraceNode *N = &rec->nodes[node];
        N->hit = true;
        N->object = obj, N->shape = s->objects[obj].kind, N->material = mi;
        N->line = s->objects[obj].line;
        N->t = h->t, N->p = sf.p, N->ng = sf.ng, N->ns = sf.ns, N->front = front;
        N->u = sf.u, N->v = sf.v;
        N->surface = gg_scene_surface_color(s, mi, sf.u, sf.v, c->acc.texture);
        N->ambient = cmul(kdc, s->ambient);
        N->emission = (mf->flags & GG_MF_EMIT) ? m->ke : rgb(0, 0, 0);
        N->first_light = (int)rec->nlights;
        N->n_other = N->n_medium;
    }

    /* Direct light: one shadow ray per light the surface faces. */
    if (FX & GG_EFFECT_SHADOWS) {
        for (li = 0; li < s->nlights; li++) {
            ggVec3 L = v3sub(s->lights[li].pos, sf.p), Lu, so, sd;
            ggColor lc = s->light_colors[li], diff, ph = rgb(0, 0, 0);
            double nl, len, tb = 1;
            int verdict = GG_SHADOW_VISIBLE, occ = -1, lr = -1;
            gg_rayq sq;
            if ((FX & FX_RECORD) && node >= 0 && (lr = gg_trace_add_light(rec)) >= 0) {
                rec->nodes[node].nlights++;
                rec->lights[lr].light = (int)li;
                rec->lights[lr].verdict = GG_SHADOW_FACING_AWAY;
                rec->lights[lr].occluder = -1;
                rec->lights[lr].t_block = 1;
            }
            if (v3dot(ng, L) <= 0 || (nl = v3dot(ns, L)) <= 0) continue;
            len = v3len(L);
            Lu = v3scale(L, 1.0 / len);
            nl /= len;
            so = o_out;
            sd = v3sub(s->lights[li].pos, so);
            th->st.shadow++;
            if ((FX & GG_EFFECT_COLORED_SHADOWS) && (s->effects & GG_EFFECT_COLORED_SHADOWS)) {
                int pre = -1, clear = 0;
                gg_hit fh = {0};
                gg_tcol all;
                sq = make_q(so, sd, 1.0, leave, GG_PRIM_TRANSPARENT);
                /* Leaving a sphere's inner side inwards: when nothing else is
                   inside it, its far side is the walk's first hit and
                   anything opaque lies beyond, for the walk to meet. */
                if (!(FX & FX_RECORD) && !front && leave == UINT32_MAX) {
                    gg_rayq iq = make_q(so, sd, 1.0, leave, 0);
                    if (gg_geom_intersect_inside(s->geom, &iq, h->prim, &fh) > 0) pre = 1;
                }
                /* Opaque blocker, or else the walk's first hit: one traversal. */
                if (!(FX & FX_RECORD) && pre < 0) {
                    if (gg_geom_shadow_query_all(s->geom, &sq, &fh, &pre,
                                                 &th->occ[li % GG_OCC_CACHES], &all))
                        continue;
                    clear = 1;
                }
                if (FX & FX_RECORD) {
                    gg_hit bh;
                    /* Recording names the occluder: find the nearest. */
                    if (gg_geom_intersect(s->geom, &sq, &bh)) {
                        verdict = GG_SHADOW_BLOCKED;
                        occ = gg_geom_prim_object(s->geom, bh.prim), tb = bh.t;
                    } else {
                        /* the renderer's crossings, to walk them the same way */
                        clear = 1;
                        gg_geom_shadow_query_all(s->geom, &sq, &fh, &pre, NULL, &all);
                    }
                }
                if (verdict == GG_SHADOW_VISIBLE) {
                    ggColor through =
                        shadow_walk(c, so, sd, leave, &r->media, &occ, &tb, pre, &fh,
                                    clear ? &all : NULL);
                    if (occ >= 0) verdict = cis0(through) ? GG_SHADOW_BLOCKED : GG_SHADOW_ATTENUATED;
                    lc = cmul(lc, through);
                }
            } else {
                sq = make_q(so, sd, 1.0, leave, 0);
                if (FX & FX_RECORD) {
                    gg_hit bh;
                    if (gg_geom_intersect(s->geom, &sq, &bh)) {
                        verdict = GG_SHADOW_BLOCKED;
                        occ = gg_geom_prim_object(s->geom, bh.prim), tb = bh.t;
                    }
                } else if (gg_geom_occluded_cached(s->geom, &sq, &th->occ[li % GG_OCC_CACHES]))
                    continue;
                if ((FX & GG_EFFECT_ABSORPTION) && r->media.n > 0 && verdict == GG_SHADOW_VISIBLE) {
                    ggColor a = media_transmittance(s, &r->media, v3len(sd));
                    if (a.r != 1 || a.g != 1 || a.b != 1) verdict = GG_SHADOW_ATTENUATED;
                    lc = cmul(lc, a);
                }
            }
            if ((FX & FX_RECORD) && lr >= 0) {
                ggTraceLight *R = &rec->lights[lr];
                const ggColor l0 = s->light_colors[li];
                R->verdict = verdict, R->occluder = occ, R->origin = so, R->dir = sd;
                R->t_block = tb;
                /* What got through, relative to the light's own colour. */
                R->transmittance = verdict == GG_SHADOW_BLOCKED
                                       ? rgb(0, 0, 0)
                                       : rgb(l0.r > 0 ? lc.r / l0.r : 0, l0.g > 0 ? lc.g / l0.g : 0,
                                             l0.b > 0 ? lc.b / l0.b : 0);
            }
            if (verdict == GG_SHADOW_BLOCKED || cis0(lc)) continue;
            diff = cmul(kdc, cscale(lc, nl));
            col = cadd(col, diff);
            if ((FX & GG_EFFECT_PHONG) && (mf->flags & GG_MF_PHONG)) {
                /* Phong: (R.V)^shine with R the light's mirror direction. */
                ggVec3 R = reflect(v3neg(Lu), ns);
                double rv = -v3dot(R, v);
                if (rv > 0) {
                    ph = cscale(lc, m->ks * pow(rv, m->shine));
                    col = cadd(col, ph);
                }
            }
            if ((FX & FX_RECORD) && lr >= 0) rec->lights[lr].diffuse = diff, rec->lights[lr].phong = ph;
        }
    }

    if (r->depth >= c->max_depth) {
        if ((FX & FX_RECORD) && node >= 0)
            rec->nodes[node].stop =
                (mf->flags & (GG_MF_REFLECT | GG_MF_TRANSMIT)) ? GG_STOP_DEPTH : GG_STOP_MATTE;
        return col;
    }

    {
        ggColor wr = rgb(m->ks, m->ks, m->ks); /* weight of the mirror ray */
        int spawn_reflect = (mf->flags & GG_MF_REFLECT) != 0, any_tir = 0;
        double cos_i = -v3dot(v, ns);
        if (cos_i < 0) cos_i = -cos_i;

        if ((FX & GG_EFFECT_FRESNEL) && m->fresnel == GG_FRESNEL_CONDUCTOR) {
            double ni = media_index(s, &r->media, r->channel);
            wr = rgb(ggFresnelConductor(cos_i, ni, m->eta_n.r, m->eta_k.r),
                     ggFresnelConductor(cos_i, ni, m->eta_n.g, m->eta_k.g),
                     ggFresnelConductor(cos_i, ni, m->eta_n.b, m->eta_k.b));
            spawn_reflect = 1;
        }

        if ((FX & GG_EFFECT_REFRACTION) && (mf->flags & GG_MF_TRANSMIT)) {
            /* Which indices: entering this material from the current
               medium, or leaving it into the medium around it. */
            gg_media inside = r->media;
            int split = (FX & GG_EFFECT_DISPERSION) && (mf->flags & GG_MF_DISPERSE) &&
                        r->channel < 0 && c->acc.wavelengths != 1;
            const int fmode = fresnel_mode(c, m);
            int ch, nch = split ? 3 : 1;
            /* Entering or leaving is decided by whether the ray is inside
               this material already, not by the face's orientation: a
               polygon mesh wound the wrong way still works. */
            const int entering = !media_has(&r->media, mi);
            if (entering) media_enter(&inside, mi);
            else media_exit(&inside, mi);
            if (c->spd_rules) spawn_reflect = 1;
            for (ch = 0; ch < nch; ch++) {
                int chan = split ? ch : r->channel, ci = -1;
                double ni, nt, F = 0, w;
                ggVec3 t;
                bool ok;
                ray_state child;
                ggColor tc;
                if (entering) {
                    ni = media_index(s, &r->media, chan);
                    nt = mat_index(s, mi, chan);
                } else {
                    ni = mat_index(s, mi, chan);
                    nt = media_index(s, &inside, chan);
                }
                if ((FX & FX_RECORD) && node >= 0) rec->nodes[node].n_other = nt;
                /* gg_refract_unit: plain double where refraction is well
                   conditioned, ggRefract elsewhere (lib/optics/refract_unit.h). */
                if (c->acc.refract == GG_ACC_REFRACT_TEXTBOOK)
                    ok = ggRefractTextbook(v, ns, ni, nt, &t);
                else if (c->acc.refract == GG_ACC_REFRACT_EXACT)
                    ok = ggRefract(v, ns, ni, nt, &t);
                else
                    ok = gg_refract_unit(v, ns, ni, nt, &t);
                /* A shading normal can bend t back to the incoming side:
                   refract about the true surface instead. */
                if (ok && v3dot(t, ng) >= 0) ok = ggRefract(v, ng, ni, nt, &t);
                w = m->kt;
                if (!ok) {
                    /* Total internal reflection: the transmitted share
                       joins the mirror ray. */
                    th->st.tir++;
                    any_tir = 1;
                    if (split) CH_ADD(wr, ch, w);
                    else wr = cadd(wr, rgb(w, w, w));
                    spawn_reflect = 1;
                    continue;
                }
                if ((FX & GG_EFFECT_FRESNEL) && fmode != GG_FRESNEL_NONE &&
                    fmode != GG_FRESNEL_CONDUCTOR) {
                    F = fmode == GG_FRESNEL_SCHLICK ? ggFresnelSchlick(cos_i, ni, nt)
                                                    : ggFresnelDielectric(cos_i, ni, nt);
                    if (split) CH_ADD(wr, ch, w * F);
                    else wr = cadd(wr, rgb(w * F, w * F, w * F));
                    spawn_reflect = 1;
                    w *= 1 - F;
                    if ((FX & FX_RECORD) && node >= 0) rec->nodes[node].fresnel = F;
                }
                child.weight = r->weight * w;
                /* Adaptive depth (POV-Ray's adc_bailout): skip rays that
                   cannot matter. Off (0) by default. */
                if (child.weight < c->acc.cutoff) continue;
                child.o = spawn(c, &sf, t);
                child.d = t;
                child.from_prim = leave;
                /* Refracted in through a sphere's outer side: inside it. */
                child.inside = front && leave == UINT32_MAX ? h->prim : UINT32_MAX;
                child.depth = r->depth + 1;
                child.channel = chan;
                child.media = inside;
                child.kind = GG_RAY_REFRACT;
                child.parent = node;
                th->st.refract++;
                if (FX & FX_RECORD) ci = (int)rec->nnodes;
                tc = TRACE_CHILD(FX, c, &child, th);
                if (split) CH_ADD(col, ch, w * (ch == 0 ? tc.r : ch == 1 ? tc.g : tc.b));
                else col = cadd(col, cscale(tc, w));
                if ((FX & FX_RECORD) && node >= 0) {
                    ggColor cw = split ? channel_weight(ch, w) : rgb(w, w, w);
                    if (ci >= 0 && (size_t)ci < rec->nnodes) rec->nodes[ci].weight = cw;
                    rec->nodes[node].refract_weight = cadd(rec->nodes[node].refract_weight, cw);
                }
            }
        }

        if (spawn_reflect && c->acc.cutoff > 0 && r->weight * cmaxc(wr) < c->acc.cutoff)
            spawn_reflect = 0;
        if (spawn_reflect) {
            ray_state child;
            ggVec3 rd = reflect(v, ns);
            ggColor rc;
            int ci = -1;
            /* A shading normal can send the mirror ray into the surface. */
            if (v3dot(rd, ng) <= 0) rd = reflect(v, ng);
            child.o = o_out;
            child.d = rd;
            child.from_prim = leave;
            /* Mirrored off a sphere's inner side: still inside it. */
            child.inside = !front && leave == UINT32_MAX ? h->prim : UINT32_MAX;
            child.depth = r->depth + 1;
            child.channel = r->channel;
            child.media = r->media;
            child.kind = any_tir ? GG_RAY_TIR : GG_RAY_REFLECT;
            child.weight = r->weight * cmaxc(wr);
            child.parent = node;
            th->st.reflect++;
            if (FX & FX_RECORD) ci = (int)rec->nnodes;
            /* Under the SPD rule a transmitter spawns (and counts) a mirror
               ray even when its weight is zero. */
            rc = TRACE_CHILD(FX, c, &child, th);
            if (!cis0(wr)) col = cmadd(col, wr, rc);
            if ((FX & FX_RECORD) && node >= 0) {
                if (ci >= 0 && (size_t)ci < rec->nnodes) rec->nodes[ci].weight = wr;
                rec->nodes[node].reflect_weight = wr;
            }
        } else if ((FX & FX_RECORD) && node >= 0 && !(mf->flags & GG_MF_TRANSMIT))
            rec->nodes[node].stop = GG_STOP_MATTE;
    }
    return col;
}

GG_INLINE ggColor trace_fx(const gg_shade_ctx *c, const ray_state *r, gg_shade_thread *th,
                           const gg_hit *known, const unsigned FX)
{
    const ggScene *s = c->s;
    gg_rayq q = make_q(r->o, r->d, INFINITY, r->from_prim, 0);
    gg_hit h;
    const gg_hit *hp = &h;
    ggColor col, att = rgb(1, 1, 1);
    int node = -1, hit;
    if ((uint64_t)r->depth > th->st.max_depth) th->st.max_depth = (uint64_t)r->depth;
    if (FX & FX_RECORD) {
        node = gg_trace_add_node(c->rec);
        if (node >= 0) {
            ggTraceNode *N = &c->rec->nodes[node];
            N->parent = r->parent, N->kind = r->kind, N->depth = r->depth;
            N->channel = r->channel, N->sample = c->rec->sample, N->o = r->o, N->d = r->d;
            N->medium = r->media.n ? r->media.mat[r->media.n - 1] : -1;
            N->n_medium = media_index(s, &r->media, r->channel);
            N->object = N->shape = N->material = -1;
            N->fresnel = -1;
            N->weight = rgb(1, 1, 1);
        }
    }
    if (known) {
        hit = 1, hp = known;
    } else {
        hit = -1;
        if (r->inside != UINT32_MAX) hit = gg_geom_intersect_inside(s->geom, &q, r->inside, &h);
        if (hit < 0) hit = gg_geom_intersect(s->geom, &q, &h);
    }
    if (!hit) {
        col = s->background;
        if ((FX & GG_EFFECT_ABSORPTION) && r->media.n > 0)
            att = media_transmittance(s, &r->media, INFINITY);
    } else {
        if (r->depth == 1) th->st.eye_hit++;
        col = shade_hit(c, r, &q, hp, th, node, FX);
        if ((FX & GG_EFFECT_ABSORPTION) && r->media.n > 0)
            att = media_transmittance(s, &r->media, hp->t);
    }
    if ((FX & GG_EFFECT_ABSORPTION) && r->media.n > 0) col = cmul(col, att);
    if ((FX & FX_RECORD) && node >= 0) {
        ggTraceNode *N = &c->rec->nodes[node];
        if (!hit) N->stop = GG_STOP_MISS;
        N->absorption = att;
        N->color = col;
    }
    return col;
}

static ggColor trace_basic(const gg_shade_ctx *c, const ray_state *r, gg_shade_thread *th,
                           const gg_hit *known)
{
    return trace_fx(c, r, th, known, FX_BASIC);
}

static ggColor trace_full(const gg_shade_ctx *c, const ray_state *r, gg_shade_thread *th,
                          const gg_hit *known)
{
    return trace_fx(c, r, th, known, FX_FULL);
}

#ifndef GG_NO_RECORDER
static ggColor trace_rec(const gg_shade_ctx *c, const ray_state *r, gg_shade_thread *th,
                         const gg_hit *known)
{
    return trace_fx(c, r, th, known, FX_REC);
}
#endif

int gg_shade_dir(ggVec3 o, ggVec3 d, ggVec3 *u)
{
    double len = v3len(d);
    if (!(len > 0) || !isfinite(len) || !v3finite(o)) return 0;
    *u = v3scale(d, 1.0 / len);
    return 1;
}

ggColor gg_shade_ray(const gg_shade_ctx *c, ggVec3 o, ggVec3 d, int depth, gg_shade_thread *th)
{
    ggVec3 u;
    if (!gg_shade_dir(o, d, &u)) return rgb(0, 0, 0);
    return gg_shade_ray_unit(c, o, u, depth, th);
}

/* A ray from o along unit u in the outside medium, as the ray tree's root. */
static void root_ray(ray_state *r, ggVec3 o, ggVec3 u, int depth)
{
    r->o = o;
    r->d = u;
    r->from_prim = UINT32_MAX;
    r->inside = UINT32_MAX;
    r->depth = depth;
    r->channel = -1;
    r->media.n = 0;
    r->kind = GG_RAY_EYE;
    r->parent = -1;
    r->weight = 1;
}

/* The recording path computes exactly what the full path does, so a
   recorded pixel equals the rendered one bit for bit. */
static ggColor trace_root(const gg_shade_ctx *c, const ray_state *r, gg_shade_thread *th,
                          const gg_hit *known)
{
#ifndef GG_NO_RECORDER
    if (c->rec) return trace_rec(c, r, th, known);
#endif
    if ((c->fx & ~(unsigned)FX_BASIC) == 0) return trace_basic(c, r, th, known);
    return trace_full(c, r, th, known);
}

ggColor gg_shade_ray_unit(const gg_shade_ctx *c, ggVec3 o, ggVec3 u, int depth,
                          gg_shade_thread *th)
{
    ray_state r;
    root_ray(&r, o, u, depth);
    if (depth == 1) th->st.eye++;
    return trace_root(c, &r, th, NULL);
}

ggColor gg_shade_eye_hit(const gg_shade_ctx *c, const gg_rayq *q, const gg_hit *h,
                         gg_shade_thread *th)
{
    ray_state r;
    root_ray(&r, q->o, q->d, 1);
    return trace_root(c, &r, th, h);
}
