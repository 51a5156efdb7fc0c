/* SPDX-License-Identifier: MIT */
/*
** ray_color.c -- evaluate ggRayColor for one ray, and look at what it hit.
**   cc -o ray_color ray_color.c $(pkg-config --cflags --libs ggrt) -lm && ./ray_color
** (-lm for the program's own acos: libggrt's libm is not the program's.)
*/
#include <ggrt.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

int main(void)
{
    /* A scene can also come from NFF text in memory. */
    const char *nff = "b 0.2 0.3 0.5\n"
                      "l 0 0 10\n"
                      "f 1 0.5 0.2 0.8 0.2 20 0 0\n"
                      "s 0 0 0 1\n";
    ggScene *scene = ggSceneCreate(NULL);
    ggError err;
    ggRay ray;
    ggHit hit;
    ggColor c;
    ggRayStats st;
    double cosine;

    if (!scene) return 1;
    if (ggSceneLoadString(scene, nff, strlen(nff), "inline.nff", &err) != GG_OK ||
        ggScenePrepare(scene, &err) != GG_OK) {
        fprintf(stderr, "ray_color: %s\n", err.message);
        ggSceneFree(scene);
        return 1;
    }
    ray.o.x = 0, ray.o.y = 0, ray.o.z = 5;
    ray.d.x = 0, ray.d.y = 0, ray.d.z = -1;
    memset(&st, 0, sizeof st);
    c = ggRayColor(scene, NULL, ray, 1, &st);
    if (!ggSceneIntersect(scene, ray, 0, 1e30, &hit)) {
        fprintf(stderr, "ray_color: the ray should hit the sphere\n");
        ggSceneFree(scene);
        return 1;
    }
    printf("hit %s %d at t = %g, point (%g, %g, %g), normal (%g, %g, %g)\n",
           ggShapeKindName(hit.kind), hit.object, hit.t, hit.p.x, hit.p.y, hit.p.z, hit.ng.x,
           hit.ng.y, hit.ng.z);
    /* The angle between the ray and the normal, by the program's own libm. */
    cosine = -(ray.d.x * hit.ng.x + ray.d.y * hit.ng.y + ray.d.z * hit.ng.z) /
             sqrt(hit.ng.x * hit.ng.x + hit.ng.y * hit.ng.y + hit.ng.z * hit.ng.z);
    printf("angle of incidence %.3f degrees\n", acos(cosine) * 180 / 3.14159265358979323846);
    printf("colour %.4f %.4f %.4f from %llu eye, %llu reflect and %llu shadow rays\n", c.r, c.g,
           c.b, (unsigned long long)st.eye, (unsigned long long)st.reflect,
           (unsigned long long)st.shadow);
    ggSceneFree(scene);
    /* The lit top of the orange sphere: red above green above blue. */
    if (!(hit.t > 3.999 && hit.t < 4.001 && c.r > c.g && c.g > c.b)) return 1;
    /* Straight down onto the top: normal incidence. */
    return fabs(cosine - 1) < 1e-12 ? 0 : 1;
}
