/* SPDX-License-Identifier: MIT */
/*
** ggrt/debug.h -- the ray debugger at image level: find the pixels whose
** rays did something (a predicate over each pixel's ray tree), check a
** whole image for invariants, explain a pixel's colour term by term (the
** ledger), and diff two renders ray by ray.
**
** Everything here is built on the recorder of trace.h: every pixel a
** function below looks at is traced exactly as ggRender computes it, so
** the values it reports are the rendered ones, bit for bit.
**
** Work: ggFind, ggCheck and ggDiff trace each pixel of the options' crop
** window (the whole image by default) once (ggDiff: once per side), on
** opt->threads worker threads; nothing else grows with the scene or the
** predicate. The options' progress callback is called as for ggRender and
** can cancel (GG_ERROR_CANCELLED), which is how a server bounds the time
** of a request; the crop window bounds its pixels.
**
** Threads: these functions read the scene only, once it is prepared
** (they prepare it first if needed, which writes into it: call
** ggScenePrepare before sharing a scene between threads). Several threads
** may call them at once on one prepared scene, each with options and
** results of its own, accuracy knobs included (scene.h, "Threads").
**
** Results are plain data -- numbers, names from fixed tables, arrays
** sized in the result -- made to be printed or turned into JSON as they
** are. Each is allocated with the scene's allocator and freed with its
** own Free function (NULL is a no-op).
*/
#ifndef GGRT_DEBUG_H
#define GGRT_DEBUG_H

#include "ggrt/base.h"
#include "ggrt/image.h"
#include "ggrt/render.h"
#include "ggrt/scene.h"
#include "ggrt/trace.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ */
/* Render options as text                                              */
/* ------------------------------------------------------------------ */

/* Apply the settings in `text` to *opt, which keeps everything the text
   does not name. Settings are separated by spaces or commas:
     size=WxH (0 for a side: the camera's) depth=N samples=N threads=N
     ray-budget=N (1 to GG_RAY_BUDGET_MAX) crop=X0,Y0,X1,Y1
     spd (the SPD's rules: pixel corners, depth 5 unless set, transmitters
     also reflect)  spd-rules (only the last)  corners  force-effects (all
     of them)  force-effects=NAME+NAME... (those: ggEffectName's names)
   and the accuracy knobs of render.h:
     offset=scaled|fixed|EPS (a number > 0: fixed with that epsilon)
     sphere=stable|textbook  refract=accurate|textbook|exact
     fresnel=scene|none|schlick|exact  texture=scene|bilinear|nearest
     wavelengths=rgb|one  cutoff=W (0 to 1)  implicit-tol=own|T
     gradient=exact|H (T, H > 0)  intersect=double|float
     shadows=colored|opaque  phong=exact|fast
   Numbers are read with '.' as the radix point whatever the locale. An
   empty text changes nothing. On a bad setting *opt is unchanged and err
   says where, "line:column: message" counting from 1 (as
   ggImplicitCreateExpr does), e.g. "1:8: sphere must be stable or
   textbook, got 'text'". Returns GG_OK, GG_ERROR_PARSE, or
   GG_ERROR_INVALID for a NULL opt or text. */
GG_API int ggRenderOptionsParse(ggRenderOptions *opt, const char *text, ggError *err);

/* The settings of *opt that differ from the defaults, in the syntax of
   ggRenderOptionsParse, in a canonical order ("" for the defaults), into
   buf (always NUL-terminated when size > 0). Returns the length the full
   text needs (like snprintf); the progress callback and the cost map are
   not settings and are left out, as are force_effects bits outside
   GG_EFFECT_ALL (which no render reads). ggRenderOptionsParse reads the
   text back to the same settings when each is in the range Parse
   accepts. A NULL opt gives "" and 0; a NULL buf (any size) only
   measures. */
GG_API size_t ggRenderOptionsFormat(const ggRenderOptions *opt, char *buf, size_t size);

/* ------------------------------------------------------------------ */
/* Predicates over a pixel's ray tree                                  */
/* ------------------------------------------------------------------ */

