/* SPDX-License-Identifier: MIT */
/*
** bench_image.c -- speed of image output, input and texture sampling.
**   make bench-image
** Prints milliseconds for writing and reading a 1024 x 1024 render-like
** image as PNG and EXR, the size of each file, and nanoseconds per texture
** sample and per value of the 8-bit sRGB encoding. The EXR is ZIP
** compressed at zlib level 1, the level ggImageWriteEXR always uses
** (include/ggrt/image.h), on its threads (as many as the CPUs, at most 8)
** and, for comparison, on one (gg_image_exr_threads, lib/image/image.h).
*/
#include "ggrt.h"
#include "core.h"
#include "image.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

static volatile double sink;

/* The size of the file just written, as bytes and MB (10^6 bytes). */
static void print_size(const char *label, const char *path)
{
    struct stat st;
    if (stat(path, &st) == 0)
        printf("  %-28s %8.2f MB (%lld bytes)\n", label, st.st_size / 1e6, (long long)st.st_size);
}

int main(void)
{
    const int n = 1024, samples = 4000000;
    char png[256], exr[256];
    const char *dir = getenv("TMPDIR");
    ggImage *img = ggImageCreate(n, n, NULL), *back = NULL;
    uint64_t s = 12345;
    double t0, acc = 0.0, *uv;
    int x, y, k, reps = 5, pass;
    snprintf(png, sizeof png, "%s/gg_bench_image.png", dir && *dir ? dir : "/tmp");
    snprintf(exr, sizeof exr, "%s/gg_bench_image.exr", dir && *dir ? dir : "/tmp");
    /* Smooth shading plus a little noise, like a render. */
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++) {
            ggColor c;
            s = s * 6364136223846793005ULL + 1442695040888963407ULL;
            c.r = 0.5 + 0.5 * sin(x * 0.01) * cos(y * 0.013) + (double)(s >> 40) / (1 << 24) * 0.02;
            c.g = (double)x / n;
            c.b = (double)y / n * 1.2;
            ggImageSet(img, x, y, c);
        }
    printf("bench_image: %d x %d image, best of %d runs\n", n, n, reps);
#define TIME(label, stmt)                                                                          \
    do {                                                                                           \
        double best = 1e30;                                                                        \
        int r_;                                                                                    \
        for (r_ = 0; r_ < reps; r_++) {                                                            \
            t0 = gg_time_now();                                                                    \
            stmt;                                                                                  \
            if (gg_time_now() - t0 < best) best = gg_time_now() - t0;                              \
        }                                                                                          \
        printf("  %-28s %8.1f ms\n", label, best * 1e3);                                           \
    } while (0)
    {
        size_t nv = 3 * (size_t)n * (size_t)n;
        unsigned char *b8 = malloc(nv);
        double best = 1e30;
        int r;
        for (r = 0; b8 && r < reps; r++) {
            t0 = gg_time_now();
            ggLinearToSRGB8(ggImagePixels(img), b8, nv);
            if (gg_time_now() - t0 < best) best = gg_time_now() - t0;
        }
        if (b8) printf("  %-28s %8.2f ns/value\n", "8-bit sRGB (ggLinearToSRGB8)", best * 1e9 / nv);
        free(b8);
    }
    TIME("write PNG (8-bit sRGB)", ggImageWritePNG(img, png, NULL));
    print_size("PNG file", png);
    TIME("read PNG", (ggImageRead(png, NULL, &back, NULL), ggImageFree(back)));
    printf("  (EXR chunks compressed on up to %ld CPUs)\n", sysconf(_SC_NPROCESSORS_ONLN));
    TIME("write EXR (float, ZIP)", ggImageWriteEXR(img, exr, NULL));
    gg_image_exr_threads = 1;
    TIME("write EXR on one thread", ggImageWriteEXR(img, exr, NULL));
    gg_image_exr_threads = 0;
    print_size("EXR file (zlib level 1)", exr);
    TIME("read EXR", (ggImageRead(exr, NULL, &back, NULL), ggImageFree(back)));
    /* Texture sampling over precomputed (u, v): "coherent" walks the
       texture in scanline order, as neighbouring rays do; "random" jumps
       anywhere in the 12 MB of pixels, so cache misses dominate. */
    uv = malloc(sizeof(double) * 2 * (size_t)samples);
    for (pass = 0; pass < 2; pass++) {
        const char *kind = pass ? "random" : "coherent";
        for (k = 0; k < samples; k++) {
            if (pass) {
                s = s * 6364136223846793005ULL + 1442695040888963407ULL;
                uv[2 * k] = (double)(s >> 11) * 0x1p-53;
                s = s * 6364136223846793005ULL + 1442695040888963407ULL;
                uv[2 * k + 1] = (double)(s >> 11) * 0x1p-53;
            } else {
                uv[2 * k] = (k % 2048) / 2047.0;
                uv[2 * k + 1] = (k / 2048) / (samples / 2048.0);
            }
        }
        t0 = gg_time_now();
        for (k = 0; k < samples; k++)
            acc += ggTextureBilinear(img, uv[2 * k], uv[2 * k + 1], GG_WRAP_REPEAT).g;
        printf("  ggTextureBilinear, %-8s %8.2f ns/sample\n", kind,
               (gg_time_now() - t0) * 1e9 / samples);
        t0 = gg_time_now();
        for (k = 0; k < samples; k++)
            acc += ggTextureNearest(img, uv[2 * k], uv[2 * k + 1], GG_WRAP_REPEAT).g;
        printf("  ggTextureNearest, %-8s  %8.2f ns/sample\n", kind,
               (gg_time_now() - t0) * 1e9 / samples);
    }
    t0 = gg_time_now();
    for (k = 0; k < samples; k++) {
        ggColor a = {1, 1, 1}, b = {0, 0, 0};
        acc += ggTextureChecker(uv[2 * k], uv[2 * k + 1], 8, a, b).g;
    }
    printf("  ggTextureChecker            %8.2f ns/sample\n", (gg_time_now() - t0) * 1e9 / samples);
    free(uv);
    sink = acc;
    unlink(png);
    unlink(exr);
    ggImageFree(img);
    return 0;
}
