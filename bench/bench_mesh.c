/* SPDX-License-Identifier: MIT */
/*
** bench_mesh.c -- meshes: how fast they are read and built, what they cost
** in memory, how fast they render. Per model and format:
**   parse   the reader alone on the file's bytes in memory, best of
**           --repeat (MB/s, and million triangles/s)
**   load    ggSceneLoadMesh: read the file, parse, place, normals
**   BVH     the build of the prepared scene's geometry, best of --repeat
**           (seconds, million triangles/s), on --build-threads threads
**           (default: --threads), and the CPU seconds it took
**   B/tri   what the scene keeps per triangle: the mesh (vertices, normals,
**           indices, face map), the geometry's primitive records, and the
**           BVH with its leaf records (ggSceneInfo.geometry_bytes)
**   trace   closest-hit queries of the camera's rays, one thread (Mrays/s)
**   render  ggRender of the framed model at 512x512 on --threads (Mrays/s)
** The models are made here (a bumpy torus of n triangles) and written as
** binary PLY and OBJ into --out (default: a temporary folder, removed).
** With --embree BIN the same triangles go to an NFF file and BIN (the
** embree-whitted anchor: RTC_BUILD_QUALITY_HIGH) renders it with
** -t THREADS, --repeat times, runs alternating with ggrt's builds; its
** best printed build time is shown beside ggrt's best.
**
**   make bench-mesh
**   make bench-mesh EMBREE=BIN
**   build/bench/bench_mesh [--sizes 10000,100000,1000000] [--threads N]
**                          [--build-threads N] [--repeat N] [--out DIR]
**                          [--embree BIN] [--formats ply,obj]
*/
#include "geom_int.h"
#include "mesh_int.h"
#include "scene.h"

#include "vec.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

typedef struct model {
    float (*v)[3];
    uint32_t (*f)[3];
    size_t nv, nf;
} model;

/* A torus of nu x nv quads (2 nu nv triangles) with bumps, so that its
   triangles are not all alike. */
static void make_torus(model *m, size_t ntri)
{
    size_t nu = (size_t)sqrt((double)ntri), nv, i, j, k = 0;
    nv = ntri / (2 * nu);
    m->nv = nu * nv, m->nf = 2 * nu * nv;
    m->v = malloc(m->nv * sizeof *m->v);
    m->f = malloc(m->nf * sizeof *m->f);
    for (i = 0; i < nu; i++)
        for (j = 0; j < nv; j++) {
            double a = 2 * GG_PI * i / nu, b = 2 * GG_PI * j / nv;
            double r = 0.6 + 0.05 * sin(7 * a) * sin(5 * b), R = 2 + 0.1 * cos(3 * a);
            float *p = m->v[i * nv + j];
            p[0] = (float)((R + r * cos(b)) * cos(a));
            p[1] = (float)(r * sin(b));
            p[2] = (float)((R + r * cos(b)) * sin(a));
        }
    for (i = 0; i < nu; i++)
        for (j = 0; j < nv; j++) {
            uint32_t a = (uint32_t)(i * nv + j), b = (uint32_t)(i * nv + (j + 1) % nv);
            uint32_t c = (uint32_t)(((i + 1) % nu) * nv + (j + 1) % nv),
                     d = (uint32_t)(((i + 1) % nu) * nv + j);
            m->f[k][0] = a, m->f[k][1] = b, m->f[k][2] = c, k++;
            m->f[k][0] = a, m->f[k][1] = c, m->f[k][2] = d, k++;
        }
}

static int write_ply(const model *m, const char *path)
{
    FILE *f = fopen(path, "wb");
    size_t i;
    if (!f) return -1;
    fprintf(f,
            "ply\nformat binary_little_endian 1.0\nelement vertex %zu\nproperty float x\n"
            "property float y\nproperty float z\nelement face %zu\n"
            "property list uchar int vertex_indices\nend_header\n",
            m->nv, m->nf);
    fwrite(m->v, sizeof *m->v, m->nv, f);
    for (i = 0; i < m->nf; i++) {
        unsigned char n = 3;
        fwrite(&n, 1, 1, f);
        fwrite(m->f[i], 4, 3, f); /* this machine is little endian (checked in main) */
    }
    return fclose(f);
}

