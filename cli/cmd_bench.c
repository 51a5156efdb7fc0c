/* SPDX-License-Identifier: MIT */
/*
** cmd_bench.c -- `ggrt bench`: measured, side by side, in one run.
**
**   ggrt bench spd       SPD scenes: ggrt vs POV-Ray 3.7 trace time, memory
**   ggrt bench counts    SPD-rules ray counts against the SPD's reference table
**   ggrt bench effects   each example scene with its effect set vs everything forced
**
** Every ggrt measurement runs in a child process so that its peak memory
** (ru_maxrss) is that scene's alone. Times are medians of --runs runs.
*/
/* wait4 (per-child peak memory) is a BSD interface. */
#define _DEFAULT_SOURCE
#include "cli.h"
#include "bench.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static const char *const spd_scenes[] = {"balls-s4", "gears", "rings", "tetra",
                                         "mount",    "tree",  "teapot-s12"};
#define NSPD 7

static void help(FILE *f)
{
    fprintf(f,
            "usage: ggrt bench spd|counts|effects|scaling [options]\n"
            "       ggrt bench accuracy SCENE... [--size W] [--out DIR] [options]\n"
            "\n"
            "  spd       render the 7 SPD scenes (depth 5, pixel centres, no antialiasing) and,\n"
            "            if povray is installed, the same scenes with POV-Ray 3.7; print trace\n"
            "            times, ratios, rays per second, peak memory and bytes per primitive\n"
            "  counts    SPD rules (pixel corners, depth 5, transmitters reflect) at 512x512:\n"
            "            eye-hit, reflect, refract and shadow rays against the SPD's table\n"
            "  effects   each example scene rendered with its own effect set and with every\n"
            "            effect forced on: times, ratio, and whether the images are identical\n"
            "  accuracy  sweep each accuracy knob from the accurate default: median time, rays,\n"
            "            RMSE, max error, PSNR, share of pixels off by > 1/255 and pixels whose\n"
            "            ray tree changed, against an all-accurate reference; writes\n"
            "            DIR/accuracy.csv and DIR/accuracy.svg (docs/accuracy.md), then the\n"
            "            scaling tables\n"
            "  scaling   render time against primitives (balls-s1..s4, fitted against ln n),\n"
            "            image size and threads\n"
            "\n"
            "options:\n"
            "  --size N        image size N x N (spd: 1024; effects: 320)\n"
            "  --threads N     threads (default 2)\n"
            "  --runs N        runs per measurement, median reported (default 3)\n"
            "  --spd DIR       NFF scenes (default examples/scenes/spd)\n"
            "  --pov DIR       POV-Ray scenes, .pov.gz (default ../shared/scenes/spd-pov)\n"
            "  --no-pov        do not run POV-Ray\n"
            "  --scenes LIST   comma-separated subset of scene names\n"
            "  --out DIR       where accuracy writes its CSV and SVG (default .)\n");
}

double bench_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

double bench_median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

int bench_in_child(bench_fn fn, void *arg, void *out, size_t outsize, double *peak_mb)
{
    int fd[2], status;
    pid_t pid;
    struct rusage ru;
    ssize_t got = 0;
    if (pipe(fd) != 0) return -1;
    fflush(stdout);
    fflush(stderr);
    pid = fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        int rc;
        close(fd[0]);
        memset(out, 0, outsize);
        rc = fn(arg, out);
        if (write(fd[1], out, outsize) != (ssize_t)outsize) rc = 1;
        _exit(rc ? 1 : 0);
    }
    close(fd[1]);
    while ((size_t)got < outsize) {
        ssize_t n = read(fd[0], (char *)out + got, outsize - (size_t)got);
        if (n <= 0) break;
        got += n;
    }
    close(fd[0]);
    if (wait4(pid, &status, 0, &ru) < 0) return -1;
    if (peak_mb) *peak_mb = ru.ru_maxrss / 1024.0;
    return (size_t)got == outsize && WIFEXITED(status) && WEXITSTATUS(status) == 0 ? 0 : -1;
}

/* ---- one ggrt measurement ---- */

typedef struct spd_job {
    char path[1024];
    int size, threads, runs, spd_rules;
} spd_job;

