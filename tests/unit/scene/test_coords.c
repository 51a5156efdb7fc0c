/* SPDX-License-Identifier: MIT */
/*
** test_coords.c -- GG_COORD_MAX (scene.h): every shape kind, placed at
** every scale up to the limit, is hit where it is by a ray from afar,
** lets through the light of a light at the limit and blocks it from
** behind; one step beyond the limit, every way of adding it (the building
** functions, ggSceneAddMesh, the NFF loader, a model file) and a light
** there are refused. An audit found triangles, polygons and rectangles
** of 1e77 accepted and never hit (a product of four coordinates
** overflowed); a sphere of 1e20 let a light at 1e150 through; implicit
** surfaces' boxes were not bounded at all.
** And ray directions of every size: base.h lets d be of any length; one
** of 1e300 or 1e-300 was a miss everywhere.
*/
#include "testutil.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static ggVec3 vec3(double x, double y, double z)
{
    ggVec3 r;
    r.x = x, r.y = y, r.z = z;
    return r;
}

static ggVec3 sub3(ggVec3 a, ggVec3 b)
{
    return vec3(a.x - b.x, a.y - b.y, a.z - b.z);
}

enum { SPHERE, TRIANGLE, POLYGON, CONE, RECT, MESH, IMPLICIT, KINDS };
static const char *const kind_name[KINDS] = {"sphere", "triangle", "polygon", "cone",
                                             "rect",   "mesh",     "implicit"};

/* Shape k spanning [-S, S] in x and y around the origin, facing +z (the
   cone lies along y, radius S; the implicit surface is the sphere of
   radius S in the box [-S, S]^3); the return of its ggSceneAdd* call. */
static int add_shape(ggScene *s, int mat, int k, double S)
{
    const ggVec3 q[4] = {vec3(-S, -S, 0), vec3(S, -S, 0), vec3(S, S, 0), vec3(-S, S, 0)};
    const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
    ggMeshData d;
    ggMeshOptions o;
    ggError e;
    ggImplicit *imp;
    char f[96];
    switch (k) {
    case SPHERE:
        return ggSceneAddSphere(s, mat, vec3(0, 0, 0), S);
    case TRIANGLE:
        return ggSceneAddTriangle(s, mat, q, NULL);
    case POLYGON:
        return ggSceneAddPolygon(s, mat, q, 4);
    case CONE:
        return ggSceneAddCone(s, mat, vec3(0, -S, 0), S, vec3(0, S, 0), S);
    case RECT:
        return ggSceneAddRect(s, mat, q[0], vec3(2 * S, 0, 0), vec3(0, 2 * S, 0));
    case IMPLICIT:
        snprintf(f, sizeof f, "x*x + y*y + z*z - %.17g", S * S);
        if (ggImplicitCreateExpr(f, vec3(-S, -S, -S), vec3(S, S, S), NULL, &imp, &e) != GG_OK)
            fail_msg("%s: %s", f, e.message);
        return ggSceneAddImplicit(s, mat, imp);
    default:
        memset(&d, 0, sizeof d);
        d.positions = q, d.npositions = 4, d.indices = idx, d.ntriangles = 2;
        ggMeshOptionsDefault(&o);
        o.material = mat;
        return ggSceneAddMesh(s, &d, &o, &e);
    }
}

/* The largest S for which every coordinate and size add_shape forms
   (the rectangle's edges are 2 S) is within the limit. */
#define S_MAX (GG_COORD_MAX / 2)

