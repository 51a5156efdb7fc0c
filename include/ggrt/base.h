/* SPDX-License-Identifier: MIT */
/*
** ggrt/base.h -- version, export macro, status codes, errors, allocator and
** the plain math types every other ggrt header uses.
**
** Conventions (the whole library follows them):
**  - Math types are plain structs of double passed by value.
**  - Big objects are opaque handles with a create/free pair; freeing NULL is
**    a no-op.
**  - Functions that can fail return an int status: GG_OK (0) or a GG_ERROR_*
**    code. Those that can say more take an optional `ggError *` that receives
**    the code and a message naming what and where, e.g.
**    "scene.nff:12:5: expected a number after 's'". Pass NULL to ignore it.
**  - The library never prints, exits or aborts.
**
** The API rules. Every public function follows these three; a declaration
** only adds what is particular to it. tests/api/test_null.c calls every
** GG_API function with NULL handles and fails if one is left out.
**  1. NULL. Freeing NULL is a no-op. Any other function given NULL for a
**     handle (ggScene, ggImage, ggImplicit, ggTrace, ggPredicate, ggLedger,
**     a result) or for a pointer it cannot do without (a path, a text, an
**     output) does nothing, writes no output and returns GG_ERROR_INVALID
**     if it returns a status (-GG_ERROR_INVALID if it returns an index),
**     otherwise the neutral value of its type: 0 for counts, sizes and bit
**     sets, -1 for an index or kind, false, NULL, "" for a file name,
**     black for a colour, an all-zero struct, NaN for a value or gradient
**     of f (implicit.h); void setters do nothing. Pointers a declaration
**     calls optional ("may be NULL": err, stats, alloc, options, ...) are
**     never required. Where a declaration says an output is NULL or
**     zeroed on failure, that is for the failures after these checks: a
**     call given a NULL handle or output leaves every output as it was.
**  2. Statistics. A function that takes a ggRayStats *stats (ggRender,
**     ggTracePixel, ggRayColor) overwrites it, never adds to it: on return
**     -- success or failure -- it holds the counts of that call alone
**     (all zero when the call cast no ray). Add the structs yourself to
**     total several calls.
**  3. Allocators. A function that takes a const ggAllocator *alloc copies
**     the struct (its three functions and ud): the caller may reuse or
**     discard its ggAllocator variable at once, but the functions and
**     what ud points to must stay valid while any object made with them
**     lives. Objects a scene makes (rendered images, textures, results of
**     ggFind, ggCheck and ggDiff) use a copy of the scene's allocator, so
**     they may outlive the scene. A function that takes ownership of an
**     object (ggSceneAddTexture, ggSceneAddImplicit) frees it also when it
**     fails, NULL scene included.
*/
#ifndef GGRT_BASE_H
#define GGRT_BASE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* GG_API marks the exported functions; everything else in libggrt.so is
   hidden (the library is built with -fvisibility=hidden). */
#if defined(_WIN32) && defined(GG_BUILDING_DLL)
#define GG_API __declspec(dllexport)
#elif defined(__GNUC__) && __GNUC__ >= 4
#define GG_API __attribute__((visibility("default")))
#else
#define GG_API
#endif

#define GG_VERSION_MAJOR  0
#define GG_VERSION_MINOR  1
#define GG_VERSION_PATCH  0
#define GG_VERSION_STRING "0.1.0"

/* Returns GG_VERSION_STRING of the library actually linked. */
GG_API const char *ggVersion(void);

/* The identity of the library's build: "src-" and the POSIX cksum (a
   CRC-32) of the sources it was compiled from, lib/ and include/, their
   names and bytes, as the Makefile computes it. Two builds of the same
   sources have the same id, whatever the machine or compiler; a change
   to any source changes it (but for a CRC collision, 1 in 2^32). The
   version does not change between releases; this does. ggrt's tiles,
   reports and plans record it, and files of two builds are not merged
   (docs/cluster.md). Static storage, never NULL. */
GG_API const char *ggBuildId(void);

/* ------------------------------------------------------------------ */
/* Status codes                                                        */
/* ------------------------------------------------------------------ */

#define GG_OK                0 /* success */
#define GG_ERROR_INVALID     1 /* an argument is invalid (NULL, NaN, out of range) */
#define GG_ERROR_NOMEM       2 /* an allocation failed */
#define GG_ERROR_PARSE       3 /* malformed input (scene text, expression, image) */
#define GG_ERROR_IO          4 /* a file could not be opened, read or written */
#define GG_ERROR_UNSUPPORTED 5 /* valid but not supported (e.g. an image format) */
#define GG_ERROR_LIMIT       6 /* input exceeds a documented limit (size, count) */
#define GG_ERROR_CANCELLED   7 /* a callback asked to stop */

/* A fixed English description of a status code ("out of memory"); never
   NULL, also for unknown codes. */
GG_API const char *ggStatusString(int code);

/* UTF-8 as the library reads and shows text (file names, tokens, the
   messages of ggError, which show every other byte as the text \xHH):
   well-formed is RFC 3629's -- no overlong forms, no surrogates
   (U+D800..U+DFFF), nothing above U+10FFFF.
   ggUTF8Length: the length in bytes (1 to 4) of the well-formed sequence
   that begins s[0..n); 0 when s[0..n) does not begin with one (a stray
   continuation byte, a sequence cut short by n) and when n is 0. A byte
   below 0x80, NUL included, is a sequence of length 1.
   ggUTF8Valid: true when s[0..n) is well-formed sequences end to end
   (n == 0 is), else false. */
GG_API int ggUTF8Length(const char *s, size_t n);
GG_API bool ggUTF8Valid(const char *s, size_t n);

/* Receives the details of a failure. `code` repeats the returned status;
   `message` is NUL-terminated and names the place ("file:line:col: ...")
   when there is one. */
typedef struct ggError {
    int code;
    char message[512];
} ggError;

/* Progress of a long step: done out of total (done never decreases within
   a step, and done <= total). Return non-zero to cancel: the step then
   returns GG_ERROR_CANCELLED. Each function that takes one says its
   units, how often it calls, and what a cancel leaves (ggRender: pixels,
   render.h; loading and preparing a scene: ggSceneSetProgress, scene.h).
   `ud` is passed back unchanged. */
typedef int (*ggProgressFn)(void *ud, long done, long total);

/* ------------------------------------------------------------------ */
/* Allocator                                                           */
/* ------------------------------------------------------------------ */

/* Every object that allocates takes an optional allocator; NULL means the C
   library's malloc/realloc/free. The three functions behave like their C
   counterparts; `ud` is passed back unchanged. free(ud, NULL) must be a no-op.
   The struct is copied (rule 3 above); its functions and ud must outlive
   every object created with it, and be thread-safe if objects created with
   it are used from several threads. */
typedef struct ggAllocator {
    void *(*malloc)(void *ud, size_t size);
    void *(*realloc)(void *ud, void *ptr, size_t size);
    void (*free)(void *ud, void *ptr);
    void *ud;
} ggAllocator;

/* ------------------------------------------------------------------ */
/* Math types                                                          */
/* ------------------------------------------------------------------ */

typedef struct ggVec3 {
    double x, y, z;
} ggVec3;

/* Linear RGB radiance or reflectance. */
typedef struct ggColor {
    double r, g, b;
} ggColor;

/* A ray o + t d. d need not be unit length unless a function says so:
   any finite nonzero d, 1e-300 or 1e300 long as well (t then scales with
   it, and may overflow). */
typedef struct ggRay {
    ggVec3 o, d;
} ggRay;

#ifdef __cplusplus
}
#endif
#endif /* GGRT_BASE_H */
