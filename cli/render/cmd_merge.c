/* SPDX-License-Identifier: MIT */
/*
** cmd_merge.c -- `ggrt merge TILE.exr... -o OUT.png|OUT.exr`: join the
** tiles of ggrt render --tile into the image one process renders
** (tile.h has the cut and the manifest).
*/
#include "render/tile.h"

#include <stdlib.h>
#include <string.h>

static const char about[] =
    "Join the tiles written by 'ggrt render --tile' or '--tiles' into one image, PNG\n"
    "or OpenEXR by the extension of OUT: the same file a single 'ggrt render' with\n"
    "the same options writes, byte for byte. Every tile must come from the same\n"
    "scene file (its hash), render options, ggrt version and build (ggrt --version)\n"
    "and cut, and together they must cover the image once: otherwise merge names\n"
    "the tile and the reason and writes nothing.\n"
    "With --reports, the JSON reports of 'ggrt find', 'check' or 'diff --tile'\n"
    "instead, joined into the report one process writes for the whole image.";

static const char tail[] = "exit: 0 ok, 1 usage, 2 bad or missing tile, 3 I/O error";

/* One tile file: its header, the manifest fields, its pixels. */
typedef struct tile_file {
    const char *path;
    ggEXRHeader hd;
    int index, n;
    tile_cut cut; /* the first tile's; the others' equal it as text */
    ggImage *img;
} tile_file;

static const char *const manifest[] = {TILE_A_VERSION, TILE_A_BUILD, TILE_A_HASH, TILE_A_OPTIONS,
                                       TILE_A_CUT,     TILE_A_TILE,  NULL};
static const char *const what[] = {"ggrt version",   "ggrt build", "scene (hash)",
                                   "render options", "cut",        NULL};

/* Read a header and the manifest; the first tile's fields are the
   reference for the others (ref NULL: this is the first). */
static int read_header(tile_file *t, const tile_file *ref)
{
    ggError err;
    const char *cut, *idx, *end;
    char why[160];
    long v;
    int k, rc = ggImageReadEXRHeader(t->path, &t->hd, &err);
    if (rc != GG_OK) return cli_fail(rc, &err, 0);
    for (k = 0; manifest[k]; k++)
        if (!ggEXRHeaderGet(&t->hd, manifest[k])) {
            /* A tile of a ggrt from before the build id: which build it
               is cannot be told, so it cannot be trusted to match. */
            if (k && !strcmp(manifest[k], TILE_A_BUILD)) {
                cli_error("%s: a tile of an older ggrt: no %s attribute (render it again "
                          "with this one)",
                          t->path, TILE_A_BUILD);
                return EXIT_INPUT;
            }
            cli_error("%s: not a ggrt tile: no %s attribute", t->path, manifest[k]);
            return EXIT_INPUT;
        }
    for (k = 0; ref && what[k]; k++) {
        const char *a = ggEXRHeaderGet(&t->hd, manifest[k]);
        const char *b = ggEXRHeaderGet(&ref->hd, manifest[k]);
        if (strcmp(a, b) != 0 && !strcmp(manifest[k], TILE_A_OPTIONS)) {
            char d[512];
            cli_render_text_diff(a, b, d, sizeof d);
            cli_error("%s: different %s from %s: %s", t->path, what[k], ref->path, d);
            return EXIT_INPUT;
        } else if (strcmp(a, b) != 0) {
            cli_error("%s: different %s from %s: '%s', not '%s'", t->path, what[k], ref->path, a,
                      b);
            return EXIT_INPUT;
        }
    }
    cut = ggEXRHeaderGet(&t->hd, TILE_A_CUT), idx = ggEXRHeaderGet(&t->hd, TILE_A_TILE);
    if (!ref && tile_cut_parse(cut, t->hd.display_height, &t->cut, why, sizeof why) != 0) {
        cli_error("%s: bad cut '%.40s%s': %s", t->path, cut, strlen(cut) > 40 ? "..." : "", why);
        return EXIT_INPUT;
    }
    t->n = ref ? ref->n : t->cut.n;
    v = tile_number(idx, &end);
    if (v < 0 || *end || v >= t->n) {
        cli_error("%s: tile index '%s' is not in 0..%d", t->path, idx, t->n - 1);
        return EXIT_INPUT;
    }
    t->index = (int)v;
    return EXIT_OK;
}

