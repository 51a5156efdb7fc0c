/* SPDX-License-Identifier: MIT */
/*
** cmd_trace.c -- `ggrt trace SCENE --pixel X,Y`: the full ray tree of one
** pixel, as an indented tree, JSON (docs/trace-json.md), SVG or OBJ.
*/
#include "common/cli.h"
#include "debug/debug.h"
#include "trace/trace_view.h"

#include <locale.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char about[] =
    "Print every ray that made one pixel: eye, reflection, refraction, total\n"
    "internal reflection and shadow rays, what each hit (object, scene-file line,\n"
    "point, normals; for a mesh the triangle, its face, line, group and material in\n"
    "the file), the material terms, Fresnel split, absorption, why a branch stopped,\n"
    "and the colour each ray returns with its weight in the pixel, its share of the\n"
    "pixel and its factor in its parent. SCENE may be an OBJ or PLY model (framed as\n"
    "by ggrt render).";

static const char tail[] =
    "The printed colour equals, bit for bit, what ggrt render writes for the pixel\n"
    "with the same render options. -j is accepted and ignored (one pixel is traced\n"
    "on one thread); a --crop that leaves the pixel out is refused (render leaves\n"
    "it black).\n"
    "exit: 0 ok, 1 usage, 2 bad scene, 3 I/O error";

static const char *const formats[] = {"text", "json", NULL};

typedef struct trace_args {
    const char *scenes[2], *svg, *obj, *scene_obj, *a_text, *b_text, *lpe, *paths_jsonl, *paths_obj;
    uint64_t paths_max; /* --paths-max */
    int nscenes, pixel[2], sample, format, ascii, ledger, diff, no_numeric;
    ggRenderOptions oa, ob; /* --diff: the two sides */
    cli_render ro;
} trace_args;

/* --a and --b: any text, the empty one too. */
static int take_text(void *ud, const char *v, char *why, size_t whylen)
{
    (void)why, (void)whylen;
    *(const char **)ud = v;
    return 0;
}

/* The --diff sides: the render options plus --a, plus --b. */
static int diff_sides(trace_args *a, const cli_cmd *cmd)
{
    ggError err;
    a->oa = a->ob = a->ro.opt;
    if (ggRenderOptionsParse(&a->oa, a->a_text, &err) != GG_OK)
        return cli_usage_error(cmd, "--a:%s", err.message);
    if (ggRenderOptionsParse(&a->ob, a->b_text, &err) != GG_OK)
        return cli_usage_error(cmd, "--b:%s", err.message);
    return CLI_GO;
}

/* The render options every command takes, here where they do not decide
   the pixel: -j is said once to do nothing, and a crop must hold the
   pixel (outside it render writes black, which no trace explains). */
static int crop_and_threads(const trace_args *a, const cli_cmd *cmd)
{
    const ggRenderOptions *o = &a->ro.opt;
    int x = a->pixel[0], y = a->pixel[1];
    if (cli_given(cmd, "threads"))
        cli_warn("-j does not apply to a trace (one pixel, one thread); ignored");
    if (cli_given(cmd, "crop") &&
        (x < o->crop_x0 || x >= o->crop_x1 || y < o->crop_y0 || y >= o->crop_y1))
        return cli_usage_error(cmd,
                               "--pixel %d,%d is outside --crop %d,%d,%d,%d, where ggrt render "
                               "writes black",
                               x, y, o->crop_x0, o->crop_y0, o->crop_x1, o->crop_y1);
    return CLI_GO;
}

/* No output file may be a scene: writing it would destroy the input
   (trace --svg scene.nff). */
