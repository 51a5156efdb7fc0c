/* SPDX-License-Identifier: MIT */
/*
** test_nomem.c -- allocation failure everywhere, after SQLite's malloc
** tests: for every k, an allocator that fails exactly its k-th allocation
** (and no other) runs one whole pipeline on an example scene:
**   create the scene, load it (from the file, or from memory), prepare,
**   render 32x24 with 1 and with 2 threads, create a trace and trace the
**   centre pixel (every sample), write the image as PNG and as EXR and
**   read both back.
** Every step must return GG_OK or GG_ERROR_NOMEM. After a GG_ERROR_NOMEM
** the step's object must be as its header says (a failed load leaves the
** scene's counts and camera as they were, a failed render or read stores
** no image, a failed write leaves no file and no temporary behind); then
** failures are switched off and the step is done again, so the rest of
** the pipeline also checks that the failure left nothing half-done.
** Whatever failed, the final render, pixel trace and both read-back
** images must be bit-identical to the run without failures -- in
** particular when every step said GG_OK: that would be a silent loss.
** LeakSanitizer (the asan build of make check) checks every path's frees.
**
** Every allocation site of every phase is hit: the sweep is not strided.
** The run without failures counts the allocations the pipeline makes
** (N); the sweep runs k = 1, 2, ... and stops at the first k that the
** pipeline never reaches, so each of the N allocations -- each site, as
** often as it runs -- fails once. The pipeline's allocations are
** deterministic (the worker threads of ggRender allocate nothing; the
** counter is locked anyway). The test prints N per scene. libpng's and
** OpenEXR's own allocations (through malloc, not a ggAllocator: OpenEXR's
** hook takes no user pointer) are outside the sweep; the buffers ggrt
** allocates around them are in it.
*/
#include "testutil.h"

#include <dirent.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define W 32
#define H 24

typedef struct scene_case {
    const char *path; /* examples/scenes/... */
    int from_memory;  /* ggSceneLoadString on the file's text */
    const char *what;
} scene_case;

/* What one pipeline produced. */
typedef struct result {
    ggImage *img, *png, *exr; /* render; PNG and EXR read back */
    ggColor pixel;            /* ggTracePixel of the centre */
    size_t nodes, lights;     /* its trace */
    int nomem;                /* steps that said GG_ERROR_NOMEM */
    const char *where;        /* the last of them */
} result;

static char tmpdir[64];

static int count_entries(void)
{
    DIR *d = opendir(tmpdir);
    struct dirent *e;
    int n = 0;
    while (d && (e = readdir(d)))
        if (e->d_name[0] != '.') n++;
    if (d) closedir(d);
    return n;
}

/* The scene's text, with texture names made relative to the working
   directory (ggSceneLoadString resolves them there). */
static char *scene_text(const char *path, size_t *len)
{
    size_t n, i, o = 0, dl;
    char *src = tu_slurp(path, &n), *dst, *slash = strrchr(path, '/');
    dl = slash ? (size_t)(slash - path + 1) : 0;
    dst = malloc(n * (dl + 1) + 1);
    assert_non_null(dst);
    for (i = 0; i < n; i++) {
        dst[o++] = src[i];
        if (src[i] == '"' && i >= 8 && memcmp(src + i - 8, "texture ", 8) == 0)
            memcpy(dst + o, path, dl), o += dl;
    }
    free(src);
    *len = o;
    return dst;
}

/* Each step: its status is GG_OK or GG_ERROR_NOMEM; a NOMEM is counted,
   failing is switched off, and the caller repeats the step. */
static int failed_step(int rc, tu_failer *f, result *r, const char *where)
{
    assert_true(rc == GG_OK || rc == GG_ERROR_NOMEM);
    if (rc == GG_OK) return 0;
    r->nomem++, r->where = where;
    tu_failer_stop(f);
    return 1;
}

