/* SPDX-License-Identifier: MIT */
/*
** image_png.c -- PNG input and output through libpng's simplified API
** (no setjmp here: the simplified API catches libpng's errors itself and
** never prints).
*/
#include "image.h"

#include <errno.h>
#include <png.h>
#include <string.h>

/* libpng says "Read Error" both for a short file and a failing disk; the
   stream's end-of-file flag tells them apart. */
static int read_fail(FILE *fp, const char *path, const png_image *pi, ggError *err)
{
    char m[sizeof pi->message];
    gg_image_lower(pi->message, m, sizeof m);
    if (feof(fp)) return gg_error_set(err, GG_ERROR_PARSE, "%s: invalid PNG: truncated file", path);
    if (ferror(fp)) return gg_error_set(err, GG_ERROR_IO, "%s: cannot read: %s", path, m);
    return gg_error_set(err, GG_ERROR_PARSE, "%s: invalid PNG: %s", path, m);
}

/* libpng 1.6.39 allocates and zeroes a buffer of a tEXt, zTXt, iTXt, sPLT
   or pCAL chunk's declared length before reading its data: a 60-byte file
   declaring 2^31 bytes cost 2 GiB. Its own chunk limit does not stop that
   (png_set_chunk_malloc_max(p, 1000) on the low-level reader still costs
   2 GiB: for an ancillary chunk the limit is a benign error, a warning
   while reading), and the simplified API reads every chunk before the
   first IDAT inside png_image_begin_read_*, before a limit could be set.
   So those chunks are walked here first: each must fit in what is left of
   the file, which bounds what any of them can cost. The IDAT data and the
   chunks after it are libpng's: it streams IDAT and reads nothing after. */
static int check_chunks(FILE *fp, const char *path, ggError *err)
{
    unsigned char h[8];
    long size, pos = 8;
    char ebuf[128];
    if (fseek(fp, 0, SEEK_END) != 0 || (size = ftell(fp)) < 0) goto io;
    for (;;) {
        unsigned long len;
        if (fseek(fp, pos, SEEK_SET) != 0) goto io;
        if (fread(h, 1, sizeof h, fp) < sizeof h) break; /* libpng says what is short */
        len = (unsigned long)h[0] << 24 | (unsigned long)h[1] << 16 | (unsigned long)h[2] << 8 | h[3];
        if (memcmp(h + 4, "IDAT", 4) == 0) break;
        if (size - pos < 12 || len > (unsigned long)(size - pos - 12))
            return gg_error_set(err, GG_ERROR_PARSE,
                                "%s: invalid PNG: truncated file (byte %ld: a chunk of %lu bytes, "
                                "%ld are left)",
                                path, pos, len, size - pos - 12 > 0 ? size - pos - 12 : 0L);
        pos += 12 + (long)len;
    }
    clearerr(fp);
    if (fseek(fp, 0, SEEK_SET) == 0) return GG_OK;
io:
    return gg_error_set(err, GG_ERROR_IO, "%s: cannot read: %s", path,
                        gg_image_strerror(errno, ebuf, sizeof ebuf));
}

