/* SPDX-License-Identifier: MIT */
/*
** shade.c -- the colour of a ray: Whitted's illumination model (T. Whitted,
** "An Improved Illumination Model for Shaded Display", CACM 23(6), 1980),
** with Phong highlights, Fresnel weights and absorption:
**
**   colour = ke + kd C ambient + sum over lights of (kd C (N.L) + ks (R.V)^shine) light
**            + ks' reflection + kt' refraction
**
** where ks' and kt' are ks and kt, or Fresnel-weighted. shade_hit is that
** sum, one helper per term: emission_ambient, direct_light (a shadow ray
** per light), then the secondary rays, transmission before the mirror ray
** because total internal reflection and the Fresnel split add to the
** mirror ray's weight. Recursion stops at the depth limit or when the
** eye ray's tree has used its ray budget.
**
** Specialisation. trace_fx and everything it inlines take the effect set
** FX as a compile-time constant and are compiled once per line of
** GG_SHADE_COPIES (below), whose order is also the order in which a ray
** tree picks its copy (trace_root); in a copy whose FX lacks an effect,
** that effect's branches are dead code. What runs within a copy is
** decided once per render by gg_shade_init (c->on and the resolved knobs,
** RUNS). docs/performance.md has what the smaller copies save.
**
** Recorder hooks. Everything the recorder stores goes through the rec_*
** functions below. Each takes FX and starts with `if (!(FX & FX_RECORD))
** return`, so in the basic and full paths it compiles to nothing; in the
** recording path it sees all that the shading computed at that point:
**   rec_ray        a ray is about to be cast: its ray_state
**   rec_intersect  its closest-hit query, through the counting copy of the
**                  traversal (gg_geom_intersect_cost): the same hit
**   rec_hit        its closest hit: hit_info (the query, gg_hit with the
**                  barycentrics b1, b2, gg_surf with p, normals and the
**                  error bound perr, the origin o_out of rays leaving it)
**   rec_light      one light is considered at the hit
**   rec_shadow     its shadow ray and verdict: shadow_ray
**   rec_light_terms  the diffuse and Phong terms it gave
**   rec_refract    one transmitted channel: indices ni -> nt, |cos| of
**                  incidence, whether it refracted (else TIR), Fresnel F
**   rec_child      a child ray has returned: the child's ray_state, weight
**   rec_stop       why a ray spawned no (more) children
**   rec_ray_end    the ray's colour and absorption
** Per-hit diagnostics (docs/internals.md, "Shading and the recorder hooks") belong in these
** functions and nowhere else in the shading.
**
** Path layers. The aov_* hooks split a ray tree's colour into the path
** layers of c->layers (lpe.h) in the layer copy (FX_AOV) alone, as the
** rec_* hooks record in the recording copy alone.
*/
#include "shade.h"
#include "lpe.h"
#include "refract_unit.h"

#include "trace_int.h"
#include "vec.h"

#include <math.h>
#include <string.h>

#define FX_BASIC                                                                                   \
    (GG_EFFECT_SHADOWS | GG_EFFECT_REFLECTION | GG_EFFECT_PHONG | GG_EFFECT_EMISSION |             \
     GG_EFFECT_TEXTURES | GG_EFFECT_IMPLICIT | GG_EFFECT_SUPERSAMPLING)
/* Not an effect: shadow rays stop short of their light (a light inside
   the scene's bounds, gg_shade_ctx.end_margin); the full copies only. */
#define FX_END  (1u << 28)
#define FX_FULL (GG_EFFECT_ALL | FX_END)
/* The basic path with glass: refraction and the coloured shadows it
   casts (gears, mount), without the rarer effects' tests. */
#define FX_GLASS (FX_BASIC | GG_EFFECT_REFRACTION | GG_EFFECT_COLORED_SHADOWS)
/* Not an effect: the path that also records the ray tree (trace.h). */
#define FX_RECORD (1u << 30)
#define FX_REC    (FX_FULL | FX_RECORD)
/* Not an effect: the path that also splits the colour into path layers
   (lpe.h, the aov_* hooks). */
#define FX_AOV    (1u << 29)
#define FX_LAYERS (FX_FULL | FX_AOV)

/* Shadow rays through transparent occluders give up after this many
   surfaces (the light is then taken as blocked). */
#define GG_MAX_SHADOW_STEPS 64

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
    int kind;      /* GG_RAY_*, recorded only */
    int parent;    /* parent node, recorded only */
    /* The layer copy only (FX_AOV): the ray's weight in the pixel per
       channel, and each layer's automaton state after its events; lmask
       has bit l for each layer not dead (lpe[l] != 0; the others' lpe
       are not kept). */
    ggColor thru;
    unsigned lmask;
    uint16_t lpe[GG_LAYERS_MAX];
} ray_state;

/* What shading knows about one hit (hit_setup fills it). */
typedef struct hit_info {
    const gg_rayq *q; /* the query that found it */
    const gg_hit *h;
    int32_t obj;
    int mi; /* material index */
    const ggMaterial *m;
    const gg_mat_fast *mf;
    uint32_t leave; /* the primitive that rays leaving the hit skip (leave_prim) */
    gg_surf sf;     /* point, normals as the shape defines them, (u, v), perr */
    ggVec3 ng, ns;  /* geometric and shading normal, facing the incoming ray */
    int front;      /* the ray arrived against sf.ng */
    ggVec3 o_out;   /* origin of every ray that leaves to the incoming side */
    ggColor kdc;    /* kd times the surface colour (texture included) */
    /* The layer copy (aov_local fills them): the ray's thru times its
       absorption to the hit; per live layer not quiet there the terms its
       automaton accepts there (lpe.h, GG_LPE_T_*); the layers that accept
       some light's term there (bit l); awz: aw has a channel of exactly 0
       (wmul's tests needed). */
    ggColor aw;
    int awz;
    uint32_t lterm[GG_LAYERS_MAX];
    unsigned llive;
} hit_info;

/* One shadow ray and what it found. */
typedef struct shadow_ray {
    ggVec3 o, d; /* origin and d = light - o: the light is at t = 1 */
    double tend; /* where the query stops: shadow_end */
    ggColor lc;  /* the light's colour times what got through */
    int verdict; /* GG_SHADOW_* */
    int occ;     /* the blocking object, else the first transparent one crossed, or -1 */
    double tb;   /* where it was met (ray parameter), else 1 */
} shadow_ray;

/* A hit's secondary rays, as the terms decide them. */
typedef struct secondary {
    ggColor wr;   /* weight of the mirror ray */
    int reflect;  /* whether it is cast */
    int tir;      /* it carries a totally internally reflected share */
    double cos_i; /* |cos| of the angle of incidence on ns */
} secondary;

/* The shading copies, one line each: a name and the effect set FX it is
   compiled for (trace_fx with FX a compile-time constant). The order is
   the selection order: a ray tree takes the first copy whose FX holds
   every effect it needs (trace_root), and a child ray the copy of its
   parent (TRACE_CHILD). This list is the only place that names them; it
   generates their prototypes, definitions, the child dispatch and the
   root selection. GG_NO_RECORDER builds the library without the
   recording copy, only to measure what having it costs (make
   bench-trace). */
#ifdef GG_NO_RECORDER
#define GG_SHADE_COPY_REC(X)
#define GG_SHADE_RECORDS 0u
#else
#define GG_SHADE_COPY_REC(X) X(rec, FX_REC)
#define GG_SHADE_RECORDS     FX_RECORD
#endif
#define GG_SHADE_COPIES(X)                                                                         \
    X(basic, FX_BASIC)                                                                             \
    X(glass, FX_GLASS)                                                                             \
    X(full, FX_FULL)                                                                               \
    X(layers_basic, FX_BASIC | FX_AOV)                                                             \
    X(layers, FX_LAYERS)                                                                           \
    GG_SHADE_COPY_REC(X)

/* known: the ray's closest hit when the caller has already asked the
   geometry (eye rays from the renderer's tile loop), else NULL. */
