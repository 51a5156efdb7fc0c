/* SPDX-License-Identifier: MIT */
/*
** cmd_render.c -- `ggrt render SCENE -o out.png|out.exr`.
*/
#include "common/cli.h"
#include "common/heatmap.h"
#include "render/aov.h"
#include "render/tile.h"
#include "render/warn.h"

#include <stdlib.h>
#include <string.h>

static const char about[] =
    "Render an NFF scene (SPD NFF plus ggrt's extensions) to an 8-bit sRGB PNG or a\n"
    "float linear OpenEXR, chosen by the extension of OUT. SCENE may also be an OBJ\n"
    "or PLY model: it is framed by a default camera and two lights, printed (as NFF,\n"
    "to paste into a scene) on stderr. SIGINT or SIGTERM cancels the render: nothing\n"
    "is written and an existing OUT is left as it was; one that comes while OUT is\n"
    "being written lets it finish whole, says so, and then stops ggrt.";

static const char tail[] =
    "A scene with no objects, or with no lights and no emitting surface, renders with\n"
    "a warning on stderr (also under -q).\n"
    "exit: 0 ok, 1 usage, 2 bad scene, 3 I/O error";

static const char *const heat_kinds[] = {"rays", "depth", "time", NULL};

typedef struct render_args {
    const char *scene, *out, *plan;
    int quiet, no_srgb, heat, pixel[2], has_pixel;
    cli_render ro;
    tile_list tiles; /* --tile or --tiles; tiles.count 0 without */
    aov_list aov;    /* --aov and --aov-png */
} render_args;

/* Every tile's file, before any tile is rendered: a bad path found at the
   second tile would leave the first written and the set half done. */
static int check_tile_outputs(const cli_cmd *cmd, const render_args *a)
{
    const char *inputs[2];
    char path[CLI_PATH_MAX];
    int k, rc;
    inputs[0] = a->scene, inputs[1] = a->plan;
    for (k = 0; k < a->tiles.count; k++) {
        if (tile_path(a->out, a->tiles.idx[k], path, sizeof path) != 0)
            return cli_usage_error(cmd, "output path too long: '%s'", a->out);
        if ((rc = cli_check_not_input(cmd, "-o", path, inputs, 2)) != CLI_GO) return rc;
        if ((rc = cli_check_output("render", path)) != 0) return rc;
    }
    return CLI_GO;
}

/* What --tile and --tiles exclude. */
static int check_tiles(const cli_cmd *cmd, const render_args *a, const cli_opt *mine)
{
    if (mine[4].given + mine[5].given > 1)
        return cli_usage_error(cmd, "give one of --tile and --tiles, once");
    if (!a->tiles.n && !a->plan)
        return cli_usage_error(cmd, "--tile I and --tiles I,J need /N, the number of tiles, "
                                    "or --plan");
    if (cli_image_kind(a->out) != CLI_IMAGE_EXR)
        return cli_usage_error(cmd, "tiles are OpenEXR files: -o must end in .exr");
    if (a->heat >= 0 || a->has_pixel || a->no_srgb || cli_given(cmd, "crop"))
        return cli_usage_error(cmd, "--tile and --tiles take none of --heatmap, --pixel, "
                                    "--no-srgb and --crop");
    if (a->tiles.count > 1 && !strstr(a->out, "%d"))
        return cli_usage_error(cmd, "--tiles writes several files: -o needs a %%d (a plain "
                                    "one, for the tile's number)");
    if (strchr(a->out, '%') != strstr(a->out, "%d") ||
        (strstr(a->out, "%d") && strchr(strstr(a->out, "%d") + 1, '%')))
        return cli_usage_error(cmd, "-o may hold one %%d and no other %%");
    return check_tile_outputs(cmd, a);
}

