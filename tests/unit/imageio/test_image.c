/* SPDX-License-Identifier: MIT */
/*
** test_image.c -- ggImage basics, sRGB, PNG input/output, atomic writes,
** reading broken files, crop/paste and ggImageCompare.
*/
#include "testutil.h"

#include "image.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <png.h>
#include <setjmp.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- helpers ------------------------------------------------------------ */

static int setup_dir(void **state)
{
    (void)state;
    return tu_tmpdir_make("image");
}

static int teardown_dir(void **state)
{
    (void)state;
    tu_tmpdir_remove();
    return 0;
}

static int count_entries(const char *dir)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    int n = 0;
    while (d && (e = readdir(d)))
        if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0) n++;
    if (d) closedir(d);
    return n;
}

static unsigned char *slurp(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    unsigned char *b;
    long sz;
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    sz = ftell(f);
    fseek(f, 0, SEEK_SET);
    b = malloc(sz > 0 ? (size_t)sz : 1);
    *n = fread(b, 1, (size_t)sz, f);
    fclose(f);
    return b;
}

static void spit(const char *path, const void *b, size_t n)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(b, 1, n, f), n);
    assert_int_equal(fclose(f), 0);
}

static ggImage *random_image(int w, int h, tu_rng *r, double lo, double hi)
{
    ggImage *img = ggImageCreate(w, h, NULL);
    size_t i;
    assert_non_null(img);
    for (i = 0; i < (size_t)w * (size_t)h * 3; i++)
        ggImagePixels(img)[i] = (float)tu_range(r, lo, hi);
    return img;
}

/* ---- object ------------------------------------------------------------- */

static int live_blocks;
static void *c_malloc(void *ud, size_t n)
{
    (void)ud;
    live_blocks++;
    return malloc(n);
}
static void *c_realloc(void *ud, void *p, size_t n)
{
    (void)ud;
    if (!p) live_blocks++;
    return realloc(p, n);
}
static void c_free(void *ud, void *p)
{
    (void)ud;
    if (p) live_blocks--;
    free(p);
}

static void test_create_get_set(void **state)
{
    ggAllocator a = {c_malloc, c_realloc, c_free, NULL};
    ggImage *img;
    ggColor c, red = {1.0, 0.25, -3.5};
    (void)state;
    assert_null(ggImageCreate(0, 5, NULL));
    assert_null(ggImageCreate(5, -1, NULL));
    assert_null(ggImageCreate(GG_IMAGE_MAX_DIM + 1, 1, NULL));
    assert_null(ggImageCreate(GG_IMAGE_MAX_DIM, GG_IMAGE_MAX_DIM, NULL)); /* > MAX_PIXELS */
    img = ggImageCreate(7, 3, &a);
    assert_non_null(img);
    assert_int_equal(live_blocks, 2);
    assert_int_equal(ggImageWidth(img), 7);
    assert_int_equal(ggImageHeight(img), 3);
    c = ggImageGet(img, 6, 2);
    assert_true(c.r == 0.0 && c.g == 0.0 && c.b == 0.0);
    ggImageSet(img, 6, 2, red);
    c = ggImageGet(img, 6, 2);
    assert_true(c.r == 1.0 && c.g == 0.25 && c.b == -3.5);
    assert_true(ggImagePixels(img)[3 * (2 * 7 + 6) + 2] == -3.5f);
    assert_ptr_equal(ggImagePixels(img), ggImagePixelsConst(img));
    /* Out of range: reads black, writes nothing. */
    ggImageSet(img, 7, 0, red);
    ggImageSet(img, -1, 0, red);
    ggImageSet(img, 0, 3, red);
    c = ggImageGet(img, 7, 2);
    assert_true(c.r == 0.0 && c.g == 0.0 && c.b == 0.0);
    c = ggImageGet(img, 0, -1);
    assert_true(c.r == 0.0);
    {
        size_t i, nz = 0;
        for (i = 0; i < 7 * 3 * 3; i++) nz += ggImagePixels(img)[i] != 0.0f;
        assert_int_equal(nz, 3);
    }
    ggImageFree(img);
    assert_int_equal(live_blocks, 0);
    ggImageFree(NULL);
    assert_int_equal(ggImageWidth(NULL), 0);
    assert_null(ggImagePixels(NULL));
    c = ggImageGet(NULL, 0, 0);
    assert_true(c.r == 0.0);
}