static int outputs_not_inputs(const trace_args *a, const cli_cmd *cmd)
{
    int rc;
    if ((rc = cli_check_not_input(cmd, "--svg", a->svg, a->scenes, a->nscenes)) != CLI_GO ||
        (rc = cli_check_not_input(cmd, "--obj", a->obj, a->scenes, a->nscenes)) != CLI_GO ||
        (rc = cli_check_not_input(cmd, "--scene-obj", a->scene_obj, a->scenes, a->nscenes)) !=
            CLI_GO ||
        (rc = cli_check_not_input(cmd, "--paths-jsonl", a->paths_jsonl, a->scenes, a->nscenes)) !=
            CLI_GO)
        return rc;
    return cli_check_not_input(cmd, "--paths-obj", a->paths_obj, a->scenes, a->nscenes);
}

static int parse(trace_args *a, int argc, char **argv)
{
    cli_opt mine[] = {
        CLI_OPT_XY('p', "pixel", a->pixel, 0, GG_IMAGE_MAX_DIM - 1, "X,Y",
                   "the pixel (0,0 is the top left); required"),
        CLI_OPT_INT(0, "sample", &a->sample, 0, 4095, "K",
                    "record only sample K of the pixel (default: all);\n"
                    "with --diff, on both sides"),
        CLI_OPT_CHOICE('f', "format", &a->format, formats, "F",
                       "text (default) or json (schema: docs/trace-json.md)"),
        CLI_OPT_FLAG(0, "ascii", &a->ascii, "plain ASCII tree even on a UTF-8 terminal"),
        CLI_OPT_FLAG(0, "no-numeric", &a->no_numeric,
                     "leave out each hit's numeric state (error bound, offset,\n"
                     "TIR margin, edge distance, traversal cost) from the\n"
                     "text tree"),
        CLI_OPT_STRING(0, "svg", &a->svg, "FILE",
                       "draw the tree over a top and a side view of the scene"),
        CLI_OPT_STRING(0, "obj", &a->obj, "FILE", "write the rays as OBJ line geometry"),
        CLI_OPT_FLAG(0, "ledger", &a->ledger,
                     "print the pixel's colour term by term instead of the\n"
                     "tree: every emission, ambient, diffuse, highlight and\n"
                     "background term, the rays that carried it, its share,\n"
                     "and that they add up to the pixel"),
        CLI_OPT_FLAG(0, "diff", &a->diff,
                     "trace the pixel twice and show both trees side by\n"
                     "side, the first divergent ray marked: with --a and\n"
                     "--b (render options as text, as for ggrt diff), or\n"
                     "with a second scene SCENE_B"),
        CLI_OPT_STRING(0, "path", &a->lpe, "LPE",
                       "print only the paths a light-path expression matches\n"
                       "(docs/debugging.md), each with its ledger term, and\n"
                       "their share of the pixel (text or json)"),
        CLI_OPT_FUNC(0, "a", take_text, &a->a_text, "OPTIONS",
                     "--diff: render options of side a (default '')"),
        CLI_OPT_FUNC(0, "b", take_text, &a->b_text, "OPTIONS",
                     "--diff: render options of side b (default '')"),
        CLI_OPT_STRING(0, "paths-jsonl", &a->paths_jsonl, "FILE",
                       "--path: write the matching paths as JSON lines, one\n"
                       "path a line: events, points, weights, contribution"),
        CLI_OPT_STRING(0, "paths-obj", &a->paths_obj, "FILE",
                       "--path: write the matching paths as OBJ polylines,\n"
                       "eye to light, one per path"),
        CLI_OPT_FUNC(0, "paths-max", dbg_paths_max_parse, &a->paths_max, "SIZE",
                     DBG_PATHS_MAX_HELP),
        CLI_OPT_STRING(0, "scene-obj", &a->scene_obj, "FILE",
                       "write the scene's objects as OBJ faces, to open\n"
                       "with --obj's rays or --paths-obj's paths; implicit\n"
                       "surfaces at most 500000 triangles in all, a rough\n"
                       "one written coarser or left out, with a warning"),
        CLI_OPT_END,
    };
    cli_cmd cmd = {.name = "trace",
                   .usage = "SCENE [SCENE_B] --pixel X,Y [options]",
                   .about = about,
                   .tail = tail,
                   .opts = {mine, a->ro.table},
                   .args = a->scenes,
                   .min_args = 1,
                   .max_args = 2,
                   .nargs = &a->nscenes,
                   .args_name = "scene"};
    int rc;
    a->sample = -1, a->a_text = a->b_text = "";
    a->paths_max = DBG_PATHS_MAX;
    cli_render_init(&a->ro, CLI_RENDER_ALL);
    if ((rc = cli_parse(&cmd, argc, argv)) != CLI_GO) return rc;
    cli_render_finish(&a->ro);
    if (!mine[0].given) return cli_usage_error(&cmd, "need --pixel X,Y");
    if ((rc = crop_and_threads(a, &cmd)) != CLI_GO) return rc;
    if (a->nscenes > 1 && !a->diff) return cli_usage_error(&cmd, "a second scene needs --diff");
    if ((mine[10].given || mine[11].given) && !a->diff)
        return cli_usage_error(&cmd, "--a and --b need --diff");
    if (a->ledger && a->sample >= 0)
        return cli_usage_error(&cmd, "--ledger explains the whole pixel: drop --sample");
    if (a->lpe && (a->sample >= 0 || a->ledger || a->diff))
        return cli_usage_error(&cmd, "--path looks at the whole pixel: no --sample, --ledger, --diff");
    if (a->diff && (a->svg || a->obj || a->scene_obj || a->ledger || a->format == 1))
        return cli_usage_error(&cmd,
                               "--diff prints text only (no --svg, --obj, --scene-obj, --ledger, "
                               "json)");
    if (a->diff && (rc = diff_sides(a, &cmd)) != CLI_GO) return rc;
    if ((a->paths_jsonl || a->paths_obj) && !a->lpe)
        return cli_usage_error(&cmd, "--paths-jsonl and --paths-obj write the paths of --path LPE");
    if ((rc = outputs_not_inputs(a, &cmd)) != CLI_GO) return rc;
    {
        const char *opts[] = {"--svg", "--obj", "--scene-obj", "--paths-jsonl", "--paths-obj"};
        const char *paths[5];
        paths[0] = a->svg, paths[1] = a->obj, paths[2] = a->scene_obj;
        paths[3] = a->paths_jsonl, paths[4] = a->paths_obj;
        if ((rc = cli_check_distinct(&cmd, opts, paths, 5)) != CLI_GO) return rc;
    }
    if ((rc = dbg_paths_check("trace", a->paths_jsonl, a->paths_obj)) != 0) return rc;
    if (a->svg && (rc = cli_check_output("trace", a->svg)) != 0) return rc;
    if (a->obj && (rc = cli_check_output("trace", a->obj)) != 0) return rc;
    if (a->scene_obj && (rc = cli_check_output("trace", a->scene_obj)) != 0) return rc;
    return CLI_GO;
}

