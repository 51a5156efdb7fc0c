/* SPDX-License-Identifier: MIT */
/*
** test_mesh.c -- meshes in a scene: ggSceneAddMesh against the same
** triangles added one by one (same image, bit for bit), placement,
** normals (file, computed with creases, flat), objects by material, what
** a hit says about the face, framing, and failures that leave the scene
** as it was.
*/
#include "testutil.h"

#include "scene.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* An octahedron: 6 vertices, 8 triangles, counter-clockwise from outside. */
static const ggVec3 oct_v[6] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
static const uint32_t oct_i[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4,
                                   2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};

static ggMeshData oct_data(void)
{
    ggMeshData d;
    memset(&d, 0, sizeof d);
    d.name = "oct";
    d.positions = oct_v, d.npositions = 6;
    d.indices = oct_i, d.ntriangles = 8;
    return d;
}

static void camera(ggScene *s)
{
    ggCamera c;
    memset(&c, 0, sizeof c);
    c.from = (ggVec3){2.5, 1.8, 3.1}, c.at = (ggVec3){0, 0, 0}, c.up = (ggVec3){0, 1, 0};
    c.fov_deg = 45, c.width = 48, c.height = 40;
    ggSceneSetCamera(s, &c);
    ggSceneAddLight(s, (ggVec3){4, 5, 6}, (ggColor){0.8, 0.8, 0.8});
}

static ggImage *render(ggScene *s)
{
    ggRenderOptions o;
    ggImage *img = NULL;
    ggError e;
    ggRenderOptionsDefault(&o);
    o.threads = 1;
    assert_int_equal(ggRender(s, &o, &img, NULL, &e), GG_OK);
    return img;
}

static int same_image(const ggImage *a, const ggImage *b)
{
    size_t n = (size_t)ggImageWidth(a) * ggImageHeight(a) * 3;
    return ggImageWidth(a) == ggImageWidth(b) && ggImageHeight(a) == ggImageHeight(b) &&
           !memcmp(ggImagePixelsConst(a), ggImagePixelsConst(b), n * sizeof(float));
}

/* The same hits, to the bit, for rays from all around. */
static void same_hits(ggScene *a, ggScene *b)
{
    tu_rng r = {12345};
    int k;
    assert_int_equal(ggScenePrepare(a, NULL), GG_OK);
    assert_int_equal(ggScenePrepare(b, NULL), GG_OK);
    for (k = 0; k < 2000; k++) {
        ggRay ray;
        ggHit ha, hb;
        bool xa, xb;
        ray.o = tu_unit(&r);
        ray.o.x *= 3, ray.o.y *= 3, ray.o.z *= 3;
        ray.d = tu_unit(&r);
        xa = ggSceneIntersect(a, ray, 0, INFINITY, &ha);
        xb = ggSceneIntersect(b, ray, 0, INFINITY, &hb);
        assert_int_equal(xa, xb);
        if (!xa) continue;
        assert_true(ha.t == hb.t && ha.front == hb.front && ha.u == hb.u && ha.v == hb.v);
        assert_memory_equal(&ha.ng, &hb.ng, sizeof ha.ng);
        assert_memory_equal(&ha.ns, &hb.ns, sizeof ha.ns);
        assert_memory_equal(&ha.p, &hb.p, sizeof ha.p);
    }
}

/* A mesh and the same triangles added one by one render the same image
   and give the same hits: flat (passes 0, 2), with vertex normals along
   the winding (1, 3) and against it (4, 5: the triangles' ng flips),
   opaque and glass (2, 3, 5). */
