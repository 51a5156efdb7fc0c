/* SPDX-License-Identifier: MIT */
/*
** image.c -- the ggImage object: creation, pixel access, crop and paste,
** the sRGB transfer functions and image comparison.
*/
#include "image.h"

#include <math.h>
#include <string.h>

int gg_image_check_size(const char *path, int64_t w, int64_t h, ggError *err)
{
    if (w <= 0 || h <= 0)
        return gg_error_set(err, GG_ERROR_PARSE, "%s: invalid image size %lld x %lld", path,
                            (long long)w, (long long)h);
    if (w > GG_IMAGE_MAX_DIM || h > GG_IMAGE_MAX_DIM ||
        (uint64_t)w * (uint64_t)h > (uint64_t)GG_IMAGE_MAX_PIXELS)
        return gg_error_set(err, GG_ERROR_LIMIT,
                            "%s: image of %lld x %lld pixels exceeds the limit (%d per side, "
                            "%lu pixels)",
                            path, (long long)w, (long long)h, GG_IMAGE_MAX_DIM,
                            (unsigned long)GG_IMAGE_MAX_PIXELS);
    return GG_OK;
}

int gg_image_check_budget(const char *path, int64_t w, int64_t h, const gg_image_budget *b,
                          ggError *err)
{
    if (!b || GG_IMAGE_BYTES(w, h) <= b->left) return GG_OK;
    return gg_error_set(err, GG_ERROR_LIMIT,
                        "%s: %lld x %lld pixels decode to %lld bytes, over the texture budget "
                        "(%lld bytes left of %lld)",
                        path, (long long)w, (long long)h, (long long)GG_IMAGE_BYTES(w, h),
                        (long long)b->left, (long long)b->total);
}

GG_API ggImage *ggImageCreate(int width, int height, const ggAllocator *alloc)
{
    ggImage *img;
    if (gg_image_check_size("", width, height, NULL) != GG_OK) return NULL;
    img = gg_mem_alloc(alloc, sizeof *img);
    if (!img) return NULL;
    img->width = width;
    img->height = height;
    img->has_alloc = alloc != NULL;
    if (alloc) img->alloc = *alloc;
    img->px = gg_mem_calloc(alloc, (size_t)width * (size_t)height * 3, sizeof(float));
    if (!img->px) {
        gg_mem_free(alloc, img);
        return NULL;
    }
    return img;
}

GG_API void ggImageFree(ggImage *img)
{
    ggAllocator a;
    int has;
    if (!img) return;
    /* Copy first: the allocator lives inside the block being freed. */
    a = img->alloc;
    has = img->has_alloc;
    gg_mem_free(has ? &a : NULL, img->px);
    gg_mem_free(has ? &a : NULL, img);
}

GG_API int ggImageWidth(const ggImage *img)
{
    return img ? img->width : 0;
}
GG_API int ggImageHeight(const ggImage *img)
{
    return img ? img->height : 0;
}
GG_API float *ggImagePixels(ggImage *img)
{
    return img ? img->px : NULL;
}
GG_API const float *ggImagePixelsConst(const ggImage *img)
{
    return img ? img->px : NULL;
}

GG_API ggColor ggImageGet(const ggImage *img, int x, int y)
{
    ggColor c = {0.0, 0.0, 0.0};
    const float *p;
    if (!img || x < 0 || y < 0 || x >= img->width || y >= img->height) return c;
    p = img->px + 3 * ((size_t)y * (size_t)img->width + (size_t)x);
    c.r = p[0];
    c.g = p[1];
    c.b = p[2];
    return c;
}

GG_API void ggImageSet(ggImage *img, int x, int y, ggColor c)
{
    float *p;
    if (!img || x < 0 || y < 0 || x >= img->width || y >= img->height) return;
    p = img->px + 3 * ((size_t)y * (size_t)img->width + (size_t)x);
    p[0] = (float)c.r;
    p[1] = (float)c.g;
    p[2] = (float)c.b;
}

GG_API int ggImageCrop(const ggImage *img, int x, int y, int w, int h, ggImage **out)
{
    ggImage *c;
    int row;
    if (!img || !out || w < 1 || h < 1 || x < 0 || y < 0 || x > img->width - w ||
        y > img->height - h)
        return GG_ERROR_INVALID;
    c = ggImageCreate(w, h, GG_IMAGE_ALLOC(img));
    if (!c) return GG_ERROR_NOMEM;
    for (row = 0; row < h; row++)
        memcpy(c->px + 3 * (size_t)row * (size_t)w,
               img->px + 3 * ((size_t)(y + row) * (size_t)img->width + (size_t)x),
               3 * sizeof(float) * (size_t)w);
    *out = c;
    return GG_OK;
}

