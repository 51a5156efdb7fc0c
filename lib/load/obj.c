/* SPDX-License-Identifier: MIT */
/*
** obj.c -- the Wavefront OBJ reader: v, vt, vn, f in all its index forms
** (v, v/vt, v//vn, v/vt/vn, negative = relative to the end), o, g,
** usemtl, mtllib, s, line continuations; polygons are split into
** triangles (meshbuild.c). Points, lines, free-form geometry and unknown
** statements are counted as ignored. The subset and its limits are in
** docs/scene-format.md ("Meshes").
**
** A corner of a face is a (position, texture, normal) triple; each
** distinct triple becomes one vertex of the mesh, so that a vertex carries
** one position, one normal and one (u, v).
*/
#include "mesh_int.h"

#include "vec.h"

#include <stdio.h>
#include <string.h>

/* (v, vt + 1, vn + 1) -> vertex, by open addressing. */
typedef struct tuples {
    uint32_t (*key)[3];
    uint32_t *val;
    size_t cap, n;
    uint64_t seed; /* gg_hash_seed of the current table (core.h: why) */
} tuples;

typedef struct objp {
    ggScene *s;
    gg_mb *mb;
    const ggMeshOptions *o;
    gg_lc c;
    const char *dir; /* NULL: read no other file */
    ggVec3 *v, *vn;
    double *vt;
    size_t nv, nvt, nvn, cap_v, cap_vt, cap_vn;
    uint32_t *vmap; /* position-only corners: vertex + 1, 0 = none yet */
    size_t cap_vmap;
    tuples tm;
    uint32_t *corner;
    size_t cap_corner;
    /* o and g names, and each (o, g) pair seen ("oid gid") with its
       label's index in mb->groups (pgroup): a g line costs its own name,
       not the o name's length again */
    gg_names onames, gnames, pairs;
    uint32_t oid, gid, *pgroup;
    size_t cap_pgroup;
    size_t label_bytes, label_max; /* of the pairs' labels, and their limit */
    uint32_t group, mtl, smooth;
    gg_mtl_lib lib;
    int libs; /* MTL files read */
    gg_file_id *libid; /* which files they were: each is read once */
    size_t nlibid, cap_libid;
    size_t ignored;
} objp;

static int nomem(objp *op)
{
    return gg_lc_fail(&op->c, NULL, GG_ERROR_NOMEM, "out of memory");
}

static int too_many(objp *op, const char *what)
{
    return gg_lc_fail(&op->c, NULL, GG_ERROR_LIMIT, "more than %u %s", GG_MESH_MAX, what);
}

static int vertex(objp *op)
{
    double d[3], extra;
    int rc, k;
    if (op->nv >= GG_MESH_MAX) return too_many(op, "vertices");
    for (k = 0; k < 3; k++)
        if ((rc = gg_lc_number(&op->c, &d[k], "a coordinate")) != GG_OK) return rc;
    /* a weight w, or a vertex colour r g b [a]: read and not used */
    for (k = 0; k < 4; k++) {
        gg_lc_blank(&op->c);
        if (gg_lc_eol(&op->c)) break;
        if ((rc = gg_lc_number(&op->c, &extra, "a number")) != GG_OK) return rc;
    }
    if (gg_mem_grow(op->mb->a, (void **)&op->v, &op->cap_v, op->nv + 1, sizeof *op->v))
        return nomem(op);
    op->v[op->nv++] = v3(d[0], d[1], d[2]);
    return gg_lc_end(&op->c);
}

static int texcoord(objp *op)
{
    double d[3] = {0, 0, 0};
    int rc, k;
    if (op->nvt >= GG_MESH_MAX) return too_many(op, "texture coordinates");
    if ((rc = gg_lc_number(&op->c, &d[0], "a texture coordinate")) != GG_OK) return rc;
    for (k = 1; k < 3; k++) {
        gg_lc_blank(&op->c);
        if (gg_lc_eol(&op->c)) break;
        if ((rc = gg_lc_number(&op->c, &d[k], "a texture coordinate")) != GG_OK) return rc;
    }
    if (gg_mem_grow(op->mb->a, (void **)&op->vt, &op->cap_vt, 2 * (op->nvt + 1), sizeof *op->vt))
        return nomem(op);
    /* OBJ's v = 0 is the image's bottom row, ggrt's its top row */
    op->vt[2 * op->nvt] = d[0], op->vt[2 * op->nvt + 1] = 1 - d[1];
    op->nvt++;
    return gg_lc_end(&op->c);
}

