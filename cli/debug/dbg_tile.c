/* SPDX-License-Identifier: MIT */
/*
** dbg_tile.c -- find, check and diff --tile I/N [--plan FILE]: the scan
** of one band of rows (the render's crop window), and its JSON report with
** a tile manifest that ggrt merge --reports reads (docs/cluster.md).
*/
#include "debug/debug.h"

#include <stdlib.h>
#include <string.h>

int dbg_tile_check(const cli_cmd *cmd, const dbg_tile *t, int format, int images)
{
    if (!t->tl.count) {
        if (t->plan) return cli_usage_error(cmd, "--plan goes with --tile");
        return CLI_GO;
    }
    if (!t->tl.n && !t->plan)
        return cli_usage_error(cmd, "--tile I needs /N, the number of tiles, or --plan");
    if (format != 1) return cli_usage_error(cmd, "--tile writes a JSON report: add -f json");
    if (images)
        return cli_usage_error(cmd, "--tile writes the JSON report alone: not with -o, "
                                    "--overlay, --paths-jsonl, --paths-obj or --crop");
    return CLI_GO;
}

int dbg_tile_begin(dbg_tile *t, ggScene *scene, const char *scene_path, ggRenderOptions *opt)
{
    int rc;
    if (!t->tl.count) return EXIT_OK;
    if ((rc = tile_band_init(&t->band, scene, scene_path, opt, &t->tl, t->plan)) != EXIT_OK)
        return rc;
    opt->crop_x0 = 0, opt->crop_x1 = t->band.w;
    opt->crop_y0 = t->band.y0, opt->crop_y1 = t->band.y1;
    return EXIT_OK;
}

void dbg_tile_options(const dbg_tile *t, const ggRenderOptions *opt, ggRenderOptions *out)
{
    *out = *opt;
    if (t->tl.count) out->crop_x0 = out->crop_y0 = out->crop_x1 = out->crop_y1 = 0;
}

FILE *dbg_tile_open(dbg_tile *t)
{
    if (!t->tl.count) return stdout;
    t->text = NULL, t->len = 0;
    return open_memstream(&t->text, &t->len);
}

int dbg_tile_close(dbg_tile *t, FILE *f, const char *params)
{
    size_t n;
    if (!t->tl.count) return EXIT_OK;
    if (!f || fclose(f) != 0 || !t->text) {
        free(t->text);
        cli_error("out of memory for the report");
        return EXIT_INPUT;
    }
    n = t->len;
    while (n && (t->text[n - 1] == '\n' || t->text[n - 1] == '}')) {
        if (t->text[--n] == '}') break;
    }
    fwrite(t->text, 1, n, stdout);
    printf(",\"tile\":{\"version\":");
    json_str(stdout, ggVersion());
    printf(",\"buildId\":");
    json_str(stdout, ggBuildId());
    printf(",\"sceneHash\":");
    json_str(stdout, t->band.hash);
    printf(",\"options\":");
    json_str(stdout, t->band.options);
    printf(",\"cut\":");
    json_str(stdout, t->band.cut);
    printf(",\"index\":%d,\"rows\":[%d,%d],\"params\":", t->band.index, t->band.y0, t->band.y1);
    json_str(stdout, params ? params : "");
    printf("}}\n");
    free(t->text);
    t->text = NULL;
    return EXIT_OK;
}
