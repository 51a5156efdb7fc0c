/* SPDX-License-Identifier: MIT */
/*
** test_golden.c -- low-resolution golden images: every SPD scene and every
** example scene rendered at 64 pixels across and compared with the PNG in
** tests/golden/. Tolerance (sRGB, as the PNG stores it): RMSE at most
** 1/255 and at most 0.5% of pixels off by more than 1/255. The renderer is
** deterministic, so the plain build matches exactly; the tolerance absorbs
** the sanitized build's different optimisation and 8-bit rounding.
**
** GG_UPDATE_GOLDEN=1 rewrites the files (after checking the pictures by eye
** beside POV-Ray's, docs/spd-compare.md).
*/
#include "testutil.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const scenes[] = {
    "spd/balls-s3", "spd/gears", "spd/rings",   "spd/tetra", "spd/mount",
    "spd/tree",     "spd/teapot", "default",    "glass",     "water",
    "gold",         "torus",     "texture",
};

/* What an 8-bit sRGB PNG of img would hold, back in linear floats. */
static ggImage *quantized(const ggImage *img)
{
    int w = ggImageWidth(img), h = ggImageHeight(img);
    ggImage *q = ggImageCreate(w, h, NULL);
    size_t k, n = (size_t)w * h * 3;
    const float *src = ggImagePixelsConst(img);
    float *dst;
    if (!q) return NULL;
    dst = ggImagePixels(q);
    for (k = 0; k < n; k++) {
        double c = src[k] != src[k] ? 0 : src[k] < 0 ? 0 : src[k] > 1 ? 1 : src[k];
        dst[k] = (float)ggSRGBToLinear(floor(ggLinearToSRGB(c) * 255 + 0.5) / 255);
    }
    return q;
}

static void test_golden_images(void **state)
{
    size_t i;
    int update = getenv("GG_UPDATE_GOLDEN") && *getenv("GG_UPDATE_GOLDEN") == '1';
    (void)state;
    for (i = 0; i < sizeof scenes / sizeof scenes[0]; i++) {
        char path[256], gold[256];
        const char *base = strrchr(scenes[i], '/') ? strrchr(scenes[i], '/') + 1 : scenes[i];
        ggScene *s = ggSceneCreate(NULL);
        ggRenderOptions o;
        ggImage *img = NULL, *ref = NULL, *q = NULL;
        ggError e;
        ggImageDiff d;
        ggCamera cam;
        snprintf(path, sizeof path, "examples/scenes/%s.nff", scenes[i]);
        snprintf(gold, sizeof gold, "tests/golden/%s.png", base);
        assert_int_equal(ggSceneLoadFile(s, path, &e), GG_OK);
        cam = ggSceneCamera(s);
        ggRenderOptionsDefault(&o);
        o.width = 64;
        o.height = 64 * cam.height / cam.width;
        o.threads = 2;
        assert_int_equal(ggRender(s, &o, &img, NULL, &e), GG_OK);
        if (update) {
            assert_int_equal(ggImageWritePNG(img, gold, &e), GG_OK);
            print_message("wrote %s\n", gold);
        }
        if (ggImageRead(gold, NULL, &ref, &e) != GG_OK) {
            print_error("%s\n", e.message);
            fail();
        }
        q = quantized(img);
        assert_non_null(q);
        assert_int_equal(ggImageCompare(q, ref, GG_COMPARE_SRGB, &d), GG_OK);
        print_message("%-8s rmse %.5f, %.3f%% of pixels over 1/255\n", base, d.rmse,
                      100 * d.frac_over);
        if (!(d.rmse <= 1.0 / 255 && d.frac_over <= 0.005))
            print_error("%s differs from %s beyond the tolerance\n", path, gold);
        assert_true(d.rmse <= 1.0 / 255);
        assert_true(d.frac_over <= 0.005);
        ggImageFree(img), ggImageFree(ref), ggImageFree(q);
        ggSceneFree(s);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_golden_images),
    };
    return cmocka_run_group_tests_name("golden", tests, NULL, NULL);
}
