/* SPDX-License-Identifier: MIT */
/*
** accuracy.c -- `ggrt bench accuracy SCENE...`: what each accuracy
** knob costs in time and buys in error, one knob at a time from the
** accurate defaults. Writes a CSV, an SVG plot of error against time per
** knob (the Pareto front marked), and prints the tables.
**
** Error is measured against a reference rendered with every knob at its
** most accurate. Two knobs have no finite "most accurate" setting, so they
** get references of their own: samples per pixel (16 samples) and the depth
** limit (depth 12); every other knob is compared with the accurate default
** (one sample, depth 5), so that aliasing and the depth limit do not hide
** the knob's own effect.
** "changed" counts the pixels whose ray tree differs from the default's,
** as ggDiff finds them (include/ggrt/debug.h), one sample per pixel.
*/
#include "bench/bench.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef struct knob {
    const char *name, *setting;
    int is_default;
    void (*apply)(ggRenderOptions *o, double v);
    double value;
} knob;

static void k_none(ggRenderOptions *o, double v)
{
    (void)o, (void)v;
}
static void k_offset(ggRenderOptions *o, double v)
{
    o->accuracy.offset = v > 0 ? GG_ACC_OFFSET_FIXED : GG_ACC_OFFSET_SCALED;
    o->accuracy.offset_eps = v;
}
static void k_sphere(ggRenderOptions *o, double v)
{
    o->accuracy.sphere = (int)v;
}
static void k_refract(ggRenderOptions *o, double v)
{
    o->accuracy.refract = (int)v;
}
static void k_fresnel(ggRenderOptions *o, double v)
{
    o->accuracy.fresnel = (int)v;
}
static void k_texture(ggRenderOptions *o, double v)
{
    o->accuracy.texture = (int)v;
}
static void k_waves(ggRenderOptions *o, double v)
{
    o->accuracy.wavelengths = (int)v;
}
static void k_cutoff(ggRenderOptions *o, double v)
{
    o->accuracy.cutoff = v;
}
static void k_depth(ggRenderOptions *o, double v)
{
    o->max_depth = (int)v;
}
static void k_spp(ggRenderOptions *o, double v)
{
    o->samples = (int)v;
}
static void k_tol(ggRenderOptions *o, double v)
{
    o->accuracy.implicit_tol = v;
}
static void k_grad(ggRenderOptions *o, double v)
{
    o->accuracy.gradient_h = v;
}
static void k_isect(ggRenderOptions *o, double v)
{
    o->accuracy.intersect = (int)v;
}
static void k_shadows(ggRenderOptions *o, double v)
{
    o->accuracy.shadows = (int)v;
}
static void k_phong(ggRenderOptions *o, double v)
{
    o->accuracy.phong = (int)v;
}