static int write_obj(const model *m, const char *path)
{
    FILE *f = fopen(path, "w");
    size_t i;
    if (!f) return -1;
    for (i = 0; i < m->nv; i++)
        fprintf(f, "v %.9g %.9g %.9g\n", m->v[i][0], m->v[i][1], m->v[i][2]);
    for (i = 0; i < m->nf; i++)
        fprintf(f, "f %u %u %u\n", m->f[i][0] + 1, m->f[i][1] + 1, m->f[i][2] + 1);
    return fclose(f);
}

/* The same triangles for the Embree anchor, with the camera and lights
   ggSceneFrame chooses. */
static int write_nff(const model *m, const ggScene *s, const char *path)
{
    FILE *f = fopen(path, "w");
    ggCamera c = ggSceneCamera(s);
    size_t i;
    int k;
    if (!f) return -1;
    fprintf(f,
            "v\nfrom %.17g %.17g %.17g\nat %.17g %.17g %.17g\nup 0 1 0\nangle %g\nhither 0.001\n"
            "resolution 512 512\nb 0 0 0\n",
            c.from.x, c.from.y, c.from.z, c.at.x, c.at.y, c.at.z, c.fov_deg);
    for (k = 0; k < ggSceneLightCount(s); k++) {
        ggVec3 p;
        ggSceneGetLight(s, k, &p, NULL);
        fprintf(f, "l %.17g %.17g %.17g\n", p.x, p.y, p.z);
    }
    fprintf(f, "f 1 1 1 1 0 100000 0 0\n");
    for (i = 0; i < m->nf; i++) {
        fprintf(f, "p 3\n");
        for (k = 0; k < 3; k++) {
            const float *p = m->v[m->f[i][k]];
            fprintf(f, "%.9g %.9g %.9g\n", p[0], p[1], p[2]);
        }
    }
    return fclose(f);
}

/* The reader alone, on bytes in memory: seconds. */
static double parse_seconds(const char *data, size_t len, int fmt, size_t *ntri)
{
    gg_mb mb;
    ggScene *s = ggSceneCreate(NULL);
    ggMeshOptions o;
    ggError e;
    double t0, t;
    int rc;
    ggMeshOptionsDefault(&o);
    gg_mb_init(&mb, NULL, fmt);
    t0 = gg_time_now();
    rc = fmt == GG_MESH_FORMAT_PLY ? gg_ply_read(&mb, (const unsigned char *)data, len, "m", &e)
                                   : gg_obj_read(s, &mb, data, len, "m", NULL, &o, &e);
    t = gg_time_now() - t0;
    if (rc != GG_OK) fprintf(stderr, "bench_mesh: %s\n", e.message), exit(1);
    *ntri = mb.b.m.ntri;
    gg_mb_free(&mb);
    ggSceneFree(s);
    return t;
}

/* Closest hits of the camera's w x h pixel-centre rays, one thread. */
static double trace_mrays(const ggScene *s, int w, int h)
{
    ggCamera c = ggSceneCamera(s);
    ggVec3 fw = v3norm(v3sub(c.at, c.from)), rt = v3norm(v3cross(fw, c.up)), up = v3cross(rt, fw);
    double tx = tan(c.fov_deg * GG_PI / 360), ty = tx * h / w, t0 = gg_time_now();
    long hits = 0;
    int x, y;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            ggRay r;
            double sx = (2 * (x + 0.5) / w - 1) * tx, sy = (1 - 2 * (y + 0.5) / h) * ty;
            r.o = c.from, r.d = v3add(fw, v3add(v3scale(rt, sx), v3scale(up, sy)));
            hits += ggSceneIntersect(s, r, 0, INFINITY, NULL);
        }
    return hits >= 0 ? (double)w * h / (gg_time_now() - t0) / 1e6 : 0;
}

static double render_mrays(ggScene *s, int threads)
{
    ggRenderOptions o;
    ggImage *img = NULL;
    ggRayStats st;
    ggError e;
    double t0;
    ggRenderOptionsDefault(&o);
    o.width = o.height = 512, o.threads = threads;
    t0 = gg_time_now();
    if (ggRender(s, &o, &img, &st, &e) != GG_OK)
        fprintf(stderr, "bench_mesh: %s\n", e.message), exit(1);
    t0 = gg_time_now() - t0;
    ggImageFree(img);
    return (double)(st.eye + st.reflect + st.refract + st.shadow) / t0 / 1e6;
}

