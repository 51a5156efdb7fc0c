/* SPDX-License-Identifier: MIT */
/*
** ggrt/render.h -- the Whitted renderer: ggRayColor for one ray, ggRender
** for an image, the effect set a scene calls for, and ray statistics.
*/
#ifndef GGRT_RENDER_H
#define GGRT_RENDER_H

#include "ggrt/base.h"
#include "ggrt/image.h"
#include "ggrt/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- effects ----
   At ggScenePrepare the scene works out which effects it needs, each with
   the reason (which material or object, which line). The renderer runs a
   path specialised to that set; forcing effects on gives the same image,
   only slower. */
#define GG_EFFECT_SHADOWS         (1u << 0)  /* shadow rays to point lights */
#define GG_EFFECT_REFLECTION      (1u << 1)  /* mirror rays (ks > 0) */
#define GG_EFFECT_REFRACTION      (1u << 2)  /* transmitted rays (kt > 0) */
#define GG_EFFECT_FRESNEL         (1u << 3)  /* Fresnel-weighted ks/kt */
#define GG_EFFECT_ABSORPTION      (1u << 4)  /* Beer-Lambert inside media */
#define GG_EFFECT_DISPERSION      (1u << 5)  /* per-wavelength refraction */
#define GG_EFFECT_COLORED_SHADOWS (1u << 6)  /* light through transparent occluders */
#define GG_EFFECT_TEXTURES        (1u << 7)  /* image or procedural textures */
#define GG_EFFECT_IMPLICIT        (1u << 8)  /* implicit surfaces */
#define GG_EFFECT_SUPERSAMPLING   (1u << 9)  /* more than one sample per pixel */
#define GG_EFFECT_PHONG           (1u << 10) /* Phong highlights */
#define GG_EFFECT_EMISSION        (1u << 11) /* emissive materials */
#define GG_EFFECT_COUNT           12
#define GG_EFFECT_ALL             ((1u << GG_EFFECT_COUNT) - 1)

/* Short name of one effect bit ("refraction"); "?" otherwise. */
GG_API const char *ggEffectName(unsigned effect);
/* The effect set of a prepared scene (0 if not prepared or NULL). */
GG_API unsigned ggSceneEffects(const ggScene *scene);
/* Why the scene needs `effect` ("material 2 (line 14) has kt 0.9"), or
   NULL if it does not. Valid until the scene changes. */
GG_API const char *ggSceneEffectReason(const ggScene *scene, unsigned effect);

/* ---- options ---- */

/* ggRender's progress (ggProgressFn, base.h): done and total in pixels.
   Return non-zero to cancel (ggRender then returns GG_ERROR_CANCELLED).
   Called from one thread at a time, a few hundred times per render as
   tiles of 16x16 pixels finish, and besides at most ten times a second
   from within a tile of several samples per pixel, a cost map or a
   recording that takes long (every 2^15 rays a thread casts), so that a
   cancel is seen within about a tenth of a second and a pixel. done never
   decreases. */

/* Accuracy knobs, for measuring what accuracy costs (ggrt bench accuracy,
   docs/accuracy.md). All zero = the accurate defaults. */
#define GG_ACC_DEFAULT 0
/* offset */
#define GG_ACC_OFFSET_SCALED 0 /* secondary-ray origins pushed by the hit point's error bound */
#define GG_ACC_OFFSET_FIXED  1 /* pushed by one fixed epsilon (offset_eps), nothing else */
/* sphere */
#define GG_ACC_SPHERE_STABLE   0 /* Haines et al.'s stable quadratic */
#define GG_ACC_SPHERE_TEXTBOOK 1 /* b^2 - 4ac */
/* refract */
#define GG_ACC_REFRACT_ACCURATE 0 /* plain double where cos^2(theta_t) >= 1/16 (within
                                     2^-45 relative), ggRefract near the critical angle */