/* A compiled predicate. The language (docs/debugging.md has examples):

     some(RAY-EXPR)    some ray of the pixel's trees satisfies RAY-EXPR
     all(RAY-EXPR)     every ray does
     count(RAY-EXPR)   how many rays do (a number)
     A && B, A || B, !A, ( ), and comparisons == != < <= > >=

   The rays are the eye, reflect, refract and tir rays of the trees and
   their shadow rays (kind shadow). Fields of a ray, usable inside some,
   all and count only:
     kind      eye reflect refract tir shadow
     depth     the eye ray has 1; a shadow ray has the depth of the ray
               whose hit cast it
     object material line shape front back
               the surface hit (for a shadow ray: the surface it leaves);
               shape is sphere triangle polygon cone rect implicit mesh
     hit miss  the ray met a surface / left the scene (not shadow rays)
     t         ray parameter of the hit (shadow ray: of the occluder)
     stop      none miss depth matte budget: why it spawned no children
     fresnel   the dielectric reflectance used at the hit
     weight    the ray's weight in the pixel (colour): the pixel changes
               by weight * d when the colour the ray returns changes by d
     color     the colour the ray returns; absorption: over its segment
     nonfinite the colour it returns is NaN or infinite
     light verdict occluder transmittance diffuse phong
               shadow rays: which light, visible blocked attenuated
               facing_away, the blocking object (else the first
               transparent one crossed), and what the light gave
     perr offset tir_margin edge
               the hit's numeric state (trace.h's ggTraceNode; a shadow
               ray: of the hit it leaves)
     medium    the material the ray travels in, -1 outside
     triangle  mesh objects: the triangle hit (ggSceneGetFaceInfo)
   Fields of the pixel, usable anywhere: x, y, pixel (its value), rays
   (rays in its trees, shadow rays included). Colour fields take a
   component .r .g .b .min .max; alone they mean .max. Names after == or
   != on the other side of a field with named values are those values
   (stop == depth is the depth-limit stop). A field that a ray does not
   have (fresnel where none was computed, verdict of an eye ray) makes
   comparisons with it unknown: unknown is neither true nor false, !
   keeps it unknown, false && unknown is false, true || unknown is true,
   and a pixel matches only if the whole predicate is true.

   Examples: some(kind == tir); some(kind == refract && object == 2);
   some(verdict == blocked && occluder == 1);
   some(stop == depth && weight > 0.01); count(kind == shadow) > 8. */
typedef struct ggPredicate ggPredicate;

/* Limits of ggPredicateParse; beyond them it returns GG_ERROR_LIMIT. */
#define GG_PREDICATE_MAX_TEXT  4096 /* bytes of text */
#define GG_PREDICATE_MAX_DEPTH 64   /* nesting of ( ), !, some, all, count */

/* Compile `text`. On success *out receives the predicate (free it with
   ggPredicateFree); on failure *out is NULL and err names the place as
   "line:column: message", counting from 1, e.g.
   "1:14: 'tri' is not a kind (eye, reflect, refract, tir, shadow)".
   Returns GG_OK, GG_ERROR_PARSE, GG_ERROR_LIMIT, GG_ERROR_INVALID (NULL
   text or out) or GG_ERROR_NOMEM. alloc may be NULL (malloc); it is
   copied. A compiled predicate is only read afterwards: threads may share
   it. */
GG_API int ggPredicateParse(const char *text, const ggAllocator *alloc, ggPredicate **out,
                            ggError *err);
GG_API void ggPredicateFree(ggPredicate *pred);

/* Whether the pixel (x, y) of value `pixel`, whose every sample is
   recorded in trace (ggTracePixel with sample -1), satisfies pred: 1 or
   0; 0 for a NULL pred or trace. */
GG_API int ggPredicateMatch(const ggPredicate *pred, const ggTrace *trace, int x, int y,
                            ggColor pixel);

/* ------------------------------------------------------------------ */
/* Find                                                                */
/* ------------------------------------------------------------------ */

typedef struct ggFindMatch {
    int x, y;
    ggColor pixel; /* its value, as ggRender writes it */
    double share;  /* ggFindPath: the matching paths' share of pixel; ggFind: 0 */
} ggFindMatch;