static void test_mesh_equals_triangles(void **state)
{
    int pass;
    (void)state;
    for (pass = 0; pass < 6; pass++) {
        ggScene *a = ggSceneCreate(NULL), *b = ggSceneCreate(NULL);
        ggMaterial m = ggMaterialDefault();
        ggMeshData d = oct_data();
        ggMeshOptions o;
        ggVec3 n[6];
        ggImage *ia, *ib;
        int i, ma, mb, smooth = pass & 1 || pass >= 4;
        double k = pass >= 4 ? -2 : 2;
        ggError e;
        for (i = 0; i < 6; i++) n[i] = (ggVec3){oct_v[i].x * k + 0.3, oct_v[i].y * k, oct_v[i].z * k};
        if (pass & 2 || pass == 5) m.kt = 0.9, m.ior = 1.5, m.kd = 0.1, m.ks = 0.1;
        ma = ggSceneAddMaterial(a, &m), mb = ggSceneAddMaterial(b, &m);
        ggMeshOptionsDefault(&o);
        o.material = ma;
        o.normals = smooth ? GG_NORMALS_AUTO : GG_NORMALS_FLAT;
        if (smooth) d.normals = n;
        assert_true(ggSceneAddMesh(a, &d, &o, &e) == 0);
        for (i = 0; i < 8; i++) {
            ggVec3 v[3], nn[3];
            int c;
            for (c = 0; c < 3; c++) {
                double l;
                v[c] = oct_v[oct_i[3 * i + c]];
                /* unit normals: what the mesh stores */
                nn[c] = n[oct_i[3 * i + c]];
                l = sqrt(nn[c].x * nn[c].x + nn[c].y * nn[c].y + nn[c].z * nn[c].z);
                nn[c].x /= l, nn[c].y /= l, nn[c].z /= l;
            }
            assert_true(ggSceneAddTriangle(b, mb, v, smooth ? nn : NULL) >= 0);
        }
        camera(a), camera(b);
        ia = render(a), ib = render(b);
        assert_true(same_image(ia, ib));
        same_hits(a, b);
        ggImageFree(ia), ggImageFree(ib);
        ggSceneFree(a), ggSceneFree(b);
    }
}

static void test_hit_names_triangle(void **state)
{
    ggScene *s = ggSceneCreate(NULL);
    ggMeshData d = oct_data();
    ggHit h;
    ggFaceInfo fi;
    ggMeshInfo mi;
    ggRay r = {{0.2, 0.2, 5}, {0, 0, -1}};
    ggError e;
    (void)state;
    assert_int_equal(ggSceneAddMesh(s, &d, NULL, &e), 0);
    assert_int_equal(ggScenePrepare(s, &e), GG_OK);
    assert_true(ggSceneIntersect(s, r, 0, INFINITY, &h));
    assert_int_equal(h.kind, GG_SHAPE_MESH);
    assert_int_equal(h.triangle, 0); /* (0, 2, 4) faces +x +y +z */
    assert_int_equal(ggSceneGetFaceInfo(s, h.object, h.triangle, &fi), GG_OK);
    assert_int_equal(fi.mesh, 0);
    assert_string_equal(fi.mesh_name, "oct");
    assert_int_equal(fi.face, 0);
    assert_int_equal(ggSceneGetMeshInfo(s, 0, &mi), GG_OK);
    assert_int_equal(mi.triangles, 8);
    assert_int_equal(mi.objects, 1);
    assert_false(mi.file_normals);
    r.o = (ggVec3){-0.2, -0.2, -5}, r.d = (ggVec3){0, 0, 1};
    assert_true(ggSceneIntersect(s, r, 0, INFINITY, &h));
    assert_int_equal(h.triangle, 6); /* (3, 1, 5) */
    assert_true(h.front);
    assert_int_equal(ggSceneGetFaceInfo(s, h.object, 8, &fi), GG_ERROR_INVALID);
    /* other kinds say -1 */
    ggSceneAddSphere(s, 0, (ggVec3){0, 0, 10}, 1);
    assert_int_equal(ggScenePrepare(s, &e), GG_OK);
    r.o = (ggVec3){0, 0, 20}, r.d = (ggVec3){0, 0, -1};
    assert_true(ggSceneIntersect(s, r, 0, INFINITY, &h));
    assert_int_equal(h.kind, GG_SHAPE_SPHERE);
    assert_int_equal(h.triangle, -1);
    ggSceneFree(s);
}

