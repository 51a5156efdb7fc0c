/* SPDX-License-Identifier: MIT */
/*
** kernels.c -- ggRenderCountKernels and ggKernelLoop: what a render's
** queries cost, kernel by kernel (`ggrt bench limit`). The counts come
** from a counting copy of the AVX traversal (bvh_avx.c built with
** GG_TRAV_COUNT), swapped in for one render; the copies renders take
** count nothing. The loops run the kernels of the copy the scene's
** queries take (gg_geom_kloop) and the shading without its rays
** (gg_shade_local).
*/
#include "render.h"
#include "shade.h"

#include "vec.h"

#include <math.h>
#include <string.h>

GG_API int ggRenderCountKernels(ggScene *scene, const ggRenderOptions *opt,
                                ggKernelCounts *counts, ggError *err)
{
    ggRenderOptions o;
    ggImage *img = NULL;
    gg_kcount kc;
    int rc;
    if (!scene || !counts) return gg_error_set(err, GG_ERROR_INVALID, "scene or counts is NULL");
    memset(counts, 0, sizeof *counts); /* after the NULL checks: base.h rule 1 */
    if (opt)
        o = *opt;
    else
        ggRenderOptionsDefault(&o);
    if (o.accuracy.intersect == GG_ACC_ISECT_FLOAT)
        return gg_error_set(err, GG_ERROR_UNSUPPORTED,
                            "single-precision queries have no counting copy");
    if ((rc = ggScenePrepare(scene, err)) != GG_OK) return rc;
    memset(&kc, 0, sizeof kc);
    if (gg_geom_count_begin(scene->geom, &kc))
        return gg_error_set(err, GG_ERROR_UNSUPPORTED,
                            "the scene's queries take the plain traversal (no counting copy)");
    o.threads = 1;
    o.cost_map = NULL;
    rc = ggRender(scene, &o, &img, NULL, err);
    gg_geom_count_end(scene->geom);
    ggImageFree(img);
    if (rc != GG_OK) return rc;
    counts->closest = kc.closest, counts->any = kc.any, counts->shadow = kc.shadow;
    counts->packets = kc.packets, counts->node = kc.box8, counts->packet_node = kc.pbox4;
    counts->packet_leaf = kc.plane, counts->tri4 = kc.tri4, counts->tri = kc.tri;
    counts->sphere = kc.sphere, counts->other = kc.other, counts->hits = kc.hits;
    return GG_OK;
}

/* A hit for the shading loop: the first of a few eye rays from the
   image's centre outwards. */
static int first_hit(const ggScene *s, const ggRenderOptions *o, gg_rayq *q, gg_hit *h)
{
    int w = o->width > 0 ? o->width : s->camera.width;
    int ht = o->height > 0 ? o->height : s->camera.height, i, j;
    for (i = 0; i < 8; i++)
        for (j = 0; j < 8; j++) {
            ggRay ray = ggCameraRay(s, o, w * (0.5 + (i & 1 ? i : -i) / 17.0),
                                    ht * (0.5 + (j & 1 ? j : -j) / 17.0));
            *q = gg_rayq_make(ray.o, ray.d, 0, INFINITY, NULL);
            if (gg_geom_intersect(s->geom, q, h)) return 1;
        }
    return 0;
}

static double shade_loop(const ggScene *s, const ggRenderOptions *o, long n)
{
    static volatile double zero_v;
    const double zero = zero_v;
    gg_shade_ctx ctx;
    gg_rayq q;
    gg_hit h;
    double sum = 0;
    long i;
    if (!first_hit(s, o, &q, &h)) return -1;
    gg_shade_init(&ctx, s, 5, 0, false, &o->accuracy);
    for (i = 0; i < n; i++) {
        ggColor c = gg_shade_local(&ctx, &q, &h);
        sum += c.r + c.g + c.b;
        h.t += c.r * zero; /* the next call waits for this one */
    }
    return sum;
}

GG_API double ggKernelLoop(const ggScene *scene, const ggRenderOptions *opt, int k, long n)
{
    ggRenderOptions o;
    ggRay ray;
    gg_rayq q;
    if (!scene || !scene->prepared || k < 0 || k >= GG_KERNEL_KINDS || n < 0) return -1;
    if (opt)
        o = *opt;
    else
        ggRenderOptionsDefault(&o);
    if (k == GG_KERNEL_SHADE) return shade_loop(scene, &o, n);
    ray = ggCameraRay(scene, &o, 0, 0);
    q = gg_rayq_make(ray.o, ray.d, 0, INFINITY, NULL);
    return gg_geom_kloop(scene->geom, k, &q, n);
}
