/* SPDX-License-Identifier: MIT */
/*
** test_uv.c -- textures and texture coordinates as a client sees them
** (scene.h, "textures and texture coordinates"): ggSceneObjectUV gives
** every kind of shape the (u, v) that ggSceneIntersect's hits carry, and
** the one its contract states, at 200 random points of each, and at
** every scale from 2^-1074 to 2^1023; its failures write nothing; ggSceneObjectShape's sphere and
*cone frames
** are the ones u is measured in; and ggSceneGetTexture describes each
** texture so that sampling it as it says gives the ray tree's surface
** colour bit for bit, for every filter and wrap mode and the checker.
*/
#include "testutil.h"
#include "vec.h"

#include <math.h>
#include <string.h>

#define PI 3.14159265358979323846

/* p = v0 + b1 (v1 - v0) + b2 (v2 - v0) */
static ggVec3 bary(const ggVec3 *v0, const ggVec3 *v1, const ggVec3 *v2, double b1, double b2)
{
    return v3add(*v0, v3add(v3scale(v3sub(*v1, *v0), b1), v3scale(v3sub(*v2, *v0), b2)));
}

/* One object of each kind, 10 apart along x, all with a checker. */
static const char scene_text[] =
    "v from 35 -40 0 at 35 0 0 up 0 0 1 angle 90 resolution 32 24\n"
    "l 35 -30 30\n"
    "f 1 1 1 1 0 100000 0 0\n"
    "checker 7 1 1 1 0.1 0.2 0.3\n"
    "s 0 0 0 1\n"
    "c 10 0 -1 1  11 0.5 1 0.4\n"
    "rect 20 0 -1  1.5 0.2 0  0.3 0.1 2\n"
    "p 3  30 0 -1  32 0.5 -1  30.5 0.2 1\n"
    "pp 5  40 0 -1 0 -1 0  41 0 -0.5 0 -1 0  41 0 0.5 0 -1 0  40 0 1 0 -1 0  39 0 0 0 -1 0\n"
    "p 6  50 0 -1  52 0 -1  52 0 0  51 0 0  51 0 1  50 0 1\n"
    "implicit \"(x-70)^2+y^2+z^2-1\" 68.5 -1.5 -1.5 71.5 1.5 1.5\n";
enum { SPHERE, CONE, RECT, TRI, FAN, POLY, IMPLICIT, MESH, NOBJ };

static const ggVec3 mesh_v[4] = {{60, 0, -1}, {62, 0.3, -1}, {61.5, 0, 1}, {60, 0.2, 1}};
static const double mesh_uv[8] = {0.1, 0.2, 0.9, 0.3, 0.5, 1.2, -0.3, 0.8};
static const uint32_t mesh_i[6] = {0, 1, 2, 0, 2, 3};

static ggScene *uv_scene(void)
{
    ggScene *s = ggSceneCreate(NULL);
    ggMeshData d;
    ggMeshOptions o;
    ggError e;
    assert_int_equal(ggSceneLoadString(s, scene_text, sizeof scene_text - 1, "uv.nff", &e), GG_OK);
    memset(&d, 0, sizeof d);
    d.positions = mesh_v, d.npositions = 4, d.uv = mesh_uv, d.indices = mesh_i, d.ntriangles = 2;
    ggMeshOptionsDefault(&o);
    o.material = ggSceneObjectMaterial(s, 0);
    assert_int_equal(ggSceneAddMesh(s, &d, &o, &e), 0);
    assert_int_equal(ggSceneObjectCount(s), NOBJ);
    assert_int_equal(ggSceneObjectKind(s, FAN), GG_SHAPE_TRIANGLE);
    assert_int_equal(ggSceneObjectKind(s, POLY), GG_SHAPE_POLYGON);
    assert_int_equal(ggScenePrepare(s, &e), GG_OK);
    return s;
}

/* |a - b|, for u on a sphere or cone around the turn (0 and 1 meet). */
static double du(double a, double b, int circular)
{
    double d = fabs(a - b);
    return circular && d > 0.5 ? 1 - d : d;
}

/* A point of object k, its documented (u, v), the mesh triangle or fan
   triangle it lies in, and a ray that hits it there from outside. */
typedef struct sample {
    ggVec3 p;
    double u, v;
    long part;
    ggRay ray;
} sample;

