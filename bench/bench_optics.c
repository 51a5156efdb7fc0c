/* SPDX-License-Identifier: MIT */
/*
** bench_optics.c -- `make bench-optics`: nanoseconds per call of the
** accurate refraction against the textbook formula, and of the Fresnel
** variants. Not a test: it only prints its figures.
**
** Each function runs over the same 4096 precomputed inputs, 200 times
** (819200 calls), results summed into a volatile sink so nothing is
** optimised away; the best of 5 such runs is reported (the least
** disturbed by other processes). Runs in about 3 s.
*/
#include "core.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Instruction counts: under valgrind --tool=callgrind (bench/optics_counts.sh)
   `bench_optics --count` dumps the counts of each kernel separately. */
#if defined(__has_include)
#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#define GG_COUNT(name, k, in)                                                                      \
    do {                                                                                           \
        CALLGRIND_ZERO_STATS;                                                                      \
        sink += k(in, NIN);                                                                        \
        CALLGRIND_DUMP_STATS_AT(name);                                                             \
    } while (0)
#endif
#endif
#ifndef GG_COUNT
#define GG_COUNT(name, k, in) (sink += k(in, NIN))
#endif

#define NIN    4096
#define REPS   200
#define TRIALS 5

typedef struct input {
    ggVec3 v, n;
    double ni, nt, c;
} input;

