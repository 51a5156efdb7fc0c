/* SPDX-License-Identifier: MIT */
/*
** cmd_find.c -- `ggrt find SCENE --where EXPR`: the pixels whose ray trees
** satisfy a predicate (ggFind), with the command that replays each and a
** mask image.
*/
#include "debug/debug.h"

#include <stdlib.h>
#include <string.h>

static const char about[] =
    "Find the pixels whose rays did something: every pixel is traced as ggrt render\n"
    "computes it and tested with a predicate over its ray trees, e.g.\n"
    "  some(kind == tir)                         total internal reflection\n"
    "  some(kind == refract && object == 2)      object 2 seen through a refraction\n"
    "  some(verdict == blocked && occluder == 1) shadows cast by object 1\n"
    "  some(stop == depth && weight > 0.01)      depth-limit cuts that matter\n"
    "The language (fields, some/all/count, && || !) is in docs/debugging.md.\n"
    "With --path, the pixels with a light path of that shape instead (OSL's\n"
    "light-path expressions, read from the eye), each with the share of its value\n"
    "those paths carry:\n"
    "  C<TS>+B             background seen only through refractions\n"
    "  C.*<RS'tir'>.*      light that took a total internal reflection\n"
    "  C<RD>L              direct diffuse light";

static const char tail[] = "exit: 0 ok (matches or not), 1 usage or a bad predicate, 2 bad scene,\n"
                           "3 I/O error";

static const char *const formats[] = {"text", "json", NULL};

typedef struct find_args {
    const char *scene, *where, *path, *out, *overlay, *paths_jsonl, *paths_obj;
    uint64_t paths_max; /* --paths-max */
    int limit, format, quiet;
    cli_render ro;
    dbg_tile tile;
} find_args;

