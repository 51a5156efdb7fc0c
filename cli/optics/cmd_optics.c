/* SPDX-License-Identifier: MIT */
/*
** cmd_optics.c -- `ggrt optics`: one reflection, refraction, Fresnel or
** absorption evaluation, printed in full, for debugging one interaction.
**
**   ggrt optics refract --v X,Y,Z --n X,Y,Z [--ni N] [--nt N] [--textbook]
**   ggrt optics reflect --v X,Y,Z --n X,Y,Z
**   ggrt optics fresnel (--angle DEG | --cos C | --v X,Y,Z --n X,Y,Z)
**                       [--ni N] [--nt N] [--k K]
**   ggrt optics absorb  --k K --lambda L --distance D
**   ggrt optics check   [--lib PATH --symbol NAME] [--kind KIND] ...  (optics_check.c)
**   ggrt optics seeds   DIR                                          (optics_check.c)
*/
#include "common/cli.h"
#include "optics/optics_check.h"

#include <float.h>
#include <math.h>
#include <string.h>

#define PI     3.14159265358979323846
#define DEG(x) ((x) * (180.0 / PI))

/* Option flags: which options a form accepts. */
#define O_V        0x001
#define O_N        0x002
#define O_NI       0x004
#define O_NT       0x008
#define O_K        0x010
#define O_COS      0x020
#define O_ANGLE    0x040
#define O_LAMBDA   0x080
#define O_DISTANCE 0x100
#define O_TEXTBOOK 0x200

typedef struct opts {
    unsigned seen;
    ggVec3 v, n;
    double ni, nt, k, cos_i, angle, lambda, distance;
} opts;

static const char about_all[] =
    "forms:\n"
    "  refract  transmitted direction, angles, TIR, critical angle, Fresnel terms\n"
    "  reflect  mirror direction\n"
    "  fresnel  reflectance of a dielectric or (with --k) a conductor\n"
    "  absorb   Beer-Lambert transmittance of a path through an absorbing medium\n"
    "  check    a refraction, reflection or Fresnel function against the exact values\n"
    "  seeds    write a seed corpus of hard cases for examples/fuzz_your_refract.c";

/* Each form's --help: the usage line after "ggrt optics FORM ", then
   what it computes; the options come from the table in parse. */
static const char use_refract[] = "--v X,Y,Z --n X,Y,Z [--ni N] [--nt N] [--textbook]";
static const char about_refract[] =
    "Refracts v through a surface with normal n from index ni (v's side,\n"
    "default 1) into nt (default 1.5). A negative index is a metamaterial:\n"
    "the ray bends to the same side of the normal. Prints the transmitted\n"
    "direction (or, under total internal reflection, the mirror direction),\n"
    "the incidence and refraction angles, whether TIR occurred, the critical\n"
    "angle and the Fresnel terms Rs, Rp, R, T = 1 - R. --textbook also shows\n"
    "the textbook formula's result and how far it is from the accurate one.";
static const char tail_refract[] =
    "Example: ggrt optics refract --v 0.5,-0.866,0 --n 0,1,0 --ni 1 --nt 1.33";

static const char use_reflect[] = "--v X,Y,Z --n X,Y,Z";
static const char about_reflect[] =
    "Prints r = v - 2 n (v.n)/(n.n), the mirror image of v (same length), and\n"
    "the angle of incidence (= angle of reflection).";

static const char use_fresnel[] = "(--angle DEG | --cos C | --v X,Y,Z --n X,Y,Z)\n"
                                  "                           [--ni N] [--nt N] [--k K]";
static const char about_fresnel[] =
    "Fresnel reflectance for light arriving from index ni (default 1) on a\n"
    "medium of index nt (default 1.5) at the given angle of incidence. With\n"
    "--k the medium is a conductor of complex index nt + i k (nt >= 0, k >= 0;\n"
    "e.g. gold at 650 nm: --nt 0.14 --k 3.70). Prints Rs, Rp, R = (Rs+Rp)/2,\n"
    "T = 1 - R, Schlick's approximation, the critical and Brewster angles.";

