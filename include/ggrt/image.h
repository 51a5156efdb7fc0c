/* SPDX-License-Identifier: MIT */
/*
** ggrt/image.h -- float RGB images, PNG/EXR input and output, image
** comparison, texture sampling. Only the file functions need libpng and
** OpenEXR's C core.
**
** Conventions: an image is width x height linear-RGB pixels, 3 floats
** each, stored row by row from the top (y = 0 is the top row). Every
** function accepts a NULL image and then does nothing harmful (returns 0,
** black, NULL or GG_ERROR_INVALID as stated). Functions on distinct images
** may run concurrently; functions that only read an image (Get, the
** samplers, Compare, writing it to a file) may run concurrently on the same
** image.
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

/* Limits that guard against absurd allocations from hostile input: no side
   may exceed GG_IMAGE_MAX_DIM and width*height may not exceed
   GG_IMAGE_MAX_PIXELS (16,777,216, e.g. 4096 x 4096: 192 MiB of float
   pixels). They hold for every image: files read, images created, renders
   (ggRender fails with GG_ERROR_LIMIT naming the size and the limit before
   it allocates). Readers check them against the file's declared size
   before allocating anything large and fail with GG_ERROR_LIMIT. */
#define GG_IMAGE_MAX_DIM    65536
#define GG_IMAGE_MAX_PIXELS ((size_t)1 << 24)

/* New black image (every float 0.0f); NULL if out of memory or a size is
   <= 0 or over the limits. alloc may be NULL (malloc); a non-NULL
   allocator is copied (base.h rule 3). */
GG_API ggImage *ggImageCreate(int width, int height, const ggAllocator *alloc);
/* Frees the image; NULL is a no-op. */
GG_API void ggImageFree(ggImage *img);
/* Size in pixels; 0 for a NULL image. */
GG_API int ggImageWidth(const ggImage *img);
GG_API int ggImageHeight(const ggImage *img);
/* Row-major RGB floats: pixel (x, y) starts at [3 * (y * width + x)].
   NULL for a NULL image. The pointer stays valid until ggImageFree. */
GG_API float *ggImagePixels(ggImage *img);
GG_API const float *ggImagePixelsConst(const ggImage *img);
/* Pixel access; out-of-range coordinates (or a NULL image) read black and
   write nothing. Set stores the channels as floats (rounded to nearest). */
GG_API ggColor ggImageGet(const ggImage *img, int x, int y);
GG_API void ggImageSet(ggImage *img, int x, int y, ggColor c);

/* Copy the w x h rectangle whose top-left pixel is (x, y) into a new image
   *out made with img's allocator. The rectangle must lie inside img and w,
   h must be >= 1, else GG_ERROR_INVALID. A full-size crop is a copy.
   Returns GG_OK, GG_ERROR_INVALID or GG_ERROR_NOMEM (*out untouched on
   failure). */
GG_API int ggImageCrop(const ggImage *img, int x, int y, int w, int h, ggImage **out);
/* Copy all of src into dst with src's top-left pixel landing on (x, y) of
   dst; the part falling outside dst is clipped (so a crop window rendered
   separately can be pasted back exactly). NULL images are a no-op; dst and
   src must be different images. */
GG_API void ggImagePaste(ggImage *dst, const ggImage *src, int x, int y);

/* ---- files ---- */

/* Read a PNG or an OpenEXR file, chosen by the file's magic bytes (not by
   its name). On success *out receives a new image made with alloc (NULL:
   malloc) and GG_OK is returned; on failure *out is left untouched.

   PNG: any colour type, 1 to 16 bits. Grey becomes R = G = B. Every
   sample, at any depth, is decoded to linear by ggSRGBToLinear (of the
   sample over 2^depth - 1), unless the file has a gAMA chunk (and no sRGB
   or iCCP chunk) more than 5% from sRGB's 1/2.2: then by the power its
   gamma gives (gAMA 1.0: the sample as it is). An alpha channel (or a
   tRNS) multiplies the linear value (composited over black); the alpha
   itself is dropped. As libpng does, a file
   whose pixel data is complete reads even if its closing IEND chunk is
   missing; any shorter file is GG_ERROR_PARSE.

   OpenEXR: the first part, scanline or tiled (the full-resolution level of
   a mip- or rip-map), any compression the linked OpenEXR C core decodes
   (3.1 decodes all but DWAA/DWAB, which give GG_ERROR_UNSUPPORTED), half,
   float or uint channels (uint converted to float). Channels named exactly R, G, B
   are read; a missing one reads as 0. If none of the three exists, a lone
   Y channel is read as grey (Y with RY or BY chroma is refused). Values are kept as stored (linear,
   may be negative, > 1, infinite or NaN). The image is the file's data window.

   Errors (the message starts with the path):
     GG_ERROR_INVALID      path or out is NULL
     GG_ERROR_IO           cannot open or read ("x.png: No such file or
                           directory"), or not a regular file
                           ("x.png: not a regular file": a FIFO, device or
                           directory is refused at once, never waited on)
     GG_ERROR_UNSUPPORTED  neither magic ("x.png: not a PNG or OpenEXR
                           file"), deep EXR data, a subsampled
                           channel, luminance/chroma images, no R, G, B
                           or Y channel, a compression
                           the OpenEXR core cannot decode
     GG_ERROR_PARSE        corrupt or truncated file, also an uncompressed
                           EXR chunk shorter than its pixels: no pixel is
                           ever taken from memory the file did not fill
     GG_ERROR_LIMIT        a side over GG_IMAGE_MAX_DIM or more pixels than
                           GG_IMAGE_MAX_PIXELS (checked before allocating),
                           more than 1024 EXR channels
     GG_ERROR_NOMEM        an allocation failed
   On failure *out is left as it was. Nothing is ever printed. */
