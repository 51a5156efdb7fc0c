/* SPDX-License-Identifier: MIT */
/*
** test_progress.c -- ggSceneSetProgress: what loading and preparing
** report, on every scene and mesh file of the repo and on files large
** enough (NFF, OBJ, binary and ascii PLY, a mesh an NFF file names, a
** BVH built by threads) to report on the way; and that a cancel at each
** of the calls leaves the scene as the contract says.
*/
#include "testutil.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* Under ThreadSanitizer (make test-tsan) only what runs threads: the
   BVH builds of over 20,000 elements, which only the large files have,
   with a cancel at each call of preparing them. */
#if defined(__SANITIZE_THREAD__)
#define UNDER_TSAN 1
#else
#define UNDER_TSAN 0
#endif

/* What a run of calls looked like: every call, and a cancel at call
   number `stop_at` (1-based; 0 never). */
#define MAXCALLS 4096
typedef struct rec {
    long done[MAXCALLS], total[MAXCALLS];
    int n, stop_at;
} rec;

static int record(void *ud, long done, long total)
{
    rec *r = ud;
    if (r->n < MAXCALLS) r->done[r->n] = done, r->total[r->n] = total;
    r->n++;
    return r->stop_at && r->n == r->stop_at;
}

/* Calls first .. last-1 of r make one step of `total`: start at 0, never
   go back, end at total, each within [0, total]. Returns how many lay
   strictly between 0 and total. */
static int check_step(const rec *r, int first, int last, long total, const char *what)
{
    int i, inside = 0;
    if (!(last > first && r->done[first] == 0 && r->done[last - 1] == total))
        fail_msg("%s: calls %d..%d do not run from 0 to %ld (first %ld, last %ld)", what, first,
                 last - 1, total, r->done[first], r->done[last - 1]);
    for (i = first; i < last; i++) {
        if (r->total[i] != total)
            fail_msg("%s: call %d has total %ld, not %ld", what, i, r->total[i], total);
        if (r->done[i] < 0 || r->done[i] > total)
            fail_msg("%s: call %d: done %ld", what, i, r->done[i]);
        if (i > first && r->done[i] < r->done[i - 1])
            fail_msg("%s: call %d went back from %ld to %ld", what, i, r->done[i - 1], r->done[i]);
        inside += r->done[i] > 0 && r->done[i] < total;
    }
    return inside;
}

static long file_size(const char *path)
{
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    return (long)st.st_size;
}

/* The counts a cancelled load must leave as they were. */
typedef struct counts {
    int objects, lights, materials, textures, meshes, inputs;
} counts;

static counts count(const ggScene *s)
{
    counts c;
    c.objects = ggSceneObjectCount(s), c.lights = ggSceneLightCount(s);
    c.materials = ggSceneMaterialCount(s), c.textures = ggSceneTextureCount(s);
    c.meshes = ggSceneMeshCount(s), c.inputs = ggSceneInputCount(s);
    return c;
}

static void same_counts(counts a, counts b, const char *what)
{
    if (memcmp(&a, &b, sizeof a) != 0)
        fail_msg(
            "%s: the scene changed: objects %d/%d, lights %d/%d, materials %d/%d, meshes %d/%d",
            what, a.objects, b.objects, a.lights, b.lights, a.materials, b.materials, a.meshes,
            b.meshes);
}

/* A scene that already holds something, so that "as before" is not just
   "empty". */
static ggScene *base_scene(void)
{
    static const char text[] = "l 1 2 3\nf 1 0 0 1 0 0 0 0\ns 9 9 9 0.5\n";
    ggScene *s = ggSceneCreate(NULL);
    assert_non_null(s);
    assert_int_equal(ggSceneLoadString(s, text, sizeof text - 1, "base.nff", NULL), GG_OK);
    return s;
}

static int load(ggScene *s, const char *path, int mesh, ggError *e)
{
    return mesh ? ggSceneLoadMesh(s, path, NULL, e) : ggSceneLoadFile(s, path, e);
}

/* path loaded and prepared with a recording callback: the load is one
   step (or, where the file names meshes, several), preparing one step
   of 1000. Returns the calls made between 0 and the end. */
typedef struct seen {
    int load_inside, prep_inside, steps;
} seen;

