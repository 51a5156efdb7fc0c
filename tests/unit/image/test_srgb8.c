/* SPDX-License-Identifier: MIT */
/*
** test_srgb8.c -- ggLinearToSRGB8, the bytes of ggImageWritePNG, which
** ggrt serve's PNG encoder calls instead of a copy of its own.
*/
#include "testutil.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void test_srgb8_levels(void **state)
{
    float in[6] = {0.0f, -1.0f, NAN, 1.0f, 2.0f, INFINITY};
    unsigned char out[6];
    int k;
    (void)state;
    ggLinearToSRGB8(in, out, 6);
    assert_int_equal(out[0], 0);
    assert_int_equal(out[1], 0);
    assert_int_equal(out[2], 0);
    assert_int_equal(out[3], 255);
    assert_int_equal(out[4], 255);
    assert_int_equal(out[5], 255);
    /* Each level k decodes and encodes back to k; values a little either
       side of its midpoints with the level rounding to them. */
    for (k = 0; k < 256; k++) {
        float v[3];
        unsigned char b[3];
        v[0] = (float)ggSRGBToLinear(k / 255.0);
        v[1] = (float)ggSRGBToLinear((k - 0.45) / 255.0);
        v[2] = (float)ggSRGBToLinear((k + 0.45) / 255.0);
        ggLinearToSRGB8(v, b, 3);
        assert_int_equal(b[0], k);
        assert_int_equal(b[1], k == 0 ? 0 : k);
        assert_int_equal(b[2], k);
    }
}

/* Away from the midpoints the bytes are round(255 * ggLinearToSRGB(c)). */
static void test_srgb8_rounding(void **state)
{
    unsigned seed = 12345;
    int i;
    (void)state;
    for (i = 0; i < 100000; i++) {
        float v;
        unsigned char b;
        double s, frac;
        seed = seed * 1103515245u + 12345u;
        v = (float)((seed >> 8) / 16777216.0);
        s = 255.0 * ggLinearToSRGB(v);
        frac = s - floor(s);
        if (fabs(frac - 0.5) < 1e-6) continue; /* the exact midpoint decides */
        ggLinearToSRGB8(&v, &b, 1);
        assert_int_equal(b, (int)floor(s + 0.5));
    }
}

/* ggImageWritePNG writes the bytes ggLinearToSRGB8 gives: the PNG read
   back (each byte decoded to linear) encodes to the same bytes. */
static void test_srgb8_is_png(void **state)
{
    enum { W = 64, H = 8, N = W * H * 3 };
    ggImage *img = ggImageCreate(W, H, NULL), *back = NULL;
    unsigned char want[N], got[N];
    char path[64];
    float *px;
    int i;
    (void)state;
    assert_non_null(img);
    px = ggImagePixels(img);
    for (i = 0; i < N; i++) px[i] = (float)(i % 301) / 280.0f - 0.05f;
    px[5] = NAN;
    ggLinearToSRGB8(px, want, N);
    snprintf(path, sizeof path, "/tmp/test_srgb8_%ld.png", (long)getpid());
    assert_int_equal(ggImageWritePNG(img, path, NULL), GG_OK);
    assert_int_equal(ggImageRead(path, NULL, &back, NULL), GG_OK);
    unlink(path);
    ggLinearToSRGB8(ggImagePixels(back), got, N);
    assert_memory_equal(want, got, N);
    ggImageFree(img);
    ggImageFree(back);
}

/* Every float from 2^-16 to 2 (and a stride through the rest of the
   32-bit patterns: negative, tiny, huge, infinite, NaN) encodes to the
   largest level whose midpoint is <= it, found here by a plain search of
   the midpoints as the contract states them. */
static int level_of(const double thr[256], float v)
{
    double c = v;
    int k = 0;
    if (!(c > 0.0)) return 0;
    while (k < 255 && thr[k + 1] <= c) k++;
    return k;
}

/* ggLinearToSRGB8 on the bit patterns from, from + stride, ... below to;
   with `rising` the patterns are positive floats in increasing order, so
   the expected level only grows and is found by stepping on from the
   last one. */
static void check_range(const double thr[256], uint32_t from, uint32_t to, uint32_t stride,
                        int rising)
{
    enum { CHUNK = 1 << 16 };
    static float in[CHUNK];
    static unsigned char out[CHUNK];
    uint64_t u = from;
    int want = 0;
    while (u < to) {
        size_t n = 0, i;
        for (; n < CHUNK && u < to; n++, u += stride) {
            uint32_t b = (uint32_t)u;
            memcpy(&in[n], &b, sizeof b);
        }
        ggLinearToSRGB8(in, out, n);
        for (i = 0; i < n; i++) {
            if (!rising)
                want = level_of(thr, in[i]);
            else
                while (want < 255 && thr[want + 1] <= in[i]) want++;
            if (out[i] != want) fail_msg("%a: %d, want %d", (double)in[i], out[i], want);
        }
    }
}

static void test_srgb8_every_float(void **state)
{
    double thr[256];
    int k;
    (void)state;
    thr[0] = 0.0;
    for (k = 1; k < 256; k++) thr[k] = ggSRGBToLinear((k - 0.5) / 255.0);
    check_range(thr, 0x37800000u, 0x40000000u, 1, 1); /* 2^-16 .. 2, every one */
    check_range(thr, 0x00000000u, 0x37800000u, 4093, 0);
    check_range(thr, 0x40000000u, 0xffffffffu, 4093, 0);
    /* the floats nearest each midpoint, either side */
    for (k = 1; k < 256; k++) {
        float m = (float)thr[k];
        uint32_t b;
        memcpy(&b, &m, sizeof b);
        check_range(thr, b - 64, b + 64, 1, 0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_srgb8_levels),
        cmocka_unit_test(test_srgb8_rounding),
        cmocka_unit_test(test_srgb8_is_png),
        cmocka_unit_test(test_srgb8_every_float),
    };
    return cmocka_run_group_tests_name("srgb8", tests, NULL, NULL);
}