/* ggSceneObjectTriangle hands out every triangle of every part once, with
   the corners the renderer hits: a ray at each triangle's centroid hits
   that very triangle. */
static void test_object_triangles(void **state)
{
    ggScene *s = ggSceneCreate(NULL);
    ggMeshData d = oct_data();
    ggMaterial m = ggMaterialDefault();
    int mats[8], i, obj, seen[8] = {0};
    long k, t, total = 0;
    ggVec3 v[3];
    ggError e;
    (void)state;
    mats[0] = ggSceneAddMaterial(s, &m);
    m.color.g = 0.5;
    mats[1] = ggSceneAddMaterial(s, &m);
    for (i = 7; i >= 0; i--) mats[i] = mats[i % 3 == 1];
    d.materials = mats;
    ggSceneAddSphere(s, mats[0], (ggVec3){0, 0, 10}, 1);
    assert_int_equal(ggSceneAddMesh(s, &d, NULL, &e), 0);
    assert_int_equal(ggScenePrepare(s, &e), GG_OK);
    assert_int_equal(ggSceneObjectTriangleCount(s, 0), 0); /* the sphere */
    assert_int_equal(ggSceneObjectTriangle(s, 0, 0, v, &t), GG_ERROR_INVALID);
    for (obj = 1; obj < ggSceneObjectCount(s); obj++) {
        long n = ggSceneObjectTriangleCount(s, obj);
        assert_true(n > 0);
        total += n;
        assert_int_equal(ggSceneObjectTriangle(s, obj, n, v, &t), GG_ERROR_INVALID);
        assert_int_equal(ggSceneObjectTriangle(s, obj, -1, v, &t), GG_ERROR_INVALID);
        for (k = 0; k < n; k++) {
            ggVec3 c, nrm, a, b;
            ggHit h;
            ggRay r;
            assert_int_equal(ggSceneObjectTriangle(s, obj, k, v, &t), GG_OK);
            assert_true(t >= 0 && t < 8);
            seen[t]++;
            c = (ggVec3){(v[0].x + v[1].x + v[2].x) / 3, (v[0].y + v[1].y + v[2].y) / 3,
                         (v[0].z + v[1].z + v[2].z) / 3};
            a = (ggVec3){v[1].x - v[0].x, v[1].y - v[0].y, v[1].z - v[0].z};
            b = (ggVec3){v[2].x - v[0].x, v[2].y - v[0].y, v[2].z - v[0].z};
            nrm = (ggVec3){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
            r.o = (ggVec3){c.x + 3 * nrm.x, c.y + 3 * nrm.y, c.z + 3 * nrm.z};
            r.d = (ggVec3){-nrm.x, -nrm.y, -nrm.z};
            assert_true(ggSceneIntersect(s, r, 0, INFINITY, &h));
            assert_int_equal(h.object, obj);
            assert_int_equal(h.triangle, t);
        }
    }
    assert_int_equal(total, 8);
    for (i = 0; i < 8; i++) assert_int_equal(seen[i], 1);
    ggSceneFree(s);
}

/* One object per material, in order of first use; faces keep their
   material and their index through the regrouping. */
static void test_objects_by_material(void **state)
{
    ggScene *s = ggSceneCreate(NULL);
    ggMeshData d = oct_data();
    ggMaterial m = ggMaterialDefault();
    int mats[8], i, m0, m1;
    ggFaceInfo fi;
    ggError e;
    (void)state;
    m0 = ggSceneAddMaterial(s, &m);
    m.color.g = 0.5;
    m1 = ggSceneAddMaterial(s, &m);
    for (i = 0; i < 8; i++) mats[i] = i % 3 == 1 ? m1 : m0;
    d.materials = mats;
    assert_int_equal(ggSceneAddMesh(s, &d, NULL, &e), 0);
    assert_int_equal(ggSceneObjectCount(s), 2);
    assert_int_equal(ggSceneObjectKind(s, 0), GG_SHAPE_MESH);
    assert_int_equal(ggSceneObjectMaterial(s, 0), m0);
    assert_int_equal(ggSceneObjectMaterial(s, 1), m1);
    assert_int_equal(ggSceneObjectMesh(s, 1), 0);
    for (i = 0; i < 8; i++) {
        int obj = i < 5 ? 0 : 1; /* 5 triangles of m0 first, then 3 of m1 */
        assert_int_equal(ggSceneGetFaceInfo(s, obj, i, &fi), GG_OK);
        assert_int_equal(fi.material, mats[fi.face]);
    }
    /* the faces are a permutation */
    {
        int seen = 0;
        for (i = 0; i < 8; i++) {
            ggSceneGetFaceInfo(s, i < 5 ? 0 : 1, i, &fi);
            seen |= 1 << fi.face;
        }
        assert_int_equal(seen, 255);
    }
    ggSceneFree(s);
}

/* Computed normals: smooth within the crease angle, split beyond it. */
static void test_computed_normals(void **state)
{
    ggScene *s = ggSceneCreate(NULL);
    ggMeshData d = oct_data();
    ggMeshOptions o;
    ggMeshInfo mi;
    ggHit h;
    ggRay r = {{0.3, 0.3, 5}, {0, 0, -1}};
    ggError e;
    (void)state;
    /* normals of neighbouring faces differ by 70.5 degrees, of opposite ones
       at a vertex by 109.5: 120 smooths them all */
    ggMeshOptionsDefault(&o);
    o.crease_deg = 120;
    assert_int_equal(ggSceneAddMesh(s, &d, &o, &e), 0);
    ggSceneGetMeshInfo(s, 0, &mi);
    assert_int_equal(mi.vertices, 6);
    assert_int_equal(ggScenePrepare(s, &e), GG_OK);
    assert_true(ggSceneIntersect(s, r, 0, INFINITY, &h));
    /* the shading normal bends away from the face normal (1,1,1)/sqrt 3 */
    assert_true(fabs(h.ns.x - h.ng.x) > 1e-3);
    ggSceneFree(s);
    /* the default 60 degrees keeps every edge: each vertex splits into its
       4 faces, and the shading normal is the face's */
    s = ggSceneCreate(NULL);
    assert_int_equal(ggSceneAddMesh(s, &d, NULL, &e), 0);
    ggSceneGetMeshInfo(s, 0, &mi);
    assert_int_equal(mi.vertices, 24);
    assert_int_equal(ggScenePrepare(s, &e), GG_OK);
    assert_true(ggSceneIntersect(s, r, 0, INFINITY, &h));
    assert_close(h.ns.x, h.ng.x, 1e-12);
    assert_close(h.ns.z, h.ng.z, 1e-12);
    ggSceneFree(s);
}

/* Angle weighting: a vertex normal does not depend on how a flat side
   was cut into triangles. At the corner (0,0,0) of a unit cube the -z and
   -y sides are cut into 2 triangles and the -x side into 3 (all touching
   the corner, at 26.6, 18.4 and 45 degrees): everything smoothed (crease
   180), the normal is still (-1,-1,-1)/sqrt 3, which counting triangles
   would not give. */
static void test_angle_weights(void **state)
{
    static const ggVec3 v[] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0},   {0, 1, 0},
                               {0, 0, 1}, {0, 1, 1}, {0, 0.5, 1}, {1, 0, 1}};
    static const uint32_t idx[] = {0, 3, 2, 0, 2, 1,          /* -z */
                                   0, 4, 6, 0, 6, 5, 0, 5, 3, /* -x */
                                   0, 1, 7, 0, 7, 4};         /* -y */
    ggScene *s = ggSceneCreate(NULL);
    ggMeshData d;
    ggMeshOptions o;
    const gg_mesh *m;
    ggVec3 n;
    ggError e;
    (void)state;
    memset(&d, 0, sizeof d);
    d.positions = v, d.npositions = 8, d.indices = idx, d.ntriangles = 7;
    ggMeshOptionsDefault(&o);
    o.crease_deg = 180;
    assert_int_equal(ggSceneAddMesh(s, &d, &o, &e), 0);
    m = &s->meshes[0];
    assert_int_equal(m->nverts, 8);
    n = m->nrm[0];
    assert_close(n.x, -1 / sqrt(3), 1e-12);
    assert_close(n.y, -1 / sqrt(3), 1e-12);
    assert_close(n.z, -1 / sqrt(3), 1e-12);
    ggSceneFree(s);
}

