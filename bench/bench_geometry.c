/* SPDX-License-Identifier: MIT */
/*
** bench_geometry.c -- BVH build and ray throughput, single-threaded.
**
**   make bench-geometry                 all scenes
**   build/bench/bench_geometry [-n RES] [-r RAYS] [-k COLUMN] [SCENE.nff...]
**
** Per scene: build time, BVH nodes, bytes per primitive (BVH nodes, leaf
** slots and intersection records), and millions of rays per second for
** closest hit and any hit on random rays (origin in the scene box, random
** direction) and on camera rays (RES x RES pixel centres), plus shadow
** rays from the camera rays' hit points to every light (any hit, t < 1).
** Scenes: generated ones (random spheres, random triangles, a sphereflake
** like SPD balls) and the SPD files in examples/scenes/spd, read with
** ggSceneLoadFile (build time = the BVH build inside ggScenePrepare).
*/
#include "geom.h"
#include "scene.h"
#include "vec.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct bscene {
    char name[64];
    gg_geom *g;
    ggVec3 from, at, up;
    double fov;
    ggVec3 lights[16];
    int nlights;
    int prebuilt; /* the scene loader built the BVH already */
} bscene;

/* ---- SPD files through the library's NFF loader ---- */

static int load_nff(bscene *s, const char *path, ggScene **owner)
{
    ggScene *sc = ggSceneCreate(NULL);
    ggError err;
    ggCamera cam;
    size_t i;
    if (!sc || ggSceneLoadFile(sc, path, &err) != GG_OK || ggScenePrepare(sc, &err) != GG_OK) {
        ggSceneFree(sc);
        return -1;
    }
    cam = ggSceneCamera(sc);
    s->from = cam.from, s->at = cam.at, s->up = cam.up, s->fov = cam.fov_deg;
    for (i = 0; i < sc->nlights && i < 16; i++) s->lights[s->nlights++] = sc->lights[i].pos;
    s->g = sc->geom;
    *owner = sc;
    return 0;
}

/* ---- generated scenes ---- */

/* The plain any-hit query, without an occluder cache. */
static int occluded(const gg_geom *g, const gg_rayq *q)
{
    uint32_t none = 0;
    return gg_geom_occluded(g, q, &none, NULL);
}

static uint64_t rng = 88172645463325252ull;
static double urand(void)
{
    rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
    return (double)(rng >> 11) * 0x1.0p-53;
}

static void flake(gg_geom *g, ggVec3 c, double r, ggVec3 dir, int depth, int *obj)
{
    ggVec3 u, w;
    int i;
    gg_geom_add_sphere(g, c, r, (*obj)++);
    if (depth == 0) return;
    u = v3norm(v3cross(dir, fabs(dir.x) < 0.9 ? v3(1, 0, 0) : v3(0, 1, 0)));
    w = v3cross(dir, u);
    for (i = 0; i < 9; i++) {
        double a = 2 * GG_PI * i / 9 + (i % 3) * 0.3, el = i < 6 ? 0.2 : 1.0;
        ggVec3 d = v3norm(v3add(v3scale(dir, sin(el)),
                                v3scale(v3add(v3scale(u, cos(a)), v3scale(w, sin(a))), cos(el))));
        flake(g, v3madd(c, d, r * 4.0 / 3.0), r / 3, d, depth - 1, obj);
    }
}

static void gen_scene(bscene *s, int which)
{
    int i, obj = 0;
    s->g = gg_geom_create(NULL);
    s->fov = 45;
    s->up = v3(0, 0, 1);
    s->nlights = 2;
    s->lights[0] = v3(10, 20, 30);
    s->lights[1] = v3(-20, 5, 25);
    if (which == 0) {
        snprintf(s->name, sizeof s->name, "gen 10k spheres");
        for (i = 0; i < 10000; i++)
            gg_geom_add_sphere(s->g, v3(urand() * 20 - 10, urand() * 20 - 10, urand() * 20 - 10),
                               0.05 + 0.2 * urand(), obj++);
        s->from = v3(25, 18, 12), s->at = v3(0, 0, 0);
    } else if (which == 1) {
        snprintf(s->name, sizeof s->name, "gen 100k triangles");
        for (i = 0; i < 100000; i++) {
            ggVec3 c = v3(urand() * 20 - 10, urand() * 20 - 10, urand() * 20 - 10), p[3];
            int k;
            for (k = 0; k < 3; k++)
                p[k] = v3add(c, v3(urand() * 0.6 - 0.3, urand() * 0.6 - 0.3, urand() * 0.6 - 0.3));
            gg_geom_add_triangle(s->g, p, NULL, obj++);
        }
        s->from = v3(25, 18, 12), s->at = v3(0, 0, 0);
    } else {
        ggVec3 q[4] = {{12, 12, -0.5}, {-12, 12, -0.5}, {-12, -12, -0.5}, {12, -12, -0.5}};
        snprintf(s->name, sizeof s->name, "gen sphereflake");
        gg_geom_add_polygon(s->g, q, 4, obj++);
        flake(s->g, v3(0, 0, 0), 0.5, v3(0, 0, 1), 4, &obj);
        s->from = v3(2.1, 1.3, 1.7), s->at = v3(0, 0, 0);
        s->lights[0] = v3(4, 3, 2), s->lights[1] = v3(1, -4, 4);
    }
}

