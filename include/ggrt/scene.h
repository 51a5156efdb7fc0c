/* SPDX-License-Identifier: MIT */
/*
** ggrt/scene.h -- a scene: camera, lights, materials, objects, textures.
** Load one from NFF (the SPD format plus ggrt's extensions, see
** docs/scene-format.md) or build it in code; then render it (render.h).
**
** Threads. A scene is written by the functions that load, add, set and
** prepare, and only read by everything else. Once prepared, any number
** of threads may render, trace and query it at once (ggRender,
** ggTracePixel, ggRayColor, ggCameraRay, ggSceneIntersect,
** ggSceneOccluded, the getters), each with options of its own: rendering
** keeps every choice of its options to itself and writes nothing into the
** scene. Writing functions need the scene to themselves: no other call on
** it may overlap them. ggRender and ggTracePixel prepare an unprepared
** scene first; several of them may do so at once (one prepares, the others
** wait for it), but nothing else may overlap that first preparation, so a
** scene shared between threads is best prepared before it is shared.
*/
#ifndef GGRT_SCENE_H
#define GGRT_SCENE_H

#include "ggrt/base.h"
#include "ggrt/image.h"
#include "ggrt/implicit.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct ggScene ggScene;

/* Kinds of shape, as reported in hits and statistics. */
typedef enum ggShapeKind {
    GG_SHAPE_SPHERE = 0,
    GG_SHAPE_TRIANGLE, /* from NFF p with 3 vertices, or pp */
    GG_SHAPE_POLYGON,  /* planar, any vertex count, concave allowed */
    GG_SHAPE_CONE,     /* open cone or cylinder, no caps (NFF c) */
    GG_SHAPE_RECT,     /* corner + two edges, (u,v) over [0,1]^2 */
    GG_SHAPE_IMPLICIT, /* f(x,y,z) = 0 inside a box */
    GG_SHAPE_MESH,     /* the triangles of a mesh that share one material */
    GG_SHAPE_COUNT
} ggShapeKind;

/* Name of a shape kind ("sphere"); "?" if out of range. */
GG_API const char *ggShapeKindName(int kind);

/* How a material's reflection and transmission weights are found. */
#define GG_FRESNEL_NONE      0 /* constant ks and kt, as the SPD */
#define GG_FRESNEL_SCHLICK   1 /* Schlick's approximation, dielectric */
#define GG_FRESNEL_EXACT     2 /* exact unpolarised dielectric Fresnel */
#define GG_FRESNEL_CONDUCTOR 3 /* complex index n + ik per channel */

/* The wavelengths (nm) that the R, G and B channels stand for when a
   quantity depends on wavelength (absorption, dispersion, conductors). */
#define GG_LAMBDA_R 650.0
#define GG_LAMBDA_G 550.0
#define GG_LAMBDA_B 450.0

typedef struct ggMaterial {
    ggColor color; /* surface colour (NFF r g b); a texture multiplies it */
    double kd;     /* diffuse weight */
    double ks;     /* specular weight: Phong highlight and mirror ray */
    double shine;  /* Phong exponent (NFF's 100000 = no highlight) */
    double kt;     /* transmittance: weight of the refracted ray */
    double ior;    /* index of refraction; if dispersive, n_d (at 587.6 nm): the
                      channels' indices follow Cauchy's law through n_d and the
                      Abbe number (docs/scene-format.md, `dispersion`) */
    ggColor ke;    /* emission added to whatever the surface reflects */
    int fresnel;   /* GG_FRESNEL_* */
    ggColor eta_n, eta_k; /* conductor: complex index per channel */
    /* Extinction coefficient k per channel inside a transparent medium
       (the imaginary part of its index): over a path of d scene units the
       light keeps exp(-4 pi k d * unit / lambda), lambda = GG_LAMBDA_R/G/B
       in metres (Beer-Lambert). All zero: no absorption. */
    ggColor extinction;
    double unit_m; /* metres per scene unit for absorption (0 means 1) */
    double abbe;         /* dispersion: Abbe number V_d (0 = none) */
    int texture;         /* texture index from ggSceneAddTexture, or -1 */
    int line;            /* scene-file line that defined it (0 from code) */
} ggMaterial;

/* The NFF default: white, kd 1, everything else off, no texture. */
GG_API ggMaterial ggMaterialDefault(void);

/* Upper bounds of the physical parameters: GG_PARAM_MAX for colours,
   ambient, background, emission, extinction, |ior|, conductor n and k,
   unit_m and abbe; GG_WEIGHT_MAX for kd, ks and kt. Within them, and with
   lights of at most GG_PARAM_MAX too, every term of a pixel's sum stays
   below about 1e230 (weights of at most 100 along 64 bounces, times a
   colour and a light of at most 1e30), so rendering never overflows a
   double and never makes a NaN (a pixel above the float range is stored
   as +inf). Light colours are deliberately bounded only by being finite:
   a light of 1e308 is how a scene plants non-finite pixels for ggrt check
   (tests/data/debug); such samples are counted in ggRayStats.nonfinite. */
#define GG_PARAM_MAX  1e30
#define GG_WEIGHT_MAX 100

