/* SPDX-License-Identifier: MIT */
/*
** ply.c -- the Stanford PLY reader (Turk, "The PLY polygon file format",
** 1994): ascii, binary_little_endian and binary_big_endian; vertex x y z
** with optional nx ny nz and u v (also s t, texture_u texture_v); face
** lists of any length (vertex_indices or vertex_index); every other
** property and element is skipped. Errors name "file:line:col" in ascii
** and "file: byte N (face K)" in binary bodies.
*/
#include "mesh_int.h"

#include "vec.h"

#include <float.h>
#include <math.h>

#include <stdio.h>
#include <string.h>

#define PLY_MAX_ELEMS 64
#define PLY_MAX_PROPS 256

enum { T_I8 = 1, T_U8, T_I16, T_U16, T_I32, T_U32, T_F32, T_F64 };
static const struct {
    const char *name;
    int type, size;
} types[] = {
    {"char", T_I8, 1},   {"int8", T_I8, 1},     {"uchar", T_U8, 1},   {"uint8", T_U8, 1},
    {"short", T_I16, 2}, {"int16", T_I16, 2},   {"ushort", T_U16, 2}, {"uint16", T_U16, 2},
    {"int", T_I32, 4},   {"int32", T_I32, 4},   {"uint", T_U32, 4},   {"uint32", T_U32, 4},
    {"float", T_F32, 4}, {"float32", T_F32, 4}, {"double", T_F64, 8}, {"float64", T_F64, 8}};

static int type_size(int t)
{
    static const int sz[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};
    return sz[t];
}

typedef struct pprop {
    const char *nm;
    size_t nn;
    int type;  /* scalar type, or a list's item type */
    int ctype; /* a list's count type; 0 for a scalar */
} pprop;

typedef struct pelem {
    const char *nm;
    size_t nn;
    unsigned long long count;
    int line, col; /* where the header gives the count, for errors about it */
    pprop p[PLY_MAX_PROPS];
    int np;
} pelem;

typedef struct plyp {
    gg_mb *mb;
    const char *name;
    ggError *err;
    int fmt;   /* 0 ascii, 1 little, 2 big endian */
    bool has_format;
    bool swap; /* binary values in the other byte order than this machine's */
    pelem el[PLY_MAX_ELEMS];
    int nel;
    const unsigned char *data, *p, *end;
    gg_lc c;          /* ascii body (and the header) */
    const char *what; /* the element being read, for messages */
    unsigned long long index;
    uint32_t *corner;
    size_t cap_corner;
} plyp;

static bool is(const char *w, size_t n, const char *kw)
{
    return strlen(kw) == n && !memcmp(w, kw, n);
}

static int lookup_type(const char *w, size_t n)
{
    size_t i;
    for (i = 0; i < sizeof types / sizeof types[0]; i++)
        if (is(w, n, types[i].name)) return types[i].type;
    return 0;
}

static int hfail(plyp *pp, const char *at, const char *fmt, const char *w, size_t n)
{
    char b[100];
    return gg_lc_fail(&pp->c, at, GG_ERROR_PARSE, fmt, gg_lc_show(w, n, b, sizeof b));
}

/* property TYPE NAME | property list CTYPE TYPE NAME */
static int property(plyp *pp)
{
    pelem *e;
    pprop *p;
    const char *w, *at;
    size_t n;
    if (!pp->nel) return gg_lc_fail(&pp->c, NULL, GG_ERROR_PARSE, "a property before any element");
    e = &pp->el[pp->nel - 1];
    if (e->np >= PLY_MAX_PROPS)
        return gg_lc_fail(&pp->c, NULL, GG_ERROR_LIMIT, "more than %d properties", PLY_MAX_PROPS);
    p = &e->p[e->np];
    memset(p, 0, sizeof *p);
    gg_lc_blank(&pp->c), at = pp->c.p;
    n = gg_lc_word(&pp->c, &w);
    if (is(w, n, "list")) {
        gg_lc_blank(&pp->c), at = pp->c.p;
        n = gg_lc_word(&pp->c, &w);
        if (!(p->ctype = lookup_type(w, n)) || p->ctype == T_F32 || p->ctype == T_F64)
            return hfail(pp, at, "bad list count type '%s'", w, n);
        gg_lc_blank(&pp->c), at = pp->c.p;
        n = gg_lc_word(&pp->c, &w);
    }
    if (!(p->type = lookup_type(w, n))) return hfail(pp, at, "unknown property type '%s'", w, n);
    if (!(p->nn = gg_lc_word(&pp->c, &p->nm)))
        return gg_lc_fail(&pp->c, NULL, GG_ERROR_PARSE, "a property needs a name");
    e->np++;
    return gg_lc_end(&pp->c);
}

