/* SPDX-License-Identifier: MIT */
/*
** test_render.c -- the renderer: thread-count and crop invariance, forced
** effects give the same image, each compiled shading path agrees with the
** full one and with the recorder, ggRayColor equals the rendered pixel, the
** effect set and its reasons, the depth limit, SPD-rule ray counts, and
** the opaque-shadow knob.
*/
#include "testutil.h"

#include "scene.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A scene from NFF text, prepared. */
static ggScene *load_text(const char *txt, const char *name)
{
    ggScene *s = ggSceneCreate(NULL);
    assert_int_equal(ggSceneLoadString(s, txt, strlen(txt), name, NULL), GG_OK);
    assert_int_equal(ggScenePrepare(s, NULL), GG_OK);
    return s;
}

/* The ray straight down from (0, 0, z). */
static ggRay down_from(double z)
{
    ggRay r;
    r.o.x = 0, r.o.y = 0, r.o.z = z;
    r.d.x = 0, r.d.y = 0, r.d.z = -1;
    return r;
}

static ggImage *render(ggScene *s, const ggRenderOptions *o, ggRayStats *st)
{
    ggImage *img = NULL;
    ggError e;
    int rc = ggRender(s, o, &img, st, &e);
    if (rc != GG_OK) print_error("%s\n", e.message);
    assert_int_equal(rc, GG_OK);
    return img;
}

static int same_pixels(const ggImage *a, const ggImage *b)
{
    size_t n = (size_t)ggImageWidth(a) * ggImageHeight(a) * 3;
    return ggImageWidth(a) == ggImageWidth(b) && ggImageHeight(a) == ggImageHeight(b) &&
           memcmp(ggImagePixelsConst(a), ggImagePixelsConst(b), n * sizeof(float)) == 0;
}

static const char *const scenes[] = {
    "examples/scenes/default.nff", "examples/scenes/glass.nff", "examples/scenes/water.nff",
    "examples/scenes/gold.nff",    "examples/scenes/prism.nff", "examples/scenes/torus.nff",
};

/* One scene for each compiled shading path (lib/render/shade.c,
   trace_root): the basic one (shadows, mirrors, highlights), basic with
   glass (refraction and coloured shadows, no Fresnel), and the full one;
   with the effects that keep it from a smaller copy (has) and those that
   would send it to a larger one (lacks), so that a scene edit cannot
   quietly test another path. */
#define RARE_EFFECTS (GG_EFFECT_FRESNEL | GG_EFFECT_ABSORPTION | GG_EFFECT_DISPERSION)
static const struct {
    const char *path;
    unsigned has, lacks;
} path_scenes[] = {
    {"examples/scenes/spd/balls-s4.nff", 0,
     GG_EFFECT_REFRACTION | GG_EFFECT_COLORED_SHADOWS | RARE_EFFECTS},
    {"examples/scenes/spd/mount.nff", GG_EFFECT_REFRACTION | GG_EFFECT_COLORED_SHADOWS,
     RARE_EFFECTS},
    {"examples/scenes/glass.nff", GG_EFFECT_FRESNEL, 0},
};

/* 1, 2 and 7 threads give bit-identical images. */
static void test_threads_identical(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < 3; i++) {
        ggScene *s = tu_load(scenes[i]);
        ggRenderOptions o;
        ggImage *a, *b, *c;
        ggRayStats sa, sb, sc;
        ggRenderOptionsDefault(&o);
        o.width = 96, o.height = 72;
        o.threads = 1;
        a = render(s, &o, &sa);
        o.threads = 2;
        b = render(s, &o, &sb);
        o.threads = 7;
        c = render(s, &o, &sc);
        assert_true(same_pixels(a, b));
        assert_true(same_pixels(a, c));
        assert_true(sa.eye == sb.eye && sa.shadow == sc.shadow && sa.reflect == sc.reflect);
        ggImageFree(a), ggImageFree(b), ggImageFree(c);
        ggSceneFree(s);
    }
}

/* Crop windows the renderer refuses, each with GG_ERROR_INVALID and its
   reason: empty ones (all 0 is the whole image) and ones that leave the
   image; nothing is written to *img. */
/* ggRenderOptionsResolve on one scene file: what 0 leaves open comes out
   as the render takes it, and the resolved options render the same bits
   and rays as the open ones. */
static void check_resolve(const char *path, void *ud)
{
    ggScene *s = tu_load(path);
    ggCamera cam = ggSceneCamera(s);
    ggRenderOptions o, r;
    ggRayStats sa, sb;
    ggImage *a, *b;
    ggRenderOptionsDefault(&o);
    assert_int_equal(ggRenderOptionsResolve(s, &o, &r), GG_OK);
    assert_int_equal(r.width, cam.width);
    assert_int_equal(r.height, cam.height);
    assert_true(r.max_depth >= 1 && r.max_depth <= 64);
    assert_true(r.samples >= 1 && r.samples <= 4096);
    assert_int_equal(r.ray_budget, GG_RAY_BUDGET);
    o.width = 8, o.height = 6, o.threads = 1; /* (threads do not change an image) */
    assert_int_equal(ggRenderOptionsResolve(s, &o, &r), GG_OK);
    assert_int_equal(r.width, 8);
    a = render(s, &o, &sa);
    b = render(s, &r, &sb);
    if (!same_pixels(a, b) || memcmp(&sa, &sb, sizeof sa) != 0)
        fail_msg("%s: the resolved options render another image or other rays", path);
    /* resolving again changes nothing; in place is allowed */
    o = r;
    assert_int_equal(ggRenderOptionsResolve(s, &r, &r), GG_OK);
    assert_memory_equal(&o, &r, sizeof o);
    ggImageFree(a), ggImageFree(b);
    ggSceneFree(s);
    ++*(int *)ud;
}

static void test_options_resolve(void **state)
{
    ggScene *s = load_text("v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\n"
                           "resolution 32 24\ndepth 7\nsamples 4\nl 1 1 5\nf 1 1 1 1 0 0 0 0\n"
                           "s 0 0 0 1\n",
                           "resolve.nff");
    ggRenderOptions o, r;
    int n = 0;
    (void)state;
    ggRenderOptionsDefault(&o);
    assert_int_equal(ggRenderOptionsResolve(s, &o, &r), GG_OK);
    assert_int_equal(r.width, 32);
    assert_int_equal(r.height, 24);
    assert_int_equal(r.max_depth, 7);
    assert_int_equal(r.samples, 4);
    /* what is set is kept, negative values too (ggRender refuses them) */
    o.max_depth = 3, o.samples = -2, o.width = -1, o.ray_budget = 9;
    assert_int_equal(ggRenderOptionsResolve(s, &o, &r), GG_OK);
    assert_int_equal(r.max_depth, 3);
    assert_int_equal(r.samples, -2);
    assert_int_equal(r.width, -1);
    assert_int_equal(r.height, 24);
    assert_int_equal(r.ray_budget, 9);
    ggSceneFree(s);
    /* every scene file: the defaults (5, 1) where the file sets none */
    tu_each_file("examples/scenes", ".nff", check_resolve, &n);
    tu_each_file(tu_spd_dir(), ".nff", check_resolve, &n);
    tu_each_file("tests/data", ".nff", check_resolve, &n);
    assert_true(n >= 25);
}

/* ggRender refuses o: GG_ERROR_INVALID, no image, a message holding msg. */
static void refused(ggScene *s, const ggRenderOptions *o, const char *msg)
{
    ggImage *img = NULL;
    ggError err;
    assert_int_equal(ggRender(s, o, &img, NULL, &err), GG_ERROR_INVALID);
    assert_null(img);
    if (!strstr(err.message, msg)) fail_msg("'%s' does not hold '%s'", err.message, msg);
}

