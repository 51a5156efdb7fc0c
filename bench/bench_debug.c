/* SPDX-License-Identifier: MIT */
/*
** bench_debug.c -- what the image-level debugger costs: ggFind (three
** kinds of predicate), ggFindPath (a light-path expression), ggCheck and
** a render with four path layers (ggRenderOptions.layers: the four of
** docs/debugging.md, "Path layers") over a SIZE x SIZE image against a
** plain ggRender of it with the same threads, alternated round by round,
** medians (docs/debugging.md, "Cost"). The targets: at most 3x the
** render; the path find at most 2.5x; the layers at most 1.3x.
**   make bench-debug     or   build/bench/bench_debug [-s SIZE] [-r ROUNDS] [-t THREADS] SCENE...
** Prints one line per scene and task, the largest ratio of the debugger's
** tasks, the path find's and the layers' largest ratios.
*/
#include "ggrt.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* The tasks timed: a render, three finds, a check. */
#define PATH_EXPR "C.*<TS>.*<RD>L"
static const char *const task_name[] = {"render", "find some(kind == tir)",
                                        "find some(verdict == blocked)", "find pixel.r > 0.5",
                                        "check", ("find --path " PATH_EXPR),
                                        "render --aov (4 layers)"};
static const char *const layer_exprs[4] = {"C(<RD>[LA]|<RG>L|O)", "C<RS>+(<RD>[LA]|<RG>L|O|B)",
                                           "C<RS>*<TS>[<RS><TS>]*(<RD>[LA]|<RG>L|O|B)", "CB"};
static const char *const predicates[] = {"some(kind == tir)", "some(verdict == blocked)",
                                         "pixel.r > 0.5"};
#define NTASKS 7
#define PATH_TASK 5
#define AOV_TASK 6

/* o[0]: the render's options, o[1]: with the layers. */
static int run_task(ggScene *s, const ggRenderOptions *o, int k, ggPredicate *const *pred,
                    const ggPathExpr *path)
{
    ggError e;
    int rc;
    if (k == 0 || k == AOV_TASK) {
        ggImage *img = NULL;
        rc = ggRender(s, o + (k == AOV_TASK), &img, NULL, &e);
        ggImageFree(img);
    } else if (k < 4) {
        ggFindResult *r = NULL;
        rc = ggFind(s, o, pred[k - 1], 10, &r, &e);
        ggFindResultFree(r);
    } else if (k == PATH_TASK) {
        ggFindResult *r = NULL;
        rc = ggFindPath(s, o, path, 10, &r, &e);
        ggFindResultFree(r);
    } else {
        ggCheckResult *r = NULL;
        rc = ggCheck(s, o, NULL, &r, &e);
        ggCheckResultFree(r);
    }
    if (rc != GG_OK) fprintf(stderr, "bench_debug: %s\n", e.message);
    return rc;
}

int main(int argc, char **argv)
{
    static char *def[] = {"examples/scenes/glass.nff",          "examples/scenes/default.nff",
                          "examples/scenes/water.nff",          "examples/scenes/spd/balls-s3.nff",
                          "examples/scenes/spd/gears.nff",      "examples/scenes/spd/mount.nff",
                          "examples/scenes/spd/tetra.nff",      "examples/scenes/spd/rings.nff",
                          "examples/scenes/spd/teapot-s12.nff", "examples/scenes/spd/tree.nff"};
    int size = 512, rounds = 3, threads = 2, i, k, r;
    double worst = 0, worst_path = 0, worst_aov = 0;
    const char *worst_at = "", *worst_path_at = "", *worst_aov_at = "";
    ggPredicate *pred[3];
    ggPathExpr *path;
    ggPathLayers *layers;
    float *map;
    static const char usage[] = "usage: bench_debug [-s SIZE] [-r ROUNDS 1..64] [-t THREADS] "
                                "[SCENE...]\n(make bench-debug; default: 10 example and SPD "
                                "scenes, 512, 3 rounds, 2 threads)\n";
    for (i = 1; i < argc && argv[i][0] == '-'; i += 2) {
        if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) return printf("%s", usage), 0;
        if (i + 1 >= argc) return fprintf(stderr, "%s", usage), 2;
        if (!strcmp(argv[i], "-s"))
            size = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "-r"))
            rounds = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "-t"))
            threads = atoi(argv[i + 1]);
        else
            return fprintf(stderr, "bench_debug: unknown option '%s'\n%s", argv[i], usage), 2;
    }
    if (i >= argc) argv = def, i = 0, argc = (int)(sizeof def / sizeof def[0]);
    if (rounds < 1 || rounds > 64 || size < 1) return fprintf(stderr, "%s", usage), 2;
    for (k = 0; k < 3; k++)
        if (ggPredicateParse(predicates[k], NULL, &pred[k], NULL) != GG_OK) return 1;
    if (ggPathParse(PATH_EXPR, NULL, &path, NULL) != GG_OK) return 1;
    if (ggPathLayersCompile(layer_exprs, 4, NULL, &layers, NULL) != GG_OK) return 1;
    if (!(map = calloc((size_t)size * size * 3, 4 * sizeof *map))) return 1;
    printf("bench_debug: %dx%d, %d threads, median of %d alternated rounds; ratio = task / "
           "render\n",
           size, size, threads, rounds);
    for (; i < argc; i++) {
        ggScene *s = ggSceneCreate(NULL);
        ggRenderOptions o[2];
        ggError e;
        double t[NTASKS][64];
        if (!s || ggSceneLoadFile(s, argv[i], &e) != GG_OK || ggScenePrepare(s, &e) != GG_OK) {
            fprintf(stderr, "bench_debug: %s\n", s ? e.message : "out of memory");
            return 1;
        }
        ggRenderOptionsDefault(&o[0]);
        o[0].width = o[0].height = size, o[0].threads = threads;
        o[1] = o[0], o[1].layers = layers, o[1].layer_map = map;
        for (r = 0; r < rounds; r++)
            for (k = 0; k < NTASKS; k++) {
                double t0 = now();
                if (run_task(s, o, k, pred, path) != GG_OK) return 1;
                t[k][r] = now() - t0;
            }
        for (k = 0; k < NTASKS; k++) qsort(t[k], (size_t)rounds, sizeof t[k][0], cmp);
        for (k = 0; k < NTASKS; k++) {
            double ratio = t[k][rounds / 2] / t[0][rounds / 2];
            printf("%-36s %-30s %8.4fs %6.2fx\n", argv[i], task_name[k], t[k][rounds / 2], ratio);
            if (k && k != AOV_TASK && ratio > worst) worst = ratio, worst_at = argv[i];
            if (k == AOV_TASK && ratio > worst_aov) worst_aov = ratio, worst_aov_at = argv[i];
            if (k == PATH_TASK && ratio > worst_path) worst_path = ratio, worst_path_at = argv[i];
        }
        ggSceneFree(s);
    }
    printf("bench_debug: largest ratio %.2fx (%s); target <= 3x\n", worst, worst_at);
    printf("bench_debug: find --path %s: largest ratio %.2fx (%s); target <= 2.5x\n", PATH_EXPR,
           worst_path, worst_path_at);
    printf("bench_debug: render with 4 path layers: largest ratio %.2fx (%s); target <= 1.3x\n",
           worst_aov, worst_aov_at);
    ggPathLayersFree(layers);
    free(map);
    for (k = 0; k < 3; k++) ggPredicateFree(pred[k]);
    ggPathFree(path);
    return 0;
}
