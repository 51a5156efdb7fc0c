/* SPDX-License-Identifier: MIT */
/*
** test_numbers.c -- gg_parse_number, the decimal reader of NFF, OBJ, MTL
** and ascii PLY, gives strtod's double to the bit wherever both read a
** decimal number, and refuses what it should: random decimals over the
** whole range of doubles (1 to 25 significant digits, exponents from
** -400 to +400, subnormals and overflow included), every double's
** shortest and 17-digit forms near rounding boundaries, the corner
** strings, and every token of every scene and model file in the repo.
*/
#include "testutil.h"

#include "mesh_int.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Bits equal (so -0 differs from 0). */
static int same_bits(double a, double b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

/* Whether s is what gg_parse_number reads: sign, digits with at most one
   point, at least one digit, an optional exponent with digits. */
static int decimal_syntax(const char *s)
{
    int dig = 0;
    if (*s == '+' || *s == '-') s++;
    for (; *s >= '0' && *s <= '9'; s++) dig = 1;
    if (*s == '.')
        for (s++; *s >= '0' && *s <= '9'; s++) dig = 1;
    if (!dig) return 0;
    if (*s == 'e' || *s == 'E') {
        s++;
        if (*s == '+' || *s == '-') s++;
        if (!(*s >= '0' && *s <= '9')) return 0;
        while (*s >= '0' && *s <= '9') s++;
    }
    return *s == '\0';
}

/* Check one string against strtod; returns 1 if it was a number. */
static int check(const char *s)
{
    size_t n = strlen(s);
    const char *end;
    char *e;
    double want = strtod(s, &e), got = 0;
    int ok = e == s + n && n > 0 && isfinite(want) && decimal_syntax(s);
    end = gg_parse_number(s, s + n, &got);
    if (ok) {
        if (end != s + n || !same_bits(got, want))
            fail_msg("'%s': gg_parse_number %s %.17g, strtod %.17g", s, end ? "read" : "refused",
                     got, want);
    } else if (end == s + n) {
        fail_msg("'%s': gg_parse_number read %.17g, strtod does not (or not finite)", s, got);
    }
    return ok;
}

static void test_corners(void **state)
{
    static const char *const s[] = {
        "0", "-0", "+0", "0.0", "-0.0", "1", "-1", "1.", ".5", "-.5", "+.5", "1e5", "1E5", "1e+5",
        "1e-5", "1.5e300", "0.1", "0.3", "123456789012345678", "9007199254740992",
        "9007199254740993", "9007199254740995", "4.9e-324", "2.4703282292062327e-324",
        "2.4703282292062328e-324", "2.2250738585072011e-308", "2.2250738585072014e-308",
        "1.7976931348623157e308", "1.7976931348623158e308", "1.7976931348623159e308", "1e309",
        "-1e309", "1e-400", "-1e-400", "1e100000000", "1e-100000000", "0e999999",
        "000000000000000000000000000001", "1.000000000000000000000000000001",
        "0.000000000000000000000000000000000000000000000000000000000000000001", "1e22", "1e23",
        "8.98846567431158e307", "123.456e-2", "7.", "1e0005",
        /* refused by both, or by gg_parse_number's syntax */
        "", "+", "-", ".", "e5", "1e", "1e+", "1e-", "--1", "+-1", "1..2", "1.2.3", "1e5.5",
        "nan", "inf", "-inf", "infinity", "0x10", "0x1p3", " 1", "1 ", "1f", "1d5", "1,5"};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof s / sizeof *s; i++) check(s[i]);
}

/* Random decimals: the digits, the point and the exponent drawn so that
   every order of magnitude of double (and beyond it, both ways) comes up,
   with short mantissas (Clinger's fast path) and long ones (strtod). */
static void test_random(void **state)
{
    tu_rng r = {0x5eed0f7e57ull};
    char s[80];
    long i, numbers = 0;
    (void)state;
    for (i = 0; i < 300000; i++) {
        int nd = 1 + (int)(tu_next(&r) % (tu_next(&r) % 2 ? 16 : 25)), pt = -1, k, n = 0;
        long ex;
        if (tu_next(&r) % 4 == 0) s[n++] = tu_next(&r) % 2 ? '-' : '+';
        if (tu_next(&r) % 2) pt = (int)(tu_next(&r) % (unsigned)(nd + 1));
        for (k = 0; k < nd; k++) {
            if (k == pt) s[n++] = '.';
            s[n++] = (char)('0' + tu_next(&r) % 10);
        }
        if (pt == nd) s[n++] = '.';
        switch (tu_next(&r) % 4) {
        case 0: /* none */
            break;
        case 1: /* small: the fast path's range */
            n += sprintf(s + n, "e%ld", (long)(tu_next(&r) % 45) - 22);
            break;
        default: /* anywhere, past both ends of double */
            ex = (long)(tu_next(&r) % 801) - 400;
            n += sprintf(s + n, tu_next(&r) % 2 ? "E%+ld" : "e%ld", ex);
            break;
        }
        s[n] = '\0';
        numbers += check(s);
    }
    /* most drawn strings are numbers, so the comparison above is not idle */
    assert_true(numbers > 250000);
}

/* Doubles printed shortest-ish and in full: near every rounding
   boundary, from subnormals to the largest. */
static void test_printed(void **state)
{
    tu_rng r = {0xdecafbadull};
    char s[512]; /* "%.20f" of the largest double: 330 characters */
    long i;
    (void)state;
    for (i = 0; i < 100000; i++) {
        uint64_t u = tu_next(&r) & 0x7fefffffffffffffull;
        double d;
        memcpy(&d, &u, sizeof d);
        if (tu_next(&r) % 2) d = -d;
        snprintf(s, sizeof s, "%.17g", d), check(s);
        snprintf(s, sizeof s, "%.15g", d), check(s);
        snprintf(s, sizeof s, "%.6e", d), check(s);
        snprintf(s, sizeof s, "%.20f", d), check(s);
    }
}

/* Every space-separated token of file path; returns the count read as
   numbers. */
static long check_file(const char *path)
{
    size_t len;
    char *text = tu_slurp(path, &len), *p = text, tok[80];
    long numbers = 0;
    while (*p) {
        size_t n = strcspn(p, " \t\r\n\f\v/");
        if (n > 0 && n < sizeof tok) {
            memcpy(tok, p, n), tok[n] = '\0';
            numbers += check(tok);
        }
        p += n;
        if (*p) p++;
    }
    free(text);
    return numbers;
}

/* tu_each_file's callback: adds the file's numbers to *(long *)ud. */
static void check_one(const char *path, void *ud)
{
    *(long *)ud += check_file(path);
}

/* The repo's scenes and models, token by token (OBJ's a/b/c split at
   the slashes). */
static void test_files(void **state)
{
    long n = 0;
    (void)state;
    tu_each_file("examples/scenes", ".nff", check_one, &n);
    tu_each_file("examples/scenes/spd", ".nff", check_one, &n);
    tu_each_file("examples/scenes/models", ".obj", check_one, &n);
    tu_each_file("tests/data", ".nff", check_one, &n);
    tu_each_file("tests/data/meshes", ".obj", check_one, &n);
    tu_each_file("tests/data/meshes", ".ply", check_one, &n);
    assert_true(n > 100000); /* the SPD scenes alone hold far more */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_corners),
        cmocka_unit_test(test_random),
        cmocka_unit_test(test_printed),
        cmocka_unit_test(test_files),
    };
    return cmocka_run_group_tests_name("numbers", tests, NULL, NULL);
}