static int element(plyp *pp)
{
    pelem *e;
    const char *at;
    double d;
    int rc;
    if (pp->nel >= PLY_MAX_ELEMS)
        return gg_lc_fail(&pp->c, NULL, GG_ERROR_LIMIT, "more than %d elements", PLY_MAX_ELEMS);
    e = &pp->el[pp->nel];
    memset(e, 0, sizeof *e);
    if (!(e->nn = gg_lc_word(&pp->c, &e->nm)))
        return gg_lc_fail(&pp->c, NULL, GG_ERROR_PARSE, "an element needs a name");
    gg_lc_blank(&pp->c), at = pp->c.p;
    e->line = pp->c.line, e->col = (int)(at - pp->c.ls) + 1;
    if ((rc = gg_lc_number(&pp->c, &d, "an element count")) != GG_OK) return rc;
    if (!(d >= 0 && d <= 4294967295.0) || d != floor(d))
        return gg_lc_fail(&pp->c, at, GG_ERROR_PARSE, "bad element count");
    e->count = (unsigned long long)d;
    pp->nel++;
    return gg_lc_end(&pp->c);
}

/* format ascii|binary_little_endian|binary_big_endian 1.0: without the
   version, or without the line, a file once loaded as ascii. */
static int format(plyp *pp)
{
    static const char *const names[] = {"ascii", "binary_little_endian", "binary_big_endian"};
    const char *w, *at;
    size_t n;
    double v;
    gg_lc_blank(&pp->c), at = pp->c.p;
    n = gg_lc_word(&pp->c, &w);
    for (pp->fmt = 0; pp->fmt < 3 && !is(w, n, names[pp->fmt]); pp->fmt++)
        ;
    if (pp->fmt == 3) return hfail(pp, at, "unknown format '%s'", w, n);
    if (!(n = gg_lc_word(&pp->c, &w)))
        return gg_lc_fail(&pp->c, NULL, GG_ERROR_PARSE, "the format needs its version (1.0)");
    if (gg_parse_number(w, w + n, &v) != w + n || v != 1)
        return hfail(pp, w, "unsupported format version '%s' (PLY defines 1.0)", w, n);
    pp->has_format = true;
    return gg_lc_end(&pp->c);
}

