/* SPDX-License-Identifier: MIT */
/*
** geom.c -- primitive storage, the build that turns primitives into BVH
** elements, the brute-force reference query and the surface dispatch.
*/
#include "geom_leaf.h"

#include <string.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

gg_geom *gg_geom_create(const ggAllocator *alloc)
{
    gg_geom *g = gg_mem_calloc(alloc, 1, sizeof *g);
    if (!g) return NULL;
    if (alloc) {
        g->alloc_copy = *alloc;
        g->alloc = &g->alloc_copy;
    }
    g->poly_mode = GG_POLY_TRIANGULATE;
    g->cpu = GG_CPU_ALL;
    return g;
}

void gg_geom_set_cpu(gg_geom *g, unsigned cpu)
{
    g->cpu = cpu;
}

const gg_qopt gg_qopt_default = {GG_SPHERE_STABLE, GG_ISECT_DOUBLE, 0, 0};

static void free_built(gg_geom *g)
{
    gg_mem_free(g->alloc, g->slots);
    gg_mem_free(g->alloc, g->lsph);
    gg_mem_free(g->alloc, g->ltri);
    gg_mem_free(g->alloc, g->lcone);
    gg_mem_free(g->alloc, g->lrect);
    gg_mem_free(g->alloc, g->iso);
    gg_mem_free(g->alloc, g->iso_margin);
    g->iso = NULL, g->iso_margin = NULL;
    g->slots = NULL, g->lsph = NULL, g->ltri = NULL, g->lcone = NULL, g->lrect = NULL;
    g->nslots = 0, g->clipped = 0;
    gg_bvh_free(g);
    g->built = 0;
}

void gg_geom_free(gg_geom *g)
{
    if (!g) return;
    free_built(g);
    gg_mem_free(g->alloc, g->prims);
    gg_mem_free(g->alloc, g->pflags);
    gg_mem_free(g->alloc, g->sphs);
    gg_mem_free(g->alloc, g->tris);
    gg_mem_free(g->alloc, g->tnrm);
    gg_mem_free(g->alloc, g->polys);
    gg_mem_free(g->alloc, g->pverts);
    gg_mem_free(g->alloc, g->pieces);
    gg_mem_free(g->alloc, g->cones);
    gg_mem_free(g->alloc, g->rects);
    gg_mem_free(g->alloc, (void *)g->imps);
    gg_mem_free(g->alloc, g->gmeshes);
    gg_mem_free(g->alloc, g);
}

/* Append a primitive record once its shape data is stored at `data`. */
static int add_prim(gg_geom *g, int kind, size_t data, int32_t obj)
{
    gg_prim *p;
    if (g->nprim >= (size_t)INT32_MAX || g->nprim >= GG_MAX_ELEMS) return GG_GEOM_LIMIT;
    if (gg_mem_grow(g->alloc, (void **)&g->prims, &g->cap_prim, g->nprim + 1, sizeof *g->prims))
        return GG_GEOM_NOMEM;
    if (gg_mem_grow(g->alloc, (void **)&g->pflags, &g->cap_flags, g->nprim + 1, 1))
        return GG_GEOM_NOMEM;
    p = &g->prims[g->nprim];
    p->kind = (uint8_t)kind;
    p->data = (uint32_t)data;
    p->obj = obj;
    p->tag = 0;
    g->pflags[g->nprim] = 0;
    g->built = 0;
    return (int)g->nprim++;
}

/* 0, or GG_GEOM_NOMEM */
static int grow(gg_geom *g, void **arr, size_t *cap, size_t need, size_t elem)
{
    return gg_mem_grow(g->alloc, arr, cap, need, elem) ? GG_GEOM_NOMEM : 0;
}

/* Room for exactly `need` elements (no doubling past it). */
static int reserve(gg_geom *g, void **arr, size_t *cap, size_t need, size_t elem)
{
    void *np;
    if (need <= *cap) return 0;
    if (need > (size_t)-1 / elem) return GG_GEOM_NOMEM;
    if (!(np = gg_mem_realloc(g->alloc, *arr, need * elem))) return GG_GEOM_NOMEM;
    *arr = np, *cap = need;
    return 0;
}