static void test_srgb(void **state)
{
    tu_rng r = {11};
    int i;
    (void)state;
    assert_true(ggLinearToSRGB(0.0) == 0.0);
    assert_close(ggLinearToSRGB(1.0), 1.0, 1e-15);
    assert_close(ggSRGBToLinear(1.0), 1.0, 1e-15);
    assert_close(ggLinearToSRGB(0.5), 0.735356983052449, 1e-12);
    assert_close(ggSRGBToLinear(0.5), 0.214041140482232, 1e-12);
    assert_close(ggLinearToSRGB(0.001), 0.01292, 1e-12);
    /* The two pieces meet (the standard's constants make them agree to
       about 1e-7, not exactly). */
    assert_close(ggLinearToSRGB(0.0031308), ggLinearToSRGB(0.0031308 + 1e-12), 1e-6);
    assert_close(ggSRGBToLinear(0.04045), ggSRGBToLinear(0.04045 + 1e-12), 1e-6);
    for (i = 0; i < 1000; i++) {
        double x = tu_uniform(&r);
        assert_close(ggSRGBToLinear(ggLinearToSRGB(x)), x, 1e-12);
        if (i > 0) assert_true(ggLinearToSRGB(x) >= ggLinearToSRGB(x * 0.999));
    }
    assert_true(ggLinearToSRGB(-0.5) < 0.0); /* documented: no clamping */
    assert_true(isnan(ggLinearToSRGB(NAN)));
    assert_true(isnan(ggSRGBToLinear(NAN)));
}

/* ---- PNG ---------------------------------------------------------------- */

/* Read a PNG's 8-bit RGB bytes with libpng directly (independent check). */
static unsigned char *png_bytes(const char *path, int *w, int *h)
{
    png_image pi;
    unsigned char *buf;
    memset(&pi, 0, sizeof pi);
    pi.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&pi, path)) return NULL;
    pi.format = PNG_FORMAT_RGB;
    buf = malloc(PNG_IMAGE_SIZE(pi));
    if (!png_image_finish_read(&pi, NULL, buf, 0, NULL)) {
        free(buf);
        return NULL;
    }
    *w = (int)pi.width;
    *h = (int)pi.height;
    return buf;
}

static void test_png_round_trip_exact(void **state)
{
    ggImage *img, *back = NULL, *again = NULL;
    unsigned char *b;
    ggError e;
    int w, h, k, c;
    (void)state;
    /* Every sRGB level in every channel, rotated between channels. */
    img = ggImageCreate(256, 2, NULL);
    for (k = 0; k < 256; k++)
        for (c = 0; c < 3; c++) {
            ggImagePixels(img)[3 * k + c] = (float)ggSRGBToLinear(((k + 85 * c) % 256) / 255.0);
            ggImagePixels(img)[3 * (256 + k) + c] = (float)ggSRGBToLinear((255 - k) / 255.0);
        }
    assert_int_equal(ggImageWritePNG(img, tu_tmppath("levels.png"), &e), GG_OK);
    b = png_bytes(tu_tmppath("levels.png"), &w, &h);
    assert_non_null(b);
    assert_int_equal(w, 256);
    assert_int_equal(h, 2);
    for (k = 0; k < 256; k++)
        for (c = 0; c < 3; c++) {
            assert_int_equal(b[3 * k + c], (k + 85 * c) % 256);
            assert_int_equal(b[3 * (256 + k) + c], 255 - k);
        }
    free(b);
    assert_int_equal(ggImageRead(tu_tmppath("levels.png"), NULL, &back, &e), GG_OK);
    assert_int_equal(ggImageWidth(back), 256);
    assert_int_equal(ggImageHeight(back), 2);
    assert_memory_equal(ggImagePixels(back), ggImagePixels(img), 256 * 2 * 3 * sizeof(float));
    /* Writing what was read reproduces the file byte for byte. */
    assert_int_equal(ggImageWrite(back, tu_tmppath("levels2.PNG"), &e), GG_OK);
    assert_int_equal(ggImageRead(tu_tmppath("levels2.PNG"), NULL, &again, &e), GG_OK);
    assert_memory_equal(ggImagePixels(again), ggImagePixels(img), 256 * 2 * 3 * sizeof(float));
    ggImageFree(img);
    ggImageFree(back);
    ggImageFree(again);
}

static void test_png_encode_rounding(void **state)
{
    tu_rng r = {5};
    ggImage *img = ggImageCreate(64, 64, NULL);
    float *p = ggImagePixels(img);
    unsigned char *b;
    size_t i, n = 64 * 64 * 3, checked = 0;
    int w, h;
    (void)state;
    for (i = 0; i < n; i++) p[i] = (float)tu_uniform(&r);
    p[0] = NAN, p[1] = -1.0f, p[2] = 7.0f;
    p[3] = INFINITY, p[4] = -INFINITY, p[5] = -0.0f;
    p[6] = 1.0f, p[7] = 0.0f, p[8] = (float)ggSRGBToLinear(0.5 / 255.0);
    assert_int_equal(ggImageWritePNG(img, tu_tmppath("round.png"), NULL), GG_OK);
    b = png_bytes(tu_tmppath("round.png"), &w, &h);
    assert_non_null(b);
    assert_int_equal(b[0], 0);
    assert_int_equal(b[1], 0);
    assert_int_equal(b[2], 255);
    assert_int_equal(b[3], 255);
    assert_int_equal(b[4], 0);
    assert_int_equal(b[5], 0);
    assert_int_equal(b[6], 255);
    assert_int_equal(b[7], 0);
    assert_true(b[8] <= 1); /* exactly on the 0/1 midpoint, up to float rounding */
    for (i = 9; i < n; i++) {
        double s = 255.0 * ggLinearToSRGB(p[i]);
        double frac = s - floor(s);
        if (fabs(frac - 0.5) < 1e-6) continue; /* a tie: either neighbour is right */
        assert_int_equal(b[i], (int)floor(s + 0.5));
        checked++;
    }
    assert_true(checked > n - 20);
    free(b);
    ggImageFree(img);
}

