/* SPDX-License-Identifier: MIT */
/*
** cmd_plan.c -- `ggrt plan SCENE --tiles N -o plan.json`: a cut of the
** image into N bands of rows of about equal cost, from a low-resolution
** render's per-pixel cost map (ggRenderOptions.cost_map), for ggrt
** render --plan (tile.h, docs/cluster.md).
*/
#include "render/tile.h"
#include "common/json.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char about[] =
    "Cut an image into N bands of whole rows that cost about the same to render, for\n"
    "'ggrt render --plan FILE --tile I' on N processes or machines. The cost is\n"
    "measured on a render at 1/F of the size in each direction (--scale F) with the\n"
    "same options: by default the time each pixel takes, the least of R renders\n"
    "(--runs R), or the rays it casts (--cost rays: the same plan on every run and\n"
    "machine, but less even). The plan records the scene file's hash, the render\n"
    "options and the size; render refuses a plan made for other ones.";

static const char tail[] = "exit: 0 ok, 1 usage, 2 bad scene, 3 I/O error";

static const char *const cost_kinds[] = {"rays", "time", NULL};

typedef struct plan_args {
    const char *scene, *out;
    int n, cost, scale, runs, quiet;
    cli_render ro;
} plan_args;

static int parse(plan_args *a, int argc, char **argv)
{
    cli_opt mine[] = {
        CLI_OPT_INT('t', "tiles", &a->n, 1, TILE_MAX_PLAN, "N",
                    "the number of tiles (required), 1 to 1024 and at\n"
                    "most the number of rows"),
        CLI_OPT_STRING('o', "output", &a->out, "FILE",
                       "the plan to write (required), JSON; written whole\n"
                       "or not at all; not the scene's file"),
        CLI_OPT_CHOICE(0, "cost", &a->cost, cost_kinds, "KIND",
                       "time (default: seconds per pixel, measured) or\n"
                       "rays (rays cast: reproducible, less even)"),
        CLI_OPT_INT(0, "scale", &a->scale, 1, 64, "F",
                    "measure on a render of 1/F of the width and height\n"
                    "(default 4: about 1/16 of the render's work)"),
        CLI_OPT_INT(0, "runs", &a->runs, 1, 100, "R",
                    "with --cost time: render R times and keep each\n"
                    "pixel's least time (default 3)"),
        CLI_OPT_FLAG('q', "quiet", &a->quiet, "no progress bar and no summary"),
        CLI_OPT_END,
    };
    cli_cmd cmd = {.name = "plan",
                   .usage = "SCENE --tiles N -o PLAN.json [options]",
                   .about = about,
                   .tail = tail,
                   .opts = {mine, a->ro.table},
                   .args = &a->scene,
                   .min_args = 1,
                   .max_args = 1,
                   .args_name = "scene"};
    int rc;
    a->scale = 4, a->cost = 1, a->runs = 3;
    cli_render_init(&a->ro, CLI_RENDER_PIXEL | CLI_RENDER_THREADS);
    if ((rc = cli_parse(&cmd, argc, argv)) != CLI_GO) return rc;
    cli_render_finish(&a->ro);
    if (!a->out) return cli_usage_error(&cmd, "need -o PLAN.json");
    /* A plan is JSON: under an image's name a viewer would choke on it
       (as merge --reports refuses). */
    if (cli_image_kind(a->out) != CLI_IMAGE_NONE)
        return cli_usage_error(&cmd, "a plan is JSON, not an image: '%s'", a->out);
    if (!a->n) return cli_usage_error(&cmd, "need --tiles N");
    /* Rays cast do not vary between runs: one is measured and recorded. */
    if (mine[4].given && a->cost == 0)
        return cli_usage_error(&cmd, "--runs goes with --cost time (rays are the same every run)");
    return cli_check_not_input(&cmd, "-o", a->out, &a->scene, 1);
}

/* Each row's cost at full size: the heat map row its centre falls in,
   shared equally among the full rows that fall there. */
