/* SPDX-License-Identifier: MIT */
/*
** scene.c -- the scene object: building it in code, inspecting it, and
** preparing it for rendering (primitives, BVH, resolved materials).
*/
#include "scene.h"

#include "image.h"
#include "implicit.h"
#include "vec.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <string.h>

GG_API const char *ggShapeKindName(int kind)
{
    static const char *const names[GG_SHAPE_COUNT] = {"sphere", "triangle", "polygon", "cone",
                                                       "rect",   "implicit", "mesh"};
    return kind >= 0 && kind < GG_SHAPE_COUNT ? names[kind] : "?";
}

GG_API ggMaterial ggMaterialDefault(void)
{
    ggMaterial m;
    memset(&m, 0, sizeof m);
    m.color = rgb(1, 1, 1);
    m.kd = 1;
    m.shine = 100000;
    m.ior = 1;
    m.fresnel = GG_FRESNEL_NONE;
    m.eta_n = rgb(1, 1, 1);
    m.texture = -1;
    return m;
}

GG_API ggScene *ggSceneCreate(const ggAllocator *alloc)
{
    ggScene *s = gg_mem_calloc(alloc, 1, sizeof *s);
    if (!s) return NULL;
    if (alloc) {
        s->alloc_copy = *alloc;
        s->alloc = &s->alloc_copy;
    }
    s->camera.from = v3(0, 0, 1);
    s->camera.at = v3(0, 0, 0);
    s->camera.up = v3(0, 1, 0);
    s->camera.fov_deg = 45;
    s->camera.width = 512;
    s->camera.height = 512;
    s->background = rgb(0, 0, 0);
    s->ambient = rgb(0.1, 0.1, 0.1);
    s->tex_budget = GG_TEXTURE_BUDGET;
    return s;
}

static void unprepare(ggScene *s)
{
    gg_geom_free(s->geom);
    s->geom = NULL;
    gg_mem_free(s->alloc, s->mfast);
    s->mfast = NULL;
    gg_mem_free(s->alloc, s->light_colors);
    s->light_colors = NULL;
    gg_effects_clear(s);
    s->prepared = false;
}

void gg_scene_set_aside(ggScene *s, gg_prepared *p)
{
    int i;
    p->prepared = s->prepared, p->geom = s->geom, p->mfast = s->mfast;
    p->light_colors = s->light_colors, p->effects = s->effects;
    p->prepare_seconds = s->prepare_seconds;
    for (i = 0; i < GG_EFFECT_COUNT; i++) p->reasons[i] = s->reasons[i], s->reasons[i] = NULL;
    s->geom = NULL, s->mfast = NULL, s->light_colors = NULL, s->effects = 0;
    s->prepared = false;
}

void gg_scene_put_back(ggScene *s, gg_prepared *p)
{
    int i;
    unprepare(s);
    s->prepared = p->prepared, s->geom = p->geom, s->mfast = p->mfast;
    s->light_colors = p->light_colors, s->effects = p->effects;
    s->prepare_seconds = p->prepare_seconds;
    for (i = 0; i < GG_EFFECT_COUNT; i++) s->reasons[i] = p->reasons[i];
}

void gg_scene_drop_aside(ggScene *s, gg_prepared *p)
{
    int i;
    gg_geom_free(p->geom);
    gg_mem_free(s->alloc, p->mfast);
    gg_mem_free(s->alloc, p->light_colors);
    for (i = 0; i < GG_EFFECT_COUNT; i++) gg_mem_free(s->alloc, p->reasons[i]);
}

GG_API void ggSceneFree(ggScene *s)
{
    size_t i;
    if (!s) return;
    unprepare(s);
    for (i = 0; i < s->nobjects; i++) ggImplicitFree(s->objects[i].imp);
    gg_scene_drop_textures(s, 0, 0);
    gg_scene_drop_meshes(s, 0);
    gg_mem_free(s->alloc, s->meshes);
    gg_mem_free(s->alloc, s->mesh_files);
    gg_mem_free(s->alloc, s->objects);
    gg_mem_free(s->alloc, s->materials);
    gg_mem_free(s->alloc, s->lights);
    gg_mem_free(s->alloc, s->textures);
    gg_mem_free(s->alloc, s->images);
    gg_mem_free(s->alloc, s->verts);
    gg_mem_free(s->alloc, s->norms);
    gg_mem_free(s->alloc, s->filename);
    gg_mem_free(s->alloc, s);
}

/* ---- validation (docs/scene-format.md, "Parameter ranges") ---- */

/* The largest magnitude, NaN if any coordinate is: fmax alone drops a
   NaN, and the checks compare this to a bound (a NaN must fail them). */
static double vmax(ggVec3 v)
{
    if (isnan(v.x) || isnan(v.y) || isnan(v.z)) return NAN;
    return fmax(fabs(v.x), fmax(fabs(v.y), fabs(v.z)));
}
static bool in_range(double x, double hi)
{
    return x >= 0 && x <= hi;
}
static bool color_ok(ggColor c)
{
    return in_range(c.r, GG_PARAM_MAX) && in_range(c.g, GG_PARAM_MAX) &&
           in_range(c.b, GG_PARAM_MAX);
}
static bool unit_len(ggVec3 v)
{
    return fabs(v3len(v) - 1) < 1e-6;
}

/* Two camera vectors closer (or more parallel) than this, relative to
   their size, leave the view direction with fewer than 30 correct bits:
   they count as equal (parallel). The basis is then computed as the
   renderer does (lib/render/render.c, basis()) and must come out unit. */
#define CAM_EPS 1e-9
/* Larger coordinates would overflow the squares of the basis' lengths. */
#define CAM_MAX 1e150

int gg_camera_fault(const ggCamera *c)
{
    ggVec3 d, fwd, cr;
    if (!v3finite(c->from) || !v3finite(c->at) || !v3finite(c->up) ||
        !(fmax(vmax(c->from), fmax(vmax(c->at), vmax(c->up))) <= CAM_MAX))
        return GG_CAMERA_NONFINITE;
    d = v3sub(c->at, c->from);
    fwd = v3unit(d);
    if (!v3finite(d) || !(vmax(d) > CAM_EPS * fmax(vmax(c->from), vmax(c->at))) || !unit_len(fwd))
        return GG_CAMERA_FROM_AT;
    /* zero would pass as parallel to anything: say what it is */
    if (vmax(c->up) == 0) return GG_CAMERA_UP_ZERO;
    cr = v3cross(fwd, c->up);
    if (!(vmax(cr) > CAM_EPS * vmax(c->up)) || !unit_len(v3unit(cr))) return GG_CAMERA_UP;
    if (!(c->fov_deg > 0 && c->fov_deg < 180)) return GG_CAMERA_FOV;
    if (c->width < 1 || c->height < 1 || c->width > GG_IMAGE_MAX_DIM ||
        c->height > GG_IMAGE_MAX_DIM || (size_t)c->width * (size_t)c->height > GG_IMAGE_MAX_PIXELS)
        return GG_CAMERA_SIZE;
    return GG_CAMERA_OK;
}