/* Placement: translate, non-uniform scale (normals by the inverse
   transpose), and a mirror keeps the outside out. */
static void test_transform(void **state)
{
    int mirror;
    (void)state;
    for (mirror = 0; mirror < 2; mirror++) {
        ggScene *s = ggSceneCreate(NULL);
        ggMeshData d = oct_data();
        ggMeshOptions o;
        ggMeshInfo mi;
        ggHit h;
        ggRay r = {{0.1, 0.1, 10}, {0, 0, -1}};
        ggError e;
        ggMeshOptionsDefault(&o);
        o.normals = GG_NORMALS_FLAT;
        o.transform[0] = mirror ? -2 : 2, o.transform[10] = 3, o.transform[11] = 1;
        assert_int_equal(ggSceneAddMesh(s, &d, &o, &e), 0);
        ggSceneGetMeshInfo(s, 0, &mi);
        assert_true(mi.lo.x == -2 && mi.hi.x == 2 && mi.lo.z == -2 && mi.hi.z == 4);
        assert_int_equal(ggScenePrepare(s, &e), GG_OK);
        assert_true(ggSceneIntersect(s, r, 0, INFINITY, &h));
        assert_close(h.t, 10 - (3 * (1 - 0.05 - 0.1) + 1), 1e-9); /* z = 3 (1 - |x|/2 - |y|) + 1 */
        /* the top is hit from outside: front face, normal up */
        assert_true(h.front);
        assert_true(h.ng.z > 0);
        ggSceneFree(s);
    }
}

