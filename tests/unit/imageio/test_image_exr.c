/* SPDX-License-Identifier: MIT */
/*
** test_image_exr.c -- OpenEXR input and output. Fixture files are written
** here with OpenEXR's C core directly (scanline and tiled, half, float and
** uint, every compression, odd data windows), so the reader is checked
** against files it did not write itself.
*/
#include "testutil.h"

#include "image.h"

#include <OpenEXR/openexr.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static int setup_dir(void **state)
{
    (void)state;
    return tu_tmpdir_make("exr");
}

static int teardown_dir(void **state)
{
    (void)state;
    tu_tmpdir_remove();
    return 0;
}

/* ---- fixture writer ------------------------------------------------------ */

typedef struct fixture {
    exr_storage_t storage;
    exr_compression_t comp;
    exr_pixel_type_t type;
    const char *chans; /* one-letter channel names, e.g. "RGBA" or "Y" */
    int x0, y0, w, h;  /* data window */
    int tile;
    exr_tile_level_mode_t levels;
} fixture;

static void quiet(exr_const_context_t c, exr_result_t code, const char *msg)
{
    (void)c, (void)code, (void)msg;
}

/* Value of channel k at data-window pixel (x, y) of mip level l: small
   multiples of 1/4 (exact in half, float) or integers for uint. */
static double fx_value(const fixture *f, int k, int x, int y, int l)
{
    double v = (x * 3 + y * 5 + k * 7) % 23 + 100 * l;
    return f->type == EXR_PIXEL_UINT ? v : v * 0.25;
}

/* Exact float -> half for the values fx_value makes. */
static uint16_t to_half(float f)
{
    uint32_t b;
    memcpy(&b, &f, 4);
    if ((b & 0x7fffffffu) == 0) return (uint16_t)(b >> 16);
    return (uint16_t)(((b >> 16) & 0x8000u) | ((((b >> 23) & 0xffu) - 127u + 15u) << 10) |
                      ((b >> 13) & 0x3ffu));
}

/* Fill planar level data for channel k (w x h). */
static void *level_data(const fixture *f, int k, int w, int h, int l)
{
    size_t n = (size_t)w * (size_t)h, i;
    void *p = malloc(n * 4);
    for (i = 0; i < n; i++) {
        double v = fx_value(f, k, (int)(i % (size_t)w), (int)(i / (size_t)w), l);
        if (f->type == EXR_PIXEL_HALF)
            ((uint16_t *)p)[i] = to_half((float)v);
        else if (f->type == EXR_PIXEL_UINT)
            ((uint32_t *)p)[i] = (uint32_t)v;
        else
            ((float *)p)[i] = (float)v;
    }
    return p;
}

static int chan_index(const fixture *f, const char *name)
{
    const char *p = strchr(f->chans, name[0]);
    return p ? (int)(p - f->chans) : -1;
}

/* Encode one chunk whose top-left pixel is (cx, cy) in the level buffers. */
static void encode_chunk(exr_context_t ctx, const fixture *f, const exr_chunk_info_t *ci,
                         exr_encode_pipeline_t *enc, int *ready, void **data, int lw, int cx,
                         int cy)
{
    int bpe = f->type == EXR_PIXEL_HALF ? 2 : 4, c;
    if (*ready)
        assert_int_equal(exr_encoding_update(ctx, 0, ci, enc), EXR_ERR_SUCCESS);
    else
        assert_int_equal(exr_encoding_initialize(ctx, 0, ci, enc), EXR_ERR_SUCCESS);
    for (c = 0; c < enc->channel_count; c++) {
        exr_coding_channel_info_t *ch = &enc->channels[c];
        int k = chan_index(f, ch->channel_name);
        assert_true(k >= 0);
        ch->user_data_type = (uint16_t)f->type;
        ch->user_bytes_per_element = (int16_t)bpe;
        ch->user_pixel_stride = bpe;
        ch->user_line_stride = bpe * lw;
        ch->encode_from_ptr = (const uint8_t *)data[k] + ((size_t)cy * lw + cx) * bpe;
    }
    if (!*ready)
        assert_int_equal(exr_encoding_choose_default_routines(ctx, 0, enc), EXR_ERR_SUCCESS);
    *ready = 1;
    assert_int_equal(exr_encoding_run(ctx, 0, enc), EXR_ERR_SUCCESS);
}

/* Our own writer callback: the core's default one deletes a file that was
   not finished, and the header-only fixtures are exactly that. */
static int64_t fx_write(exr_const_context_t c, void *ud, const void *buf, uint64_t sz, uint64_t off,
                        exr_stream_error_func_ptr_t error_cb)
{
    (void)c, (void)error_cb;
    return (int64_t)pwrite(*(int *)ud, buf, (size_t)sz, (off_t)off);
}

