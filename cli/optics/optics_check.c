/* SPDX-License-Identifier: MIT */
/*
** optics_check.c -- `ggrt optics check`: someone's refraction, reflection
** or Fresnel function (loaded with dlopen, or ggrt's own) against the exact
** values of ggRefractError and friends, over the hard-case classes of
** optics_cases.c; per class the worst error and the input that gave it.
** And `ggrt optics seeds DIR`: those cases as a seed corpus for
** examples/fuzz_your_refract.c.
*/
#include "common/cli.h"
#include "common/json.h"
#include "optics/optics_cases.h"
#include "optics/optics_check.h"

#include <dlfcn.h>
#include <errno.h>
#include <math.h>
#include <string.h>
#include <sys/stat.h>

#define TIR_BAND   0x1p-96 /* decisions this close to critical are not counted */

typedef bool (*refract_fn)(ggVec3, ggVec3, double, double, ggVec3 *);
typedef ggVec3 (*reflect_fn)(ggVec3, ggVec3);
typedef double (*fresnel_fn)(double, double, double);
typedef double (*conductor_fn)(double, double, double, double);

typedef struct chk {
    const char *lib, *symbol;
    int kind, cases, seed, format;
    double max_ulp;
    void *fn; /* one of the four function types, by kind */
} chk;

typedef struct cstat {
    long cases, tir_wrong, tir_band, nonfinite, uncertain;
    long measured;         /* finite results measured: wi is one of them */
    double worst, worst_c; /* worst error (R or direction), worst 1 - R */
    oc_case wi, tir_i, nf_i;
} cstat;

static const char *const kinds[] = {"refract", "reflect", "fresnel", "conductor", NULL};
static const char *const own[] = {"ggRefract", "ggReflection", "ggFresnelDielectric",
                                  "ggFresnelConductor"};
static const char *const formats[] = {"text", "json", NULL};

static void *own_fn(int kind)
{
    refract_fn a = ggRefract;
    reflect_fn b = ggReflection;
    fresnel_fn c = ggFresnelDielectric;
    conductor_fn d = ggFresnelConductor;
    void *p = NULL;
    /* object and function pointers have the same size on POSIX (dlsym) */
    switch (kind) {
    case OC_REFRACT:
        memcpy(&p, &a, sizeof p);
        break;
    case OC_REFLECT:
        memcpy(&p, &b, sizeof p);
        break;
    case OC_FRESNEL:
        memcpy(&p, &c, sizeof p);
        break;
    default:
        memcpy(&p, &d, sizeof p);
        break;
    }
    return p;
}

/* One case: call the function, measure, count. */
static void run_direction(const chk *k, const oc_case *c, cstat *s)
{
    ggDirectionError e;
    ggVec3 t = {NAN, NAN, NAN};
    int rc;
    if (k->kind == OC_REFRACT) {
        refract_fn f;
        bool ok;
        memcpy(&f, &k->fn, sizeof f);
        ok = f(c->v, c->n, c->ni, c->nt, &t);
        rc = ggRefractError(c->v, c->n, c->ni, c->nt, t, !ok, &e);
    } else {
        reflect_fn f;
        memcpy(&f, &k->fn, sizeof f);
        t = f(c->v, c->n);
        rc = ggReflectionError(c->v, c->n, t, &e);
    }
    if (rc != GG_OK) return;
    s->cases++;
    if (!e.finite && !s->nonfinite++) s->nf_i = *c;
    if (!e.certain) {
        s->uncertain++;
    } else if (!e.tir_agrees) {
        if (fabs(e.cos2_t) <= TIR_BAND) {
            s->tir_band++;
        } else {
            if (!s->tir_wrong++) s->tir_i = *c;
            return;
        }
    }
    if (e.finite && (!s->measured++ || !(e.max_ulp <= s->worst))) s->worst = e.max_ulp, s->wi = *c;
}

