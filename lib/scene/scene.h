/* SPDX-License-Identifier: MIT */
/*
** scene.h -- the scene's insides, shared by the loader, the effect
** analysis and the renderer (internal).
**
** Objects are kept as the user described them (shape parameters, material,
** defining line); ggScenePrepare turns them into primitives in a gg_geom
** and works out the effect set. Keeping the description lets the scene be
** reported (`ggrt info`, the ray tree) in the user's own terms.
*/
#ifndef GG_LIB_SCENE_H
#define GG_LIB_SCENE_H

#include "geom.h"

typedef struct gg_object {
    int kind;     /* ggShapeKind */
    int material;
    int line, col; /* where the scene file defined it (0 from code) */
    /* Shape parameters; which ones are used depends on kind. */
    ggVec3 a, b, c;   /* sphere: a = centre; cone: a = base, b = apex; rect: a, b, c */
    double ra, rb;    /* sphere: ra = radius; cone: ra = base radius, rb = apex radius */
    size_t vfirst;    /* polygon/triangle: first vertex in the scene's vertex pool */
    int nverts;
    bool has_normals; /* triangle from pp: normals pool parallel to vertices */
    ggImplicit *imp;  /* implicit: owned */
    int mesh;         /* mesh part: the mesh's index, and its triangles */
    size_t tri_first, ntri; /* tri_first .. tri_first + ntri - 1 of that mesh */
} gg_object;

#include "mesh.h"

typedef struct gg_light {
    ggVec3 pos;
    ggColor color; /* r < 0: the SPD default, 1/sqrt(number of lights) */
    int line;
} gg_light;

typedef struct gg_texture {
    ggImage *img;   /* NULL for a procedural checker */
    int shared;     /* img belongs to the scene's image cache, not to this texture */
    double checker_n;
    ggColor checker_a, checker_b;
    int wrap;       /* GG_WRAP_* */
    int nearest;    /* nearest-texel sampling instead of bilinear */
} gg_texture;

/* An image file named by the scene's files, decoded once: the texture
   cache, charged to the texture budget (ggSceneSetTextureBudget). */
typedef struct gg_teximage {
    char *path; /* as the loader resolved it against the scene file's folder */
    ggImage *img;
    uint64_t id[2]; /* the file's device and inode, when has_id */
    int has_id;
} gg_teximage;

/* Resolved per-material data used while shading. */
typedef struct gg_mat_fast {
    ggColor kd_color;  /* kd * color */
    double n_r, n_g, n_b; /* index per wavelength (dispersion), else all ior */
    ggColor alpha;     /* absorption per unit of scene length */
    unsigned flags;    /* GG_MF_* */
} gg_mat_fast;

#define GG_MF_REFLECT   1u  /* ks > 0 */
#define GG_MF_TRANSMIT  2u  /* kt > 0 */
#define GG_MF_PHONG     4u  /* ks > 0 with a visible highlight */
#define GG_MF_ABSORB    8u
#define GG_MF_DISPERSE  16u
#define GG_MF_TEXTURE   32u
#define GG_MF_EMIT      64u

struct ggScene {
    const ggAllocator *alloc;
    ggAllocator alloc_copy;
    char *filename;
    ggCamera camera;
    bool has_camera;
    ggColor background, ambient;
    int depth, samples;
    ggError last;         /* what the last building call refused (ggSceneLastError) */
    ggImageReader reader; /* NULL: gg_load_default_reader() */
    ggProgressFn progress; /* loading's and preparing's (ggSceneSetProgress), or NULL */
    void *progress_ud;
    void *reader_ud;