static const knob knobs[] = {
    {"default", "all accurate", 1, k_none, 0},
    {"offset", "scaled", 1, k_offset, 0},
    {"offset", "fixed 1e-9", 0, k_offset, 1e-9},
    {"offset", "fixed 1e-6", 0, k_offset, 1e-6},
    {"offset", "fixed 1e-3", 0, k_offset, 1e-3},
    {"sphere", "stable", 1, k_sphere, GG_ACC_SPHERE_STABLE},
    {"sphere", "textbook", 0, k_sphere, GG_ACC_SPHERE_TEXTBOOK},
    {"refract", "accurate", 1, k_refract, GG_ACC_REFRACT_ACCURATE},
    {"refract", "exact", 0, k_refract, GG_ACC_REFRACT_EXACT},
    {"refract", "textbook", 0, k_refract, GG_ACC_REFRACT_TEXTBOOK},
    {"fresnel", "as scene", 1, k_fresnel, 0},
    {"fresnel", "none", 0, k_fresnel, GG_ACC_FRESNEL_NONE},
    {"fresnel", "schlick", 0, k_fresnel, GG_ACC_FRESNEL_SCHLICK},
    {"fresnel", "exact", 0, k_fresnel, GG_ACC_FRESNEL_EXACT},
    {"implicit-tol", "own", 1, k_tol, 0},
    {"implicit-tol", "1e-3", 0, k_tol, 1e-3},
    {"implicit-tol", "1e-6", 0, k_tol, 1e-6},
    {"gradient", "exact", 1, k_grad, 0},
    {"gradient", "h 1e-2", 0, k_grad, 1e-2},
    {"gradient", "h 6e-6", 0, k_grad, 6e-6},
    {"gradient", "h 1e-10", 0, k_grad, 1e-10},
    {"depth", "2", 0, k_depth, 2},
    {"depth", "3", 0, k_depth, 3},
    {"depth", "5", 1, k_depth, 5},
    {"depth", "8", 0, k_depth, 8},
    {"depth", "12", 0, k_depth, 12},
    {"cutoff", "off", 1, k_cutoff, 0},
    {"cutoff", "1e-3", 0, k_cutoff, 1e-3},
    {"cutoff", "1e-2", 0, k_cutoff, 1e-2},
    {"cutoff", "1e-1", 0, k_cutoff, 1e-1},
    {"texture", "as scene", 1, k_texture, 0},
    {"texture", "nearest", 0, k_texture, GG_ACC_TEXTURE_NEAREST},
    {"texture", "bilinear", 0, k_texture, GG_ACC_TEXTURE_BILINEAR},
    {"wavelengths", "R,G,B", 1, k_waves, 0},
    {"wavelengths", "one", 0, k_waves, 1},
    {"samples", "1", 1, k_spp, 1},
    {"samples", "4", 0, k_spp, 4},
    {"samples", "9", 0, k_spp, 9},
    {"intersect", "double", 1, k_isect, GG_ACC_ISECT_DOUBLE},
    {"intersect", "float", 0, k_isect, GG_ACC_ISECT_FLOAT},
    {"shadows", "colored", 1, k_shadows, GG_ACC_SHADOWS_COLORED},
    {"shadows", "opaque", 0, k_shadows, GG_ACC_SHADOWS_OPAQUE},
    {"phong", "exact", 1, k_phong, GG_ACC_PHONG_EXACT},
    {"phong", "fast", 0, k_phong, GG_ACC_PHONG_FAST},
};
#define NKNOBS (sizeof knobs / sizeof knobs[0])

int bench_knob_names(const char **names, int max)
{
    size_t i;
    int n = 0, k;
    for (i = 0; i < NKNOBS; i++) {
        if (knobs[i].apply == k_none) continue;
        for (k = 0; k < n && strcmp(names[k], knobs[i].name); k++) continue;
        if (k == n && n < max) names[n++] = knobs[i].name;
    }
    return n;
}
#define REF_SPP   16
#define REF_DEPTH 12

typedef struct row {
    int done; /* measured (--knobs may leave knobs out) */
    double time;
    ggRayStats st;
    ggImageDiff d;
    size_t changed;
} row;

/* Pixels whose ray tree the knob changes: ggDiff of one sample per pixel
   with the accurate defaults (debug.h: another object hit or from the
   other side, a TIR decision, a shadow verdict or occluder, a ray missing
   or an extra one, another stop reason). The knob side renders its own
   copy of the scene: some knobs live in the geometry. -1 if it failed. */
static long trees_changed(ggScene *s, ggScene *copy, const ggRenderOptions *base,
                          const ggRenderOptions *o)
{
    ggRenderOptions a = *base, b = *o;
    ggDiffResult *r = NULL;
    long n;
    a.samples = b.samples = 1;
    if (ggDiff(s, &a, copy, &b, 0, &r, NULL) != GG_OK) return -1;
    n = r->tree_differ;
    ggDiffResultFree(r);
    return n;
}

