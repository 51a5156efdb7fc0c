/* SPDX-License-Identifier: MIT */
/*
** cpu.c -- the one run-time CPU detection of the library: which of the
** instruction sets that per-ISA objects are compiled for (compiler.h,
** "Per-ISA code") the CPU and the operating system run.
*/
#include "core.h"

#if GG_ISA_X86
#include <cpuid.h>
#include <pthread.h>

static unsigned features;
static pthread_once_t once = PTHREAD_ONCE_INIT;

/* AVX needs the CPU flag and the OS saving the YMM registers on a context
   switch (OSXSAVE set and XCR0 bits 1 and 2, SSE and AVX state: Intel 64
   and IA-32 Architectures Software Developer's Manual, vol. 1, 14.3
   "Detection of Intel AVX Instructions"); FMA is VEX-encoded and needs the
   same (14.5.3). */
static void probe(void)
{
    unsigned a, b, c, d, lo, hi;
    if (!__get_cpuid(1, &a, &b, &c, &d)) return;
    if (!(c & bit_OSXSAVE) || !(c & bit_AVX)) return;
    __asm__("xgetbv" : "=a"(lo), "=d"(hi) : "c"(0));
    (void)hi;
    if ((lo & 6) != 6) return;
    features = GG_CPU_AVX | (c & bit_FMA ? GG_CPU_FMA : 0u);
}

unsigned gg_cpu_features(void)
{
    pthread_once(&once, probe);
    return features;
}
#else
unsigned gg_cpu_features(void)
{
    return 0;
}
#endif
