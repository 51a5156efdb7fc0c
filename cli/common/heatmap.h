/* SPDX-License-Identifier: MIT */
/*
** heatmap.h -- per-pixel cost maps as pictures with a legend.
*/
#ifndef GG_HEATMAP_H
#define GG_HEATMAP_H

#include "common/cli.h"

/* A w x (h + legend) image: cost as a colour ramp from 0 to the largest
   finite value (returned in *vmax), then a legend bar labelled 0, the
   maximum and `label` (drawn with a built-in 3x5 font: digits, '.', '-',
   '+', and the letters of "rays depth time s"). NULL if out of memory. */
ggImage *heatmap_image(const float *cost, int w, int h, const char *label, double *vmax);

#endif
