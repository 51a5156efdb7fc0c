/* SPDX-License-Identifier: MIT */
/*
** nff.c -- the NFF scene reader: Eric Haines' Neutral File Format exactly
** as the SPD writes it, plus ggrt's extension keywords in the same token
** stream (docs/scene-format.md).
**
** NFF is token based: line breaks carry no meaning, so neither do they
** here; every token remembers its line and column for error messages. A
** failed load leaves the scene as it was (see rollback()).
*/
#include "load.h"
#include "mesh_int.h"
#include "scene.h"

#include "vec.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Hard limits: a scene file may be hostile. */
#define NFF_MAX_POLY_VERTS 1000000
#define NFF_MAX_TOKEN      4096

typedef struct token {
    const char *p; /* start in the text (for a string: after the quote) */
    size_t n;      /* length */
    int line, col;
    int quoted;
} token;

typedef struct parser {
    ggScene *s;
    const char *text, *end, *cur;
    int line, col;
    const char *name, *dir;
    ggError *err;
    const char *keyword; /* the entity being read, for messages */
    token kw_tok;
    ggMaterial mat;      /* the current material state */
    int mat_id;          /* its index, or -1 if it changed since last used */
    bool has_peek;
    token peek;
    token last; /* the last number read, for messages about its value */
    token comp[3]; /* the numbers of the last colour read */
    token mat_tok; /* the keyword that last changed the material */
    gg_progress prog; /* bytes read (ggSceneSetProgress) */
    size_t told;      /* ... when last reported */
} parser;

