/* SPDX-License-Identifier: MIT */
/*
** meshbuild.c -- what the mesh readers share: the growing mesh (gg_mb),
** polygons split into triangles, interned names, decimal numbers, and
** reading files (mesh_int.h).
*/
#include "image.h"
#include "mesh_int.h"

#include "vec.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

void gg_mb_init(gg_mb *mb, const ggAllocator *a, int format)
{
    memset(mb, 0, sizeof *mb);
    mb->a = a;
    mb->b.m.format = format;
}

int gg_mb_report(gg_mb *mb, size_t at)
{
    mb->told = at;
    return gg_progress_to(&mb->prog, at, mb->len);
}

void gg_mb_free(gg_mb *mb)
{
    gg_mesh_build_free(mb->a, &mb->b);
    gg_names_free(mb->a, &mb->groups);
    gg_names_free(mb->a, &mb->mtls);
    gg_mem_free(mb->a, mb->ring);
    gg_mem_free(mb->a, mb->q);
    gg_mem_free(mb->a, mb->next);
    gg_mem_free(mb->a, mb->prev);
    gg_mem_free(mb->a, mb->ear);
    memset(mb, 0, sizeof *mb);
}

static int grow(gg_mb *mb, void *arr, size_t *cap, size_t need, size_t elem)
{
    return gg_mem_grow(mb->a, (void **)arr, cap, need, elem);
}

/* A column that most meshes do not need (per-vertex "has a normal", per-
   triangle material and smoothing group): allocated when a value first
   differs from `dflt`, the earlier entries filled with it. */
static int column(gg_mb *mb, uint32_t **col, size_t *cap, size_t at, uint32_t v, uint32_t dflt)
{
    size_t i;
    if (!*col) {
        if (v == dflt) return 0;
        if (grow(mb, col, cap, at + 1, sizeof **col)) return -1;
        for (i = 0; i < at; i++) (*col)[i] = dflt;
    } else if (grow(mb, col, cap, at + 1, sizeof **col))
        return -1;
    (*col)[at] = v;
    return 0;
}

/* One byte per vertex: 1 where the file gave a normal. */
static int vnrm_push(gg_mb *mb, size_t at, uint8_t v, uint8_t earlier)
{
    size_t i;
    bool fresh = !mb->b.vnrm;
    if (grow(mb, &mb->b.vnrm, &mb->cap_vnrm, at + 1, 1)) return -1;
    if (fresh)
        for (i = 0; i < at; i++) mb->b.vnrm[i] = earlier;
    mb->b.vnrm[at] = v;
    return 0;
}

int gg_mb_vertex(gg_mb *mb, ggVec3 p, const ggVec3 *n, const double *uv)
{
    gg_mesh *m = &mb->b.m;
    size_t at = m->nverts, i;
    if (grow(mb, &m->pos, &mb->cap_pos, at + 1, sizeof *m->pos)) return -1;
    m->pos[at] = p;
    if (n && !m->nrm) {
        if (grow(mb, &m->nrm, &mb->cap_nrm, at + 1, sizeof *m->nrm)) return -1;
        for (i = 0; i < at; i++) m->nrm[i] = v3(0, 0, 0);
        if (at && vnrm_push(mb, at, 1, 0)) return -1;
    } else if (m->nrm) {
        if (grow(mb, &m->nrm, &mb->cap_nrm, at + 1, sizeof *m->nrm)) return -1;
        if ((!n || mb->b.vnrm) && vnrm_push(mb, at, n != NULL, 1)) return -1;
    }
    if (m->nrm) m->nrm[at] = n ? *n : v3(0, 0, 0);
    if (uv && !m->uv) {
        if (grow(mb, &m->uv, &mb->cap_uv, 2 * (at + 1), sizeof *m->uv)) return -1;
        for (i = 0; i < 2 * at; i++) m->uv[i] = 0;
    } else if (m->uv && grow(mb, &m->uv, &mb->cap_uv, 2 * (at + 1), sizeof *m->uv))
        return -1;
    if (m->uv) m->uv[2 * at] = uv ? uv[0] : 0, m->uv[2 * at + 1] = uv ? uv[1] : 0;
    m->nverts++;
    return 0;
}