static void test_options_refused(void **state)
{
    static const struct {
        int crop[4], depth, samples, threads;
        const char *msg;
    } bad[] = {{{3, 3, 3, 5}, 0, 0, 1, "is empty"},
               {{3, 5, 9, 5}, 0, 0, 1, "is empty"},
               {{9, 3, 3, 5}, 0, 0, 1, "is empty"},
               {{0, 0, 0, 1}, 0, 0, 1, "is empty"},
               {{-1, 0, 4, 4}, 0, 0, 1, "is not inside the 80x60"},
               {{0, -1, 4, 4}, 0, 0, 1, "is not inside the 80x60"},
               {{70, 0, 81, 4}, 0, 0, 1, "is not inside the 80x60"},
               {{0, 50, 4, 61}, 0, 0, 1, "is not inside the 80x60"},
               {{0, 0, 0, 0}, -1, 0, 1, "max_depth must be 0 (the scene's) or 1..64, got -1"},
               {{0, 0, 0, 0}, 65, 0, 1, "max_depth must be 0 (the scene's) or 1..64, got 65"},
               {{0, 0, 0, 0}, 0, -2, 1, "samples must be 0 (the scene's) or 1..4096, got -2"},
               {{0, 0, 0, 0}, 0, 4097, 1, "samples must be 0 (the scene's) or 1..4096, got 4097"},
               {{0, 0, 0, 0}, 0, 0, -4, "threads must be 0 (one per processor) or more, got -4"}};
    ggScene *s = tu_load("examples/scenes/glass.nff");
    ggRenderOptions o;
    size_t i;
    (void)state;
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        ggRenderOptionsDefault(&o);
        o.width = 80, o.height = 60;
        o.crop_x0 = bad[i].crop[0], o.crop_y0 = bad[i].crop[1];
        o.crop_x1 = bad[i].crop[2], o.crop_y1 = bad[i].crop[3];
        o.max_depth = bad[i].depth, o.samples = bad[i].samples, o.threads = bad[i].threads;
        refused(s, &o, bad[i].msg);
    }
    ggSceneFree(s);
}

/* ggSceneSetMaterial on a scene already rendered: its next render is the
   render of the same file given that material before it was ever
   prepared (no state of the first preparation survives), for the first
   and the last material of every scene file (each render loads and
   prepares a file again: every material of the SPD files would take a
   minute), set to glass (which turns on refraction and coloured shadows
   where the scene had none). */
typedef struct set_counts {
    int files, materials, changed;
} set_counts;

static void check_set_material(const char *path, void *ud)
{
    set_counts *n = ud;
    ggScene *s = tu_load(path);
    ggRenderOptions o;
    ggRayStats st;
    ggError err;
    int i, j, count = ggSceneMaterialCount(s);
    ggRenderOptionsDefault(&o);
    o.width = 12, o.height = 9, o.threads = 1;
    n->files++;
    for (i = 0; i < count; i = i + 1 < count - 1 ? count - 1 : i + 1) {
        ggMaterial m = ggSceneMaterial(s, i);
        ggScene *fresh = ggSceneCreate(NULL);
        ggImage *before = render(s, &o, &st), *after, *ref;
        m.kd *= 0.5, m.kt = 0.6, m.ior = 1.33, m.ks = 0.2;
        assert_int_equal(ggSceneSetMaterial(s, i, &m), GG_OK);
        assert_int_equal(ggSceneLoadFile(fresh, path, &err), GG_OK);
        for (j = 0; j <= i; j++) { /* those set before it too */
            ggMaterial mj = ggSceneMaterial(s, j);
            assert_int_equal(ggSceneSetMaterial(fresh, j, &mj), GG_OK);
        }
        after = render(s, &o, &st);
        ref = render(fresh, &o, &st);
        if (!same_pixels(after, ref))
            fail_msg("%s: material %d set after a render renders another image than set before",
                     path, i);
        n->materials++;
        n->changed += !same_pixels(before, after);
        ggImageFree(before), ggImageFree(after), ggImageFree(ref);
        ggSceneFree(fresh);
    }
    /* refused: the scene unchanged */
    {
        ggMaterial bad = ggSceneMaterial(s, 0), keep = bad;
        bad.kd = -1;
        assert_int_equal(ggSceneSetMaterial(s, 0, &bad), GG_ERROR_INVALID);
        assert_int_equal(ggSceneSetMaterial(s, count, &keep), GG_ERROR_INVALID);
        assert_int_equal(ggSceneSetMaterial(s, -1, &keep), GG_ERROR_INVALID);
        assert_int_equal(ggSceneSetMaterial(s, 0, NULL), GG_ERROR_INVALID);
        bad = ggSceneMaterial(s, 0);
        assert_memory_equal(&bad, &keep, sizeof bad);
    }
    ggSceneFree(s);
}

static void test_set_material(void **state)
{
    set_counts n = {0, 0, 0};
    (void)state;
    tu_each_file("examples/scenes", ".nff", check_set_material, &n);
    tu_each_file(tu_spd_dir(), ".nff", check_set_material, &n);
    tu_each_file("tests/data", ".nff", check_set_material, &n);
    print_message("test_set_material: %d files, %d materials set, %d changed the image\n", n.files,
                  n.materials, n.changed);
    assert_true(n.files >= 25 && n.changed >= n.files / 2);
}

/* A light set into a surface (a lamp in a ceiling, a light on a sphere):
   the segment to it ends short of it by the rounding of a hit there, so
   the surface through the light blocks none of its shadow rays (it did
   on 935 of 19200 pixels of this room at t = 1 - 2^-53); the same as the
   light a hair below the surface. (The fixed-offset knob keeps the
   segment to the light, as the textbook epsilon it studies does.) */
static void test_light_on_surface(void **state)
{
    static const char room[] = "v\nfrom 0 -3 2\nat 0 0 0\nup 0 0 1\nangle 60\nhither 0.01\n"
                               "resolution 80 60\nb 0 0 0\nl 0.3 0.2 %s\nf 1 1 1 1 0 100000 0 0\n"
                               "p 4 -4 -4 0 4 -4 0 4 4 0 -4 4 0\n"
                               "p 4 -4 -4 4 -4 4 4 4 4 4 4 -4 4\n%s";
    static const char *const extra[] = {"", "s 1.5 1 3 1\n"}; /* a sphere touching the ceiling */
    static const char *const lz[][2] = {{"4", "3.9999999"}, {"4", "3.9999999"}};
    char ta[512], tb[512];
    int k, fixed = 0;
    (void)state;
    for (k = 0; k < 2; k++) {
        ggScene *a, *b;
        ggRenderOptions o;
        ggRayStats sa, sb;
        ggImage *ia, *ib;
        const float *pa, *pb;
        size_t i, n = 80 * 60 * 3, off = 0;
        snprintf(ta, sizeof ta, room, lz[k][0], extra[k]);
        snprintf(tb, sizeof tb, room, lz[k][1], extra[k]);
        a = load_text(ta, "on.nff"), b = load_text(tb, "below.nff");
        ggRenderOptionsDefault(&o);
        o.threads = 1;
        ia = render(a, &o, &sa), ib = render(b, &o, &sb);
        pa = ggImagePixelsConst(ia), pb = ggImagePixelsConst(ib);
        for (i = 0; i < n; i++) off += fabs(pa[i] - pb[i]) > 1e-3;
        if (off || sa.shadow_blocked != sb.shadow_blocked)
            fail_msg("scene %d, fixed %d: %lu channels off by > 1e-3, blocked %llu vs %llu", k,
                     fixed, (unsigned long)off, (unsigned long long)sa.shadow_blocked,
                     (unsigned long long)sb.shadow_blocked);
        ggImageFree(ia), ggImageFree(ib), ggSceneFree(a), ggSceneFree(b);
    }
}

/* A ray of weight 0 is not cast: a sphere of index 1 with exact Fresnel
   reflects nothing (F = 0), one of index 1e30 transmits nothing (1 - F
   rounds to 0); either would otherwise spawn rays that take from the
   budget and change nothing (or, once the budget ran out, cut rays that
   carried light). */
