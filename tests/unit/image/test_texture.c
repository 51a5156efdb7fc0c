/* SPDX-License-Identifier: MIT */
/*
** test_texture.c -- ggTextureBilinear against its formula (ggrt/image.h), nearest
** texel, wrap modes, edge cases, and the procedural checker.
*/
#include "testutil.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static ggImage *image_of(int w, int h, const float *rgb)
{
    ggImage *img = ggImageCreate(w, h, NULL);
    size_t i;
    assert_non_null(img);
    for (i = 0; i < (size_t)w * (size_t)h * 3; i++) ggImagePixels(img)[i] = rgb[i];
    return img;
}

static ggImage *random_image(int w, int h, tu_rng *r, double lo, double hi)
{
    ggImage *img = ggImageCreate(w, h, NULL);
    size_t i;
    for (i = 0; i < (size_t)w * (size_t)h * 3; i++)
        ggImagePixels(img)[i] = (float)tu_range(r, lo, hi);
    return img;
}

#define assert_color_eq(c, R, G, B)                                                                \
    do {                                                                                           \
        ggColor c_ = (c);                                                                          \
        assert_close(c_.r, (R), 1e-12);                                                            \
        assert_close(c_.g, (G), 1e-12);                                                            \
        assert_close(c_.b, (B), 1e-12);                                                            \
    } while (0)

/* A worked example of the formula: u = v = 0.5 gives u_p = 0, v_p = 0.5 and
   Color = C00 (1)(0.5) + C01 (1)(0.5) = (C00 + C01) / 2. With
   d_i = (w - 1) u that happens for an odd width and an even height; a
   3 x 2 texture is the smallest. */
static void test_notes_worked_example(void **state)
{
    /* Rows from the top; C00 = (i, j) = (1, 0), C01 = (1, 1). */
    const float px[] = {9, 9, 9, 0.2f, 0.4f, 0.6f, 9, 9, 9, 9, 9, 9, 0.6f, 0.8f, 1.0f, 9, 9, 9};
    ggImage *img = image_of(3, 2, px);
    ggColor c = ggTextureBilinear(img, 0.5, 0.5, GG_WRAP_CLAMP);
    (void)state;
    assert_close(c.r, (0.2f + 0.6f) / 2.0, 1e-7);
    assert_close(c.g, (0.4f + 0.8f) / 2.0, 1e-7);
    assert_close(c.b, (0.6f + 1.0f) / 2.0, 1e-7);
    ggImageFree(img);
}

/* On a 2 x 2 texture the same (0.5, 0.5) has u_p = v_p = 0.5: every texel
   weighs 1/4. Off-centre points weigh them as the formula says. */
static void test_two_by_two(void **state)
{
    const float px[] = {0.0f, 0.1f, 0.2f, 0.4f, 0.5f, 0.6f,  /* top: C00, C10 */
                        0.8f, 0.2f, 0.0f, 0.2f, 0.2f, 0.2f}; /* bottom: C01, C11 */
    ggImage *img = image_of(2, 2, px);
    ggColor c;
    double up = 0.25, vp = 0.75;
    (void)state;
    c = ggTextureBilinear(img, 0.5, 0.5, GG_WRAP_CLAMP);
    assert_close(c.r, (0.0f + 0.4f + 0.8f + 0.2f) / 4.0, 1e-7);
    assert_close(c.g, (0.1f + 0.5f + 0.2f + 0.2f) / 4.0, 1e-7);
    assert_close(c.b, (0.2f + 0.6f + 0.0f + 0.2f) / 4.0, 1e-7);
    c = ggTextureBilinear(img, up, vp, GG_WRAP_CLAMP);
    assert_close(c.r,
                 0.0f * (1 - up) * (1 - vp) + 0.8f * (1 - up) * vp + 0.4f * up * (1 - vp) +
                     0.2f * up * vp,
                 1e-7);
    ggImageFree(img);
}