static int header(plyp *pp)
{
    const char *w;
    size_t n;
    int rc = GG_OK;
    n = gg_lc_word(&pp->c, &w);
    if (!is(w, n, "ply") || gg_lc_end(&pp->c) != GG_OK)
        return gg_error_set(pp->err, GG_ERROR_PARSE, "%s: not a PLY file (no 'ply' line)",
                            pp->name);
    for (gg_lc_next_line(&pp->c); rc == GG_OK; gg_lc_next_line(&pp->c)) {
        const char *at;
        if (pp->c.p >= pp->c.end)
            return gg_lc_fail(&pp->c, NULL, GG_ERROR_PARSE, "the header has no end_header line");
        gg_lc_blank(&pp->c), at = pp->c.p;
        n = gg_lc_word(&pp->c, &w);
        if (is(w, n, "end_header") && !pp->has_format)
            return gg_lc_fail(&pp->c, at, GG_ERROR_PARSE,
                              "the header has no format line (format ascii 1.0, "
                              "binary_little_endian 1.0 or binary_big_endian 1.0)");
        if (is(w, n, "end_header")) return gg_lc_end(&pp->c);
        if (is(w, n, "format") && (pp->has_format || pp->nel)) {
            /* the elements' types depend on it: one, before them */
            return gg_lc_fail(&pp->c, at, GG_ERROR_PARSE, "%s",
                              pp->has_format ? "a second format line"
                                             : "the format line must come before the elements");
        } else if (is(w, n, "format")) {
            rc = format(pp);
        } else if (is(w, n, "element")) {
            rc = element(pp);
        } else if (is(w, n, "property")) {
            rc = property(pp);
        } else {
            /* comment, obj_info, and lines no reader defines (Blender 2.47
               wrote "Created by ..." without "comment") */
            if (n && !is(w, n, "comment") && !is(w, n, "obj_info")) pp->mb->b.m.ignored++;
            gg_lc_rest(&pp->c, &w);
        }
    }
    return rc;
}

/* ---- the body ---- */

static int bfail(plyp *pp, int code, const char *fmt, ...) GG_PRINTF(3, 4);

/* Progress at the parser's byte (binary or ascii), every MiB; a cancel
   fails at the element reached. */
#define PROGRESS(pp)                                                                               \
    (gg_mb_progress((pp)->mb,                                                                      \
                    (pp)->fmt ? (size_t)((pp)->p - (pp)->data)                                     \
                              : (size_t)((const unsigned char *)(pp)->c.p - (pp)->data),           \
                    0)                                                                             \
         ? bfail(pp, GG_ERROR_CANCELLED, "loading cancelled")                                      \
         : GG_OK)

static int bfail(plyp *pp, int code, const char *fmt, ...)
{
    char msg[300];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (pp->fmt == 0)
        return gg_lc_fail(&pp->c, NULL, code, "%s %llu: %s", pp->what, pp->index, msg);
    return gg_error_set(pp->err, code, "%s: byte %zu (%s %llu): %s", pp->name,
                        (size_t)(pp->p - pp->data), pp->what, pp->index, msg);
}

/* An element's count cannot be: in ascii at the count in the header (the
   body's place was the end of the elements before), in binary at the byte
   where the element would start, as its element 0 (the index was the
   previous element's count). */
static int cfail(plyp *pp, const pelem *e, int code, const char *fmt, ...) GG_PRINTF(4, 5);
static int cfail(plyp *pp, const pelem *e, int code, const char *fmt, ...)
{
    char msg[300];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    pp->index = 0;
    if (pp->fmt == 0)
        return gg_error_set(pp->err, code, "%s:%d:%d: %s", pp->name, e->line, e->col, msg);
    return bfail(pp, code, "%s", msg);
}

static bool host_little(void)
{
    const uint16_t one = 1;
    unsigned char b;
    memcpy(&b, &one, 1);
    return b == 1;
}

/* Decode one binary value of `type` at p (bounds already checked). */
static inline double decode(const unsigned char *p, int type, bool swap)
{
    unsigned char b[8];
    int n = type_size(type), i;
    if (!swap && type == T_F32) {
        float v;
        memcpy(&v, p, 4);
        return v;
    }
    if (swap)
        for (i = 0; i < n; i++) b[i] = p[n - 1 - i];
    else
        memcpy(b, p, (size_t)n);
    switch (type) {
    case T_I8:
        return (double)(int8_t)b[0];
    case T_U8:
        return (double)b[0];
    case T_I16: {
        int16_t v;
        memcpy(&v, b, 2);
        return v;
    }
    case T_U16: {
        uint16_t v;
        memcpy(&v, b, 2);
        return v;
    }
    case T_I32: {
        int32_t v;
        memcpy(&v, b, 4);
        return v;
    }
    case T_U32: {
        uint32_t v;
        memcpy(&v, b, 4);
        return v;
    }
    case T_F32: {
        float v;
        memcpy(&v, b, 4);
        return v;
    }
    default: {
        double v;
        memcpy(&v, b, 8);
        return v;
    }
    }
}

