/* SPDX-License-Identifier: MIT */
/*
** cpu.c -- the one run-time CPU detection of the library: which of the
** instruction sets that per-ISA objects are compiled for (compiler.h,
** "Per-ISA code") the CPU and the operating system run, and the kernel
** table (core.h) filled from it in the same pthread_once.
*/
#include "core.h"

#if GG_ISA_X86
#include <cpuid.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

static unsigned features;
static gg_kernel_table kernels; /* all GG_KERNEL_PLAIN until probe */
static pthread_once_t once = PTHREAD_ONCE_INIT;

/* AVX needs the CPU flag and the OS saving the YMM registers on a context
   switch (OSXSAVE set and XCR0 bits 1 and 2, SSE and AVX state: Intel 64
   and IA-32 Architectures Software Developer's Manual, vol. 1, 14.3
   "Detection of Intel AVX Instructions"); FMA is VEX-encoded and needs the
   same (14.5.3). The AVX2 copy is compiled with -mavx2 -mbmi -mbmi2
   -mlzcnt -mpopcnt (Makefile, ISA_avx2), so it needs each of those flags:
   CPUID leaf 7 EBX (AVX2, BMI1, BMI2), leaf 0x80000001 ECX (LZCNT, "ABM")
   and leaf 1 ECX (POPCNT); they use the same YMM state as AVX. */
static unsigned avx2_flags(unsigned c1)
{
    unsigned a, b, c, d;
    const unsigned want7 = bit_AVX2 | bit_BMI | bit_BMI2;
    if (!(c1 & bit_POPCNT)) return 0;
    if (!__get_cpuid_count(7, 0, &a, &b, &c, &d) || (b & want7) != want7) return 0;
    if (!__get_cpuid(0x80000001u, &a, &b, &c, &d) || !(c & bit_LZCNT)) return 0;
    return GG_CPU_AVX2;
}

/* AVX-512 needs the CPU flags (CPUID leaf 7 EBX: F bit 16, DQ bit 17, BW
   bit 30, VL bit 31) and the OS saving the opmask, the upper halves of
   ZMM0-15 and ZMM16-31 as well as the SSE and AVX state (XCR0 bits 5, 6
   and 7 with 1 and 2: SDM vol. 1, 15.2 "Detection of AVX-512 Foundation
   Instructions"). The copy is compiled with AVX2 and the bit
   instructions too (Makefile, ISA_avx512), so it needs avx2_flags and
   FMA besides; every CPU with AVX-512 has them. */
static unsigned avx512_flags(unsigned xcr0, unsigned have)
{
    unsigned a, b, c, d;
    const unsigned want7 = 1u << 16 | 1u << 17 | 1u << 30 | 1u << 31;
    if ((xcr0 & 0xe6) != 0xe6 || (have & (GG_CPU_AVX2 | GG_CPU_FMA)) != (GG_CPU_AVX2 | GG_CPU_FMA))
        return 0;
    if (!__get_cpuid_count(7, 0, &a, &b, &c, &d) || (b & want7) != want7) return 0;
    return GG_CPU_AVX512;
}

/* GGRT_ISA caps the features (core.h): the mask of those kept. */
static unsigned isa_cap(void)
{
    static const struct {
        const char *name;
        unsigned keep;
    } caps[] = {{"sse2", 0},
                {"avx", GG_CPU_AVX | GG_CPU_FMA},
                {"avx2", GG_CPU_AVX | GG_CPU_FMA | GG_CPU_AVX2},
                {"avx512", GG_CPU_ALL}};
    const char *e = getenv("GGRT_ISA");
    size_t i;
    for (i = 0; e && i < sizeof caps / sizeof caps[0]; i++)
        if (!strcmp(e, caps[i].name)) return caps[i].keep;
    return GG_CPU_ALL;
}

static unsigned detect(void)
{
    unsigned a, b, c, d, lo, hi, f;
    if (!__get_cpuid(1, &a, &b, &c, &d)) return 0;
    if (!(c & bit_OSXSAVE) || !(c & bit_AVX)) return 0;
    __asm__("xgetbv" : "=a"(lo), "=d"(hi) : "c"(0));
    (void)hi;
    if ((lo & 6) != 6) return 0;
    f = GG_CPU_AVX | (c & bit_FMA ? GG_CPU_FMA : 0u) | avx2_flags(c);
    return (f | avx512_flags(lo, f)) & isa_cap();
}

/* The features, and the best copy of each kernel they allow. */
static void probe(void)
{
    features = detect();
    kernels.refract = kernels.reflect = kernels.fresnel =
        features & GG_CPU_FMA ? GG_KERNEL_FMA : GG_KERNEL_PLAIN;
    kernels.trav = features & GG_CPU_AVX512 ? GG_KERNEL_AVX512
                   : features & GG_CPU_AVX2 ? GG_KERNEL_AVX2
                   : features & GG_CPU_AVX  ? GG_KERNEL_AVX
                                            : GG_KERNEL_PLAIN;
}

unsigned gg_cpu_features(void)
{
    pthread_once(&once, probe);
    return features;
}

#if GG_HAVE_ACQ_REL
const gg_kernel_table *gg_cpu_table;
#endif

const gg_kernel_table *gg_cpu_kernels_once(void)
{
    pthread_once(&once, probe);
#if GG_HAVE_ACQ_REL
    GG_ATOMIC_STORE_REL(&gg_cpu_table, &kernels);
#endif
    return &kernels;
}
#else
unsigned gg_cpu_features(void)
{
    return 0;
}

/* No per-ISA objects: every kernel's plain copy, the table filled from
   the start. */
static const gg_kernel_table plain = {GG_KERNEL_PLAIN, GG_KERNEL_PLAIN, GG_KERNEL_PLAIN,
                                      GG_KERNEL_PLAIN};
#if GG_HAVE_ACQ_REL
const gg_kernel_table *gg_cpu_table = &plain;
#endif

const gg_kernel_table *gg_cpu_kernels_once(void)
{
    return &plain;
}
#endif