static void test_every_scale_is_hit(void **state)
{
    const double scales[] = {1e-3, 1, 1e20, 1e45, 1e60, S_MAX};
    size_t i;
    int k;
    (void)state;
    for (k = 0; k < KINDS; k++)
        for (i = 0; i < sizeof scales / sizeof *scales; i++) {
            const double S = scales[i];
            ggScene *s = ggSceneCreate(NULL);
            ggMaterial m = ggMaterialDefault();
            const ggVec3 light = vec3(0, 0, GG_COORD_MAX);
            ggRay eye, toward, behind;
            ggHit h;
            int mat = ggSceneAddMaterial(s, &m);
            ggError e;
            bool hit, blocked, shadowed;
            double want;
            assert_true(mat >= 0);
            if (add_shape(s, mat, k, S) < 0) fail_msg("%s at %g refused", kind_name[k], S);
            assert_int_equal(ggScenePrepare(s, &e), GG_OK);
            /* from 3 S above, straight down, off the centre */
            eye.o = vec3(0.25 * S, 0.125 * S, 3 * S), eye.d = vec3(0, 0, -1);
            hit = ggSceneIntersect(s, eye, 0, INFINITY, &h);
            /* shadow rays as the renderer casts them, unnormalised, to a
               light at the limit: from just above the hit, and from
               below the shape, which it shadows */
            toward.o = vec3(h.p.x, h.p.y, h.p.z + 1e-6 * S);
            toward.d = sub3(light, toward.o);
            blocked = hit && ggSceneOccluded(s, toward, 0, 1);
            behind.o = vec3(0.25 * S, 0.125 * S, -3 * S), behind.d = sub3(light, behind.o);
            shadowed = ggSceneOccluded(s, behind, 0, 1);
            /* the plane z = 0; the sphere and the cylinder (a cone of
               equal radii) where x^2 + y^2 + z^2 or x^2 + z^2 is S^2 */
            want = 3 * S;
            if (k == SPHERE || k == IMPLICIT) want = (3 - sqrt(1 - 0.015625 - 0.0625)) * S;
            if (k == CONE) want = (3 - sqrt(1 - 0.0625)) * S;
            if (!hit || !(fabs(h.t - want) <= 1e-9 * S) || blocked || !shadowed)
                print_error("%s at S = %g: hit %d at t = %g (want %g), light blocked %d, "
                            "shadow %d\n",
                            kind_name[k], S, hit, hit ? h.t : 0, want, blocked, shadowed);
            assert_true(hit);
            assert_true(fabs(h.t - want) <= 1e-9 * S);
            assert_false(blocked);
            assert_true(shadowed);
            ggSceneFree(s);
        }
}

/* One step past the limit: refused by every way in, the scene unchanged. */
static void test_beyond_is_refused(void **state)
{
    const double S = nextafter(GG_COORD_MAX, INFINITY);
    char text[256];
    ggError e;
    int k;
    (void)state;
    for (k = 0; k < KINDS; k++) {
        ggScene *s = ggSceneCreate(NULL);
        ggMaterial m = ggMaterialDefault();
        int mat = ggSceneAddMaterial(s, &m), rc = add_shape(s, mat, k, S);
        if (rc != -GG_ERROR_INVALID) print_error("%s of %g: %d\n", kind_name[k], S, rc);
        assert_int_equal(rc, -GG_ERROR_INVALID);
        assert_int_equal(ggSceneObjectCount(s), 0);
        ggSceneFree(s);
    }
    {
        ggScene *s = ggSceneCreate(NULL);
        ggColor c = {1, 1, 1};
        assert_int_equal(ggSceneAddLight(s, vec3(0, -S, 0), c), -GG_ERROR_INVALID);
        assert_true(ggSceneAddLight(s, vec3(0, -GG_COORD_MAX, 0), c) >= 0);
        ggSceneFree(s);
    }
    /* the loader says where, and why */
    snprintf(text, sizeof text, "s 0 0 0 1\np 3\n0 0 0\n1 0 0\n0 %.17g 0\n", S);
    {
        ggScene *s = ggSceneCreate(NULL);
        assert_int_equal(ggSceneLoadString(s, text, strlen(text), "c.nff", &e), GG_ERROR_PARSE);
        assert_string_equal(
            e.message, "c.nff:2:1: a coordinate or size is over 1e64 in magnitude (GG_COORD_MAX)");
        assert_int_equal(ggSceneObjectCount(s), 0);
        ggSceneFree(s);
    }
    snprintf(text, sizeof text, "v 0 0 0\nv %.17g 0 0\nv 0 1 0\nf 1 2 3\n", S);
    {
        ggScene *s = ggSceneCreate(NULL);
        ggMeshOptions o;
        int rc;
        ggMeshOptionsDefault(&o);
        o.format = GG_MESH_FORMAT_OBJ;
        rc = ggSceneLoadMeshMemory(s, text, strlen(text), "c.obj", &o, &e);
        assert_int_equal(rc, GG_ERROR_INVALID);
        assert_string_equal(e.message, "c.obj: a vertex is over 1e64 in magnitude (GG_COORD_MAX)");
        ggSceneFree(s);
    }
}

/* The same rays with d scaled by 2^k, k from -1021 to 1023 (exact):
   ggSceneIntersect hits the same object at the same point (t 2^k the
   same within 1e-12; inf where t itself overflows), ggSceneOccluded says
   the same, ggRayColor gives the same bits; ggImplicitIntersect likewise.
   Scenes with spheres, glass, an implicit surface and a mesh. */
