/* SPDX-License-Identifier: MIT */
/*
** heatmap.h -- per-pixel cost maps as pictures with a legend.
*/
#ifndef GG_HEATMAP_H
#define GG_HEATMAP_H

#include "common/cli.h"

/* The scale of a cost map: max is its largest finite value, top the
   scale's top, above how many values are over it. top is max, except
   with `robust` where max is over HEATMAP_OUTLIER times the 99.9th
   percentile of the positive values (to within 1/16 of it): there top is
   that percentile. For measured times, where a thread descheduled for
   one pixel left every other the colour of 0; counts (rays, depth) are
   exact and keep their largest value. Out of memory, top is max. */
#define HEATMAP_OUTLIER 4.0
typedef struct heatmap_range {
    double max, top;
    size_t above;
    int legend; /* the legend's rows under the map (0: left out) */
} heatmap_range;

/* A w x (h + legend) image: cost as a colour ramp from 0 to the scale's
   top (returned in *range when range is not NULL; values
   over it take the top colour), then a legend bar labelled 0, the top
   ("+" after it when values are over it) and `label` (drawn with a
   built-in 3x5 font: digits, '.', '-', '+', and the letters of "rays
   depth time s"). Where the legend's rows would take the image over
   GG_IMAGE_MAX_PIXELS or GG_IMAGE_MAX_DIM (a 4096x4096 map), the map
   alone, range->legend 0. NULL if out of memory. */
ggImage *heatmap_image(const float *cost, int w, int h, const char *label, int robust,
                       heatmap_range *range);

#endif
