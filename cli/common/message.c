/* SPDX-License-Identifier: MIT */
/*
** message.c -- what a command says: exit codes, messages with the one
** prefix rule "ggrt CMD: ...", commands printed for a shell, and the
** close of stdout. (Output files: output.c; signals: cancel.c.)
*/
#include "common/cli.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

int cli_exit_code(int status, int from_args)
{
    switch (status) {
    case GG_OK:
        return EXIT_OK;
    case GG_ERROR_IO:
        return EXIT_IO;
    case GG_ERROR_INVALID:
        return from_args ? EXIT_USAGE : EXIT_INPUT;
    default:
        return EXIT_INPUT;
    }
}

/* ---- messages: every error and warning is "ggrt CMD: ..." ---- */

static char command_name[64]; /* set by cli_parse; empty before a command runs */

void cli_set_command(const char *name)
{
    snprintf(command_name, sizeof command_name, "%s", name ? name : "");
}

static void say(const char *cmd, const char *kind, const char *fmt, va_list ap)
{
    fprintf(stderr, "ggrt%s%s: %s", cmd && *cmd ? " " : "", cmd ? cmd : "", kind);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
}

void cli_error(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    say(command_name, "", fmt, ap);
    va_end(ap);
}

void cli_warn(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    say(command_name, "warning: ", fmt, ap);
    va_end(ap);
}

void cli_error_in(const char *cmd, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    say(cmd, "", fmt, ap);
    va_end(ap);
}

void cli_usage_hint(void)
{
    if (command_name[0]) fprintf(stderr, "(see 'ggrt %s --help')\n", command_name);
}

int cli_fail(int status, const ggError *err, int from_args)
{
    const char *m = err && err->message[0] ? err->message : ggStatusString(status), *p = m;
    /* A library message that names its function ("ggDiff: ...") speaks to a
       programmer; the user ran a command, which the prefix already names. */
    if (p[0] == 'g' && p[1] == 'g' && isupper((unsigned char)p[2])) {
        for (p += 2; isalnum((unsigned char)*p); p++) continue;
        m = p[0] == ':' && p[1] == ' ' ? p + 2 : m;
    }
    cli_error("%s", m);
    if (cli_exit_code(status, from_args) == EXIT_USAGE) cli_usage_hint();
    return cli_exit_code(status, from_args);
}

/* ---- shell quoting ---- */

void cli_print_arg(FILE *f, const char *a)
{
    const char *p;
    int plain = *a != '\0';
    for (p = a; *p && plain; p++)
        plain = strchr("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_-+./,:=@%",
                       *p) != NULL;
    if (plain) {
        fprintf(f, " %s", a);
        return;
    }
    fputs(" '", f);
    for (p = a; *p; p++)
        if (*p == '\'')
            fputs("'\\''", f);
        else
            fputc(*p, f);
    fputc('\'', f);
}

void cli_print_file(FILE *f, const char *path)
{
    char buf[CLI_PATH_MAX + 3];
    if (path[0] == '-' && strlen(path) < CLI_PATH_MAX) {
        snprintf(buf, sizeof buf, "./%s", path);
        path = buf;
    }
    cli_print_arg(f, path);
}

/* ---- stdout ---- */

/* A write that failed earlier (output longer than the stream's buffer)
   leaves ferror set and an empty buffer, so fflush succeeds and says
   nothing: the reason is then errno as that write left it, trusted only
   if it is an error a write gives. */
static int write_errno(int e)
{
    return e == ENOSPC || e == EIO || e == EPIPE || e == EFBIG || e == EDQUOT ? e : 0;
}

int cli_close_stdout(void)
{
    int bad = ferror(stdout), e = bad ? write_errno(errno) : 0;
    if (fflush(stdout) != 0) bad = 1, e = errno;
    if (fclose(stdout) != 0 && !bad) bad = 1, e = errno;
    if (!bad) return 0;
    cli_error("error writing standard output%s%s", e ? ": " : "", e ? strerror(e) : "");
    return EXIT_IO;
}

static int put_num(char *buf, size_t size, int prec, double d)
{
    return isnan(d) ? snprintf(buf, size, "nan") : snprintf(buf, size, "%.*g", prec, d);
}

const char *cli_color(char *buf, size_t size, int prec, ggColor c)
{
    size_t n = 0;
    const double v[3] = {c.r, c.g, c.b};
    int k, w;
    for (k = 0; k < 3 && n < size; k++) {
        if (k) buf[n++] = ' ';
        if (n >= size) break;
        w = put_num(buf + n, size - n, prec, v[k]);
        n += w > 0 ? (size_t)w : 0;
    }
    if (size) buf[n < size ? n : size - 1] = '\0';
    return buf;
}

void cli_shortest(char *buf, size_t size, double d)
{
    int p;
    for (p = 1; p < 17; p++) {
        snprintf(buf, size, "%.*g", p, d);
        if (strtod(buf, NULL) == d) return;
    }
    snprintf(buf, size, "%.17g", d);
}
