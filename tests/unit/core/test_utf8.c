/* SPDX-License-Identifier: MIT */
/*
** test_utf8.c -- ggUTF8Length and ggUTF8Valid (RFC 3629), which the
** CLI's JSON writer calls instead of a copy of its own.
*/
#include "testutil.h"

#include <stdio.h>
#include <string.h>

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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_utf8_length),
        cmocka_unit_test(test_utf8_valid),
        cmocka_unit_test(test_utf8_exhaustive),
    };
    return cmocka_run_group_tests_name("utf8", tests, NULL, NULL);
}
