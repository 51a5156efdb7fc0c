/* SPDX-License-Identifier: MIT */
/*
** testutil.h -- shared helpers for the cmocka suites.
*/
#ifndef GG_TESTUTIL_H
#define GG_TESTUTIL_H

#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "ggrt.h"

/* Distance in units in the last place between two doubles (0 if equal,
   UINT64_MAX if either is NaN). */
uint64_t tu_ulps(double a, double b);

/* Deterministic PRNG (splitmix64) so failures reproduce. */
typedef struct tu_rng {
    uint64_t s;
} tu_rng;
uint64_t tu_next(tu_rng *r);
double tu_uniform(tu_rng *r);                  /* [0, 1) */
double tu_range(tu_rng *r, double lo, double hi);
ggVec3 tu_unit(tu_rng *r);                     /* uniform on the sphere */

/* Assert |a - b| <= tol * max(1, |a|, |b|) with a readable message. */
#define assert_close(a, b, tol) tu_assert_close((a), (b), (tol), #a, #b, __FILE__, __LINE__)
void tu_assert_close(double a, double b, double tol, const char *sa, const char *sb,
                     const char *file, int line);
#define assert_vec_close(a, b, tol)                                                              \
    do {                                                                                         \
        ggVec3 a_ = (a), b_ = (b);                                                               \
        tu_assert_close(a_.x, b_.x, (tol), #a ".x", #b ".x", __FILE__, __LINE__);                \
        tu_assert_close(a_.y, b_.y, (tol), #a ".y", #b ".y", __FILE__, __LINE__);                \
        tu_assert_close(a_.z, b_.z, (tol), #a ".z", #b ".z", __FILE__, __LINE__);                \
    } while (0)

/* The whole file at path, NUL-terminated, in malloc'd memory (the caller
   frees it); *len gets its size. Fails the test if it cannot be read. */
char *tu_slurp(const char *path, size_t *len);

/* A suite's scratch folder: tu_tmpdir_make creates a fresh
   /tmp/gg_test_NAME_XXXXXX (0 on success, -1 if it cannot: a cmocka group
   setup's return value), tu_tmpdir names it, tu_tmppath(file) is a path
   in it (four rotating buffers: at most four in use at once), and
   tu_tmpdir_remove deletes it with everything below it, read-only
   folders too (a group teardown). One folder per process. */
int tu_tmpdir_make(const char *name);
const char *tu_tmpdir(void);
const char *tu_tmppath(const char *file);
void tu_tmpdir_remove(void);

/* The scene file at path, loaded and prepared with the default
   allocator; fails the test, printing the path and the error, if either
   step does not return GG_OK. The caller frees it (ggSceneFree). */
ggScene *tu_load(const char *path);

/* Calls fn(path, ud) for every file in dir whose name ends in ext
   (".nff"), path being "dir/name"; returns how many. Fails the test if
   dir cannot be read. */
int tu_each_file(const char *dir, const char *ext, void (*fn)(const char *path, void *ud),
                 void *ud);

/* An allocator that fails exactly one allocation, for SQLite-style
   sweeps: run once counting what the code allocates (N), then for each
   k = 1 .. N run again with the k-th malloc or realloc returning NULL
   (and no other). Each counter is under a mutex, so worker threads may
   allocate through it. `live` counts the blocks not yet freed (a leak
   check where LeakSanitizer is not running). tu_failer_init makes one
   that never fails with its ggAllocator in f->alloc; tu_failer_arm
   zeroes count and failed and fails the k-th allocation from there (0:
   none); tu_failer_stop fails nothing more; tu_failer_done frees the
   mutex. Read the counters when no thread is allocating. */
typedef struct tu_failer {
    pthread_mutex_t mu;
    long count;        /* allocations since the last arm (or init) */
    long fail_at;      /* the one that fails (1-based); 0: none */
    long live;         /* blocks allocated and not freed */
    int failed;        /* the failure happened */
    ggAllocator alloc; /* allocates through this failer */
} tu_failer;
void tu_failer_init(tu_failer *f);
void tu_failer_arm(tu_failer *f, long k);
void tu_failer_stop(tu_failer *f);
void tu_failer_done(tu_failer *f);

/* The implicit surface expr = 0 in the box [lo, hi] (ggImplicitCreateExpr,
   the default allocator); fails the test, printing the expression and
   the error, if it is refused. The caller frees it (ggImplicitFree). */
ggImplicit *tu_implicit(const char *expr, ggVec3 lo, ggVec3 hi);

/* Path of the SPD scenes (GG_SPD_DIR or the repository's examples/scenes/spd). */
const char *tu_spd_dir(void);

#endif
