/* SPDX-License-Identifier: MIT */
/*
** debug_int.h -- what the files of the debug layer share (private to
** lib/debug: docs/internals.md, "Headers").
*/
#ifndef GG_DEBUG_INT_H
#define GG_DEBUG_INT_H

#include "render.h"
#include "scene.h"

/* What a predicate (or a check) reads from a pixel. */
#define GG_NEED_TREE   1u  /* ray trees (without it pixel values serve) */
#define GG_NEED_LIGHTS 2u  /* shadow-ray records */
#define GG_NEED_WEIGHT 4u  /* the rays' weights in the pixel */
#define GG_NEED_XY     8u  /* the pixel's coordinates */
#define GG_NEED_COST   16u /* the rays' traversal cost (each eye ray's own) */

/* A pixel being looked at: its value, its recorded trees (NULL when only
   the value is known) and, if computed, each node's weight in the pixel. */
typedef struct gg_dbg_pixel {
    const ggTrace *trace;
    int x, y;
    ggColor px;
    const ggColor *w;
    struct gg_path_cache *cache; /* path matching: this worker's steps (NULL: none) */
} gg_dbg_pixel;

/* ---- predicates (pred.c, pred_eval.c) ---- */

/* Field types and the level they live at. */
enum { PT_NUM, PT_COLOR, PT_BOOL, PT_ENUM };

enum {
    PN_OR,
    PN_AND,
    PN_NOT,
    PN_SOME, /* a: the body */
    PN_ALL,
    PN_COUNT, /* a number */
    PN_CMP,   /* a, b: operands; cmp: the operator */
    PN_BOOL,  /* field: a boolean field */
    PN_NUM,   /* num */
    PN_FIELD  /* field, comp */
};

enum { PC_EQ, PC_NE, PC_LT, PC_LE, PC_GT, PC_GE };

typedef struct gg_pnode {
    int op;
    int a, b;  /* operand nodes */
    int field; /* index in the field table */
    int comp;  /* colour component: 0 r, 1 g, 2 b, 3 max, 4 min */
    int cmp;   /* PC_* */
    double num;
} gg_pnode;

struct ggPredicate {
    ggAllocator alloc_copy;
    const ggAllocator *alloc;
    gg_pnode *n;
    int count, root;
    unsigned needs; /* GG_NEED_* */
};

/* The field table, shared by the parser and the evaluator. */
enum {
    PF_KIND,
    PF_DEPTH,
    PF_CHANNEL,
    PF_OBJECT,
    PF_MATERIAL,
    PF_LINE,
    PF_SHAPE,
    PF_FRONT,
    PF_BACK,
    PF_HIT,
    PF_MISS,
    PF_T,
    PF_STOP,
    PF_FRESNEL,
    PF_WEIGHT,
    PF_COLOR,
    PF_ABSORPTION,
    PF_NONFINITE,
    PF_LIGHT,
    PF_VERDICT,
    PF_OCCLUDER,
    PF_TRANSMITTANCE,
    PF_DIFFUSE,
    PF_PHONG,
    PF_MEDIUM,
    PF_PERR,
    PF_OFFSET,
    PF_TIR_MARGIN,
    PF_EDGE,
    PF_TRIANGLE,
    PF_NODES,
    PF_PRIMS,
    PF_X, /* pixel fields from here on */
    PF_Y,
    PF_PIXEL,
    PF_RAYS,
    PF_COUNT
};
#define PF_FIRST_PIXEL PF_X

/* The kind a shadow ray has in the language (after GG_RAY_*). */
#define GG_PRED_SHADOW 4

/* Evaluate on one pixel: 1 true, 0 not (false or unknown). */
int gg_pred_eval(const ggPredicate *p, const gg_dbg_pixel *px);
/* Work out p->needs (after parsing). */
unsigned gg_pred_analyse(const ggPredicate *p);

