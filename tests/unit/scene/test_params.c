/* SPDX-License-Identifier: MIT */
/*
** test_params.c -- physically invalid parameters (negative colours,
** weights, Phong exponent, light, ambient and background values, a zero
** conductor index, a degenerate camera) are refused by the NFF loader at
** the value that set them and by the building functions with
** GG_ERROR_INVALID and ggSceneLastError's message; what is accepted on
** purpose renders finite.
*/
#include "testutil.h"

#include "scene.h" /* the resolved per-channel indices, mfast */

#include <math.h>
#include <string.h>

/* Loading `text` fails with GG_ERROR_PARSE and exactly `msg`; the scene is
   left empty. */
static void refuse(const char *text, const char *msg)
{
    ggScene *s = ggSceneCreate(NULL);
    ggError e;
    int rc = ggSceneLoadString(s, text, strlen(text), "p.nff", &e);
    if (rc != GG_ERROR_PARSE || strcmp(e.message, msg) != 0)
        print_error("input: %s\ngot %d '%s'\nwant '%s'\n", text, rc, rc ? e.message : "", msg);
    assert_int_equal(rc, GG_ERROR_PARSE);
    assert_string_equal(e.message, msg);
    assert_int_equal(ggSceneObjectCount(s), 0);
    assert_int_equal(ggSceneMaterialCount(s), 0);
    assert_int_equal(ggSceneLightCount(s), 0);
    ggSceneFree(s);
}

static void test_nff_material(void **state)
{
    (void)state;
    refuse("f 1 1 -1 1 0 1 0 0\ns 0 0 0 1\n", "p.nff:1:7: the colour must not be negative, got -1");
    refuse("f 1 1 1 -0.5 0 1 0 0\ns 0 0 0 1\n",
           "p.nff:1:9: Kd (the diffuse weight) must not be negative, got -0.5");
    refuse("f 1 1 1 1 -1 1 0 0\ns 0 0 0 1\n",
           "p.nff:1:11: Ks (the specular weight) must not be negative, got -1");
    refuse("f 1 1 1 1 0.5 -5 0 0\ns 0 0 0 1\n",
           "p.nff:1:15: the Phong exponent must not be negative, got -5");
    refuse("f 1 1 1 1 0 1 -0.2 1.5\ns 0 0 0 1\n",
           "p.nff:1:15: T (the transmittance) must not be negative, got -0.2");
    /* The error is at the f line even when the object comes lines later. */
    refuse("f -1 1 1 1 0 1 0 0\n\n# comment\ns 0 0 0 1\n",
           "p.nff:1:3: the colour must not be negative, got -1");
    refuse("emission 0 -1 0\ns 0 0 0 1\n", "p.nff:1:12: emission must not be negative, got -1");
    refuse("absorb 0 0 -1e-9\ns 0 0 0 1\n",
           "p.nff:1:12: extinction coefficient must not be negative, got -1e-9");
    refuse("checker 4 1 1 1 0 -1 0\ns 0 0 0 1\n",
           "p.nff:1:19: checker colour must not be negative, got -1");
}

/* Above the bounds of scene.h (GG_PARAM_MAX, GG_WEIGHT_MAX) a render
   could overflow a double and make NaN from inf * 0. */
static void test_nff_upper_bounds(void **state)
{
    (void)state;
    refuse("f 1 1 1 101 0 1 0 0\ns 0 0 0 1\n",
           "p.nff:1:9: Kd (the diffuse weight) must be at most 100, got 101");
    refuse("f 1 1 1 1 0 1 1e3 1.5\ns 0 0 0 1\n",
           "p.nff:1:15: T (the transmittance) must be at most 100, got 1e3");
    refuse("f 1 1e31 1 1 0 1 0 0\ns 0 0 0 1\n",
           "p.nff:1:5: the colour must be at most 1e+30, got 1e31");
    refuse("f 1 1 1 1 0 1 0.5 1e300\ns 0 0 0 1\n",
           "p.nff:1:19: the index of refraction must be at most 1e+30");
    refuse("b 0 0 2e30\n", "p.nff:1:7: the background must be at most 1e+30, got 2e30");
    /* a number beyond a double's range is said to be one; a malformed one not */
    refuse(
        "s 0 0 1e400 1\n",
        "p.nff:1:7: expected a number after 's', got '1e400' (not a number in a double's range)");
    refuse("s 0 0 -.5E+999 1\n", "p.nff:1:7: expected a number after 's', got '-.5E+999' (not a "
                                 "number in a double's range)");
    refuse("s 0 0 1.2.3 1\n", "p.nff:1:7: expected a number after 's', got '1.2.3'");
    refuse("s 0 0 1e 1\n", "p.nff:1:7: expected a number after 's', got '1e'");
    refuse("conductor 1e40 1 1 1 1 1\ns 0 0 0 1\n",
           "p.nff:1:11: conductor n must be at most 1e+30, got 1e40");
    refuse("f 1 1 1 1 0 1 0.9 1.5\ndispersion 0.5\ns 0 0 0 1\n",
           "p.nff:2:12: the Abbe number must be 0 (none) or from 1 to 1e+30 (glasses: 20 to 90)");
}