typedef struct ggFindResult {
    int width, height;     /* the image */
    int x0, y0, x1, y1;    /* the window scanned, [x0, x1) x [y0, y1) */
    long scanned, matched; /* pixels scanned, pixels that matched */
    int nmatches;          /* matches listed: the first min(matched, limit) in row order */
    ggFindMatch *matches;
    unsigned char *mask; /* width * height bytes, row by row: 1 where matched */
    ggImage *image;      /* the pixels' values (the render of the window; black outside) */
    int traced;          /* 1 if ray trees were recorded, 0 if the predicate needed
                            only pixel values and a plain render served (not
                            through pixel corners: there each pixel is traced) */
    ggRayStats stats;    /* rays cast, each pixel's own: a window's add up to
                            the whole image's */
} ggFindResult;

/* Every pixel of opt's window that satisfies pred, as in ggPredicateMatch.
   limit: how many matches to list (0: none; the count and the mask cover
   all). Only what the predicate reads is recorded. *out receives the
   result (NULL on failure). Returns GG_OK, GG_ERROR_INVALID (NULL scene,
   pred or out; bad options; a negative limit), GG_ERROR_NOMEM,
   GG_ERROR_CANCELLED, or what ggRender would. */
GG_API int ggFind(ggScene *scene, const ggRenderOptions *opt, const ggPredicate *pred, int limit,
                  ggFindResult **out, ggError *err);
GG_API void ggFindResultFree(ggFindResult *res);


/* ------------------------------------------------------------------ */
/* Check                                                               */
/* ------------------------------------------------------------------ */

/* The invariants, by index into ggCheckResult.items. */
#define GG_CHECK_NONFINITE 0 /* a NaN or infinite pixel value */
#define GG_CHECK_NEGATIVE  1 /* a negative pixel value */
#define GG_CHECK_ENERGY                                                                            \
    2 /* a hit surface returns more than it receives:                                              \
         kd * max(colour) + ks + kt > 1 (a conductor counts 1 for ks) */
#define GG_CHECK_TRUNCATION                                                                        \
    3 /* rays cut by the depth limit or the ray budget while their                                 \
         children would have weighed more than the threshold */
#define GG_CHECK_SELF_HIT                                                                          \
    4 /* a secondary or shadow ray meets the surface it leaves                                     \
         within a few lengths of its origin's error bound */
#define GG_CHECK_NEAR_TIR                                                                          \
    5                      /* a refraction decided within a few rounding errors of                 \
                              total internal reflection */
#define GG_CHECK_GRAZING 6 /* a hit at grazing incidence (|cos| below the threshold) */
#define GG_CHECK_COUNT   7

#define GG_SEVERITY_INFO    0
#define GG_SEVERITY_WARNING 1
#define GG_SEVERITY_ERROR   2

/* Short name of an invariant ("nonfinite", "negative", "energy",
   "truncation", "self-hit", "near-tir", "grazing"), "?" otherwise; of a
   severity ("info", "warning", "error"). */
GG_API const char *ggCheckName(int check);
GG_API const char *ggSeverityName(int severity);

typedef struct ggCheckOptions {
    int severity[GG_CHECK_COUNT]; /* GG_SEVERITY_* of each invariant */
    double truncation;            /* weight threshold of GG_CHECK_TRUNCATION */
    double self_hit;              /* GG_CHECK_SELF_HIT: hits within this many error bounds */
    double near_tir; /* GG_CHECK_NEAR_TIR: |discriminant| within this many rounding errors */
    double grazing;  /* GG_CHECK_GRAZING: |cos(incidence)| below this */
    /* NULL: check every pixel. Else only the pixels with at least one path
       this expression matches (ggPathMatch; the light-path expressions
       below) are checked: the others count in `scanned` only, and each
       listed pixel carries the share of its value those paths carry. The
       invariants still look at the whole of a checked pixel's trees (a
       truncation or a NaN on another path of that pixel counts): the
       question is "are the pixels lit this way sound", not a split of the
       checks by path. */
    const struct ggPathExpr *path;
} ggCheckOptions;

/* The defaults: nonfinite, negative, energy and truncation are errors,
   self-hit a warning, near-tir and grazing information; truncation 0.1,
   self_hit 4, near_tir 16, grazing 1e-3; no path expression. */