/* At the end of an ascii line (after gg_lc_blank, which leaves only a
   \r that ends a line): '#' is no comment in a PLY body. */
static bool at_eol(const gg_lc *c)
{
    return c->p >= c->end || *c->p == '\n' || *c->p == '\r';
}

/* Whether an ascii value (the text w[0..n)) fits its declared type, as
   a binary file's bytes always do: `property uchar x` took 300 and -5. */
static int ascii_range(plyp *pp, int type, double d, const char *w, size_t n)
{
    static const struct {
        const char *name;
        double lo, hi;
    } r[] = {{"", 0, 0},
             {"char", -128, 127},
             {"uchar", 0, 255},
             {"short", -32768, 32767},
             {"ushort", 0, 65535},
             {"int", -2147483648.0, 2147483647.0},
             {"uint", 0, 4294967295.0},
             {"float", -FLT_MAX, FLT_MAX},
             {"double", -DBL_MAX, DBL_MAX}};
    char b[100];
    if (type == T_F32 || type == T_F64) {
        if (!(fabs(d) > r[type].hi)) return GG_OK; /* NaN is the caller's */
        return bfail(pp, GG_ERROR_PARSE, "%s is beyond the range of a float (+-%.9g)",
                     gg_lc_show(w, n, b, sizeof b), FLT_MAX);
    }
    if (d == floor(d) && d >= r[type].lo && d <= r[type].hi) return GG_OK;
    return bfail(pp, GG_ERROR_PARSE, "a%s %s must be a whole number from %.0f to %.0f, got %s",
                 type == T_I32 ? "n" : "", r[type].name, r[type].lo, r[type].hi,
                 gg_lc_show(w, n, b, sizeof b));
}

/* The next value of the body; NaN and infinity are passed on (the caller
   decides whether they matter). */
static int value(plyp *pp, int type, double *out)
{
    if (pp->fmt) {
        int n = type_size(type);
        if ((size_t)(pp->end - pp->p) < (size_t)n)
            return bfail(pp, GG_ERROR_PARSE, "the file ends here (truncated)");
        *out = decode(pp->p, type, pp->swap);
        pp->p += n;
        return GG_OK;
    }
    /* ascii: an element is one line (ascii_end), its values separated by
       blanks */
    gg_lc_blank(&pp->c);
    if (pp->c.p >= pp->c.end) return bfail(pp, GG_ERROR_PARSE, "the file ends here (truncated)");
    if (at_eol(&pp->c))
        return bfail(pp, GG_ERROR_PARSE, "expected a number, got the end of the line");
    {
        const char *q = gg_parse_number(pp->c.p, pp->c.end, out);
        if (!q || (q < pp->c.end && *q != ' ' && *q != '\t' && *q != '\r' && *q != '\n'))
            return bfail(pp, GG_ERROR_PARSE, "expected a number");
        if (ascii_range(pp, type, *out, pp->c.p, (size_t)(q - pp->c.p)) != GG_OK)
            return GG_ERROR_PARSE;
        pp->c.p = q;
    }
    return GG_OK;
}

/* After an ascii element: nothing else on its line, then the next line
   (LF, CRLF or a lone CR). Values used to run on across lines, so a short
   line took the next one's values and a long one's rest began the next
   element. */
static int ascii_end(plyp *pp)
{
    char b[100];
    const char *q;
    if (pp->fmt) return GG_OK;
    gg_lc_blank(&pp->c);
    if (!at_eol(&pp->c)) {
        for (q = pp->c.p; q < pp->c.end && *q != ' ' && *q != '\t' && *q != '\r' && *q != '\n'; q++)
            ;
        return bfail(pp, GG_ERROR_PARSE, "expected the end of the line, got '%s'",
                     gg_lc_show(pp->c.p, (size_t)(q - pp->c.p), b, sizeof b));
    }
    gg_lc_next_line(&pp->c);
    return GG_OK;
}

