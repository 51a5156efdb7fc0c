/* SPDX-License-Identifier: MIT */
/*
** test_null.c -- the NULL rule of ggrt/base.h: every public function, given
** NULL where a handle (or a required pointer) goes, returns GG_ERROR_INVALID
** or the neutral value its declaration names, writes none of its outputs
** (they start as sentinels and are checked after), and never crashes; Free
** functions take NULL as a no-op. The last test reads the GG_API
** declarations in include/ and fails if a function is not called here.
*/
#include "testutil.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- which functions the tests call ---- */

#define MAX_NAMES 512
static const char *covered[MAX_NAMES];
static int ncovered;

static void mark(const char *name, void (*fn)(void))
{
    assert_non_null(fn);
    assert_true(ncovered < MAX_NAMES);
    covered[ncovered++] = name;
}
/* COVER(f): the test calls f with NULL handles next. */
#define COVER(f) mark(#f, (void (*)(void))f)

/* Rule 1: a call given a NULL handle writes no output. Outputs start as
   a pointer to themselves (or bytes of 0xff) and must stay so. */
#define UNTOUCHED(p) assert_ptr_equal((const void *)(p), (const void *)&(p))
static bool all_ff(const void *p, size_t n)
{
    const unsigned char *b = p;
    size_t i;
    for (i = 0; i < n; i++)
        if (b[i] != 0xff) return false;
    return true;
}

static bool is_black(ggColor c)
{
    return c.r == 0 && c.g == 0 && c.b == 0;
}
static bool is_nan3(ggVec3 v)
{
    return isnan(v.x) && isnan(v.y) && isnan(v.z);
}

/* A small prepared scene and a recorded trace of one of its pixels. */
static const char scene_text[] = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 resolution 8 6\n"
                                 "l 2 3 4\nf 1 0.5 0.5 0.8 0.2 20 0 0\ns 0 0 0 1\n";

static ggScene *scene(void)
{
    ggScene *s = ggSceneCreate(NULL);
    assert_int_equal(ggSceneLoadString(s, scene_text, sizeof scene_text - 1, NULL, NULL), GG_OK);
    assert_int_equal(ggScenePrepare(s, NULL), GG_OK);
    return s;
}

static void test_base_optics(void **state)
{
    ggVec3 v = {0, -1, 0}, n = {0, 1, 0};
    (void)state;
    /* No handles: called to show they are covered and answer. */
    COVER(ggVersion), assert_non_null(ggVersion());
    COVER(ggBuildId), assert_non_null(ggBuildId());
    COVER(ggStatusString), assert_non_null(ggStatusString(-99));
    COVER(ggUTF8Length), assert_int_equal(ggUTF8Length(NULL, 4), 0);
    COVER(ggUTF8Valid), assert_false(ggUTF8Valid(NULL, 0));
    COVER(ggReflection), assert_true(ggReflection(v, n).y == 1);
    /* Optional out pointers: NULL asks for the decision or nothing. */
    COVER(ggRefract), assert_true(ggRefract(v, n, 1, 1.5, NULL));
    COVER(ggRefractTextbook), assert_true(ggRefractTextbook(v, n, 1, 1.5, NULL));
    COVER(ggCriticalAngle), assert_true(isnan(ggCriticalAngle(0, 1)));
    COVER(ggFresnelDielectric), assert_true(ggFresnelDielectric(1, 1, 1) == 0);
    COVER(ggFresnelDielectricPolarized), ggFresnelDielectricPolarized(1, 1, 1.5, NULL, NULL);
    COVER(ggFresnelConductor), assert_true(isnan(ggFresnelConductor(1, 1, 0, 0)));
    COVER(ggFresnelConductorPolarized), ggFresnelConductorPolarized(1, 1, 0.2, 3, NULL, NULL);
    COVER(ggFresnelSchlick), assert_true(ggFresnelSchlick(1, 1, 1) == 0);
    COVER(ggAbsorptionCoefficient), assert_true(isnan(ggAbsorptionCoefficient(-1, 1)));
    COVER(ggBeerLambert), assert_true(ggBeerLambert(0, 1, 1) == 1);
    /* The error measures: a NULL result is GG_ERROR_INVALID. */
    COVER(ggRefractError);
    assert_int_equal(ggRefractError(v, n, 1, 1.5, v, false, NULL), GG_ERROR_INVALID);
    COVER(ggReflectionError), assert_int_equal(ggReflectionError(v, n, n, NULL), GG_ERROR_INVALID);
    COVER(ggFresnelDielectricError);
    assert_int_equal(ggFresnelDielectricError(1, 1, 1.5, 0.04, NULL), GG_ERROR_INVALID);
    COVER(ggFresnelConductorError);
    assert_int_equal(ggFresnelConductorError(1, 1, 0.2, 3, 0.9, NULL), GG_ERROR_INVALID);
    COVER(ggBeerLambertColor), (void)ggBeerLambertColor((ggColor){0, 0, 0}, (ggColor){1, 1, 1}, 1);
}