static int fail(parser *ps, const token *t, int code, const char *fmt, ...) GG_PRINTF(4, 5);
static int fail(parser *ps, const token *t, int code, const char *fmt, ...)
{
    char msg[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return gg_error_set(ps->err, code, "%s:%d:%d: %s", ps->name, t ? t->line : ps->line,
                        t ? t->col : ps->col, msg);
}

/* A line ends at "\n", at "\r\n" (on its '\n') or at a lone "\r" (files
   with CR line endings), for line numbers and comments alike. */
static bool line_end(const char *c, const char *end)
{
    return *c == '\n' || (*c == '\r' && (c + 1 >= end || c[1] != '\n'));
}

/* Next token, or 0 at end of input. Comments run from '#' to the end of
   the line wherever a token could start. */
static int lex(parser *ps, token *t)
{
    const char *c = ps->cur;
    for (;;) {
        while (c < ps->end && (*c == ' ' || *c == '\t' || *c == '\r' || *c == '\n' ||
                               *c == '\f' || *c == '\v')) {
            if (line_end(c, ps->end)) ps->line++, ps->col = 1;
            else ps->col++;
            c++;
        }
        if (c < ps->end && *c == '#') {
            while (c < ps->end && !line_end(c, ps->end)) c++, ps->col++;
            continue;
        }
        break;
    }
    ps->cur = c;
    if (c >= ps->end) return 0;
    t->line = ps->line, t->col = ps->col, t->quoted = 0;
    if (*c == '"') {
        const char *q = c + 1;
        while (q < ps->end && *q != '"' && *q != '\n' && *q != '\r') q++;
        if (q >= ps->end || *q != '"') {
            t->p = c, t->n = 1;
            return -1; /* unterminated string */
        }
        t->p = c + 1, t->n = (size_t)(q - c - 1), t->quoted = 1;
        ps->col += (int)(q + 1 - c);
        ps->cur = q + 1;
        return 1;
    }
    t->p = c;
    while (c < ps->end && !(*c == ' ' || *c == '\t' || *c == '\r' || *c == '\n' || *c == '\f' ||
                            *c == '\v'))
        c++;
    t->n = (size_t)(c - t->p);
    ps->col += (int)t->n;
    ps->cur = c;
    return 1;
}

static int next(parser *ps, token *t)
{
    if (ps->has_peek) {
        *t = ps->peek;
        ps->has_peek = false;
        return 1;
    }
    return lex(ps, t);
}

/* Look at the next token without taking it; 0 at end of input. */
static int peek(parser *ps, token *t)
{
    int r;
    if (!ps->has_peek) {
        r = lex(ps, &ps->peek);
        if (r <= 0) return r;
        ps->has_peek = true;
    }
    *t = ps->peek;
    return 1;
}

static bool tok_is(const token *t, const char *w)
{
    return !t->quoted && t->n == strlen(w) && memcmp(t->p, w, t->n) == 0;
}

/* A token for messages: its first 40 bytes, escaped (gg_text_escape). */
static const char *show(const token *t, char *buf, size_t n)
{
    gg_text_escape(buf, n, t->p, t->n < 40 ? t->n : 40);
    return buf;
}

/* A token that is a decimal number, finite: gg_parse_number (no nan, inf
   or hex), correctly rounded like strtod, whatever the locale. */
static bool tok_number(const token *t, double *d)
{
    const char *end = t->p + t->n;
    if (t->quoted || t->n == 0) return false;
    return gg_parse_number(t->p, end, d) == end;
}

/* Whether a token that is not a number is written as one, [+-]digits[.digits]
   [e[+-]digits] ("1e400": beyond a double's range), for a message that
   says so. */
static bool tok_numeric(const token *t)
{
    const char *p = t->p, *e = t->p + t->n;
    size_t mant = 0;
    if (p < e && (*p == '+' || *p == '-')) p++;
    for (; p < e && *p >= '0' && *p <= '9'; p++) mant++;
    if (p < e && *p == '.')
        for (p++; p < e && *p >= '0' && *p <= '9'; p++) mant++;
    if (!mant) return false;
    if (p < e && (*p == 'e' || *p == 'E')) {
        const char *d;
        p++;
        if (p < e && (*p == '+' || *p == '-')) p++;
        for (d = p; p < e && *p >= '0' && *p <= '9'; p++) {
        }
        if (p == d) return false;
    }
    return p == e;
}

static int number(parser *ps, double *d, const char *what)
{
    token t;
    char b[48];
    int r = next(ps, &t);
    *d = 0; /* defined on every path (gcc -O3 cannot see it otherwise) */
    if (r <= 0)
        return fail(ps, NULL, GG_ERROR_PARSE, "expected %s after '%s', got end of file", what,
                    ps->keyword);
    if (!tok_number(&t, d))
        return fail(ps, &t, GG_ERROR_PARSE, "expected %s after '%s', got '%s'%s", what, ps->keyword,
                    show(&t, b, sizeof b),
                    !t.quoted && tok_numeric(&t) ? " (not a number in a double's range)" : "");
    ps->last = t;
    return GG_OK;
}

static int numbers(parser *ps, double *d, int n)
{
    int i, rc;
    for (i = 0; i < n; i++)
        if ((rc = number(ps, &d[i], "a number")) != GG_OK) return rc;
    return GG_OK;
}

static int vec(parser *ps, ggVec3 *v)
{
    double d[3];
    int rc = numbers(ps, d, 3);
    if (rc == GG_OK) *v = v3(d[0], d[1], d[2]);
    return rc;
}

static int color(parser *ps, ggColor *c)
{
    double d[3];
    int i, rc;
    for (i = 0; i < 3; i++) {
        if ((rc = number(ps, &d[i], "a number")) != GG_OK) return rc;
        ps->comp[i] = ps->last;
    }
    *c = rgb(d[0], d[1], d[2]);
    return GG_OK;
}

/* Physically invalid parameters are errors at the value that set them
   (docs/scene-format.md, "Parameter ranges"). */
static int ranged(parser *ps, const token *t, double d, double hi, const char *what)
{
    char b[48];
    if (d < 0)
        return fail(ps, t, GG_ERROR_PARSE, "%s must not be negative, got %s", what,
                    show(t, b, sizeof b));
    if (d > hi)
        return fail(ps, t, GG_ERROR_PARSE, "%s must be at most %g, got %s", what, hi,
                    show(t, b, sizeof b));
    return GG_OK;
}

static int nonneg_number(parser *ps, double *d, double hi, const char *what)
{
    int rc = number(ps, d, what);
    return rc == GG_OK ? ranged(ps, &ps->last, *d, hi, what) : rc;
}

static int color_upto(parser *ps, ggColor *c, double hi, const char *what)
{
    double ch[3];
    int i, rc = color(ps, c);
    ch[0] = c->r, ch[1] = c->g, ch[2] = c->b;
    for (i = 0; rc == GG_OK && i < 3; i++) rc = ranged(ps, &ps->comp[i], ch[i], hi, what);
    return rc;
}

static int nonneg_color(parser *ps, ggColor *c, const char *what)
{
    return color_upto(ps, c, GG_PARAM_MAX, what);
}

static int integer(parser *ps, long lo, long hi, long *out, const char *what)
{
    double d;
    int rc = number(ps, &d, what);
    if (rc != GG_OK) return rc;
    if (d != floor(d) || d < (double)lo || d > (double)hi) {
        char b[48];
        return fail(ps, &ps->last, d > (double)hi ? GG_ERROR_LIMIT : GG_ERROR_PARSE,
                    "%s after '%s' must be a whole number from %ld to %ld, got %s", what,
                    ps->keyword, lo, hi, show(&ps->last, b, sizeof b));
    }
    *out = (long)d;
    return GG_OK;
}

/* Does the next token look like a number (an optional argument)? */
static bool next_is_number(parser *ps)
{
    token t;
    double d;
    return peek(ps, &t) > 0 && tok_number(&t, &d);
}

/* The current material's index, registering it if it changed. */
static int material(parser *ps)
{
    if (ps->mat_id < 0) {
        int id = ggSceneAddMaterial(ps->s, &ps->mat);
        ggError e2;
        /* The loader checks each value where it is read; this names what
           ggMaterialCheck still finds, at the statement that set it. */
        if (id == -GG_ERROR_INVALID && ggMaterialCheck(&ps->mat, &e2) != GG_OK)
            return fail(ps, &ps->mat_tok, GG_ERROR_PARSE, "%s", e2.message);
        if (id < 0)
            return fail(ps, &ps->kw_tok, -id, "%s",
                        id == -GG_ERROR_NOMEM ? "out of memory storing the material"
                                              : "the material is invalid");
        ps->mat_id = id;
    }
    return GG_OK;
}

static int add_object(parser *ps, gg_object *o)
{
    int rc = material(ps), id;
    if (rc != GG_OK) return rc;
    o->material = ps->mat_id;
    o->line = ps->kw_tok.line;
    o->col = ps->kw_tok.col;
    id = gg_scene_add_object(ps->s, o);
    /* the values parsed, the material known: out of range is all that
       remains invalid */
    if (id == -GG_ERROR_INVALID)
        return fail(ps, &ps->kw_tok, GG_ERROR_PARSE,
                    "a coordinate or size is over 1e64 in magnitude (GG_COORD_MAX)");
    if (id < 0) return fail(ps, &ps->kw_tok, -id, "cannot add the object: %s", ggStatusString(-id));
    return GG_OK;
}

/* from/at/up: the vector and where its first number is, for messages. */
static int view_vec(parser *ps, token *t, const char *kw, ggVec3 *v, token *at)
{
    next(ps, t), ps->keyword = kw;
    if (peek(ps, at) <= 0) *at = *t;
    return vec(ps, v);
}

/* A degenerate basis is reported at the value that made it so: the later
   of from and at, or up. */
static int view_check(parser *ps, const ggCamera *c, const token *from, const token *at,
                      const token *up)
{
    const token *last =
        from->line > at->line || (from->line == at->line && from->col > at->col) ? from : at;
    int f = gg_camera_fault(c);
    if (f == GG_CAMERA_OK) return GG_OK;
    if ((f == GG_CAMERA_UP || f == GG_CAMERA_UP_ZERO) &&
        (up->line > last->line || (up->line == last->line && up->col > last->col)))
        last = up;
    return fail(ps, last, GG_ERROR_PARSE, "view: %s", gg_camera_fault_text(f));
}

static int kw_view(parser *ps)
{
    ggCamera *c = &ps->s->camera;
    token t, tf = ps->kw_tok, ta = ps->kw_tok, tu = ps->kw_tok;
    int rc = GG_OK;
    double d;
    long w, h;
    while (peek(ps, &t) > 0) {
        if (tok_is(&t, "from"))
            rc = view_vec(ps, &t, "from", &c->from, &tf);
        else if (tok_is(&t, "at"))
            rc = view_vec(ps, &t, "at", &c->at, &ta);
        else if (tok_is(&t, "up"))
            rc = view_vec(ps, &t, "up", &c->up, &tu);
        else if (tok_is(&t, "angle")) {
            next(ps, &t), ps->keyword = "angle";
            if ((rc = number(ps, &d, "an angle in degrees")) == GG_OK) {
                if (!(d > 0 && d < 180))
                    return fail(ps, &ps->last, GG_ERROR_PARSE, "angle must be in (0, 180), got %g",
                                d);
                c->fov_deg = d;
            }
        } else if (tok_is(&t, "hither")) {
            next(ps, &t), ps->keyword = "hither", rc = number(ps, &d, "a distance");
        } else if (tok_is(&t, "resolution")) {
            next(ps, &t), ps->keyword = "resolution", ps->kw_tok = t;
            if ((rc = integer(ps, 1, GG_IMAGE_MAX_DIM, &w, "a width")) != GG_OK) return rc;
            if ((rc = integer(ps, 1, GG_IMAGE_MAX_DIM, &h, "a height")) != GG_OK) return rc;
            if ((size_t)w * (size_t)h > GG_IMAGE_MAX_PIXELS)
                return fail(ps, &t, GG_ERROR_LIMIT, "resolution %ldx%ld exceeds the limit of %zu pixels",
                            w, h, (size_t)GG_IMAGE_MAX_PIXELS);
            c->width = (int)w, c->height = (int)h;
        } else
            break;
        if (rc != GG_OK) return rc;
    }
    if ((rc = view_check(ps, c, &tf, &ta, &tu)) != GG_OK) return rc;
    ps->s->has_camera = true;
    return GG_OK;
}

static int kw_light(parser *ps)
{
    ggVec3 p;
    ggColor c = rgb(-1, -1, -1);
    int rc = vec(ps, &p), id;
    if (rc != GG_OK) return rc;
    /* Lights are only finite: see GG_PARAM_MAX in scene.h. */
    if (next_is_number(ps) && (rc = color_upto(ps, &c, DBL_MAX, "a light's colour")) != GG_OK)
        return rc;
    id = ggSceneAddLight(ps->s, p, c);
    if (id == -GG_ERROR_INVALID)
        return fail(ps, &ps->kw_tok, GG_ERROR_PARSE,
                    "a light's position is over 1e64 in magnitude (GG_COORD_MAX)");
    if (id < 0)
        return fail(ps, &ps->kw_tok, -id, "%s",
                    id == -GG_ERROR_NOMEM ? "out of memory adding the light"
                                          : "cannot add the light");
    ps->s->lights[id].line = ps->kw_tok.line;
    return GG_OK;
}

/* f r g b Kd Ks Shine T index_of_refraction */
static int kw_fill(parser *ps)
{
    static const char *const what[4] = {"Kd (the diffuse weight)", "Ks (the specular weight)",
                                        "the Phong exponent", "T (the transmittance)"};
    static const double hi[4] = {GG_WEIGHT_MAX, GG_WEIGHT_MAX, DBL_MAX, GG_WEIGHT_MAX};
    ggColor c;
    double d[5];
    int i, rc = nonneg_color(ps, &c, "the colour");
    for (i = 0; rc == GG_OK && i < 4; i++) rc = nonneg_number(ps, &d[i], hi[i], what[i]);
    if (rc == GG_OK) rc = number(ps, &d[4], "an index of refraction");
    if (rc == GG_OK && fabs(d[4]) > GG_PARAM_MAX)
        return fail(ps, &ps->last, GG_ERROR_PARSE, "the index of refraction must be at most %g",
                    GG_PARAM_MAX);
    if (rc != GG_OK) return rc;
    /* Opaque SPD materials carry ior 0: a transmitter needs a real index. */
    if (d[3] > 0 && !(d[4] > 0))
        return fail(ps, &ps->last, GG_ERROR_PARSE,
                    "a transparent material (T = %g) needs an index of refraction > 0", d[3]);
    ps->mat = ggMaterialDefault();
    ps->mat.color = c;
    ps->mat.kd = d[0], ps->mat.ks = d[1], ps->mat.shine = d[2], ps->mat.kt = d[3];
    ps->mat.ior = d[4] > 0 ? d[4] : 1;
    ps->mat.line = ps->kw_tok.line;
    ps->mat_tok = ps->kw_tok;
    ps->mat_id = -1;
    return GG_OK;
}

static int kw_sphere(parser *ps)
{
    gg_object o;
    double d[4];
    int rc = numbers(ps, d, 4);
    if (rc != GG_OK) return rc;
    if (!(d[3] > 0))
        return fail(ps, &ps->last, GG_ERROR_PARSE, "sphere radius must be > 0, got %g", d[3]);
    memset(&o, 0, sizeof o);
    o.kind = GG_SHAPE_SPHERE, o.a = v3(d[0], d[1], d[2]), o.ra = d[3];
    return add_object(ps, &o);
}

static int kw_cone(parser *ps)
{
    gg_object o;
    double d[8];
    int rc = numbers(ps, d, 8);
    if (rc != GG_OK) return rc;
    memset(&o, 0, sizeof o);
    o.kind = GG_SHAPE_CONE;
    o.a = v3(d[0], d[1], d[2]), o.ra = fabs(d[3]);
    o.b = v3(d[4], d[5], d[6]), o.rb = fabs(d[7]);
    if (v3len(v3sub(o.a, o.b)) == 0 || (o.ra == 0 && o.rb == 0))
        return fail(ps, &ps->kw_tok, GG_ERROR_PARSE, "degenerate cone (zero length or radii)");
    return add_object(ps, &o);
}

static int kw_polygon(parser *ps, bool normals)
{
    gg_object o;
    ggVec3 *v = NULL, *n = NULL;
    size_t cap_v = 0, cap_n = 0;
    long count, i;
    int rc = integer(ps, 3, NFF_MAX_POLY_VERTS, &count, "a vertex count");
    if (rc != GG_OK) return rc;
    /* Grow as vertices arrive: a huge count in a short file must fail on
       the missing numbers, not on a giant allocation. */
    for (i = 0; i < count && rc == GG_OK; i++) {
        if (gg_mem_grow(ps->s->alloc, (void **)&v, &cap_v, (size_t)i + 1, sizeof *v) ||
            (normals && gg_mem_grow(ps->s->alloc, (void **)&n, &cap_n, (size_t)i + 1, sizeof *n))) {
            rc = fail(ps, &ps->kw_tok, GG_ERROR_NOMEM, "out of memory reading a polygon");
            break;
        }
        rc = vec(ps, &v[i]);
        if (rc == GG_OK && normals) rc = vec(ps, &n[i]);
    }
    if (rc == GG_OK) {
        memset(&o, 0, sizeof o);
        o.kind = (count == 3 || normals) ? GG_SHAPE_TRIANGLE : GG_SHAPE_POLYGON;
        o.nverts = (int)count;
        o.has_normals = normals;
        rc = gg_scene_push_vertices(ps->s, v, n, (int)count, &o.vfirst);
        if (rc < 0) rc = fail(ps, &ps->kw_tok, GG_ERROR_NOMEM, "out of memory reading a polygon");
        else rc = add_object(ps, &o);
    }
    gg_mem_free(ps->s->alloc, v);
    gg_mem_free(ps->s->alloc, n);
    return rc;
}

/* ---- ggrt extensions (docs/scene-format.md) ---- */

static int kw_ambient(parser *ps)
{
    return nonneg_color(ps, &ps->s->ambient, "ambient");
}

/* Extension keywords that change the current material. */
static int mat_changed(parser *ps)
{
    ps->mat_tok = ps->kw_tok;
    ps->mat_id = -1;
    return GG_OK;
}

static int kw_emission(parser *ps)
{
    int rc = nonneg_color(ps, &ps->mat.ke, "emission");
    return rc == GG_OK ? mat_changed(ps) : rc;
}

static int kw_fresnel(parser *ps)
{
    token t;
    char b[48];
    if (next(ps, &t) <= 0)
        return fail(ps, NULL, GG_ERROR_PARSE, "expected none, schlick or exact after 'fresnel'");
    if (tok_is(&t, "none")) ps->mat.fresnel = GG_FRESNEL_NONE;
    else if (tok_is(&t, "schlick")) ps->mat.fresnel = GG_FRESNEL_SCHLICK;
    else if (tok_is(&t, "exact")) ps->mat.fresnel = GG_FRESNEL_EXACT;
    else
        return fail(ps, &t, GG_ERROR_PARSE,
                    "expected none, schlick or exact after 'fresnel', got '%s'",
                    show(&t, b, sizeof b));
    return mat_changed(ps);
}

static int kw_conductor(parser *ps)
{
    token tn[3];
    int i, rc = nonneg_color(ps, &ps->mat.eta_n, "conductor n");
    const double *n[3], *k[3];
    memcpy(tn, ps->comp, sizeof tn);
    if (rc == GG_OK) rc = nonneg_color(ps, &ps->mat.eta_k, "conductor k");
    if (rc != GG_OK) return rc;
    n[0] = &ps->mat.eta_n.r, n[1] = &ps->mat.eta_n.g, n[2] = &ps->mat.eta_n.b;
    k[0] = &ps->mat.eta_k.r, k[1] = &ps->mat.eta_k.g, k[2] = &ps->mat.eta_k.b;
    /* n + ik = 0 has no Fresnel reflectance (ggFresnelConductor gives NaN). */
    for (i = 0; i < 3; i++)
        if (*n[i] == 0 && *k[i] == 0)
            return fail(ps, &tn[i], GG_ERROR_PARSE,
                        "conductor: n and k are both 0 in the %s channel (the index n + ik "
                        "must not be 0)",
                        i == 0   ? "R"
                        : i == 1 ? "G"
                                 : "B");
    ps->mat.fresnel = GG_FRESNEL_CONDUCTOR;
    return mat_changed(ps);
}

static int kw_absorb(parser *ps)
{
    double unit = 1;
    int rc = nonneg_color(ps, &ps->mat.extinction, "extinction coefficient");
    if (rc != GG_OK) return rc;
    if (next_is_number(ps)) {
        if ((rc = number(ps, &unit, "metres per scene unit")) != GG_OK) return rc;
        if (!(unit > 0 && unit <= GG_PARAM_MAX))
            return fail(ps, &ps->last, GG_ERROR_PARSE,
                        "metres per scene unit must be > 0 and at most %g", GG_PARAM_MAX);
    }
    ps->mat.unit_m = unit;
    return mat_changed(ps);
}

static int kw_dispersion(parser *ps)
{
    int rc = number(ps, &ps->mat.abbe, "an Abbe number");
    if (rc != GG_OK) return rc;
    if (ps->mat.abbe != 0 && !(ps->mat.abbe >= 1 && ps->mat.abbe <= GG_PARAM_MAX))
        return fail(ps, &ps->last, GG_ERROR_PARSE,
                    "the Abbe number must be 0 (none) or from 1 to %g (glasses: 20 to 90)",
                    GG_PARAM_MAX);
    return mat_changed(ps);
}

/* texture "file" [repeat|clamp] [nearest|bilinear]  |  texture none */
static int kw_texture(parser *ps)
{
    token t, o;
    gg_texture tx;
    ggError e2 = {0, ""};
    char path[NFF_MAX_TOKEN + 1024];
    int rc, id, r = next(ps, &t);
    if (r < 0) return fail(ps, &t, GG_ERROR_PARSE, "unterminated string");
    if (r == 0) return fail(ps, NULL, GG_ERROR_PARSE, "expected a file name after 'texture'");
    if (tok_is(&t, "none")) {
        ps->mat.texture = -1;
        return mat_changed(ps);
    }
    if (t.n == 0 || t.n > NFF_MAX_TOKEN)
        return fail(ps, &t, GG_ERROR_PARSE, "bad texture file name");
    memset(&tx, 0, sizeof tx);
    tx.wrap = GG_WRAP_REPEAT;
    tx.shared = 1; /* the image is the scene's cache's */
    while (peek(ps, &o) > 0) {
        if (tok_is(&o, "repeat")) tx.wrap = GG_WRAP_REPEAT;
        else if (tok_is(&o, "clamp")) tx.wrap = GG_WRAP_CLAMP;
        else if (tok_is(&o, "nearest")) tx.nearest = 1;
        else if (tok_is(&o, "bilinear")) tx.nearest = 0;
        else break;
        next(ps, &o);
    }
    if (t.p[0] == '/' || !ps->dir[0])
        snprintf(path, sizeof path, "%.*s", (int)t.n, t.p);
    else
        snprintf(path, sizeof path, "%s%.*s", ps->dir, (int)t.n, t.p);
    rc = gg_load_texture(ps->s, path, &tx.img, &e2);
    if (rc != GG_OK)
        return fail(ps, &t, rc, "cannot read texture: %s", e2.message);
    id = gg_scene_add_texture_desc(ps->s, &tx);
    if (id < 0)
        return fail(ps, &t, -id, "%s",
                    id == -GG_ERROR_NOMEM ? "out of memory adding the texture"
                                          : "cannot add the texture");
    ps->mat.texture = id;
    return mat_changed(ps);
}

/* checker n r g b r g b: an n x n checkerboard over (u, v). */
static int kw_checker(parser *ps)
{
    gg_texture tx;
    double n;
    int rc, id;
    memset(&tx, 0, sizeof tx);
    if ((rc = number(ps, &n, "a square count")) != GG_OK) return rc;
    if (!(n > 0 && n <= 1e6))
        return fail(ps, &ps->last, GG_ERROR_PARSE, "checker square count must be in (0, 1e6]");
    if ((rc = nonneg_color(ps, &tx.checker_a, "checker colour")) != GG_OK) return rc;
    if ((rc = nonneg_color(ps, &tx.checker_b, "checker colour")) != GG_OK) return rc;
    tx.checker_n = n;
    id = gg_scene_add_texture_desc(ps->s, &tx);
    if (id < 0)
        return fail(ps, &ps->kw_tok, -id, "%s",
                    id == -GG_ERROR_NOMEM ? "out of memory adding the texture"
                                          : "cannot add the texture");
    ps->mat.texture = id;
    return mat_changed(ps);
}

static int kw_rect(parser *ps)
{
    gg_object o;
    int rc;
    memset(&o, 0, sizeof o);
    o.kind = GG_SHAPE_RECT;
    if ((rc = vec(ps, &o.a)) != GG_OK || (rc = vec(ps, &o.b)) != GG_OK ||
        (rc = vec(ps, &o.c)) != GG_OK)
        return rc;
    if (v3maxabs(v3cross(o.b, o.c)) == 0)
        return fail(ps, &ps->kw_tok, GG_ERROR_PARSE, "rect edges are parallel or zero");
    return add_object(ps, &o);
}

/* implicit "expr" lox loy loz hix hiy hiz */
static int kw_implicit(parser *ps)
{
    token t;
    gg_object o;
    ggVec3 lo, hi;
    ggError e2;
    char *expr;
    int rc, line, col, r = next(ps, &t);
    if (r < 0) return fail(ps, &t, GG_ERROR_PARSE, "unterminated string");
    if (r == 0 || !t.quoted)
        return fail(ps, r ? &t : NULL, GG_ERROR_PARSE,
                    "expected a quoted expression after 'implicit'");
    if ((rc = vec(ps, &lo)) != GG_OK || (rc = vec(ps, &hi)) != GG_OK) return rc;
    if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z))
        return fail(ps, &ps->kw_tok, GG_ERROR_PARSE, "implicit: the box must have lo < hi");
    expr = gg_mem_alloc(ps->s->alloc, t.n + 1);
    if (!expr) return fail(ps, &t, GG_ERROR_NOMEM, "out of memory");
    memcpy(expr, t.p, t.n);
    expr[t.n] = '\0';
    memset(&o, 0, sizeof o);
    o.kind = GG_SHAPE_IMPLICIT;
    rc = ggImplicitCreateExpr(expr, lo, hi, ps->s->alloc, &o.imp, &e2);
    gg_mem_free(ps->s->alloc, expr);
    if (rc != GG_OK) {
        /* The expression's own "1:7: ..." becomes a position in the file. */
        token at = t;
        const char *msg = e2.message;
        if (sscanf(e2.message, "%d:%d:", &line, &col) == 2 && line == 1) {
            at.col = t.col + col; /* +1 for the quote, -1 for 1-based col */
            msg = strchr(strchr(e2.message, ':') + 1, ':') + 1;
            while (*msg == ' ') msg++;
        }
        return fail(ps, &at, rc, "in implicit expression: %s", msg);
    }
    rc = add_object(ps, &o);
    if (rc != GG_OK) ggImplicitFree(o.imp);
    return rc;
}

