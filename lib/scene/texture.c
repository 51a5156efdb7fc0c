/* SPDX-License-Identifier: MIT */
/*
** texture.c -- the public side of textures: what each texture is, and
** the (u, v) the renderer gives a point of an object (ggSceneObjectUV),
** worked out by the formulas the hit surfaces use (lib/geom/uv.c).
*/
#include "scene.h"

#include "vec.h"

#include <string.h>

GG_API int ggSceneTextureCount(const ggScene *s)
{
    return s ? (int)s->ntextures : 0;
}

GG_API int ggSceneGetTexture(const ggScene *s, int index, ggTextureInfo *out)
{
    const gg_texture *t;
    if (!s || !out || index < 0 || (size_t)index >= s->ntextures) return GG_ERROR_INVALID;
    t = &s->textures[index];
    memset(out, 0, sizeof *out);
    out->image = t->img;
    out->wrap = t->wrap;
    out->nearest = t->nearest != 0;
    if (!t->img) {
        out->checker_n = t->checker_n;
        out->checker_a = t->checker_a;
        out->checker_b = t->checker_b;
    }
    return GG_OK;
}

/* The corners of the triangle `part` of a triangle object (a fan when it
   has more than 3 vertices): 0, or -1 when part is out of range. */
static int fan_triangle(const ggScene *s, const gg_object *o, long part, ggVec3 v[3])
{
    if (part < 0 || part > (long)o->nverts - 3) return -1;
    v[0] = s->verts[o->vfirst];
    v[1] = s->verts[o->vfirst + (size_t)part + 1];
    v[2] = s->verts[o->vfirst + (size_t)part + 2];
    return 0;
}

GG_API int ggSceneObjectUV(const ggScene *s, int object, long part, const ggVec3 *p, size_t n,
                           double *uv)
{
    const gg_object *o;
    gg_uv_plane plane;
    ggVec3 v[3];
    double tuv[6], *corner_uv = NULL, e[2];
    size_t i;
    int k;
    if (!s || (n && (!p || !uv)) || object < 0 || (size_t)object >= s->nobjects)
        return GG_ERROR_INVALID;
    for (i = 0; i < n; i++)
        if (!v3finite(p[i])) return GG_ERROR_INVALID;
    o = &s->objects[object];
    /* First whether the shape has (u, v) at all, on a point of its own,
       so that a failure writes nothing. */
    switch (o->kind) {
    case GG_SHAPE_SPHERE:
        if (gg_uv_sphere(o->a, o->ra, o->a, e)) return GG_ERROR_INVALID;
        break;
    case GG_SHAPE_CONE:
        if (gg_uv_cone(o->a, o->ra, o->b, o->rb, o->a, e)) return GG_ERROR_INVALID;
        break;
    case GG_SHAPE_RECT:
        if (gg_uv_rect(o->a, o->b, o->c, o->a, e)) return GG_ERROR_INVALID;
        break;
    case GG_SHAPE_TRIANGLE:
    case GG_SHAPE_POLYGON:
        if (o->nverts == 3 || o->kind == GG_SHAPE_TRIANGLE) {
            if (fan_triangle(s, o, o->kind == GG_SHAPE_TRIANGLE ? part : 0, v) ||
                gg_uv_triangle(v, NULL, v[0], e))
                return GG_ERROR_INVALID;
        } else if (gg_uv_plane_make(s->verts + o->vfirst, o->nverts, &plane)) {
            return GG_ERROR_INVALID;
        }
        break;
    case GG_SHAPE_MESH: {
        const gg_mesh *m = &s->meshes[o->mesh];
        const uint32_t *t;
        if (part < (long)o->tri_first || part >= (long)(o->tri_first + o->ntri))
            return GG_ERROR_INVALID;
        t = m->idx + 3 * (size_t)part;
        for (k = 0; k < 3; k++) {
            v[k] = m->pos[t[k]];
            if (m->uv)
                tuv[2 * k] = m->uv[2 * (size_t)t[k]], tuv[2 * k + 1] = m->uv[2 * (size_t)t[k] + 1];
        }
        corner_uv = m->uv ? tuv : NULL;
        if (gg_uv_triangle(v, corner_uv, v[0], e)) return GG_ERROR_INVALID;
        break;
    }
    default: /* implicit */
        for (i = 0; i < 2 * n; i++) uv[i] = 0;
        return GG_OK;
    }
    for (i = 0; i < n; i++) {
        double *w = uv + 2 * i;
        switch (o->kind) {
        case GG_SHAPE_SPHERE:
            gg_uv_sphere(o->a, o->ra, p[i], w);
            break;
        case GG_SHAPE_CONE:
            gg_uv_cone(o->a, o->ra, o->b, o->rb, p[i], w);
            break;
        case GG_SHAPE_RECT:
            gg_uv_rect(o->a, o->b, o->c, p[i], w);
            break;
        case GG_SHAPE_TRIANGLE:
        case GG_SHAPE_POLYGON:
            if (o->nverts == 3 || o->kind == GG_SHAPE_TRIANGLE)
                gg_uv_triangle(v, NULL, p[i], w);
            else
                gg_uv_plane_at(&plane, p[i], w);
            break;
        default:
            gg_uv_triangle(v, corner_uv, p[i], w);
        }
    }
    return GG_OK;
}