/* Write a PNG with libpng directly in the given format. */
static void write_png_raw(const char *path, int w, int h, png_uint_32 format, const void *buf)
{
    png_image pi;
    memset(&pi, 0, sizeof pi);
    pi.version = PNG_IMAGE_VERSION;
    pi.width = (png_uint_32)w;
    pi.height = (png_uint_32)h;
    pi.format = format;
    assert_true(png_image_write_to_file(&pi, path, 0, buf, 0, NULL));
}

static void test_png_formats(void **state)
{
    unsigned char grey[6] = {0, 64, 128, 192, 255, 10};
    unsigned char ga[4] = {200, 255, 200, 0};
    unsigned char rgba[8] = {10, 20, 30, 255, 40, 50, 60, 255};
    png_uint_16 lin[6] = {0, 65535, 32768, 1000, 20000, 65535};
    ggImage *img = NULL;
    ggColor c;
    int i;
    (void)state;
    write_png_raw(tu_tmppath("grey.png"), 3, 2, PNG_FORMAT_GRAY, grey);
    assert_int_equal(ggImageRead(tu_tmppath("grey.png"), NULL, &img, NULL), GG_OK);
    assert_int_equal(ggImageWidth(img), 3);
    for (i = 0; i < 6; i++) {
        c = ggImageGet(img, i % 3, i / 3);
        assert_true(c.r == c.g && c.g == c.b);
        assert_close(c.r, ggSRGBToLinear(grey[i] / 255.0), 1e-6);
    }
    ggImageFree(img);
    img = NULL;
    /* Grey + alpha: opaque keeps its value, transparent goes black. */
    write_png_raw(tu_tmppath("ga.png"), 2, 1, PNG_FORMAT_GA, ga);
    assert_int_equal(ggImageRead(tu_tmppath("ga.png"), NULL, &img, NULL), GG_OK);
    c = ggImageGet(img, 0, 0);
    assert_close(c.g, ggSRGBToLinear(200 / 255.0), 1e-6);
    c = ggImageGet(img, 1, 0);
    assert_true(c.r == 0.0 && c.g == 0.0 && c.b == 0.0);
    ggImageFree(img);
    img = NULL;
    write_png_raw(tu_tmppath("rgba.png"), 2, 1, PNG_FORMAT_RGBA, rgba);
    assert_int_equal(ggImageRead(tu_tmppath("rgba.png"), NULL, &img, NULL), GG_OK);
    c = ggImageGet(img, 1, 0);
    assert_close(c.r, ggSRGBToLinear(40 / 255.0), 1e-6);
    assert_close(c.b, ggSRGBToLinear(60 / 255.0), 1e-6);
    ggImageFree(img);
    img = NULL;
    /* 16-bit linear RGB written by libpng reads back as value / 65535. */
    write_png_raw(tu_tmppath("lin16.png"), 2, 1, PNG_FORMAT_LINEAR_RGB, lin);
    assert_int_equal(ggImageRead(tu_tmppath("lin16.png"), NULL, &img, NULL), GG_OK);
    for (i = 0; i < 6; i++) assert_close(ggImagePixels(img)[i], lin[i] / 65535.0, 2e-5);
    ggImageFree(img);
}

/* ---- every sample decoded ------------------------------------------------

   PNG files written with libpng's low-level API in each colour type, at 8
   and 16 bits, with no colour chunk, an sRGB chunk or a gAMA: every
   sample must read as image.h says, exactly: ggSRGBToLinear (no chunk,
   sRGB, or a gAMA within 5% of 1/2.2), else the gAMA's power; times alpha. */
typedef struct png_case {
    int depth, type; /* PNG_COLOR_TYPE_* */
    int chunk;       /* 0 none, 1 sRGB, else a gAMA in 1e-5 units */
} png_case;

static unsigned sample_of(int depth, int x, int k)
{
    unsigned v = (unsigned)(x * 7 + k * 50) % 256;
    return depth == 16 ? v * 256 + (unsigned)(x * 37 + k) % 256 : v;
}