/* The largest magnitude of an object's coordinates and sizes (sphere
   centres and radii, cone ends and radii, rectangle corners, edges and
   far corners, polygon, triangle and mesh vertices after the mesh's
   transform, implicit surfaces' box corners) and of a light's position. Within it every product an
   intersection test forms stays finite, for eye rays from a camera up to
   its 1e150 (they are unit) and for shadow rays, which run from a hit to
   a light unnormalised; beyond it, from about 1e77, triangles, polygons
   and rectangles were accepted and never hit, and a sphere of 1e20 let
   the light of a light at 1e150 through. ggSceneAdd* and the loaders
   refuse more with GG_ERROR_INVALID. */
#define GG_COORD_MAX 1e64

/* The least a scene may span: the largest side of the box around its
   objects and the camera's eye (ggScenePrepare refuses a smaller one
   with GG_ERROR_INVALID). A scene scaled by a power of two renders the
   same image from this size up to GG_COORD_MAX (tests/unit/scene/
   test_coords.c, from 2^-196 of a unit scene; before this limit the same
   renders held down to 2^-250); below about 2^-255 the
   quadratic of a cone's intersection underflows, below 2^-340 a
   triangle's, and the picture is lost without an error. */
#define GG_SCENE_SIZE_MIN 1e-60

/* Whether m is physically valid, the rule ggSceneAddMaterial and the NFF
   loader apply: colour, ke, extinction and unit_m in [0, GG_PARAM_MAX];
   kd, ks and kt in [0, GG_WEIGHT_MAX] (above 1 is accepted: `ggrt check`
   reports the energy it adds); shine finite and >= 0; abbe 0 or in [1,
   GG_PARAM_MAX]; |ior| <= GG_PARAM_MAX, non-zero when kt > 0 (negative: a
   metamaterial, optics.h); |eta_n| <= GG_PARAM_MAX, eta_k in [0,
   GG_PARAM_MAX], and for GG_FRESNEL_CONDUCTOR eta_n >= 0 with n and k not
   both 0 in any channel;
   fresnel one of GG_FRESNEL_*; texture >= -1 (whether the texture exists
   is the scene's to check). Returns GG_OK, or GG_ERROR_INVALID with err
   naming the first field at fault ("material: ks must be in [0, 100],
   got -1"); a NULL m is GG_ERROR_INVALID. */
GG_API int ggMaterialCheck(const ggMaterial *m, ggError *err);

typedef struct ggCamera {
    ggVec3 from, at, up; /* up need not be perpendicular: it is orthogonalised */
    double fov_deg;      /* full field of view, horizontal = vertical scaled by aspect */
    int width, height;   /* image size */
} ggCamera;

/* Whether cam gives a camera basis: from, at and up finite with no
   coordinate over 1e150 in magnitude; at - from not
   zero (nor below 1e-9 of their size); up not zero and not parallel to at
   - from (within 1e-9 rad); 0 < fov_deg < 180; width and height 1 to
   GG_IMAGE_MAX_DIM, at most GG_IMAGE_MAX_PIXELS pixels. Returns GG_OK, or
   GG_ERROR_INVALID with err naming the fault ("camera: 'up' is parallel
   to the view direction"); a NULL cam is GG_ERROR_INVALID. */
GG_API int ggCameraCheck(const ggCamera *cam, ggError *err);

/* New empty scene; NULL if out of memory. alloc may be NULL; it is copied
   (base.h rule 3). Empty but for a default camera, which a scene file or
   ggSceneSetCamera replaces: from (0, 0, 1) looking at the origin, up +y,
   45 degrees, 512x512 (ggSceneCamera returns it; ggRender renders with
   it). ggSceneLoadFile of a lone model frames its own camera only while
   the scene has no other: it tells the default from a set one. */
GG_API ggScene *ggSceneCreate(const ggAllocator *alloc);
/* Frees the scene and everything it owns; NULL is a no-op. */
GG_API void ggSceneFree(ggScene *scene);

/* Add what an NFF file (or text) says to the scene. Errors name the place:
   "scene.nff:12:5: expected a number after 's'". Textures and meshes named
   in the file are read relative to the file's folder. On error the scene is
   left as it was before the call, prepared if it was; a load that succeeds
   leaves it unprepared, as every addition does. ggSceneLoadString's name
   stands for the file in messages ("<string>" when NULL), and textures and
   meshes it names are read relative to the current folder.
   ggSceneLoadFile also takes a model on its own: a path ending in .obj or
   .ply (any case) is loaded with ggSceneLoadMesh and default options, then
   framed with ggSceneFrame (camera if the scene has none, lights if it has
   none). ggSceneLoadString reads NFF only.
   Only regular files are read, as scenes, meshes, material libraries and
   textures: a FIFO, device or directory is GG_ERROR_IO "path: not a
   regular file" at once (opened without blocking, then checked).
   Limits (GG_ERROR_LIMIT, the message naming the limit and the value): a
   scene file of more than GG_SCENE_MAX_FILE bytes is refused before it is
   read; a resolution over the image limits of image.h; textures beyond
   the texture budget (ggSceneSetTextureBudget). */
#define GG_SCENE_MAX_FILE ((size_t)256 << 20)
GG_API int ggSceneLoadFile(ggScene *scene, const char *path, ggError *err);
GG_API int ggSceneLoadString(ggScene *scene, const char *text, size_t len, const char *name,
                             ggError *err);

