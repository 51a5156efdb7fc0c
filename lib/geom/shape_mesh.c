/* SPDX-License-Identifier: MIT */
/*
** shape_mesh.c -- indexed triangle meshes: their triangles are ordinary
** BVH triangles (the same intersection records and kernel), but what
** shading needs -- vertices, normals, texture coordinates -- is read from
** the caller's shared vertex arrays instead of being copied per triangle
** (a gg_tri holds 152 bytes; a mesh triangle costs its gg_prim alone).
*/
#include "geom_int.h"

int gg_geom_add_mesh(gg_geom *g, const ggVec3 *pos, const ggVec3 *nrm, const double *uv,
                     const uint32_t *idx, size_t ntri, int32_t obj)
{
    gg_gmesh *m;
    size_t i, need = g->nprim + ntri;
    if (!pos || !idx || ntri == 0) return GG_GEOM_DEGENERATE;
    if (need >= (size_t)INT32_MAX || need >= GG_MAX_ELEMS) return GG_GEOM_LIMIT;
    if (gg_mem_grow(g->alloc, (void **)&g->gmeshes, &g->cap_gmesh, g->ngmesh + 1,
                    sizeof *g->gmeshes) ||
        gg_mem_grow(g->alloc, (void **)&g->prims, &g->cap_prim, need, sizeof *g->prims) ||
        gg_mem_grow(g->alloc, (void **)&g->pflags, &g->cap_flags, need, 1))
        return GG_GEOM_NOMEM;
    m = &g->gmeshes[g->ngmesh];
    m->pos = pos, m->nrm = nrm, m->uv = uv, m->idx = idx;
    m->pfirst = (uint32_t)g->nprim, m->ntri = (uint32_t)ntri;
    for (i = 0; i < ntri; i++) {
        gg_prim *p = &g->prims[g->nprim + i];
        p->kind = GG_SHAPE_MESH;
        p->data = (uint32_t)g->ngmesh;
        p->obj = obj;
        g->pflags[g->nprim + i] = 0;
    }
    g->ngmesh++;
    g->nmtri += ntri;
    g->nprim = need;
    g->built = 0;
    return (int)m->pfirst;
}

long gg_geom_prim_mesh_triangle(const gg_geom *g, uint32_t prim)
{
    if (prim >= g->nprim || g->prims[prim].kind != GG_SHAPE_MESH) return -1;
    return (long)(prim - g->gmeshes[g->prims[prim].data].pfirst);
}

static const uint32_t *tri_of(const gg_geom *g, uint32_t prim, const gg_gmesh **m)
{
    *m = &g->gmeshes[g->prims[prim].data];
    return (*m)->idx + 3 * (size_t)(prim - (*m)->pfirst);
}

void gg_mesh_ktri(const gg_geom *g, uint32_t prim, gg_ktri *k)
{
    const gg_gmesh *m;
    const uint32_t *t = tri_of(g, prim, &m);
    int v;
    for (v = 0; v < 3; v++) {
        const ggVec3 *p = &m->pos[t[v]];
        k->v[v][0] = p->x, k->v[v][1] = p->y, k->v[v][2] = p->z;
    }
}

/* The triangle's surface exactly as gg_tri_surface computes it for a
   gg_tri made by gg_geom_add_triangle from the same vertices and normals
   (so a mesh and the same triangles added one by one shade alike), then
   (u, v) from the texture coordinates when the mesh has them. */
void gg_mesh_surface(const gg_geom *g, uint32_t prim, const gg_rayq *q, const gg_hit *h,
                     gg_surf *out, unsigned what)
{
    const gg_gmesh *m;
    const uint32_t *t = tri_of(g, prim, &m);
    gg_tri tr;
    ggVec3 n[3];
    int i, has_n = 0;
    memset(&tr, 0, sizeof tr);
    tr.ni = GG_TRI_FLAT; /* the normals are n, here */
    gg_mesh_ktri(g, prim, &tr.k);
    if (m->nrm) {
        ggVec3 a = m->pos[t[0]], ng = v3cross(v3sub(m->pos[t[1]], a), v3sub(m->pos[t[2]], a));
        has_n = 1;
        for (i = 0; i < 3; i++) {
            n[i] = m->nrm[t[i]];
            if (!(v3dot(n[i], n[i]) > 0.5)) has_n = 0;
        }
        if (has_n) tr.flip = v3dot(ng, v3add(v3add(n[0], n[1]), n[2])) < 0;
    }
    gg_tri_set_normal(&tr);
    gg_tri_surface(&tr, has_n ? n : NULL, q, h, out, what);
    if (m->uv && (what & GG_SURF_UV)) {
        double uv[2];
        gg_uv_interp(m->uv + 2 * (size_t)t[0], m->uv + 2 * (size_t)t[1], m->uv + 2 * (size_t)t[2],
                     h->b1, h->b2, uv);
        out->u = uv[0], out->v = uv[1];
    }
}