/* ---- measurement ---- */

static void camera_ray(const bscene *s, int res, int i, int j, gg_rayq *q)
{
    ggVec3 w = v3norm(v3sub(s->at, s->from)), u = v3norm(v3cross(w, s->up)), v = v3cross(u, w);
    double h = tan(s->fov * GG_PI / 360), x = (2 * (i + 0.5) / res - 1) * h,
           y = (1 - 2 * (j + 0.5) / res) * h;
    q->o = s->from;
    q->d = v3norm(v3add(w, v3add(v3scale(u, x), v3scale(v, y))));
    q->tmin = 0, q->tmax = INFINITY;
    q->ignore_prim = UINT32_MAX, q->skip_flags = 0;
    q->inside = UINT32_MAX, q->opt = &gg_qopt_default;
}

static void random_rays(const gg_geom *g, gg_rayq *qs, int n)
{
    ggVec3 lo, hi;
    int i;
    gg_geom_bounds(g, &lo, &hi);
    for (i = 0; i < n; i++) {
        double z = urand() * 2 - 1, ph = urand() * 2 * GG_PI, sr = sqrt(1 - z * z);
        qs[i].o = v3(lo.x + (hi.x - lo.x) * urand(), lo.y + (hi.y - lo.y) * urand(),
                     lo.z + (hi.z - lo.z) * urand());
        qs[i].d = v3(sr * cos(ph), sr * sin(ph), z);
        qs[i].tmin = 0, qs[i].tmax = INFINITY;
        qs[i].ignore_prim = UINT32_MAX, qs[i].skip_flags = 0;
        qs[i].inside = UINT32_MAX, qs[i].opt = &gg_qopt_default;
    }
}

static volatile long sink;
static int only = -1; /* -k K: measure only column K (0..4), for profiling */

/* Mrays/s of closest (any = 0) or any hit over the rays: the best of
   three runs, since the machine may be shared. */
static double rate(const gg_geom *g, const gg_rayq *qs, int n, int any)
{
    double best = 0;
    int rep;
    for (rep = 0; rep < 3; rep++) {
        double t0 = gg_time_now(), t;
        long hits = 0;
        int i;
        gg_hit h;
        for (i = 0; i < n; i++)
            hits += any ? occluded(g, &qs[i]) : gg_geom_intersect(g, &qs[i], &h);
        t = gg_time_now() - t0;
        sink += hits;
        if (n / t * 1e-6 > best) best = n / t * 1e-6;
    }
    return best;
}

/* Shadow rays with one occluder cache per light, in pixel order, as a
   renderer would issue them. */
static double rate_cached(const gg_geom *g, const gg_rayq *qs, const int *light, int n)
{
    double best = 0;
    int rep;
    for (rep = 0; rep < 3; rep++) {
        uint32_t cache[16] = {0};
        double t0 = gg_time_now(), t;
        long hits = 0;
        int i;
        for (i = 0; i < n; i++) hits += gg_geom_occluded(g, &qs[i], &cache[light[i]], NULL);
        t = gg_time_now() - t0;
        sink += hits;
        if (n / t * 1e-6 > best) best = n / t * 1e-6;
    }
    return best;
}