int gg_geom_reserve(gg_geom *g, size_t nprim, size_t ntri)
{
    if (reserve(g, (void **)&g->prims, &g->cap_prim, nprim, sizeof *g->prims) ||
        reserve(g, (void **)&g->pflags, &g->cap_flags, nprim, 1) ||
        reserve(g, (void **)&g->tris, &g->cap_tri, ntri, sizeof *g->tris))
        return GG_GEOM_NOMEM;
    return 0;
}

static int finite3(const ggVec3 *p, int n)
{
    int i;
    for (i = 0; i < n; i++)
        if (!v3finite(p[i])) return 0;
    return 1;
}

int gg_geom_add_sphere(gg_geom *g, ggVec3 c, double r, int32_t obj)
{
    int rc;
    if (!v3finite(c) || !(r > 0) || !isfinite(r) || !isfinite(r * r)) return GG_GEOM_DEGENERATE;
    if (grow(g, (void **)&g->sphs, &g->cap_sph, g->nsph + 1, sizeof *g->sphs)) return GG_GEOM_NOMEM;
    g->sphs[g->nsph].c = c;
    g->sphs[g->nsph].r = r;
    if ((rc = add_prim(g, GG_SHAPE_SPHERE, g->nsph, obj)) < 0) return rc;
    g->nsph++;
    return (int)g->nprim - 1;
}

static void set_ktri(gg_ktri *k, ggVec3 a, ggVec3 b, ggVec3 c)
{
    k->v[0][0] = a.x, k->v[0][1] = a.y, k->v[0][2] = a.z;
    k->v[1][0] = b.x, k->v[1][1] = b.y, k->v[1][2] = b.z;
    k->v[2][0] = c.x, k->v[2][1] = c.y, k->v[2][2] = c.z;
}

int gg_geom_add_triangle(gg_geom *g, const ggVec3 p[3], const ggVec3 *n, int32_t obj)
{
    gg_tri *t;
    ggVec3 ng;
    int rc;
    if (!finite3(p, 3)) return GG_GEOM_DEGENERATE;
    ng = v3cross(v3sub(p[1], p[0]), v3sub(p[2], p[0]));
    /* nonzero, not |ng|^2 > 0: that underflows for edges below 2^-268 */
    if (!(v3maxabs(ng) > 0) || !v3finite(ng)) return GG_GEOM_DEGENERATE;
    if (grow(g, (void **)&g->tris, &g->cap_tri, g->ntri + 1, sizeof *g->tris)) return GG_GEOM_NOMEM;
    t = &g->tris[g->ntri];
    memset(t, 0, sizeof *t);
    t->ni = GG_TRI_FLAT;
    set_ktri(&t->k, p[0], p[1], p[2]);
    if (n && finite3(n, 3)) {
        ggVec3 u[3];
        int i, ok = 1;
        for (i = 0; i < 3; i++) {
            u[i] = v3unit(n[i]);
            if (!(v3dot(u[i], u[i]) > 0.5)) ok = 0;
        }
        /* Which side the normals call "out" is decided once per triangle,
           from their sum, so ng never flips inside a triangle. */
        if (ok) {
            if (g->ntnrm / 3 >= GG_TRI_FLAT ||
                grow(g, (void **)&g->tnrm, &g->cap_tnrm, g->ntnrm + 3, sizeof *g->tnrm))
                return GG_GEOM_NOMEM;
            memcpy(&g->tnrm[g->ntnrm], u, sizeof u);
            t->ni = (uint32_t)(g->ntnrm / 3);
            t->flip = v3dot(ng, v3add(v3add(u[0], u[1]), u[2])) < 0;
        }
    }
    gg_tri_set_normal(t);
    if ((rc = add_prim(g, GG_SHAPE_TRIANGLE, g->ntri, obj)) < 0) return rc;
    if (t->ni != GG_TRI_FLAT) g->ntnrm += 3;
    g->ntri++;
    return (int)g->nprim - 1;
}

