/* SPDX-License-Identifier: MIT */
/*
** renderopts.c -- the render options every rendering command shares
** (args.h: cli_render), and their canonical command-line form for the
** replay commands ggrt prints.
*/
#include "args.h"
#include "cli.h"

#include <math.h>
#include <string.h>

/* ---- --accuracy KNOB=VALUE[,KNOB=VALUE...] ---- */

/* Words of the knobs that take one, in the order of their GG_ACC_* values. */
static const char *const w_offset[] = {"scaled", NULL};
static const char *const w_sphere[] = {"stable", "textbook", NULL};
static const char *const w_refract[] = {"accurate", "textbook", "exact", NULL};
static const char *const w_fresnel[] = {"scene", "none", "schlick", "exact", NULL};
static const char *const w_texture[] = {"scene", "bilinear", "nearest", NULL};
static const char *const w_waves[] = {"rgb", "one", NULL};
static const char *const w_own[] = {"own", NULL};
static const char *const w_exact[] = {"exact", NULL};

enum { K_OFFSET, K_SPHERE, K_REFRACT, K_FRESNEL, K_TEXTURE, K_WAVES, K_CUTOFF, K_TOL, K_GRAD };

static const struct knob {
    const char *name;
    const char *const *words; /* NULL: a number only */
    const char *number;       /* what a number means, or NULL: words only */
    double lo, hi;            /* allowed numbers; lo excluded when lo_open */
    int lo_open;
} knobs[] = {
    {"offset", w_offset, "a fixed epsilon > 0", 0, 1, 1},
    {"sphere", w_sphere, NULL, 0, 0, 0},
    {"refract", w_refract, NULL, 0, 0, 0},
    {"fresnel", w_fresnel, NULL, 0, 0, 0},
    {"texture", w_texture, NULL, 0, 0, 0},
    {"wavelengths", w_waves, NULL, 0, 0, 0},
    {"cutoff", NULL, "a weight from 0 (off) to 1", 0, 1, 0},
    {"implicit-tol", w_own, "a root tolerance > 0", 0, 1, 1},
    {"gradient", w_exact, "a difference step > 0", 0, 1, 1},
};
#define NKNOBS (int)(sizeof knobs / sizeof knobs[0])

static void set_knob(ggAccuracy *a, int k, int word, double num)
{
    switch (k) {
    case K_OFFSET:
        a->offset = word >= 0 ? GG_ACC_OFFSET_SCALED : GG_ACC_OFFSET_FIXED;
        a->offset_eps = word >= 0 ? 0 : num;
        break;
    case K_SPHERE:
        a->sphere = word;
        break;
    case K_REFRACT:
        a->refract = word;
        break;
    case K_FRESNEL:
        a->fresnel = word;
        break;
    case K_TEXTURE:
        a->texture = word;
        break;
    case K_WAVES:
        a->wavelengths = word;
        break;
    case K_CUTOFF:
        a->cutoff = num;
        break;
    case K_TOL:
        a->implicit_tol = word >= 0 ? 0 : num;
        break;
    default:
        a->gradient_h = word >= 0 ? 0 : num;
        break;
    }
}

/* "one of a, b, c" or "a number from 0 to 1" for the knob's message. */
static void knob_allowed(const struct knob *kb, char *buf, size_t len)
{
    size_t at = 0, i;
    if (kb->words) {
        at += (size_t)snprintf(buf, len, "%s", kb->words[1] ? "one of " : "");
        for (i = 0; kb->words[i] && at < len; i++)
            at += (size_t)snprintf(buf + at, len - at, "%s%s", i ? ", " : "", kb->words[i]);
    }
    if (kb->number && at < len) snprintf(buf + at, len - at, "%s%s", at ? " or " : "", kb->number);
}

/* One KNOB=VALUE (len bytes at s). */
static int one_knob(ggAccuracy *a, const char *s, size_t len, char *why, size_t whylen)
{
    char item[128], allowed[160], sub[96];
    const char *eq;
    int k, w;
    double num = 0;
    if (len >= sizeof item) {
        snprintf(why, whylen, "'%.40s...' is too long", s);
        return -1;
    }
    memcpy(item, s, len);
    item[len] = '\0';
    eq = strchr(item, '=');
    for (k = 0; eq && k < NKNOBS; k++)
        if (strlen(knobs[k].name) == (size_t)(eq - item) &&
            !strncmp(item, knobs[k].name, (size_t)(eq - item)))
            break;
    if (!eq || k == NKNOBS) {
        snprintf(why, whylen,
                 "'%s' is not KNOB=VALUE with a knob of offset, sphere, refract, "
                 "fresnel, texture, wavelengths, cutoff, implicit-tol, gradient",
                 item);
        return -1;
    }
    for (w = 0; knobs[k].words && knobs[k].words[w]; w++)
        if (!strcmp(eq + 1, knobs[k].words[w])) {
            set_knob(a, k, w, 0);
            return 0;
        }
    if (knobs[k].number &&
        cli_parse_num(eq + 1, knobs[k].lo, knobs[k].hi, &num, sub, sizeof sub) == 0 &&
        !(knobs[k].lo_open && num == knobs[k].lo)) {
        set_knob(a, k, -1, num);
        return 0;
    }
    knob_allowed(&knobs[k], allowed, sizeof allowed);
    snprintf(why, whylen, "%s wants %s, not '%s'", knobs[k].name, allowed, eq + 1);
    return -1;
}

