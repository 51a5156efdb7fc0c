/* SPDX-License-Identifier: MIT */
/*
** progress.c -- a bar while a scene loads and prepares, and a cancel
** that leaves the scene as it was (ggSceneSetProgress).
**   cc -o progress progress.c $(pkg-config --cflags --libs ggrt) && ./progress
*/
#include <ggrt.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The callback: one line per tenth, on stderr. A program with a window
   would move its bar here, and return 1 once its Cancel button is
   pressed. */
typedef struct bar {
    const char *step;
    long last, stop_at; /* stop_at: cancel at this tenth (0: never) */
} bar;

static int on_progress(void *ud, long done, long total)
{
    bar *b = ud;
    long tenth = total > 0 ? done * 10 / total : 10;
    if (tenth == b->last) return 0;
    b->last = tenth;
    fprintf(stderr, "%-9s %3ld%%\n", b->step, tenth * 10);
    return b->stop_at && tenth >= b->stop_at;
}

/* An NFF scene of n small triangles in a grid, a few MB of text. */
static char *grid_scene(int n, size_t *len)
{
    size_t cap = (size_t)n * 96 + 256, k;
    char *t = malloc(cap);
    int i;
    if (!t) return NULL;
    k = (size_t)snprintf(t, cap,
                         "v\nfrom 0 -30 20\nat 0 0 0\nup 0 0 1\nangle 45\nhither 0.01\n"
                         "resolution 64 48\nl 5 -5 20\nf 0.8 0.7 0.6 0.8 0.2 10 0 0\n");
    for (i = 0; i < n; i++) {
        double x = (i % 400) * 0.05 - 10, y = (i / 400) * 0.05 - 10;
        k += (size_t)snprintf(t + k, cap - k, "p 3\n%.4f %.4f 0\n%.4f %.4f 0\n%.4f %.4f 0.02\n", x,
                              y, x + 0.05, y, x, y + 0.05);
    }
    *len = k;
    return t;
}

int main(void)
{
    size_t len = 0;
    char *text = grid_scene(100000, &len);
    ggScene *s = ggSceneCreate(NULL);
    ggError err;
    bar b = {"loading", -1, 0};
    int st;

    if (!text || !s) return 1;
    printf("a scene of %.1f MB\n", (double)len / 1e6);

    /* Loading and preparing with a bar. */
    ggSceneSetProgress(s, on_progress, &b);
    st = ggSceneLoadString(s, text, len, "grid.nff", &err);
    if (st == GG_OK) {
        b.step = "preparing", b.last = -1;
        st = ggScenePrepare(s, &err);
    }
    if (st != GG_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    printf("loaded and prepared: %d objects\n", ggSceneObjectCount(s));

    /* The same text again, cancelled half-way: an error that names where
       the load stopped, and the scene as it was before the call. */
    b.step = "loading", b.last = -1, b.stop_at = 5;
    st = ggSceneLoadString(s, text, len, "grid.nff", &err);
    printf("cancelled: %s (%s)\n", st == GG_ERROR_CANCELLED ? "yes" : "no", err.message);
    printf("still %d objects, prepared: %s\n", ggSceneObjectCount(s),
           ggScenePrepare(s, NULL) == GG_OK ? "yes" : "no");

    ggSceneSetProgress(s, NULL, NULL); /* b goes out of scope */
    ggSceneFree(s);
    free(text);
    return st == GG_ERROR_CANCELLED ? 0 : 1;
}
