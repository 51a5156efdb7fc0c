/* SPDX-License-Identifier: MIT */
/*
** fresnel_fma.c -- the Fresnel reflectances of fresnel.inc.h compiled
** for x86-64 CPUs with fused multiply-add: a per-ISA object, built with
** -mfma (compiler.h, "Per-ISA code"). fresnel.c calls it only where
** gg_cpu_features() has GG_CPU_FMA.
*/
#include "core.h"

#include "fresnel_fma.h"

#if GG_ISA_X86
#ifndef __FMA__
#error "fresnel_fma.c is compiled with -mfma (Makefile: ISA_fma)"
#endif

#define GG_DD_FMA      1
#define GG_INC_NAME(f) GG_ISA_NAME(gg_##f) /* gg_fresnel_dielectric_fma, ..._conductor_fma */
#define GG_INC_LINK                        /* external: declared in fresnel_fma.h */
#include "fresnel.inc.h"

#else
/* ISO C forbids an empty translation unit. */
typedef int gg_fresnel_fma_unused;
#endif