static int parse_accuracy(void *ud, const char *v, char *why, size_t whylen)
{
    ggAccuracy a = *(ggAccuracy *)ud;
    const char *p = v;
    for (;;) {
        size_t len = strcspn(p, ",");
        if (one_knob(&a, p, len, why, whylen) != 0) return -1;
        if (!p[len]) break;
        p += len + 1;
    }
    *(ggAccuracy *)ud = a; /* all or nothing */
    return 0;
}

static void print_accuracy(FILE *f, const ggAccuracy *a)
{
    const char *sep = " --accuracy ";
    if (a->offset == GG_ACC_OFFSET_FIXED)
        fprintf(f, "%soffset=%.17g", sep, a->offset_eps > 0 ? a->offset_eps : 1e-6), sep = ",";
    if (a->sphere) fprintf(f, "%ssphere=%s", sep, w_sphere[a->sphere]), sep = ",";
    if (a->refract) fprintf(f, "%srefract=%s", sep, w_refract[a->refract]), sep = ",";
    if (a->fresnel) fprintf(f, "%sfresnel=%s", sep, w_fresnel[a->fresnel]), sep = ",";
    if (a->texture) fprintf(f, "%stexture=%s", sep, w_texture[a->texture]), sep = ",";
    if (a->wavelengths) fprintf(f, "%swavelengths=%s", sep, w_waves[a->wavelengths]), sep = ",";
    if (a->cutoff > 0) fprintf(f, "%scutoff=%.17g", sep, a->cutoff), sep = ",";
    if (a->implicit_tol > 0) fprintf(f, "%simplicit-tol=%.17g", sep, a->implicit_tol), sep = ",";
    if (a->gradient_h > 0) fprintf(f, "%sgradient=%.17g", sep, a->gradient_h);
}

/* ---- the group ---- */

void cli_render_init(cli_render *r, unsigned parts)
{
    int n = 0;
    memset(r, 0, sizeof *r);
    ggRenderOptionsDefault(&r->opt);
    r->parts = parts;
    r->table[n++] = (cli_opt)CLI_OPT_SECTION("render options (the same in every command)");
    if (parts & CLI_RENDER_SIZE)
        r->table[n++] = (cli_opt)CLI_OPT_SIZE('s', "size", r->size, 1, GG_IMAGE_MAX_DIM, "WxH",
                                              "image size (default: the scene's resolution)");
    if (parts & CLI_RENDER_DEPTH)
        r->table[n++] = (cli_opt)CLI_OPT_INT('d', "depth", &r->depth, 1, 64, "N",
                                             "ray-tree depth counting the eye ray (default: the\n"
                                             "scene's, else 5)");
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
        r->table[n++] =
            (cli_opt)CLI_OPT_FLAG(0, "corners", &r->corners, "rays through pixel corners only");
        r->table[n++] = (cli_opt)CLI_OPT_FLAG(0, "force-effects", &r->force,
                                              "simulate every effect even if the scene needs "
                                              "fewer\n(same image, slower: for measuring)");
    }
    if (parts & CLI_RENDER_ACCURACY)
        r->table[n++] =
            (cli_opt)CLI_OPT_FUNC('a', "accuracy", parse_accuracy, &r->opt.accuracy, "KNOB=V,...",
                                  "numerical choices, accurate by default (see\n"
                                  "docs/accuracy.md): offset=scaled|EPS,\n"
                                  "sphere=stable|textbook, refract=accurate|exact|textbook,\n"
                                  "fresnel=scene|none|schlick|exact,\n"
                                  "texture=scene|bilinear|nearest, wavelengths=rgb|one,\n"
                                  "cutoff=W, implicit-tol=own|T, gradient=exact|H");
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
    if (given(r, "samples")) r->opt.samples = r->samples;
    if (given(r, "threads")) r->opt.threads = r->threads;
    if (given(r, "crop")) {
        r->opt.crop_x0 = r->crop[0], r->opt.crop_y0 = r->crop[1];
        r->opt.crop_x1 = r->crop[2], r->opt.crop_y1 = r->crop[3];
    }
    if (r->corners) r->opt.pixel_corners = true;
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
    if ((parts & CLI_RENDER_SAMPLES) && given(r, "samples")) fprintf(f, " -n %d", o->samples);
    if ((parts & CLI_RENDER_THREADS) && given(r, "threads")) fprintf(f, " -j %d", o->threads);
    if ((parts & CLI_RENDER_CROP) && given(r, "crop"))
        fprintf(f, " --crop %d,%d,%d,%d", o->crop_x0, o->crop_y0, o->crop_x1, o->crop_y1);
    if (parts & CLI_RENDER_RULES) {
        if (r->spd)
            fprintf(f, " --spd");
        else if (r->corners)
            fprintf(f, " --corners");
        if (r->force) fprintf(f, " --force-effects");
    }
    if (parts & CLI_RENDER_ACCURACY) print_accuracy(f, &o->accuracy);
}