/* Every parameter at its bound, a deep ray tree, Fresnel and a conductor:
   the render's doubles stay finite (no NaN or infinite sample); pixels
   beyond the float range are +inf in the image, never NaN. */
static void test_bounds_render_finite(void **state)
{
    static const char text[] =
        "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 resolution 16 12\n"
        "l 0 5 5 1e30 1e30 1e30\nl 0 -5 5 1e30 1e30 1e30\n"
        "b 1e30 1e30 1e30\nambient 1e30 1e30 1e30\n"
        "f 1e30 1e30 1e30 100 100 0 100 1e30\nemission 1e30 1e30 1e30\nfresnel exact\n"
        "dispersion 1\nabsorb 1e30 1e30 1e30 1e30\ns 0 0 0 1\ns 0 0 -3 1\n"
        /* with exact Fresnel, 1 - F rounds to 0 at index 1e30 and no ray
           refracts (a ray of weight 0 is not cast): the same glass without
           Fresnel refracts, and inside it every ray meets TIR */
        "f 1e30 1e30 1e30 100 100 0 100 1e30\nemission 1e30 1e30 1e30\n"
        "dispersion 1\nabsorb 1e30 1e30 1e30 1e30\ns -1 -1 0.5 0.8\n"
        "f 1e30 1e30 1e30 100 100 0 0 0\nconductor 1e30 1e-30 1 1e30 1e30 1e30\n"
        "s 1 1 -1 0.5\ndepth 64\n";
    ggScene *s = ggSceneCreate(NULL);
    ggImage *img = NULL;
    ggRayStats st;
    ggError e;
    const float *p;
    size_t k, n;
    (void)state;
    assert_int_equal(ggSceneLoadString(s, text, sizeof text - 1, NULL, &e), GG_OK);
    assert_int_equal(ggRender(s, NULL, &img, &st, &e), GG_OK);
    assert_true(st.reflect > 1000 && st.tir > 1000 && st.refract > 100);
    assert_true(st.nonfinite == 0);
    p = ggImagePixelsConst(img);
    n = 3 * (size_t)ggImageWidth(img) * (size_t)ggImageHeight(img);
    for (k = 0; k < n; k++) assert_true(!isnan(p[k]) && p[k] >= 0);
    ggImageFree(img);
    ggSceneFree(s);
}

static void test_nff_conductor(void **state)
{
    (void)state;
    refuse("conductor 0 0.1 0.1 0 3 3\ns 0 0 0 1\n",
           "p.nff:1:11: conductor: n and k are both 0 in the R channel (the index n + ik must "
           "not be 0)");
    refuse("conductor 0.1 0.1 0 3 3 0\ns 0 0 0 1\n",
           "p.nff:1:19: conductor: n and k are both 0 in the B channel (the index n + ik must "
           "not be 0)");
    refuse("conductor 0.1 -1 0.1 3 3 3\ns 0 0 0 1\n",
           "p.nff:1:15: conductor n must not be negative, got -1");
    refuse("conductor 0.1 1 0.1 3 3 -3\ns 0 0 0 1\n",
           "p.nff:1:25: conductor k must not be negative, got -3");
}

static void test_nff_lights_background(void **state)
{
    (void)state;
    refuse("l 1 2 3 -1 0 0\n", "p.nff:1:9: a light's colour must not be negative, got -1");
    refuse("l 1 2 3 1 1 -0.001\n", "p.nff:1:13: a light's colour must not be negative, got -0.001");
    refuse("ambient -0.1 0 0\n", "p.nff:1:9: ambient must not be negative, got -0.1");
    refuse("b 0 -2 0\n", "p.nff:1:5: the background must not be negative, got -2");
}

