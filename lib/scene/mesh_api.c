/* SPDX-License-Identifier: MIT */
/*
** mesh_api.c -- the public side of meshes: building one in code, what a
** mesh and a hit triangle are in the file's terms, and framing a scene
** (a camera and lights for a model loaded on its own).
*/
#include "scene.h"

#include "implicit.h"
#include "vec.h"

#include <math.h>
#include <string.h>

/* Copy n elements of size sz (NULL stays NULL); 0 when out of memory. */
static int dup(const ggAllocator *a, const void *src, size_t n, size_t sz, void **out)
{
    *out = NULL;
    if (!src) return 1;
    if (!(*out = gg_mem_calloc(a, n ? n : 1, sz))) return 0;
    memcpy(*out, src, n * sz);
    return 1;
}

GG_API int ggSceneAddMesh(ggScene *s, const ggMeshData *d, const ggMeshOptions *o, ggError *err)
{
    gg_mesh_build b;
    gg_mesh *m = &b.m;
    size_t i;
    int rc;
    if (!s || !d || !d->positions || !d->indices || !d->ntriangles)
        return -gg_error_set(err, GG_ERROR_INVALID,
                             "ggSceneAddMesh: NULL argument or no triangles");
    if (d->ntriangles >= GG_MESH_MAX || d->npositions >= GG_MESH_MAX)
        return -gg_error_set(err, GG_ERROR_LIMIT, "%s: more than 2^28 triangles or vertices",
                             d->name ? d->name : "mesh");
    memset(&b, 0, sizeof b);
    m->name = gg_mem_strdup(s->alloc, d->name ? d->name : "");
    m->nverts = m->file_vertices = d->npositions;
    m->ntri = m->nfaces = d->ntriangles;
    if (!m->name || !dup(s->alloc, d->positions, d->npositions, sizeof(ggVec3), (void **)&m->pos) ||
        !dup(s->alloc, d->normals, d->npositions, sizeof(ggVec3), (void **)&m->nrm) ||
        !dup(s->alloc, d->uv, 2 * d->npositions, sizeof(double), (void **)&m->uv) ||
        !dup(s->alloc, d->indices, 3 * d->ntriangles, sizeof(uint32_t), (void **)&m->idx) ||
        !dup(s->alloc, d->materials, d->ntriangles, sizeof(int), (void **)&b.tmat)) {
        gg_mesh_build_free(s->alloc, &b);
        return -gg_error_set(err, GG_ERROR_NOMEM, "%s: out of memory", d->name ? d->name : "mesh");
    }
    for (i = 0; b.tmat && i < m->ntri; i++)
        if (b.tmat[i] < -1) b.tmat[i] = (int)s->nmaterials; /* reported as unknown */
    rc = gg_scene_add_mesh_build(s, &b, o, 0, err);
    /* No triangle with an area: in a file a parse error, from code a bad
       argument, as scene.h lists it. */
    if (rc == -GG_ERROR_PARSE) {
        if (err) err->code = GG_ERROR_INVALID;
        rc = -GG_ERROR_INVALID;
    }
    return rc;
}

GG_API int ggSceneMeshCount(const ggScene *s)
{
    return s ? (int)s->nmeshes : 0;
}

GG_API int ggSceneObjectMesh(const ggScene *s, int i)
{
    if (!s || i < 0 || (size_t)i >= s->nobjects || s->objects[i].kind != GG_SHAPE_MESH) return -1;
    return s->objects[i].mesh;
}

static size_t mesh_bytes(const gg_mesh *m)
{
    size_t b = sizeof *m + m->nverts * sizeof(ggVec3) + 3 * m->ntri * sizeof(uint32_t), i;
    if (m->nrm) b += m->nverts * sizeof(ggVec3);
    if (m->uv) b += 2 * m->nverts * sizeof(double);
    if (m->tface) b += m->ntri * sizeof(uint32_t);
    b += m->nfaces * sizeof(uint32_t) *
         ((m->fline != NULL) + (m->fgroup != NULL) + (m->fmtl != NULL));
    for (i = 0; i < m->ngroups; i++) b += strlen(m->groups[i]) + 1 + sizeof(char *);
    for (i = 0; i < m->nmtlnames; i++) b += strlen(m->mtlnames[i]) + 1 + sizeof(char *);
    return b;
}

