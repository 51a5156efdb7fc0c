/* SPDX-License-Identifier: MIT */
/*
** warn.c -- the warnings of a render, whole or a tile's (warn.h).
*/
#include "render/warn.h"

#include <math.h>

void render_warn_pixels(const ggImage *img, int x0, int y0, const char *scene, const cli_render *ro,
                        const char *what)
{
    int w = ggImageWidth(img), h = ggImageHeight(img), x, y, bx = -1, by = -1;
    long bad = 0;
    double worst = 0;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            ggColor c = ggImageGet(img, x, y);
            double m = c.r < c.g ? c.r : c.g;
            if (c.b < m) m = c.b;
            /* NaN and infinity rank worst, then the most negative. */
            if (!isfinite(c.r) || !isfinite(c.g) || !isfinite(c.b)) m = -INFINITY;
            if (m < 0) {
                bad++;
                if (bx < 0 || m < worst) worst = m, bx = x, by = y;
            }
        }
    if (!bad) return;
    cli_warn("%s%ld pixel%s NaN, infinite or negative; the worst is %d,%d. Replay it with:", what,
             bad, bad == 1 ? " is" : "s are", x0 + bx, y0 + by);
    fprintf(stderr, "  ggrt trace");
    cli_print_file(stderr, scene);
    cli_render_print(stderr, ro, CLI_RENDER_PIXEL);
    fprintf(stderr, " --pixel %d,%d\n", x0 + bx, y0 + by);
}

void render_warn_stats(const ggRayStats *st, const cli_render *ro, const char *what)
{
    if (st->nonfinite)
        cli_warn("%s%llu samples were NaN or infinite", what, (unsigned long long)st->nonfinite);
    if (st->budget_cut) {
        int b = ro->opt.ray_budget > 0 ? ro->opt.ray_budget : GG_RAY_BUDGET;
        cli_warn("%sthe ray budget (%d ray%s per eye ray) left %llu rays uncast; --ray-budget "
                 "raises it",
                 what, b, b == 1 ? "" : "s", (unsigned long long)st->budget_cut);
    }
    if (st->implicit_cut)
        cli_warn("%s%llu ray tests of implicit surfaces ran out of their evaluation budget and "
                 "count as misses (holes possible)",
                 what, (unsigned long long)st->implicit_cut);
}
