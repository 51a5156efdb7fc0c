/* SPDX-License-Identifier: MIT */
/*
** core.h -- helpers shared by the library's sources; never installed.
** Internal names carry the gg_ prefix (module after it) so the static
** archive cannot collide with a user's symbols.
*/
#ifndef GG_CORE_H
#define GG_CORE_H

#include "compiler.h"
#include "ggrt.h"

#include <stdarg.h>
#include <stdio.h>

#define GG_PI 3.14159265358979323846

/* Fill *err (if not NULL) and return code. The formatted message goes
   through gg_text_escape, so every message of the library shows bytes
   the same way, whatever file or name they came from. */
int gg_error_set(ggError *err, int code, const char *fmt, ...) GG_PRINTF(3, 4);
int gg_error_setv(ggError *err, int code, const char *fmt, va_list ap);

/* The length of the well-formed UTF-8 sequence at s[0..n) (RFC 3629: no
   overlong forms, no surrogates, nothing above U+10FFFF), else 0. */
int gg_utf8_len(const unsigned char *s, size_t n);
/* The one way the library shows text it did not write (file names,
   tokens, names): src[0..n) copied to dst (size bytes, always
   NUL-terminated, cut at a whole character), printable ASCII and
   well-formed UTF-8 as they are, every other byte (control characters,
   DEL, bytes that are not UTF-8) as the four characters \xHH. Its output
   is left unchanged by a second pass. Returns the length written. */
size_t gg_text_escape(char *dst, size_t size, const char *src, size_t n);

/* strtod of s[0..n) with '.' as the radix point whatever LC_NUMERIC says
   (the library must not depend on the locale): the callers check the
   text against their own grammar first. Returns the count of characters
   strtod read (0: none, or n >= 400), the value in *out (inf when it
   overflows, as strtod). */
size_t gg_strtod_c(const char *s, size_t n, double *out);

/* Allocation through an optional allocator (NULL = libc). */
void *gg_mem_alloc(const ggAllocator *a, size_t size);
void *gg_mem_calloc(const ggAllocator *a, size_t n, size_t size); /* zeroed, overflow-checked */
void *gg_mem_realloc(const ggAllocator *a, void *p, size_t size);
void gg_mem_free(const ggAllocator *a, void *p);

/* Grow *arr (elements of size `elem`) so it holds at least `need` elements;
   *cap is updated. Returns 0 on success, -1 on overflow or no memory (the
   array is unchanged then). */
int gg_mem_grow(const ggAllocator *a, void **arr, size_t *cap, size_t need, size_t elem);

/* Duplicate a NUL-terminated string (NULL on failure). */
char *gg_mem_strdup(const ggAllocator *a, const char *s);

/* Open path for reading if it is a regular file, the one way every
   reader of the library opens scene, mesh, material and image files: with
   O_NONBLOCK, so that a FIFO cannot block the open waiting for a writer,
   then fstat, so that a FIFO, device or directory is refused before a byte
   is read (GG_ERROR_IO "path: not a regular file"). A failed open is
   GG_ERROR_IO "path: why", or "path: verb: why" when verb is not NULL.
   *size (may be NULL) gets the file's size. The FILE is the caller's. */
int gg_file_open(const char *path, const char *verb, FILE **out, int64_t *size, ggError *err);

/* Hashing for tables whose keys a file chooses (OBJ corners and names,
   a mesh's vertex positions). With a fixed hash, keys that agree in the
   bits a table indexes by can be computed in advance, and one cluster
   made loading quadratic: an audit's 5.5 MB OBJ of such corners loaded
   in 108 s, 0.4 s with ordinary ones. Such tables hash through a seed of
   their own, drawn from addresses that the system randomises (ASLR), so
   that colliding keys cannot be prepared; nothing the library outputs
   depends on a table's order. gg_hash_seed(p): a seed from p (the
   table's memory) and the stack; gg_hash_word: one 64-bit word into the
   running hash h (splitmix64's finaliser, a bijection, after h ^ w);
   gg_hash_bytes: n bytes, a word at a time, with their length. */
uint64_t gg_hash_seed(const void *p);
static inline uint64_t gg_hash_word(uint64_t h, uint64_t w)
{
    h ^= w;
    h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ull;
    h = (h ^ (h >> 27)) * 0x94d049bb133111ebull;
    return h ^ (h >> 31);
}
uint64_t gg_hash_bytes(uint64_t seed, const void *p, size_t n);

