/* SPDX-License-Identifier: MIT */
/*
** util.c -- helpers shared by the subcommands: exit codes, the clock,
** output files, shell quoting, cancellation by signals, stdout.
*/
#include "common/cli.h"

#include <ctype.h>
#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

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

static void error_in(const char *cmd, const char *fmt, ...) CLI_PRINTF(2, 3);
static void error_in(const char *cmd, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    say(cmd, "", fmt, ap);
    va_end(ap);
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
    return cli_exit_code(status, from_args);
}

double cli_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---- output files ---- */

/* A new file: its folder must exist and take files, checked now so that
   a command fails before its work, not after it (trace --svg would print
   the whole tree first). */
static int check_folder(const char *cmd, const char *path)
{
    char dir[1024] = ".";
    const char *slash = strrchr(path, '/');
    struct stat st;
    size_t n = slash ? (size_t)(slash - path) + (slash == path) : 0; /* "/x.png": the root */
    if (n >= sizeof dir) {
        error_in(cmd, "'%s': file name too long", path);
        return EXIT_IO;
    }
    if (slash) memcpy(dir, path, n), dir[n] = '\0';
    if (stat(dir, &st) != 0 || (!S_ISDIR(st.st_mode) && (errno = ENOTDIR) != 0) ||
        access(dir, W_OK | X_OK) != 0) {
        error_in(cmd, "cannot write '%s': %s: %s", path, dir, strerror(errno));
        return EXIT_IO;
    }
    return 0;
}

int cli_check_output(const char *cmd, const char *path)
{
    struct stat st;
    const char *why = NULL;
    if (lstat(path, &st) != 0) {
        if (errno == ENOENT) return check_folder(cmd, path); /* a new file */
        error_in(cmd, "cannot write '%s': %s", path, strerror(errno));
        return EXIT_IO;
    }
    /* The writers replace the file whole (a new file renamed over it), so
       a link would be replaced by a file and a device by an image. */
    if (S_ISLNK(st.st_mode))
        why = "it is a symbolic link, which ggrt would replace by a file (give the path of the "
              "file it points to)";
    else if (S_ISDIR(st.st_mode))
        why = "it is a directory (give a file name)";
    else if (!S_ISREG(st.st_mode))
        why = "it is not a regular file (a device, FIFO or socket)";
    else if (!(st.st_mode & (S_IWUSR | S_IWGRP | S_IWOTH)))
        why = "the file is read-only (make it writable or remove it first)";
    else if (access(path, W_OK) != 0)
        why = strerror(errno);
    if (!why) return 0;
    error_in(cmd, "refusing to write '%s': %s", path, why);
    return EXIT_IO;
}

int cli_out_open(cli_out *o, const char *cmd, const char *path)
{
    int fd, rc;
    memset(o, 0, sizeof *o);
    if ((rc = cli_check_output(cmd, path)) != 0) return rc;
    if (strlen(path) >= sizeof o->path) {
        error_in(cmd, "'%s': file name too long", path);
        return EXIT_IO;
    }
    strcpy(o->path, path);
    snprintf(o->tmp, sizeof o->tmp, "%s.tmp%ld", path, (long)getpid());
    fd = open(o->tmp, O_WRONLY | O_CREAT | O_EXCL, 0666);
    if (fd < 0 || !(o->f = fdopen(fd, "w"))) {
        error_in(cmd, "%s: cannot create a temporary file beside it: %s", path, strerror(errno));
        if (fd >= 0) close(fd), unlink(o->tmp);
        return EXIT_IO;
    }
    return 0;
}

int cli_out_close(cli_out *o, const char *cmd)
{
    int bad = fflush(o->f) != 0 || ferror(o->f), e = errno;
    if (!bad && fsync(fileno(o->f)) != 0) bad = 1, e = errno;
    if (fclose(o->f) != 0 && !bad) bad = 1, e = errno;
    o->f = NULL;
    if (!bad && rename(o->tmp, o->path) != 0) bad = 1, e = errno;
    if (!bad) return 0;
    unlink(o->tmp);
    error_in(cmd, "%s: %s", o->path, e ? strerror(e) : "write error");
    return EXIT_IO;
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

/* ---- cancellation ---- */

static volatile sig_atomic_t got_signal;
static const int cancel_signals[] = {SIGINT, SIGTERM, SIGHUP};
#define NCANCEL (int)(sizeof cancel_signals / sizeof cancel_signals[0])

static void on_signal(int signo)
{
    got_signal = signo;
}

void cli_cancel_begin(void)
{
    int i;
    for (i = 0; i < NCANCEL; i++) {
        struct sigaction sa, old;
        /* A signal ignored at start (nohup, a background job of a
           non-interactive shell) stays ignored. */
        if (sigaction(cancel_signals[i], NULL, &old) == 0 && old.sa_handler == SIG_IGN) continue;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_signal;
        sigemptyset(&sa.sa_mask);
        sigaction(cancel_signals[i], &sa, NULL);
    }
}

int cli_cancelled(void)
{
    return (int)got_signal;
}

static void mask(int how)
{
    sigset_t set;
    int i;
    sigemptyset(&set);
    for (i = 0; i < NCANCEL; i++) sigaddset(&set, cancel_signals[i]);
    sigprocmask(how, &set, NULL);
}

void cli_cancel_hold(void)
{
    mask(SIG_BLOCK);
}
void cli_cancel_release(void)
{
    mask(SIG_UNBLOCK);
}

void cli_cancel_exit(int signo)
{
    signal(signo, SIG_DFL);
    cli_cancel_release();
    raise(signo);
    exit(128 + signo); /* not reached unless the signal is blocked elsewhere */
}

/* ---- stdout ---- */

int cli_close_stdout(void)
{
    int bad = ferror(stdout), e = 0;
    if (fflush(stdout) != 0) bad = 1, e = errno;
    if (fclose(stdout) != 0 && !bad) bad = 1, e = errno;
    if (!bad) return 0;
    cli_error("error writing standard output%s%s", e ? ": " : "", e ? strerror(e) : "");
    return EXIT_IO;
}
