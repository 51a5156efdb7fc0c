/* SPDX-License-Identifier: MIT */
/*
** test_scene.c -- NFF loading: the SPD scenes, extensions, and errors that
** name file, line and column and leave the scene unchanged.
*/
#include "testutil.h"

#include "geom_int.h"
#include "scene.h"

#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

static ggScene *load_ok(const char *text)
{
    ggScene *s = ggSceneCreate(NULL);
    ggError e;
    int rc = ggSceneLoadString(s, text, strlen(text), "t.nff", &e);
    if (rc != GG_OK) print_error("unexpected error: %s\n", e.message);
    assert_int_equal(rc, GG_OK);
    return s;
}

/* Loading text must fail with this code and exactly this message. */
static void expect_error(const char *text, int code, const char *msg)
{
    ggScene *s = ggSceneCreate(NULL);
    ggError e;
    int rc = ggSceneLoadString(s, text, strlen(text), "scene.nff", &e);
    if (rc != code || strcmp(e.message, msg) != 0)
        print_error("input: %s\ngot %d '%s'\nwant %d '%s'\n", text, rc,
                    rc == GG_OK ? "" : e.message, code, msg);
    assert_int_equal(rc, code);
    assert_string_equal(e.message, msg);
    /* Nothing of a failed load stays in the scene. */
    assert_int_equal(ggSceneObjectCount(s), 0);
    assert_int_equal(ggSceneLightCount(s), 0);
    assert_int_equal(ggSceneMaterialCount(s), 0);
    ggSceneFree(s);
}

static void test_basic_entities(void **state)
{
    ggScene *s;
    ggCamera c;
    ggMaterial m;
    (void)state;
    s = load_ok("b 0.1 0.2 0.3\n"
                "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 64 32\n"
                "l 1 2 3\nl 4 5 6 0.5 0.25 1\n"
                "f 1 0 0 0.7 0.3 20 0 0\n"
                "s 0 0 0 1   # a comment\n"
                "c 0 0 0 1 0 1 0 0.5\n"
                "p 3 0 0 0 1 0 0 0 1 0\n"
                "p 4 0 0 0 1 0 0 1 1 0 0 1 0\n"
                "pp 3 0 0 0 0 0 1 1 0 0 0 0 1 0 1 0 0 0 1\n");
    assert_int_equal(ggSceneObjectCount(s), 5);
    assert_int_equal(ggSceneLightCount(s), 2);
    assert_int_equal(ggSceneMaterialCount(s), 1);
    assert_int_equal(ggSceneObjectKind(s, 0), GG_SHAPE_SPHERE);
    assert_int_equal(ggSceneObjectKind(s, 1), GG_SHAPE_CONE);
    assert_int_equal(ggSceneObjectKind(s, 2), GG_SHAPE_TRIANGLE);
    assert_int_equal(ggSceneObjectKind(s, 3), GG_SHAPE_POLYGON);
    assert_int_equal(ggSceneObjectKind(s, 4), GG_SHAPE_TRIANGLE);
    assert_int_equal(ggSceneObjectLine(s, 0), 12);
    c = ggSceneCamera(s);
    assert_int_equal(c.width, 64);
    assert_int_equal(c.height, 32);
    assert_true(c.fov_deg == 40);
    assert_true(c.from.z == 5);
    m = ggSceneMaterial(s, 0);
    assert_true(m.color.r == 1 && m.color.g == 0 && m.kd == 0.7 && m.ks == 0.3);
    assert_true(m.shine == 20 && m.kt == 0 && m.ior == 1);
    assert_int_equal(m.line, 11);
    ggSceneFree(s);
}

static void test_materials_shared(void **state)
{
    ggScene *s;
    (void)state;
    /* One f serves many objects; an extension after it makes a new one. */
    s = load_ok("f 1 1 1 1 0 1 0 0\ns 0 0 0 1\ns 2 0 0 1\nemission 1 0 0\ns 4 0 0 1\n"
                "f 1 1 1 1 0 1 0.5 1.5\nfresnel exact\ns 6 0 0 1\n");
    assert_int_equal(ggSceneMaterialCount(s), 3);
    assert_int_equal(ggSceneObjectMaterial(s, 0), 0);
    assert_int_equal(ggSceneObjectMaterial(s, 1), 0);
    assert_int_equal(ggSceneObjectMaterial(s, 2), 1);
    assert_true(ggSceneMaterial(s, 1).ke.r == 1);
    assert_int_equal(ggSceneMaterial(s, 2).fresnel, GG_FRESNEL_EXACT);
    /* f resets the extension state. */
    assert_true(ggSceneMaterial(s, 2).ke.r == 0);
    ggSceneFree(s);
}

