/* SPDX-License-Identifier: MIT */
/*
** mtl.c -- Wavefront MTL material libraries, mapped to ggMaterial as
** docs/scene-format.md ("Meshes: materials") describes: Kd is the colour,
** the illumination model decides which of Ks (mirror and highlight) and
** d/Tr (transmission) ggrt's shading model gets, Ni the index, Ke the
** emission, map_Kd a texture. What ggrt's model has no place for (Ka, Tf
** outside the refraction models, the other maps) is read and not used.
*/
#include "mesh_int.h"

#include "vec.h"

#include <stdio.h>
#include <string.h>

void gg_mtl_free(const ggAllocator *a, gg_mtl_lib *lib)
{
    size_t i;
    for (i = 0; i < lib->n; i++) {
        gg_mem_free(a, lib->e[i].name);
        gg_mem_free(a, lib->e[i].map_kd);
        gg_mem_free(a, lib->e[i].where);
    }
    gg_mem_free(a, lib->e);
    memset(lib, 0, sizeof *lib);
}

/* What one newmtl block said, before it becomes a ggMaterial. */
typedef struct raw {
    ggColor kd, ks, ke, tf;
    double ns, ni, d;
    int illum;
    bool has_ks, has_tf, has_illum;
} raw;

static void raw_init(raw *r)
{
    memset(r, 0, sizeof *r);
    r->kd = rgb(0.8, 0.8, 0.8); /* the MTL default is 0.8 grey */
    r->ns = 0, r->ni = 1, r->d = 1;
}

static double cmax(ggColor c)
{
    return c.r > c.g ? (c.r > c.b ? c.r : c.b) : (c.g > c.b ? c.g : c.b);
}

/* The mapping (docs/scene-format.md): illum 0-2 matte (ggrt's ks is the
   mirror weight too, so illum 2's highlight-without-mirror has no
   equivalent and is left out), 3 and 8 mirror, 5 Fresnel mirror, 4, 6, 7
   and 9 glass (refraction with Ni; 7 with Fresnel). A dissolve d < 1
   outside the glass models is see-through without bending (index 1). */
static ggMaterial to_material(const raw *r)
{
    ggMaterial m = ggMaterialDefault();
    int il = r->has_illum ? r->illum : (r->has_ks && cmax(r->ks) > 0 ? 2 : 1);
    bool mirror = il == 3 || il == 4 || il == 5 || il == 6 || il == 7 || il == 8 || il == 9;
    bool glass = il == 4 || il == 6 || il == 7 || il == 9;
    double t = 1 - r->d;
    if ((il == 6 || il == 7) && r->has_tf && t == 0) t = cmax(r->tf);
    if (t < 0) t = 0;
    if (t > 1) t = 1;
    m.color = r->kd;
    m.kd = 1 - t;
    m.ks = mirror ? cmax(r->ks) : 0;
    m.shine = m.ks > 0 && r->ns > 0 ? r->ns : 100000;
    m.kt = t;
    m.ior = glass && r->ni > 0 ? r->ni : 1;
    m.fresnel = (il == 5 || il == 7) ? GG_FRESNEL_EXACT : GG_FRESNEL_NONE;
    m.ke = r->ke;
    return m;
}

static int color(gg_lc *c, ggColor *out, const char *kw)
{
    double v[3];
    int rc, i, n = 3;
    const char *w, *at[3];
    size_t wn;
    gg_lc_blank(c);
    at[0] = c->p;
    /* Only the named forms are unsupported: anything else that is no
       number (nan, inf, 0x1) is "expected a colour, got ..." */
    wn = gg_lc_word(c, &w);
    if ((wn == 8 && !memcmp(w, "spectral", 8)) || (wn == 3 && !memcmp(w, "xyz", 3)))
        return gg_lc_fail(c, at[0], GG_ERROR_UNSUPPORTED, "%s: only r g b colours are supported",
                          kw);
    c->p = at[0];
    if ((rc = gg_lc_number(c, &v[0], "a colour")) != GG_OK) return rc;
    gg_lc_blank(c);
    /* "Kd r" alone means grey r */
    if (gg_lc_eol(c)) v[1] = v[2] = v[0], n = 1;
    for (i = 1; i < n; i++) {
        gg_lc_blank(c), at[i] = c->p;
        if ((rc = gg_lc_number(c, &v[i], "a colour")) != GG_OK) return rc;
    }
    /* at the component that is negative */
    for (i = 0; i < n; i++)
        if (v[i] < 0) return gg_lc_fail(c, at[i], GG_ERROR_PARSE, "%s must not be negative", kw);
    *out = rgb(v[0], v[1], v[2]);
    return gg_lc_end(c);
}