/* The camera view of --svg, rendered first, with a bar (a deep scene's
   thumbnail can take seconds) and cancelled by a signal. */
static int camera_view(const trace_args *a, const trace_view *view, ggImage **img)
{
    ggError err;
    cli_bar bar;
    int rc, sig;
    cli_bar_begin(&bar, "trace: camera view", a->format == 1);
    rc = trace_camera_render(view, cli_bar_step, &bar, img, &err);
    cli_bar_end(&bar);
    if ((sig = cli_cancelled()) != 0) {
        ggImageFree(*img);
        cli_error_in("trace", "cancelled by signal %d; %s not written", sig, a->svg);
        cli_cancel_exit(sig);
    }
    return rc == GG_OK ? EXIT_OK : cli_fail(rc, &err, 0);
}

/* --svg into o: the views with the camera view img, embedded through a
   PNG beside it. EXIT_OK, or the error said and nothing left. */
static int write_svg(const trace_args *a, const trace_view *view, const ggImage *img, cli_out *o)
{
    ggError err;
    char png[sizeof o->tmp + 8];
    size_t n;
    int rc;
    if ((rc = cli_out_open(o, "trace", a->svg)) != 0) return rc;
    snprintf(png, sizeof png, "%s.png", o->tmp);
    if ((rc = trace_write_svg_views(o->f, view, 1, img, png, &err)) == GG_OK) return EXIT_OK;
    n = strlen(png);
    cli_out_abandon(o), unlink(png);
    /* (the message names the temporary file: name the output) */
    cli_error_in("trace", "%s: the camera view: %s", a->svg,
                 strncmp(err.message, png, n) == 0 && err.message[n] == ':' ? err.message + n + 2
                                                                            : err.message);
    return cli_exit_code(rc, 0);
}

