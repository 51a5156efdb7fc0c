/* SPDX-License-Identifier: MIT */
/*
** jdom.h -- a small JSON reader (jdom.c) for ggrt merge --reports and
** plan files: the document as a tree of nodes pointing into the text
** (which must outlive the tree), so that a value can be written back
** exactly as it was read.
*/
#ifndef GG_CLI_JDOM_H
#define GG_CLI_JDOM_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* 32 bytes a node, all of a document's nodes in one block: a report of
   find's matches (8 nodes in about 90 bytes of text each) takes about 3
   times its size in nodes. */
typedef struct jnode {
    const char *s;     /* the value's text [s, s + len) */
    struct jnode *kid; /* its n members or elements */
    uint32_t len;      /* bytes of its text */
    uint32_t keylen;   /* an object member's key: bytes between its quotes */
    int n;             /* members or elements */
    char type;         /* 'o' object, 'a' array, 's' string, 'n' number, 't', 'f', 'z' null */
    char member;       /* 1 for an object's member (it has a key) */
} jnode;

/* Parse a whole document (one value): the text is read twice, the first
   time to count the nodes, so that they take one block of the size they
   need. 0, or -1 with the reason in why (and, for text that is not JSON,
   " at byte N"). Free the root with jdom_free, also after a failure. */
int jdom_parse(const char *text, jnode *root, char *why, size_t whylen);
void jdom_free(jnode *root);

/* The end of n's text. */
static inline const char *jdom_end(const jnode *n)
{
    return n->s + n->len;
}
/* The first byte of a member's key (after its quote; keylen bytes), or
   NULL for a node that is not an object's member. */
const char *jdom_key(const jnode *n);
/* The member key of an object (NULL if none or not an object). */
const jnode *jdom_get(const jnode *obj, const char *key);
/* A number's value (0 for anything else; null, ggrt's NaN or infinity,
   as infinity). */
double jdom_num(const jnode *n);
/* Two values with the same text (both NULL too). */
int jdom_same(const jnode *a, const jnode *b);
/* A string into buf with its escapes decoded. 0, or -1 if n is not a
   string, does not fit with its NUL, or has a \u escape of NUL or of
   anything beyond ASCII. */
int jdom_str(const jnode *n, char *buf, size_t size);
/* The value's text as it was read. */
void jdom_write(FILE *f, const jnode *n);

#endif