int gg_mb_reserve(gg_mb *mb, size_t nverts, bool nrm, bool uv, size_t ntri)
{
    gg_mesh *m = &mb->b.m;
    size_t v = m->nverts + nverts, t = m->ntri + ntri;
    return (nverts && grow(mb, &m->pos, &mb->cap_pos, v, sizeof *m->pos)) ||
                   (nverts && nrm && grow(mb, &m->nrm, &mb->cap_nrm, v, sizeof *m->nrm)) ||
                   (nverts && uv && grow(mb, &m->uv, &mb->cap_uv, 2 * v, sizeof *m->uv)) ||
                   (ntri && grow(mb, &m->idx, &mb->cap_idx, 3 * t, sizeof *m->idx)) ||
                   (ntri && grow(mb, &m->tface, &mb->cap_tface, t, sizeof *m->tface))
               ? -1
               : 0;
}

static int emit(gg_mb *mb, uint32_t a, uint32_t b, uint32_t c, int mat, uint32_t smooth)
{
    gg_mesh *m = &mb->b.m;
    size_t t = m->ntri;
    if ((3 * (t + 1) > mb->cap_idx &&
         grow(mb, &m->idx, &mb->cap_idx, 3 * (t + 1), sizeof *m->idx)) ||
        (t + 1 > mb->cap_tface && grow(mb, &m->tface, &mb->cap_tface, t + 1, sizeof *m->tface)) ||
        ((mat != -1 || mb->b.tmat) &&
         column(mb, (uint32_t **)&mb->b.tmat, &mb->cap_tmat, t, (uint32_t)mat, UINT32_MAX)) ||
        ((smooth != 1 || mb->b.tsmooth) && column(mb, &mb->b.tsmooth, &mb->cap_tsm, t, smooth, 1)))
        return -1;
    m->idx[3 * t] = a, m->idx[3 * t + 1] = b, m->idx[3 * t + 2] = c;
    m->tface[t] = (uint32_t)m->nfaces;
    m->ntri++;
    return 0;
}

/* ---- splitting polygons ---- */

static ggVec3 newell(const gg_mesh *m, const uint32_t *r, size_t n)
{
    ggVec3 N = v3(0, 0, 0);
    size_t i;
    for (i = 0; i < n; i++) {
        ggVec3 a = m->pos[r[i]], b = m->pos[r[i + 1 < n ? i + 1 : 0]];
        N.x += (a.y - b.y) * (a.z + b.z);
        N.y += (a.z - b.z) * (a.x + b.x);
        N.z += (a.x - b.x) * (a.y + b.y);
    }
    return N;
}

/* A quad along the diagonal that keeps both halves facing the quad's
   normal (the other one for a concave quad). */
static int quad(gg_mb *mb, const uint32_t *r, int mat, uint32_t sm)
{
    const gg_mesh *m = &mb->b.m;
    ggVec3 N = newell(m, r, 4), a = m->pos[r[0]], b = m->pos[r[1]], c = m->pos[r[2]],
           d = m->pos[r[3]];
    bool ok1 = v3dot(N, v3cross(v3sub(b, a), v3sub(c, a))) > 0 &&
               v3dot(N, v3cross(v3sub(c, a), v3sub(d, a))) > 0;
    bool ok2 = v3dot(N, v3cross(v3sub(b, a), v3sub(d, a))) > 0 &&
               v3dot(N, v3cross(v3sub(c, b), v3sub(d, b))) > 0;
    if (ok1 || !ok2)
        return emit(mb, r[0], r[1], r[2], mat, sm) || emit(mb, r[0], r[2], r[3], mat, sm);
    return emit(mb, r[0], r[1], r[3], mat, sm) || emit(mb, r[1], r[2], r[3], mat, sm);
}

static double orient(const double (*q)[2], int a, int b, int c)
{
    return (q[b][0] - q[a][0]) * (q[c][1] - q[a][1]) - (q[b][1] - q[a][1]) * (q[c][0] - q[a][0]);
}

static bool same(const double (*q)[2], int a, int b)
{
    return q[a][0] == q[b][0] && q[a][1] == q[b][1];
}