/* A ray expression (some's body) in text[start..] up to its closing ']'
   (path expressions, path.c): *end receives the byte after the ']';
   errors name columns of the whole text. */
int gg_pred_parse_ray(const char *text, size_t len, size_t start, const ggAllocator *alloc,
                      ggPredicate **out, size_t *end, ggError *err);
/* Evaluate a ray expression on node `node` of px->trace, or on its shadow
   ray L (not NULL): 1 only when true. */
int gg_pred_eval_ray(const ggPredicate *p, const gg_dbg_pixel *px, int node, const ggTraceLight *L);

/* ---- path expressions (path.c, path_match.c) ---- */

#include <stdint.h>

enum { PE_C, PE_R, PE_T, PE_L, PE_O, PE_B, PE_A, PE_NTYPES }; /* event types */
enum { PS_NONE, PS_D, PS_G, PS_S };                          /* scatter */
enum { PL_TIR, PL_NUMBER, PL_MATERIAL };                       /* label kinds */

#define GG_PATH_WORDS   (GG_PATH_MAX_STATES / 64)
#define GG_PATH_MAX_LABELS 8 /* labels in one < > */

/* A place in an expression's text, for messages after parsing (path
   layers name the predicate or the label they refuse). */
typedef struct gg_path_place {
    int line, col;
} gg_path_place;

typedef struct gg_path_pat {
    unsigned types, scatters; /* masks: bit PE_*, bit PS_* */
    int nlabels;
    int label_kind[GG_PATH_MAX_LABELS];
    long label_num[GG_PATH_MAX_LABELS];
    gg_path_place label_at[GG_PATH_MAX_LABELS]; /* each label's quote */
} gg_path_pat;

/* What one transition accepts: any of its patterns (none of them when
   neg), and then its predicate (if any). */
typedef struct gg_path_class {
    int first, count, neg;
    ggPredicate *pred;
    gg_path_place pred_at; /* where its '[' is */
} gg_path_class;

typedef struct gg_path_edge {
    int from, cls, to; /* cls -1: an empty move */
} gg_path_edge;

typedef uint64_t gg_path_set[GG_PATH_WORDS];

struct ggPathExpr {
    ggAllocator alloc_copy;
    const ggAllocator *alloc;
    gg_path_pat *pats;
    gg_path_class *cls;
    gg_path_edge *edges;
    int npats, ncls, nedges, nstates, accept;
    unsigned needs;                          /* GG_NEED_* of the predicates */
    gg_path_set closure[GG_PATH_MAX_STATES]; /* each state's empty-move closure */
};

/* A worker's memory of the automaton's steps: the state set after an
   event from a state set, by the event's type, scatter and labels (for an
   expression without predicates, that is all a step reads). Direct
   mapped; one per thread, kept across its pixels (path_match.c). */
#define GG_PATH_CACHE 512
typedef struct gg_path_step {
    gg_path_set in, out;
    int sig[6]; /* type, scatter, tir, object, material, light */
    int valid;
} gg_path_step;
typedef struct gg_path_cache {
    const ggPathExpr *e;
    int usable;          /* e has no predicates */
    int numbers, materials; /* e has labels 'N' (objects, lights), 'mN' */
    gg_path_step slot[GG_PATH_CACHE];
} gg_path_cache;

/* The states after one event from the states in, for an expression
   without predicates: type PE_*, scatter PS_*, the tir flag, and the
   labels the event has: the surface's object and material when
   has_at, the light's number on PE_L (path_match.c's step: the one
   matcher, which path_layers.c compiles into the layers' automata). */
void gg_path_step_event(const ggPathExpr *e, const uint64_t *in, int type, int scatter, int tir,
                        int has_at, long object, long material, long light, uint64_t *out);

/* e (without predicates) as one path layer, from e's allocator
   (path_layers.c): GG_OK or ggPathLayersCompile's errors. */
int gg_path_layers_of(const ggPathExpr *e, ggPathLayers **out, ggError *err);

