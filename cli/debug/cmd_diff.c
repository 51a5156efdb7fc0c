/* SPDX-License-Identifier: MIT */
/*
** cmd_diff.c -- `ggrt diff SCENE --a OPTIONS --b OPTIONS` or `ggrt diff
** SCENE_A SCENE_B`: two renders compared pixel by pixel and ray by ray
** (ggDiff), the first divergent ray of the worst pixels, a divergence map.
*/
#include "debug/debug.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define DIFF_LIMIT_ALL (1 << 30) /* --limit not given: every pixel that differs */

static const char about[] =
    "Render two settings of a scene (--a and --b: render options as text, e.g.\n"
    "--b 'sphere=textbook depth=8'; see docs/debugging.md), or two scenes, with every\n"
    "pixel's ray trees recorded, and compare: how many pixels differ in value and in\n"
    "ray tree, and for the worst the first ray where the trees part (which ray, and\n"
    "what: the object hit, a TIR decision, a shadow verdict, a child missing).\n"
    "The render options below apply to both sides; --a and --b add to them.\n"
    "With --path LPE, also the pixels whose light moved between path classes: the\n"
    "paths LPE matches differ between a and b (by their events and labels, as trace\n"
    "--path prints them; values alone do not count), listed in row order with both\n"
    "sides' shares and the first divergent ray (the decision that flipped).";

static const char tail[] = "exit: 0 ok (differences or not), 1 usage, 2 bad scene, 3 I/O error";

static const char *const formats[] = {"text", "json", NULL};

typedef struct diff_args {
    const char *scenes[2], *a_text, *b_text, *out, *path;
    int nscenes, worst, format, quiet, limit;
    ggRenderOptions oa, ob;
    cli_render ro;
    dbg_tile tile;
} diff_args;

static int side(const cli_cmd *cmd, const char *name, const char *text, const ggRenderOptions *base,
                ggRenderOptions *o)
{
    ggError err;
    *o = *base;
    if (ggRenderOptionsParse(o, text, &err) != GG_OK)
        return cli_usage_error(cmd, "--%s:%s", name, err.message);
    /* ggDiff compares one window, side a's: a crop of one side would be
       ignored (b's) or make b's render black around a's window (a's). */
    if (o->crop_x0 != base->crop_x0 || o->crop_y0 != base->crop_y0 || o->crop_x1 != base->crop_x1 ||
        o->crop_y1 != base->crop_y1)
        return cli_usage_error(cmd, "--%s: crop= is the window of both sides: give it as --crop",
                               name);
    return CLI_GO;
}

/* --a and --b: any text, the empty one too (the defaults). */
static int take_text(void *ud, const char *v, char *why, size_t whylen)
{
    (void)why, (void)whylen;
    *(const char **)ud = v;
    return 0;
}