static void test_zero_weight_rays(void **state)
{
    static const char fmt[] =
        "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\n"
        "resolution 16 12\nl 1 1 5\nf 1 1 1 0 0 100000 1 %s\nfresnel exact\n"
        "s 0 0 0 1\nf 0.5 0.5 0.5 1 0 0 0 0\np 4 -3 -3 -2 3 -3 -2 3 3 -2 -3 3 -2\n";
    static const char *const ior[] = {"1", "1e30"};
    char text[512];
    int k;
    (void)state;
    for (k = 0; k < 2; k++) {
        ggScene *s;
        ggRenderOptions o;
        ggRayStats st;
        ggImage *img;
        ggRenderOptionsDefault(&o);
        o.threads = 1;
        snprintf(text, sizeof text, fmt, ior[k]);
        s = load_text(text, "zero.nff");
        img = render(s, &o, &st);
        /* index 1: refraction only; index 1e30: reflection only */
        assert_true(k ? st.reflect > 0 : st.refract > 0);
        assert_int_equal(k ? st.refract : st.reflect, 0);
        ggImageFree(img), ggSceneFree(s);
    }
}

/* The scene's setters refuse what a file may not say, the scene
   unchanged. (ggRender's own refusals: test_options_refused.) */
static void test_scene_setters(void **state)
{
    ggScene *s = tu_load("examples/scenes/glass.nff");
    ggRenderOptions o;
    (void)state;
    assert_int_equal(ggSceneSetDepth(s, 7), GG_OK);
    assert_int_equal(ggSceneSetDepth(s, -7), GG_ERROR_INVALID);
    assert_int_equal(ggSceneSetDepth(s, 65), GG_ERROR_INVALID);
    assert_int_equal(ggSceneSetSamples(s, 4), GG_OK);
    assert_int_equal(ggSceneSetSamples(s, 1 << 30), GG_ERROR_INVALID);
    assert_int_equal(ggSceneSetSamples(s, -1), GG_ERROR_INVALID);
    ggRenderOptionsDefault(&o);
    assert_int_equal(ggRenderOptionsResolve(s, &o, &o), GG_OK);
    assert_int_equal(o.max_depth, 7); /* the refused values changed nothing */
    assert_int_equal(o.samples, 4);
    assert_int_equal(ggSceneSetDepth(s, 0), GG_OK); /* back to the renderer's */
    ggRenderOptionsDefault(&o);
    assert_int_equal(ggRenderOptionsResolve(s, &o, &o), GG_OK);
    assert_int_equal(o.max_depth, 5);
    ggSceneFree(s);
}

/* A crop window reproduces exactly those pixels of the full render. */
static void test_crop_matches_full(void **state)
{
    ggScene *s = tu_load("examples/scenes/glass.nff");
    ggRenderOptions o;
    ggImage *full, *part;
    int x, y, k;
    (void)state;
    ggRenderOptionsDefault(&o);
    o.width = 80, o.height = 60, o.threads = 2;
    full = render(s, &o, NULL);
    o.crop_x0 = 13, o.crop_y0 = 7, o.crop_x1 = 51, o.crop_y1 = 44;
    part = render(s, &o, NULL);
    for (y = 0; y < 60; y++)
        for (x = 0; x < 80; x++) {
            ggColor a = ggImageGet(full, x, y), b = ggImageGet(part, x, y);
            int inside = x >= 13 && x < 51 && y >= 7 && y < 44;
            for (k = 0; k < 3; k++) {
                double va = k == 0 ? a.r : k == 1 ? a.g : a.b;
                double vb = k == 0 ? b.r : k == 1 ? b.g : b.b;
                if (inside)
                    assert_true(va == vb);
                else
                    assert_true(vb == 0);
            }
        }
    ggImageFree(full), ggImageFree(part);
    ggSceneFree(s);
}

/* The counts of a render in three bands (crop windows), added with
   ggRayStatsAdd, are the whole render's, on every example and SPD scene
   (but implicit_cut, which a thread's shadow cache may change:
   render.h). ud: the sum of the whole renders' counts, so that the test
   sees blocked and attenuated shadow rays. */
static void bands_add_up(const char *path, void *ud)
{
    ggScene *s = tu_load(path);
    ggRenderOptions o;
    ggRayStats whole, sum, band;
    ggImage *img;
    int b;
    ggRenderOptionsDefault(&o);
    o.width = 40, o.height = 30, o.threads = 2;
    img = render(s, &o, &whole);
    ggImageFree(img);
    ggRayStatsAdd(ud, &whole);
    memset(&sum, 0, sizeof sum);
    for (b = 0; b < 3; b++) {
        o.crop_x0 = 0, o.crop_x1 = 40, o.crop_y0 = 10 * b, o.crop_y1 = 10 * b + 10;
        img = render(s, &o, &band);
        ggImageFree(img);
        ggRayStatsAdd(&sum, &band);
    }
    ggRayStatsAdd(&sum, NULL), ggRayStatsAdd(NULL, &band);
    whole.implicit_cut = sum.implicit_cut = 0;
    if (memcmp(&whole, &sum, sizeof sum) != 0)
        print_error(
            "%s: bands add up to %llu shadow rays (%llu blocked), the whole to %llu (%llu)\n", path,
            (unsigned long long)sum.shadow, (unsigned long long)sum.shadow_blocked,
            (unsigned long long)whole.shadow, (unsigned long long)whole.shadow_blocked);
    assert_memory_equal(&whole, &sum, sizeof sum);
    ggSceneFree(s);
}

static void test_bands_add_up(void **state)
{
    ggRayStats all;
    (void)state;
    memset(&all, 0, sizeof all);
    assert_true(tu_each_file("examples/scenes", ".nff", bands_add_up, &all) >= 10);
    assert_true(tu_each_file(tu_spd_dir(), ".nff", bands_add_up, &all) >= 7);
    assert_true(all.shadow_blocked > 0 && all.shadow_attenuated > 0 && all.tir > 0);
}

/* Scene `path` at w x h rendered as it is and with every effect forced on
   (the full shading copy): the same image and ray counts. Returns the
   first image, with *o the options that made it. */
static ggImage *forced_same(ggScene *s, const char *path, int w, int h, ggRenderOptions *o)
{
    ggImage *a, *b;
    ggRayStats sa, sb;
    ggRenderOptionsDefault(o);
    o->width = w, o->height = h, o->threads = 2;
    a = render(s, o, &sa);
    o->force_effects = GG_EFFECT_ALL;
    b = render(s, o, &sb);
    o->force_effects = 0;
    if (!same_pixels(a, b)) print_error("%s differs when forced\n", path);
    assert_true(same_pixels(a, b));
    assert_true(sa.eye == sb.eye && sa.shadow == sb.shadow && sa.reflect == sb.reflect &&
                sa.refract == sb.refract);
    ggImageFree(b);
    return a;
}

/* Forcing every effect on changes the time, not the image. */
static void test_forced_effects_same_image(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < sizeof scenes / sizeof scenes[0]; i++) {
        ggScene *s = tu_load(scenes[i]);
        ggRenderOptions o;
        ggImageFree(forced_same(s, scenes[i], 64, 48, &o));
        ggSceneFree(s);
    }
}

/* Each path gives the image the full path gives (every effect forced on,
   which runs it), and the recording path (ggTracePixel) the same pixels:
   the paths differ only in the branches compiled out. */
static void test_paths_agree(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < sizeof path_scenes / sizeof path_scenes[0]; i++) {
        ggScene *s = tu_load(path_scenes[i].path);
        ggTrace *t = ggTraceCreate(NULL);
        ggRenderOptions o;
        ggImage *a;
        unsigned fx = ggSceneEffects(s);
        int x, y, bad = 0;
        assert_non_null(t);
        assert_int_equal(fx & path_scenes[i].has, path_scenes[i].has);
        assert_int_equal(fx & path_scenes[i].lacks, 0);
        a = forced_same(s, path_scenes[i].path, 40, 30, &o);
        for (y = 0; y < 30; y++)
            for (x = 0; x < 40; x++) {
                ggColor px, im = ggImageGet(a, x, y);
                assert_int_equal(ggTracePixel(s, &o, x, y, -1, t, &px, NULL, NULL), GG_OK);
                bad += !(px.r == im.r && px.g == im.g && px.b == im.b);
            }
        if (bad) print_error("%s: %d traced pixels differ\n", path_scenes[i].path, bad);
        assert_int_equal(bad, 0);
        ggTraceFree(t);
        ggImageFree(a);
        ggSceneFree(s);
    }
}