/* "a.svg, r.obj and s.obj" */
static void name_files(char *buf, size_t size, const char *const *names, int n)
{
    size_t at = 0;
    int k;
    buf[0] = '\0';
    for (k = 0; k < n && at < size; k++)
        at += (size_t)snprintf(buf + at, size - at, "%s%s",
                               k == 0       ? ""
                               : k == n - 1 ? " and "
                                            : ", ",
                               names[k]);
}

/* --svg, --obj, --scene-obj: each written to a temporary file, the lot
   renamed over their names at the end with the signals held, so that
   each is written whole or not at all. A signal before that (--scene-obj
   of a large scene takes seconds: it stops within a surface) removes the
   temporary files, writes none and ends the process. */
static int write_files(const trace_args *a, const trace_view *view)
{
    cli_out o[3];
    const char *names[3];
    char all[3 * CLI_PATH_MAX];
    ggImage *img = NULL;
    int rc = EXIT_OK, sig, n = 0, k;
    if (!a->svg && !a->obj && !a->scene_obj) return EXIT_OK;
    cli_cancel_begin();
    if (a->svg && (rc = camera_view(a, view, &img)) != EXIT_OK) return rc;
    if (a->svg && (rc = write_svg(a, view, img, &o[n])) == EXIT_OK) names[n++] = a->svg;
    ggImageFree(img);
    if (rc == EXIT_OK && a->obj && !cli_cancelled() &&
        (rc = cli_out_open(&o[n], "trace", a->obj)) == EXIT_OK) {
        trace_write_obj(o[n].f, view);
        names[n++] = a->obj;
    }
    if (rc == EXIT_OK && a->scene_obj && !cli_cancelled() &&
        (rc = cli_out_open(&o[n], "trace", a->scene_obj)) == EXIT_OK) {
        trace_write_scene_obj(o[n].f, view->scene, view->path);
        names[n++] = a->scene_obj;
    }
    if (rc != EXIT_OK || (sig = cli_cancelled()) != 0) {
        for (k = 0; k < n; k++) cli_out_abandon(&o[k]);
        if ((sig = cli_cancelled()) != 0) {
            names[0] = a->svg, names[1] = a->obj, names[2] = a->scene_obj;
            for (k = n = 0; k < 3; k++)
                if (names[k]) names[n++] = names[k];
            name_files(all, sizeof all, names, n);
            cli_error_in("trace", "cancelled by signal %d; %s not written", sig, all);
            cli_cancel_exit(sig);
        }
        return rc;
    }
    name_files(all, sizeof all, names, n);
    cli_cancel_hold();
    for (k = 0; k < n; k++)
        if (rc == EXIT_OK)
            rc = cli_out_close(&o[k], "trace");
        else
            cli_out_abandon(&o[k]);
    if (rc == EXIT_OK) cli_cancel_after_write(all);
    cli_cancel_release();
    if ((sig = cli_cancelled()) != 0) cli_cancel_exit(sig);
    return rc;
}

/* Trace the pixel of `scene` with `opt` into tr and *v; the ledger too
   when every sample is recorded (*ledger, freed by the caller). */