static int parse(render_args *a, int argc, char **argv)
{
    cli_opt mine[] = {
        CLI_OPT_STRING('o', "output", &a->out, "FILE",
                       "image to write (required), .png or .exr; written\n"
                       "whole or not at all; a symbolic link, a directory or a\n"
                       "read-only file is refused"),
        CLI_OPT_XY(0, "pixel", a->pixel, 0, GG_IMAGE_MAX_DIM - 1, "X,Y",
                   "also print the value written at pixel X,Y (linear,\n"
                   "%.9g), and each --aov layer's"),
        CLI_OPT_FLAG(0, "no-srgb", &a->no_srgb,
                     "PNG only (-o must end in .png): store the values as\n"
                     "they are instead of sRGB-encoding them (as POV-Ray\n"
                     "3.7 and SPD-era renderers do)"),
        CLI_OPT_CHOICE(0, "heatmap", &a->heat, heat_kinds, "KIND",
                       "write a per-pixel cost map instead of the picture,\n"
                       "with a legend: rays (rays cast), depth (deepest\n"
                       "ray) or time"),
        CLI_OPT_FUNC(0, "tile", tile_parse_one, &a->tiles, "I/N",
                     "render only tile I (0 to N-1) of N bands of rows\n"
                     "into OUT.exr, its data window, with a manifest for\n"
                     "ggrt merge (docs/cluster.md)"),
        CLI_OPT_FUNC(0, "tiles", tile_parse_list, &a->tiles, "I,J,A-B/N",
                     "several tiles of N, loading the scene once; OUT\n"
                     "names each with %d replaced by the index\n"
                     "(-o part-%d.exr)"),
        CLI_OPT_MANY(0, "aov", aov_parse_one, &a->aov, "NAME=LPE",
                     "a path layer (repeatable, up to 16): the part of\n"
                     "each pixel that the light paths LPE matches carry\n"
                     "(docs/debugging.md, \"Path layers\"), written into\n"
                     "the .exr as channels NAME.R, NAME.G, NAME.B"),
        CLI_OPT_STRING(0, "aov-png", &a->aov.png_dir, "DIR",
                       "also write each --aov layer as DIR/NAME.png\n"
                       "(DIR is created if missing, its parent is not);\n"
                       "each file is checked as -o is, before rendering"),
        CLI_OPT_STRING(0, "plan", &a->plan, "FILE",
                       "with --tile or --tiles: the cut of a plan from ggrt\n"
                       "plan (bands of equal cost) instead of equal bands;\n"
                       "N may be left out (--tile I)"),
        CLI_OPT_FLAG('q', "quiet", &a->quiet, "no progress bar and no summary"),
        CLI_OPT_END,
    };
    cli_cmd cmd = {.name = "render",
                   .usage = "SCENE -o OUT.png|OUT.exr [options]",
                   .about = about,
                   .tail = tail,
                   .opts = {mine, a->ro.table},
                   .args = &a->scene,
                   .min_args = 1,
                   .max_args = 1,
                   .args_name = "scene"};
    int rc;
    a->heat = -1;
    cli_render_init(&a->ro, CLI_RENDER_ALL);
    if ((rc = cli_parse(&cmd, argc, argv)) != CLI_GO) return rc;
    cli_render_finish(&a->ro);
    a->has_pixel = mine[1].given;
    if (!a->out) return cli_usage_error(&cmd, "need -o OUT.png or -o OUT.exr");
    if (a->tiles.count && (a->aov.n || a->aov.png_dir))
        return cli_usage_error(&cmd, "--tile and --tiles take no --aov or --aov-png");
    /* (before the image-name check: a tile must be .exr, not .png either) */
    if (a->tiles.count) return check_tiles(&cmd, a, mine);
    if ((rc = cli_check_image_name(&cmd, "the output", a->out)) != CLI_GO) return rc;
    /* The flag undoes the PNG writer's encoding: on an EXR's linear floats
       it would clamp and distort the values (and break --aov sums). */
    if (a->no_srgb && cli_image_kind(a->out) != CLI_IMAGE_PNG)
        return cli_usage_error(&cmd, "--no-srgb is for a PNG: -o must end in .png");
    if (a->aov.png_dir && !a->aov.n) return cli_usage_error(&cmd, "--aov-png needs --aov");
    if (a->aov.n && a->heat >= 0) return cli_usage_error(&cmd, "--aov takes no --heatmap");
    if (a->aov.n && !a->aov.png_dir && cli_image_kind(a->out) != CLI_IMAGE_EXR)
        return cli_usage_error(&cmd, "--aov writes its layers into -o OUT.exr or, with "
                                     "--aov-png DIR, as PNGs");
    if (a->plan) return cli_usage_error(&cmd, "--plan goes with --tile or --tiles");
    return cli_check_not_input(&cmd, "-o", a->out, &a->scene, 1);
}

/* The heat map replaces the picture; --no-srgb pre-decodes what the PNG
   writer will encode. */