/* Is i an ear of the remaining outline: convex, and no other remaining
   vertex inside or on its triangle (except copies of its corners)? */
static bool is_ear(const gg_mb *mb, int i)
{
    const double(*q)[2] = (const double(*)[2])mb->q;
    int p = mb->prev[i], n = mb->next[i], j;
    if (!(orient(q, p, i, n) > 0)) return false;
    for (j = mb->next[n]; j != p; j = mb->next[j]) {
        if (same(q, j, p) || same(q, j, i) || same(q, j, n)) continue;
        if (orient(q, p, i, j) >= 0 && orient(q, i, n, j) >= 0 && orient(q, n, p, j) >= 0)
            return false;
    }
    return true;
}

/* Project onto the plane of the normal's two minor axes, turned so that
   the outline runs counter-clockwise; 0 if it has no area there. */
static int project(gg_mb *mb, const uint32_t *r, size_t n)
{
    const gg_mesh *m = &mb->b.m;
    ggVec3 N = newell(m, r, n);
    double ax = fabs(N.x), ay = fabs(N.y), az = fabs(N.z), s;
    int kz = ax > ay ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2), kx = (kz + 1) % 3, ky = (kz + 2) % 3;
    size_t i;
    s = v3get(N, kz);
    if (!(s != 0)) return 0;
    for (i = 0; i < n; i++) {
        ggVec3 p = m->pos[r[i]];
        mb->q[i][0] = v3get(p, kx);
        mb->q[i][1] = s > 0 ? v3get(p, ky) : -v3get(p, ky);
    }
    return 1;
}

/* Ear clipping with cached ear flags (only a clipped ear's neighbours are
   looked at again): O(n^2). A polygon that has no ear left (it crosses
   itself) gets the rest as a fan. */
static int ear_clip(gg_mb *mb, const uint32_t *r, size_t n, int mat, uint32_t sm)
{
    int i, left = (int)n, cur = 0, k;
    for (i = 0; i < (int)n; i++)
        mb->next[i] = i + 1 < (int)n ? i + 1 : 0, mb->prev[i] = i ? i - 1 : (int)n - 1;
    for (i = 0; i < (int)n; i++) mb->ear[i] = is_ear(mb, i);
    while (left > 3) {
        int p, nx, found = -1;
        for (i = cur, k = 0; k < left; k++, i = mb->next[i]) {
            if (orient((const double(*)[2])mb->q, mb->prev[i], i, mb->next[i]) == 0 || mb->ear[i]) {
                found = i;
                break;
            }
        }
        if (found < 0) break;
        p = mb->prev[found], nx = mb->next[found];
        if (mb->ear[found] && emit(mb, r[p], r[found], r[nx], mat, sm)) return -1;
        mb->next[p] = nx, mb->prev[nx] = p;
        left--;
        mb->ear[p] = is_ear(mb, p), mb->ear[nx] = is_ear(mb, nx);
        cur = nx;
    }
    /* the last triangle, or the fan of what no ear could take */
    for (k = 0, i = mb->next[cur]; k < left - 2; k++, i = mb->next[i])
        if (emit(mb, r[cur], r[i], r[mb->next[i]], mat, sm)) return -1;
    return 0;
}

