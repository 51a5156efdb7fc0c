/* SPDX-License-Identifier: MIT */
/*
** implicit.h -- what the geometry module needs from implicit surfaces
** (internal).
*/
#ifndef GG_LIB_IMPLICIT_H
#define GG_LIB_IMPLICIT_H

#include "core.h"

/* The surface normal (unnormalised) as the renderer uses it: central
   differences with step h when h > 0, else the surface's own choice (the
   exact gradient, or central differences when ggImplicitSetNormalStep
   chose a step). Reads imp only. */
ggVec3 gg_implicit_normal_step(const ggImplicit *imp, ggVec3 p, double h);

/* The box the surface lives in. */
void gg_implicit_bounds(const ggImplicit *imp, ggVec3 *lo, ggVec3 *hi);

/* First root of f along o + t d with t in (tmin, tmax), clipped to the
   box. Returns 1 and *t on a hit, 0 on a miss. Thread-safe (no mutable
   state in imp but the atomic warning flag below).
   Same as gg_implicit_intersect_status followed by gg_implicit_note. */
int gg_implicit_intersect(const ggImplicit *imp, ggVec3 o, ggVec3 d, double tmin, double tmax,
                          double *t);
/* The same with root tolerance tol (scene units) when tol > 0, else the
   surface's own (ggImplicitSetTolerance): a render's choice that is never
   stored in imp. */
int gg_implicit_intersect_tol(const ggImplicit *imp, ggVec3 o, ggVec3 d, double tmin, double tmax,
                              double tol, double *t);
/* gg_implicit_intersect_tol that also returns this ray's warnings
   (GG_IMPLICIT_WARN_*) in *warn, for the renderer's statistics. */
int gg_implicit_intersect_warn(const ggImplicit *imp, ggVec3 o, ggVec3 d, double tmin, double tmax,
                               double tol, double *t, unsigned *warn);

/* What one intersection saw. */
typedef struct gg_implicit_status {
    unsigned warn;    /* GG_IMPLICIT_WARN_* raised by this ray */
    double max_slope; /* largest |f(p) - f(q)| / |p - q| seen between samples
                         (Lipschitz method only; 0 otherwise) */
    long evals;       /* evaluations of f, in any form (point, dual, interval) */
} gg_implicit_status;

/* gg_implicit_intersect without any write to imp: the warnings of this ray
   go to *st (not optional) and nowhere else. A renderer can sum them per
   thread and call gg_implicit_note once at the end. */
int gg_implicit_intersect_status(const ggImplicit *imp, ggVec3 o, ggVec3 d, double tmin,
                                 double tmax, double *t, gg_implicit_status *st);

/* The root tolerance in scene units (ggImplicitSetTolerance; default 1e-12
   times the box diagonal). A hit t is within tol / |d| of a sign change of
   the computed f, usually far closer (a final Newton step when a
   derivative is known). For gg_surf.perr: add it to the rounding error of
   o + t d. Where f itself is ill-conditioned (|grad f| tiny against the
   rounding of f), the computed surface is off the exact one by more. */
double gg_implicit_tolerance(const ggImplicit *imp);

/* Fold st into imp's sticky warnings (ggImplicitWarnings) and its largest
   slope seen (ggImplicitMaxSlope). Atomic, callable from any thread. */
void gg_implicit_note(const ggImplicit *imp, const gg_implicit_status *st);

#endif