GG_API int ggSceneGetMeshInfo(const ggScene *s, int i, ggMeshInfo *in)
{
    const gg_mesh *m;
    if (!s || !in) return GG_ERROR_INVALID; /* rule 1: nothing written */
    memset(in, 0, sizeof *in);
    if (i < 0 || (size_t)i >= s->nmeshes) return GG_ERROR_INVALID;
    m = &s->meshes[i];
    in->name = m->name;
    in->format = m->format == GG_MESH_FORMAT_OBJ   ? "obj"
                 : m->format == GG_MESH_FORMAT_PLY ? "ply"
                                                   : "";
    in->file_vertices = m->file_vertices, in->file_faces = m->nfaces;
    in->vertices = m->nverts, in->triangles = m->ntri;
    in->skipped_faces = m->skipped, in->ignored = m->ignored;
    in->first_object = m->first_object, in->objects = m->nobjects;
    in->groups = m->ngroups > 1 ? (int)m->ngroups - 1 : 0; /* groups[0] is "": none */
    in->file_normals = m->file_normals, in->has_uv = m->uv != NULL;
    in->bytes = mesh_bytes(m);
    in->lo = m->lo, in->hi = m->hi;
    in->warnings = m->nwarn;
    in->warning = m->warning ? m->warning : "";
    return GG_OK;
}

GG_API int ggSceneGetFaceInfo(const ggScene *s, int object, long tri, ggFaceInfo *fi)
{
    const gg_mesh *m;
    size_t face;
    int k;
    if (!s || !fi) return GG_ERROR_INVALID; /* rule 1: nothing written */
    memset(fi, 0, sizeof *fi);
    fi->group = fi->material_name = fi->mesh_name = "";
    fi->mesh = ggSceneObjectMesh(s, object);
    if (fi->mesh < 0) return GG_ERROR_INVALID;
    m = &s->meshes[fi->mesh];
    if (tri < 0 || (size_t)tri >= m->ntri) return GG_ERROR_INVALID;
    face = m->tface ? m->tface[tri] : (size_t)tri;
    fi->mesh_name = m->name;
    fi->face = (long)face;
    fi->line = m->fline ? (int)m->fline[face] : 0;
    if (m->ngroups) fi->group = m->groups[m->fgroup ? m->fgroup[face] : 0];
    if (m->nmtlnames) fi->material_name = m->mtlnames[m->fmtl ? m->fmtl[face] : 0];
    for (k = 0; k < m->nobjects; k++) {
        const gg_object *o = &s->objects[m->first_object + k];
        if ((size_t)tri >= o->tri_first && (size_t)tri < o->tri_first + o->ntri)
            fi->material = o->material;
    }
    return GG_OK;
}

static const gg_object *mesh_part(const ggScene *s, int object)
{
    if (!s || object < 0 || object >= ggSceneObjectCount(s)) return NULL;
    return s->objects[object].kind == GG_SHAPE_MESH ? &s->objects[object] : NULL;
}

GG_API long ggSceneObjectTriangleCount(const ggScene *s, int object)
{
    const gg_object *o = mesh_part(s, object);
    return o ? (long)o->ntri : 0;
}

GG_API int ggSceneObjectTriangle(const ggScene *s, int object, long k, ggVec3 v[3],
                                 long *triangle)
{
    const gg_object *o = mesh_part(s, object);
    const gg_mesh *m;
    size_t t;
    int i;
    if (!o || !v || k < 0 || (size_t)k >= o->ntri) return GG_ERROR_INVALID;
    m = &s->meshes[o->mesh];
    t = o->tri_first + (size_t)k;
    for (i = 0; i < 3; i++) v[i] = m->pos[m->idx[3 * t + (size_t)i]];
    if (triangle) *triangle = (long)t;
    return GG_OK;
}

long gg_scene_hit_triangle(const ggScene *s, const gg_object *o, uint32_t prim)
{
    if (o->kind != GG_SHAPE_MESH) return -1;
    return (long)o->tri_first + gg_geom_prim_mesh_triangle(s->geom, prim);
}

/* ---- framing ---- */

static void grow(ggVec3 *lo, ggVec3 *hi, ggVec3 p, double r)
{
    *lo = v3min(*lo, v3(p.x - r, p.y - r, p.z - r));
    *hi = v3max(*hi, v3(p.x + r, p.y + r, p.z + r));
}