/* The windows must be those the cut gives the tile's index. */
static int check_windows(const tile_file *t, const tile_cut *cut)
{
    const ggEXRHeader *h = &t->hd;
    int y0, y1;
    if (h->display_x != 0 || h->display_y != 0 || h->display_height < t->n) {
        cli_error("%s: display window %dx%d at %d,%d is not an image of %d tiles", t->path,
                  h->display_width, h->display_height, h->display_x, h->display_y, t->n);
        return EXIT_INPUT;
    }
    tile_cut_rows(cut, t->index, h->display_height, &y0, &y1);
    if (h->data_x != 0 || h->data_width != h->display_width || h->data_y != y0 ||
        h->data_height != y1 - y0) {
        cli_error("%s: data window %dx%d at %d,%d is not tile %d of %d (rows %d..%d)", t->path,
                  h->data_width, h->data_height, h->data_x, h->data_y, t->index, t->n, y0,
                  y1 - 1);
        return EXIT_INPUT;
    }
    return EXIT_OK;
}

/* Headers of every file, then coverage: each tile once, none missing. */
static int check_all(tile_file *t, int nt)
{
    int i, k, rc;
    const tile_file **seen;
    for (i = 0; i < nt; i++) {
        if ((rc = read_header(&t[i], i ? &t[0] : NULL)) != EXIT_OK) return rc;
        if (i && (t[i].hd.display_width != t[0].hd.display_width ||
                  t[i].hd.display_height != t[0].hd.display_height)) {
            cli_error("%s: image size %dx%d, not %dx%d as in %s", t[i].path,
                      t[i].hd.display_width, t[i].hd.display_height, t[0].hd.display_width,
                      t[0].hd.display_height, t[0].path);
            return EXIT_INPUT;
        }
        if ((rc = check_windows(&t[i], &t[0].cut)) != EXIT_OK) return rc;
    }
    if (!(seen = calloc((size_t)t[0].n, sizeof *seen))) {
        cli_error("out of memory");
        return EXIT_INPUT;
    }
    for (i = 0, rc = EXIT_OK; i < nt && rc == EXIT_OK; i++) {
        if (seen[t[i].index] && tile_same_file(t[i].path, seen[t[i].index]->path)) {
            cli_error("%s: given twice (tile %d)", t[i].path, t[i].index);
            rc = EXIT_INPUT;
        } else if (seen[t[i].index]) {
            cli_error("%s: tile %d again (also in %s)", t[i].path, t[i].index,
                      seen[t[i].index]->path);
            rc = EXIT_INPUT;
        }
        seen[t[i].index] = &t[i];
    }
    for (k = 0; k < t[0].n && rc == EXIT_OK; k++)
        if (!seen[k]) {
            int y0, y1;
            tile_cut_rows(&t[0].cut, k, t[0].hd.display_height, &y0, &y1);
            cli_error("tile %d of %d (rows %d..%d) is missing", k, t[0].n, y0, y1 - 1);
            rc = EXIT_INPUT;
        }
    free(seen);
    return rc;
}

/* Read every tile's pixels into the whole image. */
static int assemble(tile_file *t, int nt, ggImage **out)
{
    ggImage *all = ggImageCreate(t[0].hd.display_width, t[0].hd.display_height, NULL);
    ggError err;
    int i, rc;
    if (!all) {
        cli_error("out of memory for a %dx%d image", t[0].hd.display_width,
                  t[0].hd.display_height);
        return EXIT_INPUT;
    }
    for (i = 0; i < nt; i++) {
        ggImage *img = NULL;
        if ((rc = ggImageRead(t[i].path, NULL, &img, &err)) != GG_OK) {
            ggImageFree(all);
            return cli_fail(rc, &err, 0);
        }
        ggImagePaste(all, img, 0, t[i].hd.data_y);
        ggImageFree(img);
    }
    *out = all;
    return EXIT_OK;
}