GG_API void ggCheckOptionsDefault(ggCheckOptions *co);

#define GG_CHECK_WORST 8 /* pixels kept per invariant */

typedef struct ggCheckPixel {
    int x, y;
    double value; /* how badly: the invariant's measure (see ggCheckItem.value) */
    int node;     /* the first ray where it fails in that pixel's trees, -1 for the pixel */
    int light;    /* a shadow ray: index into the trace's light records, else -1 */
    int object;   /* the surface involved, or -1 */
    int material; /* its material, or -1 */
    int line;     /* the scene-file line of that material (energy) or object, 0 if none */
    double share; /* with a path expression: the share of the pixel its matching paths
                     carry (ggPathSummary.share); else 0 */
} ggCheckPixel;

typedef struct ggCheckItem {
    int check;    /* GG_CHECK_* */
    int severity; /* GG_SEVERITY_* in force */
    long pixels;  /* pixels where it fails */
    long rays;    /* rays (or hits) where it fails */
    double worst; /* the largest measure seen (0 if none) */
    int nworst;   /* pixels listed in `pixels_worst`, worst first */
    ggCheckPixel pixels_worst[GG_CHECK_WORST];
} ggCheckItem;

/* What each measure (ggCheckPixel.value, ggCheckItem.worst) is, larger
   always worse: nonfinite 1; negative -(the most negative channel);
   energy kd * max(colour) + ks + kt of the surface; truncation the weight
   the cut children would have had in the pixel; self-hit the origin's
   error bound (perr + offset of the hit it leaves) over the distance to
   the hit; near-tir 1 / |tir_margin|; grazing 1 / |cos|. */

typedef struct ggCheckResult {
    int width, height;
    int x0, y0, x1, y1; /* the window scanned */
    long scanned;
    long checked;   /* pixels checked: scanned, or with a path expression those that
                       have a matching path */
    double share;   /* with a path expression: the mean over the checked pixels of
                       the share their matching paths carry (summed row by row,
                       the same bits for any number of threads); else 0 */
    int failed; /* invariants of severity error with pixels > 0 */
    ggCheckItem items[GG_CHECK_COUNT];
    /* Truncation: an upper bound on any ray's colour in this scene (the
       largest channel; INFINITY when ks + kt >= 1 somewhere makes the
       recursion's sum unbounded), so the light a pixel misses is at
       most its truncation measure times this. */
    double radiance_bound;
    ggRayStats stats;
} ggCheckResult;

/* Scan every pixel of opt's window for the invariants. co NULL: the
   defaults. Returns GG_OK whether invariants fail or not (see
   res->failed), or GG_ERROR_INVALID, GG_ERROR_NOMEM, GG_ERROR_CANCELLED,
   or what ggRender would. */
GG_API int ggCheck(ggScene *scene, const ggRenderOptions *opt, const ggCheckOptions *co,
                   ggCheckResult **out, ggError *err);
GG_API void ggCheckResultFree(ggCheckResult *res);

/* ------------------------------------------------------------------ */
/* Ledger: a pixel's colour term by term                               */
/* ------------------------------------------------------------------ */

#define GG_TERM_EMISSION   0 /* ke at a hit */
#define GG_TERM_AMBIENT    1 /* kd C ambient at a hit */
#define GG_TERM_DIFFUSE    2 /* one light's kd C (N.L) at a hit */
#define GG_TERM_PHONG      3 /* one light's highlight at a hit */
#define GG_TERM_BACKGROUND 4 /* a ray that left the scene */

/* "emission", "ambient", "diffuse", "phong", "background"; "?" otherwise. */
GG_API const char *ggTermName(int kind);

typedef struct ggLedgerTerm {
    int kind;      /* GG_TERM_* */
    int node;      /* the ray at whose hit (or miss) the light enters */
    int light;     /* diffuse, phong: the light's index; else -1 */
    ggColor value; /* what it adds to the pixel */
    double share;  /* (r + g + b) of value over (r + g + b) of the pixel; 0 if that is 0 */
} ggLedgerTerm;

