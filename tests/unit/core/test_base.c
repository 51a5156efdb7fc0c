/* SPDX-License-Identifier: MIT */
/*
** test_base.c -- version, status strings, errors, allocation helpers.
*/
#include "testutil.h"

#include "core.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void test_version(void **state)
{
    (void)state;
    assert_string_equal(ggVersion(), GG_VERSION_STRING);
}

/* "src-" and the cksum the Makefile computed: decimal digits, the same
   pointer and text on every call. */
static void test_build_id(void **state)
{
    const char *id = ggBuildId();
    size_t n;
    (void)state;
    assert_non_null(id);
    assert_int_equal(strncmp(id, "src-", 4), 0);
    n = strlen(id + 4);
    assert_true(n >= 1 && n <= 10);
    assert_int_equal(strspn(id + 4, "0123456789"), n);
    assert_ptr_equal(ggBuildId(), id);
}

static void test_status_strings(void **state)
{
    int c;
    (void)state;
    for (c = GG_OK; c <= GG_ERROR_CANCELLED; c++) {
        assert_non_null(ggStatusString(c));
        assert_string_not_equal(ggStatusString(c), "unknown status code");
    }
    assert_string_equal(ggStatusString(999), "unknown status code");
}

static void test_error_set(void **state)
{
    ggError e;
    (void)state;
    assert_int_equal(gg_error_set(&e, GG_ERROR_PARSE, "%s:%d:%d: bad", "f.nff", 12, 5),
                     GG_ERROR_PARSE);
    assert_int_equal(e.code, GG_ERROR_PARSE);
    assert_string_equal(e.message, "f.nff:12:5: bad");
    assert_int_equal(gg_error_set(NULL, GG_ERROR_IO, "x"), GG_ERROR_IO);
}

static int counted_allocs;
static void *c_malloc(void *ud, size_t n)
{
    (void)ud;
    counted_allocs++;
    return malloc(n);
}
static void *c_realloc(void *ud, void *p, size_t n)
{
    (void)ud;
    if (!p) counted_allocs++;
    return realloc(p, n);
}
static void c_free(void *ud, void *p)
{
    (void)ud;
    if (p) counted_allocs--;
    free(p);
}

static void test_grow_with_allocator(void **state)
{
    ggAllocator a = {c_malloc, c_realloc, c_free, NULL};
    int *arr = NULL;
    size_t cap = 0, i;
    (void)state;
    for (i = 0; i < 1000; i++) {
        assert_int_equal(gg_mem_grow(&a, (void **)&arr, &cap, i + 1, sizeof *arr), 0);
        arr[i] = (int)i;
    }
    assert_true(cap >= 1000);
    for (i = 0; i < 1000; i++) assert_int_equal(arr[i], (int)i);
    assert_int_equal(counted_allocs, 1);
    gg_mem_free(&a, arr);
    assert_int_equal(counted_allocs, 0);
    /* Overflow is refused, not wrapped. */
    arr = NULL, cap = 0;
    assert_int_equal(gg_mem_grow(&a, (void **)&arr, &cap, (size_t)-1 / 2, 16), -1);
    assert_null(arr);
    assert_null(gg_mem_calloc(NULL, (size_t)-1 / 2, 4));
}

/* Blocks of 4 MB and more from the C library carry a huge-page hint
   (base.c, huge_hint) over their 2 MB-aligned interior: it must not change
   what they hold, at either end or across a realloc that moves them. */
static void test_large_blocks(void **state)
{
    const size_t n = ((size_t)9 << 20) + 3, m = ((size_t)21 << 20) + 5;
    unsigned char *p, *q;
    size_t i;
    (void)state;
    p = gg_mem_calloc(NULL, n, 1);
    assert_non_null(p);
    for (i = 0; i < n; i += 4093) assert_int_equal(p[i], 0);
    assert_int_equal(p[n - 1], 0);
    for (i = 0; i < n; i++) p[i] = (unsigned char)(i * 7 + 1);
    q = gg_mem_realloc(NULL, p, m);
    assert_non_null(q);
    for (i = 0; i < n; i++)
        if (q[i] != (unsigned char)(i * 7 + 1)) fail_msg("byte %zu changed by the realloc", i);
    memset(q + n, 0x5a, m - n);
    assert_int_equal(q[m - 1], 0x5a);
    gg_mem_free(NULL, q);
    p = gg_mem_alloc(NULL, (size_t)5 << 20);
    assert_non_null(p);
    memset(p, 0xa5, (size_t)5 << 20);
    assert_int_equal(p[((size_t)5 << 20) - 1], 0xa5);
    gg_mem_free(NULL, p);
}

static void test_ulps(void **state)
{
    (void)state;
    assert_true(tu_ulps(1.0, 1.0) == 0);
    assert_true(tu_ulps(1.0, 1.0 + 0x1p-52) == 1);
    assert_true(tu_ulps(-0.0, 0.0) == 0);
    assert_true(tu_ulps(0x1p-1074, -0x1p-1074) == 2);
}

/* Hash tables keyed by a file's contents are seeded per table
   (core.h): keys prepared to share the low bits of one table's hash --
   what made an OBJ load quadratically -- do not share them in another.
   Of 2^20 keys (OBJ corners, and strings), the ~1000 whose hash under
   seed A is 0 in its low 10 bits spread out under seed B; unseeded, all
   of them would collide again. Two tables get different seeds. */
static void test_hash_seeded(void **state)
{
    char a_mem = 0, b_mem = 0;
    uint64_t sa = gg_hash_seed(&a_mem), sb = gg_hash_seed(&b_mem);
    uint32_t k;
    int picked = 0, again = 0, spicked = 0, sagain = 0;
    (void)state;
    assert_true(sa != sb);
    for (k = 1; k <= 1u << 20; k++) {
        uint64_t w = (uint64_t)k | (uint64_t)(k * 7u) << 32;
        char name[16];
        size_t n = (size_t)snprintf(name, sizeof name, "g%x", k);
        if ((gg_hash_word(gg_hash_word(sa, w), k) & 1023) == 0) {
            picked++;
            again += (gg_hash_word(gg_hash_word(sb, w), k) & 1023) == 0;
        }
        if ((gg_hash_bytes(sa, name, n) & 1023) == 0) {
            spicked++;
            sagain += (gg_hash_bytes(sb, name, n) & 1023) == 0;
        }
    }
    print_message("words: %d picked, %d collide again; strings: %d, %d\n", picked, again, spicked,
                  sagain);
    assert_true(picked > 800 && picked < 1300 && spicked > 800 && spicked < 1300);
    assert_true(again < 10 && sagain < 10);
    /* a string's hash depends on every byte and on its length */
    assert_true(gg_hash_bytes(sa, "abc", 3) != gg_hash_bytes(sa, "abd", 3));
    assert_true(gg_hash_bytes(sa, "abc", 3) != gg_hash_bytes(sa, "abc\0", 4));
    assert_true(gg_hash_bytes(sa, "abcdefghi", 9) != gg_hash_bytes(sa, "abcdefghj", 9));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_version),
        cmocka_unit_test(test_build_id),
        cmocka_unit_test(test_status_strings),
        cmocka_unit_test(test_error_set),
        cmocka_unit_test(test_grow_with_allocator),
        cmocka_unit_test(test_large_blocks),
        cmocka_unit_test(test_ulps),
        cmocka_unit_test(test_hash_seeded),
    };
    return cmocka_run_group_tests_name("base", tests, NULL, NULL);
}
