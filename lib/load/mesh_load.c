/* SPDX-License-Identifier: MIT */
/*
** mesh_load.c -- ggSceneLoadMesh and friends: pick the reader, hand what
** it read to the scene (gg_scene_add_mesh_build), and leave the scene as it
** was when anything fails. Also a model loaded as a scene of its own
** (ggSceneLoadFile of a .obj or .ply): the mesh, framed.
*/
#include "mesh_int.h"

#include <string.h>

static bool ends_with(const char *s, const char *ext)
{
    size_t n = strlen(s), k = strlen(ext), i;
    if (n < k) return false;
    for (i = 0; i < k; i++) {
        char c = s[n - k + i];
        if (c >= 'A' && c <= 'Z') c = (char)(c - 'A' + 'a');
        if (c != ext[i]) return false;
    }
    return true;
}

int gg_load_mesh_format(const char *name)
{
    if (ends_with(name, ".obj")) return GG_MESH_FORMAT_OBJ;
    if (ends_with(name, ".ply")) return GG_MESH_FORMAT_PLY;
    return GG_MESH_FORMAT_AUTO;
}

/* What a failed load must undo. */
typedef struct mark {
    size_t nobjects, nmaterials, ntextures, nimages, nmeshes, nlights;
    ggCamera camera;
    bool has_camera;
} mark;

static void take(const ggScene *s, mark *m)
{
    m->nobjects = s->nobjects, m->nmaterials = s->nmaterials, m->ntextures = s->ntextures;
    m->nmeshes = s->nmeshes, m->nlights = s->nlights, m->nimages = s->nimages;
    m->camera = s->camera, m->has_camera = s->has_camera;
}

static void undo(ggScene *s, const mark *m)
{
    gg_scene_drop_textures(s, m->ntextures, m->nimages);
    gg_scene_drop_meshes(s, m->nmeshes);
    s->nobjects = m->nobjects, s->nmaterials = m->nmaterials, s->ntextures = m->ntextures;
    s->nlights = m->nlights, s->camera = m->camera, s->has_camera = m->has_camera;
}

/* file: where data came from, NULL for memory; repeat: an earlier mesh of
   the scene is the same file (check_repeat). */
static int load(ggScene *s, const char *data, size_t len, const char *name, const char *dir,
                const ggMeshOptions *o, int line, const gg_file_id *file, bool repeat, ggError *err)
{
    ggMeshOptions def;
    gg_mb mb;
    mark mk;
    int fmt, rc, id;
    if (!o) ggMeshOptionsDefault(&def), o = &def;
    fmt = o->format ? o->format : gg_load_mesh_format(name);
    if (fmt != GG_MESH_FORMAT_OBJ && fmt != GG_MESH_FORMAT_PLY)
        return gg_error_set(err, GG_ERROR_UNSUPPORTED,
                            "%s: unknown mesh format (the name should end in .obj or .ply)", name);
    take(s, &mk);
    gg_mb_init(&mb, s->alloc, fmt);
    gg_progress_part(&mb.prog, s->progress, s->progress_ud, 0, len, len), mb.len = len;
    if (gg_mb_progress(&mb, 0, 1))
        rc = gg_error_set(err, GG_ERROR_CANCELLED, "%s: loading cancelled", name);
    else if (fmt == GG_MESH_FORMAT_OBJ)
        rc = gg_obj_read(s, &mb, data, len, name, dir, o, err);
    else
        rc = gg_ply_read(&mb, (const unsigned char *)data, len, name, err);
    if (rc == GG_OK && gg_mb_progress(&mb, len, 1))
        rc = gg_error_set(err, GG_ERROR_CANCELLED, "%s: loading cancelled", name);
    if (rc == GG_OK && !(mb.b.m.name = gg_mem_strdup(s->alloc, name)))
        rc = gg_error_set(err, GG_ERROR_NOMEM, "%s: out of memory", name);
    if (file) mb.b.m.has_file = true, mb.b.m.file_dev = file->dev, mb.b.m.file_ino = file->ino;
    mb.b.m.repeat = repeat;
    if (rc == GG_OK && (id = gg_scene_add_mesh_build(s, &mb.b, o, line, err)) < 0) rc = -id;
    gg_mb_free(&mb);
    if (rc != GG_OK) undo(s, &mk);
    return rc;
}