static int parse(find_args *a, int argc, char **argv)
{
    cli_opt mine[] = {
        CLI_OPT_STRING('w', "where", &a->where, "EXPR", "the predicate (this or --path)"),
        CLI_OPT_STRING(0, "path", &a->path, "LPE",
                       "a light-path expression instead of a predicate: the\n"
                       "pixels with a path it matches, and the share of the\n"
                       "pixel those paths carry (docs/debugging.md)"),
        CLI_OPT_STRING('o', "output", &a->out, "FILE",
                       "write the mask, .png or .exr: white where a pixel\n"
                       "matched, black elsewhere"),
        CLI_OPT_STRING(0, "overlay", &a->overlay, "FILE",
                       "write the render with the matches in full colour and\n"
                       "the other pixels dimmed to grey, .png or .exr"),
        CLI_OPT_INT(0, "limit", &a->limit, 0, 1 << 30, "N",
                    "list the first N matches in row order (default 20;\n"
                    "0 lists them all)"),
        CLI_OPT_CHOICE('f', "format", &a->format, formats, "F", "text (default) or json"),
        CLI_OPT_STRING(0, "paths-jsonl", &a->paths_jsonl, "FILE",
                       "--path: write every matched pixel's matching paths\n"
                       "as JSON lines, one path a line: pixel, events,\n"
                       "points, weights, contribution"),
        CLI_OPT_STRING(0, "paths-obj", &a->paths_obj, "FILE",
                       "--path: write them as OBJ polylines, one per path"),
        CLI_OPT_FUNC(0, "paths-max", dbg_paths_max_parse, &a->paths_max, "SIZE",
                     DBG_PATHS_MAX_HELP),
        CLI_OPT_FLAG('q', "quiet", &a->quiet, "no progress bar"),
        DBG_TILE_OPTS(&a->tile),
        CLI_OPT_END,
    };
    cli_cmd cmd = {.name = "find",
                   .usage = "SCENE (--where EXPR | --path LPE) [options]",
                   .about = about,
                   .tail = tail,
                   .opts = {mine, a->ro.table},
                   .args = &a->scene,
                   .min_args = 1,
                   .max_args = 1,
                   .args_name = "scene"};
    int rc;
    a->limit = 20;
    a->paths_max = DBG_PATHS_MAX;
    cli_render_init(&a->ro, CLI_RENDER_ALL);
    if ((rc = cli_parse(&cmd, argc, argv)) != CLI_GO) return rc;
    cli_render_finish(&a->ro);
    if (a->where && a->path)
        return cli_usage_error(&cmd, "--where and --path each choose the pixels: give one");
    if (!a->where && !a->path) return cli_usage_error(&cmd, "need --where EXPR or --path LPE");
    if ((a->paths_jsonl || a->paths_obj) && !a->path)
        return cli_usage_error(&cmd, "--paths-jsonl and --paths-obj write the paths of --path LPE");
    if ((rc = dbg_tile_check(&cmd, &a->tile, a->format,
                             a->out || a->overlay || a->paths_jsonl || a->paths_obj ||
                                 cli_given(&cmd, "crop"))) != CLI_GO)
        return rc;
    /* Known before the scan, which may take minutes. */
    if (a->out && (rc = cli_check_image_name(&cmd, "the output", a->out)) != CLI_GO) return rc;
    if (a->overlay && (rc = cli_check_image_name(&cmd, "--overlay", a->overlay)) != CLI_GO)
        return rc;
    if ((rc = cli_check_not_input(&cmd, "-o", a->out, &a->scene, 1)) != CLI_GO ||
        (rc = cli_check_not_input(&cmd, "--overlay", a->overlay, &a->scene, 1)) != CLI_GO ||
        (rc = cli_check_not_input(&cmd, "--paths-jsonl", a->paths_jsonl, &a->scene, 1)) != CLI_GO ||
        (rc = cli_check_not_input(&cmd, "--paths-obj", a->paths_obj, &a->scene, 1)) != CLI_GO)
        return rc;
    {
        const char *opts[] = {"-o", "--overlay", "--paths-jsonl", "--paths-obj"};
        const char *paths[4];
        paths[0] = a->out, paths[1] = a->overlay, paths[2] = a->paths_jsonl;
        paths[3] = a->paths_obj;
        if ((rc = cli_check_distinct(&cmd, opts, paths, 4)) != CLI_GO) return rc;
    }
    if ((rc = dbg_paths_check("find", a->paths_jsonl, a->paths_obj)) != 0) return rc;
    if (a->out && (rc = cli_check_output("find", a->out)) != 0) return rc;
    if (a->overlay && (rc = cli_check_output("find", a->overlay)) != 0) return rc;
    return CLI_GO;
}

static void print_text(const find_args *a, const ggFindResult *r)
{
    int i, bx0 = r->width, by0 = r->height, bx1 = -1, by1 = -1, x, y;
    for (y = r->y0; y < r->y1; y++)
        for (x = r->x0; x < r->x1; x++)
            if (r->mask[(size_t)y * r->width + x]) {
                if (x < bx0) bx0 = x;
                if (x > bx1) bx1 = x;
                if (y < by0) by0 = y;
                if (y > by1) by1 = y;
            }
    printf("%s: %ld of %ld pixels match %s%s (%.2f%%)", a->scene, r->matched, r->scanned,
           a->path ? "--path " : "", a->path ? a->path : a->where,
           r->scanned ? 100.0 * (double)r->matched / (double)r->scanned : 0.0);
    if (r->matched) printf(", within x %d..%d, y %d..%d", bx0, bx1, by0, by1);
    printf("\n");
    if (r->nmatches)
        printf("%s %d in row order, each with the command that replays it:\n",
               r->nmatches == r->matched ? "all" : "the first", r->nmatches);
    for (i = 0; i < r->nmatches; i++) {
        const ggFindMatch *m = &r->matches[i];
        const char *extra[3] = {"--path", a->path, NULL};
        char cb[CLI_COLOR_LEN];
        printf("  %4d,%-4d %s   ", m->x, m->y, cli_color(cb, sizeof cb, 6, m->pixel));
        if (a->path) printf("share %6.2f%%   ", 100 * m->share);
        dbg_replay(stdout, a->scene, NULL, &a->ro, m->x, m->y, a->path ? extra : NULL);
        printf("\n");
    }
    if (r->matched > r->nmatches)
        printf("(%ld more: --limit 0 lists them all)\n", r->matched - r->nmatches);
}