#define TU_PI 3.14159265358979323846

/* A sphere of n x n quads split in two, each corner's normal its
   position: into v (3 each) when v is not NULL, else as a mesh. */
static void add_grid_sphere(ggScene *s, int n, ggVec3 c, double r, int mat, int as_mesh)
{
    const size_t nv = (size_t)(n + 1) * (size_t)(n + 1), nt = 2 * (size_t)n * (size_t)n;
    ggVec3 *p = malloc(nv * sizeof *p), *nrm = malloc(nv * sizeof *nrm);
    uint32_t *idx = malloc(3 * nt * sizeof *idx);
    size_t k = 0, i;
    int a, b;
    assert_true(p && nrm && idx);
    for (a = 0; a <= n; a++)
        for (b = 0; b <= n; b++) {
            double th = TU_PI * (a + 0.5) / (n + 1), ph = 2 * TU_PI * b / n;
            ggVec3 u = {sin(th) * cos(ph), cos(th), sin(th) * sin(ph)};
            nrm[a * (n + 1) + b] = u;
            p[a * (n + 1) + b] = (ggVec3){c.x + r * u.x, c.y + r * u.y, c.z + r * u.z};
        }
    for (a = 0; a < n; a++)
        for (b = 0; b < n; b++) {
            uint32_t q = (uint32_t)(a * (n + 1) + b), w = (uint32_t)(n + 1);
            uint32_t t[6] = {q, q + w, q + 1, q + 1, q + w, q + w + 1};
            memcpy(idx + k, t, sizeof t), k += 6;
        }
    if (as_mesh) {
        ggMeshData d = {"grid", p, nv, nrm, NULL, idx, nt, NULL};
        ggMeshOptions mo;
        ggMeshOptionsDefault(&mo);
        mo.material = mat;
        assert_true(ggSceneAddMesh(s, &d, &mo, NULL) >= 0);
    } else
        for (i = 0; i < nt; i++) {
            ggVec3 v[3] = {p[idx[3 * i]], p[idx[3 * i + 1]], p[idx[3 * i + 2]]};
            ggVec3 m[3] = {nrm[idx[3 * i]], nrm[idx[3 * i + 1]], nrm[idx[3 * i + 2]]};
            assert_true(ggSceneAddTriangle(s, mat, v, i % 2 ? m : NULL) >= 0);
        }
    free(p), free(nrm), free(idx);
}

/* A scene past render.c's PREFETCH_PRIMS, so that its eye packets start
   their hits' records ahead (gg_geom_prefetch_hit: triangles with and
   without vertex normals, a mesh): each pixel is still ggRayColor's
   colour for its camera ray, which no packet and no hint reaches. */
static void test_large_scene_pixels(void **state)
{
    static const char *txt = "v\nfrom 0 0.5 6\nat 0 0 0\nup 0 1 0\nangle 40\nhither 0.01\n"
                             "resolution 48 40\nb 0.1 0.2 0.3\nl 4 5 6\nl -5 3 4\n"
                             "f 0.8 0.8 0.8 0.2 0.7 30 0 1\n"
                             "p 4\n-6 -2 -6\n6 -2 -6\n6 -2 6\n-6 -2 6\n";
    ggScene *s = ggSceneCreate(NULL);
    ggMaterial orange = ggMaterialDefault();
    ggRenderOptions o;
    ggImage *img;
    int x, y, bad = 0, lit = 0, mat;
    (void)state;
    assert_int_equal(ggSceneLoadString(s, txt, strlen(txt), "large.nff", NULL), GG_OK);
    /* orange: 51200 triangles, and as many in a mesh */
    orange.color = (ggColor){0.9, 0.5, 0.3}, orange.kd = 0.9, orange.ks = 0;
    assert_true((mat = ggSceneAddMaterial(s, &orange)) >= 0);
    add_grid_sphere(s, 160, (ggVec3){-1.1, 0, 0}, 1, mat, 0);
    add_grid_sphere(s, 160, (ggVec3){1.1, 0, 0}, 1, mat, 1);
    assert_int_equal(ggScenePrepare(s, NULL), GG_OK);
    assert_true(gg_geom_prim_count(s->geom) >= 65536);
    ggRenderOptionsDefault(&o);
    o.width = 48, o.height = 40, o.threads = 1;
    img = render(s, &o, NULL);
    for (y = 0; y < 40; y++)
        for (x = 0; x < 48; x++) {
            ggRay r = ggCameraRay(s, &o, x + 0.5, y + 0.5);
            ggColor c = ggRayColor(s, &o, r, 1, NULL), px = ggImageGet(img, x, y);
            bad += !((float)c.r == (float)px.r && (float)c.g == (float)px.g &&
                     (float)c.b == (float)px.b);
            lit += px.r > 2 * px.b; /* the spheres' orange, not the sky or the floor */
        }
    if (bad) print_error("%d of 1920 pixels differ from ggRayColor\n", bad);
    assert_int_equal(bad, 0);
    assert_true(lit > 300);
    ggImageFree(img);
    ggSceneFree(s);
}

/* ggRayColor on the camera ray of a pixel centre is that pixel. */
static void test_raycolor_equals_pixel(void **state)
{
    ggScene *s = tu_load("examples/scenes/glass.nff");
    ggRenderOptions o;
    ggImage *img;
    int x, y;
    (void)state;
    ggRenderOptionsDefault(&o);
    o.width = 40, o.height = 30, o.threads = 1;
    img = render(s, &o, NULL);
    for (y = 0; y < 30; y += 3)
        for (x = 0; x < 40; x += 3) {
            ggRay r = ggCameraRay(s, &o, x + 0.5, y + 0.5);
            ggColor c = ggRayColor(s, &o, r, 1, NULL), p = ggImageGet(img, x, y);
            assert_true((float)c.r == (float)p.r && (float)c.g == (float)p.g &&
                        (float)c.b == (float)p.b);
        }
    ggImageFree(img);
    ggSceneFree(s);
}

static void test_effect_sets(void **state)
{
    ggScene *s;
    unsigned fx;
    (void)state;
    s = tu_load("examples/scenes/spd/tetra.nff");
    fx = ggSceneEffects(s);
    /* tetra: diffuse only, one light. */
    assert_int_equal(fx, GG_EFFECT_SHADOWS);
    assert_non_null(strstr(ggSceneEffectReason(s, GG_EFFECT_SHADOWS), "1 point light"));
    assert_null(ggSceneEffectReason(s, GG_EFFECT_REFRACTION));
    ggSceneFree(s);
    s = tu_load("examples/scenes/water.nff");
    fx = ggSceneEffects(s);
    assert_true(fx & GG_EFFECT_REFRACTION);
    assert_true(fx & GG_EFFECT_ABSORPTION);
    assert_true(fx & GG_EFFECT_FRESNEL);
    assert_true(fx & GG_EFFECT_TEXTURES);
    assert_false(fx & GG_EFFECT_DISPERSION);
    assert_non_null(strstr(ggSceneEffectReason(s, GG_EFFECT_ABSORPTION), "water.nff:"));
    ggSceneFree(s);
    s = tu_load("examples/scenes/prism.nff");
    assert_true(ggSceneEffects(s) & GG_EFFECT_DISPERSION);
    assert_true(ggSceneEffects(s) & GG_EFFECT_EMISSION);
    ggSceneFree(s);
}