static void test_extensions(void **state)
{
    ggScene *s;
    ggMaterial m;
    (void)state;
    s = load_ok("ambient 0.2 0.3 0.4\ndepth 7\nsamples 4\n"
                "f 1 1 1 0 0 1 0.9 1.33\nabsorb 1e-8 2e-9 1e-9 0.5\ndispersion 40\n"
                "rect 0 0 0 1 0 0 0 1 0\n"
                "f 1 1 1 0 1 1 0 0\nconductor 0.2 0.4 1.4 3.6 2.6 1.8\ns 0 0 0 1\n"
                "checker 8 1 1 1 0 0 0\nrect 0 0 0 2 0 0 0 2 0\n");
    assert_int_equal(ggSceneObjectCount(s), 3);
    assert_int_equal(ggSceneObjectKind(s, 0), GG_SHAPE_RECT);
    m = ggSceneMaterial(s, 0);
    assert_true(m.extinction.r == 1e-8 && m.unit_m == 0.5 && m.abbe == 40 && m.ior == 1.33);
    m = ggSceneMaterial(s, 1);
    assert_int_equal(m.fresnel, GG_FRESNEL_CONDUCTOR);
    assert_true(m.eta_k.r == 3.6 && m.eta_n.b == 1.4);
    m = ggSceneMaterial(s, 2);
    assert_int_equal(m.texture, 0);
    assert_int_equal(s->depth, 7);
    assert_int_equal(s->samples, 4);
    assert_true(s->ambient.b == 0.4);
    ggSceneFree(s);
}