#define GG_STR_(x) #x
#define GG_STR(x)  GG_STR_(x)
/* GG_IMAGE_MAX_PIXELS as text (the macro is a shift, which the
   preprocessor cannot turn into digits); the typedef stops the build
   if the two ever differ. */
#define MAX_PIXELS_TEXT "16777216"
typedef char max_pixels_text_is_the_limit[GG_IMAGE_MAX_PIXELS == 16777216 ? 1 : -1];

const char *gg_camera_fault_text(int fault)
{
    switch (fault) {
    case GG_CAMERA_NONFINITE:
        return "'from', 'at' and 'up' must be finite, at most 1e150";
    case GG_CAMERA_FROM_AT:
        return "'from' and 'at' are the same point (or within 1e-9 of their size)";
    case GG_CAMERA_UP:
        return "'up' is parallel to the view direction";
    case GG_CAMERA_UP_ZERO:
        return "'up' is the zero vector";
    case GG_CAMERA_FOV:
        return "the field of view must be in (0, 180) degrees";
    case GG_CAMERA_SIZE:
        return "the image size must be 1 to " GG_STR(
            GG_IMAGE_MAX_DIM) " a side and at most " MAX_PIXELS_TEXT " pixels";
    default:
        return "no problem";
    }
}

GG_API int ggCameraCheck(const ggCamera *cam, ggError *err)
{
    int f;
    if (!cam) return gg_error_set(err, GG_ERROR_INVALID, "ggCameraCheck: NULL camera");
    f = gg_camera_fault(cam);
    if (f != GG_CAMERA_OK)
        return gg_error_set(err, GG_ERROR_INVALID, "camera: %s", gg_camera_fault_text(f));
    return GG_OK;
}

static int bad_color(ggError *err, const char *what, ggColor c)
{
    return gg_error_set(err, GG_ERROR_INVALID, "material: %s must be finite and >= 0, got %g %g %g",
                        what, c.r, c.g, c.b);
}

GG_API int ggMaterialCheck(const ggMaterial *m, ggError *err)
{
    const double w[4] = {m ? m->kd : 0, m ? m->ks : 0, m ? m->kt : 0, m ? m->shine : 0};
    const double wmax[4] = {GG_WEIGHT_MAX, GG_WEIGHT_MAX, GG_WEIGHT_MAX, DBL_MAX};
    const char *const wn[4] = {"kd", "ks", "kt", "the Phong exponent"};
    const ggColor *n, *k;
    int i;
    if (!m) return gg_error_set(err, GG_ERROR_INVALID, "ggMaterialCheck: NULL material");
    if (!color_ok(m->color)) return bad_color(err, "the colour", m->color);
    for (i = 0; i < 4; i++)
        if (!in_range(w[i], wmax[i]))
            return gg_error_set(err, GG_ERROR_INVALID, "material: %s must be in [0, %g], got %g",
                                wn[i], wmax[i], w[i]);
    if (!(fabs(m->ior) <= GG_PARAM_MAX) || (m->kt > 0 && m->ior == 0))
        return gg_error_set(err, GG_ERROR_INVALID,
                            "material: the index of refraction must be at most 1e30 in size "
                            "(and non-zero when kt > 0), got %g",
                            m->ior);
    if (!color_ok(m->ke)) return bad_color(err, "the emission", m->ke);
    if (!color_ok(m->extinction)) return bad_color(err, "the extinction", m->extinction);
    if (!in_range(m->unit_m, GG_PARAM_MAX) || !in_range(m->abbe, GG_PARAM_MAX) ||
        (m->abbe > 0 && m->abbe < 1))
        return gg_error_set(err, GG_ERROR_INVALID,
                            "material: unit_m must be in [0, 1e30] and abbe 0 or in [1, 1e30], "
                            "got %g and %g",
                            m->unit_m, m->abbe);
    if (m->fresnel < GG_FRESNEL_NONE || m->fresnel > GG_FRESNEL_CONDUCTOR)
        return gg_error_set(err, GG_ERROR_INVALID, "material: unknown fresnel mode %d", m->fresnel);
    n = &m->eta_n, k = &m->eta_k;
    if (!(vmax((ggVec3){n->r, n->g, n->b}) <= GG_PARAM_MAX) || !color_ok(*k) ||
        (m->fresnel == GG_FRESNEL_CONDUCTOR && !color_ok(*n)))
        return gg_error_set(err, GG_ERROR_INVALID,
                            "material: the complex index needs |n| <= 1e30 (n >= 0 for a "
                            "conductor) and k in [0, 1e30], got n %g %g %g, k %g %g %g",
                            n->r, n->g, n->b, k->r, k->g, k->b);
    if (m->fresnel == GG_FRESNEL_CONDUCTOR &&
        ((n->r == 0 && k->r == 0) || (n->g == 0 && k->g == 0) || (n->b == 0 && k->b == 0)))
        return gg_error_set(err, GG_ERROR_INVALID,
                            "material: a conductor index n + ik of 0 (n = k = 0 in a channel) "
                            "has no Fresnel reflectance");
    if (m->texture < -1)
        return gg_error_set(err, GG_ERROR_INVALID, "material: bad texture index %d", m->texture);
    return GG_OK;
}

/* ---- building in code ----
   Each building function answers through done() or refuse(): its status,
   and the message ggSceneLastError gives ("" after a success). */

static int done(ggScene *s, int rc)
{
    s->last.code = GG_OK;
    s->last.message[0] = '\0';
    return rc;
}

/* rc is the status returned (GG_ERROR_x, or -GG_ERROR_x where success is
   an index); the message is "FN: what". */
static int refuse(ggScene *s, int rc, const char *fmt, ...) GG_PRINTF(3, 4);
static int refuse(ggScene *s, int rc, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    gg_error_setv(&s->last, rc < 0 ? -rc : rc, fmt, ap);
    va_end(ap);
    return rc;
}

static int bad_channels(ggScene *s, int rc, const char *fn, const char *what, ggColor c)
{
    return refuse(s, rc, "%s: every channel of %s must be in [0, %g], got %g %g %g", fn, what,
                  GG_PARAM_MAX, c.r, c.g, c.b);
}

GG_API const ggError *ggSceneLastError(const ggScene *s)
{
    return s ? &s->last : NULL;
}