/* Run the anchor on the NFF file; its build_s line, or -1. */
static double embree_build(const char *bin, const char *nff, int threads)
{
    char cmd[4096], line[512];
    double b = -1;
    FILE *p;
    snprintf(cmd, sizeof cmd, "'%s' -t %d -r 256 -o - '%s' 2>&1", bin, threads, nff);
    if (!(p = popen(cmd, "r"))) return -1;
    while (fgets(line, sizeof line, p))
        if (!strncmp(line, "build_s", 7)) b = atof(line + 7);
    pclose(p);
    return b;
}

typedef struct args {
    size_t sizes[8];
    int nsizes, threads, build_threads, repeat, ply, obj;
    const char *out, *embree;
} args;

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* The geometry built again --repeat times: the best wall time, the CPU
   time of that build; with an NFF file, the anchor's build alternating
   with ggrt's (best of as many). */
static void best_builds(const args *a, ggScene *s, const char *nff, double *wall, double *cpu,
                        double *emb)
{
    int i;
    *wall = INFINITY, *emb = INFINITY, *cpu = 0;
    for (i = 0; i < a->repeat; i++) {
        ggError e;
        double t0 = gg_time_now(), c0 = cpu_now(), t;
        if (gg_geom_build(s->geom, &e) != GG_OK)
            fprintf(stderr, "bench_mesh: %s\n", e.message), exit(1);
        t = gg_time_now() - t0;
        if (t < *wall) *wall = t, *cpu = cpu_now() - c0;
        if (nff) {
            double eb = embree_build(a->embree, nff, a->threads);
            if (eb > 0 && eb < *emb) *emb = eb;
        }
    }
}

static void one(const args *a, const char *dir, size_t ntri)
{
    model m;
    char path[2][1024], nff[1024];
    int k;
    make_torus(&m, ntri);
    snprintf(path[0], sizeof path[0], "%s/torus-%zu.ply", dir, m.nf);
    snprintf(path[1], sizeof path[1], "%s/torus-%zu.obj", dir, m.nf);
    if ((a->ply && write_ply(&m, path[0])) || (a->obj && write_obj(&m, path[1])))
        fprintf(stderr, "bench_mesh: cannot write %s\n", dir), exit(1);
    for (k = 0; k < 2; k++) {
        ggScene *s;
        ggSceneInfo si;
        ggMeshInfo mi;
        ggError e;
        char *data;
        size_t len, nt = 0;
        double tp, tl, t0, bytes, bw, bc, eb;
        int r;
        if (!(k ? a->obj : a->ply)) continue;
        if (gg_load_read_file(NULL, path[k], GG_MESH_MAX_FILE, &data, &len, &e) != GG_OK)
            fprintf(stderr, "bench_mesh: %s\n", e.message), exit(1);
        for (tp = INFINITY, r = 0; r < a->repeat; r++) {
            double t = parse_seconds(data, len, k ? GG_MESH_FORMAT_OBJ : GG_MESH_FORMAT_PLY, &nt);
            if (t < tp) tp = t;
        }
        free(data);
        s = ggSceneCreate(NULL);
        t0 = gg_time_now();
        if (ggSceneLoadMesh(s, path[k], NULL, &e) != GG_OK)
            fprintf(stderr, "bench_mesh: %s\n", e.message), exit(1);
        tl = gg_time_now() - t0;
        ggSceneFrame(s, GG_FRAME_CAMERA | GG_FRAME_LIGHTS, &e);
        if (ggScenePrepare(s, &e) != GG_OK) fprintf(stderr, "bench_mesh: %s\n", e.message), exit(1);
        ggSceneGetInfo(s, &si);
        ggSceneGetMeshInfo(s, 0, &mi);
        bytes = (double)mi.bytes + (double)si.geometry_bytes + 13.0 * (double)si.primitives;
        snprintf(nff, sizeof nff, "%s/torus-%zu.nff", dir, m.nf);
        if (k || !a->embree || write_nff(&m, s, nff)) nff[0] = 0;
        best_builds(a, s, nff[0] ? nff : NULL, &bw, &bc, &eb);
        if (nff[0] && !a->out) remove(nff);
        printf("%-17s %-3s %6.1f %6.0f %6.2f %6.3f %6.3f %6.3f %6.2f %6.1f %6.2f %6.2f\n",
               strrchr(path[k], '/') + 1, k ? "obj" : "ply", len / 1e6, len / 1e6 / tp,
               nt / 1e6 / tp, tl, bw, bc, mi.triangles / 1e6 / bw, bytes / (double)mi.triangles,
               trace_mrays(s, 256, 256), render_mrays(s, a->threads));
        if (nff[0])
            printf("%-17s %-3s %20s Embree 3 HIGH build %.3f s (-t %d): ggrt %.3f s = %.2fx "
                   "Embree's\n",
                   "", "nff", "", eb, a->threads, bw, eb < INFINITY ? bw / eb : 0.0);
        fflush(stdout);
        ggSceneFree(s);
    }
    if (!a->out) remove(path[0]), remove(path[1]);
    free(m.v);
    free(m.f);
}

