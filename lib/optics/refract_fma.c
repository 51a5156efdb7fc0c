/* SPDX-License-Identifier: MIT */
/*
** refract_fma.c -- the accurate refraction and reflection compiled for
** x86-64 CPUs with fused multiply-add (see refract.inc.h and
** reflect.inc.h): a per-ISA object, built with -mfma (compiler.h,
** "Per-ISA code"). ggRefract and ggReflection (optics.c) call it only
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

#define GG_DD_FMA      1
#define GG_INC_NAME(f) GG_ISA_NAME(gg_##f) /* gg_refract_fma, gg_reflect_fma */
#define GG_INC_LINK                        /* external: declared in refract_fma.h */
#include "refract.inc.h"
#include "reflect.inc.h"

#else
/* ISO C forbids an empty translation unit. */
typedef int gg_refract_fma_unused;
#endif