GG_API int ggSceneSetCamera(ggScene *s, const ggCamera *cam)
{
    int f;
    if (!s) return GG_ERROR_INVALID;
    if (!cam) return refuse(s, GG_ERROR_INVALID, "ggSceneSetCamera: NULL camera");
    if ((f = gg_camera_fault(cam)) != GG_CAMERA_OK)
        return refuse(s, GG_ERROR_INVALID, "ggSceneSetCamera: %s", gg_camera_fault_text(f));
    s->camera = *cam;
    s->has_camera = true;
    return done(s, GG_OK);
}
GG_API ggCamera ggSceneCamera(const ggScene *s)
{
    ggCamera c;
    if (s) return s->camera;
    memset(&c, 0, sizeof c);
    return c;
}
GG_API int ggSceneSetBackground(ggScene *s, ggColor c)
{
    if (!s) return GG_ERROR_INVALID;
    if (!color_ok(c))
        return bad_channels(s, GG_ERROR_INVALID, "ggSceneSetBackground", "the colour", c);
    s->background = c;
    return done(s, GG_OK);
}
GG_API int ggSceneSetAmbient(ggScene *s, ggColor c)
{
    if (!s) return GG_ERROR_INVALID;
    if (!color_ok(c))
        return bad_channels(s, GG_ERROR_INVALID, "ggSceneSetAmbient", "the colour", c);
    s->ambient = c;
    return done(s, GG_OK);
}
GG_API void ggSceneSetImageReader(ggScene *s, ggImageReader fn, void *ud)
{
    if (!s) return;
    s->reader = fn;
    s->reader_ud = fn ? ud : NULL;
}
/* A prepared scene's effect set after a setting it depends on (depth,
   samples) changed: computed again, so that ggSceneEffects says what a
   fresh prepare would; short of memory for it, the scene is unprepared
   and the next render prepares it. */
static void refresh_effects(ggScene *s)
{
    if (s->prepared && gg_effects_compute(s) != GG_OK) unprepare(s);
}

GG_API int ggSceneSetDepth(ggScene *s, int d)
{
    if (!s) return GG_ERROR_INVALID;
    if (d < 0 || d > 64)
        return refuse(s, GG_ERROR_INVALID,
                      "ggSceneSetDepth: max_depth must be 0 (the renderer's) or 1 to 64, got %d",
                      d);
    s->depth = d;
    refresh_effects(s);
    return done(s, GG_OK);
}
GG_API int ggSceneSetSamples(ggScene *s, int n)
{
    if (!s) return GG_ERROR_INVALID;
    if (n < 0 || n > 4096)
        return refuse(s, GG_ERROR_INVALID,
                      "ggSceneSetSamples: samples_per_pixel must be 0 (the renderer's) or 1 to "
                      "4096, got %d",
                      n);
    s->samples = n;
    refresh_effects(s);
    return done(s, GG_OK);
}

GG_API int ggSceneAddLight(ggScene *s, ggVec3 pos, ggColor color)
{
    gg_light *l;
    if (!s) return -GG_ERROR_INVALID;
    if (!v3finite(pos) || !gg_scene_coord_ok(pos))
        return refuse(s, -GG_ERROR_INVALID,
                      "ggSceneAddLight: the position must be finite and at most %g in "
                      "magnitude, got %g %g %g",
                      GG_COORD_MAX, pos.x, pos.y, pos.z);
    /* r < 0 asks for the SPD default colour; any other colour is >= 0. */
    if (!isfinite(color.r) || !isfinite(color.g) || !isfinite(color.b) ||
        (color.r >= 0 && (color.g < 0 || color.b < 0)))
        return refuse(s, -GG_ERROR_INVALID,
                      "ggSceneAddLight: the colour must be finite and >= 0 (or r < 0 for the "
                      "SPD default), got %g %g %g",
                      color.r, color.g, color.b);
    if (gg_mem_grow(s->alloc, (void **)&s->lights, &s->cap_lights, s->nlights + 1, sizeof *l))
        return refuse(s, -GG_ERROR_NOMEM, "ggSceneAddLight: out of memory adding the light");
    unprepare(s);
    l = &s->lights[s->nlights];
    l->pos = pos;
    l->color = color;
    l->line = 0;
    return done(s, (int)s->nlights++);
}

/* What ggSceneAddMaterial and ggSceneSetMaterial accept; rc is the status
   a refusal returns. */
static int material_refused(ggScene *s, const char *fn, const ggMaterial *m, int rc)
{
    ggError e;
    if (!m) return refuse(s, rc, "%s: NULL material", fn);
    if (ggMaterialCheck(m, &e) != GG_OK)
        return refuse(s, rc, "%s: %s", fn,
                      strncmp(e.message, "material: ", 10) ? e.message : e.message + 10);
    if (m->texture >= 0 && (size_t)m->texture >= s->ntextures)
        return refuse(s, rc, "%s: no texture %d (the scene has %zu)", fn, m->texture, s->ntextures);
    return 0;
}

GG_API int ggSceneAddMaterial(ggScene *s, const ggMaterial *m)
{
    int rc;
    if (!s) return -GG_ERROR_INVALID;
    if ((rc = material_refused(s, "ggSceneAddMaterial", m, -GG_ERROR_INVALID)) != 0) return rc;
    if (gg_mem_grow(s->alloc, (void **)&s->materials, &s->cap_materials, s->nmaterials + 1,
                    sizeof *m))
        return refuse(s, -GG_ERROR_NOMEM, "ggSceneAddMaterial: out of memory adding the material");
    unprepare(s);
    s->materials[s->nmaterials] = *m;
    return done(s, (int)s->nmaterials++);
}

GG_API int ggSceneSetMaterial(ggScene *s, int index, const ggMaterial *m)
{
    int rc;
    if (!s) return GG_ERROR_INVALID;
    if (index < 0 || (size_t)index >= s->nmaterials)
        return refuse(s, GG_ERROR_INVALID, "ggSceneSetMaterial: no material %d (the scene has %zu)",
                      index, s->nmaterials);
    if ((rc = material_refused(s, "ggSceneSetMaterial", m, GG_ERROR_INVALID)) != 0) return rc;
    unprepare(s);
    s->materials[index] = *m;
    return done(s, GG_OK);
}

int gg_scene_add_texture_desc(ggScene *s, const gg_texture *t)
{
    if (gg_mem_grow(s->alloc, (void **)&s->textures, &s->cap_textures, s->ntextures + 1,
                    sizeof *t)) {
        if (!t->shared) ggImageFree(t->img);
        return -GG_ERROR_NOMEM;
    }
    unprepare(s);
    s->textures[s->ntextures] = *t;
    return (int)s->ntextures++;
}

ggImage *gg_scene_image_find(const ggScene *s, const char *path, const uint64_t *id)
{
    size_t i;
    for (i = 0; i < s->nimages; i++) {
        const gg_teximage *t = &s->images[i];
        if (strcmp(t->path, path) == 0 ||
            (id && t->has_id && t->id[0] == id[0] && t->id[1] == id[1]))
            return t->img;
    }
    return NULL;
}