static int scalar(gg_lc *c, double *out, double lo, double hi, const char *kw)
{
    const char *at;
    int rc;
    gg_lc_blank(c);
    at = c->p;
    if ((rc = gg_lc_number(c, out, "a number")) != GG_OK) return rc;
    if (*out < lo || *out > hi)
        return gg_lc_fail(c, at, GG_ERROR_PARSE, "%s must be in [%g, %g], got %g", kw, lo, hi,
                          *out);
    return gg_lc_end(c);
}

/* map_Kd [-option args...] file: the options ggrt uses (-clamp) or skips,
   then the file name (the rest of the line; backslashes become '/'). */
static int map_kd(const ggAllocator *a, gg_lc *c, gg_mtl_entry *e, const char *dir)
{
    static const struct {
        const char *opt;
        int args;
    } opts[] = {
        {"-blendu", 1},  {"-blendv", 1}, {"-bm", 1}, {"-boost", 1}, {"-cc", 1}, {"-clamp", 1},
        {"-imfchan", 1}, {"-mm", 2},     {"-o", 3},  {"-s", 3},     {"-t", 3},  {"-texres", 1},
    };
    const char *w, *f;
    size_t n, i, k, dl = strlen(dir);
    for (;;) {
        const char *save = c->p;
        int args = -1;
        if (!(n = gg_lc_word(c, &w)))
            return gg_lc_fail(c, NULL, GG_ERROR_PARSE, "map_Kd needs a file name");
        for (i = 0; i < sizeof opts / sizeof opts[0]; i++)
            if (strlen(opts[i].opt) == n && !memcmp(w, opts[i].opt, n)) args = opts[i].args;
        if (args < 0) {
            c->p = save;
            break;
        }
        for (k = 0; k < (size_t)args; k++) {
            const char *v;
            size_t vn = gg_lc_word(c, &v);
            if (!vn)
                return gg_lc_fail(c, NULL, GG_ERROR_PARSE, "map_Kd: %.*s needs a value", (int)n, w);
            if (n == 6 && !memcmp(w, "-clamp", 6))
                e->wrap = vn == 2 && !memcmp(v, "on", 2) ? GG_WRAP_CLAMP : GG_WRAP_REPEAT;
        }
    }
    n = gg_lc_rest(c, &f);
    gg_mem_free(a, e->map_kd);
    if (!(e->map_kd = gg_mem_alloc(a, dl + n + 1))) return GG_ERROR_NOMEM;
    if (n && f[0] == '/') dl = 0;
    memcpy(e->map_kd, dir, dl);
    for (i = 0; i < n; i++) e->map_kd[dl + i] = f[i] == '\\' ? '/' : f[i];
    e->map_kd[dl + n] = '\0';
    /* ".\file" written on Windows */
    if (n >= 2 && !memcmp(e->map_kd + dl, "./", 2))
        memmove(e->map_kd + dl, e->map_kd + dl + 2, n - 1);
    return GG_OK;
}