/* Corners and texel positions return exact texels, for any size. */
static void test_exact_texels(void **state)
{
    tu_rng r = {1};
    static const int sizes[][2] = {{1, 1}, {1, 7}, {6, 1}, {5, 4}, {17, 9}};
    size_t s;
    (void)state;
    for (s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        int w = sizes[s][0], h = sizes[s][1], i, j;
        ggImage *img = random_image(w, h, &r, 0.0, 1.0);
        for (j = 0; j < h; j++)
            for (i = 0; i < w; i++) {
                double u = w > 1 ? (double)i / (w - 1) : 0.5;
                double v = h > 1 ? (double)j / (h - 1) : 0.5;
                ggColor t = ggImageGet(img, i, j), b, n;
                /* i / (w - 1) * (w - 1) can land a hair under i: the blend
                   then is within rounding of the texel. */
                b = ggTextureBilinear(img, u, v, GG_WRAP_CLAMP);
                n = ggTextureNearest(img, u, v, GG_WRAP_CLAMP);
                assert_close(b.r, t.r, 1e-12);
                assert_close(b.b, t.b, 1e-12);
                assert_color_eq(n, t.r, t.g, t.b);
            }
        /* The four corners are exact to the bit. */
        {
            ggColor c;
            c = ggTextureBilinear(img, 0, 0, GG_WRAP_REPEAT);
            assert_true(c.g == ggImageGet(img, 0, 0).g);
            c = ggTextureBilinear(img, 1, 0, GG_WRAP_REPEAT);
            assert_true(c.g == ggImageGet(img, w - 1, 0).g);
            c = ggTextureBilinear(img, 0, 1, GG_WRAP_REPEAT);
            assert_true(c.g == ggImageGet(img, 0, h - 1).g);
            c = ggTextureBilinear(img, 1, 1, GG_WRAP_REPEAT);
            assert_true(c.g == ggImageGet(img, w - 1, h - 1).g);
        }
        ggImageFree(img);
    }
}

/* An allocator that follows every block with NaNs: a texel read past the
   pixels, even with weight 0, turns the blend NaN, which reads 0. (The
   sanitized run would also catch it.) */
static void *nan_malloc(void *ud, size_t n)
{
    float *p = malloc(n + 16 * sizeof(float));
    size_t i;
    (void)ud;
    for (i = 0; i < 16; i++) memcpy((char *)p + n + i * sizeof(float), &(float){NAN}, 4);
    return p;
}
static void *nan_realloc(void *ud, void *p, size_t n)
{
    (void)ud;
    return realloc(p, n);
}
static void nan_free(void *ud, void *p)
{
    (void)ud;
    free(p);
}
static const ggAllocator nan_alloc = {nan_malloc, nan_realloc, nan_free, NULL};

static ggImage *guarded_image(int w, int h, const float *rgb)
{
    ggImage *img = ggImageCreate(w, h, &nan_alloc);
    memcpy(ggImagePixels(img), rgb, sizeof(float) * 3 * (size_t)w * (size_t)h);
    return img;
}

/* u = 1 and v = 1 read the last texel, never past it. A 1-pixel-wide
   image is the sharpest case: i + 1 must be clamped. */
static void test_edges_never_read_past(void **state)
{
    const float one[] = {0.25f, 0.5f, 0.75f};
    const float col[] = {0.1f, 0.1f, 0.1f, 0.2f, 0.2f, 0.2f, 0.3f, 0.3f, 0.3f};
    /* 2 x 2 with NaN in the bottom-left texel: reading "i + 1" past the
       top row's end would land on it. */
    const float nan2[] = {0.1f, 0.1f, 0.1f, 0.2f, 0.2f, 0.2f, NAN, NAN, NAN, 0.4f, 0.4f, 0.4f};
    ggImage *img = guarded_image(1, 1, one), *tall = guarded_image(1, 3, col);
    ggImage *wide = guarded_image(3, 1, col), *sq = guarded_image(2, 2, nan2);
    double us[] = {0.0, 0.3, 0.999999, 1.0};
    size_t a, b;
    (void)state;
    for (a = 0; a < 4; a++)
        for (b = 0; b < 4; b++) {
            assert_color_eq(ggTextureBilinear(img, us[a], us[b], GG_WRAP_CLAMP), 0.25, 0.5, 0.75);
            assert_color_eq(ggTextureNearest(img, us[a], us[b], GG_WRAP_REPEAT), 0.25, 0.5, 0.75);
        }
    assert_close(ggTextureBilinear(tall, 0.7, 1.0, GG_WRAP_CLAMP).r, 0.3f, 1e-7);
    assert_close(ggTextureBilinear(tall, 1.0, 0.75, GG_WRAP_CLAMP).r, 0.25, 1e-6);
    assert_close(ggTextureBilinear(wide, 1.0, 1.0, GG_WRAP_CLAMP).g, 0.3f, 1e-7);
    assert_close(ggTextureBilinear(wide, 0.25, 1.0, GG_WRAP_REPEAT).g, 0.15, 1e-6);
    /* REPEAT leaves 1 alone: the last texel, not the first. */
    assert_close(ggTextureBilinear(wide, 1.0, 0.0, GG_WRAP_REPEAT).r, 0.3f, 1e-7);
    assert_close(ggTextureNearest(wide, 1.0, 0.0, GG_WRAP_REPEAT).r, 0.3f, 1e-7);
    assert_close(ggTextureBilinear(sq, 1.0, 0.0, GG_WRAP_CLAMP).r, 0.2f, 1e-7);
    assert_close(ggTextureBilinear(sq, 1.0, 1.0, GG_WRAP_CLAMP).r, 0.4f, 1e-7);
    assert_close(ggTextureBilinear(sq, 1.0, 0.5, GG_WRAP_CLAMP).r, 0.3f, 1e-7);
    ggImageFree(sq);
    ggImageFree(img);
    ggImageFree(tall);
    ggImageFree(wide);
}