int gg_scene_image_add(ggScene *s, const char *path, const uint64_t *id, ggImage *img)
{
    char *p = gg_mem_strdup(s->alloc, path);
    if (!p || gg_mem_grow(s->alloc, (void **)&s->images, &s->cap_images, s->nimages + 1,
                          sizeof *s->images)) {
        gg_mem_free(s->alloc, p);
        ggImageFree(img);
        return -GG_ERROR_NOMEM;
    }
    s->images[s->nimages].path = p;
    s->images[s->nimages].img = img;
    s->images[s->nimages].has_id = id != NULL;
    s->images[s->nimages].id[0] = id ? id[0] : 0, s->images[s->nimages].id[1] = id ? id[1] : 0;
    s->tex_used += GG_IMAGE_BYTES(img->width, img->height);
    return (int)s->nimages++;
}

void gg_scene_drop_textures(ggScene *s, size_t nt, size_t ni)
{
    size_t i;
    for (i = nt; i < s->ntextures; i++)
        if (!s->textures[i].shared) ggImageFree(s->textures[i].img);
    for (i = ni; i < s->nimages; i++) {
        s->tex_used -= GG_IMAGE_BYTES(s->images[i].img->width, s->images[i].img->height);
        ggImageFree(s->images[i].img);
        gg_mem_free(s->alloc, s->images[i].path);
    }
    if (nt < s->ntextures) s->ntextures = nt;
    if (ni < s->nimages) s->nimages = ni;
}

GG_API int64_t ggSceneSetTextureBudget(ggScene *s, int64_t bytes)
{
    int64_t old;
    if (!s) return -1;
    old = s->tex_budget;
    if (bytes >= 0) s->tex_budget = bytes;
    return old;
}

/* A texture added in code: its index, or the refusal of running out of
   memory (the image is freed either way). */
static int add_texture(ggScene *s, const char *fn, const gg_texture *t)
{
    int rc = gg_scene_add_texture_desc(s, t);
    if (rc < 0) return refuse(s, rc, "%s: out of memory adding the texture", fn);
    return done(s, rc);
}

GG_API int ggSceneAddTexture(ggScene *s, ggImage *img)
{
    gg_texture t;
    if (!s || !img) {
        ggImageFree(img);
        return s ? refuse(s, -GG_ERROR_INVALID, "ggSceneAddTexture: NULL image")
                 : -GG_ERROR_INVALID;
    }
    memset(&t, 0, sizeof t);
    t.img = img;
    t.wrap = GG_WRAP_REPEAT;
    return add_texture(s, "ggSceneAddTexture", &t);
}

GG_API int ggSceneAddChecker(ggScene *s, double n, ggColor a, ggColor b)
{
    gg_texture t;
    if (!s) return -GG_ERROR_INVALID;
    if (!(n > 0 && n <= 1e6))
        return refuse(s, -GG_ERROR_INVALID, "ggSceneAddChecker: n must be in (0, 1e6], got %g", n);
    if (!color_ok(a)) return bad_channels(s, -GG_ERROR_INVALID, "ggSceneAddChecker", "colour a", a);
    if (!color_ok(b)) return bad_channels(s, -GG_ERROR_INVALID, "ggSceneAddChecker", "colour b", b);
    memset(&t, 0, sizeof t);
    t.checker_n = n, t.checker_a = a, t.checker_b = b;
    return add_texture(s, "ggSceneAddChecker", &t);
}

int gg_scene_push_vertices(ggScene *s, const ggVec3 *v, const ggVec3 *n, int count, size_t *first)
{
    int i;
    size_t need = s->nverts + (size_t)count;
    /* norms only as far as vertices with normals reach: a scene of plain
       polygons (the SPD's, most NFF) then keeps no array of zeros, and
       its load touches half the memory */
    if (gg_mem_grow(s->alloc, (void **)&s->verts, &s->cap_verts, need, sizeof *v) ||
        (n && gg_mem_grow(s->alloc, (void **)&s->norms, &s->cap_norms, need, sizeof *v)))
        return -GG_ERROR_NOMEM;
    *first = s->nverts;
    for (i = 0; i < count; i++) s->verts[s->nverts + (size_t)i] = v[i];
    if (n)
        for (i = 0; i < count; i++) s->norms[s->nverts + (size_t)i] = n[i];
    s->nverts = need;
    return 0;
}

bool gg_scene_coord_ok(ggVec3 v)
{
    return fabs(v.x) <= GG_COORD_MAX && fabs(v.y) <= GG_COORD_MAX && fabs(v.z) <= GG_COORD_MAX;
}

static bool size_ok(double r)
{
    return fabs(r) <= GG_COORD_MAX;
}

/* Every coordinate and size of o within GG_COORD_MAX (an implicit
   surface's: its box's corners); a mesh's vertices are checked by
   mesh.c. */
static bool object_in_range(const ggScene *s, const gg_object *o)
{
    ggVec3 lo, hi;
    size_t i;
    switch (o->kind) {
    case GG_SHAPE_SPHERE:
        return gg_scene_coord_ok(o->a) && size_ok(o->ra);
    case GG_SHAPE_CONE:
        return gg_scene_coord_ok(o->a) && gg_scene_coord_ok(o->b) && size_ok(o->ra) &&
               size_ok(o->rb);
    case GG_SHAPE_RECT:
        return gg_scene_coord_ok(o->a) && gg_scene_coord_ok(o->b) && gg_scene_coord_ok(o->c) &&
               gg_scene_coord_ok(v3add(v3add(o->a, o->b), o->c));
    case GG_SHAPE_TRIANGLE:
    case GG_SHAPE_POLYGON:
        for (i = 0; i < (size_t)o->nverts; i++)
            if (!gg_scene_coord_ok(s->verts[o->vfirst + i])) return false;
        return true;
    case GG_SHAPE_IMPLICIT:
        ggImplicitBounds(o->imp, &lo, &hi);
        return gg_scene_coord_ok(lo) && gg_scene_coord_ok(hi);
    default:
        return true;
    }
}

int gg_scene_add_object(ggScene *s, const gg_object *o)
{
    if (!s) return -GG_ERROR_INVALID;
    if (!object_in_range(s, o)) return -GG_ERROR_INVALID;
    if (o->material < 0 || (size_t)o->material >= s->nmaterials) return -GG_ERROR_INVALID;
    if (s->nobjects >= (size_t)INT32_MAX) return -GG_ERROR_LIMIT;
    if (gg_mem_grow(s->alloc, (void **)&s->objects, &s->cap_objects, s->nobjects + 1,
                    sizeof *o))
        return -GG_ERROR_NOMEM;
    unprepare(s);
    s->objects[s->nobjects] = *o;
    return (int)s->nobjects++;
}

static gg_object object_init(int kind, int material)
{
    gg_object o;
    memset(&o, 0, sizeof o);
    o.kind = kind;
    o.material = material;
    return o;
}

