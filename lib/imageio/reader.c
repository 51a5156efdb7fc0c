/* SPDX-License-Identifier: MIT */
/*
** reader.c -- libggrt's default image reader for textures named in scene
** files: ggImageRead (PNG and OpenEXR). libggrt-core links
** load/reader_none.c instead (see load.h).
*/
#include "image.h"
#include "load.h"

/* ud: the scene's gg_image_budget (load.h), so the declared size is
   checked against it before decoding. */
static int read_image(void *ud, const char *path, const ggAllocator *alloc, ggImage **out,
                      ggError *err)
{
    return gg_image_read_budget(path, alloc, ud, out, err);
}

ggImageReader gg_load_default_reader(void) { return read_image; }
