/* SPDX-License-Identifier: MIT */
/*
** build_scene.c -- build a scene in code (no file), render it, write a PNG.
**   cc build_scene.c $(pkg-config --cflags --libs ggrt) -o build_scene
**   ./build_scene [out.png]
*/
#include <ggrt.h>

#include <stdio.h>

static ggVec3 vec(double x, double y, double z)
{
    ggVec3 v;
    v.x = x, v.y = y, v.z = z;
    return v;
}

static ggColor col(double r, double g, double b)
{
    ggColor c;
    c.r = r, c.g = g, c.b = b;
    return c;
}

int main(int argc, char **argv)
{
    const char *out = argc > 1 ? argv[1] : "build_scene.png";
    ggScene *scene = ggSceneCreate(NULL);
    ggCamera cam;
    ggMaterial floor, glass, red;
    ggRenderOptions opt;
    ggRayStats stats;
    ggImage *img = NULL;
    ggError err;
    int mfloor, mglass, mred;

    if (!scene) return 1;
    cam.from = vec(0, -5, 2), cam.at = vec(0, 0, 0.8), cam.up = vec(0, 0, 1);
    cam.fov_deg = 40, cam.width = 320, cam.height = 240;
    ggSceneSetCamera(scene, &cam);
    ggSceneSetBackground(scene, col(0.5, 0.65, 0.9));
    ggSceneAddLight(scene, vec(4, -4, 6), col(1, 1, 1));

    floor = ggMaterialDefault();
    floor.color = col(0.8, 0.8, 0.75), floor.kd = 0.9;
    glass = ggMaterialDefault();
    glass.kd = 0, glass.kt = 0.95, glass.ior = 1.5, glass.fresnel = GG_FRESNEL_EXACT;
    red = ggMaterialDefault();
    red.color = col(0.9, 0.2, 0.1), red.kd = 0.8, red.ks = 0.2, red.shine = 30;
    /* A building call that fails returns a negative status, and
       ggSceneLastError says why ("ggSceneAddMaterial: kt must be in ...") */
    if ((mfloor = ggSceneAddMaterial(scene, &floor)) < 0 ||
        (mglass = ggSceneAddMaterial(scene, &glass)) < 0 ||
        (mred = ggSceneAddMaterial(scene, &red)) < 0) {
        fprintf(stderr, "build_scene: %s\n", ggSceneLastError(scene)->message);
        ggSceneFree(scene);
        return 1;
    }

    ggSceneAddRect(scene, mfloor, vec(-5, -5, 0), vec(10, 0, 0), vec(0, 10, 0));
    ggSceneAddSphere(scene, mglass, vec(0, 0, 1), 1);
    ggSceneAddSphere(scene, mred, vec(1.6, 1.5, 0.6), 0.6);

    ggRenderOptionsDefault(&opt);
    opt.threads = 2;
    if (ggRender(scene, &opt, &img, &stats, &err) != GG_OK ||
        ggImageWritePNG(img, out, &err) != GG_OK) {
        fprintf(stderr, "build_scene: %s\n", err.message);
        ggImageFree(img);
        ggSceneFree(scene);
        return 1;
    }
    printf("wrote %s: %d objects, %llu eye, %llu reflect, %llu refract, %llu shadow rays\n", out,
           ggSceneObjectCount(scene), (unsigned long long)stats.eye,
           (unsigned long long)stats.reflect, (unsigned long long)stats.refract,
           (unsigned long long)stats.shadow);
    ggImageFree(img);
    ggSceneFree(scene);
    return stats.refract > 0 ? 0 : 1;
}