static int measure(ggScene *s, const ggRenderOptions *o, int runs, ggImage **img, row *r)
{
    double t[64];
    int k;
    for (k = 0; k < runs && k < 64; k++) {
        ggImage *im = NULL;
        double t0 = cli_now();
        memset(&r->st, 0, sizeof r->st);
        if (ggRender(s, o, &im, &r->st, NULL) != GG_OK) return -1;
        t[k] = cli_now() - t0;
        if (k == 0)
            *img = im;
        else
            ggImageFree(im);
    }
    r->time = bench_median(t, k);
    return 0;
}

/* ---- the plot: log10 RMSE against time, one colour per knob ---- */

static const char *const palette[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd",
                                      "#8c564b", "#e377c2", "#17becf", "#bcbd22",
                                      "#ff7f0e", "#7f7f7f", "#393b79", "#637939"};

static void plot(FILE *f, const char *scene, const row *rows, double yoff)
{
    double tmin = 1e300, tmax = 0, emin = 1e300, emax = -1e300;
    size_t i, k, prev = 0;
    const char *last = "";
    int c = -1;
    const double W = 640, H = 360, L = 70, T = 30 + yoff;
    /* Time on a log axis: the samples knob multiplies it, the others move
       it by percents. */
    for (i = 0; i < NKNOBS; i++) {
        double e = log10(rows[i].d.rmse > 1e-12 ? rows[i].d.rmse : 1e-12);
        if (!rows[i].done) continue;
        tmin = fmin(tmin, rows[i].time), tmax = fmax(tmax, rows[i].time);
        emin = fmin(emin, e), emax = fmax(emax, e);
    }
    tmin *= 0.9, tmax *= 1.1;
    if (!(tmin > 0)) tmin = 1e-6;
    if (tmax <= tmin) tmax = tmin * 2;
    if (emax <= emin) emax = emin + 1;
    fprintf(f, "<text x='%g' y='%g' font-size='14'>%s: log10 RMSE vs render time (log)</text>\n", L,
            T - 10, scene);
    fprintf(f, "<rect x='%g' y='%g' width='%g' height='%g' fill='none' stroke='#999'/>\n", L, T, W,
            H);
    fprintf(f,
            "<text x='%g' y='%g' font-size='11'>%.3fs</text><text x='%g' y='%g' "
            "font-size='11' text-anchor='end'>%.3fs</text>\n",
            L, T + H + 14, tmin, L + W, T + H + 14, tmax);
    fprintf(f,
            "<text x='%g' y='%g' font-size='11' text-anchor='end'>%.1f</text><text x='%g' "
            "y='%g' font-size='11' text-anchor='end'>%.1f</text>\n",
            L - 4, T + 10, emax, L - 4, T + H, emin);
#define PX(t) (L + log((t) / tmin) / log(tmax / tmin) * W)
#define PY(e) (T + H - ((e)-emin) / (emax - emin) * H)
    for (i = 0; i < NKNOBS; i++) {
        double e = log10(rows[i].d.rmse > 1e-12 ? rows[i].d.rmse : 1e-12);
        int pareto = 1;
        if (!rows[i].done) continue;
        if (strcmp(knobs[i].name, last)) {
            c = (c + 1) % (int)(sizeof palette / sizeof palette[0]);
            last = knobs[i].name;
            fprintf(f, "<text x='%g' y='%g' font-size='11' fill='%s'>%s</text>\n", L + W + 10,
                    T + 12 + 14 * c, palette[c], knobs[i].name);
        } else {
            double ep = log10(rows[prev].d.rmse > 1e-12 ? rows[prev].d.rmse : 1e-12);
            fprintf(f, "<line x1='%.1f' y1='%.1f' x2='%.1f' y2='%.1f' stroke='%s'/>\n",
                    PX(rows[prev].time), PY(ep), PX(rows[i].time), PY(e), palette[c]);
        }
        prev = i;
        /* Pareto: no other setting is both faster and more accurate. */
        for (k = 0; k < NKNOBS; k++)
            if (rows[k].done && rows[k].time < rows[i].time && rows[k].d.rmse < rows[i].d.rmse)
                pareto = 0;
        fprintf(f,
                "<circle cx='%.1f' cy='%.1f' r='%d' fill='%s'%s><title>%s %s: %.4fs, RMSE "
                "%.3g</title></circle>\n",
                PX(rows[i].time), PY(e), pareto ? 5 : 3, palette[c],
                pareto ? " stroke='black' stroke-width='1.5'" : "", knobs[i].name, knobs[i].setting,
                rows[i].time, rows[i].d.rmse);
    }
#undef PX
#undef PY
}