static void write_png_case(const char *path, const png_case *c, int w)
{
    const int nch = c->type == PNG_COLOR_TYPE_GRAY         ? 1
                    : c->type == PNG_COLOR_TYPE_GRAY_ALPHA ? 2
                    : c->type == PNG_COLOR_TYPE_RGB        ? 3
                    : c->type == PNG_COLOR_TYPE_RGBA       ? 4
                                                           : 1;
    png_byte row[256 * 8];
    png_color pal[256];
    png_byte trns[256];
    FILE *f = fopen(path, "wb");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    int x, k;
    assert_true(f && png && info && w <= 256);
    if (setjmp(png_jmpbuf(png))) fail_msg("libpng could not write %s", path);
    png_init_io(png, f);
    png_set_IHDR(png, info, (png_uint_32)w, 1, c->depth, c->type, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (c->type == PNG_COLOR_TYPE_PALETTE) {
        for (x = 0; x < 256; x++) {
            pal[x].red = (png_byte)sample_of(8, x, 0), pal[x].green = (png_byte)sample_of(8, x, 1);
            pal[x].blue = (png_byte)sample_of(8, x, 2), trns[x] = (png_byte)sample_of(8, x, 3);
        }
        png_set_PLTE(png, info, pal, 256);
        png_set_tRNS(png, info, trns, 256, NULL);
    }
    if (c->chunk == 1) png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    if (c->chunk > 1) png_set_gAMA_fixed(png, info, c->chunk);
    png_write_info(png, info);
    for (x = 0; x < w; x++)
        for (k = 0; k < nch; k++) {
            unsigned v =
                c->type == PNG_COLOR_TYPE_PALETTE ? (unsigned)x : sample_of(c->depth, x, k);
            if (c->depth == 16)
                row[2 * (x * nch + k)] = (png_byte)(v >> 8),
                                   row[2 * (x * nch + k) + 1] = (png_byte)v;
            else
                row[x * nch + k] = (png_byte)v;
        }
    png_write_row(png, row);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    fclose(f);
}

/* What image.h says pixel x of the case reads as, channel k. */
static float expected_sample(const png_case *c, int x, int k)
{
    const double max = c->depth == 16 ? 65535.0 : 255.0;
    const int pal = c->type == PNG_COLOR_TYPE_PALETTE,
              grey = c->type & PNG_COLOR_MASK_COLOR ? 0 : 1;
    const int alpha = pal || (c->type & PNG_COLOR_MASK_ALPHA);
    const int ach = pal ? 3 : grey ? 1 : 3;
    const double v = (pal ? sample_of(8, x, k) : sample_of(c->depth, x, grey ? 0 : k)) / max;
    const double a = alpha ? (pal ? sample_of(8, x, 3) : sample_of(c->depth, x, ach)) / max : 1;
    const double lin = c->chunk > 1 && fabs(c->chunk * 2.2e-5 - 1) >= 0.05 ? pow(v, 1e5 / c->chunk)
                                                                           : ggSRGBToLinear(v);
    return alpha ? (float)(lin * a) : (float)lin;
}

static void test_png_every_sample(void **state)
{
    static const int types[] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                PNG_COLOR_TYPE_RGBA, PNG_COLOR_TYPE_PALETTE};
    static const int chunks[] = {0, 1, 45455, 45000, 100000, 50000, 220000};
    ggImage *img = NULL;
    size_t t, g, d, bad = 0;
    int x, k;
    (void)state;
    for (d = 0; d < 2; d++)
        for (t = 0; t < sizeof types / sizeof types[0]; t++)
            for (g = 0; g < sizeof chunks / sizeof chunks[0]; g++) {
                png_case c = {d ? 16 : 8, types[t], chunks[g]};
                if (c.depth == 16 && c.type == PNG_COLOR_TYPE_PALETTE) continue;
                write_png_case(tu_tmppath("case.png"), &c, 256);
                assert_int_equal(ggImageRead(tu_tmppath("case.png"), NULL, &img, NULL), GG_OK);
                for (x = 0; x < 256; x++)
                    for (k = 0; k < 3; k++) {
                        float want = expected_sample(&c, x, k);
                        float got = ggImagePixels(img)[3 * x + k];
                        if (got != want && bad++ < 5)
                            print_message("depth %d type %d chunk %d x %d: %.9g, not %.9g\n",
                                          c.depth, c.type, c.chunk, x, got, want);
                    }
                ggImageFree(img);
                img = NULL;
            }
    assert_int_equal(bad, 0);
}

/* ---- errors ------------------------------------------------------------- */

static void test_read_errors(void **state)
{
    ggImage *img = NULL;
    ggError e;
    char msg[600];
    (void)state;
    assert_int_equal(ggImageRead(tu_tmppath("missing.png"), NULL, &img, &e), GG_ERROR_IO);
    assert_int_equal(e.code, GG_ERROR_IO);
    snprintf(msg, sizeof msg, "%s: No such file or directory", tu_tmppath("missing.png"));
    assert_string_equal(e.message, msg);
    spit(tu_tmppath("junk.png"), "hello, world", 12);
    assert_int_equal(ggImageRead(tu_tmppath("junk.png"), NULL, &img, &e), GG_ERROR_UNSUPPORTED);
    snprintf(msg, sizeof msg, "%s: not a PNG or OpenEXR file", tu_tmppath("junk.png"));
    assert_string_equal(e.message, msg);
    spit(tu_tmppath("empty.exr"), "", 0);
    assert_int_equal(ggImageRead(tu_tmppath("empty.exr"), NULL, &img, &e), GG_ERROR_UNSUPPORTED);
    assert_int_equal(ggImageRead(tu_tmpdir(), NULL, &img, &e), GG_ERROR_IO); /* a directory */
    assert_int_equal(ggImageRead(NULL, NULL, &img, &e), GG_ERROR_INVALID);
    assert_int_equal(ggImageRead(tu_tmppath("junk.png"), NULL, NULL, NULL), GG_ERROR_INVALID);
    assert_null(img);
}