/* The polygon's (u, v) as its contract states them, worked out here. */
static void poly_uv(const ggShapeDesc *d, ggVec3 p, double *u, double *v)
{
    ggVec3 n = v3(0, 0, 0), eu, ev;
    double u0 = INFINITY, u1 = -INFINITY, v0 = INFINITY, v1 = -INFINITY;
    int i;
    for (i = 0; i < d->nverts; i++)
        n = v3add(n, v3cross(d->verts[i], d->verts[(i + 1) % d->nverts]));
    n = v3norm(n);
    eu = v3sub(d->verts[1], d->verts[0]);
    eu = v3norm(v3sub(eu, v3scale(n, v3dot(eu, n))));
    ev = v3cross(n, eu);
    for (i = 0; i < d->nverts; i++) {
        ggVec3 q = v3sub(d->verts[i], d->verts[0]);
        u0 = fmin(u0, v3dot(q, eu)), u1 = fmax(u1, v3dot(q, eu));
        v0 = fmin(v0, v3dot(q, ev)), v1 = fmax(v1, v3dot(q, ev));
    }
    *u = (v3dot(v3sub(p, d->verts[0]), eu) - u0) / (u1 - u0);
    *v = (v3dot(v3sub(p, d->verts[0]), ev) - v0) / (v1 - v0);
}

static void make_sample(const ggScene *s, int k, tu_rng *r, sample *o)
{
    ggShapeDesc d;
    ggVec3 out; /* the side the ray comes from */
    double b1, b2;
    assert_int_equal(ggSceneObjectShape(s, k, &d), GG_OK);
    o->part = 0;
    switch (k) {
    case SPHERE: {
        ggVec3 n = tu_unit(r);
        o->p = v3add(d.base, v3scale(n, d.radius));
        o->u = atan2(n.y, n.x) / (2 * PI);
        if (o->u < 0) o->u += 1;
        o->v = acos(n.z) / PI;
        out = n;
        break;
    }
    case CONE: {
        ggVec3 ax = v3sub(d.apex, d.base), ez = v3norm(ax), rad;
        double h = sqrt(v3dot(ax, ax)), th = tu_range(r, 0, 2 * PI),
               z = tu_range(r, 0.02, 0.98) * h;
        double rho = d.radius + (d.radius2 - d.radius) * z / h;
        rad = v3add(v3scale(d.e1, cos(th)), v3scale(d.e2, sin(th)));
        o->p = v3add(d.base, v3add(v3scale(ez, z), v3scale(rad, rho)));
        o->u = th / (2 * PI), o->v = z / h;
        out = rad;
        break;
    }
    case RECT:
        o->u = tu_range(r, 0.01, 0.99), o->v = tu_range(r, 0.01, 0.99);
        o->p = v3add(d.base, v3add(v3scale(d.e1, o->u), v3scale(d.e2, o->v)));
        out = v3scale(v3norm(v3cross(d.e1, d.e2)), tu_uniform(r) < 0.5 ? 1 : -1);
        break;
    case TRI:
    case FAN:
    case MESH: {
        ggVec3 v[3];
        const double *t[3] = {NULL, NULL, NULL};
        do {
            b1 = tu_range(r, 0.01, 0.98), b2 = tu_range(r, 0.01, 0.98);
        } while (b1 + b2 > 0.98);
        if (k == MESH) {
            int c;
            o->part = (long)(tu_next(r) % 2);
            for (c = 0; c < 3; c++) {
                v[c] = mesh_v[mesh_i[3 * o->part + c]];
                t[c] = mesh_uv + 2 * mesh_i[3 * o->part + c];
            }
        } else {
            o->part = k == FAN ? (long)(tu_next(r) % (unsigned)(d.nverts - 2)) : 0;
            v[0] = d.verts[0], v[1] = d.verts[o->part + 1], v[2] = d.verts[o->part + 2];
        }
        o->p = bary(&v[0], &v[1], &v[2], b1, b2);
        if (k == MESH) {
            double b0 = 1 - b1 - b2;
            o->u = b0 * t[0][0] + b1 * t[1][0] + b2 * t[2][0];
            o->v = b0 * t[0][1] + b1 * t[1][1] + b2 * t[2][1];
        } else {
            o->u = b1, o->v = b2;
        }
        out = v3scale(v3norm(v3cross(v3sub(v[1], v[0]), v3sub(v[2], v[0]))),
                      tu_uniform(r) < 0.5 ? 1 : -1);
        break;
    }
    case POLY: { /* an L: the square [51, 52] x [0, 1] is cut out */
        double x, z;
        do {
            x = tu_range(r, 50.01, 51.99), z = tu_range(r, -0.99, 0.99);
        } while (x > 50.99 && z > -0.01);
        o->p = v3(x, 0, z);
        poly_uv(&d, o->p, &o->u, &o->v);
        out = v3(0, tu_uniform(r) < 0.5 ? 1 : -1, 0);
        break;
    }
    default: { /* the implicit sphere of radius 1 about (70, 0, 0) */
        ggVec3 n = tu_unit(r);
        o->p = v3add(v3(70, 0, 0), n);
        o->u = o->v = 0;
        out = n;
    }
    }
    /* From 3 units out, a little askew, aimed at p. */
    out = v3norm(v3add(out, v3scale(tu_unit(r), 0.2)));
    o->ray.o = v3add(o->p, v3scale(out, 3));
    o->ray.d = v3scale(out, -1);
}

