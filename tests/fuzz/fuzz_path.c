/* SPDX-License-Identifier: MIT */
/*
** fuzz_path.c -- libFuzzer harness for the debugger's two languages: the
** light-path expressions (ggPathParse, ggPathLayersCompile) and, for an
** input that starts with '?', the pixel predicates (ggPredicateParse).
** Arbitrary bytes are compiled; what compiles is matched against every
** pixel of a small scene with glass, a bubble that reflects totally, a
** mirror floor, Phong, an emitting ball and two lights, whose ray trees
** are recorded once. Never a crash, a leak or an endless loop, and these
** properties hold (abort() otherwise):
**   - an error is GG_ERROR_PARSE or GG_ERROR_LIMIT, with *out NULL and a
**     "line:col: " message;
**   - ggPathLayersCompile refuses what ggPathParse refuses, with the same
**     code and the message prefixed "layer 1: "; of what it parses, it
**     refuses only a predicate (GG_ERROR_UNSUPPORTED, with its place) or
**     a limit of the automaton (GG_ERROR_LIMIT);
**   - a layer's pixel is what ggPathMatch says the matching paths carry
**     (within 2^-22 of the pixel's terms, as test_layers.c holds it), and
**     the image with the layer is the image without it, bit for bit;
**   - ggFindPath marks exactly the pixels where ggPathMatch matches, with
**     its share; ggFind marks exactly the pixels where ggPredicateMatch
**     is true.
*/
#include "fuzz_text.h"
#include "ggrt.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define W 8
#define H 6

static const char scene_text[] =
    "v\nfrom 0 -5 3\nat 0 0 0.9\nup 0 0 1\nangle 40\nhither 0.01\nresolution 8 6\n"
    "b 0.6 0.7 0.9\nl 3 -3 6\nl -4 -2 5 0.8 0.8 1\n"
    "f 0.8 0.8 0.8 0.6 0.4 20 0 0\nrect -6 -6 0  12 0 0  0 12 0\n"
    "f 1 1 1 0 0 100000 1 1.5\nfresnel exact\ns 0 0 1 1\n"
    "f 1 1 1 0 0 100000 1 1\nfresnel exact\ns 0 0 1 0.8\n"
    "f 1 0.5 0.2 0.5 0.3 8 0 0\nemission 0.3 0.2 0.1\ns 1.6 0.5 0.5 0.5\n";

static ggScene *scene;
static ggRenderOptions opt;
static ggTrace *trace[W * H];
static ggColor pixel[W * H];
static ggImage *plain;

/* The scene, its plain render and every pixel's trees, once. */
static void setup(void)
{
    int i;
    scene = ggSceneCreate(NULL);
    check(scene &&
          ggSceneLoadString(scene, scene_text, sizeof scene_text - 1, "fuzz.nff", NULL) == GG_OK);
    check(ggScenePrepare(scene, NULL) == GG_OK);
    ggRenderOptionsDefault(&opt);
    opt.width = W, opt.height = H;
    check(ggRender(scene, &opt, &plain, NULL, NULL) == GG_OK);
    for (i = 0; i < W * H; i++) {
        check((trace[i] = ggTraceCreate(NULL)) != NULL);
        check(ggTracePixel(scene, &opt, i % W, i / W, -1, trace[i], &pixel[i], NULL, NULL) ==
              GG_OK);
    }
}

/* The layer's pixels against ggPathMatch's sums, and the image unchanged. */
static void check_layer(const ggPathLayers *l, const ggPathSummary *sum)
{
    ggRenderOptions o = opt;
    float map[W * H * 3];
    ggImage *img = NULL;
    int i;
    o.layers = l, o.layer_map = map;
    check(ggRender(scene, &o, &img, NULL, NULL) == GG_OK);
    check(memcmp(ggImagePixelsConst(img), ggImagePixelsConst(plain), sizeof map) == 0);
    ggImageFree(img);
    for (i = 0; i < W * H; i++) {
        const ggColor px = pixel[i];
        const float *v = map + 3 * i;
        const ggColor m = sum[i].value;
        const double tol =
            0x1p-22 * (fabs(px.r) + fabs(px.g) + fabs(px.b) + fabs(m.r) + fabs(m.g) + fabs(m.b));
        check(fabs(v[0] - m.r) <= tol && fabs(v[1] - m.g) <= tol && fabs(v[2] - m.b) <= tol);
    }
}