static uint32_t crc32_of(const unsigned char *p, size_t n)
{
    uint32_t c = 0xffffffffu;
    size_t i;
    int k;
    for (i = 0; i < n; i++) {
        c ^= p[i];
        for (k = 0; k < 8; k++) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return c ^ 0xffffffffu;
}

static void put32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24), p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8), p[3] = (unsigned char)v;
}

/* A PNG claiming w x h whose IDAT holds an empty zlib stream: enough for
   libpng to report the size, never enough pixels. */
static void write_png_header_only(const char *path, uint32_t w, uint32_t h)
{
    static const unsigned char zempty[11] = {0x78, 0x01, 0x01, 0x00, 0x00, 0xff,
                                             0xff, 0x00, 0x00, 0x00, 0x01};
    unsigned char b[8 + 25 + 23 + 12] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    unsigned char *p = b + 8;
    put32(p, 13);
    memcpy(p + 4, "IHDR", 4);
    put32(p + 8, w);
    put32(p + 12, h);
    p[16] = 8, p[17] = 2, p[18] = 0, p[19] = 0, p[20] = 0;
    put32(p + 21, crc32_of(p + 4, 17));
    p += 25;
    put32(p, sizeof zempty);
    memcpy(p + 4, "IDAT", 4);
    memcpy(p + 8, zempty, sizeof zempty);
    put32(p + 19, crc32_of(p + 4, 4 + sizeof zempty));
    p += 23;
    put32(p, 0);
    memcpy(p + 4, "IEND", 4);
    put32(p + 8, crc32_of(p + 4, 4));
    spit(path, b, sizeof b);
}

static void test_png_limits(void **state)
{
    ggImage *img = NULL;
    ggError e;
    (void)state;
    write_png_header_only(tu_tmppath("wide.png"), GG_IMAGE_MAX_DIM + 1, 1);
    assert_int_equal(ggImageRead(tu_tmppath("wide.png"), NULL, &img, &e), GG_ERROR_LIMIT);
    assert_non_null(strstr(e.message, "wide.png: image of 65537 x 1 pixels exceeds"));
    write_png_header_only(tu_tmppath("big.png"), 30000, 30000); /* 9e8 > 2^28 pixels */
    assert_int_equal(ggImageRead(tu_tmppath("big.png"), NULL, &img, &e), GG_ERROR_LIMIT);
    /* Within the limits the header alone is just truncated. */
    write_png_header_only(tu_tmppath("small.png"), 4, 4);
    assert_int_equal(ggImageRead(tu_tmppath("small.png"), NULL, &img, &e), GG_ERROR_PARSE);
    assert_null(img);
}

/* Every prefix of a valid file, and deterministic byte corruptions, must
   give an error or an image, never a crash or a leak (the ASan run checks
   the latter). A prefix missing only `tail` bytes may read fine: a PNG
   whose pixel data is complete reads without its closing IEND chunk. */
static void torture_file(const char *good, const char *name, size_t tail)
{
    size_t n = 0, len, i;
    unsigned char *b = slurp(good, &n), *m;
    tu_rng r = {99};
    int errors = 0;
    assert_non_null(b);
    m = malloc(n);
    for (len = 0; len + tail < n; len += len < 64 ? 1 : 7) {
        ggImage *img = NULL;
        ggError e;
        int rc;
        spit(tu_tmppath(name), b, len);
        rc = ggImageRead(tu_tmppath(name), NULL, &img, &e);
        assert_int_not_equal(rc, GG_OK);
        assert_null(img);
        assert_int_equal(e.code, rc);
        assert_true(strncmp(e.message, tu_tmppath(name), strlen(tu_tmppath(name))) == 0);
        errors++;
    }
    for (i = 0; i < 300; i++) {
        ggImage *img = NULL;
        int k, rc;
        memcpy(m, b, n);
        for (k = 0; k < 1 + (int)(i % 4); k++) m[tu_next(&r) % n] = (unsigned char)tu_next(&r);
        spit(tu_tmppath(name), m, n);
        rc = ggImageRead(tu_tmppath(name), NULL, &img, NULL);
        assert_true(rc == GG_OK ? img != NULL : img == NULL);
        ggImageFree(img);
    }
    assert_true(errors > 10);
    free(m);
    free(b);
}

static void test_truncated_and_corrupt(void **state)
{
    tu_rng r = {3};
    ggImage *img = random_image(23, 19, &r, -0.1, 1.5);
    (void)state;
    assert_int_equal(ggImageWritePNG(img, tu_tmppath("good.png"), NULL), GG_OK);
    assert_int_equal(ggImageWriteEXR(img, tu_tmppath("good.exr"), NULL), GG_OK);
    torture_file(tu_tmppath("good.png"), "bad.png", 12);
    torture_file(tu_tmppath("good.exr"), "bad.exr", 0);
    ggImageFree(img);
}

