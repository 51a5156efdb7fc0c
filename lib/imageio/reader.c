/* SPDX-License-Identifier: MIT */
/*
** reader.c -- libggrt's default image reader for textures named in scene
** files: ggImageRead (PNG and OpenEXR). libggrt-core links
** load/reader_none.c instead (see load.h).
*/
#include "load.h"

static int read_image(void *ud, const char *path, const ggAllocator *alloc, ggImage **out,
                      ggError *err)
{
    (void)ud;
    return ggImageRead(path, alloc, out, err);
}

ggImageReader gg_load_default_reader(void) { return read_image; }
