/* SPDX-License-Identifier: MIT */
/*
** test_exr_header.c -- ggImageWriteEXRHeader and ggImageReadEXRHeader:
** data and display windows, string attributes, the contract's refusals,
** that a NULL header writes exactly ggImageWriteEXR's file, and a layer
** map exactly ggImageWriteEXRLayers' file.
*/
#include "testutil.h"

#include "image.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static int setup_dir(void **state)
{
    (void)state;
    return tu_tmpdir_make("exrh");
}

static int teardown_dir(void **state)
{
    (void)state;
    tu_tmpdir_remove();
    return 0;
}

/* A w x h image whose every float differs. */
static ggImage *ramp(int w, int h)
{
    ggImage *img = ggImageCreate(w, h, NULL);
    float *p = ggImagePixels(img);
    size_t k;
    for (k = 0; k < (size_t)w * (size_t)h * 3; k++) p[k] = (float)k * 0.37f - 5.0f;
    return img;
}

static void test_round_trip_windows_attrs(void **state)
{
    ggEXRAttr attrs[3] = {{"ggrt.a", "one"}, {"b", ""}, {"long.value", "x y z, \"quoted\""}};
    ggEXRHeader h, r;
    ggImage *img = ramp(7, 3), *back = NULL;
    ggError err;
    const char *p = tu_tmppath("tile.exr");
    (void)state;
    memset(&h, 0, sizeof h);
    h.display_width = 7, h.display_height = 11, h.data_x = 0, h.data_y = 5;
    h.attr_count = 3, h.attrs = attrs;
    assert_int_equal(ggImageWriteEXRHeader(img, &h, p, &err), GG_OK);
    assert_int_equal(ggImageReadEXRHeader(p, &r, &err), GG_OK);
    assert_int_equal(r.display_x, 0);
    assert_int_equal(r.display_y, 0);
    assert_int_equal(r.display_width, 7);
    assert_int_equal(r.display_height, 11);
    assert_int_equal(r.data_x, 0);
    assert_int_equal(r.data_y, 5);
    assert_int_equal(r.data_width, 7);
    assert_int_equal(r.data_height, 3);
    assert_int_equal(r.attr_count, 3);
    assert_string_equal(ggEXRHeaderGet(&r, "ggrt.a"), "one");
    assert_string_equal(ggEXRHeaderGet(&r, "b"), "");
    assert_string_equal(ggEXRHeaderGet(&r, "long.value"), "x y z, \"quoted\"");
    assert_null(ggEXRHeaderGet(&r, "absent"));
    assert_null(ggEXRHeaderGet(&r, "channels")); /* not a string attribute */
    ggEXRHeaderFree(&r);
    assert_int_equal(r.attr_count, 0);
    assert_null(r.attrs);
    ggEXRHeaderFree(&r); /* zeroed: a no-op */
    /* The pixels read back are the data window, bit for bit. */
    assert_int_equal(ggImageRead(p, NULL, &back, &err), GG_OK);
    assert_int_equal(ggImageWidth(back), 7);
    assert_int_equal(ggImageHeight(back), 3);
    assert_memory_equal(ggImagePixelsConst(back), ggImagePixelsConst(img), 7 * 3 * 3 * sizeof(float));
    ggImageFree(back);
    ggImageFree(img);
}

/* A data window not at the origin on both axes, and one outside the
   display window (OpenEXR allows it). */
static void test_offset_windows(void **state)
{
    ggEXRHeader h, r;
    ggImage *img = ramp(4, 5), *back = NULL;
    ggError err;
    const char *p = tu_tmppath("off.exr");
    (void)state;
    memset(&h, 0, sizeof h);
    h.display_x = -2, h.display_y = 3, h.display_width = 10, h.display_height = 4;
    h.data_x = 9, h.data_y = -1;
    assert_int_equal(ggImageWriteEXRHeader(img, &h, p, &err), GG_OK);
    assert_int_equal(ggImageReadEXRHeader(p, &r, &err), GG_OK);
    assert_int_equal(r.display_x, -2);
    assert_int_equal(r.display_y, 3);
    assert_int_equal(r.display_width, 10);
    assert_int_equal(r.display_height, 4);
    assert_int_equal(r.data_x, 9);
    assert_int_equal(r.data_y, -1);
    assert_int_equal(r.data_width, 4);
    assert_int_equal(r.data_height, 5);
    assert_int_equal(r.attr_count, 0);
    ggEXRHeaderFree(&r);
    assert_int_equal(ggImageRead(p, NULL, &back, &err), GG_OK);
    assert_memory_equal(ggImagePixelsConst(back), ggImagePixelsConst(img), 4 * 5 * 3 * sizeof(float));
    ggImageFree(back);
    ggImageFree(img);
}