static void test_every_direction_size(void **state)
{
    static const char *files[] = {"examples/scenes/glass.nff", "examples/scenes/torus.nff",
                                  "examples/scenes/knot.nff"};
    size_t f;
    int k, i, hits = 0, n = 0;
    (void)state;
    for (f = 0; f < sizeof files / sizeof files[0]; f++) {
        ggScene *s = tu_load(files[f]);
        ggRenderOptions o;
        ggRenderOptionsDefault(&o);
        o.width = 8, o.height = 6, o.max_depth = 3;
        for (i = 0; i < 48; i++) {
            ggRay r = ggCameraRay(s, &o, i % 8 + 0.5, i / 8 + 0.5);
            ggHit h0, h;
            bool hit0 = ggSceneIntersect(s, r, 0, INFINITY, &h0);
            bool occ0 = ggSceneOccluded(s, r, 0, INFINITY);
            ggColor c0 = ggRayColor(s, &o, r, 1, NULL);
            hits += hit0;
            for (k = -1074; k <= 1023; k += 3) {
                ggRay q = r;
                ggColor c;
                bool hit;
                int exact;
                q.d.x = ldexp(r.d.x, k), q.d.y = ldexp(r.d.y, k), q.d.z = ldexp(r.d.z, k);
                /* below about 2^-1000 a component goes subnormal and loses
                   bits: another direction, only required to give a colour */
                exact = ldexp(q.d.x, -k) == r.d.x && ldexp(q.d.y, -k) == r.d.y &&
                        ldexp(q.d.z, -k) == r.d.z;
                c = ggRayColor(s, &o, q, 1, NULL);
                assert_true(isfinite(c.r) && isfinite(c.g) && isfinite(c.b));
                if (!exact) continue;
                hit = ggSceneIntersect(s, q, 0, INFINITY, &h);
                if (hit != hit0 || (hit && h.object != h0.object))
                    print_error("%s ray %d, d x 2^%d: hit %d object %d, at 1: %d %d\n", files[f], i,
                                k, hit, hit ? h.object : -1, hit0, hit0 ? h0.object : -1);
                assert_true(hit == hit0);
                if (hit) {
                    double t = ldexp(h.t, k);
                    assert_int_equal(h.object, h0.object);
                    assert_true(isinf(h.t) ? ldexp(h0.t, -k) > 1e307
                                           : fabs(t - h0.t) <= 1e-12 * h0.t);
                }
                assert_true(ggSceneOccluded(s, q, 0, INFINITY) == occ0);
                assert_memory_equal(&c, &c0, sizeof c);
                n++;
            }
        }
        ggSceneFree(s);
    }
    {
        ggImplicit *imp = NULL;
        double t0, t;
        ggRay r = {{-3, 0.1, 0.2}, {1, 0.01, 0}};
        assert_int_equal(ggImplicitCreateExpr("x^2+y^2+z^2-1", vec3(-2, -2, -2), vec3(2, 2, 2),
                                              NULL, &imp, NULL),
                         GG_OK);
        assert_true(ggImplicitIntersect(imp, r, 0, INFINITY, &t0));
        for (k = -1021; k <= 1023; k++) {
            ggRay q = r;
            q.d.x = ldexp(r.d.x, k), q.d.y = ldexp(r.d.y, k);
            assert_true(ggImplicitIntersect(imp, q, 0, INFINITY, &t));
            assert_true(fabs(ldexp(t, k) - t0) <= 1e-12 * t0);
        }
        ggImplicitFree(imp);
    }
    print_message("direction sizes: %d rays (%d hitting) at %d scales each, the same answers\n",
                  3 * 48, hits, n / (3 * 48));
}

/* Shape k at scale S, a camera 3 S above looking at it off its centre
   (12x12), two lights: a scene that spans 3 S, not prepared. */
static ggScene *scaled_scene(int k, double S)
{
    ggScene *s = ggSceneCreate(NULL);
    ggMaterial m = ggMaterialDefault();
    ggCamera cam;
    int mat;
    m.ks = 0.4, m.shine = 20;
    mat = ggSceneAddMaterial(s, &m);
    if (add_shape(s, mat, k, S) < 0) fail_msg("%s at %g refused", kind_name[k], S);
    cam.from = vec3(0.75 * S, -1.25 * S, 3 * S), cam.at = vec3(0.125 * S, 0.25 * S, 0);
    cam.up = vec3(0, 0, 1), cam.fov_deg = 50, cam.width = 12, cam.height = 12;
    if (ggSceneSetCamera(s, &cam) != GG_OK) fail_msg("%s at %g: camera refused", kind_name[k], S);
    assert_true(ggSceneAddLight(s, vec3(2 * S, -3 * S, 5 * S), (ggColor){1, 1, 1}) >= 0);
    assert_true(ggSceneAddLight(s, vec3(-3 * S, 1 * S, 4 * S), (ggColor){0.5, 0.5, 0.5}) >= 0);
    return s;
}