/* ---- atomic writes ------------------------------------------------------ */

static void test_write_unwritable(void **state)
{
    tu_rng r = {4};
    ggImage *img = random_image(8, 8, &r, 0.0, 1.0);
    char dir[512], path[600], msg[700];
    ggError e;
    (void)state;
    /* Missing directory. */
    snprintf(path, sizeof path, "%s/no/such/dir/out.png", tu_tmpdir());
    assert_int_equal(ggImageWritePNG(img, path, &e), GG_ERROR_IO);
    snprintf(msg, sizeof msg, "%s: cannot create temporary file: No such file or directory", path);
    assert_string_equal(e.message, msg);
    /* A "directory" that is a regular file. */
    spit(tu_tmppath("plain"), "x", 1);
    snprintf(path, sizeof path, "%s/plain/out.exr", tu_tmpdir());
    assert_int_equal(ggImageWriteEXR(img, path, &e), GG_ERROR_IO);
    snprintf(msg, sizeof msg, "%s: cannot create temporary file: Not a directory", path);
    assert_string_equal(e.message, msg);
    /* A read-only directory: root ignores permissions, so only check it
       when they apply. */
    snprintf(dir, sizeof dir, "%s/ro", tu_tmpdir());
    assert_int_equal(mkdir(dir, 0555), 0);
    if (geteuid() != 0) {
        snprintf(path, sizeof path, "%s/out.exr", dir);
        assert_int_equal(ggImageWriteEXR(img, path, &e), GG_ERROR_IO);
        snprintf(msg, sizeof msg, "%s: cannot create temporary file: Permission denied", path);
        assert_string_equal(e.message, msg);
        snprintf(path, sizeof path, "%s/out.png", dir);
        assert_int_equal(ggImageWritePNG(img, path, &e), GG_ERROR_IO);
    }
    assert_int_equal(count_entries(dir), 0);
    /* Unknown extension: nothing written. */
    assert_int_equal(ggImageWrite(img, tu_tmppath("out.tga"), &e), GG_ERROR_UNSUPPORTED);
    assert_int_equal(access(tu_tmppath("out.tga"), F_OK), -1);
    assert_int_equal(ggImageWrite(NULL, tu_tmppath("x.png"), &e), GG_ERROR_INVALID);
    ggImageFree(img);
}

/* Make the write fail half-way with RLIMIT_FSIZE (which binds root too):
   the old file must survive untouched and no temporary file may remain. */
static void failed_overwrite(int (*writer)(const ggImage *, const char *, ggError *),
                             const char *name)
{
    tu_rng r = {8};
    ggImage *small = random_image(4, 4, &r, 0.0, 1.0);
    ggImage *big = random_image(300, 300, &r, 0.0, 1.0); /* noise: does not compress */
    struct rlimit old, lim;
    void (*oldsig)(int);
    unsigned char *before, *after;
    size_t nb, na;
    ggError e;
    int rc, entries;
    assert_int_equal(writer(small, tu_tmppath(name), &e), GG_OK);
    entries = count_entries(tu_tmpdir());
    before = slurp(tu_tmppath(name), &nb);
    assert_non_null(before);
    assert_int_equal(getrlimit(RLIMIT_FSIZE, &old), 0);
    lim = old;
    lim.rlim_cur = 20000;
    oldsig = signal(SIGXFSZ, SIG_IGN);
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &lim), 0);
    rc = writer(big, tu_tmppath(name), &e);
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &old), 0);
    signal(SIGXFSZ, oldsig);
    assert_int_equal(rc, GG_ERROR_IO);
    assert_int_equal(e.code, GG_ERROR_IO);
    assert_true(strncmp(e.message, tu_tmppath(name), strlen(tu_tmppath(name))) == 0);
    after = slurp(tu_tmppath(name), &na);
    assert_int_equal(na, nb);
    assert_memory_equal(after, before, nb);
    assert_int_equal(count_entries(tu_tmpdir()), entries); /* no temporary left */
    /* And without the limit the same write succeeds. */
    assert_int_equal(writer(big, tu_tmppath(name), &e), GG_OK);
    assert_int_equal(count_entries(tu_tmpdir()), entries);
    free(before);
    free(after);
    ggImageFree(small);
    ggImageFree(big);
}

static void test_failed_write_keeps_old_file(void **state)
{
    static const int threads[] = {0, 1, 3, 8};
    size_t i;
    (void)state;
    failed_overwrite(ggImageWritePNG, "keep.png");
    /* the EXR writer's chunks compressed on one thread and on several:
       the failure stops them all (300 rows: 19 chunks) */
    for (i = 0; i < sizeof threads / sizeof threads[0]; i++) {
        gg_image_exr_threads = threads[i];
        failed_overwrite(ggImageWriteEXR, "keep.exr");
        failed_overwrite(ggImageWrite, "keep2.exr");
    }
    gg_image_exr_threads = 0;
}