#define GG_ACC_REFRACT_TEXTBOOK 1 /* ggRefractTextbook (docs/optics.md) */
#define GG_ACC_REFRACT_EXACT    2 /* ggRefract for every ray */
/* fresnel: 0 = as each material says, else for every transmitter: */
#define GG_ACC_FRESNEL_NONE    1
#define GG_ACC_FRESNEL_SCHLICK 2
#define GG_ACC_FRESNEL_EXACT   3
/* texture: 0 = as each texture says, else: */
#define GG_ACC_TEXTURE_BILINEAR 1
#define GG_ACC_TEXTURE_NEAREST  2
/* wavelengths: 0 = dispersive surfaces split rays into R, G, B; 1 = no split */
/* intersect: the precision of the ray/shape tests.
   GG_ACC_ISECT_DOUBLE (default): every shape in double precision.
   GG_ACC_ISECT_FLOAT: triangles (with the triangles polygons are split
   into) and spheres are tested in single precision: Woop, Benthin and
   Wald's watertight triangle test (JCGT 2013) on the vertices, origin and
   shear rounded to float, with the three edge functions recomputed in
   double from the same float operands where one of them is exactly 0
   (exact there, so shared edges stay watertight), and the stable sphere
   quadratic (Ray Tracing Gems ch. 7) in float. The BVH boxes are float
   either way. Cones, rectangles, untriangulated polygons and implicit
   surfaces stay double. The origin of a ray leaving a float-tested hit is
   pushed off by the hit's error bound scaled to float roundings (2^29
   times the double one), or curved surfaces find themselves again.
   What it trades: 24 bits instead of 53, relative to the magnitude of the
   coordinates and of the hit distance. Where those are large against the
   features -- a scene far from the world origin, small spheres seen from
   far away -- hits, edges and hit points go wrong (a unit sphere seen
   from 3e7 away gets t to within 2, its hit point off by more than its
   radius). The boxes are conservative for the exact shapes, not for the
   float tests' roundings; tests/unit/geom/test_float.c finds the traversal's answer
   equal to testing every element on all of its rays. The answer is still
   a function of the ray alone: images do not depend on the thread count.
   It is not faster here: the queries take the plain traversal, without
   the AVX copy's 4-wide double triangle test. Measured error and time on
   the accuracy study's scenes: docs/accuracy.md. */
#define GG_ACC_ISECT_DOUBLE 0
#define GG_ACC_ISECT_FLOAT  1
/* shadows: what a transparent surface (kt > 0) between a point and a light
   does to the light.
   GG_ACC_SHADOWS_COLORED (default): the light passes, scaled by each
   surface's kt and the absorption of the media between them (coloured
   shadows, GG_EFFECT_COLORED_SHADOWS), which means walking the whole
   segment to the light.
   GG_ACC_SHADOWS_OPAQUE: any surface blocks the light, as in Whitted's
   paper and in tracers built on an any-hit query (Embree's rtcOccluded1):
   the walk stops at the first element it meets. Only scenes with
   transmitters change (the shadows under glass go black); the ray counts
   stay the same, one shadow ray per light at each hit. */
#define GG_ACC_SHADOWS_COLORED 0
#define GG_ACC_SHADOWS_OPAQUE  1
/* phong: the power (R.V)^shine of the Phong highlight.
   GG_ACC_PHONG_EXACT (default): the C library's pow (within 1 ulp).
   GG_ACC_PHONG_FAST: a shine that is a whole number from 1 to 2^20 by
   repeated squaring (at most 40 products), any other shine by pow. The
   relative error is at most (shine - 1) 2^-53 to first order (5.4e-15 at
   shine 50), or the term is below 2^-1022 where a partial power goes
   subnormal; its cost and the pixels it moves: docs/accuracy.md, "Phong's
   power". */
#define GG_ACC_PHONG_EXACT 0
#define GG_ACC_PHONG_FAST  1

typedef struct ggAccuracy {
    int offset;          /* GG_ACC_OFFSET_* */
    double offset_eps;   /* epsilon of GG_ACC_OFFSET_FIXED in scene units (0: 1e-6) */
    int sphere;          /* GG_ACC_SPHERE_* */
    int refract;         /* GG_ACC_REFRACT_* */
    int fresnel;         /* 0 or GG_ACC_FRESNEL_* */
    int texture;         /* 0 or GG_ACC_TEXTURE_* */
    int wavelengths;     /* 0 (R, G, B) or 1 (one index for all) */
    double cutoff;       /* adaptive depth: no ray whose weight in the pixel is below
                            this (POV-Ray's adc_bailout); 0 = off */
    double implicit_tol; /* root tolerance of implicit surfaces (0: their own) */
    double gradient_h;   /* 0: exact gradients; > 0: central differences with step h */
    int intersect;       /* GG_ACC_ISECT_* */
    int shadows;         /* GG_ACC_SHADOWS_* */
    int phong;           /* GG_ACC_PHONG_* */
} ggAccuracy;

