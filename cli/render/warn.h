/* SPDX-License-Identifier: MIT */
/*
** warn.h -- what a render left out or got wrong, said on stderr (every
** warning, also under -q): by ggrt render for the whole image and for
** each tile of --tile and --tiles alike (warn.c).
*/
#ifndef GG_CLI_RENDER_WARN_H
#define GG_CLI_RENDER_WARN_H

#include "common/cli.h"

/* NaN, infinite or negative pixels of img: count them and print the
   ggrt trace command that replays the worst (the pixel-deciding options
   of ro, from the parsed values). img's pixel 0,0 is the image's x0,y0
   (a tile's band); what ("" or "tile 3: ") starts the warning. */
void render_warn_pixels(const ggImage *img, int x0, int y0, const char *scene, const cli_render *ro,
                        const char *what);

/* The samples the render found NaN or infinite, the rays its budget left
   uncast and the implicit-surface tests cut off, from its statistics. */
void render_warn_stats(const ggRayStats *st, const cli_render *ro, const char *what);

#endif