static void test_nff_camera(void **state)
{
    (void)state;
    refuse("v\nfrom 1 2 3\nat 1 2 3\nup 0 1 0\nangle 40\n",
           "p.nff:3:4: view: 'from' and 'at' are the same point (or within 1e-9 of their size)");
    /* The later of the two is the one that made them equal. */
    refuse("v\nat 1 2 3\nfrom 1 2 3\nup 0 1 0\nangle 40\n",
           "p.nff:3:6: view: 'from' and 'at' are the same point (or within 1e-9 of their size)");
    /* Equal after rounding: 1e12 and 1e12 + 1e-3 differ by 1e-15 of their size. */
    refuse("v\nfrom 1e12 0 0\nat 1000000000000.001 0 0\nup 0 1 0\nangle 40\n",
           "p.nff:3:4: view: 'from' and 'at' are the same point (or within 1e-9 of their size)");
    refuse("v\nfrom 0 0 5\nat 0 0 0\nup 0 0 1\nangle 40\n",
           "p.nff:4:4: view: 'up' is parallel to the view direction");
    refuse("v\nfrom 0 0 5\nat 0 0 0\nup 0 0 0\nangle 40\n",
           "p.nff:4:4: view: 'up' is the zero vector");
    refuse("v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 0\n",
           "p.nff:5:7: angle must be in (0, 180), got 0");
    refuse("v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 180\n",
           "p.nff:5:7: angle must be in (0, 180), got 180");
}

static ggScene *api_scene(void)
{
    ggScene *s = ggSceneCreate(NULL);
    assert_non_null(s);
    return s;
}

/* ggSceneAddMaterial refuses m, ggMaterialCheck names `field`. */
static void refuse_material(ggScene *s, const ggMaterial *m, const char *field)
{
    ggError e;
    int n = ggSceneMaterialCount(s);
    assert_int_equal(ggSceneAddMaterial(s, m), -GG_ERROR_INVALID);
    assert_int_equal(ggSceneMaterialCount(s), n);
    assert_int_equal(ggMaterialCheck(m, &e), GG_ERROR_INVALID);
    if (!strstr(e.message, field)) print_error("'%s' does not name '%s'\n", e.message, field);
    assert_non_null(strstr(e.message, field));
}

/* ggSceneAddChecker is NFF's `checker`: the same texture description and
   the same image, built in code; the loader's limits refused alike. */
static void test_api_checker(void **state)
{
    static const char head[] =
        "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 resolution 24 18\nl 1 1 5\n";
    static const char rest[] = "checker 8 1 0.5 0 0 0.2 1\nrect -2 -2 0 4 0 0 0 4 0\n";
    const ggColor a = {1, 0.5, 0}, b = {0, 0.2, 1};
    const ggVec3 corner = {-2, -2, 0}, e1 = {4, 0, 0}, e2 = {0, 4, 0};
    char text[256];
    ggScene *sa = ggSceneCreate(NULL), *sb = ggSceneCreate(NULL);
    ggMaterial m = ggMaterialDefault();
    ggTextureInfo ta, tb;
    ggImage *ia = NULL, *ib = NULL;
    size_t n = 24 * 18 * 3;
    (void)state;
    snprintf(text, sizeof text, "%s%s", head, rest);
    assert_int_equal(ggSceneLoadString(sa, text, strlen(text), "c.nff", NULL), GG_OK);
    assert_int_equal(ggSceneLoadString(sb, head, strlen(head), "c.nff", NULL), GG_OK);
    m.texture = ggSceneAddChecker(sb, 8, a, b);
    assert_int_equal(m.texture, 0);
    assert_int_equal(ggSceneAddRect(sb, ggSceneAddMaterial(sb, &m), corner, e1, e2), 0);
    assert_int_equal(ggSceneGetTexture(sa, 0, &ta), GG_OK);
    assert_int_equal(ggSceneGetTexture(sb, 0, &tb), GG_OK);
    assert_memory_equal(&ta, &tb, sizeof ta);
    assert_int_equal(ggRender(sa, NULL, &ia, NULL, NULL), GG_OK);
    assert_int_equal(ggRender(sb, NULL, &ib, NULL, NULL), GG_OK);
    assert_memory_equal(ggImagePixelsConst(ia), ggImagePixelsConst(ib), n * sizeof(float));
    /* the loader's limits */
    assert_int_equal(ggSceneAddChecker(sb, 0, a, b), -GG_ERROR_INVALID);
    assert_int_equal(ggSceneAddChecker(sb, 2e6, a, b), -GG_ERROR_INVALID);
    assert_int_equal(ggSceneAddChecker(sb, NAN, a, b), -GG_ERROR_INVALID);
    assert_int_equal(ggSceneAddChecker(sb, 4, (ggColor){-1, 0, 0}, b), -GG_ERROR_INVALID);
    assert_int_equal(ggSceneAddChecker(sb, 4, a, (ggColor){0, 2e30, 0}), -GG_ERROR_INVALID);
    assert_int_equal(ggSceneTextureCount(sb), 1);
    ggImageFree(ia), ggImageFree(ib);
    ggSceneFree(sa), ggSceneFree(sb);
}