static double *row_costs(const float *cost, int lw, int lh, int h)
{
    double *low = calloc((size_t)lh, sizeof *low), *row = malloc((size_t)h * sizeof *row);
    int *count = calloc((size_t)lh, sizeof *count), x, y;
    if (!low || !row || !count) {
        free(low), free(row), free(count);
        return NULL;
    }
    for (y = 0; y < lh; y++)
        for (x = 0; x < lw; x++) {
            float c = cost[(size_t)y * lw + x];
            if (isfinite(c) && c > 0) low[y] += c;
        }
    for (y = 0; y < h; y++) count[(long long)(2 * y + 1) * lh / (2LL * h)]++;
    for (y = 0; y < h; y++) {
        int r = (int)((long long)(2 * y + 1) * lh / (2LL * h));
        row[y] = low[r] / count[r];
    }
    free(low), free(count);
    return row;
}

/* Boundaries y[0..n]: y[i] the row where the cost before it comes
   nearest i/n of the total, every band at least one row. share[i] gets
   band i's part of the total. Equal bands if nothing cost anything. */
static void cut_rows(const double *row, int h, int n, int *y, double *share)
{
    double *pre = malloc(((size_t)h + 1) * sizeof *pre), total;
    int i, k;
    if (!pre) {
        for (i = 0; i <= n; i++) y[i] = (int)((long long)i * h / n);
        for (i = 0; i < n; i++) share[i] = 1.0 / n;
        return;
    }
    for (pre[0] = 0, k = 0; k < h; k++) pre[k + 1] = pre[k] + row[k];
    total = pre[h];
    y[0] = 0, y[n] = h;
    for (i = 1; i < n; i++) {
        double target = total * i / n;
        int at = y[i - 1] + 1, hi = h - (n - i);
        if (total <= 0) {
            y[i] = (int)((long long)i * h / n);
            continue;
        }
        while (at < hi && pre[at + 1] <= target) at++;
        if (at < hi && pre[at + 1] - target < target - pre[at]) at++;
        y[i] = at;
    }
    for (i = 0; i < n; i++) share[i] = total > 0 ? (pre[y[i + 1]] - pre[y[i]]) / total : 0;
    free(pre);
}

/* The cost map of a render at 1/scale of the size. By time: each
   pixel's least wall-clock time over a->runs renders. The least, because
   whatever else the machine does (a preemption, a cold cache in the first
   render) only ever adds to a pixel's time; wall clock, because it costs
   about 30 ns to read where the per-thread CPU clock (GG_COST_CPU) is a
   system call of about 1 us here, a third of a gears pixel at -n 4, added
   to every pixel alike, which made cheap rows look dearer than they are
   (docs/log/2026-12-05-plan.md). */
static int measure(ggScene *scene, const plan_args *a, int w, int h, float **cost, int *lw,
                   int *lh)
{
    ggRenderOptions o = a->ro.opt;
    ggImage *img = NULL;
    ggError err;
    size_t n, i;
    int r, rc = GG_OK, runs = a->cost ? a->runs : 1;
    float *run;
    *lw = (w + a->scale - 1) / a->scale, *lh = (h + a->scale - 1) / a->scale;
    n = (size_t)*lw * (size_t)*lh;
    *cost = calloc(n, sizeof **cost), run = calloc(n, sizeof *run);
    if (!*cost || !run) {
        free(run);
        cli_error("out of memory for a %dx%d cost map", *lw, *lh);
        return EXIT_INPUT;
    }
    o.width = *lw, o.height = *lh;
    o.cost_map = run, o.cost_kind = a->cost ? GG_COST_TIME : GG_COST_RAYS;
    cli_cancel_begin();
    for (r = 0; r < runs && rc == GG_OK; r++) {
        cli_bar bar;
        char what[48];
        snprintf(what, sizeof what, "measuring %d/%d", r + 1, runs);
        cli_bar_begin(&bar, what, a->quiet);
        o.progress = cli_bar_step, o.progress_ud = &bar;
        rc = ggRender(scene, &o, &img, NULL, &err);
        cli_bar_end(&bar);
        ggImageFree(img), img = NULL;
        if (cli_cancelled()) {
            free(run);
            cli_error("cancelled by signal %d; %s not written", cli_cancelled(), a->out);
            cli_cancel_exit(cli_cancelled());
        }
        for (i = 0; i < n && rc == GG_OK; i++)
            if (r == 0 || run[i] < (*cost)[i]) (*cost)[i] = run[i];
    }
    free(run);
    return rc == GG_OK ? EXIT_OK : cli_fail(rc, &err, 1);
}