static void print_row(FILE *csv, const char *scene, size_t i, const row *r)
{
    const ggRayStats *st = &r->st;
    unsigned long long rays =
        (unsigned long long)(st->eye + st->reflect + st->refract + st->shadow);
    printf("%-13s %-12s %8.4fs %9llu %10.3g %9.3g %8.1f %7.2f%% %8zu%s\n", knobs[i].name,
           knobs[i].setting, r->time, rays, r->d.rmse, r->d.max_abs, r->d.psnr,
           100 * r->d.frac_over, r->changed,
           r->d.rmse == 0 && r->changed == 0 && !knobs[i].is_default ? "  (no effect on this scene)"
                                                                     : "");
    fprintf(csv, "%s,%s,%s,%d,%.6f,%llu,%llu,%llu,%llu,%llu,%.6g,%.6g,%.4f,%.6f,%zu\n", scene,
            knobs[i].name, knobs[i].setting, knobs[i].is_default, r->time,
            (unsigned long long)st->eye, (unsigned long long)st->reflect,
            (unsigned long long)st->refract, (unsigned long long)st->shadow,
            (unsigned long long)st->tir, r->d.rmse, r->d.max_abs, r->d.psnr, r->d.frac_over,
            r->changed);
}

/* Every knob on one prepared scene: a row each, then the scene's plot. */
static int sweep(ggScene *s, ggScene *copy, const bench_opts *bo, const char *scene, int w, int h,
                 FILE *csv, FILE *svg, double yoff)
{
    ggRenderOptions base, o;
    ggImage *ref = NULL, *ref_spp = NULL, *ref_depth = NULL;
    row rows[NKNOBS];
    size_t i;
    int rc = EXIT_INPUT;
    ggRenderOptionsDefault(&base);
    base.width = w, base.height = h, base.threads = bo->threads;
    o = base;
    if (measure(s, &o, 1, &ref, &rows[0]) != 0) goto done;
    o.samples = REF_SPP;
    if (measure(s, &o, 1, &ref_spp, &rows[0]) != 0) goto done;
    o = base;
    o.max_depth = REF_DEPTH;
    if (measure(s, &o, 1, &ref_depth, &rows[0]) != 0) goto done;
    printf("\n%s\n%-13s %-12s %9s %9s %10s %9s %8s %8s %8s\n", scene, "knob", "setting", "time",
           "rays", "RMSE", "max", "PSNR", ">1/255", "changed");
    for (i = 0; i < NKNOBS; i++) {
        ggImage *img = NULL;
        long changed;
        int is_spp = knobs[i].apply == k_spp, is_depth = knobs[i].apply == k_depth;
        rows[i].done = 0;
        if (knobs[i].apply != k_none && !bench_selected(bo->knobs, knobs[i].name)) continue;
        rows[i].done = 1;
        o = base;
        knobs[i].apply(&o, knobs[i].value);
        if (measure(s, &o, bo->runs, &img, &rows[i]) != 0) {
            cli_error("render failed");
            goto done;
        }
        ggImageCompare(img,
                       is_spp     ? ref_spp
                       : is_depth ? ref_depth
                                  : ref,
                       GG_COMPARE_LINEAR, &rows[i].d);
        changed = is_spp || is_depth ? 0 : trees_changed(s, copy, &base, &o);
        if (changed < 0) {
            cli_error("the ray-tree comparison failed");
            goto done;
        }
        rows[i].changed = (size_t)changed;
        print_row(csv, scene, i, &rows[i]);
        ggImageFree(img);
        fflush(stdout);
    }
    plot(svg, scene, rows, yoff);
    rc = EXIT_OK;
done:
    ggImageFree(ref), ggImageFree(ref_spp), ggImageFree(ref_depth);
    return rc;
}

