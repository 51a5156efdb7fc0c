/* SPDX-License-Identifier: MIT */
/*
** base.c -- version, status strings, error reporting, allocation, clock.
*/
/* madvise's MADV_HUGEPAGE is outside POSIX (the build's _POSIX_C_SOURCE). */
#if defined(__linux__) && !defined(_DEFAULT_SOURCE)
#define _DEFAULT_SOURCE 1
#endif
#include "core.h"
#include "vec.h"
/* GG_BUILD_ID: made by the Makefile under the build folder. */
#include "buildid.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <locale.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif
#include <time.h>
#include <unistd.h>

GG_API const char *ggVersion(void) { return GG_VERSION_STRING; }

GG_API const char *ggBuildId(void)
{
    return GG_BUILD_ID;
}

GG_API const char *ggStatusString(int code)
{
    switch (code) {
    case GG_OK: return "success";
    case GG_ERROR_INVALID: return "invalid argument";
    case GG_ERROR_NOMEM: return "out of memory";
    case GG_ERROR_PARSE: return "malformed input";
    case GG_ERROR_IO: return "input/output error";
    case GG_ERROR_UNSUPPORTED: return "not supported";
    case GG_ERROR_LIMIT: return "limit exceeded";
    case GG_ERROR_CANCELLED: return "cancelled";
    default: return "unknown status code";
    }
}

int gg_error_setv(ggError *err, int code, const char *fmt, va_list ap)
{
    if (err) {
        char raw[sizeof err->message];
        err->code = code;
        if (fmt) {
            vsnprintf(raw, sizeof raw, fmt, ap);
            gg_text_escape(err->message, sizeof err->message, raw, strlen(raw));
        } else
            snprintf(err->message, sizeof err->message, "%s", ggStatusString(code));
    }
    return code;
}

int gg_utf8_len(const unsigned char *s, size_t n)
{
    size_t k, i;
    unsigned c;
    if (!n) return 0;
    c = s[0];
    if (c < 0x80) return 1;
    if (c >= 0xc2 && c <= 0xdf)
        k = 2;
    else if (c >= 0xe0 && c <= 0xef)
        k = 3;
    else if (c >= 0xf0 && c <= 0xf4)
        k = 4;
    else
        return 0;
    if (k > n) return 0;
    for (i = 1; i < k; i++)
        if ((s[i] & 0xc0) != 0x80) return 0;
    if (k == 3 && ((c == 0xe0 && s[1] < 0xa0) || (c == 0xed && s[1] > 0x9f))) return 0;
    if (k == 4 && ((c == 0xf0 && s[1] < 0x90) || (c == 0xf4 && s[1] > 0x8f))) return 0;
    return (int)k;
}

GG_API int ggUTF8Length(const char *s, size_t n)
{
    return s ? gg_utf8_len((const unsigned char *)s, n) : 0;
}

GG_API bool ggUTF8Valid(const char *s, size_t n)
{
    size_t i = 0;
    if (!s) return false;
    while (i < n) {
        int len = gg_utf8_len((const unsigned char *)s + i, n - i);
        if (!len) return false;
        i += (size_t)len;
    }
    return true;
}

size_t gg_text_escape(char *dst, size_t size, const char *src, size_t n)
{
    static const char hex[] = "0123456789ABCDEF";
    const unsigned char *s = (const unsigned char *)src;
    size_t i = 0, k = 0;
    if (!size) return 0;
    while (i < n) {
        int len = gg_utf8_len(s + i, n - i);
        if (len == 1 && (s[i] < 0x20 || s[i] == 0x7f)) len = 0;
        if (len == 0) {
            if (k + 4 >= size) break;
            dst[k++] = '\\', dst[k++] = 'x';
            dst[k++] = hex[s[i] >> 4], dst[k++] = hex[s[i] & 15];
            i++;
        } else {
            if (k + (size_t)len >= size) break;
            memcpy(dst + k, s + i, (size_t)len);
            k += (size_t)len, i += (size_t)len;
        }
    }
    dst[k] = '\0';
    return k;
}

