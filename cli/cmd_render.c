/* SPDX-License-Identifier: MIT */
/*
** cmd_render.c -- `ggrt render SCENE -o out.png|out.exr`.
*/
#include "cli.h"
#include "heatmap.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static void help(FILE *f)
{
    fprintf(f,
            "usage: ggrt render SCENE -o OUT.png|OUT.exr [options]\n"
            "\n"
            "Render an NFF scene (SPD NFF plus ggrt's extensions) to an 8-bit sRGB PNG or a\n"
            "float linear OpenEXR, chosen by the extension of OUT.\n"
            "\n"
            "options:\n"
            "  -o, --output FILE     image to write (required); written atomically\n"
            "  -s, --size WxH        image size (default: the scene's resolution)\n"
            "  -d, --depth N         ray-tree depth counting the eye ray (default: scene, else 5)\n"
            "  -n, --samples N       samples per pixel (default: scene, else 1)\n"
            "  -j, --threads N       worker threads (default: all processors); the image\n"
            "                        does not depend on it\n"
            "      --crop X0,Y0,X1,Y1  render only [X0,X1) x [Y0,Y1); other pixels black\n"
            "      --spd             SPD test rules: rays through pixel corners, depth 5,\n"
            "                        transmitters also spawn reflection rays\n"
            "      --corners         rays through pixel corners only\n"
            "      --force-effects   simulate every effect even if the scene needs fewer\n"
            "                        (same image, slower: for measuring)\n"
            "      --pixel X,Y       also print the value written at pixel X,Y (%%.9g, linear)\n"
            "      --no-srgb         PNG: store the values as they are instead of sRGB-encoding\n"
            "                        them (as POV-Ray 3.7 and SPD-era renderers do)\n"
            "      --heatmap KIND    write a per-pixel cost map instead of the picture, with a\n"
            "                        legend: rays (rays cast), depth (deepest ray) or time\n"
            "  -q, --quiet           no progress bar and no summary\n"
            "  -h, --help            this text\n"
            "\n"
            "exit: 0 ok, 1 usage, 2 bad scene, 3 I/O error\n");
}

typedef struct progress_state {
    double t0;
    int last_pct;
} progress_state;

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int progress(void *ud, long done, long total)
{
    progress_state *p = ud;
    int pct = total > 0 ? (int)(100.0 * (double)done / (double)total) : 100, i;
    double el = now() - p->t0;
    if (pct == p->last_pct) return 0;
    p->last_pct = pct;
    fprintf(stderr, "\r[");
    for (i = 0; i < 40; i++) fputc(i < pct * 40 / 100 ? '#' : '.', stderr);
    fprintf(stderr, "] %3d%%  %.1fs", pct, el);
    if (pct > 0 && pct < 100) fprintf(stderr, "  ~%.0fs left ", el * (100 - pct) / pct);
    else fprintf(stderr, "             ");
    fflush(stderr);
    return 0;
}

/* NaN, infinite or negative pixels: count them and show how to replay the
   worst with ggrt trace (same options). */
static void report_bad_pixels(const ggImage *img, int argc, char **argv)
{
    int w = ggImageWidth(img), h = ggImageHeight(img), x, y, bx = -1, by = -1, i;
    long bad = 0;
    double worst = 0;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            ggColor c = ggImageGet(img, x, y);
            double m = c.r < c.g ? c.r : c.g;
            if (c.b < m) m = c.b;
            /* NaN and infinity rank worst, then the most negative. */
            if (!isfinite(c.r) || !isfinite(c.g) || !isfinite(c.b)) m = -INFINITY;
            if (m < 0) {
                bad++;
                if (bx < 0 || m < worst) worst = m, bx = x, by = y;
            }
        }
    if (!bad) return;
    fprintf(stderr, "ggrt render: %ld pixel%s NaN, infinite or negative; the worst is %d,%d. "
                    "Replay it with:\n  ggrt trace",
            bad, bad == 1 ? " is" : "s are", bx, by);
    for (i = 1; i < argc; i++) {
        /* Keep the scene and the render options, drop what trace lacks. */
        if (!strcmp(argv[i], "-o") || !strcmp(argv[i], "--output") || !strcmp(argv[i], "--pixel") ||
            !strcmp(argv[i], "--heatmap") || !strcmp(argv[i], "-j") || !strcmp(argv[i], "--threads") ||
            !strcmp(argv[i], "--crop")) {
            i++;
            continue;
        }
        if (!strcmp(argv[i], "-q") || !strcmp(argv[i], "--quiet") || !strcmp(argv[i], "--no-srgb"))
            continue;
        fprintf(stderr, " %s", argv[i]);
    }
    fprintf(stderr, " --pixel %d,%d\n", bx, by);
}