static int trace_into(const trace_args *a, ggScene *scene, const ggRenderOptions *opt,
                      const char *path, ggTrace *tr, trace_view *v, ggLedger **ledger)
{
    ggError err;
    int rc;
    memset(v, 0, sizeof *v);
    *ledger = NULL;
    if ((rc = cli_check_recordable("trace", scene, opt, 1, 1)) != 0) return rc;
    rc = ggTracePixel(scene, opt, a->pixel[0], a->pixel[1], a->sample, tr, &v->pixel, &v->stats,
                      &err);
    if (rc != GG_OK) return cli_fail(rc, &err, 1); /* a pixel or sample outside the image */
    if (a->sample < 0 && (rc = ggLedgerCreate(tr, v->pixel, NULL, ledger, &err)) != GG_OK)
        return cli_fail(rc, &err, 0);
    v->scene = scene, v->trace = tr, v->opt = opt, v->path = path;
    v->x = a->pixel[0], v->y = a->pixel[1], v->sample = a->sample, v->ledger = *ledger;
    v->hide_numeric = a->no_numeric;
    return EXIT_OK;
}

/* --path: the ledger's terms whose paths match. */
static int print_paths(const trace_args *a, const ggPathExpr *e, const trace_view *v)
{
    unsigned char *matched = calloc(v->ledger->count ? v->ledger->count : 1, 1);
    ggPathSummary sum;
    int rc;
    if (!matched) {
        cli_error("out of memory");
        return EXIT_INPUT;
    }
    rc = ggPathMatch(e, v->trace, v->x, v->y, v->pixel, v->ledger, matched, &sum);
    if (rc == GG_OK && a->format == 1)
        trace_print_paths_json(stdout, v, a->lpe, matched, &sum);
    else if (rc == GG_OK)
        trace_print_paths(stdout, v, a->lpe, matched, &sum);
    free(matched);
    if (rc == GG_OK) return EXIT_OK;
    cli_error("out of memory");
    return EXIT_INPUT;
}

/* --paths-jsonl, --paths-obj */
static int write_paths(const trace_args *a, const ggPathExpr *e, const trace_view *v)
{
    dbg_paths_out o;
    int rc = dbg_paths_open(&o, "trace", a->paths_jsonl, a->paths_obj, a->paths_max);
    if (rc != 0) return rc;
    if ((rc = dbg_paths_pixel(&o, e, v->trace, v->x, v->y, v->pixel)) != EXIT_OK) {
        dbg_paths_abandon(&o);
        return rc;
    }
    return dbg_paths_close(&o);
}

static int run_one(trace_args *a, ggScene *scene, ggTrace *tr, const ggPathExpr *e)
{
    trace_view view;
    ggLedger *ledger;
    int rc = trace_into(a, scene, &a->ro.opt, a->scenes[0], tr, &view, &ledger);
    if (rc != EXIT_OK) return rc;
    if (e) {
        rc = print_paths(a, e, &view);
        if (rc == EXIT_OK) rc = write_files(a, &view);
        if (rc == EXIT_OK && (a->paths_jsonl || a->paths_obj)) rc = write_paths(a, e, &view);
        ggLedgerFree(ledger);
        return rc;
    }
    if (a->format == 1) {
        trace_print_json(stdout, &view);
    } else if (a->ledger) {
        char cb[CLI_COLOR_LEN];
        printf("pixel %d,%d of %s\ncolour %s\n\n", view.x, view.y, view.path,
               cli_color(cb, sizeof cb, 9, view.pixel));
        trace_print_ledger(stdout, &view, 40);
    } else {
        const char *lc = setlocale(LC_CTYPE, "");
        int utf8 = !a->ascii && isatty(1) && lc &&
                   (strstr(lc, "UTF-8") || strstr(lc, "utf8") || strstr(lc, "UTF8"));
        trace_print_text(stdout, &view, utf8);
    }
    rc = write_files(a, &view);
    ggLedgerFree(ledger);
    return rc;
}

