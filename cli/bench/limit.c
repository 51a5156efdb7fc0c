/* SPDX-License-Identifier: MIT */
/*
** limit.c -- `ggrt bench limit`: how close a render comes to the time its
** kernels alone would take. Per scene: a render counted kernel by kernel
** (ggRenderCountKernels: the node, packet and leaf tests as the scene's
** traversal copy makes them, and the closest hits, each of which is
** shaded); each kernel timed alone in a loop on cached data
** (ggKernelLoop: ns per call, each call waiting for the last, median of
** `runs`); the kernel bound = sum over kernels of calls x ns per call;
** and the render's own time on one thread (ggRender, median of `runs`),
** over that bound. Everything on one thread.
**
** The model's assumptions: a kernel costs in a render what it costs in the
** loop (its data in the L1 cache, its branches predicted, one call at a
** time); the rest of a render (ray set-up, stack work, sorting the
** children, the leaf loops' bookkeeping, shadow-ray and secondary-ray
** set-up, tiles, the image) costs nothing. So render / bound >= 1, and
** what it exceeds 1 by is the time outside the kernels or kernels slower
** than alone (cache misses, mispredictions).
*/
#include "bench/bench.h"

#include <stdlib.h>
#include <string.h>

static const char *const kname[GG_KERNEL_KINDS] = {"node", "pnode", "pleaf", "tri4",
                                                   "tri",  "sphere", "other", "shade"};

/* ns per call of kernel k, the fastest of runs (a loop is only ever
   slowed down, by other work on the machine); -1 if the scene has no
   data. */
static double kernel_ns(const ggScene *s, const ggRenderOptions *o, int k, int runs)
{
    double t[64];
    const long n = 1000000;
    double best;
    int i;
    if (ggKernelLoop(s, o, k, 1000) < 0) return -1;
    for (i = 0; i < runs && i < 64; i++) {
        double t0 = cli_now();
        volatile double sink = ggKernelLoop(s, o, k, n);
        (void)sink;
        t[i] = (cli_now() - t0) / (double)n * 1e9;
    }
    if (i == 0) return -1;
    for (best = t[0]; i-- > 1;) best = t[i] < best ? t[i] : best;
    return best;
}

/* The render's median time over runs; *fast gets the fastest. */
static double render_s(ggScene *s, const ggRenderOptions *o, int runs, ggRayStats *st,
                       double *fast, ggError *err)
{
    double t[64] = {0};
    int i;
    for (i = 0; i < runs && i < 64; i++) {
        ggImage *img = NULL;
        double t0 = cli_now();
        int rc = ggRender(s, o, &img, st, err);
        t[i] = cli_now() - t0;
        ggImageFree(img);
        if (rc != GG_OK) return -1;
    }
    for (*fast = t[0], runs = 1; runs < i; runs++) *fast = t[runs] < *fast ? t[runs] : *fast;
    return bench_median(t, i);
}

static void count_row(int w, const char *name, const ggKernelCounts *c, uint64_t rays)
{
    const uint64_t v[7] = {c->node, c->packet_node, c->packet_leaf, c->tri4,
                           c->tri,  c->sphere,      c->other};
    double r = rays ? (double)rays : 1;
    int k;
    printf("%-*s %9llu", w, name, (unsigned long long)rays);
    for (k = 0; k < 7; k++) printf(" %7.2f", (double)v[k] / r);
    printf(" %7.3f\n", (double)c->hits / r);
}