static seen one_file(const char *path, int mesh)
{
    rec *r = calloc(1, sizeof *r);
    ggScene *s = base_scene();
    ggError e;
    seen sn = {0, 0, 0};
    int i, nload;
    assert_non_null(r);
    ggSceneSetProgress(s, record, r);
    if (load(s, path, mesh, &e) != GG_OK) fail_msg("%s: %s", path, e.message);
    nload = r->n;
    assert_true(nload >= 2 && nload < MAXCALLS);
    /* the file's own step starts first and ends last; a mesh an NFF file
       names is a step inside it */
    assert_int_equal(r->done[0], 0);
    assert_int_equal(r->total[0], file_size(path));
    assert_int_equal(r->total[nload - 1], file_size(path));
    assert_int_equal(r->done[nload - 1], file_size(path));
    for (i = 0; i < nload; i++) sn.steps += r->done[i] == 0;
    if (sn.steps == 1) sn.load_inside = check_step(r, 0, nload, file_size(path), path);
    r->n = 0;
    if (ggScenePrepare(s, &e) != GG_OK) fail_msg("%s: %s", path, e.message);
    assert_true(r->n >= 2 && r->n < MAXCALLS);
    sn.prep_inside = check_step(r, 0, r->n, 1000, path);
    ggSceneFree(s);
    free(r);
    return sn;
}

/* One run with a cancel at call k of loading (prep 0) or preparing
   (prep 1): GG_ERROR_CANCELLED with the step named, the load leaving the
   scene as it was, the prepare leaving it unprepared; either way the
   scene then prepares to the end. Returns the calls the step made (fewer
   than k: it ran to its end, uncancelled). */
static int cancel_at(const char *path, int mesh, int prep, int k, rec *r)
{
    ggScene *s = base_scene();
    counts before;
    ggError e;
    int rc, calls;
    if (prep) assert_int_equal(load(s, path, mesh, NULL), GG_OK);
    before = count(s);
    memset(r, 0, sizeof *r), r->stop_at = k;
    ggSceneSetProgress(s, record, r);
    rc = prep ? ggScenePrepare(s, &e) : load(s, path, mesh, &e);
    calls = r->n;
    if (calls < k) {
        assert_int_equal(rc, GG_OK);
    } else {
        if (rc != GG_ERROR_CANCELLED)
            fail_msg("%s: cancel at %s call %d: %d (%s)", path, prep ? "prepare" : "load", k, rc,
                     e.message);
        if (!strstr(e.message, prep ? "preparing the scene: cancelled" : "loading cancelled"))
            fail_msg("%s: '%s'", path, e.message);
        same_counts(before, count(s), path);
        memset(r, 0, sizeof *r);
        assert_int_equal(ggScenePrepare(s, &e), GG_OK);
        assert_int_equal(r->done[r->n - 1], 1000);
    }
    ggSceneFree(s);
    return calls;
}

/* A cancel at each call of loading, then of preparing; past `max`
   calls, only at the last. Returns the cancels. */
static int cancel_each(const char *path, int mesh, int max)
{
    rec *r = calloc(1, sizeof *r);
    int prep, k, calls, n = 0;
    assert_non_null(r);
    for (prep = 0; prep < 2; prep++)
        for (k = 1; (calls = cancel_at(path, mesh, prep, k, r)) >= k; k++) {
            n++;
            if (k >= max && calls - 1 > k) k = calls - 1;
            if (UNDER_TSAN && !prep) break; /* loading runs no threads */
        }
    free(r);
    return n;
}

typedef struct tally {
    int files, cancels, mesh, refused;
} tally;

static void each(const char *path, void *ud)
{
    tally *t = ud;
    ggScene *s = ggSceneCreate(NULL);
    int ok = load(s, path, t->mesh, NULL) == GG_OK && ggScenePrepare(s, NULL) == GG_OK;
    ggSceneFree(s);
    if (!ok) { /* a file made to be refused (tests/data/meshes/flat.obj) */
        t->refused++;
        return;
    }
    (void)one_file(path, t->mesh);
    t->cancels += cancel_each(path, t->mesh, 8);
    t->files++;
}

/* Every scene and mesh file of the repo: the calls, and a cancel at
   each. */
static void test_every_file(void **state)
{
    tally t = {0, 0, 0, 0};
    (void)state;
    tu_each_file("examples/scenes", ".nff", each, &t);
    tu_each_file("examples/scenes/spd", ".nff", each, &t);
    tu_each_file("tests/data", ".nff", each, &t);
    t.mesh = 1;
    tu_each_file("tests/data/meshes", ".obj", each, &t);
    tu_each_file("tests/data/meshes", ".ply", each, &t);
    tu_each_file("examples/scenes/models", ".obj", each, &t);
    tu_each_file("examples/scenes/models", ".ply", each, &t);
    print_message("%d files, %d cancels, %d files refused\n", t.files, t.cancels, t.refused);
    assert_true(t.files >= 30 && t.cancels >= 6 * t.files && t.refused <= 2);
}

