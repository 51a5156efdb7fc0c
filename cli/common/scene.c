/* SPDX-License-Identifier: MIT */
/*
** scene.c -- a scene file, loaded the one way every command loads it,
** and what the commands print about meshes: each mesh of a scene (ggrt
** info), its warnings, the default view of a model rendered on its own as
** NFF to paste into a scene (ggrt render), and a hit triangle in the
** file's terms (ggrt trace); how much one pixel's recorded trees can
** take (find, check, diff, trace; ggrt serve's bound too).
*/
#include "common/cli.h"

#include <string.h>
#include <strings.h>
#include <unistd.h>

/* The bar of one step of cli_load_scene (the scene's progress callback
   while it runs). */
static void step_bar(ggScene *s, cli_bar *bar, const char *label, int quiet)
{
    cli_bar_begin(bar, label, quiet);
    bar->after = cli_bar_delay(0.5);
    ggSceneSetProgress(s, cli_bar_step, bar);
}

ggScene *cli_load_scene(const char *path, cli_loaded_fn loaded, void *ud, int quiet, int *rc)
{
    ggScene *s;
    ggError err;
    cli_bar bar;
    int st;
    if (!path[0]) { /* the library would say ": No such file or directory" */
        cli_error("the scene's file name is empty");
        *rc = EXIT_IO;
        return NULL;
    }
    if (!(s = ggSceneCreate(NULL))) {
        cli_error("out of memory");
        *rc = EXIT_INPUT;
        return NULL;
    }
    step_bar(s, &bar, "loading", quiet);
    st = ggSceneLoadFile(s, path, &err);
    cli_bar_end(&bar);
    if (st == GG_OK && loaded) loaded(s, path, ud);
    if (st == GG_OK) {
        step_bar(s, &bar, "preparing", quiet);
        if ((st = ggScenePrepare(s, &err)) != GG_OK) {
            /* the loader's errors name the file and line; preparing's, the scene */
            char m[sizeof err.message];
            memcpy(m, err.message, sizeof m);
            snprintf(err.message, sizeof err.message, "%.200s: %.300s", path, m);
        }
        cli_bar_end(&bar);
    }
    ggSceneSetProgress(s, NULL, NULL); /* the bar is this function's */
    if (st != GG_OK) {
        *rc = cli_fail(st, &err, 0);
        ggSceneFree(s);
        return NULL;
    }
    *rc = EXIT_OK;
    return s;
}

const int cli_surface_cells[CLI_SURFACE_STEPS] = {64, 48, 32, 24, 16, 12, 8};

int cli_is_model(const char *path)
{
    size_t n = strlen(path);
    return n > 4 && (!strcasecmp(path + n - 4, ".obj") || !strcasecmp(path + n - 4, ".ply"));
}

void cli_print_meshes(FILE *f, const ggScene *s)
{
    int i, n = ggSceneMeshCount(s);
    for (i = 0; i < n; i++) {
        ggMeshInfo mi;
        ggSceneGetMeshInfo(s, i, &mi);
        fprintf(f, "mesh %-5d %s (%s): %zu vertices, %zu faces in the file", i, mi.name,
                mi.format[0] ? mi.format : "code", mi.file_vertices, mi.file_faces);
        if (mi.skipped_faces) fprintf(f, ", %zu of zero area dropped", mi.skipped_faces);
        if (mi.ignored) fprintf(f, ", %zu statements or elements not used", mi.ignored);
        fprintf(f, "\n           %zu triangles, %zu vertices, normals %s%s; objects #%d..#%d",
                mi.triangles, mi.vertices, mi.file_normals ? "from the file" : "computed",
                mi.has_uv ? ", uv" : "", mi.first_object, mi.first_object + mi.objects - 1);
        if (mi.groups) fprintf(f, ", %d group%s", mi.groups, mi.groups == 1 ? "" : "s");
        fprintf(f, "\n           %.2f MB (%.1f bytes per triangle), bounds %g %g %g .. %g %g %g\n",
                mi.bytes / 1e6, mi.triangles ? (double)mi.bytes / (double)mi.triangles : 0.0,
                mi.lo.x, mi.lo.y, mi.lo.z, mi.hi.x, mi.hi.y, mi.hi.z);
        if (mi.warnings)
            fprintf(f, "           %d warning%s, the first: %s\n", mi.warnings,
                    mi.warnings == 1 ? "" : "s", mi.warning);
    }
}

void cli_print_mesh_warnings(const ggScene *s)
{
    int i, n = ggSceneMeshCount(s);
    for (i = 0; i < n; i++) {
        ggMeshInfo mi;
        ggSceneGetMeshInfo(s, i, &mi);
        if (mi.warnings)
            cli_warn("%s%s", mi.warning, mi.warnings > 1 ? " (and more: see ggrt info)" : "");
    }
}

