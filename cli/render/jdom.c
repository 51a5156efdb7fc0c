/* SPDX-License-Identifier: MIT */
/*
** jdom.c -- a small JSON reader for ggrt merge --reports (jdom.h): the
** document as a tree of nodes that point into the text, so that merged
** values are written back exactly as ggrt wrote them. The text is read
** twice by the same code: the first reading counts each container's
** members, the second places every node in one block of the size the
** counts add up to (a report can hold millions of nodes: no array grown
** by doubling, no allocation per container).
*/
#include "render/jdom.h"

#include <stdlib.h>
#include <string.h>

typedef struct jp {
    const char *p;
    int depth;
    char *why;
    size_t whylen;
    uint32_t *count; /* members of each container, in the order they open */
    size_t ncount;   /* containers opened so far in this reading */
    size_t cap;      /* of count */
    jnode *block;    /* the nodes: NULL in the first reading */
    size_t used;     /* nodes of the block placed */
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
        if (!*r->p) return fail(r, "the text ends in a string"); /* cut off */
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

/* A container opens: the first reading starts its count; the second
   gives it the block's next count[c] nodes. */
static int open_container(jp *r, jnode *n, size_t *c)
{
    *c = r->ncount++;
    if (r->block) {
        n->kid = r->block + r->used;
        r->used += r->count[*c];
        return 0;
    }
    if (*c == r->cap) {
        size_t cap = r->cap ? 2 * r->cap : 64;
        uint32_t *k = realloc(r->count, cap * sizeof *k);
        if (!k) return -1;
        r->count = k, r->cap = cap;
    }
    r->count[*c] = 0;
    return 0;
}

/* An object's or array's members. The first reading parses each into a
   scratch node and counts it. */
static int members(jp *r, jnode *n, char close)
{
    jnode scratch;
    size_t c;
    if (open_container(r, n, &c) != 0) return fail(r, "out of memory");
    r->p++;
    ws(r);
    if (*r->p == close) return r->p++, 0;
    for (;;) {
        jnode *k = &scratch;
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
        if (r->block)
            k = &n->kid[n->n++];
        else if (r->count[c]++ == UINT32_MAX - 1)
            return fail(r, "more than 2^32 - 2 members");
        memset(k, 0, sizeof *k);
        if (key) k->member = 1, k->keylen = (uint32_t)(keye - key);
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
    n->len = (uint32_t)(r->p - n->s); /* jdom_parse took no text of 4 GiB */
    return rc;
}

/* One reading of the whole text into root. */
static int reading(jp *r, const char *text, jnode *root)
{
    r->p = text, r->depth = 0, r->ncount = 0, r->used = 0;
    memset(root, 0, sizeof *root);
    if (value(r, root) != 0) {
        size_t at = (size_t)(r->p - text);
        size_t n = strlen(r->why);
        snprintf(r->why + n, r->whylen - n, " at byte %lu", (unsigned long)at);
        return -1;
    }
    ws(r);
    if (*r->p) {
        snprintf(r->why, r->whylen, "text after the value at byte %lu",
                 (unsigned long)(r->p - text));
        return -1;
    }
    return 0;
}

int jdom_parse(const char *text, jnode *root, char *why, size_t whylen)
{
    jp r;
    size_t i, total = 0;
    int rc;
    memset(&r, 0, sizeof r);
    r.why = why, r.whylen = whylen;
    memset(root, 0, sizeof *root);
    if (strlen(text) >= UINT32_MAX) {
        snprintf(why, whylen, "a text of 4 GiB or more");
        return -1;
    }
    if ((rc = reading(&r, text, root)) == 0) {
        for (i = 0; i < r.ncount; i++) total += r.count[i];
        /* one node more, so that every root owns a block (jdom_free) */
        if (!(r.block = malloc((total + 1) * sizeof *r.block))) {
            snprintf(why, whylen, "out of memory for %lu values", (unsigned long)total);
            rc = -1;
        } else {
            rc = reading(&r, text, root);
            root->kid = r.block; /* the root's members come first */
        }
    }
    free(r.count);
    return rc;
}

void jdom_free(jnode *root)
{
    free(root->kid);
    root->kid = NULL, root->n = 0;
}

const char *jdom_key(const jnode *n)
{
    const char *p = n->s;
    if (!n->member) return NULL;
    /* back over the whitespace and ':' between the key's quote and the value */
    do p--;
    while (*p != ':');
    do p--;
    while (*p != '"');
    return p - n->keylen;
}

const jnode *jdom_get(const jnode *obj, const char *key)
{
    size_t len = strlen(key);
    int i;
    if (!obj || obj->type != 'o') return NULL;
    for (i = 0; i < obj->n; i++)
        if (obj->kid[i].keylen == len && !memcmp(jdom_key(&obj->kid[i]), key, len))
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
    return a->len == b->len && !memcmp(a->s, b->s, a->len);
}

int jdom_str(const jnode *n, char *buf, size_t size)
{
    static const char esc[] = "\"\"\\\\//b\bf\fn\nr\rt\t";
    const char *p, *e;
    size_t k = 0;
    if (!n || n->type != 's' || !size) return -1;
    for (p = n->s + 1, e = jdom_end(n) - 1; p < e; p++) {
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
    fwrite(n->s, 1, n->len, f);
}