/* Reads an image file that a scene file names (a texture), with the
   contract of ggImageRead (image.h); `ud` is the pointer given with it.
   Its failure fails the load (an OBJ's map_Kd: a warning) with its
   message; a reader that wrote none gets "PATH: the image reader failed
   (status N) without a message", and a status that is not a GG_ERROR_*
   code is reported as GG_ERROR_IO. */
typedef int (*ggImageReader)(void *ud, const char *path, const ggAllocator *alloc,
                             ggImage **out, ggError *err);
/* How ggSceneLoadFile and ggSceneLoadString read textures from now on.
   fn NULL (the initial state) means the library's default: ggImageRead in
   libggrt; none in libggrt-core (the static core without PNG or OpenEXR,
   pkg-config ggrt-core), where a scene that names a texture fails with
   GG_ERROR_UNSUPPORTED unless a reader is given here. */
GG_API void ggSceneSetImageReader(ggScene *scene, ggImageReader fn, void *ud);

/* The texture budget: how many bytes of decoded texels (12 per pixel) the
   image textures that this scene's files name may hold in all, default
   GG_TEXTURE_BUDGET (256 MiB). A file named several times (the same path
   after resolving it against the scene file's folder) is decoded once and
   counted once. The library's reader checks the size a PNG or OpenEXR
   header declares against what is left before decoding; an image from a
   reader given with ggSceneSetImageReader is checked when it returns.
   Going over is GG_ERROR_LIMIT, "t.png: 3000 x 3000 pixels decode to
   108000000 bytes, over the texture budget (60000000 bytes left of
   268435456)", and the load fails as any load error does. Images given
   with ggSceneAddTexture are not counted.
   The contract is SQLite's sqlite3_limit(): bytes >= 0 sets the budget
   for the loads that follow (what is loaded stays, even above a lowered
   budget); bytes < 0 changes nothing. Either way the budget in effect
   before the call is returned; -1 for a NULL scene. */
#define GG_TEXTURE_BUDGET ((int64_t)256 << 20)
GG_API int64_t ggSceneSetTextureBudget(ggScene *scene, int64_t bytes);

/* Progress of the long steps on this scene from now on, for a bar and a
   cancel button (ggProgressFn, base.h): fn NULL (the initial state)
   means none. fn(ud, done, total) is called on the thread that called
   the step:
   - loading (ggSceneLoadFile, ggSceneLoadString, ggSceneLoadMesh,
     ggSceneLoadMeshMemory, and a mesh file an NFF file names): bytes of
     the file being read, total its size. Once with done 0 when a file's
     reading starts, again each time a further MiB has been read, and with
     done == total when it is read, before the load takes effect. A mesh
     file named by an NFF file is a step of its own: its bytes from 0,
     then the NFF file's count goes on where it was;
   - preparing (ggScenePrepare, and ggRender and the debugger's functions
     when they prepare): thousandths, total 1000. 0 at the start, up to
     300 as the objects' primitives are gathered (every 65536 of them),
     then up to 1000 as the BVH is built: its subtrees as they are
     finished (about every 16384 elements), then its nodes; 1000 at the
     end. The thousandths count work, not time.
   A non-zero return cancels: the call returns GG_ERROR_CANCELLED with a
   message naming the step ("scene.nff:912:1: loading cancelled"), and
   the scene is as a failed call leaves it: a load as before the call, a
   prepare unprepared (nothing in the scene lost; preparing again starts
   over). fn must not change the scene it reports on. A scene shared
   between threads must not change its callback while another thread
   prepares it. */
GG_API void ggSceneSetProgress(ggScene *scene, ggProgressFn fn, void *ud);

/* ---- building in code ----
   Functions that add something return its index (>= 0), or a negative
   status (-GG_ERROR_NOMEM, -GG_ERROR_INVALID, -GG_ERROR_LIMIT) on
   failure; the setters return GG_OK or GG_ERROR_INVALID. Invalid values
   are refused by the rule the NFF loader applies (docs/scene-format.md,
   "Parameter ranges"), and the scene is then unchanged but for what
   ggSceneLastError says. */

/* Why the last building call on this scene failed, as SQLite's
   sqlite3_errmsg() tells a connection's: the code (the status returned,
   made positive) and a message naming the function, the value and the
   rule, "ggSceneAddSphere: the radius must be > 0, got -1"; code GG_OK and
   message "" after a building call that succeeded (and before any). The
   building calls are the functions of this section from
   ggSceneSetCamera to ggSceneAddImplicit, ggSceneSetDepth and
   ggSceneSetSamples; a call with a NULL scene has nowhere to say it.
   Valid until the next call that writes to the scene; NULL for a NULL
   scene. */
GG_API const ggError *ggSceneLastError(const ggScene *scene);

/* GG_ERROR_INVALID unless ggCameraCheck(cam) accepts it. */
GG_API int ggSceneSetCamera(ggScene *scene, const ggCamera *cam);
/* The camera; all zero for a NULL scene. */
GG_API ggCamera ggSceneCamera(const ggScene *scene);
/* GG_ERROR_INVALID unless every channel is in [0, GG_PARAM_MAX]. */
GG_API int ggSceneSetBackground(ggScene *scene, ggColor c);
GG_API int ggSceneSetAmbient(ggScene *scene, ggColor c);
/* Point light at a finite position, no coordinate over GG_COORD_MAX
   in magnitude. NFF lights without a colour get
   1/sqrt(number of lights) (the SPD convention) at render time when
   `color` has r < 0; any other colour must be finite and >= 0 (no upper
   bound, see GG_PARAM_MAX). */
