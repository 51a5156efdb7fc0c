/* SPDX-License-Identifier: MIT */
/*
** renderopts.c -- the render options every rendering command shares
** (args.h: cli_render), and their canonical command-line form for the
** replay commands ggrt prints.
*/
#include "common/args.h"
#include "common/cli.h"

#include <math.h>
#include <string.h>

/* ---- --accuracy KNOB=VALUE[,KNOB=VALUE...] ----
   The knobs in the one grammar of render options as text
   (ggRenderOptionsParse, include/ggrt/debug.h), limited to the accuracy
   knobs: the rest of a render's options have flags of their own here. */

int cli_parse_accuracy(void *ud, const char *v, char *why, size_t whylen)
{
    ggRenderOptions o, d;
    ggError err;
    const char *msg;
    ggRenderOptionsDefault(&o);
    o.accuracy = *(ggAccuracy *)ud;
    if (ggRenderOptionsParse(&o, v, &err) != GG_OK) {
        /* "1:9: refract must be ..." -> "refract must be ..." */
        msg = strstr(err.message, ": ");
        snprintf(why, whylen, "%s", msg ? msg + 2 : err.message);
        return -1;
    }
    ggRenderOptionsDefault(&d);
    d.accuracy = o.accuracy;
    if (memcmp(&o, &d, sizeof o) != 0) {
        snprintf(why, whylen,
                 "only the knobs offset, sphere, refract, fresnel, texture, wavelengths, cutoff, "
                 "implicit-tol, gradient, intersect, shadows, phong go here; the other "
                 "render options have their own flags");
        return -1;
    }
    *(ggAccuracy *)ud = o.accuracy; /* all or nothing */
    return 0;
}

void cli_print_accuracy(FILE *f, const ggAccuracy *a)
{
    ggRenderOptions o;
    char buf[600], *c;
    ggRenderOptionsDefault(&o);
    o.accuracy = *a;
    ggRenderOptionsFormat(&o, buf, sizeof buf);
    if (!buf[0]) return;
    for (c = buf; *c; c++)
        if (*c == ' ') *c = ',';
    fprintf(f, " --accuracy %s", buf);
}

/* ---- the group ---- */

void cli_render_init(cli_render *r, unsigned parts)
{
    int n = 0;
    memset(r, 0, sizeof *r);
    ggRenderOptionsDefault(&r->opt);
    r->parts = parts;
    r->table[n++] = (cli_opt)CLI_OPT_SECTION(
        "render options (shared by the commands that render: ggrt(1), RENDER OPTIONS)");
    if (parts & CLI_RENDER_SIZE)
        r->table[n++] =
            (cli_opt)CLI_OPT_SIZE('s', "size", r->size, 1, GG_IMAGE_MAX_DIM, "WxH",
                                  "image size (default: the scene's resolution); each\n"
                                  "side 1 to 65536, at most 16777216 pixels (4096x4096)");
    if (parts & CLI_RENDER_DEPTH)
        r->table[n++] = (cli_opt)CLI_OPT_INT('d', "depth", &r->depth, 1, 64, "N",
                                             "ray-tree depth counting the eye ray (default: the\n"
                                             "scene's, else 5)");
    if (parts & CLI_RENDER_DEPTH)
        r->table[n++] = (cli_opt)CLI_OPT_INT(0, "ray-budget", &r->budget, 1, GG_RAY_BUDGET_MAX, "N",
                                             "at most N reflected and refracted rays per eye ray\n"
                                             "(default 1024): bounds the time of deep glass");
    if (parts & CLI_RENDER_SAMPLES)
        r->table[n++] = (cli_opt)CLI_OPT_INT('n', "samples", &r->samples, 1, 4096, "N",
                                             "samples per pixel (default: the scene's, else 1)");
    if (parts & CLI_RENDER_THREADS)
        r->table[n++] = (cli_opt)CLI_OPT_INT('j', "threads", &r->threads, 1, 256, "N",
                                             "worker threads (default: all processors); the\n"
                                             "image does not depend on it");
    if (parts & CLI_RENDER_CROP)
        r->table[n++] = (cli_opt)CLI_OPT_BOX(0, "crop", r->crop, 0, GG_IMAGE_MAX_DIM, "X0,Y0,X1,Y1",
                                             "render only [X0,X1) x [Y0,Y1); other pixels black");
    if (parts & CLI_RENDER_RULES) {
        r->table[n++] = (cli_opt)CLI_OPT_FLAG(0, "spd", &r->spd,
                                              "SPD test rules: rays through pixel corners, depth "
                                              "5,\ntransmitters also spawn reflection rays");
        r->table[n++] = (cli_opt)CLI_OPT_FLAG(0, "spd-rules", &r->spd_rules,
                                              "transmitters also spawn reflection rays (the\n"
                                              "rule of --spd alone)");
        r->table[n++] =
            (cli_opt)CLI_OPT_FLAG(0, "corners", &r->corners, "rays through pixel corners only");
        r->table[n++] = (cli_opt)CLI_OPT_FLAG(0, "force-effects", &r->force,
                                              "simulate every effect even if the scene needs "
                                              "fewer\n(same image, slower: for measuring)");
    }
    if (parts & CLI_RENDER_ACCURACY)
        r->table[n++] = (cli_opt)CLI_OPT_MANY(
            'a', "accuracy", cli_parse_accuracy, &r->opt.accuracy, "KNOB=V,...",
            "numerical choices, accurate by default (see\n"
            "docs/accuracy.md): offset=scaled|fixed|EPS,\n"
            "sphere=stable|textbook, refract=accurate|exact|textbook,\n"
            "fresnel=scene|none|schlick|exact,\n"
            "texture=scene|bilinear|nearest, wavelengths=rgb|one,\n"
            "cutoff=W, implicit-tol=own|T, gradient=exact|H,\n"
            "intersect=double|float (triangles and spheres in\n"
            "single precision; wrong far from the origin),\n"
            "shadows=colored|opaque (opaque: anything blocks the\n"
            "light, glass too), phong=exact|fast (fast: a whole\n"
            "shine by repeated squaring, not pow)");
    r->table[n] = (cli_opt)CLI_OPT_END;
}