/* A box around object o (loose for cones: both end spheres). */
static void object_box(const ggScene *s, const gg_object *o, ggVec3 *lo, ggVec3 *hi)
{
    int i;
    switch (o->kind) {
    case GG_SHAPE_SPHERE:
        grow(lo, hi, o->a, o->ra);
        break;
    case GG_SHAPE_CONE:
        grow(lo, hi, o->a, o->ra), grow(lo, hi, o->b, o->rb);
        break;
    case GG_SHAPE_RECT:
        for (i = 0; i < 4; i++)
            grow(lo, hi, v3add(v3add(o->a, v3scale(o->b, i & 1)), v3scale(o->c, i >> 1)), 0);
        break;
    case GG_SHAPE_IMPLICIT: {
        ggVec3 a, b;
        gg_implicit_bounds(o->imp, &a, &b);
        grow(lo, hi, a, 0), grow(lo, hi, b, 0);
        break;
    }
    case GG_SHAPE_MESH:
        grow(lo, hi, s->meshes[o->mesh].lo, 0), grow(lo, hi, s->meshes[o->mesh].hi, 0);
        break;
    default:
        for (i = 0; i < o->nverts; i++) grow(lo, hi, s->verts[o->vfirst + (size_t)i], 0);
    }
}

/* The bounds [lo, hi] are within GG_COORD_MAX, but the lights placed
   around them (up to about six times as far out) need not be. */
static int too_large(ggError *err, int code, ggVec3 lo, ggVec3 hi, const char *why)
{
    return gg_error_set(err, code,
                        "framing: the scene's bounds (%g %g %g to %g %g %g) are too large to "
                        "frame: %s",
                        lo.x, lo.y, lo.z, hi.x, hi.y, hi.z, why);
}

/* A key and a fill light around the bounds; none on failure. */
static int frame_lights(ggScene *s, ggVec3 c, double r, ggVec3 lo, ggVec3 hi, ggError *err)
{
    const size_t n = s->nlights;
    int id = ggSceneAddLight(s, v3madd(c, v3(1, 1.6, 1.2), 2.5 * r), rgb(0.8, 0.8, 0.8));
    if (id >= 0)
        id = ggSceneAddLight(s, v3madd(c, v3(-1.5, 0.5, 1), 2.5 * r), rgb(0.35, 0.35, 0.35));
    if (id >= 0) return GG_OK;
    s->nlights = n;
    if (id == -GG_ERROR_NOMEM) return gg_error_set(err, GG_ERROR_NOMEM, "framing: out of memory");
    return too_large(err, -id, lo, hi, "a light would be over 1e64 in magnitude (GG_COORD_MAX)");
}

GG_API int ggSceneFrame(ggScene *s, unsigned what, ggError *err)
{
    ggVec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY), c, dir;
    double r, d;
    size_t i;
    ggCamera cam0;
    ggError ce = {0, ""};
    bool had;
    int rc;
    if (!s || !s->nobjects)
        return gg_error_set(err, GG_ERROR_INVALID, "framing: the scene is empty");
    for (i = 0; i < s->nobjects; i++) object_box(s, &s->objects[i], &lo, &hi);
    if (!v3finite(lo) || !v3finite(hi))
        return gg_error_set(err, GG_ERROR_INVALID, "the scene's bounds are not finite");
    cam0 = s->camera, had = s->has_camera;
    c = v3scale(v3add(lo, hi), 0.5);
    r = 0.5 * v3len(v3sub(hi, lo));
    if (!(r > 0)) r = 1;
    if (what & GG_FRAME_CAMERA) {
        ggCamera cam = s->camera;
        double aspect = cam.width > 0 && cam.height > 0 ? (double)cam.height / cam.width : 1;
        double tx, ty;
        ggVec3 right, up;
        int k;
        cam.fov_deg = 40;
        tx = tan(cam.fov_deg * GG_PI / 360), ty = tx * aspect;
        dir = v3norm(v3(0.5, 0.4, 1));
        right = v3norm(v3cross(v3(0, 1, 0), dir)), up = v3cross(dir, right);
        /* the nearest distance at which every corner of the box is in view */
        d = 0;
        for (k = 0; k < 8; k++) {
            ggVec3 q = v3sub(v3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z), c);
            double z = v3dot(q, dir),
                   need = z + fmax(fabs(v3dot(q, right)) / tx, fabs(v3dot(q, up)) / ty);
            if (need > d) d = need;
        }
        if (!(d > 0)) d = r / sin(atan(ty < tx ? ty : tx));
        cam.at = c, cam.from = v3madd(c, dir, 1.08 * d), cam.up = v3(0, 1, 0);
        if (ggCameraCheck(&cam, &ce) != GG_OK || ggSceneSetCamera(s, &cam) != GG_OK)
            return too_large(err, GG_ERROR_INVALID, lo, hi, ce.message);
    }
    if ((what & GG_FRAME_LIGHTS) && (rc = frame_lights(s, c, r, lo, hi, err)) != GG_OK) {
        s->camera = cam0, s->has_camera = had;
        return rc;
    }
    return GG_OK;
}