static void write_fixture(const char *path, const fixture *f, int header_only)
{
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    exr_context_t ctx;
    exr_attr_box2i_t dw;
    exr_attr_v2f_t center = {{{0.0f, 0.0f}}};
    void *data[8];
    int part, k, nch = (int)strlen(f->chans), ready = 0;
    assert_true(fd >= 0);
    init.error_handler_fn = quiet;
    init.write_fn = fx_write;
    init.user_data = &fd;
    dw.min.x = f->x0, dw.min.y = f->y0;
    dw.max.x = f->x0 + f->w - 1, dw.max.y = f->y0 + f->h - 1;
    assert_int_equal(exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init), 0);
    assert_int_equal(exr_add_part(ctx, NULL, f->storage, &part), 0);
    assert_int_equal(exr_initialize_required_attr(ctx, part, &dw, &dw, 1.0f, &center, 1.0f,
                                                  EXR_LINEORDER_INCREASING_Y, f->comp),
                     0);
    if (f->storage == EXR_STORAGE_TILED)
        assert_int_equal(exr_set_tile_descriptor(ctx, part, (uint32_t)f->tile, (uint32_t)f->tile,
                                                 f->levels, EXR_TILE_ROUND_DOWN),
                         0);
    for (k = 0; k < nch; k++) {
        char name[2] = {f->chans[k], 0};
        assert_int_equal(
            exr_add_channel(ctx, part, name, f->type, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1), 0);
    }
    assert_int_equal(exr_write_header(ctx), 0);
    if (header_only) {
        exr_finish(&ctx);
        close(fd);
        return;
    }
    if (f->storage == EXR_STORAGE_SCANLINE) {
        int32_t lpc;
        int y;
        for (k = 0; k < nch; k++) data[k] = level_data(f, k, f->w, f->h, 0);
        assert_int_equal(exr_get_scanlines_per_chunk(ctx, part, &lpc), 0);
        for (y = f->y0; y < f->y0 + f->h; y += lpc) {
            exr_chunk_info_t ci;
            assert_int_equal(exr_write_scanline_chunk_info(ctx, part, y, &ci), 0);
            encode_chunk(ctx, f, &ci, &enc, &ready, data, f->w, 0, y - f->y0);
        }
        for (k = 0; k < nch; k++) free(data[k]);
    } else {
        int32_t nlx = 1, nly = 1, lx, ly;
        if (f->levels != EXR_TILE_ONE_LEVEL)
            assert_int_equal(exr_get_tile_levels(ctx, part, &nlx, &nly), 0);
        for (ly = 0; ly < nly; ly++)
            for (lx = 0; lx < nlx; lx++) {
                int32_t lw, lh;
                int tx, ty;
                if (f->levels == EXR_TILE_MIPMAP_LEVELS && lx != ly) continue;
                assert_int_equal(exr_get_level_sizes(ctx, part, lx, ly, &lw, &lh), 0);
                for (k = 0; k < nch; k++) data[k] = level_data(f, k, lw, lh, lx + ly);
                for (ty = 0; ty * f->tile < lh; ty++)
                    for (tx = 0; tx * f->tile < lw; tx++) {
                        exr_chunk_info_t ci;
                        assert_int_equal(exr_write_tile_chunk_info(ctx, part, tx, ty, lx, ly, &ci),
                                         0);
                        encode_chunk(ctx, f, &ci, &enc, &ready, data, lw, tx * f->tile,
                                     ty * f->tile);
                    }
                for (k = 0; k < nch; k++) free(data[k]);
            }
    }
    if (ready) exr_encoding_destroy(ctx, &enc);
    assert_int_equal(exr_finish(&ctx), 0);
    close(fd);
}

/* Read path with ggImageRead and compare with the fixture's R, G, B (or Y
   as grey); returns the largest absolute error. */