/* Depth 1 casts eye rays only; each extra level adds rays on a mirror. */
static void test_depth_limit(void **state)
{
    const char *txt = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 30 resolution 8 8\n"
                      "l 0 0 10\nf 1 1 1 0.5 0.5 100000 0 0\ns 0 0 0 1\n";
    ggScene *s = ggSceneCreate(NULL);
    ggRenderOptions o;
    ggRayStats st;
    ggImage *img;
    (void)state;
    assert_int_equal(ggSceneLoadString(s, txt, strlen(txt), "d.nff", NULL), GG_OK);
    ggRenderOptionsDefault(&o);
    o.max_depth = 1;
    memset(&st, 0, sizeof st);
    img = render(s, &o, &st);
    assert_true(st.eye == 64 && st.reflect == 0 && st.eye_hit > 0);
    ggImageFree(img);
    o.max_depth = 2;
    img = render(s, &o, &st);
    /* Every eye ray that hits the sphere spawns one mirror ray. */
    assert_true(st.reflect == st.eye_hit);
    ggImageFree(img);
    ggSceneFree(s);
}

/* A lit point's colour is the sum of its terms: check one by hand. */
static void test_direct_light_added(void **state)
{
    /* Floor facing +z at z = 0, light straight above at height 1: N.L = 1,
       colour = kd C ambient + kd C Lc: the direct term is added to the
       ambient one, not assigned over it; ambient must survive. */
    const char *txt = "ambient 0.25 0.25 0.25\nl 0 0 1 1 1 1\n"
                      "f 0.5 0.5 0.5 0.8 0 100000 0 0\np 4 -1 -1 0 1 -1 0 1 1 0 -1 1 0\n";
    ggScene *s = load_text(txt, "l.nff");
    ggColor c;
    (void)state;
    c = ggRayColor(s, NULL, down_from(0.5), 1, NULL);
    assert_close(c.r, 0.8 * 0.5 * 0.25 + 0.8 * 0.5 * 1.0, 1e-12);
    ggSceneFree(s);
}

/* Dispersion splits a transmitted ray into one per channel (shade.c,
   transmission): a pane of glass (ior 1.5, abbe 40) tilted 40 degrees to
   the eye ray, against a white background, nothing else lit. The eye
   ray's children are exactly three refracted rays, channels 0, 1, 2 (R,
   G, B), each in glass of its own index, n_b > n_g > n_r, each obeying
   Snell's law with it, so blue is bent most (closest to the normal); and
   each brings its channel of the background: the pixel is (1, 1, 1),
   every channel carried by refracted light, in the recorder and in
   ggRayColor (3 refracted rays). The same pane without dispersion casts
   one ray for all channels. Guards the loop over the channels (a loop of
   2 leaves blue black, one of 4 or 3 unsplit rays add light) and the sign
   of the dispersion (lib/scene/scene.c, cauchy). */
static void test_dispersion_channels(void **state)
{
    static const char pane[] =
        "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 10\nresolution 1 1\nb 1 1 1\nambient 0 0 0\n"
        "f 1 1 1 0 0 0 1 1.5\n%s"
        "p 4\n-2 -1.5320888862379562 1.2855752193730785\n2 -1.5320888862379562 "
        "1.2855752193730785\n2 1.5320888862379562 -1.2855752193730785\n"
        "-2 1.5320888862379562 -1.2855752193730785\n";
    const ggVec3 N = {0, 0.64278760968653925, 0.76604444311897801}; /* towards the eye */
    int disp;
    (void)state;
    for (disp = 1; disp >= 0; disp--) {
        char txt[600];
        ggScene *s;
        ggTrace *t = ggTraceCreate(NULL);
        ggColor px, c;
        ggRayStats st;
        double n_ch[3] = {0, 0, 0}, cos_ch[3] = {0, 0, 0}, sin_i;
        size_t i, nref = 0;
        snprintf(txt, sizeof txt, pane, disp ? "dispersion 40\n" : "");
        s = load_text(txt, "pane.nff");
        assert_int_equal(!!(ggSceneEffects(s) & GG_EFFECT_DISPERSION), disp);
        assert_int_equal(ggTracePixel(s, NULL, 0, 0, 0, t, &px, NULL, NULL), GG_OK);
        {
            const ggTraceNode *eye = ggTraceGetNode(t, 0);
            assert_true(eye->hit && eye->kind == GG_RAY_EYE);
            sin_i = sqrt(1 - (eye->d.x * N.x + eye->d.y * N.y + eye->d.z * N.z) *
                                 (eye->d.x * N.x + eye->d.y * N.y + eye->d.z * N.z));
            assert_true(sin_i > 0.6 && sin_i < 0.7); /* 40 degrees */
        }
        for (i = 1; i < ggTraceNodeCount(t); i++) {
            const ggTraceNode *nd = ggTraceGetNode(t, i);
            double ct, st_;
            if (nd->parent != 0) continue;
            assert_int_equal(nd->kind, GG_RAY_REFRACT);
            nref++;
            ct = -(nd->d.x * N.x + nd->d.y * N.y + nd->d.z * N.z);
            st_ = sqrt(1 - ct * ct);
            assert_close(st_ * nd->n_medium, sin_i, 1e-12); /* Snell, n = 1 outside */
            if (disp) {
                assert_true(nd->channel >= 0 && nd->channel <= 2);
                assert_true(n_ch[nd->channel] == 0); /* once each */
                n_ch[nd->channel] = nd->n_medium, cos_ch[nd->channel] = ct;
            } else {
                assert_int_equal(nd->channel, -1);
                assert_true(nd->n_medium == 1.5);
            }
        }
        assert_int_equal(nref, disp ? 3 : 1);
        if (disp) {
            /* normal dispersion: blue sees the highest index and bends most */
            assert_true(n_ch[2] > n_ch[1] && n_ch[1] > n_ch[0] && n_ch[0] > 1);
            assert_true(cos_ch[2] > cos_ch[1] && cos_ch[1] > cos_ch[0]);
        }
        /* every channel of the background comes through, once */
        assert_close(px.r, 1, 1e-12);
        assert_close(px.g, 1, 1e-12);
        assert_close(px.b, 1, 1e-12);
        c = ggRayColor(s, NULL, ggCameraRay(s, NULL, 0.5, 0.5), 1, &st);
        assert_true((float)c.r == (float)px.r && (float)c.g == (float)px.g &&
                    (float)c.b == (float)px.b);
        assert_true(st.refract == (disp ? 3u : 1u));
        ggTraceFree(t);
        ggSceneFree(s);
    }
}

/* The adaptive-depth cutoff (ggAccuracy.cutoff, POV-Ray's adc_bailout)
   drops a refracted ray whose weight in the pixel, its parent's weight
   times the share it would carry, is below the cutoff. Two panes of kt
   0.5 in a row in front of a white background, seen head on, nothing lit:
   the ray through the first carries 0.5 of the pixel, through the second
   0.25. Cutoff 0 or 0.2 casts both (pixel 0.25), 0.3 only the first
   (pixel 0: the second pane is black), 0.6 neither. Guards the
   `r->weight * w` of transmit (lib/render/shade.c): comparing the
   parent's weight alone casts one ray too many at 0.3 and at 0.6. */
static void test_cutoff_refraction(void **state)
{
    static const char txt[] =
        "v from 0 0 5 at 0 0 0 up 0 1 0 angle 10 resolution 1 1\n"
        "b 1 1 1\nambient 0 0 0\nf 1 1 1 0 0 0 0.5 1\n"
        "p 4 -2 -2 0 2 -2 0 2 2 0 -2 2 0\np 4 -2 -2 -1 2 -2 -1 2 2 -1 -2 2 -1\n";
    static const struct {
        double cutoff;
        unsigned refract;
        double pixel;
    } cases[] = {{0, 2, 0.25}, {0.2, 2, 0.25}, {0.3, 1, 0}, {0.6, 0, 0}};
    ggScene *s = load_text(txt, "cut.nff");
    size_t k;
    (void)state;
    for (k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        ggRenderOptions o;
        ggRayStats st;
        ggColor c;
        ggRenderOptionsDefault(&o);
        o.accuracy.cutoff = cases[k].cutoff;
        c = ggRayColor(s, &o, ggCameraRay(s, &o, 0.5, 0.5), 1, &st);
        if (st.refract != cases[k].refract)
            print_error("cutoff %g: %llu refracted rays, want %u\n", cases[k].cutoff,
                        (unsigned long long)st.refract, cases[k].refract);
        assert_true(st.refract == cases[k].refract);
        assert_close(c.r, cases[k].pixel, 1e-15);
        assert_close(c.b, cases[k].pixel, 1e-15);
    }
    ggSceneFree(s);
}