/* Match e against every path of px (whose w must be set), with sets
   holding GG_PATH_WORDS words per ray of px->trace (path_match.c).
   cache: NULL, or a zeroed (or earlier) gg_path_cache of this thread. */
void gg_path_run(const ggPathExpr *e, const gg_dbg_pixel *px, uint64_t *sets, ggPathSummary *sum,
                 gg_path_cache *cache);

/* ---- trees (tree.c) ---- */

/* Number of trees (roots) in t. */
int gg_dbg_roots(const ggTrace *t);
/* Each node's weight in the pixel into w (n = ggTraceNodeCount entries):
   the pixel changes by w[i] * d when node i's colour changes by d. The
   roots weigh 1 / (number of roots); a child weighs its parent's weight
   times the parent's absorption times its own weight. */
void gg_dbg_weights(const ggTrace *t, ggColor *w);

/* A growable per-thread buffer for gg_dbg_weights. */
typedef struct gg_dbg_buf {
    ggColor *w;
    size_t cap;
} gg_dbg_buf;
/* Fill b->w for t; -1 if out of memory. */
int gg_dbg_buf_weights(gg_dbg_buf *b, const ggAllocator *a, const ggTrace *t);

/* ---- the pixel scan (scan.c) ---- */

/* Called for every pixel of the window, from worker thread `thread`
   (0 .. threads - 1): recs[i] and px[i] for each tracer (recs NULL when
   not recording). same: 1 when they are those of the previous call (the
   pixel to its left, in a span of misses; scan.c). Return non-zero to
   stop the scan with that status. */
typedef int (*gg_scan_fn)(void *ud, int thread, int x, int y, ggTrace *const *recs,
                          const ggColor *px, int same);

typedef struct gg_scan {
    const gg_tracer *tracer[2];
    int ntracers;
    int record;          /* record trees */
    gg_tracer_desc desc; /* of tracer[0] */
    int threads;         /* worker threads the scan will use (set by gg_scan_init) */
    gg_scan_fn fn;
    void *ud;
    const ggAllocator *alloc;
    ggRayStats stats[2];  /* per tracer, summed over threads */
    unsigned char *empty; /* during the run: which tiles all miss */
    int every_pixel;      /* trace each pixel: no tree serves a neighbour (scan.c) */
    int tiles_x;
} gg_scan;

/* Fill in desc and threads from the tracers (call before allocating
   per-thread state). */
void gg_scan_init(gg_scan *sc);
/* Run it. Returns GG_OK, GG_ERROR_NOMEM, GG_ERROR_CANCELLED or what fn
   returned. */
int gg_scan_run(gg_scan *sc, ggError *err);

/* ---- results ---- */

/* ---- helpers (util.c) ---- */

/* A result's allocator, kept beside it (the scene may go first). */
typedef struct gg_dbg_alloc {
    ggAllocator copy;
    const ggAllocator *a;
} gg_dbg_alloc;
void gg_dbg_alloc_init(gg_dbg_alloc *al, const ggAllocator *a);

/* Store c at (x, y) of img as ggRender does (floats). */
void gg_dbg_put(ggImage *img, int x, int y, ggColor c);

/* Whether c has a NaN or infinite channel. */
int gg_dbg_nonfinite(ggColor c);
/* A decimal number at s (at most n bytes: sign, digits, fraction,
   exponent), read with '.' as the radix point whatever the locale:
   returns the bytes it takes (0 if none, or if it is 128 bytes or
   longer) and the value in *out. */
size_t gg_dbg_number(const char *s, size_t n, double *out);
/* The index in names[0..count) of the name s[0..n) most likely meant,
   for "did you mean", or -1: the only name it starts, else the nearest
   by edits (insertions, deletions, changes and swaps of neighbours), at
   most one edit in three letters and never three. The rule of the
   command line's suggestions (cli_suggest, cli/common/args.h). */
int gg_dbg_suggest(const char *s, size_t n, const char *const *names, size_t count);

#endif