static const char use_absorb[] = "--k K --lambda L --distance D";
static const char about_absorb[] =
    "Beer-Lambert: the fraction T = exp(-alpha D), alpha = 4 pi K / L, of light\n"
    "of vacuum wavelength L that survives a path of length D (same unit as L)\n"
    "in a medium with extinction coefficient K (the imaginary part of its\n"
    "index).";
static const char tail_absorb[] = "Example, red light through a metre of water:\n"
                                  "  ggrt optics absorb --k 1.76e-8 --lambda 650e-9 --distance 1";

static const char tail_all[] =
    "Directions are X,Y,Z (no spaces); they need not be unit length.\n"
    "exit: 0 ok (total internal reflection included), 1 usage (unknown or missing\n"
    "option, a value malformed or out of range: zero vector or index, |cos| > 1,\n"
    "negative k, ...), 2 a library or symbol that cannot be loaded (check), 3 I/O\n"
    "error (seeds), 4 a check failed (check)";

/* Parse argv[1..] (argv[0] is the form) into o with the options the form
   allows. Returns CLI_GO or the exit code. */
static int parse(const char *form, unsigned allowed, const char *usage, const char *about,
                 const char *tail, int argc, char **argv, opts *o)
{
    static const unsigned flags[] = {O_V,   O_N,     O_NI,     O_NT,       O_K,
                                     O_COS, O_ANGLE, O_LAMBDA, O_DISTANCE, O_TEXTBOOK};
    const double inf = HUGE_VAL;
    int textbook = 0, rc, i, n = 0;
    char name[32];
    cli_opt all[] = {
        CLI_OPT_VEC3(0, "v", &o->v, "X,Y,Z", "incoming direction (towards the surface)"),
        CLI_OPT_VEC3(0, "n", &o->n, "X,Y,Z", "surface normal, either way"),
        CLI_OPT_DOUBLE(0, "ni", &o->ni, -inf, inf, "N", "index on the incoming side (default 1)"),
        CLI_OPT_DOUBLE(0, "nt", &o->nt, -inf, inf, "N", "index on the far side (default 1.5)"),
        CLI_OPT_DOUBLE(0, "k", &o->k, 0, inf, "K",
                       "extinction coefficient: the imaginary part of the index"),
        CLI_OPT_DOUBLE(0, "cos", &o->cos_i, -1, 1, "C", "cosine of the angle of incidence"),
        CLI_OPT_DOUBLE(0, "angle", &o->angle, 0, 90, "DEG", "angle of incidence, degrees"),
        CLI_OPT_DOUBLE(0, "lambda", &o->lambda, -inf, inf, "L", "vacuum wavelength"),
        CLI_OPT_DOUBLE(0, "distance", &o->distance, 0, inf, "D", "path length, in the unit of L"),
        CLI_OPT_FLAG(0, "textbook", &textbook,
                     "also the textbook formula and its distance from\n"
                     "ggRefract's result"),
    };
    cli_opt mine[sizeof all / sizeof all[0] + 1];
    cli_cmd cmd = {.name = name, .usage = usage, .about = about, .tail = tail, .opts = {mine}};
    snprintf(name, sizeof name, "optics %s", form);
    for (i = 0; i < (int)(sizeof all / sizeof all[0]); i++)
        if (flags[i] & allowed) mine[n++] = all[i];
    mine[n] = (cli_opt)CLI_OPT_END;
    if ((rc = cli_parse(&cmd, argc, argv)) != CLI_GO) return rc;
    for (i = 0; i < (int)(sizeof all / sizeof all[0]); i++)
        if ((flags[i] & allowed) && cli_given(&cmd, all[i].name)) o->seen |= flags[i];
    return CLI_GO;
}

static int need(const opts *o, unsigned flags, const char *form, const char *names)
{
    if ((o->seen & flags) == flags) return 0;
    cli_error("%s required", names);
    fprintf(stderr, "(see 'ggrt optics %s --help')\n", form);
    return EXIT_USAGE;
}