/* Skip n values of `type` (a list nobody reads). */
static int skip(plyp *pp, int type, double n)
{
    double d;
    int rc = GG_OK;
    if (pp->fmt) {
        double bytes = n * type_size(type);
        if (bytes > (double)(pp->end - pp->p))
            return bfail(pp, GG_ERROR_PARSE, "the file ends inside a list (truncated)");
        pp->p += (size_t)bytes;
        return GG_OK;
    }
    for (; n > 0 && rc == GG_OK; n--) rc = value(pp, type, &d);
    return rc;
}

/* A list's length: a whole number in [0, GG_MB_MAX_POLY]. */
static int list_count(plyp *pp, const pprop *p, double *n)
{
    int rc;
    if (pp->fmt && p->ctype == T_U8 && pp->p < pp->end) { /* the common case */
        *n = *pp->p++;
        return GG_OK;
    }
    rc = value(pp, p->ctype, n);
    if (rc == GG_OK && !(*n >= 0 && *n <= GG_MB_MAX_POLY))
        return bfail(pp, GG_ERROR_LIMIT, "a list of %.0f items (the limit is %u)", *n,
                     GG_MB_MAX_POLY);
    return rc;
}

/* The properties ggrt reads from a vertex: x y z, nx ny nz, u v. */
enum { W_X, W_Y, W_Z, W_NX, W_NY, W_NZ, W_U, W_V, W_N };

static void vertex_props(const pelem *e, int w[W_N])
{
    static const char *const names[][4] = {{"x"},
                                           {"y"},
                                           {"z"},
                                           {"nx"},
                                           {"ny"},
                                           {"nz"},
                                           {"u", "s", "texture_u", "texture_s"},
                                           {"v", "t", "texture_v", "texture_t"}};
    int k, i, j;
    for (k = 0; k < W_N; k++) {
        w[k] = -1;
        for (i = 0; i < e->np && w[k] < 0; i++)
            for (j = 0; j < 4 && names[k][j]; j++)
                if (!e->p[i].ctype && is(e->p[i].nm, e->p[i].nn, names[k][j])) w[k] = i;
    }
}

/* Bytes one instance of e takes at least (its lists empty). */
static double min_bytes(const pelem *e)
{
    double b = 0;
    int k;
    for (k = 0; k < e->np; k++) b += type_size(e->p[k].ctype ? e->p[k].ctype : e->p[k].type);
    return b;
}

/* A count the rest of the file cannot hold is a truncated file: said
   before anything is allocated for it. */
static int plausible(plyp *pp, const pelem *e)
{
    double left = pp->fmt ? (double)(pp->end - pp->p) : (double)(pp->c.end - pp->c.p);
    double need = (double)e->count * (pp->fmt ? min_bytes(e) : 2.0 * e->np);
    /* ascii: the last value may end the file without a separator */
    if (need <= left + (pp->fmt ? 0 : 1)) return GG_OK;
    return cfail(pp, e, GG_ERROR_PARSE,
                 "%llu %.*s elements need at least %.0f bytes, %.0f are left "
                 "(truncated or a bad count)",
                 e->count, (int)e->nn, e->nm, need, left);
}

/* Binary vertices of fixed size (no list property): each property at its
   offset, straight from the bytes. */