static int normal(objp *op)
{
    double d[3];
    int rc, k;
    if (op->nvn >= GG_MESH_MAX) return too_many(op, "normals");
    for (k = 0; k < 3; k++)
        if ((rc = gg_lc_number(&op->c, &d[k], "a normal coordinate")) != GG_OK) return rc;
    if (gg_mem_grow(op->mb->a, (void **)&op->vn, &op->cap_vn, op->nvn + 1, sizeof *op->vn))
        return nomem(op);
    op->vn[op->nvn++] = v3(d[0], d[1], d[2]);
    return gg_lc_end(&op->c);
}

/* Where a field of a face corner ends: a blank, the end of the line, a
   comment or a continuation. An empty field there (`1/ `, `1/` at the
   end of the line) is no index, whatever follows it. */
static bool field_end(const gg_lc *c, const char *p)
{
    return p >= c->end || *p == ' ' || *p == '\t' || *p == '\r' || *p == '\n' || *p == '\f' ||
           *p == '\v' || *p == '#' || *p == '\\';
}

/* A 1-based (or negative, relative) index into `count` items: a whole
   number up to '/' or the field's end. `0x1` once read as index 0, and
   a number beyond the long range was "expected an index". */
static int index_of(objp *op, const char *what, size_t count, long *out)
{
    const char *at = op->c.p, *q = at, *e;
    char b[200];
    if (q < op->c.end && (*q == '+' || *q == '-')) q++;
    for (e = q; e < op->c.end && *e >= '0' && *e <= '9'; e++)
        ;
    if (e == q || (!field_end(&op->c, e) && *e != '/')) {
        /* the callers stand on a character that is no field end */
        for (e = at + 1; !field_end(&op->c, e) && *e != '/'; e++)
            ;
        return gg_lc_fail(&op->c, at, GG_ERROR_PARSE, "expected a %s index, got '%s'", what,
                          gg_lc_show(at, (size_t)(e - at), b, sizeof b));
    }
    op->c.p = e;
    if (!gg_parse_long(at, e, -2147483647L, 2147483647L, out))
        return gg_lc_fail(&op->c, at, GG_ERROR_PARSE,
                          "%s index %s is out of range (%zu defined so far)", what,
                          gg_lc_show(at, (size_t)(e - at), b, sizeof b), count);
    if (*out == 0)
        return gg_lc_fail(&op->c, at, GG_ERROR_PARSE, "%s index 0 (OBJ indices start at 1)", what);
    if (*out > 0 && (size_t)*out <= count) return (*out)--, GG_OK;
    if (*out < 0 && (size_t) - *out <= count) return *out += (long)count, GG_OK;
    return gg_lc_fail(&op->c, at, GG_ERROR_PARSE,
                      "%s index %ld is out of range (%zu defined so far)", what, *out, count);
}

static uint64_t thash(uint64_t seed, const uint32_t k[3])
{
    return gg_hash_word(gg_hash_word(seed, k[0] | (uint64_t)k[1] << 32), k[2]);
}

static int tuples_grow(const ggAllocator *a, tuples *t)
{
    size_t cap = t->cap ? 2 * t->cap : 1024, i, k;
    uint32_t(*key)[3] = gg_mem_calloc(a, cap, sizeof *key);
    uint32_t *val = gg_mem_alloc(a, cap * sizeof *val);
    uint64_t seed = gg_hash_seed(key);
    if (!key || !val) {
        gg_mem_free(a, key);
        gg_mem_free(a, val);
        return -1;
    }
    for (i = 0; i < t->cap; i++) {
        if (!t->key[i][0]) continue;
        for (k = thash(seed, t->key[i]) & (cap - 1); key[k][0]; k = (k + 1) & (cap - 1))
            ;
        memcpy(key[k], t->key[i], sizeof key[k]);
        val[k] = t->val[i];
    }
    gg_mem_free(a, t->key);
    gg_mem_free(a, t->val);
    t->key = key, t->val = val, t->cap = cap, t->seed = seed;
    return 0;
}

