/* SPDX-License-Identifier: MIT */
/*
** cmd_check.c -- `ggrt check SCENE`: every pixel traced and tested for the
** invariants of ggCheck; a table, the worst pixels with their replay
** commands, and exit 4 when an invariant of class error fails (for CI).
*/
#include "debug/debug.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char about[] =
    "Trace every pixel as ggrt render computes it and test the ray trees for:\n"
    "  nonfinite   NaN or infinite pixel values (and the first ray that made them)\n"
    "  negative    negative pixel values\n"
    "  energy      a surface hit with kd * colour + ks + kt > 1 (with its material's\n"
    "              line)\n"
    "  truncation  rays cut by the depth limit (-d) or the ray budget whose children\n"
    "              would have weighed more than --truncation in the pixel (with a\n"
    "              bound on the missing light, and which option raises the limit)\n"
    "  self-hit    secondary rays hitting within a few error bounds of their origin\n"
    "  near-tir    refractions decided within a few rounding errors of the critical\n"
    "              angle\n"
    "  grazing     hits at grazing incidence\n"
    "nonfinite, negative, energy and truncation are errors, self-hit a warning, the\n"
    "others information (--severity changes that).\n"
    "With --path LPE, only the pixels with a light path LPE matches are checked (the\n"
    "whole of their trees), and each listed pixel shows the share of its value those\n"
    "paths carry: are the pixels lit this way sound?\n"
    "With --aov-sum LAYERS.exr (from ggrt render --aov), instead: do the file's path\n"
    "layers add up to its image in every pixel, within rounding? It names the light\n"
    "no layer claims (a gap) and the light two layers claim (an overlap), and traces\n"
    "the worst pixel of each in SCENE (default: the scene the file names) for an\n"
    "example path.";

static const char tail[] =
    "exit: 0 no error-class invariant failed (--aov-sum: the layers add up), 4 one\n"
    "did (--aov-sum: a gap or an overlap), 1 usage, 2 bad scene or file, 3 I/O error";

static const char *const formats[] = {"text", "json", NULL};

typedef struct check_args {
    const char *scene, *path, *aov_sum;
    int format, quiet, worst;
    ggCheckOptions co;
    cli_render ro;
    dbg_tile tile;
} check_args;

/* --severity NAME=LEVEL[,NAME=LEVEL...] */
static int parse_severity(void *ud, const char *v, char *why, size_t whylen)
{
    ggCheckOptions *co = ud, c = *co;
    const char *p = v;
    for (;;) {
        size_t len = strcspn(p, ","), eq = strcspn(p, "=");
        int k, s;
        for (k = 0; k < GG_CHECK_COUNT; k++)
            if (eq < len && strlen(ggCheckName(k)) == eq && !strncmp(p, ggCheckName(k), eq)) break;
        for (s = 0; k < GG_CHECK_COUNT && s < 3; s++)
            if (strlen(ggSeverityName(s)) == len - eq - 1 &&
                !strncmp(p + eq + 1, ggSeverityName(s), len - eq - 1))
                break;
        if (k == GG_CHECK_COUNT || s == 3) {
            snprintf(why, whylen,
                     "'%.*s' is not NAME=LEVEL with a NAME of nonfinite, negative, energy, "
                     "truncation, self-hit, near-tir, grazing and a LEVEL of error, warning, info",
                     (int)len, p);
            return -1;
        }
        c.severity[k] = s;
        if (!p[len]) break;
        p += len + 1;
    }
    *co = c;
    return 0;
}

