/* SPDX-License-Identifier: MIT */
/*
** fuzz_json.c -- libFuzzer harness for the CLI's JSON reader
** (cli/render/jdom.c), which reads the reports of ggrt merge --reports and
** the plan files of --plan. Arbitrary bytes, cut at the first NUL as the
** CLI cuts a file with one (it refuses it). Never a crash or a leak, and
** these properties hold (abort() otherwise):
**   - an error says "... at byte N" with N at most the text's length;
**   - a document's text is the input without its surrounding whitespace,
**     and every node's text lies inside its parent's, in order;
**   - numbers and strings are JSON's, by the grammar written out again
**     here (no hex, inf, nan, '+', leading zeros, bare '.'; no control
**     byte or other escape in a string); strtod reads each number whole;
**     a string's decoded text is no longer than its body;
**   - a document written back compactly (keys and leaves as read, no
**     whitespace) parses again to the same tree, and written again is the
**     same bytes.
*/
#include "fuzz_text.h"
#include "render/jdom.h"

#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

typedef struct out {
    char *buf;
    size_t len, cap;
} out;

static void put(out *o, const char *s, size_t n)
{
    if (o->len + n + 1 > o->cap) {
        o->cap = 2 * (o->len + n + 1);
        o->buf = realloc(o->buf, o->cap);
        check(o->buf != NULL);
    }
    memcpy(o->buf + o->len, s, n);
    o->len += n;
    o->buf[o->len] = '\0';
}

/* The tree without whitespace: keys and leaves as they were read. */
static void compact(out *o, const jnode *n)
{
    int i;
    if (n->type != 'o' && n->type != 'a') {
        put(o, n->s, (size_t)n->len);
        return;
    }
    put(o, n->type == 'o' ? "{" : "[", 1);
    for (i = 0; i < n->n; i++) {
        const jnode *k = &n->kid[i];
        if (i) put(o, ",", 1);
        if (n->type == 'o') {
            put(o, jdom_key(k) - 1, (size_t)k->keylen + 2);
            put(o, ":", 1);
        }
        compact(o, k);
    }
    put(o, n->type == 'o' ? "}" : "]", 1);
}

/* JSON's number grammar, written out again: -?(0|[1-9][0-9]*)(.[0-9]+)?([eE][+-]?[0-9]+)? */
static int json_number(const char *p, const char *e)
{
    const char *d;
    if (p < e && *p == '-') p++;
    if (p < e && *p == '0') {
        p++;
    } else {
        for (d = p; p < e && *p >= '0' && *p <= '9'; p++) continue;
        if (p == d) return 0; /* a leading '0' took the branch above */
    }
    if (p < e && *p == '.') {
        for (d = ++p; p < e && *p >= '0' && *p <= '9'; p++) continue;
        if (p == d) return 0;
    }
    if (p < e && (*p == 'e' || *p == 'E')) {
        if (++p < e && (*p == '+' || *p == '-')) p++;
        for (d = p; p < e && *p >= '0' && *p <= '9'; p++) continue;
        if (p == d) return 0;
    }
    return p == e;
}

/* A JSON string's body: no control byte, only JSON's escapes. */
static int json_string(const char *p, const char *e)
{
    int k;
    for (; p < e; p++) {
        if ((unsigned char)*p < 0x20 || *p == '"') return 0;
        if (*p != '\\') continue;
        if (++p == e) return 0;
        if (strchr("\"\\/bfnrt", *p)) continue;
        if (*p != 'u' || e - p < 5) return 0;
        for (k = 1; k <= 4; k++)
            if (!strchr("0123456789abcdefABCDEF", p[k])) return 0;
        p += 4;
    }
    return 1;
}

static void leaf(const jnode *n)
{
    size_t len = (size_t)n->len;
    char *end, *str;
    switch (n->type) {
    case 'n':
        check(json_number(n->s, jdom_end(n)));
        strtod(n->s, &end);
        check(end == jdom_end(n));
        break;
    case 's':
        check(len >= 2 && n->s[0] == '"' && jdom_end(n)[-1] == '"' &&
              json_string(n->s + 1, jdom_end(n) - 1));
        str = malloc(len);
        check(str != NULL);
        if (jdom_str(n, str, len) == 0) check(strlen(str) <= len - 2);
        free(str);
        break;
    case 't':
        check(len == 4 && !memcmp(n->s, "true", 4));
        break;
    case 'f':
        check(len == 5 && !memcmp(n->s, "false", 5));
        break;
    case 'z':
        check(len == 4 && !memcmp(n->s, "null", 4));
        break;
    default:
        check(!"a node of no type");
    }
}

/* Nodes nest: each kid's text (and key) inside the parent's, in order. */
static void nested(const jnode *n)
{
    const char *at;
    int i;
    check(n->s < jdom_end(n));
    if (n->type != 'o' && n->type != 'a') {
        check(n->n == 0);
        leaf(n);
        return;
    }
    check(n->s[0] == (n->type == 'o' ? '{' : '[') &&
          jdom_end(n)[-1] == (n->type == 'o' ? '}' : ']'));
    for (at = n->s + 1, i = 0; i < n->n; i++) {
        const jnode *k = &n->kid[i];
        if (n->type == 'o') {
            const char *key = jdom_key(k);
            check(k->member && key > at && key[-1] == '"' && key[k->keylen] == '"');
            check(key + k->keylen < k->s);
        } else {
            check(!k->member && !jdom_key(k) && k->keylen == 0);
        }
        check(k->s >= at && jdom_end(k) < jdom_end(n));
        nested(k);
        at = jdom_end(k);
    }
}

static int same_tree(const jnode *a, const jnode *b)
{
    int i;
    if (a->type != b->type || a->n != b->n) return 0;
    if (a->member != b->member || a->keylen != b->keylen ||
        (a->member && memcmp(jdom_key(a), jdom_key(b), a->keylen)))
        return 0;
    if (a->type != 'o' && a->type != 'a') return jdom_same(a, b);
    for (i = 0; i < a->n; i++)
        if (!same_tree(&a->kid[i], &b->kid[i])) return 0;
    return 1;
}

/* "... at byte N", N <= len. */
static void error_place(const char *why, size_t len)
{
    const char *at = strstr(why, " at byte ");
    char *end;
    unsigned long n;
    check(at != NULL);
    n = strtoul(at + 9, &end, 10);
    check(end > at + 9 && *end == '\0' && n <= len);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1), why[200];
    const char *s, *e;
    jnode root, again;
    out o = {NULL, 0, 0}, o2 = {NULL, 0, 0};
    if (!text) return 0;
    memcpy(text, data, size);
    text[size] = '\0';
    if (jdom_parse(text, &root, why, sizeof why) != 0) {
        error_place(why, strlen(text));
        jdom_free(&root);
        free(text);
        return 0;
    }
    for (s = text; *s == ' ' || *s == '\t' || *s == '\n' || *s == '\r'; s++) continue;
    for (e = text + strlen(text); e > s && strchr(" \t\n\r", e[-1]); e--) continue;
    check(root.s == s && jdom_end(&root) == e && !root.member);
    nested(&root);
    compact(&o, &root);
    check(jdom_parse(o.buf, &again, why, sizeof why) == 0);
    check(same_tree(&root, &again));
    compact(&o2, &again);
    check(o2.len == o.len && !memcmp(o2.buf, o.buf, o.len));
    jdom_free(&again);
    jdom_free(&root);
    free(o.buf), free(o2.buf), free(text);
    return 0;
}