static int fixed_vertices(plyp *pp, const pelem *e, const int w[W_N], bool has_n, bool has_uv)
{
    gg_mb *mb = pp->mb;
    size_t off[PLY_MAX_PROPS], stride = 0;
    int k, rc;
    for (k = 0; k < e->np; k++) off[k] = stride, stride += (size_t)type_size(e->p[k].type);
    if ((double)stride * (double)e->count > (double)(pp->end - pp->p))
        return bfail(pp, GG_ERROR_PARSE, "the file ends inside the vertices (truncated)");
    if (gg_mb_reserve(mb, (size_t)e->count, has_n, has_uv, 0))
        return bfail(pp, GG_ERROR_NOMEM, "out of memory");
    for (pp->index = 0; pp->index < e->count; pp->index++, pp->p += stride) {
        const unsigned char *b = pp->p;
        ggVec3 p, nv;
        double uv[2];
#define GET(i) decode(b + off[w[i]], e->p[w[i]].type, pp->swap)
        p = v3(GET(W_X), GET(W_Y), GET(W_Z));
        if (has_n) nv = v3(GET(W_NX), GET(W_NY), GET(W_NZ));
        if (has_uv) uv[0] = GET(W_U), uv[1] = 1 - GET(W_V);
#undef GET
        if (!v3finite(p) || (has_n && !v3finite(nv)) ||
            (has_uv && !(isfinite(uv[0]) && isfinite(uv[1]))))
            return bfail(pp, GG_ERROR_PARSE,
                         "a coordinate, normal or texture coordinate is not finite");
        if (gg_mb_vertex(mb, p, has_n ? &nv : NULL, has_uv ? uv : NULL))
            return bfail(pp, GG_ERROR_NOMEM, "out of memory");
        if ((rc = PROGRESS(pp)) != GG_OK) return rc;
    }
    return GG_OK;
}

static int vertices(plyp *pp, const pelem *e)
{
    gg_mb *mb = pp->mb;
    int w[W_N], k, rc = GG_OK;
    double val[PLY_MAX_PROPS], n;
    bool has_n, has_uv;
    vertex_props(e, w);
    if (w[W_X] < 0 || w[W_Y] < 0 || w[W_Z] < 0)
        return bfail(pp, GG_ERROR_PARSE, "the vertex element has no x, y and z properties");
    if (e->count >= GG_MESH_MAX) return cfail(pp, e, GG_ERROR_LIMIT, "more than 2^28 vertices");
    if ((rc = plausible(pp, e)) != GG_OK) return rc;
    has_n = w[W_NX] >= 0 && w[W_NY] >= 0 && w[W_NZ] >= 0;
    has_uv = w[W_U] >= 0 && w[W_V] >= 0;
    for (k = 0; k < e->np && !e->p[k].ctype; k++)
        ;
    if (pp->fmt && k == e->np) {
        if ((rc = fixed_vertices(pp, e, w, has_n, has_uv)) == GG_OK)
            mb->b.m.file_vertices = e->count;
        return rc;
    }
    for (pp->index = 0; pp->index < e->count; pp->index++) {
        ggVec3 p, nv;
        double uv[2];
        for (k = 0; k < e->np && rc == GG_OK; k++)
            if (!e->p[k].ctype)
                rc = value(pp, e->p[k].type, &val[k]);
            else if ((rc = list_count(pp, &e->p[k], &n)) == GG_OK)
                rc = skip(pp, e->p[k].type, n);
        if (rc != GG_OK || (rc = ascii_end(pp)) != GG_OK) return rc;
        p = v3(val[w[W_X]], val[w[W_Y]], val[w[W_Z]]);
        if (has_n) nv = v3(val[w[W_NX]], val[w[W_NY]], val[w[W_NZ]]);
        if (has_uv) uv[0] = val[w[W_U]], uv[1] = 1 - val[w[W_V]];
        if (!v3finite(p) || (has_n && !v3finite(nv)) ||
            (has_uv && !(isfinite(uv[0]) && isfinite(uv[1]))))
            return bfail(pp, GG_ERROR_PARSE,
                         "a coordinate, normal or texture coordinate is not finite");
        if (gg_mb_vertex(mb, p, has_n ? &nv : NULL, has_uv ? uv : NULL))
            return bfail(pp, GG_ERROR_NOMEM, "out of memory");
        if ((rc = PROGRESS(pp)) != GG_OK) return rc;
    }
    mb->b.m.file_vertices = e->count;
    return GG_OK;
}

