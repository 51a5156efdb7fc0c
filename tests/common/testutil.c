/* SPDX-License-Identifier: MIT */
#include "testutil.h"

#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

uint64_t tu_ulps(double a, double b)
{
    int64_t ia, ib;
    if (isnan(a) || isnan(b)) return UINT64_MAX;
    if (a == b) return 0;
    memcpy(&ia, &a, 8);
    memcpy(&ib, &b, 8);
    /* Map the sign-magnitude bit patterns onto a monotonic integer line. */
    if (ia < 0) ia = INT64_MIN - ia;
    if (ib < 0) ib = INT64_MIN - ib;
    return ia > ib ? (uint64_t)ia - (uint64_t)ib : (uint64_t)ib - (uint64_t)ia;
}

uint64_t tu_next(tu_rng *r)
{
    uint64_t z = (r->s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

double tu_uniform(tu_rng *r) { return (double)(tu_next(r) >> 11) * 0x1.0p-53; }

double tu_range(tu_rng *r, double lo, double hi) { return lo + (hi - lo) * tu_uniform(r); }

ggVec3 tu_unit(tu_rng *r)
{
    double z = tu_range(r, -1, 1), phi = tu_range(r, 0, 6.283185307179586);
    double s = sqrt(1 - z * z);
    ggVec3 v;
    v.x = s * cos(phi), v.y = s * sin(phi), v.z = z;
    return v;
}

void tu_assert_close(double a, double b, double tol, const char *sa, const char *sb,
                     const char *file, int line)
{
    double m = fabs(a) > fabs(b) ? fabs(a) : fabs(b);
    if (m < 1) m = 1;
    if (!(fabs(a - b) <= tol * m)) {
        print_error("%s = %.17g, %s = %.17g, differ by %.3g (tolerance %.3g)\n", sa, a, sb, b,
                    fabs(a - b), tol * m);
        _fail(file, line);
    }
}

char *tu_slurp(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    char *buf;
    long n;
    assert_non_null(f);
    assert_int_equal(fseek(f, 0, SEEK_END), 0);
    n = ftell(f);
    assert_true(n >= 0);
    assert_int_equal(fseek(f, 0, SEEK_SET), 0);
    buf = malloc((size_t)n + 1);
    assert_non_null(buf);
    assert_int_equal(fread(buf, 1, (size_t)n, f), (size_t)n);
    fclose(f);
    buf[n] = '\0';
    *len = (size_t)n;
    return buf;
}

const char *tu_spd_dir(void)
{
    const char *d = getenv("GG_SPD_DIR");
    return d && *d ? d : "examples/scenes/spd";
}

static char tmpdir[64];

int tu_tmpdir_make(const char *name)
{
    snprintf(tmpdir, sizeof tmpdir, "/tmp/gg_test_%.20s_XXXXXX", name);
    return mkdtemp(tmpdir) ? 0 : -1;
}

const char *tu_tmpdir(void)
{
    return tmpdir;
}

const char *tu_tmppath(const char *file)
{
    static char buf[4][512];
    static int k;
    k = (k + 1) % 4;
    snprintf(buf[k], sizeof buf[k], "%s/%s", tmpdir, file);
    return buf[k];
}

/* Everything below dir (made writable first, so a test's read-only
   folder goes too). */
static void clear_dir(const char *dir)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    char p[512];
    while (d && (e = readdir(d))) {
        if (e->d_name[0] == '.' && (!e->d_name[1] || (e->d_name[1] == '.' && !e->d_name[2])))
            continue;
        snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
        chmod(p, 0700);
        clear_dir(p);
        if (remove(p) != 0) rmdir(p);
    }
    if (d) closedir(d);
}

void tu_tmpdir_remove(void)
{
    if (!tmpdir[0]) return;
    clear_dir(tmpdir);
    rmdir(tmpdir);
    tmpdir[0] = 0;
}

int tu_each_file(const char *dir, const char *ext, void (*fn)(const char *path, void *ud), void *ud)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    char path[512];
    size_t m = strlen(ext);
    int n = 0;
    if (!d) fail_msg("cannot open %s", dir);
    while ((e = readdir(d)) != NULL) {
        size_t len = strlen(e->d_name);
        if (len > m && strcmp(e->d_name + len - m, ext) == 0) {
            snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
            fn(path, ud);
            n++;
        }
    }
    closedir(d);
    return n;
}

ggScene *tu_load(const char *path)
{
    ggScene *s = ggSceneCreate(NULL);
    ggError e;
    int rc;
    assert_non_null(s);
    if ((rc = ggSceneLoadFile(s, path, &e)) == GG_OK) rc = ggScenePrepare(s, &e);
    if (rc != GG_OK) print_error("%s: %s\n", path, e.message);
    assert_int_equal(rc, GG_OK);
    return s;
}

/* ---- the failing allocator ---- */

static int fail_now(tu_failer *f)
{
    int r;
    pthread_mutex_lock(&f->mu);
    r = ++f->count == f->fail_at;
    if (r) f->failed = 1;
    pthread_mutex_unlock(&f->mu);
    return r;
}

static void live_add(tu_failer *f, long d)
{
    pthread_mutex_lock(&f->mu);
    f->live += d;
    pthread_mutex_unlock(&f->mu);
}

static void *failer_malloc(void *ud, size_t n)
{
    void *p;
    if (fail_now(ud)) return NULL;
    if ((p = malloc(n))) live_add(ud, 1);
    return p;
}

static void *failer_realloc(void *ud, void *p, size_t n)
{
    void *q;
    if (fail_now(ud)) return NULL;
    q = realloc(p, n);
    if (q && !p) live_add(ud, 1);
    return q;
}

static void failer_free(void *ud, void *p)
{
    if (p) live_add(ud, -1);
    free(p);
}

void tu_failer_init(tu_failer *f)
{
    memset(f, 0, sizeof *f);
    assert_int_equal(pthread_mutex_init(&f->mu, NULL), 0);
    f->alloc.malloc = failer_malloc, f->alloc.realloc = failer_realloc;
    f->alloc.free = failer_free, f->alloc.ud = f;
}

void tu_failer_arm(tu_failer *f, long k)
{
    pthread_mutex_lock(&f->mu);
    f->count = 0, f->failed = 0, f->fail_at = k;
    pthread_mutex_unlock(&f->mu);
}

void tu_failer_stop(tu_failer *f)
{
    pthread_mutex_lock(&f->mu);
    f->fail_at = 0;
    pthread_mutex_unlock(&f->mu);
}

void tu_failer_done(tu_failer *f)
{
    pthread_mutex_destroy(&f->mu);
}

ggImplicit *tu_implicit(const char *expr, ggVec3 lo, ggVec3 hi)
{
    ggImplicit *imp = NULL;
    ggError err;
    int rc = ggImplicitCreateExpr(expr, lo, hi, NULL, &imp, &err);
    if (rc != GG_OK) print_error("creating \"%s\": %s\n", expr, err.message);
    assert_int_equal(rc, GG_OK);
    return imp;
}
