/* SPDX-License-Identifier: MIT */
/*
** textlex.c -- the line cursor of the text mesh formats (OBJ, MTL): blanks,
** continuations, words, numbers and "file:line:col" messages (mesh_int.h).
** Lines end at LF, CRLF or a lone CR; a UTF-8 byte order mark is skipped.
*/
#include "mesh_int.h"

#include <stdio.h>
#include <string.h>

/* A line ends at "\n", "\r\n" or a lone "\r" (CR line endings), as in
   NFF (nff.c); *p is the end of its line. */
static bool line_end(const char *p, const char *e)
{
    return *p == '\n' || (*p == '\r' && (p + 1 >= e || p[1] != '\n'));
}

static const char *next_line_end(const char *p, const char *e)
{
    while (p < e && !line_end(p, e)) p++;
    return p;
}

void gg_lc_init(gg_lc *c, const char *text, size_t len, const char *name, ggError *err)
{
    c->p = c->ls = text, c->end = text + len, c->line = 1, c->name = name, c->err = err;
}

int gg_lc_check_text(gg_lc *c)
{
    const unsigned char *t = (const unsigned char *)c->p;
    size_t len = (size_t)(c->end - c->p);
    const char *z, *q, *kind = gg_load_binary_kind(c->p, len);
    if (kind)
        return gg_error_set(c->err, GG_ERROR_PARSE, "%s: this is %s, not a text file (OBJ or MTL)",
                            c->name, kind);
    if (len >= 2 && ((t[0] == 0xFE && t[1] == 0xFF) || (t[0] == 0xFF && t[1] == 0xFE)))
        return gg_lc_fail(c, NULL, GG_ERROR_UNSUPPORTED,
                          "UTF-16 text is not supported (convert the file to UTF-8)");
    if (len >= 3 && !memcmp(t, "\xEF\xBB\xBF", 3)) c->p += 3, c->ls = c->p;
    z = memchr(c->p, '\0', (size_t)(c->end - c->p));
    if (!z) return GG_OK;
    for (q = c->p; q < z; q++)
        if (line_end(q, c->end)) c->line++, c->ls = q + 1;
    return gg_lc_fail(c, z, GG_ERROR_PARSE, "NUL byte in a text file");
}

void gg_lc_blank(gg_lc *c)
{
    const char *p = c->p, *e = c->end;
    for (;;) {
        while (p < e && (*p == ' ' || *p == '\t' || *p == '\f' || *p == '\v' ||
                         (*p == '\r' && !line_end(p, e))))
            p++;
        if (p < e && *p == '\\') {
            const char *q = p + 1;
            while (q < e && *q == '\r' && !line_end(q, e)) q++;
            if (q < e && line_end(q, e)) {
                p = q + 1;
                c->line++, c->ls = p;
                continue;
            }
        }
        break;
    }
    c->p = p;
}

bool gg_lc_eol(const gg_lc *c)
{
    return c->p >= c->end || line_end(c->p, c->end) || *c->p == '#';
}

void gg_lc_next_line(gg_lc *c)
{
    const char *nl = next_line_end(c->p, c->end);
    c->p = nl < c->end ? nl + 1 : c->end;
    c->ls = c->p;
    c->line++;
}

static bool blank(char ch)
{
    return ch == ' ' || ch == '\t' || ch == '\r' || ch == '\n' || ch == '\f' || ch == '\v';
}

size_t gg_lc_word(gg_lc *c, const char **w)
{
    const char *p;
    gg_lc_blank(c);
    if (gg_lc_eol(c)) return 0;
    for (p = c->p; p < c->end && !blank(*p); p++)
        ;
    *w = c->p;
    c->p = p;
    return (size_t)(p - *w);
}

size_t gg_lc_rest(gg_lc *c, const char **s)
{
    const char *p, *q, *h;
    gg_lc_blank(c);
    p = c->p;
    q = next_line_end(p, c->end);
    c->p = q;
    /* `usemtl red # c` named 'red # c' (the default material) and
       `mtllib red.mtl # c` warned of a library '#' */
    for (h = p; h < q; h++)
        if (*h == '#' && (h == p || blank(h[-1]))) {
            q = h;
            break;
        }
    while (q > p && blank(q[-1])) q--;
    *s = p;
    return (size_t)(q - p);
}

const char *gg_lc_show(const char *w, size_t n, char *buf, size_t size)
{
    gg_text_escape(buf, size, w, n < 40 ? n : 40);
    return buf;
}

int gg_lc_fail(const gg_lc *c, const char *at, int code, const char *fmt, ...)
{
    char msg[400];
    va_list ap;
    const char *p = at ? at : c->p;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return gg_error_set(c->err, code, "%s:%d:%ld: %s", c->name, c->line, (long)(p - c->ls) + 1,
                        msg);
}

/* What stands at the cursor, for "got ..." in messages. */
static const char *got(const gg_lc *c, char *buf, size_t n)
{
    const char *q = c->p;
    if (gg_lc_eol(c)) return "the end of the line";
    while (q < c->end && !blank(*q)) q++;
    buf[0] = '\'';
    gg_lc_show(c->p, (size_t)(q - c->p), buf + 1, n - 2);
    strcat(buf, "'");
    return buf;
}

int gg_lc_number(gg_lc *c, double *d, const char *what)
{
    const char *q;
    char b[200];
    gg_lc_blank(c);
    q = c->p < c->end ? gg_parse_number(c->p, c->end, d) : NULL;
    if (!q || (q < c->end && !blank(*q) && *q != '#'))
        return gg_lc_fail(c, NULL, GG_ERROR_PARSE, "expected %s, got %s", what,
                          got(c, b, sizeof b));
    c->p = q;
    return GG_OK;
}

int gg_lc_end(gg_lc *c)
{
    char b[200];
    gg_lc_blank(c);
    if (gg_lc_eol(c)) return GG_OK;
    return gg_lc_fail(c, NULL, GG_ERROR_PARSE, "unexpected %s", got(c, b, sizeof b));
}
