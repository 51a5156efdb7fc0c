/* SPDX-License-Identifier: MIT */
/*
** test_limits.c -- bounded memory (docs/scene-format.md, "NFF"): the texture budget
** and its contract, a texture named many times decoded once, declared
** image sizes refused before anything large is allocated, the scene-file
** size limit and the render's image-size limit. The files are
** tests/data/hostile/ (written by tests/data/hostile.py).
*/
#include "testutil.h"

#include "scene.h"

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define HOSTILE     "tests/data/hostile/"
#define TEX1M_BYTES 1051392 /* 296 x 296 pixels x 3 floats */

/* An allocator that remembers the largest single request. */
static size_t largest;
static void *big_malloc(void *ud, size_t n)
{
    (void)ud;
    if (n > largest) largest = n;
    return malloc(n);
}
static void *big_realloc(void *ud, void *p, size_t n)
{
    (void)ud;
    if (n > largest) largest = n;
    return realloc(p, n);
}
static void big_free(void *ud, void *p)
{
    (void)ud;
    free(p);
}
static const ggAllocator watch = {big_malloc, big_realloc, big_free, NULL};

static int load(ggScene *s, const char *text, ggError *e)
{
    return ggSceneLoadString(s, text, strlen(text), "t.nff", e);
}

static void test_budget_contract(void **state)
{
    ggScene *s = ggSceneCreate(NULL);
    (void)state;
    assert_int_equal(GG_TEXTURE_BUDGET, (int64_t)256 << 20);
    assert_true(ggSceneSetTextureBudget(s, -1) == GG_TEXTURE_BUDGET); /* query */
    assert_true(ggSceneSetTextureBudget(s, 1000) == GG_TEXTURE_BUDGET);
    assert_true(ggSceneSetTextureBudget(s, -5) == 1000);
    assert_true(ggSceneSetTextureBudget(s, 0) == 1000);
    assert_true(ggSceneSetTextureBudget(s, -1) == 0);
    assert_true(ggSceneSetTextureBudget(NULL, 5) == -1);
    ggSceneFree(s);
}

/* A reader that counts its calls, then reads as the library does. */
static int calls;
static int counting_reader(void *ud, const char *path, const ggAllocator *a, ggImage **out,
                           ggError *err)
{
    (void)ud;
    calls++;
    return ggImageRead(path, a, out, err);
}

static char *repeated_scene(int n)
{
    const char *line = "texture \"" HOSTILE "tex1m.png\" clamp\ns 0 0 0 1\n";
    size_t len = strlen(line);
    char *t = malloc(len * (size_t)n + 1);
    int i;
    assert_non_null(t);
    for (i = 0; i < n; i++) memcpy(t + len * (size_t)i, line, len);
    t[len * (size_t)n] = '\0';
    return t;
}

static void test_named_250_times_decoded_once(void **state)
{
    char *text = repeated_scene(250);
    ggScene *s = ggSceneCreate(NULL);
    ggError e;
    (void)state;
    assert_int_equal(load(s, text, &e), GG_OK);
    assert_int_equal(s->nimages, 1);
    assert_int_equal(s->ntextures, 250);
    assert_true(s->tex_used == TEX1M_BYTES);
    assert_ptr_equal(s->textures[0].img, s->textures[249].img);
    ggSceneFree(s);
    /* The same through a reader of the caller's: called once. */
    s = ggSceneCreate(NULL);
    calls = 0;
    ggSceneSetImageReader(s, counting_reader, NULL);
    assert_int_equal(load(s, text, &e), GG_OK);
    assert_int_equal(calls, 1);
    ggSceneFree(s);
    free(text);
}

/* One file under three names is one image, decoded and charged once (it
   was keyed by the name: each spelling cost the budget its bytes again). */
static void test_one_file_three_names(void **state)
{
    const char *text = "texture \"" HOSTILE "tex1m.png\" clamp\ns 0 0 0 1\n"
                       "texture \"" HOSTILE "./tex1m.png\" clamp\ns 1 0 0 1\n"
                       "texture \"" HOSTILE "../hostile/tex1m.png\" clamp\ns 2 0 0 1\n";
    ggScene *s = ggSceneCreate(NULL);
    ggError e;
    (void)state;
    assert_true(ggSceneSetTextureBudget(s, TEX1M_BYTES + TEX1M_BYTES / 2) == GG_TEXTURE_BUDGET);
    assert_int_equal(load(s, text, &e), GG_OK);
    assert_int_equal(s->nimages, 1);
    assert_true(s->tex_used == TEX1M_BYTES);
    assert_ptr_equal(s->textures[0].img, s->textures[2].img);
    ggSceneFree(s);
}