/* ---- files large enough to report on the way ---- */

static void write_file(const char *path, void (*body)(FILE *f, int n), int n)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    body(f, n);
    assert_int_equal(fclose(f), 0);
}

/* n triangles in a grid of slightly bumpy squares' halves, as NFF */
static void nff_body(FILE *f, int n)
{
    int i;
    fprintf(f, "v\nfrom 0 -30 10\nat 0 0 0\nup 0 0 1\nangle 40\nhither 0.01\nresolution 8 8\n"
               "l 5 -5 20\nf 0.8 0.7 0.6 0.8 0.2 10 0 0\n");
    for (i = 0; i < n; i++) {
        double x = (i % 300) * 0.1 - 15, y = (i / 300) * 0.1 - 15;
        fprintf(f, "p 3\n%.6f %.6f %.6f\n%.6f %.6f 0\n%.6f %.6f 0.01\n", x, y, 0.001 * (i % 7),
                x + 0.1, y, x, y + 0.1);
    }
}

static void obj_body(FILE *f, int n)
{
    int i;
    for (i = 0; i < n; i++) {
        double x = (i % 300) * 0.1, y = (i / 300) * 0.1;
        fprintf(f, "v %.6f %.6f %.6f\nv %.6f %.6f 0\nv %.6f %.6f 0.01\nf -3 -2 -1\n", x, y,
                0.001 * (i % 7), x + 0.1, y, x, y + 0.1);
    }
}

static void ply_body(FILE *f, int n, int binary)
{
    int i, k;
    fprintf(f,
            "ply\nformat %s 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
            "property float z\nelement face %d\nproperty list uchar int vertex_indices\n"
            "end_header\n",
            binary ? "binary_little_endian" : "ascii", 3 * n, n);
    for (i = 0; i < n; i++) {
        float v[3][3];
        float x = (float)(i % 300) * 0.1f, y = (float)(i / 300) * 0.1f;
        v[0][0] = x, v[0][1] = y, v[0][2] = 0.001f * (float)(i % 7);
        v[1][0] = x + 0.1f, v[1][1] = y, v[1][2] = 0;
        v[2][0] = x, v[2][1] = y + 0.1f, v[2][2] = 0.01f;
        for (k = 0; k < 3; k++) {
            if (binary) {
                unsigned char b[12];
                int j;
                for (j = 0; j < 3; j++) { /* little-endian, whatever the host */
                    uint32_t u;
                    memcpy(&u, &v[k][j], 4);
                    b[4 * j] = (unsigned char)u, b[4 * j + 1] = (unsigned char)(u >> 8);
                    b[4 * j + 2] = (unsigned char)(u >> 16),
                              b[4 * j + 3] = (unsigned char)(u >> 24);
                }
                fwrite(b, 1, sizeof b, f);
            } else {
                fprintf(f, "%.6f %.6f %.6f\n", v[k][0], v[k][1], v[k][2]);
            }
        }
    }
    for (i = 0; i < n; i++) {
        if (binary) {
            unsigned char b[13];
            int j;
            b[0] = 3;
            for (j = 0; j < 3; j++) {
                uint32_t u = (uint32_t)(3 * i + j);
                b[1 + 4 * j] = (unsigned char)u, b[2 + 4 * j] = (unsigned char)(u >> 8);
                b[3 + 4 * j] = (unsigned char)(u >> 16), b[4 + 4 * j] = (unsigned char)(u >> 24);
            }
            fwrite(b, 1, sizeof b, f);
        } else {
            fprintf(f, "3 %d %d %d\n", 3 * i, 3 * i + 1, 3 * i + 2);
        }
    }
}

static void ply_bin_body(FILE *f, int n)
{
    ply_body(f, n, 1);
}

static void ply_ascii_body(FILE *f, int n)
{
    ply_body(f, n, 0);
}

/* an NFF file around big.obj */
static void nest_body(FILE *f, int n)
{
    (void)n;
    fprintf(f, "v\nfrom 0 -30 10\nat 0 0 0\nup 0 0 1\nangle 40\nhither 0.01\nresolution 8 8\n"
               "l 5 -5 20\nf 0.8 0.7 0.6 0.8 0.2 10 0 0\nmesh big.obj\ns 0 0 3 1\n");
}