#define GG_SHADE_PROTO(name, fx)                                                                   \
    static ggColor trace_##name(const gg_shade_ctx *c, const ray_state *r, gg_shade_thread *th,    \
                                const gg_hit *known);
GG_SHADE_COPIES(GG_SHADE_PROTO)
#undef GG_SHADE_PROTO

/* Never called: the end of TRACE_CHILD's chain, which FX (always one of
   the list's sets) folds away. */
static ggColor trace_none(void)
{
    return rgb(0, 0, 0);
}

/* A child ray in its parent's copy (TRACE_CHILD): FX is a compile-time
   constant, so this folds to one direct call. */
#define GG_SHADE_CHILD(name, fx)                                                                   \
    if (FX == (fx)) return trace_##name(c, r, th, NULL);
GG_INLINE ggColor trace_child(const gg_shade_ctx *c, const ray_state *r, gg_shade_thread *th,
                              const unsigned FX)
{
    GG_SHADE_COPIES(GG_SHADE_CHILD)
    return trace_none();
}
#undef GG_SHADE_CHILD
#define TRACE_CHILD(FX, c, r, th) trace_child(c, r, th, FX)

/* x^n for a whole n in [1, 2^20], by repeated squaring (the phong=fast
   knob, render.h): one rounding per product, so the relative error is at
   most (n - 1) 2^-53 to first order; any other exponent goes to pow. */
static double phong_power(double x, double shine)
{
    unsigned n;
    double r, p;
    if (!(shine >= 1 && shine <= 0x1p20) || (double)(n = (unsigned)shine) != shine)
        return pow(x, shine);
    for (r = 1, p = x;; p *= p) {
        if (n & 1) r *= p;
        if (!(n >>= 1)) return r;
    }
}

/* What the shading tests per ray, resolved here once: the effects that
   run (a copy compiled with an effect runs its code only where `on` has
   it: coloured shadows only in a scene that has some, whatever was
   forced), the offset knob, the Fresnel override and Phong's power. */
static void resolve_knobs(gg_shade_ctx *ctx, const ggScene *s)
{
    ctx->on = ctx->fx;
    if (!(s->effects & GG_EFFECT_COLORED_SHADOWS)) ctx->on &= ~GG_EFFECT_COLORED_SHADOWS;
    ctx->fixed_offset = ctx->acc.offset == GG_ACC_OFFSET_FIXED;
    ctx->offset_eps = ctx->acc.offset_eps > 0 ? ctx->acc.offset_eps : 1e-6;
    ctx->fresnel_knob = ctx->acc.fresnel == 0                        ? -1
                        : ctx->acc.fresnel == GG_ACC_FRESNEL_NONE    ? GG_FRESNEL_NONE
                        : ctx->acc.fresnel == GG_ACC_FRESNEL_SCHLICK ? GG_FRESNEL_SCHLICK
                                                                     : GG_FRESNEL_EXACT;
    ctx->power = ctx->acc.phong == GG_ACC_PHONG_FAST ? phong_power : pow;
}

void gg_shade_set_layers(gg_shade_ctx *ctx, const struct ggPathLayers *layers)
{
    ctx->layers = layers;
    /* Not an effect: makes trace_root pick the layer copy, the one
       GG_SHADE_COPIES line that holds FX_AOV. */
    if (layers) ctx->fx |= FX_AOV;
}

/* Whether a light lies inside the box of the scene's primitives grown by
   2^-40 of the coordinates' size (far more than a hit's rounding): only
   there can a surface's crossing round onto the light. */
static int light_in_bounds(const ggScene *s)
{
    ggVec3 lo, hi;
    size_t i;
    if (!s->geom) return 0;
    gg_geom_bounds(s->geom, &lo, &hi);
    for (i = 0; i < s->nlights; i++) {
        ggVec3 L = s->lights[i].pos;
        double m = 0x1p-40 * (v3maxabs(lo) + v3maxabs(hi) + v3maxabs(L));
        if (L.x >= lo.x - m && L.x <= hi.x + m && L.y >= lo.y - m && L.y <= hi.y + m &&
            L.z >= lo.z - m && L.z <= hi.z + m)
            return 1;
    }
    return 0;
}

void gg_shade_init(gg_shade_ctx *ctx, const ggScene *s, int max_depth, unsigned force,
                   bool spd_rules, const ggAccuracy *acc)
{
    ctx->s = s;
    ctx->max_depth = max_depth;
    ctx->fx = s->effects | force;
    ctx->spd_rules = spd_rules;
    if (acc)
        ctx->acc = *acc;
    else
        memset(&ctx->acc, 0, sizeof ctx->acc);
    /* The knobs the geometry answers by travel with every query. */
    ctx->qopt.sphere =
        ctx->acc.sphere == GG_ACC_SPHERE_TEXTBOOK ? GG_SPHERE_TEXTBOOK : GG_SPHERE_STABLE;
    ctx->qopt.isect = ctx->acc.intersect == GG_ACC_ISECT_FLOAT ? GG_ISECT_FLOAT : GG_ISECT_DOUBLE;
    ctx->qopt.implicit_tol = ctx->acc.implicit_tol;
    ctx->qopt.gradient_h = ctx->acc.gradient_h;
    /* A Fresnel override on a transmitter needs the Fresnel code. */
    if (ctx->acc.fresnel >= GG_ACC_FRESNEL_SCHLICK && (s->effects & GG_EFFECT_REFRACTION))
        ctx->fx |= GG_EFFECT_FRESNEL;
    /* Opaque shadows: the effect is not simulated, even if forced. */
    if (ctx->acc.shadows == GG_ACC_SHADOWS_OPAQUE) ctx->fx &= ~GG_EFFECT_COLORED_SHADOWS;
    resolve_knobs(ctx, s);
    ctx->end_margin = !ctx->fixed_offset && light_in_bounds(s);
    if (ctx->end_margin) ctx->fx |= FX_END; /* a copy that has it (trace_root) */
    ctx->budget = GG_RAY_BUDGET;
    ctx->rec = NULL;
    ctx->layers = NULL;
}

/* ---- small pieces ---- */

/* Origin of a ray leaving sf in direction d, as the offset knob says. The
   fixed variant is the textbook one: one epsilon and nothing else (it also
   drops the skip of the planar primitive a ray leaves, see leave_prim). */
static ggVec3 spawn(const gg_shade_ctx *c, const gg_surf *sf, ggVec3 d)
{
    if (c->fixed_offset) return gg_offset_origin_fixed(sf, d, c->offset_eps);
    return gg_offset_origin(sf, d);
}

/* The Fresnel mode in force for a material (the knob overrides dielectrics). */
static int fresnel_mode(const gg_shade_ctx *c, const ggMaterial *m)
{
    if (m->fresnel == GG_FRESNEL_CONDUCTOR || c->fresnel_knob < 0) return m->fresnel;
    return c->fresnel_knob;
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
    return channel == 0   ? f->n_r
           : channel == 2 ? f->n_b
           : channel == 1 ? f->n_g
                          : s->materials[mat].ior;
}

/* The media stack is copied whole from ray to ray but only mat[0..n) is
   ever set or read; through the inlined recursion GCC's -O3 cannot see that
   and warns on the reads below (maybe-uninitialized), so the warning is
   off for these two functions only. */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
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
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

static void media_enter(gg_media *m, int mat)
{
    if (m->n < GG_MAX_MEDIA) m->mat[m->n++] = mat;
}