typedef struct spd_result {
    double parse, prepare, render;
    ggRayStats st;
    ggSceneInfo info;
    int objects;
    char error[512];
} spd_result;

static int spd_child(void *arg, void *outp)
{
    spd_job *j = arg;
    spd_result *r = outp;
    ggScene *s = ggSceneCreate(NULL);
    ggRenderOptions o;
    ggError err;
    double t0, times[64];
    int k;
    if (!s) return 1;
    t0 = bench_now();
    if (ggSceneLoadFile(s, j->path, &err) != GG_OK) goto fail;
    r->parse = bench_now() - t0;
    t0 = bench_now();
    if (ggScenePrepare(s, &err) != GG_OK) goto fail;
    r->prepare = bench_now() - t0;
    ggSceneGetInfo(s, &r->info);
    r->objects = ggSceneObjectCount(s);
    ggRenderOptionsDefault(&o);
    o.width = o.height = j->size;
    o.threads = j->threads;
    o.max_depth = 5;
    if (j->spd_rules) o.spd_rules = o.pixel_corners = true;
    for (k = 0; k < j->runs && k < 64; k++) {
        ggImage *img = NULL;
        memset(&r->st, 0, sizeof r->st);
        t0 = bench_now();
        if (ggRender(s, &o, &img, &r->st, &err) != GG_OK) goto fail;
        times[k] = bench_now() - t0;
        ggImageFree(img);
    }
    r->render = bench_median(times, k);
    ggSceneFree(s);
    return 0;
fail:
    snprintf(r->error, sizeof r->error, "%s", err.message);
    ggSceneFree(s);
    return 0; /* the error travels in the result */
}

/* ---- POV-Ray ---- */

typedef struct pov_result {
    double trace, peak_mb;
    int ok;
} pov_result;

static pov_result run_pov(const char *povdir, const char *name, int size, int threads, int runs)
{
    pov_result pr;
    char cmd[4096], tmpdir[] = "/tmp/ggrt-pov-XXXXXX", line[1024];
    double times[64];
    int k, n = 0;
    memset(&pr, 0, sizeof pr);
    if (!mkdtemp(tmpdir)) return pr;
    snprintf(cmd, sizeof cmd,
             "gzip -dc '%s/%s.pov.gz' > %s/scene.pov 2>/dev/null && cp '%s/spd_globals.inc' %s/",
             povdir, name, tmpdir, povdir, tmpdir);
    if (system(cmd) != 0) goto done;
    for (k = 0; k < runs && k < 64; k++) {
        FILE *p;
        double t = -1;
        /* -F: no output file; POV-Ray's statistics go to stderr. */
        snprintf(cmd, sizeof cmd,
                 "cd %s && povray +Iscene.pov +HIspd_globals.inc -F +W%d +H%d -A +WT%d -D "
                 "2>&1 >/dev/null",
                 tmpdir, size, size, threads);
        p = popen(cmd, "r");
        if (!p) goto done;
        while (fgets(line, sizeof line, p)) {
            char *q = strstr(line, "Trace Time:");
            if (q && (q = strchr(q, '('))) t = atof(q + 1);
        }
        pclose(p);
        if (t < 0) goto done;
        times[n++] = t;
    }
    /* Peak memory of one more run, measured the same way as ggrt's. */
    snprintf(cmd, sizeof cmd,
             "cd %s && povray +Iscene.pov +HIspd_globals.inc -F +W%d +H%d -A +WT%d -D "
             ">/dev/null 2>&1",
             tmpdir, size, size, threads);
    {
        pid_t pid;
        int status;
        struct rusage ru;
        fflush(stdout);
        pid = fork();
        if (pid == 0) {
            execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
            _exit(127);
        }
        if (pid > 0 && wait4(pid, &status, 0, &ru) > 0) pr.peak_mb = ru.ru_maxrss / 1024.0;
    }
    pr.trace = bench_median(times, n);
    pr.ok = n > 0;
done:
    snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
    if (system(cmd) != 0) pr.ok = pr.ok;
    return pr;
}

static int have_povray(void) { return system("command -v povray >/dev/null 2>&1") == 0; }

