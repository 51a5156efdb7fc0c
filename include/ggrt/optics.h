/*
** ggrt/optics.h -- reflection, refraction, Fresnel and absorption.
** (Being completed under issue 2; see docs/optics.md.)
*/
#ifndef GGRT_OPTICS_H
#define GGRT_OPTICS_H

#include "ggrt/base.h"

#ifdef __cplusplus
extern "C" {
#endif

/* r = v - 2 n (v.n); v is the incoming direction, n a unit normal. */
GG_API ggVec3 ggReflection(ggVec3 v, ggVec3 n);

/* Refract unit direction v (travelling towards the surface) through a
   surface with unit normal n, which may face either way, from index ni
   (v's side) into nt. Returns true and writes the unit transmitted
   direction to *t; on total internal reflection returns false and writes
   the mirror direction. */
GG_API bool ggRefract(ggVec3 v, ggVec3 n, double ni, double nt, ggVec3 *t);

#ifdef __cplusplus
}
#endif
#endif