/* The render with the matches in colour and the rest dimmed to grey. */
static int write_overlay(const char *path, const ggFindResult *r)
{
    ggImage *img = ggImageCreate(r->width, r->height, NULL);
    ggError err;
    int x, y, rc;
    if (!img) {
        cli_error("out of memory for the overlay");
        return EXIT_INPUT;
    }
    for (y = 0; y < r->height; y++)
        for (x = 0; x < r->width; x++) {
            ggColor c = ggImageGet(r->image, x, y);
            if (!r->mask[(size_t)y * r->width + x]) {
                double g = 0.25 * (0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b);
                c.r = c.g = c.b = g;
            }
            ggImageSet(img, x, y, c);
        }
    cli_cancel_hold();
    rc = ggImageWrite(img, path, &err);
    cli_cancel_release();
    ggImageFree(img);
    return rc == GG_OK ? EXIT_OK : cli_fail(rc, &err, 0);
}

/* --paths-jsonl, --paths-obj: each matched pixel traced again (its trees
   are not kept by the find), in row order, with a
   bar (this pass can take longer than the scan) and cancelled by the
   signals the scan is (nothing written). */
static int write_paths(const find_args *a, ggScene *scene, const ggPathExpr *e,
                       const ggFindResult *r)
{
    dbg_paths_out o;
    ggTrace *tr = ggTraceCreate(NULL);
    ggError err;
    ggColor px;
    cli_bar bar;
    long done = 0;
    int x, y, sig,
        rc = tr ? dbg_paths_open(&o, "find", a->paths_jsonl, a->paths_obj, a->paths_max)
                : EXIT_INPUT;
    if (!tr) cli_error_in("find", "out of memory");
    if (rc != 0) {
        ggTraceFree(tr);
        return rc;
    }
    cli_bar_begin(&bar, "find: paths", a->quiet || a->format == 1);
    for (y = r->y0; rc == EXIT_OK && y < r->y1; y++)
        for (x = r->x0; rc == EXIT_OK && x < r->x1; x++) {
            if (!r->mask[(size_t)y * r->width + x]) continue;
            if (cli_bar_step(&bar, done++, r->matched)) {
                rc = -1;
                break;
            }
            if ((rc = ggTracePixel(scene, &a->ro.opt, x, y, -1, tr, &px, NULL, &err)) != GG_OK)
                rc = cli_fail(rc, &err, 0);
            else
                rc = dbg_paths_pixel(&o, e, tr, x, y, px);
        }
    cli_bar_end(&bar);
    ggTraceFree(tr);
    /* (a signal during the last pixel: nothing written either) */
    if (rc == EXIT_OK && cli_cancelled()) rc = -1;
    if (rc != EXIT_OK) {
        dbg_paths_abandon(&o);
        if ((sig = cli_cancelled()) != 0) {
            cli_error_in("find", "cancelled by signal %d; %s%s%s not written", sig,
                         a->paths_jsonl ? a->paths_jsonl : "",
                         a->paths_jsonl && a->paths_obj ? " and " : "",
                         a->paths_obj ? a->paths_obj : "");
            cli_cancel_exit(sig);
        }
        return rc;
    }
    cli_cancel_hold();
    if ((rc = dbg_paths_close(&o)) == EXIT_OK && a->format != 1)
        printf("wrote %ld paths to %s%s%s\n", o.paths, a->paths_jsonl ? a->paths_jsonl : "",
               a->paths_jsonl && a->paths_obj ? " and " : "", a->paths_obj ? a->paths_obj : "");
    if (rc == EXIT_OK) cli_cancel_after_write(a->paths_jsonl ? a->paths_jsonl : a->paths_obj);
    cli_cancel_release(); /* a signal that came meanwhile is handled now */
    if (rc == EXIT_OK && (sig = cli_cancelled()) != 0) cli_cancel_exit(sig);
    return rc;
}