typedef struct ggLedger {
    size_t count;
    ggLedgerTerm *terms; /* sorted by share, largest first (then by node) */
    ggColor sum;         /* the terms added up (in double) */
    ggColor pixel;       /* the pixel value given */
    ggColor bound;       /* per channel: |sum - pixel| is at most this (rounding) */
    int holds;           /* 1 when |sum - pixel| <= bound on every channel */
} ggLedger;

/* The ledger of a pixel whose every sample is recorded in trace
   (ggTracePixel with sample -1, value `pixel`). Each term's value is the
   product of the factors (ggTraceNode.weight) and absorptions on the path
   of rays that carried it, times the term at its hit, divided by the
   number of samples; terms that are exactly zero are left out. They add up to the pixel within
   `bound`, the rounding of the renderer's own sums and of the float pixel:
     bound = 2^-24 (|pixel| + sum |t|) + gamma(2 n + m + 4 d + s + 2) sum |t|
   per channel, gamma(k) = k 2^-53 / (1 - k 2^-53), for n terms, m rays,
   depth d and s samples (lib/debug/ledger.c derives it). holds is 0 for
   a pixel that is not finite. alloc may be NULL; it is copied. Returns
   GG_OK, GG_ERROR_INVALID (NULL trace or out, an empty trace) or
   GG_ERROR_NOMEM. */
GG_API int ggLedgerCreate(const ggTrace *trace, ggColor pixel, const ggAllocator *alloc,
                          ggLedger **out, ggError *err);
GG_API void ggLedgerFree(ggLedger *ledger);

/* ------------------------------------------------------------------ */
/* Light-path expressions                                              */
/* ------------------------------------------------------------------ */

/* A compiled light-path expression (OSL's LPE syntax for the events of a
   Whitted ray tracer; docs/debugging.md has the grammar and examples).

   Paths. A pixel's paths are its ledger's terms (ggLedgerCreate): each
   way light that is not exactly zero reaches the eye, read from the eye
   to the light as a string of events:
     C        the eye ray (the root of a tree)
     <RS>     a mirror reflection at a hit; a total internal reflection is
              <RS> with the label 'tir'
     <TS>     a refraction at a hit
     <RD>L    the diffuse term of a light at a hit (L: the shadow ray)
     <RG>L    the Phong highlight of a light at a hit
     <RD>A    the ambient term at a hit (A: a ggrt event, not OSL's)
     O        the emission (ke) of a surface hit
     B        a ray that left the scene: the background
   so "C<TS><TS>B" is the background seen through a glass ball. Shadow
   rays that were blocked, and terms that are exactly zero, are no paths.

   Labels. A surface event (<RS>, <TS>, <RD>, <RG>, O) has the labels
   'N' (the object hit, a number as in ggrt trace), 'mK' (its material)
   and 'tir' for a total internal reflection; an L event has 'N', the
   light's number. C, A and B have none. Numbers are written as ggrt
   prints them ('01' is refused); one the scene does not have matches
   nothing (an expression is compiled without a scene).

   Syntax, loosest first:  E|E  alternatives;  E E  one after the other;
   E*  E+  E?  E{n}  E{n,}  E{n,m}  repetition;  ( E )  a group; and the
   events:  C R T L O B A  (an event of that type), D G S (of that scatter),
   .  (any event),  'label'  (any event with that label),
   <TYPE SCATTER 'label'...>  with TYPE one of C R T L O B A or '.',
   SCATTER one of D G S or '.', both optional (<R> is <R.>, <S> is
   <.S>), every label required;  [e e ...]  any of these events;  [^e e ...]  any event but
   these. An event or a set may be followed by a predicate in brackets,
   [RAY-EXPR] (a '[' followed, after any spaces, by a lower-case letter, a
   digit, '(' or '!'): the ray expression of ggPredicateParse, on the ray
   that arrives at the event (for L: the shadow ray; for C: the eye ray;
   for A: the ray whose hit it lights), e.g.
   <TS>[object == 2 && tir_margin < 16]; only a true value matches.
   Spaces between items are ignored. A path matches when the whole string
   of its events does (the expression is anchored at both ends).

   Limits: GG_PATH_MAX_TEXT bytes, GG_PATH_MAX_DEPTH nesting of ( ), [ ]
   and < >, GG_PATH_MAX_STATES states of the automaton the expression
   compiles to (a {n} makes n copies) and GG_PATH_MAX_EVENTS distinct
   event patterns: beyond them ggPathParse returns GG_ERROR_LIMIT. A match
   then takes time linear in the pixel's rays. */
