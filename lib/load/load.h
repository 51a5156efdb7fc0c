/* SPDX-License-Identifier: MIT */
/*
** load.h -- the scene-file readers (NFF) and how they reach image files
** (internal).
**
** The loaders read textures through a ggImageReader: the scene's own (see
** ggSceneSetImageReader) or else gg_load_default_reader(). That default is
** the one link-time choice in the library: libggrt defines it in
** imageio/reader.c (ggImageRead: PNG and OpenEXR), libggrt-core in
** load/reader_none.c (no reader, so the core archive never refers to
** libpng or OpenEXR). Each archive holds exactly one of the two.
*/
#ifndef GG_LIB_LOAD_H
#define GG_LIB_LOAD_H

#include "core.h"

/* Parse NFF text into the scene (nff.c). `dir` is the folder relative
   paths (textures) are resolved against. */
int gg_nff_parse(ggScene *s, const char *text, size_t len, const char *name, const char *dir,
                 ggError *err);

/* Meshes (mesh_load.c). gg_load_mesh_file reads a mesh file into the
   scene, its objects tagged with scene-file line `line`; the scene is
   unchanged on error. gg_load_model loads a model as a scene of its own:
   the mesh, then ggSceneFrame for what the scene lacks (camera, lights).
   gg_load_mesh_format: GG_MESH_FORMAT_* from a file name's extension. */
int gg_load_mesh_file(ggScene *s, const char *path, const ggMeshOptions *o, int line,
                      ggError *err);
int gg_load_model(ggScene *s, const char *path, ggError *err);
int gg_load_mesh_format(const char *name);

/* Read a whole file into memory (NUL-terminated; *len without the NUL):
   only a regular file (a FIFO, device or directory is GG_ERROR_IO "path:
   not a regular file", never a block) of at most `limit` bytes, checked
   before anything is allocated (GG_ERROR_LIMIT "path: N bytes exceed the
   limit of M"). */
int gg_load_read_file(const ggAllocator *a, const char *path, size_t limit, char **out, size_t *len,
                      ggError *err);

/* Which file a path names, whatever its spelling ("a.obj", "./a.obj",
   a link): its device and inode. 0 and *id set, or -1 when it cannot be
   stat'ed (the read that follows says why). */
typedef struct gg_file_id {
    uint64_t dev, ino;
} gg_file_id;
int gg_load_file_id(const char *path, gg_file_id *id);

/* What a binary file is, from its first bytes ("a PNG image", "an OpenEXR
   image", "a ZIP archive", ...), or NULL when they match no known format.
   The text readers call it before anything else: an image given as a scene
   is named as such, not reported as a NUL byte at line 3. */
const char *gg_load_binary_kind(const char *data, size_t len);

/* The image texture at path for scene s, through the texture cache: a path
   already read gives the same image again; else it is read through the
   scene's reader (or the default one, given the budget's remainder) and
   checked against the texture budget (ggSceneSetTextureBudget). *img
   belongs to the scene's cache (a gg_texture holding it is `shared`). */
int gg_load_texture(ggScene *s, const char *path, ggImage **img, ggError *err);

/* The image reader a scene without its own uses, or NULL (none: a texture
   is then GG_ERROR_UNSUPPORTED). */
ggImageReader gg_load_default_reader(void);

#endif
