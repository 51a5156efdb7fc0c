/* SPDX-License-Identifier: MIT */
/*
** bench_render.c -- render time of scenes, for comparing library builds
** (make bench-trace runs it against a library built without the ray-tree
** recorder). usage: bench_render [-s SIZE] [-r RUNS] [-t THREADS] SCENE...
** Prints one line per scene: name and the median render seconds.
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

int main(int argc, char **argv)
{
    static char *def[] = {"examples/scenes/spd/balls-s3.nff", "examples/scenes/glass.nff"};
    int size = 512, runs = 3, threads = 2, i, k;
    static const char usage[] = "usage: bench_render [-s SIZE] [-r RUNS 1..64] [-t THREADS] "
                                "[SCENE...]\n(make bench-render; default: balls-s3 and glass, "
                                "512, 3 runs, 2 threads)\n";
    for (i = 1; i < argc && argv[i][0] == '-'; i += 2) {
        if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) return printf("%s", usage), 0;
        if (i + 1 >= argc) return fprintf(stderr, "%s", usage), 2;
        if (!strcmp(argv[i], "-s")) size = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "-r")) runs = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "-t")) threads = atoi(argv[i + 1]);
        else
            return fprintf(stderr, "bench_render: unknown option '%s'\n%s", argv[i], usage), 2;
    }
    if (i >= argc) argv = def, i = 0, argc = 2; /* `make bench` runs it bare */
    if (runs < 1 || runs > 64 || size < 1) return fprintf(stderr, "%s", usage), 2;
    for (; i < argc; i++) {
        ggScene *s = ggSceneCreate(NULL);
        ggRenderOptions o;
        ggError e;
        double t[64];
        if (!s || ggSceneLoadFile(s, argv[i], &e) != GG_OK || ggScenePrepare(s, &e) != GG_OK) {
            fprintf(stderr, "bench_render: %s\n", s ? e.message : "out of memory");
            return 1;
        }
        ggRenderOptionsDefault(&o);
        o.width = o.height = size;
        o.threads = threads;
        for (k = 0; k < runs; k++) {
            ggImage *img = NULL;
            double t0 = now();
            if (ggRender(s, &o, &img, NULL, &e) != GG_OK) return 1;
            t[k] = now() - t0;
            ggImageFree(img);
        }
        qsort(t, (size_t)runs, sizeof t[0], cmp);
        printf("%s %.6f\n", argv[i], t[runs / 2]);
        ggSceneFree(s);
    }
    return 0;
}