int gg_error_set(ggError *err, int code, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    gg_error_setv(err, code, fmt, ap);
    va_end(ap);
    return code;
}

size_t gg_strtod_c(const char *s, size_t n, double *out)
{
    char buf[400], *e;
    const char *dp = localeconv()->decimal_point;
    size_t i;
    *out = 0;
    if (n >= sizeof buf) return 0;
    memcpy(buf, s, n);
    buf[n] = '\0';
    if (dp && dp[0] && dp[0] != '.' && dp[1] == 0)
        for (i = 0; i < n; i++)
            if (buf[i] == '.') buf[i] = dp[0];
    *out = strtod(buf, &e);
    return (size_t)(e - buf);
}

/* A large block of the C library's allocator, not yet touched: on Linux,
   ask for transparent huge pages over it, so that the first touch of
   each 2 MB is one page fault, not 512 (each costs microseconds, more in
   a virtual machine). The hint covers every page the block lies in: a
   hint on its 2 MB-aligned interior alone split the C library's mapping
   of the block in three, and glibc's realloc then failed to move it
   (mremap: EFAULT) and copied it instead, every time a growing array
   doubled (parsing torus-1m.nff: 1.19 s against 0.48 s). A hint:
   the kernel may refuse it (THP "never"), and nothing depends on its
   answer. A caller's allocator's memory is its own and is left alone. */
#define HUGE_BLOCK ((size_t)4 << 20)

static void *huge_hint(void *p, size_t size)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    long pg = sysconf(_SC_PAGESIZE);
    if (p && size >= HUGE_BLOCK && pg > 0) {
        const uintptr_t m = (uintptr_t)pg - 1;
        uintptr_t a = (uintptr_t)p & ~m, e = ((uintptr_t)p + size + m) & ~m;
        (void)madvise((void *)a, (size_t)(e - a), MADV_HUGEPAGE);
    }
#else
    (void)size;
#endif
    return p;
}

void *gg_mem_alloc(const ggAllocator *a, size_t size)
{
    if (size == 0) size = 1;
    return a ? a->malloc(a->ud, size) : huge_hint(malloc(size), size);
}

void *gg_mem_calloc(const ggAllocator *a, size_t n, size_t size)
{
    void *p;
    if (size && n > (size_t)-1 / size) return NULL;
    /* The C library's calloc gets large blocks from the OS already zero
       (mmap): no pass over a 12 MB image before the render writes it. */
    if (!a) return n && size ? huge_hint(calloc(n, size), n * size) : calloc(1, 1);
    p = gg_mem_alloc(a, n * size);
    if (p && n * size > 0) memset(p, 0, n * size);
    return p;
}

void *gg_mem_realloc(const ggAllocator *a, void *p, size_t size)
{
    if (size == 0) size = 1;
    return a ? a->realloc(a->ud, p, size) : huge_hint(realloc(p, size), size);
}

void gg_mem_free(const ggAllocator *a, void *p)
{
    if (!p) return;
    if (a)
        a->free(a->ud, p);
    else
        free(p);
}

int gg_mem_grow(const ggAllocator *a, void **arr, size_t *cap, size_t need, size_t elem)
{
    size_t ncap;
    void *np;
    if (need <= *cap) return 0;
    ncap = *cap ? *cap : 8;
    while (ncap < need) {
        if (ncap > ((size_t)-1 / 2) / elem) return -1;
        ncap *= 2;
    }
    if (ncap > (size_t)-1 / elem) return -1;
    np = gg_mem_realloc(a, *arr, ncap * elem);
    if (!np) return -1;
    *arr = np;
    *cap = ncap;
    return 0;
}

char *gg_mem_strdup(const ggAllocator *a, const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = gg_mem_alloc(a, n);
    if (d) memcpy(d, s, n);
    return d;
}

/* A count as a long: v scaled by 2^k, k the same for the three values
   of a part, so that `of` fits. */