typedef struct ggPathExpr ggPathExpr;

#define GG_PATH_MAX_TEXT   4096
#define GG_PATH_MAX_DEPTH  64
#define GG_PATH_MAX_STATES 256
#define GG_PATH_MAX_EVENTS 256

/* Compile `text`. On success *out receives the expression (free it with
   ggPathFree); on failure *out is NULL and err names the place as
   "line:column: message", counting from 1 as ggPredicateParse does, e.g.
   "1:3: 'X' is not an event type (C R T L O B A or .)". Returns GG_OK,
   GG_ERROR_PARSE, GG_ERROR_LIMIT, GG_ERROR_INVALID (NULL text or out) or
   GG_ERROR_NOMEM. alloc may be NULL (malloc); it is copied. A compiled
   expression is only read afterwards: threads may share it. */
GG_API int ggPathParse(const char *text, const ggAllocator *alloc, ggPathExpr **out,
                       ggError *err);
GG_API void ggPathFree(ggPathExpr *expr);

typedef struct ggPathSummary {
    long paths;      /* the pixel's paths (its ledger's terms) */
    long matched;    /* those the expression matches */
    ggColor value;   /* what the matching paths add to the pixel (their terms' sum) */
    double share;    /* (r + g + b) of value over (r + g + b) of the pixel; 0 if that is 0
                        or not finite */
} ggPathSummary;

/* Match expr against every path of the pixel (x, y) of value `pixel`,
   whose every sample is recorded in trace (ggTracePixel with sample -1).
   *sum receives the counts and the share. matched (may be NULL), when
   ledger is given (ggLedgerCreate of the same trace and pixel), receives
   ledger->count bytes: 1 where the term's path matches. Memory: one bit
   set of GG_PATH_MAX_STATES bits per ray and the weights, from expr's
   allocator, freed before it returns. Returns GG_OK, GG_ERROR_INVALID
   (NULL expr, trace or sum; matched without ledger) or GG_ERROR_NOMEM
   (then *sum is zero). */
GG_API int ggPathMatch(const ggPathExpr *expr, const ggTrace *trace, int x, int y, ggColor pixel,
                       const ggLedger *ledger, unsigned char *matched, ggPathSummary *sum);

/* The events of one ledger term's path as text, e.g. "C<TS'2'><TS'2'>B":
   each surface event with its object label (and 'tir'), each L with its
   light's, into buf (always NUL-terminated when size > 0, a NULL trace or
   term included: "", as ggRenderOptionsFormat's NULL opt). Returns the
   length the full text needs (like snprintf); 0 for a NULL trace or
   term, or a term whose node is not in the trace. */
GG_API size_t ggPathFormat(const ggTrace *trace, const ggLedgerTerm *term, char *buf,
                           size_t size);

/* One point of a path's polyline (ggPathPoints). */
typedef struct ggPathPoint {
    ggVec3 p;
    ggColor weight; /* the weight in the pixel of the ray that arrives at p (the
                       first point: of the eye ray that leaves it), as find's weight
                       field: the pixel changes by weight * d when that ray's colour
                       changes by d */
} ggPathPoint;

/* The points of one ledger term's path, from the eye to the light, into
   pts (at most max; pts may be NULL when max is 0): the eye ray's origin,
   the hit point of every ray on the path, and then for a diffuse or Phong
   term the light's position (the shadow ray's end), for a background term
   a point on the ray that left the scene, as far from its origin as the
   path so far is long (at least 1), so that the direction shows at the
   scene's scale. Emission and ambient terms end at their hit. Returns the
   number of points the path has (like snprintf: more than max means pts
   holds the first max); 0 for a NULL trace or term, or a term whose node
   is not in the trace. */
GG_API size_t ggPathPoints(const ggTrace *trace, const ggLedgerTerm *term, ggPathPoint *pts,
                           size_t max);

