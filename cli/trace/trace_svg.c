/* SPDX-License-Identifier: MIT */
/*
** trace_svg.c -- a recorded ray tree drawn over the scene as SVG: top
** view, side view, camera view with the pixel marked. (OBJ: trace_obj.c.)
*/
#include "trace/trace_view.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define PANEL        420.0 /* size of a view panel in SVG units */
#define MAX_OUTLINED 20000

typedef struct proj {
    ggVec3 ax, ay; /* world directions drawn as +x (right) and +y (up) */
    double cx, cy, scale, ox, oy;
} proj;

static double dot3(ggVec3 a, ggVec3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
static ggVec3 v3s(double x, double y, double z)
{
    ggVec3 v;
    v.x = x, v.y = y, v.z = z;
    return v;
}
static ggVec3 axis_vec(int a)
{
    return v3s(a == 0, a == 1, a == 2);
}
static ggVec3 add_s(ggVec3 a, ggVec3 b, double s)
{
    return v3s(a.x + b.x * s, a.y + b.y * s, a.z + b.z * s);
}

static void to2d(const proj *p, ggVec3 w, double *x, double *y)
{
    *x = p->ox + PANEL / 2 + (dot3(w, p->ax) - p->cx) * p->scale;
    *y = p->oy + PANEL / 2 - (dot3(w, p->ay) - p->cy) * p->scale;
}

static void grow(double *x0, double *x1, double *y0, double *y1, const proj *p, ggVec3 w)
{
    double a = dot3(w, p->ax), b = dot3(w, p->ay);
    *x0 = fmin(*x0, a), *x1 = fmax(*x1, a), *y0 = fmin(*y0, b), *y1 = fmax(*y1, b);
}

/* Frame the action: every hit point and the shapes that were hit, with a
   margin. Rays from outside (the eye, rays to lights, misses) are clipped
   at the panel's edge. Falls back to the scene's bounds if nothing hit. */
static void frame(proj *p, const trace_view *v, ggVec3 lo, ggVec3 hi, double reach)
{
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300, ext;
    size_t i, n = ggTraceNodeCount(v->trace);
    int k, any = 0;
    (void)reach;
    for (i = 0; i < n; i++) {
        const ggTraceNode *nd = ggTraceGetNode(v->trace, i);
        ggShapeDesc d;
        if (!nd->hit) continue;
        any = 1;
        grow(&x0, &x1, &y0, &y1, p, nd->p);
        if (ggSceneObjectShape(v->scene, nd->object, &d) == GG_OK && d.kind == GG_SHAPE_SPHERE) {
            for (k = 0; k < 6; k++) {
                ggVec3 e = d.base;
                double r = k & 1 ? d.radius : -d.radius;
                if (k < 2)
                    e.x += r;
                else if (k < 4)
                    e.y += r;
                else
                    e.z += r;
                grow(&x0, &x1, &y0, &y1, p, e);
            }
        }
    }
    if (!any)
        for (k = 0; k < 8; k++)
            grow(&x0, &x1, &y0, &y1, p,
                 v3s(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z));
    p->cx = (x0 + x1) / 2, p->cy = (y0 + y1) / 2;
    ext = fmax(x1 - x0, y1 - y0);
    if (!(ext > 0)) ext = 1;
    p->scale = (PANEL * 0.7) / ext;
}

static void outline(FILE *f, const proj *p, const ggShapeDesc *d)
{
    double x, y, x2, y2;
    int i;
    switch (d->kind) {
    case GG_SHAPE_SPHERE:
        to2d(p, d->base, &x, &y);
        fprintf(f, "<circle cx='%.2f' cy='%.2f' r='%.2f'/>\n", x, y, d->radius * p->scale);
        break;
    case GG_SHAPE_CONE: {
        /* The silhouette: a quadrilateral around the axis. */
        double ax, ay, bx, by, dx, dy, l;
        to2d(p, d->base, &ax, &ay);
        to2d(p, d->apex, &bx, &by);
        dx = by - ay, dy = -(bx - ax), l = sqrt(dx * dx + dy * dy);
        if (l > 0) dx /= l, dy /= l;
        fprintf(f, "<polygon points='%.2f,%.2f %.2f,%.2f %.2f,%.2f %.2f,%.2f'/>\n",
                ax + dx * d->radius * p->scale, ay + dy * d->radius * p->scale,
                bx + dx * d->radius2 * p->scale, by + dy * d->radius2 * p->scale,
                bx - dx * d->radius2 * p->scale, by - dy * d->radius2 * p->scale,
                ax - dx * d->radius * p->scale, ay - dy * d->radius * p->scale);
        break;
    }
    case GG_SHAPE_RECT:
        fprintf(f, "<polygon points='");
        for (i = 0; i < 4; i++) {
            ggVec3 c = add_s(add_s(d->base, d->e1, i == 1 || i == 2), d->e2, i >= 2);
            to2d(p, c, &x, &y);
            fprintf(f, "%.2f,%.2f ", x, y);
        }
        fprintf(f, "'/>\n");
        break;
    case GG_SHAPE_IMPLICIT:
    case GG_SHAPE_MESH: /* the box around it (a mesh's part) */
        to2d(p, d->base, &x, &y);
        to2d(p, d->apex, &x2, &y2);
        fprintf(f, "<rect x='%.2f' y='%.2f' width='%.2f' height='%.2f' stroke-dasharray='4 3'/>\n",
                fmin(x, x2), fmin(y, y2), fabs(x2 - x), fabs(y2 - y));
        break;
    default:
        fprintf(f, "<polygon points='");
        for (i = 0; i < d->nverts; i++) {
            to2d(p, d->verts[i], &x, &y);
            fprintf(f, "%.2f,%.2f ", x, y);
        }
        fprintf(f, "'/>\n");
    }
}

static const char *kind_color(int kind)
{
    switch (kind) {
    case GG_RAY_EYE:
        return "#111";
    case GG_RAY_REFLECT:
        return "#1f5fd0";
    case GG_RAY_REFRACT:
        return "#17a34a";
    default:
        return "#c026d3"; /* TIR */
    }
}

static void panel(FILE *f, const trace_view *v, proj *p, const char *title, double reach)
{
    size_t i, n = ggTraceNodeCount(v->trace);
    int o, nobj = ggSceneObjectCount(v->scene), l;
    /* The panels of one document sit at different x: a unique id without
       state shared between threads (ggrt serve draws from several). */
    int clip_id = (int)p->ox;
    fprintf(f,
            "<clipPath id='c%d'><rect x='%.0f' y='%.0f' width='%.0f' height='%.0f'/></clipPath>\n",
            clip_id, p->ox, p->oy, PANEL, PANEL);
    fprintf(f,
            "<rect x='%.0f' y='%.0f' width='%.0f' height='%.0f' fill='#fbfbf8' "
            "stroke='#bbb'/>\n<g clip-path='url(#c%d)'>\n",
            p->ox, p->oy, PANEL, PANEL, clip_id);
    fprintf(f, "<text x='%.0f' y='%.0f' font-size='13' fill='#333'>%s</text>\n", p->ox + 6,
            p->oy + 16, title);
    fprintf(f, "<g fill='none' stroke='#9aa' stroke-width='0.6'>\n");
    for (o = 0; o < nobj && o < MAX_OUTLINED; o++) {
        ggShapeDesc d;
        if (ggSceneObjectShape(v->scene, o, &d) == GG_OK) outline(f, p, &d);
    }
    fprintf(f, "</g>\n");
    for (i = 0; i < n; i++) {
        const ggTraceNode *nd = ggTraceGetNode(v->trace, i);
        double x0, y0, x1, y1;
        ggVec3 e = nd->hit ? nd->p : add_s(nd->o, nd->d, reach);
        to2d(p, nd->o, &x0, &y0);
        to2d(p, e, &x1, &y1);
        fprintf(
            f, "<line x1='%.2f' y1='%.2f' x2='%.2f' y2='%.2f' stroke='%s' stroke-width='1.6'%s/>\n",
            x0, y0, x1, y1, kind_color(nd->kind), nd->hit ? "" : " stroke-opacity='0.5'");
        if (!nd->hit) continue;
        fprintf(f, "<circle cx='%.2f' cy='%.2f' r='2.6' fill='%s'/>\n", x1, y1,
                kind_color(nd->kind));
        for (l = 0; l < nd->nlights; l++) {
            const ggTraceLight *L = ggTraceGetLight(v->trace, (size_t)(nd->first_light + l));
            double t = L->verdict == GG_SHADOW_BLOCKED ? L->t_block : 1;
            if (L->verdict == GG_SHADOW_FACING_AWAY) continue;
            to2d(p, L->origin, &x0, &y0);
            to2d(p, add_s(L->origin, L->dir, t), &x1, &y1);
            fprintf(f,
                    "<line x1='%.2f' y1='%.2f' x2='%.2f' y2='%.2f' stroke='%s' "
                    "stroke-width='1.1' stroke-dasharray='5 3'/>\n",
                    x0, y0, x1, y1, L->verdict == GG_SHADOW_BLOCKED ? "#dc2626" : "#f59e0b");
            if (L->verdict == GG_SHADOW_BLOCKED)
                fprintf(f,
                        "<path d='M%.2f %.2f l4 4 m0 -4 l-4 4' transform='translate(-2 -2)' "
                        "stroke='#dc2626' stroke-width='1.5'/>\n",
                        x1, y1);
        }
    }
    fprintf(f, "</g>\n");
}

/* s as XML character data. */
static void xml_text(FILE *f, const char *s)
{
    for (; *s; s++)
        if (*s == '<')
            fputs("&lt;", f);
        else if (*s == '>')
            fputs("&gt;", f);
        else if (*s == '&')
            fputs("&amp;", f);
        else
            fputc(*s, f);
}

/* Base64 of a file's bytes, for embedding the camera view as a PNG: 0,
   or -1 with errno if the file could not be read. */
static int base64_file(FILE *out, const char *path)
{
    static const char tb[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    FILE *in = fopen(path, "rb");
    unsigned char b[3];
    size_t n;
    int bad;
    if (!in) return -1;
    while ((n = fread(b, 1, 3, in)) > 0) {
        unsigned v = (unsigned)b[0] << 16 | (n > 1 ? (unsigned)b[1] << 8 : 0) | (n > 2 ? b[2] : 0);
        fputc(tb[v >> 18 & 63], out), fputc(tb[v >> 12 & 63], out);
        fputc(n > 1 ? tb[v >> 6 & 63] : '=', out), fputc(n > 2 ? tb[v & 63] : '=', out);
    }
    bad = ferror(in);
    fclose(in);
    return bad ? -1 : 0;
}

/* The camera view's size: the render's, scaled to PANEL on its longer
   side; *sc the scale. */
static void camera_size(const trace_view *v, int *tw, int *th, double *sc)
{
    ggCamera cam = ggSceneCamera(v->scene);
    int w = v->opt->width > 0 ? v->opt->width : cam.width;
    int h = v->opt->height > 0 ? v->opt->height : cam.height;
    *sc = PANEL / (w > h ? w : h);
    *tw = (int)(w * *sc + 0.5), *th = (int)(h * *sc + 0.5);
    if (*tw < 1) *tw = 1;
    if (*th < 1) *th = 1;
}

int trace_camera_render(const trace_view *v, ggProgressFn progress, void *ud, ggImage **img,
                        ggError *err)
{
    ggRenderOptions o = *v->opt;
    double sc;
    camera_size(v, &o.width, &o.height, &sc);
    o.crop_x0 = o.crop_y0 = o.crop_x1 = o.crop_y1 = 0;
    o.samples = 1, o.pixel_corners = false;
    o.progress = progress, o.progress_ud = ud;
    return ggRender(v->scene, &o, img, NULL, err);
}

/* The camera view, its image (if any) written to png_tmp and embedded:
   GG_OK, or the error of that file. */
static int camera_panel(FILE *f, const trace_view *v, double ox, double oy, const ggImage *img,
                        const char *png_tmp, ggError *err)
{
    double sc;
    int tw, th, rc = GG_OK;
    camera_size(v, &tw, &th, &sc);
    fprintf(
        f,
        "<g>\n<text x='%.0f' y='%.0f' font-size='13' fill='#333'>camera view, pixel %d,%d</text>\n",
        ox + 6, oy + 16, v->x, v->y);
    if (img) {
        char ebuf[128];
        if ((rc = ggImageWritePNG(img, png_tmp, err)) != GG_OK) return rc;
        fprintf(f, "<image x='%.0f' y='%.0f' width='%d' height='%d' href='data:image/png;base64,",
                ox, oy + 24, tw, th);
        if (base64_file(f, png_tmp) != 0) {
            snprintf(ebuf, sizeof ebuf, "%s", strerror(errno));
            rc = GG_ERROR_IO;
            if (err) snprintf(err->message, sizeof err->message, "%s: %s", png_tmp, ebuf);
            if (err) err->code = rc;
        }
        fprintf(f, "'/>\n");
        unlink(png_tmp);
    }
    fprintf(f, "<rect x='%.0f' y='%.0f' width='%d' height='%d' fill='none' stroke='#bbb'/>\n", ox,
            oy + 24, tw, th);
    fprintf(f,
            "<circle cx='%.2f' cy='%.2f' r='7' fill='none' stroke='#dc2626' stroke-width='2'/>\n",
            ox + (v->x + 0.5) * sc, oy + 24 + (v->y + 0.5) * sc);
    fprintf(f, "</g>\n");
    return rc;
}

int trace_write_svg_views(FILE *f, const trace_view *v, int camera, const ggImage *img,
                          const char *png_tmp, ggError *err)
{
    int rc;
    ggSceneInfo in;
    ggCamera cam = ggSceneCamera(v->scene);
    proj top, side;
    int up = 2, horiz;
    double ux = fabs(cam.up.x), uy = fabs(cam.up.y), uz = fabs(cam.up.z), reach;
    ggVec3 fwd = v3s(cam.at.x - cam.from.x, cam.at.y - cam.from.y, cam.at.z - cam.from.z);
    /* The scene is prepared (ggTracePixel did it), so this cannot fail. */
    ggSceneGetInfo(v->scene, &in);
    reach = sqrt(pow(in.hi.x - in.lo.x, 2) + pow(in.hi.y - in.lo.y, 2) + pow(in.hi.z - in.lo.z, 2));
    if (!isfinite(reach) || reach <= 0) reach = 1;
    /* Top view looks down the world axis closest to the camera's up; the
       side view keeps up vertical and looks across the view direction. */
    if (ux >= uy && ux >= uz)
        up = 0;
    else if (uy >= uz)
        up = 1;
    {
        int a = (up + 1) % 3, b = (up + 2) % 3;
        double fa = fabs(a == 0 ? fwd.x : a == 1 ? fwd.y : fwd.z);
        double fb = fabs(b == 0 ? fwd.x : b == 1 ? fwd.y : fwd.z);
        /* Horizontal axis of the side view: the one least along the view. */
        horiz = fa <= fb ? a : b;
        top.ax = axis_vec(a), top.ay = axis_vec(b);
    }
    side.ax = axis_vec(horiz), side.ay = axis_vec(up);
    top.ox = 10, top.oy = 40, side.ox = 20 + PANEL, side.oy = 40;
    frame(&top, v, in.lo, in.hi, reach);
    frame(&side, v, in.lo, in.hi, reach);
    fprintf(f,
            "<?xml version='1.0' encoding='UTF-8'?>\n"
            "<svg xmlns='http://www.w3.org/2000/svg' width='%.0f' height='%.0f' "
            "font-family='sans-serif'>\n",
            (camera ? 3 : 2) * PANEL + (camera ? 40 : 30), PANEL + (camera ? 90 : 110));
    fprintf(f, "<rect width='100%%' height='100%%' fill='white'/>\n");
    fprintf(f, "<text x='10' y='24' font-size='15' fill='#111'>ggrt trace ");
    xml_text(f, v->path);
    fprintf(f, " --pixel %d,%d: colour %.4f %.4f %.4f, %zu rays</text>\n", v->x, v->y, v->pixel.r,
            v->pixel.g, v->pixel.b, ggTraceNodeCount(v->trace));
    panel(f, v, &top, "top view", reach);
    panel(f, v, &side, "side view", reach);
    if (camera && (rc = camera_panel(f, v, 30 + 2 * PANEL, 40, img, png_tmp, err)) != GG_OK)
        return rc;
    {
        static const char *const names[] = {"eye", "reflect", "refract", "TIR"};
        int k;
        double y = PANEL + 66;
        for (k = 0; k < 4; k++) {
            fprintf(f,
                    "<line x1='%d' y1='%.0f' x2='%d' y2='%.0f' stroke='%s' stroke-width='2'/>"
                    "<text x='%d' y='%.0f' font-size='12'>%s</text>\n",
                    10 + 110 * k, y, 40 + 110 * k, y, kind_color(k), 46 + 110 * k, y + 4, names[k]);
        }
        /* the shadow rays: after the others, or on a row of their own where
           the two views alone (the page's SVG, 870 px) leave no room */
        int sx = camera ? 450 : 10, sx2 = camera ? 660 : 230;
        if (!camera) y += 20;
        fprintf(f,
                "<line x1='%d' y1='%.0f' x2='%d' y2='%.0f' stroke='#f59e0b' "
                "stroke-dasharray='5 3' stroke-width='1.5'/><text x='%d' y='%.0f' "
                "font-size='12'>shadow ray, light reached</text>\n",
                sx, y, sx + 30, y, sx + 36, y + 4);
        fprintf(f,
                "<line x1='%d' y1='%.0f' x2='%d' y2='%.0f' stroke='#dc2626' "
                "stroke-dasharray='5 3' stroke-width='1.5'/><text x='%d' y='%.0f' "
                "font-size='12'>shadow ray, stopped at its occluder</text>\n",
                sx2, y, sx2 + 30, y, sx2 + 36, y + 4);
    }
    fprintf(f, "</svg>\n");
    return GG_OK;
}