/* ---- mesh "file" [transform and options] (docs/scene-format.md) ---- */

/* m = op * m for 3x4 affine matrices (op applied after m). */
static void compose(double m[12], const double op[12])
{
    double r[12];
    int i, j;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 4; j++)
            r[4 * i + j] = op[4 * i] * m[j] + op[4 * i + 1] * m[4 + j] + op[4 * i + 2] * m[8 + j];
        r[4 * i + 3] += op[4 * i + 3];
    }
    memcpy(m, r, sizeof r);
}

/* Rotation by deg degrees about axis a (right-handed; Rodrigues). */
static int rotation(parser *ps, ggVec3 a, double deg, double op[12])
{
    double l = v3len(a), c, s, t, x, y, z;
    if (!(l > 0) || !isfinite(l))
        return fail(ps, &ps->kw_tok, GG_ERROR_PARSE, "mesh: the rotation axis is zero");
    x = a.x / l, y = a.y / l, z = a.z / l;
    c = cos(deg * GG_PI / 180), s = sin(deg * GG_PI / 180), t = 1 - c;
    op[0] = t * x * x + c, op[1] = t * x * y - s * z, op[2] = t * x * z + s * y, op[3] = 0;
    op[4] = t * x * y + s * z, op[5] = t * y * y + c, op[6] = t * y * z - s * x, op[7] = 0;
    op[8] = t * x * z - s * y, op[9] = t * y * z + s * x, op[10] = t * z * z + c, op[11] = 0;
    return GG_OK;
}