GG_API void ggImagePaste(ggImage *dst, const ggImage *src, int x, int y)
{
    /* Clip in 64 bits: x + src->width may overflow int. */
    int64_t x0, y0, x1, y1, row;
    if (!dst || !src) return;
    x0 = x < 0 ? 0 : x;
    y0 = y < 0 ? 0 : y;
    x1 = (int64_t)x + src->width;
    y1 = (int64_t)y + src->height;
    if (x1 > dst->width) x1 = dst->width;
    if (y1 > dst->height) y1 = dst->height;
    if (x0 >= x1 || y0 >= y1) return;
    for (row = y0; row < y1; row++)
        memmove(dst->px + 3 * ((size_t)row * (size_t)dst->width + (size_t)x0),
                src->px + 3 * ((size_t)(row - y) * (size_t)src->width + (size_t)(x0 - x)),
                3 * sizeof(float) * (size_t)(x1 - x0));
}

GG_API double ggLinearToSRGB(double c)
{
    if (c <= 0.0031308) return 12.92 * c;
    return 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

GG_API double ggSRGBToLinear(double c)
{
    if (c <= 0.04045) return c / 12.92;
    return pow((c + 0.055) / 1.055, 2.4);
}

/* thr[k] (k = 1..255) is the linear value of the sRGB level midpoint
   (k - 0.5) / 255: a linear c encodes to the largest k with thr[k] <= c,
   which is round(255 * ggLinearToSRGB(c)) evaluated exactly, without a
   pow per channel. */
static unsigned char encode8(const double thr[256], double c)
{
    int lo = 0, step;
    for (step = 128; step > 0; step >>= 1)
        if (lo + step < 256 && thr[lo + step] <= c) lo += step;
    return (unsigned char)lo;
}

/* A float's bits from 2^-13 up to 1, taken 16 bits at a time (an exponent
   and 7 bits of mantissa): SRGB8_BUCKETS buckets, each narrower (2^-7 of
   its start) than any gap between two midpoints (at least 0.9% of the
   lower one), so the level at a bucket's start is the answer but for at
   most one step up. Below 2^-13 every value is level 0 (thr[1] is 1.5e-4). */
#define SRGB8_SHIFT   16
#define SRGB8_FIRST   (0x39000000u >> SRGB8_SHIFT) /* 2^-13 */
#define SRGB8_BUCKETS ((0x3f800000u >> SRGB8_SHIFT) - SRGB8_FIRST)

static float bits_float(uint32_t u)
{
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

GG_API void ggLinearToSRGB8(const float *in, unsigned char *out, size_t n)
{
    double thr[257];
    unsigned char start[SRGB8_BUCKETS];
    size_t i;
    int k;
    if (!in || !out) return;
    thr[0] = 0.0;
    for (k = 1; k < 256; k++) thr[k] = ggSRGBToLinear((k - 0.5) / 255.0);
    thr[256] = INFINITY; /* the step up from 255 is never taken */
    for (k = 0; k < (int)SRGB8_BUCKETS; k++)
        start[k] = encode8(thr, bits_float((SRGB8_FIRST + (uint32_t)k) << SRGB8_SHIFT));
    for (i = 0; i < n; i++) {
        uint32_t u, b;
        double c = in[i];
        memcpy(&u, &in[i], sizeof u);
        b = (u >> SRGB8_SHIFT) - SRGB8_FIRST; /* wraps for small and negative */
        if (b < SRGB8_BUCKETS) {
            k = start[b];
            out[i] = (unsigned char)(k + (thr[k + 1] <= c));
        } else
            out[i] = c >= 1.0 ? 255 : 0; /* also NaN, tiny and negative */
    }
}

static double to_compare_space(double c, int space)
{
    if (space == GG_COMPARE_LINEAR) return c;
    if (!(c > 0.0)) return 0.0; /* also NaN */
    if (c > 1.0) c = 1.0;
    return ggLinearToSRGB(c);
}

GG_API int ggImageCompare(const ggImage *a, const ggImage *b, int space, ggImageDiff *out)
{
    ggImageDiff r;
    size_t n, i;
    double sum = 0.0;
    const double step = 1.0 / 255.0;
    if (!a || !b || !out || a->width != b->width || a->height != b->height) return GG_ERROR_INVALID;
    if (space != GG_COMPARE_LINEAR && space != GG_COMPARE_SRGB) return GG_ERROR_INVALID;
    memset(&r, 0, sizeof r);
    n = (size_t)a->width * (size_t)a->height;
    for (i = 0; i < n; i++) {
        int k, over = 0;
        for (k = 0; k < 3; k++) {
            double x = to_compare_space(a->px[3 * i + k], space);
            double y = to_compare_space(b->px[3 * i + k], space);
            double d;
            if (x == y) continue; /* also equal infinities */
            if (isnan(x) || isnan(y)) {
                if (isnan(x) && isnan(y)) continue;
                r.nan_channels++;
                over = 1;
                continue;
            }
            d = fabs(x - y);
            sum += d * d;
            if (d > r.max_abs) r.max_abs = d;
            if (d > step) over = 1;
        }
        r.pixels_over += (size_t)over;
    }
    sum /= 3.0 * (double)n;
    r.rmse = sqrt(sum);
    r.psnr = sum > 0.0 ? -10.0 * log10(sum) : HUGE_VAL;
    r.frac_over = (double)r.pixels_over / (double)n;
    *out = r;
    return GG_OK;
}