/* A long step's progress (ggProgressFn, base.h) as a part of the
   caller's count: gg_progress_part(p, fn, ud, lo, hi, of) makes the part
   that runs from lo to hi of `of`; gg_progress_to(p, done, total) calls
   fn with done/total of the part mapped into [lo, hi] (never below the
   value passed before, so that done never decreases), and returns
   non-zero once fn has asked to stop: sticky, later calls return it
   without calling fn. With fn NULL it never calls and never stops.
   Counts above LONG_MAX are scaled down (a 4 GiB mesh on a 32-bit long). */
typedef struct gg_progress {
    ggProgressFn fn;
    void *ud;
    long lo, hi, of, last;
    int stopped;
} gg_progress;
void gg_progress_part(gg_progress *p, ggProgressFn fn, void *ud, uint64_t lo, uint64_t hi,
                      uint64_t of);
int gg_progress_to(gg_progress *p, uint64_t done, uint64_t total);

/* Monotonic clock in seconds. */
double gg_time_now(void);
/* Seconds of CPU time the calling thread has used (for differences
   only); gg_time_now where the system has no per-thread clock. */
double gg_time_cpu(void);

/* The instruction sets of the per-ISA objects (compiler.h) that this CPU
   and its OS run: a mask of GG_CPU_* bits, 0 where the build has no
   per-ISA objects. Detected once (cpu.c); thread-safe. The environment
   variable GGRT_ISA (sse2, avx, avx2 or avx512), read at that detection,
   caps the mask at that level, so that one machine can time its copies
   side by side (bench/ab_time.sh on two wrappers); anything else leaves
   the mask as detected. */
#define GG_CPU_AVX  1u /* AVX: bvh_avx.o */
#define GG_CPU_FMA  2u /* FMA3 (with AVX): refract_fma.o, fresnel_fma.o */
#define GG_CPU_AVX2 4u /* AVX2 with BMI1, BMI2, LZCNT and POPCNT (with AVX): bvh_avx2.o */
/* AVX-512 F, BW, DQ and VL with the OS saving the opmask and ZMM state
   (with AVX2 and FMA): bvh_avx512.o */
#define GG_CPU_AVX512 8u
#define GG_CPU_ALL    (GG_CPU_AVX | GG_CPU_FMA | GG_CPU_AVX2 | GG_CPU_AVX512)
unsigned gg_cpu_features(void);

/* The kernel table: the one run-time choice among the per-ISA copies of
   a kernel (compiler.h, "Per-ISA code"). Each entry is an index into
   that kernel's array of copies, kept in its layer (optics.c,
   fresnel.c, bvh.c), filled once (pthread_once, with the CPU detection)
   from gg_cpu_features(). Every copy of a kernel returns the same bits.
   gg_cpu_kernels() is called per ggRefract, ggReflection and Fresnel
   call: once the table is filled, an inline acquire load of
   gg_cpu_table, not a call into pthread_once (which made ggRefract 8%
   and ggReflection 13% more instructions: docs/optics.md). */
#define GG_KERNEL_PLAIN  0 /* the base instruction set */
#define GG_KERNEL_FMA    1 /* optics: the fma builds */
#define GG_KERNEL_AVX    1 /* traversal: bvh_avx.o */
#define GG_KERNEL_AVX2   2 /* traversal: bvh_avx2.o */
#define GG_KERNEL_AVX512 3 /* traversal: bvh_avx512.o */
typedef struct gg_kernel_table {
    int refract; /* ggRefract's copy */
    int reflect; /* ggReflection's */
    int fresnel; /* the dielectric and the conductor Fresnel reflectances' */
    int trav;    /* the BVH traversal's: the most a geometry takes; gg_geom_set_cpu
                    may restrict a geometry to less (its index, g->trav_avx) */
} gg_kernel_table;
/* The table, filled if need be (cpu.c): never NULL. */
const gg_kernel_table *gg_cpu_kernels_once(void);
#if GG_HAVE_ACQ_REL
/* The filled table, published with a release store; NULL before. */
extern const gg_kernel_table *gg_cpu_table;
GG_INLINE const gg_kernel_table *gg_cpu_kernels(void)
{
    const gg_kernel_table *k = GG_ATOMIC_LOAD_ACQ(&gg_cpu_table);
    return GG_LIKELY(k != NULL) ? k : gg_cpu_kernels_once();
}
#else
#define gg_cpu_kernels gg_cpu_kernels_once
#endif

#endif