static void test_errors(void **state)
{
    (void)state;
    expect_error("s 1 2", GG_ERROR_PARSE, "scene.nff:1:6: expected a number after 's', got end of file");
    expect_error("f 1 1 1 1 0 1 0 0\n  s 1 2 x 4\n", GG_ERROR_PARSE,
                 "scene.nff:2:9: expected a number after 's', got 'x'");
    expect_error("s 0 0 0 nan", GG_ERROR_PARSE, "scene.nff:1:9: expected a number after 's', got 'nan'");
    expect_error("s 0 0 0 1e999", GG_ERROR_PARSE,
                 "scene.nff:1:9: expected a number after 's', got '1e999' (not a number in a "
                 "double's range)");
    expect_error("q 1", GG_ERROR_PARSE, "scene.nff:1:1: unknown keyword 'q'");
    /* a value's error is at the value, not its keyword or the file name */
    expect_error("s 0 0 0 -1", GG_ERROR_PARSE, "scene.nff:1:9: sphere radius must be > 0, got -1");
    expect_error("mesh \"tri.obj\" crease 200", GG_ERROR_PARSE,
                 "scene.nff:1:23: mesh: the crease angle must be in [0, 180]");
    expect_error("mesh \"tri.obj\" scale 0", GG_ERROR_INVALID,
                 "scene.nff:1:22: mesh: scale 0 makes the transform singular");
    expect_error("mesh \"tri.obj\" scale 2 0 2 rotate x 90", GG_ERROR_INVALID,
                 "scene.nff:1:24: mesh: scale 0 makes the transform singular");
    expect_error("p 2 0 0 0 1 1 1", GG_ERROR_PARSE,
                 "scene.nff:1:3: a vertex count after 'p' must be a whole number from 3 to 1000000, got 2");
    expect_error("p 4\n0 0 0\n1 0 0\n1 1 0\n", GG_ERROR_PARSE,
                 "scene.nff:5:1: expected a number after 'p', got end of file");
    expect_error("p 999999999 0 0 0", GG_ERROR_LIMIT,
                 "scene.nff:1:3: a vertex count after 'p' must be a whole number from 3 to 1000000, got 999999999");
    expect_error("v\nfrom 0 0 1\nat 0 0 0\nup 0 1 0\nangle 45\nresolution 100000 100000\n",
                 GG_ERROR_LIMIT,
                 "scene.nff:6:12: a width after 'resolution' must be a whole number from 1 to 65536, got 100000");
    expect_error("v\nfrom 0 0 1\nat 0 0 0\nup 0 1 0\nangle 45\nresolution 60000 60000\n",
                 GG_ERROR_LIMIT, "scene.nff:6:1: resolution 60000x60000 exceeds the limit of 16777216 pixels");
    expect_error(
        "v\nfrom 0 0 1\nat 0 0 1\nup 0 1 0\n", GG_ERROR_PARSE,
        "scene.nff:3:4: view: 'from' and 'at' are the same point (or within 1e-9 of their size)");
    expect_error(
        "f 1 1 1 1 0 1 0.5 0\n", GG_ERROR_PARSE,
        "scene.nff:1:19: a transparent material (T = 0.5) needs an index of refraction > 0");
    expect_error("fresnel maybe", GG_ERROR_PARSE,
                 "scene.nff:1:9: expected none, schlick or exact after 'fresnel', got 'maybe'");
    expect_error("texture \"no-such-file.png\"", GG_ERROR_IO,
                 "scene.nff:1:9: cannot read texture: no-such-file.png: "
                 "No such file or directory");
    expect_error("implicit \"x*x + y*", GG_ERROR_PARSE, "scene.nff:1:10: unterminated string");
    /* mesh's options at the end of the file: an error at the end, no token
       read that is not there (valgrind saw one after 'material') */
    expect_error("mesh \"tri.obj\" material", GG_ERROR_PARSE,
                 "scene.nff:1:24: expected current or file after 'material', got end of file");
    expect_error("mesh \"tri.obj\" material\n", GG_ERROR_PARSE,
                 "scene.nff:2:1: expected current or file after 'material', got end of file");
    expect_error("mesh \"tri.obj\" material other", GG_ERROR_PARSE,
                 "scene.nff:1:25: expected current or file after 'material', got 'other'");
    expect_error("mesh \"tri.obj\" rotate", GG_ERROR_PARSE,
                 "scene.nff:1:22: expected a number after 'rotate', got end of file");
    expect_error("mesh \"tri.obj\" rotate x", GG_ERROR_PARSE,
                 "scene.nff:1:24: expected an angle in degrees after 'rotate', got end of file");
    expect_error("mesh \"tri.obj\" scale", GG_ERROR_PARSE,
                 "scene.nff:1:21: expected a scale factor after 'scale', got end of file");
    expect_error("mesh \"tri.obj\" scale 1 2", GG_ERROR_PARSE,
                 "scene.nff:1:25: expected a number after 'scale', got end of file");
    expect_error("mesh \"tri.obj\" translate 1 2", GG_ERROR_PARSE,
                 "scene.nff:1:29: expected a number after 'translate', got end of file");
    expect_error(
        "mesh \"tri.obj\" flat crease", GG_ERROR_PARSE,
        "scene.nff:1:27: expected a crease angle in degrees after 'crease', got end of file");
    /* Everything before the error is rolled back too. */
    expect_error("l 0 0 0\nf 1 1 1 1 0 1 0 0\ns 0 0 0 1\ns 0 0", GG_ERROR_PARSE,
                 "scene.nff:4:6: expected a number after 's', got end of file");
}

static void test_rollback_keeps_earlier_load(void **state)
{
    ggScene *s = load_ok("l 0 0 0\nf 1 1 1 1 0 1 0 0\ns 0 0 0 1\n");
    ggError e;
    (void)state;
    assert_int_not_equal(ggSceneLoadString(s, "s 1 1 1 1\ns 2", 14, "b.nff", &e), GG_OK);
    assert_int_equal(ggSceneObjectCount(s), 1);
    assert_int_equal(ggSceneLightCount(s), 1);
    ggSceneFree(s);
}

/* A failed load leaves a prepared scene prepared, as scene.h promises
   ("left as it was"): its additions unprepared it, and only the counts
   were rolled back, so ggSceneIntersect missed, ggRayColor gave black
   and the next render prepared again a scene shared between threads. A
   load that succeeds leaves it unprepared, as any addition does. */
