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
#include <stdio.h>

typedef struct jnode {
    char type;              /* 'o' object, 'a' array, 's' string, 'n' number, 't', 'f', 'z' null */
    const char *s, *e;      /* the value's text [s, e) */
    const char *key, *keye; /* an object member's key, without its quotes */
    int n;                  /* members or elements */
    struct jnode *kid;
} jnode;

/* Parse a whole document (one value). 0, or -1 with the reason and the
   byte in why. Free with jdom_free, also after a failure. */
int jdom_parse(const char *text, jnode *root, char *why, size_t whylen);
void jdom_free(jnode *n);

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
