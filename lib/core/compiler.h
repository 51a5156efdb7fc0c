/* SPDX-License-Identifier: MIT */
/*
** compiler.h -- the library's compiler-specific spellings, in one place
** (internal). Everything here degrades to plain C99 on a compiler that
** is neither GCC nor clang: the code stays correct, only slower.
*/
#ifndef GG_COMPILER_H
#define GG_COMPILER_H

/* IEEE arithmetic, not a tuning knob: the error bounds of the hit points
   and offsets, the Fresnel and refraction kernels' exact steps and every
   NaN and infinity check assume it, and a build that breaks it renders
   other images under the same ggBuildId (tests/build/compilers.sh). The
   Makefile passes -ffp-contract=off after the caller's CFLAGS for the
   same reason. */
#if defined(__FAST_MATH__) || (defined(__FINITE_MATH_ONLY__) && __FINITE_MATH_ONLY__)
#error "libggrt needs IEEE arithmetic: build it without -ffast-math, -Ofast or -ffinite-math-only"
#endif

#if defined(__GNUC__) /* GCC and clang */
/* A static function the compiler must inline: the hot paths are written
   as small functions over a struct and rely on it to keep their fields
   in registers (and, in shade.c, to fold the constant effect set). */
#ifndef GG_NO_FORCED_INLINE
#define GG_INLINE      static inline __attribute__((always_inline))
#else
/* The sanitizer trees (Makefile: SAN_FLAGS, TSAN_FLAGS) leave inlining to
   the compiler: forced, it copies the instrumented walks into every
   caller (GCC ASan's bvh_avx.o took 26 s and held 521 KB of UBSan site
   data; 7.6 s and 205 KB without), for no check that the copies add.
   The operations and their order are the same, so are the results. */
#define GG_INLINE      static inline
#endif
#define GG_NOINLINE    __attribute__((noinline))
/* A rarely taken function: GCC moves it, and the calls to it, out of the
   hot path (so a caller can keep its fast path free of a stack frame). */
#define GG_COLD        __attribute__((cold))
#define GG_PRINTF(a, b) __attribute__((format(printf, a, b)))
#define GG_LIKELY(x)   __builtin_expect(!!(x), 1)
#define GG_UNLIKELY(x) __builtin_expect(!!(x), 0)
#define GG_CTZ(m)      __builtin_ctz(m)
/* A hint that the line holding p will soon be written. */
#define GG_PREFETCH_W(p) __builtin_prefetch(p, 1, 3)
/* A hint that the line holding p will soon be read. */
#define GG_PREFETCH(p) __builtin_prefetch(p, 0, 3)
/* One fused multiply-add instruction, in a per-ISA object built for it
   (dd.h's dd_two_prod in refract_fma.c and fresnel_fma.c); math.h's fma
   may be a call. */
#define GG_FMA(a, b, c) __builtin_fma(a, b, c)
#else
#define GG_INLINE      static inline
#define GG_NOINLINE
#define GG_COLD
#define GG_PRINTF(a, b)
#define GG_LIKELY(x)   (x)
#define GG_UNLIKELY(x) (x)
static inline int gg_ctz_portable(unsigned m)
{
    int i = 0;
    while (!(m & 1u)) m >>= 1, i++;
    return i;
}
#define GG_CTZ(m) gg_ctz_portable(m)
#define GG_PREFETCH_W(p) ((void)(p))
#define GG_PREFETCH(p)   ((void)(p))
#define GG_FMA(a, b, c) fma(a, b, c)
#endif

/* No contraction of a*b + c into one fused operation anywhere: the
   error-free transformations of dd.h need the two roundings, and the
   plain and per-ISA copies of a kernel must round alike. The Makefile
   also passes -ffp-contract=off; this covers other builds. C99 7.12.2;
   clang (which contracts by default) honours it, GCC does not contract
   in ISO C mode and does not know the pragma. */
#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#endif

/* Relaxed atomics on a shared, sticky hint (lib/implicit/implicit.c):
   C99 has none of its own. Without GCC's or clang's builtins they are
   plain accesses, a benign race (a hint read stale is only re-learnt);
   the CAS then just stores and reports success. The acquire load and
   release store publish a structure filled once (the kernel table,
   core.h); without the builtins there are none (GG_HAVE_ACQ_REL 0) and
   the caller takes its locked path every time. */