static double check_fixture_mean(const char *path, const fixture *f, double *mean)
{
    ggImage *img = NULL;
    ggError e;
    int kr = chan_index(f, "R"), kg = chan_index(f, "G"), kb = chan_index(f, "B");
    int x, y;
    double maxerr = 0.0, sum = 0.0;
    if (kr < 0 && kg < 0 && kb < 0) kr = kg = kb = chan_index(f, "Y");
    e.message[0] = 0;
    if (ggImageRead(path, NULL, &img, &e) != GG_OK) fail_msg("%s", e.message);
    assert_int_equal(ggImageWidth(img), f->w);
    assert_int_equal(ggImageHeight(img), f->h);
    for (y = 0; y < f->h; y++)
        for (x = 0; x < f->w; x++) {
            ggColor c = ggImageGet(img, x, y);
            double r = kr < 0 ? 0.0 : fx_value(f, kr, x, y, 0);
            double g = kg < 0 ? 0.0 : fx_value(f, kg, x, y, 0);
            double b = kb < 0 ? 0.0 : fx_value(f, kb, x, y, 0);
            maxerr = fmax(maxerr, fabs(c.r - r));
            maxerr = fmax(maxerr, fabs(c.g - g));
            maxerr = fmax(maxerr, fabs(c.b - b));
            sum += fabs(c.r - r) + fabs(c.g - g) + fabs(c.b - b);
        }
    ggImageFree(img);
    *mean = sum / (3.0 * f->w * f->h);
    return maxerr;
}

static double check_fixture(const char *path, const fixture *f)
{
    double mean;
    return check_fixture_mean(path, f, &mean);
}

/* ---- tests --------------------------------------------------------------- */

static void test_exr_round_trip_bit_exact(void **state)
{
    static const int sizes[][2] = {{37, 41}, {1, 1}, {1, 40}, {300, 2}};
    tu_rng r = {17};
    size_t s;
    (void)state;
    for (s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        int w = sizes[s][0], h = sizes[s][1];
        ggImage *img = ggImageCreate(w, h, NULL), *back = NULL;
        float *p = ggImagePixels(img);
        size_t i, n = (size_t)w * (size_t)h * 3;
        ggError e;
        for (i = 0; i < n; i++) {
            uint32_t bits = (uint32_t)tu_next(&r);
            switch (i % 4) {
            case 0:
                memcpy(&p[i], &bits, 4);
                break; /* any bit pattern, NaNs included */
            case 1:
                p[i] = (float)tu_range(&r, -1e30, 1e30);
                break;
            case 2:
                p[i] = (float)tu_range(&r, 0.0, 1.0);
                break;
            default:
                p[i] = (float)(tu_range(&r, -1.0, 1.0) * 1e-40);
                break; /* denormals */
            }
        }
        if (n > 3) p[0] = INFINITY, p[1] = -INFINITY, p[2] = -0.0f;
        assert_int_equal(ggImageWriteEXR(img, tu_tmppath("rt.exr"), &e), GG_OK);
        assert_int_equal(ggImageRead(tu_tmppath("rt.exr"), NULL, &back, &e), GG_OK);
        assert_int_equal(ggImageWidth(back), w);
        assert_int_equal(ggImageHeight(back), h);
        assert_memory_equal(ggImagePixels(back), p, n * sizeof(float));
        ggImageFree(img);
        ggImageFree(back);
    }
}

/* One image of n floats, the first k zero and the rest any bits, written
   alone or with a layer of any bits beside it (ggrt render --aov's
   files); the image and the layer must come back. */
static int round_trips(int w, int h, int k, int layered, tu_rng *r)
{
    static const char *const names[1] = {"aov"};
    const char *path = tu_tmppath("sweep.exr");
    ggImage *img = ggImageCreate(w, h, NULL), *layer = ggImageCreate(w, h, NULL);
    ggImage *back = NULL, *lback = NULL;
    const ggImage *layers[1];
    float *p = ggImagePixels(img), *q = ggImagePixels(layer);
    size_t i, n = (size_t)w * (size_t)h * 3;
    ggError e;
    int same;
    for (i = 0; i < n; i++) {
        uint32_t a = i < (size_t)k ? 0u : (uint32_t)(tu_next(r) >> 16);
        uint32_t b = layered ? (uint32_t)(tu_next(r) >> 16) : 0u;
        memcpy(&p[i], &a, 4);
        memcpy(&q[i], &b, 4);
    }
    layers[0] = layer;
    assert_int_equal(layered ? ggImageWriteEXRLayers(img, layers, names, 1, NULL, path, &e)
                             : ggImageWriteEXR(img, path, &e),
                     GG_OK);
    assert_int_equal(ggImageRead(path, NULL, &back, &e), GG_OK);
    same = memcmp(ggImagePixels(back), p, n * sizeof(float)) == 0;
    if (layered) {
        assert_int_equal(ggImageReadEXRLayer(path, "aov", NULL, &lback, &e), GG_OK);
        same = same && memcmp(ggImagePixels(lback), q, n * sizeof(float)) == 0;
    }
    ggImageFree(img);
    ggImageFree(layer);
    ggImageFree(back);
    ggImageFree(lback);
    return same;
}