int cmd_render(int argc, char **argv)
{
    const char *scene_path = NULL, *out = NULL;
    ggRenderOptions opt;
    ggScene *scene;
    ggImage *img = NULL;
    ggRayStats st;
    ggError err;
    progress_state ps;
    int i, rc, quiet = 0, px = -1, py = -1, no_srgb = 0, heat = -1;
    float *cost = NULL;
    double t0, t1, t2, t3;
    unsigned long long total;

    ggRenderOptionsDefault(&opt);
    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
#define NEEDV()                                                                                  \
    do {                                                                                         \
        if (!v) {                                                                                \
            fprintf(stderr, "ggrt render: %s needs a value\n", a);                               \
            return EXIT_USAGE;                                                                   \
        }                                                                                        \
        i++;                                                                                     \
    } while (0)
        if (cli_is_help(a)) {
            help(stdout);
            return EXIT_OK;
        } else if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
            NEEDV();
            out = v;
        } else if (!strcmp(a, "-s") || !strcmp(a, "--size")) {
            char *x;
            NEEDV();
            x = strchr(v, 'x');
            if (!x) x = strchr(v, 'X');
            if (!x) goto bad;
            *x = '\0';
            if (cli_parse_int(v, 1, 65536, &opt.width) || cli_parse_int(x + 1, 1, 65536, &opt.height))
                goto bad;
        } else if (!strcmp(a, "-d") || !strcmp(a, "--depth")) {
            NEEDV();
            if (cli_parse_int(v, 1, 64, &opt.max_depth)) goto bad;
        } else if (!strcmp(a, "-n") || !strcmp(a, "--samples")) {
            NEEDV();
            if (cli_parse_int(v, 1, 4096, &opt.samples)) goto bad;
        } else if (!strcmp(a, "-j") || !strcmp(a, "--threads")) {
            NEEDV();
            if (cli_parse_int(v, 1, 256, &opt.threads)) goto bad;
        } else if (!strcmp(a, "--crop")) {
            NEEDV();
            if (sscanf(v, "%d,%d,%d,%d", &opt.crop_x0, &opt.crop_y0, &opt.crop_x1,
                       &opt.crop_y1) != 4)
                goto bad;
        } else if (!strcmp(a, "--pixel")) {
            NEEDV();
            if (sscanf(v, "%d,%d", &px, &py) != 2 || px < 0 || py < 0) goto bad;
        } else if (!strcmp(a, "--spd")) {
            opt.spd_rules = true, opt.pixel_corners = true;
            if (!opt.max_depth) opt.max_depth = 5;
        } else if (!strcmp(a, "--heatmap")) {
            NEEDV();
            if (!strcmp(v, "rays")) heat = GG_COST_RAYS;
            else if (!strcmp(v, "depth")) heat = GG_COST_DEPTH;
            else if (!strcmp(v, "time")) heat = GG_COST_TIME;
            else goto bad;
        } else if (!strcmp(a, "--no-srgb")) {
            no_srgb = 1;
        } else if (!strcmp(a, "--corners")) {
            opt.pixel_corners = true;
        } else if (!strcmp(a, "--force-effects")) {
            opt.force_effects = GG_EFFECT_ALL;
        } else if (!strcmp(a, "-q") || !strcmp(a, "--quiet")) {
            quiet = 1;
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "ggrt render: unknown option '%s' (see ggrt render --help)\n", a);
            return EXIT_USAGE;
        } else if (!scene_path) {
            scene_path = a;
        } else {
            fprintf(stderr, "ggrt render: more than one scene given ('%s')\n", a);
            return EXIT_USAGE;
        }
        continue;
    bad:
        fprintf(stderr, "ggrt render: bad value '%s' for %s\n", v, a);
        return EXIT_USAGE;