static void test_failed_load_keeps_prepared(void **state)
{
    ggScene *s = load_ok("l 0 0 5\nf 1 1 1 1 0.5 1 0 0\ns 0 0 0 1\n");
    ggRay r = {{0, 0, 5}, {0, 0, -1}};
    ggHit h;
    ggError e;
    unsigned fx;
    const char *trav;
    (void)state;
    assert_int_equal(ggScenePrepare(s, &e), GG_OK);
    fx = ggSceneEffects(s), trav = ggSceneTraversal(s);
    assert_true(ggSceneIntersect(s, r, 0, INFINITY, &h));
    static const char *bad = "s 1 1 1 1\np 3\n0 0 0\n1 0 0\n9"; /* cut short: a parse error */
    assert_int_equal(ggSceneLoadString(s, bad, strlen(bad), "b.nff", &e), GG_ERROR_PARSE);
    assert_true(ggSceneIntersect(s, r, 0, INFINITY, &h));
    assert_true(h.t == 4);
    assert_int_equal(ggSceneEffects(s), fx);
    assert_non_null(trav);
    assert_string_equal(ggSceneTraversal(s), trav);
    assert_int_equal(ggSceneLoadString(s, "s 3 3 3 1\n", 10, "c.nff", &e), GG_OK);
    assert_false(ggSceneIntersect(s, r, 0, INFINITY, &h)); /* unprepared: no hits */
    assert_int_equal(ggScenePrepare(s, &e), GG_OK);
    assert_int_equal(ggSceneObjectCount(s), 2);
    ggSceneFree(s);
}

/* Vertex normals are kept only for pp polygons: plain polygons before,
   between and after them (and a failed load in between) leave each pp
   polygon's normals as the file gave them, and a plain one has none. */
static void test_pp_normals_among_plain_polygons(void **state)
{
    static const char *a = "f 1 1 1 1 0 1 0 0\n"
                           "p 3\n0 0 0\n1 0 0\n0 1 0\n"
                           "pp 4\n0 0 1 0 0 1\n1 0 1 0 0.6 0.8\n1 1 1 0.6 0 0.8\n0 1 1 0 0 1\n";
    static const char *b = "p 4\n0 0 2\n1 0 2\n1 1 2\n0 1 2\n"
                           "pp 3\n0 0 3 1 0 0\n1 0 3 0 1 0\n0 1 3 0 0 1\n";
    static const double want[7][3] = {{0, 0, 1}, {0, 0.6, 0.8}, {0.6, 0, 0.8}, {0, 0, 1},
                                      {1, 0, 0}, {0, 1, 0},     {0, 0, 1}};
    ggScene *s = load_ok(a);
    ggShapeDesc d;
    ggError e;
    static const char *bad = "pp 3\n0 0 9 1 0 0\n1 0 9 1 0 0\n0 1 9 1 0 0\ns 1";
    int i, j, k = 0, obj[2] = {1, 3};
    (void)state;
    /* a failed load (its pp polygon pushed, then an error) changes nothing */
    assert_int_not_equal(ggSceneLoadString(s, bad, strlen(bad), "bad.nff", &e), GG_OK);
    assert_int_equal(ggSceneLoadString(s, b, strlen(b), "b.nff", &e), GG_OK);
    assert_int_equal(ggSceneObjectCount(s), 4);
    for (i = 0; i < 4; i++) {
        assert_int_equal(ggSceneObjectShape(s, i, &d), GG_OK);
        if (i != obj[0] && i != obj[1]) {
            assert_null(d.normals);
            continue;
        }
        assert_non_null(d.normals);
        for (j = 0; j < d.nverts; j++, k++) {
            assert_true(d.normals[j].x == want[k][0] && d.normals[j].y == want[k][1]);
            assert_true(d.normals[j].z == want[k][2]);
        }
    }
    assert_int_equal(k, 7);
    assert_int_equal(ggScenePrepare(s, &e), GG_OK);
    ggSceneFree(s);
}

/* One prepared scene: each primitive's record names its object, that
   object's material (the tag shading reads in place of the object) and
   the kind gg_geom_prim_kind gives; the primitive and triangle arrays
   were allocated once, at the size prepare reserved (a file with
   degenerate shapes, which add nothing, may leave room over). Returns 1
   when the arrays are exactly full. */
