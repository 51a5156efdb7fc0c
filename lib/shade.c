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

#include "vec.h"

#include <math.h>
#include <string.h>

#define FX_BASIC                                                                                 \
    (GG_EFFECT_SHADOWS | GG_EFFECT_REFLECTION | GG_EFFECT_PHONG | GG_EFFECT_EMISSION |           \
     GG_EFFECT_TEXTURES | GG_EFFECT_IMPLICIT | GG_EFFECT_SUPERSAMPLING)
#define FX_FULL GG_EFFECT_ALL

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
    int depth;
    int channel;
    gg_media media;
} ray_state;

static ggColor trace_basic(const gg_shade_ctx *c, const ray_state *r, ggRayStats *st);
static ggColor trace_full(const gg_shade_ctx *c, const ray_state *r, ggRayStats *st);

void gg_shade_init(gg_shade_ctx *ctx, const ggScene *s, int max_depth, unsigned force,
                   bool spd_rules)
{
    ctx->s = s;
    ctx->max_depth = max_depth;
    ctx->fx = s->effects | force;
    ctx->spd_rules = spd_rules;
    ctx->offset_mode = GG_OFFSET_SCALED;
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

/* Light arriving at the shadow origin from a light at distance 1 along d
   (d = light - o), through transparent occluders: kt per surface crossed
   and absorption inside. Returns black if an opaque surface blocks. */
static ggColor shadow_walk(const gg_shade_ctx *c, ggVec3 o, ggVec3 d, uint32_t from,
                           const gg_media *start)
{
    const ggScene *s = c->s;
    gg_media m = *start;
    ggColor tr = rgb(1, 1, 1);
    double tprev = 0, len = v3len(d);
    gg_rayq q = make_q(o, d, 1.0, from, 0);
    gg_hit h;
    int step;
    for (step = 0; step < GG_MAX_SHADOW_STEPS; step++) {
        int obj, mat;
        gg_surf sf;
        if (!gg_geom_intersect(s->geom, &q, &h)) {
            return cmul(tr, media_transmittance(s, &m, (1.0 - tprev) * len));
        }
        obj = gg_geom_prim_object(s->geom, h.prim);
        mat = s->objects[obj].material;
        if (s->materials[mat].kt <= 0) return rgb(0, 0, 0);
        tr = cmul(tr, media_transmittance(s, &m, (h.t - tprev) * len));
        tr = cscale(tr, s->materials[mat].kt);
        gg_geom_surface(s->geom, &q, &h, &sf);
        if (v3dot(d, sf.ng) < 0) media_enter(&m, mat);
        else media_exit(&m, mat);
        if (cmaxc(tr) <= 0) return tr;
        /* Continue from just past this surface, in parameter units of the
           original ray so the light stays at t = 1. */
        q.o = gg_offset_origin(&sf, d, c->offset_mode);
        q.d = v3sub(v3add(o, d), q.o);
        o = q.o;
        d = q.d;
        len = v3len(d);
        tprev = 0;
        q.ignore_prim = h.prim;
    }
    return rgb(0, 0, 0);
}

/* The body of rayColor at a hit, specialised by FX at compile time. */
GG_INLINE ggColor shade_hit(const gg_shade_ctx *c, const ray_state *r, const gg_rayq *q,
                            const gg_hit *h, ggRayStats *st, const unsigned FX)
{
    const ggScene *s = c->s;
    const int32_t obj = gg_geom_prim_object(s->geom, h->prim);
    const int mi = s->objects[obj].material;
    const ggMaterial *m = &s->materials[mi];
    const gg_mat_fast *mf = &s->mfast[mi];
    gg_surf sf;
    ggVec3 ng, ns, v = r->d;
    ggColor col, kdc;
    int front;
    size_t li;

    gg_geom_surface(s->geom, q, h, &sf);
    /* Normals facing the incoming ray: surfaces are two-sided. */
    front = v3dot(v, sf.ng) < 0;
    ng = front ? sf.ng : v3neg(sf.ng);
    ns = front ? sf.ns : v3neg(sf.ns);

    kdc = mf->kd_color;
    if ((FX & GG_EFFECT_TEXTURES) && (mf->flags & GG_MF_TEXTURE))
        kdc = cscale(gg_scene_surface_color(s, mi, sf.u, sf.v), m->kd);

    /* Emission and ambient. */
    col = cmul(kdc, s->ambient);
    if ((FX & GG_EFFECT_EMISSION) && (mf->flags & GG_MF_EMIT)) col = cadd(col, m->ke);

    /* Direct light: one shadow ray per light the surface faces. */
    if (FX & GG_EFFECT_SHADOWS) {
        for (li = 0; li < s->nlights; li++) {
            ggVec3 L = v3sub(s->lights[li].pos, sf.p), Lu, so, sd;
            ggColor lc = s->light_colors[li], through;
            double nl, len;
            gg_rayq sq;
            if (v3dot(ng, L) <= 0 || (nl = v3dot(ns, L)) <= 0) continue;
            len = v3len(L);
            Lu = v3scale(L, 1.0 / len);
            nl /= len;
            so = gg_offset_origin(&sf, Lu, c->offset_mode);
            sd = v3sub(s->lights[li].pos, so);
            st->shadow++;
            if ((FX & GG_EFFECT_COLORED_SHADOWS) && (s->effects & GG_EFFECT_COLORED_SHADOWS)) {
                sq = make_q(so, sd, 1.0, h->prim, GG_PRIM_TRANSPARENT);
                if (gg_geom_occluded(s->geom, &sq)) continue;
                through = shadow_walk(c, so, sd, h->prim, &r->media);
                lc = cmul(lc, through);
                if (cis0(lc)) continue;
            } else {
                sq = make_q(so, sd, 1.0, h->prim, 0);
                if (gg_geom_occluded(s->geom, &sq)) continue;
                if ((FX & GG_EFFECT_ABSORPTION) && r->media.n > 0)
                    lc = cmul(lc, media_transmittance(s, &r->media, v3len(sd)));
            }
            col = cadd(col, cmul(kdc, cscale(lc, nl)));
            if ((FX & GG_EFFECT_PHONG) && (mf->flags & GG_MF_PHONG)) {
                /* Phong: (R.V)^shine with R the light's mirror direction. */
                ggVec3 R = ggReflection(v3neg(Lu), ns);
                double rv = -v3dot(R, v);
                if (rv > 0) col = cadd(col, cscale(lc, m->ks * pow(rv, m->shine)));
            }
        }
    }

    if (r->depth >= c->max_depth) return col;

    {
        ggColor wr = rgb(m->ks, m->ks, m->ks); /* weight of the mirror ray */
        int spawn_reflect = (mf->flags & GG_MF_REFLECT) != 0;
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
                        r->channel < 0;
            int ch, nch = split ? 3 : 1;
            if (front) media_enter(&inside, mi);
            else media_exit(&inside, mi);
            if (c->spd_rules) spawn_reflect = 1;
            for (ch = 0; ch < nch; ch++) {
                int chan = split ? ch : r->channel;
                double ni, nt, F = 0, w;
                ggVec3 t;
                bool ok;
                ray_state child;
                if (front) {
                    ni = media_index(s, &r->media, chan);
                    nt = mat_index(s, mi, chan);
                } else {
                    ni = mat_index(s, mi, chan);
                    nt = media_index(s, &inside, chan);
                }
                ok = ggRefract(v, ns, ni, nt, &t);
                /* A shading normal can bend t back to the incoming side:
                   refract about the true surface instead. */
                if (ok && v3dot(t, ng) >= 0) ok = ggRefract(v, ng, ni, nt, &t);
                w = m->kt;
                if (!ok) {
                    /* Total internal reflection: the transmitted share
                       joins the mirror ray. */
                    st->tir++;
                    if (split) {
                        if (ch == 0) wr.r += w;
                        else if (ch == 1) wr.g += w;
                        else wr.b += w;
                    } else
                        wr = cadd(wr, rgb(w, w, w));
                    spawn_reflect = 1;
                    continue;
                }
                if ((FX & GG_EFFECT_FRESNEL) && m->fresnel != GG_FRESNEL_NONE &&
                    m->fresnel != GG_FRESNEL_CONDUCTOR) {
                    F = m->fresnel == GG_FRESNEL_SCHLICK ? ggFresnelSchlick(cos_i, ni, nt)
                                                         : ggFresnelDielectric(cos_i, ni, nt);
                    if (split) {
                        if (ch == 0) wr.r += w * F;
                        else if (ch == 1) wr.g += w * F;
                        else wr.b += w * F;
                    } else
                        wr = cadd(wr, rgb(w * F, w * F, w * F));
                    spawn_reflect = 1;
                    w *= 1 - F;
                }
                child.o = gg_offset_origin(&sf, t, c->offset_mode);
                child.d = t;
                child.from_prim = h->prim;
                child.depth = r->depth + 1;
                child.channel = chan;
                child.media = inside;
                st->refract++;
                {
                    ggColor tc = FX == FX_BASIC ? trace_basic(c, &child, st)
                                                : trace_full(c, &child, st);
                    if (split) {
                        if (ch == 0) col.r += w * tc.r;
                        else if (ch == 1) col.g += w * tc.g;
                        else col.b += w * tc.b;
                    } else
                        col = cadd(col, cscale(tc, w));
                }
            }
        }

        if (spawn_reflect) {
            ray_state child;
            ggVec3 rd = ggReflection(v, ns);
            /* A shading normal can send the mirror ray into the surface. */
            if (v3dot(rd, ng) <= 0) rd = ggReflection(v, ng);
            child.o = gg_offset_origin(&sf, rd, c->offset_mode);
            child.d = rd;
            child.from_prim = h->prim;
            child.depth = r->depth + 1;
            child.channel = r->channel;
            child.media = r->media;
            st->reflect++;
            if (!cis0(wr)) {
                ggColor rc = FX == FX_BASIC ? trace_basic(c, &child, st)
                                            : trace_full(c, &child, st);
                col = cmadd(col, wr, rc);
            } else {
                /* SPD rule: a transmitter spawns (and counts) a mirror ray
                   even when its weight is zero; trace it for the counts. */
                (void)(FX == FX_BASIC ? trace_basic(c, &child, st) : trace_full(c, &child, st));
            }
        }
    }
    return col;
}