static int finish_image(const render_args *a, ggImage **img, const float *cost)
{
    static const char *const label[] = {"rays", "depth", "time s"};
    if (cost) {
        heatmap_range r;
        ggImage *map = heatmap_image(cost, ggImageWidth(*img), ggImageHeight(*img), label[a->heat],
                                     !strcmp(heat_kinds[a->heat], "time"), &r);
        if (!map) {
            cli_error("out of memory for the heat map");
            return EXIT_INPUT;
        }
        if (!a->quiet && r.above)
            printf("heat map: %s per pixel, 0 to %.4g (the 99.9th percentile; %zu pixel%s over it, "
                   "up to %.4g)\n",
                   label[a->heat], r.top, r.above, r.above == 1 ? "" : "s", r.max);
        else if (!a->quiet)
            printf("heat map: %s per pixel, 0 to %.4g\n", label[a->heat], r.top);
        if (!a->quiet && !r.legend)
            printf("heat map: no legend under it (its rows would take the image over the limit "
                   "of %lu pixels or %d rows)\n",
                   (unsigned long)GG_IMAGE_MAX_PIXELS, GG_IMAGE_MAX_DIM);
        ggImageFree(*img);
        *img = map;
    }
    if (a->no_srgb) {
        float *p = ggImagePixels(*img);
        size_t k, n = (size_t)ggImageWidth(*img) * ggImageHeight(*img) * 3;
        for (k = 0; k < n; k++) p[k] = (float)ggSRGBToLinear(p[k] > 1 ? 1 : p[k] > 0 ? p[k] : 0);
    }
    return EXIT_OK;
}

static void summary(const render_args *a, ggScene *scene, const ggImage *img, const ggRayStats *st,
                    const double *t)
{
    unsigned long long total =
        (unsigned long long)(st->eye + st->reflect + st->refract + st->shadow);
    printf("%s: %dx%d, %d objects, %d lights -> %s\n", a->scene, ggImageWidth(img),
           ggImageHeight(img), ggSceneObjectCount(scene), ggSceneLightCount(scene), a->out);
    /* The same words as ggrt trace's header: reflect counts the total
       internal reflections, shadow the blocked and attenuated ones (the
       verdicts of a trace), and total is the sum of the four kinds. */
    printf("rays: eye %llu (hit %llu), reflect %llu (tir %llu of them), refract %llu, "
           "shadow %llu (blocked %llu, attenuated %llu), total %llu\n",
           (unsigned long long)st->eye, (unsigned long long)st->eye_hit,
           (unsigned long long)st->reflect, (unsigned long long)st->tir,
           (unsigned long long)st->refract, (unsigned long long)st->shadow,
           (unsigned long long)st->shadow_blocked, (unsigned long long)st->shadow_attenuated,
           total);
    printf("time: parse %.3fs, prepare %.3fs, render %.3fs (%.2f Mrays/s), write %.3fs\n",
           t[1] - t[0], t[2] - t[1], t[3] - t[2], t[3] > t[2] ? total / (t[3] - t[2]) / 1e6 : 0.0,
           t[4] - t[3]);
}

/* Render, print what was asked, write. The image is written with the
   cancel signals held, so it lands whole or not at all. */
static int run(render_args *a, ggScene *scene, double *t)
{
    ggRenderOptions *opt = &a->ro.opt;
    ggImage *img = NULL;
    ggRayStats st;
    ggError err;
    cli_bar bar;
    ggCamera cam = ggSceneCamera(scene);
    int w = opt->width ? opt->width : cam.width, h = opt->height ? opt->height : cam.height;
    int rc, sig;
    float *cost = NULL;
    if (a->has_pixel && (a->pixel[0] >= w || a->pixel[1] >= h)) {
        cli_error("--pixel %d,%d is outside the %dx%d image", a->pixel[0], a->pixel[1], w, h);
        cli_usage_hint();
        return EXIT_USAGE;
    }
    /* Only for a size ggRender accepts: it refuses a larger one with the
       size-limit message before allocating anything of that size. */
    if (a->heat >= 0 && w > 0 && h > 0 && w <= GG_IMAGE_MAX_DIM && h <= GG_IMAGE_MAX_DIM &&
        (size_t)w * (size_t)h <= GG_IMAGE_MAX_PIXELS) {
        if (!(cost = calloc((size_t)w * (size_t)h, sizeof *cost))) {
            cli_error("out of memory for a %dx%d heat map", w, h);
            return EXIT_INPUT;
        }
        opt->cost_map = cost, opt->cost_kind = a->heat;
    }
    if (a->aov.n && (rc = aov_prepare(&a->aov, opt, w, h)) != EXIT_OK) {
        free(cost);
        return rc;
    }
    cli_bar_begin(&bar, "", a->quiet);
    bar.t0 = t[2];
    opt->progress = cli_bar_step, opt->progress_ud = &bar;
    cli_cancel_begin();
    rc = ggRender(scene, opt, &img, &st, &err);
    cli_bar_end(&bar);
    t[3] = cli_now();
    if ((sig = cli_cancelled()) != 0) {
        ggImageFree(img);
        free(cost);
        cli_error("cancelled by signal %d; %s not written", sig, a->out);
        cli_cancel_exit(sig);
    }
    if (rc != GG_OK) {
        free(cost);
        return cli_fail(rc, &err, 1);
    }
    if (a->has_pixel) {
        ggColor c = ggImageGet(img, a->pixel[0], a->pixel[1]);
        char cb[CLI_COLOR_LEN];
        printf("pixel %d,%d %s\n", a->pixel[0], a->pixel[1], cli_color(cb, sizeof cb, 9, c));
        aov_print_pixel(&a->aov, a->pixel[0], a->pixel[1]);
    }
    render_warn_pixels(img, 0, 0, a->scene, &a->ro, "");
    rc = finish_image(a, &img, cost);
    free(cost);
    if (rc == EXIT_OK) {
        cli_cancel_hold();
        rc = a->aov.n ? aov_write(&a->aov, img, a->out, a->scene, opt, &err)
                       : ggImageWrite(img, a->out, &err);
        if (rc == GG_OK) cli_cancel_after_write(a->out);
        t[4] = cli_now();     /* the layers and the image, as written */
        cli_cancel_release(); /* a signal that came meanwhile is handled now */
        rc = rc == GG_OK ? EXIT_OK : cli_fail(rc, &err, 0);
    }
    if (rc == EXIT_OK && (sig = cli_cancelled()) != 0) cli_cancel_exit(sig);
    if (rc == EXIT_OK && !a->quiet) summary(a, scene, img, &st, t);
    if (rc == EXIT_OK) render_warn_stats(&st, &a->ro, "");
    ggImageFree(img);
    return rc;
}

