/* SPDX-License-Identifier: MIT */
/*
** args.c -- the command-line parser (args.h): options, values, --help.
*/
#include "common/args.h"
#include "common/cli.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

/* ---- values ---- */

int cli_parse_long(const char *s, long lo, long hi, long *out, char *why, size_t whylen)
{
    char *end;
    long v;
    if (!isdigit((unsigned char)s[(s[0] == '+' || s[0] == '-') ? 1 : 0])) {
        snprintf(why, whylen, "%s", *s ? "not a whole number" : "empty");
        return -1;
    }
    errno = 0;
    v = strtol(s, &end, 10);
    if (*end) {
        snprintf(why, whylen, "'%s' after the number", end);
        return -1;
    }
    if (errno == ERANGE || v < lo || v > hi) {
        snprintf(why, whylen, "out of range");
        return -1;
    }
    *out = v;
    return 0;
}

int cli_parse_num(const char *s, double lo, double hi, double *out, char *why, size_t whylen)
{
    char *end;
    double v;
    if (!*s || isspace((unsigned char)*s)) {
        snprintf(why, whylen, "%s", *s ? "space before the number" : "empty");
        return -1;
    }
    errno = 0;
    v = strtod(s, &end);
    if (end == s) {
        snprintf(why, whylen, "not a number");
        return -1;
    }
    if (*end) {
        snprintf(why, whylen, "'%s' after the number", end);
        return -1;
    }
    /* ERANGE on underflow still gives the nearest double; only an overflow
       (or inf/nan spelled out) is not a finite number. */
    if (!isfinite(v) || (errno == ERANGE && fabs(v) == HUGE_VAL)) {
        snprintf(why, whylen, "not finite");
        return -1;
    }
    if (v < lo || v > hi) {
        snprintf(why, whylen, "out of range");
        return -1;
    }
    *out = v;
    return 0;
}

/* n whole numbers separated by sep (sep2 also allowed, 0 = none), each in
   [lo, hi]; names[i] names field i in the reason. */
static int parse_fields(const char *s, const char *sep, int n, long lo, long hi, int *out,
                        const char *const *names, char *why, size_t whylen)
{
    const char *p = s;
    int i;
    for (i = 0; i < n; i++) {
        char *end;
        long v;
        if (!isdigit((unsigned char)p[(p[0] == '+' || p[0] == '-') ? 1 : 0])) {
            snprintf(why, whylen, "%s is %s", names[i], *p ? "not a whole number" : "missing");
            return -1;
        }
        errno = 0;
        v = strtol(p, &end, 10);
        if (errno == ERANGE || v < lo || v > hi) {
            snprintf(why, whylen, "%s is out of range", names[i]);
            return -1;
        }
        out[i] = (int)v;
        if (i < n - 1) {
            if (!*end || !strchr(sep, *end)) {
                if (*end)
                    snprintf(why, whylen, "'%s' after %s", end, names[i]);
                else
                    snprintf(why, whylen, "only %d number%s", i + 1, i ? "s" : "");
                return -1;
            }
            p = end + 1;
        } else if (*end) {
            if (strchr(sep, *end))
                snprintf(why, whylen, "more than %d numbers", n);
            else
                snprintf(why, whylen, "'%s' after %s", end, names[i]);
            return -1;
        }
    }
    return 0;
}

static int parse_vec3(const char *s, ggVec3 *v, char *why, size_t whylen)
{
    static const char *const names[3] = {"X", "Y", "Z"};
    double c[3];
    const char *p = s;
    int i;
    for (i = 0; i < 3; i++) {
        char buf[128], sub[96];
        size_t len = strcspn(p, ",");
        if (len >= sizeof buf) {
            snprintf(why, whylen, "%s is too long", names[i]);
            return -1;
        }
        memcpy(buf, p, len);
        buf[len] = '\0';
        if (cli_parse_num(buf, -HUGE_VAL, HUGE_VAL, &c[i], sub, sizeof sub) != 0) {
            snprintf(why, whylen, "%s: %s", names[i], sub);
            return -1;
        }
        p += len;
        if (i < 2) {
            if (*p != ',') {
                snprintf(why, whylen, "only %d number%s", i + 1, i ? "s" : "");
                return -1;
            }
            p++;
        } else if (*p) {
            snprintf(why, whylen, "more than 3 numbers");
            return -1;
        }
    }
    v->x = c[0], v->y = c[1], v->z = c[2];
    return 0;
}