static void test_api_material(void **state)
{
    ggScene *s = api_scene();
    ggMaterial m;
    (void)state;
    m = ggMaterialDefault(), m.color.g = -1, refuse_material(s, &m, "colour");
    m = ggMaterialDefault(), m.kd = -0.1, refuse_material(s, &m, "kd");
    m = ggMaterialDefault(), m.ks = -1, refuse_material(s, &m, "ks");
    m = ggMaterialDefault(), m.kt = -1, refuse_material(s, &m, "kt");
    m = ggMaterialDefault(), m.shine = -2, refuse_material(s, &m, "Phong");
    m = ggMaterialDefault(), m.kt = 0.5, m.ior = 0, refuse_material(s, &m, "index");
    m = ggMaterialDefault(), m.ke.b = -1, refuse_material(s, &m, "emission");
    m = ggMaterialDefault(), m.ks = NAN, refuse_material(s, &m, "ks");
    m = ggMaterialDefault(), m.ks = 1e300, refuse_material(s, &m, "ks");
    m = ggMaterialDefault(), m.color.r = 1e31, refuse_material(s, &m, "colour");
    m = ggMaterialDefault(), m.abbe = 0.5, refuse_material(s, &m, "abbe");
    m = ggMaterialDefault(), m.fresnel = GG_FRESNEL_CONDUCTOR;
    m.eta_n = (ggColor){0.2, 0, 0.2}, m.eta_k = (ggColor){3, 0, 3};
    refuse_material(s, &m, "conductor");
    m.eta_n = (ggColor){0.2, -0.1, 0.2}, m.eta_k = (ggColor){3, 3, 3};
    refuse_material(s, &m, "conductor");
    /* a NaN index is refused whatever the Fresnel mode (fmax dropped it) */
    m = ggMaterialDefault(), m.eta_n.r = NAN, refuse_material(s, &m, "complex index");
    m = ggMaterialDefault(), m.eta_n.b = NAN, m.fresnel = GG_FRESNEL_CONDUCTOR;
    refuse_material(s, &m, "complex index");
    m = ggMaterialDefault(), m.eta_n.g = -1e300, refuse_material(s, &m, "complex index");
    /* Accepted on purpose: zero weights and exponent, n = 0 with k > 0,
       weights above 1 (ggrt check reports the energy). */
    m = ggMaterialDefault(), m.kd = 0, m.shine = 0, m.ks = 1.5;
    assert_int_equal(ggSceneAddMaterial(s, &m), 0);
    m.fresnel = GG_FRESNEL_CONDUCTOR, m.eta_n = (ggColor){0, 0, 0}, m.eta_k = (ggColor){1, 2, 3};
    assert_int_equal(ggSceneAddMaterial(s, &m), 1);
    assert_int_equal(ggMaterialCheck(&m, NULL), GG_OK);
    assert_int_equal(ggMaterialCheck(NULL, NULL), GG_ERROR_INVALID);
    ggSceneFree(s);
}

/* Dispersion (docs/scene-format.md, `dispersion V`): Cauchy's law
   n = A + B / lambda^2 fitted to ior = n_d (at 587.6 nm) and the Abbe
   number V_d = (n_d - 1) / (n_F - n_C), F = 486.1 nm, C = 656.3 nm. The
   prepared scene's indices at the channels' wavelengths (GG_LAMBDA_R, G,
   B) must lie on that curve: B from n_b - n_r, then n_F - n_C and
   n(587.6) back from it. Glass (n_d > 1) disperses normally, blue bent
   most: n_b > n_g > n_r, for ior 1.5 and abbe 40 and over ior in (1, 4],
   abbe over [1, 1e6]. Guards the fit in cauchy() (lib/scene/scene.c):
   swapping lambda_F and lambda_C reverses the order. */
static void test_dispersion_indices(void **state)
{
    tu_rng r = {31};
    const double lr = GG_LAMBDA_R, lb = GG_LAMBDA_B, lf = 486.1, lc = 656.3, ld = 587.6;
    int i;
    (void)state;
    for (i = 0; i < 2000; i++) {
        ggScene *s = api_scene();
        ggMaterial m = ggMaterialDefault();
        const gg_mat_fast *f;
        double b, a, nfc, want;
        int mi;
        m.kt = 0.5;
        m.ior = i == 0 ? 1.5 : tu_range(&r, 1.001, 4);
        m.abbe = i == 0 ? 40 : pow(10, tu_range(&r, 0, 6));
        mi = ggSceneAddMaterial(s, &m);
        assert_true(mi >= 0);
        assert_true(ggSceneAddSphere(s, mi, (ggVec3){0, 0, 0}, 1) >= 0);
        assert_int_equal(ggScenePrepare(s, NULL), GG_OK);
        f = &s->mfast[mi];
        if (!(f->n_b > f->n_g && f->n_g > f->n_r))
            print_error("ior %.17g abbe %.17g: n_r %.17g n_g %.17g n_b %.17g\n", m.ior, m.abbe,
                        f->n_r, f->n_g, f->n_b);
        assert_true(f->n_b > f->n_g && f->n_g > f->n_r);
        /* the curve through n_r and n_b */
        b = (f->n_b - f->n_r) / (1 / (lb * lb) - 1 / (lr * lr));
        a = f->n_r - b / (lr * lr);
        nfc = b * (1 / (lf * lf) - 1 / (lc * lc));
        want = (m.ior - 1) / m.abbe;
        /* n_b - n_r loses about 8 ulps of ior to rounding */
        assert_true(fabs(nfc - want) <= 1e-9 * want + 16 * 0x1p-52 * m.ior);
        assert_close(a + b / (ld * ld), m.ior, 16 * 0x1p-52);
        assert_close(a + b / (GG_LAMBDA_G * GG_LAMBDA_G), f->n_g, 16 * 0x1p-52);
        ggSceneFree(s);
    }
}

