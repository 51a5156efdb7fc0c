/* SPDX-License-Identifier: MIT */
/*
** fuzz_your_refract.c -- a libFuzzer harness for YOUR refraction function:
** it turns the fuzzer's bytes into hard cases (grazing, near critical, eta
** near 1, normal incidence, negative index, axis normals with exact dot
** products, huge and tiny magnitudes), measures your result with
** ggRefractError (the exact value for the given doubles) and aborts with
** the measured error when it exceeds the bound. docs/optics.md has the
** recipe; in short, for a function
**     bool my_refract(ggVec3 v, ggVec3 n, double ni, double nt, ggVec3 *t);
** (ggRefract's signature: true if transmitted; *t the unit direction):
**
**   clang -g -O1 -fsanitize=fuzzer -DUSER_REFRACT=my_refract \
**     fuzz_your_refract.c my_refract.c $(pkg-config --cflags --libs ggrt) -o fuzz_my_refract
**   ggrt optics seeds corpus
**   ./fuzz_my_refract -max_total_time=60 corpus
**
** Knobs (-D...): USER_REFRACT (default ggRefract), MAX_ULP (1), MAX_ULP_NEAR
** (4: the bound where the transmitted ray is within 2^-40 rad of the
** surface, ggRefract's documented exception), ETA_MAX (4: inputs with
** |ni/nt| outside [1/ETA_MAX, ETA_MAX] are skipped).
**
** Input: a mode byte, then up to 8 little-endian doubles v.x v.y v.z n.x
** n.y n.z ni nt (missing ones keep the defaults below), then a parameter
** byte for the mode. Inputs with a non-zero component below 2^-480 of its
** vector's largest are skipped (ggRefract documents that it treats them as
** zero). Wrong total-internal-reflection decisions count outside
** |cos^2 theta_t| <= 2^-96, where even ggRefract's double-double decision
** may differ from the exact one.
*/
#include <ggrt.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef USER_REFRACT
#define USER_REFRACT ggRefract
#else
bool USER_REFRACT(ggVec3 v, ggVec3 n, double ni, double nt, ggVec3 *t);
#endif
#ifndef MAX_ULP
#define MAX_ULP 1.0
#endif
#ifndef MAX_ULP_NEAR
#define MAX_ULP_NEAR 4.0
#endif
#ifndef ETA_MAX
#define ETA_MAX 4.0
#endif
#define TIR_BAND 0x1p-96

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

typedef struct input {
    ggVec3 v, n;
    double ni, nt;
} input;