/* The mesh vertex of corner (iv, it, in); it, in = -1 for none. */
static int corner_vertex(objp *op, long iv, long it, long in, uint32_t *out)
{
    gg_mb *mb = op->mb;
    uint32_t key[3], *slot;
    size_t k;
    double uv[2];
    if (it < 0 && in < 0) {
        if ((size_t)iv >= op->cap_vmap) {
            size_t cap = op->cap_vmap * 2 > op->nv ? op->cap_vmap * 2 : op->nv + 1;
            uint32_t *m = gg_mem_realloc(mb->a, op->vmap, cap * sizeof *m);
            if (!m) return -1;
            memset(m + op->cap_vmap, 0, (cap - op->cap_vmap) * sizeof *m);
            op->vmap = m, op->cap_vmap = cap;
        }
        slot = &op->vmap[iv];
    } else {
        /* key[0] = iv + 1 never 0: 0 marks an empty slot */
        key[0] = (uint32_t)iv + 1, key[1] = (uint32_t)(it + 1), key[2] = (uint32_t)(in + 1);
        if (2 * (op->tm.n + 1) > op->tm.cap && tuples_grow(mb->a, &op->tm)) return -1;
        for (k = thash(op->tm.seed, key) & (op->tm.cap - 1); op->tm.key[k][0];
             k = (k + 1) & (op->tm.cap - 1))
            if (!memcmp(op->tm.key[k], key, sizeof key)) {
                *out = op->tm.val[k];
                return 0;
            }
        memcpy(op->tm.key[k], key, sizeof key);
        op->tm.n++;
        op->tm.val[k] = 0;
        slot = &op->tm.val[k];
        *slot = 0;
    }
    if (*slot) {
        *out = *slot - 1;
        return 0;
    }
    if (it >= 0) uv[0] = op->vt[2 * it], uv[1] = op->vt[2 * it + 1];
    if (gg_mb_vertex(mb, op->v[iv], in >= 0 ? &op->vn[in] : NULL, it >= 0 ? uv : NULL)) return -1;
    *out = (uint32_t)(mb->b.m.nverts - 1);
    /* tuple slots hold the vertex itself, the position map vertex + 1 */
    if (it < 0 && in < 0)
        *slot = *out + 1;
    else
        *slot = *out;
    return 0;
}

/* One corner: v, v/vt, v//vn or v/vt/vn (an empty field means none). */
static int corner(objp *op, uint32_t *out)
{
    gg_lc *c = &op->c;
    long iv, it = -1, in = -1;
    int rc = index_of(op, "vertex", op->nv, &iv);
    if (rc == GG_OK && c->p < c->end && *c->p == '/') {
        c->p++;
        if (!field_end(c, c->p) && *c->p != '/')
            rc = index_of(op, "texture coordinate", op->nvt, &it);
        if (rc == GG_OK && c->p < c->end && *c->p == '/') {
            c->p++;
            if (!field_end(c, c->p)) rc = index_of(op, "normal", op->nvn, &in);
        }
    }
    if (rc != GG_OK) return rc;
    if (!field_end(c, c->p))
        return gg_lc_fail(c, NULL, GG_ERROR_PARSE, "unexpected '%c' in a face corner", *c->p);
    return corner_vertex(op, iv, it, in, out) ? nomem(op) : GG_OK;
}