int gg_mb_face(gg_mb *mb, const uint32_t *v, size_t n, int mat, uint32_t smooth)
{
    size_t i, k = 0;
    int rc = 0;
    /* the common case: a triangle with three different corners */
    if (n == 3 && v[0] != v[1] && v[1] != v[2] && v[2] != v[0]) {
        rc = emit(mb, v[0], v[1], v[2], mat, smooth);
        mb->b.m.nfaces++;
        return rc;
    }
    if (n > mb->cap_ring) {
        size_t c = n;
        gg_mem_free(mb->a, mb->ring), gg_mem_free(mb->a, mb->q);
        gg_mem_free(mb->a, mb->next), gg_mem_free(mb->a, mb->prev), gg_mem_free(mb->a, mb->ear);
        mb->ring = gg_mem_alloc(mb->a, c * sizeof *mb->ring);
        mb->q = gg_mem_alloc(mb->a, c * sizeof *mb->q);
        mb->next = gg_mem_alloc(mb->a, c * sizeof *mb->next);
        mb->prev = gg_mem_alloc(mb->a, c * sizeof *mb->prev);
        mb->ear = gg_mem_alloc(mb->a, c);
        mb->cap_ring = mb->ring && mb->q && mb->next && mb->prev && mb->ear ? c : 0;
        if (!mb->cap_ring) return -1;
    }
    for (i = 0; i < n; i++)
        if (!k || v[i] != mb->ring[k - 1]) mb->ring[k++] = v[i];
    while (k > 1 && mb->ring[k - 1] == mb->ring[0]) k--;
    if (k < 3)
        mb->b.m.skipped++;
    else if (k == 3)
        rc = emit(mb, mb->ring[0], mb->ring[1], mb->ring[2], mat, smooth);
    else if (k == 4)
        rc = quad(mb, mb->ring, mat, smooth);
    else if (k <= GG_MB_MAX_CLIP && project(mb, mb->ring, k))
        rc = ear_clip(mb, mb->ring, k, mat, smooth);
    else
        for (i = 1; rc == 0 && i + 1 < k; i++)
            rc = emit(mb, mb->ring[0], mb->ring[i], mb->ring[i + 1], mat, smooth);
    mb->b.m.nfaces++;
    return rc;
}

int gg_mb_face_line(gg_mb *mb, uint32_t line)
{
    gg_mesh *m = &mb->b.m;
    if (grow(mb, &m->fline, &mb->cap_fline, m->nfaces, sizeof *m->fline)) return -1;
    m->fline[m->nfaces - 1] = line;
    return 0;
}

int gg_mb_face_names(gg_mb *mb, uint32_t group, uint32_t mtl)
{
    gg_mesh *m = &mb->b.m;
    size_t f = m->nfaces - 1;
    return column(mb, &m->fgroup, &mb->cap_fgroup, f, group, 0) ||
           column(mb, &m->fmtl, &mb->cap_fmtl, f, mtl, 0);
}

void gg_mb_warn(gg_mb *mb, const char *fmt, ...)
{
    char msg[512];
    va_list ap;
    if (mb->b.m.nwarn++ || !fmt) return;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    mb->b.m.warning = gg_mem_strdup(mb->a, msg);
}

/* ---- names ---- */

int gg_names_add(const ggAllocator *a, gg_names *t, const char *name, size_t len, uint32_t *id)
{
    size_t k, i;
    char *c;
    if (2 * (t->n + 1) > t->tcap) {
        size_t cap = t->tcap ? 2 * t->tcap : 64;
        uint32_t *tab = gg_mem_calloc(a, cap, sizeof *tab);
        uint64_t seed = gg_hash_seed(tab);
        if (!tab) return -1;
        for (i = 0; i < t->n; i++) {
            for (k = gg_hash_bytes(seed, t->s[i], strlen(t->s[i])) & (cap - 1); tab[k];
                 k = (k + 1) & (cap - 1))
                ;
            tab[k] = (uint32_t)i + 1;
        }
        gg_mem_free(a, t->tab);
        t->tab = tab, t->tcap = cap, t->seed = seed;
    }
    for (k = gg_hash_bytes(t->seed, name, len) & (t->tcap - 1); t->tab[k];
         k = (k + 1) & (t->tcap - 1)) {
        const char *s = t->s[t->tab[k] - 1];
        if (strlen(s) == len && !memcmp(s, name, len)) {
            *id = t->tab[k] - 1;
            return 0;
        }
    }
    if (t->n >= UINT32_MAX - 1 || gg_mem_grow(a, (void **)&t->s, &t->cap, t->n + 1, sizeof *t->s) ||
        !(c = gg_mem_alloc(a, len + 1)))
        return -1;
    memcpy(c, name, len);
    c[len] = '\0';
    t->s[t->n] = c;
    t->tab[k] = (uint32_t)t->n + 1;
    *id = (uint32_t)t->n++;
    return 0;
}