static ggScene *load(const scene_case *c, tu_failer *f, const ggAllocator *a, result *r)
{
    ggScene *s;
    ggError e;
    ggCamera cam0, cam1;
    int rc;
    while (!(s = ggSceneCreate(a))) {
        r->nomem++;
        tu_failer_stop(f);
    }
    cam0 = ggSceneCamera(s);
    for (;;) {
        if (c->from_memory) {
            size_t len;
            char *text = scene_text(c->path, &len);
            rc = ggSceneLoadString(s, text, len, c->path, &e);
            free(text);
        } else {
            rc = ggSceneLoadFile(s, c->path, &e);
        }
        if (!failed_step(rc, f, r, "load")) break;
        /* the message says what ran out (base.h: "naming what and where") */
        if (!strstr(e.message, "out of memory")) fail_msg("load: NOMEM said '%s'", e.message);
        /* "On error the scene is left as it was before the call" */
        assert_int_equal(ggSceneObjectCount(s), 0);
        assert_int_equal(ggSceneLightCount(s), 0);
        assert_int_equal(ggSceneMaterialCount(s), 0);
        assert_int_equal(ggSceneMeshCount(s), 0);
        assert_string_equal(ggSceneFileName(s), "");
        cam1 = ggSceneCamera(s);
        assert_memory_equal(&cam0, &cam1, sizeof cam0);
    }
    if (!c->from_memory) assert_string_equal(ggSceneFileName(s), c->path);
    do rc = ggScenePrepare(s, &e);
    while (failed_step(rc, f, r, "prepare"));
    return s;
}

static ggImage *render(ggScene *s, int threads, tu_failer *f, result *r)
{
    ggRenderOptions o;
    ggImage *img;
    ggError e;
    int rc;
    ggRenderOptionsDefault(&o);
    o.width = W, o.height = H, o.threads = threads;
    for (;;) {
        img = (ggImage *)&o; /* must be overwritten */
        rc = ggRender(s, &o, &img, NULL, &e);
        if (!failed_step(rc, f, r, "render")) break;
        assert_null(img);
    }
    assert_non_null(img);
    return img;
}

static void trace(ggScene *s, const ggAllocator *a, tu_failer *f, result *r)
{
    ggRenderOptions o;
    ggTrace *t;
    ggError e;
    int rc;
    ggRenderOptionsDefault(&o);
    o.width = W, o.height = H, o.threads = 1;
    while (!(t = ggTraceCreate(a))) {
        r->nomem++;
        tu_failer_stop(f);
    }
    for (;;) {
        rc = ggTracePixel(s, &o, W / 2, H / 2, -1, t, &r->pixel, NULL, &e);
        if (!failed_step(rc, f, r, "trace")) break;
        /* no partial tree (trace.h) */
        assert_int_equal(ggTraceNodeCount(t), 0);
        assert_int_equal(ggTraceLightCount(t), 0);
    }
    r->nodes = ggTraceNodeCount(t), r->lights = ggTraceLightCount(t);
    ggTraceFree(t);
}

static ggImage *write_read(const ggImage *img, const char *name, const ggAllocator *a, tu_failer *f,
                           result *r)
{
    char path[128];
    ggImage *back;
    ggError e;
    int rc, before = count_entries();
    struct stat st;
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    for (;;) {
        rc = ggImageWrite(img, path, &e);
        if (!failed_step(rc, f, r, "write")) break;
        assert_int_equal(count_entries(), before); /* no file, no temporary */
    }
    assert_int_equal(stat(path, &st), 0);
    for (;;) {
        back = (ggImage *)path;
        rc = ggImageRead(path, a, &back, &e);
        if (!failed_step(rc, f, r, "read")) break;
        assert_ptr_equal(back, (ggImage *)path); /* untouched */
    }
    assert_int_equal(remove(path), 0);
    return back;
}

static void pipeline(const scene_case *c, tu_failer *f, result *r)
{
    const ggAllocator a = f->alloc;
    ggScene *s;
    ggImage *two;
    memset(r, 0, sizeof *r);
    s = load(c, f, &a, r);
    r->img = render(s, 1, f, r);
    two = render(s, 2, f, r);
    assert_memory_equal(ggImagePixelsConst(two), ggImagePixelsConst(r->img),
                        W * H * 3 * sizeof(float));
    ggImageFree(two);
    trace(s, &a, f, r);
    r->png = write_read(r->img, "out.png", &a, f, r);
    r->exr = write_read(r->img, "out.exr", &a, f, r);
    ggSceneFree(s);
}

static void result_free(result *r)
{
    ggImageFree(r->img), ggImageFree(r->png), ggImageFree(r->exr);
}