/* What the option accepts, for messages: "a whole number from 1 to 64". */
static void describe(const cli_opt *o, char *buf, size_t len)
{
    const char *what = NULL;
    int n = 0;
    switch (o->kind) {
    case CLI_INT:
        snprintf(buf, len, "a whole number from %.0f to %.0f", o->lo, o->hi);
        return;
    case CLI_DOUBLE:
        if (o->lo == -HUGE_VAL && o->hi == HUGE_VAL)
            snprintf(buf, len, "a finite number");
        else if (o->hi == HUGE_VAL)
            snprintf(buf, len, "a finite number >= %g", o->lo);
        else
            snprintf(buf, len, "a number from %g to %g", o->lo, o->hi);
        return;
    case CLI_CHOICE: {
        size_t k, at;
        at = (size_t)snprintf(buf, len, "one of");
        for (k = 0; o->choices[k] && at < len; k++)
            at += (size_t)snprintf(buf + at, len - at, "%s %s", k ? "," : "", o->choices[k]);
        return;
    }
    case CLI_SIZE:
        snprintf(buf, len, "WxH, two whole numbers from %.0f to %.0f, at most %lu pixels", o->lo,
                 o->hi, (unsigned long)GG_IMAGE_MAX_PIXELS);
        return;
    case CLI_XY:
        what = "X,Y", n = 2;
        break;
    case CLI_BOX:
        what = "X0,Y0,X1,Y1", n = 4;
        break;
    case CLI_VEC3:
        snprintf(buf, len, "X,Y,Z, three finite numbers");
        return;
    case CLI_STRING:
        snprintf(buf, len, "a non-empty %s", o->arg ? o->arg : "value");
        return;
    default:
        snprintf(buf, len, "%s", o->arg ? o->arg : "a value");
        return;
    }
    snprintf(buf, len, "%s, %s whole numbers from %.0f to %.0f", what, n == 2 ? "two" : "four",
             o->lo, o->hi);
}

/* Store value v of option o; 0, or -1 with the reason in why. */
static int set_value(cli_opt *o, const char *v, char *why, size_t whylen)
{
    static const char *const wh[] = {"W", "H"}, *const xy[] = {"X", "Y"},
                             *const box[] = {"X0", "Y0", "X1", "Y1"};
    long l;
    size_t k;
    why[0] = '\0';
    switch (o->kind) {
    case CLI_INT:
        if (cli_parse_long(v, (long)o->lo, (long)o->hi, &l, why, whylen) != 0) return -1;
        *(int *)o->dst = (int)l;
        return 0;
    case CLI_DOUBLE:
        return cli_parse_num(v, o->lo, o->hi, (double *)o->dst, why, whylen);
    case CLI_STRING:
        if (!*v) {
            snprintf(why, whylen, "empty");
            return -1;
        }
        *(const char **)o->dst = v;
        return 0;
    case CLI_CHOICE:
        for (k = 0; o->choices[k]; k++)
            if (!strcmp(v, o->choices[k])) {
                *(int *)o->dst = (int)k;
                return 0;
            }
        return -1;
    case CLI_SIZE: {
        const int *s = (const int *)o->dst;
        if (parse_fields(v, "xX", 2, (long)o->lo, (long)o->hi, o->dst, wh, why, whylen) != 0)
            return -1;
        /* The library's cap, refused here as a usage error: else a command
           fails only after loading the scene (plan after measuring). */
        if ((unsigned long long)s[0] * (unsigned long long)s[1] <= GG_IMAGE_MAX_PIXELS) return 0;
        snprintf(why, whylen, "%dx%d is %.0f pixels", s[0], s[1], (double)s[0] * s[1]);
        return -1;
    }
    case CLI_XY:
        return parse_fields(v, ",", 2, (long)o->lo, (long)o->hi, o->dst, xy, why, whylen);
    case CLI_BOX: {
        const int *b = (const int *)o->dst;
        if (parse_fields(v, ",", 4, (long)o->lo, (long)o->hi, o->dst, box, why, whylen) != 0)
            return -1;
        /* (an all-zero window would mean the whole image to the library) */
        if (b[0] < b[2] && b[1] < b[3]) return 0;
        snprintf(why, whylen, "an empty window: X1 must exceed X0 and Y1 Y0");
        return -1;
    }
    case CLI_VEC3:
        return parse_vec3(v, (ggVec3 *)o->dst, why, whylen);
    case CLI_FUNC:
        return o->fn(o->ud, v, why, whylen) ? -1 : 0;
    default:
        return -1;
    }
}

