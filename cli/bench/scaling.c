/* SPDX-License-Identifier: MIT */
/*
** scaling.c -- `ggrt bench scaling`: render time against primitive count
** (balls-s1..s4), image size and threads.
*/
#include "bench.h"

#include <math.h>
#include <string.h>

static double render_seconds(ggScene *s, int w, int h, int threads, int runs, ggRayStats *st)
{
    ggRenderOptions o;
    double t[64];
    int k;
    ggRenderOptionsDefault(&o);
    o.width = w, o.height = h, o.threads = threads;
    for (k = 0; k < runs && k < 64; k++) {
        ggImage *img = NULL;
        double t0 = cli_now();
        memset(st, 0, sizeof *st);
        if (ggRender(s, &o, &img, st, NULL) != GG_OK) return -1;
        t[k] = cli_now() - t0;
        ggImageFree(img);
    }
    return bench_median(t, k);
}

static ggScene *load_prepared(const char *path)
{
    ggScene *s = ggSceneCreate(NULL);
    ggError e;
    if (!s || ggSceneLoadFile(s, path, &e) != GG_OK || ggScenePrepare(s, &e) != GG_OK) {
        fprintf(stderr, "ggrt: %s\n", s ? e.message : "out of memory");
        ggSceneFree(s);
        return NULL;
    }
    return s;
}

int bench_scaling(const bench_opts *bo)
{
    static const char *const balls[] = {"balls-s1", "balls-s2", "balls-s3", "balls-s4"};
    double ns[4], tr[4];
    int i, size = bo->size ? bo->size : 256;
    printf("\nscaling: render time against primitive count (%dx%d, %d threads, median of %d)\n",
           size, size, bo->threads, bo->runs);
    printf("%-10s %8s %9s %10s %12s\n", "scene", "prims", "time", "rays", "ns per ray");
    for (i = 0; i < 4; i++) {
        char path[512];
        ggScene *s;
        ggSceneInfo in;
        ggRayStats st;
        double t, rays;
        snprintf(path, sizeof path, "%s/%s.nff", bo->spd_dir, balls[i]);
        if (!(s = load_prepared(path))) return EXIT_INPUT;
        ggSceneGetInfo(s, &in);
        t = render_seconds(s, size, size, bo->threads, bo->runs, &st);
        rays = (double)(st.eye + st.reflect + st.refract + st.shadow);
        ns[i] = (double)in.primitives, tr[i] = t / rays * 1e9 * bo->threads;
        printf("%-10s %8zu %8.4fs %10.0f %12.1f\n", balls[i], in.primitives, t, rays, tr[i]);
        ggSceneFree(s);
    }
    {
        /* Least squares of time per ray against ln n over balls-s2..s4, and
           the power-law exponent between s2 and s4: log-like growth shows
           as a small exponent and a good straight-line fit in ln n. */
        double sx = 0, sy = 0, sxx = 0, sxy = 0, b, a, alpha;
        int k, m = 3;
        for (k = 1; k < 4; k++) {
            double x = log(ns[k]);
            sx += x, sy += tr[k], sxx += x * x, sxy += x * tr[k];
        }
        b = (m * sxy - sx * sy) / (m * sxx - sx * sx);
        a = (sy - b * sx) / m;
        alpha = log(tr[3] / tr[1]) / log(ns[3] / ns[1]);
        printf("fit balls-s2..s4: ns/ray = %.1f + %.2f ln(n); as a power law ns/ray ~ n^%.3f "
               "(n grew %.0fx, ln n %.2fx, ns/ray %.2fx)\n",
               a, b, alpha, ns[3] / ns[1], log(ns[3]) / log(ns[1]), tr[3] / tr[1]);
    }
    {
        char path[512];
        ggScene *s;
        ggRayStats st;
        int sz[3] = {128, 256, 512}, th;
        double t1 = 0;
        snprintf(path, sizeof path, "%s/balls-s3.nff", bo->spd_dir);
        if (!(s = load_prepared(path))) return EXIT_INPUT;
        printf("\nscaling: balls-s3 against image size (%d threads)\n", bo->threads);
        for (i = 0; i < 3; i++) {
            double t = render_seconds(s, sz[i], sz[i], bo->threads, bo->runs, &st);
            printf("%4dx%-4d %8.4fs  %6.1f ns per pixel\n", sz[i], sz[i], t,
                   t / ((double)sz[i] * sz[i]) * 1e9);
        }
        printf("\nscaling: balls-s3 at %dx%d against threads\n", size, size);
        for (th = 1; th <= 2; th++) {
            double t = render_seconds(s, size, size, th, bo->runs, &st);
            if (th == 1) t1 = t;
            printf("%d thread%s %8.4fs  speed-up %.2fx\n", th, th > 1 ? "s" : " ", t, t1 / t);
        }
        ggSceneFree(s);
    }
    return EXIT_OK;
}
