/* SPDX-License-Identifier: MIT */
/*
** test_encode.c -- the public encoders the CLI calls instead of copying
** them: ggUTF8Length and ggUTF8Valid (RFC 3629), ggLinearToSRGB8 (the
** bytes of ggImageWritePNG).
*/
#include "testutil.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* len(s) over the whole string, without its NUL. */
static int ulen(const char *s)
{
    return ggUTF8Length(s, strlen(s));
}

static void test_utf8_length(void **state)
{
    (void)state;
    assert_int_equal(ulen("a"), 1);
    assert_int_equal(ggUTF8Length("\0x", 2), 1);   /* NUL is one byte */
    assert_int_equal(ulen("\xc3\xa9"), 2);         /* U+00E9 */
    assert_int_equal(ulen("\xe2\x82\xac"), 3);     /* U+20AC */
    assert_int_equal(ulen("\xf0\x9f\x98\x80"), 4); /* U+1F600 */
    assert_int_equal(ulen("\xf4\x8f\xbf\xbf"), 4); /* U+10FFFF, the last */
    /* Not well-formed: a stray continuation, overlong forms, surrogates,
       above U+10FFFF, bytes that never occur. */
    assert_int_equal(ulen("\x80"), 0);
    assert_int_equal(ulen("\xc0\xaf"), 0);
    assert_int_equal(ulen("\xc1\xbf"), 0);
    assert_int_equal(ulen("\xe0\x9f\xbf"), 0);
    assert_int_equal(ulen("\xf0\x8f\xbf\xbf"), 0);
    assert_int_equal(ulen("\xed\xa0\x80"), 0); /* U+D800 */
    assert_int_equal(ulen("\xed\xbf\xbf"), 0); /* U+DFFF */
    assert_int_equal(ulen("\xf4\x90\x80\x80"), 0);
    assert_int_equal(ulen("\xf5\x80\x80\x80"), 0);
    assert_int_equal(ulen("\xfe"), 0);
    assert_int_equal(ulen("\xff"), 0);
    /* Cut short: by a byte that is not a continuation, or by n. */
    assert_int_equal(ulen("\xe2\x82x"), 0);
    assert_int_equal(ggUTF8Length("\xe2\x82\xac", 2), 0);
    assert_int_equal(ggUTF8Length("\xf0\x9f\x98\x80", 3), 0);
    assert_int_equal(ggUTF8Length("a", 0), 0);
}

static void test_utf8_valid(void **state)
{
    (void)state;
    assert_true(ggUTF8Valid("", 0));
    assert_true(ggUTF8Valid("x", 0)); /* n bytes only */
    assert_true(ggUTF8Valid("caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80", 14));
    assert_false(ggUTF8Valid("caf\xc3", 4));        /* cut in the middle */
    assert_true(ggUTF8Valid("caf\xc3\xa9", 3));     /* the n bytes are whole */
    assert_false(ggUTF8Valid("ok\xed\xa0\x80", 5)); /* a surrogate */
    assert_false(ggUTF8Valid("ok\xff", 3));
    assert_true(ggUTF8Valid("a\0b", 3)); /* NUL is UTF-8 */
}

/* Every byte sequence of one to three bytes whose first byte is each
   value: ggUTF8Length agrees with a decoder written from RFC 3629's
   table of code points. */
static int decode_len(const unsigned char *s, size_t n)
{
    unsigned long cp;
    int k, i;
    if (!n) return 0;
    if (s[0] < 0x80) return 1;
    if ((s[0] & 0xe0) == 0xc0)
        k = 2, cp = s[0] & 0x1f;
    else if ((s[0] & 0xf0) == 0xe0)
        k = 3, cp = s[0] & 0x0f;
    else if ((s[0] & 0xf8) == 0xf0)
        k = 4, cp = s[0] & 0x07;
    else
        return 0;
    if ((size_t)k > n) return 0;
    for (i = 1; i < k; i++) {
        if ((s[i] & 0xc0) != 0x80) return 0;
        cp = cp << 6 | (s[i] & 0x3f);
    }
    if ((k == 2 && cp < 0x80) || (k == 3 && cp < 0x800) || (k == 4 && cp < 0x10000)) return 0;
    if ((cp >= 0xd800 && cp <= 0xdfff) || cp > 0x10ffff) return 0;
    return k;
}

static void test_utf8_exhaustive(void **state)
{
    unsigned a, b, c;
    (void)state;
    for (a = 0; a < 256; a++)
        for (b = 0; b < 256; b++)
            for (c = 0x80; c < 0xc0; c += 0x3f) {
                unsigned char s[4] = {(unsigned char)a, (unsigned char)b, (unsigned char)c, 0x80};
                size_t n;
                for (n = 1; n <= 4; n++)
                    if (ggUTF8Length((const char *)s, n) != decode_len(s, n)) {
                        print_error("%02x %02x %02x 80, n %zu: %d, want %d\n", a, b, c, n,
                                    ggUTF8Length((const char *)s, n), decode_len(s, n));
                        fail();
                    }
            }
}

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
    snprintf(path, sizeof path, "/tmp/test_encode_%ld.png", (long)getpid());
    assert_int_equal(ggImageWritePNG(img, path, NULL), GG_OK);
    assert_int_equal(ggImageRead(path, NULL, &back, NULL), GG_OK);
    unlink(path);
    ggLinearToSRGB8(ggImagePixels(back), got, N);
    assert_memory_equal(want, got, N);
    ggImageFree(img);
    ggImageFree(back);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_utf8_length),     cmocka_unit_test(test_utf8_valid),
        cmocka_unit_test(test_utf8_exhaustive), cmocka_unit_test(test_srgb8_levels),
        cmocka_unit_test(test_srgb8_rounding),  cmocka_unit_test(test_srgb8_is_png),
    };
    return cmocka_run_group_tests_name("encode", tests, NULL, NULL);
}