static void parse_args(args *a, int argc, char **argv)
{
    int i;
    memset(a, 0, sizeof *a);
    a->sizes[0] = 10000, a->sizes[1] = 100000, a->sizes[2] = 1000000, a->nsizes = 3;
    a->threads = 2, a->ply = a->obj = 1, a->repeat = 3;
    for (i = 1; i < argc; i++) {
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(argv[i], "--sizes") && v) {
            char *p = argv[++i];
            for (a->nsizes = 0; *p && a->nsizes < 8; p += *p == ',')
                a->sizes[a->nsizes++] = strtoul(p, &p, 10);
        } else if (!strcmp(argv[i], "--threads") && v) {
            a->threads = atoi(argv[++i]);
        } else if (!strcmp(argv[i], "--build-threads") && v) {
            a->build_threads = atoi(argv[++i]);
        } else if (!strcmp(argv[i], "--repeat") && v) {
            a->repeat = atoi(argv[++i]) > 0 ? atoi(argv[i]) : 1;
        } else if (!strcmp(argv[i], "--out") && v) {
            a->out = argv[++i];
        } else if (!strcmp(argv[i], "--embree") && v) {
            a->embree = argv[++i];
        } else if (!strcmp(argv[i], "--formats") && v) {
            a->ply = strstr(argv[++i], "ply") != NULL, a->obj = strstr(argv[i], "obj") != NULL;
        } else {
            fprintf(stderr, "usage: bench_mesh [--sizes N,...] [--threads N] [--build-threads N] "
                            "[--repeat N] [--out DIR] [--embree BIN] [--formats ply,obj]\n");
            exit(1);
        }
    }
}

int main(int argc, char **argv)
{
    args a;
    char tmp[] = "/tmp/bench_mesh.XXXXXX";
    const char *dir;
    const uint16_t one16 = 1;
    int i;
    struct rusage ru;
    parse_args(&a, argc, argv);
    gg_bvh_set_threads(a.build_threads ? a.build_threads : a.threads);
    if (*(const unsigned char *)&one16 != 1)
        return fprintf(stderr, "bench_mesh: little endian only\n"), 1;
    dir = a.out ? a.out : mkdtemp(tmp);
    if (!dir) return perror("bench_mesh: mkdtemp"), 1;
    printf("%-17s %-3s %6s %6s %6s %6s %6s %6s %6s %6s %6s %6s\n", "model", "fmt", "MB", "parse",
           "Mtri/s", "load", "BVH", "BVH", "Mtri/s", "B/tri", "trace", "render");
    printf("%-17s %-3s %6s %6s %6s %6s %6s %6s %6s %6s %6s %6s\n", "", "", "", "MB/s", "parse", "s",
           "s", "cpu s", "BVH", "", "Mray/s", "Mray/s");
    for (i = 0; i < a.nsizes; i++) one(&a, dir, a.sizes[i]);
    getrusage(RUSAGE_SELF, &ru);
    printf(
        "peak resident memory %.0f MB; render on %d threads, BVH build on %d (best of %d); trace: "
        "closest hits of 256x256 camera rays, one thread\n",
        ru.ru_maxrss / 1024.0, a.threads, a.build_threads ? a.build_threads : a.threads, a.repeat);
    if (!a.out) rmdir(dir);
    return 0;
}