/* One placement option into op: scale s | scale x y z | rotate x|y|z deg
   | rotate ax ay az deg | translate x y z. */
static int transform_op(parser *ps, const token *o, double op[12])
{
    double d[4];
    token t;
    int rc;
    memset(op, 0, 12 * sizeof *op);
    op[0] = op[5] = op[10] = 1;
    if (tok_is(o, "translate")) {
        if ((rc = numbers(ps, d, 3)) != GG_OK) return rc;
        op[3] = d[0], op[7] = d[1], op[11] = d[2];
    } else if (tok_is(o, "scale")) {
        token at[3];
        int k;
        if ((rc = number(ps, &d[0], "a scale factor")) != GG_OK) return rc;
        d[1] = d[2] = d[0], at[0] = at[1] = at[2] = ps->last;
        if (next_is_number(ps))
            for (k = 1; k < 3; k++) {
                if ((rc = number(ps, &d[k], "a number")) != GG_OK) return rc;
                at[k] = ps->last;
            }
        /* said at the factor, before the file is read (it was at the file
           name, after reading it) */
        for (k = 0; k < 3; k++)
            if (d[k] == 0)
                return fail(ps, &at[k], GG_ERROR_INVALID,
                            "mesh: scale 0 makes the transform singular");
        op[0] = d[0], op[5] = d[1], op[10] = d[2];
    } else if (peek(ps, &t) > 0 && (tok_is(&t, "x") || tok_is(&t, "y") || tok_is(&t, "z"))) {
        next(ps, &t);
        if ((rc = number(ps, &d[3], "an angle in degrees")) != GG_OK) return rc;
        return rotation(ps, v3(t.p[0] == 'x', t.p[0] == 'y', t.p[0] == 'z'), d[3], op);
    } else {
        if ((rc = numbers(ps, d, 4)) != GG_OK) return rc;
        return rotation(ps, v3(d[0], d[1], d[2]), d[3], op);
    }
    return GG_OK;
}

