/* SPDX-License-Identifier: MIT */
/*
** image.h -- what the image sources share: the ggImage layout, the
** format readers and writers, and the atomic temporary-file helpers.
*/
#ifndef GG_LIB_IMAGE_H
#define GG_LIB_IMAGE_H

#include "core.h"

#include <stdio.h>

struct ggImage {
    int width, height;
    float *px;         /* 3 * width * height floats */
    ggAllocator alloc; /* copy of the creator's allocator when has_alloc */
    int has_alloc;
};

/* The allocator an image was created with (NULL = libc). */
#define GG_IMAGE_ALLOC(img) ((img)->has_alloc ? &(img)->alloc : NULL)

/* GG_ERROR_LIMIT with "path: image of W x H pixels exceeds ..." unless
   1 <= w, h <= GG_IMAGE_MAX_DIM and w * h <= GG_IMAGE_MAX_PIXELS. Sizes
   are 64-bit so hostile headers cannot overflow the check; <= 0 gives
   GG_ERROR_PARSE. */
int gg_image_check_size(const char *path, int64_t w, int64_t h, ggError *err);

/* What is left of a scene's texture budget (ggSceneSetTextureBudget) for
   the next image a reader decodes: `left` bytes of the `total`. */
typedef struct gg_image_budget {
    int64_t left, total;
} gg_image_budget;

/* The bytes a decoded w x h ggImage holds (3 floats per pixel). */
#define GG_IMAGE_BYTES(w, h) ((int64_t)(w) * (int64_t)(h)*3 * (int64_t)sizeof(float))

/* GG_OK if b is NULL or a w x h image fits in b->left, else GG_ERROR_LIMIT
   "path: 3000 x 3000 pixels decode to 108000000 bytes, over the texture
   budget (... bytes left of ...)". Checked before decoding. */
int gg_image_check_budget(const char *path, int64_t w, int64_t h, const gg_image_budget *b,
                          ggError *err);

/* ggImageRead, with the declared size also checked against b (may be
   NULL) before anything is decoded. */
int gg_image_read_budget(const char *path, const ggAllocator *alloc, const gg_image_budget *b,
                         ggImage **out, ggError *err);

/* strerror into buf, thread-safe; returns buf. */
const char *gg_image_strerror(int errnum, char *buf, size_t n);
/* A codec library's message in the middle of one of ours: msg into buf
   with a capitalised first word lowered ("End of file ..." -> "end of
   file ..."; "EXR ..." stays); returns buf. */
const char *gg_image_lower(const char *msg, char *buf, size_t n);

/* Format readers, called by ggImageRead once the magic bytes matched. fp
   is open at offset 0 and stays owned by the caller. */
int gg_image_read_png(FILE *fp, const char *path, const ggAllocator *alloc,
                      const gg_image_budget *b, ggImage **out, ggError *err);
int gg_image_read_exr(FILE *fp, const char *path, const ggAllocator *alloc,
                      const gg_image_budget *b, ggImage **out, ggError *err);

/* The threads an OpenEXR write compresses its chunks on (image_exr.c): 0,
   the default, for the CPUs online, at most 8, with four chunks or more
   each. The tests set a count to compare files; the bytes written are
   the same for any. */
extern int gg_image_exr_threads;

/* A temporary file beside its destination, renamed over it on commit. */
typedef struct gg_image_tmp {
    const char *path; /* destination, as the caller spelled it */
    char *tmp;        /* "<path>.tmpNNNN", malloc'd */
    int fd;           /* open for writing, -1 once closed */
} gg_image_tmp;

/* Create the temporary file (O_EXCL, mode 0666 & ~umask). GG_ERROR_IO
   "path: cannot create temporary file: why" or GG_ERROR_NOMEM. */
int gg_image_tmp_open(gg_image_tmp *t, const char *path, ggError *err);
/* Flush (fp if not NULL, which must wrap t->fd and is closed here), fsync,
   close and rename over the destination. On failure the temporary file is
   removed and GG_ERROR_IO returned. Always releases t. */
int gg_image_tmp_commit(gg_image_tmp *t, FILE *fp, ggError *err);
/* Give up: close (fp if not NULL, else the fd), remove the temporary
   file, release t. */
void gg_image_tmp_abort(gg_image_tmp *t, FILE *fp);

#endif