GG_API int ggImageRead(const char *path, const ggAllocator *alloc, ggImage **out, ggError *err);

/* Write an 8-bit RGB sRGB PNG. Each channel is clamped to [0,1] (NaN
   becomes 0), encoded with ggLinearToSRGB and rounded to the nearest of
   the 256 levels (the rounding is done in linear space against the exact
   level midpoints, so reading the PNG back and writing it again reproduces
   every byte). */
GG_API int ggImageWritePNG(const ggImage *img, const char *path, ggError *err);
/* Write a float (32-bit) linear R, G, B scanline OpenEXR, ZIP compressed
   (zlib level 1: about as small for float data as the default level and
   faster, docs/performance.md); values, including NaN and infinities,
   are stored bit for bit. A chunk that zlib does not shrink is stored
   raw, also where OpenEXR's own ZIP encoder (up to 3.4.7) would store a
   chunk that reads back as other pixels. The chunks (16 rows each) are
   compressed on threads of the call's own, as many as the CPUs online
   (at most 8, four chunks or more each), and written in order: the
   file's bytes do not depend on the count. Several threads may write
   at once, as with the other writers. */
GG_API int ggImageWriteEXR(const ggImage *img, const char *path, ggError *err);
/* Chooses PNG or EXR by the extension of path (.png / .exr, any case);
   another extension gives GG_ERROR_UNSUPPORTED.

   All three writers are atomic: the data go to a new temporary file
   "<path>.tmpNNNN" in the same directory, created with mode 0666 less the
   umask, flushed with fsync and renamed over path. On any failure the
   temporary file is removed and an existing file at path is left as it
   was, so a failure never leaves a truncated image. Errors: GG_ERROR_INVALID
   (NULL image or path), GG_ERROR_IO ("out.exr: cannot create temporary
   file: Permission denied", write or rename failures), GG_ERROR_NOMEM. */
GG_API int ggImageWrite(const ggImage *img, const char *path, ggError *err);

/* ---- OpenEXR windows and string attributes ---- */

/* A string attribute of an OpenEXR header: name and value, both
   NUL-terminated. */
typedef struct ggEXRAttr {
    const char *name;
    const char *value;
} ggEXRAttr;

/* Where an OpenEXR image lies and what its header says besides. The
   display window is the whole picture, (display_x, display_y) its top-left
   pixel; the data window is the part the file holds pixels for (what
   ggImageRead returns), in the same coordinates. A tile of a larger
   render is a data window inside the display window. attrs lists the
   header's string attributes but those OpenEXR reserves (the names
   ggImageWriteEXRHeader refuses: "type", which OpenEXR's core writes,
   for one); other attribute types are not listed. */
typedef struct ggEXRHeader {
    int display_x, display_y, display_width, display_height;
    int data_x, data_y, data_width, data_height;
    int attr_count;
    ggEXRAttr *attrs;
} ggEXRHeader;

/* Read the header of the OpenEXR file at path (its first part) into *out:
   both windows and the string attributes in file order (a value is cut
   at an embedded NUL byte). No pixel is read, so a file truncated after
   its header reads here and fails in ggImageRead. *out is zeroed first
   and, on success, owns memory that ggEXRHeaderFree releases.
   Errors (the message starts with the path): GG_ERROR_INVALID (NULL
   argument), GG_ERROR_IO (cannot open or read, not a regular file),
   GG_ERROR_UNSUPPORTED (not an OpenEXR file), GG_ERROR_PARSE (corrupt
   header, a window over GG_IMAGE_MAX_DIM on a side), GG_ERROR_NOMEM.
   Nothing is printed. */
