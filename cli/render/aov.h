/* SPDX-License-Identifier: MIT */
/*
** aov.h -- path layers of `ggrt render --aov NAME=LPE` (docs/debugging.md,
** "Path layers"): the layers compiled once, rendered by the shading's
** layer copy (ggRenderOptions.layers), written as NAME.R, NAME.G, NAME.B
** channels of the EXR and, with --aov-png DIR, as DIR/NAME.png.
*/
#ifndef GG_CLI_AOV_H
#define GG_CLI_AOV_H

#include "common/cli.h"

/* The EXR attribute that lists a file's layers, one "NAME=LPE" a line
   (ggrt check --aov-sum reads it). */
#define AOV_ATTR "ggrt.aov"
/* and the scene and render options that made it (ggRenderOptionsFormat),
   for tracing a pixel that does not add up */
#define AOV_ATTR_SCENE   "ggrt.aov.scene"
#define AOV_ATTR_OPTIONS "ggrt.aov.options"

typedef struct aov_list {
    int n;
    const char *arg[GG_PATH_LAYERS_MAX]; /* each --aov as given */
    const char *expr[GG_PATH_LAYERS_MAX];
    char name[GG_PATH_LAYERS_MAX][GG_EXR_LAYER_NAME + 1];
    const char *png_dir; /* --aov-png DIR, or NULL */
    ggPathLayers *layers;
    float *map;       /* the render's layer map (ggRenderOptions.layer_map) */
    ggImage *scratch; /* with --aov-png: a layer at a time, for ggImageWritePNG */
    int w, h;
} aov_list;

/* CLI_FUNC parser of one --aov NAME=LPE; ud is an aov_list. */
int aov_parse_one(void *ud, const char *value, char *why, size_t whylen);
/* Compile the layers and give opt a map for a w x h image, allocating
   before the render all that writing the layers takes: EXIT_OK, or the
   exit status after saying why (a column for an expression; for memory,
   EXIT_INPUT and how much the layers need). */
int aov_prepare(aov_list *l, ggRenderOptions *opt, int w, int h);
/* Before the render: --aov-png DIR must be a directory, or a missing one
   whose parent takes files, and each DIR/NAME.png must pass
   cli_check_output as -o does and be neither out (-o) nor scene. 0, or
   EXIT_IO / EXIT_USAGE after saying why. */
int aov_check_pngs(const aov_list *l, const char *out, const char *scene);
/* Once the scene is loaded: no DIR/NAME.png may be a file it reads
   (cli_check_not_read). 0, or EXIT_USAGE after saying which. */
int aov_check_not_read(const aov_list *l, const ggScene *s);
/* Write img with its layers to out (.exr: the layers as channels, and the
   AOV_ATTR* attributes from scene and opt; .png: the image alone) and,
   with --aov-png, each layer to DIR/NAME.png: GG_OK or the library's
   error in err. */
int aov_write(const aov_list *l, const ggImage *img, const char *out, const char *scene,
              const ggRenderOptions *opt, ggError *err);
/* --pixel X,Y: each layer's value there, "layer NAME X,Y R G B". */
void aov_print_pixel(const aov_list *l, int x, int y);
void aov_free(aov_list *l);

#endif