    gg_object *objects;
    size_t nobjects, cap_objects;
    ggMaterial *materials;
    size_t nmaterials, cap_materials;
    gg_light *lights;
    size_t nlights, cap_lights;
    gg_texture *textures;
    size_t ntextures, cap_textures;
    gg_teximage *images; /* the texture cache */
    size_t nimages, cap_images;
    int64_t tex_budget, tex_used; /* bytes of decoded texels: allowed, cached */
    ggVec3 *verts, *norms; /* polygon vertex pool; norms parallel, set (and allocated) only
                              for the vertices of objects with has_normals */
    size_t nverts, cap_verts, cap_norms;
    gg_mesh *meshes;       /* mesh.c */
    size_t nmeshes, cap_meshes;
    uint64_t mesh_again;   /* gg_mesh_repeat_cost of the meshes that repeat a file */
    uint32_t *mesh_files;  /* the meshes first to read a file, by (device, inode):
                              open addressing, mesh index + 1, 0 empty */
    size_t cap_mesh_files; /* a power of two, or 0 */

    /* Valid after prepare. */
    bool prepared;
    gg_geom *geom;
    gg_mat_fast *mfast;
    ggColor *light_colors; /* resolved */
    unsigned effects;
    char *reasons[GG_EFFECT_COUNT];
    double prepare_seconds;
};

/* A scene's prepared state, set aside while a load that may fail runs
   (nff.c): the load's additions find nothing to free, a failed load puts
   it back (the scene is then prepared as it was), a load that succeeds
   drops it (the scene is unprepared, as any addition leaves it). */
typedef struct gg_prepared {
    bool prepared;
    gg_geom *geom;
    gg_mat_fast *mfast;
    ggColor *light_colors;
    unsigned effects;
    char *reasons[GG_EFFECT_COUNT];
    double prepare_seconds;
} gg_prepared;
void gg_scene_set_aside(ggScene *s, gg_prepared *p);
void gg_scene_put_back(ggScene *s, gg_prepared *p);
void gg_scene_drop_aside(ggScene *s, gg_prepared *p);

/* Append helpers (return index or -GG_ERROR_NOMEM). */
int gg_scene_push_vertices(ggScene *s, const ggVec3 *v, const ggVec3 *n, int count, size_t *first);
/* -GG_ERROR_INVALID when a coordinate or size of o (its vertices for a
   polygon or triangle, pushed before) is beyond GG_COORD_MAX. */
int gg_scene_add_object(ggScene *s, const gg_object *o);
/* Whether every coordinate of v is at most GG_COORD_MAX in magnitude
   (false for NaN). */
bool gg_scene_coord_ok(ggVec3 v);
int gg_scene_add_texture_desc(ggScene *s, const gg_texture *t);

/* What is wrong with a camera (the first problem found), for the loader's
   messages and ggCameraCheck. */
#define GG_CAMERA_OK        0
#define GG_CAMERA_NONFINITE 1 /* from, at or up is not finite */
#define GG_CAMERA_FROM_AT   2 /* from and at are (all but) the same point */
#define GG_CAMERA_UP        3 /* up is parallel to the view direction */
#define GG_CAMERA_FOV       4 /* fov_deg outside (0, 180) */
#define GG_CAMERA_SIZE      5 /* width or height outside the image limits */
#define GG_CAMERA_UP_ZERO   6 /* up is the zero vector */
int gg_camera_fault(const ggCamera *c);
const char *gg_camera_fault_text(int fault);

/* The texture cache: the image cached under path, or under the file id
   (device, inode; NULL: none) whatever the path that named it (b.png and
   ./b.png are one file, decoded and charged to the budget once), or NULL;
   cache img under path and id (the scene owns it from then on, also when
   this fails with -GG_ERROR_NOMEM); free the textures from index nt and
   the cached images from index ni on (a failed load's rollback). */
ggImage *gg_scene_image_find(const ggScene *s, const char *path, const uint64_t *id);
int gg_scene_image_add(ggScene *s, const char *path, const uint64_t *id, ggImage *img);
void gg_scene_drop_textures(ggScene *s, size_t nt, size_t ni);

/* Work out the effect set and reasons (effects.c). */
int gg_effects_compute(ggScene *s);
void gg_effects_clear(ggScene *s);

/* Shared by shading: the material's colour at a surface point. filter:
   0 as the texture says, GG_ACC_TEXTURE_BILINEAR or _NEAREST. */
ggColor gg_scene_surface_color(const ggScene *s, int material, double u, double v, int filter);

#endif