GG_INLINE ggColor trace_fx(const gg_shade_ctx *c, const ray_state *r, ggRayStats *st,
                           const unsigned FX)
{
    const ggScene *s = c->s;
    gg_rayq q = make_q(r->o, r->d, INFINITY, r->from_prim, 0);
    gg_hit h;
    ggColor col;
    if (!gg_geom_intersect(s->geom, &q, &h)) {
        col = s->background;
        if ((FX & GG_EFFECT_ABSORPTION) && r->media.n > 0)
            col = cmul(col, media_transmittance(s, &r->media, INFINITY));
        return col;
    }
    if (r->depth == 1) st->eye_hit++;
    col = shade_hit(c, r, &q, &h, st, FX);
    if ((FX & GG_EFFECT_ABSORPTION) && r->media.n > 0)
        col = cmul(col, media_transmittance(s, &r->media, h.t));
    return col;
}

static ggColor trace_basic(const gg_shade_ctx *c, const ray_state *r, ggRayStats *st)
{
    return trace_fx(c, r, st, FX_BASIC);
}

static ggColor trace_full(const gg_shade_ctx *c, const ray_state *r, ggRayStats *st)
{
    return trace_fx(c, r, st, FX_FULL);
}

ggColor gg_shade_ray(const gg_shade_ctx *c, ggVec3 o, ggVec3 d, int depth, ggRayStats *st)
{
    ray_state r;
    double len = v3len(d);
    if (!(len > 0) || !isfinite(len) || !v3finite(o)) return rgb(0, 0, 0);
    r.o = o;
    r.d = v3scale(d, 1.0 / len);
    r.from_prim = UINT32_MAX;
    r.depth = depth;
    r.channel = -1;
    r.media.n = 0;
    if (depth == 1) st->eye++;
    if ((c->fx & ~(unsigned)FX_BASIC) == 0) return trace_basic(c, &r, st);
    return trace_full(c, &r, st);
}
