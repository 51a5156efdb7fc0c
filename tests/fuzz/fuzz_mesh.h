/* SPDX-License-Identifier: MIT */
/*
** fuzz_mesh.h -- what the two mesh harnesses (fuzz_obj.c, fuzz_ply.c)
** check on every input: the load succeeds, or fails with a message that
** names the input and leaves the scene empty; no allocation grows beyond
** a bound proportional to the input (a count in a file must never buy
** memory the file cannot back); a mesh that loads is consistent in what
** it reports, and renders 4x3 pixels framed by ggSceneFrame, all finite.
*/
#ifndef GG_FUZZ_MESH_H
#define GG_FUZZ_MESH_H

#include "ggrt.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static size_t fuzz_cap;

static void fuzz_check(int ok, const char *what)
{
    if (!ok) {
        fprintf(stderr, "fuzz_mesh: property violated: %s\n", what);
        abort();
    }
}

static void *fz_malloc(void *ud, size_t n)
{
    (void)ud;
    if (n > fuzz_cap) fprintf(stderr, "fuzz_mesh: allocation of %zu bytes\n", n);
    fuzz_check(n <= fuzz_cap, "an allocation beyond 64 MB + 2000 bytes per input byte");
    return malloc(n);
}
static void *fz_realloc(void *ud, void *p, size_t n)
{
    (void)ud;
    if (n > fuzz_cap) fprintf(stderr, "fuzz_mesh: allocation of %zu bytes\n", n);
    fuzz_check(n <= fuzz_cap, "an allocation beyond 64 MB + 2000 bytes per input byte");
    return realloc(p, n);
}
static void fz_free(void *ud, void *p)
{
    (void)ud;
    free(p);
}

static const ggAllocator fuzz_alloc = {fz_malloc, fz_realloc, fz_free, NULL};

/* Load data as `name` and check everything above. */
static void fuzz_mesh_one(const uint8_t *data, size_t size, const char *name)
{
    ggScene *s;
    ggError e;
    ggMeshInfo mi;
    int rc, i;
    size_t nl = strlen(name);
    fuzz_cap = ((size_t)64 << 20) + 2000 * size;
    s = ggSceneCreate(&fuzz_alloc);
    if (!s) return;
    memset(&e, 0, sizeof e);
    rc = ggSceneLoadMeshMemory(s, data, size, name, NULL, &e);
    if (rc != GG_OK) {
        fuzz_check(e.code == rc, "the error repeats the status");
        fuzz_check(!strncmp(e.message, name, nl) && (e.message[nl] == ':'),
                   "the message names the input");
        fuzz_check(ggSceneObjectCount(s) == 0 && ggSceneMaterialCount(s) == 0 &&
                       ggSceneMeshCount(s) == 0,
                   "a failed load leaves the scene empty");
        ggSceneFree(s);
        return;
    }
    fuzz_check(ggSceneMeshCount(s) == 1, "one mesh");
    fuzz_check(ggSceneGetMeshInfo(s, 0, &mi) == GG_OK, "mesh info");
    fuzz_check(mi.triangles > 0 && mi.objects >= 1 && mi.first_object == 0 &&
                   mi.objects == ggSceneObjectCount(s),
               "a mesh has triangles and objects");
    for (i = 0; i < mi.objects; i++)
        fuzz_check(ggSceneObjectMesh(s, i) == 0, "objects name their mesh");
    {
        long t;
        for (t = 0; t < (long)mi.triangles; t++) {
            ggFaceInfo fi;
            int obj, ok = 0;
            for (obj = 0; obj < mi.objects && !ok; obj++)
                ok = ggSceneGetFaceInfo(s, obj, t, &fi) == GG_OK;
            fuzz_check(ok && fi.face >= 0 && (size_t)fi.face < mi.file_faces,
                       "every triangle comes from a face of the file");
        }
    }
    if (mi.triangles < 20000 && ggSceneFrame(s, GG_FRAME_CAMERA | GG_FRAME_LIGHTS, &e) == GG_OK) {
        ggRenderOptions o;
        ggImage *img = NULL;
        ggRenderOptionsDefault(&o);
        o.width = 4, o.height = 3, o.threads = 1, o.max_depth = 3;
        if (ggRender(s, &o, &img, NULL, &e) == GG_OK) {
            int x, y;
            for (y = 0; y < 3; y++)
                for (x = 0; x < 4; x++) {
                    ggColor c = ggImageGet(img, x, y);
                    fuzz_check(isfinite(c.r) && isfinite(c.g) && isfinite(c.b), "finite pixels");
                }
            ggImageFree(img);
        }
    }
    ggSceneFree(s);
}

#endif