int gg_geom_add_polygon(gg_geom *g, const ggVec3 *p, int n, int32_t obj)
{
    gg_poly pl;
    int rc;
    if (!p || n < 3 || !finite3(p, n)) return GG_GEOM_DEGENERATE;
    if (n == 3) {
        int id = gg_geom_add_triangle(g, p, NULL, obj);
        return id;
    }
    if (grow(g, (void **)&g->polys, &g->cap_poly, g->npoly + 1, sizeof *g->polys))
        return GG_GEOM_NOMEM;
    if ((rc = gg_poly_prepare(g, p, n, &pl)) != 0) return rc;
    g->polys[g->npoly] = pl;
    if ((rc = add_prim(g, GG_SHAPE_POLYGON, g->npoly, obj)) < 0) {
        g->npverts = pl.vfirst;
        g->npieces = pl.piece_first;
        return rc;
    }
    g->npoly++;
    return (int)g->nprim - 1;
}

int gg_geom_add_cone(gg_geom *g, ggVec3 base, double rb, ggVec3 apex, double ra, int32_t obj)
{
    gg_cone c;
    int rc;
    if (gg_cone_prepare(base, rb, apex, ra, &c)) return GG_GEOM_DEGENERATE;
    if (grow(g, (void **)&g->cones, &g->cap_cone, g->ncone + 1, sizeof *g->cones))
        return GG_GEOM_NOMEM;
    g->cones[g->ncone] = c;
    if ((rc = add_prim(g, GG_SHAPE_CONE, g->ncone, obj)) < 0) return rc;
    g->ncone++;
    return (int)g->nprim - 1;
}

int gg_geom_add_rect(gg_geom *g, ggVec3 corner, ggVec3 e1, ggVec3 e2, int32_t obj)
{
    gg_rect r;
    int rc;
    if (gg_rect_prepare(corner, e1, e2, &r)) return GG_GEOM_DEGENERATE;
    if (grow(g, (void **)&g->rects, &g->cap_rect, g->nrect + 1, sizeof *g->rects))
        return GG_GEOM_NOMEM;
    g->rects[g->nrect] = r;
    if ((rc = add_prim(g, GG_SHAPE_RECT, g->nrect, obj)) < 0) return rc;
    g->nrect++;
    return (int)g->nprim - 1;
}

int gg_geom_add_implicit(gg_geom *g, const ggImplicit *imp, int32_t obj)
{
    double lo[3], hi[3];
    int rc;
    if (!imp) return GG_GEOM_DEGENERATE;
    gg_implicit_shape_bounds(imp, lo, hi);
    if (!(lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2])) return GG_GEOM_DEGENERATE;
    if (grow(g, (void **)&g->imps, &g->cap_imp, g->nimp + 1, sizeof *g->imps)) return GG_GEOM_NOMEM;
    g->imps[g->nimp] = imp;
    if ((rc = add_prim(g, GG_SHAPE_IMPLICIT, g->nimp, obj)) < 0) return rc;
    g->nimp++;
    return (int)g->nprim - 1;
}

void gg_geom_set_flags(gg_geom *g, int prim, unsigned flags)
{
    if (prim >= 0 && (size_t)prim < g->nprim) g->pflags[prim] = (uint8_t)flags;
}

size_t gg_geom_prim_count(const gg_geom *g)
{
    return g->nprim;
}

int32_t gg_geom_prim_object(const gg_geom *g, uint32_t prim)
{
    return prim < g->nprim ? g->prims[prim].obj : -1;
}

/* Every line of the n bytes at p. */
static void prefetch_span(const void *p, size_t n)
{
    const char *c = p;
    size_t i;
    for (i = 0; i < n; i += 64) GG_PREFETCH(c + i);
    GG_PREFETCH(c + n - 1);
}

void gg_geom_prefetch_hit(const gg_geom *g, uint32_t prim, int stage)
{
    const gg_prim *p;
    if (prim >= g->nprim) return;
    p = &g->prims[prim];
    if (stage == 0) {
        GG_PREFETCH(p);
        return;
    }
    if (p->kind == GG_SHAPE_TRIANGLE) {
        const gg_tri *t = &g->tris[p->data];
        if (stage == 1)
            prefetch_span(t, sizeof *t);
        else if (stage == 2 && t->ni != GG_TRI_FLAT)
            prefetch_span(&g->tnrm[3 * (size_t)t->ni], 3 * sizeof *g->tnrm);
    } else if (p->kind == GG_SHAPE_MESH) {
        const gg_gmesh *m = &g->gmeshes[p->data];
        const uint32_t *t = m->idx + 3 * (size_t)(prim - m->pfirst);
        int v;
        if (stage == 1) {
            prefetch_span(t, 3 * sizeof *t);
            return;
        }
        for (v = 0; v < 3; v++) {
            GG_PREFETCH(&m->pos[t[v]]);
            if (m->nrm) GG_PREFETCH(&m->nrm[t[v]]);
        }
    }
}