/* A mesh's shading normal at the point that (0.1, 0.2, 10) looks down on,
   the mesh placed by diag(sx, sy, sz) (GG_NORMALS_SMOOTH from the given
   normals, which the transform's inverse transpose carries). */
static int scaled_normal(double sx, double sy, double sz, ggVec3 *ns)
{
    ggScene *s = ggSceneCreate(NULL);
    ggMeshData d = oct_data();
    ggMeshOptions o;
    ggHit h;
    ggRay r = {{0.1 * sx, 0.2 * sy, 10 * sz}, {0, 0, -1}};
    ggError e;
    int rc;
    ggMeshOptionsDefault(&o);
    d.normals = oct_v;
    o.transform[0] = sx, o.transform[5] = sy, o.transform[10] = sz;
    rc = ggSceneAddMesh(s, &d, &o, &e);
    if (rc == 0) rc = ggScenePrepare(s, &e);
    if (rc == 0) rc = ggSceneIntersect(s, r, 0, INFINITY, &h) ? 0 : -1;
    if (rc == 0) *ns = h.ns;
    ggSceneFree(s);
    return rc;
}

/* Tiny and huge scales are not singular: where the determinant
   underflowed (a uniform scale below about 1e-108, or 2^-500 along y and
   2^-600 along z) a mesh was refused as "the transform is singular". A
   scale by a power of two gives the same normals bit for bit from 2^-270 up to GG_COORD_MAX, x,
   y and z scaled 1, 2 and 4 times; any other scale within a few ulp, also 2^-300 and 2^-330, where
   the faces were refused as having no area until their edges' cross product, not its square (which
   underflowed from 2^-268), was held to be nonzero. Beyond that the faces are what is refused. */