/* A light behind a surface's geometric plane gives it nothing, even where
   an interpolated shading normal leans towards the light (direct_light in
   lib/render/shade.c tests ng.L before ns.L). A smooth-shaded triangle at
   z = 0 seen from +z, every vertex normal leaning to +x: a light at
   (10, 0, -1) is behind the plane (ng.L < 0) but in front of the shading
   normal (ns.L > 0), so the pixel stays black (ambient 0) and no shadow
   ray is cast; the recorder says facing-away. Lights in front of both
   light it (so the scene can fail). Guards `ng.L <= 0`: without it the
   point is lit through its back. */
static void test_light_behind_geometric_plane(void **state)
{
    static const char fmt[] =
        "v from 0 0 5 at 0 0 0 up 0 1 0 angle 10 resolution 1 1\nb 0 0 0\nambient 0 0 0\n"
        "l %s\nf 1 1 1 1 0.5 10 0 1\n"
        "pp 3\n-3 -3 0 0.8 0 0.6\n3 -3 0 0.8 0 0.6\n0 3 0 0.8 0 0.6\n";
    static const char *const behind[] = {"10 0 -1", "4 3 -0.5", "10 -2 -0.01"};
    char txt[400];
    size_t k;
    (void)state;
    for (k = 0; k < 4; k++) {
        ggScene *s;
        ggTrace *t = ggTraceCreate(NULL);
        ggColor px, c;
        ggRayStats st;
        const ggTraceNode *eye;
        snprintf(txt, sizeof txt, fmt, k < 3 ? behind[k] : "10 0 1");
        s = load_text(txt, "pp.nff");
        assert_int_equal(ggTracePixel(s, NULL, 0, 0, 0, t, &px, NULL, NULL), GG_OK);
        eye = ggTraceGetNode(t, 0);
        assert_true(eye->hit && eye->ng.z > 0.999 && eye->ns.x > 0.7);
        assert_int_equal(eye->nlights, 1);
        c = ggRayColor(s, NULL, ggCameraRay(s, NULL, 0.5, 0.5), 1, &st);
        if (k < 3) {
            assert_int_equal(ggTraceGetLight(t, (size_t)eye->first_light)->verdict,
                             GG_SHADOW_FACING_AWAY);
            assert_true(px.r == 0 && px.g == 0 && px.b == 0);
            assert_true(c.r == 0 && c.g == 0 && c.b == 0);
            assert_true(st.shadow == 0);
        } else {
            assert_true(px.r > 0.01 && (float)c.r == (float)px.r && st.shadow == 1);
        }
        ggTraceFree(t);
        ggSceneFree(s);
    }
}

/* shadows=opaque: a transparent pane between a lit point and the light
   passes kt of the light by default and none of it with the knob; scenes
   without transmitters render the same either way; a knob outside its
   values is refused. */
static void test_opaque_shadows(void **state)
{
    /* Floor at z = 0, light above at z = 1, a pane of kt 0.5 (index 1: no
       bending) at z = 0.5; the ray starts under the pane. */
    const char *txt = "ambient 0.25 0.25 0.25\nl 0 0 1 1 1 1\n"
                      "f 0.5 0.5 0.5 0.8 0 100000 0 0\np 4 -1 -1 0 1 -1 0 1 1 0 -1 1 0\n"
                      "f 1 1 1 0 0 100000 0.5 1\np 4 -1 -1 0.5 1 -1 0.5 1 1 0.5 -1 1 0.5\n";
    ggScene *s = load_text(txt, "pane.nff");
    ggRenderOptions o;
    ggImage *a, *b;
    ggRay r = down_from(0.2);
    ggColor c;
    ggError e;
    (void)state;
    ggRenderOptionsDefault(&o);
    c = ggRayColor(s, &o, r, 1, NULL);
    assert_close(c.r, 0.8 * 0.5 * 0.25 + 0.8 * 0.5 * 0.5, 1e-12);
    o.accuracy.shadows = GG_ACC_SHADOWS_OPAQUE;
    c = ggRayColor(s, &o, r, 1, NULL);
    assert_close(c.r, 0.8 * 0.5 * 0.25, 1e-12);
    o.force_effects = GG_EFFECT_ALL; /* forcing does not bring them back */
    c = ggRayColor(s, &o, r, 1, NULL);
    assert_close(c.r, 0.8 * 0.5 * 0.25, 1e-12);
    o.accuracy.shadows = 2;
    a = NULL;
    assert_int_equal(ggRender(s, &o, &a, NULL, &e), GG_ERROR_INVALID);
    assert_null(a);
    assert_string_equal(e.message, "accuracy knob shadows is 2, not 0..1");
    ggSceneFree(s);

    s = tu_load("examples/scenes/gold.nff");
    assert_false(ggSceneEffects(s) & GG_EFFECT_COLORED_SHADOWS);
    ggRenderOptionsDefault(&o);
    o.width = 48, o.height = 36, o.threads = 2;
    a = render(s, &o, NULL);
    o.accuracy.shadows = GG_ACC_SHADOWS_OPAQUE;
    b = render(s, &o, NULL);
    assert_true(same_pixels(a, b));
    ggImageFree(a), ggImageFree(b);
    ggSceneFree(s);
}

/* Absorption on a shadow ray that crosses nothing: the floor and the
   light are both inside a ball of red-absorbing glass (index 1: no
   bending, no Fresnel), so the shadow walk has an empty crossing list but
   starts in the medium. The ray comes down the z axis, enters at z = 3,
   meets the floor at z = 0 (3 units in the glass) and the floor's light
   is 1 unit above it: red keeps exp(-4 pi k (3 + 1) / lambda_R), green
   all of it. (Without the medium's term on the shadow ray red would keep
   exp(-4 pi k 3 / lambda_R); without absorption, the same image with and
   without the absorb line.) */
static void test_absorbing_shadow_no_crossing(void **state)
{
    const char *txt = "ambient 0 0 0\nl 0 0 1 1 1 1\n"
                      "f 1 1 1 0 0 100000 1 1\nabsorb 1e-8 0 0 1\ns 0 0 0 3\n"
                      "f 1 1 1 1 0 100000 0 0\np 4 -1 -1 0 1 -1 0 1 1 0 -1 1 0\n";
    const double alpha = 4 * GG_PI * 1e-8 / (GG_LAMBDA_R * 1e-9);
    ggScene *s = load_text(txt, "inside.nff");
    ggColor c;
    (void)state;
    assert_true(ggSceneEffects(s) & GG_EFFECT_ABSORPTION);
    c = ggRayColor(s, NULL, down_from(5), 4, NULL);
    assert_close(c.g, 1.0, 1e-12);
    assert_close(c.r, exp(-alpha * 4), 1e-9);
    ggSceneFree(s);
}

/* The renderer's shortcuts -- tiles whose eye rays can reach nothing
   filled with the background, the pixel-centre loop that casts eye rays
   itself -- against the plain path that traces every sample (a cost map
   turns both off): same pixels and same ray counts, with pixel centres,
   4 samples, pixel corners and a crop, on scenes with much background. */