/* ggFind with a path expression: the pixels of opt's window with at least
   one path that expr matches (ggPathMatch); each match's `share` is the
   share of the pixel's value those paths carry (ggPathSummary.share).
   Everything else as ggFind. An expression without predicates, at one
   sample per pixel at its centre (not corners), is answered by a render
   whose shading carries the expression's automaton, as path layers
   (ggPathLayersCompile), with the same matches and shares bit for bit
   and res->traced 0; otherwise every pixel's trees are recorded and
   matched (ggPathMatch), res->traced 1. */
GG_API int ggFindPath(ggScene *scene, const ggRenderOptions *opt, const ggPathExpr *expr,
                      int limit, ggFindResult **out, ggError *err);

/* Path layers for ggRender (render.h, ggRenderOptions.layers): each of
   the n expressions (1..GG_PATH_LAYERS_MAX) compiled once into a
   deterministic automaton that the shading steps as it traces (one table
   lookup per event and layer), so a render with layers costs no recorder
   and no trees. A layer's pixel is what the terms whose paths its
   expression matches (ggPathMatch's rule) add to the pixel. Expressions
   take the whole grammar but predicates: a '[...]' predicate is refused
   with GG_ERROR_UNSUPPORTED, "layer K: LINE:COL: ..." naming its place.
   A layer may name at most GG_PATH_LAYER_LABELS distinct numbers and as
   many materials (GG_ERROR_LIMIT, naming the place of the first label
   too many), and its automaton may have at most 4096 states
   (GG_ERROR_LIMIT, with no place). Errors of the expression itself are
   ggPathParse's, prefixed "layer K: " (K from 1). On success *out receives the layers
   (free with ggPathLayersFree); on failure NULL. GG_ERROR_INVALID: NULL
   exprs, an element of it, or out; n out of range. alloc may be NULL
   (malloc); it is copied. Compiled layers are only read afterwards:
   renders on any number of threads may share them. */
#define GG_PATH_LAYERS_MAX   16
#define GG_PATH_LAYER_LABELS 8
GG_API int ggPathLayersCompile(const char *const *exprs, int n, const ggAllocator *alloc,
                               ggPathLayers **out, ggError *err);
/* The number of layers (0 for NULL). */
GG_API int ggPathLayersCount(const ggPathLayers *layers);
/* NULL is a no-op. */
GG_API void ggPathLayersFree(ggPathLayers *layers);

/* ------------------------------------------------------------------ */
/* Diff: two renders ray by ray                                        */
/* ------------------------------------------------------------------ */

/* What differs at the first divergent ray. */
#define GG_DIFF_SAME     0
#define GG_DIFF_HIT      1 /* one ray hit a surface, the other left the scene */
#define GG_DIFF_OBJECT   2 /* they hit different objects */
#define GG_DIFF_FACE     3 /* the same object, from the other side */
#define GG_DIFF_TIR      4 /* one refracted, the other was totally internally reflected */
#define GG_DIFF_SHADOW   5 /* a light's shadow verdict differs */
#define GG_DIFF_OCCLUDER 6 /* the same verdict, another occluder */
#define GG_DIFF_CHILD    7 /* a child ray exists in one tree only */
#define GG_DIFF_STOP     8 /* they stopped for different reasons */
#define GG_DIFF_SAMPLES  9 /* the trees are of different sample counts */
#define GG_DIFF_COUNT    10

/* "same", "hit", "object", "face", "tir", "shadow", "occluder", "child",
   "stop", "samples"; "?" otherwise. */
GG_API const char *ggDiffName(int what);

typedef struct ggDivergence {
    int what;           /* GG_DIFF_* */
    int node_a, node_b; /* the divergent ray in each tree; -1 where it does not exist */
    int light;          /* SHADOW, OCCLUDER: the light; else -1 */
    int a, b;           /* what each side has: objects (OBJECT, OCCLUDER, HIT: -1 = none),
                           GG_SHADOW_* (SHADOW), GG_STOP_* (STOP), 1 = front (FACE),
                           GG_RAY_* of the child (CHILD, TIR: the ray that differs) */
} ggDivergence;

