/* SPDX-License-Identifier: MIT */
/*
** input.c -- reading a whole text file that ggrt wrote (a plan, a
** tile's report) into memory sized to the file (cli.h).
*/
#include "common/cli.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

/* path opened for reading if it is a regular file: a FIFO would wait for
   a writer, a device (/dev/zero) never end. NULL with errno set, or with
   *notfile set. */
static FILE *open_regular(const char *path, int *notfile)
{
    struct stat st;
    int fd = open(path, O_RDONLY | O_NONBLOCK), e;
    FILE *f;
    *notfile = 0;
    if (fd < 0) return NULL;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) ||
        fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) & ~O_NONBLOCK) != 0 || !(f = fdopen(fd, "rb"))) {
        e = errno;
        *notfile = fstat(fd, &st) == 0 && !S_ISREG(st.st_mode);
        close(fd);
        errno = e;
        return NULL;
    }
    return f;
}

int cli_read_text(const char *path, size_t max, char **text, size_t *len)
{
    size_t cap = 0, n = 0, got;
    char *b = NULL;
    int rc = 0, notfile;
    FILE *f = open_regular(path, &notfile);
    *text = NULL, *len = 0;
    if (!f) return notfile ? CLI_READ_NOTFILE : CLI_READ_IO;
    /* The buffer grows as the file is read: a buffer of max bytes up
       front costs its whole size in page faults under AddressSanitizer
       (and 256 MiB for a 2 KB report). */
    for (;;) {
        if (n == cap) {
            size_t ncap = cap ? 2 * cap : 65536;
            char *nb;
            if (ncap > max + 1) ncap = max + 1;
            if (ncap <= cap) {
                rc = CLI_READ_LARGE;
                break;
            }
            if (!(nb = realloc(b, ncap + 1))) {
                rc = CLI_READ_NOMEM;
                break;
            }
            b = nb, cap = ncap;
        }
        got = fread(b + n, 1, cap - n, f);
        n += got;
        if (got == 0) break;
    }
    if (!rc && ferror(f)) rc = CLI_READ_IO;
    {
        int e = errno; /* fread's reason, not fclose's */
        fclose(f);
        errno = e;
    }
    if (rc) {
        free(b);
        return rc;
    }
    b[n] = '\0';
    *text = b, *len = n;
    return 0;
}