/* A shape added in code, its own values checked: the material, then
   gg_scene_add_object's range, limit and memory, each refusal named. */
static int add_shape(ggScene *s, const char *fn, const gg_object *o)
{
    int rc;
    if (o->material < 0 || (size_t)o->material >= s->nmaterials)
        return refuse(s, -GG_ERROR_INVALID, "%s: no material %d (the scene has %zu)", fn,
                      o->material, s->nmaterials);
    rc = gg_scene_add_object(s, o);
    if (rc == -GG_ERROR_INVALID)
        return refuse(s, rc, "%s: a coordinate or size over %g in magnitude", fn, GG_COORD_MAX);
    if (rc == -GG_ERROR_LIMIT)
        return refuse(s, rc, "%s: the scene holds %zu objects, the most it can", fn, s->nobjects);
    if (rc < 0) return refuse(s, rc, "%s: out of memory adding the object", fn);
    return done(s, rc);
}

static int not_finite(ggScene *s, const char *fn, const char *what, ggVec3 v)
{
    return refuse(s, -GG_ERROR_INVALID, "%s: %s must be finite, got %g %g %g", fn, what, v.x, v.y,
                  v.z);
}

GG_API int ggSceneAddSphere(ggScene *s, int material, ggVec3 c, double r)
{
    gg_object o = object_init(GG_SHAPE_SPHERE, material);
    if (!s) return -GG_ERROR_INVALID;
    if (!v3finite(c)) return not_finite(s, "ggSceneAddSphere", "the centre", c);
    if (!isfinite(r) || !(r > 0))
        return refuse(s, -GG_ERROR_INVALID, "ggSceneAddSphere: the radius must be > 0, got %g", r);
    o.a = c;
    o.ra = r;
    return add_shape(s, "ggSceneAddSphere", &o);
}

static int add_vertex_object(ggScene *s, const char *fn, int kind, int material, const ggVec3 *v,
                             const ggVec3 *n, int count)
{
    gg_object o = object_init(kind, material);
    int i, rc;
    char what[48];
    if (!s) return -GG_ERROR_INVALID;
    if (!v) return refuse(s, -GG_ERROR_INVALID, "%s: NULL vertices", fn);
    if (count < 3)
        return refuse(s, -GG_ERROR_INVALID, "%s: a polygon needs 3 vertices or more, got %d", fn,
                      count);
    for (i = 0; i < count; i++) {
        snprintf(what, sizeof what, "vertex %d", i);
        if (!v3finite(v[i])) return not_finite(s, fn, what, v[i]);
        snprintf(what, sizeof what, "normal %d", i);
        if (n && !v3finite(n[i])) return not_finite(s, fn, what, n[i]);
    }
    if (material < 0 || (size_t)material >= s->nmaterials)
        return add_shape(s, fn, &o); /* which refuses it, naming the material */
    if ((rc = gg_scene_push_vertices(s, v, n, count, &o.vfirst)) < 0)
        return refuse(s, rc, "%s: out of memory adding the vertices", fn);
    o.nverts = count;
    o.has_normals = n != NULL;
    rc = add_shape(s, fn, &o);
    if (rc < 0) s->nverts = o.vfirst;
    return rc;
}

GG_API int ggSceneAddPolygon(ggScene *s, int material, const ggVec3 *v, int n)
{
    return add_vertex_object(s, "ggSceneAddPolygon", n == 3 ? GG_SHAPE_TRIANGLE : GG_SHAPE_POLYGON,
                             material, v, NULL, n);
}

GG_API int ggSceneAddTriangle(ggScene *s, int material, const ggVec3 v[3], const ggVec3 *normals)
{
    return add_vertex_object(s, "ggSceneAddTriangle", GG_SHAPE_TRIANGLE, material, v, normals, 3);
}

GG_API int ggSceneAddCone(ggScene *s, int material, ggVec3 base, double rb, ggVec3 apex,
                          double ra)
{
    gg_object o = object_init(GG_SHAPE_CONE, material);
    if (!s) return -GG_ERROR_INVALID;
    if (!v3finite(base)) return not_finite(s, "ggSceneAddCone", "the base", base);
    if (!v3finite(apex)) return not_finite(s, "ggSceneAddCone", "the apex", apex);
    if (!isfinite(rb) || !isfinite(ra) || rb < 0 || ra < 0 || (rb == 0 && ra == 0))
        return refuse(s, -GG_ERROR_INVALID,
                      "ggSceneAddCone: the radii must be finite and >= 0, not both 0, got %g "
                      "and %g",
                      rb, ra);
    if (v3len(v3sub(apex, base)) == 0)
        return refuse(s, -GG_ERROR_INVALID, "ggSceneAddCone: the base and the apex are one point");
    o.a = base, o.b = apex, o.ra = rb, o.rb = ra;
    return add_shape(s, "ggSceneAddCone", &o);
}

GG_API int ggSceneAddRect(ggScene *s, int material, ggVec3 corner, ggVec3 e1, ggVec3 e2)
{
    gg_object o = object_init(GG_SHAPE_RECT, material);
    if (!s) return -GG_ERROR_INVALID;
    if (!v3finite(corner)) return not_finite(s, "ggSceneAddRect", "the corner", corner);
    if (!v3finite(e1)) return not_finite(s, "ggSceneAddRect", "e1", e1);
    if (!v3finite(e2)) return not_finite(s, "ggSceneAddRect", "e2", e2);
    if (v3maxabs(v3cross(e1, e2)) == 0)
        return refuse(s, -GG_ERROR_INVALID,
                      "ggSceneAddRect: e1 and e2 are parallel (or one is zero): no area");
    o.a = corner, o.b = e1, o.c = e2;
    return add_shape(s, "ggSceneAddRect", &o);
}

GG_API int ggSceneAddImplicit(ggScene *s, int material, ggImplicit *imp)
{
    gg_object o = object_init(GG_SHAPE_IMPLICIT, material);
    int rc;
    if (!s || !imp) {
        ggImplicitFree(imp);
        return s ? refuse(s, -GG_ERROR_INVALID, "ggSceneAddImplicit: NULL implicit surface")
                 : -GG_ERROR_INVALID;
    }
    o.imp = imp;
    rc = add_shape(s, "ggSceneAddImplicit", &o);
    if (rc < 0) ggImplicitFree(imp);
    return rc;
}