/* The temporary files a and b hold the same bytes. */
static void assert_same_files(const char *a, const char *b)
{
    size_t na = 0, nb = 0;
    char *pa = tu_slurp(tu_tmppath(a), &na), *pb = tu_slurp(tu_tmppath(b), &nb);
    assert_non_null(pa);
    assert_non_null(pb);
    assert_int_equal(na, nb);
    assert_memory_equal(pa, pb, na);
    free(pa);
    free(pb);
}

/* A NULL header writes ggImageWriteEXR's file, byte for byte. */
static void test_null_header_same_file(void **state)
{
    ggImage *img = ramp(9, 17);
    ggError err;
    (void)state;
    assert_int_equal(ggImageWriteEXR(img, tu_tmppath("a.exr"), &err), GG_OK);
    assert_int_equal(ggImageWriteEXRHeader(img, NULL, tu_tmppath("b.exr"), &err), GG_OK);
    assert_same_files("a.exr", "b.exr");
    ggImageFree(img);
}

/* Layers written from a layer map (ggrt render --aov's) make the file
   the same layers copied into images make, byte for byte, and read back
   as the map's layers. */
static void test_layer_map_same_file(void **state)
{
    static const char *const names[3] = {"a", "b-2", "c_3"};
    ggEXRAttr attr[1] = {{"ggrt.aov", "a=C.*"}};
    ggEXRHeader h;
    ggImage *img = ramp(9, 17), *layers[3], *back = NULL;
    const size_t n = 9 * 17 * 3;
    float *map = malloc(3 * n * sizeof(float));
    ggError err;
    size_t k;
    int i;
    (void)state;
    assert_non_null(map);
    for (k = 0; k < 3 * n; k++) map[k] = (float)k * -1.3f + 2.0f;
    for (i = 0; i < 3; i++) {
        layers[i] = ggImageCreate(9, 17, NULL);
        memcpy(ggImagePixels(layers[i]), map + i * n, n * sizeof(float));
    }
    memset(&h, 0, sizeof h);
    h.display_width = 9, h.display_height = 17, h.attrs = attr, h.attr_count = 1;
    assert_int_equal(ggImageWriteEXRLayers(img, (const ggImage *const *)layers, names, 3, &h,
                                           tu_tmppath("a.exr"), &err),
                     GG_OK);
    assert_int_equal(ggImageWriteEXRLayerMap(img, map, names, 3, &h, tu_tmppath("b.exr"), &err),
                     GG_OK);
    assert_same_files("a.exr", "b.exr");
    assert_int_equal(ggImageReadEXRLayer(tu_tmppath("b.exr"), "b-2", NULL, &back, &err), GG_OK);
    assert_memory_equal(ggImagePixelsConst(back), map + n, n * sizeof(float));
    /* n = 0: the image alone, as ggImageWriteEXRHeader writes it */
    assert_int_equal(ggImageWriteEXRLayerMap(img, NULL, NULL, 0, NULL, tu_tmppath("c.exr"), &err),
                     GG_OK);
    assert_int_equal(ggImageWriteEXRLayerMap(img, map, names, 65, NULL, tu_tmppath("d.exr"), &err),
                     GG_ERROR_INVALID);
    assert_int_equal(access(tu_tmppath("d.exr"), F_OK), -1);
    for (i = 0; i < 3; i++) ggImageFree(layers[i]);
    ggImageFree(back);
    ggImageFree(img);
    free(map);
}