/* An OpenEXR file's bytes do not depend on how many threads compressed
   its chunks: images of 1 to 70 chunks, smooth and noisy, with and
   without a layer, on 1, 2, 3, 5 and 8 threads, against one thread. */
static void test_exr_threads_same_bytes(void **state)
{
    static const int heights[] = {1, 15, 16, 17, 64, 100, 1111};
    static const int threads[] = {2, 3, 5, 8};
    tu_rng r = {31};
    size_t h, t;
    int noisy;
    (void)state;
    for (h = 0; h < sizeof heights / sizeof heights[0]; h++)
        for (noisy = 0; noisy < 2; noisy++) {
            ggImage *img = random_image(37, heights[h], &r, 0.0, noisy ? 1.0 : 0.0);
            ggImage *layer = random_image(37, heights[h], &r, 0.0, 1.0);
            const ggImage *layers[1];
            const char *names[1] = {"aov"};
            unsigned char *one, *one_l;
            size_t n1, n1_l;
            layers[0] = layer;
            gg_image_exr_threads = 1;
            assert_int_equal(ggImageWriteEXR(img, tu_tmppath("t1.exr"), NULL), GG_OK);
            assert_int_equal(
                ggImageWriteEXRLayers(img, layers, names, 1, NULL, tu_tmppath("t1l.exr"), NULL),
                GG_OK);
            one = slurp(tu_tmppath("t1.exr"), &n1);
            one_l = slurp(tu_tmppath("t1l.exr"), &n1_l);
            for (t = 0; t < sizeof threads / sizeof threads[0]; t++) {
                unsigned char *b;
                size_t nb;
                gg_image_exr_threads = threads[t];
                assert_int_equal(ggImageWriteEXR(img, tu_tmppath("tn.exr"), NULL), GG_OK);
                b = slurp(tu_tmppath("tn.exr"), &nb);
                assert_int_equal(nb, n1);
                assert_memory_equal(b, one, n1);
                free(b);
                assert_int_equal(
                    ggImageWriteEXRLayers(img, layers, names, 1, NULL, tu_tmppath("tnl.exr"), NULL),
                    GG_OK);
                b = slurp(tu_tmppath("tnl.exr"), &nb);
                assert_int_equal(nb, n1_l);
                assert_memory_equal(b, one_l, n1_l);
                free(b);
            }
            free(one);
            free(one_l);
            ggImageFree(img);
            ggImageFree(layer);
        }
    gg_image_exr_threads = 0;
}

static void test_write_mode_and_dispatch(void **state)
{
    tu_rng r = {6};
    ggImage *img = random_image(5, 5, &r, 0.0, 1.0);
    unsigned char *b;
    struct stat st;
    mode_t mask = umask(022);
    size_t n = 0;
    (void)state;
    umask(mask);
    assert_int_equal(ggImageWrite(img, tu_tmppath("d.Exr"), NULL), GG_OK);
    b = slurp(tu_tmppath("d.Exr"), &n);
    assert_true(n > 4 && b[0] == 0x76 && b[1] == 0x2f && b[2] == 0x31 && b[3] == 0x01);
    free(b);
    assert_int_equal(ggImageWrite(img, tu_tmppath("d.PnG"), NULL), GG_OK);
    b = slurp(tu_tmppath("d.PnG"), &n);
    assert_true(n > 8 && memcmp(b, "\x89PNG", 4) == 0);
    free(b);
    assert_int_equal(stat(tu_tmppath("d.PnG"), &st), 0);
    assert_int_equal(st.st_mode & 0777, 0666 & ~mask);
    ggImageFree(img);
}

/* ---- crop, paste, compare ----------------------------------------------- */

static void test_crop_paste(void **state)
{
    tu_rng r = {21};
    ggImage *img = random_image(10, 8, &r, 0.0, 1.0), *c = NULL, *dst;
    int x, y;
    (void)state;
    assert_int_equal(ggImageCrop(img, 3, 2, 4, 5, &c), GG_OK);
    assert_int_equal(ggImageWidth(c), 4);
    assert_int_equal(ggImageHeight(c), 5);
    for (y = 0; y < 5; y++)
        for (x = 0; x < 4; x++) {
            ggColor a = ggImageGet(c, x, y), b = ggImageGet(img, x + 3, y + 2);
            assert_true(a.r == b.r && a.g == b.g && a.b == b.b);
        }
    assert_int_equal(ggImageCrop(img, 7, 0, 4, 1, &c), GG_ERROR_INVALID);
    assert_int_equal(ggImageCrop(img, -1, 0, 1, 1, &c), GG_ERROR_INVALID);
    assert_int_equal(ggImageCrop(img, 0, 0, 0, 1, &c), GG_ERROR_INVALID);
    /* Paste the crop back into a black image, partly off the edge. */
    dst = ggImageCreate(10, 8, NULL);
    ggImagePaste(dst, c, 3, 2);
    for (y = 0; y < 8; y++)
        for (x = 0; x < 10; x++) {
            ggColor a = ggImageGet(dst, x, y), b = ggImageGet(img, x, y);
            int inside = x >= 3 && x < 7 && y >= 2 && y < 7;
            assert_true(inside ? a.g == b.g : a.g == 0.0);
        }
    ggImagePaste(dst, c, -2, 6); /* only columns 2..3, rows 0..1 of c land */
    assert_true(ggImageGet(dst, 0, 6).r == ggImageGet(c, 2, 0).r);
    assert_true(ggImageGet(dst, 1, 7).b == ggImageGet(c, 3, 1).b);
    assert_true(ggImageGet(dst, 2, 6).r == 0.0);
    ggImagePaste(dst, c, 2147483000, 0); /* far outside: nothing, no overflow */
    ggImageFree(c);
    ggImageFree(dst);
    ggImageFree(img);
}

