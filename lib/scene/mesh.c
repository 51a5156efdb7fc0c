/* SPDX-License-Identifier: MIT */
/*
** mesh.c -- triangle meshes in a scene: placing what a reader (or
** ggSceneAddMesh) hands over, splitting it into one object per material,
** and describing it afterwards in the file's terms (mesh.h).
*/
#include "scene.h"

#include "vec.h"

#include <math.h>
#include <string.h>

GG_API void ggMeshOptionsDefault(ggMeshOptions *o)
{
    if (!o) return;
    memset(o, 0, sizeof *o);
    o->transform[0] = o->transform[5] = o->transform[10] = 1;
    o->normals = GG_NORMALS_AUTO;
    o->crease_deg = 60;
    o->material = -1;
    o->override_materials = false;
    o->format = GG_MESH_FORMAT_AUTO;
}

static void free_names(const ggAllocator *a, char **names, size_t n)
{
    size_t i;
    if (!names) return;
    for (i = 0; i < n; i++) gg_mem_free(a, names[i]);
    gg_mem_free(a, names);
}

void gg_mesh_free(const ggAllocator *a, gg_mesh *m)
{
    gg_mem_free(a, m->name);
    gg_mem_free(a, m->pos);
    gg_mem_free(a, m->nrm);
    gg_mem_free(a, m->uv);
    gg_mem_free(a, m->idx);
    gg_mem_free(a, m->tface);
    gg_mem_free(a, m->fline);
    gg_mem_free(a, m->fgroup);
    gg_mem_free(a, m->fmtl);
    free_names(a, m->groups, m->ngroups);
    free_names(a, m->mtlnames, m->nmtlnames);
    free_names(a, m->libs, m->nlibs);
    gg_mem_free(a, m->warning);
    memset(m, 0, sizeof *m);
}

void gg_mesh_build_free(const ggAllocator *a, gg_mesh_build *b)
{
    gg_mesh_free(a, &b->m);
    gg_mem_free(a, b->tmat);
    gg_mem_free(a, b->tsmooth);
    gg_mem_free(a, b->vnrm);
    memset(b, 0, sizeof *b);
}

/* ---- meshes by file ----
   ggSceneLoadMesh and the NFF `mesh` line ask, for every file, whether
   the scene read it before (lib/load/mesh_load.c): a search of the
   meshes made a scene of 80,000 `mesh "tri.obj"` lines take 185 s. */

static size_t file_hash(uint64_t dev, uint64_t ino, size_t cap)
{
    uint64_t h = (ino ^ (dev * 0x9e3779b97f4a7c15u)) * 0xff51afd7ed558ccdu;
    return (size_t)(h ^ (h >> 32)) & (cap - 1);
}

const gg_mesh *gg_scene_mesh_by_file(const ggScene *s, uint64_t dev, uint64_t ino)
{
    size_t i;
    if (!s->cap_mesh_files) return NULL;
    for (i = file_hash(dev, ino, s->cap_mesh_files); s->mesh_files[i];
         i = (i + 1) & (s->cap_mesh_files - 1)) {
        const gg_mesh *m = &s->meshes[s->mesh_files[i] - 1];
        if (m->file_dev == dev && m->file_ino == ino) return m;
    }
    return NULL;
}

static void index_file(ggScene *s, size_t mi)
{
    const gg_mesh *m = &s->meshes[mi];
    size_t i = file_hash(m->file_dev, m->file_ino, s->cap_mesh_files);
    while (s->mesh_files[i]) i = (i + 1) & (s->cap_mesh_files - 1);
    s->mesh_files[i] = (uint32_t)(mi + 1);
}

/* The index rebuilt from the meshes, into a table of cap entries. */
static void reindex_files(ggScene *s)
{
    size_t i;
    memset(s->mesh_files, 0, s->cap_mesh_files * sizeof *s->mesh_files);
    for (i = 0; i < s->nmeshes; i++)
        if (s->meshes[i].has_file && !s->meshes[i].repeat) index_file(s, i);
}

/* Room in the index for one more file (at most half full). */
static int reserve_file(ggScene *s)
{
    size_t cap = s->cap_mesh_files ? s->cap_mesh_files : 16;
    uint32_t *t;
    while (2 * (s->nmeshes + 1) > cap) cap *= 2;
    if (cap == s->cap_mesh_files) return GG_OK;
    if (!(t = gg_mem_calloc(s->alloc, cap, sizeof *t))) return GG_ERROR_NOMEM;
    gg_mem_free(s->alloc, s->mesh_files);
    s->mesh_files = t, s->cap_mesh_files = cap;
    reindex_files(s);
    return GG_OK;
}