/* Every amount of redundancy, from none to all, in one chunk of 16 rows
   or in the second: zlib's output then passes through the length of the
   raw chunk, which OpenEXR's own ZIP encoder gets wrong
   (lib/imageio/image_exr.c, compress_guarded). Before the guard, 6 of these
   1,570 images, 2 of the 785 files with a layer, and the 2x3 image below
   (found by tests/fuzz/fuzz_image.c) came back with other pixels. */
static void test_exr_round_trip_any_compressibility(void **state)
{
    static const int sizes[][2] = {{1, 1},  {2, 3},  {3, 2},  {4, 4},
                                   {1, 17}, {2, 17}, {5, 16}, {3, 33}};
    static const uint32_t found[18] = {0x00000001, 0x00000000, 0xc9559c78, 0x00020047, 0x00000001,
                                       0x00001151, 0xabfab694, 0xccee1d8a, 0x00000000, 0xce9014b9,
                                       0x8ddcd314, 0x00010000, 0x5d1efded, 0xea46c64d, 0x65eb7524,
                                       0xc03f548b, 0xde96a98a, 0xb97b91e4};
    tu_rng r = {23};
    ggImage *img = ggImageCreate(2, 3, NULL), *back = NULL;
    ggError e;
    size_t s;
    int k, rep, bad = 0;
    (void)state;
    memcpy(ggImagePixels(img), found, sizeof found);
    assert_int_equal(ggImageWriteEXR(img, tu_tmppath("found.exr"), &e), GG_OK);
    assert_int_equal(ggImageRead(tu_tmppath("found.exr"), NULL, &back, &e), GG_OK);
    assert_memory_equal(ggImagePixels(back), found, sizeof found);
    ggImageFree(img);
    ggImageFree(back);
    for (s = 0; s < sizeof sizes / sizeof sizes[0]; s++)
        for (k = 0; k <= sizes[s][0] * sizes[s][1] * 3; k++)
            for (rep = 0; rep < 2; rep++) bad += !round_trips(sizes[s][0], sizes[s][1], k, 0, &r);
    assert_int_equal(bad, 0);
    /* the same with a layer beside the image (ggrt render --aov's files) */
    for (s = 0; s < sizeof sizes / sizeof sizes[0]; s++)
        for (k = 0; k <= sizes[s][0] * sizes[s][1] * 3; k++)
            bad += !round_trips(sizes[s][0], sizes[s][1], k, 1, &r);
    assert_int_equal(bad, 0);
}

/* What ggImageWriteEXR writes, as OpenEXR itself sees it. */
static void test_exr_written_header(void **state)
{
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    ggImage *img = ggImageCreate(9, 40, NULL);
    const exr_attr_chlist_t *chl;
    exr_context_t ctx;
    exr_compression_t comp;
    exr_storage_t st;
    exr_attr_box2i_t dw;
    int i;
    (void)state;
    init.error_handler_fn = quiet;
    assert_int_equal(ggImageWrite(img, tu_tmppath("hdr.exr"), NULL), GG_OK);
    assert_int_equal(exr_start_read(&ctx, tu_tmppath("hdr.exr"), &init), 0);
    assert_int_equal(exr_get_storage(ctx, 0, &st), 0);
    assert_int_equal(st, EXR_STORAGE_SCANLINE);
    assert_int_equal(exr_get_compression(ctx, 0, &comp), 0);
    assert_int_equal(comp, EXR_COMPRESSION_ZIP);
    assert_int_equal(exr_get_data_window(ctx, 0, &dw), 0);
    assert_true(dw.min.x == 0 && dw.min.y == 0 && dw.max.x == 8 && dw.max.y == 39);
    assert_int_equal(exr_get_channels(ctx, 0, &chl), 0);
    assert_int_equal(chl->num_channels, 3);
    for (i = 0; i < 3; i++) {
        assert_int_equal(chl->entries[i].pixel_type, EXR_PIXEL_FLOAT);
        assert_non_null(strchr("RGB", chl->entries[i].name.str[0]));
    }
    exr_finish(&ctx);
    ggImageFree(img);
}

static void test_exr_half_every_compression(void **state)
{
    static const exr_compression_t comps[] = {
        EXR_COMPRESSION_NONE, EXR_COMPRESSION_RLE,   EXR_COMPRESSION_ZIPS, EXR_COMPRESSION_ZIP,
        EXR_COMPRESSION_PIZ,  EXR_COMPRESSION_PXR24, EXR_COMPRESSION_B44,  EXR_COMPRESSION_B44A};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof comps / sizeof comps[0]; i++) {
        fixture f = {EXR_STORAGE_SCANLINE, comps[i], EXR_PIXEL_HALF, "RGB", 0, 0, 21, 35, 0, 0};
        int lossy = comps[i] >= EXR_COMPRESSION_B44;
        double err, mean;
        write_fixture(tu_tmppath("half.exr"), &f, 0);
        err = check_fixture_mean(tu_tmppath("half.exr"), &f, &mean);
        /* Lossless codecs must be exact. B44 is lossy by design and this
           noise (values 0..5.5) is its worst case (measured: max 1.75, mean
           0.32); a misplaced or garbled decode would be far off. (The 3.1
           C core writes no DWA; see test_exr_cpp_fixtures.) */
        if (lossy)
            assert_true(err < 2.5 && mean < 0.5);
        else if (err != 0.0)
            fail_msg("compression %d: max error %g", (int)comps[i], err);
    }
}