void gg_names_free(const ggAllocator *a, gg_names *t)
{
    size_t i;
    for (i = 0; i < t->n; i++) gg_mem_free(a, t->s[i]);
    gg_mem_free(a, t->s);
    gg_mem_free(a, t->tab);
    memset(t, 0, sizeof *t);
}

/* ---- numbers ---- */

static bool digit(char c)
{
    return c >= '0' && c <= '9';
}

const char *gg_parse_number(const char *p, const char *end, double *out)
{
    static const double p10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                   1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                   1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    const char *s = p;
    uint64_t mant = 0;
    long e10 = 0, ex = 0;
    bool neg = false, any = false, exact = true;
    if (p < end && (*p == '+' || *p == '-')) neg = *p++ == '-';
    for (; p < end && digit(*p); p++, any = true) {
        if (mant < 100000000000000000ull)
            mant = mant * 10 + (uint64_t)(*p - '0');
        else
            e10++, exact = exact && *p == '0';
    }
    if (p < end && *p == '.') {
        for (p++; p < end && digit(*p); p++, any = true) {
            if (mant < 100000000000000000ull)
                mant = mant * 10 + (uint64_t)(*p - '0'), e10--;
            else
                exact = exact && *p == '0';
        }
    }
    if (!any) return NULL;
    if (p < end && (*p == 'e' || *p == 'E')) {
        bool eneg = false, edig = false;
        p++;
        if (p < end && (*p == '+' || *p == '-')) eneg = *p++ == '-';
        for (; p < end && digit(*p); p++, edig = true)
            if (ex < 100000) ex = ex * 10 + (*p - '0');
        if (!edig) return NULL;
        e10 += eneg ? -ex : ex;
    }
    /* Both operands exact and one rounding: correctly rounded (Clinger,
       "How to read floating point numbers accurately", PLDI 1990). */
    if (exact && mant <= (1ull << 53) && e10 >= -22 && e10 <= 22) {
        double d = (double)mant;
        d = e10 < 0 ? d / p10[-e10] : d * p10[e10];
        *out = neg ? -d : d;
        return p;
    }
    {
        size_t n = (size_t)(p - s);
        double d;
        if (gg_strtod_c(s, n, &d) != n || !isfinite(d)) return NULL;
        *out = d;
        return p;
    }
}

const char *gg_parse_long(const char *p, const char *end, long lo, long hi, long *out)
{
    bool neg = false, any = false;
    long long v = 0;
    if (p < end && (*p == '+' || *p == '-')) neg = *p++ == '-';
    for (; p < end && digit(*p); p++, any = true) {
        if (v > 100000000000000LL) return NULL; /* far beyond any limit used */
        v = v * 10 + (*p - '0');
    }
    if (!any) return NULL;
    if (neg) v = -v;
    if (v < lo || v > hi) return NULL;
    *out = (long)v;
    return p;
}

/* ---- files ---- */

const char *gg_load_binary_kind(const char *data, size_t len)
{
    static const struct {
        const char *magic;
        size_t len;
        const char *kind;
    } known[] = {
        {"\x89PNG\r\n\x1a\n", 8, "a PNG image"},
        {"\x76\x2f\x31\x01", 4, "an OpenEXR image"},
        {"\xff\xd8\xff", 3, "a JPEG image"},
        {"GIF87a", 6, "a GIF image"},
        {"GIF89a", 6, "a GIF image"},
        {"II*\0", 4, "a TIFF image"},
        {"MM\0*", 4, "a TIFF image"},
        {"glTF", 4, "a binary glTF model"},
        {"\x1f\x8b", 2, "gzip-compressed data"},
        {"PK\x03\x04", 4, "a ZIP archive"},
        {"%PDF-", 5, "a PDF document"},
        {"\x7f"
         "ELF",
         4, "an executable (ELF)"},
    };
    size_t i;
    for (i = 0; i < sizeof known / sizeof known[0]; i++)
        if (len >= known[i].len && memcmp(data, known[i].magic, known[i].len) == 0)
            return known[i].kind;
    if (len >= 12 && memcmp(data, "RIFF", 4) == 0 && memcmp(data + 8, "WEBP", 4) == 0)
        return "a WebP image";
    return NULL;
}

