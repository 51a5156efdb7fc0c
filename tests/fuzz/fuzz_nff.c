/* SPDX-License-Identifier: MIT */
/*
** fuzz_nff.c -- libFuzzer harness for the scene reader: arbitrary bytes as
** NFF text must load or fail with a file:line:col message, never crash or
** leak; a scene that loads must prepare and render a 4x3 image. Under
** `make check` the same harness replays tests/fuzz/corpus/nff/.
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
        if (ggRender(s, &o, &img, NULL, &e) == GG_OK) ggImageFree(img);
    }
    ggSceneFree(s);
    return 0;
}
