/* SPDX-License-Identifier: MIT */
/*
** rays.c -- `ggrt bench rays`: millions of rays per second on one core
** for the eye, the secondary (reflection, refraction, TIR) and the shadow
** rays of each SPD scene, or of the scene files given (the large meshes
** of scripts/make-mesh-scenes.py), so that ggrt's ray queries can be
** placed beside published BVH figures. The rays are the render's own: every pixel of a
** SIZE x SIZE image (depth 5, pixel centres) is traced with the recorder
** (ggTracePixel) and its ray tree's rays kept by kind; each set is then
** cast again in a loop on one thread, closest hit (ggSceneIntersect) for
** eye and secondary rays, any hit on (0, 1) (ggSceneOccluded) for shadow
** rays, `runs` times, median reported. These are single-ray queries
** through the public API, without the hit record (hit NULL: filling a
** ggHit's point, normals and surface coordinates took 70% of the time on
** gears) and without the renderer's per-light occluder cache; ggRender
** casts its eye rays as packets, so its eye-ray rate differs.
*/
#include "bench/bench.h"

#include <float.h>
#include <stdlib.h>
#include <string.h>

/* One growing array of rays. */
typedef struct ray_set {
    ggRay *r;
    size_t n, cap;
} ray_set;

static int ray_push(ray_set *s, ggVec3 o, ggVec3 d)
{
    if (s->n == s->cap) {
        size_t cap = s->cap ? 2 * s->cap : 4096;
        ggRay *r = realloc(s->r, cap * sizeof *r);
        if (!r) return -1;
        s->r = r, s->cap = cap;
    }
    s->r[s->n].o = o, s->r[s->n].d = d;
    s->n++;
    return 0;
}

enum { SET_EYE, SET_SECONDARY, SET_SHADOW, NSETS };

/* The rays of pixel (x, y)'s tree into sets. */
static int collect_pixel(ggTrace *tr, ray_set *sets)
{
    size_t i;
    for (i = 0; i < ggTraceNodeCount(tr); i++) {
        const ggTraceNode *n = ggTraceGetNode(tr, i);
        if (ray_push(&sets[n->kind == GG_RAY_EYE ? SET_EYE : SET_SECONDARY], n->o, n->d)) return -1;
    }
    for (i = 0; i < ggTraceLightCount(tr); i++) {
        const ggTraceLight *l = ggTraceGetLight(tr, i);
        if (l->verdict == GG_SHADOW_FACING_AWAY) continue; /* no shadow ray sent */
        if (ray_push(&sets[SET_SHADOW], l->origin, l->dir)) return -1;
    }
    return 0;
}

static int collect(ggScene *s, int size, ray_set *sets, ggError *err)
{
    ggRenderOptions o;
    ggTrace *tr = ggTraceCreate(NULL);
    ggColor px;
    int x, y, rc = GG_OK;
    if (!tr) return GG_ERROR_NOMEM;
    ggRenderOptionsDefault(&o);
    o.width = o.height = size;
    o.max_depth = 5;
    for (y = 0; y < size && rc == GG_OK; y++)
        for (x = 0; x < size && rc == GG_OK; x++) {
            rc = ggTracePixel(s, &o, x, y, 0, tr, &px, NULL, err);
            if (rc == GG_OK && collect_pixel(tr, sets)) rc = GG_ERROR_NOMEM;
        }
    ggTraceFree(tr);
    return rc;
}

/* Seconds for one pass over set k (hits counted into *hits, so that the
   loop is not optimised away). */
static double cast_set(const ggScene *s, const ray_set *set, int k, long *hits)
{
    double t0 = cli_now();
    size_t i;
    long h = 0;
    for (i = 0; i < set->n; i++) {
        if (k == SET_SHADOW)
            h += ggSceneOccluded(s, set->r[i], 0, 1);
        else
            h += ggSceneIntersect(s, set->r[i], 0, DBL_MAX, NULL);
    }
    *hits = h;
    return cli_now() - t0;
}

/* Mrays/s of set k: the median of `runs` passes. */
static double set_rate(const ggScene *s, const ray_set *set, int k, int runs, long *hits)
{
    double t[64];
    int i;
    if (!set->n) return 0;
    for (i = 0; i < runs && i < 64; i++) t[i] = cast_set(s, set, k, hits);
    return (double)set->n / bench_median(t, i) / 1e6;
}

/* Returns an exit code. */
static int scene_row(const bench_opts *bo, const char *name, const char *path)
{
    ggScene *s = ggSceneCreate(NULL);
    ray_set sets[NSETS];
    ggError err;
    int k, rc = EXIT_OK;
    int st = GG_OK;
    memset(sets, 0, sizeof sets);
    printf("%-*s", bench_name_width(bo), name);
    if (!s || (st = ggSceneLoadFile(s, path, &err)) != GG_OK ||
        (st = ggScenePrepare(s, &err)) != GG_OK ||
        (st = collect(s, bo->size, sets, &err)) != GG_OK) {
        printf(" failed: %s\n", s ? err.message : "out of memory");
        /* also where errors go, as every command says them (the table
           may be redirected or read by a script) */
        cli_error("%s", s ? err.message : "out of memory");
        rc = s ? cli_exit_code(st, 0) : EXIT_INPUT;
    } else {
        for (k = 0; k < NSETS; k++) {
            long hits = 0;
            double rate = set_rate(s, &sets[k], k, bo->runs, &hits);
            printf(" %9zu %6.1f%% %8.2f", sets[k].n,
                   sets[k].n ? 100.0 * (double)hits / (double)sets[k].n : 0.0, rate);
        }
        printf("\n");
    }
    for (k = 0; k < NSETS; k++) free(sets[k].r);
    ggSceneFree(s);
    fflush(stdout);
    return rc;
}

int bench_rays(const bench_opts *bo)
{
    char path[1024];
    int i, rc = EXIT_OK;
    printf("ggrt bench rays: the rays of a %dx%d render (depth 5, pixel centres), cast again "
           "on one thread, median of %d passes\n",
           bo->size, bo->size, bo->runs);
    bench_print_machine();
    printf("%-*s %9s %7s %8s %9s %7s %8s %9s %7s %8s\n", bench_name_width(bo), "scene", "eye",
           "hit", "Mrays/s", "secondary", "hit", "Mrays/s", "shadow", "blocked", "Mrays/s");
    for (i = 0; i < BENCH_NSPD && !bo->nargs; i++)
        if (bench_selected(bo->scenes, bench_spd_scenes[i])) {
            int r;
            snprintf(path, sizeof path, "%s/%s.nff", bo->spd_dir, bench_spd_scenes[i]);
            if ((r = scene_row(bo, bench_spd_scenes[i], path)) != EXIT_OK) rc = r;
        }
    for (i = 0; i < bo->nargs; i++) {
        int r = scene_row(bo, bench_row_name(bo->args[i]), bo->args[i]);
        if (r != EXIT_OK) rc = r;
    }
    printf("eye, secondary: closest hit (ggSceneIntersect, single rays, no hit record); shadow: "
           "any hit on (0, 1)\n(ggSceneOccluded, no occluder cache). secondary = reflection, "
           "refraction and TIR rays.\nMrays/s on one core; ggRender's eye rays go as packets.\n");
    return rc;
}
