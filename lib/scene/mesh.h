/* SPDX-License-Identifier: MIT */
/*
** mesh.h -- triangle meshes inside a scene (internal; included by
** scene.h). A mesh keeps its vertices and triangles once; each material
** it uses is one scene object (kind GG_SHAPE_MESH) over a run of its
** triangles, which are stored grouped by object. What the file said about
** each triangle (face index, line, group and material names) is kept
** beside it for reports.
**
** The readers (lib/load) fill a gg_mesh_build; gg_scene_add_mesh_build
** places it (transform), drops zero-area triangles, works out normals and
** splits it into objects by material.
*/
#ifndef GG_LIB_MESH_H
#define GG_LIB_MESH_H

/* Largest mesh: triangles and vertices each (the BVH holds 2^28 elements). */
#define GG_MESH_MAX (1u << 28)
/* Computed normals: at a vertex shared by more faces than this the faces
   are shaded flat there (the crease test is quadratic in the count). */
#define GG_MESH_MAX_SMOOTH 128

typedef struct gg_mesh {
    char *name;
    int format;        /* GG_MESH_FORMAT_OBJ or _PLY; 0 for a mesh built in code */
    ggVec3 *pos, *nrm; /* nverts each; nrm unit (zero: none at that corner) or NULL */
    double *uv;        /* 2 per vertex, or NULL */
    size_t nverts;
    uint32_t *idx; /* 3 per triangle, the triangles of each object together */
    size_t ntri;
    uint32_t *tface;  /* per triangle: the face it comes from; NULL: face = triangle */
    size_t nfaces;    /* faces in the file (the per-face arrays' length) */
    uint32_t *fline;  /* per face: its line in the file, or NULL */
    uint32_t *fgroup; /* per face: index in groups, or NULL (all 0) */
    uint32_t *fmtl;   /* per face: index in mtlnames, or NULL (all 0) */
    char **groups;    /* ngroups names ("" allowed) */
    size_t ngroups;
    char **mtlnames;
    size_t nmtlnames;
    size_t file_vertices, skipped, ignored;
    int first_object, nobjects;
    bool file_normals;
    ggVec3 lo, hi;
    int nwarn;
    char *warning; /* the first warning, or NULL */
    /* The file read (lib/load/mesh_load.c): device and inode, whatever the
       path's spelling; repeat: an earlier mesh of the scene is that file. */
    uint64_t file_dev, file_ino;
    bool has_file, repeat;
    char **libs; /* the MTL files an OBJ read (paths as resolved), for ggSceneInputFile */
    size_t nlibs;
} gg_mesh;

/* What a reader hands over: the mesh in file order, plus per-triangle
   data used while it is placed. */
typedef struct gg_mesh_build {
    gg_mesh m;
    int *tmat;         /* per triangle: scene material, -1 for none given; NULL: none */
    uint32_t *tsmooth; /* per triangle: OBJ smoothing group, 0 = off (flat); NULL: all one */
    uint8_t *vnrm;     /* per vertex: 1 where m.nrm holds the file's normal; NULL: all */
} gg_mesh_build;

/* Free everything a mesh or a builder holds (and zero it). */
void gg_mesh_free(const ggAllocator *a, gg_mesh *m);
void gg_mesh_build_free(const ggAllocator *a, gg_mesh_build *b);

/* Place a builder's mesh in the scene: its objects get source line
   `line` (0: none). Takes everything b holds (b is emptied, also on
   failure). Returns the mesh index, or -status with err set; on failure
   the scene holds what it held before (apart from spare capacity). */
int gg_scene_add_mesh_build(ggScene *s, gg_mesh_build *b, const ggMeshOptions *o, int line,
                            ggError *err);

/* Remove the meshes after the first n (their objects are the caller's to
   remove). */
void gg_scene_drop_meshes(ggScene *s, size_t n);
/* The first mesh of s read from the file (dev, ino), or NULL. */
const gg_mesh *gg_scene_mesh_by_file(const ggScene *s, uint64_t dev, uint64_t ino);
/* A mesh's own records (struct, name, objects, the top tree's entries),
   in triangles' worth: 20,000 one-triangle meshes took 1.5 KB each. */
#define GG_MESH_REPEAT_RECORD 8
/* What mesh m costs when a file is named again, in triangles: its own,
   GG_MESH_REPEAT_RECORD more for the mesh's records, and one per 256
   bytes of its group and material names (GG_MESH_REPEAT_MAX). */
uint64_t gg_mesh_repeat_cost(const gg_mesh *m);

/* Angle-weighted vertex normals with creases (mesh_normals.c): computes a
   normal for every corner whose vertex has none from the file (all of them
   when b->vnrm is NULL and b->m.nrm is NULL), splitting vertices whose
   corners end up with different normals. b->m.nrm is allocated when
   missing. Returns GG_OK, or GG_ERROR_NOMEM / GG_ERROR_LIMIT with b
   half done (the caller frees it). */
int gg_mesh_compute_normals(const ggAllocator *a, gg_mesh_build *b, double crease_deg);

/* The mesh triangle behind a hit on primitive `prim` of mesh object o,
   or -1 when o is not a mesh. */
long gg_scene_hit_triangle(const ggScene *s, const gg_object *o, uint32_t prim);

#endif