static void test_transform_scales(void **state)
{
    static const double any[] = {0x1p-330, 0x1p-300, 1e-80, 1e-78, 1e-40,
                                 3e-7,     0.3,      7.5,   1e30,  1e63};
    ggVec3 ref, n;
    int k;
    (void)state;
    assert_int_equal(scaled_normal(1, 2, 4, &ref), 0);
    for (k = -270; k <= 210; k++) {
        double sc = ldexp(1, k);
        assert_int_equal(scaled_normal(sc, 2 * sc, 4 * sc, &n), 0);
        assert_true(n.x == ref.x && n.y == ref.y && n.z == ref.z);
    }
    for (k = 0; k < (int)(sizeof any / sizeof *any); k++) {
        double sc = any[k];
        assert_int_equal(scaled_normal(sc, 2 * sc, 4 * sc, &n), 0);
        assert_close(n.x, ref.x, 1e-15);
        assert_close(n.y, ref.y, 1e-15);
        assert_close(n.z, ref.z, 1e-15);
    }
    {
        ggScene *s = ggSceneCreate(NULL);
        ggMeshData d = oct_data();
        ggMeshOptions o;
        ggError e;
        /* squashed to 2^-500 along y and 2^-600 along z: the determinant is
           2^-1100, the faces' cross products 2^-500 */
        ggMeshOptionsDefault(&o);
        o.transform[5] = 0x1p-500, o.transform[10] = 0x1p-600;
        assert_int_equal(ggSceneAddMesh(s, &d, &o, &e), 0);
        ggMeshOptionsDefault(&o);
        o.transform[0] = o.transform[5] = o.transform[10] = 1e-170; /* cross products 0 */
        assert_int_equal(ggSceneAddMesh(s, &d, &o, &e), -GG_ERROR_INVALID);
        assert_string_equal(e.message, "oct: no face has an area");
        ggSceneFree(s);
    }
}

/* Every failure leaves the scene exactly as it was. */
static void test_failures(void **state)
{
    ggScene *s = ggSceneCreate(NULL);
    ggMeshData d = oct_data();
    ggMeshOptions o;
    uint32_t bad[24];
    ggVec3 nanv[6];
    int mats[8] = {0, 0, 0, 0, 0, 0, 0, 5};
    ggError e;
    (void)state;
    memcpy(bad, oct_i, sizeof bad);
    bad[7] = 6;
    d.indices = bad;
    assert_int_equal(ggSceneAddMesh(s, &d, NULL, &e), -GG_ERROR_INVALID);
    assert_string_equal(e.message, "oct: an index is out of range");
    d = oct_data();
    memcpy(nanv, oct_v, sizeof nanv);
    nanv[3].y = NAN;
    d.positions = nanv;
    assert_int_equal(ggSceneAddMesh(s, &d, NULL, &e), -GG_ERROR_INVALID);
    d = oct_data();
    ggMeshOptionsDefault(&o);
    o.transform[5] = 0;
    assert_int_equal(ggSceneAddMesh(s, &d, &o, &e), -GG_ERROR_INVALID);
    assert_string_equal(e.message, "oct: the transform is singular");
    d.materials = mats;
    assert_int_equal(ggSceneAddMesh(s, &d, NULL, &e), -GG_ERROR_INVALID);
    d = oct_data();
    d.ntriangles = 0;
    assert_true(ggSceneAddMesh(s, &d, NULL, &e) < 0);
    assert_int_equal(ggSceneObjectCount(s), 0);
    assert_int_equal(ggSceneMaterialCount(s), 0);
    assert_int_equal(ggSceneMeshCount(s), 0);
    /* all faces of zero area */
    {
        static const ggVec3 line[3] = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
        static const uint32_t t[3] = {0, 1, 2};
        d.positions = line, d.npositions = 3, d.indices = t, d.ntriangles = 1;
        /* a bad argument, as scene.h lists it (PARSE is for files) */
        d.name = "line";
        assert_int_equal(ggSceneAddMesh(s, &d, NULL, &e), -GG_ERROR_INVALID);
        assert_int_equal(e.code, GG_ERROR_INVALID);
        assert_string_equal(e.message, "line: no face has an area");
        assert_int_equal(ggSceneAddMesh(s, &d, NULL, NULL), -GG_ERROR_INVALID);
    }
    assert_int_equal(ggSceneMaterialCount(s), 0);
    ggSceneFree(s);
}