/* The options after the file name, until a token that is none of them. */
static int mesh_options(parser *ps, ggMeshOptions *mo)
{
    token o, v;
    double op[12];
    int rc = GG_OK;
    char b[48];
    while (rc == GG_OK && peek(ps, &o) > 0) {
        if (tok_is(&o, "translate") || tok_is(&o, "scale") || tok_is(&o, "rotate")) {
            next(ps, &o);
            /* Number errors name the option, not 'mesh'. */
            ps->keyword = o.p[0] == 't' ? "translate" : o.p[0] == 's' ? "scale" : "rotate";
            if ((rc = transform_op(ps, &o, op)) == GG_OK) compose(mo->transform, op);
        } else if (tok_is(&o, "crease")) {
            next(ps, &o), ps->keyword = "crease";
            if ((rc = number(ps, &mo->crease_deg, "a crease angle in degrees")) == GG_OK &&
                !(mo->crease_deg >= 0 && mo->crease_deg <= 180))
                rc = fail(ps, &ps->last, GG_ERROR_PARSE,
                          "mesh: the crease angle must be in [0, 180]");
            if (mo->normals == GG_NORMALS_FLAT) mo->normals = GG_NORMALS_AUTO;
        } else if (tok_is(&o, "flat")) {
            next(ps, &o), mo->normals = GG_NORMALS_FLAT;
        } else if (tok_is(&o, "smooth")) {
            next(ps, &o), mo->normals = GG_NORMALS_COMPUTE;
        } else if (tok_is(&o, "material")) {
            next(ps, &o);
            /* At the end of the file v holds nothing: the error is at the end. */
            if (next(ps, &v) <= 0)
                rc = fail(ps, NULL, GG_ERROR_PARSE,
                          "expected current or file after 'material', got end of file");
            else if (tok_is(&v, "current"))
                mo->override_materials = true;
            else if (tok_is(&v, "file")) mo->override_materials = false;
            else
                rc = fail(ps, &v, GG_ERROR_PARSE, "expected current or file after 'material', got '%s'",
                          show(&v, b, sizeof b));
        } else
            break;
    }
    return rc;
}

