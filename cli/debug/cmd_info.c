/* SPDX-License-Identifier: MIT */
/*
** cmd_info.c -- `ggrt info SCENE`: what a scene holds and what it costs.
*/
#include "common/cli.h"

#include <string.h>

static const char about[] =
    "Describe a scene: objects by kind, lights, materials, meshes (what the file\n"
    "held and what is stored), the BVH (nodes, depth, memory, build time) and the\n"
    "effects the scene calls for, each with its reason. SCENE may be an OBJ or PLY\n"
    "model.";

int cmd_info(int argc, char **argv)
{
    const char *path = NULL;
    ggScene *s;
    ggSceneInfo in;
    ggCamera cam;
    int i, rc;
    unsigned fx;
    cli_opt none[] = {CLI_OPT_END};
    cli_cmd cmd = {.name = "info",
                   .usage = "SCENE",
                   .about = about,
                   .tail = "exit: 0 ok, 1 usage, 2 bad scene, 3 I/O error",
                   .opts = {none},
                   .args = &path,
                   .min_args = 1,
                   .max_args = 1,
                   .args_name = "scene"};
    if ((rc = cli_parse(&cmd, argc, argv)) != CLI_GO) return rc;
    if (!(s = cli_load_scene(path, NULL, NULL, 0, &rc))) return rc;
    ggSceneGetInfo(s, &in);
    cam = ggSceneCamera(s);
    printf("scene      %s\n", path);
    printf("camera     from %g %g %g  at %g %g %g  angle %g  %dx%d\n", cam.from.x, cam.from.y,
           cam.from.z, cam.at.x, cam.at.y, cam.at.z, cam.fov_deg, cam.width, cam.height);
    printf("objects    %d:", ggSceneObjectCount(s));
    for (i = 0; i < GG_SHAPE_COUNT; i++)
        if (in.objects_by_kind[i]) printf(" %d %s", in.objects_by_kind[i], ggShapeKindName(i));
    printf("\n");
    printf("lights     %d\n", ggSceneLightCount(s));
    printf("materials  %d\n", ggSceneMaterialCount(s));
    cli_print_meshes(stdout, s);
    printf("bounds     %g %g %g .. %g %g %g\n", in.lo.x, in.lo.y, in.lo.z, in.hi.x, in.hi.y,
           in.hi.z);
    printf("bvh        %zu primitive%s, %zu node%s (%zu lea%s), depth %zu\n", in.primitives,
           in.primitives == 1 ? "" : "s", in.bvh_nodes, in.bvh_nodes == 1 ? "" : "s", in.bvh_leaves,
           in.bvh_leaves == 1 ? "f" : "ves", in.bvh_depth);
    if (in.bvh_blocks)
        printf("           %zu lea%s of 2-4 triangles tested four at a time\n", in.bvh_blocks,
               in.bvh_blocks == 1 ? "f" : "ves");
    else
        printf("           no leaves of 2-4 triangles to test four at a time\n");
    printf("traversal  %s\n", ggSceneTraversal(s));
    printf("memory     %.2f MB geometry (%.1f bytes per primitive)\n", in.geometry_bytes / 1e6,
           in.primitives ? (double)in.geometry_bytes / (double)in.primitives : 0.0);
    printf("time       prepare %.4fs (BVH build %.4fs)\n", in.prepare_seconds, in.bvh_seconds);
    fx = ggSceneEffects(s);
    printf("effects    %s\n", fx ? "" : "none (ambient and emission only)");
    for (i = 0; i < GG_EFFECT_COUNT; i++) {
        unsigned e = 1u << i;
        if (fx & e) printf("  %-16s %s\n", ggEffectName(e), ggSceneEffectReason(s, e));
    }
    ggSceneFree(s);
    return EXIT_OK;
}
