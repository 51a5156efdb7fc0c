/* SPDX-License-Identifier: MIT */
/*
** cmd_trace.c -- `ggrt trace SCENE --pixel X,Y`: the full ray tree of one
** pixel, as an indented tree, JSON (docs/trace-json.md), SVG or OBJ.
*/
#include "cli.h"
#include "trace_out.h"

#include <locale.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char about[] =
    "Print every ray that made one pixel: eye, reflection, refraction, total internal\n"
    "reflection and shadow rays, what each hit (object, scene-file line, point,\n"
    "normals), the material terms, Fresnel weights, absorption, why a branch stopped,\n"
    "and the colour each ray returns with its weight in its parent.";

static const char tail[] =
    "The printed colour equals, bit for bit, what ggrt render writes for the pixel\n"
    "with the same render options.\n"
    "exit: 0 ok, 1 usage, 2 bad scene, 3 I/O error";

static const char *const formats[] = {"text", "json", NULL};

typedef struct trace_args {
    const char *scene, *svg, *obj;
    int pixel[2], sample, format, ascii;
    cli_render ro;
} trace_args;

static int parse(trace_args *a, int argc, char **argv)
{
    cli_opt mine[] = {
        CLI_OPT_XY('p', "pixel", a->pixel, 0, GG_IMAGE_MAX_DIM - 1, "X,Y",
                   "the pixel (0,0 is the top left); required"),
        CLI_OPT_INT(0, "sample", &a->sample, 0, 4095, "K",
                    "record only sample K of the pixel (default: all)"),
        CLI_OPT_CHOICE('f', "format", &a->format, formats, "F",
                       "text (default) or json (schema: docs/trace-json.md)"),
        CLI_OPT_FLAG(0, "ascii", &a->ascii, "plain ASCII tree even on a UTF-8 terminal"),
        CLI_OPT_STRING(0, "svg", &a->svg, "FILE",
                       "draw the tree over a top and a side view of the scene"),
        CLI_OPT_STRING(0, "obj", &a->obj, "FILE", "write the rays as OBJ line geometry"),
        CLI_OPT_END,
    };
    cli_cmd cmd = {.name = "trace",
                   .usage = "SCENE --pixel X,Y [options]",
                   .about = about,
                   .tail = tail,
                   .opts = {mine, a->ro.table},
                   .args = &a->scene,
                   .min_args = 1,
                   .max_args = 1,
                   .args_name = "scene"};
    int rc;
    a->sample = -1;
    cli_render_init(&a->ro, CLI_RENDER_PIXEL);
    if ((rc = cli_parse(&cmd, argc, argv)) != CLI_GO) return rc;
    cli_render_finish(&a->ro);
    if (!mine[0].given) return cli_usage_error(&cmd, "need --pixel X,Y");
    if (a->svg && (rc = cli_check_output("trace", a->svg)) != 0) return rc;
    if (a->obj && (rc = cli_check_output("trace", a->obj)) != 0) return rc;
    return CLI_GO;
}

static int write_files(const trace_args *a, const trace_view *view)
{
    cli_out o;
    int rc = EXIT_OK;
    if (a->svg && (rc = cli_out_open(&o, "trace", a->svg)) == 0) {
        trace_write_svg(o.f, view);
        rc = cli_out_close(&o, "trace");
    }
    if (rc == EXIT_OK && a->obj && (rc = cli_out_open(&o, "trace", a->obj)) == 0) {
        trace_write_obj(o.f, view);
        rc = cli_out_close(&o, "trace");
    }
    return rc;
}

int cmd_trace(int argc, char **argv)
{
    trace_args a;
    ggScene *scene;
    ggTrace *tr;
    ggRayStats st;
    ggColor px;
    ggError err;
    int rc;
    trace_view view;

    memset(&a, 0, sizeof a);
    if ((rc = parse(&a, argc, argv)) != CLI_GO) return rc;
    scene = ggSceneCreate(NULL);
    tr = ggTraceCreate(NULL);
    if (!scene || !tr) {
        fprintf(stderr, "ggrt trace: out of memory\n");
        ggSceneFree(scene);
        ggTraceFree(tr);
        return EXIT_INPUT;
    }
    memset(&st, 0, sizeof st);
    rc = ggSceneLoadFile(scene, a.scene, &err);
    if (rc == GG_OK) rc = ggScenePrepare(scene, &err);
    if (rc != GG_OK) {
        rc = cli_fail(rc, &err, 0);
    } else if ((rc = ggTracePixel(scene, &a.ro.opt, a.pixel[0], a.pixel[1], a.sample, tr, &px, &st,
                                  &err)) != GG_OK) {
        rc = cli_fail(rc, &err, 1); /* a pixel or sample outside the image */
    } else {
        view.scene = scene, view.trace = tr, view.opt = &a.ro.opt, view.path = a.scene;
        view.x = a.pixel[0], view.y = a.pixel[1], view.sample = a.sample, view.pixel = px;
        view.stats = st;
        if (a.format == 1) {
            trace_print_json(stdout, &view);
        } else {
            const char *lc = setlocale(LC_CTYPE, "");
            int utf8 = !a.ascii && isatty(1) && lc &&
                       (strstr(lc, "UTF-8") || strstr(lc, "utf8") || strstr(lc, "UTF8"));
            trace_print_text(stdout, &view, utf8);
        }
        rc = write_files(&a, &view);
    }
    ggTraceFree(tr);
    ggSceneFree(scene);
    return rc;
}
