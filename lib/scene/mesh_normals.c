/* SPDX-License-Identifier: MIT */
/*
** mesh_normals.c -- vertex normals for meshes that have none: at each
** corner, the sum of the normals of the faces around the corner's
** position, each weighted by the face's angle at that position (Thurmer
** and Wuthrich, "Computing vertex normals from polygonal facets", JGT
** 1998: the result does not depend on how the faces were triangulated),
** over only those faces whose normal is within the crease angle of the
** corner's own face and, for OBJ, in the same smoothing group.
**
** Faces meet at a position, not at a vertex index: files often repeat a
** position (texture seams, triangle soups), so positions are matched by
** value. A vertex whose corners get different normals is split.
*/
#include "scene.h"

#include "vec.h"

#include <math.h>
#include <string.h>

typedef struct nctx {
    const ggAllocator *a;
    gg_mesh_build *b;
    ggVec3 *fn;          /* unit face normals */
    double *ang;         /* angle at each corner */
    uint32_t *cls;       /* position class of each vertex */
    uint32_t *off, *lst; /* corners of each class: lst[off[c] .. off[c + 1]) */
    uint8_t *done;       /* vertex already holds its computed normal */
    size_t ncls, cap_v;
    double cos_crease;
    double cos_half; /* a little under half the crease angle (all_smooth) */
} nctx;

static ggVec3 unit(ggVec3 n)
{
    double m = v3maxabs(n);
    if (!(m > 0) || !isfinite(m)) return v3(0, 0, 0);
    n = v3scale(n, 1 / m);
    return v3scale(n, 1 / v3len(n));
}

static uint64_t bits(double x)
{
    uint64_t u;
    x += 0.0; /* -0 and +0 are the same place */
    memcpy(&u, &x, 8);
    return u;
}

/* Give vertices at the same position the same class (open addressing on
   the coordinates' bits). */
static int classes(nctx *c)
{
    const gg_mesh *m = &c->b->m;
    size_t cap = 16, i;
    uint32_t *tab;
    uint64_t seed;
    while (cap < 2 * m->nverts) cap *= 2;
    tab = gg_mem_alloc(c->a, cap * sizeof *tab);
    c->cls = gg_mem_alloc(c->a, (m->nverts + 1) * sizeof *c->cls);
    if (!tab || !c->cls) {
        gg_mem_free(c->a, tab);
        return GG_ERROR_NOMEM;
    }
    memset(tab, 0xff, cap * sizeof *tab);
    seed = gg_hash_seed(tab); /* the positions are the file's (core.h) */
    for (i = 0; i < m->nverts; i++) {
        ggVec3 p = m->pos[i];
        uint64_t h =
            gg_hash_word(gg_hash_word(gg_hash_word(seed, bits(p.x)), bits(p.y)), bits(p.z));
        size_t k = (size_t)h & (cap - 1);
        for (;; k = (k + 1) & (cap - 1)) {
            uint32_t v = tab[k];
            if (v == UINT32_MAX) {
                tab[k] = (uint32_t)i;
                c->cls[i] = (uint32_t)c->ncls++;
                break;
            }
            if (bits(m->pos[v].x) == bits(p.x) && bits(m->pos[v].y) == bits(p.y) &&
                bits(m->pos[v].z) == bits(p.z)) {
                c->cls[i] = c->cls[v];
                break;
            }
        }
    }
    gg_mem_free(c->a, tab);
    return GG_OK;
}