static input rnd[NIN], hard[NIN];
static volatile double sink;

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static double uniform(void)
{
    uint64_t z = (rng_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return (double)(z >> 11) * 0x1.0p-53;
}
static ggVec3 unit_rand(void)
{
    double z = 2 * uniform() - 1, phi = 2 * GG_PI * uniform(), s = sqrt(1 - z * z);
    ggVec3 v;
    v.x = s * cos(phi), v.y = s * sin(phi), v.z = z;
    return v;
}
/* Unit direction towards the surface with unit normal n at cosine c. */
static ggVec3 incoming(ggVec3 n, double c)
{
    ggVec3 a = unit_rand(), u, v;
    double d = a.x * n.x + a.y * n.y + a.z * n.z, l, s = sqrt((1 - c) * (1 + c));
    u.x = a.x - d * n.x, u.y = a.y - d * n.y, u.z = a.z - d * n.z;
    l = sqrt(u.x * u.x + u.y * u.y + u.z * u.z);
    v.x = -c * n.x + s * u.x / l, v.y = -c * n.y + s * u.y / l, v.z = -c * n.z + s * u.z / l;
    return v;
}

static void make_inputs(void)
{
    static const double idx[] = {1.0, 1.33, 1.5, 2.42};
    int i;
    for (i = 0; i < NIN; i++) {
        input *r = &rnd[i], *h = &hard[i];
        r->n = unit_rand();
        r->c = uniform();
        r->v = incoming(r->n, r->c);
        r->ni = idx[i % 4], r->nt = idx[(i / 4) % 4];
        /* hard: grazing with eta near 1, or within 1e-9 of the critical angle */
        h->n = unit_rand();
        if (i % 2) {
            h->ni = 1.5, h->nt = 1.5 * (1 + 1e-12 * (i % 7));
            h->c = pow(10.0, -1 - 15 * uniform());
        } else {
            h->ni = idx[1 + i % 3], h->nt = 1.0;
            h->c = sqrt(1 - 1 / (h->ni * h->ni)) * (1 + 1e-9 * (uniform() - 0.5));
        }
        h->v = incoming(h->n, h->c);
    }
}

/* One timed run over the inputs; returns ns per call. */
typedef double (*kernel)(const input *in, int n);

static double k_refract(const input *in, int n)
{
    double s = 0;
    int i;
    ggVec3 t;
    for (i = 0; i < n; i++) {
        ggRefract(in[i].v, in[i].n, in[i].ni, in[i].nt, &t);
        s += t.x + t.y + t.z;
    }
    return s;
}
static double k_textbook(const input *in, int n)
{
    double s = 0;
    int i;
    ggVec3 t;
    for (i = 0; i < n; i++) {
        ggRefractTextbook(in[i].v, in[i].n, in[i].ni, in[i].nt, &t);
        s += t.x + t.y + t.z;
    }
    return s;
}
static double k_reflect(const input *in, int n)
{
    double s = 0;
    int i;
    for (i = 0; i < n; i++) {
        ggVec3 r = ggReflection(in[i].v, in[i].n);
        s += r.x + r.y + r.z;
    }
    return s;
}
/* The plain r = v - 2 (v.n) n, inline, for scale. */
static double k_reflect_plain(const input *in, int n)
{
    double s = 0;
    int i;
    for (i = 0; i < n; i++) {
        ggVec3 v = in[i].v, m = in[i].n;
        double d = 2 * (v.x * m.x + v.y * m.y + v.z * m.z);
        s += (v.x - d * m.x) + (v.y - d * m.y) + (v.z - d * m.z);
    }
    return s;
}
static double k_fresnel(const input *in, int n)
{
    double s = 0;
    int i;
    for (i = 0; i < n; i++) s += ggFresnelDielectric(in[i].c, in[i].ni, in[i].nt);
    return s;
}
/* The textbook unpolarised Fresnel, inline, for scale. */
static double k_fresnel_plain(const input *in, int n)
{
    double s = 0;
    int i;
    for (i = 0; i < n; i++) {
        double c = in[i].c, ni = in[i].ni, nt = in[i].nt, e = ni / nt;
        double k = 1 - e * e * (1 - c * c), ct, rs, rp;
        if (k <= 0) {
            s += 1;
            continue;
        }
        ct = sqrt(k);
        rs = (ni * c - nt * ct) / (ni * c + nt * ct);
        rp = (nt * c - ni * ct) / (nt * c + ni * ct);
        s += 0.5 * (rs * rs + rp * rp);
    }
    return s;
}
static double k_schlick(const input *in, int n)
{
    double s = 0;
    int i;
    for (i = 0; i < n; i++) s += ggFresnelSchlick(in[i].c, in[i].ni, in[i].nt);
    return s;
}
/* Conductor inputs: metal-like n + ik from the random indices; the hard
   ones are the refraction's hard cases (grazing between nearly matched
   indices, near critical) with a tiny k. */
static double cond_n(const input *in, int hard_set)
{
    return hard_set ? in->nt : in->ni * 0.1;
}
static double cond_k(const input *in, int hard_set)
{
    return hard_set ? 1e-9 : in->nt * 2;
}
static double cond_n1(const input *in, int hard_set)
{
    return hard_set ? in->ni : 1.0;
}
static double conductor_set(const input *in, int n, int hard_set)
{
    double s = 0;
    int i;
    for (i = 0; i < n; i++)
        s += ggFresnelConductor(in[i].c, cond_n1(&in[i], hard_set), cond_n(&in[i], hard_set),
                                cond_k(&in[i], hard_set));
    return s;
}
static double k_conductor(const input *in, int n)
{
    return conductor_set(in, n, 0);
}
static double k_conductor_hard(const input *in, int n)
{
    return conductor_set(in, n, 1);
}
/* The textbook conductor Fresnel in plain double complex arithmetic, inline
   (eta = (n + ik)/n1, z = sqrt(eta^2 - sin^2), rs = (c - z)/(c + z),
   rp = (eta^2 c - z)/(eta^2 c + z)), for scale. */
static double textbook_conductor(double c, double n1, double n, double k)
{
    double er = n / n1, ei = k / n1, e2r = er * er - ei * ei, e2i = 2 * er * ei;
    double xr = e2r - (1 - c * c), m = sqrt(xr * xr + e2i * e2i), za, zb, pr, pi, rs, rp;
    za = sqrt(0.5 * (m + xr)), zb = za > 0 ? e2i / (2 * za) : sqrt(0.5 * (m - xr));
    rs = ((c - za) * (c - za) + zb * zb) / ((c + za) * (c + za) + zb * zb);
    pr = e2r * c, pi = e2i * c;
    rp = ((pr - za) * (pr - za) + (pi - zb) * (pi - zb)) /
         ((pr + za) * (pr + za) + (pi + zb) * (pi + zb));
    return 0.5 * (rs + rp);
}
static double conductor_plain_set(const input *in, int n, int hard_set)
{
    double s = 0;
    int i;
    for (i = 0; i < n; i++)
        s += textbook_conductor(in[i].c, cond_n1(&in[i], hard_set), cond_n(&in[i], hard_set),
                                cond_k(&in[i], hard_set));
    return s;
}
static double k_conductor_plain(const input *in, int n)
{
    return conductor_plain_set(in, n, 0);
}
static double k_conductor_plain_hard(const input *in, int n)
{
    return conductor_plain_set(in, n, 1);
}
static double k_beer(const input *in, int n)
{
    double s = 0;
    int i;
    for (i = 0; i < n; i++) s += ggBeerLambert(1e-8 * in[i].ni, 650e-9, in[i].c);
    return s;
}

static double time_kernel(kernel k, const input *in)
{
    double best = 1e300;
    int trial, r;
    sink += k(in, NIN); /* warm up */
    for (trial = 0; trial < TRIALS; trial++) {
        double t0 = gg_time_now(), dt;
        for (r = 0; r < REPS; r++) sink += k(in, NIN);
        dt = gg_time_now() - t0;
        if (dt < best) best = dt;
    }
    return best * 1e9 / ((double)NIN * REPS);
}

static double row(const char *name, kernel k, const input *in, double base)
{
    double t = time_kernel(k, in);
    printf("%-50s %8.1f %10.2f\n", name, t, base > 0 ? t / base : 1.0);
    return t;
}

/* One pass of each kernel, each dumped on its own (see GG_COUNT). */
static void count_kernels(void)
{
    GG_COUNT("textbook random", k_textbook, rnd);
    GG_COUNT("refract random", k_refract, rnd);
    GG_COUNT("textbook hard", k_textbook, hard);
    GG_COUNT("refract hard", k_refract, hard);
    GG_COUNT("reflect_inline random", k_reflect_plain, rnd);
    GG_COUNT("reflect random", k_reflect, rnd);
    GG_COUNT("reflect_inline hard", k_reflect_plain, hard);
    GG_COUNT("reflect hard", k_reflect, hard);
    GG_COUNT("fresnel_inline random", k_fresnel_plain, rnd);
    GG_COUNT("fresnel random", k_fresnel, rnd);
    GG_COUNT("fresnel_inline hard", k_fresnel_plain, hard);
    GG_COUNT("fresnel hard", k_fresnel, hard);
    GG_COUNT("conductor_inline random", k_conductor_plain, rnd);
    GG_COUNT("conductor random", k_conductor, rnd);
    GG_COUNT("conductor_inline hard", k_conductor_plain_hard, hard);
    GG_COUNT("conductor hard", k_conductor_hard, hard);
}

int main(int argc, char **argv)
{
    double base, t0 = gg_time_now();
    make_inputs();
    if (argc > 1 && strcmp(argv[1], "--count") == 0) {
        count_kernels();
        return 0;
    }
    printf("bench-optics: ns per call, best of %d runs of %d calls each\n", TRIALS, NIN * REPS);
    printf("(ggRefract and ggReflection take their fma build where the CPU has fma: %s)\n\n",
           gg_cpu_features() & GG_CPU_FMA ? "yes" : "no");
    printf("%-50s %8s %10s\n", "function (inputs)", "ns/call", "x textbook");
    base = row("ggRefractTextbook (random)", k_textbook, rnd, 0);
    row("ggRefract, accurate (random)", k_refract, rnd, base);
    row("ggRefractTextbook (grazing / near critical)", k_textbook, hard, base);
    row("ggRefract, accurate (grazing / near critical)", k_refract, hard, base);
    printf("\n%-50s %8s %10s\n", "", "ns/call", "x plain");
    base = row("v - 2 (v.n) n, inline (random)", k_reflect_plain, rnd, 0);
    row("ggReflection (random)", k_reflect, rnd, base);
    base = row("v - 2 (v.n) n, inline (grazing / near critical)", k_reflect_plain, hard, 0);
    row("ggReflection (grazing / near critical)", k_reflect, hard, base);
    base = row("textbook Fresnel, inline (random)", k_fresnel_plain, rnd, 0);
    row("ggFresnelDielectric, exact (random)", k_fresnel, rnd, base);
    row("ggFresnelSchlick (random)", k_schlick, rnd, base);
    row("ggBeerLambert (random)", k_beer, rnd, base);
    base = row("textbook Fresnel, inline (grazing / near critical)", k_fresnel_plain, hard, 0);
    row("ggFresnelDielectric, exact (grazing / near critical)", k_fresnel, hard, base);
    printf("\n%-50s %8s %10s\n", "", "ns/call", "x plain");
    base = row("textbook conductor, inline (random metals)", k_conductor_plain, rnd, 0);
    row("ggFresnelConductor (random metals)", k_conductor, rnd, base);
    base = row("textbook conductor, inline (hard, k = 1e-9)", k_conductor_plain_hard, hard, 0);
    row("ggFresnelConductor (hard, k = 1e-9)", k_conductor_hard, hard, base);
    printf("\ntotal %.1f s (sink %g)\n", gg_time_now() - t0, (double)sink);
    return 0;
}