static void test_wrap_modes(void **state)
{
    tu_rng r = {7};
    ggImage *img = random_image(9, 6, &r, 0.0, 1.0);
    int k;
    (void)state;
    for (k = 0; k < 200; k++) {
        double u = tu_uniform(&r), v = tu_uniform(&r);
        ggColor base = ggTextureBilinear(img, u, v, GG_WRAP_REPEAT);
        ggColor rep = ggTextureBilinear(img, u + 3.0, v - 2.0, GG_WRAP_REPEAT);
        ggColor cl = ggTextureBilinear(img, u + 3.0, v - 2.0, GG_WRAP_CLAMP);
        ggColor edge = ggTextureBilinear(img, 1.0, 0.0, GG_WRAP_CLAMP);
        /* u + 3 - floor(u + 3) differs from u by rounding only. */
        assert_close(rep.r, base.r, 1e-9);
        assert_close(rep.b, base.b, 1e-9);
        assert_color_eq(cl, edge.r, edge.g, edge.b);
    }
    /* Negative values wrap to the far side. */
    assert_close(ggTextureBilinear(img, -0.25, 0.5, GG_WRAP_REPEAT).g,
                 ggTextureBilinear(img, 0.75, 0.5, GG_WRAP_REPEAT).g, 1e-12);
    assert_close(ggTextureNearest(img, -0.25, -0.5, GG_WRAP_REPEAT).g,
                 ggTextureNearest(img, 0.75, 0.5, GG_WRAP_REPEAT).g, 1e-12);
    /* Infinity clamps under CLAMP, and is black under REPEAT. */
    assert_color_eq(ggTextureBilinear(img, INFINITY, -INFINITY, GG_WRAP_CLAMP),
                    ggImageGet(img, 8, 0).r, ggImageGet(img, 8, 0).g, ggImageGet(img, 8, 0).b);
    assert_color_eq(ggTextureBilinear(img, INFINITY, 0.5, GG_WRAP_REPEAT), 0, 0, 0);
    /* An unknown mode behaves as CLAMP. */
    assert_color_eq(ggTextureBilinear(img, -5.0, 0.0, 42), ggImageGet(img, 0, 0).r,
                    ggImageGet(img, 0, 0).g, ggImageGet(img, 0, 0).b);
    ggImageFree(img);
}

static void test_nan_and_null(void **state)
{
    const float white[] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
    ggImage *img = image_of(2, 2, white);
    int mode;
    (void)state;
    for (mode = 0; mode < 2; mode++) {
        assert_color_eq(ggTextureBilinear(img, NAN, 0.5, mode), 0, 0, 0);
        assert_color_eq(ggTextureBilinear(img, 0.5, NAN, mode), 0, 0, 0);
        assert_color_eq(ggTextureNearest(img, NAN, NAN, mode), 0, 0, 0);
        assert_color_eq(ggTextureBilinear(img, 0.5, 0.5, mode), 1, 1, 1);
    }
    assert_color_eq(ggTextureBilinear(NULL, 0.5, 0.5, GG_WRAP_CLAMP), 0, 0, 0);
    assert_color_eq(ggTextureNearest(NULL, 0.5, 0.5, GG_WRAP_CLAMP), 0, 0, 0);
    /* A NaN texel reads 0 where it has weight, and stays out elsewhere. */
    ggImagePixels(img)[0] = NAN;
    assert_true(ggTextureBilinear(img, 0.5, 0.5, GG_WRAP_CLAMP).r == 0.0);
    assert_true(ggTextureBilinear(img, 0.5, 0.5, GG_WRAP_CLAMP).g == 1.0);
    ggImageFree(img);
}

