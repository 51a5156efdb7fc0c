/* SPDX-License-Identifier: MIT */
/*
** fuzz_text.h -- what the harnesses of text inputs (fuzz_path.c,
** fuzz_options.c, fuzz_json.c) share: check(), which names the property
** that failed before it aborts (the fuzzer and the replayer report the
** abort), and the shape of an error's place, "line:col: ".
*/
#ifndef GG_FUZZ_TEXT_H
#define GG_FUZZ_TEXT_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static inline void fuzz_text_check(int ok, const char *what, const char *file, int line)
{
    if (!ok) {
        fprintf(stderr, "%s:%d: property violated: %s\n", file, line, what);
        abort();
    }
}

#define check(ok) fuzz_text_check((ok) != 0, #ok, __FILE__, __LINE__)

/* Does message m start with "LINE:COL: "? */
static inline int is_place(const char *m)
{
    size_t a = strspn(m, "0123456789"), b;
    if (a == 0 || m[a] != ':') return 0;
    b = strspn(m + a + 1, "0123456789");
    return b > 0 && m[a + 1 + b] == ':' && m[a + 2 + b] == ' ';
}

#endif