#undef NEEDV
    }
    if (!scene_path || !out) {
        fprintf(stderr, "ggrt render: need a scene and -o OUT (see ggrt render --help)\n");
        return EXIT_USAGE;
    }
    {
        size_t n = strlen(out);
        if (n < 4 || (strcmp(out + n - 4, ".png") && strcmp(out + n - 4, ".exr") &&
                      strcmp(out + n - 4, ".PNG") && strcmp(out + n - 4, ".EXR"))) {
            fprintf(stderr, "ggrt render: output must end in .png or .exr: '%s'\n", out);
            return EXIT_USAGE;
        }
    }

    scene = ggSceneCreate(NULL);
    if (!scene) {
        fprintf(stderr, "ggrt render: out of memory\n");
        return EXIT_INPUT;
    }
    t0 = now();
    rc = ggSceneLoadFile(scene, scene_path, &err);
    t1 = now();
    if (rc == GG_OK) rc = ggScenePrepare(scene, &err);
    t2 = now();
    if (rc == GG_OK) {
        ps.t0 = t2, ps.last_pct = -1;
        if (!quiet && isatty(2)) opt.progress = progress, opt.progress_ud = &ps;
        if (heat >= 0) {
            ggCamera cam = ggSceneCamera(scene);
            int w = opt.width ? opt.width : cam.width, h = opt.height ? opt.height : cam.height;
            cost = calloc((size_t)w * (size_t)h, sizeof *cost);
            if (!cost) {
                fprintf(stderr, "ggrt render: out of memory for the heat map\n");
                ggSceneFree(scene);
                return EXIT_INPUT;
            }
            opt.cost_map = cost, opt.cost_kind = heat;
        }
        rc = ggRender(scene, &opt, &img, &st, &err);
        if (opt.progress) fputc('\n', stderr);
    }
    t3 = now();
    if (rc == GG_OK && px >= 0 && (px >= ggImageWidth(img) || py >= ggImageHeight(img))) {
        fprintf(stderr, "ggrt render: pixel %d,%d is outside the image\n", px, py);
        ggImageFree(img);
        ggSceneFree(scene);
        return EXIT_USAGE;
    }
    if (rc == GG_OK && px >= 0) {
        ggColor c = ggImageGet(img, px, py);
        printf("pixel %d,%d %.9g %.9g %.9g\n", px, py, c.r, c.g, c.b);
    }
    if (rc == GG_OK) report_bad_pixels(img, argc, argv);
    if (rc == GG_OK && cost) {
        static const char *const names[] = {"rays", "depth", "time s"};
        double vmax = 0;
        ggImage *map = heatmap_image(cost, ggImageWidth(img), ggImageHeight(img), names[heat], &vmax);
        if (!map) {
            fprintf(stderr, "ggrt render: out of memory for the heat map\n");
            free(cost);
            ggImageFree(img);
            ggSceneFree(scene);
            return EXIT_INPUT;
        }
        if (!quiet) printf("heat map: %s per pixel, 0 to %.4g\n", names[heat], vmax);
        ggImageFree(img);
        img = map;
    }
    free(cost);
    cost = NULL;
    if (rc == GG_OK && no_srgb) {
        /* The PNG writer sRGB-encodes; pre-decoding cancels it. */
        float *p = ggImagePixels(img);
        size_t k, n = (size_t)ggImageWidth(img) * ggImageHeight(img) * 3;
        for (k = 0; k < n; k++)
            p[k] = (float)ggSRGBToLinear(p[k] > 1 ? 1 : p[k] > 0 ? p[k] : 0);
    }
    if (rc == GG_OK) rc = ggImageWrite(img, out, &err);
    if (rc != GG_OK) {
        fprintf(stderr, "ggrt: %s\n", err.message);
        ggImageFree(img);
        ggSceneFree(scene);
        return cli_exit_code(rc);
    }
    total = (unsigned long long)(st.eye + st.reflect + st.refract + st.shadow);
    if (!quiet) {
        printf("%s: %dx%d, %d objects, %d lights -> %s\n", scene_path, ggImageWidth(img),
               ggImageHeight(img), ggSceneObjectCount(scene), ggSceneLightCount(scene), out);
        printf("rays: eye %llu (hit %llu), reflect %llu, refract %llu, shadow %llu, tir %llu, "
               "total %llu\n",
               (unsigned long long)st.eye, (unsigned long long)st.eye_hit,
               (unsigned long long)st.reflect, (unsigned long long)st.refract,
               (unsigned long long)st.shadow, (unsigned long long)st.tir, total);
        printf("time: parse %.3fs, prepare %.3fs, render %.3fs (%.2f Mrays/s)\n", t1 - t0, t2 - t1,
               t3 - t2, t3 > t2 ? total / (t3 - t2) / 1e6 : 0.0);
        if (st.nonfinite)
            printf("warning: %llu samples were NaN or infinite\n",
                   (unsigned long long)st.nonfinite);
    }
    ggImageFree(img);
    ggSceneFree(scene);
    return EXIT_OK;
}