/* Every kind, 200 points each: the documented (u, v) at the point, and
   the hit's at the point ggSceneIntersect finds, both from
   ggSceneObjectUV (the first a batch of all 200 at once). */
static void test_uv_agrees_with_hits(void **state)
{
    ggScene *s = uv_scene();
    tu_rng r = {0x7e57u};
    enum { N = 200 };
    int k, i;
    (void)state;
    for (k = 0; k < NOBJ; k++) {
        static sample sm[N];
        static ggVec3 pts[N];
        static double uv[2 * N];
        const int circ = k == SPHERE || k == CONE;
        double worst_doc = 0, worst_hit = 0;
        int hits = 0;
        for (i = 0; i < N; i++) {
            make_sample(s, k, &r, &sm[i]);
            pts[i] = sm[i].p;
        }
        if (k == TRI || k == POLY || k == SPHERE || k == CONE || k == RECT || k == IMPLICIT) {
            /* one call for every point (part does not matter here) */
            assert_int_equal(ggSceneObjectUV(s, k, 0, pts, N, uv), GG_OK);
        } else {
            for (i = 0; i < N; i++)
                assert_int_equal(ggSceneObjectUV(s, k, sm[i].part, &pts[i], 1, uv + 2 * i), GG_OK);
        }
        for (i = 0; i < N; i++) {
            ggHit h;
            double hu[2];
            worst_doc =
                fmax(worst_doc, fmax(du(uv[2 * i], sm[i].u, circ), fabs(uv[2 * i + 1] - sm[i].v)));
            assert_true(ggSceneIntersect(s, sm[i].ray, 0, INFINITY, &h));
            assert_int_equal(h.object, k);
            if (k == MESH) assert_int_equal(h.triangle, sm[i].part);
            assert_int_equal(
                ggSceneObjectUV(s, k, k == MESH || k == FAN ? sm[i].part : 0, &h.p, 1, hu), GG_OK);
            worst_hit = fmax(worst_hit, fmax(du(hu[0], h.u, circ), fabs(hu[1] - h.v)));
            hits++;
        }
        if (worst_doc > 1e-9 || worst_hit > 1e-9)
            fail_msg("object %d: (u, v) off by %g from the contract, %g from the hits", k,
                     worst_doc, worst_hit);
        assert_int_equal(hits, N);
    }
    ggSceneFree(s);
}

/* The frames of ggSceneObjectShape: a sphere's are +x and +y; a cone's
   are unit, perpendicular to its axis and each other, and u = 0 along e1,
   1/4 along e2, v = 1 at the apex. */
static void test_frames(void **state)
{
    ggScene *s = uv_scene();
    ggShapeDesc d;
    ggVec3 ax, p[3];
    double uv[6];
    (void)state;
    assert_int_equal(ggSceneObjectShape(s, SPHERE, &d), GG_OK);
    assert_true(d.e1.x == 1 && d.e1.y == 0 && d.e1.z == 0);
    assert_true(d.e2.x == 0 && d.e2.y == 1 && d.e2.z == 0);
    assert_int_equal(ggSceneObjectShape(s, CONE, &d), GG_OK);
    ax = v3norm(v3sub(d.apex, d.base));
    assert_close(v3dot(d.e1, d.e1), 1, 1e-15);
    assert_close(v3dot(d.e2, d.e2), 1, 1e-15);
    assert_true(fabs(v3dot(d.e1, d.e2)) < 1e-15 && fabs(v3dot(d.e1, ax)) < 1e-15 &&
                fabs(v3dot(d.e2, ax)) < 1e-15);
    p[0] = v3add(d.base, d.e1), p[1] = v3add(d.base, d.e2),
    p[2] = v3add(d.apex, v3scale(d.e1, 0.4));
    assert_int_equal(ggSceneObjectUV(s, CONE, 0, p, 3, uv), GG_OK);
    assert_true(du(uv[0], 0, 1) < 1e-15 && uv[1] < 1e-15);
    assert_close(uv[2], 0.25, 1e-15);
    assert_close(uv[5], 1, 1e-15);
    /* other kinds keep their e1, e2 (a rect's edges) or zeros */
    assert_int_equal(ggSceneObjectShape(s, TRI, &d), GG_OK);
    assert_true(d.e1.x == 0 && d.e2.x == 0);
    ggSceneFree(s);
}