void gg_geom_set_tag(gg_geom *g, size_t first, size_t n, int32_t tag)
{
    size_t i;
    for (i = first; i < g->nprim && i - first < n; i++) g->prims[i].tag = tag;
}

int gg_geom_prim_info(const gg_geom *g, uint32_t prim, gg_prim_info *out)
{
    const gg_prim *p;
    if (prim >= g->nprim) return 0;
    p = &g->prims[prim];
    out->obj = p->obj, out->tag = p->tag;
    out->kind = p->kind == GG_SHAPE_MESH ? GG_SHAPE_TRIANGLE : p->kind;
    return 1;
}

int gg_geom_prim_kind(const gg_geom *g, uint32_t prim)
{
    if (prim >= g->nprim) return -1;
    return g->prims[prim].kind == GG_SHAPE_MESH ? GG_SHAPE_TRIANGLE : g->prims[prim].kind;
}

/* ---- build ---- */

/* One BVH element per primitive, or one per triangle of a split polygon. */
typedef struct elem {
    uint32_t prim, kind, data, sub;
} elem;

static size_t count_elems(const gg_geom *g)
{
    size_t n = 0, i;
    for (i = 0; i < g->nprim; i++) {
        const gg_prim *p = &g->prims[i];
        if (p->kind == GG_SHAPE_POLYGON && g->polys[p->data].npiece)
            n += g->polys[p->data].npiece;
        else if (p->kind == GG_SHAPE_CONE)
            n += gg_cone_slices(&g->cones[p->data]);
        else
            n++;
    }
    return n;
}

static void elem_bounds(const gg_geom *g, const elem *e, double lo[3], double hi[3])
{
    switch (e->kind) {
    case GG_EK_SPHERE:
        gg_sphere_bounds(&g->sphs[e->data], lo, hi);
        break;
    case GG_EK_TRI:
        if (g->prims[e->prim].kind == GG_SHAPE_MESH) {
            gg_ktri k;
            gg_mesh_ktri(g, e->prim, &k);
            gg_tri_bounds(&k, lo, hi);
        } else
            gg_tri_bounds(g->prims[e->prim].kind == GG_SHAPE_POLYGON ? &g->pieces[e->data]
                                                                     : &g->tris[e->data].k,
                          lo, hi);
        break;
    case GG_EK_CONE: {
        gg_kcone k;
        const gg_cone *c = &g->cones[e->data];
        gg_cone_slice(c, e->sub, gg_cone_slices(c), &k);
        gg_cone_bounds(&k, lo, hi);
        break;
    }
    case GG_EK_RECT:
        gg_rect_bounds(&g->rects[e->data], lo, hi);
        break;
    case GG_EK_POLY:
        gg_poly_bounds(g, &g->polys[e->data], lo, hi);
        break;
    default:
        gg_implicit_shape_bounds(g->imps[e->data], lo, hi);
        break;
    }
}

