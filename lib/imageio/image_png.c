/* SPDX-License-Identifier: MIT */
/*
** image_png.c -- PNG input through libpng's low-level API (its errors
** caught by setjmp in one function, decode), output through its simplified
** API (which catches its own); neither ever prints.
*/
#include "image.h"

#include <errno.h>
#include <math.h>
#include <png.h>
#include <setjmp.h>
#include <stdio.h>
#include <string.h>

/* libpng says "Read Error" both for a short file and a failing disk; the
   stream's end-of-file flag tells them apart. */
static int read_fail(FILE *fp, const char *path, const char *message, ggError *err)
{
    char m[128];
    /* libpng's own allocations ("Out of memory", "insufficient memory") */
    if (strstr(message, "memory"))
        return gg_error_set(err, GG_ERROR_NOMEM, "%s: out of memory (in libpng)", path);
    gg_image_lower(message, m, sizeof m);
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
   the file, which bounds what reading any of them can cost (and decode
   has libpng skip those no sample depends on, so that a compressed text
   is not inflated either). The IDAT data and the chunks after it are
   libpng's: it streams IDAT and reads nothing after. */
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

/* ---- reading: libpng's low-level API, so that every sample is decoded
   here. The simplified API decodes 16-bit files with libpng's own gamma
   code (a file without gAMA or sRGB as linear, an sRGB one as a 2.2
   power) and passes 8-bit files with alpha or another gamma through 8-bit
   sRGB, 1-2% off: the same picture read differently at two depths. ---- */

typedef struct png_reader {
    FILE *fp;
    const char *path;
    const ggAllocator *alloc;
    const gg_image_budget *budget;
    png_structp png;
    png_infop info;
    png_bytep data;  /* the decoded rows */
    png_bytepp rows; /* pointers into data */
    double *lut;     /* sample -> linear, 256 or 65536 entries */
    ggImage *img;
    ggError *err;
    int rc;            /* GG_OK, or the code of an error already set in err */
    char message[128]; /* libpng's error */
} png_reader;

/* Never print: libpng's message is kept for the error, its warnings
   (ancillary chunks it skips) are dropped. */
static void on_png_error(png_structp png, png_const_charp msg)
{
    png_reader *r = png_get_error_ptr(png);
    snprintf(r->message, sizeof r->message, "%s", msg);
    png_longjmp(png, 1);
}

static void on_png_warning(png_structp png, png_const_charp msg)
{
    (void)png, (void)msg;
}

/* The file's transfer function as an exponent: 0 for sRGB, which an sRGB
   or iCCP chunk declares and a file without either is taken to be; else
   1/gamma of its gAMA, where that is not within 5% of sRGB's 1/2.2 (the
   tolerance libpng itself takes a gAMA as sRGB with). */
static double transfer_exponent(const png_reader *r)
{
    png_fixed_point g = 0;
    if (png_get_valid(r->png, r->info, PNG_INFO_sRGB | PNG_INFO_iCCP)) return 0;
    if (!png_get_gAMA_fixed(r->png, r->info, &g) || g <= 0) return 0;
    if (fabs(g * 2.2e-5 - 1) < 0.05) return 0;
    return 1e5 / g;
}

static int fill_lut(png_reader *r, int depth)
{
    const size_t n = depth == 16 ? 65536 : 256;
    const double e = transfer_exponent(r), max = (double)(n - 1);
    size_t i;
    r->lut = gg_mem_alloc(r->alloc, n * sizeof *r->lut);
    if (!r->lut) return 0;
    for (i = 0; i < n; i++) r->lut[i] = e == 0 ? ggSRGBToLinear(i / max) : pow(i / max, e);
    return 1;
}

/* The rows, as 8- or 16-bit RGB or RGBA, into r->img: colour through the
   transfer function, then times alpha (over black, premultiplied). */
static void convert(png_reader *r, int channels, int depth)
{
    const size_t w = (size_t)r->img->width, h = (size_t)r->img->height;
    const double amax = depth == 16 ? 65535.0 : 255.0;
    size_t x, y;
    int k;
    for (y = 0; y < h; y++) {
        const png_byte *s = r->rows[y];
        float *d = r->img->px + 3 * w * y;
        for (x = 0; x < w; x++, s += channels * (depth / 8), d += 3) {
            unsigned v[4];
            for (k = 0; k < channels; k++)
                v[k] = depth == 16 ? (unsigned)s[2 * k] << 8 | s[2 * k + 1] : s[k];
            for (k = 0; k < 3; k++)
                d[k] = channels == 4 ? (float)(r->lut[v[k]] * (v[3] / amax)) : (float)r->lut[v[k]];
        }
    }
}

#ifdef PNG_HANDLE_AS_UNKNOWN_SUPPORTED
static const png_byte unused_chunks[] = "tEXt\0zTXt\0iTXt\0sPLT\0pCAL\0eXIf\0hIST\0sCAL\0"
                                        "tIME\0pHYs\0bKGD\0cHRM\0sBIT\0oFFs";
#endif

/* Everything that may call on_png_error: r's fields say what to free. */
static int decode(png_reader *r)
{
    png_uint_32 w, h, y;
    int depth, channels;
    size_t rowbytes;
    if (setjmp(png_jmpbuf(r->png))) return 0;
    png_init_io(r->png, r->fp);
    png_set_user_limits(r->png, 0x7fffffff, 0x7fffffff); /* ours are checked below */
#ifdef PNG_HANDLE_AS_UNKNOWN_SUPPORTED
    /* The ancillary chunks no sample depends on are skipped unread: libpng
       inflates each zTXt or compressed iTXt (to 8 MB, up to 1000 chunks)
       and keeps the text, so a 1.5 MB file of them took 1.6 GB. gAMA,
       sRGB, iCCP, tRNS and PLTE are still read. */
    png_set_keep_unknown_chunks(r->png, PNG_HANDLE_CHUNK_NEVER, unused_chunks,
                                (int)(sizeof unused_chunks / 5));
#endif
    png_read_info(r->png, r->info);
    w = png_get_image_width(r->png, r->info);
    h = png_get_image_height(r->png, r->info);
    /* The header's size, before a byte of pixel data is decoded. */
    r->rc = gg_image_check_size(r->path, w, h, r->err);
    if (r->rc == GG_OK) r->rc = gg_image_check_budget(r->path, w, h, r->budget, r->err);
    if (r->rc != GG_OK) return 0;
    png_set_expand(r->png); /* palette to RGB, grey to 8 bits, tRNS to alpha */
    png_set_gray_to_rgb(r->png);
    png_set_interlace_handling(r->png);
    png_read_update_info(r->png, r->info);
    depth = png_get_bit_depth(r->png, r->info);
    channels = png_get_channels(r->png, r->info);
    rowbytes = png_get_rowbytes(r->png, r->info);
    if ((depth != 8 && depth != 16) || (channels != 3 && channels != 4) ||
        rowbytes != (size_t)w * (size_t)channels * (size_t)(depth / 8))
        png_error(r->png, "unexpected layout after expansion"); /* (not reached) */
    r->img = ggImageCreate((int)w, (int)h, r->alloc);
    r->data = r->img ? gg_mem_calloc(r->alloc, rowbytes, h) : NULL;
    r->rows = r->data ? gg_mem_calloc(r->alloc, h, sizeof *r->rows) : NULL;
    if (!r->rows || !fill_lut(r, depth)) {
        r->rc = gg_error_set(r->err, GG_ERROR_NOMEM, "%s: out of memory for %u x %u pixels",
                             r->path, (unsigned)w, (unsigned)h);
        return 0;
    }
    for (y = 0; y < h; y++) r->rows[y] = r->data + (size_t)y * rowbytes;
    /* As the simplified API did, nothing after the image data is read: a
       file whose IEND is missing still reads. */
    png_read_image(r->png, r->rows);
    convert(r, channels, depth);
    return 1;
}

int gg_image_read_png(FILE *fp, const char *path, const ggAllocator *alloc,
                      const gg_image_budget *b, ggImage **out, ggError *err)
{
    png_reader r;
    int ok, rc;
    if ((rc = check_chunks(fp, path, err)) != GG_OK) return rc;
    memset(&r, 0, sizeof r);
    r.fp = fp, r.path = path, r.alloc = alloc, r.budget = b, r.err = err, r.rc = GG_OK;
    r.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &r, on_png_error, on_png_warning);
    r.info = r.png ? png_create_info_struct(r.png) : NULL;
    ok = r.info && decode(&r);
    if (ok)
        rc = GG_OK;
    else if (!r.info)
        rc = gg_error_set(err, GG_ERROR_NOMEM, "%s: out of memory", path);
    else if (r.rc != GG_OK)
        rc = r.rc;
    else
        rc = read_fail(fp, path, r.message, err);
    png_destroy_read_struct(r.png ? &r.png : NULL, r.info ? &r.info : NULL, NULL);
    gg_mem_free(alloc, r.lut);
    gg_mem_free(alloc, r.rows);
    gg_mem_free(alloc, r.data);
    if (!ok) {
        ggImageFree(r.img);
        return rc;
    }
    *out = r.img;
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
