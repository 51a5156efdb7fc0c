/* SPDX-License-Identifier: MIT */
/*
** jdom.c -- a small JSON reader for ggrt merge --reports (jdom.h): the
** document as a tree of nodes that point into the text, so that merged
** values are written back exactly as ggrt wrote them.
*/
#include "render/jdom.h"

#include <stdlib.h>
#include <string.h>

typedef struct jp {
    const char *p;
    int depth;
    char *why;
    size_t whylen;
} jp;

static void ws(jp *r)
{
    while (*r->p == ' ' || *r->p == '\t' || *r->p == '\n' || *r->p == '\r') r->p++;
}

static int fail(jp *r, const char *what)
{
    snprintf(r->why, r->whylen, "%s", what);
    return -1;
}

static int digit(char c)
{
    return c >= '0' && c <= '9';
}

/* JSON's escapes only, since a value may be written back as it was read. */
static int string(jp *r)
{
    if (*r->p != '"') return fail(r, "expected a string");
    for (r->p++; *r->p != '"'; r->p++) {
        int k;
        if ((unsigned char)*r->p < 0x20) return fail(r, "a control character in a string");
        if (*r->p != '\\') continue;
        if (!*++r->p) return fail(r, "the text ends in a string");
        if (strchr("\"\\/bfnrt", *r->p)) continue;
        if (*r->p != 'u') return fail(r, "not a JSON escape in a string");
        for (k = 1; k <= 4; k++)
            if (!r->p[k] || !strchr("0123456789abcdefABCDEF", r->p[k]))
                return fail(r, "a \\u escape without 4 hex digits");
        r->p += 4;
    }
    r->p++;
    return 0;
}

/* JSON's number grammar, which is narrower than strtod's (no hex, inf,
   nan, leading '+' or zeros), since a value may be written back as read. */
static int number(jp *r)
{
    const char *p = r->p;
    if (*p == '-') p++;
    if (*p == '0')
        p++;
    else if (digit(*p))
        while (digit(*p)) p++;
    else
        return fail(r, "expected a value");
    if (*p == '.') {
        if (!digit(*++p)) return fail(r, "a number without digits after '.'");
        while (digit(*p)) p++;
    }
    if (*p == 'e' || *p == 'E') {
        p += p[1] == '+' || p[1] == '-' ? 2 : 1;
        if (!digit(*p)) return fail(r, "a number without digits in its exponent");
        while (digit(*p)) p++;
    }
    r->p = p;
    return 0;
}

static int value(jp *r, jnode *n);

static int add_kid(jnode *n, jnode **kid)
{
    if ((n->n & (n->n - 1)) == 0) { /* 0, 1, 2, 4...: grow to the next power of two */
        jnode *k = realloc(n->kid, (size_t)(n->n ? 2 * n->n : 1) * sizeof *k);
        if (!k) return -1;
        n->kid = k;
    }
    *kid = &n->kid[n->n++];
    memset(*kid, 0, sizeof **kid);
    return 0;
}

/* An object's or array's members. */
static int members(jp *r, jnode *n, char close)
{
    r->p++;
    ws(r);
    if (*r->p == close) return r->p++, 0;
    for (;;) {
        jnode *k;
        const char *key = NULL, *keye = NULL;
        if (close == '}') {
            ws(r);
            key = r->p + 1;
            if (string(r) != 0) return -1;
            keye = r->p - 1;
            ws(r);
            if (*r->p != ':') return fail(r, "expected ':'");
            r->p++;
        }
        if (add_kid(n, &k) != 0) return fail(r, "out of memory");
        k->key = key, k->keye = keye;
        if (value(r, k) != 0) return -1;
        ws(r);
        if (*r->p == close) return r->p++, 0;
        /* the byte an error names is the one that is wrong */
        if (*r->p != ',')
            return fail(r, close == '}' ? "expected ',' or '}'" : "expected ',' or ']'");
        r->p++;
    }
}

static int value(jp *r, jnode *n)
{
    int rc = 0;
    ws(r);
    n->s = r->p;
    if (++r->depth > 64) return fail(r, "nested more than 64 deep");
    if (*r->p == '{' || *r->p == '[') {
        n->type = *r->p == '{' ? 'o' : 'a';
        rc = members(r, n, *r->p == '{' ? '}' : ']');
    } else if (*r->p == '"') {
        n->type = 's', rc = string(r);
    } else if (!strncmp(r->p, "true", 4) || !strncmp(r->p, "null", 4)) {
        n->type = *r->p == 't' ? 't' : 'z', r->p += 4;
    } else if (!strncmp(r->p, "false", 5)) {
        n->type = 'f', r->p += 5;
    } else {
        if (number(r) != 0) return -1;
        n->type = 'n';
    }
    r->depth--;
    n->e = r->p;
    return rc;
}

int jdom_parse(const char *text, jnode *root, char *why, size_t whylen)
{
    jp r;
    r.p = text, r.depth = 0, r.why = why, r.whylen = whylen;
    memset(root, 0, sizeof *root);
    if (value(&r, root) != 0) {
        size_t at = (size_t)(r.p - text);
        size_t n = strlen(why);
        snprintf(why + n, whylen - n, " at byte %lu", (unsigned long)at);
        return -1;
    }
    ws(&r);
    if (*r.p) {
        snprintf(why, whylen, "text after the value at byte %lu", (unsigned long)(r.p - text));
        return -1;
    }
    return 0;
}

void jdom_free(jnode *n)
{
    int i;
    for (i = 0; i < n->n; i++) jdom_free(&n->kid[i]);
    free(n->kid);
    n->kid = NULL, n->n = 0;
}

const jnode *jdom_get(const jnode *obj, const char *key)
{
    size_t len = strlen(key);
    int i;
    if (!obj || obj->type != 'o') return NULL;
    for (i = 0; i < obj->n; i++)
        if ((size_t)(obj->kid[i].keye - obj->kid[i].key) == len &&
            !memcmp(obj->kid[i].key, key, len))
            return &obj->kid[i];
    return NULL;
}

double jdom_num(const jnode *n)
{
    if (!n) return 0;
    if (n->type == 'z') return 1e308 * 10; /* null: json_num's NaN or infinity */
    return n->type == 'n' ? strtod(n->s, NULL) : 0;
}

int jdom_same(const jnode *a, const jnode *b)
{
    if (!a || !b) return a == b;
    return a->e - a->s == b->e - b->s && !memcmp(a->s, b->s, (size_t)(a->e - a->s));
}

int jdom_str(const jnode *n, char *buf, size_t size)
{
    static const char esc[] = "\"\"\\\\//b\bf\fn\nr\rt\t";
    const char *p, *e;
    size_t k = 0;
    if (!n || n->type != 's' || !size) return -1;
    for (p = n->s + 1, e = n->e - 1; p < e; p++) {
        int c = (unsigned char)*p;
        if (c == '\\' && p[1] == 'u') { /* jdom_parse saw its 4 hex digits */
            char hex[5];
            memcpy(hex, p + 2, 4), hex[4] = '\0', p += 5;
            if ((c = (int)strtol(hex, NULL, 16)) < 1 || c > 0x7f) return -1;
        } else if (c == '\\') {
            c = strchr(esc, *++p)[1]; /* pairs: the escape's letter, its byte */
        }
        if (k + 1 >= size) return -1;
        buf[k++] = (char)c;
    }
    buf[k] = '\0';
    return 0;
}

void jdom_write(FILE *f, const jnode *n)
{
    fwrite(n->s, 1, (size_t)(n->e - n->s), f);
}
