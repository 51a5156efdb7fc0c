/* SPDX-License-Identifier: MIT */
/*
** fresnel_fma.h -- the fma build of the Fresnel reflectances (internal).
*/
#ifndef GG_FRESNEL_FMA_H
#define GG_FRESNEL_FMA_H

#include "core.h"

/* gg_dd of dd.h, not included here: fresnel_fma.c includes it only after
   asking it for the fma TwoProd. */
struct gg_dd;

/* The per-ISA object fresnel_fma.c (compiler.h, "Per-ISA code"): the
   kernels of fresnel.inc.h, same arguments and same bits as fresnel.c's
   plain build; call only where gg_cpu_features() has GG_CPU_FMA. */
#if GG_ISA_X86
void gg_fresnel_dielectric_fma(double c, double a, double b, struct gg_dd *rs, struct gg_dd *rp);
void gg_fresnel_conductor_fma(double c, double n1, double n, double k, struct gg_dd *rs,
                              struct gg_dd *rp);
#endif

#endif