static void run_reflectance(const chk *k, const oc_case *c, cstat *s)
{
    ggReflectanceError e;
    int rc;
    if (k->kind == OC_FRESNEL) {
        fresnel_fn f;
        memcpy(&f, &k->fn, sizeof f);
        rc = ggFresnelDielectricError(c->c, c->ni, c->nt, f(c->c, c->ni, c->nt), &e);
    } else {
        conductor_fn f;
        memcpy(&f, &k->fn, sizeof f);
        rc = ggFresnelConductorError(c->c, c->ni, c->nt, c->k, f(c->c, c->ni, c->nt, c->k), &e);
    }
    if (rc != GG_OK) return;
    s->cases++;
    if (!e.finite) {
        if (!s->nonfinite++) s->nf_i = *c;
        return;
    }
    if (!s->measured++ || !(e.ulp <= s->worst)) s->worst = e.ulp, s->wi = *c;
    if (!(e.complement_ulp <= s->worst_c)) s->worst_c = e.complement_ulp;
}

/* The input as C hex floats, in the function's argument order. */
static void print_input(FILE *f, int kind, const oc_case *c, int json)
{
    const char *q = json ? "\"" : "";
    if (kind == OC_REFRACT || kind == OC_REFLECT) {
        fprintf(f, "%sv={%a, %a, %a} n={%a, %a, %a}", q, c->v.x, c->v.y, c->v.z, c->n.x, c->n.y,
                c->n.z);
        if (kind == OC_REFRACT) fprintf(f, " ni=%a nt=%a", c->ni, c->nt);
    } else {
        fprintf(f, "%scos_i=%a %s=%a %s=%a", q, c->c, kind == OC_FRESNEL ? "ni" : "n_outside",
                c->ni, kind == OC_FRESNEL ? "nt" : "n", c->nt);
        if (kind == OC_CONDUCTOR) fprintf(f, " k=%a", c->k);
    }
    fputs(q, f);
}

static int failed(const chk *k, const cstat *s)
{
    return !(s->worst <= k->max_ulp) || s->tir_wrong || s->nonfinite;
}

static void print_num(double x, int json)
{
    if (json && !isfinite(x))
        fputs("null", stdout);
    else
        printf(json ? "%.6g" : "%11.4g", x);
}

static void print_text(const chk *k, const char *const *names, const cstat *st, int bad)
{
    int i, dir = k->kind == OC_REFRACT || k->kind == OC_REFLECT;
    double worst = 0;
    long tir = 0, nf = 0;
    printf("%-22s %6s %11s %11s %9s %10s\n", "class", "cases", "worst ulp",
           dir ? "TIR wrong" : "1-R ulp", dir ? "in band" : "", "non-finite");
    for (i = 0; names[i]; i++) {
        const cstat *s = &st[i];
        printf("%-22s %6ld ", names[i], s->cases);
        if (s->measured)
            print_num(s->worst, 0);
        else
            printf("%11s", "-");
        if (dir)
            printf(" %11ld %9ld", s->tir_wrong, s->tir_band);
        else
            printf(" "), print_num(s->worst_c, 0), printf(" %9s", "");
        printf(" %10ld%s\n", s->nonfinite, failed(k, s) ? "  FAIL" : "");
        if (!(s->worst <= worst)) worst = s->worst;
        tir += s->tir_wrong, nf += s->nonfinite;
    }
    printf("\nworst input of each class (hex floats, the function's argument order):\n");
    for (i = 0; names[i]; i++) {
        printf("  %-20s ", names[i]);
        if (st[i].measured)
            print_input(stdout, k->kind, &st[i].wi, 0);
        else
            printf("none: no finite result");
        printf("\n");
        if (st[i].tir_wrong) {
            printf("  %-20s ", "  first TIR wrong");
            print_input(stdout, k->kind, &st[i].tir_i, 0);
            printf("\n");
        }
        if (st[i].nonfinite) {
            printf("  %-20s ", "  first non-finite");
            print_input(stdout, k->kind, &st[i].nf_i, 0);
            printf("\n");
        }
    }
    if (k->kind == OC_REFRACT)
        printf("TIR decisions with |cos^2 theta_t| <= 2^-96 (where even a double-double\n"
               "decision may differ from the exact one) are counted 'in band', not wrong.\n");
    if (!dir) printf("1 - R is informative: a double R near 1 cannot carry 1 - R to 1 ulp.\n");
    printf("%s: worst %.4g ulp %s --max-ulp %g; %ld TIR disagreements; %ld non-finite\n",
           bad ? "FAIL" : "PASS", worst, worst <= k->max_ulp ? "<=" : ">", k->max_ulp, tir, nf);
}