static int parse(check_args *a, int argc, char **argv)
{
    cli_opt mine[] = {
        CLI_OPT_CHOICE('f', "format", &a->format, formats, "F", "text (default) or json"),
        CLI_OPT_INT(0, "worst", &a->worst, 0, GG_CHECK_WORST, "N",
                    "worst pixels shown per failing invariant (default 3)"),
        CLI_OPT_MANY(0, "severity", parse_severity, &a->co, "NAME=LEVEL,...",
                     "change an invariant's class: error, warning or info"),
        CLI_OPT_DOUBLE(0, "truncation", &a->co.truncation, 0, 1e300, "W",
                       "weight in the pixel above which cut rays count\n"
                       "(default 0.1)"),
        CLI_OPT_DOUBLE(0, "self-hit", &a->co.self_hit, 0, 1e300, "K",
                       "hits within K error bounds of the origin (default 4)"),
        CLI_OPT_DOUBLE(0, "near-tir", &a->co.near_tir, 0, 1e300, "K",
                       "discriminants within K rounding errors (default 16)"),
        CLI_OPT_DOUBLE(0, "grazing", &a->co.grazing, 0, 1, "C",
                       "|cos| of incidence below C (default 1e-3)"),
        CLI_OPT_STRING(0, "path", &a->path, "LPE",
                       "check only the pixels with a path this light-path\n"
                       "expression matches (docs/debugging.md)"),
        CLI_OPT_STRING(0, "aov-sum", &a->aov_sum, "LAYERS.exr",
                       "check that the path layers of this ggrt render\n"
                       "--aov file add up to its image (SCENE optional;\n"
                       "text only, no -f json)"),
        CLI_OPT_FLAG('q', "quiet", &a->quiet, "no progress bar"),
        DBG_TILE_OPTS(&a->tile),
        CLI_OPT_END,
    };
    cli_cmd cmd = {.name = "check",
                   .usage = "SCENE [--path LPE] [options] | --aov-sum LAYERS.exr [SCENE]",
                   .about = about,
                   .tail = tail,
                   .opts = {mine, a->ro.table},
                   .args = &a->scene,
                   .min_args = 0,
                   .max_args = 1,
                   .args_name = "scene"};
    int rc;
    ggCheckOptionsDefault(&a->co);
    a->worst = 3;
    cli_render_init(&a->ro, CLI_RENDER_ALL);
    if ((rc = cli_parse(&cmd, argc, argv)) != CLI_GO) return rc;
    cli_render_finish(&a->ro);
    if (!a->scene && !a->aov_sum) return cli_usage_error(&cmd, "need a scene");
    if (a->aov_sum && (a->path || a->format))
        return cli_usage_error(&cmd, "--aov-sum takes neither --path nor -f json");
    if (a->aov_sum && (a->tile.tl.count || a->tile.plan))
        return cli_usage_error(&cmd, "--aov-sum takes no --tile or --plan");
    return dbg_tile_check(&cmd, &a->tile, a->format, cli_given(&cmd, "crop"));
}

/* The JSON report; with --tile, its manifest: the params hold what else
   must agree (the check options). */
static int json_out(check_args *a, const ggCheckResult *r)
{
    ggRenderOptions o;
    FILE *f = dbg_tile_open(&a->tile);
    char params[600], t[4][32];
    int k, n;
    dbg_tile_options(&a->tile, &a->ro.opt, &o);
    if (f) json_check(f, a->scene, &o, r);
    /* in the options' own words, so that merge can name the one that
       differs: "self-hit=4 ... severity.self-hit=warning" */
    cli_shortest(t[0], sizeof t[0], a->co.truncation),
        cli_shortest(t[1], sizeof t[1], a->co.self_hit);
    cli_shortest(t[2], sizeof t[2], a->co.near_tir), cli_shortest(t[3], sizeof t[3], a->co.grazing);
    n = snprintf(params, sizeof params, "truncation=%s self-hit=%s near-tir=%s grazing=%s", t[0],
                 t[1], t[2], t[3]);
    for (k = 0; k < GG_CHECK_COUNT && n > 0 && (size_t)n < sizeof params; k++)
        n += snprintf(params + n, sizeof params - (size_t)n, " severity.%s=%s", ggCheckName(k),
                      ggSeverityName(a->co.severity[k]));
    return dbg_tile_close(&a->tile, f, params);
}

