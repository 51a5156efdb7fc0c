/* SPDX-License-Identifier: MIT */
/*
** spd.c -- `ggrt bench spd` (the SPD scenes, ggrt against POV-Ray 3.7:
** trace time and peak memory) and `ggrt bench counts` (SPD-rule ray counts
** against the SPD's reference table). Every ggrt measurement runs in a
** child process (child.c) so that its peak memory is that scene's alone.
** With --embree BIN, `bench spd` also times the embree-whitted anchor (a
** Whitted tracer on Intel Embree 3 that prints one "RESULT key=value ..."
** line per render) with single eye rays (-p 1) and 16-ray eye packets
** (-p 16), round by round interleaved with ggrt and POV-Ray, so that all
** of them see the same machine load.
*/
/* wait4 (POV-Ray's peak memory) is a BSD interface. */
#define _DEFAULT_SOURCE
#include "bench/bench.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

/* ---- one ggrt measurement ---- */

typedef struct spd_job {
    char path[1024];
    int size, threads, runs, spd_rules;
    ggAccuracy accuracy;
} spd_job;

typedef struct spd_result {
    double parse, prepare, render;
    ggRayStats st;
    ggSceneInfo info;
    int objects;
    int status; /* of the call that failed, with error */
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
    t0 = cli_now();
    if ((r->status = ggSceneLoadFile(s, j->path, &err)) != GG_OK) goto fail;
    r->parse = cli_now() - t0;
    t0 = cli_now();
    if ((r->status = ggScenePrepare(s, &err)) != GG_OK) goto fail;
    r->prepare = cli_now() - t0;
    ggSceneGetInfo(s, &r->info);
    r->objects = ggSceneObjectCount(s);
    ggRenderOptionsDefault(&o);
    o.width = o.height = j->size;
    o.threads = j->threads;
    o.max_depth = 5;
    if (j->spd_rules) o.spd_rules = o.pixel_corners = true;
    o.accuracy = j->accuracy;
    for (k = 0; k < j->runs && k < 64; k++) {
        ggImage *img = NULL;
        memset(&r->st, 0, sizeof r->st);
        t0 = cli_now();
        if ((r->status = ggRender(s, &o, &img, &r->st, &err)) != GG_OK) goto fail;
        times[k] = cli_now() - t0;
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

/* j measured in a child process into *r (and its peak memory into
   *peak, unless NULL). On failure the table gets the scene's row saying
   why, and the exit code is returned: the failed call's (cli_exit_code),
   or EXIT_INPUT when the child itself failed (it could not start, or
   died). */
static int spd_measure(spd_job *j, const char *name, spd_result *r, double *peak)
{
    memset(r, 0, sizeof *r);
    if (bench_in_child(spd_child, j, r, sizeof *r, peak) != 0) {
        printf("%-11s failed: the measuring process failed\n", name);
        cli_error("%s: the measuring process failed", name); /* and on stderr */
        return EXIT_INPUT;
    }
    if (r->error[0]) {
        printf("%-11s failed: %s\n", name, r->error);
        cli_error("%s", r->error);
        return cli_exit_code(r->status, 0);
    }
    return EXIT_OK;
}

/* ---- POV-Ray ---- */

typedef struct pov_result {
    double trace, peak_mb;
    int ok;
} pov_result;

static pov_result run_pov(const char *povdir, const char *name, int size, int threads, int runs,
                          int peak)
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
    if (!peak) goto timed;
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
timed:
    pr.trace = bench_median(times, n);
    pr.ok = n > 0;
done:
    snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
    if (system(cmd) != 0) pr.ok = pr.ok;
    return pr;
}

static int have_povray(void)
{
    return system("command -v povray >/dev/null 2>&1") == 0;
}

/* ---- the Embree anchor ---- */

typedef struct emb_result {
    double trace, rays, shadow, blocked;
    int ok;
} emb_result;

/* The value of key=... in a RESULT line, or -1. */
static double result_field(const char *line, const char *key)
{
    size_t n = strlen(key);
    const char *p = line;
    while ((p = strstr(p, key)) != NULL) {
        if ((p == line || p[-1] == ' ') && p[n] == '=') return atof(p + n + 1);
        p += n;
    }
    return -1;
}

/* One render of the anchor: -t threads, -r size, -p packet, no image. */
static emb_result run_embree(const char *bin, const char *scene, int size, int threads, int packet)
{
    emb_result er;
    char cmd[4096], line[2048];
    FILE *p;
    memset(&er, 0, sizeof er);
    snprintf(cmd, sizeof cmd, "'%s' -t %d -r %d -p %d -o - '%s' 2>/dev/null", bin, threads, size,
             packet, scene);
    fflush(stdout);
    if (!(p = popen(cmd, "r"))) return er;
    while (fgets(line, sizeof line, p))
        if (!strncmp(line, "RESULT ", 7)) {
            er.trace = result_field(line, "trace_s");
            er.rays = result_field(line, "total");
            er.shadow = result_field(line, "shadow");
            er.blocked = result_field(line, "blocked");
            er.ok = er.trace > 0;
        }
    if (pclose(p) != 0) er.ok = 0;
    return er;
}

/* The anchor's own line on what Embree runs here (its -v: version, the
   packet sizes its build has natively, ...), from a tiny render of the
   first scene of the table. */
static void print_anchor(const bench_opts *bo)
{
    char cmd[4096], line[1024], path[1024];
    const char *first = NULL;
    int i, found = 0;
    FILE *p;
    for (i = 0; i < BENCH_NSPD && !first; i++)
        if (bench_selected(bo->scenes, bench_spd_scenes[i])) first = bench_spd_scenes[i];
    if (!first) return;
    snprintf(path, sizeof path, "%s/%s.nff", bo->spd_dir, first);
    snprintf(cmd, sizeof cmd, "'%s' -v -t 1 -r 8 -o - '%s' 2>&1", bo->embree, path);
    fflush(stdout);
    if (!(p = popen(cmd, "r"))) return;
    while (fgets(line, sizeof line, p))
        if (!found && !strncmp(line, "embree ", 7)) {
            line[strcspn(line, "\n")] = '\0';
            printf("anchor: %s\n", line);
            found = 1;
        }
    pclose(p);
    if (!found) printf("anchor: (its -v printed no \"embree\" line)\n");
}

/* Median of the first `runs` values of v (v is left as it is). */
static double med_of(const double *v, int runs)
{
    double t[64];
    int k;
    for (k = 0; k < runs && k < 64; k++) t[k] = v[k];
    return bench_median(t, k);
}

/* The line under a table's title naming ggrt's accuracy knobs, if any. */
static void print_knobs(const bench_opts *bo)
{
    if (!bo->has_accuracy) return;
    printf("ggrt with");
    cli_print_accuracy(stdout, &bo->accuracy);
    printf("\n");
}

/* bench spd --embree: per scene, `runs` rounds of ggrt, anchor -p 1,
   anchor -p 16 and (if enabled) POV-Ray, one render each; medians. */
static int bench_spd_embree(const bench_opts *bo, int pov)
{
    double lg[3] = {0, 0, 0}, worst16 = 1e300, blk[BENCH_NSPD][2];
    int i, n = 0, npov = 0, runs = bo->runs < 64 ? bo->runs : 64;
    printf("ggrt bench spd --embree: %dx%d, %d thread%s, depth 5, pixel centres, %d round%s "
           "interleaved, medians\n",
           bo->size, bo->size, bo->threads, BENCH_S(bo->threads), runs, BENCH_S(runs));
    bench_print_machine();
    print_anchor(bo);
    print_knobs(bo);
    if (bo->pov && !pov) printf("(povray not found: install it with apt-get install povray)\n");
    printf("\n%-11s %7s %8s %7s | %7s %7s %8s | %7s | %9s %9s %8s\n", "scene", "ggrt", "Mrays/s",
           "peakMB", "emb-p1", "emb-p16", "Mrays/s", "pov", "emb1/ggrt", "emb16/ggrt", "pov/ggrt");
    for (i = 0; i < BENCH_NSPD; i++) {
        double tg[64], t1[64], t16[64], tp[64], peak = 0, rays = 0, erays = 0, g, e1, e16, pv = 0;
        int k, povok = pov;
        spd_job j;
        if (!bench_selected(bo->scenes, bench_spd_scenes[i])) continue;
        memset(&j, 0, sizeof j);
        snprintf(j.path, sizeof j.path, "%s/%s.nff", bo->spd_dir, bench_spd_scenes[i]);
        j.size = bo->size, j.threads = bo->threads, j.runs = 1;
        j.accuracy = bo->accuracy;
        for (k = 0; k < runs; k++) {
            spd_result r;
            emb_result a, b;
            double pk = 0;
            int rc = spd_measure(&j, bench_spd_scenes[i], &r, &pk);
            if (rc != EXIT_OK) return rc;
            tg[k] = r.render, peak = pk > peak ? pk : peak;
            rays = (double)(r.st.eye + r.st.reflect + r.st.refract + r.st.shadow);
            a = run_embree(bo->embree, j.path, bo->size, bo->threads, 1);
            b = run_embree(bo->embree, j.path, bo->size, bo->threads, 16);
            if (!a.ok || !b.ok) {
                printf("%-11s the anchor failed (%s -t %d -r %d -p 1|16 -o - %s)\n",
                       bench_spd_scenes[i], bo->embree, bo->threads, bo->size, j.path);
                return EXIT_INPUT;
            }
            t1[k] = a.trace, t16[k] = b.trace, erays = b.rays;
            blk[i][0] = r.st.shadow ? 100.0 * (double)r.st.shadow_blocked / (double)r.st.shadow : 0;
            blk[i][1] = b.shadow > 0 && b.blocked >= 0 ? 100.0 * b.blocked / b.shadow : -1;
            if (povok) {
                pov_result pr =
                    run_pov(bo->pov_dir, bench_spd_scenes[i], bo->size, bo->threads, 1, 0);
                povok = pr.ok;
                tp[k] = pr.trace;
            }
        }
        g = med_of(tg, runs), e1 = med_of(t1, runs), e16 = med_of(t16, runs);
        if (povok) pv = med_of(tp, runs);
        printf("%-11s %6.3fs %8.2f %7.1f | %6.3fs %6.3fs %8.2f |", bench_spd_scenes[i], g,
               rays / g / 1e6, peak, e1, e16, erays / e16 / 1e6);
        if (povok)
            printf(" %6.3fs |", pv);
        else
            printf(" %7s |", "-");
        printf(" %8.2fx %9.2fx", e1 / g, e16 / g);
        if (povok)
            printf(" %7.2fx\n", pv / g);
        else
            printf(" %8s\n", "-");
        fflush(stdout);
        lg[0] += log(e1 / g), lg[1] += log(e16 / g), n++;
        if (povok) lg[2] += log(pv / g), npov++;
        if (e16 / g < worst16) worst16 = e16 / g;
    }
    if (n) {
        printf("\ngeometric mean over %d scenes: emb1/ggrt %.2fx, emb16/ggrt %.2fx", n,
               exp(lg[0] / n), exp(lg[1] / n));
        if (npov) printf(", pov/ggrt %.2fx (%d scenes)", exp(lg[2] / npov), npov);
        printf("; lowest emb16/ggrt %.2fx\n", worst16);
        /* The work of the two shadow models: under ggrt's coloured
           shadows a ray that crosses glass is walked on to the light,
           where the anchor stops it. */
        printf("shadow rays blocked, ggrt | anchor:");
        for (i = 0; i < BENCH_NSPD; i++)
            if (bench_selected(bo->scenes, bench_spd_scenes[i])) {
                printf(" %s %.1f%% | ", bench_spd_scenes[i], blk[i][0]);
                /* an anchor whose RESULT line has no shadow= or blocked= */
                if (blk[i][1] < 0)
                    printf("-;");
                else
                    printf("%.1f%%;", blk[i][1]);
            }
        printf("\n");
    }
    printf("ggrt = ggRender wall time; emb-p1, emb-p16 = the anchor's trace_s (single eye rays, "
           "16-ray eye packets; its Mrays/s from its own ray count); pov = POV-Ray's \"Trace "
           "Time\"; above 1x ggrt is faster\n");
    return EXIT_OK;
}

int bench_spd(const bench_opts *bo)
{
    int i, npov = 0, pov = bo->pov && have_povray();
    double logsum = 0, worst = 1e300;
    int rc;
    if (bo->embree) return bench_spd_embree(bo, pov);
    printf("ggrt bench spd: %dx%d, %d thread%s, depth 5, pixel centres, no antialiasing, "
           "median of %d run%s\n",
           bo->size, bo->size, bo->threads, BENCH_S(bo->threads), bo->runs, BENCH_S(bo->runs));
    bench_print_machine();
    print_knobs(bo);
    if (bo->pov && !pov) printf("(povray not found: install it with apt-get install povray)\n");
    printf("\n%-11s %7s %7s %8s %8s %9s %8s %7s %9s | %8s %7s %7s\n", "scene", "prims", "parse",
           "prepare", "render", "Mrays", "Mrays/s", "peakMB", "B/prim", "pov", "povMB", "speedup");
    for (i = 0; i < BENCH_NSPD; i++) {
        spd_job j;
        spd_result r;
        pov_result pr;
        double peak = 0, rays;
        if (!bench_selected(bo->scenes, bench_spd_scenes[i])) continue;
        memset(&j, 0, sizeof j);
        snprintf(j.path, sizeof j.path, "%s/%s.nff", bo->spd_dir, bench_spd_scenes[i]);
        j.size = bo->size, j.threads = bo->threads, j.runs = bo->runs;
        j.accuracy = bo->accuracy;
        if ((rc = spd_measure(&j, bench_spd_scenes[i], &r, &peak)) != EXIT_OK) return rc;
        rays = (double)(r.st.eye + r.st.reflect + r.st.refract + r.st.shadow);
        printf("%-11s %7zu %6.3fs %7.3fs %7.3fs %9.2f %8.2f %7.1f %9.1f |", bench_spd_scenes[i],
               r.info.primitives, r.parse, r.prepare, r.render, rays / 1e6, rays / r.render / 1e6,
               peak, r.info.primitives ? (double)r.info.geometry_bytes / r.info.primitives : 0.0);
        if (pov) {
            pr = run_pov(bo->pov_dir, bench_spd_scenes[i], bo->size, bo->threads, bo->runs, 1);
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
    return EXIT_OK;
}

int bench_counts(const bench_opts *bo)
{
    /* The SPD README's reference table (eye rays hitting, reflect, refract,
       shadow), about 10% spread expected. */
    static const double ref[BENCH_NSPD][4] = {
        {263169, 175095, 0, 954368},      {245086, 304643, 207564, 2246955},
        {263169, 315236, 0, 1085002},     {49788, 0, 0, 46112},
        {173125, 354769, 354769, 412922}, {169836, 0, 0, 1097419},
        {161120, 225248, 0, 407656},
    };
    static const char *const kinds[4] = {"eye-hit", "reflect", "refract", "shadow"};
    int i, k, bad = 0, rc;
    printf("ggrt bench counts: SPD rules (513x513 corner rays, depth 5, transmitters spawn "
           "reflection rays), %d thread%s\n\n",
           bo->threads, BENCH_S(bo->threads));
    printf("%-11s %-8s %10s %10s %8s\n", "scene", "rays", "ggrt", "SPD", "diff");
    for (i = 0; i < BENCH_NSPD; i++) {
        spd_job j;
        spd_result r;
        double got[4];
        if (!bench_selected(bo->scenes, bench_spd_scenes[i])) continue;
        memset(&j, 0, sizeof j);
        snprintf(j.path, sizeof j.path, "%s/%s.nff", bo->spd_dir, bench_spd_scenes[i]);
        j.size = 512, j.threads = bo->threads, j.runs = 1, j.spd_rules = 1;
        if ((rc = spd_measure(&j, bench_spd_scenes[i], &r, NULL)) != EXIT_OK) return rc;
        got[0] = (double)r.st.eye_hit, got[1] = (double)r.st.reflect;
        got[2] = (double)r.st.refract, got[3] = (double)r.st.shadow;
        for (k = 0; k < 4; k++) {
            double d = ref[i][k] > 0 ? 100.0 * (got[k] - ref[i][k]) / ref[i][k] : 0;
            int off = ref[i][k] > 0 ? fabs(d) > 10 : got[k] != 0;
            bad += off;
            printf("%-11s %-8s %10.0f %10.0f %+7.1f%%%s\n", k ? "" : bench_spd_scenes[i], kinds[k],
                   got[k], ref[i][k], d, off ? "  <- outside 10%" : "");
        }
    }
    printf("\n%d of the counts are outside 10%% of the SPD table\n", bad);
    return EXIT_OK;
}