/* Refusals: nothing written, every reason. */
static void test_refusals(void **state)
{
    ggScene *s = uv_scene(), *bad = ggSceneCreate(NULL);
    ggVec3 p = {0, 0, 1}, nan3 = {NAN, 0, 0};
    double uv[2] = {7, 7};
    static const char flat[] = "p 4 0 0 0  1 0 0  2 0 0  3 0 0\n"; /* no area */
    (void)state;
    assert_int_equal(ggSceneObjectUV(NULL, 0, 0, &p, 1, uv), GG_ERROR_INVALID);
    assert_int_equal(ggSceneObjectUV(s, -1, 0, &p, 1, uv), GG_ERROR_INVALID);
    assert_int_equal(ggSceneObjectUV(s, NOBJ, 0, &p, 1, uv), GG_ERROR_INVALID);
    assert_int_equal(ggSceneObjectUV(s, 0, 0, NULL, 1, uv), GG_ERROR_INVALID);
    assert_int_equal(ggSceneObjectUV(s, 0, 0, &p, 1, NULL), GG_ERROR_INVALID);
    assert_int_equal(ggSceneObjectUV(s, 0, 0, &nan3, 1, uv), GG_ERROR_INVALID);
    assert_int_equal(ggSceneObjectUV(s, MESH, 2, &p, 1, uv), GG_ERROR_INVALID); /* 2 triangles */
    assert_int_equal(ggSceneObjectUV(s, MESH, -1, &p, 1, uv), GG_ERROR_INVALID);
    assert_int_equal(ggSceneObjectUV(s, FAN, 3, &p, 1, uv), GG_ERROR_INVALID); /* 3 in the fan */
    assert_int_equal(ggSceneObjectUV(s, TRI, 1, &p, 1, uv), GG_ERROR_INVALID);
    assert_true(uv[0] == 7 && uv[1] == 7);
    /* n = 0 asks for nothing; part is ignored where it has no meaning */
    assert_int_equal(ggSceneObjectUV(s, 0, 0, NULL, 0, NULL), GG_OK);
    assert_int_equal(ggSceneObjectUV(s, SPHERE, 99, &p, 1, uv), GG_OK);
    assert_true(uv[0] == 0 && uv[1] == 0); /* the pole */
    assert_int_equal(ggSceneObjectUV(s, IMPLICIT, -5, &p, 1, uv), GG_OK);
    assert_true(uv[0] == 0 && uv[1] == 0);
    /* a shape the renderer never hits has no (u, v); an unprepared scene works */
    assert_int_equal(ggSceneLoadString(bad, flat, sizeof flat - 1, "flat.nff", NULL), GG_OK);
    uv[0] = uv[1] = 7;
    assert_int_equal(ggSceneObjectUV(bad, 0, 0, &p, 1, uv), GG_ERROR_INVALID);
    assert_true(uv[0] == 7 && uv[1] == 7);
    ggSceneFree(bad);
    ggSceneFree(s);
}

/* Points at every scale a double has: u and v of spheres and cones
   depend only on p's direction from the centre or axis, so the same
   direction at 2^k, k from -1074 to 1023, gives the same (u, v) (within
   1e-12 where the offset keeps its bits; in range everywhere), and a
   point whose offset overflows still has one. Before,
   |d| overflowed and underflowed: (1e308, 1e308, 1e308) left uv unwritten
   with GG_OK, (4.9e-324, 0, 0) was the pole, and a cone's u was 0 within
   1e-154 of its axis. */