int bench_selected(const char *list, const char *name)
{
    const char *p;
    size_t n = strlen(name);
    if (!list) return 1;
    for (p = list; (p = strstr(p, name)); p += n)
        if ((p == list || p[-1] == ',') && (p[n] == '\0' || p[n] == ',')) return 1;
    return 0;
}

static int bench_spd(const bench_opts *bo)
{
    int i, npov = 0, pov = bo->pov && have_povray();
    double logsum = 0, worst = 1e300;
    int avx = 0;
    printf("ggrt bench spd: %dx%d, %d threads, depth 5, pixel centres, no antialiasing, "
           "median of %d runs\n",
           bo->size, bo->size, bo->threads, bo->runs);
    if (bo->pov && !pov) printf("(povray not found: install it with apt-get install povray)\n");
    printf("\n%-11s %7s %7s %8s %8s %9s %8s %7s %9s | %8s %7s %7s\n", "scene", "prims", "parse",
           "prepare", "render", "Mrays", "Mrays/s", "peakMB", "B/prim", "pov", "povMB",
           "speedup");
    for (i = 0; i < NSPD; i++) {
        spd_job j;
        spd_result r;
        pov_result pr;
        double peak = 0, rays;
        if (!bench_selected(bo->scenes, spd_scenes[i])) continue;
        memset(&j, 0, sizeof j);
        snprintf(j.path, sizeof j.path, "%s/%s.nff", bo->spd_dir, spd_scenes[i]);
        j.size = bo->size, j.threads = bo->threads, j.runs = bo->runs;
        if (bench_in_child(spd_child, &j, &r, sizeof r, &peak) != 0 || r.error[0]) {
            printf("%-11s failed: %s\n", spd_scenes[i], r.error[0] ? r.error : "child failed");
            return EXIT_INPUT;
        }
        rays = (double)(r.st.eye + r.st.reflect + r.st.refract + r.st.shadow);
        avx |= r.info.bvh_blocks > 0;
        printf("%-11s %7zu %6.3fs %7.3fs %7.3fs %9.2f %8.2f %7.1f %9.1f |", spd_scenes[i],
               r.info.primitives, r.parse, r.prepare, r.render, rays / 1e6, rays / r.render / 1e6,
               peak, r.info.primitives ? (double)r.info.geometry_bytes / r.info.primitives : 0.0);
        if (pov) {
            pr = run_pov(bo->pov_dir, spd_scenes[i], bo->size, bo->threads, bo->runs);
            if (pr.ok) {
                double ratio = pr.trace / r.render;
                printf(" %7.3fs %7.1f %6.2fx\n", pr.trace, pr.peak_mb, ratio);
                logsum += log(ratio);
                npov++;
                if (ratio < worst) worst = ratio;
            } else
                printf(" %8s\n", "failed");
        } else
            printf("\n");
        fflush(stdout);
    }
    if (npov)
        printf("\nspeedup over POV-Ray (trace time / ggrt render time): geometric mean %.2fx, "
               "lowest %.2fx over %d scenes\n",
               exp(logsum / npov), worst, npov);
    printf("render = ggRender wall time (parse and BVH build excluded); pov = POV-Ray's "
           "\"Trace Time\"; peak = max RSS of the whole process\n");
    printf("traversal: %s\n", avx ? "AVX, leaves of 2-4 triangles tested four at a time"
                                   : "plain (this CPU has no AVX)");
    return EXIT_OK;
}