int gg_image_read_png(FILE *fp, const char *path, const ggAllocator *alloc,
                      const gg_image_budget *b, ggImage **out, ggError *err)
{
    png_image pi;
    ggImage *img;
    void *buf;
    size_t n, i, bytes;
    int linear, rc;
    if ((rc = check_chunks(fp, path, err)) != GG_OK) return rc;
    memset(&pi, 0, sizeof pi);
    pi.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_stdio(&pi, fp)) {
        rc = read_fail(fp, path, &pi, err);
        png_image_free(&pi);
        return rc;
    }
    /* The header's size, before a byte of pixel data is decoded. */
    rc = gg_image_check_size(path, pi.width, pi.height, err);
    if (rc == GG_OK) rc = gg_image_check_budget(path, pi.width, pi.height, b, err);
    if (rc != GG_OK) {
        png_image_free(&pi);
        return rc;
    }
    /* 16-bit files only come out of the simplified API as 16-bit linear;
       everything else as 8-bit sRGB, which we decode with our own table. */
    linear = (pi.format & PNG_FORMAT_FLAG_LINEAR) != 0;
    pi.format = linear ? PNG_FORMAT_LINEAR_RGB : PNG_FORMAT_RGB;
    n = (size_t)pi.width * (size_t)pi.height * 3;
    bytes = n * (linear ? 2 : 1);
    img = ggImageCreate((int)pi.width, (int)pi.height, alloc);
    /* Zeroed: libpng composites alpha onto what the buffer holds, so
       transparent pixels come out over black in both paths. */
    buf = img ? gg_mem_calloc(alloc, bytes, 1) : NULL;
    if (!buf) {
        ggImageFree(img);
        png_image_free(&pi);
        return gg_error_set(err, GG_ERROR_NOMEM, "%s: out of memory for %u x %u pixels", path,
                            (unsigned)pi.width, (unsigned)pi.height);
    }
    if (!png_image_finish_read(&pi, NULL, buf, (png_int_32)(pi.width * 3), NULL)) {
        rc = read_fail(fp, path, &pi, err);
        png_image_free(&pi);
        gg_mem_free(alloc, buf);
        ggImageFree(img);
        return rc;
    }
    if (linear) {
        const png_uint_16 *s = buf;
        for (i = 0; i < n; i++) img->px[i] = (float)(s[i] / 65535.0);
    } else {
        const png_byte *s = buf;
        float lut[256];
        for (i = 0; i < 256; i++) lut[i] = (float)ggSRGBToLinear((double)i / 255.0);
        for (i = 0; i < n; i++) img->px[i] = lut[s[i]];
    }
    gg_mem_free(alloc, buf);
    *out = img;
    return GG_OK;
}

GG_API int ggImageWritePNG(const ggImage *img, const char *path, ggError *err)
{
    gg_image_tmp t;
    png_image pi;
    png_byte *buf;
    FILE *fp;
    size_t n;
    int rc;
    if (!img || !path) return gg_error_set(err, GG_ERROR_INVALID, "ggImageWritePNG: NULL argument");
    n = (size_t)img->width * (size_t)img->height * 3;
    buf = gg_mem_alloc(GG_IMAGE_ALLOC(img), n);
    if (!buf) return gg_error_set(err, GG_ERROR_NOMEM, "%s: out of memory", path);
    ggLinearToSRGB8(img->px, buf, n);
    rc = gg_image_tmp_open(&t, path, err);
    if (rc != GG_OK) {
        gg_mem_free(GG_IMAGE_ALLOC(img), buf);
        return rc;
    }
    fp = fdopen(t.fd, "wb");
    if (!fp) {
        char ebuf[128];
        rc = gg_error_set(err, GG_ERROR_IO, "%s: cannot write: %s", path,
                          gg_image_strerror(errno, ebuf, sizeof ebuf));
        gg_image_tmp_abort(&t, NULL);
        gg_mem_free(GG_IMAGE_ALLOC(img), buf);
        return rc;
    }
    memset(&pi, 0, sizeof pi);
    pi.version = PNG_IMAGE_VERSION;
    pi.width = (png_uint_32)img->width;
    pi.height = (png_uint_32)img->height;
    pi.format = PNG_FORMAT_RGB;
    errno = 0;
    if (!png_image_write_to_stdio(&pi, fp, 0, buf, 0, NULL)) {
        char ebuf[128];
        int e = errno;
        rc = gg_error_set(err, GG_ERROR_IO, "%s: cannot write PNG: %s%s%s%s", path, pi.message,
                          e ? " (" : "", e ? gg_image_strerror(e, ebuf, sizeof ebuf) : "",
                          e ? ")" : "");
        png_image_free(&pi);
        gg_image_tmp_abort(&t, fp);
        gg_mem_free(GG_IMAGE_ALLOC(img), buf);
        return rc;
    }
    gg_mem_free(GG_IMAGE_ALLOC(img), buf);
    return gg_image_tmp_commit(&t, fp, err);
}