static void test_api_lights_background(void **state)
{
    ggScene *s = api_scene();
    (void)state;
    assert_int_equal(ggSceneAddLight(s, (ggVec3){0, 0, 0}, (ggColor){1, -1, 1}), -GG_ERROR_INVALID);
    assert_int_equal(ggSceneAddLight(s, (ggVec3){0, 0, 0}, (ggColor){0, 0, -0.5}),
                     -GG_ERROR_INVALID);
    assert_int_equal(ggSceneAddLight(s, (ggVec3){0, 0, 0}, (ggColor){1, INFINITY, 1}),
                     -GG_ERROR_INVALID);
    assert_int_equal(ggSceneLightCount(s), 0);
    /* r < 0 is the SPD default colour, documented. */
    assert_int_equal(ggSceneAddLight(s, (ggVec3){0, 0, 0}, (ggColor){-1, -1, -1}), 0);
    assert_int_equal(ggSceneSetBackground(s, (ggColor){0.5, -0.5, 0}), GG_ERROR_INVALID);
    assert_int_equal(ggSceneSetAmbient(s, (ggColor){0, 0, -1}), GG_ERROR_INVALID);
    assert_int_equal(ggSceneSetAmbient(s, (ggColor){0, INFINITY, 0}), GG_ERROR_INVALID);
    assert_int_equal(ggSceneSetBackground(s, (ggColor){0.25, 0.5, 1}), GG_OK);
    assert_int_equal(ggSceneLoadString(s, "ambient 0 0 0\n", 14, NULL, NULL), GG_OK);
    assert_int_equal(ggSceneAddLight(s, (ggVec3){0, 0, 0}, (ggColor){0, 0, 0}), 1);
    ggSceneFree(s);
}

static void refuse_camera(ggScene *s, const ggCamera *c, const char *what)
{
    ggCamera before = ggSceneCamera(s), after;
    ggError e;
    assert_int_equal(ggSceneSetCamera(s, c), GG_ERROR_INVALID);
    after = ggSceneCamera(s);
    assert_memory_equal(&before, &after, sizeof before);
    assert_int_equal(ggCameraCheck(c, &e), GG_ERROR_INVALID);
    if (!strstr(e.message, what)) print_error("'%s' does not say '%s'\n", e.message, what);
    assert_non_null(strstr(e.message, what));
}

static void test_api_camera(void **state)
{
    ggScene *s = api_scene();
    ggCamera c0, c;
    (void)state;
    memset(&c0, 0, sizeof c0);
    c0.from = (ggVec3){0, 0, 5}, c0.up = (ggVec3){0, 1, 0}, c0.fov_deg = 40;
    c0.width = 16, c0.height = 12;
    assert_int_equal(ggSceneSetCamera(s, &c0), GG_OK);
    c = c0, c.at = c.from, refuse_camera(s, &c, "same point");
    c = c0, c.up = (ggVec3){0, 0, 2}, refuse_camera(s, &c, "parallel");
    c = c0, c.up = (ggVec3){0, 0, 0}, refuse_camera(s, &c, "zero vector");
    c = c0, c.up = (ggVec3){1e-300, 1e-300, 1}, refuse_camera(s, &c, "parallel");
    c = c0, c.fov_deg = 0, refuse_camera(s, &c, "field of view");
    c = c0, c.fov_deg = 180, refuse_camera(s, &c, "field of view");
    c = c0, c.width = 0, refuse_camera(s, &c, "image size");
    /* the pixel limit the message names is GG_IMAGE_MAX_PIXELS */
    c = c0, c.width = 8192, c.height = 4096;
    refuse_camera(s, &c, "the image size must be 1 to 65536 a side and at most 16777216 pixels");
    assert_int_equal(GG_IMAGE_MAX_PIXELS, 16777216);
    c = c0, c.from.x = NAN, refuse_camera(s, &c, "finite");
    c = c0, c.from.z = 1e200, refuse_camera(s, &c, "1e150");
    /* A huge but valid distance: the basis still comes out unit. */
    c = c0, c.from = (ggVec3){0, 0, 1e100};
    assert_int_equal(ggSceneSetCamera(s, &c), GG_OK);
    assert_int_equal(ggCameraCheck(NULL, NULL), GG_ERROR_INVALID);
    ggSceneFree(s);
}