/* Bounds too large to frame: GG_ERROR_INVALID saying so, and the camera
   and lights as they were (not GG_OK with the camera unchanged, nor an
   "out of memory" for the lights). */
static void test_frame_too_large(void **state)
{
    ggScene *s = ggSceneCreate(NULL);
    ggMaterial m = ggMaterialDefault();
    ggCamera c0, c1;
    ggError e;
    int mi = ggSceneAddMaterial(s, &m);
    (void)state;
    /* objects past GG_COORD_MAX are refused before framing sees them */
    assert_int_equal(ggSceneAddSphere(s, mi, (ggVec3){1e200, 0, 0}, 1), -GG_ERROR_INVALID);
    /* bounds at the limit: the camera is placed, the lights (about six
       radii out) would be beyond it, and nothing changes */
    assert_int_equal(ggSceneAddSphere(s, mi, (ggVec3){0, 0, 0}, GG_COORD_MAX), 0);
    c0 = ggSceneCamera(s);
    assert_int_equal(ggSceneFrame(s, GG_FRAME_CAMERA | GG_FRAME_LIGHTS, &e), GG_ERROR_INVALID);
    assert_string_equal(e.message, "framing: the scene's bounds (-1e+64 -1e+64 -1e+64 to 1e+64 "
                                   "1e+64 1e+64) are too large to frame: a light would be over "
                                   "1e64 in magnitude (GG_COORD_MAX)");
    c1 = ggSceneCamera(s);
    assert_memory_equal(&c0, &c1, sizeof c0);
    assert_int_equal(ggSceneLightCount(s), 0);
    assert_int_equal(ggSceneFrame(s, GG_FRAME_CAMERA, &e), GG_OK);
    ggSceneFree(s);
}

/* Framing: the camera looks at the bounds' centre and every box corner
   is in view; two lights are added. */
static void test_frame(void **state)
{
    ggScene *s = ggSceneCreate(NULL);
    ggMeshData d = oct_data();
    ggMeshOptions o;
    ggCamera c;
    ggImage *img;
    ggError e;
    int x, y, lit = 0;
    (void)state;
    ggMeshOptionsDefault(&o);
    o.transform[3] = 10, o.transform[7] = -3;
    assert_int_equal(ggSceneFrame(s, GG_FRAME_CAMERA, &e), GG_ERROR_INVALID);
    assert_int_equal(ggSceneAddMesh(s, &d, &o, &e), 0);
    assert_int_equal(ggSceneFrame(s, GG_FRAME_CAMERA | GG_FRAME_LIGHTS, &e), GG_OK);
    c = ggSceneCamera(s);
    assert_true(c.at.x == 10 && c.at.y == -3 && c.at.z == 0);
    assert_int_equal(ggSceneLightCount(s), 2);
    c.width = 40, c.height = 30;
    ggSceneSetCamera(s, &c);
    img = render(s);
    /* lit pixels, and none on the border: the model is inside the view */
    for (y = 0; y < 30; y++)
        for (x = 0; x < 40; x++) {
            ggColor p = ggImageGet(img, x, y);
            if (p.r > 0) {
                lit++;
                assert_true(x > 0 && y > 0 && x < 39 && y < 29);
            }
        }
    assert_true(lit > 100);
    ggImageFree(img);
    ggSceneFree(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mesh_equals_triangles),
        cmocka_unit_test(test_hit_names_triangle),
        cmocka_unit_test(test_objects_by_material),
        cmocka_unit_test(test_computed_normals),
        cmocka_unit_test(test_angle_weights),
        cmocka_unit_test(test_transform),
        cmocka_unit_test(test_transform_scales),
        cmocka_unit_test(test_failures),
        cmocka_unit_test(test_frame),
        cmocka_unit_test(test_frame_too_large),
        cmocka_unit_test(test_object_triangles),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