static int face(objp *op, int line)
{
    gg_mb *mb = op->mb;
    size_t n = 0;
    int rc;
    for (;;) {
        gg_lc_blank(&op->c);
        if (gg_lc_eol(&op->c)) break;
        if (n >= GG_MB_MAX_POLY)
            return gg_lc_fail(&op->c, NULL, GG_ERROR_LIMIT, "a face has more than %u corners",
                              GG_MB_MAX_POLY);
        if (gg_mem_grow(mb->a, (void **)&op->corner, &op->cap_corner, n + 1, sizeof *op->corner))
            return nomem(op);
        if ((rc = corner(op, &op->corner[n])) != GG_OK) return rc;
        n++;
    }
    if (n < 3)
        return gg_lc_fail(&op->c, NULL, GG_ERROR_PARSE, "a face needs 3 or more corners, got %zu",
                          n);
    if (mb->b.m.nfaces >= GG_MESH_MAX || mb->b.m.ntri + n >= GG_MESH_MAX)
        return too_many(op, "faces");
    if (gg_mb_face(mb, op->corner, n, (int)op->mtl - 1, op->smooth) ||
        gg_mb_face_line(mb, (uint32_t)line) || gg_mb_face_names(mb, op->group, op->mtl))
        return nomem(op);
    return GG_OK;
}

/* o NAME / g NAME...: faces after it belong to "o/g" (either alone when
   the other is unset; a new o clears g). The label is built and interned
   once per (o, g) pair: 10,000 g lines under a 400,000-byte o name copied
   and hashed it 10,000 times (5.35 s). Each distinct pair still stores
   its whole label, so their bytes are bounded by the file's size (plus
   GG_MESH_LABELS_MAX): 500 g names under that o name took 200 MB. */
static int group(objp *op, bool is_o)
{
    const ggAllocator *a = op->mb->a;
    const char *w, *on, *gn;
    size_t n = gg_lc_rest(&op->c, &w), lo, lg, before = op->pairs.n;
    char key[32], *label;
    uint32_t pid;
    int rc;
    if (gg_names_add(a, is_o ? &op->onames : &op->gnames, w, n, is_o ? &op->oid : &op->gid))
        return nomem(op);
    if (is_o) op->gid = 0; /* "" */
    snprintf(key, sizeof key, "%lu %lu", (unsigned long)op->oid, (unsigned long)op->gid);
    if (gg_names_add(a, &op->pairs, key, strlen(key), &pid)) return nomem(op);
    if (op->pairs.n == before) {
        op->group = op->pgroup[pid];
        return GG_OK;
    }
    if (gg_mem_grow(a, (void **)&op->pgroup, &op->cap_pgroup, op->pairs.n, sizeof *op->pgroup))
        return nomem(op);
    on = op->onames.s[op->oid], gn = op->gnames.s[op->gid];
    lo = strlen(on), lg = strlen(gn);
    if (lo + lg + 1 > op->label_max - op->label_bytes)
        return gg_lc_fail(&op->c, w, GG_ERROR_LIMIT,
                          "the group labels would pass %zu bytes, the file's size plus %u MiB "
                          "(each distinct o and g pair stores its \"o/g\" label)",
                          op->label_max, (unsigned)(GG_MESH_LABELS_MAX >> 20));
    op->label_bytes += lo + lg + 1;
    if (!(label = gg_mem_alloc(a, lo + lg + 2))) return nomem(op);
    memcpy(label, on, lo);
    if (lo && lg) label[lo++] = '/';
    memcpy(label + lo, gn, lg);
    label[lo + lg] = '\0';
    rc = gg_names_add(a, &op->mb->groups, label, lo + lg, &op->group);
    gg_mem_free(a, label);
    if (rc) return nomem(op);
    op->pgroup[pid] = op->group;
    return GG_OK;
}

static int usemtl(objp *op)
{
    const char *w;
    size_t n = gg_lc_rest(&op->c, &w);
    return gg_names_add(op->mb->a, &op->mb->mtls, w, n, &op->mtl) ? nomem(op) : GG_OK;
}