/* Crossing the surface of material mat: into it, or out of it. */
static void media_cross(gg_media *m, int mat)
{
    if (!media_has(m, mat))
        media_enter(m, mat);
    else
        media_exit(m, mat);
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

/* Whether effect e runs here: compiled into this copy (FX, a constant:
   the test folds away) and resolved on for this render (c->on,
   gg_shade_init).
   Absorption: without it every medium a ray can be in (a material with
   kt > 0, media_cross) has zero extinction, so media_transmittance would
   give (1, 1, 1), which changes no bit of what it multiplies: skip the
   call. */
#define RUNS(c, FX, e) (((FX) & (e)) && ((c)->on & (e)))
#define ABSORBS(c, FX) RUNS(c, FX, GG_EFFECT_ABSORPTION)

/* *p read one double at a time: for vectors written so just before
   (a child ray by its parent, a hit's normals by gg_geom_surface), whose
   two halves a paired 16-byte load would wait for (GG_SCALAR). */
static inline ggVec3 v3_unpaired(const ggVec3 *p)
{
    double x = p->x, y = p->y, z = p->z;
    GG_SCALAR(x);
    GG_SCALAR(y);
    GG_SCALAR(z);
    return v3(x, y, z);
}

/* A query of this render from o along d, t in (0, tmax), skipping prim
   `ignore` and the primitives flagged `skip`; th's statistics count the
   implicit surfaces whose evaluation budget it exhausts. */
static gg_rayq make_q(const gg_shade_ctx *c, gg_shade_thread *th, ggVec3 o, ggVec3 d, double tmax,
                      uint32_t ignore, unsigned skip)
{
    gg_rayq q = gg_rayq_make(o, d, 0, tmax, &c->qopt);
    q.ignore_prim = ignore, q.skip_flags = skip;
    q.implicit_cut = &th->st.implicit_cut;
    return q;
}

/* r = v - 2 n (v.n) for unit n, in plain double: the hot-path twin of
   ggReflection, which spends double-double arithmetic to be exact for any
   input. With unit vectors the plain formula is within a few ulp. */
static inline ggVec3 reflect(ggVec3 v, ggVec3 n)
{
    return v3madd(v, n, -2 * v3dot(v, n));
}

/* Rays leaving a planar primitive cannot meet it again: they skip it
   outright. Curved ones (a sphere's far side, a torus shadowing itself)
   must stay in; the origin offset keeps them robust. */
static uint32_t leave_kind(int k, uint32_t prim)
{
    return k == GG_SHAPE_TRIANGLE || k == GG_SHAPE_POLYGON || k == GG_SHAPE_RECT ? prim
                                                                                 : UINT32_MAX;
}

static uint32_t leave_prim(const ggScene *s, uint32_t prim)
{
    return leave_kind(gg_geom_prim_kind(s->geom, prim), prim);
}

/* Add w to channel ch of a colour (split: a dispersed ray), or to all three. */
static void add_share(ggColor *col, int split, int ch, double w)
{
    if (!split)
        *col = cadd(*col, rgb(w, w, w));
    else if (ch == 0)
        col->r += w;
    else if (ch == 1)
        col->g += w;
    else
        col->b += w;
}

/* Weight of a child in one channel only (a dispersed ray). */
static ggColor channel_weight(int ch, double w)
{
    return rgb(ch == 0 ? w : 0, ch == 1 ? w : 0, ch == 2 ? w : 0);
}

/* A secondary ray of r leaving hit hi from o along d. */
static void child_ray(ray_state *child, const ray_state *r, int node, ggVec3 o, ggVec3 d, int kind,
                      double weight)
{
    child->o = o;
    child->d = d;
    child->depth = r->depth + 1;
    child->kind = kind;
    child->weight = weight;
    child->parent = node;
}

/* ---- recorder hooks (see the top of the file) ---- */

GG_INLINE int rec_ray(const gg_shade_ctx *c, const ray_state *r, const unsigned FX)
{
    ggTraceNode *N;
    int node;
    if (!(FX & FX_RECORD) || (node = gg_trace_add_node(c->rec)) < 0) return -1;
    N = &c->rec->nodes[node];
    N->parent = r->parent, N->kind = r->kind, N->depth = r->depth;
    N->channel = r->channel, N->sample = c->rec->sample, N->o = r->o, N->d = r->d;
    N->medium = r->media.n ? r->media.mat[r->media.n - 1] : -1;
    N->n_medium = media_index(c->s, &r->media, r->channel);
    N->object = N->shape = N->material = -1;
    N->triangle = -1;
    N->fresnel = -1;
    N->weight = rgb(1, 1, 1);
    N->perr = N->offset = N->tir_margin = N->edge = NAN;
    N->nodes = N->prims = -1;
    return node;
}

/* The recorder's closest-hit query: gg_geom_intersect's answer, and what
   the traversal tested. A hit the caller already knows (the tracer's eye
   rays) stays the one used; the query then only counts. */
GG_INLINE int rec_intersect(const gg_shade_ctx *c, int node, const gg_rayq *q, const gg_hit *known,
                            gg_hit *h)
{
    gg_trav_cost cost = {0, 0};
    gg_hit other;
    int hit = gg_geom_intersect_cost(c->s->geom, q, known ? &other : h, &cost);
    if (node >= 0) c->rec->nodes[node].nodes = cost.nodes, c->rec->nodes[node].prims = cost.prims;
    return known ? 1 : hit;
}

/* How close a hit lies to the nearest edge of its triangle or mesh
   triangle (the smallest barycentric coordinate) or rectangle (in (u,
   v)); NaN for other shapes. */
static double edge_distance(int kind, const gg_hit *h)
{
    double m;
    if (kind == GG_SHAPE_TRIANGLE || kind == GG_SHAPE_MESH) {
        m = 1 - h->b1 - h->b2;
        if (h->b1 < m) m = h->b1;
        return h->b2 < m ? h->b2 : m;
    }
    if (kind != GG_SHAPE_RECT) return NAN;
    m = h->b1 < 1 - h->b1 ? h->b1 : 1 - h->b1;
    if (h->b2 < m) m = h->b2;
    return 1 - h->b2 < m ? 1 - h->b2 : m;
}

GG_INLINE void rec_hit(const gg_shade_ctx *c, int node, const hit_info *hi, const unsigned FX)
{
    const ggScene *s = c->s;
    ggTraceNode *N;
    if (!(FX & FX_RECORD) || node < 0) return;
    N = &c->rec->nodes[node];
    N->hit = true;
    N->object = hi->obj, N->shape = s->objects[hi->obj].kind, N->material = hi->mi;
    N->line = s->objects[hi->obj].line;
    N->triangle = gg_scene_hit_triangle(s, &s->objects[hi->obj], hi->h->prim);
    N->t = hi->h->t, N->p = hi->sf.p, N->ng = hi->sf.ng, N->ns = hi->sf.ns, N->front = hi->front;
    N->u = hi->sf.u, N->v = hi->sf.v;
    N->surface = gg_scene_surface_color(s, hi->mi, hi->sf.u, hi->sf.v, c->acc.texture);
    N->ambient = cmul(hi->kdc, s->ambient);
    N->emission = (hi->mf->flags & GG_MF_EMIT) ? hi->m->ke : rgb(0, 0, 0);
    N->first_light = (int)c->rec->nlights;
    N->n_other = N->n_medium;
    N->perr = hi->sf.perr;
    N->offset = v3len(v3sub(hi->o_out, hi->sf.p));
    N->edge = edge_distance(N->shape, hi->h);
}

/* A light record for light li at node's hit, facing away until the
   shadow ray says otherwise; its index, or -1. */
GG_INLINE int rec_light(const gg_shade_ctx *c, int node, size_t li, const unsigned FX)
{
    ggTraceLight *R;
    int lr;
    if (!(FX & FX_RECORD) || node < 0 || (lr = gg_trace_add_light(c->rec)) < 0) return -1;
    c->rec->nodes[node].nlights++;
    R = &c->rec->lights[lr];
    R->light = (int)li;
    R->verdict = GG_SHADOW_FACING_AWAY;
    R->occluder = -1;
    R->t_block = 1;
    return lr;
}

GG_INLINE void rec_shadow(const gg_shade_ctx *c, int lr, size_t li, const shadow_ray *sh,
                          const unsigned FX)
{
    ggTraceLight *R;
    ggColor l0;
    if (!(FX & FX_RECORD) || lr < 0) return;
    R = &c->rec->lights[lr];
    l0 = c->s->light_colors[li];
    R->verdict = sh->verdict, R->occluder = sh->occ, R->origin = sh->o, R->dir = sh->d;
    R->t_block = sh->tb;
    /* What got through, relative to the light's own colour. */
    R->transmittance = sh->verdict == GG_SHADOW_BLOCKED
                           ? rgb(0, 0, 0)
                           : rgb(l0.r > 0 ? sh->lc.r / l0.r : 0, l0.g > 0 ? sh->lc.g / l0.g : 0,
                                 l0.b > 0 ? sh->lc.b / l0.b : 0);
}

GG_INLINE void rec_light_terms(const gg_shade_ctx *c, int lr, ggColor diff, ggColor ph,
                               const unsigned FX)
{
    if (!(FX & FX_RECORD) || lr < 0) return;
    c->rec->lights[lr].diffuse = diff, c->rec->lights[lr].phong = ph;
}

/* One transmitted channel: from index ni into nt at |cos| cos_i; ok = 0
   is total internal reflection; F is the dielectric Fresnel reflectance
   when `fresnel` says one was computed. */
GG_INLINE void rec_refract(const gg_shade_ctx *c, int node, double ni, double nt, double cos_i,
                           int ok, int fresnel, double F, const unsigned FX)
{
    ggTraceNode *N;
    double eta, e2, k, margin;
    (void)ok;
    if (!(FX & FX_RECORD) || node < 0) return;
    N = &c->rec->nodes[node];
    N->n_other = nt;
    if (fresnel) N->fresnel = F;
    /* The discriminant in units of a bound on its rounding error: a few
       roundings of cos^2, eta^2, their products and 1 - each, and the
       error of cos itself (a dot product of unit vectors) times its
       derivative 2 eta^2 cos. Dispersion: the channel nearest to 0. */
    eta = ni / nt, e2 = eta * eta;
    k = 1 - e2 * (1 - cos_i * cos_i);
    margin = k / (0x1p-53 * (1 + 5 * e2 + 8 * e2 * cos_i));
    if (!(fabs(margin) >= fabs(N->tir_margin))) N->tir_margin = margin;
}

/* The index the next ray's record will get (before tracing a child). */
GG_INLINE int rec_next(const gg_shade_ctx *c, const unsigned FX)
{
    return (FX & FX_RECORD) ? (int)c->rec->nnodes : -1;
}

/* Child ray `child` (record ci) has returned, with weight w in node's colour. */
GG_INLINE void rec_child(const gg_shade_ctx *c, int node, int ci, const ray_state *child, ggColor w,
                         const unsigned FX)
{
    ggTraceNode *N;
    if (!(FX & FX_RECORD) || node < 0) return;
    N = &c->rec->nodes[node];
    if (ci >= 0 && (size_t)ci < c->rec->nnodes) c->rec->nodes[ci].weight = w;
    if (child->kind == GG_RAY_REFRACT)
        N->refract_weight = cadd(N->refract_weight, w);
    else
        N->reflect_weight = w;
}

GG_INLINE void rec_stop(const gg_shade_ctx *c, int node, int stop, const unsigned FX)
{
    if (!(FX & FX_RECORD) || node < 0) return;
    c->rec->nodes[node].stop = stop;
}

GG_INLINE void rec_ray_end(const gg_shade_ctx *c, int node, int hit, ggColor att, ggColor col,
                           const unsigned FX)
{
    ggTraceNode *N;
    if (!(FX & FX_RECORD) || node < 0) return;
    N = &c->rec->nodes[node];
    if (!hit) N->stop = GG_STOP_MISS;
    N->absorption = att;
    N->color = col;
}

/* ---- path layers (lpe.h): the layer copy's hooks ----
   Each takes FX and starts with `if (!(FX & FX_AOV)) return`, so only the
   layer copy runs them. A ray carries its weight in the pixel per channel
   (thru) and each layer's automaton state after the events that led to
   it (lpe; 0: dead). At a hit, hi->aw is thru times the absorption along
   the ray: a term T there (what the ledger calls a term: ambient,
   emission, a light's diffuse or Phong share; the background at a miss)
   adds aw * T to every layer whose automaton accepts the term's events,
   in th->aov. */

/* a * b per channel, a weight of exactly 0 keeping out even an infinite
   term (as the ledger does, lib/debug/ledger.c). */
static ggColor wmul(ggColor a, ggColor b)
{
    return rgb(a.r == 0 ? 0 : a.r * b.r, a.g == 0 ? 0 : a.g * b.g, a.b == 0 ? 0 : a.b * b.b);
}

/* th->aov_n (only ggCheck's layer sums ask for it): layer l's count of
   terms, the ledger's non-zero ones (lib/debug/ledger.c). Out of line,
   so that the tests stay out of ggRender's path. */
static GG_NOINLINE void aov_count(gg_shade_thread *th, int l, ggColor term)
{
    if (term.r != 0 || term.g != 0 || term.b != 0) th->aov_n[l]++;
}

static void aov_add(gg_shade_thread *th, int l, ggColor a, ggColor term)
{
    th->aov[l] = cadd(th->aov[l], wmul(a, term));
    if (GG_UNLIKELY(th->aov_n != NULL)) aov_count(th, l, term);
}

/* aov_add with a = hi->aw: a plain product when aw has no zero channel
   (wmul's result then is the same, bit for bit). */
GG_INLINE void aov_add_hit(gg_shade_thread *th, int l, const hit_info *hi, ggColor term)
{
    const ggColor p = hi->awz ? wmul(hi->aw, term) : cmul(hi->aw, term);
    th->aov[l] = cadd(th->aov[l], p);
    if (GG_UNLIKELY(th->aov_n != NULL)) aov_count(th, l, term);
}

/* An eye ray: weight 1, every layer not dead after its C. */
static void aov_root(const gg_shade_ctx *c, ray_state *r)
{
    r->thru = rgb(1, 1, 1);
    r->lmask = c->layers->live;
    memcpy(r->lpe, c->layers->start, sizeof r->lpe);
}

/* The hit's per-layer terms (hi->lterm, llive), then the terms that end
   a path there: ambient amb (<RD>A) and, if it glows, emission (O). One
   lookup per live layer (lpe.h, term), none for a layer in a quiet state
   (one that accepts none of them here, as a layer of mirror paths before
   its first mirror). */
GG_INLINE void aov_local(const gg_shade_ctx *c, const ray_state *r, hit_info *hi,
                         gg_shade_thread *th, ggColor amb, const unsigned FX)
{
    unsigned m;
    if (!(FX & FX_AOV)) return;
    hi->llive = 0;
    for (m = r->lmask; m; m &= m - 1) {
        const int l = (int)GG_CTZ(m);
        const gg_lpe_dfa *d = &c->layers->layer[l];
        uint32_t t;
        if (d->quiet[r->lpe[l]]) continue;
        t = d->term[(size_t)r->lpe[l] * (size_t)d->ncls +
                    (size_t)gg_lpe_surface(d, hi->obj, hi->mi)];
        hi->lterm[l] = t;
        if (t & (GG_LPE_T_L << GG_LPE_T_RDL | GG_LPE_T_L << GG_LPE_T_RGL)) hi->llive |= 1u << l;
        if (t & GG_LPE_T_A) aov_add_hit(th, l, hi, amb);
        if ((FX & GG_EFFECT_EMISSION) && (hi->mf->flags & GG_MF_EMIT) && (t & GG_LPE_T_O))
            aov_add_hit(th, l, hi, hi->m->ke);
    }
}

/* Light li's diffuse (<RD>L) and Phong (<RG>L) terms at the hit. */
GG_INLINE void aov_light(const gg_shade_ctx *c, const ray_state *r, const hit_info *hi,
                         gg_shade_thread *th, size_t li, ggColor diff, ggColor ph,
                         const unsigned FX)
{
    unsigned m;
    (void)r;
    if (!(FX & FX_AOV)) return;
    for (m = hi->llive; m; m &= m - 1) {
        const int l = (int)GG_CTZ(m);
        const uint32_t t = hi->lterm[l] >> gg_lpe_num_class(&c->layers->layer[l], (long)li);
        if (t >> GG_LPE_T_RDL & 1u) aov_add_hit(th, l, hi, diff);
        if (t >> GG_LPE_T_RGL & 1u) aov_add_hit(th, l, hi, ph);
    }
}

/* A child ray of kind k (GG_LPE_RS, _RS_TIR, _TS) leaving the hit with
   weight w in its parent's colour. */
GG_INLINE void aov_child(const gg_shade_ctx *c, const ray_state *r, const hit_info *hi,
                         ray_state *child, int k, ggColor w, const unsigned FX)
{
    unsigned m;
    if (!(FX & FX_AOV)) return;
    child->thru = wmul(hi->aw, w);
    child->lmask = 0;
    for (m = r->lmask; m; m &= m - 1) {
        const int l = (int)GG_CTZ(m);
        const gg_lpe_dfa *d = &c->layers->layer[l];
        if ((child->lpe[l] = (uint16_t)gg_lpe_step(d, r->lpe[l], k,
                                                   gg_lpe_surface(d, hi->obj, hi->mi))) != 0)
            child->lmask |= 1u << l;
    }
}

/* A miss: the background bg, seen through absorption att. */
GG_INLINE void aov_background(const gg_shade_ctx *c, const ray_state *r, gg_shade_thread *th,
                              ggColor att, ggColor bg, const unsigned FX)
{
    const ggColor a = (FX & FX_AOV) ? wmul(r->thru, att) : att;
    unsigned m;
    if (!(FX & FX_AOV)) return;
    for (m = r->lmask; m; m &= m - 1) {
        const int l = (int)GG_CTZ(m);
        const gg_lpe_dfa *d = &c->layers->layer[l];
        if (d->term[(size_t)r->lpe[l] * (size_t)d->ncls] & GG_LPE_T_B) aov_add(th, l, a, bg);
    }
}

/* ---- the ray budget ---- */

/* Whether the eye ray's tree may cast one more secondary ray (and count
   it against the budget); if not, the ray is counted as cut and node says
   why it stopped. */
GG_INLINE int budget_take(const gg_shade_ctx *c, gg_shade_thread *th, int node, const unsigned FX)
{
    if (GG_LIKELY(th->left > 0)) {
        th->left--;
        return 1;
    }
    th->st.budget_cut++;
    rec_stop(c, node, GG_STOP_BUDGET, FX);
    return 0;
}

/* ---- the hit ---- */

GG_INLINE void hit_setup(const gg_shade_ctx *c, const ray_state *r, const gg_rayq *q,
                         const gg_hit *h, hit_info *hi, const unsigned FX)
{
    const ggScene *s = c->s;
    gg_prim_info pi;
    ggVec3 ng, ns;
    hi->q = q, hi->h = h;
    /* the material from the primitive's record (its tag), not the
       object's: one read, where a mesh of NFF triangles has an object
       record per triangle */
    gg_geom_prim_info(s->geom, h->prim, &pi);
    hi->obj = pi.obj, hi->mi = pi.tag;
    hi->m = &s->materials[hi->mi];
    hi->mf = &s->mfast[hi->mi];
    hi->leave = c->fixed_offset ? UINT32_MAX : leave_kind(pi.kind, h->prim);
    /* (u, v) costs an atan2 on curved shapes: only for textures and the
       recorder. */
    gg_geom_surface(s->geom, q, h, &hi->sf,
                    ((FX & FX_RECORD) || (hi->mf->flags & GG_MF_TEXTURE)) ? GG_SURF_UV : 0u);
    /* Normals facing the incoming ray: surfaces are two-sided. The
       normals were just written one double at a time: read them so
       (v3_unpaired; 1-2% of a render of spd/tree or teapot-s12). */
    ng = v3_unpaired(&hi->sf.ng), ns = v3_unpaired(&hi->sf.ns);
    hi->front = v3dot(r->d, ng) < 0;
    hi->ng = hi->front ? ng : v3neg(ng);
    hi->ns = hi->front ? ns : v3neg(ns);
    /* The offset depends only on the side a new ray leaves to: shadow and
       mirror rays all leave on the incoming side, so share one origin. */
    hi->o_out = spawn(c, &hi->sf, hi->ng);
    hi->kdc = hi->mf->kd_color;
    if ((FX & GG_EFFECT_TEXTURES) && (hi->mf->flags & GG_MF_TEXTURE))
        hi->kdc = cscale(gg_scene_surface_color(s, hi->mi, hi->sf.u, hi->sf.v, c->acc.texture),
                         hi->m->kd);
}

GG_INLINE ggColor emission_ambient(const gg_shade_ctx *c, const hit_info *hi, const unsigned FX)
{
    ggColor col = cmul(hi->kdc, c->s->ambient);
    if ((FX & GG_EFFECT_EMISSION) && (hi->mf->flags & GG_MF_EMIT)) col = cadd(col, hi->m->ke);
    return col;
}

/* ---- direct light ---- */

/* Where a shadow ray toward `light` from o stops: short of the light by
   the rounding of a hit there (gg_offset_end), as its origin is pushed
   off the surface it leaves; at the light with the fixed-offset knob. */
static double shadow_end(const gg_shade_ctx *c, ggVec3 o, ggVec3 light)
{
    return c->end_margin ? gg_offset_end(o, light) : 1.0;
}

/* Light arriving at the shadow origin o from a light at parameter 1
   along d (d = light - o), through transparent occluders: kt per surface
   crossed and absorption inside. Returns black if an opaque surface
   blocks. *first_obj receives the first object crossed (-1 if none) and
   *t_first where (parameter of the original ray). `all` is what
   gg_geom_occluded found on the segment, which it did not find blocked. */
GG_INLINE ggColor shadow_walk(const gg_shade_ctx *c, gg_shade_thread *th, ggVec3 o, ggVec3 d,
                              uint32_t from, const gg_media *start, int *first_obj, double *t_first,
                              const gg_tcol *all, const unsigned FX)
{
    const ggScene *s = c->s;
    ggVec3 light;
    gg_media m;
    ggColor tr = rgb(1, 1, 1);
    double len;
    gg_rayq q;
    gg_hit h;
    int step;
    *first_obj = -1;
    *t_first = 1;
    /* Every crossing known, nothing opaque: no query, no hit point, no
       offset origin is needed, only kt and the media between crossings.
       The stepwise walk below asks again from just past each surface: for
       lists that overflowed or met an implicit surface, for walks that
       start inside a sphere, and for the fixed-epsilon knob, whose re-hits
       are part of what the accuracy study shows. */
    if (all->complete && !c->fixed_offset) {
        double prev = 0;
        int i;
        const int absorb = ABSORBS(c, FX);
        /* Most shadow rays: nothing crossed, no medium to absorb. The
           general loop would give (1, 1, 1) times a transmittance of
           (1, 1, 1): the same bits. */
        if (all->n == 0 && (start->n == 0 || !absorb)) return tr;
        m = *start;
        len = v3len(d);
        for (i = 0; i < all->n; i++) {
            const gg_hit *hi = &all->h[i];
            gg_prim_info pi;
            int obj, mat;
            gg_geom_prim_info(s->geom, hi->prim, &pi);
            obj = pi.obj, mat = pi.tag;
            if (*first_obj < 0) *first_obj = obj, *t_first = hi->t;
            if (absorb) tr = cmul(tr, media_transmittance(s, &m, (hi->t - prev) * len));
            tr = cscale(tr, s->materials[mat].kt);
            media_cross(&m, mat);
            if (cmaxc(tr) <= 0) return tr;
            prev = hi->t;
        }
        return absorb ? cmul(tr, media_transmittance(s, &m, (1 - prev) * len)) : tr;
    }
    light = v3add(o, d);
    m = *start;
    len = v3len(d);
    q = make_q(c, th, o, d, shadow_end(c, o, light), from, 0);
    for (step = 0; step < GG_MAX_SHADOW_STEPS; step++) {
        int obj, mat, found;
        gg_prim_info pi;
        gg_surf sf;
        /* The first query came answered: its nearest crossing. */
        if (step == 0) {
            found = all->has_near;
            if (found) h = all->near;
        } else
            found = gg_geom_intersect(s->geom, &q, &h);
        if (!found) return cmul(tr, media_transmittance(s, &m, len));
        gg_geom_prim_info(s->geom, h.prim, &pi);
        obj = pi.obj, mat = pi.tag;
        if (*first_obj < 0) *first_obj = obj, *t_first = h.t;
        if (s->materials[mat].kt <= 0) {
            *first_obj = obj, *t_first = h.t;
            return rgb(0, 0, 0);
        }
        tr = cmul(tr, media_transmittance(s, &m, h.t * len));
        tr = cscale(tr, s->materials[mat].kt);
        gg_geom_surface(s->geom, &q, &h, &sf, 0u);
        media_cross(&m, mat);
        if (cmaxc(tr) <= 0) return tr;
        /* Go on from just past this surface towards the light. */
        q.o = spawn(c, &sf, q.d);
        q.d = v3sub(light, q.o);
        q.tmax = shadow_end(c, q.o, light);
        len = v3len(q.d);
        q.ignore_prim = c->fixed_offset ? UINT32_MAX : leave_prim(s, h.prim);
        /* Crossed into a sphere: the next surface may well be its far side. */
        q.inside = q.ignore_prim == UINT32_MAX && v3dot(q.d, sf.ng) < 0 ? h.prim : UINT32_MAX;
    }
    return rgb(0, 0, 0);
}

/* The recorder names what blocks a shadow ray, so it asks for the nearest
   opaque element where the renderer asks whether there is any (the same
   verdict). Returns 1 when blocked. */
static int nearest_blocker(const gg_shade_ctx *c, const gg_rayq *sq, shadow_ray *sh)
{
    gg_hit bh;
    if (!gg_geom_intersect(c->s->geom, sq, &bh)) return 0;
    sh->verdict = GG_SHADOW_BLOCKED;
    sh->occ = gg_geom_prim_object(c->s->geom, bh.prim), sh->tb = bh.t;
    return 1;
}

/* A shadow ray in a scene without coloured shadows: anything blocks it,
   and the medium the hit is in absorbs. */
GG_INLINE void shadow_opaque(const gg_shade_ctx *c, const ray_state *r, const hit_info *hi,
                             size_t li, gg_shade_thread *th, shadow_ray *sh, const unsigned FX)
{
    const ggScene *s = c->s;
    const gg_rayq sq = make_q(c, th, sh->o, sh->d, sh->tend, hi->leave, 0);
    if (FX & FX_RECORD) {
        if (nearest_blocker(c, &sq, sh)) return;
    } else if (gg_geom_occluded(s->geom, &sq, &th->occ[li % GG_OCC_CACHES], NULL)) {
        sh->verdict = GG_SHADOW_BLOCKED;
        return;
    }
    if (ABSORBS(c, FX) && r->media.n > 0) {
        ggColor a = media_transmittance(s, &r->media, v3len(sh->d));
        if (a.r != 1 || a.g != 1 || a.b != 1) sh->verdict = GG_SHADOW_ATTENUATED;
        sh->lc = cmul(sh->lc, a);
    }
}

/* A shadow ray that transparent occluders let through (shadow_walk). One
   query answers whether anything opaque blocks it and, if not, what
   transparent surfaces it crosses, for the walk. */
GG_INLINE void shadow_colored(const gg_shade_ctx *c, const ray_state *r, const hit_info *hi,
                              size_t li, gg_shade_thread *th, shadow_ray *sh, const unsigned FX)
{
    const ggScene *s = c->s;
    gg_rayq sq = make_q(c, th, sh->o, sh->d, sh->tend, hi->leave, GG_PRIM_TRANSPARENT);
    gg_tcol all;
    ggColor through;
    if (FX & FX_RECORD) {
        uint32_t none = 0;
        if (nearest_blocker(c, &sq, sh)) return;
        /* the renderer's crossings, to walk them the same way */
        gg_geom_occluded(s->geom, &sq, &none, &all);
    } else {
        /* Leaving a sphere's inner side inwards: when nothing else is
           inside it, its far side is the walk's first hit and anything
           opaque lies beyond, for the walk to meet. */
        if (!hi->front && hi->leave == UINT32_MAX) sq.inside = hi->h->prim;
        if (gg_geom_occluded(s->geom, &sq, &th->occ[li % GG_OCC_CACHES], &all)) {
            sh->verdict = GG_SHADOW_BLOCKED;
            return;
        }
    }
    through = shadow_walk(c, th, sh->o, sh->d, hi->leave, &r->media, &sh->occ, &sh->tb, &all, FX);
    /* As shadow_opaque's: attenuated only when something was taken. A
       crossing that takes nothing (kt = 1, no absorption) leaves the
       light visible; sh->occ still names the first object crossed. */
    if (sh->occ >= 0 && cis0(through))
        sh->verdict = GG_SHADOW_BLOCKED;
    else if (through.r != 1 || through.g != 1 || through.b != 1)
        sh->verdict = GG_SHADOW_ATTENUATED;
    sh->lc = cmul(sh->lc, through);
}

/* Diffuse and Phong terms of one light, whose colour lc arrives along unit Lu. */
GG_INLINE void light_terms(const gg_shade_ctx *c, const ray_state *r, const hit_info *hi,
                           gg_shade_thread *th, size_t li, ggColor lc, double nl, ggVec3 Lu,
                           int lr, ggColor *col, const unsigned FX)
{
    ggColor diff = cmul(hi->kdc, cscale(lc, nl)), ph = rgb(0, 0, 0);
    *col = cadd(*col, diff);
    if ((FX & GG_EFFECT_PHONG) && (hi->mf->flags & GG_MF_PHONG)) {
        /* Phong: (R.V)^shine with R the light's mirror direction. */
        ggVec3 R = reflect(v3neg(Lu), hi->ns);
        double rv = -v3dot(R, r->d);
        if (rv > 0) {
            ph = cscale(lc, hi->m->ks * c->power(rv, hi->m->shine));
            *col = cadd(*col, ph);
        }
    }
    rec_light_terms(c, lr, diff, ph, FX);
    aov_light(c, r, hi, th, li, diff, ph, FX);
}

/* Direct light: one shadow ray per light the surface faces. */
GG_INLINE void direct_light(const gg_shade_ctx *c, const ray_state *r, const hit_info *hi,
                            gg_shade_thread *th, int node, ggColor *col, const unsigned FX)
{
    const ggScene *s = c->s;
    size_t li;
    for (li = 0; li < s->nlights; li++) {
        const ggVec3 L = v3sub(s->lights[li].pos, hi->sf.p);
        const int lr = rec_light(c, node, li, FX);
        shadow_ray sh;
        double nl, len;
        if (v3dot(hi->ng, L) <= 0 || (nl = v3dot(hi->ns, L)) <= 0) continue;
        th->st.shadow++;
        sh.o = hi->o_out;
        sh.d = v3sub(s->lights[li].pos, sh.o);
        /* only the copies with FX_END look (light_in_bounds) */
        sh.tend = (FX & FX_END) ? shadow_end(c, sh.o, s->lights[li].pos) : 1.0;
        sh.lc = s->light_colors[li];
        sh.verdict = GG_SHADOW_VISIBLE, sh.occ = -1, sh.tb = 1;
        /* the scene has them, and the shadows knob did not drop them */
        if (RUNS(c, FX, GG_EFFECT_COLORED_SHADOWS))
            shadow_colored(c, r, hi, li, th, &sh, FX);
        else
            shadow_opaque(c, r, hi, li, th, &sh, FX);
        rec_shadow(c, lr, li, &sh, FX);
        if (sh.verdict == GG_SHADOW_BLOCKED) {
            th->st.shadow_blocked++;
            continue;
        }
        if (sh.verdict == GG_SHADOW_ATTENUATED) th->st.shadow_attenuated++;
        if (cis0(sh.lc)) continue;
        /* L's length and direction only now: a blocked light needs
           neither, and nothing has to survive the shadow query's call. */
        len = v3len(L);
        light_terms(c, r, hi, th, li, sh.lc, nl / len, v3scale(L, 1.0 / len), lr, col, FX);
    }
}

/* ---- secondary rays ---- */

/* The mirror ray's weight before transmission adds to it: ks, or the
   conductor's Fresnel reflectance. */
GG_INLINE void mirror_weight(const gg_shade_ctx *c, const ray_state *r, const hit_info *hi,
                             secondary *sc, const unsigned FX)
{
    const ggMaterial *m = hi->m;
    sc->wr = rgb(m->ks, m->ks, m->ks);
    sc->reflect = (hi->mf->flags & GG_MF_REFLECT) != 0;
    sc->tir = 0;
    sc->cos_i = -v3dot(r->d, hi->ns);
    if (sc->cos_i < 0) sc->cos_i = -sc->cos_i;
    if ((FX & GG_EFFECT_FRESNEL) && m->fresnel == GG_FRESNEL_CONDUCTOR) {
        double ni = media_index(c->s, &r->media, r->channel);
        sc->wr = rgb(ggFresnelConductor(sc->cos_i, ni, m->eta_n.r, m->eta_k.r),
                     ggFresnelConductor(sc->cos_i, ni, m->eta_n.g, m->eta_k.g),
                     ggFresnelConductor(sc->cos_i, ni, m->eta_n.b, m->eta_k.b));
        sc->reflect = 1;
    }
}

/* Direction t of the ray v refracted at the hit from index ni into nt, as
   the refraction knob says; 0 on total internal reflection. */
GG_INLINE int refract_dir(const gg_shade_ctx *c, ggVec3 v, const hit_info *hi, double ni, double nt,
                          ggVec3 *t)
{
    int ok;
    /* gg_refract_unit: plain double where refraction is well conditioned,
       ggRefract elsewhere (lib/optics/refract_unit.h). */
    if (c->acc.refract == GG_ACC_REFRACT_TEXTBOOK)
        ok = ggRefractTextbook(v, hi->ns, ni, nt, t);
    else if (c->acc.refract == GG_ACC_REFRACT_EXACT)
        ok = ggRefract(v, hi->ns, ni, nt, t);
    else
        ok = gg_refract_unit(v, hi->ns, ni, nt, t);
    /* A shading normal can bend t back to the incoming side: refract
       about the true surface instead. */
    if (ok && v3dot(*t, hi->ng) >= 0) ok = ggRefract(v, hi->ng, ni, nt, t);
    return ok;
}

/* Where a transmitted channel goes (transmission fills it). */
typedef struct crossing {
    gg_media inside; /* the media on the far side */
    int entering;    /* into the hit's material (else out of it) */
    int split;       /* a dispersive surface splits the ray into R, G, B */
    int fmode;       /* fresnel_mode */
} crossing;

/* One transmitted channel ch (all of R, G, B unless x->split): the
   refracted ray, or on total internal reflection its share to the
   mirror ray; the Fresnel reflectance also goes to the mirror ray. */
GG_INLINE void transmit(const gg_shade_ctx *c, const ray_state *r, const hit_info *hi,
                        gg_shade_thread *th, int node, const crossing *x, int ch, secondary *sc,
                        ggColor *col, const unsigned FX)
{
    const ggScene *s = c->s;
    const int chan = x->split ? ch : r->channel;
    double ni, nt, F = 0, w = hi->m->kt;
    ray_state child;
    ggVec3 t;
    ggColor tc;
    int ok, fresnel, ci;
    ni = x->entering ? media_index(s, &r->media, chan) : mat_index(s, hi->mi, chan);
    nt = x->entering ? mat_index(s, hi->mi, chan) : media_index(s, &x->inside, chan);
    ok = refract_dir(c, r->d, hi, ni, nt, &t);
    fresnel = ok && (FX & GG_EFFECT_FRESNEL) && x->fmode != GG_FRESNEL_NONE &&
              x->fmode != GG_FRESNEL_CONDUCTOR;
    if (fresnel)
        F = x->fmode == GG_FRESNEL_SCHLICK ? ggFresnelSchlick(sc->cos_i, ni, nt)
                                           : ggFresnelDielectric(sc->cos_i, ni, nt);
    rec_refract(c, node, ni, nt, sc->cos_i, ok, fresnel, F, FX);
    if (!ok) {
        /* Total internal reflection: the transmitted share joins the
           mirror ray. */
        th->st.tir++;
        sc->tir = 1;
        add_share(&sc->wr, x->split, ch, w);
        sc->reflect = 1;
        return;
    }
    if (fresnel) {
        /* F = 0 (equal indices) gives the mirror ray nothing, F = 1 (an
           index so large that 1 - F rounds to 0) the refracted ray: a
           ray of weight 0 is not cast, nor does it take from the budget
           (the SPD rule's zero-weight mirror ray aside, transmission()). */
        if (F > 0) {
            add_share(&sc->wr, x->split, ch, w * F);
            sc->reflect = 1;
        }
        w *= 1 - F;
    }
    /* Adaptive depth (POV-Ray's adc_bailout): skip rays that cannot
       matter. Off (0) by default. */
    if (!(w > 0) || r->weight * w < c->acc.cutoff || !budget_take(c, th, node, FX)) return;
    child_ray(&child, r, node, spawn(c, &hi->sf, t), t, GG_RAY_REFRACT, r->weight * w);
    child.from_prim = hi->leave;
    /* Refracted in through a sphere's outer side: inside it. */
    child.inside = hi->front && hi->leave == UINT32_MAX ? hi->h->prim : UINT32_MAX;
    child.channel = chan;
    child.media = x->inside;
    th->st.refract++;
    aov_child(c, r, hi, &child, GG_LPE_TS, x->split ? channel_weight(ch, w) : rgb(w, w, w), FX);
    ci = rec_next(c, FX);
    tc = TRACE_CHILD(FX, c, &child, th);
    if (x->split)
        add_share(col, 1, ch, w * (ch == 0 ? tc.r : ch == 1 ? tc.g : tc.b));
    else
        *col = cadd(*col, cscale(tc, w));
    rec_child(c, node, ci, &child, x->split ? channel_weight(ch, w) : rgb(w, w, w), FX);
}

/* Transmission: a refracted ray per channel (three after a dispersive
   surface). Entering or leaving is decided by whether the ray is inside
   the material already, not by the face's orientation: a polygon mesh
   wound the wrong way still works. */
GG_INLINE void transmission(const gg_shade_ctx *c, const ray_state *r, const hit_info *hi,
                            gg_shade_thread *th, int node, secondary *sc, ggColor *col,
                            const unsigned FX)
{
    crossing x;
    int ch;
    x.inside = r->media;
    x.entering = !media_has(&r->media, hi->mi);
    media_cross(&x.inside, hi->mi);
    x.split = (FX & GG_EFFECT_DISPERSION) && (hi->mf->flags & GG_MF_DISPERSE) && r->channel < 0 &&
              c->acc.wavelengths != 1;
    x.fmode = fresnel_mode(c, hi->m);
    if (c->spd_rules) sc->reflect = 1;
    for (ch = 0; ch < (x.split ? 3 : 1); ch++) transmit(c, r, hi, th, node, &x, ch, sc, col, FX);
}

/* The mirror ray, with the weight the other terms left it. */
GG_INLINE void mirror(const gg_shade_ctx *c, const ray_state *r, const hit_info *hi,
                      gg_shade_thread *th, int node, secondary *sc, ggColor *col, const unsigned FX)
{
    ray_state child;
    ggVec3 rd;
    ggColor rc;
    int ci;
    if (sc->reflect && c->acc.cutoff > 0 && r->weight * cmaxc(sc->wr) < c->acc.cutoff)
        sc->reflect = 0;
    if (!sc->reflect) {
        if (!(hi->mf->flags & GG_MF_TRANSMIT)) rec_stop(c, node, GG_STOP_MATTE, FX);
        return;
    }
    if (!budget_take(c, th, node, FX)) return;
    rd = reflect(r->d, hi->ns);
    /* A shading normal can send the mirror ray into the surface. */
    if (v3dot(rd, hi->ng) <= 0) rd = reflect(r->d, hi->ng);
    child_ray(&child, r, node, hi->o_out, rd, sc->tir ? GG_RAY_TIR : GG_RAY_REFLECT,
              r->weight * cmaxc(sc->wr));
    child.from_prim = hi->leave;
    /* Mirrored off a sphere's inner side: still inside it. */
    child.inside = !hi->front && hi->leave == UINT32_MAX ? hi->h->prim : UINT32_MAX;
    child.channel = r->channel;
    child.media = r->media;
    th->st.reflect++;
    aov_child(c, r, hi, &child, sc->tir ? GG_LPE_RS_TIR : GG_LPE_RS, sc->wr, FX);
    ci = rec_next(c, FX);
    /* Under the SPD rule a transmitter spawns (and counts) a mirror ray
       even when its weight is zero. */
    rc = TRACE_CHILD(FX, c, &child, th);
    if (!cis0(sc->wr)) *col = cmadd(*col, sc->wr, rc);
    rec_child(c, node, ci, &child, sc->wr, FX);
}

/* The colour leaving hit h of ray r (whose record is node); att: the
   absorption along r to h, which only the layer copy knows (and needs)
   at this point. */
GG_INLINE ggColor shade_hit(const gg_shade_ctx *c, const ray_state *r, const gg_rayq *q,
                            const gg_hit *h, gg_shade_thread *th, int node, ggColor att,
                            const unsigned FX)
{
    hit_info hi;
    secondary sc;
    ggColor col;
    hit_setup(c, r, q, h, &hi, FX);
    col = emission_ambient(c, &hi, FX);
    if (FX & FX_AOV) {
        hi.aw = wmul(r->thru, att);
        hi.awz = hi.aw.r == 0 || hi.aw.g == 0 || hi.aw.b == 0;
        aov_local(c, r, &hi, th, cmul(hi.kdc, c->s->ambient), FX);
    }
    rec_hit(c, node, &hi, FX);
    if (FX & GG_EFFECT_SHADOWS) direct_light(c, r, &hi, th, node, &col, FX);
    if (r->depth >= c->max_depth) {
        rec_stop(c, node,
                 (hi.mf->flags & (GG_MF_REFLECT | GG_MF_TRANSMIT)) ? GG_STOP_DEPTH : GG_STOP_MATTE,
                 FX);
        return col;
    }
    mirror_weight(c, r, &hi, &sc, FX);
    if ((FX & GG_EFFECT_REFRACTION) && (hi.mf->flags & GG_MF_TRANSMIT))
        transmission(c, r, &hi, th, node, &sc, &col, FX);
    mirror(c, r, &hi, th, node, &sc, &col, FX);
    return col;
}

/* ---- rays ---- */

GG_INLINE ggColor trace_fx(const gg_shade_ctx *c, const ray_state *r, gg_shade_thread *th,
                           const gg_hit *known, const unsigned FX)
{
    const ggScene *s = c->s;
    gg_rayq q = make_q(c, th, v3_unpaired(&r->o), v3_unpaired(&r->d), INFINITY, r->from_prim, 0);
    gg_hit h;
    const gg_hit *hp = known ? known : &h;
    ggColor col, att = rgb(1, 1, 1);
    int node, hit = 1;
    /* The layer copy: a tree's root starts its layers here, so that
       the other copies' roots cost nothing for them. Every root is
       root_ray's, a local of gg_shade_ray_unit or gg_shade_eye_hit (not
       const): started in place, as a copy's wide loads of root_ray's
       narrow stores stalled (store forwarding; 1/4 of this copy's time
       on spd/tetra). */
    if ((FX & FX_AOV) && r->kind == GG_RAY_EYE) aov_root(c, (ray_state *)r);
    if ((uint64_t)r->depth > th->st.max_depth) th->st.max_depth = (uint64_t)r->depth;
    node = rec_ray(c, r, FX);
    q.inside = r->inside;
    if (FX & FX_RECORD)
        hit = rec_intersect(c, node, &q, known, &h);
    else if (!known)
        hit = gg_geom_intersect(s->geom, &q, &h);
    if (!hit) {
        col = s->background;
        if (ABSORBS(c, FX) && r->media.n > 0) att = media_transmittance(s, &r->media, INFINITY);
        aov_background(c, r, th, att, col, FX);
    } else {
        if (r->depth == 1) th->st.eye_hit++;
        /* The layer copy needs the absorption to the hit before shading
           it; the others take it after, as they always did. */
        if ((FX & FX_AOV) && ABSORBS(c, FX) && r->media.n > 0)
            att = media_transmittance(s, &r->media, hp->t);
        col = shade_hit(c, r, &q, hp, th, node, att, FX);
        if (!(FX & FX_AOV) && ABSORBS(c, FX) && r->media.n > 0)
            att = media_transmittance(s, &r->media, hp->t);
    }
    if (ABSORBS(c, FX) && r->media.n > 0) col = cmul(col, att);
    rec_ray_end(c, node, hit, att, col, FX);
    return col;
}

#define GG_SHADE_DEF(name, fx)                                                                     \
    static ggColor trace_##name(const gg_shade_ctx *c, const ray_state *r, gg_shade_thread *th,    \
                                const gg_hit *known)                                               \
    {                                                                                              \
        return trace_fx(c, r, th, known, fx);                                                      \
    }