static int face_indices(plyp *pp, const pprop *p, size_t *n)
{
    const size_t nv = pp->mb->b.m.nverts;
    double c, d;
    size_t j;
    int rc = list_count(pp, p, &c);
    if (rc != GG_OK) return rc;
    if ((size_t)c + 1 > pp->cap_corner &&
        gg_mem_grow(pp->mb->a, (void **)&pp->corner, &pp->cap_corner, (size_t)c + 1,
                    sizeof *pp->corner))
        return bfail(pp, GG_ERROR_NOMEM, "out of memory");
    if (pp->fmt && (p->type == T_I32 || p->type == T_U32) && !pp->swap) {
        /* the common case, decoded without going through double */
        if ((size_t)(pp->end - pp->p) < 4 * (size_t)c)
            return bfail(pp, GG_ERROR_PARSE,
                         "the file ends inside this list of %.0f indices (truncated)", c);
        for (j = 0; j < (size_t)c; j++, pp->p += 4) {
            uint32_t u;
            memcpy(&u, pp->p, 4);
            if ((p->type == T_I32 && (int32_t)u < 0) || u >= nv)
                return bfail(pp, GG_ERROR_PARSE,
                             "vertex index %.17g is out of range (%zu vertices)",
                             p->type == T_I32 ? (double)(int32_t)u : (double)u, nv);
            pp->corner[j] = u;
        }
        *n = (size_t)c;
        return GG_OK;
    }
    for (j = 0; j < (size_t)c; j++) {
        const unsigned char *at = pp->p;
        const char *cat;
        if ((rc = value(pp, p->type, &d)) != GG_OK) return rc;
        if (!(d >= 0 && d < (double)nv) || d != (double)(size_t)d) {
            /* the message points at the index itself */
            cat = pp->c.p;
            while (!pp->fmt && cat > pp->c.ls && cat[-1] != ' ' && cat[-1] != '\t') cat--;
            pp->p = at, pp->c.p = cat;
            return bfail(pp, GG_ERROR_PARSE, "vertex index %.17g is out of range (%zu vertices)", d,
                         nv);
        }
        pp->corner[j] = (uint32_t)d;
    }
    *n = (size_t)c;
    return GG_OK;
}

static int faces(plyp *pp, const pelem *e, bool have_vertices)
{
    gg_mb *mb = pp->mb;
    int li = -1, k, rc;
    double d;
    for (k = 0; k < e->np && li < 0; k++)
        if (e->p[k].ctype && (is(e->p[k].nm, e->p[k].nn, "vertex_indices") ||
                              is(e->p[k].nm, e->p[k].nn, "vertex_index")))
            li = k;
    if (li < 0) return bfail(pp, GG_ERROR_PARSE, "the face element has no vertex_indices list");
    if (!have_vertices)
        return bfail(pp, GG_ERROR_UNSUPPORTED, "faces before the vertex element are not supported");
    if (e->count >= GG_MESH_MAX) return cfail(pp, e, GG_ERROR_LIMIT, "more than 2^28 faces");
    if ((rc = plausible(pp, e)) != GG_OK) return rc;
    if (gg_mb_reserve(mb, 0, false, false, (size_t)e->count))
        return bfail(pp, GG_ERROR_NOMEM, "out of memory");
    for (pp->index = 0; pp->index < e->count; pp->index++) {
        size_t n = 0;
        for (k = 0, rc = GG_OK; k < e->np && rc == GG_OK; k++)
            if (k == li)
                rc = face_indices(pp, &e->p[k], &n);
            else if (!e->p[k].ctype)
                rc = value(pp, e->p[k].type, &d);
            else if ((rc = list_count(pp, &e->p[k], &d)) == GG_OK)
                rc = skip(pp, e->p[k].type, d);
        if (rc != GG_OK || (rc = ascii_end(pp)) != GG_OK) return rc;
        if (mb->b.m.ntri + n >= GG_MESH_MAX)
            return bfail(pp, GG_ERROR_LIMIT, "more than 2^28 triangles");
        if (gg_mb_face(mb, pp->corner, n, -1, 1)) return bfail(pp, GG_ERROR_NOMEM, "out of memory");
        if ((rc = PROGRESS(pp)) != GG_OK) return rc;
    }
    return GG_OK;
}

