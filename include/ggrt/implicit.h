/*
** ggrt/implicit.h -- implicit surfaces f(x, y, z) = 0 with gradient normals
** N = grad f. From a text expression (exact gradients by forward-mode
** automatic differentiation) or from C callbacks.
** (Being completed under issue 3.)
*/
#ifndef GGRT_IMPLICIT_H
#define GGRT_IMPLICIT_H

#include "ggrt/base.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct ggImplicit ggImplicit;

/* f(p) and optionally its gradient, supplied by the caller. */
typedef double (*ggImplicitFn)(void *ud, ggVec3 p);
typedef ggVec3 (*ggImplicitGradFn)(void *ud, ggVec3 p);

/* Parse an expression in x, y, z (numbers, + - * / ^, unary -, parentheses,
   sqrt sin cos tan exp log abs min max pow). The surface is f = 0 inside
   the box [lo, hi]. Errors name the column: "1:7: unknown function 'sinn'". */
GG_API int ggImplicitCreateExpr(const char *expr, ggVec3 lo, ggVec3 hi,
                                const ggAllocator *alloc, ggImplicit **out, ggError *err);
/* From callbacks; grad may be NULL (central differences are then used). */
GG_API int ggImplicitCreateFn(ggImplicitFn f, ggImplicitGradFn grad, void *ud, ggVec3 lo,
                              ggVec3 hi, const ggAllocator *alloc, ggImplicit **out,
                              ggError *err);
GG_API void ggImplicitFree(ggImplicit *imp);

GG_API double ggImplicitEval(const ggImplicit *imp, ggVec3 p);
/* Unnormalised grad f at p: exact for expressions and when a gradient
   callback was given, central differences otherwise. */
GG_API ggVec3 ggGradientNormal(const ggImplicit *imp, ggVec3 p);
/* Central differences with step h on each axis (for measuring accuracy). */
GG_API ggVec3 ggGradientCentral(const ggImplicit *imp, ggVec3 p, double h);

#ifdef __cplusplus
}
#endif
#endif