static int newmtl(const ggAllocator *a, gg_lc *c, gg_mtl_lib *lib, gg_mtl_entry **cur)
{
    const char *w;
    size_t n = gg_lc_rest(c, &w);
    char where[300];
    gg_mtl_entry *e;
    if (gg_mem_grow(a, (void **)&lib->e, &lib->cap, lib->n + 1, sizeof *lib->e))
        return GG_ERROR_NOMEM;
    e = &lib->e[lib->n];
    memset(e, 0, sizeof *e);
    e->material = -1, e->wrap = GG_WRAP_REPEAT;
    snprintf(where, sizeof where, "%s:%d", c->name, c->line);
    if (!(e->name = gg_mem_alloc(a, n + 1)) || !(e->where = gg_mem_strdup(a, where))) {
        gg_mem_free(a, e->name);
        return GG_ERROR_NOMEM;
    }
    memcpy(e->name, w, n);
    e->name[n] = '\0';
    lib->n++;
    *cur = e;
    return GG_OK;
}

static bool is(const char *w, size_t n, const char *kw)
{
    return strlen(kw) == n && !memcmp(w, kw, n);
}

/* One statement of the current material. */
static int statement(const ggAllocator *a, gg_lc *c, gg_mtl_lib *lib, gg_mtl_entry *e, raw *r,
                     const char *w, size_t n, const char *dir)
{
    double d;
    int rc;
    if (is(w, n, "Kd")) return color(c, &r->kd, "Kd");
    if (is(w, n, "Ks")) return r->has_ks = true, color(c, &r->ks, "Ks");
    if (is(w, n, "Ke")) return color(c, &r->ke, "Ke");
    if (is(w, n, "Tf")) return r->has_tf = true, color(c, &r->tf, "Tf");
    if (is(w, n, "Ns")) return scalar(c, &r->ns, 0, 1e6, "Ns");
    if (is(w, n, "Ni")) return scalar(c, &r->ni, 0, 100, "Ni");
    if (is(w, n, "d")) {
        const char *save = c->p, *h;
        if (gg_lc_word(c, &h) == 5 && !memcmp(h, "-halo", 5))
            lib->ignored++; /* read as plain d */
        else
            c->p = save;
        return scalar(c, &r->d, 0, 1, "d");
    }
    if (is(w, n, "Tr")) {
        if ((rc = scalar(c, &d, 0, 1, "Tr")) == GG_OK) r->d = 1 - d;
        return rc;
    }
    if (is(w, n, "illum")) {
        const char *at;
        gg_lc_blank(c), at = c->p;
        if ((rc = scalar(c, &d, 0, 10, "illum")) != GG_OK) return rc;
        /* a model is a number: 3.9 is none, not 3 */
        if (d != (int)d)
            return gg_lc_fail(c, at, GG_ERROR_PARSE, "illum must be a whole number, got %g", d);
        r->illum = (int)d, r->has_illum = true;
        return rc;
    }
    if (is(w, n, "map_Kd")) return map_kd(a, c, e, dir);
    lib->ignored++; /* Ka, the other maps, PBR extensions, ... */
    return GG_OK;
}

int gg_mtl_parse(const ggAllocator *a, gg_mtl_lib *lib, const char *text, size_t len,
                 const char *name, const char *dir, ggError *err)
{
    gg_lc c;
    gg_mtl_entry *cur = NULL;
    raw r;
    int rc = GG_OK;
    raw_init(&r);
    gg_lc_init(&c, text, len, name, err);
    if ((rc = gg_lc_check_text(&c)) != GG_OK) return rc;
    while (rc == GG_OK && c.p < c.end) {
        const char *w;
        size_t n = gg_lc_word(&c, &w);
        if (!n) {
            gg_lc_next_line(&c);
            continue;
        }
        if (is(w, n, "newmtl")) {
            if (cur) cur->mat = to_material(&r);
            raw_init(&r);
            rc = newmtl(a, &c, lib, &cur);
        } else if (!cur) {
            lib->ignored++;
        } else {
            rc = statement(a, &c, lib, cur, &r, w, n, dir);
        }
        if (rc == GG_OK) gg_lc_next_line(&c);
    }
    if (cur) cur->mat = to_material(&r);
    if (rc == GG_ERROR_NOMEM) gg_lc_fail(&c, NULL, rc, "out of memory");
    return rc;
}