static int check_prims(const char *path)
{
    ggScene *s = ggSceneCreate(NULL);
    const gg_geom *g;
    ggError e;
    size_t i;
    int exact;
    if (ggSceneLoadFile(s, path, &e) != GG_OK || ggScenePrepare(s, &e) != GG_OK)
        fail_msg("%s: %s", path, e.message);
    g = s->geom;
    for (i = 0; i < g->nprim; i++) {
        gg_prim_info pi;
        assert_int_equal(gg_geom_prim_info(g, (uint32_t)i, &pi), 1);
        assert_int_equal(pi.obj, gg_geom_prim_object(g, (uint32_t)i));
        assert_true(pi.obj >= 0 && (size_t)pi.obj < s->nobjects);
        if (pi.tag != s->objects[pi.obj].material)
            fail_msg("%s: primitive %lu tagged %d, its object's material is %d", path,
                     (unsigned long)i, pi.tag, s->objects[pi.obj].material);
        assert_int_equal(pi.kind, gg_geom_prim_kind(g, (uint32_t)i));
        /* the hints read records (under ASan: in bounds) and change nothing */
        gg_geom_prefetch_hit(g, (uint32_t)i, 0);
        gg_geom_prefetch_hit(g, (uint32_t)i, 1);
        gg_geom_prefetch_hit(g, (uint32_t)i, 2);
    }
    gg_geom_prefetch_hit(g, (uint32_t)g->nprim, 1);
    {
        gg_prim_info none;
        assert_int_equal(gg_geom_prim_info(g, (uint32_t)g->nprim, &none), 0);
    }
    assert_true(g->cap_prim >= g->nprim && g->cap_tri >= g->ntri);
    exact = g->cap_prim == g->nprim && g->cap_tri == g->ntri;
    ggSceneFree(s);
    return exact;
}

/* tu_each_file's callback: counts the files whose arrays are exactly
   full into *(int *)ud. */
static void check_prims_file(const char *path, void *ud)
{
    if (check_prims(path))
        ++*(int *)ud;
    else
        print_message("%s: room left over (degenerate shapes?)\n", path);
}

/* Every scene file of the repo (26 today). The reservation is exact on
   all of them; a too small one would double the arrays, never exact. */
static void test_prim_records(void **state)
{
    int n = 0, exact = 0;
    (void)state;
    n += tu_each_file("examples/scenes", ".nff", check_prims_file, &exact);
    n += tu_each_file("examples/scenes/spd", ".nff", check_prims_file, &exact);
    n += tu_each_file("tests/data", ".nff", check_prims_file, &exact);
    print_message("%d scene files, %d with the arrays exactly full\n", n, exact);
    assert_true(n >= 20 && exact >= n - 2);
}

static void test_missing_file(void **state)
{
    ggScene *s = ggSceneCreate(NULL);
    ggError e;
    (void)state;
    assert_int_equal(ggSceneLoadFile(s, "/nonexistent/x.nff", &e), GG_ERROR_IO);
    assert_string_equal(e.message, "/nonexistent/x.nff: No such file or directory");
    ggSceneFree(s);
}

/* Every SPD scene loads unchanged, with the entity counts of its README. */
static void test_spd_scenes_load(void **state)
{
    static const struct {
        const char *name;
        int objects, lights;
    } spd[] = {
        {"balls-s4", 7381 + 1, 3},   {"gears", 9345, 5},         {"mount", 8192 + 4, 1},
        {"rings", 4200 + 1 + 4200, 3}, {"tetra", 4096, 1},       {"tree", 4095 + 1 + 4095, 7},
        {"teapot-s12", 144 + 9120, 2},
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof spd / sizeof spd[0]; i++) {
        char path[512];
        ggScene *s = ggSceneCreate(NULL);
        ggError e;
        int rc;
        snprintf(path, sizeof path, "examples/scenes/spd/%s.nff", spd[i].name);
        rc = ggSceneLoadFile(s, path, &e);
        if (rc != GG_OK) print_error("%s\n", e.message);
        assert_int_equal(rc, GG_OK);
        if (ggSceneObjectCount(s) != spd[i].objects)
            print_error("%s: %d objects\n", spd[i].name, ggSceneObjectCount(s));
        assert_int_equal(ggSceneObjectCount(s), spd[i].objects);
        assert_int_equal(ggSceneLightCount(s), spd[i].lights);
        assert_int_equal(ggScenePrepare(s, &e), GG_OK);
        ggSceneFree(s);
    }
}

/* ggSceneGetInfo: refused before the scene is prepared; then counts that
   agree with the scene and with each other (tetra: 4096 triangles; AVX
   blocks exactly when the traversal uses them). */