/* A value the parser took but the form cannot: a usage error in the
   parser's words, with its hint. */
static int bad_value(const char *form, const char *value, const char *name, const char *expected)
{
    cli_error("bad value '%s' for %s: expected %s", value, name, expected);
    fprintf(stderr, "(see 'ggrt optics %s --help')\n", form);
    return EXIT_USAGE;
}

static int is_zero(ggVec3 a)
{
    return a.x == 0 && a.y == 0 && a.z == 0;
}
static double dot(ggVec3 a, ggVec3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

/* Angle between the line of a and the normal n, in [0, 90] degrees:
   atan2(|a x n|, |a.n|) is accurate at 0 and 90 degrees alike. Scaled
   first so no product overflows. */
static double angle_deg(ggVec3 a, ggVec3 n, double *cosine)
{
    double ma = fmax(fmax(fabs(a.x), fabs(a.y)), fabs(a.z));
    double mn = fmax(fmax(fabs(n.x), fabs(n.y)), fabs(n.z));
    ggVec3 w;
    double s, c, la, ln;
    a.x /= ma, a.y /= ma, a.z /= ma;
    n.x /= mn, n.y /= mn, n.z /= mn;
    w.x = a.y * n.z - a.z * n.y, w.y = a.z * n.x - a.x * n.z, w.z = a.x * n.y - a.y * n.x;
    la = sqrt(dot(a, a)), ln = sqrt(dot(n, n));
    s = sqrt(dot(w, w)) / (la * ln);
    c = fabs(dot(a, n)) / (la * ln);
    if (cosine) *cosine = c > 1 ? 1 : c;
    return DEG(atan2(s, c));
}

/* a.n with both scaled to unit maximum component, so it cannot overflow:
   only its sign is used. */
static double dot_sign(ggVec3 a, ggVec3 n)
{
    double ma = fmax(fmax(fabs(a.x), fabs(a.y)), fabs(a.z));
    double mn = fmax(fmax(fabs(n.x), fabs(n.y)), fabs(n.z));
    return (a.x / ma) * (n.x / mn) + (a.y / ma) * (n.y / mn) + (a.z / ma) * (n.z / mn);
}

static void print_vec(const char *label, ggVec3 a)
{
    printf("%-18s (%.17g, %.17g, %.17g)\n", label, a.x, a.y, a.z);
}

static void print_fresnel(double c, double ni, double nt)
{
    double rs, rp, r;
    ggFresnelDielectricPolarized(c, ni, nt, &rs, &rp);
    r = ggFresnelDielectric(c, ni, nt);
    printf("%-18s Rs = %.17g, Rp = %.17g\n", "Fresnel:", rs, rp);
    printf("%-18s R = %.17g, T = 1 - R = %.17g\n", "", r, 1 - r);
    printf("%-18s %.17g\n", "Schlick R:", ggFresnelSchlick(c, ni, nt));
}

static void print_critical(double ni, double nt)
{
    double tc = ggCriticalAngle(ni, nt);
    if (fabs(nt) >= fabs(ni))
        printf("%-18s none (|nt| >= |ni|: no total internal reflection)\n", "critical angle:");
    else
        printf("%-18s %.9f deg\n", "critical angle:", DEG(tc));
}

static int check_index(const char *form, const char *name, double x)
{
    return x != 0 ? 0 : bad_value(form, "0", name, "an index other than 0");
}

static int check_dirs(const char *form, const opts *o)
{
    if (is_zero(o->v)) return bad_value(form, "0,0,0", "--v", "a direction other than zero");
    if (is_zero(o->n)) return bad_value(form, "0,0,0", "--n", "a normal other than zero");
    return 0;
}

/* The indices and their ratio; a ratio outside the normal doubles
   (|ni/nt| beyond 2^1024 or below 2^-1022: ggRefract takes any) as
   m * 2^e, not inf or 0. */
static void print_indices(double ni, double nt)
{
    double q = ni / nt, m;
    int ei, et;
    printf("%-18s ni = %.17g, nt = %.17g, eta = ni/nt = ", "indices:", ni, nt);
    if (isfinite(q) && fabs(q) >= DBL_MIN) {
        printf("%.17g\n", q);
        return;
    }
    m = frexp(ni, &ei) / frexp(nt, &et);
    printf("%.17g * 2^%d\n", m, ei - et);
}

static int run_refract(const opts *o)
{
    ggVec3 t;
    bool ok;
    double ci, ct, th_i, vn;
    int rc, tangent;
    ggDirectionError e;
    if ((rc = need(o, O_V | O_N, "refract", "--v and --n")) != 0) return rc;
    if ((rc = check_dirs("refract", o)) != 0) return rc;
    vn = dot_sign(o->v, o->n);
    if ((rc = check_index("refract", "--ni", o->ni)) != 0) return rc;
    if ((rc = check_index("refract", "--nt", o->nt)) != 0) return rc;

    ok = ggRefract(o->v, o->n, o->ni, o->nt, &t);
    /* Whether v lies in the surface comes from the exact reference, not
       from the rounded vn: a normal part far below the tangential one
       rounds vn to 0 though v crosses the surface. */
    tangent = ggRefractError(o->v, o->n, o->ni, o->nt, t, !ok, &e) == GG_OK && e.exact_tir == -1;
    th_i = angle_deg(o->v, o->n, &ci);
    print_vec("incident v:", o->v);
    print_vec("normal n:", o->n);
    printf("%-18s %s\n", "",
           tangent  ? "(v lies in the surface)"
           : vn < 0 ? "(n faces the incoming ray)"
           : vn > 0 ? "(n faces away from the incoming ray; same result)"
                    : "(v grazes the surface: v.n rounds to 0 but is not 0)");
    print_indices(o->ni, o->nt);
    if ((o->ni < 0) != (o->nt < 0))
        printf("%-18s one index is negative: the ray bends to the same side of the normal\n", "");
    printf("%-18s %.9f deg (cos = %.17g)\n", "incidence angle:", th_i, ci);
    print_critical(o->ni, o->nt);
    if (ok) {
        double th_t = angle_deg(t, o->n, &ct);
        printf("%-18s no\n", "TIR:");
        print_vec("transmitted t:", t);
        printf("%-18s %.9f deg (cos = %.17g)\n", "refraction angle:", th_t, ct);
    } else if (tangent) {
        printf("%-18s no: v lies in the surface and does not cross it\n", "TIR:");
        print_vec("direction:", t);
    } else {
        printf("%-18s yes (total internal reflection)\n", "TIR:");
        print_vec("reflected t:", t);
    }
    print_fresnel(ci, o->ni, o->nt);
    if (o->seen & O_TEXTBOOK) {
        ggVec3 u = o->v, m = o->n, tb;
        double lu, lm, d, su = fmax(fmax(fabs(u.x), fabs(u.y)), fabs(u.z));
        double sm = fmax(fmax(fabs(m.x), fabs(m.y)), fabs(m.z));
        bool okb;
        /* the textbook formula needs unit vectors: normalise (scaled
           first, so huge or tiny input does not overflow) */
        u.x /= su, u.y /= su, u.z /= su, m.x /= sm, m.y /= sm, m.z /= sm;
        lu = sqrt(dot(u, u)), lm = sqrt(dot(m, m));
        u.x /= lu, u.y /= lu, u.z /= lu, m.x /= lm, m.y /= lm, m.z /= lm;
        okb = ggRefractTextbook(u, m, o->ni, o->nt, &tb);
        d = fmax(fmax(fabs(tb.x - t.x), fabs(tb.y - t.y)), fabs(tb.z - t.z));
        print_vec("textbook t:", tb);
        printf("%-18s %s; differs by %.3g (%.4g ulp of 2^-53)\n", "", okb ? "transmitted" : "TIR",
               d, d * 9007199254740992.0);
    }
    return EXIT_OK;
}

static int run_reflect(const opts *o)
{
    ggVec3 r;
    double c, th;
    int rc;
    if ((rc = need(o, O_V | O_N, "reflect", "--v and --n")) != 0) return rc;
    if ((rc = check_dirs("reflect", o)) != 0) return rc;
    r = ggReflection(o->v, o->n);
    print_vec("incident v:", o->v);
    print_vec("normal n:", o->n);
    print_vec("reflected r:", r);
    th = angle_deg(o->v, o->n, &c);
    printf("%-18s %.9f deg (cos = %.17g)\n", "incidence angle:", th, c);
    printf("%-18s |v| = %.17g, |r| = %.17g\n", "lengths:", hypot(hypot(o->v.x, o->v.y), o->v.z),
           hypot(hypot(r.x, r.y), r.z));
    return EXIT_OK;
}

static int run_fresnel(const opts *o)
{
    double c = 1;
    int rc, how = !!(o->seen & O_ANGLE) + !!(o->seen & O_COS) + !!(o->seen & (O_V | O_N));
    if (how != 1) {
        cli_error("give exactly one of --angle, --cos, or --v with --n");
        fprintf(stderr, "(see 'ggrt optics fresnel --help')\n");
        return EXIT_USAGE;
    }
    if (o->seen & (O_V | O_N)) {
        if ((rc = need(o, O_V | O_N, "fresnel", "--v and --n together")) != 0) return rc;
        if ((rc = check_dirs("fresnel", o)) != 0) return rc;
        (void)angle_deg(o->v, o->n, &c);
    } else if (o->seen & O_ANGLE) { /* [0, 90]: the parser's range */
        c = o->angle == 90 ? 0 : cos(o->angle * (PI / 180));
    } else { /* [-1, 1] */
        c = fabs(o->cos_i);
    }
    if ((rc = check_index("fresnel", "--ni", o->ni)) != 0) return rc;
    if ((o->seen & O_K) && (o->nt < 0 || (o->nt == 0 && o->k == 0))) {
        char v[32];
        snprintf(v, sizeof v, "%g", o->nt);
        return bad_value("fresnel", v, "--nt",
                         "a conductor's n >= 0 (with --k; n and k not both 0)");
    }
    if (!(o->seen & O_K) && (rc = check_index("fresnel", "--nt", o->nt)) != 0) return rc;
    printf("%-18s %.9f deg (cos = %.17g)\n", "incidence angle:", DEG(acos(c)), c);
    if (o->seen & O_K) {
        double rs, rp;
        ggFresnelConductorPolarized(c, o->ni, o->nt, o->k, &rs, &rp);
        printf("%-18s outside ni = %.17g, conductor n + ik = %.17g + %.17gi\n", "indices:", o->ni,
               o->nt, o->k);
        printf("%-18s Rs = %.17g, Rp = %.17g\n", "Fresnel:", rs, rp);
        printf("%-18s R = %.17g, absorbed 1 - R = %.17g\n", "",
               ggFresnelConductor(c, o->ni, o->nt, o->k),
               1 - ggFresnelConductor(c, o->ni, o->nt, o->k));
        printf("%-18s %.17g\n", "normal incidence:", ggFresnelConductor(1, o->ni, o->nt, o->k));
        return EXIT_OK;
    }
    printf("%-18s ni = %.17g, nt = %.17g\n", "indices:", o->ni, o->nt);
    print_critical(o->ni, o->nt);
    printf("%-18s %.9f deg\n", "Brewster angle:", DEG(atan2(fabs(o->nt), fabs(o->ni))));
    printf("%-18s %s\n", "TIR:",
           fabs(o->nt) < fabs(o->ni) && acos(c) > ggCriticalAngle(o->ni, o->nt) ? "yes" : "no");
    print_fresnel(c, o->ni, o->nt);
    return EXIT_OK;
}

static int run_absorb(const opts *o)
{
    int rc;
    if ((rc = need(o, O_K | O_LAMBDA | O_DISTANCE, "absorb", "--k, --lambda and --distance")) != 0)
        return rc;
    if (!(o->lambda > 0)) { /* --k and --distance: >= 0 by the parser's range */
        char v[32];
        snprintf(v, sizeof v, "%g", o->lambda);
        return bad_value("absorb", v, "--lambda", "a wavelength > 0");
    }
    printf("%-18s k = %.17g, lambda = %.17g, distance = %.17g\n", "medium:", o->k, o->lambda,
           o->distance);
    printf("%-18s %.17g per unit of length\n",
           "alpha = 4 pi k/L:", ggAbsorptionCoefficient(o->k, o->lambda));
    printf("%-18s %.17g\n", "transmittance T:", ggBeerLambert(o->k, o->lambda, o->distance));
    return EXIT_OK;
}

/* A first word that names no form: say so before its options are read
   (they belong to the form the user meant, "refrac --v ..."). */
static int unknown_form(const char *form)
{
    static const char *const names[] = {"refract", "reflect", "fresnel",
                                        "absorb",  "check",   "seeds"};
    const char *near = cli_suggest(form, names, sizeof names / sizeof names[0]);
    cli_set_command("optics");
    if (near)
        cli_error("unknown form '%s'; did you mean '%s'?", form, near);
    else
        cli_error("unknown form '%s' (refract, reflect, fresnel, absorb, check, seeds)", form);
    fprintf(stderr, "(see 'ggrt optics --help')\n");
    return EXIT_USAGE;
}

int cmd_optics(int argc, char **argv)
{
    static const struct {
        const char *name;
        unsigned allowed;
        const char *usage, *about, *tail;
        int (*run)(const opts *o);
    } forms[] = {
        {"refract", O_V | O_N | O_NI | O_NT | O_TEXTBOOK, use_refract, about_refract, tail_refract,
         run_refract},
        {"reflect", O_V | O_N, use_reflect, about_reflect, NULL, run_reflect},
        {"fresnel", O_V | O_N | O_NI | O_NT | O_K | O_COS | O_ANGLE, use_fresnel, about_fresnel,
         NULL, run_fresnel},
        {"absorb", O_K | O_LAMBDA | O_DISTANCE, use_absorb, about_absorb, tail_absorb, run_absorb},
    };
    size_t i;
    opts o;
    int rc;
    if (argc >= 2 && strcmp(argv[1], "check") == 0) return cli_optics_check(argc - 1, argv + 1);
    if (argc >= 2 && strcmp(argv[1], "seeds") == 0) return cli_optics_seeds(argc - 1, argv + 1);
    if (argc >= 2 && argv[1][0] != '-') {
        for (i = 0; i < sizeof forms / sizeof forms[0]; i++) {
            if (strcmp(argv[1], forms[i].name) != 0) continue;
            memset(&o, 0, sizeof o);
            o.ni = 1.0, o.nt = 1.5;
            rc = parse(forms[i].name, forms[i].allowed, forms[i].usage, forms[i].about,
                       forms[i].tail, argc - 1, argv + 1, &o);
            return rc != CLI_GO ? rc : forms[i].run(&o);
        }
        return unknown_form(argv[1]);
    }
    {
        const char *form = NULL;
        cli_opt none[] = {CLI_OPT_END};
        cli_cmd cmd = {.name = "optics",
                       .usage = "FORM [options]   (ggrt optics FORM --help for each)",
                       .about = about_all,
                       .tail = tail_all,
                       .opts = {none},
                       .args = &form,
                       .min_args = 1,
                       .max_args = 1,
                       .args_name = "form (refract, reflect, fresnel, absorb, check or seeds)"};
        if ((rc = cli_parse(&cmd, argc, argv)) != CLI_GO) return rc;
        return cli_usage_error(
            &cmd, "unknown form '%s' (refract, reflect, fresnel, absorb, check, seeds)", form);
    }
}