static int setup(void **state)
{
    (void)state;
    if (tu_tmpdir_make("test_progress")) return -1;
    write_file(tu_tmppath("big.nff"), nff_body, 30000);
    write_file(tu_tmppath("big.obj"), obj_body, 30000);
    write_file(tu_tmppath("big.ply"), ply_bin_body, 50000);
    write_file(tu_tmppath("big_ascii.ply"), ply_ascii_body, 30000);
    write_file(tu_tmppath("nest.nff"), nest_body, 0);
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    tu_tmpdir_remove();
    return 0;
}

/* Each file is over 1 MiB: its load reports on the way, and so does
   preparing (30,000 triangles or more: the BVH is built by threads where there
   are several). A cancel at each call. */
static void big(const char *name, int mesh)
{
    const char *path = tu_tmppath(name);
    seen sn = one_file(path, mesh);
    int n;
    assert_true(file_size(path) > 2L << 20);
    print_message("%s: %ld bytes, %d load calls inside, %d prepare calls inside\n", name,
                  file_size(path), sn.load_inside, sn.prep_inside);
    assert_true(sn.load_inside >= 1 && sn.prep_inside >= 2);
    n = cancel_each(path, mesh, 1000);
    assert_true(n >= 6);
}

static void test_big_nff(void **state)
{
    (void)state;
    big("big.nff", 0);
}

static void test_big_obj(void **state)
{
    (void)state;
    big("big.obj", 1);
}

static void test_big_ply(void **state)
{
    (void)state;
    big("big.ply", 1);
    big("big_ascii.ply", 1);
}

/* The mesh an NFF file names is a step of its own inside the file's:
   two steps start from 0, and the NFF file's own ends the load. */
static void test_nested_mesh(void **state)
{
    const char *path = tu_tmppath("nest.nff");
    seen sn = one_file(path, 0);
    (void)state;
    assert_int_equal(sn.steps, 2);
    assert_true(cancel_each(path, 0, 1000) >= 6);
}

/* The message of a cancel names the place reached: an NFF file's line
   past the first, an OBJ file's line, a PLY file's byte. */
static void test_cancel_names_place(void **state)
{
    static const struct {
        const char *name, *want;
        int mesh;
    } c[] = {
        {"big.nff", "big.nff:", 0}, {"big.obj", "big.obj:", 1}, {"big.ply", "big.ply: byte ", 1}};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof c / sizeof c[0]; i++) {
        rec *r = calloc(1, sizeof *r);
        ggScene *s = ggSceneCreate(NULL);
        ggError e;
        assert_non_null(r);
        r->stop_at = 2; /* the first call past the start */
        ggSceneSetProgress(s, record, r);
        assert_int_equal(load(s, tu_tmppath(c[i].name), c[i].mesh, &e), GG_ERROR_CANCELLED);
        print_message("%s\n", e.message);
        assert_non_null(strstr(e.message, c[i].want));
        assert_non_null(strstr(e.message, "loading cancelled"));
        assert_true(r->done[1] > 0 && r->done[1] < r->total[1]);
        if (i == 0) assert_null(strstr(e.message, "big.nff:1:")); /* not the first line */
        ggSceneFree(s);
        free(r);
    }
}

/* No callback: no calls, and the NULL scene is ignored. */
static void test_none(void **state)
{
    ggScene *s = base_scene();
    (void)state;
    ggSceneSetProgress(NULL, record, NULL);
    ggSceneSetProgress(s, NULL, NULL);
    assert_int_equal(ggSceneLoadFile(s, tu_tmppath("big.nff"), NULL), GG_OK);
    assert_int_equal(ggScenePrepare(s, NULL), GG_OK);
    ggSceneFree(s);
}

int main(void)
{
    const struct CMUnitTest all[] = {
        cmocka_unit_test(test_every_file),  cmocka_unit_test(test_big_nff),
        cmocka_unit_test(test_big_obj),     cmocka_unit_test(test_big_ply),
        cmocka_unit_test(test_nested_mesh), cmocka_unit_test(test_cancel_names_place),
        cmocka_unit_test(test_none),
    };
    const struct CMUnitTest tsan[] = {cmocka_unit_test(test_big_obj)};
    if (UNDER_TSAN) return cmocka_run_group_tests(tsan, setup, teardown);
    return cmocka_run_group_tests(all, setup, teardown);
}
