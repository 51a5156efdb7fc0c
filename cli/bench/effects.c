/* SPDX-License-Identifier: MIT */
/*
** effects.c -- `ggrt bench effects`: what simulating only the
** effects a scene calls for saves, and proof that it changes nothing.
*/
#include "bench/bench.h"

#include <string.h>

const char *const bench_effects_scenes[] = {
    "default", "glass", "water", "gold", "prism", "torus", "texture",
    /* Opaque SPD scenes: where the specialised path has the most to skip. */
    "spd/balls-s3", "spd/tetra", "spd/tree"};
typedef char bench_neffects_ok
    [sizeof bench_effects_scenes / sizeof *bench_effects_scenes == BENCH_NEFFECTS ? 1 : -1];

static int render_timed(ggScene *s, ggRenderOptions *o, int runs, ggImage **keep, double *med)
{
    double t[64];
    int k;
    for (k = 0; k < runs && k < 64; k++) {
        ggImage *img = NULL;
        double t0 = cli_now();
        if (ggRender(s, o, &img, NULL, NULL) != GG_OK) return -1;
        t[k] = cli_now() - t0;
        if (k == 0)
            *keep = img;
        else
            ggImageFree(img);
    }
    *med = bench_median(t, k);
    return 0;
}

int bench_effects(const bench_opts *bo)
{
    size_t i;
    int e;
    printf("ggrt bench effects: %dx%d, %d thread%s, median of %d run%s\n\n", bo->size, bo->size,
           bo->threads, BENCH_S(bo->threads), bo->runs, BENCH_S(bo->runs));
    printf("%-12s %9s %9s %7s %-9s  effects\n", "scene", "own", "forced", "ratio", "image");
    for (i = 0; i < BENCH_NEFFECTS; i++) {
        char path[512];
        ggScene *s = ggSceneCreate(NULL);
        ggRenderOptions o;
        ggImage *a = NULL, *b = NULL;
        ggError err;
        double ta, tb;
        int same;
        unsigned fx;
        int st;
        if (!bench_selected(bo->scenes, bench_effects_scenes[i])) {
            ggSceneFree(s);
            continue;
        }
        snprintf(path, sizeof path, "examples/scenes/%s.nff", bench_effects_scenes[i]);
        if (!s || (st = ggSceneLoadFile(s, path, &err)) != GG_OK ||
            (st = ggScenePrepare(s, &err)) != GG_OK) {
            int rc = s ? cli_exit_code(st, 0) : EXIT_INPUT;
            printf("%-9s failed: %s\n", bench_effects_scenes[i], s ? err.message : "out of memory");
            ggSceneFree(s);
            return rc;
        }
        ggRenderOptionsDefault(&o);
        o.width = bo->size, o.height = bo->size * 3 / 4, o.threads = bo->threads;
        if (render_timed(s, &o, bo->runs, &a, &ta) != 0) return EXIT_INPUT;
        o.force_effects = GG_EFFECT_ALL;
        if (render_timed(s, &o, bo->runs, &b, &tb) != 0) return EXIT_INPUT;
        same = memcmp(ggImagePixelsConst(a), ggImagePixelsConst(b),
                      (size_t)o.width * o.height * 3 * sizeof(float)) == 0;
        fx = ggSceneEffects(s);
        printf("%-12s %8.3fs %8.3fs %6.2fx %-9s ", bench_effects_scenes[i], ta, tb, tb / ta,
               same ? "identical" : "DIFFERENT");
        for (e = 0; e < GG_EFFECT_COUNT; e++)
            if (fx & (1u << e)) printf(" %s", ggEffectName(1u << e));
        printf("\n");
        ggImageFree(a), ggImageFree(b);
        ggSceneFree(s);
    }
    printf("\nown = the scene's effect set; forced = every effect simulated "
           "(--force-effects); ratio = forced / own\n");
    return EXIT_OK;
}