static void test_exr_float_uint_and_windows(void **state)
{
    fixture f1 = {
        EXR_STORAGE_SCANLINE, EXR_COMPRESSION_ZIP, EXR_PIXEL_FLOAT, "BGR", -5, 7, 19, 37, 0, 0};
    fixture f2 = {
        EXR_STORAGE_SCANLINE, EXR_COMPRESSION_PIZ, EXR_PIXEL_UINT, "RGB", 3, -2, 6, 40, 0, 0};
    fixture f3 = {
        EXR_STORAGE_SCANLINE, EXR_COMPRESSION_RLE, EXR_PIXEL_FLOAT, "ABGRZ", 0, 0, 4, 3, 0, 0};
    (void)state;
    write_fixture(tu_tmppath("f1.exr"), &f1, 0);
    assert_true(check_fixture(tu_tmppath("f1.exr"), &f1) == 0.0);
    write_fixture(tu_tmppath("f2.exr"), &f2, 0);
    assert_true(check_fixture(tu_tmppath("f2.exr"), &f2) == 0.0);
    write_fixture(tu_tmppath("f3.exr"), &f3, 0);
    assert_true(check_fixture(tu_tmppath("f3.exr"), &f3) == 0.0);
}

static void test_exr_tiled(void **state)
{
    fixture f1 = {EXR_STORAGE_TILED, EXR_COMPRESSION_ZIP, EXR_PIXEL_FLOAT, "RGB", 3, -4, 19, 13, 8,
                  EXR_TILE_ONE_LEVEL};
    fixture f2 = {EXR_STORAGE_TILED, EXR_COMPRESSION_ZIP, EXR_PIXEL_HALF, "RGBA", 0, 0, 5, 7, 32,
                  EXR_TILE_ONE_LEVEL};
    fixture f3 = {
        EXR_STORAGE_TILED,     EXR_COMPRESSION_PIZ, EXR_PIXEL_HALF, "RGB", -1, -1, 16, 12, 4,
        EXR_TILE_MIPMAP_LEVELS};
    fixture f4 = {EXR_STORAGE_TILED, EXR_COMPRESSION_ZIPS, EXR_PIXEL_FLOAT, "G", 0, 0, 9, 9, 2,
                  EXR_TILE_ONE_LEVEL};
    /* An unused channel sorting last: OpenEXR 3.1.5 crashed on it when it
       was skipped with a NULL pointer (found by fuzzing). */
    fixture f5 = {EXR_STORAGE_TILED, EXR_COMPRESSION_ZIP, EXR_PIXEL_HALF, "BGN", 1, -1, 5, 4, 2,
                  EXR_TILE_ONE_LEVEL};
    (void)state;
    write_fixture(tu_tmppath("t1.exr"), &f1, 0);
    assert_true(check_fixture(tu_tmppath("t1.exr"), &f1) == 0.0);
    write_fixture(tu_tmppath("t2.exr"), &f2, 0);
    assert_true(check_fixture(tu_tmppath("t2.exr"), &f2) == 0.0);
    write_fixture(tu_tmppath("t3.exr"), &f3, 0); /* levels 1.. hold +100: must not leak in */
    assert_true(check_fixture(tu_tmppath("t3.exr"), &f3) == 0.0);
    write_fixture(tu_tmppath("t4.exr"), &f4, 0);
    assert_true(check_fixture(tu_tmppath("t4.exr"), &f4) == 0.0);
    write_fixture(tu_tmppath("t5.exr"), &f5, 0);
    assert_true(check_fixture(tu_tmppath("t5.exr"), &f5) == 0.0);
}

