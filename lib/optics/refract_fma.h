/* SPDX-License-Identifier: MIT */
/*
** refract_fma.h -- the fma build of the accurate refraction (internal).
*/
#ifndef GG_REFRACT_FMA_H
#define GG_REFRACT_FMA_H

#include "core.h"

/* GCC on x86-64 can compile one function for fma while the rest of the
   library targets SSE2 (clang spells the pragma differently: it uses the
   plain path). */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(GG_NO_FMA_CLONE)
#define GG_HAVE_REFRACT_FMA 1
/* The accurate refraction (same contract and same bits as optics.c's
   refract_plain); call only where the CPU has fma (gg_cpu_has_fma). */
int gg_refract_fma(const ggVec3 *v, const ggVec3 *n, double ni, double nt, ggVec3 *t);
/* The same for ggReflection. */
void gg_reflect_fma(const ggVec3 *v, const ggVec3 *n, ggVec3 *r);
#else
#define GG_HAVE_REFRACT_FMA 0
#endif

#endif