/* What the worst pixel of an invariant is about, in words. */
static void describe(FILE *f, const check_args *a, const ggCheckResult *r, int c,
                     const ggCheckPixel *p)
{
    char at[600] = "";
    if (p->line > 0) snprintf(at, sizeof at, " (%s:%d)", a->scene, p->line);
    switch (c) {
    case GG_CHECK_NONFINITE:
        fprintf(f, "ray #%d is the first to return NaN, infinity or more than a float holds",
                p->node);
        break;
    case GG_CHECK_NEGATIVE:
        fprintf(f, "the pixel goes to %.4g; ray #%d is the first to return a negative value",
                -p->value, p->node);
        break;
    case GG_CHECK_ENERGY:
        fprintf(f, "ray #%d hits material %d%s: kd * colour + ks + kt = %.4g", p->node, p->material,
                at, p->value);
        return;
    case GG_CHECK_TRUNCATION:
        fprintf(f,
                "cut rays would have weighed %.4g in the pixel (the most at ray #%d); missing "
                "light <= %.4g",
                p->value, p->node, p->value * r->radiance_bound);
        return;
    case GG_CHECK_NEAR_TIR:
        fprintf(f, "ray #%d refracts %.3g rounding errors from total internal reflection", p->node,
                p->value > 0 ? 1 / p->value : 0);
        break;
    case GG_CHECK_GRAZING:
        fprintf(f, "ray #%d meets its surface at |cos| = %.3g", p->node,
                p->value > 0 ? 1 / p->value : 0);
        break;
    default:
        fprintf(f, "ray #%d hits within %.3g error bounds of its origin", p->node,
                p->value > 0 ? 1 / p->value : 0);
        break;
    }
    if (p->object >= 0) fprintf(f, "; object #%d%s", p->object, at);
}

/* What truncation cut and which option raises the limit: a first run of
   check on glass.nff fails on it, and the table alone does not say how to
   go deeper. */
static void truncation_hint(const check_args *a, const ggCheckResult *r)
{
    unsigned long long budget = (unsigned long long)r->stats.budget_cut;
    int deepest = (int)r->stats.max_depth;
    int rb = a->ro.opt.ray_budget > 0 ? a->ro.opt.ray_budget : GG_RAY_BUDGET;
    if (!budget)
        printf("\ntruncation: the depth limit (%d here, counting the eye ray) cut rays whose "
               "light\nwould have weighed more than %g in the pixel.\n",
               deepest, a->co.truncation);
    else
        printf(
            "\ntruncation: the ray budget (%d ray%s per eye ray) left %llu rays uncast, and the\n"
            "depth limit (the deepest ray is at depth %d) may have cut others; their light\n"
            "would have weighed more than %g in the pixel.\n--ray-budget N raises the "
            "budget; ",
            rb, rb == 1 ? "" : "s", budget, deepest, a->co.truncation);
    printf("-d N raises the depth limit (up to 64); --truncation W the weight that counts.\n");
}