GG_API int ggSceneAddLight(ggScene *scene, ggVec3 pos, ggColor color);
/* Copies *m; -GG_ERROR_INVALID unless ggMaterialCheck(m) accepts it and
   its texture (if any) exists. */
GG_API int ggSceneAddMaterial(ggScene *scene, const ggMaterial *m);
/* Replaces material `index` with a copy of *m: every object of that
   material takes the new one at the next render, which prepares the
   scene again (what a material is decides which effects run and which
   surfaces a shadow ray sees through). GG_OK, or GG_ERROR_INVALID for a
   NULL scene, an index out of range or a material ggSceneAddMaterial
   would refuse, the scene unchanged. A writing function (see Threads). */
GG_API int ggSceneSetMaterial(ggScene *scene, int index, const ggMaterial *m);
/* Takes ownership of img (freed with the scene, also on failure). */
GG_API int ggSceneAddTexture(ggScene *scene, ggImage *img);
/* A procedural n x n checkerboard over (u, v), squares of colours a and
   b (NFF `checker n a b`): n in (0, 1e6], every channel in [0,
   GG_PARAM_MAX]; else -GG_ERROR_INVALID. */
GG_API int ggSceneAddChecker(ggScene *scene, double n, ggColor a, ggColor b);
/* The shapes: -GG_ERROR_INVALID for a coordinate or size that is not
   finite or is over GG_COORD_MAX in magnitude, or a degenerate shape: a
   sphere's radius not > 0; a cone's radius < 0, both 0, or base = apex;
   a rect's e1 and e2 parallel. A polygon or triangle with no area is
   accepted (scene files have them) and never hit: ggScenePrepare leaves
   it out, ggSceneObjectUV refuses it. */
GG_API int ggSceneAddSphere(ggScene *scene, int material, ggVec3 center, double radius);
/* Planar polygon, n >= 3 vertices, counter-clockwise seen from the front. */
GG_API int ggSceneAddPolygon(ggScene *scene, int material, const ggVec3 *v, int n);
/* Triangle with per-vertex normals (NULL normals: flat). The shading
   normal is the normals interpolated and normalised, where it faces the
   geometric normal's side, else the geometric normal: a zero normal
   weighs nothing (all three zero: flat). Mesh files differ: there a
   corner with a zero normal makes its triangle flat (scene-format.md). */
GG_API int ggSceneAddTriangle(ggScene *scene, int material, const ggVec3 v[3],
                              const ggVec3 *normals);
/* Open cone or cylinder from base (radius rb) to apex (radius ra). */
GG_API int ggSceneAddCone(ggScene *scene, int material, ggVec3 base, double rb, ggVec3 apex,
                          double ra);
/* Rectangle corner + s e1 + t e2, (s, t) in [0,1]^2 = texture (u, v). */
GG_API int ggSceneAddRect(ggScene *scene, int material, ggVec3 corner, ggVec3 e1, ggVec3 e2);
/* Takes ownership of imp (freed also on failure); -GG_ERROR_INVALID for
   a NULL imp or a box corner over GG_COORD_MAX. */
GG_API int ggSceneAddImplicit(ggScene *scene, int material, ggImplicit *imp);

/* ---- meshes (docs/scene-format.md, "Meshes") ----
   A triangle mesh is stored once (positions, normals, texture coordinates,
   triangles) and appears as one object of kind GG_SHAPE_MESH per material
   it uses; ggSceneGetMeshInfo lists them. Hits on a mesh name the triangle
   (ggHit.triangle), which ggSceneGetFaceInfo turns into the file's terms:
   face index, source line, group and material names. */

/* Where vertex normals come from (ggMeshOptions.normals). */
#define GG_NORMALS_AUTO    0 /* the file's where it has them, else computed */
#define GG_NORMALS_COMPUTE 1 /* computed, ignoring any in the file */
#define GG_NORMALS_FLAT    2 /* none: every triangle is shaded flat */

/* Mesh formats (ggMeshOptions.format). */
#define GG_MESH_FORMAT_AUTO 0 /* from the file name: .obj or .ply, any case */
#define GG_MESH_FORMAT_OBJ  1 /* Wavefront OBJ, materials from its MTL files */
#define GG_MESH_FORMAT_PLY  2 /* Stanford PLY: ascii, binary little or big endian */

typedef struct ggMeshOptions {
    /* Placement p' = M p + t, row-major: M's rows are transform[0..2],
       [4..6], [8..10] and t = (transform[3], [7], [11]). Normals go
       through the inverse transpose of M. M must be invertible. */
    double transform[12];
    int normals; /* GG_NORMALS_* */
    /* Computed normals are angle-weighted averages (Thurmer and Wuthrich
       1998) over the faces at a vertex whose normals are within this angle
       of the face's own (degrees, 0..180): larger angles stay creases. */
    double crease_deg;
    /* Scene material for faces the file gives none (every PLY face, OBJ
       faces before any usemtl or naming an unknown material); -1: add
       ggMaterialDefault() when a face needs it. */
    int material;
    bool override_materials; /* every face gets `material`: MTL files are not read */
    int format;              /* GG_MESH_FORMAT_* */
} ggMeshOptions;