GG_API int ggSceneObjectCount(const ggScene *s)
{
    return s ? (int)s->nobjects : 0;
}
GG_API int ggSceneLightCount(const ggScene *s)
{
    return s ? (int)s->nlights : 0;
}
GG_API int ggSceneGetLight(const ggScene *s, int i, ggVec3 *pos, ggColor *color)
{
    if (!s || i < 0 || (size_t)i >= s->nlights) return GG_ERROR_INVALID;
    if (pos) *pos = s->lights[i].pos;
    if (color) *color = s->lights[i].color;
    return GG_OK;
}
GG_API int ggSceneMaterialCount(const ggScene *s)
{
    return s ? (int)s->nmaterials : 0;
}
GG_API ggMaterial ggSceneMaterial(const ggScene *s, int i)
{
    return s && i >= 0 && (size_t)i < s->nmaterials ? s->materials[i] : ggMaterialDefault();
}
GG_API int ggSceneObjectKind(const ggScene *s, int i)
{
    return s && i >= 0 && (size_t)i < s->nobjects ? s->objects[i].kind : -1;
}
GG_API int ggSceneObjectMaterial(const ggScene *s, int i)
{
    return s && i >= 0 && (size_t)i < s->nobjects ? s->objects[i].material : -1;
}
GG_API int ggSceneObjectLine(const ggScene *s, int i)
{
    return s && i >= 0 && (size_t)i < s->nobjects ? s->objects[i].line : 0;
}
GG_API const char *ggSceneFileName(const ggScene *s)
{
    return s && s->filename ? s->filename : "";
}

/* Input i of s, in ggSceneInputFile's order, or NULL past the end. */
static const char *input_file(const ggScene *s, size_t i)
{
    size_t k, l;
    if (s->filename) {
        if (i == 0) return s->filename;
        i--;
    }
    for (k = 0; k < s->nmeshes; k++)
        if (s->meshes[k].has_file && !s->meshes[k].repeat && i-- == 0) return s->meshes[k].name;
    for (k = 0; k < s->nmeshes; k++)
        for (l = 0; l < s->meshes[k].nlibs; l++)
            if (i-- == 0) return s->meshes[k].libs[l];
    return i < s->nimages ? s->images[i].path : NULL;
}

GG_API int ggSceneInputCount(const ggScene *s)
{
    size_t n = 0;
    if (!s) return 0;
    while (input_file(s, n)) n++;
    return n > INT_MAX ? INT_MAX : (int)n;
}

GG_API const char *ggSceneInputFile(const ggScene *s, int index)
{
    return s && index >= 0 ? input_file(s, (size_t)index) : NULL;
}

/* ---- prepare ---- */

/* Index of refraction at wavelength lambda (nm) from n_d and the Abbe
   number by Cauchy's two-term law n = A + B / lambda^2 fitted so that
   n(587.6) = n_d and n(486.1) - n(656.3) = (n_d - 1) / V_d. */
static double cauchy(double nd, double abbe, double lambda)
{
    const double lf = 486.1, lc = 656.3, ld = 587.6;
    double b, a;
    if (abbe <= 0) return nd;
    b = (nd - 1) / abbe / (1 / (lf * lf) - 1 / (lc * lc));
    a = nd - b / (ld * ld);
    return a + b / (lambda * lambda);
}

static void resolve_materials(ggScene *s)
{
    size_t i;
    for (i = 0; i < s->nmaterials; i++) {
        const ggMaterial *m = &s->materials[i];
        gg_mat_fast *f = &s->mfast[i];
        double unit = m->unit_m > 0 ? m->unit_m : 1;
        f->kd_color = cscale(m->color, m->kd);
        f->n_r = cauchy(m->ior, m->abbe, GG_LAMBDA_R);
        f->n_g = cauchy(m->ior, m->abbe, GG_LAMBDA_G);
        f->n_b = cauchy(m->ior, m->abbe, GG_LAMBDA_B);
        /* alpha = 4 pi k / lambda per metre, times metres per scene unit. */
        f->alpha = rgb(4 * GG_PI * m->extinction.r / (GG_LAMBDA_R * 1e-9) * unit,
                       4 * GG_PI * m->extinction.g / (GG_LAMBDA_G * 1e-9) * unit,
                       4 * GG_PI * m->extinction.b / (GG_LAMBDA_B * 1e-9) * unit);
        f->flags = 0;
        if (m->ks > 0 || m->fresnel == GG_FRESNEL_CONDUCTOR) f->flags |= GG_MF_REFLECT;
        if (m->kt > 0) f->flags |= GG_MF_TRANSMIT;
        /* Shine 100000 is the SPD's "no highlight"; below 1e4 a highlight
           is visible at 8-bit precision only near its centre anyway. */
        if (m->ks > 0 && m->shine < 10000) f->flags |= GG_MF_PHONG;
        if (m->kt > 0 && !cis0(m->extinction)) f->flags |= GG_MF_ABSORB;
        if (m->kt > 0 && m->abbe > 0) f->flags |= GG_MF_DISPERSE;
        if (m->texture >= 0) f->flags |= GG_MF_TEXTURE;
        if (!cis0(m->ke)) f->flags |= GG_MF_EMIT;
    }
}

/* The primitives and triangles add_prims will add (at most). */
static void count_prims(const ggScene *s, size_t *nprim, size_t *ntri)
{
    size_t i;
    *nprim = *ntri = 0;
    for (i = 0; i < s->nobjects; i++) {
        const gg_object *o = &s->objects[i];
        if (o->kind == GG_SHAPE_MESH)
            *nprim += o->ntri;
        else if (o->kind == GG_SHAPE_TRIANGLE && o->nverts > 3)
            *nprim += (size_t)o->nverts - 2, *ntri += (size_t)o->nverts - 2;
        else {
            *nprim += 1;
            if ((o->kind == GG_SHAPE_TRIANGLE || o->kind == GG_SHAPE_POLYGON) && o->nverts == 3)
                *ntri += 1;
        }
    }
}

