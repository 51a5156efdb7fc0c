/* SPDX-License-Identifier: MIT */
/*
** test_mesh_nomem.c -- allocation failure while loading meshes: for every
** k, an allocator that fails its k-th allocation, then load (OBJ with MTL
** and texture, PLY ascii and binary, an NFF scene with a mesh line, a
** mesh built in code), prepare and render. Each step returns GG_OK or
** GG_ERROR_NOMEM; a failed load leaves the scene as it was; when every
** step said GG_OK the image is bit-identical to the run without failures.
** LeakSanitizer (the asan build of make check) sees every path's frees.
*/
#include "testutil.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef int (*loader)(ggScene *s, ggError *e);

static int load_obj(ggScene *s, ggError *e)
{
    return ggSceneLoadMesh(s, "tests/data/meshes/cube.obj", NULL, e);
}
static int load_ply(ggScene *s, ggError *e)
{
    return ggSceneLoadMesh(s, "tests/data/meshes/cube_be.ply", NULL, e);
}
static int load_ascii(ggScene *s, ggError *e)
{
    return ggSceneLoadMesh(s, "tests/data/meshes/cube_ascii.ply", NULL, e);
}
static int load_model(ggScene *s, ggError *e)
{
    return ggSceneLoadFile(s, "tests/data/meshes/cube.obj", e);
}
static int load_nff(ggScene *s, ggError *e)
{
    const char *t = "v from 3 2 4 at 0.5 0.5 0.5 up 0 1 0 angle 40 resolution 24 18\nl 4 5 6\n"
                    "f 1 0.5 0.2 1 0 100000 0 0\nmesh \"tests/data/meshes/cube_le.ply\" rotate y "
                    "20 smooth crease 30\n";
    return ggSceneLoadString(s, t, strlen(t), "t.nff", e);
}
static int add_code(ggScene *s, ggError *e)
{
    static const ggVec3 v[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    static const uint32_t i[12] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    ggMeshData d;
    int rc;
    memset(&d, 0, sizeof d);
    d.name = "tet", d.positions = v, d.npositions = 4, d.indices = i, d.ntriangles = 4;
    rc = ggSceneAddMesh(s, &d, NULL, e);
    return rc < 0 ? -rc : GG_OK;
}

/* One run: load into a scene that already holds a mesh, frame it,
   render 24x18. Returns the image (NULL if a step failed). */
static ggImage *run(loader ld, tu_failer *f, int *rc_out)
{
    ggScene *s = ggSceneCreate(&f->alloc);
    ggRenderOptions o;
    ggImage *img = NULL;
    ggError e;
    ggMaterial m = ggMaterialDefault();
    int rc, nobj, nmat, nmesh, nl;
    if (!s) return *rc_out = GG_ERROR_NOMEM, NULL;
    rc = ggSceneAddMaterial(s, &m) < 0 ? GG_ERROR_NOMEM : GG_OK;
    if (rc == GG_OK) rc = add_code(s, &e);
    nobj = ggSceneObjectCount(s), nmat = ggSceneMaterialCount(s), nmesh = ggSceneMeshCount(s);
    nl = ggSceneLightCount(s);
    if (rc == GG_OK) {
        rc = ld(s, &e);
        assert_true(rc == GG_OK || rc == GG_ERROR_NOMEM);
        if (rc != GG_OK) {
            assert_int_equal(ggSceneObjectCount(s), nobj);
            assert_int_equal(ggSceneMaterialCount(s), nmat);
            assert_int_equal(ggSceneMeshCount(s), nmesh);
            assert_int_equal(ggSceneLightCount(s), nl);
        }
    }
    if (rc == GG_OK && ggSceneLightCount(s) == 0)
        rc = ggSceneFrame(s, GG_FRAME_CAMERA | GG_FRAME_LIGHTS, &e);
    if (rc == GG_OK) rc = ggScenePrepare(s, &e);
    if (rc == GG_OK) {
        ggRenderOptionsDefault(&o);
        o.width = 24, o.height = 18, o.threads = 1;
        rc = ggRender(s, &o, &img, NULL, &e);
    }
    assert_true(rc == GG_OK || rc == GG_ERROR_NOMEM);
    ggSceneFree(s);
    *rc_out = rc;
    return rc == GG_OK ? img : NULL;
}

static void sweep(loader ld, const char *what)
{
    tu_failer f;
    int rc;
    long k, points = 0, kept;
    ggImage *ref, *img;
    tu_failer_init(&f);
    ref = run(ld, &f, &rc);
    assert_int_equal(rc, GG_OK);
    kept = f.live; /* the reference image's blocks */
    for (k = 1;; k++) {
        tu_failer_arm(&f, k);
        img = run(ld, &f, &rc);
        if (!f.failed) {
            ggImageFree(img);
            assert_int_equal(f.live, kept);
            break;
        }
        points++;
        /* a failure that every step absorbed must not change the picture */
        if (rc == GG_OK)
            assert_memory_equal(ggImagePixelsConst(img), ggImagePixelsConst(ref),
                                24 * 18 * 3 * sizeof(float));
        ggImageFree(img);
        assert_int_equal(f.live, kept); /* nothing left behind, whatever failed */
    }
    printf("test_mesh_nomem: %s: %ld allocation failure points, each GG_OK with the same image or "
           "GG_ERROR_NOMEM with the scene unchanged\n",
           what, points);
    ggImageFree(ref);
    assert_int_equal(f.live, 0);
    tu_failer_done(&f);
}

static void test_obj(void **state)
{
    (void)state, sweep(load_obj, "cube.obj + cube.mtl + texture");
}
static void test_ply(void **state)
{
    (void)state, sweep(load_ply, "cube_be.ply");
}
static void test_ascii(void **state)
{
    (void)state, sweep(load_ascii, "cube_ascii.ply");
}
static void test_model(void **state)
{
    (void)state, sweep(load_model, "cube.obj as a scene (framed)");
}
static void test_nff(void **state)
{
    (void)state, sweep(load_nff, "NFF with a mesh line");
}
static void test_code(void **state)
{
    (void)state, sweep(add_code, "ggSceneAddMesh");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_obj),   cmocka_unit_test(test_ply), cmocka_unit_test(test_ascii),
        cmocka_unit_test(test_model), cmocka_unit_test(test_nff), cmocka_unit_test(test_code),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
