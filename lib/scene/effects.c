/* SPDX-License-Identifier: MIT */
/*
** effects.c -- which effects a scene calls for, and why.
**
** The renderer specialises its shading path to this set (shade.c), so an
** opaque diffuse scene never pays for refraction. Each effect keeps the
** first reason found, in the user's terms: a material or object and the
** scene-file line that defined it.
*/
#include "scene.h"

#include <stdio.h>
#include <string.h>

static const char *const effect_names[GG_EFFECT_COUNT] = {
    "shadows",  "reflection", "refraction", "fresnel",  "absorption",    "dispersion",
    "colored-shadows", "textures", "implicit", "supersampling", "phong", "emission"};

GG_API const char *ggEffectName(unsigned effect)
{
    int i;
    for (i = 0; i < GG_EFFECT_COUNT; i++)
        if (effect == (1u << i)) return effect_names[i];
    return "?";
}

static int bit_index(unsigned effect)
{
    int i;
    for (i = 0; i < GG_EFFECT_COUNT; i++)
        if (effect == (1u << i)) return i;
    return -1;
}

GG_API unsigned ggSceneEffects(const ggScene *s)
{
    return s && s->prepared ? s->effects : 0;
}

GG_API const char *ggSceneEffectReason(const ggScene *s, unsigned effect)
{
    int i = bit_index(effect);
    if (!s || !s->prepared || i < 0 || !(s->effects & effect)) return NULL;
    return s->reasons[i];
}

void gg_effects_clear(ggScene *s)
{
    int i;
    for (i = 0; i < GG_EFFECT_COUNT; i++) {
        gg_mem_free(s->alloc, s->reasons[i]);
        s->reasons[i] = NULL;
    }
    s->effects = 0;
}

/* Record effect with a reason unless it already has one. */
static int need(ggScene *s, unsigned effect, const char *why)
{
    int i = bit_index(effect);
    if (s->effects & effect) return 0;
    s->reasons[i] = gg_mem_strdup(s->alloc, why);
    if (!s->reasons[i]) return -1;
    s->effects |= effect;
    return 0;
}

static void where(const ggScene *s, int line, char *buf, size_t n)
{
    if (line > 0)
        snprintf(buf, n, " (%s:%d)", s->filename ? s->filename : "scene", line);
    else
        buf[0] = '\0';
}

int gg_effects_compute(ggScene *s)
{
    char why[256], at[160];
    size_t i;
    int used_any = 0;
    unsigned char *used = gg_mem_calloc(s->alloc, s->nmaterials ? s->nmaterials : 1, 1);
    if (!used) return GG_ERROR_NOMEM;
    gg_effects_clear(s);
    /* Only materials that some object uses can call for an effect. */
    for (i = 0; i < s->nobjects; i++) {
        const gg_object *o = &s->objects[i];
        used[o->material] = 1;
        used_any = 1;
        if (o->kind == GG_SHAPE_IMPLICIT) {
            where(s, o->line, at, sizeof at);
            snprintf(why, sizeof why, "object %zu is an implicit surface%s", i, at);
            if (need(s, GG_EFFECT_IMPLICIT, why)) goto nomem;
        }
    }
    if (s->nlights > 0 && used_any) {
        where(s, s->lights[0].line, at, sizeof at);
        snprintf(why, sizeof why, "%zu point light%s, first%s", s->nlights,
                 s->nlights == 1 ? "" : "s", at);
        if (need(s, GG_EFFECT_SHADOWS, why)) goto nomem;
    }
    for (i = 0; i < s->nmaterials; i++) {
        const ggMaterial *m = &s->materials[i];
        unsigned f = s->mfast[i].flags;
        if (!used[i]) continue;
        where(s, m->line, at, sizeof at);
#define NEED(effect, ...)                                                                       \
    do {                                                                                        \
        snprintf(why, sizeof why, __VA_ARGS__);                                                 \
        if (need(s, effect, why)) goto nomem;                                                   \
    } while (0)
        if (f & GG_MF_REFLECT)
            NEED(GG_EFFECT_REFLECTION, "material %zu%s has ks %g", i, at, m->ks);
        if (f & GG_MF_TRANSMIT) {
            NEED(GG_EFFECT_REFRACTION, "material %zu%s has kt %g", i, at, m->kt);
            if (s->nlights > 0)
                NEED(GG_EFFECT_COLORED_SHADOWS,
                     "material %zu%s is transparent (kt %g): its shadows let light through", i,
                     at, m->kt);
        }
        if (m->fresnel != GG_FRESNEL_NONE && (f & (GG_MF_REFLECT | GG_MF_TRANSMIT)))
            NEED(GG_EFFECT_FRESNEL, "material %zu%s uses %s Fresnel", i, at,
                 m->fresnel == GG_FRESNEL_SCHLICK     ? "Schlick"
                 : m->fresnel == GG_FRESNEL_CONDUCTOR ? "conductor"
                                                      : "exact");
        if (f & GG_MF_ABSORB)
            NEED(GG_EFFECT_ABSORPTION, "material %zu%s absorbs (k = %g %g %g)", i, at,
                 m->extinction.r, m->extinction.g, m->extinction.b);
        if (f & GG_MF_DISPERSE)
            NEED(GG_EFFECT_DISPERSION, "material %zu%s disperses (Abbe number %g)", i, at,
                 m->abbe);
        if (f & GG_MF_TEXTURE)
            NEED(GG_EFFECT_TEXTURES, "material %zu%s has texture %d", i, at, m->texture);
        if ((f & GG_MF_PHONG) && s->nlights > 0)
            NEED(GG_EFFECT_PHONG, "material %zu%s has a highlight (ks %g, shine %g)", i, at,
                 m->ks, m->shine);
        if (f & GG_MF_EMIT)
            NEED(GG_EFFECT_EMISSION, "material %zu%s emits (%g %g %g)", i, at, m->ke.r, m->ke.g,
                 m->ke.b);
#undef NEED
    }
    if (s->samples > 1) {
        snprintf(why, sizeof why, "the scene asks for %d samples per pixel", s->samples);
        if (need(s, GG_EFFECT_SUPERSAMPLING, why)) goto nomem;
    }
    gg_mem_free(s->alloc, used);
    return GG_OK;
nomem:
    gg_mem_free(s->alloc, used);
    gg_effects_clear(s);
    return GG_ERROR_NOMEM;
}
