/* SPDX-License-Identifier: MIT */
/*
** output.c -- output files: checked before a command spends time on
** them, and text files written whole or not at all (cli.h).
*/
/* realpath is XSI (POSIX.1-2008 with the X/Open extension). */
#define _XOPEN_SOURCE 700
#include "common/cli.h"

#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

/* The folder of path into dir ("." for a bare name, "/" for "/x.png"):
   0, or -1 when it does not fit. */
static int folder_of(const char *path, char dir[CLI_PATH_MAX])
{
    const char *slash = strrchr(path, '/');
    size_t n = slash ? (size_t)(slash - path) + (slash == path) : 0;
    if (n >= CLI_PATH_MAX) return -1;
    if (slash)
        memcpy(dir, path, n), dir[n] = '\0';
    else
        strcpy(dir, ".");
    return 0;
}

/* A new file: its folder must exist and take files, checked now so that
   a command fails before its work, not after it (trace --svg would print
   the whole tree first). */
static int check_folder(const char *cmd, const char *path)
{
    char dir[CLI_PATH_MAX];
    struct stat st;
    if (folder_of(path, dir) != 0) {
        cli_error_in(cmd, "'%s': file name too long", path);
        return EXIT_IO;
    }
    if (stat(dir, &st) != 0 || (!S_ISDIR(st.st_mode) && (errno = ENOTDIR) != 0) ||
        access(dir, W_OK | X_OK) != 0) {
        cli_error_in(cmd, "cannot write '%s': %s: %s", path, dir, strerror(errno));
        return EXIT_IO;
    }
    return 0;
}

/* Whether the file (st) sits in a sticky folder (as /tmp) that lets only
   its owner, the folder's or root rename over it: not us. */
static int sticky_other(const char *path, const struct stat *st)
{
    char dir[CLI_PATH_MAX];
    struct stat ds;
    uid_t me = geteuid();
    if (folder_of(path, dir) != 0) return 0; /* check_folder says so */
    return me != 0 && st->st_uid != me && stat(dir, &ds) == 0 && (ds.st_mode & S_ISVTX) &&
           ds.st_uid != me;
}