void cli_print_model_view(FILE *f, const ggScene *s, const char *path)
{
    ggCamera c = ggSceneCamera(s);
    int i, n = ggSceneLightCount(s);
    fprintf(f,
            "# ggrt: %s has no camera or lights; it is rendered with these (NFF: paste them "
            "into a scene)\n",
            path);
    fprintf(f,
            "v\nfrom %.6g %.6g %.6g\nat %.6g %.6g %.6g\nup %g %g %g\nangle %g\nhither 0\n"
            "resolution %d %d\n",
            c.from.x, c.from.y, c.from.z, c.at.x, c.at.y, c.at.z, c.up.x, c.up.y, c.up.z, c.fov_deg,
            c.width, c.height);
    for (i = 0; i < n; i++) {
        ggVec3 p;
        ggColor col;
        ggSceneGetLight(s, i, &p, &col);
        fprintf(f, "l %.6g %.6g %.6g %g %g %g\n", p.x, p.y, p.z, col.r, col.g, col.b);
    }
    fprintf(f, "mesh \"%s\"\n", path);
}

int cli_face_text(const ggScene *s, int object, long triangle, char *buf, size_t n)
{
    ggFaceInfo fi;
    size_t k;
    if (triangle < 0 || ggSceneGetFaceInfo(s, object, triangle, &fi) != GG_OK) return 0;
    k = (size_t)snprintf(buf, n, "triangle %ld: face %ld of %s", triangle, fi.face, fi.mesh_name);
    if (fi.line > 0 && k < n) k += (size_t)snprintf(buf + k, n - k, " (line %d)", fi.line);
    if (fi.group[0] && k < n) k += (size_t)snprintf(buf + k, n - k, ", group '%s'", fi.group);
    if (fi.material_name[0] && k < n)
        k += (size_t)snprintf(buf + k, n - k, ", usemtl '%s'", fi.material_name);
    return 1;
}

/* The most children a hit of s has: a reflection (a mirror, or the total
   internal reflection of glass) and a refraction, three after dispersion
   (shade.c: transmit, reflect). */
static double children(const ggScene *s)
{
    unsigned fx = ggSceneEffects(s);
    if (fx & GG_EFFECT_REFRACTION) return fx & GG_EFFECT_DISPERSION ? 4 : 2;
    return fx & GG_EFFECT_REFLECTION ? 1 : 0;
}

double cli_record_bytes(const ggScene *s, const ggRenderOptions *given)
{
    ggRenderOptions r; /* depth 0 is the scene's or 5: what the render takes */
    const ggRenderOptions *o = ggRenderOptionsResolve(s, given, &r) == GG_OK ? &r : given;
    double eyes = (double)(o->samples > 0 ? o->samples : 1) * (o->pixel_corners ? 4 : 1);
    double cap = o->ray_budget > 0 ? o->ray_budget : GG_RAY_BUDGET, rays = 0, level = 1;
    double b = children(s);
    int d;
    for (d = 1; o->max_depth > 0 && d < o->max_depth && rays < cap; d++) rays += level *= b;
    if (o->max_depth <= 0 || rays > cap) rays = cap;
    return eyes * (1 + rays) *
           ((double)sizeof(ggTraceNode) +
            (double)ggSceneLightCount(s) * (double)sizeof(ggTraceLight));
}

int cli_check_recordable(const char *cmd, const ggScene *s, const ggRenderOptions *o, int threads,
                         int sides)
{
    long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGESIZE);
    double mem = pages > 0 && size > 0 ? (double)pages * (double)size : 0;
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    int at_once = (threads > 0 ? threads : cores > 0 ? (int)cores : 1) * sides;
    double one = cli_record_bytes(s, o), need = one * at_once;
    if (!(mem > 0) || need <= mem / 2) return 0;
    cli_error_in(cmd,
                 "the ray trees of one pixel could take %.0f MiB here (%d at once: %.0f MiB), "
                 "over half of this machine's %.0f MiB: lower samples, depth or ray-budget",
                 one / (1 << 20), at_once, need / (1 << 20), mem / (1 << 20));
    cli_usage_hint();
    return EXIT_USAGE;
}

int cli_check_same_size(const char *cmd, const ggScene *sa, const ggRenderOptions *oa,
                        const ggScene *sb, const ggRenderOptions *ob)
{
    ggRenderOptions ra, rb; /* the sizes each render takes */
    if (ggRenderOptionsResolve(sa, oa, &ra) != GG_OK ||
        ggRenderOptionsResolve(sb, ob, &rb) != GG_OK)
        return 0; /* (NULLs: the render says so) */
    if (ra.width == rb.width && ra.height == rb.height) return 0;
    cli_error_in(cmd,
                 "the two sides are images of different sizes (a %dx%d, b %dx%d): give -s WxH "
                 "for both, or size=WxH in --a or --b",
                 ra.width, ra.height, rb.width, rb.height);
    cli_usage_hint();
    return EXIT_USAGE;
}
