/* SPDX-License-Identifier: MIT */
/*
** json.h -- the CLI's one JSON writer (trace, find, check, diff, optics
** check, serve). Each function writes one value, or `"key":value` when it
** takes a key, to a FILE*, so that ggrt serve writes the same documents
** into memory (open_memstream). Documents: docs/trace-json.md,
** docs/debugging.md, docs/serve.md.
*/
#ifndef GG_CLI_JSON_H
#define GG_CLI_JSON_H

#include "ggrt.h"

#include <stdio.h>

/* Numbers. JSON has no NaN or infinity; two rules stand for them:
   json_num writes null (find, check, diff, serve), json_num_text the
   strings "nan", "inf", "-inf" (the trace document's rule since its
   version 2, docs/trace-json.md); json_num_opt writes a NaN, the
   library's "does not apply", as null and anything else as json_num_text.
   Finite numbers as %.17g (they read back to the same double). */
void json_num(FILE *f, double d);
void json_num_text(FILE *f, double d);
void json_num_opt(FILE *f, double d);

/* The CLI's one JSON string writer: ", \ and control characters escaped;
   a byte that is not UTF-8 becomes the text \xHH, the way the library's
   messages show it, so the document always parses and says which byte
   it was. */
void json_str(FILE *f, const char *s);

/* Three numbers as an array, `"key":[r,g,b]` (no key when key is NULL):
   json_color and json_vec with json_num, the _text forms with
   json_num_text. */
void json_color(FILE *f, const char *key, ggColor c);
void json_color_text(FILE *f, const char *key, ggColor c);
void json_vec(FILE *f, const char *key, ggVec3 v);
void json_vec_text(FILE *f, const char *key, ggVec3 v);

/* The options as ggRenderOptionsFormat text. */
void json_options(FILE *f, const char *key, const ggRenderOptions *opt);
/* Ray counts: {"eye","reflect","refract","shadow","tir","shadow_blocked",
   "shadow_attenuated"} (reflect counts the TIR rays too; tir says how
   many of them; the last two, how many shadow rays had each verdict). */
void json_stats(FILE *f, const char *key, const ggRayStats *st);

#endif