/* A mesh file named again costs its triangles again (each mention is
   placed on its own), so a small scene naming one file many times could
   ask for any amount of memory: every mention after a file's first
   counts gg_mesh_repeat_cost (its triangles, its records and its names)
   against GG_MESH_REPEAT_MAX, checked before the file is read again. A
   file is its device and inode: compared as strings, `./grid.ply`,
   `././grid.ply`, ... passed the limit (250 such lines naming a 193 KB
   PLY took 997 MB). The scene keeps the sum and finds a file's first
   mesh by hashing (lib/scene/mesh.c). *repeat: the file was read
   before. */
static int check_repeat(const ggScene *s, const char *path, const gg_file_id *id, bool *repeat,
                        ggError *err)
{
    const gg_mesh *first = gg_scene_mesh_by_file(s, id->dev, id->ino);
    uint64_t prev;
    *repeat = first != NULL;
    if (!first || s->mesh_again + (prev = gg_mesh_repeat_cost(first)) <= GG_MESH_REPEAT_MAX)
        return GG_OK;
    return gg_error_set(err, GG_ERROR_LIMIT,
                        "%s: named again: at %llu triangles' worth (%llu triangle%s, its records "
                        "and names) it would bring the meshes named more than once to %llu, over "
                        "the limit of %lu",
                        path, (unsigned long long)prev, (unsigned long long)first->ntri,
                        first->ntri == 1 ? "" : "s", (unsigned long long)(s->mesh_again + prev),
                        (unsigned long)GG_MESH_REPEAT_MAX);
}

int gg_load_mesh_file(ggScene *s, const char *path, const ggMeshOptions *o, int line, ggError *err)
{
    char *text = NULL, *dir;
    size_t len = 0;
    gg_file_id id;
    bool repeat = false;
    /* a path that cannot be stat'ed cannot be read either: the read says why */
    int known = gg_load_file_id(path, &id) == 0,
        rc = known ? check_repeat(s, path, &id, &repeat, err) : GG_OK;
    if (rc == GG_OK) rc = gg_load_read_file(s->alloc, path, GG_MESH_MAX_FILE, &text, &len, err);
    if (rc != GG_OK) return rc;
    if (!(dir = gg_load_dirname(s->alloc, path)))
        rc = gg_error_set(err, GG_ERROR_NOMEM, "%s: out of memory", path);
    else
        rc = load(s, text, len, path, dir, o, line, known ? &id : NULL, repeat, err);
    gg_mem_free(s->alloc, dir);
    gg_mem_free(s->alloc, text);
    return rc;
}

GG_API int ggSceneLoadMesh(ggScene *s, const char *path, const ggMeshOptions *o, ggError *err)
{
    if (!s || !path) return gg_error_set(err, GG_ERROR_INVALID, "ggSceneLoadMesh: NULL argument");
    return gg_load_mesh_file(s, path, o, 0, err);
}

GG_API int ggSceneLoadMeshMemory(ggScene *s, const void *data, size_t len, const char *name,
                                 const ggMeshOptions *o, ggError *err)
{
    if (!s || (!data && len))
        return gg_error_set(err, GG_ERROR_INVALID, "ggSceneLoadMeshMemory: NULL argument");
    return load(s, data ? (const char *)data : "", len, name ? name : "<memory>", NULL, o, 0, NULL,
                false, err);
}

int gg_load_model(ggScene *s, const char *path, ggError *err)
{
    mark mk;
    unsigned what;
    int rc;
    take(s, &mk);
    what = (s->has_camera ? 0u : GG_FRAME_CAMERA) | (s->nlights ? 0u : GG_FRAME_LIGHTS);
    rc = gg_load_mesh_file(s, path, NULL, 0, err);
    if (rc == GG_OK && what) rc = ggSceneFrame(s, what, err);
    if (rc != GG_OK) {
        undo(s, &mk);
        return rc;
    }
    {
        char *name = gg_mem_strdup(s->alloc, path);
        if (!name) {
            undo(s, &mk);
            return gg_error_set(err, GG_ERROR_NOMEM, "%s: out of memory", path);
        }
        gg_mem_free(s->alloc, s->filename);
        s->filename = name;
    }
    return GG_OK;
}