GG_SHADE_COPIES(GG_SHADE_DEF)
#undef GG_SHADE_DEF

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

/* The first copy of GG_SHADE_COPIES whose FX holds what the tree needs:
   the scene's effects (c->fx) and, when recording, FX_RECORD. The
   recording path computes exactly what the full path does, so a
   recorded pixel equals the rendered one bit for bit. */
#define GG_SHADE_PICK(name, fx)                                                                    \
    if ((need & ~(unsigned)(fx)) == 0) return trace_##name(c, r, th, known);
static ggColor trace_root(const gg_shade_ctx *c, const ray_state *r, gg_shade_thread *th,
                          const gg_hit *known)
{
    const unsigned need = c->fx | (c->rec ? GG_SHADE_RECORDS : 0u);
    th->left = c->budget;
    GG_SHADE_COPIES(GG_SHADE_PICK)
    return trace_none();
}
#undef GG_SHADE_PICK

ggColor gg_shade_ray_unit(const gg_shade_ctx *c, ggVec3 o, ggVec3 u, int depth, gg_shade_thread *th)
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

/* The shading of hit h of the eye ray q (unit direction) without a ray:
   hit_setup, emission and ambient, the diffuse and Phong terms of every
   light the surface faces as if nothing blocked it, and the mirror
   weight: the arithmetic a hit costs besides its queries, in the glass
   copy's code (`ggrt bench limit`, through ggKernelLoop). */
ggColor gg_shade_local(const gg_shade_ctx *c, const gg_rayq *q, const gg_hit *h)
{
    const unsigned FX = FX_GLASS;
    const ggScene *s = c->s;
    ray_state r;
    hit_info hi;
    secondary sc;
    ggColor col;
    size_t li;
    root_ray(&r, q->o, q->d, 1);
    hit_setup(c, &r, q, h, &hi, FX);
    col = emission_ambient(c, &hi, FX);
    for (li = 0; li < s->nlights; li++) {
        const ggVec3 L = v3sub(s->lights[li].pos, hi.sf.p);
        double nl, len;
        if (v3dot(hi.ng, L) <= 0 || (nl = v3dot(hi.ns, L)) <= 0) continue;
        len = v3len(L);
        /* no thread: FX_GLASS has no path layers (aov_light returns at once) */
        light_terms(c, &r, &hi, NULL, li, s->light_colors[li], nl / len, v3scale(L, 1.0 / len),
                    -1, &col, FX);
    }
    mirror_weight(c, &r, &hi, &sc, FX);
    return cadd(col, sc.wr);
}