GG_API int ggImageReadEXRHeader(const char *path, ggEXRHeader *out, ggError *err);
/* Free what ggImageReadEXRHeader put in *h and zero it; NULL, or a zeroed
   header, is a no-op. Only for headers that function filled. */
GG_API void ggEXRHeaderFree(ggEXRHeader *h);
/* The value of the string attribute `name` in h, or NULL if it has none. */
GG_API const char *ggEXRHeaderGet(const ggEXRHeader *h, const char *name);

/* ggImageWriteEXR (same format, same atomic write, same pixel bytes) with
   the windows and string attributes of *h: the data window's top-left
   pixel is (h->data_x, h->data_y), its size the image's (h->data_width
   and data_height are ignored); the display window is h's. h NULL gives
   exactly ggImageWriteEXR's file. GG_ERROR_INVALID, nothing written, for
   a NULL image or path, a display window of size < 1 or over
   GG_IMAGE_MAX_DIM, a coordinate of either window beyond +-GG_IMAGE_MAX_DIM,
   attr_count < 0 or over 256, a NULL name or value, a name that is
   empty, longer than 31 bytes, repeated, or one of the attributes the
   writer sets itself (channels, compression, dataWindow, displayWindow,
   lineOrder, pixelAspectRatio, screenWindowCenter, screenWindowWidth,
   and name, type, version, chunkCount, tiles). */
GG_API int ggImageWriteEXRHeader(const ggImage *img, const ggEXRHeader *h, const char *path,
                                 ggError *err);

/* ---- OpenEXR layers ---- */

#define GG_EXR_LAYERS_MAX 64 /* layers besides the image */
#define GG_EXR_LAYER_NAME 24 /* bytes in a layer's name */

/* ggImageWriteEXRHeader (h may be NULL) with n more images of img's size,
   the layers, each as three float channels NAME.R, NAME.G, NAME.B beside
   the image's R, G, B (the layer naming of OpenEXR's multi-channel
   files, which compositors read as layers). A name is 1 to
   GG_EXR_LAYER_NAME letters, digits, '_' or '-', all different.
   GG_ERROR_INVALID, nothing written: NULL img or path, layers or names
   NULL with n > 0, n outside 0..GG_EXR_LAYERS_MAX, a NULL layer, one of
   another size, a bad or repeated name, or h refused as
   ggImageWriteEXRHeader refuses it. n = 0 writes ggImageWriteEXRHeader's
   file. */
GG_API int ggImageWriteEXRLayers(const ggImage *img, const ggImage *const *layers,
                                 const char *const *names, int n, const ggEXRHeader *h,
                                 const char *path, ggError *err);
/* ggImageWriteEXRLayers with the n layers read in place from map, laid
   out as ggRenderOptions.layer_map (render.h) for img's size: layer l's
   pixel (x, y) at map[3 * ((l * height + y) * width + x)]. The same file,
   byte for byte, as the layers copied into images give, without the
   memory of that copy (ggrt render --aov). map must hold n such layers.
   GG_ERROR_INVALID, nothing written: map NULL with n > 0, and
   ggImageWriteEXRLayers' refusals. */
GG_API int ggImageWriteEXRLayerMap(const ggImage *img, const float *map, const char *const *names,
                                   int n, const ggEXRHeader *h, const char *path, ggError *err);
/* Read layer `layer` (channels LAYER.R, .G, .B) of the OpenEXR file at
   path as an image, as ggImageRead reads R, G, B (the first part, the
   data window); layer NULL or "" reads the image's own R, G, B (or Y).
   A missing channel of the three reads as 0. GG_ERROR_UNSUPPORTED when
   the file has no channel of the layer; GG_ERROR_PARSE when it is not
   an OpenEXR file (or a damaged one); GG_ERROR_INVALID for a NULL path
   or out; otherwise ggImageRead's errors. As there, *out is left as it
   was on failure. */
GG_API int ggImageReadEXRLayer(const char *path, const char *layer, const ggAllocator *alloc,
                               ggImage **out, ggError *err);

/* ---- comparison ---- */

/* Colour space for ggImageCompare: GG_COMPARE_LINEAR compares the stored
   floats as they are; GG_COMPARE_SRGB as the PNG writer sees them, each
   channel clamped to [0,1] (NaN to 0) and encoded with ggLinearToSRGB (not
   quantised). */
#define GG_COMPARE_LINEAR 0
#define GG_COMPARE_SRGB   1

/* Difference metrics between two images of the same size. Channel
   differences d = |a - b| run over all 3 * width * height channels. */
