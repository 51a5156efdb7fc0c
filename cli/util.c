/* SPDX-License-Identifier: MIT */
/*
** util.c -- helpers shared by the subcommands.
*/
#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

int cli_exit_code(int status)
{
    switch (status) {
    case GG_OK: return EXIT_OK;
    case GG_ERROR_IO: return EXIT_IO;
    case GG_ERROR_INVALID: return EXIT_USAGE;
    default: return EXIT_INPUT;
    }
}

int cli_parse_double(const char *s, double *d)
{
    char *end;
    errno = 0;
    *d = strtod(s, &end);
    if (end == s || *end != '\0' || errno == ERANGE || !isfinite(*d)) return -1;
    return 0;
}

int cli_parse_int(const char *s, long lo, long hi, int *out)
{
    char *end;
    long v;
    errno = 0;
    v = strtol(s, &end, 10);
    if (end == s || *end != '\0' || errno == ERANGE || v < lo || v > hi) return -1;
    *out = (int)v;
    return 0;
}

int cli_parse_vec3(const char *s, ggVec3 *v)
{
    char *end;
    double c[3];
    int i;
    for (i = 0; i < 3; i++) {
        errno = 0;
        c[i] = strtod(s, &end);
        if (end == s || errno == ERANGE || !isfinite(c[i])) return -1;
        if (i < 2) {
            if (*end != ',') return -1;
            s = end + 1;
        }
    }
    if (*end != '\0') return -1;
    v->x = c[0], v->y = c[1], v->z = c[2];
    return 0;
}

int cli_is_help(const char *a) { return strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0; }