/* After the last ascii element: blank lines at most. Lines beyond the
   header's counts (a second face where it declares one) were dropped. */
static int ascii_rest(plyp *pp)
{
    char b[100];
    const char *q;
    for (; pp->c.p < pp->c.end; gg_lc_next_line(&pp->c)) {
        gg_lc_blank(&pp->c);
        if (at_eol(&pp->c)) continue;
        for (q = pp->c.p; q < pp->c.end && *q != ' ' && *q != '\t' && *q != '\r' && *q != '\n'; q++)
            ;
        return gg_lc_fail(&pp->c, NULL, GG_ERROR_PARSE,
                          "'%s': more lines than the header's element counts declare",
                          gg_lc_show(pp->c.p, (size_t)(q - pp->c.p), b, sizeof b));
    }
    return GG_OK;
}

/* After the last binary element: whitespace at most (a writer's closing
   newline). Anything else means the header's counts are short of the
   data, which was dropped without a word. */
static int binary_rest(plyp *pp)
{
    const unsigned char *q;
    for (q = pp->p; q < pp->end; q++)
        if (*q != '\n' && *q != '\r' && *q != ' ' && *q != '\t')
            return gg_error_set(pp->err, GG_ERROR_PARSE,
                                "%s: byte %zu: %zu bytes after the elements the header declares",
                                pp->name, (size_t)(pp->p - pp->data), (size_t)(pp->end - pp->p));
    return GG_OK;
}

/* An element ggrt does not read. */
static int skip_element(plyp *pp, const pelem *e)
{
    double d;
    int k, rc = plausible(pp, e);
    for (pp->index = 0; rc == GG_OK && pp->index < e->count && e->np; pp->index++) {
        for (k = 0; k < e->np && rc == GG_OK; k++)
            if (!e->p[k].ctype)
                rc = value(pp, e->p[k].type, &d);
            else if ((rc = list_count(pp, &e->p[k], &d)) == GG_OK)
                rc = skip(pp, e->p[k].type, d);
        if (rc == GG_OK) rc = ascii_end(pp);
    }
    pp->mb->b.m.ignored += e->count;
    return rc;
}

int gg_ply_read(gg_mb *mb, const unsigned char *data, size_t len, const char *name, ggError *err)
{
    plyp *pp = gg_mem_calloc(mb->a, 1, sizeof *pp);
    bool have_v = false, have_f = false;
    int i, rc;
    if (!pp) return gg_error_set(err, GG_ERROR_NOMEM, "%s: out of memory", name);
    pp->mb = mb, pp->name = name, pp->err = err, pp->data = data, pp->end = data + len;
    gg_lc_init(&pp->c, (const char *)data, len, name, err);
    rc = header(pp);
    pp->swap = (pp->fmt == 1) != host_little();
    if (rc == GG_OK) {
        gg_lc_next_line(&pp->c);
        pp->p = (const unsigned char *)pp->c.p;
    }
    for (i = 0; rc == GG_OK && i < pp->nel; i++) {
        const pelem *e = &pp->el[i];
        if (is(e->nm, e->nn, "vertex") && !have_v) {
            pp->what = "vertex", rc = vertices(pp, e), have_v = true;
        } else if (is(e->nm, e->nn, "face") && !have_f) {
            pp->what = "face", rc = faces(pp, e, have_v), have_f = true;
        } else {
            pp->what = "element", rc = skip_element(pp, e);
        }
    }
    if (rc == GG_OK) rc = pp->fmt ? binary_rest(pp) : ascii_rest(pp);
    if (rc == GG_OK && !mb->b.m.nfaces)
        rc = gg_error_set(err, GG_ERROR_PARSE, "%s: no faces (%zu vertices: a point cloud?)", name,
                          mb->b.m.nverts);
    gg_mem_free(mb->a, pp->corner);
    gg_mem_free(mb->a, pp);
    return rc;
}