static int run(find_args *a, ggScene *scene, const ggPredicate *pred, const ggPathExpr *path)
{
    static const float mask_colours[2][3] = {{0, 0, 0}, {1, 1, 1}};
    ggFindResult *r = NULL;
    dbg_progress_state ps;
    ggError err;
    int rc;
    if ((rc = dbg_tile_begin(&a->tile, scene, a->scene, &a->ro.opt)) != EXIT_OK) return rc;
    if ((rc = cli_check_recordable("find", scene, &a->ro.opt, a->ro.opt.threads, 1)) != 0)
        return rc;
    dbg_progress_begin(&ps, "find", a->quiet || a->format == 1);
    a->ro.opt.progress = dbg_progress, a->ro.opt.progress_ud = &ps;
    if (path)
        rc = ggFindPath(scene, &a->ro.opt, path, a->limit ? a->limit : 1 << 30, &r, &err);
    else
        rc = ggFind(scene, &a->ro.opt, pred, a->limit ? a->limit : 1 << 30, &r, &err);
    dbg_progress_end(&ps);
    if (rc != GG_OK) return cli_fail(rc, &err, 1);
    if (a->format == 1) {
        ggRenderOptions o;
        FILE *f = dbg_tile_open(&a->tile);
        char params[64];
        dbg_tile_options(&a->tile, &a->ro.opt, &o);
        if (f) json_find(f, a->scene, &o, a->where, a->path, r);
        snprintf(params, sizeof params, "limit=%d", a->limit);
        rc = dbg_tile_close(&a->tile, f, params);
    } else {
        print_text(a, r);
        rc = EXIT_OK;
    }
    if (a->out) {
        rc = dbg_write_map("find", a->out, r->mask, r->width, r->height, mask_colours, 2);
        if (rc == EXIT_OK && a->format != 1)
            printf("wrote %s (white where a pixel matched)\n", a->out);
    }
    if (rc == EXIT_OK && (a->paths_jsonl || a->paths_obj)) rc = write_paths(a, scene, path, r);
    if (rc == EXIT_OK && a->overlay) {
        rc = write_overlay(a->overlay, r);
        if (rc == EXIT_OK && a->format != 1)
            printf("wrote %s (matches in colour, the rest grey)\n", a->overlay);
    }
    ggFindResultFree(r);
    return rc;
}

/* The --where predicate or the --path expression, compiled. */
static int compile(const find_args *a, ggPredicate **pred, ggPathExpr **path)
{
    ggError err;
    int rc;
    *pred = NULL, *path = NULL;
    if (a->path) {
        if ((rc = ggPathParse(a->path, NULL, path, &err)) != GG_OK)
            return rc == GG_ERROR_NOMEM ? cli_fail(rc, &err, 0)
                                        : dbg_expr_error("find", "path", a->path, &err);
    } else if ((rc = ggPredicateParse(a->where, NULL, pred, &err)) != GG_OK) {
        return rc == GG_ERROR_NOMEM ? cli_fail(rc, &err, 0)
                                    : dbg_predicate_error("find", a->where, &err);
    }
    return EXIT_OK;
}

int cmd_find(int argc, char **argv)
{
    find_args a;
    ggScene *scene;
    ggPredicate *pred;
    ggPathExpr *path;
    int rc;
    memset(&a, 0, sizeof a);
    if ((rc = parse(&a, argc, argv)) != CLI_GO) return rc;
    if ((rc = compile(&a, &pred, &path)) != EXIT_OK) return rc;
    if (!(scene = cli_load_scene(a.scene, NULL, NULL, a.quiet, &rc))) {
        ggPredicateFree(pred), ggPathFree(path);
        return rc;
    }
    {
        const char *opts[] = {"-o", "--overlay", "--paths-jsonl", "--paths-obj"};
        const char *outs[4];
        outs[0] = a.out, outs[1] = a.overlay, outs[2] = a.paths_jsonl, outs[3] = a.paths_obj;
        rc = cli_check_not_read("find", scene, opts, outs, 4);
    }
    if (rc == 0) rc = run(&a, scene, pred, path);
    ggPredicateFree(pred), ggPathFree(path);
    ggSceneFree(scene);
    return rc;
}