static void test_refusals(void **state)
{
    ggEXRAttr bad_name[1] = {{"", "v"}};
    ggEXRAttr reserved[1] = {{"dataWindow", "v"}};
    ggEXRAttr twice[2] = {{"a", "1"}, {"a", "2"}};
    ggEXRAttr too_long[1] = {{"abcdefghijklmnopqrstuvwxyz0123456", "v"}};
    ggEXRAttr null_value[1] = {{"a", NULL}};
    ggEXRAttr *cases[5] = {bad_name, reserved, twice, too_long, null_value};
    int counts[5] = {1, 1, 2, 1, 1}, k;
    ggEXRHeader h, r;
    ggImage *img = ramp(2, 2);
    ggError err;
    const char *p = tu_tmppath("refused.exr");
    (void)state;
    for (k = 0; k < 5; k++) {
        memset(&h, 0, sizeof h);
        h.display_width = 2, h.display_height = 2;
        h.attr_count = counts[k], h.attrs = cases[k];
        assert_int_equal(ggImageWriteEXRHeader(img, &h, p, &err), GG_ERROR_INVALID);
        assert_int_equal(access(p, F_OK), -1); /* nothing written */
    }
    memset(&h, 0, sizeof h);
    assert_int_equal(ggImageWriteEXRHeader(img, &h, p, &err), GG_ERROR_INVALID); /* 0x0 display */
    h.display_width = h.display_height = 2, h.attr_count = -1;
    assert_int_equal(ggImageWriteEXRHeader(img, &h, p, &err), GG_ERROR_INVALID);
    assert_int_equal(ggImageWriteEXRHeader(NULL, NULL, p, &err), GG_ERROR_INVALID);
    assert_int_equal(access(p, F_OK), -1);
    /* Reading: missing file, not EXR, NULL arguments. */
    assert_int_equal(ggImageReadEXRHeader(tu_tmppath("none.exr"), &r, &err), GG_ERROR_IO);
    assert_int_equal(ggImageWritePNG(img, tu_tmppath("x.png"), &err), GG_OK);
    assert_int_equal(ggImageReadEXRHeader(tu_tmppath("x.png"), &r, &err), GG_ERROR_UNSUPPORTED);
    assert_int_equal(ggImageReadEXRHeader(NULL, &r, &err), GG_ERROR_INVALID);
    assert_int_equal(ggImageReadEXRHeader(p, NULL, &err), GG_ERROR_INVALID);
    ggImageFree(img);
}

/* A file cut inside its header fails; one cut after it reads here and
   fails in ggImageRead. */
static void test_truncated(void **state)
{
    ggEXRAttr attrs[1] = {{"k", "value"}};
    ggEXRHeader h, r;
    ggImage *img = ramp(64, 64), *back = NULL;
    ggError err;
    size_t n = 0;
    char *data;
    FILE *f;
    (void)state;
    memset(&h, 0, sizeof h);
    h.display_width = 64, h.display_height = 64, h.attr_count = 1, h.attrs = attrs;
    assert_int_equal(ggImageWriteEXRHeader(img, &h, tu_tmppath("full.exr"), &err), GG_OK);
    data = tu_slurp(tu_tmppath("full.exr"), &n);
    assert_non_null(data);
    assert_true(n > 2000);
    f = fopen(tu_tmppath("cut.exr"), "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, n - 1000, f), n - 1000);
    fclose(f);
    assert_int_equal(ggImageReadEXRHeader(tu_tmppath("cut.exr"), &r, &err), GG_OK);
    assert_string_equal(ggEXRHeaderGet(&r, "k"), "value");
    ggEXRHeaderFree(&r);
    assert_int_equal(ggImageRead(tu_tmppath("cut.exr"), NULL, &back, &err), GG_ERROR_PARSE);
    f = fopen(tu_tmppath("head.exr"), "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, 40, f), 40);
    fclose(f);
    assert_int_equal(ggImageReadEXRHeader(tu_tmppath("head.exr"), &r, &err), GG_ERROR_PARSE);
    assert_int_equal(r.attr_count, 0);
    free(data);
    ggImageFree(img);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip_windows_attrs),
        cmocka_unit_test(test_offset_windows),
        cmocka_unit_test(test_null_header_same_file),
        cmocka_unit_test(test_layer_map_same_file),
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_truncated),
    };
    return cmocka_run_group_tests_name("exr_header", tests, setup_dir, teardown_dir);
}
