/* SPDX-License-Identifier: MIT */
/*
** scaling.c -- `ggrt bench scaling`: render time against primitive count
** (balls-s1..s4), image size and threads, and per SPD scene the speed-up
** from 1 to 2 threads with the share of the render spent outside the
** parallel tile loop.
*/
#include "bench/bench.h"

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

/* The tile loop seen through the progress callback: the first and the
   last report (time and pixels done). */
typedef struct tile_clock {
    double t0, t1;
    long d0, d1;
    int n;
} tile_clock;

static int clock_progress(void *ud, long done, long total)
{
    tile_clock *c = ud;
    double t = cli_now();
    (void)total;
    if (c->n++ == 0) c->t0 = t, c->d0 = done;
    c->t1 = t, c->d1 = done;
    return 0;
}

/* One render; *serial gets the seconds outside the tile loop: the whole
   render minus the tile loop's span, which runs from the first report
   back (at the rate between the first and the last report) to where the
   loop had done nothing, up to the last report (all pixels done). */
static double render_serial(ggScene *s, int size, int threads, double *serial)
{
    ggRenderOptions o;
    ggImage *img = NULL;
    tile_clock c;
    double t0, t, rate, start;
    memset(&c, 0, sizeof c);
    ggRenderOptionsDefault(&o);
    o.width = o.height = size, o.threads = threads;
    o.progress = clock_progress, o.progress_ud = &c;
    t0 = cli_now();
    if (ggRender(s, &o, &img, NULL, NULL) != GG_OK) return -1;
    t = cli_now() - t0;
    ggImageFree(img);
    rate = c.n > 1 && c.d1 > c.d0 ? (c.d1 - c.d0) / (c.t1 - c.t0) : 0;
    start = rate > 0 ? c.t0 - c.d0 / rate : t0;
    *serial = t - (c.t1 - (start > t0 ? start : t0));
    if (*serial < 0) *serial = 0;
    return t;
}

/* Per SPD scene: 1 and 2 threads, medians of bo->runs, the speed-up and
   the serial share (of the 2-thread render). */
static int threads_table(const bench_opts *bo, int size)
{
    int i, rc;
    printf("\nscaling: SPD scenes at %dx%d against threads (median of %d; serial = time outside "
           "the tile loop)\n",
           size, size, bo->runs);
    printf("%-11s %9s %9s %9s %9s %8s\n", "scene", "1 thread", "2 threads", "speed-up", "serial",
           "share");
    for (i = 0; i < BENCH_NSPD; i++) {
        char path[512];
        ggScene *s;
        double t[2][64], sr[64], tm[2], smed;
        int th, k, runs = bo->runs < 64 ? bo->runs : 64;
        if (!bench_selected(bo->scenes, bench_spd_scenes[i])) continue;
        snprintf(path, sizeof path, "%s/%s.nff", bo->spd_dir, bench_spd_scenes[i]);
        if (!(s = cli_load_scene(path, NULL, NULL, 1, &rc))) return rc;
        for (k = 0; k < runs; k++)
            for (th = 1; th <= 2; th++) {
                double ser = 0;
                t[th - 1][k] = render_serial(s, size, th, &ser);
                if (t[th - 1][k] < 0) {
                    ggSceneFree(s);
                    return EXIT_INPUT;
                }
                if (th == 2) sr[k] = ser;
            }
        tm[0] = bench_median(t[0], runs), tm[1] = bench_median(t[1], runs);
        smed = bench_median(sr, runs);
        printf("%-11s %8.4fs %8.4fs %8.2fx %8.4fs %7.2f%%\n", bench_spd_scenes[i], tm[0], tm[1],
               tm[0] / tm[1], smed, 100 * smed / tm[1]);
        ggSceneFree(s);
    }
    return EXIT_OK;
}

int bench_scaling(const bench_opts *bo)
{
    static const char *const balls[] = {"balls-s1", "balls-s2", "balls-s3", "balls-s4"};
    double ns[4], tr[4];
    int i, rc, size = bo->size ? bo->size : 256;
    printf("\nscaling: render time against primitive count (%dx%d, %d thread%s, median of %d)\n",
           size, size, bo->threads, BENCH_S(bo->threads), bo->runs);
    printf("%-10s %8s %9s %10s %12s\n", "scene", "prims", "time", "rays", "ns per ray");
    for (i = 0; i < 4; i++) {
        char path[512];
        ggScene *s;
        ggSceneInfo in;
        ggRayStats st;
        double t, rays;
        snprintf(path, sizeof path, "%s/%s.nff", bo->spd_dir, balls[i]);
        if (!(s = cli_load_scene(path, NULL, NULL, 1, &rc))) return rc;
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
        if (!(s = cli_load_scene(path, NULL, NULL, 1, &rc))) return rc;
        printf("\nscaling: balls-s3 against image size (%d thread%s)\n", bo->threads,
               BENCH_S(bo->threads));
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
    return threads_table(bo, size);
}
