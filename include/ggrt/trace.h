/* SPDX-License-Identifier: MIT */
/*
** ggrt/trace.h -- recording the ray tree of one pixel: every eye,
** reflection, refraction, total-internal-reflection and shadow ray, what it
** hit, and what it contributed.
**
** Recording has its own compiled path in the renderer: when no recorder
** is given (ggRender, ggRayColor) not one instruction of it runs.
*/
#ifndef GGRT_TRACE_H
#define GGRT_TRACE_H

#include "ggrt/base.h"
#include "ggrt/render.h"
#include "ggrt/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Ray kinds. Shadow rays are recorded per light (ggTraceLight). */
#define GG_RAY_EYE     0
#define GG_RAY_REFLECT 1 /* mirror ray */
#define GG_RAY_REFRACT 2 /* transmitted ray */
#define GG_RAY_TIR     3 /* mirror ray that carries a totally internally reflected share */

/* Why a ray spawned no children. */
#define GG_STOP_NONE     0 /* it did spawn what its material asks for */
#define GG_STOP_MISS     1 /* it left the scene: the background */
#define GG_STOP_DEPTH    2 /* the depth limit forbids children */
#define GG_STOP_MATTE    3 /* the surface has neither ks nor kt */
#define GG_STOP_BUDGET   4 /* the eye ray's tree had used its ray budget (render.h) */

/* The fate of one light at a hit. */
#define GG_SHADOW_VISIBLE     0 /* the shadow ray reached the light, all of it */
#define GG_SHADOW_BLOCKED     1 /* an opaque object (occluder) is in the way */
#define GG_SHADOW_ATTENUATED  2 /* some got through (objects or a medium took the rest) */
#define GG_SHADOW_FACING_AWAY 3 /* the surface faces away: no shadow ray sent */

typedef struct ggTraceLight {
    int light;            /* light index */
    int verdict;          /* GG_SHADOW_* */
    int occluder;         /* the blocking object, else the first transparent
                             one crossed (VISIBLE too, when it took nothing), or -1 */
    ggVec3 origin;        /* the shadow ray: origin + t dir, light at t = 1 */
    ggVec3 dir;
    double t_block;       /* where the occluder was hit (ray parameter), else 1 */
    ggColor transmittance; /* light that got through (1 1 1 when visible) */
    ggColor diffuse;      /* kd C Lc (N.L) times transmittance */
    ggColor phong;        /* ks Lc (R.V)^shine times transmittance */
} ggTraceLight;

typedef struct ggTraceNode {
    int parent;     /* parent node index, -1 for a root (eye ray) */
    int kind;       /* GG_RAY_* */
    int depth;      /* the eye ray has depth 1 */
    int channel;    /* -1: all of R G B; 0, 1, 2: one wavelength after dispersion */
    int sample;     /* which sample of the pixel this tree belongs to */
    ggVec3 o, d;    /* the ray; d is unit length */
    int medium;     /* material whose inside the ray travels through, -1 outside */
    double n_medium; /* index of refraction of that medium */
    bool hit;
    /* The hit (when hit). */
    int object, shape, material, line; /* object, ggShapeKind, material, scene-file line */
    long triangle; /* mesh objects: the triangle hit (ggSceneGetFaceInfo), else -1 */
    double t;
    ggVec3 p, ng, ns; /* point, geometric and shading normal (as the shape defines them) */
    bool front;       /* the ray arrived against ng */
    double u, v;
    double n_other;   /* index on the far side of the surface (for refraction) */
    ggColor surface;  /* material colour times texture at (u, v) */
    ggColor emission; /* ke term */
    ggColor ambient;  /* kd C ambient term */
    int first_light, nlights; /* this hit's records in ggTraceGetLight */
    double fresnel;   /* dielectric reflectance F used, or -1 when none was computed */
    ggColor reflect_weight, refract_weight; /* factors given to the children */
    /* The hit's numeric state (NaN where it does not apply). */
    double perr;       /* bound on the absolute error of each coordinate of p */
    double offset;     /* how far the origins of rays leaving the hit were pushed off p */
    double tir_margin; /* refraction: 1 - eta^2 (1 - cos^2), eta = n_medium / n_other, in
                          units of its rounding error u (1 + 5 eta^2 + 8 eta^2 cos), u =
                          2^-53; below 0 means total internal reflection, within a few
                          units of 0 the decision was a close call. With dispersion, the
                          channel nearest to 0 */
    double edge;       /* triangles and mesh triangles: the smallest barycentric coordinate
                          of the hit (0 on an edge); rectangles: the distance in (u, v) to
                          the nearest side */
    /* The ray's traversal (-1 if not recorded): BVH nodes whose child boxes
       its closest-hit query tested, and primitives it tested. */
    long nodes, prims;
    /* Always. */
    ggColor absorption; /* Beer-Lambert transmittance over this ray's segment */
    ggColor weight;     /* factor: what this ray's colour is multiplied by in its
                           parent's (the JSON's `factor`; its `weight` is the
                           product down from the pixel, as find's) */
    int stop;           /* GG_STOP_* */
    ggColor color;      /* the colour this ray returns (after absorption) */
} ggTraceNode;

typedef struct ggTrace ggTrace;

/* New empty recorder; NULL if out of memory. alloc may be NULL; it is
   copied. */
GG_API ggTrace *ggTraceCreate(const ggAllocator *alloc);
/* Frees it; NULL is a no-op. */
GG_API void ggTraceFree(ggTrace *trace);
/* Number of nodes and light records; index them with the getters below
   (NULL when out of range). Nodes are in the order rays were cast, so a
   parent always comes before its children. */
GG_API size_t ggTraceNodeCount(const ggTrace *trace);
GG_API const ggTraceNode *ggTraceGetNode(const ggTrace *trace, size_t i);
GG_API size_t ggTraceLightCount(const ggTrace *trace);
GG_API const ggTraceLight *ggTraceGetLight(const ggTrace *trace, size_t i);

/* Trace pixel (x, y) exactly as ggRender computes it with these options,
   recording the rays of sample `sample` (0-based; -1 records every
   sample) into trace, which is cleared first (a failed call, NULL
   arguments aside, leaves it empty). *pixel receives the value
   ggRender writes for that pixel, bit for bit; stats, if not NULL,
   receives the counts of the rays of the recorded samples, overwritten
   (base.h rule 2; all zero when the call fails). In pixel-corner mode the pixel's four
   corner rays are its samples 0..3. Threads: as ggRender, with a trace of
   its own per thread (a ggTrace is written by the call).
   Returns GG_OK; GG_ERROR_INVALID for a NULL scene, trace or pixel,
   options out of range, a pixel outside the image or a sample the pixel
   does not have ("sample 9 does not exist (the pixel has 4)");
   GG_ERROR_UNSUPPORTED from a library built without the recorder;
   ggScenePrepare's errors; or GG_ERROR_NOMEM. */
GG_API int ggTracePixel(ggScene *scene, const ggRenderOptions *opt, int x, int y, int sample,
                        ggTrace *trace, ggColor *pixel, ggRayStats *stats, ggError *err);

/* Short names: "eye", "reflect", "refract", "tir"; "miss", "depth",
   "matte", "budget"; "visible", "blocked", "attenuated", "facing-away". */
GG_API const char *ggRayKindName(int kind);
GG_API const char *ggStopName(int stop);
GG_API const char *ggShadowName(int verdict);

#ifdef __cplusplus
}
#endif
#endif