static int add_prims(ggScene *s, size_t i)
{
    const gg_object *o = &s->objects[i];
    int32_t id = (int32_t)i;
    int p = -1, k;
    switch (o->kind) {
    case GG_SHAPE_SPHERE: p = gg_geom_add_sphere(s->geom, o->a, o->ra, id); break;
    case GG_SHAPE_CONE: p = gg_geom_add_cone(s->geom, o->a, o->ra, o->b, o->rb, id); break;
    case GG_SHAPE_RECT: p = gg_geom_add_rect(s->geom, o->a, o->b, o->c, id); break;
    case GG_SHAPE_IMPLICIT: p = gg_geom_add_implicit(s->geom, o->imp, id); break;
    case GG_SHAPE_POLYGON: p = gg_geom_add_polygon(s->geom, s->verts + o->vfirst, o->nverts, id); break;
    case GG_SHAPE_MESH: {
        const gg_mesh *m = &s->meshes[o->mesh];
        size_t t;
        p = gg_geom_add_mesh(s->geom, m->pos, m->nrm, m->uv, m->idx + 3 * o->tri_first, o->ntri,
                             id);
        if (p < 0) return p == GG_GEOM_DEGENERATE ? 0 : p;
        if (s->materials[o->material].kt > 0)
            for (t = 0; t < o->ntri; t++) gg_geom_set_flags(s->geom, p + (int)t, GG_PRIM_TRANSPARENT);
        return 0;
    }
    case GG_SHAPE_TRIANGLE:
        if (o->nverts == 3) {
            p = gg_geom_add_triangle(s->geom, s->verts + o->vfirst,
                                     o->has_normals ? s->norms + o->vfirst : NULL, id);
            break;
        }
        /* A pp polygon of more than 3 vertices: a fan of smooth triangles
           (NFF pp polygons are convex in practice). */
        for (k = 1; k + 1 < o->nverts; k++) {
            ggVec3 v[3], n[3];
            v[0] = s->verts[o->vfirst], v[1] = s->verts[o->vfirst + k],
            v[2] = s->verts[o->vfirst + k + 1];
            if (o->has_normals)
                n[0] = s->norms[o->vfirst], n[1] = s->norms[o->vfirst + k],
                n[2] = s->norms[o->vfirst + k + 1];
            p = gg_geom_add_triangle(s->geom, v, o->has_normals ? n : NULL, id);
            if (p >= 0 && s->materials[o->material].kt > 0)
                gg_geom_set_flags(s->geom, p, GG_PRIM_TRANSPARENT);
            if (p < 0 && p != GG_GEOM_DEGENERATE) return p;
        }
        return 0;
    }
    if (p >= 0 && s->materials[o->material].kt > 0)
        gg_geom_set_flags(s->geom, p, GG_PRIM_TRANSPARENT);
    /* A degenerate shape (a zero-area polygon) simply cannot be hit, which
       is what the user's data says; running out of memory or into the
       element limit is an error (the object would silently vanish). */
    return p < 0 && p != GG_GEOM_DEGENERATE ? p : 0;
}

/* The largest side of the box around the prepared geometry and the
   camera's eye; without objects nothing can be too small: infinite. */
static double scene_size(const ggScene *s)
{
    ggVec3 lo, hi, e = s->camera.from;
    if (!gg_geom_prim_count(s->geom)) return HUGE_VAL;
    gg_geom_bounds(s->geom, &lo, &hi);
    lo = v3(fmin(lo.x, e.x), fmin(lo.y, e.y), fmin(lo.z, e.z));
    hi = v3(fmax(hi.x, e.x), fmax(hi.y, e.y), fmax(hi.z, e.z));
    return fmax(hi.x - lo.x, fmax(hi.y - lo.y, hi.z - lo.z));
}

GG_API void ggSceneSetProgress(ggScene *s, ggProgressFn fn, void *ud)
{
    if (!s) return;
    s->progress = fn, s->progress_ud = ud;
}

/* Preparing's thousandths (ggSceneSetProgress): gathering the
   primitives up to GATHERED, the BVH the rest. */
#define PREP_OF       1000
#define PREP_GATHERED 300

static int prepare_cancelled(ggScene *s, ggError *err)
{
    unprepare(s);
    return gg_error_set(err, GG_ERROR_CANCELLED, "preparing the scene: cancelled");
}

/* The objects' primitives into s->geom, with progress every 2^16 of
   them; 1 when out of memory, GG_GEOM_LIMIT, or 2 when cancelled. */
static int gather(ggScene *s, gg_progress *pg, size_t np, size_t *bad)
{
    size_t i, told = 0;
    for (i = 0; i < s->nobjects; i++) {
        const size_t first = gg_geom_prim_count(s->geom);
        int rc = add_prims(s, i);
        /* shading reads the material from the primitive (geom.h) */
        gg_geom_set_tag(s->geom, first, gg_geom_prim_count(s->geom) - first,
                        s->objects[i].material);
        if (rc == GG_GEOM_LIMIT) return *bad = i, GG_GEOM_LIMIT;
        if (rc < 0) return 1;
        if (gg_geom_prim_count(s->geom) - told >= ((size_t)1 << 16) || i + 1 == s->nobjects) {
            told = gg_geom_prim_count(s->geom);
            if (gg_progress_to(pg, told, np)) return 2;
        }
    }
    return 0;
}

GG_API int ggScenePrepare(ggScene *s, ggError *err)
{
    size_t i, bad = 0;
    double size;
    int rc;
    double t0 = gg_time_now();
    gg_progress pg, pb;
    if (!s) return gg_error_set(err, GG_ERROR_INVALID, "ggScenePrepare: NULL scene");
    if (s->prepared) return GG_OK;
    unprepare(s);
    gg_progress_part(&pg, s->progress, s->progress_ud, 0, PREP_GATHERED, PREP_OF);
    gg_progress_part(&pb, s->progress, s->progress_ud, PREP_GATHERED, PREP_OF, PREP_OF);
    if (gg_progress_to(&pg, 0, 1)) return prepare_cancelled(s, err);
    s->geom = gg_geom_create(s->alloc);
    s->mfast = gg_mem_calloc(s->alloc, s->nmaterials ? s->nmaterials : 1, sizeof *s->mfast);
    s->light_colors = gg_mem_calloc(s->alloc, s->nlights ? s->nlights : 1, sizeof(ggColor));
    if (!s->geom || !s->mfast || !s->light_colors) goto nomem;
    {
        size_t np, nt;
        count_prims(s, &np, &nt);
        if (gg_geom_reserve(s->geom, np, nt)) goto nomem;
        rc = gather(s, &pg, np, &bad);
    }
    if (rc == GG_GEOM_LIMIT) {
        unprepare(s);
        return gg_error_set(err, GG_ERROR_LIMIT,
                            "preparing the scene: object %lu exceeds the BVH's primitive limit",
                            (unsigned long)bad);
    }
    if (rc == 2) return prepare_cancelled(s, err);
    if (rc) goto nomem;
    gg_geom_set_progress(s->geom, s->progress ? &pb : NULL);
    rc = gg_geom_build(s->geom, err);
    if (rc == GG_ERROR_CANCELLED) return prepare_cancelled(s, err);
    if (rc != GG_OK) {
        unprepare(s);
        return rc;
    }
    size = scene_size(s);
    if (size < GG_SCENE_SIZE_MIN) {
        unprepare(s);
        return gg_error_set(err, GG_ERROR_INVALID,
                            "preparing the scene: its objects and the camera's eye span only %g, "
                            "under %g (GG_SCENE_SIZE_MIN), where intersection tests underflow; "
                            "scale it up",
                            size, GG_SCENE_SIZE_MIN);
    }
    resolve_materials(s);
    for (i = 0; i < s->nlights; i++) {
        ggColor c = s->lights[i].color;
        if (c.r < 0) {
            double w = 1 / sqrt((double)s->nlights);
            c = rgb(w, w, w);
        }
        s->light_colors[i] = c;
    }
    if (gg_effects_compute(s) != GG_OK) goto nomem;
    if (gg_progress_to(&pb, 1, 1)) return prepare_cancelled(s, err);
    s->prepared = true;
    s->prepare_seconds = gg_time_now() - t0;
    return GG_OK;
nomem:
    unprepare(s);
    return gg_error_set(err, GG_ERROR_NOMEM, "preparing the scene: out of memory");
}