static int bench_counts(const bench_opts *bo)
{
    /* The SPD README's reference table (eye rays hitting, reflect, refract,
       shadow), about 10% spread expected. */
    static const double ref[NSPD][4] = {
        {263169, 175095, 0, 954368},     {245086, 304643, 207564, 2246955},
        {263169, 315236, 0, 1085002},    {49788, 0, 0, 46112},
        {173125, 354769, 354769, 412922}, {169836, 0, 0, 1097419},
        {161120, 225248, 0, 407656},
    };
    static const char *const kinds[4] = {"eye-hit", "reflect", "refract", "shadow"};
    int i, k, bad = 0;
    printf("ggrt bench counts: SPD rules (513x513 corner rays, depth 5, transmitters spawn "
           "reflection rays), %d threads\n\n",
           bo->threads);
    printf("%-11s %-8s %10s %10s %8s\n", "scene", "rays", "ggrt", "SPD", "diff");
    for (i = 0; i < NSPD; i++) {
        spd_job j;
        spd_result r;
        double got[4];
        if (!bench_selected(bo->scenes, spd_scenes[i])) continue;
        memset(&j, 0, sizeof j);
        snprintf(j.path, sizeof j.path, "%s/%s.nff", bo->spd_dir, spd_scenes[i]);
        j.size = 512, j.threads = bo->threads, j.runs = 1, j.spd_rules = 1;
        if (bench_in_child(spd_child, &j, &r, sizeof r, NULL) != 0 || r.error[0]) {
            printf("%-11s failed: %s\n", spd_scenes[i], r.error);
            return EXIT_INPUT;
        }
        got[0] = (double)r.st.eye_hit, got[1] = (double)r.st.reflect;
        got[2] = (double)r.st.refract, got[3] = (double)r.st.shadow;
        for (k = 0; k < 4; k++) {
            double d = ref[i][k] > 0 ? 100.0 * (got[k] - ref[i][k]) / ref[i][k] : 0;
            int off = ref[i][k] > 0 ? fabs(d) > 10 : got[k] != 0;
            bad += off;
            printf("%-11s %-8s %10.0f %10.0f %+7.1f%%%s\n", k ? "" : spd_scenes[i], kinds[k],
                   got[k], ref[i][k], d, off ? "  <- outside 10%" : "");
        }
    }
    printf("\n%d of the counts are outside 10%% of the SPD table\n", bad);
    return EXIT_OK;
}

int cmd_bench(int argc, char **argv)
{
    bench_opts bo;
    int i;
    memset(&bo, 0, sizeof bo);
    bo.size = 0, bo.threads = 2, bo.runs = 3, bo.pov = 1;
    bo.spd_dir = "examples/scenes/spd";
    bo.pov_dir = "../shared/scenes/spd-pov";
    if (argc < 2 || cli_is_help(argv[1])) {
        help(argc < 2 ? stderr : stdout);
        return argc < 2 ? EXIT_USAGE : EXIT_OK;
    }
    for (i = 2; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (cli_is_help(a)) {
            help(stdout);
            return EXIT_OK;
        } else if (!strcmp(a, "--no-pov")) {
            bo.pov = 0;
            continue;
        } else if (a[0] != '-') {
            if (bo.nargs < BENCH_MAX_ARGS) bo.args[bo.nargs++] = a;
            continue;
        }
        if (!v) {
            fprintf(stderr, "ggrt bench: %s needs a value\n", a);
            return EXIT_USAGE;
        }
        i++;
        if (!strcmp(a, "--size")) {
            if (cli_parse_int(v, 1, 16384, &bo.size)) goto bad;
        } else if (!strcmp(a, "--threads")) {
            if (cli_parse_int(v, 1, 256, &bo.threads)) goto bad;
        } else if (!strcmp(a, "--runs")) {
            if (cli_parse_int(v, 1, 64, &bo.runs)) goto bad;
        } else if (!strcmp(a, "--spd")) {
            bo.spd_dir = v;
        } else if (!strcmp(a, "--pov")) {
            bo.pov_dir = v;
        } else if (!strcmp(a, "--scenes")) {
            bo.scenes = v;
        } else if (!strcmp(a, "--out")) {
            bo.out_dir = v;
        } else {
            fprintf(stderr, "ggrt bench: unknown option '%s'\n", a);
            return EXIT_USAGE;
        }
        continue;
    bad:
        fprintf(stderr, "ggrt bench: bad value '%s' for %s\n", v, a);
        return EXIT_USAGE;
    }
    if (!strcmp(argv[1], "spd")) {
        if (!bo.size) bo.size = 1024;
        return bench_spd(&bo);
    }
    if (!strcmp(argv[1], "counts")) return bench_counts(&bo);
    if (!strcmp(argv[1], "effects")) {
        if (!bo.size) bo.size = 320;
        return bench_effects(&bo);
    }
    if (!strcmp(argv[1], "accuracy")) return bench_accuracy(&bo);
    if (!strcmp(argv[1], "scaling")) return bench_scaling(&bo);
    fprintf(stderr, "ggrt bench: unknown benchmark '%s'\n", argv[1]);
    help(stderr);
    return EXIT_USAGE;
}