static void test_budget_checked_before_decoding(void **state)
{
    ggScene *s = ggSceneCreate(&watch);
    ggError e;
    (void)state;
    assert_true(ggSceneSetTextureBudget(s, 1000000) == GG_TEXTURE_BUDGET);
    largest = 0;
    assert_int_equal(load(s, "s 0 0 0 1\ntexture \"" HOSTILE "tex1m.png\"\ns 1 0 0 1\n", &e),
                     GG_ERROR_LIMIT);
    assert_string_equal(e.message, "t.nff:2:9: cannot read texture: " HOSTILE
                                   "tex1m.png: 296 x 296 pixels decode to 1051392 bytes, over "
                                   "the texture budget (1000000 bytes left of 1000000)");
    assert_true(largest < 100000); /* libpng's buffers; no pixels */
    assert_int_equal(s->nobjects, 0);
    assert_int_equal(s->nimages, 0);
    assert_true(s->tex_used == 0);
    ggSceneFree(s);
}

/* The budget is per scene, over every file: a copy of tex1m.png is
   another file, decoded and charged again. */
static const char *copy_of_tex1m(void)
{
    static char path[512];
    char buf[4096];
    FILE *in = fopen(HOSTILE "tex1m.png", "rb"), *out;
    size_t n;
    assert_int_equal(tu_tmpdir_make("limits"), 0);
    snprintf(path, sizeof path, "%s", tu_tmppath("copy.png"));
    out = fopen(path, "wb");
    assert_true(in && out);
    while ((n = fread(buf, 1, sizeof buf, in)) > 0) assert_true(fwrite(buf, 1, n, out) == n);
    fclose(in);
    assert_int_equal(fclose(out), 0);
    return path;
}

static void test_budget_is_cumulative(void **state)
{
    ggScene *s = ggSceneCreate(NULL);
    ggError e;
    char text[700], want[900];
    const char *copy = copy_of_tex1m();
    (void)state;
    ggSceneSetTextureBudget(s, 1500000);
    assert_int_equal(load(s, "texture \"" HOSTILE "tex1m.png\"\ns 0 0 0 1\n", &e), GG_OK);
    snprintf(text, sizeof text, "texture \"%s\"\ns 0 0 0 1\n", copy);
    assert_int_equal(load(s, text, &e), GG_ERROR_LIMIT);
    snprintf(want, sizeof want,
             "t.nff:1:9: cannot read texture: %s: 296 x 296 pixels decode to 1051392 "
             "bytes, over the texture budget (448608 bytes left of 1500000)",
             copy);
    assert_string_equal(e.message, want);
    tu_tmpdir_remove();
    /* The failed load took nothing; the first texture stays. */
    assert_int_equal(s->nimages, 1);
    assert_true(s->tex_used == TEX1M_BYTES);
    /* Lowering the budget keeps what is loaded; the cached path still works. */
    ggSceneSetTextureBudget(s, 0);
    assert_int_equal(load(s, "texture \"" HOSTILE "tex1m.png\"\ns 0 0 0 1\n", &e), GG_OK);
    assert_int_equal(s->nimages, 1);
    ggSceneFree(s);
}

/* A reader of the caller's is checked when it returns. */
static int big_reader(void *ud, const char *path, const ggAllocator *a, ggImage **out, ggError *err)
{
    (void)ud, (void)path, (void)err;
    *out = ggImageCreate(400, 400, a);
    return *out ? GG_OK : GG_ERROR_NOMEM;
}

static void test_budget_with_own_reader(void **state)
{
    ggScene *s = ggSceneCreate(NULL);
    ggError e;
    (void)state;
    ggSceneSetImageReader(s, big_reader, NULL);
    ggSceneSetTextureBudget(s, 1000000);
    assert_int_equal(load(s, "texture \"any.png\"\ns 0 0 0 1\n", &e), GG_ERROR_LIMIT);
    assert_string_equal(e.message, "t.nff:1:9: cannot read texture: any.png: 400 x 400 pixels "
                                   "decode to 1920000 bytes, over the texture budget (1000000 "
                                   "bytes left of 1000000)");
    assert_int_equal(s->nimages, 0);
    ggSceneFree(s);
}