static int parse(diff_args *a, int argc, char **argv)
{
    cli_opt mine[] = {
        CLI_OPT_FUNC(0, "a", take_text, &a->a_text, "OPTIONS",
                     "render options of side a (default '')"),
        CLI_OPT_FUNC(0, "b", take_text, &a->b_text, "OPTIONS",
                     "render options of side b (default '')"),
        CLI_OPT_STRING('o', "output", &a->out, "FILE",
                       "write the divergence map, .png or .exr: black where\n"
                       "the pixels agree, blue where only the value differs,\n"
                       "red where the ray tree differs"),
        CLI_OPT_INT(0, "worst", &a->worst, 0, 1000, "N",
                    "list the N pixels that differ most (default 10)"),
        CLI_OPT_STRING(0, "path", &a->path, "LPE",
                       "also the pixels whose paths LPE matches differ\n"
                       "between a and b (docs/debugging.md)"),
        CLI_OPT_INT(0, "limit", &a->limit, 0, DIFF_LIMIT_ALL, "N",
                    "--path: list at most N of those pixels (default all;\n"
                    "0 lists them all, as in ggrt find)"),
        CLI_OPT_CHOICE('f', "format", &a->format, formats, "F", "text (default) or json"),
        CLI_OPT_FLAG('q', "quiet", &a->quiet, "no progress bar"),
        DBG_TILE_OPTS(&a->tile),
        CLI_OPT_END,
    };
    cli_cmd cmd = {.name = "diff",
                   .usage = "SCENE [SCENE_B] [--a OPTIONS] [--b OPTIONS] [--path LPE]\n"
                            "                 [options]",
                   .about = about,
                   .tail = tail,
                   .opts = {mine, a->ro.table},
                   .args = a->scenes,
                   .min_args = 1,
                   .max_args = 2,
                   .nargs = &a->nscenes,
                   .args_name = "scene"};
    int rc;
    a->worst = 10, a->a_text = "", a->b_text = "", a->limit = DIFF_LIMIT_ALL;
    cli_render_init(&a->ro, CLI_RENDER_ALL);
    if ((rc = cli_parse(&cmd, argc, argv)) != CLI_GO) return rc;
    cli_render_finish(&a->ro);
    /* Without --path no list is cut by it: it would do nothing. */
    if (mine[5].given && !a->path) return cli_usage_error(&cmd, "--limit goes with --path");
    if (a->limit == 0) a->limit = DIFF_LIMIT_ALL; /* as find's --limit 0 */
    if ((rc = side(&cmd, "a", a->a_text, &a->ro.opt, &a->oa)) != CLI_GO) return rc;
    if ((rc = side(&cmd, "b", a->b_text, &a->ro.opt, &a->ob)) != CLI_GO) return rc;
    if ((rc = dbg_tile_check(&cmd, &a->tile, a->format, a->out || cli_given(&cmd, "crop"))) !=
        CLI_GO)
        return rc;
    /* Known before the scan, which may take minutes. */
    if (a->out && (rc = cli_check_image_name(&cmd, "the output", a->out)) != CLI_GO) return rc;
    if ((rc = cli_check_not_input(&cmd, "-o", a->out, a->scenes, a->nscenes)) != CLI_GO) return rc;
    if (a->out && (rc = cli_check_output("diff", a->out)) != 0) return rc;
    return CLI_GO;
}

/* One listed pixel: both values and the first divergence in words (the
   pixel is traced again on both sides to name the rays). */
static void print_pixel(const diff_args *a, ggScene *sa, ggScene *sb, const ggDiffPixel *p)
{
    const char *extra[8];
    char text[800], sa_text[CLI_COLOR_LEN], sb_text[CLI_COLOR_LEN];
    ggTrace *ta = ggTraceCreate(NULL), *tb = ggTraceCreate(NULL);
    ggColor ca, cb;
    int k = 0;
    printf("  %4d,%-4d a %s  b %s  |a-b| %.3g\n", p->x, p->y,
           cli_color(sa_text, sizeof sa_text, 6, p->a), cli_color(sb_text, sizeof sb_text, 6, p->b),
           p->delta);
    if (p->first.what != GG_DIFF_SAME && ta && tb &&
        ggTracePixel(sa, &a->oa, p->x, p->y, -1, ta, &ca, NULL, NULL) == GG_OK &&
        ggTracePixel(sb, &a->ob, p->x, p->y, -1, tb, &cb, NULL, NULL) == GG_OK) {
        dbg_divergence_text(text, sizeof text, ta, tb, &p->first);
        printf("      first divergence: %s\n", text);
    } else if (p->first.what == GG_DIFF_SAME) {
        printf("      same ray tree; only the values differ\n");
    }
    extra[k++] = "--diff";
    if (a->a_text[0]) extra[k++] = "--a", extra[k++] = a->a_text;
    if (a->b_text[0]) extra[k++] = "--b", extra[k++] = a->b_text;
    extra[k] = NULL;
    printf("      ");
    dbg_replay(stdout, a->scenes[0], a->nscenes > 1 ? a->scenes[1] : NULL, &a->ro, p->x, p->y,
               extra);
    printf("\n");
    ggTraceFree(ta);
    ggTraceFree(tb);
}