/* Files from tests/data/make_exr_fixtures.cpp (OpenEXR's C++ library). */
static void test_exr_cpp_fixtures(void **state)
{
    static const char *dwa[2] = {"tests/data/dwaa.exr", "tests/data/dwab.exr"};
    ggImage *img = NULL;
    ggError e;
    int i, x, y;
    (void)state;
    /* DWA: OpenEXR 3.1's C core cannot decompress it and says so; a newer
       core reads it, lossy but close on this smooth ramp. */
    for (i = 0; i < 2; i++) {
        int rc = ggImageRead(dwa[i], NULL, &img, &e);
        if (rc == GG_ERROR_UNSUPPORTED) {
            assert_non_null(strstr(e.message, "DWA"));
            assert_null(img);
            continue;
        }
        assert_int_equal(rc, GG_OK);
        for (y = 0; y < 16; y++)
            for (x = 0; x < 16; x++) {
                ggColor c = ggImageGet(img, x, y);
                assert_close(c.r, x / 16.0, 0.02);
                assert_close(c.g, y / 16.0, 0.02);
                assert_close(c.b, (x + y) / 32.0, 0.02);
            }
        ggImageFree(img);
        img = NULL;
    }
    /* Ripmap: only level (0, 0) is read; the others add 10 (lx + ly). */
    assert_int_equal(ggImageRead("tests/data/ripmap.exr", NULL, &img, &e), GG_OK);
    assert_int_equal(ggImageWidth(img), 9);
    assert_int_equal(ggImageHeight(img), 7);
    for (y = 0; y < 7; y++)
        for (x = 0; x < 9; x++) {
            ggColor c = ggImageGet(img, x, y);
            assert_true(c.r == ((x * 3 + y * 5) % 23) * 0.25);
            assert_true(c.g == ((x * 3 + y * 5 + 7) % 23) * 0.25);
            assert_true(c.b == ((x * 3 + y * 5 + 14) % 23) * 0.25);
        }
    ggImageFree(img);
}

static void test_exr_channels(void **state)
{
    fixture y = {EXR_STORAGE_SCANLINE, EXR_COMPRESSION_ZIPS, EXR_PIXEL_HALF, "Y", 0, 0, 6, 5, 0, 0};
    fixture g = {
        EXR_STORAGE_SCANLINE, EXR_COMPRESSION_NONE, EXR_PIXEL_FLOAT, "GA", 0, 0, 3, 3, 0, 0};
    fixture yr = {
        EXR_STORAGE_SCANLINE, EXR_COMPRESSION_NONE, EXR_PIXEL_FLOAT, "YR", 0, 0, 3, 3, 0, 0};
    fixture none = {
        EXR_STORAGE_SCANLINE, EXR_COMPRESSION_NONE, EXR_PIXEL_FLOAT, "AZ", 0, 0, 3, 3, 0, 0};
    ggImage *img = NULL;
    ggError e;
    char msg[600];
    int x;
    (void)state;
    write_fixture(tu_tmppath("y.exr"), &y, 0);
    assert_true(check_fixture(tu_tmppath("y.exr"), &y) == 0.0); /* grey: R = G = B = Y */
    write_fixture(tu_tmppath("g.exr"), &g, 0);
    assert_true(check_fixture(tu_tmppath("g.exr"), &g) == 0.0); /* R = B = 0 */
    /* With R present, Y is ignored (G and B missing read 0). */
    write_fixture(tu_tmppath("yr.exr"), &yr, 0);
    assert_int_equal(ggImageRead(tu_tmppath("yr.exr"), NULL, &img, &e), GG_OK);
    for (x = 0; x < 3; x++) {
        ggColor c = ggImageGet(img, x, 1);
        assert_true(c.r == fx_value(&yr, 1, x, 1, 0) && c.g == 0.0 && c.b == 0.0);
    }
    ggImageFree(img);
    img = NULL;
    write_fixture(tu_tmppath("none.exr"), &none, 0);
    assert_int_equal(ggImageRead(tu_tmppath("none.exr"), NULL, &img, &e), GG_ERROR_UNSUPPORTED);
    snprintf(msg, sizeof msg, "%s: no R, G, B or Y channel", tu_tmppath("none.exr"));
    assert_string_equal(e.message, msg);
    assert_null(img);
    /* a failed read leaves *out as it was, by either reader */
    img = (ggImage *)&img;
    assert_int_equal(ggImageRead(tu_tmppath("none.exr"), NULL, &img, &e), GG_ERROR_UNSUPPORTED);
    assert_ptr_equal(img, (ggImage *)&img);
    assert_int_equal(ggImageReadEXRLayer(tu_tmppath("none.exr"), "aov", NULL, &img, &e),
                     GG_ERROR_UNSUPPORTED);
    assert_ptr_equal(img, (ggImage *)&img);
    assert_int_equal(ggImageReadEXRLayer(tu_tmppath("missing.exr"), NULL, NULL, &img, &e),
                     GG_ERROR_IO);
    assert_ptr_equal(img, (ggImage *)&img);
}