/* Path layers compiled for a render (ggPathLayersCompile in debug.h). */
typedef struct ggPathLayers ggPathLayers;

typedef struct ggRenderOptions {
    int width, height;  /* 0: from the scene's camera; < 0: GG_ERROR_INVALID */
    int max_depth;      /* ray-tree depth counting the eye ray; 0: scene or 5 */
    int samples;        /* samples per pixel (n*n grid when a square); 0: scene or 1 */
    int threads;        /* worker threads (at most 256 run); 0: one per processor; < 0:
                           GG_ERROR_INVALID. Output does not depend on it */
    /* Crop window [x0, x1) x [y0, y1) in pixels; all 0 = the whole image.
       Pixels outside stay black; inside they equal the full render's. A
       window that is empty or leaves the image: GG_ERROR_INVALID. */
    int crop_x0, crop_y0, crop_x1, crop_y1;
    bool pixel_corners; /* SPD rule: rays through pixel corners, (w+1)x(h+1) eye rays */
    bool spd_rules;     /* SPD rule: transmitters also spawn reflection rays */
    unsigned force_effects; /* effects to simulate even if the scene does not call for them */
    ggAccuracy accuracy;    /* numerical choices; zero = accurate */
    /* The ray budget: at most this many reflected, refracted and totally
       internally reflected rays in the ray tree of one eye ray; the rays
       its tree would cast beyond it are not cast (ggRayStats.budget_cut
       counts them, ggTraceNode.stop says GG_STOP_BUDGET). So a pixel
       costs at most samples x (1 + budget) eye and secondary rays, plus a
       shadow ray per light at each hit, whatever the depth limit: nested
       glass at depth 64 would otherwise cast up to 2^63. The tree is grown
       depth first, mirror and refracted children in a fixed order, so the
       image stays a function of the options. 0: GG_RAY_BUDGET;
       1..GG_RAY_BUDGET_MAX. */
    int ray_budget;
    ggProgressFn progress;
    void *progress_ud;
    /* Optional per-pixel cost map (ggrt render --heatmap): width * height
       floats, row by row, that ggRender fills with cost_kind's measure for
       every rendered pixel, and only those. GG_COST_RAYS adds up to the
       render's ggRayStats eye + reflect + refract + shadow. Corner mode
       gives each corner's cost to one pixel: the one whose top left it
       is, or on the image's right and bottom edges the edge pixel; the
       depth is the deepest of its corners. A crop's map then leaves out
       the corners right of and below the crop, which pixels outside it
       own, so tiles' maps add up to the whole image's. It measures the render as it runs: the
       pixels of a tile that no ray can hit, filled with the background without tracing, get the
       rays and depth tracing would give and their share of the fill's
       time. NULL = none. */
    float *cost_map;
    int cost_kind; /* GG_COST_* */
    /* Optional path layers (ggrt render --aov): layers compiled by
       ggPathLayersCompile (debug.h) from light-path expressions, and the
       map ggRender fills with them: width * height * 3 floats per layer,
       layer after layer, each row by row like the image (layer l's pixel
       (x, y) at layer_map[3 * ((l * height + y) * width + x)]). Each
       layer's pixel is the part of the image's pixel that the paths its
       expression matches carry (the ledger's terms, ggLedgerCreate), so a
       set of disjoint expressions that covers every path adds up to the
       image within rounding (docs/debugging.md, "Path layers"). Only the
       rendered pixels are written (zero the map first for a crop). Both
       NULL = none; layers without a map is GG_ERROR_INVALID. The image
       is the one a render without layers gives, bit for bit. */
    const ggPathLayers *layers;
    float *layer_map;
} ggRenderOptions;

#define GG_RAY_BUDGET     1024      /* the default ray budget per eye ray */
#define GG_RAY_BUDGET_MAX (1 << 24)