static void print_json(const chk *k, const char *const *names, const cstat *st, int bad)
{
    int i;
    printf("{\"kind\": \"%s\", \"function\": \"%s\", \"library\": ", kinds[k->kind], k->symbol);
    if (k->lib)
        json_str(stdout, k->lib);
    else
        printf("null");
    printf(", \"cases_per_class\": %d, \"seed\": %d, \"max_ulp\": %.17g, \"tir_band\": %.17g,"
           "\n \"classes\": [",
           k->cases, k->seed, k->max_ulp, TIR_BAND);
    for (i = 0; names[i]; i++) {
        const cstat *s = &st[i];
        printf("%s\n  {\"name\": \"%s\", \"cases\": %ld, \"worst_ulp\": ", i ? "," : "", names[i],
               s->cases);
        print_num(s->measured ? s->worst : NAN, 1);
        if (k->kind == OC_FRESNEL || k->kind == OC_CONDUCTOR) {
            printf(", \"worst_complement_ulp\": ");
            print_num(s->worst_c, 1);
        }
        printf(", \"tir_wrong\": %ld, \"tir_in_band\": %ld, \"nonfinite\": %ld, "
               "\"reference_undecided\": %ld, \"pass\": %s, \"worst_input\": ",
               s->tir_wrong, s->tir_band, s->nonfinite, s->uncertain,
               failed(k, s) ? "false" : "true");
        if (s->measured)
            print_input(stdout, k->kind, &s->wi, 1);
        else
            printf("null");
        if (s->tir_wrong)
            printf(", \"first_tir_wrong\": "), print_input(stdout, k->kind, &s->tir_i, 1);
        if (s->nonfinite)
            printf(", \"first_nonfinite\": "), print_input(stdout, k->kind, &s->nf_i, 1);
        printf("}");
    }
    printf("\n ],\n \"pass\": %s}\n", bad ? "false" : "true");
}

static int run(chk *k)
{
    const char *const *names = oc_classes(k->kind);
    cstat st[16];
    oc_rng r;
    int n, bad = 0;
    long j;
    memset(st, 0, sizeof st);
    for (n = 0; names[n]; n++) {
        r.s = 0x9e3779b97f4a7c15ULL ^ ((uint64_t)k->seed * 1000003 + (uint64_t)n);
        for (j = 0; j < k->cases; j++) {
            oc_case c;
            oc_make(k->kind, n, &r, &c);
            if (k->kind == OC_REFRACT || k->kind == OC_REFLECT)
                run_direction(k, &c, &st[n]);
            else
                run_reflectance(k, &c, &st[n]);
        }
        bad |= failed(k, &st[n]);
    }
    if (k->format == 1) {
        print_json(k, names, st, bad);
    } else {
        printf("ggrt optics check: %s, %s%s%s, %d cases a class, seed %d\n", kinds[k->kind],
               k->symbol, k->lib ? " from " : " (ggrt's own)", k->lib ? k->lib : "", k->cases,
               k->seed);
        print_text(k, names, st, bad);
    }
    return bad ? EXIT_CHECK : EXIT_OK;
}

static const char about_check[] =
    "Measures a reflection, refraction or Fresnel function against the exact\n"
    "values (ggRefractError and friends, 512-bit reference) on classes of hard\n"
    "inputs, and prints per class the worst error in ulps with the input that\n"
    "gave it (hex floats, ready to paste into a test), wrong total-internal-\n"
    "reflection decisions and non-finite results. The function is NAME in the\n"
    "shared library PATH, with the signature of ggRefract (refract),\n"
    "ggReflection (reflect), ggFresnelDielectric (fresnel) or\n"
    "ggFresnelConductor (conductor); without --lib, ggrt's own.";