static void test_image(void **state)
{
    ggImage *img = ggImageCreate(2, 2, NULL), *out = img;
    ggImageDiff d;
    ggError e;
    (void)state;
    COVER(ggImageCreate), assert_null(ggImageCreate(0, 1, NULL));
    COVER(ggImageFree), ggImageFree(NULL);
    COVER(ggImageWidth), assert_int_equal(ggImageWidth(NULL), 0);
    COVER(ggImageHeight), assert_int_equal(ggImageHeight(NULL), 0);
    COVER(ggImagePixels), assert_null(ggImagePixels(NULL));
    COVER(ggImagePixelsConst), assert_null(ggImagePixelsConst(NULL));
    COVER(ggImageGet), assert_true(is_black(ggImageGet(NULL, 0, 0)));
    COVER(ggImageSet), ggImageSet(NULL, 0, 0, (ggColor){1, 1, 1});
    COVER(ggImageCrop), assert_int_equal(ggImageCrop(NULL, 0, 0, 1, 1, &out), GG_ERROR_INVALID);
    assert_ptr_equal(out, img);
    assert_int_equal(ggImageCrop(img, 0, 0, 1, 1, NULL), GG_ERROR_INVALID);
    COVER(ggImagePaste), ggImagePaste(NULL, img, 0, 0), ggImagePaste(img, NULL, 0, 0);
    COVER(ggImageRead), assert_int_equal(ggImageRead(NULL, NULL, &out, &e), GG_ERROR_INVALID);
    assert_int_equal(ggImageRead("x.png", NULL, NULL, &e), GG_ERROR_INVALID);
    COVER(ggImageWritePNG), assert_int_equal(ggImageWritePNG(NULL, "x.png", &e), GG_ERROR_INVALID);
    assert_int_equal(ggImageWritePNG(img, NULL, &e), GG_ERROR_INVALID);
    COVER(ggImageWriteEXR), assert_int_equal(ggImageWriteEXR(NULL, "x.exr", &e), GG_ERROR_INVALID);
    assert_int_equal(ggImageWriteEXR(img, NULL, &e), GG_ERROR_INVALID);
    {
        ggEXRHeader h;
        memset(&h, 0x5a, sizeof h);
        COVER(ggImageReadEXRHeader),
            assert_int_equal(ggImageReadEXRHeader(NULL, &h, &e), GG_ERROR_INVALID);
        assert_int_equal(ggImageReadEXRHeader("x.exr", NULL, &e), GG_ERROR_INVALID);
        COVER(ggEXRHeaderFree), ggEXRHeaderFree(NULL);
        memset(&h, 0, sizeof h);
        ggEXRHeaderFree(&h); /* a zeroed header: a no-op */
        COVER(ggEXRHeaderGet), assert_null(ggEXRHeaderGet(NULL, "ggrt.tile"));
        assert_null(ggEXRHeaderGet(&h, "ggrt.tile"));
        COVER(ggImageWriteEXRHeader),
            assert_int_equal(ggImageWriteEXRHeader(NULL, NULL, "x.exr", &e), GG_ERROR_INVALID);
        assert_int_equal(ggImageWriteEXRHeader(img, NULL, NULL, &e), GG_ERROR_INVALID);
    }
    COVER(ggImageWrite), assert_int_equal(ggImageWrite(NULL, "x.png", &e), GG_ERROR_INVALID);
    assert_int_equal(ggImageWrite(img, NULL, NULL), GG_ERROR_INVALID);
    COVER(ggImageCompare);
    assert_int_equal(ggImageCompare(NULL, img, GG_COMPARE_LINEAR, &d), GG_ERROR_INVALID);
    assert_int_equal(ggImageCompare(img, NULL, GG_COMPARE_LINEAR, &d), GG_ERROR_INVALID);
    assert_int_equal(ggImageCompare(img, img, GG_COMPARE_LINEAR, NULL), GG_ERROR_INVALID);
    COVER(ggTextureBilinear), assert_true(is_black(ggTextureBilinear(NULL, 0.5, 0.5, 0)));
    COVER(ggTextureNearest), assert_true(is_black(ggTextureNearest(NULL, 0.5, 0.5, 0)));
    COVER(ggTextureChecker),
        (void)ggTextureChecker(0.5, 0.5, 2, (ggColor){1, 1, 1}, (ggColor){0, 0, 0});
    COVER(ggLinearToSRGB), assert_true(ggLinearToSRGB(0) == 0);
    COVER(ggSRGBToLinear), assert_true(ggSRGBToLinear(0) == 0);
    {
        unsigned char b[3] = {7, 7, 7};
        float px[3] = {1, 1, 1};
        COVER(ggLinearToSRGB8), ggLinearToSRGB8(NULL, b, 3), ggLinearToSRGB8(px, NULL, 3);
        assert_true(b[0] == 7 && b[1] == 7 && b[2] == 7);
    }
    ggImageFree(img);
}

static double sphere_f(void *ud, ggVec3 p)
{
    (void)ud;
    return p.x * p.x + p.y * p.y + p.z * p.z - 1;
}

static void test_implicit(void **state)
{
    ggImplicit *imp = (ggImplicit *)&imp; /* untouched: rule 1 */
    ggVec3 lo = {-1, -1, -1}, hi = {1, 1, 1}, a = {7, 7, 7}, b = a;
    ggRay r = {{0, 0, -5}, {0, 0, 1}};
    double t = 42;
    ggError e;
    (void)state;
    COVER(ggImplicitCreateExpr);
    assert_int_equal(ggImplicitCreateExpr(NULL, lo, hi, NULL, &imp, &e), GG_ERROR_INVALID);
    UNTOUCHED(imp);
    assert_int_equal(ggImplicitCreateExpr("x", lo, hi, NULL, NULL, &e), GG_ERROR_INVALID);
    COVER(ggImplicitCreateFn);
    assert_int_equal(ggImplicitCreateFn(NULL, NULL, NULL, lo, hi, NULL, &imp, &e),
                     GG_ERROR_INVALID);
    UNTOUCHED(imp);
    assert_int_equal(ggImplicitCreateFn(sphere_f, NULL, NULL, lo, hi, NULL, NULL, &e),
                     GG_ERROR_INVALID);
    COVER(ggImplicitFree), ggImplicitFree(NULL);
    COVER(ggImplicitSetTolerance),
        assert_int_equal(ggImplicitSetTolerance(NULL, 1e-6), GG_ERROR_INVALID);
    COVER(ggImplicitSetGradientBound);
    assert_int_equal(ggImplicitSetGradientBound(NULL, 1), GG_ERROR_INVALID);
    COVER(ggImplicitGradientBound), assert_true(ggImplicitGradientBound(NULL) == 0);
    COVER(ggImplicitSetMethod), assert_int_equal(ggImplicitSetMethod(NULL, 0), GG_ERROR_INVALID);
    COVER(ggImplicitSetBudget), assert_int_equal(ggImplicitSetBudget(NULL, 100), GG_ERROR_INVALID);
    COVER(ggImplicitSetNormalStep),
        assert_int_equal(ggImplicitSetNormalStep(NULL, 0), GG_ERROR_INVALID);
    COVER(ggImplicitBounds), ggImplicitBounds(NULL, &a, &b);
    assert_true(a.x == 7 && b.x == 7); /* nothing written */
    COVER(ggImplicitIntersect), assert_int_equal(ggImplicitIntersect(NULL, r, 0, 10, &t), 0);
    assert_true(t == 42);
    COVER(ggImplicitWarnings), assert_int_equal(ggImplicitWarnings(NULL), 0);
    COVER(ggImplicitMaxSlope), assert_true(ggImplicitMaxSlope(NULL) == 0);
    COVER(ggImplicitClearWarnings), ggImplicitClearWarnings(NULL);
    COVER(ggImplicitEval), assert_true(isnan(ggImplicitEval(NULL, a)));
    {
        ggTriangulation *tr = (ggTriangulation *)&tr;
        COVER(ggImplicitTriangulate);
        assert_int_equal(ggImplicitTriangulate(NULL, 8, 0, NULL, &tr), GG_ERROR_INVALID);
        UNTOUCHED(tr);
        COVER(ggTriangulationFree), ggTriangulationFree(NULL);
    }
    COVER(ggGradientNormal), assert_true(is_nan3(ggGradientNormal(NULL, a)));
    COVER(ggGradientCentral), assert_true(is_nan3(ggGradientCentral(NULL, a, 0)));
    /* A real surface with NULL out pointers. */
    assert_int_equal(ggImplicitCreateExpr("x^2 + y^2 + z^2 - 0.5", lo, hi, NULL, &imp, &e), GG_OK);
    ggImplicitBounds(imp, NULL, NULL);
    assert_int_equal(ggImplicitIntersect(imp, r, 0, 10, &t), 1);
    assert_int_equal(ggImplicitIntersect(imp, r, 0, 10, NULL), 0); /* t is required */
    ggImplicitFree(imp);
}