/* Between two texels the blend is linear, hence monotone and bounded. */
static void test_monotone(void **state)
{
    tu_rng r = {13};
    ggImage *img = random_image(8, 5, &r, 0.0, 1.0);
    const float ramp[] = {0.0f, 0.0f, 0.0f, 1.0f, 0.5f, 0.25f};
    ggImage *g = image_of(2, 1, ramp);
    int row, i, k;
    (void)state;
    for (k = 0; k <= 100; k++) {
        double u = k / 100.0;
        ggColor c = ggTextureBilinear(g, u, 0.3, GG_WRAP_CLAMP);
        assert_close(c.r, u, 1e-12);
        assert_close(c.g, 0.5 * u, 1e-12);
    }
    for (row = 0; row < 5; row++)
        for (i = 0; i < 7; i++) {
            double v = row / 4.0, prev = 0.0;
            ggColor a = ggImageGet(img, i, row), b = ggImageGet(img, i + 1, row);
            int up = b.r >= a.r;
            for (k = 0; k <= 20; k++) {
                double u = (i + k / 20.0) / 7.0;
                double x = ggTextureBilinear(img, u, v, GG_WRAP_CLAMP).r;
                assert_true(x >= fmin(a.r, b.r) - 1e-12 && x <= fmax(a.r, b.r) + 1e-12);
                if (k > 0) assert_true(up ? x >= prev - 1e-12 : x <= prev + 1e-12);
                prev = x;
            }
        }
    ggImageFree(img);
    ggImageFree(g);
}

/* "Clamp at 1.0": above only. */
static void test_clamp_at_one(void **state)
{
    const float px[] = {4.0f, 0.0f, -0.5f, 2.0f, 2.0f, -0.5f};
    ggImage *img = image_of(2, 1, px);
    ggColor c;
    (void)state;
    c = ggTextureBilinear(img, 0.0, 0.0, GG_WRAP_CLAMP);
    assert_color_eq(c, 1.0, 0.0, -0.5);
    c = ggTextureBilinear(img, 0.25, 0.0, GG_WRAP_CLAMP); /* r 3.5, g 0.5 */
    assert_color_eq(c, 1.0, 0.5, -0.5);
    c = ggTextureBilinear(img, 0.75, 0.0, GG_WRAP_CLAMP); /* g 1.5 */
    assert_color_eq(c, 1.0, 1.0, -0.5);
    c = ggTextureNearest(img, 0.9, 0.0, GG_WRAP_CLAMP);
    assert_color_eq(c, 1.0, 1.0, -0.5);
    ggImageFree(img);
}

/* Nearest picks the texel the bilinear weights favour; halves round up. */
static void test_nearest_vs_bilinear(void **state)
{
    const float px[] = {0.0f, 0.0f, 0.0f, 0.3f, 0.3f, 0.3f, 0.9f, 0.9f, 0.9f};
    ggImage *img = image_of(3, 1, px);
    tu_rng r = {31};
    int k;
    (void)state;
    assert_close(ggTextureNearest(img, 0.24, 0, GG_WRAP_CLAMP).r, 0.0, 0);
    assert_close(ggTextureNearest(img, 0.25, 0, GG_WRAP_CLAMP).r, 0.3f, 1e-7);
    assert_close(ggTextureNearest(img, 0.74, 0, GG_WRAP_CLAMP).r, 0.3f, 1e-7);
    assert_close(ggTextureNearest(img, 0.76, 0, GG_WRAP_CLAMP).r, 0.9f, 1e-7);
    assert_close(ggTextureBilinear(img, 0.25, 0, GG_WRAP_CLAMP).r, 0.15, 1e-7);
    for (k = 0; k < 500; k++) {
        double u = tu_uniform(&r);
        double n = ggTextureNearest(img, u, 0.5, GG_WRAP_CLAMP).r;
        double b = ggTextureBilinear(img, u, 0.5, GG_WRAP_CLAMP).r;
        int i = (int)floor(2.0 * u + 0.5);
        assert_true(n == (double)px[3 * i]);
        /* The bilinear value lies between the two neighbours, nearest is
           the closer one, so |b - n| is at most half their difference. */
        assert_true(fabs(b - n) <= 0.5 * 0.6 + 1e-7);
    }
    ggImageFree(img);
}