/* Face normals, corner angles and the corners of each class. */
static int gather(nctx *c)
{
    const gg_mesh *m = &c->b->m;
    size_t t, i, k;
    c->fn = gg_mem_alloc(c->a, (m->ntri + 1) * sizeof *c->fn);
    c->ang = gg_mem_alloc(c->a, (3 * m->ntri + 1) * sizeof *c->ang);
    c->off = gg_mem_calloc(c->a, c->ncls + 2, sizeof *c->off);
    c->lst = gg_mem_alloc(c->a, (3 * m->ntri + 1) * sizeof *c->lst);
    if (!c->fn || !c->ang || !c->off || !c->lst) return GG_ERROR_NOMEM;
    for (t = 0; t < m->ntri; t++) {
        const uint32_t *v = m->idx + 3 * t;
        c->fn[t] =
            unit(v3cross(v3sub(m->pos[v[1]], m->pos[v[0]]), v3sub(m->pos[v[2]], m->pos[v[0]])));
        for (k = 0; k < 3; k++) {
            ggVec3 p = m->pos[v[k]];
            ggVec3 e1 = v3sub(m->pos[v[(k + 1) % 3]], p), e2 = v3sub(m->pos[v[(k + 2) % 3]], p);
            c->ang[3 * t + k] = atan2(v3len(v3cross(e1, e2)), v3dot(e1, e2));
            c->off[c->cls[v[k]] + 2]++;
        }
    }
    for (i = 2; i < c->ncls + 2; i++) c->off[i] += c->off[i - 1];
    for (i = 0; i < 3 * m->ntri; i++) c->lst[c->off[c->cls[m->idx[i]] + 1]++] = (uint32_t)i;
    return GG_OK;
}

static bool smooth_with(const nctx *c, size_t ti, size_t tj)
{
    const uint32_t *sg = c->b->tsmooth;
    if (ti == tj) return true;
    if (sg && (sg[ti] == 0 || sg[ti] != sg[tj])) return false;
    return v3dot(c->fn[ti], c->fn[tj]) >= c->cos_crease;
}

/* Does every corner of the class smooth with every other? Then one sum
   serves them all -- the same sum, bit for bit, that each would add up
   (same terms, same order). Sufficient, and cheap: all in one smoothing
   group, and every face normal within a little less than half the crease
   angle of their mean (so any two are within the crease angle, rounding
   included). */
static bool all_smooth(const nctx *c, const uint32_t *L, size_t d)
{
    const uint32_t *sg = c->b->tsmooth;
    ggVec3 mean = v3(0, 0, 0);
    size_t j;
    if (sg)
        for (j = 0; j < d; j++)
            if (sg[L[j] / 3] == 0 || sg[L[j] / 3] != sg[L[0] / 3]) return false;
    if (c->cos_crease < -1) return true;
    for (j = 0; j < d; j++) mean = v3add(mean, c->fn[L[j] / 3]);
    mean = unit(mean);
    for (j = 0; j < d; j++)
        if (!(v3dot(mean, c->fn[L[j] / 3]) >= c->cos_half)) return false;
    return true;
}

/* A new vertex: a copy of v0 with normal n. */
static int split(nctx *c, uint32_t v0, ggVec3 n, uint32_t *out)
{
    gg_mesh *m = &c->b->m;
    size_t cap = c->cap_v;
    void *p;
    if (m->nverts >= UINT32_MAX - 1) return GG_ERROR_LIMIT;
    if (m->nverts + 1 > cap) {
        cap = 2 * cap + 16;
        if (!(p = gg_mem_realloc(c->a, m->pos, cap * sizeof *m->pos))) return GG_ERROR_NOMEM;
        m->pos = p;
        if (!(p = gg_mem_realloc(c->a, m->nrm, cap * sizeof *m->nrm))) return GG_ERROR_NOMEM;
        m->nrm = p;
        if (m->uv) {
            if (!(p = gg_mem_realloc(c->a, m->uv, 2 * cap * sizeof *m->uv))) return GG_ERROR_NOMEM;
            m->uv = p;
        }
        if (!(p = gg_mem_realloc(c->a, c->done, cap))) return GG_ERROR_NOMEM;
        c->done = p;
        if (c->b->vnrm) {
            if (!(p = gg_mem_realloc(c->a, c->b->vnrm, cap))) return GG_ERROR_NOMEM;
            c->b->vnrm = p;
        }
        c->cap_v = cap;
    }
    *out = (uint32_t)m->nverts++;
    m->pos[*out] = m->pos[v0], m->nrm[*out] = n, c->done[*out] = 1;
    if (c->b->vnrm) c->b->vnrm[*out] = 0;
    if (m->uv) m->uv[2 * *out] = m->uv[2 * v0], m->uv[2 * *out + 1] = m->uv[2 * v0 + 1];
    return GG_OK;
}