static int kw_mesh(parser *ps)
{
    token t;
    ggMeshOptions mo;
    ggError e2;
    char path[NFF_MAX_TOKEN + 1024];
    int rc, r = next(ps, &t);
    if (r < 0) return fail(ps, &t, GG_ERROR_PARSE, "unterminated string");
    if (r == 0 || t.n == 0 || t.n > NFF_MAX_TOKEN)
        return fail(ps, r ? &t : NULL, GG_ERROR_PARSE, "expected a file name after 'mesh'");
    ggMeshOptionsDefault(&mo);
    if ((rc = mesh_options(ps, &mo)) != GG_OK) return rc;
    /* Faces the file gives no material get the current one. */
    if ((rc = material(ps)) != GG_OK) return rc;
    mo.material = ps->mat_id;
    if (t.p[0] == '/' || !ps->dir[0]) snprintf(path, sizeof path, "%.*s", (int)t.n, t.p);
    else snprintf(path, sizeof path, "%s%.*s", ps->dir, (int)t.n, t.p);
    rc = gg_load_mesh_file(ps->s, path, &mo, ps->kw_tok.line, &e2);
    if (rc != GG_OK) return fail(ps, &t, rc, "mesh: %s", e2.message);
    return GG_OK;
}

static int kw_depth(parser *ps)
{
    long d = 0;
    int rc = integer(ps, 1, 64, &d, "a depth");
    if (rc == GG_OK) ps->s->depth = (int)d;
    return rc;
}