static const char tail_check[] =
    "Classes (refract): random, grazing (cos = 2^-k), grazing exact dot, near\n"
    "critical (+-2000 ulp of the critical angle), eta near 1, normal incidence,\n"
    "negative index, exactly tangent, huge and tiny, non-unit (all with |eta| in\n"
    "[1/4, 4]), extreme eta, tiny normal part, every exponent, any index ratio\n"
    "(every exponent of every component and index), huge eta, tilted (eta up to\n"
    "2^62 near its critical angle, v near a normal off every axis). The other\n"
    "kinds' classes:\n"
    "docs/optics.md, \"ggrt optics check\".\n"
    "Example:\n"
    "ggrt optics check --lib build/libtextbook_refract.so --symbol textbook_refract\n"
    "exit: 0 pass, 4 fail (an error above --max-ulp, a wrong TIR decision or a\n"
    "non-finite result), 1 usage, 2 library or symbol not found, 3 output error";

int cli_optics_check(int argc, char **argv)
{
    chk k;
    const char *symbol = NULL;
    int rc;
    cli_opt opts[] = {
        CLI_OPT_STRING(0, "lib", &k.lib, "PATH",
                       "shared library with the function (default: ggrt)"),
        CLI_OPT_STRING(0, "symbol", &symbol, "NAME",
                       "the function's name (default: ggrt's, e.g. ggRefract)"),
        CLI_OPT_CHOICE(0, "kind", &k.kind, kinds, "KIND",
                       "refract (default), reflect, fresnel or conductor"),
        CLI_OPT_INT(0, "cases", &k.cases, 1, 10000000, "N", "cases per class (default 2000)"),
        CLI_OPT_INT(0, "seed", &k.seed, 0, 2147483647, "S", "random seed (default 1)"),
        CLI_OPT_DOUBLE(0, "max-ulp", &k.max_ulp, 0, HUGE_VAL, "U",
                       "the bound each class must meet (default 1)"),
        CLI_OPT_CHOICE('f', "format", &k.format, formats, "F", "text (default) or json"),
        CLI_OPT_END,
    };
    cli_cmd cmd = {.name = "optics check",
                   .usage = "[--lib PATH --symbol NAME] [--kind KIND] [--cases N]\n"
                            "                         [--seed S] [--max-ulp U] [--format text|json]",
                   .about = about_check,
                   .tail = tail_check,
                   .opts = {opts}};
    memset(&k, 0, sizeof k);
    k.cases = 2000, k.seed = 1, k.max_ulp = 1;
    if ((rc = cli_parse(&cmd, argc, argv)) != CLI_GO) return rc;
    k.symbol = symbol ? symbol : own[k.kind];
    if (!k.lib) {
        if (symbol && strcmp(symbol, own[k.kind]) != 0)
            return cli_usage_error(&cmd, "--symbol needs --lib (without it: %s)", own[k.kind]);
        k.fn = own_fn(k.kind);
    } else {
        struct stat st;
        void *h;
        /* dlopen of a FIFO waits for a writer: a path that names something
           other than a regular file is refused first (a bare name is
           looked up by dlopen in the library path). */
        if (strchr(k.lib, '/') && stat(k.lib, &st) == 0 && !S_ISREG(st.st_mode)) {
            cli_error("%s: not a regular file", k.lib);
            return EXIT_IO;
        }
        h = dlopen(k.lib, RTLD_NOW | RTLD_LOCAL);
        if (!h) {
            /* A name without '/' is searched in the system's library
               paths, not here: say so when there is such a file here. */
            int here = !strchr(k.lib, '/') && stat(k.lib, &st) == 0;
            cli_error("%s%s%s%s", dlerror(),
                      here ? " (a name without '/' is looked up in the "
                             "library paths: give ./"
                           : "",
                      here ? k.lib : "", here ? " for the file here)" : "");
            return EXIT_INPUT;
        }
        k.fn = dlsym(h, k.symbol);
        if (!k.fn) {
            cli_error("%s: no symbol '%s'", k.lib, k.symbol);
            return EXIT_INPUT;
        }
    }
    return run(&k);
}