static void run(bscene *s, int res, int nrand)
{
    gg_bvh_stats st;
    gg_rayq *rq = malloc(sizeof *rq * (size_t)nrand);
    gg_rayq *cq = malloc(sizeof *cq * (size_t)res * (size_t)res);
    gg_rayq *sq = malloc(sizeof *sq * (size_t)res * (size_t)res * (size_t)s->nlights);
    int *sl = malloc(sizeof *sl * (size_t)res * (size_t)res * (size_t)s->nlights);
    int i, j, k, ns = 0, nc = res * res;
    double cr, ca, rr, ra, sr, sc;
    if (!s->g || (!s->prebuilt && gg_geom_build(s->g, NULL) != GG_OK)) {
        printf("%-24s build failed\n", s->name);
        return;
    }
    gg_geom_bvh_stats(s->g, &st);
    random_rays(s->g, rq, nrand);
    for (j = 0; j < res; j++)
        for (i = 0; i < res; i++) camera_ray(s, res, i, j, &cq[j * res + i]);
    /* Shadow rays from the camera rays' hits, spawned as the renderer will. */
    for (i = 0; i < nc; i++) {
        gg_hit h;
        gg_surf sf;
        if (!gg_geom_intersect(s->g, &cq[i], &h)) continue;
        gg_geom_surface(s->g, &cq[i], &h, &sf, GG_SURF_UV);
        for (k = 0; k < s->nlights; k++) {
            gg_rayq *q = &sq[ns];
            q->d = v3sub(s->lights[k], sf.p);
            if (v3dot(q->d, sf.ng) * v3dot(cq[i].d, sf.ng) >= 0) continue; /* faces away */
            q->o = gg_offset_origin(&sf, q->d);
            q->d = v3sub(s->lights[k], q->o);
            q->tmin = 0, q->tmax = 1;
            q->ignore_prim = h.prim, q->skip_flags = 0;
            q->inside = UINT32_MAX, q->opt = &gg_qopt_default;
            sl[ns] = k;
            ns++;
        }
    }
    if (only >= 0) {
        int cnt[5];
        cnt[0] = cnt[1] = nrand, cnt[2] = cnt[3] = nc, cnt[4] = ns;
        printf("queries: %d\n", only < 6 ? 3 * cnt[only == 5 ? 4 : only] : 0);
    }
    rr = only < 0 || only == 0 ? rate(s->g, rq, nrand, 0) : 0;
    ra = only < 0 || only == 1 ? rate(s->g, rq, nrand, 1) : 0;
    cr = only < 0 || only == 2 ? rate(s->g, cq, nc, 0) : 0;
    ca = only < 0 || only == 3 ? rate(s->g, cq, nc, 1) : 0;
    sr = ns && (only < 0 || only == 4) ? rate(s->g, sq, ns, 1) : 0;
    sc = ns && (only < 0 || only == 5) ? rate_cached(s->g, sq, sl, ns) : 0;
    printf("%-24s %6zu %8.1f %6zu %5zu %6.1f %7.2f %7.2f %7.2f %7.2f %7.2f %7.2f\n", s->name,
           gg_geom_prim_count(s->g), st.build_seconds * 1e3, st.nodes, st.max_depth,
           (double)st.bytes / (double)gg_geom_prim_count(s->g), rr, ra, cr, ca, sr, sc);
    fflush(stdout);
    free(rq);
    free(cq);
    free(sq);
    free(sl);
}

/* Which traversal copy runs (GGRT_ISA caps it): an AVX-512 comparison
   on a CPU without it would otherwise time the AVX2 copy twice. */
static void print_traversal(void)
{
    static const char sphere[] = "f 1 1 1 1 0 0 0 0\ns 0 0 0 1\n";
    ggScene *s = ggSceneCreate(NULL);
    ggError err;
    const char *trav = NULL;
    if (s && ggSceneLoadString(s, sphere, sizeof sphere - 1, "probe.nff", &err) == GG_OK &&
        ggScenePrepare(s, &err) == GG_OK)
        trav = ggSceneTraversal(s);
    printf("ggrt: traversal %s%s\n", trav ? trav : "unknown",
           getenv("GGRT_ISA") ? " (GGRT_ISA is set)" : "");
    ggSceneFree(s);
}

int main(int argc, char **argv)
{
    static const char *spd[] = {"balls-s4",   "gears", "mount", "rings",
                                "teapot-s12", "tetra", "tree"};
    int res = 512, nrand = 300000, i, nfiles = 0, failed = 0;
    for (i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "-n") && i + 1 < argc)
            res = atoi(argv[++i]);
        else if (!strcmp(argv[i], "-r") && i + 1 < argc)
            nrand = atoi(argv[++i]);
        else if (!strcmp(argv[i], "-k") && i + 1 < argc)
            only = atoi(argv[++i]);
        else
            argv[nfiles++ + 1] = argv[i];
    }
    printf("single thread; camera rays %dx%d pixel centres; %d random rays\n", res, res, nrand);
    print_traversal();
    printf("%-24s %6s %8s %6s %5s %6s %7s %7s %7s %7s %7s %7s\n", "scene", "prims", "build_ms",
           "nodes", "depth", "B/prim", "rnd_cl", "rnd_any", "cam_cl", "cam_any", "shadow", "shd_c");
    printf("%-24s %6s %8s %6s %5s %6s %7s %7s %7s %7s %7s %7s\n", "", "", "", "", "", "", "Mray/s",
           "Mray/s", "Mray/s", "Mray/s", "Mray/s", "Mray/s");
    if (nfiles == 0) {
        for (i = 0; i < 3; i++) {
            bscene s;
            memset(&s, 0, sizeof s);
            gen_scene(&s, i);
            run(&s, res, nrand);
            gg_geom_free(s.g);
        }
    }
    for (i = 0; i < (nfiles ? nfiles : 7); i++) {
        bscene s;
        char path[512];
        ggScene *owner = NULL;
        memset(&s, 0, sizeof s);
        if (nfiles)
            snprintf(path, sizeof path, "%s", argv[i + 1]);
        else
            snprintf(path, sizeof path, "examples/scenes/spd/%s.nff", spd[i]);
        if (load_nff(&s, path, &owner)) {
            fprintf(stderr, "bench_geometry: cannot read %s\n", path);
            failed = 1;
            continue;
        }
        {
            const char *base = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
            size_t l = strlen(base);
            if (l >= sizeof s.name) l = sizeof s.name - 1;
            memcpy(s.name, base, l);
            s.name[l] = 0;
        }
        s.prebuilt = 1;
        run(&s, res, nrand);
        ggSceneFree(owner);
    }
    return failed;
}
