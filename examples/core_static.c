/* SPDX-License-Identifier: MIT */
/*
** core_static.c -- load an NFF scene and render it with libggrt-core, the
** archive without image files, into a binary PPM written with stdio. It
** links statically against libc, libm and pthreads alone:
**   cc -static core_static.c $(pkg-config --static --cflags --libs ggrt-core) -o core_static
**   ./core_static [scene.nff [out.ppm [WxH]]]
** Without a scene it renders a small one of its own. (With libggrt it
** builds as well; then scene files may also name image textures.)
*/
#include <ggrt.h>

#include <stdio.h>
#include <string.h>

/* A glass ball over a checkered floor, in NFF with ggrt's extensions. */
static const char scene_text[] = "v\nfrom 0 -6 2.5\nat 0 0 0.8\nup 0 0 1\nangle 40\nhither 1\n"
                                 "resolution 160 120\nb 0.5 0.6 0.8\nl 4 -4 6\n"
                                 "f 0.9 0.9 0.85 0.9 0 0 0 1\nchecker 8 0.9 0.9 0.85 0.2 0.2 0.25\n"
                                 "rect -4 -4 0 8 0 0 0 8 0\n"
                                 "f 1 1 1 0 0.1 30 0.9 1.5\ns 0 0 1 1\n";

static int write_ppm(const ggImage *img, const char *path)
{
    int w = ggImageWidth(img), h = ggImageHeight(img), i;
    const float *px = ggImagePixelsConst(img);
    FILE *f = fopen(path, "wb");
    if (!f) return -1;
    fprintf(f, "P6\n%d %d\n255\n", w, h);
    for (i = 0; i < 3 * w * h; i++) {
        double v = ggLinearToSRGB(px[i] > 0 ? (px[i] < 1 ? px[i] : 1) : 0);
        fputc((int)(v * 255 + 0.5), f);
    }
    return fclose(f) == 0 ? 0 : -1;
}

int main(int argc, char **argv)
{
    ggScene *scene;
    ggRenderOptions opt;
    ggRayStats stats;
    ggImage *img = NULL;
    ggError err;
    const char *out = argc > 2 ? argv[2] : "core_static.ppm";
    int rc;
    ggRenderOptionsDefault(&opt);
    if (argc > 3 && sscanf(argv[3], "%dx%d", &opt.width, &opt.height) != 2) return 1;
    opt.threads = 2;
    scene = ggSceneCreate(NULL);
    if (!scene) return 1;
    rc = argc > 1 ? ggSceneLoadFile(scene, argv[1], &err)
                  : ggSceneLoadString(scene, scene_text, strlen(scene_text), "core_static", &err);
    if (rc != GG_OK || ggRender(scene, &opt, &img, &stats, &err) != GG_OK) {
        fprintf(stderr, "core_static: %s\n", err.message);
        ggSceneFree(scene);
        return 1;
    }
    if (write_ppm(img, out) != 0) {
        perror(out);
        ggImageFree(img);
        ggSceneFree(scene);
        return 1;
    }
    printf("wrote %s: %dx%d, %llu eye rays, %llu shadow rays\n", out, ggImageWidth(img),
           ggImageHeight(img), (unsigned long long)stats.eye, (unsigned long long)stats.shadow);
    ggImageFree(img);
    ggSceneFree(scene);
    return 0;
}