static void test_exr_limits(void **state)
{
    fixture wide = {EXR_STORAGE_SCANLINE,
                    EXR_COMPRESSION_ZIP,
                    EXR_PIXEL_HALF,
                    "RGB",
                    0,
                    0,
                    GG_IMAGE_MAX_DIM + 1,
                    2,
                    0,
                    0};
    fixture huge = {EXR_STORAGE_SCANLINE,
                    EXR_COMPRESSION_ZIP,
                    EXR_PIXEL_HALF,
                    "RGB",
                    -9,
                    0,
                    20000,
                    20000,
                    0,
                    0};
    fixture tall = {
        EXR_STORAGE_SCANLINE, EXR_COMPRESSION_NONE, EXR_PIXEL_HALF, "RGB", 0, 0, 4000, 4000, 0, 0};
    ggImage *img = NULL;
    ggError e;
    (void)state;
    write_fixture(tu_tmppath("wide.exr"), &wide, 1);
    assert_int_equal(ggImageRead(tu_tmppath("wide.exr"), NULL, &img, &e), GG_ERROR_LIMIT);
    assert_non_null(strstr(e.message, "wide.exr: image of 65537 x 2 pixels exceeds"));
    write_fixture(tu_tmppath("huge.exr"), &huge, 1);
    assert_int_equal(ggImageRead(tu_tmppath("huge.exr"), NULL, &img, &e), GG_ERROR_LIMIT);
    /* Within the limits, a header alone is a truncated file (4000 chunks
       cannot fit in a few hundred bytes), found before allocating. */
    write_fixture(tu_tmppath("tall.exr"), &tall, 1);
    assert_int_equal(ggImageRead(tu_tmppath("tall.exr"), NULL, &img, &e), GG_ERROR_PARSE);
    assert_non_null(strstr(e.message, "truncated"));
    assert_null(img);
}

/* ---- luminance/chroma ------------------------------------------------------

   An uncompressed scanline file of half channels BY, RY (sampling s in x
   and y) and Y, written byte by byte: what OpenEXR's RgbaOutputFile writes
   in its YC mode with s = 2, but in one-line chunks. */
static size_t put_attr(unsigned char *p, const char *name, const char *type, const void *v,
                       int32_t n)
{
    size_t k = strlen(name) + 1, t = strlen(type) + 1;
    memcpy(p, name, k);
    memcpy(p + k, type, t);
    memcpy(p + k + t, &n, 4); /* (little-endian, as the file: x86) */
    memcpy(p + k + t + 4, v, (size_t)n);
    return k + t + 4 + (size_t)n;
}

static void write_yc(const char *path, int w, int h, int s)
{
    static const char *const names[3] = {"BY", "RY", "Y"};
    unsigned char hdr[1024], chl[128], *p = hdr, *q = chl;
    const int32_t box[4] = {0, 0, w - 1, h - 1};
    const float one = 1, center[2] = {0, 0};
    const uint16_t half_one = 0x3c00;
    uint64_t off;
    FILE *f;
    int c, x, y;
    for (c = 0; c < 3; c++) {
        int32_t v[4] = {1 /* HALF */, 0, c < 2 ? s : 1, c < 2 ? s : 1};
        memcpy(q, names[c], strlen(names[c]) + 1);
        q += strlen(names[c]) + 1;
        memcpy(q, v, sizeof v);
        q += sizeof v;
    }
    *q++ = 0;
    memcpy(p, "\x76\x2f\x31\x01\x02\0\0\0", 8);
    p += 8;
    p += put_attr(p, "channels", "chlist", chl, (int32_t)(q - chl));
    p += put_attr(p, "compression", "compression", "", 1);
    p += put_attr(p, "dataWindow", "box2i", box, 16);
    p += put_attr(p, "displayWindow", "box2i", box, 16);
    p += put_attr(p, "lineOrder", "lineOrder", "", 1);
    p += put_attr(p, "pixelAspectRatio", "float", &one, 4);
    p += put_attr(p, "screenWindowCenter", "v2f", center, 8);
    p += put_attr(p, "screenWindowWidth", "float", &one, 4);
    *p++ = 0;
    f = fopen(path, "wb");
    assert_non_null(f);
    fwrite(hdr, 1, (size_t)(p - hdr), f);
    off = (uint64_t)(p - hdr) + 8 * (uint64_t)h;
    for (y = 0; y < h; y++) { /* the offset table */
        int chroma = y % s == 0 ? 2 * (w / s) : 0;
        fwrite(&off, 8, 1, f);
        off += 8 + 2 * (uint64_t)(chroma + w);
    }
    for (y = 0; y < h; y++) {
        int32_t n = 2 * ((y % s == 0 ? 2 * (w / s) : 0) + w);
        fwrite(&y, 4, 1, f);
        fwrite(&n, 4, 1, f);
        for (x = 0; x < n / 2; x++) fwrite(&half_one, 2, 1, f);
    }
    fclose(f);
}