/* What is accepted on purpose renders finite and non-negative. */
static void test_accepted_renders_finite(void **state)
{
    static const char *const scenes[] = {
        "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 resolution 16 12\nl 2 3 4\n"
        "f 1 1 1 0 1 0 0 0\ns 0 0 0 1\n", /* kd 0, Phong exponent 0 */
        "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 resolution 16 12\nl 2 3 4 0 0 0\n"
        "b 0 0 0\nambient 0 0 0\nconductor 0 0 0 1 2 3\ns 0 0 0 1\n", /* n = 0, k > 0 */
        "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 resolution 16 12\nl 2 3 4\n"
        "f 0 0 0 0 0 0 1 1.5\ns 0 0 0 1\n", /* black, fully transmitting */
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof scenes / sizeof scenes[0]; i++) {
        ggScene *s = ggSceneCreate(NULL);
        ggImage *img = NULL;
        ggError e;
        const float *p;
        size_t k, n;
        assert_int_equal(ggSceneLoadString(s, scenes[i], strlen(scenes[i]), NULL, &e), GG_OK);
        assert_int_equal(ggRender(s, NULL, &img, NULL, &e), GG_OK);
        p = ggImagePixelsConst(img);
        n = 3 * (size_t)ggImageWidth(img) * (size_t)ggImageHeight(img);
        for (k = 0; k < n; k++) assert_true(isfinite(p[k]) && p[k] >= 0);
        ggImageFree(img);
        ggSceneFree(s);
    }
}

/* ggSceneLastError after a building call that returned rc: the code is
   rc made positive, the message starts "FN: " and holds `has`; after a
   success, GG_OK and "". */
static void said(const ggScene *s, int rc, const char *fn, const char *has)
{
    const ggError *e = ggSceneLastError(s);
    char want[64];
    assert_non_null(e);
    if (!fn) {
        assert_true(rc >= 0);
        assert_int_equal(e->code, GG_OK);
        assert_string_equal(e->message, "");
        return;
    }
    snprintf(want, sizeof want, "%s: ", fn);
    if (e->code != (rc < 0 ? -rc : rc) || strncmp(e->message, want, strlen(want)) ||
        !strstr(e->message, has))
        print_error("rc %d; said %d '%s'; want '%s...%s'\n", rc, e->code, e->message, want, has);
    assert_true(rc != GG_OK);
    assert_int_equal(e->code, rc < 0 ? -rc : rc);
    assert_true(strncmp(e->message, want, strlen(want)) == 0);
    assert_non_null(strstr(e->message, has));
}

/* Every refusal scene.h lists for the building functions, each followed
   by ggSceneLastError's answer, and the scene unchanged; a success after
   each clears it. */
/* ggSceneSetSamples on a prepared scene: still prepared, and its effect
   set says what a fresh prepare would (supersampling came and went only
   at the next prepare, with the reason NULL meanwhile). */
static void test_settings_keep_effects(void **state)
{
    ggScene *s = ggSceneCreate(NULL);
    ggMaterial m = ggMaterialDefault();
    ggRay r = {{0, 0, 5}, {0, 0, -1}};
    ggColor white = {1, 1, 1};
    ggHit h;
    ggError e;
    (void)state;
    assert_true(ggSceneAddSphere(s, ggSceneAddMaterial(s, &m), (ggVec3){0, 0, 0}, 1) >= 0);
    assert_true(ggSceneAddLight(s, (ggVec3){0, 0, 5}, white) >= 0);
    assert_int_equal(ggScenePrepare(s, &e), GG_OK);
    assert_false(ggSceneEffects(s) & GG_EFFECT_SUPERSAMPLING);
    assert_int_equal(ggSceneSetSamples(s, 4), GG_OK);
    assert_true(ggSceneEffects(s) & GG_EFFECT_SUPERSAMPLING);
    assert_non_null(ggSceneEffectReason(s, GG_EFFECT_SUPERSAMPLING));
    assert_true(ggSceneIntersect(s, r, 0, INFINITY, &h)); /* still prepared */
    assert_int_equal(ggSceneSetDepth(s, 3), GG_OK);
    assert_true(ggSceneEffects(s) & GG_EFFECT_SUPERSAMPLING);
    assert_int_equal(ggSceneSetSamples(s, 1), GG_OK);
    assert_false(ggSceneEffects(s) & GG_EFFECT_SUPERSAMPLING);
    assert_null(ggSceneEffectReason(s, GG_EFFECT_SUPERSAMPLING));
    assert_true(ggSceneIntersect(s, r, 0, INFINITY, &h));
    ggSceneFree(s);
}

