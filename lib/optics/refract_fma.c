/* SPDX-License-Identifier: MIT */
/*
** refract_fma.c -- the accurate refraction compiled for x86-64 CPUs with
** fused multiply-add (see refract_core.h). ggRefract (optics.c) calls it
** only after checking, at run time, that the CPU and the OS support it;
** the default build keeps targeting plain SSE2.
*/
#include "core.h"

#include "refract_fma.h"

#if GG_HAVE_REFRACT_FMA

#include <math.h>
#include <stdint.h>
#include <string.h>

#pragma GCC target("fma")
#define GG_DD_FMA 1
#define GG_REFRACT_NAME   gg_refract_fma
#define GG_REFLECT_NAME   gg_reflect_fma
#define GG_OPTICS_LINKAGE /* external: declared in refract_fma.h */
#include "refract_core.h"

#else
/* ISO C forbids an empty translation unit. */
typedef int gg_refract_fma_unused;
#endif
