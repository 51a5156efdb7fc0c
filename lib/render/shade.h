/* SPDX-License-Identifier: MIT */
/*
** shade.h -- the recursive shading core behind ggRayColor and ggRender
** (internal).
*/
#ifndef GG_SHADE_H
#define GG_SHADE_H

#include "scene.h"

/* The media a ray is inside, innermost last (materials with kt > 0). The
   space outside every object is a vacuum-like medium of index 1. */
#define GG_MAX_MEDIA 8
typedef struct gg_media {
    int n;
    int mat[GG_MAX_MEDIA];
} gg_media;

/* Everything a shading call needs that does not change per ray. */
typedef struct gg_shade_ctx {
    const ggScene *s;
    int max_depth;
    unsigned fx; /* effects simulated: the scene's plus the forced ones */
    /* Resolved once by gg_shade_init from the scene, the forced effects
       and the knobs; shading tests these plain flags, never the knobs. */
    unsigned on;       /* the effects the chosen copy's code performs (RUNS, shade.c) */
    int fixed_offset;  /* offset=EPS: rays leave at offset_eps, no primitive skipped */
    /* A light lies within the scene's bounds (a hair beyond them): shadow
       rays stop short of it (gg_offset_end); else at it, which is the same
       answer for less work (no surface can round onto the light). */
    int end_margin;
    double offset_eps; /* the fixed offset's epsilon */
    int fresnel_knob;  /* GG_FRESNEL_* replacing every dielectric's, or -1 */
    /* Phong's power: pow, or with phong=fast whole shines by repeated
       squaring (a pointer, so the default costs no test per highlight) */
    double (*power)(double x, double shine);
    bool spd_rules;
    ggAccuracy acc;  /* numerical knobs (render.h) */
    gg_qopt qopt;    /* those the geometry answers by, for every query */
    uint32_t budget; /* secondary rays per eye ray's tree (ggRenderOptions.ray_budget) */
    ggTrace *rec;    /* non-NULL: record the ray tree (single-threaded use) */
    /* non-NULL: split every ray tree's colour into these path layers
       (the layer copy of shade.c), into gg_shade_thread.aov */
    const struct ggPathLayers *layers;
} gg_shade_ctx;

/* What one rendering thread keeps for itself: its ray counts and, per
   light, the element that blocked its last shadow ray if one did (tested
   first next time: neighbouring shadow rays are mostly blocked by the
   same one; the cache argument of gg_geom_occluded). */
#define GG_OCC_CACHES 16
typedef struct gg_shade_thread {
    ggRayStats st;
    uint32_t occ[GG_OCC_CACHES];
    uint32_t left; /* secondary rays the current eye ray's tree may still cast */
    /* With ctx.layers: one colour per layer that the traced rays add
       their layers' shares to (the caller zeroes them per sample), and,
       if not NULL, per layer the number of non-zero terms it took. */
    ggColor *aov;
    uint32_t *aov_n;
} gg_shade_thread;

/* Fill ctx from a prepared scene and resolved options; acc may be NULL.
   The ray budget is GG_RAY_BUDGET until the caller sets ctx->budget. */
void gg_shade_init(gg_shade_ctx *ctx, const ggScene *s, int max_depth, unsigned force,
                   bool spd_rules, const ggAccuracy *acc);

/* Split every ray tree's colour into these path layers (NULL: none)
   from now on, into each thread's gg_shade_thread.aov: the layer copy. */
void gg_shade_set_layers(gg_shade_ctx *ctx, const struct ggPathLayers *layers);

/* Colour along a ray starting in the outside medium (an eye ray, or any
   ray of ggRayColor) at the given depth (eye ray = 1). */
ggColor gg_shade_ray(const gg_shade_ctx *ctx, ggVec3 o, ggVec3 d, int depth, gg_shade_thread *th);

/* gg_shade_ray in two steps, so that a caller can compute many directions
   first (their divisions and square roots then overlap instead of
   delaying each ray): gg_shade_dir returns 0 where gg_shade_ray would
   return black without casting anything, else 1 with the unit direction
   it would trace; gg_shade_ray_unit traces it. Same result, same bits. */
int gg_shade_dir(ggVec3 o, ggVec3 d, ggVec3 *u);
ggColor gg_shade_ray_unit(const gg_shade_ctx *ctx, ggVec3 o, ggVec3 u, int depth,
                          gg_shade_thread *th);

/* gg_shade_ray_unit(ctx, o, u, 1, th) for a caller that casts its eye
   rays itself, so that a miss costs it no call into the shading: q is
   the eye ray's query (gg_rayq_make(o, u, 0, INFINITY, &ctx->qopt)) and h
   what gg_geom_intersect returned for it.
   A miss's colour is gg_shade_eye_miss(ctx). The caller counts its eye
   rays in st.eye and raises st.max_depth to 1 (gg_shade_ray_unit does
   both per ray; a batch of rays can do it once). */
ggColor gg_shade_eye_hit(const gg_shade_ctx *ctx, const gg_rayq *q, const gg_hit *h,
                         gg_shade_thread *th);

/* What shading hit h of eye ray q (unit d) costs besides its rays: the
   surface, emission, ambient, each facing light's terms as if unblocked,
   the mirror weight (ggKernelLoop's GG_KERNEL_SHADE). Not a pixel's colour. */
ggColor gg_shade_local(const gg_shade_ctx *ctx, const gg_rayq *q, const gg_hit *h);
/* An eye ray starts in the outside medium: a miss is the background,
   with no absorption. */
static inline ggColor gg_shade_eye_miss(const gg_shade_ctx *ctx)
{
    return ctx->s->background;
}

#endif