static int fill_elems(const gg_geom *g, elem *el)
{
    size_t i, n = 0;
    for (i = 0; i < g->nprim; i++) {
        const gg_prim *p = &g->prims[i];
        elem e;
        e.prim = (uint32_t)i, e.data = p->data, e.sub = 0;
        switch (p->kind) {
        case GG_SHAPE_SPHERE:
            e.kind = GG_EK_SPHERE;
            break;
        case GG_SHAPE_TRIANGLE:
        case GG_SHAPE_MESH:
            e.kind = GG_EK_TRI;
            break;
        case GG_SHAPE_CONE: {
            uint32_t k, ns = gg_cone_slices(&g->cones[p->data]);
            for (k = 0; k < ns; k++) {
                el[n].prim = (uint32_t)i, el[n].kind = GG_EK_CONE;
                el[n].data = p->data, el[n].sub = k;
                n++;
            }
            continue;
        }
        case GG_SHAPE_RECT:
            e.kind = GG_EK_RECT;
            break;
        case GG_SHAPE_IMPLICIT:
            e.kind = GG_EK_IMPLICIT;
            break;
        default: {
            const gg_poly *pl = &g->polys[p->data];
            uint32_t k;
            if (!pl->npiece) {
                e.kind = GG_EK_POLY;
                break;
            }
            for (k = 0; k < pl->npiece; k++) {
                el[n].prim = (uint32_t)i, el[n].kind = GG_EK_TRI;
                el[n].data = pl->piece_first + k, el[n].sub = pl->piece_first + k;
                n++;
            }
            continue;
        }
        }
        el[n++] = e;
    }
    return (int)n;
}

/* Squared distance from point c to the box [lo, hi]. */
static double box_dist2(const double c[3], const double lo[3], const double hi[3])
{
    double d2 = 0;
    int k;
    for (k = 0; k < 3; k++) {
        double e = c[k] < lo[k] ? lo[k] - c[k] : c[k] > hi[k] ? c[k] - hi[k] : 0;
        d2 += e * e;
    }
    return d2;
}

/* Mark the spheres nothing else comes near (gg_geom_inside_hit).
   The margin m = 2^-30 (|c| + r) is far above the rounding of a hit point
   or of the tests below, and far below any gap worth keeping. Another
   sphere counts by its ball (centre distance), everything else by its
   conservative box. Quadratic: skipped for scenes with many spheres.
   -1 when out of memory: an error, not a quiet fallback, so a scene
   renders the same whatever the allocator did (tests/api/test_nomem.c). */
static int mark_isolated(gg_geom *g, const elem *el, const double (*lo)[3], const double (*hi)[3],
                         size_t n)
{
    size_t i, j;
    if (!g->nsph || (double)g->nsph * (double)n > 4e6) return 0;
    g->iso = gg_mem_calloc(g->alloc, g->nprim + 1, sizeof *g->iso);
    g->iso_margin = gg_mem_calloc(g->alloc, g->nprim + 1, sizeof *g->iso_margin);
    if (!g->iso || !g->iso_margin) return -1; /* free_built frees them */
    for (i = 0; i < n; i++) {
        const gg_sph *a;
        double c[3], m, R;
        int ok = 1;
        if (el[i].kind != GG_EK_SPHERE) continue;
        a = &g->sphs[el[i].data];
        c[0] = a->c.x, c[1] = a->c.y, c[2] = a->c.z;
        m = 0x1p-30 * (fabs(c[0]) + fabs(c[1]) + fabs(c[2]) + a->r);
        R = a->r + m;
        if (!(R < 1e150) || !(fabs(c[0]) + fabs(c[1]) + fabs(c[2]) < 1e150)) continue;
        for (j = 0; j < n && ok; j++) {
            if (j == i) continue;
            if (el[j].kind == GG_EK_SPHERE) {
                const gg_sph *b = &g->sphs[el[j].data];
                ggVec3 dc = v3sub(b->c, a->c);
                double s = R + b->r + m;
                ok = v3dot(dc, dc) > s * s;
            } else
                ok = box_dist2(c, lo[j], hi[j]) > R * R * (1 + 0x1p-40);
        }
        if (ok) g->iso[el[i].prim] = 1, g->iso_margin[el[i].prim] = m;
    }
    return 0;
}

/* The sphere test of gg_geom_inside_hit in float (GG_ISECT_FLOAT), out of
   line: the double path keeps its ray state in registers. */
static GG_NOINLINE int inside_float(const gg_ksph *k, const gg_rayq *q, double *t)
{
    gg_rpre r;
    return gg_rpre_init(&r, q) && gg_sphere_kernel_f(k, &r, gg_next_down(q->tmax), t);
}

