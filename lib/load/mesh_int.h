/* SPDX-License-Identifier: MIT */
/*
** mesh_int.h -- what the mesh readers (obj.c, mtl.c, ply.c) share: a mesh
** being read (gg_mb: growing arrays, polygons split into triangles,
** interned names), a correctly rounded decimal number parser, and the file
** reading (private to lib/load: docs/internals.md, "Headers").
*/
#ifndef GG_LOAD_MESH_INT_H
#define GG_LOAD_MESH_INT_H

#include "load.h"
#include "scene.h"

/* Largest polygon a file may hold (corners), and the largest split by ear
   clipping (beyond it, a fan: clipping costs the square of the count). */
#define GG_MB_MAX_POLY (1u << 20)
#define GG_MB_MAX_CLIP 1024
/* Largest mesh file read. */
#define GG_MESH_MAX_FILE ((size_t)1 << 32)

/* Interned names: each distinct string once, looked up by hash. */
typedef struct gg_names {
    char **s; /* the names, in order of first use */
    size_t n, cap;
    uint32_t *tab; /* open addressing: index + 1, 0 empty */
    size_t tcap;
    uint64_t seed; /* gg_hash_seed of tab (core.h: why) */
} gg_names;

/* A mesh being read. Faces are added in file order; a face's triangles
   remember its index (tface), the reader's per-face data go in the face
   columns. */
typedef struct gg_mb {
    const ggAllocator *a;
    gg_mesh_build b;
    size_t cap_pos, cap_nrm, cap_uv, cap_vnrm, cap_idx, cap_tface, cap_tmat, cap_tsm;
    size_t cap_fline, cap_fgroup, cap_fmtl, cap_libs;
    gg_names groups, mtls;
    /* scratch for splitting polygons */
    uint32_t *ring;
    double (*q)[2];
    int *next, *prev;
    uint8_t *ear;
    size_t cap_ring;
    /* The file's bytes read (ggSceneSetProgress): its size, and the
       position last reported. */
    gg_progress prog;
    size_t len, told;
} gg_mb;

void gg_mb_init(gg_mb *mb, const ggAllocator *a, int format);
/* Report that the parser is at byte `at` of the file: every MiB, or now
   with force. Non-zero when the scene's progress callback asked to stop
   (the parser then fails with GG_ERROR_CANCELLED, "loading cancelled").
   Inline: parsers call it per line or element. */
int gg_mb_report(gg_mb *mb, size_t at);
static inline int gg_mb_progress(gg_mb *mb, size_t at, int force)
{
    if (!mb->prog.fn || (!force && at - mb->told < ((size_t)1 << 20))) return 0;
    return gg_mb_report(mb, at);
}
void gg_mb_free(gg_mb *mb);
/* Append a vertex (position, and optional normal / uv: NULL for none).
   Returns 0, or -1 when out of memory. */
int gg_mb_vertex(gg_mb *mb, ggVec3 p, const ggVec3 *n, const double *uv);
/* Make room for nverts more vertices (with normals, uv) and ntri more
   triangles, so that appending them does not reallocate: for counts a
   file has declared and shown it can hold. -1 when out of memory. */
int gg_mb_reserve(gg_mb *mb, size_t nverts, bool nrm, bool uv, size_t ntri);
/* Append face number mb->b.m.nfaces (then counted) with n corners v[],
   split into triangles; repeated neighbouring corners are merged first,
   and a face left with fewer than 3 is counted as skipped. mat: scene
   material or -1; smooth: OBJ smoothing group (1 unless the file says).
   Returns 0, or -1 when out of memory. */
int gg_mb_face(gg_mb *mb, const uint32_t *v, size_t n, int mat, uint32_t smooth);
/* Per-face columns for the face just added (OBJ). */
int gg_mb_face_line(gg_mb *mb, uint32_t line);
int gg_mb_face_names(gg_mb *mb, uint32_t group, uint32_t mtl);

/* Intern name[0..len) (copied); *id receives its index. -1: no memory. */
int gg_names_add(const ggAllocator *a, gg_names *t, const char *name, size_t len, uint32_t *id);
void gg_names_free(const ggAllocator *a, gg_names *t);

