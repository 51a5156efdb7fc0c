/* SPDX-License-Identifier: MIT */
/*
** refract_fma.h -- the fma build of the accurate refraction (internal).
*/
#ifndef GG_REFRACT_FMA_H
#define GG_REFRACT_FMA_H

#include "core.h"

/* The per-ISA object refract_fma.c (compiler.h, "Per-ISA code"). */
#if GG_ISA_X86
/* The accurate refraction (same contract and same bits as optics.c's
   refract_plain); call only where gg_cpu_features() has GG_CPU_FMA. */
bool gg_refract_fma(ggVec3 v, ggVec3 n, double ni, double nt, ggVec3 *t);
/* The accurate reflection (reflect.inc.h; same contract and bits as
   optics.c's reflect_plain and ggReflection). */
ggVec3 gg_reflect_fma(const ggVec3 *v, const ggVec3 *n);
#endif

#endif