static int parse(int argc, char **argv, const char **files, int *nfiles, const char **out,
                 int *quiet, int *reports)
{
    cli_opt mine[] = {
        CLI_OPT_STRING('o', "output", out, "FILE",
                       "the image to write (required), .png or .exr;\n"
                       "written whole or not at all; not one of the inputs;\n"
                       "with --reports the JSON report (not .png or .exr)"),
        CLI_OPT_FLAG(0, "reports", reports,
                     "the files are JSON reports of find, check or diff\n"
                     "--tile: write the whole image's report to -o FILE"),
        CLI_OPT_FLAG('q', "quiet", quiet, "no summary"),
        CLI_OPT_END,
    };
    cli_cmd cmd = {.name = "merge",
                   .usage = "TILE.exr... -o OUT.png|OUT.exr [options]\n"
                            "       ggrt merge --reports PART.json... -o OUT.json [options]",
                   .about = about,
                   .tail = tail,
                   .opts = {mine},
                   .args = files,
                   .min_args = 0, /* counted below, where --reports says what they are */
                   .max_args = argc,
                   .nargs = nfiles,
                   .args_name = "tile"};
    int rc;
    if ((rc = cli_parse(&cmd, argc, argv)) != CLI_GO) return rc;
    if (!*nfiles) return cli_usage_error(&cmd, "need a %s", *reports ? "report" : "tile");
    if (!*out)
        return cli_usage_error(&cmd,
                               *reports ? "need -o OUT.json" : "need -o OUT.png or -o OUT.exr");
    if ((rc = cli_check_not_input(&cmd, "-o", *out, files, *nfiles)) != CLI_GO) return rc;
    if (!*reports) return cli_check_image_name(&cmd, "the output", *out);
    /* A report is JSON: under an image's name a viewer would choke on it. */
    if (cli_image_kind(*out) != CLI_IMAGE_NONE)
        return cli_usage_error(&cmd, "--reports writes a JSON report, not an image: '%s'", *out);
    return CLI_GO;
}

int cmd_merge(int argc, char **argv)
{
    const char **files = calloc((size_t)argc + 1, sizeof *files), *out = NULL;
    tile_file *t = NULL;
    ggImage *img = NULL;
    ggError err;
    int nfiles = 0, quiet = 0, reports = 0, i, rc;
    if (!files) return EXIT_INPUT;
    if ((rc = parse(argc, argv, files, &nfiles, &out, &quiet, &reports)) != CLI_GO) {
        free(files);
        return rc;
    }
    if (reports) {
        rc = cli_check_output("merge", out);
        if (rc == 0) rc = merge_reports(files, nfiles, out, quiet);
        free(files);
        return rc;
    }
    if ((rc = cli_check_output("merge", out)) == 0 &&
        !(t = calloc((size_t)nfiles, sizeof *t))) {
        cli_error("out of memory");
        rc = EXIT_INPUT;
    }
    for (i = 0; t && i < nfiles; i++) t[i].path = files[i];
    if (rc == 0 && (rc = check_all(t, nfiles)) == EXIT_OK) rc = assemble(t, nfiles, &img);
    if (rc == EXIT_OK && (rc = ggImageWrite(img, out, &err)) != GG_OK) rc = cli_fail(rc, &err, 0);
    if (rc == EXIT_OK && !quiet)
        printf("%d tiles of %d -> %s, %dx%d\n", nfiles, t[0].n, out, ggImageWidth(img),
               ggImageHeight(img));
    for (i = 0; t && i < nfiles; i++) ggEXRHeaderFree(&t[i].hd);
    if (t) tile_cut_free(&t[0].cut);
    ggImageFree(img);
    free(t);
    free(files);
    return rc;
}