/* One scene's rows; returns an exit code. */
static int scene_limit(const bench_opts *bo, const char *name, const char *path)
{
    ggScene *s = ggSceneCreate(NULL);
    ggRenderOptions o;
    ggKernelCounts c;
    ggRayStats st;
    ggError err;
    double ns[GG_KERNEL_KINDS], bound = 0, t, fast = 0;
    uint64_t calls[GG_KERNEL_KINDS], rays;
    int k, w = bench_name_width(bo);
    int rs = GG_OK;
    ggRenderOptionsDefault(&o);
    o.width = o.height = bo->size;
    o.max_depth = 5;
    o.threads = 1;
    if (!s || (rs = ggSceneLoadFile(s, path, &err)) != GG_OK ||
        (rs = ggScenePrepare(s, &err)) != GG_OK ||
        (rs = ggRenderCountKernels(s, &o, &c, &err)) != GG_OK ||
        (t = render_s(s, &o, bo->runs, &st, &fast, &err)) < 0) {
        /* (a failed render's status is not kept: bad input) */
        int rc = s && rs != GG_OK ? cli_exit_code(rs, 0) : EXIT_INPUT;
        printf("%-*s failed: %s\n", w, name, s ? err.message : "out of memory");
        cli_error("%s", s ? err.message : "out of memory"); /* and on stderr */
        ggSceneFree(s);
        return rc;
    }
    calls[0] = c.node, calls[1] = c.packet_node, calls[2] = c.packet_leaf, calls[3] = c.tri4;
    calls[4] = c.tri, calls[5] = c.sphere, calls[6] = c.other, calls[7] = c.hits;
    rays = st.eye + st.reflect + st.refract + st.shadow;
    count_row(w, name, &c, rays);
    printf("%-*s %9s", w, "  ns/call", "");
    for (k = 0; k < GG_KERNEL_KINDS; k++) {
        ns[k] = calls[k] ? kernel_ns(s, &o, k, bo->runs) : 0;
        if (ns[k] < 0)
            printf(" %7s", "-");
        else
            printf(" %7.2f", ns[k]);
        /* a kernel called but with no data of its own to time (none
           here): left out of the bound, which stays a lower bound */
        if (ns[k] > 0) bound += (double)calls[k] * ns[k] * 1e-9;
    }
    printf("\n%-*s %9s bound %.4f s; render %.4f s median, %.4f s fastest; render/bound "
           "%.2f median, %.2f fastest\n",
           w, "", "", bound, t, fast, bound > 0 ? t / bound : 0, bound > 0 ? fast / bound : 0);
    ggSceneFree(s);
    fflush(stdout);
    return EXIT_OK;
}

int bench_limit(const bench_opts *bo)
{
    char path[1024];
    int i, rc = EXIT_OK;
    printf("ggrt bench limit: %dx%d, depth 5, pixel centres, 1 thread, %d run%s\n", bo->size,
           bo->size, bo->runs, BENCH_S(bo->runs));
    bench_print_machine();
    printf("per ray (eye, secondary and shadow rays of the render): kernel calls as the scene's "
           "traversal makes them\n");
    printf("%-*s %9s", bench_name_width(bo), "scene", "rays");
    for (i = 0; i < GG_KERNEL_KINDS; i++) printf(" %7s", i == GG_KERNEL_SHADE ? "hits" : kname[i]);
    printf("\n");
    for (i = 0; i < BENCH_NSPD && !bo->nargs; i++) {
        int r;
        if (!bench_selected(bo->scenes, bench_spd_scenes[i])) continue;
        snprintf(path, sizeof path, "%s/%s.nff", bo->spd_dir, bench_spd_scenes[i]);
        if ((r = scene_limit(bo, bench_spd_scenes[i], path)) != EXIT_OK) rc = r;
    }
    for (i = 0; i < bo->nargs; i++) {
        int r = scene_limit(bo, bench_row_name(bo->args[i]), bo->args[i]);
        if (r != EXIT_OK) rc = r;
    }
    printf("node: 8-box node test (single rays); pnode: 8-box node test of a 16-ray packet; "
           "pleaf: a leaf's box\nagainst a packet's 16 rays; tri4: 4 triangles at once; tri, "
           "sphere, other: one element;\nhits: closest hits, each shaded (shade: the shading "
           "without its rays). ns/call: the kernel\nalone in a loop on cached data, each call "
           "after the last, fastest of the runs. bound = sum of calls x ns/call;\nrender/bound = how far the render "
           "is from its kernels' time.\n");
    return rc;
}