#define GG_COST_RAYS  0 /* rays cast for the pixel, every kind */
#define GG_COST_DEPTH 1 /* depth of the deepest ray in the pixel's trees */
#define GG_COST_TIME  2 /* seconds spent on the pixel (not reproducible) */
/* CPU seconds the rendering thread spent on the pixel (not reproducible,
   but blind to the time the thread waited for a processor). Reading a
   thread's CPU clock is a system call (about 1 us on Linux in a VM, against
   30 ns for GG_COST_TIME's clock), and that cost lands in every pixel:
   for cheap pixels prefer the least GG_COST_TIME of a few renders, as
   ggrt plan does. Where the system has no per-thread CPU clock, as
   GG_COST_TIME. */
#define GG_COST_CPU 3

/* Fill *opt with the defaults (all fields zero/false but the above); NULL
   is a no-op. */
GG_API void ggRenderOptionsDefault(ggRenderOptions *opt);

/* *opt with every setting that 0 leaves to the scene or the library
   filled in as ggRender would take it: width and height from the scene's
   camera, max_depth from the scene file or 5, samples from the scene
   file or 1, ray_budget GG_RAY_BUDGET; everything else copied as it is
   (negative values too: ggRender refuses them). Two options that resolve
   to the same settings render the same image of that scene, which is how
   a program tells "-d 5" from the default apart or not (ggrt merge, ggrt
   plan). opt and out may be the same struct. Returns GG_OK, or
   GG_ERROR_INVALID for a NULL argument (out untouched). */
GG_API int ggRenderOptionsResolve(const ggScene *scene, const ggRenderOptions *opt,
                                  ggRenderOptions *out);

/* ---- statistics ---- */
typedef struct ggRayStats {
    uint64_t eye;        /* eye rays cast */
    uint64_t eye_hit;    /* eye rays that hit something */
    uint64_t reflect;    /* mirror rays, including those from TIR */
    uint64_t refract;    /* transmitted rays */
    uint64_t shadow;     /* shadow rays */
    uint64_t tir;        /* total internal reflections (also counted in reflect) */
    uint64_t nonfinite;  /* samples that produced NaN or infinity */
    uint64_t max_depth;  /* depth of the deepest ray cast */
    uint64_t budget_cut; /* secondary rays not cast: the ray budget was used up */
    /* Tests of a ray against an implicit surface that ran out of the
       surface's evaluation budget (ggImplicitSetBudget) and so counted as a
       miss. Tests, not rays: a shadow ray's test may be skipped when a
       thread's shadow cache finds the blocker first, so this count (unlike
       the image) may differ with the number of threads. */
    uint64_t implicit_cut;
    /* Shadow rays by verdict (GG_SHADOW_* of trace.h, which ggTracePixel
       records per light): those that nothing of the light got through
       (an opaque object, or transparent ones that took every channel),
       and those that arrived dimmed by transparent objects or a medium.
       The rest of `shadow` reached the light whole. Under the default
       coloured shadows a ray that crosses a transmitter is walked to the
       light (attenuated); under shadows=opaque the transmitter blocks it. */
    uint64_t shadow_blocked;
    uint64_t shadow_attenuated;
} ggRayStats;

/* Add b's counts to *a, as one render of both parts would count them
   (max_depth: the larger): for renders of tiles or bands of one image.
   Either NULL is a no-op. */
GG_API void ggRayStatsAdd(ggRayStats *a, const ggRayStats *b);

/* ---- rendering ---- */

/* Render the scene into *out (a new image of the options' size). Prepares
   the scene if needed. stats may be NULL; else it receives this render's
   counts, overwritten (base.h rule 2), also when the render fails.
   Threads: a render reads the scene and writes only its own image, stats
   and cost map; several renders (and traces) of one prepared scene may
   run at once with different options, and each gives the image it gives
   alone. On an unprepared scene see ggScenePrepare and the threading note
   of scene.h. opt->threads workers are started and joined inside the
   call; the progress callback runs on them, one at a time.
   Returns GG_OK; GG_ERROR_INVALID for a NULL scene or out, or options
   out of range (ggRenderOptionsResolve's rules); GG_ERROR_LIMIT for an
   image over the limits of image.h; GG_ERROR_UNSUPPORTED for a layer
   sum with more than one sample per pixel; GG_ERROR_CANCELLED when the
   progress callback asked to stop; ggScenePrepare's errors; or
   GG_ERROR_NOMEM. On failure *out is NULL (a NULL scene aside: base.h
   rule 1). */
GG_API int ggRender(ggScene *scene, const ggRenderOptions *opt, ggImage **out,
                    ggRayStats *stats, ggError *err);

