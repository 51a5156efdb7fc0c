/* SPDX-License-Identifier: MIT */
/*
** bvh_avx2.c -- bvh_avx.c compiled again for CPUs with AVX2, BMI1, BMI2,
** LZCNT and POPCNT (Makefile: ISA_avx2): the same source, so the same
** operations in the same order and the same bits, with the compiler free
** to use the newer instructions (vpbroadcast, tzcnt, blsr, ...). bvh.c
** calls these where gg_cpu_features() has GG_CPU_AVX2 and the geometry
** allows it (g->trav_avx == 2). What it bought: docs/performance.md,
** "One source per instruction set".
*/
#include "core.h"

#if GG_ISA_X86 && !defined(GG_BVH_NO_SIMD)
#ifndef __AVX2__
#error "bvh_avx2.c is compiled with -mavx2 (Makefile: ISA_avx2)"
#endif
#define GG_AVX_NAME(name) name##_avx2
#include "bvh_avx.c"
#else
/* ISO C forbids an empty translation unit. */
typedef int gg_bvh_avx2_unused;
#endif