int gg_load_file_id(const char *path, gg_file_id *id)
{
    struct stat st;
    if (stat(path, &st) != 0) return -1;
    id->dev = (uint64_t)st.st_dev, id->ino = (uint64_t)st.st_ino;
    return 0;
}

int gg_load_read_file(const ggAllocator *a, const char *path, size_t limit, char **out, size_t *len,
                      ggError *err)
{
    FILE *f;
    int64_t size = 0;
    char *buf;
    size_t n, got;
    int rc = gg_file_open(path, NULL, &f, &size, err);
    if (rc != GG_OK) return rc;
    if ((unsigned long long)size > (unsigned long long)limit) {
        fclose(f);
        return gg_error_set(err, GG_ERROR_LIMIT, "%s: %lld bytes exceed the limit of %zu", path,
                            (long long)size, limit);
    }
    n = (size_t)size;
    if (!(buf = gg_mem_alloc(a, n + 1))) {
        fclose(f);
        return gg_error_set(err, GG_ERROR_NOMEM, "%s: out of memory", path);
    }
    got = fread(buf, 1, n, f);
    if (got != n || ferror(f)) {
        fclose(f);
        gg_mem_free(a, buf);
        return gg_error_set(err, GG_ERROR_IO, "%s: read error", path);
    }
    fclose(f);
    buf[n] = '\0';
    *out = buf, *len = n;
    return GG_OK;
}

/* A reader's failure as the loaders report it. A reader of the caller's
   may leave err untouched (it is optional in ggImageRead's contract) or
   return a code of its own: the caller of ggSceneLoad* gets a GG_ERROR_
   code it can name and a message, never stack garbage. */
static int reader_failed(const char *path, int rc, ggError *got, ggError *err)
{
    const int code = rc >= GG_ERROR_INVALID && rc <= GG_ERROR_CANCELLED ? rc : GG_ERROR_IO;
    got->message[sizeof got->message - 1] = '\0';
    if (got->message[0]) return gg_error_set(err, code, "%s", got->message);
    return gg_error_set(err, code, "%s: the image reader failed (status %d) without a message",
                        path, rc);
}

int gg_load_texture(ggScene *s, const char *path, ggImage **img, ggError *err)
{
    ggImageReader fn = s->reader ? s->reader : gg_load_default_reader();
    gg_image_budget b;
    ggImage *got = NULL;
    ggError e2 = {0, ""};
    gg_file_id fid;
    uint64_t id[2];
    /* One file under two names is one image; a reader of the caller's
       own (ggSceneSetImageReader) may read no files: its names alone. */
    int rc, has_id = !s->reader && gg_load_file_id(path, &fid) == 0;
    if (has_id) id[0] = fid.dev, id[1] = fid.ino;
    if ((*img = gg_scene_image_find(s, path, has_id ? id : NULL)) != NULL) return GG_OK;
    if (!fn)
        return gg_error_set(err, GG_ERROR_UNSUPPORTED,
                            "%s: this libggrt reads no image files (libggrt-core); give the "
                            "scene a reader with ggSceneSetImageReader",
                            path);
    b.total = s->tex_budget;
    b.left = s->tex_budget > s->tex_used ? s->tex_budget - s->tex_used : 0;
    rc = fn(s->reader ? s->reader_ud : &b, path, s->alloc, &got, &e2);
    if (rc != GG_OK) return reader_failed(path, rc, &e2, err);
    if (!got)
        return gg_error_set(err, GG_ERROR_INVALID, "%s: the image reader gave no image", path);
    rc = gg_image_check_budget(path, got->width, got->height, &b, err);
    if (rc != GG_OK) {
        ggImageFree(got);
        return rc;
    }
    if (gg_scene_image_add(s, path, has_id ? id : NULL, got) < 0)
        return gg_error_set(err, GG_ERROR_NOMEM, "%s: out of memory", path);
    *img = got;
    return GG_OK;
}

char *gg_load_dirname(const ggAllocator *a, const char *path)
{
    char *d = gg_mem_strdup(a, path), *slash;
    if (!d) return NULL;
    slash = strrchr(d, '/');
    if (slash)
        slash[1] = '\0';
    else
        d[0] = '\0';
    return d;
}