static void write_json(FILE *f, const plan_args *a, const char *hash, const char *options,
                       int w, int h, int lw, int lh, const int *y, const double *share,
                       double secs)
{
    int i;
    fprintf(f, "{\"ggrt_plan\":1,\"version\":");
    json_str(f, ggVersion());
    fprintf(f, ",\"buildId\":");
    json_str(f, ggBuildId());
    fprintf(f, ",\"scene\":");
    json_str(f, a->scene);
    fprintf(f, ",\"sceneHash\":");
    json_str(f, hash);
    fprintf(f, ",\"options\":");
    json_str(f, options);
    fprintf(f, ",\"size\":[%d,%d],\"tiles\":%d,\"cost\":\"%s\",\"heatmap\":[%d,%d],\"runs\":%d,\"seconds\":",
            w, h, a->n, cost_kinds[a->cost], lw, lh, a->cost ? a->runs : 1);
    json_num(f, secs);
    fprintf(f, ",\n\"rows\":[");
    for (i = 0; i <= a->n; i++) fprintf(f, i ? ",%d" : "%d", y[i]);
    fprintf(f, "],\n\"share\":[");
    for (i = 0; i < a->n; i++) fprintf(f, i ? ",%.4f" : "%.4f", share[i]);
    fprintf(f, "]}\n");
}

/* Measure, cut, write the plan and (unless -q) the bands. */
static int plan(ggScene *scene, const plan_args *a)
{
    char hash[32], options[2048];
    int w, h, lw, lh, i, rc, *y = NULL;
    double *row = NULL, *share = NULL, t0 = cli_now();
    float *cost = NULL;
    cli_out out;
    if (tile_options(scene, &a->ro.opt, &w, &h, options, sizeof options) != 0) {
        cli_error("render options too long for a plan");
        return EXIT_USAGE;
    }
    if (h < a->n) {
        cli_error("%d tiles of %d rows: at most one tile per row", a->n, h);
        cli_usage_hint();
        return EXIT_USAGE;
    }
    if (tile_hash_file(a->scene, hash, sizeof hash) != 0) {
        cli_error("%s: cannot read to hash it", a->scene);
        return EXIT_IO;
    }
    if ((rc = measure(scene, a, w, h, &cost, &lw, &lh)) != EXIT_OK) {
        free(cost);
        return rc;
    }
    row = row_costs(cost, lw, lh, h);
    y = malloc(((size_t)a->n + 1) * sizeof *y), share = malloc((size_t)a->n * sizeof *share);
    if (!row || !y || !share) {
        cli_error("out of memory");
        rc = EXIT_INPUT;
    } else {
        /* written whole or not at all, as render's images */
        cli_cancel_hold();
        if ((rc = cli_out_open(&out, "plan", a->out)) == EXIT_OK) {
            cut_rows(row, h, a->n, y, share);
            write_json(out.f, a, hash, options, w, h, lw, lh, y, share, cli_now() - t0);
            rc = cli_out_close(&out, "plan");
            if (rc == EXIT_OK) cli_cancel_after_write(a->out);
        }
        cli_cancel_release();
        if (rc == EXIT_OK && cli_cancelled()) cli_cancel_exit(cli_cancelled());
    }
    if (rc == EXIT_OK && !a->quiet) {
        printf("plan: %d tiles of %dx%d by %s, measured at %dx%d in %.3fs -> %s\n", a->n, w, h,
               cost_kinds[a->cost], lw, lh, cli_now() - t0, a->out);
        for (i = 0; i < a->n; i++)
            printf("  tile %d: rows %d..%d, %.1f%% of the %s\n", i, y[i], y[i + 1] - 1,
                   100 * share[i], cost_kinds[a->cost]);
    }
    free(cost), free(row), free(y), free(share);
    return rc;
}

int cmd_plan(int argc, char **argv)
{
    plan_args a;
    ggScene *scene;
    int rc;
    memset(&a, 0, sizeof a);
    if ((rc = parse(&a, argc, argv)) != CLI_GO) return rc;
    if ((rc = cli_check_output("plan", a.out)) != 0) return rc;
    if (!(scene = cli_load_scene(a.scene, NULL, NULL, a.quiet, &rc))) return rc;
    {
        const char *opt = "-o";
        if ((rc = cli_check_not_read("plan", scene, &opt, &a.out, 1)) == 0) rc = plan(scene, &a);
    }
    ggSceneFree(scene);
    return rc;
}