/* ---- messages ---- */

int cli_usage_error(const cli_cmd *cmd, const char *fmt, ...)
{
    char msg[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    cli_set_command(cmd->name);
    cli_error("%s", msg);
    fprintf(stderr, "(see 'ggrt %s --help')\n", cmd->name);
    return EXIT_USAGE;
}

/* "--name" or "-s" as the user would type it. */
static const char *spelled(const cli_opt *o, char *buf, size_t len)
{
    if (o->name)
        snprintf(buf, len, "--%s", o->name);
    else
        snprintf(buf, len, "-%c", o->shrt);
    return buf;
}

static int bad_value(const cli_cmd *cmd, const cli_opt *o, const char *v, const char *why)
{
    char spec[256], nm[64];
    describe(o, spec, sizeof spec);
    if (o->kind == CLI_FUNC)
        return cli_usage_error(cmd, "bad value '%s' for %s: %s", v, spelled(o, nm, sizeof nm), why);
    return cli_usage_error(cmd, "bad value '%s' for %s: expected %s%s%s%s", v,
                           spelled(o, nm, sizeof nm), spec, *why ? " (" : "", why, *why ? ")" : "");
}

/* Edit distance, for "did you mean": insertions, deletions, changes
   and swaps of two neighbours (--depht is one edit from --depth). */
static size_t distance(const char *a, const char *b)
{
    size_t la = strlen(a), lb = strlen(b), i, j, r[3][64];
    if (la >= 63 || lb >= 63) return 99;
    for (j = 0; j <= lb; j++) r[0][j] = j;
    for (i = 1; i <= la; i++) {
        size_t *cur = r[i % 3], *up = r[(i - 1) % 3], *up2 = r[(i + 1) % 3];
        cur[0] = i;
        for (j = 1; j <= lb; j++) {
            size_t best = up[j - 1] + (a[i - 1] != b[j - 1]);
            if (up[j] + 1 < best) best = up[j] + 1;
            if (cur[j - 1] + 1 < best) best = cur[j - 1] + 1;
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] &&
                up2[j - 2] + 1 < best)
                best = up2[j - 2] + 1;
            cur[j] = best;
        }
    }
    return r[la % 3][lb];
}

const char *cli_suggest(const char *word, const char *const *names, size_t n)
{
    const char *best = NULL, *prefixed = NULL;
    size_t len = strlen(word), bd = len / 3 + 1, nprefixed = 0, d, i;
    if (bd > 3) bd = 3;
    for (i = 0; i < n; i++) {
        if (len && !strncmp(names[i], word, len)) prefixed = names[i], nprefixed++;
        if ((d = distance(word, names[i])) < bd) bd = d, best = names[i];
    }
    return nprefixed == 1 ? prefixed : best;
}

static cli_opt *find_long(const cli_cmd *cmd, const char *name, size_t len);

/* The long option an unknown --word most likely meant (cli_suggest over
   the command's long names). */
static const char *nearest_long(const cli_cmd *cmd, const char *word)
{
    const char *names[256];
    size_t t, n = 0;
    int i;
    for (t = 0; cmd->opts[t]; t++)
        for (i = 0; cmd->opts[t][i].kind != CLI_END; i++) {
            const cli_opt *o = &cmd->opts[t][i];
            if (o->kind != CLI_SECTION && o->name && n < sizeof names / sizeof names[0])
                names[n++] = o->name;
        }
    return cli_suggest(word, names, n);
}

