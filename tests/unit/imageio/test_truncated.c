/* SPDX-License-Identifier: MIT */
/*
** test_truncated.c -- truncated or short PNG and OpenEXR data is an error,
** never uninitialised memory. Every prefix of several
** files is read with glibc's malloc perturbation set to two different
** bytes (mallopt M_PERTURB fills each new block with it): a read either
** fails with GG_ERROR_PARSE, or gives exactly the pixels of the whole
** file both times, so no byte the file did not supply reaches an image.
** (tests/cli/t_truncated.sh runs the image fuzz corpus under valgrind.)
*/
#include "testutil.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#define HOSTILE "tests/data/hostile/"
#define CORPUS  "tests/fuzz/corpus/image/"

static void perturb(int byte)
{
#ifdef __GLIBC__
    mallopt(M_PERTURB, byte);
#else
    (void)byte;
#endif
}

static void spit(const char *path, const unsigned char *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, n, f), n);
    fclose(f);
}

static int same_pixels(const ggImage *a, const ggImage *b)
{
    size_t n = (size_t)ggImageWidth(a) * (size_t)ggImageHeight(a) * 3;
    return ggImageWidth(a) == ggImageWidth(b) && ggImageHeight(a) == ggImageHeight(b) &&
           memcmp(ggImagePixelsConst(a), ggImagePixelsConst(b), n * sizeof(float)) == 0;
}

/* Every prefix of path (the file cut shorter and shorter: every byte of
   the first 600, every 37th beyond): an error or the whole file's pixels,
   under two malloc perturbations. Returns how many prefixes failed. */
static int check_prefixes(const char *path)
{
    char tmp[] = "/tmp/gg_trunc_XXXXXX";
    size_t n, cut;
    unsigned char *data = (unsigned char *)tu_slurp(path, &n);
    ggImage *whole = NULL;
    ggError e;
    int fd = mkstemp(tmp), errors = 0;
    assert_true(fd >= 0);
    close(fd);
    assert_int_equal(ggImageRead(path, NULL, &whole, &e), GG_OK);
    spit(tmp, data, n);
    for (cut = n; cut-- > 0;) {
        int pass;
        if (cut >= 600 && cut % 37) continue;
        assert_int_equal(truncate(tmp, (off_t)cut), 0);
        for (pass = 0; pass < 2; pass++) {
            ggImage *img = NULL;
            int rc;
            perturb(pass ? 0xA5 : 0x5A);
            rc = ggImageRead(tmp, NULL, &img, &e);
            perturb(0);
            if (rc == GG_OK && !same_pixels(img, whole))
                fail_msg("%s cut to %zu bytes: read as an image unlike the whole file's", path,
                         cut);
            if (rc != GG_OK && rc != GG_ERROR_PARSE && rc != GG_ERROR_UNSUPPORTED)
                fail_msg("%s cut to %zu bytes: code %d (%s)", path, cut, rc, e.message);
            errors += rc != GG_OK && pass == 0;
            ggImageFree(img);
        }
    }
    unlink(tmp);
    ggImageFree(whole);
    free(data);
    return errors;
}

static void test_short_uncompressed_exr_chunk(void **state)
{
    ggImage *img = NULL;
    ggError e;
    (void)state;
    assert_int_equal(ggImageRead(HOSTILE "short.exr", NULL, &img, &e), GG_ERROR_PARSE);
    assert_string_equal(e.message, HOSTILE "short.exr: invalid OpenEXR file: chunk 1 holds 20 "
                                           "bytes, its pixels take 48");
    assert_null(img);
    /* The size field says 48 but the file ends after 20 of them. */
    assert_int_equal(ggImageRead(HOSTILE "short2.exr", NULL, &img, &e), GG_ERROR_PARSE);
    assert_null(img);
}

static void test_exr_prefixes(void **state)
{
    static const char *const files[] = {CORPUS "float_zip.exr",   CORPUS "half_tiled.exr",
                                        CORPUS "uint_rle.exr",    CORPUS "y_piz.exr",
                                        CORPUS "float_pxr24.exr", CORPUS "half_b44.exr"};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof files / sizeof files[0]; i++) assert_true(check_prefixes(files[i]) > 0);
}

static void test_png_prefixes(void **state)
{
    static const char *const files[] = {CORPUS "rgb8.png", CORPUS "palette.png", CORPUS "ga16.png",
                                        HOSTILE "tex1m.png"};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof files / sizeof files[0]; i++) assert_true(check_prefixes(files[i]) > 0);
}

/* An uncompressed EXR (hostile.py), cut inside each chunk, and one of
   our own writing (ZIP). */
static void test_written_exr_prefixes(void **state)
{
    char path[] = "/tmp/gg_trunc_src_XXXXXX";
    ggImage *img = ggImageCreate(7, 5, NULL);
    ggError e;
    int fd = mkstemp(path), i;
    (void)state;
    assert_true(check_prefixes(HOSTILE "plain.exr") > 0);
    assert_true(fd >= 0);
    close(fd);
    for (i = 0; i < 7 * 5 * 3; i++) ggImagePixels(img)[i] = (float)i / 8.0f;
    assert_int_equal(ggImageWriteEXR(img, path, &e), GG_OK);
    assert_true(check_prefixes(path) > 0);
    unlink(path);
    ggImageFree(img);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_short_uncompressed_exr_chunk),
        cmocka_unit_test(test_exr_prefixes),
        cmocka_unit_test(test_png_prefixes),
        cmocka_unit_test(test_written_exr_prefixes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