static void test_scene_info(void **state)
{
    char path[512];
    ggScene *s = ggSceneCreate(NULL);
    ggSceneInfo in;
    ggError e;
    (void)state;
    snprintf(path, sizeof path, "%s/tetra.nff", tu_spd_dir());
    assert_int_equal(ggSceneLoadFile(s, path, &e), GG_OK);
    assert_int_equal(ggSceneGetInfo(s, &in), GG_ERROR_INVALID);
    assert_int_equal(ggScenePrepare(s, &e), GG_OK);
    assert_int_equal(ggSceneGetInfo(s, &in), GG_OK);
    assert_int_equal(in.primitives, 4096);
    assert_int_equal(in.objects_by_kind[GG_SHAPE_TRIANGLE] + in.objects_by_kind[GG_SHAPE_POLYGON],
                     4096);
    assert_true(in.bvh_nodes > 0 && in.bvh_leaves >= in.primitives / 4);
    assert_true(in.bvh_blocks <= in.bvh_leaves);
    assert_true(in.geometry_bytes > in.primitives * 9 * sizeof(double));
    /* blocks are reported exactly when the traversal tests them */
    assert_true((in.bvh_blocks > 0) == (s->geom->trav_avx && s->geom->ntleaves > 0));
    assert_true(in.lo.x <= in.hi.x && in.lo.y <= in.hi.y && in.lo.z <= in.hi.z);
    ggSceneFree(s);
}

/* ggSceneTraversal names the copy the kernel table chose for this CPU
   for a prepared scene with something in it (here one sphere: the copy
   does not depend on triangle blocks), and nothing before prepare. */
#if defined(__SSE2__) && !defined(GG_BVH_NO_SIMD)
#define PLAIN_TRAVERSAL "sse2"
#else
#define PLAIN_TRAVERSAL "c"
#endif
static void test_traversal(void **state)
{
    const int k = gg_cpu_kernels()->trav;
    const char *want = k == GG_KERNEL_AVX512 ? "avx512"
                       : k == GG_KERNEL_AVX2 ? "avx2"
                       : k == GG_KERNEL_AVX  ? "avx"
                                             : PLAIN_TRAVERSAL;
    ggScene *s = load_ok("f 1 0 0 0.7 0.3 20 0 0\ns 0 0 0 1\n");
    ggError e;
    (void)state;
    assert_null(ggSceneTraversal(s));
    assert_int_equal(ggScenePrepare(s, &e), GG_OK);
    assert_non_null(ggSceneTraversal(s));
    assert_string_equal(ggSceneTraversal(s), want);
    print_message("traversal: %s\n", want);
    ggSceneFree(s);
}

/* ggSceneInputFile: every file a scene was read from -- the scene, its
   meshes, an OBJ's MTL, its textures -- each an existing regular file,
   and nothing else; a scene built in code has none. */
static void test_input_files(void **state)
{
    static const char *want[] = {"tests/data/textured.nff", "examples/scenes/models/blob.ply",
                                 "tests/data/meshes/cube.obj", "tests/data/meshes/cube.mtl",
                                 "examples/scenes/texture.png"};
    ggScene *s = tu_load("tests/data/textured.nff"), *code = ggSceneCreate(NULL);
    int i, n = ggSceneInputCount(s), found[5] = {0, 0, 0, 0, 0};
    size_t k;
    (void)state;
    assert_true(n >= 5);
    for (i = 0; i < n; i++) {
        const char *f = ggSceneInputFile(s, i);
        struct stat st, sw;
        int hit = 0;
        assert_non_null(f);
        assert_int_equal(stat(f, &st), 0);
        assert_true(S_ISREG(st.st_mode));
        for (k = 0; k < 5; k++)
            if (stat(want[k], &sw) == 0 && sw.st_dev == st.st_dev && sw.st_ino == st.st_ino)
                found[k] = hit = 1;
        if (!hit) print_error("input %d: %s is none of the expected files\n", i, f);
        assert_true(hit);
    }
    for (k = 0; k < 5; k++) assert_true(found[k]);
    assert_null(ggSceneInputFile(s, n));
    assert_null(ggSceneInputFile(s, -1));
    assert_int_equal(ggSceneInputCount(code), 0);
    assert_null(ggSceneInputFile(code, 0));
    ggSceneFree(code);
    ggSceneFree(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_basic_entities),
        cmocka_unit_test(test_materials_shared),
        cmocka_unit_test(test_extensions),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_rollback_keeps_earlier_load),
        cmocka_unit_test(test_failed_load_keeps_prepared),
        cmocka_unit_test(test_pp_normals_among_plain_polygons),
        cmocka_unit_test(test_missing_file),
        cmocka_unit_test(test_spd_scenes_load),
        cmocka_unit_test(test_scene_info),
        cmocka_unit_test(test_prim_records),
        cmocka_unit_test(test_traversal),
        cmocka_unit_test(test_input_files),
    };
    return cmocka_run_group_tests_name("scene", tests, NULL, NULL);
}