static void test_every_scale(void **state)
{
    ggScene *s = uv_scene();
    ggShapeDesc cone;
    tu_rng r = {42};
    int k, i, kind;
    (void)state;
    assert_int_equal(ggSceneObjectShape(s, CONE, &cone), GG_OK);
    for (i = 0; i < 20; i++) {
        ggVec3 dir = tu_unit(&r);
        double ref[2][2];
        for (kind = 0; kind < 2; kind++) {
            /* the sphere at the origin; the cone: a direction across its axis */
            ggVec3 q =
                kind ? v3add(cone.base, v3add(v3scale(cone.e1, dir.x), v3scale(cone.e2, dir.y)))
                     : dir;
            assert_int_equal(ggSceneObjectUV(s, kind ? CONE : SPHERE, 0, &q, 1, ref[kind]), GG_OK);
        }
        for (k = -1074; k <= 1023; k++) {
            double sc = ldexp(1.0, k), uv[2] = {7, 7};
            for (kind = 0; kind < 2; kind++) {
                ggVec3 q = kind ? v3add(cone.base, v3add(v3scale(cone.e1, dir.x * sc),
                                                         v3scale(cone.e2, dir.y * sc)))
                                : v3scale(dir, sc);
                /* the cone's base (about 10) rounds q by 1e-15: u within 1e-12 from 2^-8 */
                int exact = k >= -1000 && (kind == 0 || k >= -8);
                assert_int_equal(ggSceneObjectUV(s, kind ? CONE : SPHERE, 0, &q, 1, uv), GG_OK);
                assert_true(uv[0] >= 0 && uv[0] < 1 && uv[1] >= 0 && uv[1] <= 1);
                if (exact && kind == 0 &&
                    (fabs(uv[0] - ref[0][0]) > 1e-12 || fabs(uv[1] - ref[0][1]) > 1e-12))
                    print_error("sphere, scale 2^%d: (%.17g, %.17g), at 1 (%.17g, %.17g)\n", k,
                                uv[0], uv[1], ref[0][0], ref[0][1]);
                if (exact) assert_true(fabs(uv[0] - ref[kind][0]) <= 1e-12);
                if (exact && kind == 0) assert_true(fabs(uv[1] - ref[0][1]) <= 1e-12);
            }
        }
    }
    {
        /* p - c overflows: (1e308, ...) against the sphere at the origin,
           and (-1e308, 1e308, -1e308) */
        ggVec3 far[2] = {{1e308, 1e308, 1e308}, {-1e308, 1e308, -1e308}};
        double uv[4] = {7, 7, 7, 7}, v0 = acos(1 / sqrt(3.0)) / PI;
        assert_int_equal(ggSceneObjectUV(s, SPHERE, 0, far, 2, uv), GG_OK);
        assert_true(fabs(uv[0] - 0.125) < 1e-15 && fabs(uv[1] - v0) < 1e-15);
        assert_true(fabs(uv[2] - 0.375) < 1e-15 && fabs(uv[3] - (1 - v0)) < 1e-12);
    }
    ggSceneFree(s);
}

/* Sample texture t as ggSceneGetTexture says it is sampled (filter: the
   render's texture knob, 0 for the texture's own). */
static ggColor sample_tex(const ggTextureInfo *t, double u, double v, int filter)
{
    if (!t->image) return ggTextureChecker(u, v, t->checker_n, t->checker_a, t->checker_b);
    if (filter == GG_ACC_TEXTURE_NEAREST || (filter == 0 && t->nearest))
        return ggTextureNearest(t->image, u, v, t->wrap);
    return ggTextureBilinear(t->image, u, v, t->wrap);
}

/* The ray tree's surface colour at every textured hit of every 3rd pixel
   equals the material colour times the texture sampled as
   ggSceneGetTexture describes it, and ggSceneObjectUV gives its (u, v):
   texture.nff (bilinear and nearest, clamped), knot.nff (repeat, a mesh
   in front), glass.nff (a checker), under each texture knob. */