GG_NO_SLP int gg_geom_inside_hit(const gg_geom *g, const gg_rayq *q, unsigned skip, gg_hit *hit)
{
    const uint32_t prim = q->inside;
    const gg_sph *sp;
    gg_ksph k;
    gg_rpre r;
    ggVec3 f;
    double t, lim;
    if (!g->iso || prim >= g->nprim || !g->iso[prim] || q->ignore_prim == prim ||
        (skip & g->pflags[prim]) || !(q->tmin >= 0) || !(q->tmax > q->tmin))
        return -1;
    sp = &g->sphs[g->prims[prim].data];
    /* Origin in the ball grown by half the margin (the rounding of this
       test is far below the other half). */
    f = v3sub(q->o, sp->c);
    lim = sp->r + 0.5 * g->iso_margin[prim];
    if (!(v3dot(f, f) <= lim * lim)) return -1;
    k.c[0] = sp->c.x, k.c[1] = sp->c.y, k.c[2] = sp->c.z;
    k.r2 = sp->r * sp->r;
    if (GG_UNLIKELY(q->opt->isect == GG_ISECT_FLOAT)) {
        if (!inside_float(&k, q, &t)) return -1;
    } else if (!gg_rpre_fill(&r, q) || !gg_sphere_kernel(&k, &r, gg_next_down(q->tmax), &t))
        return -1;
    hit->t = t;
    hit->prim = prim;
    hit->sub = 0;
    hit->b1 = hit->b2 = 0;
    return 1;
}

typedef struct verts_ud {
    const gg_geom *g;
    const elem *el;
} verts_ud;

/* gg_bvh_verts: the vertices of triangle element i. */
static void elem_verts(const void *ud, uint32_t i, double v[3][3])
{
    const verts_ud *u = ud;
    const elem *e = &u->el[i];
    gg_ktri k;
    if (u->g->prims[e->prim].kind == GG_SHAPE_MESH)
        gg_mesh_ktri(u->g, e->prim, &k);
    else
        k = u->g->prims[e->prim].kind == GG_SHAPE_POLYGON ? u->g->pieces[e->data]
                                                          : u->g->tris[e->data].k;
    memcpy(v, k.v, sizeof k.v);
}

/* Element e's intersection record, appended to its kind's array (cnt:
   the records so far of spheres, triangles, cone slices, rectangles);
   returns its index there (other kinds index their own arrays). */
static uint32_t add_record(gg_geom *g, const elem *e, size_t cnt[4])
{
    switch (e->kind) {
    case GG_EK_SPHERE: {
        const gg_sph *sp = &g->sphs[e->data];
        gg_ksph *k = &g->lsph[cnt[0]];
        k->c[0] = sp->c.x, k->c[1] = sp->c.y, k->c[2] = sp->c.z;
        k->r2 = sp->r * sp->r;
        return (uint32_t)cnt[0]++;
    }
    case GG_EK_TRI:
        if (g->prims[e->prim].kind == GG_SHAPE_MESH)
            gg_mesh_ktri(g, e->prim, &g->ltri[cnt[1]]);
        else
            g->ltri[cnt[1]] = g->prims[e->prim].kind == GG_SHAPE_POLYGON ? g->pieces[e->data]
                                                                         : g->tris[e->data].k;
        return (uint32_t)cnt[1]++;
    case GG_EK_CONE: {
        const gg_cone *c = &g->cones[e->data];
        gg_cone_slice(c, e->sub, gg_cone_slices(c), &g->lcone[cnt[2]]);
        return (uint32_t)cnt[2]++;
    }
    case GG_EK_RECT:
        g->lrect[cnt[3]] = g->rects[e->data].k;
        return (uint32_t)cnt[3]++;
    default:
        return e->data;
    }
}

void gg_geom_set_progress(gg_geom *g, gg_progress *p)
{
    g->prog = p;
}

