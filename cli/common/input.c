/* SPDX-License-Identifier: MIT */
/*
** input.c -- reading a whole text file that ggrt wrote (a plan, a
** tile's report) into memory sized to the file (cli.h).
*/
#include "common/cli.h"

#include <errno.h>
#include <stdlib.h>

int cli_read_text(const char *path, size_t max, char **text, size_t *len)
{
    FILE *f = fopen(path, "rb");
    size_t cap = 0, n = 0, got;
    char *b = NULL;
    int rc = 0;
    *text = NULL, *len = 0;
    if (!f) return CLI_READ_IO;
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