static int progress_shift(uint64_t of)
{
    int k = 0;
    while ((of >> k) > (uint64_t)LONG_MAX) k++;
    return k;
}

void gg_progress_part(gg_progress *p, ggProgressFn fn, void *ud, uint64_t lo, uint64_t hi,
                      uint64_t of)
{
    int k = progress_shift(of);
    p->fn = fn, p->ud = ud;
    p->lo = (long)(lo >> k), p->hi = (long)(hi >> k), p->of = (long)(of >> k);
    p->last = p->lo, p->stopped = 0;
}

int gg_progress_to(gg_progress *p, uint64_t done, uint64_t total)
{
    long v = p->hi;
    if (p->stopped || !p->fn) return p->stopped;
    if (done < total) {
        double f = (double)done / (double)total;
        v = p->lo + (long)(f * (double)(p->hi - p->lo));
        if (v > p->hi) v = p->hi;
    }
    if (v < p->last) v = p->last;
    p->last = v;
    if (p->fn(p->ud, v, p->of)) p->stopped = 1;
    return p->stopped;
}

double gg_time_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double gg_time_cpu(void)
{
#ifdef CLOCK_THREAD_CPUTIME_ID
    struct timespec ts;
    if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) == 0)
        return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
#endif
    return gg_time_now();
}

int gg_file_open(const char *path, const char *verb, FILE **out, int64_t *size, ggError *err)
{
    char ebuf[128];
    struct stat st;
    FILE *f;
    /* O_NONBLOCK changes nothing for a regular file's reads. */
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC), e;
    if (fd < 0 || fstat(fd, &st) != 0) {
        e = errno;
        if (fd >= 0) close(fd);
        if (strerror_r(e, ebuf, sizeof ebuf) != 0) snprintf(ebuf, sizeof ebuf, "error %d", e);
        return gg_error_set(err, GG_ERROR_IO, "%s: %s%s%s", path, verb ? verb : "",
                            verb ? ": " : "", ebuf);
    }
    if (!S_ISREG(st.st_mode)) {
        close(fd);
        return gg_error_set(err, GG_ERROR_IO, "%s: not a regular file", path);
    }
    if (!(f = fdopen(fd, "rb"))) {
        e = errno;
        close(fd);
        if (e == ENOMEM) return gg_error_set(err, GG_ERROR_NOMEM, "%s: out of memory", path);
        if (strerror_r(e, ebuf, sizeof ebuf) != 0) snprintf(ebuf, sizeof ebuf, "error %d", e);
        return gg_error_set(err, GG_ERROR_IO, "%s: %s", path, ebuf);
    }
    if (size) *size = (int64_t)st.st_size;
    *out = f;
    return GG_OK;
}

/* ---- vec.h's slow path ---- */

/* (zero and NaN come here too, and keep v3norm's answer) */
ggVec3 gg_vec_norm_scaled(ggVec3 a)
{
    int k;
    ggVec3 b = v3tame(a, &k);     /* tiny: its largest component now in [1, 2) */
    double l = sqrt(v3dot(b, b)); /* a unit vector: 2^k cancels */
    return l > 0 ? v3scale(b, 1.0 / l) : a;
}

/* ---- hashing (core.h) ---- */

uint64_t gg_hash_seed(const void *p)
{
    volatile char here = 0;
    uint64_t a = (uint64_t)(uintptr_t)p, b = (uint64_t)(uintptr_t)&here;
    return gg_hash_word(gg_hash_word(0x243f6a8885a308d3ull, a), b ^ here);
}

uint64_t gg_hash_bytes(uint64_t seed, const void *p, size_t n)
{
    const unsigned char *c = p;
    uint64_t h = seed, w;
    size_t i;
    for (i = 0; i + 8 <= n; i += 8) {
        memcpy(&w, c + i, 8);
        h = gg_hash_word(h, w);
    }
    for (w = 0; i < n; i++) w = w << 8 | c[i];
    return gg_hash_word(gg_hash_word(h, w), n);
}