int gg_geom_build(gg_geom *g, ggError *err)
{
    double t0 = gg_time_now();
    size_t n = count_elems(g), i, cnt[4] = {0, 0, 0, 0}, nref = 0;
    elem *el = NULL;
    double(*lo)[3] = NULL, (*hi)[3] = NULL;
    uint32_t *order = NULL, *kidx = NULL;
    verts_ud vu;
    uint8_t *tri = NULL;
    int rc = GG_ERROR_NOMEM, k;
    gg_progress *prog = g->prog;

    g->prog = NULL; /* this build's only */
    free_built(g);
    if (n >= GG_MAX_ELEMS)
        return gg_error_set(err, GG_ERROR_LIMIT, "geometry: %zu elements exceed the limit %u", n,
                            (unsigned)GG_MAX_ELEMS);
    el = gg_mem_calloc(g->alloc, n + 1, sizeof *el);
    lo = gg_mem_calloc(g->alloc, n + 1, sizeof *lo);
    hi = gg_mem_calloc(g->alloc, n + 1, sizeof *hi);
    kidx = gg_mem_alloc(g->alloc, (n + 1) * sizeof *kidx);
    tri = gg_mem_calloc(g->alloc, n + 1, sizeof *tri);
    g->lsph = gg_mem_calloc(g->alloc, g->nsph + 1, sizeof *g->lsph);
    g->ltri = gg_mem_calloc(g->alloc, g->ntri + g->npieces + g->nmtri + 1, sizeof *g->ltri);
    g->lcone = gg_mem_calloc(g->alloc, g->ncone * 8 + 1, sizeof *g->lcone);
    g->lrect = gg_mem_calloc(g->alloc, g->nrect + 1, sizeof *g->lrect);
    if (!el || !lo || !hi || !kidx || !tri || !g->lsph || !g->ltri || !g->lcone || !g->lrect)
        goto fail;
    fill_elems(g, el);
    g->lo = v3(INFINITY, INFINITY, INFINITY);
    g->hi = v3(-INFINITY, -INFINITY, -INFINITY);
    for (i = 0; i < n; i++) {
        elem_bounds(g, &el[i], lo[i], hi[i]);
        tri[i] = el[i].kind == GG_EK_TRI;
        g->lo = v3min(g->lo, v3(lo[i][0], lo[i][1], lo[i][2]));
        g->hi = v3max(g->hi, v3(hi[i][0], hi[i][1], hi[i][2]));
    }
    if (mark_isolated(g, el, (const double(*)[3])lo, (const double(*)[3])hi, n)) goto fail;
    vu.g = g, vu.el = el;
    k = gg_bvh_build(g, (const double(*)[3])lo, (const double(*)[3])hi, tri, elem_verts, &vu, n,
                     prog, &order, &nref);
    if (k) {
        if (k == -2) rc = GG_ERROR_CANCELLED;
        goto fail;
    }
    g->slots = gg_mem_calloc(g->alloc, nref + 1, sizeof *g->slots);
    if (!g->slots) goto fail;

    /* Copy the intersection records in leaf order; an element in more
       than one leaf (a triangle clipped by a spatial split) keeps one
       record, which its slots share. */
    for (i = 0; i < n; i++) kidx[i] = UINT32_MAX;
    for (i = 0; i < nref; i++) {
        const elem *e = &el[order[i]];
        gg_slot *s = &g->slots[i];
        uint32_t idx;
        s->prim = e->prim;
        s->sub = e->sub;
        if (kidx[order[i]] != UINT32_MAX) {
            s->ki = e->kind << GG_EK_SHIFT | kidx[order[i]];
            continue;
        }
        idx = add_record(g, e, cnt);
        s->ki = e->kind << GG_EK_SHIFT | idx;
        kidx[order[i]] = idx;
    }
    g->nslots = nref;
    g->clipped = nref > n;
    g->nlcone = cnt[2];
    if (gg_bvh_tri_leaves(g) || gg_bvh_wide(g)) goto fail;
    if (prog && gg_progress_to(prog, 1, 1)) {
        rc = GG_ERROR_CANCELLED;
        goto fail;
    }
    g->built = 1;
    rc = GG_OK;
fail:
    gg_mem_free(g->alloc, el);
    gg_mem_free(g->alloc, lo);
    gg_mem_free(g->alloc, hi);
    gg_mem_free(g->alloc, order);
    gg_mem_free(g->alloc, kidx);
    gg_mem_free(g->alloc, tri);
    if (rc != GG_OK) {
        free_built(g);
        return gg_error_set(err, rc,
                            rc == GG_ERROR_CANCELLED ? "building the BVH: cancelled"
                                                     : "geometry: out of memory building the BVH");
    }
    g->build_seconds = gg_time_now() - t0;
    return GG_OK;
}

