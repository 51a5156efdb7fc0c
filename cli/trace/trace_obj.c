/* SPDX-License-Identifier: MIT */
/*
** trace_obj.c -- a recorded ray tree as Wavefront OBJ lines (ggrt trace
** --obj): one line object per ray and per shadow ray, to load beside the
** scene's geometry in a 3D viewer.
*/
#include "trace/trace_view.h"

#include <math.h>

/* o + t d */
static ggVec3 along(ggVec3 o, ggVec3 d, double t)
{
    ggVec3 r;
    r.x = o.x + d.x * t, r.y = o.y + d.y * t, r.z = o.z + d.z * t;
    return r;
}

void trace_write_obj(FILE *f, const trace_view *v)
{
    size_t i, n = ggTraceNodeCount(v->trace);
    int vert = 0, l;
    fprintf(f, "# ggrt trace %s --pixel %d,%d: one line object per ray\n", v->path, v->x, v->y);
    for (i = 0; i < n; i++) {
        const ggTraceNode *nd = ggTraceGetNode(v->trace, i);
        ggVec3 e = nd->hit ? nd->p : along(nd->o, nd->d, 1.0);
        fprintf(f, "o ray%zu_%s%s\nv %.9g %.9g %.9g\nv %.9g %.9g %.9g\nl %d %d\n", i,
                ggRayKindName(nd->kind), nd->hit ? "" : "_miss", nd->o.x, nd->o.y, nd->o.z, e.x,
                e.y, e.z, vert + 1, vert + 2);
        vert += 2;
        for (l = 0; l < nd->nlights; l++) {
            const ggTraceLight *L = ggTraceGetLight(v->trace, (size_t)(nd->first_light + l));
            double t = L->verdict == GG_SHADOW_BLOCKED ? L->t_block : 1;
            ggVec3 se = along(L->origin, L->dir, t);
            if (L->verdict == GG_SHADOW_FACING_AWAY) continue;
            fprintf(f, "o shadow%zu_light%d_%s\nv %.9g %.9g %.9g\nv %.9g %.9g %.9g\nl %d %d\n", i,
                    L->light, ggShadowName(L->verdict), L->origin.x, L->origin.y, L->origin.z, se.x,
                    se.y, se.z, vert + 1, vert + 2);
            vert += 2;
        }
    }
}

/* ---- the scene ---- */

#define PI          3.14159265358979323846
#define SEGMENTS    32       /* around a sphere or cone (a sphere has half as many bands)... */
#define ROUND_VERTS 2000000L /* ...halved, to 8 at least, while they would make more */

static void put_v(FILE *f, ggVec3 p)
{
    fprintf(f, "v %.9g %.9g %.9g\n", p.x, p.y, p.z);
}

static ggVec3 comb(ggVec3 c, ggVec3 a, double s, ggVec3 b, double t)
{
    ggVec3 r;
    r.x = c.x + a.x * s + b.x * t, r.y = c.y + a.y * s + b.y * t, r.z = c.z + a.z * s + b.z * t;
    return r;
}

/* The quads of a grid of `rows` x seg vertices starting at vertex
   first + 1, closed around; returns the vertices used. */
static long quads(FILE *f, long first, int rows, int seg)
{
    int i, j;
    for (j = 0; j + 1 < rows; j++)
        for (i = 0; i < seg; i++) {
            long a = first + (long)j * seg + i + 1, b = first + (long)j * seg + (i + 1) % seg + 1;
            fprintf(f, "f %ld %ld %ld %ld\n", a, b, b + seg, a + seg);
        }
    return (long)rows * seg;
}

/* A sphere in latitude and longitude about z (its texture's frame). */
static long sphere(FILE *f, const ggShapeDesc *d, long first, int seg)
{
    int i, j;
    ggVec3 z = {0, 0, 1};
    for (j = 0; j <= seg / 2; j++) {
        double th = PI * j / (seg / 2), ct = cos(th), st = sin(th);
        for (i = 0; i < seg; i++) {
            double ph = 2 * PI * i / seg;
            ggVec3 p =
                comb(d->base, d->e1, d->radius * st * cos(ph), d->e2, d->radius * st * sin(ph));
            put_v(f, comb(p, z, d->radius * ct, z, 0));
        }
    }
    return quads(f, first, seg / 2 + 1, seg);
}

/* An open cone: its base and apex circles, joined. */
static long cone(FILE *f, const ggShapeDesc *d, long first, int seg)
{
    int i, end;
    for (end = 0; end < 2; end++)
        for (i = 0; i < seg; i++) {
            double ph = 2 * PI * i / seg, r = end ? d->radius2 : d->radius;
            put_v(f, comb(end ? d->apex : d->base, d->e1, r * cos(ph), d->e2, r * sin(ph)));
        }
    return quads(f, first, 2, seg);
}

/* Vertices v[0..n) as one face. */
static long face(FILE *f, const ggVec3 *v, int n, long first)
{
    int i;
    for (i = 0; i < n; i++) put_v(f, v[i]);
    fputc('f', f);
    for (i = 0; i < n; i++) fprintf(f, " %ld", first + i + 1);
    fputc('\n', f);
    return n;
}

/* (the loops that can be long stop at a cancel signal: the file is then
   removed) */
static long mesh_part(FILE *f, const ggScene *s, int obj, long first)
{
    long k, n = ggSceneObjectTriangleCount(s, obj), used = 0;
    ggVec3 v[3];
    for (k = 0; k < n && !cli_cancelled(); k++)
        if (ggSceneObjectTriangle(s, obj, k, v, NULL) == GG_OK) used += face(f, v, 3, first + used);
    return used;
}