/* Small files declaring 16384 x 16384: refused from the header. */
static void test_declared_size_refused(void **state)
{
    static const char *const files[] = {HOSTILE "big.png", HOSTILE "big.exr"};
    size_t i;
    (void)state;
    for (i = 0; i < 2; i++) {
        ggImage *img = NULL;
        ggError e;
        char want[256];
        largest = 0;
        assert_int_equal(ggImageRead(files[i], &watch, &img, &e), GG_ERROR_LIMIT);
        snprintf(want, sizeof want,
                 "%s: image of 16384 x 16384 pixels exceeds the limit (65536 per side, "
                 "16777216 pixels)",
                 files[i]);
        assert_string_equal(e.message, want);
        assert_null(img);
        assert_true(largest < 1000000);
    }
}

/* An IDAT whose length says 2 GB: an error, and no more memory than the
   declared 4096 x 4096 pixels take. */
static void test_lying_chunk_length(void **state)
{
    ggImage *img = NULL;
    ggError e;
    (void)state;
    largest = 0;
    assert_int_equal(ggImageRead(HOSTILE "lie.png", &watch, &img, &e), GG_ERROR_PARSE);
    assert_string_equal(e.message, HOSTILE "lie.png: invalid PNG: truncated file");
    assert_true(largest <= (size_t)4096 * 4096 * 3 * sizeof(float));
}

static void test_scene_file_size_limit(void **state)
{
    char path[] = "/tmp/gg_limits_XXXXXX", want[256];
    ggScene *s = ggSceneCreate(&watch);
    ggError e;
    int fd = mkstemp(path);
    (void)state;
    assert_true(fd >= 0);
    /* Sparse: no disk space is used. */
    assert_int_equal(ftruncate(fd, (off_t)GG_SCENE_MAX_FILE + 1), 0);
    close(fd);
    largest = 0;
    assert_int_equal(ggSceneLoadFile(s, path, &e), GG_ERROR_LIMIT);
    snprintf(want, sizeof want, "%s: 268435457 bytes exceed the limit of 268435456", path);
    assert_string_equal(e.message, want);
    assert_true(largest < 100000);
    unlink(path);
    ggSceneFree(s);
}

static void test_render_size_limit(void **state)
{
    ggScene *s = ggSceneCreate(&watch);
    ggRenderOptions o;
    ggImage *img = NULL;
    ggError e;
    (void)state;
    assert_int_equal(
        load(s, "v from 0 0 1 at 0 0 0 up 0 1 0 angle 45 resolution 16384 16384\n", &e),
        GG_ERROR_LIMIT);
    assert_string_equal(e.message,
                        "t.nff:1:41: resolution 16384x16384 exceeds the limit of 16777216 pixels");
    assert_int_equal(load(s, "s 0 0 0 1\n", &e), GG_OK);
    ggRenderOptionsDefault(&o);
    o.width = o.height = 16384;
    largest = 0;
    assert_int_equal(ggRender(s, &o, &img, NULL, &e), GG_ERROR_LIMIT);
    assert_string_equal(e.message,
                        "image size 16384x16384 exceeds the limit of 16777216 pixels (65536 per "
                        "side)");
    assert_null(img);
    assert_true(largest < 1000000);
    /* a negative size is no size over the limit: GG_ERROR_INVALID */
    o.width = -1, o.height = 0;
    assert_int_equal(ggRender(s, &o, &img, NULL, &e), GG_ERROR_INVALID);
    assert_string_equal(e.message,
                        "image width and height must be >= 0 (0: the camera's), got -1 and 0");
    assert_null(img);
    o.width = 0, o.height = -5;
    assert_int_equal(ggRender(s, &o, &img, NULL, &e), GG_ERROR_INVALID);
    o.width = o.height = 4096; /* the limit itself is allowed */
    o.crop_x0 = o.crop_y0 = 0, o.crop_x1 = o.crop_y1 = 1;
    assert_int_equal(ggRender(s, &o, &img, NULL, &e), GG_OK);
    assert_int_equal(ggImageWidth(img), 4096);
    ggImageFree(img);
    ggSceneFree(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_budget_contract),
        cmocka_unit_test(test_named_250_times_decoded_once),
        cmocka_unit_test(test_one_file_three_names),
        cmocka_unit_test(test_budget_checked_before_decoding),
        cmocka_unit_test(test_budget_is_cumulative),
        cmocka_unit_test(test_budget_with_own_reader),
        cmocka_unit_test(test_declared_size_refused),
        cmocka_unit_test(test_lying_chunk_length),
        cmocka_unit_test(test_scene_file_size_limit),
        cmocka_unit_test(test_render_size_limit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