int cli_check_output(const char *cmd, const char *path)
{
    struct stat st;
    const char *why = NULL;
    /* Many tools read "-" as standard output; a file of that name would
       surprise whoever typed it. */
    if (!strcmp(path, "-")) {
        cli_error_in(cmd, "'-' would be a file named '-', not standard output: give a file name");
        cli_usage_hint();
        return EXIT_USAGE;
    }
    if (lstat(path, &st) != 0) {
        if (errno == ENOENT) return check_folder(cmd, path); /* a new file */
        cli_error_in(cmd, "cannot write '%s': %s", path, strerror(errno));
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
    else if (sticky_other(path, &st))
        why = "its folder is sticky and the file is another user's: it cannot be replaced";
    /* The new file is made beside it and renamed over it. */
    if (!why) return check_folder(cmd, path);
    cli_error_in(cmd, "refusing to write '%s': %s", path, why);
    return EXIT_IO;
}

/* Whether path ends in ext (lower case), in any case, as ggImageWrite
   takes it. */
static int ends_in(const char *path, const char *ext)
{
    size_t n = strlen(path), k = strlen(ext), i;
    if (n < k) return 0;
    for (i = 0; i < k; i++)
        if (tolower((unsigned char)path[n - k + i]) != ext[i]) return 0;
    return 1;
}

int cli_image_kind(const char *path)
{
    if (ends_in(path, ".png")) return CLI_IMAGE_PNG;
    if (ends_in(path, ".exr")) return CLI_IMAGE_EXR;
    return CLI_IMAGE_NONE;
}

int cli_check_image_name(const cli_cmd *cmd, const char *what, const char *path)
{
    if (cli_image_kind(path) != CLI_IMAGE_NONE) return CLI_GO;
    return cli_usage_error(cmd, "%s must end in .png or .exr: '%s'", what, path);
}

int cli_check_not_input(const cli_cmd *cmd, const char *opt, const char *out,
                        const char *const *inputs, int n)
{
    struct stat so;
    int i;
    /* A missing output is no input's file; a missing input fails on its
       own when it is read. stat, not lstat: a link to an input is it. */
    if (!out || stat(out, &so) != 0) return CLI_GO;
    for (i = 0; i < n; i++)
        if (cli_same_file(out, inputs[i]))
            return cli_usage_error(cmd, "%s '%s' is the input '%s': writing it would destroy it",
                                   opt, out, inputs[i]);
    return CLI_GO;
}

/* What names the file at path: "I dev ino" when it exists, else "P " and
   the real path of its folder, '/', its name (the folder's path as given
   if that cannot be resolved). 0, or -1 if buf is too small. */
static int file_key(const char *path, char *buf, size_t n)
{
    struct stat st;
    char dir[4096], real[PATH_MAX];
    const char *slash = strrchr(path, '/'), *base = slash ? slash + 1 : path;
    int k;
    if (stat(path, &st) == 0) {
        k = snprintf(buf, n, "I %lu %lu", (unsigned long)st.st_dev, (unsigned long)st.st_ino);
        return k < 0 || (size_t)k >= n ? -1 : 0;
    }
    if (!slash)
        snprintf(dir, sizeof dir, ".");
    else if (slash == path)
        snprintf(dir, sizeof dir, "/");
    else
        snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
    k = snprintf(buf, n, "P %s/%s", realpath(dir, real) ? real : dir, base);
    return k < 0 || (size_t)k >= n ? -1 : 0;
}

int cli_same_file(const char *p, const char *q)
{
    char a[8192], b[8192];
    return p && q && !file_key(p, a, sizeof a) && !file_key(q, b, sizeof b) && !strcmp(a, b);
}

int cli_check_distinct(const cli_cmd *cmd, const char *const *opts, const char *const *paths, int n)
{
    int i, j;
    for (i = 0; i < n; i++)
        for (j = i + 1; j < n; j++)
            if (cli_same_file(paths[i], paths[j]))
                return cli_usage_error(cmd,
                                       "%s '%s' and %s '%s' are the same file: one would "
                                       "overwrite the other",
                                       opts[i], paths[i], opts[j], paths[j]);
    return CLI_GO;
}

/* A new file beside o->path, named from at most 200 bytes of its name
   (so that a name of up to NAME_MAX bytes has one), the process id and
   the clock, tried again if taken (a file left by a killed run of the
   same pid, as in a container where ggrt is pid 1); with the permissions
   of the file it will replace, so that a private file stays private. */
static int open_tmp(cli_out *o)
{
    const char *slash = strrchr(o->path, '/'), *base = slash ? slash + 1 : o->path;
    int keep = (int)(base - o->path) + (strlen(base) > 200 ? 200 : (int)strlen(base));
    struct stat st;
    int attempt, fd = -1;
    for (attempt = 0; attempt < 100; attempt++) {
        struct timespec ts;
        clock_gettime(CLOCK_REALTIME, &ts);
        snprintf(o->tmp, sizeof o->tmp, "%.*s.tmp%ld.%ld", keep, o->path, (long)getpid(),
                 (long)(ts.tv_nsec % 1000000) + attempt);
        fd = open(o->tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0 || errno != EEXIST) break;
    }
    if (fd >= 0 && stat(o->path, &st) == 0 && S_ISREG(st.st_mode))
        (void)fchmod(fd, st.st_mode & 07777);
    return fd;
}

int cli_out_open(cli_out *o, const char *cmd, const char *path)
{
    int fd, rc;
    memset(o, 0, sizeof *o);
    if ((rc = cli_check_output(cmd, path)) != 0) return rc;
    if (strlen(path) >= sizeof o->path) {
        cli_error_in(cmd, "'%s': file name too long", path);
        return EXIT_IO;
    }
    strcpy(o->path, path);
    fd = open_tmp(o);
    if (fd < 0 || !(o->f = fdopen(fd, "w"))) {
        cli_error_in(cmd, "%s: cannot create a temporary file beside it: %s", path,
                     strerror(errno));
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
    cli_error_in(cmd, "%s: %s", o->path, e ? strerror(e) : "write error");
    return EXIT_IO;
}

void cli_out_abandon(cli_out *o)
{
    if (o->f) fclose(o->f);
    o->f = NULL;
    unlink(o->tmp);
}

int cli_check_not_read(const char *cmd, const ggScene *s, const char *const *opts,
                       const char *const *outs, int n)
{
    int i, k, m = ggSceneInputCount(s);
    for (i = 0; i < n; i++)
        for (k = 0; outs[i] && k < m; k++)
            if (cli_same_file(outs[i], ggSceneInputFile(s, k))) {
                cli_error_in(cmd,
                             "%s '%s' is '%s', which the scene reads: writing it would "
                             "destroy it",
                             opts[i], outs[i], ggSceneInputFile(s, k));
                return EXIT_USAGE;
            }
    return 0;
}