/* An unknown option, with the one it most likely meant: for -b, a --b
   (diff's sides; -a is --accuracy there). */
static int unknown(const cli_cmd *cmd, const char *arg, size_t len)
{
    const char *best = NULL;
    char want[64];
    snprintf(want, sizeof want, "%.*s", (int)(len < 60 ? len : 60), arg);
    if (want[0] == '-' && want[1] == '-')
        best = nearest_long(cmd, want + 2);
    else if (want[0] == '-' && want[1] && !want[2] && find_long(cmd, want + 1, 1))
        best = want + 1;
    if (best) return cli_usage_error(cmd, "unknown option '%s'; did you mean '--%s'?", want, best);
    return cli_usage_error(cmd, "unknown option '%s'", want);
}

/* ---- lookup ---- */

static cli_opt *find_long(const cli_cmd *cmd, const char *name, size_t len)
{
    size_t t;
    int i;
    for (t = 0; cmd->opts[t]; t++)
        for (i = 0; cmd->opts[t][i].kind != CLI_END; i++) {
            cli_opt *o = &cmd->opts[t][i];
            if (o->kind != CLI_SECTION && o->name && strlen(o->name) == len &&
                !strncmp(o->name, name, len))
                return o;
        }
    return NULL;
}

static cli_opt *find_short(const cli_cmd *cmd, char c)
{
    size_t t;
    int i;
    for (t = 0; cmd->opts[t]; t++)
        for (i = 0; cmd->opts[t][i].kind != CLI_END; i++)
            if (cmd->opts[t][i].kind != CLI_SECTION && cmd->opts[t][i].shrt == c)
                return &cmd->opts[t][i];
    return NULL;
}

int cli_given(const cli_cmd *cmd, const char *name)
{
    const cli_opt *o = strlen(name) == 1 ? find_short(cmd, name[0]) : NULL;
    if (!o) o = find_long(cmd, name, strlen(name));
    return o ? o->given : 0;
}

/* ---- the parse ---- */

/* Option o's value v, once unless o repeats: a second value would have
   replaced the first without a word (a script's -s 8x6 ... -s 4x4). */
static int take_value(const cli_cmd *cmd, cli_opt *o, const char *v)
{
    char why[256], nm[64];
    if (o->given && !o->many)
        return cli_usage_error(cmd, "%s given twice ('%s', then '%s'): give it once",
                               spelled(o, nm, sizeof nm), o->last, v);
    if (set_value(o, v, why, sizeof why) != 0) return bad_value(cmd, o, v, why);
    o->given++;
    o->last = v;
    return CLI_GO;
}

/* Handle the option in argv[*i]; advances *i past a separate value. */
static int one_long(cli_cmd *cmd, int argc, char **argv, int *i)
{
    const char *a = argv[*i] + 2, *eq = strchr(a, '='), *v;
    size_t len = eq ? (size_t)(eq - a) : strlen(a);
    char nm[64];
    cli_opt *o = find_long(cmd, a, len);
    if (!o) return unknown(cmd, argv[*i], len + 2);
    if (o->kind == CLI_FLAG) {
        if (eq) return cli_usage_error(cmd, "--%s takes no value", o->name);
        *(int *)o->dst = 1;
        o->given++;
        return CLI_GO;
    }
    if (eq)
        v = eq + 1;
    else if (*i + 1 < argc)
        v = argv[++*i];
    else
        return cli_usage_error(cmd, "%s needs a value: %s", spelled(o, nm, sizeof nm), o->arg);
    return take_value(cmd, o, v);
}

/* Short options, possibly grouped (-qv) or with the value attached (-s8x6). */
static int one_short(cli_cmd *cmd, int argc, char **argv, int *i)
{
    const char *p = argv[*i] + 1, *v;
    for (; *p; p++) {
        cli_opt *o = find_short(cmd, *p);
        if (!o) {
            char s[3] = {'-', *p, '\0'};
            return unknown(cmd, s, 2);
        }
        if (o->kind == CLI_FLAG) {
            *(int *)o->dst = 1;
            o->given++;
            continue;
        }
        if (p[1])
            v = p + 1;
        else if (*i + 1 < argc)
            v = argv[++*i];
        else
            return cli_usage_error(cmd, "-%c needs a value: %s", o->shrt, o->arg);
        return take_value(cmd, o, v);
    }
    return CLI_GO;
}