static int run_diff(trace_args *a, ggScene *sa, ggTrace *ta)
{
    ggScene *sb = sa;
    ggTrace *tb = ggTraceCreate(NULL);
    trace_view va, vb;
    ggLedger *la = NULL, *lb = NULL;
    char na[1200], nb[1200];
    const char *pb = a->scenes[a->nscenes > 1];
    int rc = EXIT_OK;
    dbg_warn_same_sides(a->nscenes, &a->oa, &a->ob);
    if (!tb) {
        cli_error("out of memory");
        return EXIT_INPUT;
    }
    if (a->nscenes > 1 && !(sb = cli_load_scene(pb, NULL, NULL, a->format == 1, &rc))) {
        ggTraceFree(tb);
        return rc;
    }
    rc = cli_check_same_size("trace", sa, &a->oa, sb, &a->ob);
    if (rc == EXIT_OK) rc = trace_into(a, sa, &a->oa, a->scenes[0], ta, &va, &la);
    if (rc == EXIT_OK) rc = trace_into(a, sb, &a->ob, pb, tb, &vb, &lb);
    if (rc == EXIT_OK) {
        snprintf(na, sizeof na, "%s '%s'", a->scenes[0], a->a_text);
        snprintf(nb, sizeof nb, "%s '%s'", pb, a->b_text);
        trace_print_diff(stdout, &va, &vb, na, nb);
    }
    ggLedgerFree(la), ggLedgerFree(lb);
    ggTraceFree(tb);
    if (sb != sa) ggSceneFree(sb);
    return rc;
}

int cmd_trace(int argc, char **argv)
{
    trace_args a;
    ggScene *scene;
    ggTrace *tr;
    ggPathExpr *e = NULL;
    ggError err;
    int rc;
    memset(&a, 0, sizeof a);
    if ((rc = parse(&a, argc, argv)) != CLI_GO) return rc;
    if (a.lpe && (rc = ggPathParse(a.lpe, NULL, &e, &err)) != GG_OK)
        return rc == GG_ERROR_NOMEM ? cli_fail(rc, &err, 0)
                                    : dbg_expr_error("trace", "path", a.lpe, &err);
    if (!(scene = cli_load_scene(a.scenes[0], NULL, NULL, a.format == 1, &rc))) {
        ggPathFree(e);
        return rc;
    }
    {
        const char *opts[] = {"--svg", "--obj", "--scene-obj", "--paths-jsonl", "--paths-obj"};
        const char *outs[5];
        outs[0] = a.svg, outs[1] = a.obj, outs[2] = a.scene_obj;
        outs[3] = a.paths_jsonl, outs[4] = a.paths_obj;
        if ((rc = cli_check_not_read("trace", scene, opts, outs, 5)) != 0) {
            ggSceneFree(scene), ggPathFree(e);
            return rc;
        }
    }
    {
        /* as render says it, before any ray */
        ggRenderOptions r;
        if (ggRenderOptionsResolve(scene, &a.ro.opt, &r) == GG_OK &&
            (a.pixel[0] >= r.width || a.pixel[1] >= r.height)) {
            cli_error("--pixel %d,%d is outside the %dx%d image", a.pixel[0], a.pixel[1], r.width,
                      r.height);
            cli_usage_hint();
            ggSceneFree(scene), ggPathFree(e);
            return EXIT_USAGE;
        }
    }
    if (!(tr = ggTraceCreate(NULL))) {
        cli_error("out of memory");
        ggSceneFree(scene), ggPathFree(e);
        return EXIT_INPUT;
    }
    rc = a.diff ? run_diff(&a, scene, tr) : run_one(&a, scene, tr, e);
    ggTraceFree(tr);
    ggSceneFree(scene);
    ggPathFree(e);
    return rc;
}