/* Parse a decimal number at p (< end): optional sign, digits with an
   optional point, optional exponent; no nan, inf or hex. Correctly
   rounded (Clinger's fast path, else gg_strtod_c). Returns the end
   of the number, or NULL if there is none or it is not finite. */
const char *gg_parse_number(const char *p, const char *end, double *out);
/* A decimal integer with optional sign, within [lo, hi]; NULL if not. */
const char *gg_parse_long(const char *p, const char *end, long lo, long hi, long *out);

/* A cursor over line-based text (OBJ, MTL, ascii PLY headers): lines end
   at \n (a \r before it is blank), a backslash at the end of a line joins
   the next one, and errors name the place as "name:line:col". */
typedef struct gg_lc {
    const char *p, *end;
    const char *ls; /* start of the current line, for columns */
    int line;
    const char *name;
    ggError *err;
} gg_lc;

void gg_lc_init(gg_lc *c, const char *text, size_t len, const char *name, ggError *err);
/* Reject UTF-16 (a byte-order mark) and NUL bytes; skip a UTF-8 BOM. */
int gg_lc_check_text(gg_lc *c);
/* Skip spaces, tabs, \r and line continuations. */
void gg_lc_blank(gg_lc *c);
/* At the end of the line's data: end of text, \n, or a # comment. */
bool gg_lc_eol(const gg_lc *c);
/* Past the end of the current line. */
void gg_lc_next_line(gg_lc *c);
/* A run of characters up to a blank or the end of the line (after
   skipping blanks); its length, 0 at the end of the line. */
size_t gg_lc_word(gg_lc *c, const char **w);
/* The rest of the line up to a '#' at its start or after a blank (a
   comment; a '#' inside a word is kept: `usemtl a#1`), without
   surrounding blanks: the names of o, g, usemtl, mtllib, newmtl, map_Kd. */
size_t gg_lc_rest(gg_lc *c, const char **s);
/* A number followed by a blank or the end of the line; else an error
   ("expected %s"). */
int gg_lc_number(gg_lc *c, double *d, const char *what);
/* Nothing but blanks or a comment before the end of the line; else an
   error naming what follows. */
int gg_lc_end(gg_lc *c);
/* "name:line:col: message" for position `at` (NULL: the cursor). */
int gg_lc_fail(const gg_lc *c, const char *at, int code, const char *fmt, ...) GG_PRINTF(4, 5);
/* A printable copy of w[0..n) for messages: its first 40 bytes through
   gg_text_escape (core.h), as every message of the library shows bytes. */
const char *gg_lc_show(const char *w, size_t n, char *buf, size_t size);


/* The folder part of path ("dir/" or ""), allocated. */
char *gg_load_dirname(const ggAllocator *a, const char *path);

/* ---- the readers ---- */

/* Where an OBJ's materials come from (mtl.c). */
typedef struct gg_mtl_entry {
    char *name;
    ggMaterial mat;
    char *map_kd; /* texture file as written (resolved later), or NULL */
    int wrap;     /* GG_WRAP_* for map_Kd */
    char *where;  /* "file.mtl:LINE" of the newmtl, for warnings */
    int material; /* scene material once added, else -1 */
} gg_mtl_entry;

typedef struct gg_mtl_lib {
    gg_mtl_entry *e;
    size_t n, cap;
    size_t ignored; /* statements read and not used */
} gg_mtl_lib;

/* Parse MTL text into lib (later definitions of a name win); textures are
   named relative to dir. */
int gg_mtl_parse(const ggAllocator *a, gg_mtl_lib *lib, const char *text, size_t len,
                 const char *name, const char *dir, ggError *err);
void gg_mtl_free(const ggAllocator *a, gg_mtl_lib *lib);

/* Warnings collected while reading, for ggMeshInfo. */
void gg_mb_warn(gg_mb *mb, const char *fmt, ...) GG_PRINTF(2, 3);

/* OBJ text -> builder. dir: folder for mtllib (NULL: do not read files). */
int gg_obj_read(ggScene *s, gg_mb *mb, const char *text, size_t len, const char *name,
                const char *dir, const ggMeshOptions *o, ggError *err);
/* PLY bytes -> builder. */
int gg_ply_read(gg_mb *mb, const unsigned char *data, size_t len, const char *name, ggError *err);

#endif