/* The corners of one class: each that needs a normal gets the weighted
   sum over the faces it smooths with (its own face's normal alone past
   GG_MESH_MAX_SMOOTH corners), then a vertex: its own if still free or
   already holding that normal, else one split off it earlier with the
   same normal, else a new copy. */
static int do_class(nctx *c, const uint32_t *L, size_t d)
{
    gg_mesh *m = &c->b->m;
    ggVec3 nb[GG_MESH_MAX_SMOOTH];
    uint32_t orig[GG_MESH_MAX_SMOOTH], out[GG_MESH_MAX_SMOOTH];
    size_t i, j;
    int rc, shared = d <= GG_MESH_MAX_SMOOTH && all_smooth(c, L, d);
    ggVec3 all = v3(0, 0, 0);
    if (shared) {
        for (j = 0; j < d; j++) all = v3madd(all, c->fn[L[j] / 3], c->ang[L[j]]);
        all = unit(all);
    }
    for (i = 0; i < d; i++) {
        uint32_t ci = L[i], v0 = m->idx[ci], w = UINT32_MAX;
        ggVec3 n = c->fn[ci / 3];
        if (d <= GG_MESH_MAX_SMOOTH) orig[i] = out[i] = UINT32_MAX;
        if (c->b->vnrm && c->b->vnrm[v0]) continue; /* the file's normal */
        if (d <= GG_MESH_MAX_SMOOTH) {
            ggVec3 sum = all;
            if (!shared) {
                for (j = 0; j < d; j++)
                    if (smooth_with(c, ci / 3, L[j] / 3))
                        sum = v3madd(sum, c->fn[L[j] / 3], c->ang[L[j]]);
                sum = unit(sum);
            }
            if (v3dot(sum, sum) > 0.5) n = sum; /* else opposite faces cancelled */
            nb[i] = n, orig[i] = v0;
            for (j = 0; j < i && w == UINT32_MAX; j++)
                if (orig[j] == v0 && out[j] != UINT32_MAX && !memcmp(&nb[j], &n, sizeof n))
                    w = out[j];
        }
        if (w == UINT32_MAX && !c->done[v0]) c->done[v0] = 1, m->nrm[v0] = n, w = v0;
        if (w == UINT32_MAX && !memcmp(&m->nrm[v0], &n, sizeof n)) w = v0;
        if (w == UINT32_MAX && (rc = split(c, v0, n, &w)) != GG_OK) return rc;
        m->idx[ci] = w;
        if (d <= GG_MESH_MAX_SMOOTH) out[i] = w;
    }
    return GG_OK;
}

int gg_mesh_compute_normals(const ggAllocator *a, gg_mesh_build *b, double crease_deg)
{
    nctx c;
    gg_mesh *m = &b->m;
    size_t k;
    int rc;
    memset(&c, 0, sizeof c);
    c.a = a, c.b = b, c.cap_v = m->nverts;
    c.cos_crease = crease_deg >= 180 ? -2 : cos(crease_deg * GG_PI / 180);
    c.cos_half = cos(crease_deg * GG_PI / 360 * (1 - 1e-6));
    if (!m->nrm) {
        gg_mem_free(a, b->vnrm);
        b->vnrm = NULL;
        if (!(m->nrm = gg_mem_calloc(a, m->nverts + 1, sizeof *m->nrm))) return GG_ERROR_NOMEM;
    }
    c.done = gg_mem_calloc(a, m->nverts + 1, 1);
    rc = c.done ? classes(&c) : GG_ERROR_NOMEM;
    if (rc == GG_OK) rc = gather(&c);
    for (k = 0; rc == GG_OK && k < c.ncls; k++)
        rc = do_class(&c, c.lst + c.off[k], c.off[k + 1] - c.off[k]);
    gg_mem_free(a, c.fn);
    gg_mem_free(a, c.ang);
    gg_mem_free(a, c.cls);
    gg_mem_free(a, c.off);
    gg_mem_free(a, c.lst);
    gg_mem_free(a, c.done);
    gg_mem_free(a, b->vnrm);
    b->vnrm = NULL;
    return rc;
}