int bench_accuracy(const bench_opts *bo)
{
    const char *out = bo->out_dir ? bo->out_dir : ".";
    char path[1024];
    cli_out co, so;
    int a, rc = EXIT_OK, w = bo->size ? bo->size : 240, h = w * 3 / 4;
    /* A height of 0 would render at the scene's own height, not the
       printed size (--size 1). */
    if (h < 1) h = 1;
    if (bo->nargs == 0) {
        cli_error("name one or more scene files");
        cli_usage_hint();
        return EXIT_USAGE;
    }
    /* Every scene read once first: a bad one fails before the header, the
       files and minutes of sweeps over the scenes before it. */
    for (a = 0; a < bo->nargs; a++) {
        ggScene *s = cli_load_scene(bo->args[a], NULL, NULL, 1, &rc);
        if (!s) return rc;
        ggSceneFree(s);
    }
    snprintf(path, sizeof path, "%s/accuracy.csv", out);
    if ((rc = cli_out_open(&co, "bench accuracy", path)) != 0) return rc;
    snprintf(path, sizeof path, "%s/accuracy.svg", out);
    if ((rc = cli_out_open(&so, "bench accuracy", path)) != 0) {
        fclose(co.f), unlink(co.tmp);
        return rc;
    }
    fprintf(co.f, "scene,knob,setting,default,time_s,eye,reflect,refract,shadow,tir,rmse,max_abs,"
                  "psnr_db,share_over_1_255,changed_pixels\n");
    fprintf(so.f,
            "<?xml version='1.0' encoding='UTF-8'?>\n<svg xmlns='http://www.w3.org/2000/svg' "
            "width='860' height='%d' font-family='sans-serif'>\n<rect width='100%%' "
            "height='100%%' fill='white'/>\n",
            bo->nargs * 420 + 20);
    printf("ggrt bench accuracy: %dx%d, %d thread%s, median of %d run%s; reference = every knob "
           "accurate (samples knob: %d samples; depth knob: depth %d)\n",
           w, h, bo->threads, BENCH_S(bo->threads), bo->runs, BENCH_S(bo->runs), REF_SPP,
           REF_DEPTH);
    for (a = 0; a < bo->nargs && rc == EXIT_OK; a++) {
        ggScene *s = cli_load_scene(bo->args[a], NULL, NULL, 1, &rc), *copy = NULL;
        if (s) copy = cli_load_scene(bo->args[a], NULL, NULL, 1, &rc);
        if (copy) rc = sweep(s, copy, bo, bo->args[a], w, h, co.f, so.f, a * 420.0);
        ggSceneFree(s);
        ggSceneFree(copy);
    }
    fprintf(so.f, "</svg>\n");
    if (rc != EXIT_OK) {
        fclose(co.f), fclose(so.f), unlink(co.tmp), unlink(so.tmp);
        return rc;
    }
    if ((rc = cli_out_close(&co, "bench accuracy")) != 0) {
        fclose(so.f), unlink(so.tmp);
        return rc;
    }
    if ((rc = cli_out_close(&so, "bench accuracy")) != 0) return rc;
    printf("\nwrote %s/accuracy.csv and %s/accuracy.svg\n", out, out);
    if (bo->knobs) return EXIT_OK; /* a subset: not the whole study */
    {
        /* The scaling tables always come with the study; --size there is
           the study's, so use the scaling default. */
        bench_opts sc = *bo;
        sc.size = 0;
        return bench_scaling(&sc);
    }
}