/* The triangulation the 3D view draws (docs/serve.md): at the first of
   cli_surface_cells whose triangles fit in `share`, with a warning and a
   comment in the file when that is not the first (a rough surface at 64
   cells made a million triangles, eight of them 436 MB in 13 s); left
   out, with both, when none fits. Nothing where it fails or finds no
   sign change. *tris gets the triangles written. */
static long surface(FILE *f, const ggScene *s, const char *path, int obj, const ggShapeDesc *d,
                    long first, long share, long *tris)
{
    ggTriangulation *t = NULL;
    size_t k;
    int r, rc = GG_ERROR_LIMIT;
    *tris = 0;
    for (r = 0; r < CLI_SURFACE_STEPS && rc == GG_ERROR_LIMIT && !cli_cancelled(); r++)
        rc = ggSceneObjectTriangulate(s, obj, cli_surface_cells[r], (size_t)(share > 0 ? share : 1),
                                      &t);
    if (rc == GG_ERROR_LIMIT && !cli_cancelled()) {
        cli_warn("--scene-obj: implicit #%d (%s:%d) would take more than its share (%ld of %ld "
                 "triangles) even at %d cells: left out",
                 obj, path, d->line, share, CLI_SCENE_OBJ_TRIANGLES,
                 cli_surface_cells[CLI_SURFACE_STEPS - 1]);
        fprintf(f, "# left out: more than %ld triangles even at %d cells\n", share,
                cli_surface_cells[CLI_SURFACE_STEPS - 1]);
    }
    if (rc != GG_OK) return 0;
    if (t->resolution != cli_surface_cells[0]) {
        cli_warn("--scene-obj: implicit #%d (%s:%d) would take more than its share (%ld of %ld "
                 "triangles) at %d cells: written at %d cells, %zu triangles",
                 obj, path, d->line, share, CLI_SCENE_OBJ_TRIANGLES, cli_surface_cells[0],
                 t->resolution, t->ntris);
        fprintf(f, "# %d cells along the box's longest side, not %d: at most %ld triangles\n",
                t->resolution, cli_surface_cells[0], share);
    }
    for (k = 0; k < t->nverts && !cli_cancelled(); k++) put_v(f, t->verts[k]);
    for (k = 0; k < t->ntris && !cli_cancelled(); k++)
        fprintf(f, "f %ld %ld %ld\n", first + (long)t->tris[3 * k] + 1,
                first + (long)t->tris[3 * k + 1] + 1, first + (long)t->tris[3 * k + 2] + 1);
    *tris = (long)t->ntris;
    k = t->nverts;
    ggTriangulationFree(t);
    return (long)k;
}

/* Segments around the scene's spheres and cones: SEGMENTS, halved while
   they would make more than ROUND_VERTS vertices (balls-s4's 7382
   spheres: 16, 1.06M vertices, not 4M). */
static int segments(const ggScene *s, int n)
{
    long round = 0;
    int i, seg = SEGMENTS;
    for (i = 0; i < n; i++) {
        int k = ggSceneObjectKind(s, i);
        round += k == GG_SHAPE_SPHERE || k == GG_SHAPE_CONE;
    }
    while (seg > 8 && round * seg * (seg / 2 + 1) > ROUND_VERTS) seg /= 2;
    return seg;
}

static int implicit_count(const ggScene *s, int n)
{
    int i, k = 0;
    for (i = 0; i < n; i++) k += ggSceneObjectKind(s, i) == GG_SHAPE_IMPLICIT;
    return k;
}

int trace_write_scene_obj(FILE *f, const ggScene *s, const char *path)
{
    int i, n = ggSceneObjectCount(s), seg = segments(s, n), left = implicit_count(s, n);
    long first = 0, budget = CLI_SCENE_OBJ_TRIANGLES, used;
    fprintf(f, "# ggrt trace --scene-obj: %s, %d objects, one OBJ object each; %d segments\n", path,
            n, seg);
    for (i = 0; i < n && !cli_cancelled(); i++) {
        ggShapeDesc d;
        if (ggSceneObjectShape(s, i, &d) != GG_OK) continue;
        fprintf(f, "o object%d_%s_line%d\n", i, ggShapeKindName(d.kind), d.line);
        switch (d.kind) {
        case GG_SHAPE_SPHERE:
            first += sphere(f, &d, first, seg);
            break;
        case GG_SHAPE_CONE:
            if (d.e1.x != 0 || d.e1.y != 0 || d.e1.z != 0) first += cone(f, &d, first, seg);
            break;
        case GG_SHAPE_RECT: {
            ggVec3 q[4];
            q[0] = d.base, q[1] = comb(d.base, d.e1, 1, d.e2, 0);
            q[2] = comb(d.base, d.e1, 1, d.e2, 1), q[3] = comb(d.base, d.e1, 0, d.e2, 1);
            first += face(f, q, 4, first);
            break;
        }
        case GG_SHAPE_IMPLICIT: /* an equal share of what those before left */
            first += surface(f, s, path, i, &d, first, budget / left--, &used);
            budget -= used;
            break;
        case GG_SHAPE_MESH:
            first += mesh_part(f, s, i, first);
            break;
        default:
            if (d.verts && d.nverts >= 3) first += face(f, d.verts, d.nverts, first);
        }
    }
    return cli_cancelled();
}