static const cli_opt *opt_named(const cli_render *r, const char *name)
{
    int i;
    for (i = 0; r->table[i].kind != CLI_END; i++)
        if (r->table[i].name && !strcmp(r->table[i].name, name)) return &r->table[i];
    return NULL;
}

static int given(const cli_render *r, const char *name)
{
    const cli_opt *o = opt_named(r, name);
    return o && o->given;
}

void cli_render_finish(cli_render *r)
{
    if (given(r, "size")) r->opt.width = r->size[0], r->opt.height = r->size[1];
    if (given(r, "depth")) r->opt.max_depth = r->depth;
    if (given(r, "ray-budget")) r->opt.ray_budget = r->budget;
    if (given(r, "samples")) r->opt.samples = r->samples;
    if (given(r, "threads")) r->opt.threads = r->threads;
    if (given(r, "crop")) {
        r->opt.crop_x0 = r->crop[0], r->opt.crop_y0 = r->crop[1];
        r->opt.crop_x1 = r->crop[2], r->opt.crop_y1 = r->crop[3];
    }
    if (r->corners) r->opt.pixel_corners = true;
    if (r->spd_rules) r->opt.spd_rules = true;
    if (r->force) r->opt.force_effects = GG_EFFECT_ALL;
    if (r->spd) {
        r->opt.spd_rules = r->opt.pixel_corners = true;
        if (!given(r, "depth")) r->opt.max_depth = 5;
    }
}

void cli_render_print(FILE *f, const cli_render *r, unsigned parts)
{
    const ggRenderOptions *o = &r->opt;
    parts &= r->parts;
    if ((parts & CLI_RENDER_SIZE) && given(r, "size")) fprintf(f, " -s %dx%d", o->width, o->height);
    if ((parts & CLI_RENDER_DEPTH) && given(r, "depth")) fprintf(f, " -d %d", o->max_depth);
    if ((parts & CLI_RENDER_DEPTH) && given(r, "ray-budget"))
        fprintf(f, " --ray-budget %d", o->ray_budget);
    if ((parts & CLI_RENDER_SAMPLES) && given(r, "samples")) fprintf(f, " -n %d", o->samples);
    if ((parts & CLI_RENDER_THREADS) && given(r, "threads")) fprintf(f, " -j %d", o->threads);
    if ((parts & CLI_RENDER_CROP) && given(r, "crop"))
        fprintf(f, " --crop %d,%d,%d,%d", o->crop_x0, o->crop_y0, o->crop_x1, o->crop_y1);
    if (parts & CLI_RENDER_RULES) {
        if (r->spd) {
            fprintf(f, " --spd");
        } else {
            if (r->spd_rules) fprintf(f, " --spd-rules");
            if (r->corners) fprintf(f, " --corners");
        }
        if (r->force) fprintf(f, " --force-effects");
    }
    if (parts & CLI_RENDER_ACCURACY) cli_print_accuracy(f, &o->accuracy);
}

/* Does the space-separated list `text` hold the word w (of length n)? */
static int has_word(const char *text, const char *w, size_t n)
{
    const char *p = text;
    while (*p) {
        size_t k = strcspn(p, " ");
        if (k == n && !strncmp(p, w, n)) return 1;
        p += k;
        p += strspn(p, " ");
    }
    return 0;
}

/* The words of a that b lacks, as "'w1 w2'" or "(none)", at out. */
static size_t words_only(const char *a, const char *b, char *out, size_t size)
{
    const char *p = a + strspn(a, " ");
    size_t at = 0, any = 0;
    while (*p) {
        size_t k = strcspn(p, " ");
        if (!has_word(b, p, k) && at < size)
            at += (size_t)snprintf(out + at, size - at, "%s%.*s", any++ ? " " : "'", (int)k, p);
        p += k;
        p += strspn(p, " ");
    }
    if (at < size) at += (size_t)snprintf(out + at, size - at, "%s", any ? "'" : "(none)");
    return at;
}

void cli_render_text_diff(const char *a, const char *b, char *buf, size_t size)
{
    size_t at;
    if (!size) return;
    at = words_only(a, b, buf, size);
    if (at < size) at += (size_t)snprintf(buf + at, size - at, ", not ");
    if (at < size) words_only(b, a, buf + at, size - at);
}