/* scaled_scene(k, 2^e) rendered on one thread: the image's floats. */
static void render_scaled(int k, int e, float *px)
{
    ggScene *s = scaled_scene(k, ldexp(1, e));
    ggRenderOptions o;
    ggImage *img = NULL;
    ggError err;
    if (ggScenePrepare(s, &err) != GG_OK) fail_msg("%s at 2^%d: %s", kind_name[k], e, err.message);
    ggRenderOptionsDefault(&o);
    o.threads = 1;
    if (ggRender(s, &o, &img, NULL, &err) != GG_OK)
        fail_msg("%s at 2^%d: %s", kind_name[k], e, err.message);
    memcpy(px, ggImagePixelsConst(img), 12 * 12 * 3 * sizeof *px);
    ggImageFree(img);
    ggSceneFree(s);
}

/* The same scene at scales 2^e is the same picture: every coordinate
   and size times a power of two is exact, and the library's tests,
   offsets and normalisations are relative. An audit scaled every example
   scene by 2^k and found the images the same for k from -240 to 200, but
   below that squared lengths went subnormal: triangles, polygons and mesh
   faces dropped as degenerate (no warning), rectangles accepted and
   never hit, normals of length 1.3 (a highlight of 1e6). With those
   fixed these renders were the same down to 2^-250 (the cone's fell at
   2^-280); GG_SCENE_SIZE_MIN now refuses what is smaller than 1e-60. */
static void test_scaled_renders_same(void **state)
{
    static const int exps[] = {-100, -150, -196, 100, 150, 200}; /* 2^-196: 3 S > 1e-60 */
    float want[12 * 12 * 3], got[12 * 12 * 3];
    size_t i;
    int k, bad = 0;
    (void)state;
    for (k = 0; k < KINDS; k++) {
        render_scaled(k, 0, want);
        for (i = 0; i < sizeof exps / sizeof *exps; i++) {
            size_t j, diff = 0;
            render_scaled(k, exps[i], got);
            for (j = 0; j < 12 * 12 * 3; j++) diff += memcmp(&got[j], &want[j], sizeof got[j]) != 0;
            if (diff)
                print_error("%s at 2^%d: %zu of %d values differ\n", kind_name[k], exps[i], diff,
                            12 * 12 * 3);
            bad += diff != 0;
        }
    }
    print_message("scales 2^-196 to 2^200: %d of %d renders differ from scale 1\n", bad,
                  (int)(KINDS * (sizeof exps / sizeof *exps)));
    assert_int_equal(bad, 0);
}

/* Flat shapes far smaller than the scene around them, down to 2^-400
   across in a scene a unit wide: hit where they are, with a unit normal.
   Their |e1 x e2|^2 is subnormal or 0 there: triangles, polygons and mesh
   faces were dropped as degenerate (from 2^-268), rectangles' dual basis
   was infinite (from 2^-242) and they were never hit, and normals from
   sqrt(n . n) came out up to 1.3 long. */
static void test_tiny_flat_shapes(void **state)
{
    static const int exps[] = {-250, -270, -300, -330};
    static const int kinds[] = {TRIANGLE, POLYGON, RECT, MESH};
    size_t i, j;
    int bad = 0;
    (void)state;
    for (j = 0; j < sizeof kinds / sizeof *kinds; j++)
        for (i = 0; i < sizeof exps / sizeof *exps; i++) {
            const int k = kinds[j];
            const double S = ldexp(1, exps[i]);
            ggScene *s = ggSceneCreate(NULL);
            ggMaterial m = ggMaterialDefault();
            ggError e;
            ggRay r;
            ggHit h;
            int mat = ggSceneAddMaterial(s, &m), hit;
            double nlen;
            if (add_shape(s, mat, k, S) < 0) fail_msg("%s at 2^%d refused", kind_name[k], exps[i]);
            assert_true(ggSceneAddSphere(s, mat, vec3(0, 0, -10), 1) >=
                        0); /* the scene: a unit or more */
            assert_int_equal(ggScenePrepare(s, &e), GG_OK);
            r.o = vec3(0.25 * S, 0.125 * S, 3 * S), r.d = vec3(0, 0, -1);
            hit = ggSceneIntersect(s, r, 0, INFINITY, &h);
            nlen = hit ? sqrt(h.ng.x * h.ng.x + h.ng.y * h.ng.y + h.ng.z * h.ng.z) : 0;
            if (!hit || h.object != 0 || !(fabs(h.t - 3 * S) <= 1e-12 * S) ||
                !(fabs(nlen - 1) <= 1e-15) || !(fabs(h.ng.z) == nlen)) {
                print_error("%s 2^%d across: hit %d object %d t/S %.17g normal (%g %g %g)\n",
                            kind_name[k], exps[i] + 1, hit, hit ? h.object : -1, hit ? h.t / S : 0,
                            h.ng.x, h.ng.y, h.ng.z);
                bad++;
            }
            ggSceneFree(s);
        }
    assert_int_equal(bad, 0);
}