static void test_shortcuts_match_tracing(void **state)
{
    static const char *const names[] = {"tetra", "teapot-s12", "mount"};
    size_t i;
    int mode;
    (void)state;
    for (i = 0; i < 3; i++) {
        char path[512];
        ggScene *s;
        snprintf(path, sizeof path, "%s/%s.nff", tu_spd_dir(), names[i]);
        s = tu_load(path);
        for (mode = 0; mode < 4; mode++) {
            ggRenderOptions o;
            ggImage *a, *b;
            ggRayStats sa, sb;
            float *cost = malloc(sizeof(float) * 97 * 83);
            assert_non_null(cost);
            ggRenderOptionsDefault(&o);
            o.width = 97, o.height = 83, o.threads = 2;
            if (mode == 1) o.samples = 4;
            if (mode == 2) o.pixel_corners = true;
            if (mode == 3) o.crop_x0 = 5, o.crop_y0 = 17, o.crop_x1 = 90, o.crop_y1 = 60;
            a = render(s, &o, &sa);
            o.cost_map = cost, o.cost_kind = GG_COST_RAYS;
            b = render(s, &o, &sb);
            assert_true(same_pixels(a, b));
            assert_true(sa.eye == sb.eye && sa.eye_hit == sb.eye_hit);
            assert_true(sa.reflect == sb.reflect && sa.refract == sb.refract);
            assert_true(sa.shadow == sb.shadow && sa.tir == sb.tir);
            assert_true(sa.nonfinite == sb.nonfinite && sa.max_depth == sb.max_depth);
            ggImageFree(a), ggImageFree(b);
            free(cost);
        }
        ggSceneFree(s);
    }
}

/* A cost map of kind `kind` for o's window into map (w x h, every entry
   set to -1 first), with the render's statistics in *st. */
static void cost_render(ggScene *s, ggRenderOptions o, int kind, float *map, ggRayStats *st)
{
    size_t i, n = (size_t)o.width * (size_t)o.height;
    for (i = 0; i < n; i++) map[i] = -1.0f;
    o.cost_map = map, o.cost_kind = kind;
    ggImageFree(render(s, &o, st));
}

/* tu_each_file's callback: on the scene at path, the rays map adds up to
   the render's rays and the depth map's deepest entry is its max_depth,
   with pixel centres, 2 samples and pixel corners; a crop writes only its
   own pixels; and in corner mode the maps of four crops that tile the
   image are the whole image's map, entry for entry. */
static void check_cost_sums(const char *path, void *ud)
{
    enum { W = 23, H = 17, N = W * H };
    static float whole[N], deep[N], map[N], tiled[N];
    ggScene *s = tu_load(path);
    int mode, k, kind;
    size_t i;
    for (mode = 0; mode < 3; mode++) {
        ggRenderOptions o;
        ggRayStats st;
        double sum = 0, deepest = 0;
        ggRenderOptionsDefault(&o);
        o.width = W, o.height = H, o.threads = 2;
        o.samples = mode == 1 ? 2 : 1;
        o.pixel_corners = mode == 2;
        cost_render(s, o, GG_COST_RAYS, whole, &st);
        for (i = 0; i < N; i++) sum += whole[i];
        if (sum != (double)(st.eye + st.reflect + st.refract + st.shadow))
            print_error("%s mode %d: map %.0f rays, render %.0f\n", path, mode, sum,
                        (double)(st.eye + st.reflect + st.refract + st.shadow));
        assert_true(sum == (double)(st.eye + st.reflect + st.refract + st.shadow));
        cost_render(s, o, GG_COST_DEPTH, deep, &st);
        for (i = 0; i < N; i++) deepest = deep[i] > deepest ? deep[i] : deepest;
        assert_true(deepest == (double)st.max_depth);
        if (mode != 2) continue;
        for (kind = GG_COST_RAYS; kind <= GG_COST_DEPTH; kind++) {
            for (i = 0; i < N; i++) tiled[i] = -1.0f;
            for (k = 0; k < 4; k++) {
                ggRenderOptions c = o;
                c.crop_x0 = k & 1 ? 11 : 0, c.crop_x1 = k & 1 ? W : 11;
                c.crop_y0 = k & 2 ? 8 : 0, c.crop_y1 = k & 2 ? H : 8;
                cost_render(s, c, kind, map, &st);
                for (i = 0; i < N; i++) {
                    const int x = (int)(i % W), y = (int)(i / W);
                    const int in =
                        x >= c.crop_x0 && x < c.crop_x1 && y >= c.crop_y0 && y < c.crop_y1;
                    assert_true(in ? map[i] >= 0 : map[i] == -1.0f);
                    if (in) tiled[i] = map[i];
                }
            }
            assert_memory_equal(tiled, kind == GG_COST_RAYS ? whole : deep, sizeof whole);
        }
    }
    ggSceneFree(s);
    ++*(int *)ud;
}

static void test_cost_sums(void **state)
{
    int n = 0;
    (void)state;
    assert_true(tu_each_file("examples/scenes", ".nff", check_cost_sums, &n) >= 10);
    assert_true(tu_each_file(tu_spd_dir(), ".nff", check_cost_sums, &n) >= 7);
    assert_true(tu_each_file("tests/data", ".nff", check_cost_sums, &n) >= 1);
    assert_true(tu_each_file("tests/data/debug", ".nff", check_cost_sums, &n) >= 1);
}

/* GG_COST_CPU: a CPU time for every pixel (finite, not negative, some
   positive), the image unchanged, the same rays counted. */
static void test_cost_cpu(void **state)
{
    char path[512];
    ggScene *s;
    ggRenderOptions o;
    ggImage *a, *b;
    ggRayStats sa, sb;
    float *cost = calloc(64 * 48, sizeof(float));
    double sum = 0;
    int k;
    (void)state;
    assert_non_null(cost);
    snprintf(path, sizeof path, "%s/gears.nff", tu_spd_dir());
    s = tu_load(path);
    ggRenderOptionsDefault(&o);
    o.width = 64, o.height = 48, o.threads = 2;
    a = render(s, &o, &sa);
    for (k = 0; k < 64 * 48; k++) cost[k] = -1;
    o.cost_map = cost, o.cost_kind = GG_COST_CPU;
    b = render(s, &o, &sb);
    assert_true(same_pixels(a, b));
    assert_true(sa.eye == sb.eye && sa.shadow == sb.shadow && sa.reflect == sb.reflect);
    for (k = 0; k < 64 * 48; k++) {
        assert_true(isfinite(cost[k]) && cost[k] >= 0 && cost[k] < 1); /* seconds, not rays */
        sum += cost[k];
    }
    assert_true(sum > 0);
    ggImageFree(a), ggImageFree(b);
    free(cost);
    ggSceneFree(s);
}

static int cmp_float(const void *a, const void *b)
{
    const float x = *(const float *)a, y = *(const float *)b;
    return x < y ? -1 : x > y;
}

/* The median of the n values of v at the pixels (x, y) of a w-wide map
   for which in(x, y) is want. */
static float median_where(const float *v, int w, int h, int want, int (*in)(int, int))
{
    float *sel = malloc((size_t)w * h * sizeof *sel), m;
    int x, y, n = 0;
    assert_non_null(sel);
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++)
            if (in(x, y) == want) sel[n++] = v[(size_t)y * w + x];
    assert_true(n > 0);
    qsort(sel, (size_t)n, sizeof *sel, cmp_float);
    m = sel[n / 2];
    free(sel);
    return m;
}

/* In the 64x64 image below: 1 in the 16-pixel tiles of the corners,
   which the ball in the middle leaves empty (no ray of theirs can hit);
   2 in the middle, on the ball; else 0. */
static int corner_tile(int x, int y)
{
    if ((x < 16 || x >= 48) && (y < 16 || y >= 48)) return 1;
    return x >= 28 && x < 36 && y >= 28 && y < 36 ? 2 : 0;
}

/* Cost maps measure the render as it runs: an empty tile is filled
   without tracing (fill_empty_tile), so its pixels cost far less time
   than the ball's pixels, and their rays and depth are what tracing gives
   (one eye ray a sample, depth 1). Each pixel's least time of three
   renders, and medians, so that a preemption decides nothing. */
