/* SPDX-License-Identifier: MIT */
/*
** trace_obj.c -- a recorded ray tree as Wavefront OBJ lines (ggrt trace
** --obj): one line object per ray and per shadow ray, to load beside the
** scene's geometry in a 3D viewer.
*/
#include "trace/trace_view.h"

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