/* A scene without lights or objects renders without error, and a first
   user sees a dark or empty picture with no reason: say it once, also
   under -q (which silences progress, not warnings). A scene lit by its
   emitting surfaces alone (examples/scenes/prism.nff) means it. */
static void warn_empty(const ggScene *scene, const char *path)
{
    int i, glows = 0;
    for (i = 0; i < ggSceneMaterialCount(scene) && !glows; i++) {
        ggMaterial m = ggSceneMaterial(scene, i);
        glows = m.ke.r > 0 || m.ke.g > 0 || m.ke.b > 0;
    }
    if (ggSceneObjectCount(scene) == 0)
        cli_warn("%s has no objects: the image is its background", path);
    else if (ggSceneLightCount(scene) == 0 && !glows)
        cli_warn("%s has no lights: only ambient and emission light it", path);
}

/* Between loading and preparing (cli_load_scene): the end of parsing,
   then what a first user should know about the scene. */
typedef struct loaded_state {
    const render_args *a;
    double *t;
} loaded_state;

static void loaded(ggScene *scene, const char *path, void *ud)
{
    const loaded_state *ls = ud;
    ls->t[1] = cli_now();
    if (!ls->a->quiet) {
        if (cli_is_model(path)) cli_print_model_view(stderr, scene, path);
        cli_print_mesh_warnings(scene);
    }
    warn_empty(scene, path);
}

/* Once the scene is loaded: no output -- the image, each tile, each
   --aov-png file -- may be a file the scene reads (a mesh, a texture). */
static int outputs_not_read(const render_args *a, ggScene *scene)
{
    const char *opt = "-o", *p;
    char path[CLI_PATH_MAX];
    int k, rc;
    if (!a->tiles.count && (rc = cli_check_not_read("render", scene, &opt, &a->out, 1)) != 0)
        return rc;
    for (k = 0; k < a->tiles.count; k++) {
        if (tile_path(a->out, a->tiles.idx[k], path, sizeof path) != 0) continue; /* said */
        p = path;
        if ((rc = cli_check_not_read("render", scene, &opt, &p, 1)) != 0) return rc;
    }
    return aov_check_not_read(&a->aov, scene);
}

int cmd_render(int argc, char **argv)
{
    render_args a;
    loaded_state ls;
    ggScene *scene;
    double t[5];
    int rc;
    memset(&a, 0, sizeof a);
    if ((rc = parse(&a, argc, argv)) != CLI_GO) return rc;
    if (!a.tiles.count && (rc = cli_check_output("render", a.out)) != 0) return rc;
    if (a.aov.png_dir && (rc = aov_check_pngs(&a.aov, a.out, a.scene)) != 0) return rc;
    ls.a = &a, ls.t = t;
    t[0] = cli_now();
    if (!(scene = cli_load_scene(a.scene, loaded, &ls, a.quiet, &rc))) return rc;
    if ((rc = outputs_not_read(&a, scene)) != 0) {
        aov_free(&a.aov);
        ggSceneFree(scene);
        return rc;
    }
    t[2] = cli_now();
    if (a.tiles.count)
        rc = tile_render(scene, a.scene, &a.ro, &a.tiles, a.out, a.quiet, a.plan);
    else
        rc = run(&a, scene, t);
    aov_free(&a.aov);
    ggSceneFree(scene);
    return rc;
}