/* --path: the pixels whose light moved, with the decision that flipped. */
static void print_moves(const diff_args *a, ggScene *sa, ggScene *sb, const ggDiffResult *r)
{
    char text[800];
    int i;
    printf("  light moved (paths %s): %ld pixels", a->path, r->moved);
    if (r->nmoves < r->moved) printf(", the first %d in row order", r->nmoves);
    printf("\n");
    for (i = 0; i < r->nmoves; i++) {
        const ggDiffMove *m = &r->moves[i];
        ggTrace *ta = ggTraceCreate(NULL), *tb = ggTraceCreate(NULL);
        ggColor ca, cb;
        printf("  %4d,%-4d share a %6.2f%% (%ld paths)  b %6.2f%% (%ld paths)\n", m->x, m->y,
               100 * m->share_a, m->matched_a, 100 * m->share_b, m->matched_b);
        if (m->first.what == GG_DIFF_SAME) {
            printf("      same ray tree; only the values differ\n");
        } else if (ta && tb &&
                   ggTracePixel(sa, &a->oa, m->x, m->y, -1, ta, &ca, NULL, NULL) == GG_OK &&
                   ggTracePixel(sb, &a->ob, m->x, m->y, -1, tb, &cb, NULL, NULL) == GG_OK) {
            dbg_divergence_text(text, sizeof text, ta, tb, &m->first);
            printf("      first divergence: %s\n", text);
        }
        ggTraceFree(ta);
        ggTraceFree(tb);
    }
}

static void print_text(const diff_args *a, ggScene *sa, ggScene *sb, const ggDiffResult *r)
{
    double n = r->scanned > 0 ? (double)r->scanned : 1;
    int i, first = 1;
    if (a->nscenes > 1)
        printf("diff %s (a) and %s (b)", a->scenes[0], a->scenes[1]);
    else
        printf("diff %s: a '%s' and b '%s'", a->scenes[0], a->a_text, a->b_text);
    printf(", %dx%d, %ld pixels\n", r->width, r->height, r->scanned);
    printf("  values differ:    %8ld pixels (%.2f%%), largest |a - b| %.4g\n", r->value_differ,
           100 * r->value_differ / n, r->max_delta);
    printf("  ray trees differ: %8ld pixels (%.2f%%)", r->tree_differ, 100 * r->tree_differ / n);
    for (i = 1; i < GG_DIFF_COUNT; i++)
        if (r->first_by_kind[i]) {
            printf("%s%s %ld", first ? "; first divergence: " : ", ", ggDiffName(i),
                   r->first_by_kind[i]);
            first = 0;
        }
    printf("\n");
    if (a->path) print_moves(a, sa, sb, r);
    if (r->nworst) printf("the %d that differ most:\n", r->nworst);
    for (i = 0; i < r->nworst; i++) print_pixel(a, sa, sb, &r->worst[i]);
}

/* The JSON report; with --tile, its manifest: the params hold what else
   must agree (--worst, --limit, scene b's hash). */
static int json_out(const diff_args *a, const ggDiffResult *r)
{
    ggRenderOptions oa, ob;
    dbg_tile *t = (dbg_tile *)&a->tile;
    FILE *f = dbg_tile_open(t);
    char params[128], hash[32] = "";
    dbg_tile_options(t, &a->oa, &oa);
    dbg_tile_options(t, &a->ob, &ob);
    if (f) json_diff(f, a->scenes[0], a->scenes[a->nscenes > 1], &oa, &ob, r);
    if (t->tl.count && a->nscenes > 1 && tile_hash_file(a->scenes[1], hash, sizeof hash) != 0)
        snprintf(hash, sizeof hash, "unreadable");
    /* in the options' words ("limit=all": --limit not given), the
       second scene as "scene-b=HASH" */
    if (a->limit == DIFF_LIMIT_ALL)
        snprintf(params, sizeof params, "worst=%d limit=all%s%s", a->worst,
                 hash[0] ? " scene-b=" : "", hash);
    else
        snprintf(params, sizeof params, "worst=%d limit=%d%s%s", a->worst, a->limit,
                 hash[0] ? " scene-b=" : "", hash);
    return dbg_tile_close(t, f, params);
}