static int kw_samples(parser *ps)
{
    long n = 0;
    int rc = integer(ps, 1, 4096, &n, "a sample count");
    if (rc == GG_OK) ps->s->samples = (int)n;
    return rc;
}

typedef struct keyword {
    const char *name;
    int (*read)(parser *ps);
} keyword;

static int kw_p(parser *ps) { return kw_polygon(ps, false); }
static int kw_pp(parser *ps) { return kw_polygon(ps, true); }
static int kw_bg(parser *ps)
{
    return nonneg_color(ps, &ps->s->background, "the background");
}

static const keyword keywords[] = {
    {"v", kw_view},           {"b", kw_bg},          {"l", kw_light},
    {"f", kw_fill},           {"s", kw_sphere},      {"c", kw_cone},
    {"p", kw_p},              {"pp", kw_pp},         {"ambient", kw_ambient},
    {"emission", kw_emission}, {"fresnel", kw_fresnel}, {"conductor", kw_conductor},
    {"absorb", kw_absorb},    {"dispersion", kw_dispersion}, {"texture", kw_texture},
    {"checker", kw_checker},  {"rect", kw_rect},     {"implicit", kw_implicit},
    {"depth", kw_depth},      {"samples", kw_samples},   {"mesh", kw_mesh},
};

/* Undo everything added since the snapshot: a failed load changes nothing. */
typedef struct snapshot {
    size_t nobjects, nmaterials, nlights, ntextures, nimages, nverts, nmeshes;
    ggCamera camera;
    bool has_camera;
    ggColor background, ambient;
    int depth, samples;
    gg_prepared prep; /* the prepared state, set aside (scene.h) */
} snapshot;

static void take(const ggScene *s, snapshot *sn)
{
    sn->nobjects = s->nobjects, sn->nmaterials = s->nmaterials, sn->nlights = s->nlights;
    sn->ntextures = s->ntextures, sn->nverts = s->nverts, sn->camera = s->camera;
    sn->nmeshes = s->nmeshes, sn->nimages = s->nimages;
    sn->has_camera = s->has_camera, sn->background = s->background, sn->ambient = s->ambient;
    sn->depth = s->depth, sn->samples = s->samples;
}

static void rollback(ggScene *s, const snapshot *sn)
{
    size_t i;
    for (i = sn->nobjects; i < s->nobjects; i++) ggImplicitFree(s->objects[i].imp);
    gg_scene_drop_textures(s, sn->ntextures, sn->nimages);
    gg_scene_drop_meshes(s, sn->nmeshes);
    s->nobjects = sn->nobjects, s->nmaterials = sn->nmaterials, s->nlights = sn->nlights;
    s->ntextures = sn->ntextures, s->nverts = sn->nverts, s->camera = sn->camera;
    s->has_camera = sn->has_camera, s->background = sn->background, s->ambient = sn->ambient;
    s->depth = sn->depth, s->samples = sn->samples;
}