/* Identity transform, GG_NORMALS_AUTO, crease 60 degrees, material -1,
   MTL materials used, format from the file name. */
GG_API void ggMeshOptionsDefault(ggMeshOptions *opt);

/* Read a mesh file into the scene (opt NULL: defaults). OBJ materials come
   from the MTL files it names (read relative to the OBJ's folder, and
   their map_Kd textures through the scene's image reader). Errors name the
   place: "model.obj:12:5: face index 9 is out of range (8 vertices)" for
   OBJ and MTL, the byte offset and element index for binary PLY. Truncated
   files, bad indices, counts beyond the documented limits and NaN or
   infinite numbers are errors. On error the scene is left as it was.
   Returns GG_OK (not the mesh's index: ggSceneMeshCount - 1 is it);
   GG_ERROR_INVALID for options out of range (normals not a
   GG_NORMALS_*, a crease outside 0..180 degrees, an unknown material, a
   singular or non-finite transform) or a mesh with no face of any area;
   GG_ERROR_UNSUPPORTED for an unknown format; GG_ERROR_IO, GG_ERROR_PARSE,
   GG_ERROR_LIMIT or GG_ERROR_NOMEM as the file calls for. */
/* A mesh file loaded again (the same file under any path, also through
   an NFF `mesh` line) is read and placed again. Each such repeated load
   counts its triangles, 8 more for the mesh's own records and one more
   per 256 bytes of its group and material names; together they may not
   exceed GG_MESH_REPEAT_MAX (2^21 triangles' worth, about 700 MB with the
   BVH) in one scene, checked before the file is read again:
   GG_ERROR_LIMIT "g.obj: named again: at 20008 triangles' worth (20000
   triangles, its records and names) it would bring the meshes named more
   than once to 2100840, over the limit of 2097152". So a small scene
   naming one file many times stays bounded, in memory and in time (a
   file's earlier load is found by hashing). */
#define GG_MESH_REPEAT_MAX ((size_t)1 << 21)
/* An OBJ's group labels ("object/group", one per distinct pair of o and g
   names, kept for ggSceneGetFaceInfo) may total at most the file's size
   plus GG_MESH_LABELS_MAX bytes: each pair copies its o name, so a 403 KB
   file of one 400,000-byte o name and 500 g names asked for 200 MB.
   Beyond it, at the o or g name: GG_ERROR_LIMIT "og.obj:87:3: the group
   labels would pass 17184633 bytes, the file's size plus 16 MiB (...)". */
#define GG_MESH_LABELS_MAX ((size_t)16 << 20)
GG_API int ggSceneLoadMesh(ggScene *scene, const char *path, const ggMeshOptions *opt,
                           ggError *err);
/* The same from memory: `name` (NULL: "<memory>") is used in messages and
   for the format when opt->format is AUTO. Reads no other file: an OBJ's
   mtllib lines are counted as ignored. */
GG_API int ggSceneLoadMeshMemory(ggScene *scene, const void *data, size_t len, const char *name,
                                 const ggMeshOptions *opt, ggError *err);

/* A mesh built in code. Arrays are copied; the caller keeps them. */
typedef struct ggMeshData {
    const char *name;        /* reported by ggSceneGetMeshInfo; NULL: "" */
    const ggVec3 *positions; /* npositions of them, finite */
    size_t npositions;
    const ggVec3 *normals;   /* one per position (need not be unit), or NULL */
    const double *uv;        /* two per position, or NULL; v = 0 is an image's top row */
    const uint32_t *indices; /* three per triangle, counter-clockwise seen from the front */
    size_t ntriangles;
    const int *materials;    /* one scene material per triangle, or NULL: opt->material */
} ggMeshData;

/* Add a mesh (opt NULL: defaults; its format is ignored). Triangles of zero
   area are dropped (counted in ggMeshInfo.skipped_faces). Returns the mesh
   index (>= 0) or a negative status: -GG_ERROR_INVALID for an index out of
   range, a non-finite number, an unknown material, a singular transform
   or no triangle with an area ("mesh: no face has an area"; err says
   which), -GG_ERROR_LIMIT beyond 2^28 triangles or vertices,
   -GG_ERROR_NOMEM. On failure the scene is unchanged. */
GG_API int ggSceneAddMesh(ggScene *scene, const ggMeshData *data, const ggMeshOptions *opt,
                          ggError *err);

/* Frame what the scene holds: with GG_FRAME_CAMERA, point the camera at the
   bounds of every object from above the front right (+y up, looking toward
   -z), close enough that the bounding sphere fills the view; with
   GG_FRAME_LIGHTS, add a key and a fill light. The result is an ordinary
   camera and lights (ggSceneCamera, ggSceneGetLight), which a program may
   print as NFF. GG_ERROR_INVALID if the scene has no objects, or if its
   bounds are too large to frame (a light, placed about six bounding
   radii out, would be beyond GG_COORD_MAX; err gives the bounds);
   GG_ERROR_NOMEM. On failure the camera and lights are as they were. */