/* The eye ray through image point (x, y), in pixels from the top left:
   (x + 0.5, y + 0.5) is the centre of pixel (x, y), the point ggRender
   samples with one sample per pixel. d is unit length, however far off
   the image the point is. A NULL scene, and a NaN or infinite x or y (or
   one so large that the direction overflows), give the all-zero ray
   (base.h rule 1). */
GG_API ggRay ggCameraRay(const ggScene *scene, const ggRenderOptions *opt, double x, double y);

/* Colour seen along one ray of a prepared scene (never prepares it; any
   number of threads at once): emission + kd * ambient +
   direct light (shadow rays) + ks * reflection + kt * refraction, recursing
   until depth reaches opt->max_depth (the eye ray has depth 1; `depth` is
   this ray's, and one below 1 is taken as 1). Black for a NULL or
   unprepared scene or bad options. stats may be NULL; else it
   receives the counts of this ray's tree, overwritten (base.h rule 2). */
GG_API ggColor ggRayColor(const ggScene *scene, const ggRenderOptions *opt, ggRay ray,
                          int depth, ggRayStats *stats);

/* ---- kernel counts and kernel loops (`ggrt bench limit`) ---- */

/* What a render's ray queries did, as the traversal copy the scene's
   queries take on this CPU (its AVX, AVX2 or AVX-512 build) walks:
   queries by kind, kernel calls by kernel, and closest hits found (each
   one a hit the renderer shades, but for the hits a coloured shadow ray's
   walk meets). */
typedef struct ggKernelCounts {
    uint64_t closest; /* closest-hit queries of single rays */
    uint64_t any;     /* any-hit (occluder) queries */
    uint64_t shadow;  /* shadow queries that list transparent crossings */
    uint64_t packets; /* packet walks (up to 16 eye rays each) */
    uint64_t node;    /* GG_KERNEL_NODE calls */
    uint64_t packet_node, packet_leaf, tri4, tri, sphere, other; /* the same */
    uint64_t hits;    /* closest-hit queries (or packet lanes) that hit */
} ggKernelCounts;

/* The kernels (ggKernelLoop): */
#define GG_KERNEL_NODE        0 /* one node's 8 boxes against a ray */
#define GG_KERNEL_PACKET_NODE 1 /* one node's 4 boxes against a packet of 16 */
#define GG_KERNEL_PACKET_LEAF 2 /* a leaf's box against the 16 rays of a packet */
#define GG_KERNEL_TRI4        3 /* 4 triangles of a leaf against a ray */
#define GG_KERNEL_TRI         4 /* one triangle (the scalar kernel) */
#define GG_KERNEL_SPHERE      5 /* one sphere */
#define GG_KERNEL_OTHER       6 /* one element of another kind (cone, polygon, ...) */
#define GG_KERNEL_SHADE       7 /* the shading of one hit, without its rays */
#define GG_KERNEL_KINDS       8

/* Render as ggRender does (the same image, the same rays), on one thread
   whatever opt->threads says, with a counting copy of the traversal, and
   put its counts in *counts (overwritten). The image is not kept. Not
   while other threads use the scene. GG_ERROR_UNSUPPORTED where the
   scene's queries take the plain traversal (no AVX: it has no counting
   copy) or for single-precision queries (their own copy). */
GG_API int ggRenderCountKernels(ggScene *scene, const ggRenderOptions *opt,
                                ggKernelCounts *counts, ggError *err);

/* Run kernel k (GG_KERNEL_*) n times on data of the prepared scene: the
   first element of its kind (triangle block, triangle, sphere, other),
   the root node, or for GG_KERNEL_SHADE the first hit of a few eye rays
   through the image's centre; the ray comes from the camera and is aimed
   at the element, so that the element's test finds a hit. Each call's
   input depends on the last one's result, as a walk's next node depends
   on this one's test: time it, and the time over n is a call's latency on
   cached data. Returns a sum of the results (>= 0), or -1 if the scene
   has no such data or is not prepared, k or n is out of range, or (for
   every kernel but GG_KERNEL_SHADE, which does not walk) the scene takes
   the plain traversal. */
GG_API double ggKernelLoop(const ggScene *scene, const ggRenderOptions *opt, int k, long n);

#ifdef __cplusplus
}
#endif
#endif