static void test_last_error(void **state)
{
    ggScene *s = ggSceneCreate(NULL);
    ggMaterial m = ggMaterialDefault(), bad = ggMaterialDefault();
    ggCamera cam = ggSceneCamera(s), flat = cam;
    const ggVec3 o = {0, 0, 0}, x = {1, 0, 0}, y = {0, 1, 0}, inf = {INFINITY, 0, 0};
    const ggVec3 tri[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
                 nan3[3] = {{0, 0, 0}, {NAN, 0, 0}, {0, 1, 0}};
    const ggVec3 big[3] = {{0, 0, 0}, {2e64, 0, 0}, {0, 1, 0}};
    const ggColor neg = {0, -1, 0}, white = {1, 1, 1};
    (void)state;
    assert_null(ggSceneLastError(NULL));
    said(s, 0, NULL, NULL); /* before any call */
    flat.up = (ggVec3){cam.at.x - cam.from.x, cam.at.y - cam.from.y, cam.at.z - cam.from.z};
    said(s, ggSceneSetCamera(s, NULL), "ggSceneSetCamera", "NULL camera");
    said(s, ggSceneSetCamera(s, &flat), "ggSceneSetCamera", "");
    said(s, ggSceneSetCamera(s, &cam), NULL, NULL);
    said(s, ggSceneSetBackground(s, neg), "ggSceneSetBackground", "got 0 -1 0");
    said(s, ggSceneSetAmbient(s, (ggColor){0, 0, 2e30}), "ggSceneSetAmbient", "got 0 0 2e+30");
    said(s, ggSceneSetAmbient(s, white), NULL, NULL);
    said(s, ggSceneSetDepth(s, 65), "ggSceneSetDepth", "got 65");
    said(s, ggSceneSetDepth(s, -1), "ggSceneSetDepth", "got -1");
    said(s, ggSceneSetSamples(s, 4097), "ggSceneSetSamples", "got 4097");
    said(s, ggSceneSetSamples(s, 0), NULL, NULL);
    said(s, ggSceneAddLight(s, inf, white), "ggSceneAddLight", "position");
    said(s, ggSceneAddLight(s, (ggVec3){0, 0, -2e64}, white), "ggSceneAddLight", "got 0 0 -2e+64");
    said(s, ggSceneAddLight(s, o, (ggColor){1, -1, 1}), "ggSceneAddLight", "got 1 -1 1");
    said(s, ggSceneAddLight(s, o, (ggColor){1, NAN, 1}), "ggSceneAddLight", "colour");
    assert_int_equal(ggSceneLightCount(s), 0);
    said(s, ggSceneAddLight(s, x, white), NULL, NULL);
    said(s, ggSceneAddMaterial(s, NULL), "ggSceneAddMaterial", "NULL material");
    bad.ks = -0.5;
    said(s, ggSceneAddMaterial(s, &bad), "ggSceneAddMaterial", "ks must be in [0, ");
    bad = m, bad.texture = 3;
    said(s, ggSceneAddMaterial(s, &bad), "ggSceneAddMaterial", "no texture 3 (the scene has 0)");
    assert_int_equal(ggSceneMaterialCount(s), 0);
    said(s, ggSceneAddSphere(s, 0, o, 1), "ggSceneAddSphere", "no material 0 (the scene has 0)");
    said(s, ggSceneAddMaterial(s, &m), NULL, NULL);
    said(s, ggSceneSetMaterial(s, 1, &m), "ggSceneSetMaterial", "no material 1 (the scene has 1)");
    bad = m, bad.kt = 1, bad.ior = 0;
    said(s, ggSceneSetMaterial(s, 0, &bad), "ggSceneSetMaterial", "index of refraction");
    said(s, ggSceneSetMaterial(s, 0, &m), NULL, NULL);
    said(s, ggSceneAddTexture(s, NULL), "ggSceneAddTexture", "NULL image");
    said(s, ggSceneAddChecker(s, 0, white, white), "ggSceneAddChecker", "got 0");
    said(s, ggSceneAddChecker(s, 4, white, neg), "ggSceneAddChecker", "colour b");
    said(s, ggSceneAddSphere(s, 0, inf, 1), "ggSceneAddSphere", "the centre must be finite");
    said(s, ggSceneAddSphere(s, 0, o, -1), "ggSceneAddSphere", "got -1");
    said(s, ggSceneAddSphere(s, 0, o, 2e64), "ggSceneAddSphere", "over 1e+64");
    said(s, ggSceneAddSphere(s, -1, o, 1), "ggSceneAddSphere", "no material -1");
    said(s, ggSceneAddPolygon(s, 0, NULL, 3), "ggSceneAddPolygon", "NULL vertices");
    said(s, ggSceneAddPolygon(s, 0, tri, 2), "ggSceneAddPolygon", "got 2");
    said(s, ggSceneAddPolygon(s, 0, nan3, 3), "ggSceneAddPolygon", "vertex 1 must be finite");
    said(s, ggSceneAddPolygon(s, 0, big, 3), "ggSceneAddPolygon", "over 1e+64");
    said(s, ggSceneAddTriangle(s, 0, tri, nan3), "ggSceneAddTriangle", "normal 1 must be finite");
    said(s, ggSceneAddTriangle(s, 7, tri, NULL), "ggSceneAddTriangle", "no material 7");
    said(s, ggSceneAddCone(s, 0, o, 1, inf, 1), "ggSceneAddCone", "the apex must be finite");
    said(s, ggSceneAddCone(s, 0, o, 0, x, 0), "ggSceneAddCone", "got 0 and 0");
    said(s, ggSceneAddCone(s, 0, o, -1, x, 1), "ggSceneAddCone", "got -1 and 1");
    said(s, ggSceneAddCone(s, 0, x, 1, x, 1), "ggSceneAddCone", "one point");
    said(s, ggSceneAddRect(s, 0, o, x, (ggVec3){2, 0, 0}), "ggSceneAddRect", "parallel");
    said(s, ggSceneAddRect(s, 0, o, inf, y), "ggSceneAddRect", "e1 must be finite");
    said(s, ggSceneAddImplicit(s, 0, NULL), "ggSceneAddImplicit", "NULL implicit surface");
    assert_int_equal(ggSceneObjectCount(s), 0);
    assert_int_equal(ggSceneTextureCount(s), 0);
    said(s, ggSceneAddSphere(s, 0, o, 1), NULL, NULL);
    said(s, ggSceneAddPolygon(s, 0, tri, 3), NULL, NULL);
    said(s, ggSceneAddCone(s, 0, o, 1, x, 0), NULL, NULL);
    said(s, ggSceneAddRect(s, 0, o, x, y), NULL, NULL);
    said(s, ggSceneAddChecker(s, 4, white, white), NULL, NULL);
    assert_int_equal(ggSceneObjectCount(s), 4);
    ggSceneFree(s);
}

/* Out of memory in a building call: -GG_ERROR_NOMEM, and
   ggSceneLastError says what ran out; the allocation after it works. */
static void test_last_error_nomem(void **state)
{
    tu_failer f;
    ggScene *s;
    ggMaterial m = ggMaterialDefault();
    const ggVec3 tri[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const ggColor white = {1, 1, 1};
    int rc;
    (void)state;
    tu_failer_init(&f);
    s = ggSceneCreate(&f.alloc);
    assert_non_null(s);
    tu_failer_arm(&f, 1);
    rc = ggSceneAddMaterial(s, &m);
    said(s, rc, "ggSceneAddMaterial", "out of memory");
    tu_failer_arm(&f, 1);
    said(s, ggSceneAddLight(s, (ggVec3){0, 0, 1}, white), "ggSceneAddLight", "out of memory");
    tu_failer_stop(&f);
    assert_int_equal(ggSceneAddMaterial(s, &m), 0);
    tu_failer_arm(&f, 1);
    said(s, ggSceneAddPolygon(s, 0, tri, 3), "ggSceneAddPolygon", "out of memory");
    tu_failer_arm(&f, 2);
    said(s, ggSceneAddPolygon(s, 0, tri, 3), "ggSceneAddPolygon", "out of memory");
    tu_failer_arm(&f, 1);
    said(s, ggSceneAddChecker(s, 4, white, white), "ggSceneAddChecker", "out of memory");
    tu_failer_stop(&f);
    assert_int_equal(ggSceneObjectCount(s), 0);
    said(s, ggSceneAddPolygon(s, 0, tri, 3), NULL, NULL);
    ggSceneFree(s);
    tu_failer_done(&f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_nff_material),
        cmocka_unit_test(test_nff_upper_bounds),
        cmocka_unit_test(test_bounds_render_finite),
        cmocka_unit_test(test_nff_conductor),
        cmocka_unit_test(test_nff_lights_background),
        cmocka_unit_test(test_nff_camera),
        cmocka_unit_test(test_api_material),
        cmocka_unit_test(test_api_checker),
        cmocka_unit_test(test_dispersion_indices),
        cmocka_unit_test(test_api_lights_background),
        cmocka_unit_test(test_api_camera),
        cmocka_unit_test(test_accepted_renders_finite),
        cmocka_unit_test(test_settings_keep_effects),
        cmocka_unit_test(test_last_error),
        cmocka_unit_test(test_last_error_nomem),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