void gg_geom_bounds(const gg_geom *g, ggVec3 *lo, ggVec3 *hi)
{
    if (g->built && g->nslots) {
        *lo = g->lo;
        *hi = g->hi;
    } else {
        *lo = v3(0, 0, 0);
        *hi = v3(0, 0, 0);
    }
}

/* ---- queries ---- */

/* The caller has usually just written *q field by field: read it one
   double at a time (GG_NO_SLP, compiler.h). */
GG_NO_SLP int gg_rpre_init(gg_rpre *r, const gg_rayq *q)
{
    return gg_rpre_fill(r, q);
}

int gg_geom_intersect_brute(const gg_geom *g, const gg_rayq *q, gg_hit *hit)
{
    gg_rpre r;
    gg_hit best;
    if (!g->built || !g->nslots || !gg_rpre_init(&r, q) || !(q->tmax > q->tmin)) return 0;
    best.t = gg_next_down(q->tmax);
    best.prim = UINT32_MAX, best.sub = 0, best.b1 = best.b2 = 0;
    if (!(q->opt->isect == GG_ISECT_FLOAT
              ? gg_leaf_closest_p(g, &r, 0, (uint32_t)g->nslots, &best, 1)
              : gg_leaf_closest(g, &r, 0, (uint32_t)g->nslots, &best)))
        return 0;
    *hit = best;
    return 1;
}

/* Whether hits on primitive p came from a single-precision kernel under
   GG_ISECT_FLOAT: spheres, triangles and the triangles a polygon is split
   into. */
static int float_kind(const gg_geom *g, const gg_prim *p)
{
    return p->kind == GG_SHAPE_SPHERE || p->kind == GG_SHAPE_TRIANGLE || p->kind == GG_SHAPE_MESH ||
           (p->kind == GG_SHAPE_POLYGON && g->polys[p->data].npiece > 0);
}

/* The float kernels' roundings are 2^29 times larger than double's
   (2^-24 against 2^-53 of the same magnitudes): so is the bound, or the
   rays leaving the hit find the surface again (docs/accuracy.md). */
#define GG_FLOAT_PERR_SCALE 0x1p29

static const ggVec3 *tri_normals(const gg_geom *g, const gg_tri *t)
{
    return t->ni == GG_TRI_FLAT ? NULL : &g->tnrm[3 * (size_t)t->ni];
}

GG_INLINE void surface(const gg_geom *g, const gg_rayq *q, const gg_hit *hit, gg_surf *s,
                       unsigned what)
{
    const gg_prim *p = &g->prims[hit->prim];
    switch (p->kind) {
    case GG_SHAPE_SPHERE:
        gg_sphere_surface(&g->sphs[p->data], q, hit, s, what);
        break;
    case GG_SHAPE_TRIANGLE:
        gg_tri_surface(&g->tris[p->data], tri_normals(g, &g->tris[p->data]), q, hit, s, what);
        break;
    case GG_SHAPE_POLYGON:
        gg_poly_surface(g, &g->polys[p->data], q, hit, s, what);
        break;
    case GG_SHAPE_CONE:
        gg_cone_surface(&g->cones[p->data], q, hit, s, what);
        break;
    case GG_SHAPE_RECT:
        gg_rect_surface(&g->rects[p->data], q, hit, s);
        break;
    case GG_SHAPE_MESH:
        gg_mesh_surface(g, hit->prim, q, hit, s, what);
        break;
    default:
        gg_implicit_shape_surface(g->imps[p->data], q, hit, s);
        break;
    }
}

static GG_NOINLINE void surface_float(const gg_geom *g, const gg_rayq *q, const gg_hit *hit,
                                      gg_surf *s, unsigned what)
{
    surface(g, q, hit, s, what);
    if (float_kind(g, &g->prims[hit->prim])) s->perr *= GG_FLOAT_PERR_SCALE;
}

void gg_geom_surface(const gg_geom *g, const gg_rayq *q, const gg_hit *hit, gg_surf *s,
                     unsigned what)
{
    if (GG_UNLIKELY(q->opt->isect == GG_ISECT_FLOAT))
        surface_float(g, q, hit, s, what);
    else
        surface(g, q, hit, s, what);
}