static int smoothing(objp *op)
{
    const char *w, *at;
    size_t n;
    long g;
    gg_lc_blank(&op->c);
    at = op->c.p;
    n = gg_lc_word(&op->c, &w);
    if (n == 3 && !memcmp(w, "off", 3))
        op->smooth = 0;
    else if (n && gg_parse_long(w, w + n, 0, 4294967295L, &g) == w + n)
        op->smooth = (uint32_t)g;
    else
        return gg_lc_fail(&op->c, at, GG_ERROR_PARSE, "expected a smoothing group number or off");
    return gg_lc_end(&op->c);
}

/* Was the MTL file `id` read already? A library named again adds nothing:
   re-reading it at every mtllib line made the entries (and the time) grow
   with lines x library size, 1.16 GB for an 88 KB OBJ naming itself. */
static bool lib_read(const objp *op, const gg_file_id *id)
{
    size_t i;
    for (i = 0; i < op->nlibid; i++)
        if (op->libid[i].dev == id->dev && op->libid[i].ino == id->ino) return true;
    return false;
}

/* One MTL file named by mtllib: parse errors fail the load, a file that
   cannot be read is a warning (its materials stay unknown). */
static int read_mtl(objp *op, const char *name, size_t n, bool *found)
{
    const ggAllocator *a = op->mb->a;
    size_t dl = strlen(op->dir), i, len;
    char *path = gg_mem_alloc(a, dl + n + 1), *text = NULL, *dir;
    gg_file_id id;
    ggError e2;
    int rc, known;
    if (!path) return nomem(op);
    memcpy(path, op->dir, dl);
    if (n && (name[0] == '/')) dl = 0;
    for (i = 0; i < n; i++) path[dl + i] = name[i] == '\\' ? '/' : name[i];
    path[dl + n] = '\0';
    /* a file that cannot be stat'ed cannot be read either: the read says why */
    if ((known = gg_load_file_id(path, &id) == 0) && lib_read(op, &id)) {
        gg_mem_free(a, path);
        return *found = true, GG_OK;
    }
    rc = gg_load_read_file(a, path, 64u << 20, &text, &len, &e2);
    *found = rc == GG_OK;
    op->libs += *found;
    if (rc == GG_OK && known &&
        gg_mem_grow(a, (void **)&op->libid, &op->cap_libid, op->nlibid + 1, sizeof *op->libid))
        rc = GG_ERROR_NOMEM;
    else if (rc == GG_OK && known)
        op->libid[op->nlibid++] = id;
    if (rc == GG_OK) { /* its path, for ggSceneInputFile */
        gg_mesh *m = &op->mb->b.m;
        if (gg_mem_grow(a, (void **)&m->libs, &op->mb->cap_libs, m->nlibs + 1, sizeof *m->libs) ||
            !(m->libs[m->nlibs] = gg_mem_strdup(a, path)))
            rc = GG_ERROR_NOMEM;
        else
            m->nlibs++;
    }
    if (rc == GG_ERROR_NOMEM)
        rc = nomem(op);
    else if (rc != GG_OK)
        rc = GG_OK; /* the caller decides what to say */
    else if (!(dir = gg_load_dirname(a, path)))
        rc = nomem(op);
    else {
        rc = gg_mtl_parse(a, &op->lib, text, len, path, dir, op->c.err);
        gg_mem_free(a, dir);
    }
    gg_mem_free(a, text);
    gg_mem_free(a, path);
    return rc;
}

/* mtllib FILE...: the whole rest of the line as one name first (names
   with spaces exist), else each word. */
static int mtllib(objp *op)
{
    const char *w, *p, *end;
    size_t n = gg_lc_rest(&op->c, &w);
    bool found = false;
    int rc, line = op->c.line;
    if (!op->dir || op->o->override_materials || !n) {
        op->ignored++;
        return GG_OK;
    }
    if ((rc = read_mtl(op, w, n, &found)) != GG_OK || found) return rc;
    for (p = w, end = w + n; p < end;) {
        const char *q = p;
        while (q < end && *q != ' ' && *q != '\t') q++;
        if (q > p) {
            if ((rc = read_mtl(op, p, (size_t)(q - p), &found)) != GG_OK) return rc;
            if (!found)
                gg_mb_warn(op->mb,
                           "%s:%d: cannot read the material library '%.*s'; its "
                           "materials are unknown",
                           op->c.name, line, (int)(q - p), p);
        }
        p = q + (q < end);
    }
    return GG_OK;
}