static ggVec3 vec(double x, double y, double z)
{
    ggVec3 a;
    a.x = x, a.y = y, a.z = z;
    return a;
}
static double dot(ggVec3 a, ggVec3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
static ggVec3 scale(ggVec3 a, double s)
{
    return vec(a.x * s, a.y * s, a.z * s);
}
static double maxabs(ggVec3 a)
{
    return fmax(fmax(fabs(a.x), fabs(a.y)), fabs(a.z));
}

/* The unit normal and the unit tangential direction of v; 0 if either is
   degenerate. */
static int frame(const input *in, ggVec3 *nu, ggVec3 *u)
{
    double mn = maxabs(in->n), mv = maxabs(in->v), l, d;
    ggVec3 n = scale(in->n, 1 / mn), v = scale(in->v, 1 / mv);
    l = sqrt(dot(n, n));
    *nu = scale(n, 1 / l);
    d = dot(v, *nu);
    *u = vec(v.x - d * nu->x, v.y - d * nu->y, v.z - d * nu->z);
    l = sqrt(dot(*u, *u));
    if (!(l > 1e-300) || !isfinite(l)) return 0;
    *u = scale(*u, 1 / l);
    return 1;
}

/* v := -c n + sqrt(1 - c^2) u: incidence cosine c. */
static int at_cosine(input *in, double c)
{
    ggVec3 nu, u;
    double s = sqrt((1 - c) * (1 + c));
    if (!frame(in, &nu, &u)) return 0;
    in->v = vec(-c * nu.x + s * u.x, -c * nu.y + s * u.y, -c * nu.z + s * u.z);
    return 1;
}

/* Bend the raw input towards one kind of hard case. */
static int shape(input *in, int mode, int p)
{
    double t, vc[3];
    int ax;
    switch (mode % 8) {
    case 1:
        return at_cosine(in, ldexp(1.0, -(1 + p % 60))); /* grazing */
    case 2:                                              /* near the critical angle */
        if (fabs(in->ni) < fabs(in->nt)) t = in->ni, in->ni = in->nt, in->nt = t;
        t = fabs(in->nt / in->ni) * (1 + (p - 128) * 16 * 0x1p-53);
        return t < 1 && at_cosine(in, sqrt((1 - t) * (1 + t)));
    case 3:
        in->nt = in->ni * (1 + (p - 128) * 0x1p-52);
        return 1; /* eta near 1 */
    case 4:
        return at_cosine(in, 1 - ldexp(1.0, -(20 + p % 40))); /* near normal */
    case 5:
        in->nt = -in->nt;
        return 1; /* negative index */
    case 6:       /* axis normal, exact dot */
        ax = p % 3;
        vc[0] = in->v.x, vc[1] = in->v.y, vc[2] = in->v.z;
        vc[ax] = -ldexp(1.0, -((p / 3) % 60));
        in->v = vec(vc[0], vc[1], vc[2]);
        in->n = vec(ax == 0, ax == 1, ax == 2);
        return 1;
    case 7: /* huge and tiny */
        in->v = scale(in->v, ldexp(1.0, (p % 16 - 8) * 120));
        in->n = scale(in->n, ldexp(1.0, (p / 16 - 8) * 120));
        return 1;
    default:
        return 1;
    }
}

/* Finite, non-zero, in the eta range, no component ggRefract flushes. */
static int acceptable(const input *in)
{
    const ggVec3 *w[2];
    int i;
    w[0] = &in->v, w[1] = &in->n;
    if (!isfinite(in->ni) || !isfinite(in->nt) || in->ni == 0 || in->nt == 0) return 0;
    if (fabs(in->ni) > ETA_MAX * fabs(in->nt) || fabs(in->nt) > ETA_MAX * fabs(in->ni)) return 0;
    for (i = 0; i < 2; i++) {
        double m = maxabs(*w[i]), c[3];
        int j;
        if (!isfinite(w[i]->x + w[i]->y + w[i]->z) || m == 0) return 0;
        c[0] = w[i]->x, c[1] = w[i]->y, c[2] = w[i]->z;
        for (j = 0; j < 3; j++)
            if (c[j] != 0 && fabs(c[j]) < 0x1p-480 * m) return 0;
    }
    return 1;
}

static void fail(const char *what, const input *in, ggVec3 t, bool ok, const ggDirectionError *e)
{
    fprintf(stderr,
            "fuzz_your_refract: %s: error %.6g ulp (bound %g)\n"
            "  input:     v={%a, %a, %a} n={%a, %a, %a} ni=%a nt=%a\n"
            "  yours:     %s t={%a, %a, %a}\n"
            "  exact:     %s t={%a, %a, %a}, cos^2(theta_t) = %.6g\n",
            what, e->max_ulp, MAX_ULP, in->v.x, in->v.y, in->v.z, in->n.x, in->n.y, in->n.z, in->ni,
            in->nt, ok ? "transmitted" : "not transmitted", t.x, t.y, t.z,
            e->exact_tir == 0 ? "transmitted" : "not transmitted", e->exact.x, e->exact.y,
            e->exact.z, e->cos2_t);
    abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    double d[8] = {0.6, -0.8, 0, 0, 1, 0, 1, 1.5};
    input in;
    ggVec3 t = {NAN, NAN, NAN};
    ggDirectionError e;
    size_t i, j;
    bool ok;
    for (i = 0; i < 8 && 1 + 8 * i + 8 <= size; i++) {
        uint64_t b = 0;
        for (j = 0; j < 8; j++) b |= (uint64_t)data[1 + 8 * i + j] << (8 * j);
        memcpy(&d[i], &b, sizeof b);
    }
    in.v = vec(d[0], d[1], d[2]), in.n = vec(d[3], d[4], d[5]), in.ni = d[6], in.nt = d[7];
    if (!acceptable(&in)) return 0;
    if (!shape(&in, size ? data[0] : 0, size > 65 ? data[65] : 128) || !acceptable(&in)) return 0;
    ok = USER_REFRACT(in.v, in.n, in.ni, in.nt, &t);
    if (ggRefractError(in.v, in.n, in.ni, in.nt, t, !ok, &e) != GG_OK) return 0;
    if (!e.finite) fail("non-finite result", &in, t, ok, &e);
    if (e.certain && !e.tir_agrees && fabs(e.cos2_t) > TIR_BAND)
        fail("wrong total-internal-reflection decision", &in, t, ok, &e);
    if (e.tir_agrees &&
        e.max_ulp > (e.exact_tir == 0 && e.cos2_t < 0x1p-80 ? MAX_ULP_NEAR : MAX_ULP))
        fail("error above the bound", &in, t, ok, &e);
    return 0;
}
