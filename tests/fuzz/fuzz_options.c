/* SPDX-License-Identifier: MIT */
/*
** fuzz_options.c -- libFuzzer harness for render options as text
** (ggRenderOptionsParse, ggRenderOptionsFormat): arbitrary bytes are
** applied to the defaults, and to options that already differ from them.
** Never a crash or a leak, and these properties hold (abort() otherwise):
**   - an error is GG_ERROR_PARSE with a "line:col: " message, and the
**     options are left exactly as they were;
**   - what parses formats to a text that parses back to the same options,
**     bit for bit (every number: cutoff, epsilons, tolerances), and
**     formats again to the same text (the order is canonical);
**   - the format keeps snprintf's contract in a buffer of any size.
*/
#include "fuzz_text.h"
#include "ggrt.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Format *o, parse it back into the defaults: the same options. */
static void round_trip(const ggRenderOptions *o)
{
    char buf[2048], again[2048], small[16];
    size_t n = ggRenderOptionsFormat(o, buf, sizeof buf), k;
    ggRenderOptions p;
    ggError e;
    check(n < sizeof buf && strlen(buf) == n);
    ggRenderOptionsDefault(&p);
    check(ggRenderOptionsParse(&p, buf, &e) == GG_OK);
    check(memcmp(&p, o, sizeof p) == 0);
    check(ggRenderOptionsFormat(&p, again, sizeof again) == n && strcmp(again, buf) == 0);
    for (k = 0; k <= sizeof small; k++) {
        memset(small, 'x', sizeof small);
        check(ggRenderOptionsFormat(o, small, k) == n);
        if (k > 0)
            check(strlen(small) == (n < k ? n : k - 1) && !memcmp(small, buf, strlen(small)));
    }
}

static void apply(ggRenderOptions *o, const char *text)
{
    ggRenderOptions before = *o;
    ggError e;
    int rc = ggRenderOptionsParse(o, text, &e);
    if (rc != GG_OK) {
        check(rc == GG_ERROR_PARSE && is_place(e.message));
        check(memcmp(&before, o, sizeof before) == 0);
        return;
    }
    round_trip(o);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    ggRenderOptions o;
    char *text;
    if (size > 4096) return 0;
    text = malloc(size + 1);
    if (!text) return 0;
    memcpy(text, data, size);
    text[size] = 0;
    ggRenderOptionsDefault(&o);
    apply(&o, text);
    /* on top of settings that are not the defaults */
    ggRenderOptionsDefault(&o);
    check(ggRenderOptionsParse(&o,
                               "size=64x48 depth=9 samples=4 spd sphere=textbook cutoff=0.25 "
                               "offset=1e-7 intersect=float shadows=opaque",
                               NULL) == GG_OK);
    apply(&o, text);
    free(text);
    return 0;
}