static uint64_t names_bytes(char *const *names, size_t n)
{
    uint64_t b = 0;
    size_t i;
    for (i = 0; i < n; i++) b += sizeof *names + strlen(names[i]) + 1;
    return b;
}

uint64_t gg_mesh_repeat_cost(const gg_mesh *m)
{
    const uint64_t names =
        names_bytes(m->groups, m->ngroups) + names_bytes(m->mtlnames, m->nmtlnames);
    return (uint64_t)m->ntri + GG_MESH_REPEAT_RECORD + names / 256;
}

void gg_scene_drop_meshes(ggScene *s, size_t n)
{
    bool files = false;
    while (s->nmeshes > n) {
        gg_mesh *m = &s->meshes[--s->nmeshes];
        if (m->repeat) s->mesh_again -= gg_mesh_repeat_cost(m);
        files |= m->has_file && !m->repeat;
        gg_mesh_free(s->alloc, m);
    }
    if (files) reindex_files(s);
}

/* ---- placing ---- */

static int fail(ggError *err, const gg_mesh *m, int code, const char *what)
{
    return gg_error_set(err, code, "%s: %s", m->name && m->name[0] ? m->name : "mesh", what);
}

/* The 3x3 part of T with each row scaled by the power of two 2^-p[i]
   that brings its largest entry into [0.5, 1) (exact); 0 if a row is all
   zero. */
static int scaled_rows(const double *t, double s[9], int p[3])
{
    int i, j;
    for (i = 0; i < 3; i++) {
        double m = fmax(fmax(fabs(t[4 * i]), fabs(t[4 * i + 1])), fabs(t[4 * i + 2]));
        if (!(m > 0)) return 0;
        (void)frexp(m, &p[i]);
        for (j = 0; j < 3; j++) s[3 * i + j] = ldexp(t[4 * i + j], -p[i]);
    }
    return 1;
}

/* The inverse transpose of the 3x3 part M, as the inverse transpose X of
   D M (D = diag 2^-p, the rows scaled to about 1) and the shifts sh: M's
   is D X, so a normal's component i is X's row i times 2^sh[i] (the
   shifts are D's relative to its largest, all <= 0, for a direction the
   normalisation then scales the same) -- the same bits as computing on M,
   without its determinant underflowing: diag(1e-110, 1e-110, 1e-110) and
   diag(1, 2^-500, 2^-600) are not singular. 0 if M is singular. */
static int inverse_transpose(const double *t, double it[9], int sh[3])
{
    double s[9], a, b, c, d, e, f, g, h, k, c00, c01, c02, det;
    int p[3], least, i;
    if (!scaled_rows(t, s, p)) return 0;
    least = p[0] < p[1] ? p[0] : p[1];
    least = least < p[2] ? least : p[2];
    for (i = 0; i < 3; i++) sh[i] = least - p[i];
    a = s[0], b = s[1], c = s[2], d = s[3], e = s[4], f = s[5], g = s[6], h = s[7], k = s[8];
    c00 = e * k - f * h, c01 = f * g - d * k, c02 = d * h - e * g;
    det = a * c00 + b * c01 + c * c02;
    if (!(det != 0) || !isfinite(det)) return 0;
    /* inverse transpose = cofactor matrix / det */
    it[0] = c00 / det, it[1] = c01 / det, it[2] = c02 / det;
    it[3] = (c * h - b * k) / det, it[4] = (a * k - c * g) / det, it[5] = (b * g - a * h) / det;
    it[6] = (b * f - c * e) / det, it[7] = (c * d - a * f) / det, it[8] = (a * e - b * d) / det;
    return det > 0 ? 1 : -1;
}

/* Unit vector, computed so that tiny or huge inputs do not underflow or
   overflow on the way; zero (and anything not finite) gives zero. */
static ggVec3 unit(ggVec3 n)
{
    double m = v3maxabs(n), l;
    if (!(m > 0) || !isfinite(m)) return v3(0, 0, 0);
    n = v3scale(n, 1 / m);
    l = v3len(n);
    return v3scale(n, 1 / l);
}