/* f and c f are one surface with one normal, for any c > 0: the implicit
   unit sphere written as (x^2 + y^2 + z^2 - 1) 2^k, hit above (0.3, 0.4),
   has the normal (0.3, 0.4, 0.75^0.5) at every k whose gradient is a
   finite double. An audit found gradients below about 2^-512 or above
   2^512 (|grad f|^2 out of range) taken as a critical point: the normal
   was -d. */
static void test_implicit_gradient_every_size(void **state)
{
    static const int exps[] = {-1000, -900, -700, -540, -520, -500, 0,
                               500,   520,  540,  700,  900,  1000};
    size_t i;
    int bad = 0;
    (void)state;
    for (i = 0; i < sizeof exps / sizeof *exps; i++) {
        ggScene *s = ggSceneCreate(NULL);
        ggMaterial m = ggMaterialDefault();
        ggImplicit *imp;
        ggError e;
        ggRay r;
        ggHit h;
        char f[96];
        int mat = ggSceneAddMaterial(s, &m);
        snprintf(f, sizeof f, "(x*x + y*y + z*z - 1) * %.17g", ldexp(1, exps[i]));
        if (ggImplicitCreateExpr(f, vec3(-2, -2, -2), vec3(2, 2, 2), NULL, &imp, &e) != GG_OK)
            fail_msg("%s: %s", f, e.message);
        assert_true(ggSceneAddImplicit(s, mat, imp) >= 0);
        assert_int_equal(ggScenePrepare(s, &e), GG_OK);
        r.o = vec3(0.3, 0.4, 5), r.d = vec3(0, 0, -1);
        assert_true(ggSceneIntersect(s, r, 0, INFINITY, &h));
        if (!(fabs(h.ng.x - 0.3) <= 1e-9 && fabs(h.ng.y - 0.4) <= 1e-9 &&
              fabs(h.ng.z - sqrt(0.75)) <= 1e-9)) {
            print_error("f * 2^%d: normal (%.17g %.17g %.17g), want (0.3 0.4 %.17g)\n", exps[i],
                        h.ng.x, h.ng.y, h.ng.z, sqrt(0.75));
            bad++;
        }
        ggSceneFree(s);
    }
    assert_int_equal(bad, 0);
}

/* A scene spanning less than GG_SCENE_SIZE_MIN is refused by
   ggScenePrepare with an error that says so, and renders nothing; one
   spanning just more is prepared. */
static void test_too_small_is_refused(void **state)
{
    const double sizes[] = {GG_SCENE_SIZE_MIN / 4, GG_SCENE_SIZE_MIN * 4};
    int k;
    size_t i;
    (void)state;
    for (k = 0; k < KINDS; k++)
        for (i = 0; i < 2; i++) {
            const double S = sizes[i] / 4; /* the scene spans 3 S */
            ggScene *s = scaled_scene(k, S);
            ggError e;
            ggImage *img = NULL;
            ggRenderOptions o;
            int rc = ggScenePrepare(s, &e);
            if (i == 0) {
                assert_int_equal(rc, GG_ERROR_INVALID);
                assert_non_null(strstr(e.message, "GG_SCENE_SIZE_MIN"));
                ggRenderOptionsDefault(&o);
                o.threads = 1;
                assert_int_equal(ggRender(s, &o, &img, NULL, &e), GG_ERROR_INVALID);
                assert_null(img);
            } else if (rc != GG_OK) {
                fail_msg("%s spanning %g: %s", kind_name[k], 3 * S, e.message);
            }
            ggSceneFree(s);
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_scale_is_hit),
        cmocka_unit_test(test_beyond_is_refused),
        cmocka_unit_test(test_every_direction_size),
        cmocka_unit_test(test_scaled_renders_same),
        cmocka_unit_test(test_too_small_is_refused),
        cmocka_unit_test(test_tiny_flat_shapes),
        cmocka_unit_test(test_implicit_gradient_every_size),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