#define GG_FRAME_CAMERA 1u
#define GG_FRAME_LIGHTS 2u
GG_API int ggSceneFrame(ggScene *scene, unsigned what, ggError *err);

/* Render settings that a scene file may carry (its `depth` and `samples`):
   0 leaves them to the renderer (depth 5, 1 sample); else depth 1..64
   and samples 1..4096, as in a file. GG_OK, or GG_ERROR_INVALID for a
   NULL scene or a value out of range (the scene unchanged). A prepared
   scene stays prepared, its effect set (ggSceneEffects) brought up to
   date (short of memory for that, it is left unprepared). */
GG_API int ggSceneSetDepth(ggScene *scene, int max_depth);
GG_API int ggSceneSetSamples(ggScene *scene, int samples_per_pixel);

/* ---- inspection ----
   For a NULL scene or an index out of range (base.h rule 1): counts are 0,
   ggSceneObjectKind, ggSceneObjectMaterial and ggSceneObjectMesh -1,
   ggSceneObjectLine 0, ggSceneMaterial the ggMaterialDefault(), ggSceneGet*
   and ggSceneObjectShape GG_ERROR_INVALID, ggSceneIntersect and
   ggSceneOccluded false, ggSceneFileName "".
   ggSceneObjectCount counts the objects (a mesh is one); ggSceneLightCount
   the point lights (NFF "l" lines, ggSceneAddLight, ggSceneFrame's), which
   an emissive material is not: a scene with no light is lit only by its
   ambient light and emission, one with no object renders its background. */
GG_API int ggSceneObjectCount(const ggScene *scene);
GG_API int ggSceneLightCount(const ggScene *scene);
GG_API int ggSceneMaterialCount(const ggScene *scene);
GG_API ggMaterial ggSceneMaterial(const ggScene *scene, int index);
/* Kind, material and defining line of object `index`. */
GG_API int ggSceneObjectKind(const ggScene *scene, int index);
GG_API int ggSceneObjectMaterial(const ggScene *scene, int index);
GG_API int ggSceneObjectLine(const ggScene *scene, int index);
/* An object's shape as the scene describes it. Which fields mean
   something depends on kind: sphere (center, radius), cone (base, radius
   = base radius, apex, radius2 = apex radius), rect (corner = base, e1, e2),
   polygon and triangle (nverts vertices at verts, normals or NULL),
   implicit (its box lo = base, hi = apex), mesh (its part's bounds lo =
   base, hi = apex; nverts 0: ggSceneGetMeshInfo describes the mesh).
   Spheres and cones also get e1, e2: the unit axes across which their
   texture's u is measured (ggSceneObjectUV), (1, 0, 0) and (0, 1, 0) for
   a sphere, a pair perpendicular to the axis and to each other for a cone
   (all zero for a cone the renderer cannot hit: zero height or radii).
   Pointers stay valid until the scene changes. */
typedef struct ggShapeDesc {
    int kind, material, line;
    ggVec3 base, apex, e1, e2;
    double radius, radius2;
    int nverts;
    const ggVec3 *verts, *normals;
} ggShapeDesc;

/* Fill *d for object index; GG_ERROR_INVALID if out of range. */
GG_API int ggSceneObjectShape(const ggScene *scene, int index, ggShapeDesc *d);

/* ---- textures and texture coordinates ----
   A hit on a textured material (ggMaterial.texture >= 0) at (u, v) =
   (ggHit.u, ggHit.v) has the surface colour color x T(u, v) (the ray
   tree's `surface`, trace.h), T its texture sampled there. Both are
   exposed for a client that draws the scene as the renderer textures it
   (`ggrt serve`'s 3D view). */
/* What a texture is. An image: T = ggTextureNearest(image, u, v, wrap)
   if nearest, else ggTextureBilinear(image, u, v, wrap); a render's
   texture knob may choose the filter instead (GG_ACC_TEXTURE_*,
   render.h). A checker (image NULL): T = ggTextureChecker(u, v,
   checker_n, checker_a, checker_b). */
typedef struct ggTextureInfo {
    const ggImage *image; /* the texels (linear RGB, v = 0 the top row), or NULL for a
                             checker; valid until the scene is freed */
    int wrap;             /* image: GG_WRAP_REPEAT or GG_WRAP_CLAMP */
    bool nearest;         /* image: nearest texel, else bilinear */
    double checker_n;     /* checker: squares per side (0 for an image) */
    ggColor checker_a, checker_b;
} ggTextureInfo;

/* The textures: one per NFF `texture` or `checker` line, OBJ map_Kd and
   ggSceneAddTexture (a file named several times, under any path, is
   decoded once, and those textures share its image; with a reader of the
   caller's, ggSceneSetImageReader, the same name is). */
GG_API int ggSceneTextureCount(const ggScene *scene);
/* Fill *out for texture `index` (ggMaterial.texture); GG_ERROR_INVALID
   if out of range or out is NULL. */
GG_API int ggSceneGetTexture(const ggScene *scene, int index, ggTextureInfo *out);