static void same_image(const ggImage *a, const ggImage *b)
{
    assert_int_equal(ggImageWidth(a), ggImageWidth(b));
    assert_int_equal(ggImageHeight(a), ggImageHeight(b));
    assert_memory_equal(ggImagePixelsConst(a), ggImagePixelsConst(b),
                        (size_t)ggImageWidth(a) * ggImageHeight(a) * 3 * sizeof(float));
}

static void sweep(const scene_case *c)
{
    tu_failer f;
    result ref, r;
    long k, points = 0, total, nomem = 0;
    ggColor px;
    const char *only = getenv("GG_NOMEM_ONLY"); /* debugging: one scene */
    if (only && !strstr(c->path, only)) return;
    tu_failer_init(&f);
    pipeline(c, &f, &ref);
    total = f.count;
    assert_int_equal(ref.nomem, 0);
    /* the trace reproduces the render's pixel bit for bit (trace.h) */
    px = ggImageGet(ref.img, W / 2, H / 2);
    assert_memory_equal(&px, &ref.pixel, sizeof px);
    same_image(ref.exr, ref.img);
    for (k = 1;; k++) {
        tu_failer_arm(&f, k);
        pipeline(c, &f, &r);
        if (!f.failed) {
            result_free(&r);
            break;
        }
        points++;
        if (r.nomem) nomem++;
        if (!r.nomem && getenv("GG_NOMEM_VERBOSE"))
            printf("test_nomem: %s: allocation %ld absorbed\n", c->what, k);
        if (memcmp(ggImagePixelsConst(r.img), ggImagePixelsConst(ref.img),
                   W * H * 3 * sizeof(float)))
            printf("test_nomem: %s: allocation %ld of %ld failed (%s), the render differs\n",
                   c->what, k, total, r.nomem ? r.where : "every step said GG_OK");
        same_image(r.img, ref.img);
        same_image(r.png, ref.png);
        same_image(r.exr, ref.exr);
        assert_memory_equal(&r.pixel, &ref.pixel, sizeof px);
        assert_int_equal(r.nodes, ref.nodes);
        assert_int_equal(r.lights, ref.lights);
        result_free(&r);
    }
    assert_int_equal(points, total);
    printf("test_nomem: %s: %ld allocation failure points (of %ld allocations); %ld reported "
           "GG_ERROR_NOMEM, %ld absorbed with the same result; 0 silent losses\n",
           c->what, points, total, nomem, points - nomem);
    result_free(&ref);
    tu_failer_done(&f);
}

/* ggFind and ggFindPath on their own: the scene is loaded and prepared
   without failures, then every allocation of one find (its result, the
   workers' lists, a render or path layers) fails in turn. Each must say
   GG_OK or GG_ERROR_NOMEM; after NOMEM *out is NULL and the find done
   again gives the reference's matches. */
typedef struct find_case {
    const char *expr; /* a predicate, or a path expression when `path` */
    int path, threads;
} find_case;

static int find_once(ggScene *s, const find_case *c, ggFindResult **out)
{
    ggRenderOptions o;
    ggError e;
    int rc;
    ggRenderOptionsDefault(&o);
    o.width = W, o.height = H, o.threads = c->threads;
    *out = (ggFindResult *)&o; /* must be overwritten */
    if (c->path) {
        ggPathExpr *x = NULL;
        assert_int_equal(ggPathParse(c->expr, NULL, &x, NULL), GG_OK);
        rc = ggFindPath(s, &o, x, 1000, out, &e);
        ggPathFree(x);
    } else {
        ggPredicate *p = NULL;
        assert_int_equal(ggPredicateParse(c->expr, NULL, &p, NULL), GG_OK);
        rc = ggFind(s, &o, p, 1000, out, &e);
        ggPredicateFree(p);
    }
    assert_true(rc == GG_OK || rc == GG_ERROR_NOMEM);
    if (rc != GG_OK) assert_null(*out);
    return rc;
}

static void same_find(const ggFindResult *a, const ggFindResult *b)
{
    assert_int_equal(a->scanned, b->scanned);
    assert_int_equal(a->matched, b->matched);
    assert_int_equal(a->nmatches, b->nmatches);
    assert_memory_equal(a->mask, b->mask, (size_t)a->width * a->height);
    if (a->nmatches) assert_memory_equal(a->matches, b->matches, a->nmatches * sizeof *a->matches);
}