static void test_checker(void **state)
{
    ggColor a = {1, 0, 0}, b = {0, 0, 1};
    tu_rng r = {5};
    int k;
    (void)state;
    assert_color_eq(ggTextureChecker(0.01, 0.01, 4, a, b), 1, 0, 0);
    assert_color_eq(ggTextureChecker(0.26, 0.01, 4, a, b), 0, 0, 1);
    assert_color_eq(ggTextureChecker(0.26, 0.26, 4, a, b), 1, 0, 0);
    assert_color_eq(ggTextureChecker(0.99, 0.01, 4, a, b), 0, 0, 1);
    /* Wraps with period 1, odd n included. */
    for (k = 0; k < 300; k++) {
        double u = tu_range(&r, -3, 3), v = tu_range(&r, -3, 3);
        ggColor c0 = ggTextureChecker(u, v, 3, a, b);
        ggColor c1 = ggTextureChecker(u + 2.0, v - 1.0, 3, a, b);
        ggColor c2 = ggTextureChecker(u - floor(u), v - floor(v), 3, a, b);
        int su = (int)floor((u - floor(u)) * 3), sv = (int)floor((v - floor(v)) * 3);
        /* Away from square borders shifting by whole periods keeps the square. */
        if (fabs((u - floor(u)) * 3 - floor((u - floor(u)) * 3 + 0.5)) > 1e-9 &&
            fabs((v - floor(v)) * 3 - floor((v - floor(v)) * 3 + 0.5)) > 1e-9) {
            assert_true(c0.r == c1.r);
        }
        assert_true(c0.r == c2.r);
        assert_true(c0.r == ((su + sv) % 2 == 0 ? 1.0 : 0.0));
    }
    assert_color_eq(ggTextureChecker(-0.01, 0.01, 2, a, b), 0, 0, 1); /* u' = 0.99 */
    assert_color_eq(ggTextureChecker(NAN, 0.5, 4, a, b), 0, 0, 0);
    assert_color_eq(ggTextureChecker(0.5, INFINITY, 4, a, b), 0, 0, 0);
    assert_color_eq(ggTextureChecker(0.7, 0.7, 0, a, b), 1, 0, 0);
    assert_color_eq(ggTextureChecker(0.7, 0.7, NAN, a, b), 1, 0, 0);
    assert_color_eq(ggTextureChecker(0.7, 0.2, 2.5, a, b), 0, 0, 1); /* squares (1, 0) */
    /* n over the whole range of doubles. u = v: the square (s, s), whose
       sum is even, so a, for any n (the sum overflowed near DBL_MAX and
       gave b). n = 2^k, k >= 54: u' n is a multiple of 2 for every u' (53
       bits below the point at most), so a everywhere. */
    for (k = 0; k < 2000; k++) {
        double u = tu_uniform(&r), v = tu_uniform(&r);
        double n = exp(tu_range(&r, 0, log(DBL_MAX)));
        int e = 54 + k % (1024 - 54);
        assert_color_eq(ggTextureChecker(u, u, n, a, b), 1, 0, 0);
        assert_color_eq(ggTextureChecker(u, v, ldexp(1.0, e), a, b), 1, 0, 0);
    }
    assert_color_eq(ggTextureChecker(0.9, 0.9, DBL_MAX, a, b), 1, 0, 0);
    assert_color_eq(ggTextureChecker(0.9, 0.9, 1e308, a, b), 1, 0, 0);
}

/* The blend as ggrt/image.h writes it, computed long-hand, on random points. */
static void test_matches_formula(void **state)
{
    tu_rng r = {77};
    ggImage *img = random_image(13, 7, &r, 0.0, 0.6);
    int k;
    (void)state;
    for (k = 0; k < 2000; k++) {
        double u = tu_uniform(&r), v = tu_uniform(&r);
        double di = 12 * u, dj = 6 * v, up, vp, want;
        int i = (int)di, j = (int)dj;
        up = di - i, vp = dj - j;
        want = ggImageGet(img, i, j).g * (1 - up) * (1 - vp) +
               ggImageGet(img, i, j + 1).g * (1 - up) * vp +
               ggImageGet(img, i + 1, j).g * up * (1 - vp) +
               ggImageGet(img, i + 1, j + 1).g * up * vp;
        assert_close(ggTextureBilinear(img, u, v, GG_WRAP_REPEAT).g, want, 1e-12);
    }
    ggImageFree(img);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_notes_worked_example),
        cmocka_unit_test(test_two_by_two),
        cmocka_unit_test(test_exact_texels),
        cmocka_unit_test(test_edges_never_read_past),
        cmocka_unit_test(test_wrap_modes),
        cmocka_unit_test(test_nan_and_null),
        cmocka_unit_test(test_monotone),
        cmocka_unit_test(test_clamp_at_one),
        cmocka_unit_test(test_nearest_vs_bilinear),
        cmocka_unit_test(test_checker),
        cmocka_unit_test(test_matches_formula),
    };
    return cmocka_run_group_tests_name("texture", tests, NULL, NULL);
}