/* write_yc's file of w x h at sampling s is refused with `why`. */
static void yc_refused(int w, int h, int s, const char *why)
{
    ggImage *img = NULL;
    ggError e;
    char msg[600];
    write_yc(tu_tmppath("yc.exr"), w, h, s);
    assert_int_equal(ggImageRead(tu_tmppath("yc.exr"), NULL, &img, &e), GG_ERROR_UNSUPPORTED);
    assert_null(img);
    snprintf(msg, sizeof msg, "%s: %s", tu_tmppath("yc.exr"), why);
    assert_string_equal(e.message, msg);
}

/* Refused, with no read outside the reader's buffers (ASan): OpenEXR
   3.1.5 wrote the subsampled lines in full past ggrt's scratch buffer; and
   read with its chroma dropped, a colour image came out grey. */
static void test_exr_luminance_chroma(void **state)
{
    static const int sizes[][2] = {{64, 4}, {4, 2}, {2, 2}, {8, 6}};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        yc_refused(sizes[i][0], sizes[i][1], 2, "subsampled channel BY is not supported");
        yc_refused(sizes[i][0], sizes[i][1], 1,
                   "luminance/chroma (Y, RY, BY) images are not supported");
    }
}

/* A compressed chunk that does not decompress (from a fuzz run): OpenEXR
   3.1.5 says "out of memory" for it, which read as GG_ERROR_NOMEM. */
static void test_exr_undecompressable(void **state)
{
    ggImage *img = NULL;
    ggError e;
    (void)state;
    assert_int_equal(ggImageRead("tests/data/hostile/undecompressable.exr", NULL, &img, &e),
                     GG_ERROR_PARSE);
    assert_null(img);
    assert_non_null(strstr(e.message, "invalid OpenEXR file: unable to decompress"));
}

/* The library never prints: failing reads leave stderr empty. */
static void test_exr_silent(void **state)
{
    tu_rng r = {2};
    ggImage *img = ggImageCreate(20, 20, NULL), *back = NULL;
    char log[512];
    unsigned char buf[4096];
    FILE *f;
    size_t n, i;
    int saved, fd;
    (void)state;
    for (i = 0; i < 1200; i++) ggImagePixels(img)[i] = (float)tu_uniform(&r);
    assert_int_equal(ggImageWriteEXR(img, tu_tmppath("s.exr"), NULL), GG_OK);
    f = fopen(tu_tmppath("s.exr"), "rb");
    n = fread(buf, 1, sizeof buf, f);
    fclose(f);
    snprintf(log, sizeof log, "%s", tu_tmppath("stderr.log"));
    fflush(stderr);
    saved = dup(2);
    fd = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 2);
    close(fd);
    for (i = 0; i < n; i += 13) {
        f = fopen(tu_tmppath("cut.exr"), "wb");
        fwrite(buf, 1, i, f);
        fclose(f);
        ggImageRead(tu_tmppath("cut.exr"), NULL, &back, NULL);
        ggImageFree(back);
        back = NULL;
        f = fopen(tu_tmppath("cut.png"), "wb");
        fwrite("\x89PNG\r\n\x1a\n", 1, 8, f);
        fwrite(buf, 1, i, f);
        fclose(f);
        ggImageRead(tu_tmppath("cut.png"), NULL, &back, NULL);
        ggImageFree(back);
        back = NULL;
    }
    ggImageWriteEXR(img, "/nonexistent/dir/x.exr", NULL);
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    f = fopen(log, "rb");
    n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = 0;
    if (n) fail_msg("the library printed: %s", (char *)buf);
    ggImageFree(img);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_exr_round_trip_bit_exact),
        cmocka_unit_test(test_exr_round_trip_any_compressibility),
        cmocka_unit_test(test_exr_written_header),
        cmocka_unit_test(test_exr_half_every_compression),
        cmocka_unit_test(test_exr_float_uint_and_windows),
        cmocka_unit_test(test_exr_tiled),
        cmocka_unit_test(test_exr_cpp_fixtures),
        cmocka_unit_test(test_exr_channels),
        cmocka_unit_test(test_exr_limits),
        cmocka_unit_test(test_exr_luminance_chroma),
        cmocka_unit_test(test_exr_undecompressable),
        cmocka_unit_test(test_exr_silent),
    };
    return cmocka_run_group_tests_name("image_exr", tests, setup_dir, teardown_dir);
}