static bool is_identity(const double *t)
{
    static const double id[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    return memcmp(t, id, sizeof id) == 0;
}

static int place(gg_mesh_build *b, const ggMeshOptions *o, ggError *err)
{
    gg_mesh *m = &b->m;
    const double *t = o->transform;
    double it[9];
    size_t i;
    int side, sh[3];
    for (i = 0; i < 12; i++)
        if (!isfinite(t[i])) return fail(err, m, GG_ERROR_INVALID, "the transform is not finite");
    side = inverse_transpose(t, it, sh);
    if (!side) return fail(err, m, GG_ERROR_INVALID, "the transform is singular");
    for (i = 0; i < m->nverts; i++) {
        ggVec3 p = m->pos[i];
        if (!is_identity(t))
            p = v3(t[0] * p.x + t[1] * p.y + t[2] * p.z + t[3],
                   t[4] * p.x + t[5] * p.y + t[6] * p.z + t[7],
                   t[8] * p.x + t[9] * p.y + t[10] * p.z + t[11]);
        if (!v3finite(p))
            return fail(err, m, GG_ERROR_INVALID, "a vertex is not finite (after the transform)");
        if (!gg_scene_coord_ok(p))
            return fail(err, m, GG_ERROR_INVALID,
                        "a vertex is over 1e64 in magnitude (GG_COORD_MAX)");
        m->pos[i] = p;
        if (m->nrm) {
            ggVec3 n = m->nrm[i];
            m->nrm[i] = unit(v3(ldexp(it[0] * n.x + it[1] * n.y + it[2] * n.z, sh[0]),
                                ldexp(it[3] * n.x + it[4] * n.y + it[5] * n.z, sh[1]),
                                ldexp(it[6] * n.x + it[7] * n.y + it[8] * n.z, sh[2])));
        }
    }
    /* A mirroring transform turns the winding inside out: turn it back, so
       that the front stays the side the file's triangles face. */
    if (side < 0)
        for (i = 0; i < m->ntri; i++) {
            uint32_t x = m->idx[3 * i + 1];
            m->idx[3 * i + 1] = m->idx[3 * i + 2];
            m->idx[3 * i + 2] = x;
        }
    return GG_OK;
}

/* The test gg_geom_add_triangle applies: edge cross product nonzero and
   finite. */
static bool degenerate(const gg_mesh *m, size_t t)
{
    const uint32_t *v = m->idx + 3 * t;
    ggVec3 a = m->pos[v[0]];
    ggVec3 ng = v3cross(v3sub(m->pos[v[1]], a), v3sub(m->pos[v[2]], a));
    return !(v3maxabs(ng) > 0) || !v3finite(ng);
}

static void drop_degenerate(gg_mesh_build *b)
{
    gg_mesh *m = &b->m;
    size_t i, n = 0;
    for (i = 0; i < m->ntri; i++) {
        if (degenerate(m, i)) continue;
        if (n != i) {
            memcpy(m->idx + 3 * n, m->idx + 3 * i, 3 * sizeof *m->idx);
            if (m->tface) m->tface[n] = m->tface[i];
            if (b->tmat) b->tmat[n] = b->tmat[i];
            if (b->tsmooth) b->tsmooth[n] = b->tsmooth[i];
        }
        n++;
    }
    m->skipped += m->ntri - n;
    m->ntri = n;
}

static int normals(const ggAllocator *a, gg_mesh_build *b, const ggMeshOptions *o)
{
    gg_mesh *m = &b->m;
    if (o->normals != GG_NORMALS_AUTO || !m->nrm) {
        gg_mem_free(a, m->nrm);
        gg_mem_free(a, b->vnrm);
        m->nrm = NULL, b->vnrm = NULL;
    }
    m->file_normals = m->nrm != NULL;
    if (o->normals == GG_NORMALS_FLAT || (m->nrm && !b->vnrm)) return GG_OK;
    return gg_mesh_compute_normals(a, b, o->crease_deg);
}

/* ---- objects by material ---- */

/* Reorder the triangles so that each part's are together (a counting sort
   by part, stable: file order within a part); count[k] is part k's size. */
static int group_by_part(const ggAllocator *a, gg_mesh *m, const int *part, size_t nparts,
                         const size_t *count)
{
    uint32_t *idx = gg_mem_calloc(a, 3 * m->ntri, sizeof *idx);
    uint32_t *tf = gg_mem_calloc(a, m->ntri, sizeof *tf);
    size_t *at = gg_mem_calloc(a, nparts, sizeof *at), i, k;
    if (!idx || !tf || !at) {
        gg_mem_free(a, idx);
        gg_mem_free(a, tf);
        gg_mem_free(a, at);
        return GG_ERROR_NOMEM;
    }
    for (k = 1; k < nparts; k++) at[k] = at[k - 1] + count[k - 1];
    for (i = 0; i < m->ntri; i++) {
        size_t j = at[part[i]]++;
        memcpy(idx + 3 * j, m->idx + 3 * i, 3 * sizeof *idx);
        tf[j] = m->tface ? m->tface[i] : (uint32_t)i;
    }
    gg_mem_free(a, at);
    gg_mem_free(a, m->idx);
    gg_mem_free(a, m->tface);
    m->idx = idx, m->tface = tf;
    return GG_OK;
}

/* The scene material of each triangle, and the parts (distinct materials
   in order of first use). part[] receives each triangle's part; mats[k]
   and count[k] each part's material and triangle count. */
static int assign_parts(ggScene *s, gg_mesh_build *b, const ggMeshOptions *o, int *part, int **mats,
                        size_t **count, size_t *nparts)
{
    const gg_mesh *m = &b->m;
    int *slot = gg_mem_calloc(s->alloc, s->nmaterials + 1, sizeof *slot), fallback = o->material;
    size_t i, n = 0;
    if (!slot) return GG_ERROR_NOMEM;
    *mats = NULL, *count = NULL;
    for (i = 0; i < m->ntri; i++) {
        int mat = b->tmat && !o->override_materials ? b->tmat[i] : -1;
        if (mat < 0) {
            if (fallback < 0) {
                ggMaterial d = ggMaterialDefault();
                int *ns = gg_mem_realloc(s->alloc, slot, (s->nmaterials + 2) * sizeof *slot);
                if (!ns || (fallback = ggSceneAddMaterial(s, &d)) < 0) {
                    gg_mem_free(s->alloc, ns ? ns : slot);
                    return GG_ERROR_NOMEM;
                }
                slot = ns, slot[fallback] = 0;
            }
            mat = fallback;
        }
        if (!slot[mat]) {
            if (gg_mem_grow(s->alloc, (void **)mats, &n, n + 1, sizeof **mats)) break;
            slot[mat] = (int)++*nparts;
            (*mats)[*nparts - 1] = mat;
        }
        part[i] = slot[mat] - 1;
    }
    gg_mem_free(s->alloc, slot);
    if (i < m->ntri || !(*count = gg_mem_calloc(s->alloc, *nparts + 1, sizeof **count)))
        return GG_ERROR_NOMEM;
    for (i = 0; i < m->ntri; i++) (*count)[part[i]]++;
    return GG_OK;
}

/* One object per part; the triangles regrouped when there is more than
   one. */
static int make_objects(ggScene *s, gg_mesh_build *b, const ggMeshOptions *o, int line)
{
    gg_mesh *m = &b->m;
    int *part = gg_mem_calloc(s->alloc, m->ntri + 1, sizeof *part), *mats = NULL, rc;
    size_t *count = NULL, nparts = 0, k, at = 0;
    if (!part) return GG_ERROR_NOMEM;
    rc = assign_parts(s, b, o, part, &mats, &count, &nparts);
    if (rc == GG_OK && nparts > 1) rc = group_by_part(s->alloc, m, part, nparts, count);
    m->first_object = (int)s->nobjects;
    for (k = 0; rc == GG_OK && k < nparts; k++) {
        gg_object ob;
        int id;
        memset(&ob, 0, sizeof ob);
        ob.kind = GG_SHAPE_MESH, ob.material = mats[k], ob.line = line;
        ob.mesh = (int)s->nmeshes, ob.tri_first = at, ob.ntri = count[k];
        at += count[k];
        id = gg_scene_add_object(s, &ob);
        if (id < 0) rc = -id;
    }
    m->nobjects = (int)nparts;
    gg_mem_free(s->alloc, part);
    gg_mem_free(s->alloc, mats);
    gg_mem_free(s->alloc, count);
    return rc;
}

/* After regrouping: drop the triangle-to-face map where it is the
   identity (all-triangle files in one material). */
static void trim(const ggAllocator *a, gg_mesh *m)
{
    size_t i;
    if (!m->tface) return;
    for (i = 0; i < m->ntri; i++)
        if (m->tface[i] != i) return;
    gg_mem_free(a, m->tface);
    m->tface = NULL;
}

static void bounds(gg_mesh *m)
{
    size_t i;
    m->lo = v3(INFINITY, INFINITY, INFINITY), m->hi = v3(-INFINITY, -INFINITY, -INFINITY);
    for (i = 0; i < 3 * m->ntri; i++) {
        m->lo = v3min(m->lo, m->pos[m->idx[i]]);
        m->hi = v3max(m->hi, m->pos[m->idx[i]]);
    }
}

static int check(const ggScene *s, const gg_mesh_build *b, const ggMeshOptions *o, ggError *err)
{
    const gg_mesh *m = &b->m;
    size_t i;
    if (m->ntri >= GG_MESH_MAX || m->nverts >= GG_MESH_MAX)
        return fail(err, m, GG_ERROR_LIMIT, "more than 2^28 triangles or vertices");
    if (o->material >= 0 && (size_t)o->material >= s->nmaterials)
        return fail(err, m, GG_ERROR_INVALID, "the default material does not exist");
    if (!(o->crease_deg >= 0 && o->crease_deg <= 180))
        return fail(err, m, GG_ERROR_INVALID, "the crease angle must be in [0, 180] degrees");
    if (o->normals < GG_NORMALS_AUTO || o->normals > GG_NORMALS_FLAT)
        return fail(err, m, GG_ERROR_INVALID, "unknown normals mode");
    for (i = 0; i < 3 * m->ntri; i++)
        if (m->idx[i] >= m->nverts)
            return fail(err, m, GG_ERROR_INVALID, "an index is out of range");
    for (i = 0; b->tmat && i < m->ntri; i++)
        if (b->tmat[i] >= 0 && (size_t)b->tmat[i] >= s->nmaterials)
            return fail(err, m, GG_ERROR_INVALID, "a triangle's material does not exist");
    for (i = 0; i < m->nverts; i++)
        if (!v3finite(m->pos[i]) || (m->nrm && !v3finite(m->nrm[i])) ||
            (m->uv && (!isfinite(m->uv[2 * i]) || !isfinite(m->uv[2 * i + 1]))))
            return fail(err, m, GG_ERROR_INVALID, "a vertex is not finite");
    return GG_OK;
}

int gg_scene_add_mesh_build(ggScene *s, gg_mesh_build *b, const ggMeshOptions *o, int line,
                            ggError *err)
{
    ggMeshOptions def;
    size_t nobj = s->nobjects, nmat = s->nmaterials;
    int rc;
    if (!o) ggMeshOptionsDefault(&def), o = &def;
    rc = check(s, b, o, err);
    if (rc == GG_OK) rc = place(b, o, err);
    if (rc == GG_OK) {
        drop_degenerate(b);
        if (!b->m.ntri) rc = fail(err, &b->m, GG_ERROR_PARSE, "no face has an area");
    }
    if (rc == GG_OK && (gg_mem_grow(s->alloc, (void **)&s->meshes, &s->cap_meshes, s->nmeshes + 1,
                                    sizeof *s->meshes) ||
                        reserve_file(s) != GG_OK))
        rc = fail(err, &b->m, GG_ERROR_NOMEM, "out of memory");
    if (rc == GG_OK && (rc = normals(s->alloc, b, o)) != GG_OK)
        fail(err, &b->m, rc, "out of memory");
    if (rc == GG_OK && (rc = make_objects(s, b, o, line)) != GG_OK)
        fail(err, &b->m, rc, rc == GG_ERROR_NOMEM ? "out of memory" : "too many objects");
    if (rc != GG_OK) {
        s->nobjects = nobj, s->nmaterials = nmat;
        gg_mesh_build_free(s->alloc, b);
        return -rc;
    }
    trim(s->alloc, &b->m);
    bounds(&b->m);
    s->meshes[s->nmeshes] = b->m;
    memset(&b->m, 0, sizeof b->m);
    gg_mesh_build_free(s->alloc, b);
    if (s->meshes[s->nmeshes].repeat)
        s->mesh_again += gg_mesh_repeat_cost(&s->meshes[s->nmeshes]);
    else if (s->meshes[s->nmeshes].has_file)
        index_file(s, s->nmeshes);
    return (int)s->nmeshes++;
}