static void test_cost_empty_tiles(void **state)
{
    const char *txt = "v\nfrom 0 0 10\nat 0 0 0\nup 0 1 0\nangle 30\nhither 1\n"
                      "resolution 64 64\nl 5 5 10\nf 1 0 0 0.7 0.3 20 0 0\ns 0 0 0 1\n";
    ggScene *s = load_text(txt, "ball.nff");
    ggRenderOptions o;
    ggImage *img;
    float *t = malloc(64 * 64 * sizeof *t), *best = malloc(64 * 64 * sizeof *best);
    int k, r;
    (void)state;
    assert_non_null(t), assert_non_null(best);
    ggRenderOptionsDefault(&o);
    o.width = o.height = 64, o.threads = 1, o.samples = 4;
    o.cost_map = t, o.cost_kind = GG_COST_TIME;
    for (r = 0; r < 3; r++) {
        img = render(s, &o, NULL);
        ggImageFree(img);
        for (k = 0; k < 64 * 64; k++) best[k] = r == 0 || t[k] < best[k] ? t[k] : best[k];
    }
    assert_true(median_where(best, 64, 64, 1, corner_tile) * 10 <
                median_where(best, 64, 64, 2, corner_tile));
    o.cost_kind = GG_COST_RAYS;
    img = render(s, &o, NULL);
    ggImageFree(img);
    for (k = 0; k < 64 * 64; k++)
        if (corner_tile(k % 64, k / 64) == 1) assert_true(t[k] == 4);
    o.cost_kind = GG_COST_DEPTH;
    img = render(s, &o, NULL);
    ggImageFree(img);
    for (k = 0; k < 64 * 64; k++)
        if (corner_tile(k % 64, k / 64) == 1) assert_true(t[k] == 1);
    free(t), free(best);
    ggSceneFree(s);
}

/* trace.h: the trace "is cleared first": a call that fails leaves none
   of an earlier call's rays in it. */
static void test_trace_cleared_on_failure(void **state)
{
    static const char txt[] = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 resolution 8 6\nl 2 3 4\n"
                              "f 1 1 1 0.8 0.2 20 0.5 1.5\ns 0 0 0 1\n";
    ggScene *s = load_text(txt, "t.nff");
    ggTrace *t = ggTraceCreate(NULL);
    ggRenderOptions o;
    ggColor px = {7, 7, 7};
    int k;
    (void)state;
    ggRenderOptionsDefault(&o);
    for (k = 0; k < 3; k++) {
        assert_int_equal(ggTracePixel(s, NULL, 4, 3, -1, t, &px, NULL, NULL), GG_OK);
        assert_true(ggTraceNodeCount(t) > 0 && ggTraceLightCount(t) > 0);
        if (k == 0) /* outside the image */
            assert_int_equal(ggTracePixel(s, NULL, 99, 0, 0, t, &px, NULL, NULL), GG_ERROR_INVALID);
        else if (k == 1) /* a sample the pixel does not have */
            assert_int_equal(ggTracePixel(s, NULL, 4, 3, 5, t, &px, NULL, NULL), GG_ERROR_INVALID);
        else /* bad options */
            o.max_depth = -1,
            assert_int_equal(ggTracePixel(s, &o, 4, 3, 0, t, &px, NULL, NULL), GG_ERROR_INVALID);
        assert_int_equal(ggTraceNodeCount(t), 0);
        assert_int_equal(ggTraceLightCount(t), 0);
    }
    ggTraceFree(t);
    ggSceneFree(s);
}

/* render.h: ggCameraRay's d is unit length, also far off the image,
   where the squares of its length overflow; NaN and infinite points give
   the all-zero ray. */
static void test_camera_ray_far(void **state)
{
    static const char txt[] = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 resolution 8 6\n"
                              "s 0 0 0 1\n";
    static const double far[][2] = {{1e200, 3},     {-1e200, 3}, {3, 1e300}, {1e300, -1e300},
                                    {1e154, 1e154}, {4, 1e307},  {4, 3}};
    ggScene *s = load_text(txt, "t.nff");
    size_t i;
    (void)state;
    for (i = 0; i < sizeof far / sizeof far[0]; i++) {
        ggRay r = ggCameraRay(s, NULL, far[i][0], far[i][1]);
        double len = sqrt(r.d.x * r.d.x + r.d.y * r.d.y + r.d.z * r.d.z);
        if (!(fabs(len - 1) < 1e-15))
            fail_msg("ggCameraRay(%g, %g).d = (%g, %g, %g)", far[i][0], far[i][1], r.d.x, r.d.y,
                     r.d.z);
        assert_true(r.o.z == 5);
    }
    /* x = 1e200 looks along +x (the camera's right) */
    assert_true(ggCameraRay(s, NULL, 1e200, 3).d.x == 1);
    for (i = 0; i < 3; i++) {
        ggRay r = ggCameraRay(s, NULL, i == 0 ? NAN : i == 2 ? DBL_MAX : 4, i == 1 ? INFINITY : 3);
        assert_true(r.o.z == 0 && r.d.x == 0 && r.d.y == 0 && r.d.z == 0);
    }
    ggSceneFree(s);
}

/* render.h: the progress callback's done and total are in pixels (of
   the crop window when there is one), done rising to total. */
typedef struct progress_log {
    long calls, done, total;
    int monotone;
} progress_log;
static int log_progress(void *ud, long done, long total)
{
    progress_log *l = ud;
    if (l->calls && (done < l->done || total != l->total)) l->monotone = 0;
    l->calls++, l->done = done, l->total = total;
    return 0;
}

static void test_progress_in_pixels(void **state)
{
    static const char txt[] = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 resolution 10 10\n"
                              "l 2 3 4\ns 0 0 0 1\n";
    ggScene *s = load_text(txt, "t.nff");
    int k;
    (void)state;
    for (k = 0; k < 4; k++) {
        ggRenderOptions o;
        progress_log l = {0, 0, 0, 1};
        ggImage *img = NULL;
        long want;
        ggRenderOptionsDefault(&o);
        o.progress = log_progress, o.progress_ud = &l, o.threads = 1 + k % 2;
        if (k >= 2) o.width = 37, o.height = 23, o.pixel_corners = k == 3;
        if (k == 3) o.crop_x0 = 3, o.crop_y0 = 2, o.crop_x1 = 36, o.crop_y1 = 19;
        want = k < 2 ? 100 : k == 2 ? 37 * 23 : 33 * 17;
        assert_int_equal(ggRender(s, &o, &img, NULL, NULL), GG_OK);
        assert_true(l.calls > 0 && l.monotone);
        assert_int_equal(l.total, want);
        assert_int_equal(l.done, want);
        ggImageFree(img);
    }
    ggSceneFree(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_threads_identical),
        cmocka_unit_test(test_trace_cleared_on_failure),
        cmocka_unit_test(test_camera_ray_far),
        cmocka_unit_test(test_progress_in_pixels),
        cmocka_unit_test(test_cost_sums),
        cmocka_unit_test(test_cost_cpu),
        cmocka_unit_test(test_cost_empty_tiles),
        cmocka_unit_test(test_crop_matches_full),
        cmocka_unit_test(test_bands_add_up),
        cmocka_unit_test(test_options_refused),
        cmocka_unit_test(test_scene_setters),
        cmocka_unit_test(test_set_material),
        cmocka_unit_test(test_light_on_surface),
        cmocka_unit_test(test_zero_weight_rays),
        cmocka_unit_test(test_options_resolve),
        cmocka_unit_test(test_forced_effects_same_image),
        cmocka_unit_test(test_paths_agree),
        cmocka_unit_test(test_raycolor_equals_pixel),
        cmocka_unit_test(test_large_scene_pixels),
        cmocka_unit_test(test_effect_sets),
        cmocka_unit_test(test_depth_limit),
        cmocka_unit_test(test_direct_light_added),
        cmocka_unit_test(test_dispersion_channels),
        cmocka_unit_test(test_cutoff_refraction),
        cmocka_unit_test(test_light_behind_geometric_plane),
        cmocka_unit_test(test_opaque_shadows),
        cmocka_unit_test(test_absorbing_shadow_no_crossing),
        cmocka_unit_test(test_shortcuts_match_tracing),
    };
    return cmocka_run_group_tests_name("render", tests, NULL, NULL);
}