/* Bytes before tokens: a UTF-8 byte order mark is skipped, UTF-16 is
   refused, and so is a NUL byte anywhere (at its line and column): C
   strings would end there, so "1\0junk" must not read as 1. */
static int check_text(parser *ps)
{
    const unsigned char *u = (const unsigned char *)ps->text;
    size_t len = (size_t)(ps->end - ps->text);
    const char *z, *c, *kind = gg_load_binary_kind(ps->text, len);
    if (kind)
        return gg_error_set(ps->err, GG_ERROR_PARSE,
                            "%s: this is %s, not a scene file (NFF, OBJ or PLY)", ps->name, kind);
    if (len >= 2 && ((u[0] == 0xFE && u[1] == 0xFF) || (u[0] == 0xFF && u[1] == 0xFE)))
        return fail(ps, NULL, GG_ERROR_UNSUPPORTED,
                    "UTF-16 text is not supported (convert the file to UTF-8)");
    if (len >= 3 && memcmp(u, "\xEF\xBB\xBF", 3) == 0) ps->cur += 3;
    z = memchr(ps->cur, '\0', (size_t)(ps->end - ps->cur));
    if (!z) return GG_OK;
    for (c = ps->cur; c < z; c++)
        if (line_end(c, ps->end)) ps->line++, ps->col = 1;
        else ps->col++;
    ps->cur = ps->end;
    return fail(ps, NULL, GG_ERROR_PARSE, "NUL byte in a text file");
}

/* The bytes read so far, every MiB (ggSceneSetProgress); a cancel is an
   error at the statement reached. */
static int progress(parser *ps, int force)
{
    size_t at = (size_t)(ps->cur - ps->text);
    if (!ps->prog.fn || (!force && at - ps->told < ((size_t)1 << 20))) return GG_OK;
    ps->told = at;
    if (gg_progress_to(&ps->prog, at, (size_t)(ps->end - ps->text)))
        return fail(ps, NULL, GG_ERROR_CANCELLED, "loading cancelled");
    return GG_OK;
}

int gg_nff_parse(ggScene *s, const char *text, size_t len, const char *name, const char *dir,
                 ggError *err)
{
    parser ps;
    snapshot sn;
    token t;
    int r, rc = GG_OK;
    size_t i;
    char b[48];
    memset(&ps, 0, sizeof ps);
    ps.s = s, ps.text = ps.cur = text, ps.end = text + len;
    ps.line = 1, ps.col = 1, ps.name = name, ps.dir = dir, ps.err = err;
    ps.mat = ggMaterialDefault();
    ps.mat_id = -1;
    take(s, &sn);
    gg_scene_set_aside(s, &sn.prep);
    gg_progress_part(&ps.prog, s->progress, s->progress_ud, 0, len, len);
    rc = check_text(&ps);
    if (rc == GG_OK) rc = progress(&ps, 1);
    while (rc == GG_OK && (r = next(&ps, &t)) != 0) {
        const keyword *k = NULL;
        if (r < 0) {
            rc = fail(&ps, &t, GG_ERROR_PARSE, "unterminated string");
            break;
        }
        for (i = 0; i < sizeof keywords / sizeof keywords[0]; i++)
            if (tok_is(&t, keywords[i].name)) k = &keywords[i];
        if (!k) {
            rc = fail(&ps, &t, GG_ERROR_PARSE, "unknown keyword '%s'", show(&t, b, sizeof b));
            break;
        }
        ps.keyword = k->name;
        ps.kw_tok = t;
        rc = k->read(&ps);
        if (rc == GG_OK) rc = progress(&ps, 0);
    }
    if (rc == GG_OK) rc = progress(&ps, 1);
    if (rc != GG_OK) {
        rollback(s, &sn);
        gg_scene_put_back(s, &sn.prep); /* prepared as it was, if it was */
    } else {
        gg_scene_drop_aside(s, &sn.prep);
    }
    return rc;
}

GG_API int ggSceneLoadFile(ggScene *s, const char *path, ggError *err)
{
    char *text = NULL, *dir, *name, *slash;
    size_t len = 0;
    int rc;
    if (!s || !path) return gg_error_set(err, GG_ERROR_INVALID, "ggSceneLoadFile: NULL argument");
    if (gg_load_mesh_format(path)) return gg_load_model(s, path, err);
    rc = gg_load_read_file(s->alloc, path, GG_SCENE_MAX_FILE, &text, &len, err);
    if (rc != GG_OK) return rc;
    /* The name is copied before parsing: once the scene holds the file's
       objects, running out of memory for it would lose the name. */
    dir = gg_mem_strdup(s->alloc, path);
    name = dir ? gg_mem_strdup(s->alloc, path) : NULL;
    if (!name) {
        gg_mem_free(s->alloc, dir);
        gg_mem_free(s->alloc, text);
        return gg_error_set(err, GG_ERROR_NOMEM, "%s: out of memory", path);
    }
    slash = strrchr(dir, '/');
    if (slash) slash[1] = '\0';
    else dir[0] = '\0';
    rc = gg_nff_parse(s, text, len, path, dir, err);
    gg_mem_free(s->alloc, text);
    gg_mem_free(s->alloc, dir);
    if (rc == GG_OK) {
        gg_mem_free(s->alloc, s->filename);
        s->filename = name;
    } else {
        gg_mem_free(s->alloc, name);
    }
    return rc;
}

GG_API int ggSceneLoadString(ggScene *s, const char *text, size_t len, const char *name,
                             ggError *err)
{
    if (!s || !text) return gg_error_set(err, GG_ERROR_INVALID, "ggSceneLoadString: NULL argument");
    return gg_nff_parse(s, text, len, name ? name : "<string>", "", err);
}