static void find_sweep(const find_case *c)
{
    tu_failer f;
    ggScene *s;
    ggFindResult *ref, *r;
    long k, total, nomem = 0;
    tu_failer_init(&f);
    s = ggSceneCreate(&f.alloc);
    assert_non_null(s);
    assert_int_equal(ggSceneLoadFile(s, "examples/scenes/glass.nff", NULL), GG_OK);
    assert_int_equal(ggScenePrepare(s, NULL), GG_OK);
    tu_failer_arm(&f, 0);
    assert_int_equal(find_once(s, c, &ref), GG_OK);
    total = f.count;
    assert_true(ref->matched > 0);
    /* with 2 threads the workers' lists grow in either order: the count
       of allocations may differ from run to run, so every k up to the
       reference's count is tried, and one more */
    for (k = 1; k <= total + 1; k++) {
        tu_failer_arm(&f, k);
        if (find_once(s, c, &r) != GG_OK) {
            nomem++;
            tu_failer_stop(&f);
            assert_int_equal(find_once(s, c, &r), GG_OK);
        }
        if (c->threads == 1) assert_int_equal(f.failed, k <= total);
        same_find(r, ref);
        ggFindResultFree(r);
    }
    printf("test_nomem: %s '%s', %d thread(s): %ld allocation failure points, %ld reported "
           "GG_ERROR_NOMEM\n",
           c->path ? "ggFindPath" : "ggFind", c->expr, c->threads, total, nomem);
    ggFindResultFree(ref);
    ggSceneFree(s);
    tu_failer_done(&f);
}

static void test_find(void **state)
{
    /* a ray-tree predicate (the scan), a pixel predicate (a render), a
       path expression with a predicate (the scan) and one without (path
       layers) */
    static const find_case cases[] = {
        {"some(kind == refract)", 0, 1}, {"some(kind == refract)", 0, 2}, {"pixel > 0.2", 0, 1},
        {"C.*<RS'tir'>.*", 1, 1},        {"C.*<TS>[depth < 9].*", 1, 2},  {"C.*T.*", 1, 1},
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) find_sweep(&cases[i]);
}

static int setup(void **state)
{
    (void)state;
    snprintf(tmpdir, sizeof tmpdir, "/tmp/gg_test_nomem_XXXXXX");
    return mkdtemp(tmpdir) ? 0 : -1;
}
static int teardown(void **state)
{
    (void)state;
    return rmdir(tmpdir);
}

#define CASE(fn, path, mem, what)                                                                  \
    static void fn(void **state)                                                                   \
    {                                                                                              \
        static const scene_case c = {path, mem, what};                                             \
        (void)state;                                                                               \
        sweep(&c);                                                                                 \
    }
CASE(test_texture_file, "examples/scenes/texture.nff", 0, "texture.nff (PNG texture), file")
CASE(test_texture_memory, "examples/scenes/texture.nff", 1, "texture.nff (PNG texture), memory")
CASE(test_torus, "examples/scenes/torus.nff", 0, "torus.nff (implicit, checker), file")
CASE(test_glass, "examples/scenes/glass.nff", 1, "glass.nff, memory")
CASE(test_spd, "examples/scenes/spd/balls-s2.nff", 0, "spd/balls-s2.nff, file")
CASE(test_spd_memory, "examples/scenes/spd/balls-s1.nff", 1, "spd/balls-s1.nff, memory")
CASE(test_default, "examples/scenes/default.nff", 0, "default.nff, file")
CASE(test_prism, "examples/scenes/prism.nff", 0, "prism.nff (dispersion), file")
CASE(test_water, "examples/scenes/water.nff", 1, "water.nff, memory")
CASE(test_gold, "examples/scenes/gold.nff", 0, "gold.nff (conductor), file")
CASE(test_knot, "examples/scenes/knot.nff", 0, "knot.nff (OBJ mesh), file")

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_texture_file), cmocka_unit_test(test_texture_memory),
        cmocka_unit_test(test_torus),        cmocka_unit_test(test_glass),
        cmocka_unit_test(test_spd),          cmocka_unit_test(test_spd_memory),
        cmocka_unit_test(test_default),      cmocka_unit_test(test_prism),
        cmocka_unit_test(test_water),        cmocka_unit_test(test_gold),
        cmocka_unit_test(test_knot),         cmocka_unit_test(test_find),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