static void test_compare(void **state)
{
    ggImage *a = ggImageCreate(4, 5, NULL), *b = ggImageCreate(4, 5, NULL);
    ggImage *c = ggImageCreate(5, 4, NULL);
    ggImageDiff d;
    float *pb = ggImagePixels(b);
    (void)state;
    assert_int_equal(ggImageCompare(a, b, GG_COMPARE_LINEAR, &d), GG_OK);
    assert_true(d.rmse == 0.0 && d.max_abs == 0.0 && d.pixels_over == 0);
    assert_true(isinf(d.psnr) && d.psnr > 0);
    /* One channel off by 0.5, another by 0.003 (under 1/255). */
    pb[0] = 0.5f;
    pb[3 * 7 + 2] = 0.003f;
    assert_int_equal(ggImageCompare(a, b, GG_COMPARE_LINEAR, &d), GG_OK);
    assert_close(d.max_abs, 0.5, 1e-7);
    assert_close(d.rmse, sqrt((0.25 + 0.003 * 0.003) / 60.0), 1e-6);
    assert_close(d.psnr, -10.0 * log10((0.25 + 0.003 * 0.003) / 60.0), 1e-6);
    assert_int_equal(d.pixels_over, 1);
    assert_close(d.frac_over, 1.0 / 20.0, 1e-15);
    assert_int_equal(d.nan_channels, 0);
    /* In sRGB space the small linear step becomes large. */
    assert_int_equal(ggImageCompare(a, b, GG_COMPARE_SRGB, &d), GG_OK);
    assert_int_equal(d.pixels_over, 2);
    assert_close(d.max_abs, ggLinearToSRGB(0.5), 1e-7);
    /* NaN on one side counts as a differing pixel; NaN on both as equal;
       in sRGB space NaN is 0 like in the PNG writer. */
    ggImagePixels(a)[30] = NAN;
    pb[30] = NAN;
    pb[33] = NAN;
    assert_int_equal(ggImageCompare(a, b, GG_COMPARE_LINEAR, &d), GG_OK);
    assert_int_equal(d.nan_channels, 1);
    assert_int_equal(d.pixels_over, 2); /* pixels 0 and 11; 7 is under 1/255 */
    assert_false(isnan(d.rmse));
    assert_int_equal(ggImageCompare(a, b, GG_COMPARE_SRGB, &d), GG_OK);
    assert_int_equal(d.nan_channels, 0);
    assert_int_equal(d.pixels_over, 2);
    /* Clamping in sRGB space: 2.0 vs 1.0 is no difference. */
    ggImagePixels(a)[40] = 2.0f;
    pb[40] = 1.0f;
    assert_int_equal(ggImageCompare(a, b, GG_COMPARE_SRGB, &d), GG_OK);
    assert_int_equal(d.pixels_over, 2);
    assert_int_equal(ggImageCompare(a, c, GG_COMPARE_LINEAR, &d), GG_ERROR_INVALID);
    assert_int_equal(ggImageCompare(a, b, 7, &d), GG_ERROR_INVALID);
    assert_int_equal(ggImageCompare(a, NULL, GG_COMPARE_LINEAR, &d), GG_ERROR_INVALID);
    ggImageFree(a);
    ggImageFree(b);
    ggImageFree(c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_create_get_set),
        cmocka_unit_test(test_srgb),
        cmocka_unit_test(test_png_round_trip_exact),
        cmocka_unit_test(test_png_encode_rounding),
        cmocka_unit_test(test_png_formats),
        cmocka_unit_test(test_png_every_sample),
        cmocka_unit_test(test_read_errors),
        cmocka_unit_test(test_png_limits),
        cmocka_unit_test(test_truncated_and_corrupt),
        cmocka_unit_test(test_write_unwritable),
        cmocka_unit_test(test_failed_write_keeps_old_file),
        cmocka_unit_test(test_exr_threads_same_bytes),
        cmocka_unit_test(test_write_mode_and_dispatch),
        cmocka_unit_test(test_crop_paste),
        cmocka_unit_test(test_compare),
    };
    return cmocka_run_group_tests_name("image", tests, setup_dir, teardown_dir);
}
