/* SPDX-License-Identifier: MIT */
/*
** optics_int.h -- shared inside lib/optics (internal).
*/
#ifndef GG_OPTICS_INT_H
#define GG_OPTICS_INT_H

#include "core.h"

#if GG_ISA_X86
/* Whether the fma builds may run (gg_cpu_features() & GG_CPU_FMA), asked
   once and cached (optics.c); every per-ISA choice of the layer goes
   through it. */
int gg_optics_use_fma(void);
#endif

#endif