/* ggFindPath's mask and shares against ggPathMatch's, pixel by pixel. */
static void check_find_path(const ggPathExpr *pe, const ggPathSummary *sum)
{
    ggFindResult *res = NULL;
    int i, k = 0;
    check(ggFindPath(scene, &opt, pe, W * H, &res, NULL) == GG_OK);
    check(res->width == W && res->height == H && res->nmatches == res->matched);
    for (i = 0; i < W * H; i++) {
        check(res->mask[i] == (sum[i].matched > 0));
        if (!res->mask[i]) continue;
        check(k < res->nmatches && res->matches[k].x == i % W && res->matches[k].y == i / W);
        check(memcmp(&res->matches[k].share, &sum[i].share, sizeof sum[i].share) == 0);
        k++;
    }
    check(k == res->nmatches);
    ggFindResultFree(res);
}

static void fuzz_path(const char *text)
{
    ggPathExpr *pe = (ggPathExpr *)&pe;
    ggPathLayers *l = (ggPathLayers *)&l;
    ggPathSummary sum[W * H];
    ggError e1, e2;
    int r1 = ggPathParse(text, NULL, &pe, &e1), r2 = ggPathLayersCompile(&text, 1, NULL, &l, &e2);
    int i;
    if (r1 != GG_OK) {
        check(pe == NULL && (r1 == GG_ERROR_PARSE || r1 == GG_ERROR_LIMIT) && is_place(e1.message));
        check(r2 == r1 && l == NULL && strncmp(e2.message, "layer 1: ", 9) == 0);
        check(strcmp(e2.message + 9, e1.message) == 0);
        return;
    }
    check(pe != NULL);
    /* what the recorder's matcher says of every pixel, once for both checks */
    for (i = 0; i < W * H; i++)
        check(ggPathMatch(pe, trace[i], i % W, i / W, pixel[i], NULL, NULL, &sum[i]) == GG_OK);
    if (r2 != GG_OK) {
        /* a predicate's or a label's place; the automaton's size has none */
        check(l == NULL && strncmp(e2.message, "layer 1: ", 9) == 0 && e2.message[9]);
        check(r2 == GG_ERROR_LIMIT ||
              (r2 == GG_ERROR_UNSUPPORTED && strchr(text, '[') && is_place(e2.message + 9)));
    } else {
        check(ggPathLayersCount(l) == 1);
        check_layer(l, sum);
        ggPathLayersFree(l);
    }
    check_find_path(pe, sum);
    ggPathFree(pe);
}

static void fuzz_predicate(const char *text)
{
    ggPredicate *p = (ggPredicate *)&p;
    ggFindResult *res = NULL;
    ggError e;
    int rc = ggPredicateParse(text, NULL, &p, &e), i;
    if (rc != GG_OK) {
        check(p == NULL && (rc == GG_ERROR_PARSE || rc == GG_ERROR_LIMIT) && is_place(e.message));
        return;
    }
    check(ggFind(scene, &opt, p, 0, &res, NULL) == GG_OK);
    for (i = 0; i < W * H; i++)
        check(res->mask[i] == ggPredicateMatch(p, trace[i], i % W, i / W, pixel[i]));
    ggFindResultFree(res);
    ggPredicateFree(p);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text;
    if (!scene) setup();
    /* past the longest text either language takes, to reach its limit */
    if (size > GG_PATH_MAX_TEXT + 16) return 0;
    text = malloc(size + 1);
    if (!text) return 0;
    memcpy(text, data, size);
    text[size] = 0;
    if (text[0] == '?')
        fuzz_predicate(text + 1);
    else
        fuzz_path(text);
    free(text);
    return 0;
}