/* Compare two recorded trees: the same rays in the same order (kind,
   channel), each hitting the same object from the same side or missing,
   the same stop reasons, and the same verdict and occluder for every
   light. Positions, colours and weights are not compared. Returns 1 and
   fills *first (may be NULL) with the first divergence in the order the
   rays of `a` were cast, or 0 when the trees agree (first->what =
   GG_DIFF_SAME). NULL traces compare as empty. */
GG_API int ggTraceCompare(const ggTrace *a, const ggTrace *b, ggDivergence *first);

typedef struct ggDiffPixel {
    int x, y;
    ggColor a, b;       /* the pixel's value in each render */
    double delta;       /* largest |a - b| over the channels (INFINITY if either is not finite) */
    ggDivergence first; /* the first divergent ray (what = SAME if the trees agree) */
} ggDiffPixel;

/* ggDiffPath: a pixel whose light moved between path classes: the paths
   the expression matches differ between the two sides. */
typedef struct ggDiffMove {
    int x, y;
    double share_a, share_b; /* ggPathSummary.share on each side */
    long matched_a, matched_b; /* matching paths on each side */
    ggDivergence first;      /* the first divergent ray (what = SAME if the trees agree) */
} ggDiffMove;

typedef struct ggDiffResult {
    int width, height;
    int x0, y0, x1, y1; /* the window scanned */
    long scanned;
    long value_differ;                 /* pixels whose values differ in any bit */
    long tree_differ;                  /* pixels whose ray trees differ (ggTraceCompare) */
    long first_by_kind[GG_DIFF_COUNT]; /* pixels by what their first divergence is */
    double max_delta;
    int nworst; /* pixels listed: those that differ, largest delta first */
    ggDiffPixel *worst;
    /* width * height bytes: 0 identical, 1 the value differs but not the
       tree, 2 the tree differs (value or not). */
    unsigned char *map;
    ggImage *image_a, *image_b; /* both renders of the window */
    ggRayStats stats_a, stats_b;
    /* ggDiffPath only (ggDiff leaves them 0): the pixels whose light moved
       between path classes (ggDiffMove). */
    int by_path;       /* 1 when ggDiffPath made the result */
    long moved;        /* how many */
    int nmoves;        /* listed: the first min(moved, limit) in row order */
    ggDiffMove *moves;
} ggDiffResult;

/* Render scene_a with opt_a and scene_b with opt_b (they may be the same
   scene), pixel by pixel with both ray trees recorded, and compare. The
   two settings must give images of one size; the window is opt_a's.
   worst: how many differing pixels to list. Threads and progress come
   from opt_a. Returns GG_OK, GG_ERROR_INVALID (NULL arguments, sizes that
   differ, a negative worst), GG_ERROR_NOMEM, GG_ERROR_CANCELLED, or what
   ggRender would. */
GG_API int ggDiff(ggScene *scene_a, const ggRenderOptions *opt_a, ggScene *scene_b,
                  const ggRenderOptions *opt_b, int worst, ggDiffResult **out, ggError *err);
GG_API void ggDiffResultFree(ggDiffResult *res);

/* ggDiff, and for every pixel the paths expr matches on each side
   (ggPathMatch). A pixel's light moved between path classes when those
   paths differ as classes: the multiset of their events as ggPathFormat
   writes them (types, scatters, labels) differs between a and b -- a
   path is in the class on one side only (it matches there and not on the
   other, or exists on one side only), or more paths of one string on
   one side. A change of the paths' values alone (a hit point that moved,
   a share that changed with the same paths) is not a move. Each moved
   pixel comes with both shares (ggPathSummary.share) and the first
   divergent ray of its trees (ggTraceCompare: the decision that
   flipped; SAME when only a predicate's numbers changed). limit: how
   many moved pixels to list in res->moves, in row order (res->moved
   counts them all). Everything else as ggDiff. Returns what ggDiff does
   (GG_ERROR_INVALID also for a NULL expr or a negative limit). */
GG_API int ggDiffPath(ggScene *scene_a, const ggRenderOptions *opt_a, ggScene *scene_b,
                      const ggRenderOptions *opt_b, const ggPathExpr *expr, int worst, int limit,
                      ggDiffResult **out, ggError *err);

#ifdef __cplusplus
}
#endif
#endif
