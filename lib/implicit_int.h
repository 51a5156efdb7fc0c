/*
** implicit_int.h -- what the geometry module needs from implicit surfaces
** (internal).
*/
#ifndef GG_IMPLICIT_INT_H
#define GG_IMPLICIT_INT_H

#include "internal.h"

/* The box the surface lives in. */
void gg_implicit_bounds(const ggImplicit *imp, ggVec3 *lo, ggVec3 *hi);

/* First root of f along o + t d with t in (tmin, tmax), clipped to the
   box. Returns 1 and *t on a hit, 0 on a miss. Thread-safe (no mutable
   state in imp but the atomic warning flag below). */
int gg_implicit_intersect(const ggImplicit *imp, ggVec3 o, ggVec3 d, double tmin, double tmax,
                          double *t);

#endif