typedef struct ggImageDiff {
    double rmse;         /* sqrt(mean of d^2) */
    double max_abs;      /* max d */
    double psnr;         /* 10 log10(1 / mean d^2) in dB (peak 1.0); +inf when
                            mean d^2 is 0 */
    double frac_over;    /* share of pixels (0..1) in which some channel has
                            d > 1/255, or a NaN mismatch */
    size_t pixels_over;  /* the number of those pixels */
    size_t nan_channels; /* channels where exactly one side is NaN; they
                            are left out of rmse, max_abs and psnr (which
                            still divide by all channels). Two NaNs count
                            as equal. Always 0 in GG_COMPARE_SRGB. */
} ggImageDiff;

/* Compare a with b in `space` (GG_COMPARE_LINEAR or GG_COMPARE_SRGB) and
   fill *out. Returns GG_OK, or GG_ERROR_INVALID (NULL argument, unknown
   space, different sizes; *out untouched). Infinite channel values give
   infinite metrics unless both sides are the same infinity. */
GG_API int ggImageCompare(const ggImage *a, const ggImage *b, int space, ggImageDiff *out);

/* ---- texture sampling ---- */

/* How (u, v) outside [0,1] is brought back. GG_WRAP_REPEAT: u - floor(u)
   for u < 0 or u > 1 (+-inf gives black). GG_WRAP_CLAMP: clamp to [0,1]
   (+-inf clamps); any other value of `wrap` behaves as GG_WRAP_CLAMP.
   Values inside [0,1], both ends included, are used as they are under both
   modes, so u = 1 is the last column, not the first. */
#define GG_WRAP_REPEAT 0
#define GG_WRAP_CLAMP  1

/* Bilinear sample: d_i = (w-1) u,
   d_j = (h-1) v, i = int(d_i), u_p = d_i - i (likewise j, v_p), blend of the
   four texels C00 = (i, j), C01 = (i, j+1), C10 = (i+1, j), C11 = (i+1, j+1):
   C00 (1-u_p)(1-v_p) + C01 (1-u_p) v_p + C10 u_p (1-v_p) + C11 u_p v_p, each
   channel clamped at 1.0 (above only: negative texels stay negative, a NaN
   result reads 0). i + 1 and j + 1 are clamped to the last column and row,
   so u = 1 or v = 1 reads the last texel (never past it) and 1-pixel-wide
   or -high images work. (u, v) = (0, 0) is the top-left texel, exactly;
   v = 0 is the top row. NaN u or v, or a NULL image, gives black. */
GG_API ggColor ggTextureBilinear(const ggImage *img, double u, double v, int wrap);
/* Nearest texel: i = floor(d_i + 0.5), j = floor(d_j + 0.5) (halves round
   up); same wrapping, clamping at 1.0 and NaN rule as ggTextureBilinear. */
GG_API ggColor ggTextureNearest(const ggImage *img, double u, double v, int wrap);
/* Procedural checkerboard of n x n squares over (u, v) in [0,1]^2: with
   u' = u - floor(u), v' likewise, the square is (floor(u' n), floor(v' n))
   and it is a when the sum of the two is even, b when odd; the square in
   the top-left corner (u, v near 0) is a. n need not be an integer. NaN or
   infinite u or v gives black; n <= 0, NaN or infinite gives a
   everywhere. */
GG_API ggColor ggTextureChecker(double u, double v, double n, ggColor a, ggColor b);

/* sRGB transfer function (IEC 61966-2-1) and its inverse on one channel:
   ggLinearToSRGB(c) = 12.92 c for c <= 0.0031308, else 1.055 c^(1/2.4) -
   0.055; ggSRGBToLinear(s) = s / 12.92 for s <= 0.04045, else ((s + 0.055)
   / 1.055)^2.4. No clamping: values below 0 follow the linear segment,
   values above 1 the power segment; NaN gives NaN. */
GG_API double ggLinearToSRGB(double c);
GG_API double ggSRGBToLinear(double c);
/* Encode n linear values (n / 3 RGB pixels, or any other count) as the
   8-bit sRGB bytes ggImageWritePNG writes: each value clamped to [0,1]
   (NaN becomes 0), encoded with ggLinearToSRGB and rounded to the nearest
   of the 256 levels, the rounding done in linear space against the exact
   level midpoints (ggSRGBToLinear((k - 0.5) / 255)), so decoding a byte
   and encoding it again gives the same byte. out receives n bytes; in
   and out must not overlap. */
GG_API void ggLinearToSRGB8(const float *in, unsigned char *out, size_t n);

#ifdef __cplusplus
}
#endif
#endif