static int run(diff_args *a, ggScene *sa, ggScene *sb, const ggPathExpr *path)
{
    static const float map_colours[3][3] = {{0, 0, 0}, {0.1f, 0.3f, 1}, {1, 0.1f, 0.05f}};
    ggDiffResult *r = NULL;
    dbg_progress_state ps;
    ggError err;
    int rc;
    if ((rc = cli_check_same_size("diff", sa, &a->oa, sb, &a->ob)) != 0) return rc;
    if ((rc = dbg_tile_begin(&a->tile, sa, a->scenes[0], &a->oa)) != EXIT_OK) return rc;
    /* each thread holds both sides' trees of its pixel */
    if ((rc = cli_check_recordable("diff", sa, &a->oa, a->oa.threads, 2)) != 0 ||
        (rc = cli_check_recordable("diff", sb, &a->ob, a->oa.threads, 2)) != 0)
        return rc;
    if (a->tile.tl.count) {
        a->ob.crop_x0 = a->oa.crop_x0, a->ob.crop_x1 = a->oa.crop_x1;
        a->ob.crop_y0 = a->oa.crop_y0, a->ob.crop_y1 = a->oa.crop_y1;
    }
    dbg_progress_begin(&ps, "diff", a->quiet || a->format == 1);
    a->oa.progress = dbg_progress, a->oa.progress_ud = &ps;
    if (path)
        rc = ggDiffPath(sa, &a->oa, sb, &a->ob, path, a->worst, a->limit, &r, &err);
    else
        rc = ggDiff(sa, &a->oa, sb, &a->ob, a->worst, &r, &err);
    dbg_progress_end(&ps);
    a->oa.progress = NULL, a->oa.progress_ud = NULL;
    if (rc != GG_OK) return cli_fail(rc, &err, 1);
    if (a->format == 1)
        rc = json_out(a, r);
    else
        print_text(a, sa, sb, r), rc = EXIT_OK;
    if (rc == EXIT_OK && a->out) {
        rc = dbg_write_map("diff", a->out, r->map, r->width, r->height, map_colours, 3);
        if (rc == EXIT_OK && a->format != 1)
            printf("wrote %s (black: same; blue: the value differs; red: the ray tree differs)\n",
                   a->out);
    }
    ggDiffResultFree(r);
    return rc;
}

int cmd_diff(int argc, char **argv)
{
    diff_args a;
    ggScene *sa, *sb;
    ggPathExpr *path = NULL;
    ggError err;
    int rc;
    memset(&a, 0, sizeof a);
    if ((rc = parse(&a, argc, argv)) != CLI_GO) return rc;
    if (a.path && (rc = ggPathParse(a.path, NULL, &path, &err)) != GG_OK)
        return rc == GG_ERROR_NOMEM ? cli_fail(rc, &err, 0)
                                    : dbg_expr_error("diff", "path", a.path, &err);
    if (!(sa = cli_load_scene(a.scenes[0], NULL, NULL, a.quiet, &rc))) {
        ggPathFree(path);
        return rc;
    }
    sb = sa;
    if (a.nscenes > 1 && !(sb = cli_load_scene(a.scenes[1], NULL, NULL, a.quiet, &rc))) {
        ggSceneFree(sa);
        ggPathFree(path);
        return rc;
    }
    {
        const char *opt = "-o";
        if ((rc = cli_check_not_read("diff", sa, &opt, &a.out, 1)) == 0 &&
            (rc = cli_check_not_read("diff", sb, &opt, &a.out, 1)) == 0) {
            dbg_warn_same_sides(a.nscenes, &a.oa, &a.ob); /* once the command will run */
            rc = run(&a, sa, sb, path);
        }
    }
    if (sb != sa) ggSceneFree(sb);
    ggSceneFree(sa);
    ggPathFree(path);
    return rc;
}