static bool is(const char *w, size_t n, const char *kw)
{
    return strlen(kw) == n && !memcmp(w, kw, n);
}

static int statement(objp *op, const char *w, size_t n, int line)
{
    if (n == 1 && w[0] == 'v') return vertex(op);
    if (n == 1 && w[0] == 'f') return face(op, line);
    if (is(w, n, "vt")) return texcoord(op);
    if (is(w, n, "vn")) return normal(op);
    if (is(w, n, "g")) return group(op, false);
    if (is(w, n, "o")) return group(op, true);
    if (is(w, n, "usemtl")) return usemtl(op);
    if (is(w, n, "mtllib")) return mtllib(op);
    if (is(w, n, "s")) return smoothing(op);
    if (is(w, n, "fo")) return face(op, line); /* the old name of f */
    op->ignored++;                             /* p, l, curves and surfaces, unknown statements */
    return GG_OK;
}

/* The scene material of an MTL entry, added (with its texture) on first
   use. A texture that cannot be read is a warning. */
static int add_material(objp *op, gg_mtl_entry *e)
{
    ggMaterial m = e->mat;
    int id, rc;
    if (e->material >= 0) return GG_OK;
    if (e->map_kd) {
        ggImage *img = NULL;
        ggError e2 = {0, ""};
        rc = gg_load_texture(op->s, e->map_kd, &img, &e2);
        if (rc == GG_ERROR_NOMEM) return nomem(op);
        if (rc != GG_OK) {
            gg_mb_warn(op->mb, "%s: texture not used (%s); the material has its Kd colour alone",
                       e->where, e2.message);
        } else {
            gg_texture tx;
            memset(&tx, 0, sizeof tx);
            tx.img = img, tx.shared = 1, tx.wrap = e->wrap;
            if ((id = gg_scene_add_texture_desc(op->s, &tx)) < 0) return nomem(op);
            m.texture = id;
        }
    }
    if ((id = ggSceneAddMaterial(op->s, &m)) < 0)
        return id == -GG_ERROR_NOMEM ? nomem(op)
                                     : gg_error_set(op->c.err, GG_ERROR_PARSE,
                                                    "%s: the material is not valid", e->where);
    e->material = id;
    return GG_OK;
}

/* usemtl names -> scene materials (the last newmtl of a name wins); the
   triangles' material ids (usemtl id - 1) become scene materials. */
static int resolve_materials(objp *op)
{
    gg_mb *mb = op->mb;
    gg_names libnames;
    int *map = NULL, rc = GG_OK;
    size_t i, *last = NULL;
    uint32_t id;
    if (op->o->override_materials || !mb->b.tmat) return GG_OK;
    memset(&libnames, 0, sizeof libnames);
    map = gg_mem_calloc(mb->a, mb->mtls.n + 1, sizeof *map);
    last = gg_mem_calloc(mb->a, op->lib.n + 1, sizeof *last);
    if (!map || !last) rc = nomem(op);
    for (i = 0; rc == GG_OK && i < op->lib.n; i++) {
        const char *nm = op->lib.e[i].name;
        if (gg_names_add(mb->a, &libnames, nm, strlen(nm), &id))
            rc = nomem(op);
        else
            last[id] = i;
    }
    for (i = 1; rc == GG_OK && i < mb->mtls.n; i++) {
        const char *nm = mb->mtls.s[i];
        size_t before = libnames.n;
        map[i] = -1;
        if (gg_names_add(mb->a, &libnames, nm, strlen(nm), &id))
            rc = nomem(op);
        else if (libnames.n > before && op->libs)
            gg_mb_warn(mb,
                       "%s: usemtl '%s' names no material of the MTL files; its faces get the "
                       "default material",
                       op->c.name, nm);
        else if (libnames.n == before && (rc = add_material(op, &op->lib.e[last[id]])) == GG_OK)
            map[i] = op->lib.e[last[id]].material;
    }
    for (i = 0; rc == GG_OK && i < mb->b.m.ntri; i++)
        if (mb->b.tmat[i] >= 0) mb->b.tmat[i] = map[mb->b.tmat[i] + 1];
    gg_names_free(mb->a, &libnames);
    gg_mem_free(mb->a, map);
    gg_mem_free(mb->a, last);
    return rc;
}

