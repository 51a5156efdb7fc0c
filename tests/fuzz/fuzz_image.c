/* SPDX-License-Identifier: MIT */
/*
** fuzz_image.c -- ggImageRead on arbitrary bytes (written to a temporary
** file, since the reader takes a path). Properties checked on every input:
** no crash, no leak; success exactly when an image comes back; an image
** within the documented limits whose every pixel can be read; a failure
** with ggError filled and naming the file; and a small image that was read
** survives an EXR round trip bit for bit, alone and as a layer. PNG inputs
** of odd size get their chunks' CRCs set right first (fix_crcs).
*/
#include "ggrt.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Refuse big allocations so a tiny header claiming 2^28 pixels tests the
   out-of-memory path instead of exhausting the fuzzer's memory. */
#define FUZZ_ALLOC_CAP ((size_t)64 << 20)

static void *cap_malloc(void *ud, size_t n)
{
    (void)ud;
    return n > FUZZ_ALLOC_CAP ? NULL : malloc(n);
}
static void *cap_realloc(void *ud, void *p, size_t n)
{
    (void)ud;
    return n > FUZZ_ALLOC_CAP ? NULL : realloc(p, n);
}
static void cap_free(void *ud, void *p)
{
    (void)ud;
    free(p);
}

static const ggAllocator cap_alloc = {cap_malloc, cap_realloc, cap_free, NULL};

static void check(int ok, const char *what)
{
    if (!ok) {
        fprintf(stderr, "fuzz_image: property violated: %s\n", what);
        abort();
    }
}

static void make_temp(char *path, size_t n, const char *tag)
{
    const char *dir = getenv("TMPDIR");
    snprintf(path, n, "%s/gg_fuzz_image_%s_XXXXXX", dir && *dir ? dir : "/tmp", tag);
}

static const char *const layer_names[1] = {"L"};

static void exr_round_trip(const ggImage *img)
{
    char path[512];
    ggImage *back = NULL;
    int fd;
    size_t n = (size_t)ggImageWidth(img) * (size_t)ggImageHeight(img) * 3;
    make_temp(path, sizeof path, "rt");
    fd = mkstemp(path);
    if (fd < 0) return;
    close(fd);
    check(ggImageWriteEXR(img, path, NULL) == GG_OK, "EXR write of a read image");
    check(ggImageRead(path, NULL, &back, NULL) == GG_OK, "EXR re-read");
    check(ggImageWidth(back) == ggImageWidth(img) && ggImageHeight(back) == ggImageHeight(img),
          "EXR round trip keeps the size");
    check(memcmp(ggImagePixelsConst(back), ggImagePixelsConst(img), n * sizeof(float)) == 0,
          "EXR round trip keeps every bit");
    ggImageFree(back);
    back = NULL;
    /* The same image as a layer beside itself (ggrt render --aov's files):
       twice the channels in a chunk, through the same chunk writer. */
    check(ggImageWriteEXRLayers(img, &img, layer_names, 1, NULL, path, NULL) == GG_OK,
          "EXR write of a read image with a layer");
    check(ggImageReadEXRLayer(path, "L", NULL, &back, NULL) == GG_OK, "EXR layer re-read");
    check(ggImageWidth(back) == ggImageWidth(img) && ggImageHeight(back) == ggImageHeight(img) &&
              memcmp(ggImagePixelsConst(back), ggImagePixelsConst(img), n * sizeof(float)) == 0,
          "EXR layer round trip keeps every bit");
    ggImageFree(back);
    unlink(path);
}

/* PNG's CRC-32 (ISO 3309), bit by bit: the harness's, not zlib's. */
static uint32_t crc32_of(const uint8_t *p, size_t n)
{
    uint32_t c = 0xffffffffu;
    int k;
    while (n--)
        for (c ^= *p++, k = 0; k < 8; k++) c = c & 1 ? 0xedb88320u ^ (c >> 1) : c >> 1;
    return c ^ 0xffffffffu;
}

/* Most mutations of a PNG's IHDR, PLTE or IDAT stop at libpng's "CRC
   error" and never reach the decoder: in inputs of odd size (the others
   keep testing the CRC checks) every whole chunk's CRC is set right. */
static void fix_crcs(uint8_t *b, size_t size)
{
    size_t at = 8;
    if (size < 8 || !(size & 1) || memcmp(b, "\x89PNG\r\n\x1a\n", 8) != 0) return;
    while (size - at >= 12) {
        uint32_t len = (uint32_t)b[at] << 24 | (uint32_t)b[at + 1] << 16 |
                       (uint32_t)b[at + 2] << 8 | b[at + 3];
        uint32_t c;
        if (len > size - at - 12) return;
        c = crc32_of(b + at + 4, (size_t)len + 4);
        b[at + 8 + len] = (uint8_t)(c >> 24), b[at + 9 + len] = (uint8_t)(c >> 16);
        b[at + 10 + len] = (uint8_t)(c >> 8), b[at + 11 + len] = (uint8_t)c;
        at += 12 + (size_t)len;
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[512];
    ggImage *img = NULL;
    ggError e;
    size_t done = 0;
    uint8_t *copy = malloc(size ? size : 1);
    int fd, rc;
    if (!copy) return 0;
    memcpy(copy, data, size);
    fix_crcs(copy, size);
    make_temp(path, sizeof path, "in");
    fd = mkstemp(path);
    if (fd < 0) {
        free(copy);
        return 0;
    }
    while (done < size) {
        ssize_t w = write(fd, copy + done, size - done);
        if (w <= 0) break;
        done += (size_t)w;
    }
    free(copy);
    close(fd);
    e.code = -1;
    e.message[0] = 0;
    rc = ggImageRead(path, &cap_alloc, &img, &e);
    if (rc == GG_OK) {
        int w = ggImageWidth(img), h = ggImageHeight(img);
        const float *p = ggImagePixelsConst(img);
        size_t i, n = (size_t)w * (size_t)h * 3;
        volatile float sink = 0.0f;
        check(img != NULL, "GG_OK returns an image");
        check(w >= 1 && h >= 1 && w <= GG_IMAGE_MAX_DIM && h <= GG_IMAGE_MAX_DIM &&
                  (size_t)w * (size_t)h <= GG_IMAGE_MAX_PIXELS,
              "image within the limits");
        for (i = 0; i < n; i++) sink += p[i];
        (void)sink;
        if (n <= 3 * 4096) exr_round_trip(img);
        ggImageFree(img);
    } else {
        check(img == NULL, "a failure leaves *out untouched");
        check(e.code == rc, "ggError carries the returned code");
        check(strncmp(e.message, path, strlen(path)) == 0, "the message names the file");
        check(rc == GG_ERROR_PARSE || rc == GG_ERROR_UNSUPPORTED || rc == GG_ERROR_LIMIT ||
                  rc == GG_ERROR_NOMEM || rc == GG_ERROR_IO,
              "a documented error code");
    }
    unlink(path);
    return 0;
}