static void print_text(const check_args *a, const ggCheckResult *r)
{
    int c, k;
    if (a->path)
        printf("%s: %dx%d, %ld pixels with a path %s checked of %ld (their mean share "
               "%.2f%%)\n",
               a->scene, r->width, r->height, r->checked, a->path, r->scanned, 100 * r->share);
    else
        printf("%s: %dx%d, %ld pixels checked\n", a->scene, r->width, r->height, r->scanned);
    printf("%-11s %-8s %8s %9s %10s  %s\n", "invariant", "class", "pixels", "rays", "worst", "at");
    for (c = 0; c < GG_CHECK_COUNT; c++) {
        const ggCheckItem *it = &r->items[c];
        printf("%-11s %-8s %8ld %9ld ", ggCheckName(c), ggSeverityName(it->severity), it->pixels,
               it->rays);
        if (it->nworst)
            printf("%10.4g  %d,%d\n", it->worst, it->pixels_worst[0].x, it->pixels_worst[0].y);
        else
            printf("%10s  -\n", "-");
    }
    for (c = 0; c < GG_CHECK_COUNT; c++) {
        const ggCheckItem *it = &r->items[c];
        for (k = 0; k < it->nworst && k < a->worst; k++) {
            const ggCheckPixel *p = &it->pixels_worst[k];
            if (k == 0)
                printf("\n%s (%s), worst pixels:\n", ggCheckName(c), ggSeverityName(it->severity));
            printf("  %d,%d: ", p->x, p->y);
            if (a->path) printf("(share %.2f%%) ", 100 * p->share);
            describe(stdout, a, r, c, p);
            printf("\n    ");
            {
                const char *extra[3] = {"--path", a->path, NULL};
                dbg_replay(stdout, a->scene, NULL, &a->ro, p->x, p->y, a->path ? extra : NULL);
            }
            printf("\n");
        }
    }
    if (r->items[GG_CHECK_TRUNCATION].pixels)
        printf("\n(missing light: cut weight times %.4g, the most any ray can return here%s)\n",
               r->radiance_bound,
               isfinite(r->radiance_bound) ? "" : ": ks + kt >= 1 lets it grow without bound");
    if (r->items[GG_CHECK_TRUNCATION].pixels) truncation_hint(a, r);
    if (r->failed) {
        printf("\nFAIL: %d error-class invariant%s failed:", r->failed, r->failed > 1 ? "s" : "");
        for (c = 0; c < GG_CHECK_COUNT; c++)
            if (r->items[c].severity == GG_SEVERITY_ERROR && r->items[c].pixels)
                printf(" %s", ggCheckName(c));
        printf("\n");
    } else {
        printf("\nok: no error-class invariant failed\n");
    }
}

int cmd_check(int argc, char **argv)
{
    check_args a;
    ggScene *scene;
    ggCheckResult *r = NULL;
    ggPathExpr *path = NULL;
    dbg_progress_state ps;
    ggError err;
    int rc;
    memset(&a, 0, sizeof a);
    if ((rc = parse(&a, argc, argv)) != CLI_GO) return rc;
    if (a.aov_sum) return aov_sum_check(a.aov_sum, a.scene);
    if (a.path && (rc = ggPathParse(a.path, NULL, &path, &err)) != GG_OK)
        return rc == GG_ERROR_NOMEM ? cli_fail(rc, &err, 0)
                                    : dbg_expr_error("check", "path", a.path, &err);
    a.co.path = path;
    if (!(scene = cli_load_scene(a.scene, NULL, NULL, a.quiet, &rc))) {
        ggPathFree(path);
        return rc;
    }
    if ((rc = dbg_tile_begin(&a.tile, scene, a.scene, &a.ro.opt)) != EXIT_OK ||
        (rc = cli_check_recordable("check", scene, &a.ro.opt, a.ro.opt.threads, 1)) != 0) {
        ggSceneFree(scene);
        ggPathFree(path);
        return rc;
    }
    dbg_progress_begin(&ps, "check", a.quiet || a.format == 1);
    a.ro.opt.progress = dbg_progress, a.ro.opt.progress_ud = &ps;
    rc = ggCheck(scene, &a.ro.opt, &a.co, &r, &err);
    dbg_progress_end(&ps);
    if (rc != GG_OK) {
        rc = cli_fail(rc, &err, 1);
    } else {
        rc = EXIT_OK;
        if (a.format == 1)
            rc = json_out(&a, r);
        else
            print_text(&a, r);
        if (rc == EXIT_OK) rc = r->failed ? EXIT_CHECK : EXIT_OK;
    }
    ggCheckResultFree(r);
    ggSceneFree(scene);
    ggPathFree(path);
    return rc;
}
