/* SPDX-License-Identifier: MIT */
/*
** fuzz_nff.c -- libFuzzer harness for the scene reader: arbitrary bytes as
** NFF text must load or fail with a file:line:col message, never crash or
** leak; a scene that loads must prepare and render a 4x3 image (4
** samples). Under `make check` the same harness replays
** tests/fuzz/corpus/nff/.
*/
#include "ggrt.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    ggScene *s = ggSceneCreate(NULL);
    ggError e;
    int rc;
    if (!s) return 0;
    memset(&e, 0, sizeof e);
    rc = ggSceneLoadString(s, (const char *)data, size, "fuzz.nff", &e);
    if (rc != GG_OK) {
        /* Every failure names the place: "fuzz.nff:L:C: ..." */
        if (strncmp(e.message, "fuzz.nff:", 9) != 0 || ggSceneObjectCount(s) != 0) abort();
    } else if (ggSceneObjectCount(s) < 2000) {
        ggRenderOptions o;
        ggImage *img = NULL;
        ggRenderOptionsDefault(&o);
        o.width = 4, o.height = 3, o.threads = 1, o.max_depth = 3;
        /* 4 samples (a 2x2 grid), not the scene's: an implicit surface's
           budget bounds each ray, and a scene's own count (up to 4096 per
           pixel) would multiply that bound into a slow unit
           (tests/fuzz/corpus/nff/slow-divide-by-zero.nff asked for 233). */
        o.samples = 4;
        if (ggRender(s, &o, &img, NULL, &e) == GG_OK) ggImageFree(img);
    }
    ggSceneFree(s);
    return 0;
}
