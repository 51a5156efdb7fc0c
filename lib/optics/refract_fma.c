/* SPDX-License-Identifier: MIT */
/*
** refract_fma.c -- the accurate refraction compiled for x86-64 CPUs with
** fused multiply-add (see refract_core.h): a per-ISA object, built with
** -mfma (compiler.h, "Per-ISA code"). ggRefract (optics.c) calls it only
** where gg_cpu_features() has GG_CPU_FMA.
*/
#include "core.h"

#include "refract_fma.h"

#if GG_ISA_X86
#ifndef __FMA__
#error "refract_fma.c is compiled with -mfma (Makefile: ISA_fma)"
#endif

#include <math.h>
#include <stdint.h>
#include <string.h>

#define GG_DD_FMA 1
#define GG_REFRACT_NAME refract_fma
#include "refract_core.h"

int gg_refract_fma(ggVec3 v, ggVec3 n, double ni, double nt, ggVec3 *t)
{
    return refract_fma(v, n, ni, nt, t);
}

#else
/* ISO C forbids an empty translation unit. */
typedef int gg_refract_fma_unused;
#endif
