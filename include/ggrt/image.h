/*
** ggrt/image.h -- float RGB images, PNG/EXR input and output, texture
** sampling. Only the file functions need libpng and OpenEXR's C core.
*/
#ifndef GGRT_IMAGE_H
#define GGRT_IMAGE_H

#include "ggrt/base.h"

#ifdef __cplusplus
extern "C" {
#endif

/* An image of width*height linear-RGB pixels stored as 3 floats each, row
   by row from the top. Opaque; pixels are reachable with ggImagePixels. */
typedef struct ggImage ggImage;

/* Limits that guard against absurd allocations from hostile input. */
#define GG_IMAGE_MAX_DIM    65536
#define GG_IMAGE_MAX_PIXELS ((size_t)1 << 28)

/* New black image; NULL if out of memory or a size is <= 0 or over the
   limits. alloc may be NULL. */
GG_API ggImage *ggImageCreate(int width, int height, const ggAllocator *alloc);
/* Frees the image; NULL is a no-op. */
GG_API void ggImageFree(ggImage *img);
GG_API int ggImageWidth(const ggImage *img);
GG_API int ggImageHeight(const ggImage *img);
/* Row-major RGB floats: pixel (x, y) starts at [3 * (y * width + x)]. */
GG_API float *ggImagePixels(ggImage *img);
GG_API const float *ggImagePixelsConst(const ggImage *img);
/* Pixel access; out-of-range coordinates read black and write nothing. */
GG_API ggColor ggImageGet(const ggImage *img, int x, int y);
GG_API void ggImageSet(ggImage *img, int x, int y, ggColor c);

/* Read a PNG (8 or 16 bit; sRGB decoded to linear) or an OpenEXR file
   (scanline or tiled, half or float, R G B channels; missing channels read
   as 0, a lone Y channel as grey), chosen by the file's magic bytes. On
   success *out receives a new image. */
GG_API int ggImageRead(const char *path, const ggAllocator *alloc, ggImage **out, ggError *err);

/* Write 8-bit sRGB PNG (values clamped to [0,1], NaN written as 0) or a
   float linear OpenEXR (ZIP compressed). The file is written to a
   temporary name beside `path` and renamed into place, so a failure never
   leaves a truncated image at `path`. */
GG_API int ggImageWritePNG(const ggImage *img, const char *path, ggError *err);
GG_API int ggImageWriteEXR(const ggImage *img, const char *path, ggError *err);
/* Chooses PNG or EXR by the extension of path (.png / .exr, any case). */
GG_API int ggImageWrite(const ggImage *img, const char *path, ggError *err);

/* ---- texture sampling ---- */

/* How (u, v) outside [0,1] is brought back. */
#define GG_WRAP_REPEAT 0 /* u - floor(u) */
#define GG_WRAP_CLAMP  1 /* clamp to [0,1] */

/* Bilinear sample, exactly as in the lecture notes: d_i = (w-1) u,
   d_j = (h-1) v, i = int(d_i), u_p = d_i - i (likewise j, v_p), blend of the
   four texels C00 (1-u_p)(1-v_p) + C01 (1-u_p) v_p + C10 u_p (1-v_p) +
   C11 u_p v_p, each channel clamped at 1.0. u = 1 or v = 1 reads the last
   texel (never past it). v = 0 is the top row. NaN u or v gives black. */
GG_API ggColor ggTextureBilinear(const ggImage *img, double u, double v, int wrap);
/* Nearest texel: i = round(d_i), j = round(d_j); same conventions. */
GG_API ggColor ggTextureNearest(const ggImage *img, double u, double v, int wrap);
/* Procedural checkerboard of n x n squares over (u, v) in [0,1]^2,
   alternating a and b; (u, v) wrap. NaN gives black. */
GG_API ggColor ggTextureChecker(double u, double v, double n, ggColor a, ggColor b);

/* sRGB transfer function and its inverse on one channel. */
GG_API double ggLinearToSRGB(double c);
GG_API double ggSRGBToLinear(double c);

#ifdef __cplusplus
}
#endif
#endif