/* ---- ggrt optics seeds DIR ---------------------------------------- */

/* One seed in examples/fuzz_your_refract.c's format: a mode byte, the
   doubles v, n, ni, nt little-endian, a parameter byte. */
static int write_seed(const char *dir, const char *name, int idx, int mode, const oc_case *c,
                      int param)
{
    double d[8];
    unsigned char buf[66];
    char path[4096], base[64];
    cli_out o;
    int i, j, rc;
    d[0] = c->v.x, d[1] = c->v.y, d[2] = c->v.z, d[3] = c->n.x, d[4] = c->n.y, d[5] = c->n.z;
    d[6] = c->ni, d[7] = c->nt;
    buf[0] = (unsigned char)mode;
    for (i = 0; i < 8; i++) {
        uint64_t b;
        memcpy(&b, &d[i], sizeof b);
        for (j = 0; j < 8; j++) buf[1 + 8 * i + j] = (unsigned char)(b >> (8 * j));
    }
    buf[65] = (unsigned char)param;
    snprintf(base, sizeof base, "%s", name);
    for (i = 0; base[i]; i++)
        if (base[i] == ' ') base[i] = '-';
    snprintf(path, sizeof path, "%s/%s-%03d", dir, base, idx);
    /* Whole or not at all, as every output (a full disk left an empty
       seed, which a fuzzer would then run). */
    if ((rc = cli_out_open(&o, "optics seeds", path)) != 0) return rc;
    fwrite(buf, 1, sizeof buf, o.f);
    return cli_out_close(&o, "optics seeds");
}

int cli_optics_seeds(int argc, char **argv)
{
    const char *dir = NULL, *const *names = oc_classes(OC_REFRACT);
    int cases = 16, seed = 1, rc, n, i, count = 0;
    struct stat sb;
    cli_opt opts[] = {
        CLI_OPT_INT(0, "cases", &cases, 1, 100000, "N", "seeds per class (default 16)"),
        CLI_OPT_INT(0, "seed", &seed, 0, 2147483647, "S", "random seed (default 1)"),
        CLI_OPT_END,
    };
    cli_cmd cmd = {.name = "optics seeds",
                   .usage = "DIR [--cases N] [--seed S]",
                   .about = "Writes a seed corpus of hard refraction cases (the classes of\n"
                            "ggrt optics check, and inputs for each shaping mode) into DIR\n"
                            "(created if missing) for examples/fuzz_your_refract.c.",
                   .tail = "exit: 0 ok, 1 usage, 3 I/O error",
                   .opts = {opts},
                   .args = &dir,
                   .min_args = 1,
                   .max_args = 1,
                   .args_name = "directory"};
    if ((rc = cli_parse(&cmd, argc, argv)) != CLI_GO) return rc;
    if (stat(dir, &sb) != 0 && mkdir(dir, 0777) != 0) {
        cli_error("%s: %s", dir, strerror(errno));
        return EXIT_IO;
    }
    for (n = 0; names[n]; n++) {
        oc_rng r;
        r.s = 0x9e3779b97f4a7c15ULL ^ ((uint64_t)seed * 1000003 + (uint64_t)n);
        for (i = 0; i < cases; i++) {
            oc_case c;
            oc_make(OC_REFRACT, n, &r, &c);
            /* mode 0 replays the case as it is; the others reshape it */
            if ((rc = write_seed(dir, names[n], i,
                                 i < cases / 2 || i == 0 ? 0 : (int)(oc_next(&r) % 8), &c,
                                 (int)(oc_next(&r) & 255))) != 0)
                return rc;
            count++;
        }
    }
    printf("ggrt optics seeds: %d seeds in %s\n", count, dir);
    return EXIT_OK;
}
