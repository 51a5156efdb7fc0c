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

static void help(FILE *f)
{
    fprintf(f,
            "usage: ggrt trace SCENE --pixel X,Y [options]\n"
            "\n"
            "Print every ray that made one pixel: eye, reflection, refraction, total internal\n"
            "reflection and shadow rays, what each hit (object, scene-file line, point,\n"
            "normals), the material terms, Fresnel weights, absorption, why a branch stopped,\n"
            "and the colour each ray returns with its weight in its parent.\n"
            "\n"
            "options:\n"
            "  -p, --pixel X,Y       the pixel (0,0 is the top left); required\n"
            "      --sample K        record only sample K of the pixel (default: all)\n"
            "  -f, --format F        text (default) or json (schema: docs/trace-json.md)\n"
            "      --ascii           plain ASCII tree even on a UTF-8 terminal\n"
            "      --svg FILE        draw the tree over a top and a side view of the scene\n"
            "      --obj FILE        write the rays as OBJ line geometry\n"
            "  -s, --size WxH, -d, --depth N, -n, --samples N, --spd, --corners,\n"
            "      --force-effects   as for ggrt render: the same options give the same pixel\n"
            "  -h, --help            this text\n"
            "\n"
            "The printed colour equals, bit for bit, what ggrt render writes for the pixel\n"
            "with the same options.\n"
            "exit: 0 ok, 1 usage, 2 bad scene, 3 I/O error\n");
}

int cmd_trace(int argc, char **argv)
{
    const char *scene_path = NULL, *svg = NULL, *obj = NULL, *format = "text";
    ggRenderOptions opt;
    ggScene *scene;
    ggTrace *tr;
    ggRayStats st;
    ggColor px;
    ggError err;
    int i, rc, x = -1, y = -1, sample = -1, ascii = 0;
    trace_view view;

    ggRenderOptionsDefault(&opt);
    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        int takes = 1;
        if (cli_is_help(a)) {
            help(stdout);
            return EXIT_OK;
        }
        if (!strcmp(a, "--ascii")) ascii = 1, takes = 0;
        else if (!strcmp(a, "--spd")) {
            opt.spd_rules = true, opt.pixel_corners = true, takes = 0;
            if (!opt.max_depth) opt.max_depth = 5;
        } else if (!strcmp(a, "--corners")) opt.pixel_corners = true, takes = 0;
        else if (!strcmp(a, "--force-effects")) opt.force_effects = GG_EFFECT_ALL, takes = 0;
        else if (a[0] != '-' || !a[1]) {
            if (scene_path) {
                fprintf(stderr, "ggrt trace: more than one scene given ('%s')\n", a);
                return EXIT_USAGE;
            }
            scene_path = a;
            continue;
        }
        if (!takes) continue;
        if (!v) {
            fprintf(stderr, "ggrt trace: %s needs a value (see ggrt trace --help)\n", a);
            return EXIT_USAGE;
        }
        i++;
        if (!strcmp(a, "-p") || !strcmp(a, "--pixel")) {
            if (sscanf(v, "%d,%d", &x, &y) != 2 || x < 0 || y < 0) goto bad;
        } else if (!strcmp(a, "--sample")) {
            if (cli_parse_int(v, 0, 4095, &sample)) goto bad;
        } else if (!strcmp(a, "-f") || !strcmp(a, "--format")) {
            if (strcmp(v, "text") && strcmp(v, "json")) goto bad;
            format = v;
        } else if (!strcmp(a, "--svg")) {
            svg = v;
        } else if (!strcmp(a, "--obj")) {
            obj = v;
        } else if (!strcmp(a, "-s") || !strcmp(a, "--size")) {
            if (sscanf(v, "%dx%d", &opt.width, &opt.height) != 2 || opt.width < 1 ||
                opt.height < 1)
                goto bad;
        } else if (!strcmp(a, "-d") || !strcmp(a, "--depth")) {
            if (cli_parse_int(v, 1, 64, &opt.max_depth)) goto bad;
        } else if (!strcmp(a, "-n") || !strcmp(a, "--samples")) {
            if (cli_parse_int(v, 1, 4096, &opt.samples)) goto bad;
        } else {
            fprintf(stderr, "ggrt trace: unknown option '%s' (see ggrt trace --help)\n", a);
            return EXIT_USAGE;
        }
        continue;
    bad:
        fprintf(stderr, "ggrt trace: bad value '%s' for %s\n", v, a);
        return EXIT_USAGE;
    }
    if (!scene_path || x < 0) {
        fprintf(stderr, "ggrt trace: need a scene and --pixel X,Y (see ggrt trace --help)\n");
        return EXIT_USAGE;
    }

    scene = ggSceneCreate(NULL);
    tr = ggTraceCreate(NULL);
    if (!scene || !tr) {
        fprintf(stderr, "ggrt trace: out of memory\n");
        ggSceneFree(scene);
        ggTraceFree(tr);
        return EXIT_INPUT;
    }
    memset(&st, 0, sizeof st);
    rc = ggSceneLoadFile(scene, scene_path, &err);
    if (rc == GG_OK) rc = ggTracePixel(scene, &opt, x, y, sample, tr, &px, &st, &err);
    if (rc != GG_OK) {
        fprintf(stderr, "ggrt: %s\n", err.message);
        ggTraceFree(tr);
        ggSceneFree(scene);
        return rc == GG_ERROR_INVALID ? EXIT_USAGE : cli_exit_code(rc);
    }
    view.scene = scene, view.trace = tr, view.opt = &opt, view.path = scene_path;
    view.x = x, view.y = y, view.sample = sample, view.pixel = px, view.stats = st;
    if (!strcmp(format, "json")) {
        trace_print_json(stdout, &view);
    } else {
        const char *lc = setlocale(LC_CTYPE, "");
        int utf8 = !ascii && isatty(1) && lc &&
                   (strstr(lc, "UTF-8") || strstr(lc, "utf8") || strstr(lc, "UTF8"));
        trace_print_text(stdout, &view, utf8);
    }
    rc = EXIT_OK;
    if (svg && trace_write_svg(svg, &view, &err) != GG_OK) {
        fprintf(stderr, "ggrt: %s\n", err.message);
        rc = EXIT_IO;
    }
    if (obj && trace_write_obj(obj, &view, &err) != GG_OK) {
        fprintf(stderr, "ggrt: %s\n", err.message);
        rc = EXIT_IO;
    }
    ggTraceFree(tr);
    ggSceneFree(scene);
    return rc;
}