/* The (u, v) the renderer gives a hit on object `object` at each of the
   n points p[0..n), written to uv[2i] and uv[2i + 1]: what ggHit.u and
   .v say of a hit there, to the rounding of the hit point. Per kind, in
   ggSceneObjectShape's terms:
     sphere    d = p - center: u = atan2(d.e2, d.e1) / 2pi in [0, 1) (0
               where it would round to 1), v = acos(d.(e1 x e2) / |d|) / pi
               in [0, 1], 0 at the pole +z (e1, e2 = +x, +y); the centre
               itself counts as the pole;
     cone      d = p - base: u = atan2(d.e2, d.e1) / 2pi as for spheres
               (0 on the axis), v = the height of p above the base along the
               axis over the cone's height, clamped to [0, 1];
     rect      (s, t) with p = corner + s e1 + t e2, p projected into the
               plane along e1 x e2 (outside [0, 1] for a p beyond the edges);
     triangle  the barycentric weights of vertices 1 and 2, clamped to [0,
               1]. A triangle object of nverts > 3 (NFF pp) is hit as the fan
               of triangles (verts[0], verts[k + 1], verts[k + 2]), k = 0 ..
               nverts - 3, each with its own weights: `part` is k (0 for a
               triangle of 3);
     polygon   (nverts > 3; one of 3 is a triangle) in the plane's frame:
               n the unit Newell normal (the side from which the vertices
               run counter-clockwise), eu the first nonzero edge from vertex
               0 (to vertex 1, 2, ...) made perpendicular to n and unit, ev
               = n x eu; u = ((p - verts[0]).eu - u0) / (u1 - u0), v likewise
               along ev, each clamped to [0, 1], where [u0, u1] x [v0, v1] is
               the vertices' bounding rectangle in that frame;
     mesh      the mesh's texture coordinates at the corners of triangle
               `part` (as ggHit.triangle numbers it: one of this object's)
               interpolated by the barycentric weights of p (not clamped);
               a mesh without them: as a triangle;
     implicit  (0, 0).
   `part` is ignored for the other kinds. The scene need not be prepared.
   GG_ERROR_INVALID, with uv untouched, for a NULL scene, or p or uv with
   n > 0, an object or part out of range, a point that is not finite, or
   a shape the renderer never hits (no area, zero radius or height). */
GG_API int ggSceneObjectUV(const ggScene *scene, int object, long part, const ggVec3 *p, size_t n,
                           double *uv);

/* Light `index`: position and colour (negative r: the SPD default colour,
   see ggSceneAddLight). GG_ERROR_INVALID if out of range. */
GG_API int ggSceneGetLight(const ggScene *scene, int index, ggVec3 *pos, ggColor *color);

GG_API int ggSceneMeshCount(const ggScene *scene);
/* Mesh index of a GG_SHAPE_MESH object, else -1. */
GG_API int ggSceneObjectMesh(const ggScene *scene, int object);

typedef struct ggMeshInfo {
    const char *name;     /* the file as given, or ggMeshData.name */
    const char *format;   /* "obj", "ply", or "" for a mesh built in code */
    size_t file_vertices; /* as the file counts them: v statements, PLY vertex elements */
    size_t file_faces;    /* f statements, PLY face elements */
    size_t vertices;      /* stored: one per distinct position/normal/uv corner */
    size_t triangles;     /* stored, after triangulating faces and dropping zero areas */
    size_t skipped_faces; /* faces (or triangles of a split face) of zero area, dropped */
    size_t ignored;       /* statements or elements read and not used: points, lines,
                             curves, unknown OBJ statements, mtllib from memory */
    int first_object, objects; /* its objects: first_object .. first_object + objects - 1 */
    int groups;                /* distinct OBJ group names (o, g) */
    bool file_normals;         /* normals came from the file */
    bool has_uv;               /* texture coordinates are stored */
    size_t bytes;              /* memory the scene keeps for the mesh */
    ggVec3 lo, hi;             /* bounds, after the transform */
    /* What the file asked for that is not done, e.g. a texture that could
       not be read (the material then uses its colour alone): how many, and
       the first with its place ("m.mtl:10:1: ..."), else "". */
    int warnings;
    const char *warning;
} ggMeshInfo;

/* Fill *info for mesh `index`; GG_ERROR_INVALID if out of range. Strings
   stay valid until the scene is freed. */
GG_API int ggSceneGetMeshInfo(const ggScene *scene, int index, ggMeshInfo *info);

/* A mesh triangle in the file's terms. */
typedef struct ggFaceInfo {
    int mesh;             /* mesh index */
    const char *mesh_name;
    long face;            /* 0-based index of the face it comes from: the f statement
                             among all f statements, or the PLY face element */
    int line;             /* OBJ: the line of the f statement; PLY and code: 0 */
    const char *group;    /* OBJ: the o/g names in effect ("" if none) */
    const char *material_name; /* OBJ: the usemtl name in effect ("" if none) */
    int material;         /* scene material */
} ggFaceInfo;

/* Fill *fi for triangle `triangle` (as in ggHit.triangle) of mesh object
   `object`; GG_ERROR_INVALID if object is not a mesh or triangle is out of
   range. Strings stay valid until the scene is freed. */
GG_API int ggSceneGetFaceInfo(const ggScene *scene, int object, long triangle, ggFaceInfo *fi);