#if defined(__GNUC__)
#define GG_HAVE_ACQ_REL           1
#define GG_ATOMIC_LOAD_ACQ(p)     __atomic_load_n(p, __ATOMIC_ACQUIRE)
#define GG_ATOMIC_STORE_REL(p, v) __atomic_store_n(p, v, __ATOMIC_RELEASE)
#define GG_ATOMIC_LOAD(p)    __atomic_load_n(p, __ATOMIC_RELAXED)
#define GG_ATOMIC_STORE(p, v) __atomic_store_n(p, v, __ATOMIC_RELAXED)
#define GG_ATOMIC_OR(p, v)   (void)__atomic_fetch_or(p, v, __ATOMIC_RELAXED)
#define GG_ATOMIC_CAS(p, e, v) \
    __atomic_compare_exchange_n(p, e, v, 0, __ATOMIC_RELAXED, __ATOMIC_RELAXED)
#else
#define GG_HAVE_ACQ_REL        0
#define GG_ATOMIC_LOAD(p)      (*(p))
#define GG_ATOMIC_STORE(p, v)  (void)(*(p) = (v))
#define GG_ATOMIC_OR(p, v)     (void)(*(p) |= (v))
#define GG_ATOMIC_CAS(p, e, v) ((void)(e), *(p) = (v), 1)
#endif

/* GNU C vector types (GCC and clang; refract.inc.h): n bytes of lanes
   with element-wise operators. GG_PSABI_OFF silences the warning that
   passing such a type by value has a different ABI with and without AVX,
   for a file whose functions taking them are all inlined. */
#if defined(__GNUC__)
#define GG_VECTOR_SIZE(n) __attribute__((vector_size(n)))
#if defined(__clang__)
#define GG_PSABI_OFF _Pragma("clang diagnostic ignored \"-Wpsabi\"")
#else
#define GG_PSABI_OFF _Pragma("GCC diagnostic ignored \"-Wpsabi\"")
#endif
#endif

/* GCC's SLP vectoriser pairs neighbouring 8-byte loads into one 16-byte
   load; where the caller has just written the struct field by field, that
   load cannot be forwarded from the store buffer and waits for the stores
   to retire (Intel 64 and IA-32 Architectures Optimization Reference
   Manual, "Store Forwarding"). GG_NO_SLP turns the pass off for one
   function. Clang has no per-function switch and does not pair these. */
#if defined(__GNUC__) && !defined(__clang__)
#define GG_NO_SLP __attribute__((optimize("no-tree-slp-vectorize")))
#else
#define GG_NO_SLP
#endif
/* The same for a few loads inside a function that is inlined (where
   GG_NO_SLP does not reach): the statement GG_SCALAR(x); passes the
   double x through an empty asm, so the load that produced it is not
   paired with another. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define GG_SCALAR(x) __asm__("" : "+x"(x))
#else
#define GG_SCALAR(x) ((void)(x))
#endif

/* Per-ISA code. An object named *_avx.o, *_avx2.o or *_fma.o is
   compiled, on x86-64 with GCC or clang, with that instruction set's
   flags and -DGG_ISA=avx, avx2 or fma (Makefile, "Per-ISA objects"); the
   rest of the library targets the base instruction set (SSE2). Its
   source is the file of that name or, for a source built for several
   sets, the one ISA_AGAIN in the Makefile names (bvh_avx2.o is
   bvh_avx.c once more): one source per kernel, never a .c including
   another. Such an object holds only functions that are called through
   the kernel table (gg_cpu_kernels(), cpu.c), which offers them where the
   CPU runs them, the way Embree compiles its kernels once per
   instruction set; GG_ISA_NAME(gg_f) names one gg_f_avx2 in the avx2
   build. GG_ISA_X86 says whether this build has them (-DGG_NO_ISA
   leaves them out). */
#if (defined(__GNUC__) || defined(__clang__)) && defined(__x86_64__) && !defined(GG_NO_ISA)
#define GG_ISA_X86 1
#else
#define GG_ISA_X86 0
#endif
#define GG_PASTE_(a, b)   a##_##b
#define GG_PASTE(a, b)    GG_PASTE_(a, b)
#define GG_ISA_NAME(name) GG_PASTE(name, GG_ISA)

/* Templates. A header named *.inc.h holds kernels compiled once per
   file that includes it, each time with other hooks. Its includer
   defines, before including it, GG_INC_NAME(f), the name this copy gives
   to the template's function f (f##_plain, GG_ISA_NAME(gg_##f), ...),
   and GG_INC_LINK, their linkage (static, or empty where a header
   declares them); the template lists its other hooks at its top and
   calls nothing else that a copy could want to change. */

#endif