static void test_surface_colours(void **state)
{
    static const char *const scenes[] = {"examples/scenes/texture.nff", "examples/scenes/knot.nff",
                                         "examples/scenes/glass.nff"};
    static const int knobs[] = {0, GG_ACC_TEXTURE_BILINEAR, GG_ACC_TEXTURE_NEAREST};
    size_t f, kn;
    (void)state;
    for (f = 0; f < sizeof scenes / sizeof *scenes; f++) {
        ggScene *s = tu_load(scenes[f]);
        ggCamera cam = ggSceneCamera(s);
        ggTrace *tr = ggTraceCreate(NULL);
        int i, x, y;
        long checked = 0;
        assert_true(ggSceneTextureCount(s) > 0);
        for (i = 0; i < ggSceneTextureCount(s); i++) {
            ggTextureInfo t;
            assert_int_equal(ggSceneGetTexture(s, i, &t), GG_OK);
            assert_true(t.image ? t.checker_n == 0 : t.checker_n > 0);
            assert_true(t.wrap == GG_WRAP_REPEAT || t.wrap == GG_WRAP_CLAMP);
        }
        for (kn = 0; kn < 3; kn++) {
            ggRenderOptions o;
            ggRenderOptionsDefault(&o);
            o.max_depth = 2;
            o.accuracy.texture = knobs[kn];
            for (y = 1; y < cam.height; y += 3)
                for (x = 1; x < cam.width; x += 3) {
                    ggColor px;
                    size_t n;
                    assert_int_equal(ggTracePixel(s, &o, x, y, 0, tr, &px, NULL, NULL), GG_OK);
                    for (n = 0; n < ggTraceNodeCount(tr); n++) {
                        const ggTraceNode *nd = ggTraceGetNode(tr, n);
                        ggMaterial m;
                        ggTextureInfo t;
                        ggColor c;
                        double uv[2];
                        if (!nd->hit) continue;
                        m = ggSceneMaterial(s, nd->material);
                        if (m.texture < 0) continue;
                        assert_int_equal(ggSceneGetTexture(s, m.texture, &t), GG_OK);
                        c = sample_tex(&t, nd->u, nd->v, o.accuracy.texture);
                        assert_true(nd->surface.r == c.r * m.color.r &&
                                    nd->surface.g == c.g * m.color.g &&
                                    nd->surface.b == c.b * m.color.b);
                        assert_int_equal(
                            ggSceneObjectUV(s, nd->object, nd->triangle, &nd->p, 1, uv), GG_OK);
                        assert_true(fabs(uv[0] - nd->u) < 1e-9 && fabs(uv[1] - nd->v) < 1e-9);
                        checked++;
                    }
                }
        }
        if (checked < 1000) fail_msg("%s: only %ld textured hits", scenes[f], checked);
        ggTraceFree(tr);
        ggSceneFree(s);
    }
}

/* The count and the fields: texture.nff's two textures share one image
   (clamp, bilinear then nearest); a checker's numbers; code textures
   repeat and are bilinear; out of range is refused. */
static void test_texture_info(void **state)
{
    ggScene *s = tu_load("examples/scenes/texture.nff"), *g = tu_load("examples/scenes/glass.nff");
    ggTextureInfo a, b;
    ggImage *img = ggImageCreate(3, 2, NULL);
    (void)state;
    assert_int_equal(ggSceneTextureCount(s), 2);
    assert_int_equal(ggSceneGetTexture(s, 0, &a), GG_OK);
    assert_int_equal(ggSceneGetTexture(s, 1, &b), GG_OK);
    assert_non_null(a.image);
    assert_ptr_equal(a.image, b.image);
    assert_int_equal(ggImageWidth(a.image), 128);
    assert_true(a.wrap == GG_WRAP_CLAMP && b.wrap == GG_WRAP_CLAMP && !a.nearest && b.nearest);
    assert_int_equal(ggSceneGetTexture(s, 2, &a), GG_ERROR_INVALID);
    assert_int_equal(ggSceneGetTexture(s, -1, &a), GG_ERROR_INVALID);
    assert_int_equal(ggSceneGetTexture(s, 0, NULL), GG_ERROR_INVALID);
    assert_int_equal(ggSceneTextureCount(g), 1); /* checker 12 1 1 1 0.1 0.3 0.1 */
    assert_int_equal(ggSceneGetTexture(g, 0, &a), GG_OK);
    assert_null(a.image);
    assert_true(a.checker_n == 12 && a.checker_a.r == 1 && a.checker_b.g == 0.3);
    assert_int_equal(ggSceneAddTexture(g, img), 1);
    assert_int_equal(ggSceneGetTexture(g, 1, &a), GG_OK);
    assert_ptr_equal(a.image, img);
    assert_true(a.wrap == GG_WRAP_REPEAT && !a.nearest && a.checker_n == 0);
    ggSceneFree(s);
    ggSceneFree(g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_uv_agrees_with_hits),
        cmocka_unit_test(test_frames),
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_every_scale),
        cmocka_unit_test(test_surface_colours),
        cmocka_unit_test(test_texture_info),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