static int is_help(const char *a)
{
    return !strcmp(a, "-h") || !strcmp(a, "--help");
}

int cli_parse(cli_cmd *cmd, int argc, char **argv)
{
    int i, n = 0, only_args = 0, rc;
    const char *what = cmd->args_name ? cmd->args_name : "argument";
    cli_set_command(cmd->name); /* the prefix of every message from here on */
    /* --help anywhere wins over every error, as users expect. */
    for (i = 1; i < argc && strcmp(argv[i], "--"); i++)
        if (is_help(argv[i])) {
            cli_help(stdout, cmd);
            return EXIT_OK;
        }
    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!only_args && !strcmp(a, "--")) {
            only_args = 1;
            continue;
        }
        if (!only_args && a[0] == '-' && a[1]) {
            rc = a[1] == '-' ? one_long(cmd, argc, argv, &i) : one_short(cmd, argc, argv, &i);
            if (rc != CLI_GO) return rc;
            continue;
        }
        if (n >= cmd->max_args) {
            if (cmd->max_args == 0) return cli_usage_error(cmd, "unexpected argument '%s'", a);
            return cli_usage_error(cmd, "unexpected argument '%s' (takes %s%d %s%s)", a,
                                   cmd->min_args == cmd->max_args ? "" : "at most ", cmd->max_args,
                                   what, cmd->max_args > 1 ? "s" : "");
        }
        cmd->args[n++] = a;
    }
    if (cmd->nargs) *cmd->nargs = n;
    if (n < cmd->min_args)
        return cli_usage_error(cmd, "need %s%s %s%s", cmd->min_args > 1 ? "at least " : "",
                               cmd->min_args > 1 ? "" : "a", what, cmd->min_args > 1 ? "s" : "");
    return CLI_GO;
}

/* ---- help ---- */

#define HELP_COL 24

static void help_line(FILE *f, const cli_opt *o)
{
    char left[96];
    const char *h = o->help ? o->help : "";
    int n;
    if (o->shrt && o->name)
        n = snprintf(left, sizeof left, "  -%c, --%s", o->shrt, o->name);
    else if (o->shrt)
        n = snprintf(left, sizeof left, "  -%c", o->shrt);
    else
        n = snprintf(left, sizeof left, "      --%s", o->name);
    if (o->arg && o->kind != CLI_FLAG && n < (int)sizeof left)
        n += snprintf(left + n, sizeof left - (size_t)n, " %s", o->arg);
    if (n + 2 > HELP_COL)
        fprintf(f, "%s\n%*s", left, HELP_COL, "");
    else
        fprintf(f, "%-*s", HELP_COL, left);
    for (; *h; h++) {
        fputc(*h, f);
        if (*h == '\n') fprintf(f, "%*s", HELP_COL, "");
    }
    fputc('\n', f);
}

void cli_help(FILE *f, const cli_cmd *cmd)
{
    size_t t;
    int i, opened = 0;
    fprintf(f, "usage: ggrt %s %s\n", cmd->name, cmd->usage ? cmd->usage : "");
    if (cmd->about) fprintf(f, "\n%s\n", cmd->about);
    for (t = 0; cmd->opts[t]; t++)
        for (i = 0; cmd->opts[t][i].kind != CLI_END; i++) {
            const cli_opt *o = &cmd->opts[t][i];
            if (o->kind == CLI_SECTION) {
                fprintf(f, "\n%s:\n", o->help);
                opened = 1;
                continue;
            }
            if (!opened) fprintf(f, "\noptions:\n"), opened = 1;
            help_line(f, o);
        }
    if (!opened) fprintf(f, "\noptions:\n");
    fprintf(f, "  -h, --help            this text\n");
    if (cmd->tail) fprintf(f, "\n%s\n", cmd->tail);
}