/* The triangles of mesh object `object` (one material's part of a mesh),
   for drawing it: ggSceneObjectTriangleCount says how many (0 if the object
   is not a mesh part); ggSceneObjectTriangle writes the corners of the k-th
   (0 <= k < that count), after the mesh's transform, and in *triangle (if
   not NULL) its number in the mesh as ggHit.triangle gives it.
   GG_ERROR_INVALID for another object or k out of range. */
GG_API long ggSceneObjectTriangleCount(const ggScene *scene, int object);
GG_API int ggSceneObjectTriangle(const ggScene *scene, int object, long k, ggVec3 v[3],
                                 long *triangle);

/* The surface of implicit object `object` as triangles, for drawing it:
   ggImplicitTriangulate of its ggImplicit at that resolution and bound,
   the result made with the scene's allocator (it may outlive the scene;
   free it with ggTriangulationFree). The scene need not be prepared; it
   is only read, so any number of threads may call this at once (not
   while the scene is written). *out is NULL on failure. Returns what
   ggImplicitTriangulate does, GG_ERROR_INVALID also for a NULL scene or
   an object out of range, and GG_ERROR_UNSUPPORTED for an object of
   another kind (its shape is ggSceneObjectShape's; a mesh's triangles
   are ggSceneObjectTriangle's). */
GG_API int ggSceneObjectTriangulate(const ggScene *scene, int object, int resolution,
                                    size_t max_triangles, ggTriangulation **out);

/* Name of the file the scene was loaded from ("" if built in code). */
GG_API const char *ggSceneFileName(const ggScene *scene);

/* The files the scene was read from, by their paths as the loader
   resolved them: the scene file (ggSceneFileName), then each mesh file
   (NFF mesh lines, ggSceneLoadMesh, a model), the MTL files an OBJ read,
   and each image texture file (NFF texture lines, map_Kd); a mesh or
   texture file named several times is listed once. For a program that
   must not write over its inputs (ggrt refuses an output that is one of
   them). ggSceneInputFile gives NULL for an index outside 0 ..
   ggSceneInputCount - 1; the strings stay valid until the scene changes. */
GG_API int ggSceneInputCount(const ggScene *scene);
GG_API const char *ggSceneInputFile(const ggScene *scene, int index);

/* Build the acceleration structure and the effect set. Called by the
   renderer when needed; call it yourself to time it, to catch errors
   early, or before sharing the scene between threads. Adding to a
   prepared scene makes it unprepared again. Preparing writes the scene;
   a prepared scene returns GG_OK at once without writing. GG_ERROR_NOMEM,
   GG_ERROR_LIMIT (more primitives than the BVH holds), or
   GG_ERROR_INVALID for a scene with objects that spans less than
   GG_SCENE_SIZE_MIN; the scene is then unprepared, as before the call. */
GG_API int ggScenePrepare(ggScene *scene, ggError *err);

/* What a prepared scene holds, for reports (`ggrt info`) and benchmarks. */
typedef struct ggSceneInfo {
    int objects_by_kind[GG_SHAPE_COUNT];
    size_t primitives;      /* after splitting polygons into what the BVH holds */
    size_t bvh_nodes, bvh_leaves, bvh_depth;
    size_t bvh_blocks;      /* leaves of 2-4 triangles tested four at a time with AVX;
                               0 where the CPU lacks AVX (the plain traversal runs) */
    size_t geometry_bytes;  /* BVH nodes plus primitive data */
    double prepare_seconds; /* last ggScenePrepare, BVH build included */
    double bvh_seconds;     /* BVH build alone */
    ggVec3 lo, hi;          /* bounds of everything */
} ggSceneInfo;

/* Fill *info; GG_ERROR_INVALID if the scene is not prepared. */
GG_API int ggSceneGetInfo(const ggScene *scene, ggSceneInfo *info);

/* The instruction set of the traversal copy a prepared scene's ray
   queries take on this CPU, chosen once from its features (and the
   GGRT_ISA cap): "avx512" (AVX-512's masks on 256-bit registers),
   "avx2", "avx", "sse2" (no AVX, or a scene with nothing in it) or "c"
   (a build without SIMD). The same images and rays in every copy. For
   reports and benchmarks (`ggrt info`, `ggrt bench`). NULL if the scene
   is NULL or not prepared. A static string: do not free it. */
GG_API const char *ggSceneTraversal(const ggScene *scene);

/* A ray's closest hit (valid after ggScenePrepare). */
typedef struct ggHit {
    double t;       /* ray parameter of the hit */
    ggVec3 p;       /* hit point */
    ggVec3 ng;      /* unit geometric normal, as the shape defines it (outward) */
    ggVec3 ns;      /* unit shading normal, same side as ng */
    double u, v;    /* surface coordinates */
    bool front;     /* the ray arrived against ng */
    int object;     /* object index */
    int kind;       /* ggShapeKind */
    int material;   /* material index */
    long triangle;  /* mesh objects: the triangle hit (ggSceneGetFaceInfo), else -1 */
} ggHit;

/* Closest hit with t in (tmin, tmax); false if none. */
GG_API bool ggSceneIntersect(const ggScene *scene, ggRay ray, double tmin, double tmax,
                             ggHit *hit);
/* Anything hit with t in (tmin, tmax)? */
GG_API bool ggSceneOccluded(const ggScene *scene, ggRay ray, double tmin, double tmax);

#ifdef __cplusplus
}
#endif
#endif