ggColor gg_scene_surface_color(const ggScene *s, int material, double u, double v, int filter)
{
    const ggMaterial *m = &s->materials[material];
    const gg_texture *t;
    ggColor c;
    if (m->texture < 0) return m->color;
    t = &s->textures[m->texture];
    if (!t->img)
        c = ggTextureChecker(u, v, t->checker_n, t->checker_a, t->checker_b);
    else if (filter == GG_ACC_TEXTURE_NEAREST || (filter == 0 && t->nearest))
        c = ggTextureNearest(t->img, u, v, t->wrap);
    else
        c = ggTextureBilinear(t->img, u, v, t->wrap);
    return cmul(c, m->color);
}

static void fill_hit(const ggScene *s, const gg_rayq *q, const gg_hit *h, ggHit *out)
{
    gg_surf sf;
    int32_t obj = gg_geom_prim_object(s->geom, h->prim);
    gg_geom_surface(s->geom, q, h, &sf, GG_SURF_UV);
    out->t = h->t;
    out->p = sf.p;
    out->ng = sf.ng;
    out->ns = sf.ns;
    out->u = sf.u;
    out->v = sf.v;
    out->front = v3dot(q->d, sf.ng) < 0;
    out->object = obj;
    out->kind = s->objects[obj].kind;
    out->material = s->objects[obj].material;
    out->triangle = gg_scene_hit_triangle(s, &s->objects[obj], h->prim);
}

/* Both queries take d of any finite size (base.h): one far from 1 is
   scaled by a power of two first, and t with it (v3tame). */
GG_API bool ggSceneIntersect(const ggScene *s, ggRay ray, double tmin, double tmax, ggHit *hit)
{
    gg_rayq q;
    gg_hit h;
    int k;
    if (!s || !s->prepared) return false;
    ray.d = v3tame(ray.d, &k);
    q = gg_rayq_make(ray.o, ray.d, ldexp(tmin, -k), ldexp(tmax, -k), NULL);
    if (!gg_geom_intersect(s->geom, &q, &h)) return false;
    if (hit) fill_hit(s, &q, &h, hit), hit->t = ldexp(hit->t, k);
    return true;
}

GG_API bool ggSceneOccluded(const ggScene *s, ggRay ray, double tmin, double tmax)
{
    gg_rayq q;
    uint32_t cache = 0;
    int k;
    if (!s || !s->prepared) return false;
    ray.d = v3tame(ray.d, &k);
    q = gg_rayq_make(ray.o, ray.d, ldexp(tmin, -k), ldexp(tmax, -k), NULL);
    return gg_geom_occluded(s->geom, &q, &cache, NULL) != 0;
}

GG_API int ggSceneGetInfo(const ggScene *s, ggSceneInfo *info)
{
    gg_bvh_stats bs;
    size_t i;
    if (!s || !info) return GG_ERROR_INVALID; /* rule 1: nothing written */
    memset(info, 0, sizeof *info);
    if (!s->prepared) return GG_ERROR_INVALID;
    for (i = 0; i < s->nobjects; i++) info->objects_by_kind[s->objects[i].kind]++;
    gg_geom_bvh_stats(s->geom, &bs);
    info->primitives = gg_geom_prim_count(s->geom);
    info->bvh_nodes = bs.nodes, info->bvh_leaves = bs.leaves, info->bvh_depth = bs.max_depth;
    info->bvh_blocks = bs.blocks;
    info->geometry_bytes = bs.bytes;
    info->bvh_seconds = bs.build_seconds;
    info->prepare_seconds = s->prepare_seconds;
    gg_geom_bounds(s->geom, &info->lo, &info->hi);
    return GG_OK;
}

GG_API const char *ggSceneTraversal(const ggScene *s)
{
    gg_bvh_stats bs;
    if (!s || !s->prepared) return NULL;
    gg_geom_bvh_stats(s->geom, &bs);
    return bs.traversal;
}

GG_API int ggSceneObjectTriangulate(const ggScene *s, int i, int resolution, size_t max_triangles,
                                    ggTriangulation **out)
{
    if (!s || !out) return GG_ERROR_INVALID;
    *out = NULL;
    if (i < 0 || (size_t)i >= s->nobjects) return GG_ERROR_INVALID;
    if (s->objects[i].kind != GG_SHAPE_IMPLICIT) return GG_ERROR_UNSUPPORTED;
    return ggImplicitTriangulate(s->objects[i].imp, resolution, max_triangles, s->alloc, out);
}

GG_API int ggSceneObjectShape(const ggScene *s, int i, ggShapeDesc *d)
{
    const gg_object *o;
    if (!s || !d) return GG_ERROR_INVALID; /* rule 1: nothing written */
    memset(d, 0, sizeof *d);
    if (i < 0 || (size_t)i >= s->nobjects) return GG_ERROR_INVALID;
    o = &s->objects[i];
    d->kind = o->kind, d->material = o->material, d->line = o->line;
    switch (o->kind) {
    case GG_SHAPE_SPHERE:
        d->base = o->a, d->radius = o->ra;
        d->e1 = v3(1, 0, 0), d->e2 = v3(0, 1, 0); /* the (u, v) frame (ggSceneObjectUV) */
        break;
    case GG_SHAPE_CONE: {
        ggVec3 e[3];
        double h;
        d->base = o->a, d->apex = o->b, d->radius = o->ra, d->radius2 = o->rb;
        if (!gg_uv_cone_frame(o->a, o->ra, o->b, o->rb, e, &h)) d->e1 = e[0], d->e2 = e[1];
        break;
    }
    case GG_SHAPE_RECT: d->base = o->a, d->e1 = o->b, d->e2 = o->c; break;
    case GG_SHAPE_IMPLICIT: gg_implicit_bounds(o->imp, &d->base, &d->apex); break;
    case GG_SHAPE_MESH: {
        const gg_mesh *m = &s->meshes[o->mesh];
        size_t t;
        d->base = v3(INFINITY, INFINITY, INFINITY), d->apex = v3(-INFINITY, -INFINITY, -INFINITY);
        for (t = 3 * o->tri_first; t < 3 * (o->tri_first + o->ntri); t++) {
            d->base = v3min(d->base, m->pos[m->idx[t]]);
            d->apex = v3max(d->apex, m->pos[m->idx[t]]);
        }
        break;
    }
    default:
        d->nverts = o->nverts;
        d->verts = s->verts + o->vfirst;
        d->normals = o->has_normals ? s->norms + o->vfirst : NULL;
    }
    return GG_OK;
}