static void take_names(gg_names *t, char ***s, size_t *n, const ggAllocator *a)
{
    *s = t->s, *n = t->n;
    gg_mem_free(a, t->tab);
    memset(t, 0, sizeof *t);
}

static int finish(objp *op)
{
    gg_mb *mb = op->mb;
    gg_mesh *m = &mb->b.m;
    int rc;
    if (!m->nfaces)
        return gg_error_set(op->c.err, GG_ERROR_PARSE,
                            "%s: no faces (%zu vertices; %zu statements not read: points, lines, "
                            "curves or unknown)",
                            op->c.name, op->nv, op->ignored);
    if ((rc = resolve_materials(op)) != GG_OK) return rc;
    m->file_vertices = op->nv;
    m->ignored = op->ignored + op->lib.ignored;
    take_names(&mb->groups, &m->groups, &m->ngroups, mb->a);
    take_names(&mb->mtls, &m->mtlnames, &m->nmtlnames, mb->a);
    if (m->ngroups <= 1 && m->fgroup) gg_mem_free(mb->a, m->fgroup), m->fgroup = NULL;
    return GG_OK;
}

static void objp_free(objp *op)
{
    const ggAllocator *a = op->mb->a;
    gg_mem_free(a, op->v);
    gg_mem_free(a, op->vt);
    gg_mem_free(a, op->vn);
    gg_mem_free(a, op->vmap);
    gg_mem_free(a, op->tm.key);
    gg_mem_free(a, op->tm.val);
    gg_mem_free(a, op->corner);
    gg_names_free(a, &op->onames);
    gg_names_free(a, &op->gnames);
    gg_names_free(a, &op->pairs);
    gg_mem_free(a, op->pgroup);
    gg_mtl_free(a, &op->lib);
    gg_mem_free(a, op->libid);
}

int gg_obj_read(ggScene *s, gg_mb *mb, const char *text, size_t len, const char *name,
                const char *dir, const ggMeshOptions *o, ggError *err)
{
    objp op;
    uint32_t id;
    int rc;
    memset(&op, 0, sizeof op);
    op.s = s, op.mb = mb, op.o = o, op.dir = dir, op.smooth = 1;
    op.label_max = len < SIZE_MAX - GG_MESH_LABELS_MAX ? len + GG_MESH_LABELS_MAX : SIZE_MAX;
    gg_lc_init(&op.c, text, len, name, err);
    /* group, material, o and g name 0 are "none" */
    if (gg_names_add(mb->a, &mb->groups, "", 0, &id) ||
        gg_names_add(mb->a, &mb->mtls, "", 0, &id) || gg_names_add(mb->a, &op.onames, "", 0, &id) ||
        gg_names_add(mb->a, &op.gnames, "", 0, &id)) {
        objp_free(&op);
        return gg_error_set(err, GG_ERROR_NOMEM, "%s: out of memory", name);
    }
    rc = gg_lc_check_text(&op.c);
    while (rc == GG_OK && op.c.p < op.c.end) {
        const char *w;
        int line = op.c.line;
        size_t n = gg_lc_word(&op.c, &w);
        if (n) rc = statement(&op, w, n, line);
        if (rc == GG_OK) gg_lc_next_line(&op.c);
        if (rc == GG_OK && gg_mb_progress(mb, (size_t)(op.c.p - text), 0))
            rc = gg_lc_fail(&op.c, NULL, GG_ERROR_CANCELLED, "loading cancelled");
    }
    if (rc == GG_OK) rc = finish(&op);
    objp_free(&op);
    return rc;
}