static void test_scene_build(void **state)
{
    ggScene *s = ggSceneCreate(NULL);
    ggMaterial m = ggMaterialDefault();
    ggCamera c = ggSceneCamera(s), z = ggSceneCamera(NULL);
    ggVec3 v[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    ggImplicit *imp;
    ggImage *img = ggImageCreate(1, 1, NULL);
    ggMeshOptions mo;
    ggMeshData md;
    uint32_t idx[3] = {0, 1, 2};
    (void)state;
    memset(&md, 0, sizeof md);
    md.positions = v, md.npositions = 3, md.indices = idx, md.ntriangles = 1;
    COVER(ggShapeKindName), assert_string_equal(ggShapeKindName(-1), "?");
    COVER(ggMaterialDefault), assert_true(ggMaterialDefault().kd == 1);
    COVER(ggMaterialCheck), assert_int_equal(ggMaterialCheck(NULL, NULL), GG_ERROR_INVALID);
    COVER(ggCameraCheck), assert_int_equal(ggCameraCheck(NULL, NULL), GG_ERROR_INVALID);
    COVER(ggSceneCreate), ggSceneFree(ggSceneCreate(NULL));
    COVER(ggSceneFree), ggSceneFree(NULL);
    COVER(ggSceneLoadFile);
    assert_int_equal(ggSceneLoadFile(NULL, "examples/scenes/glass.nff", NULL), GG_ERROR_INVALID);
    assert_int_equal(ggSceneLoadFile(s, NULL, NULL), GG_ERROR_INVALID);
    COVER(ggSceneLoadString),
        assert_int_equal(ggSceneLoadString(NULL, "s 0 0 0 1", 9, NULL, NULL), GG_ERROR_INVALID);
    assert_int_equal(ggSceneLoadString(s, NULL, 9, NULL, NULL), GG_ERROR_INVALID);
    COVER(ggSceneSetImageReader), ggSceneSetImageReader(NULL, NULL, NULL);
    COVER(ggSceneSetProgress), ggSceneSetProgress(NULL, NULL, NULL);
    COVER(ggSceneSetCamera), assert_int_equal(ggSceneSetCamera(NULL, &c), GG_ERROR_INVALID);
    assert_int_equal(ggSceneSetCamera(s, NULL), GG_ERROR_INVALID);
    COVER(ggSceneCamera), assert_true(z.width == 0 && z.fov_deg == 0);
    COVER(ggSceneSetBackground);
    assert_int_equal(ggSceneSetBackground(NULL, (ggColor){0, 0, 0}), GG_ERROR_INVALID);
    COVER(ggSceneSetAmbient),
        assert_int_equal(ggSceneSetAmbient(NULL, (ggColor){0, 0, 0}), GG_ERROR_INVALID);
    COVER(ggSceneAddLight);
    assert_int_equal(ggSceneAddLight(NULL, v[0], (ggColor){1, 1, 1}), -GG_ERROR_INVALID);
    COVER(ggSceneAddMaterial), assert_int_equal(ggSceneAddMaterial(NULL, &m), -GG_ERROR_INVALID);
    COVER(ggSceneSetMaterial), assert_int_equal(ggSceneSetMaterial(NULL, 0, &m), GG_ERROR_INVALID);
    COVER(ggSceneAddChecker),
        assert_int_equal(ggSceneAddChecker(NULL, 4, m.color, m.color), -GG_ERROR_INVALID);
    assert_int_equal(ggSceneAddMaterial(s, NULL), -GG_ERROR_INVALID);
    /* Takes ownership: a refused image is freed (LSan would see a leak). */
    COVER(ggSceneAddTexture), assert_int_equal(ggSceneAddTexture(NULL, img), -GG_ERROR_INVALID);
    assert_int_equal(ggSceneAddTexture(s, NULL), -GG_ERROR_INVALID);
    COVER(ggSceneAddSphere),
        assert_int_equal(ggSceneAddSphere(NULL, 0, v[0], 1), -GG_ERROR_INVALID);
    COVER(ggSceneAddPolygon), assert_int_equal(ggSceneAddPolygon(NULL, 0, v, 3), -GG_ERROR_INVALID);
    assert_int_equal(ggSceneAddPolygon(s, 0, NULL, 3), -GG_ERROR_INVALID);
    COVER(ggSceneAddTriangle),
        assert_int_equal(ggSceneAddTriangle(NULL, 0, v, NULL), -GG_ERROR_INVALID);
    assert_int_equal(ggSceneAddTriangle(s, 0, NULL, NULL), -GG_ERROR_INVALID);
    COVER(ggSceneAddCone);
    assert_int_equal(ggSceneAddCone(NULL, 0, v[0], 1, v[1], 0), -GG_ERROR_INVALID);
    COVER(ggSceneAddRect),
        assert_int_equal(ggSceneAddRect(NULL, 0, v[0], v[1], v[2]), -GG_ERROR_INVALID);
    COVER(ggSceneAddImplicit);
    assert_int_equal(ggImplicitCreateExpr("x", v[0], (ggVec3){1, 1, 1}, NULL, &imp, NULL), GG_OK);
    assert_int_equal(ggSceneAddImplicit(NULL, 0, imp), -GG_ERROR_INVALID); /* frees imp */
    assert_int_equal(ggSceneAddImplicit(s, 0, NULL), -GG_ERROR_INVALID);
    COVER(ggMeshOptionsDefault), ggMeshOptionsDefault(NULL), ggMeshOptionsDefault(&mo);
    COVER(ggSceneLoadMesh),
        assert_int_equal(ggSceneLoadMesh(NULL, "x.obj", NULL, NULL), GG_ERROR_INVALID);
    assert_int_equal(ggSceneLoadMesh(s, NULL, NULL, NULL), GG_ERROR_INVALID);
    COVER(ggSceneLoadMeshMemory);
    assert_int_equal(ggSceneLoadMeshMemory(NULL, "v 0 0 0\n", 8, "m.obj", NULL, NULL),
                     GG_ERROR_INVALID);
    assert_int_equal(ggSceneLoadMeshMemory(s, NULL, 8, "m.obj", NULL, NULL), GG_ERROR_INVALID);
    COVER(ggSceneAddMesh),
        assert_int_equal(ggSceneAddMesh(NULL, &md, &mo, NULL), -GG_ERROR_INVALID);
    assert_int_equal(ggSceneAddMesh(s, NULL, &mo, NULL), -GG_ERROR_INVALID);
    COVER(ggSceneFrame),
        assert_int_equal(ggSceneFrame(NULL, GG_FRAME_CAMERA, NULL), GG_ERROR_INVALID);
    COVER(ggSceneSetTextureBudget), assert_true(ggSceneSetTextureBudget(NULL, 1) == -1);
    COVER(ggSceneSetDepth), assert_int_equal(ggSceneSetDepth(NULL, 3), GG_ERROR_INVALID);
    COVER(ggSceneSetSamples), assert_int_equal(ggSceneSetSamples(NULL, 3), GG_ERROR_INVALID);
    COVER(ggSceneLastError), assert_null(ggSceneLastError(NULL));
    /* Nothing above reached the scene. */
    assert_int_equal(ggSceneObjectCount(s), 0);
    assert_int_equal(ggSceneMaterialCount(s), 0);
    ggSceneFree(s);
}

static void test_scene_query(void **state)
{
    ggScene *s = scene();
    ggRay r = {{0, 0, 5}, {0, 0, -1}};
    ggShapeDesc d;
    ggMeshInfo mi;
    ggFaceInfo fi;
    ggSceneInfo si;
    ggHit h;
    ggVec3 p = {7, 7, 7};
    ggColor c = {7, 7, 7};
    (void)state;
    COVER(ggSceneObjectCount), assert_int_equal(ggSceneObjectCount(NULL), 0);
    COVER(ggSceneLightCount), assert_int_equal(ggSceneLightCount(NULL), 0);
    COVER(ggSceneMaterialCount), assert_int_equal(ggSceneMaterialCount(NULL), 0);
    COVER(ggSceneMaterial), assert_true(ggSceneMaterial(NULL, 0).kd == ggMaterialDefault().kd);
    COVER(ggSceneObjectKind), assert_int_equal(ggSceneObjectKind(NULL, 0), -1);
    COVER(ggSceneObjectMaterial), assert_int_equal(ggSceneObjectMaterial(NULL, 0), -1);
    COVER(ggSceneObjectLine), assert_int_equal(ggSceneObjectLine(NULL, 0), 0);
    memset(&d, 0xff, sizeof d), memset(&mi, 0xff, sizeof mi), memset(&fi, 0xff, sizeof fi);
    memset(&si, 0xff, sizeof si), memset(&h, 0xff, sizeof h);
    COVER(ggSceneObjectShape), assert_int_equal(ggSceneObjectShape(NULL, 0, &d), GG_ERROR_INVALID);
    assert_true(all_ff(&d, sizeof d));
    assert_int_equal(ggSceneObjectShape(s, 0, NULL), GG_ERROR_INVALID);
    COVER(ggSceneGetLight), assert_int_equal(ggSceneGetLight(NULL, 0, &p, &c), GG_ERROR_INVALID);
    assert_true(p.x == 7 && c.r == 7);
    assert_int_equal(ggSceneGetLight(s, 0, NULL, NULL), GG_OK);
    COVER(ggSceneMeshCount), assert_int_equal(ggSceneMeshCount(NULL), 0);
    COVER(ggSceneObjectMesh), assert_int_equal(ggSceneObjectMesh(NULL, 0), -1);
    COVER(ggSceneGetMeshInfo), assert_int_equal(ggSceneGetMeshInfo(NULL, 0, &mi), GG_ERROR_INVALID);
    assert_true(all_ff(&mi, sizeof mi));
    assert_int_equal(ggSceneGetMeshInfo(s, 0, NULL), GG_ERROR_INVALID);
    COVER(ggSceneGetFaceInfo),
        assert_int_equal(ggSceneGetFaceInfo(NULL, 0, 0, &fi), GG_ERROR_INVALID);
    assert_true(all_ff(&fi, sizeof fi));
    assert_int_equal(ggSceneGetFaceInfo(s, 0, 0, NULL), GG_ERROR_INVALID);
    COVER(ggSceneObjectTriangleCount), assert_int_equal(ggSceneObjectTriangleCount(NULL, 0), 0);
    COVER(ggSceneObjectTriangle),
        assert_int_equal(ggSceneObjectTriangle(NULL, 0, 0, NULL, NULL), GG_ERROR_INVALID);
    {
        ggTriangulation *tr = (ggTriangulation *)&tr;
        COVER(ggSceneObjectTriangulate);
        assert_int_equal(ggSceneObjectTriangulate(NULL, 0, 8, 0, &tr), GG_ERROR_INVALID);
        UNTOUCHED(tr);
        assert_int_equal(ggSceneObjectTriangulate(s, 0, 8, 0, NULL), GG_ERROR_INVALID);
    }
    COVER(ggSceneTextureCount), assert_int_equal(ggSceneTextureCount(NULL), 0);
    {
        ggTextureInfo ti;
        double uv[2] = {7, 7};
        memset(&ti, 0xff, sizeof ti);
        COVER(ggSceneGetTexture),
            assert_int_equal(ggSceneGetTexture(NULL, 0, &ti), GG_ERROR_INVALID);
        assert_true(all_ff(&ti, sizeof ti));
        assert_int_equal(ggSceneGetTexture(s, 0, NULL), GG_ERROR_INVALID);
        COVER(ggSceneObjectUV),
            assert_int_equal(ggSceneObjectUV(NULL, 0, 0, &p, 1, uv), GG_ERROR_INVALID);
        assert_true(uv[0] == 7 && uv[1] == 7);
        assert_int_equal(ggSceneObjectUV(s, 0, 0, NULL, 1, uv), GG_ERROR_INVALID);
        assert_int_equal(ggSceneObjectUV(s, 0, 0, &p, 1, NULL), GG_ERROR_INVALID);
    }
    COVER(ggSceneFileName), assert_string_equal(ggSceneFileName(NULL), "");
    COVER(ggSceneInputCount), assert_int_equal(ggSceneInputCount(NULL), 0);
    COVER(ggSceneInputFile), assert_null(ggSceneInputFile(NULL, 0));
    COVER(ggScenePrepare), assert_int_equal(ggScenePrepare(NULL, NULL), GG_ERROR_INVALID);
    COVER(ggSceneGetInfo), assert_int_equal(ggSceneGetInfo(NULL, &si), GG_ERROR_INVALID);
    assert_true(all_ff(&si, sizeof si));
    assert_int_equal(ggSceneGetInfo(s, NULL), GG_ERROR_INVALID);
    COVER(ggSceneTraversal), assert_null(ggSceneTraversal(NULL));
    COVER(ggSceneIntersect), assert_false(ggSceneIntersect(NULL, r, 0, 100, &h));
    assert_true(all_ff(&h, sizeof h));
    assert_true(ggSceneIntersect(s, r, 0, 100, NULL));
    COVER(ggSceneOccluded), assert_false(ggSceneOccluded(NULL, r, 0, 100));
    ggSceneFree(s);
}

static void test_render_trace(void **state)
{
    ggScene *s = scene();
    ggImage *img = (ggImage *)&img;
    ggTrace *t = ggTraceCreate(NULL);
    ggRayStats st;
    ggColor px;
    ggRay r = {{0, 0, 5}, {0, 0, -1}}, cr;
    ggRenderOptions o;
    (void)state;
    COVER(ggEffectName), assert_string_equal(ggEffectName(0), "?");
    COVER(ggSceneEffects), assert_int_equal(ggSceneEffects(NULL), 0);
    COVER(ggSceneEffectReason), assert_null(ggSceneEffectReason(NULL, GG_EFFECT_SHADOWS));
    COVER(ggRenderOptionsDefault), ggRenderOptionsDefault(NULL), ggRenderOptionsDefault(&o);
    {
        ggRenderOptions keep;
        memset(&keep, 0xff, sizeof keep);
        COVER(ggRenderOptionsResolve);
        assert_int_equal(ggRenderOptionsResolve(NULL, &o, &keep), GG_ERROR_INVALID);
        assert_int_equal(ggRenderOptionsResolve(s, NULL, &keep), GG_ERROR_INVALID);
        assert_int_equal(ggRenderOptionsResolve(s, &o, NULL), GG_ERROR_INVALID);
        assert_true(all_ff(&keep, sizeof keep));
    }
    /* stats too stay as they were (rule 1 before rule 2: they were zeroed) */
    memset(&st, 0xff, sizeof st);
    COVER(ggRender), assert_int_equal(ggRender(NULL, NULL, &img, &st, NULL), GG_ERROR_INVALID);
    assert_ptr_equal(img, (ggImage *)&img);
    assert_int_equal(ggRender(s, NULL, NULL, &st, NULL), GG_ERROR_INVALID);
    assert_true(all_ff(&st, sizeof st));
    COVER(ggCameraRay), cr = ggCameraRay(NULL, NULL, 0, 0);
    assert_true(cr.o.x == 0 && cr.d.x == 0 && cr.d.y == 0 && cr.d.z == 0);
    COVER(ggRayColor), assert_true(is_black(ggRayColor(NULL, NULL, r, 1, &st)));
    assert_true(all_ff(&st, sizeof st));
    COVER(ggRayStatsAdd), ggRayStatsAdd(NULL, &st), ggRayStatsAdd(&st, NULL);
    {
        ggKernelCounts kc;
        memset(&kc, 0xff, sizeof kc);
        COVER(ggRenderCountKernels);
        assert_int_equal(ggRenderCountKernels(NULL, NULL, &kc, NULL), GG_ERROR_INVALID);
        assert_true(all_ff(&kc, sizeof kc));
        assert_int_equal(ggRenderCountKernels(s, NULL, NULL, NULL), GG_ERROR_INVALID);
        COVER(ggKernelLoop), assert_true(ggKernelLoop(NULL, NULL, GG_KERNEL_NODE, 10) < 0);
        assert_true(ggKernelLoop(s, NULL, -1, 10) < 0);
        assert_true(ggKernelLoop(s, NULL, GG_KERNEL_KINDS, 10) < 0);
    }
    COVER(ggTraceCreate), ggTraceFree(ggTraceCreate(NULL));
    COVER(ggTraceFree), ggTraceFree(NULL);
    COVER(ggTraceNodeCount), assert_int_equal(ggTraceNodeCount(NULL), 0);
    COVER(ggTraceGetNode), assert_null(ggTraceGetNode(NULL, 0));
    COVER(ggTraceLightCount), assert_int_equal(ggTraceLightCount(NULL), 0);
    COVER(ggTraceGetLight), assert_null(ggTraceGetLight(NULL, 0));
    COVER(ggTracePixel);
    assert_int_equal(ggTracePixel(NULL, NULL, 1, 1, -1, t, &px, &st, NULL), GG_ERROR_INVALID);
    assert_int_equal(ggTracePixel(s, NULL, 1, 1, -1, NULL, &px, &st, NULL), GG_ERROR_INVALID);
    assert_int_equal(ggTracePixel(s, NULL, 1, 1, -1, t, NULL, &st, NULL), GG_ERROR_INVALID);
    assert_true(all_ff(&st, sizeof st));
    COVER(ggRayKindName), assert_string_equal(ggRayKindName(-1), "?");
    COVER(ggStopName), assert_string_equal(ggStopName(-1), "?");
    COVER(ggShadowName), assert_string_equal(ggShadowName(-1), "?");
    ggTraceFree(t);
    ggSceneFree(s);
}

static void test_debug(void **state)
{
    ggScene *s = scene();
    ggTrace *t = ggTraceCreate(NULL);
    ggPredicate *p = (ggPredicate *)&p;
    ggFindResult *fr = (ggFindResult *)&fr;
    ggCheckResult *cr = (ggCheckResult *)&cr;
    ggDiffResult *dr = (ggDiffResult *)&dr;
    ggLedger *lg = (ggLedger *)&lg;
    ggRenderOptions o;
    ggColor px = {0, 0, 0};
    char buf[8] = "x";
    ggDivergence dv;
    (void)state;
    ggRenderOptionsDefault(&o);
    COVER(ggRenderOptionsParse),
        assert_int_equal(ggRenderOptionsParse(NULL, "depth=3", NULL), GG_ERROR_INVALID);
    assert_int_equal(ggRenderOptionsParse(&o, NULL, NULL), GG_ERROR_INVALID);
    COVER(ggRenderOptionsFormat), assert_int_equal(ggRenderOptionsFormat(NULL, buf, sizeof buf), 0);
    assert_string_equal(buf, "");
    o.max_depth = 3; /* a NULL buffer only measures, whatever size says */
    assert_int_equal(ggRenderOptionsFormat(&o, NULL, 64), strlen("depth=3"));
    assert_int_equal(ggRenderOptionsFormat(&o, NULL, 0), strlen("depth=3"));
    o.max_depth = 0;
    COVER(ggPredicateParse),
        assert_int_equal(ggPredicateParse(NULL, NULL, &p, NULL), GG_ERROR_INVALID);
    UNTOUCHED(p);
    assert_int_equal(ggPredicateParse("some(kind == eye)", NULL, NULL, NULL), GG_ERROR_INVALID);
    COVER(ggPredicateFree), ggPredicateFree(NULL);
    COVER(ggPredicateMatch), assert_int_equal(ggPredicateMatch(NULL, t, 0, 0, px), 0);
    assert_int_equal(ggPredicateParse("some(kind == eye)", NULL, &p, NULL), GG_OK);
    assert_int_equal(ggPredicateMatch(p, NULL, 0, 0, px), 0);
    COVER(ggFind), assert_int_equal(ggFind(NULL, NULL, p, 0, &fr, NULL), GG_ERROR_INVALID);
    UNTOUCHED(fr);
    assert_int_equal(ggFind(s, NULL, NULL, 0, &fr, NULL), GG_ERROR_INVALID);
    UNTOUCHED(fr);
    assert_int_equal(ggFind(s, NULL, p, 0, NULL, NULL), GG_ERROR_INVALID);
    COVER(ggFindResultFree), ggFindResultFree(NULL);
    COVER(ggCheckName), assert_string_equal(ggCheckName(-1), "?");
    COVER(ggSeverityName), assert_string_equal(ggSeverityName(-1), "?");
    COVER(ggCheckOptionsDefault), ggCheckOptionsDefault(NULL);
    COVER(ggCheck), assert_int_equal(ggCheck(NULL, NULL, NULL, &cr, NULL), GG_ERROR_INVALID);
    UNTOUCHED(cr);
    assert_int_equal(ggCheck(s, NULL, NULL, NULL, NULL), GG_ERROR_INVALID);
    COVER(ggCheckResultFree), ggCheckResultFree(NULL);
    COVER(ggTermName), assert_string_equal(ggTermName(-1), "?");
    COVER(ggLedgerCreate),
        assert_int_equal(ggLedgerCreate(NULL, px, NULL, &lg, NULL), GG_ERROR_INVALID);
    UNTOUCHED(lg);
    assert_int_equal(ggLedgerCreate(t, px, NULL, NULL, NULL), GG_ERROR_INVALID);
    COVER(ggLedgerFree), ggLedgerFree(NULL);
    COVER(ggDiffName), assert_string_equal(ggDiffName(-1), "?");
    /* Documented: NULL traces compare as empty. */
    COVER(ggTraceCompare), assert_int_equal(ggTraceCompare(NULL, NULL, &dv), 0);
    assert_int_equal(dv.what, GG_DIFF_SAME);
    assert_int_equal(ggTraceCompare(NULL, NULL, NULL), 0);
    COVER(ggDiff), assert_int_equal(ggDiff(NULL, NULL, s, NULL, 1, &dr, NULL), GG_ERROR_INVALID);
    UNTOUCHED(dr);
    assert_int_equal(ggDiff(s, NULL, NULL, NULL, 1, &dr, NULL), GG_ERROR_INVALID);
    UNTOUCHED(dr);
    assert_int_equal(ggDiff(s, NULL, s, NULL, 1, NULL, NULL), GG_ERROR_INVALID);
    COVER(ggDiffResultFree), ggDiffResultFree(NULL);
    ggPredicateFree(p);
    ggTraceFree(t);
    ggSceneFree(s);
}

/* Path layers (debug.h, "ggPathLayersCompile"; render.h's layers) and
   OpenEXR layers (image.h). */
static void test_layers(void **state)
{
    ggPathLayers *l = (ggPathLayers *)&l;
    const char *ex[2] = {"CB", NULL};
    ggImage *img = ggImageCreate(2, 2, NULL), *out = (ggImage *)&out;
    const char *names[1] = {"a"};
    const ggImage *layers[1];
    ggScene *s = scene();
    ggRenderOptions o;
    ggImage *r = NULL;
    float map[2 * 2 * 3];
    ggError e;
    (void)state;
    layers[0] = img;
    COVER(ggPathLayersCompile),
        assert_int_equal(ggPathLayersCompile(NULL, 1, NULL, &l, &e), GG_ERROR_INVALID);
    UNTOUCHED(l);
    assert_int_equal(ggPathLayersCompile(ex, 1, NULL, NULL, &e), GG_ERROR_INVALID);
    /* a NULL element */
    assert_int_equal(ggPathLayersCompile(ex, 2, NULL, &l, &e), GG_ERROR_INVALID);
    assert_null(l);
    COVER(ggPathLayersCount), assert_int_equal(ggPathLayersCount(NULL), 0);
    COVER(ggPathLayersFree), ggPathLayersFree(NULL);
    /* layers without a map, and a map without layers */
    assert_int_equal(ggPathLayersCompile(ex, 1, NULL, &l, NULL), GG_OK);
    ggRenderOptionsDefault(&o);
    o.width = o.height = 2, o.layers = l;
    assert_int_equal(ggRender(s, &o, &r, NULL, NULL), GG_ERROR_INVALID);
    o.layers = NULL, o.layer_map = map;
    assert_int_equal(ggRender(s, &o, &r, NULL, NULL), GG_ERROR_INVALID);
    assert_null(r);
    ggPathLayersFree(l);
    COVER(ggImageWriteEXRLayers),
        assert_int_equal(ggImageWriteEXRLayers(NULL, layers, names, 1, NULL, "x.exr", &e),
                         GG_ERROR_INVALID);
    assert_int_equal(ggImageWriteEXRLayers(img, NULL, names, 1, NULL, "x.exr", &e),
                     GG_ERROR_INVALID);
    assert_int_equal(ggImageWriteEXRLayers(img, layers, NULL, 1, NULL, "x.exr", &e),
                     GG_ERROR_INVALID);
    assert_int_equal(ggImageWriteEXRLayers(img, layers, names, 1, NULL, NULL, &e),
                     GG_ERROR_INVALID);
    COVER(ggImageWriteEXRLayerMap),
        assert_int_equal(ggImageWriteEXRLayerMap(NULL, map, names, 1, NULL, "x.exr", &e),
                         GG_ERROR_INVALID);
    assert_int_equal(ggImageWriteEXRLayerMap(img, NULL, names, 1, NULL, "x.exr", &e),
                     GG_ERROR_INVALID);
    assert_int_equal(ggImageWriteEXRLayerMap(img, map, NULL, 1, NULL, "x.exr", &e),
                     GG_ERROR_INVALID);
    assert_int_equal(ggImageWriteEXRLayerMap(img, map, names, 1, NULL, NULL, &e), GG_ERROR_INVALID);
    COVER(ggImageReadEXRLayer),
        assert_int_equal(ggImageReadEXRLayer(NULL, "a", NULL, &out, &e), GG_ERROR_INVALID);
    UNTOUCHED(out);
    assert_int_equal(ggImageReadEXRLayer("x.exr", "a", NULL, NULL, &e), GG_ERROR_INVALID);
    ggImageFree(img);
    ggSceneFree(s);
}

/* The light-path expressions (include/ggrt/debug.h, "ggPathParse"). */
static void test_path(void **state)
{
    ggScene *s = scene();
    ggTrace *t = ggTraceCreate(NULL);
    ggPathExpr *e = (ggPathExpr *)&e;
    ggFindResult *fr = (ggFindResult *)&fr;
    ggDiffResult *dr = (ggDiffResult *)&dr;
    ggColor px = {0, 0, 0};
    ggPathSummary sum;
    unsigned char m[4];
    char buf[8] = "x";
    (void)state;
    COVER(ggPathParse), assert_int_equal(ggPathParse(NULL, NULL, &e, NULL), GG_ERROR_INVALID);
    UNTOUCHED(e);
    assert_int_equal(ggPathParse("C.*", NULL, NULL, NULL), GG_ERROR_INVALID);
    COVER(ggPathFree), ggPathFree(NULL);
    assert_int_equal(ggPathParse("C.*", NULL, &e, NULL), GG_OK);
    memset(&sum, 0xff, sizeof sum);
    COVER(ggPathMatch), assert_int_equal(ggPathMatch(NULL, t, 0, 0, px, NULL, NULL, &sum),
                                         GG_ERROR_INVALID);
    assert_int_equal(ggPathMatch(e, NULL, 0, 0, px, NULL, NULL, &sum), GG_ERROR_INVALID);
    assert_true(all_ff(&sum, sizeof sum));
    assert_int_equal(ggPathMatch(e, t, 0, 0, px, NULL, NULL, NULL), GG_ERROR_INVALID);
    /* matched without a ledger */
    assert_int_equal(ggPathMatch(e, t, 0, 0, px, NULL, m, &sum), GG_ERROR_INVALID);
    COVER(ggPathPoints), assert_int_equal(ggPathPoints(NULL, NULL, NULL, 0), 0);
    COVER(ggDiffPath),
        assert_int_equal(ggDiffPath(NULL, NULL, s, NULL, e, 1, 0, &dr, NULL), GG_ERROR_INVALID);
    UNTOUCHED(dr);
    assert_int_equal(ggDiffPath(s, NULL, s, NULL, NULL, 1, 0, &dr, NULL), GG_ERROR_INVALID);
    UNTOUCHED(dr);
    assert_int_equal(ggDiffPath(s, NULL, s, NULL, e, 1, -1, &dr, NULL), GG_ERROR_INVALID);
    assert_int_equal(ggDiffPath(s, NULL, s, NULL, e, 1, 0, NULL, NULL), GG_ERROR_INVALID);
    COVER(ggPathFormat), assert_int_equal(ggPathFormat(NULL, NULL, buf, sizeof buf), 0);
    assert_string_equal(buf, "");
    COVER(ggFindPath), assert_int_equal(ggFindPath(NULL, NULL, e, 0, &fr, NULL), GG_ERROR_INVALID);
    UNTOUCHED(fr);
    assert_int_equal(ggFindPath(s, NULL, NULL, 0, &fr, NULL), GG_ERROR_INVALID);
    UNTOUCHED(fr);
    assert_int_equal(ggFindPath(s, NULL, e, 0, NULL, NULL), GG_ERROR_INVALID);
    ggPathFree(e);
    ggTraceFree(t);
    ggSceneFree(s);
}

/* ---- statistics are overwritten, never added to ---- */

static bool same_stats(const ggRayStats *a, const ggRayStats *b)
{
    return a->eye == b->eye && a->eye_hit == b->eye_hit && a->reflect == b->reflect &&
           a->refract == b->refract && a->shadow == b->shadow && a->tir == b->tir &&
           a->nonfinite == b->nonfinite && a->max_depth == b->max_depth &&
           a->budget_cut == b->budget_cut && a->implicit_cut == b->implicit_cut &&
           a->shadow_blocked == b->shadow_blocked && a->shadow_attenuated == b->shadow_attenuated;
}

static void test_stats_overwritten(void **state)
{
    ggScene *s = scene();
    ggTrace *t = ggTraceCreate(NULL);
    ggImage *img = NULL;
    ggRayStats once, twice, junk;
    ggRay r = {{0, 0, 5}, {0, 0, -1}};
    ggColor px;
    (void)state;
    memset(&junk, 0x5a, sizeof junk);
    assert_int_equal(ggRender(s, NULL, &img, &once, NULL), GG_OK);
    ggImageFree(img);
    twice = junk;
    assert_int_equal(ggRender(s, NULL, &img, &twice, NULL), GG_OK);
    ggImageFree(img);
    assert_true(once.eye == 48 && same_stats(&once, &twice));
    (void)ggRayColor(s, NULL, r, 1, &once);
    twice = junk;
    (void)ggRayColor(s, NULL, r, 1, &twice);
    assert_true(once.shadow > 0 && same_stats(&once, &twice));
    assert_int_equal(ggTracePixel(s, NULL, 4, 3, -1, t, &px, &once, NULL), GG_OK);
    twice = junk;
    assert_int_equal(ggTracePixel(s, NULL, 4, 3, -1, t, &px, &twice, NULL), GG_OK);
    assert_true(once.eye == 1 && same_stats(&once, &twice));
    /* Failures leave the counts of the call: none. */
    twice = junk;
    assert_int_equal(ggTracePixel(s, NULL, 99, 3, -1, t, &px, &twice, NULL), GG_ERROR_INVALID);
    assert_true(twice.eye == 0 && twice.shadow == 0 && twice.max_depth == 0);
    ggTraceFree(t);
    ggSceneFree(s);
}

/* ---- allocators are copied ---- */

static long live_blocks;
static void *c_malloc(void *ud, size_t n)
{
    void *p = malloc(n);
    (void)ud;
    if (p) live_blocks++;
    return p;
}
static void *c_realloc(void *ud, void *p, size_t n)
{
    void *q = realloc(p, n);
    (void)ud;
    if (q && !p) live_blocks++;
    return q;
}
static void c_free(void *ud, void *p)
{
    (void)ud;
    if (p) live_blocks--;
    free(p);
}

/* Each object is made with an allocator variable that is wiped right
   after: objects that kept a pointer to it would crash or leak. */
static void test_allocator_copied(void **state)
{
    const ggAllocator counting = {c_malloc, c_realloc, c_free, NULL};
    ggVec3 lo = {-1, -1, -1}, hi = {1, 1, 1};
    ggAllocator a;
    ggImage *img, *rd = NULL;
    ggScene *s;
    ggTrace *t;
    ggImplicit *ie, *ifn;
    ggPredicate *p;
    ggLedger *lg;
    ggColor px;
    (void)state;
    live_blocks = 0;
    a = counting, img = ggImageCreate(4, 4, &a), memset(&a, 0, sizeof a);
    a = counting, s = ggSceneCreate(&a), memset(&a, 0, sizeof a);
    a = counting, t = ggTraceCreate(&a), memset(&a, 0, sizeof a);
    a = counting;
    assert_int_equal(ggImplicitCreateExpr("x^2 + y^2 + z^2 - 0.5", lo, hi, &a, &ie, NULL), GG_OK);
    memset(&a, 0, sizeof a);
    a = counting;
    assert_int_equal(ggImplicitCreateFn(sphere_f, NULL, NULL, lo, hi, &a, &ifn, NULL), GG_OK);
    memset(&a, 0, sizeof a);
    a = counting;
    assert_int_equal(ggPredicateParse("some(kind == eye)", &a, &p, NULL), GG_OK);
    memset(&a, 0, sizeof a);
    a = counting;
    assert_int_equal(ggImageRead("examples/scenes/texture.png", &a, &rd, NULL), GG_OK);
    memset(&a, 0, sizeof a);
    assert_non_null(img), assert_non_null(s), assert_non_null(t);
    assert_int_equal(ggSceneLoadString(s, scene_text, sizeof scene_text - 1, NULL, NULL), GG_OK);
    assert_int_equal(ggTracePixel(s, NULL, 4, 3, -1, t, &px, NULL, NULL), GG_OK);
    a = counting;
    assert_int_equal(ggLedgerCreate(t, px, &a, &lg, NULL), GG_OK);
    memset(&a, 0, sizeof a);
    assert_true(live_blocks > 0);
    ggImplicitFree(ie);
    ggImplicitFree(ifn);
    ggLedgerFree(lg);
    ggPredicateFree(p);
    ggTraceFree(t);
    ggSceneFree(s);
    ggImageFree(img);
    ggImageFree(rd);
    assert_int_equal(live_blocks, 0);
}

/* ---- every GG_API declaration is covered ---- */

/* Append the names declared "GG_API type name(" at the start of a line of
   file `path` to names[]. */
static void read_decls(const char *path, char **names, int *n)
{
    FILE *f = fopen(path, "r");
    char line[1024];
    assert_non_null(f);
    while (fgets(line, sizeof line, f)) {
        const char *p = line, *paren, *q;
        while (*p == ' ' || *p == '\t') p++;
        if (strncmp(p, "GG_API ", 7) != 0 || !(paren = strchr(p, '('))) continue;
        q = paren;
        while (q > p && q[-1] == ' ') q--;
        paren = q;
        while (q > p && (q[-1] == '_' || (q[-1] >= 'a' && q[-1] <= 'z') ||
                         (q[-1] >= 'A' && q[-1] <= 'Z') || (q[-1] >= '0' && q[-1] <= '9')))
            q--;
        assert_true(*n < MAX_NAMES);
        names[*n] = calloc(1, (size_t)(paren - q) + 1);
        memcpy(names[*n], q, (size_t)(paren - q));
        (*n)++;
    }
    fclose(f);
}

static bool listed(const char *name, const char *const *list, int n)
{
    int i;
    for (i = 0; i < n; i++)
        if (strcmp(name, list[i]) == 0) return true;
    return false;
}

static void test_every_function_covered(void **state)
{
    char *decl[MAX_NAMES], path[512];
    int ndecl = 0, i, missing = 0, headers = 0;
    DIR *d;
    struct dirent *de;
    (void)state;
    read_decls("include/ggrt.h", decl, &ndecl);
    d = opendir("include/ggrt");
    assert_non_null(d);
    while ((de = readdir(d)) != NULL) {
        size_t len = strlen(de->d_name);
        if (len < 3 || strcmp(de->d_name + len - 2, ".h") != 0) continue;
        snprintf(path, sizeof path, "include/ggrt/%s", de->d_name);
        read_decls(path, decl, &ndecl);
        headers++;
    }
    closedir(d);
    /* A parse that finds nothing would prove nothing. */
    assert_true(headers >= 8 && ndecl >= 100);
    for (i = 0; i < ndecl; i++)
        if (!listed(decl[i], covered, ncovered)) {
            print_error("%s is declared GG_API in include/ but test_null.c does not cover it\n",
                        decl[i]);
            missing++;
        }
    for (i = 0; i < ncovered; i++)
        if (!listed(covered[i], (const char *const *)decl, ndecl)) {
            print_error("test_null.c covers %s, which include/ does not declare\n", covered[i]);
            missing++;
        }
    print_message("test_null: %d GG_API functions in %d headers, %d covered\n", ndecl, headers + 1,
                  ncovered);
    for (i = 0; i < ndecl; i++) free(decl[i]);
    assert_int_equal(missing, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_base_optics),
        cmocka_unit_test(test_image),
        cmocka_unit_test(test_implicit),
        cmocka_unit_test(test_scene_build),
        cmocka_unit_test(test_scene_query),
        cmocka_unit_test(test_render_trace),
        cmocka_unit_test(test_debug), cmocka_unit_test(test_path), cmocka_unit_test(test_layers),
        cmocka_unit_test(test_stats_overwritten),
        cmocka_unit_test(test_allocator_copied),
        /* Last: the others record what they cover. */
        cmocka_unit_test(test_every_function_covered),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
