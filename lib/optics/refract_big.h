/* SPDX-License-Identifier: MIT */
/*
** refract_big.h -- ggRefract's 512-bit fallback (internal, refract_big.c).
*/
#ifndef GG_REFRACT_BIG_H
#define GG_REFRACT_BIG_H

/* The refraction of v through the surface of normal n from index ni into
   nt (the caller's doubles, not scaled), for a v that is not in the
   surface; s is the sign of the exact v.n (-1 or 1). Writes the unit
   transmitted direction (returns 1) or the unit mirror direction (returns
   0) to t, each component rounded to nearest from a value within 2^-250
   of the exact one; the decision is exact unless |cos^2(theta_t)| <
   2^-507 (docs/optics.md, "Index ratios beyond 2^450 with spread
   components"). 16 to 30 microseconds a call: only for inputs the
   double-double path cannot represent after scaling (refract.inc.h,
   refract_full). */
int gg_optics_refract_big(const double v[3], const double n[3], double ni, double nt, int s,
                          double t[3]);

#endif
