/* SPDX-License-Identifier: MIT */
/*
** bigf.h -- a small binary floating-point type of 512-bit precision
** (internal), the reference of the error-measurement functions (error.c).
**
** A gg_bf is sign * 0.m * 2^exp with m GG_BF_LIMBS 32-bit limbs, most
** significant first, normalised so that the top bit of m[0] is set (zero
** has sign 0). The exponent is an int: no overflow or underflow for any
** product of a few doubles. Every operation truncates (rounds towards
** zero) to 512 bits: with u = 2^-511,
**   add, sub   |error| <= u max(|a|, |b|)  (exact when the exact result
**              fits in 512 bits, e.g. a sum of two products of two
**              doubles whose exponents are less than 400 apart),
**   mul        relative error <= u,
**   div, sqrt  relative error <= 8u (Newton iterations from a double
**              estimate, each doubling the correct bits, then one
**              correction step).
** `inexact` is set on a result when it, or an operand it came from, was
** rounded; div and sqrt always set it.
*/
#ifndef GG_BIGF_H
#define GG_BIGF_H

#include "compiler.h" /* IEEE arithmetic required */

#include <stdint.h>

#define GG_BF_LIMBS 16

typedef struct gg_bf {
    int sign;    /* -1, 0 or 1 */
    int inexact; /* this value, or one it was computed from, was rounded */
    int exp;
    uint32_t m[GG_BF_LIMBS];
} gg_bf;

gg_bf gg_bf_from(double x);
/* Rounded to the nearest double (subnormal results may round twice). */
double gg_bf_to_double(gg_bf a);
gg_bf gg_bf_add(gg_bf a, gg_bf b);
gg_bf gg_bf_sub(gg_bf a, gg_bf b);
gg_bf gg_bf_mul(gg_bf a, gg_bf b);
/* b must not be zero. */
gg_bf gg_bf_div(gg_bf a, gg_bf b);
/* 0 for a <= 0. */
gg_bf gg_bf_sqrt(gg_bf a);
gg_bf gg_bf_neg(gg_bf a);
/* a * 2^e, exact. */
gg_bf gg_bf_scale2(gg_bf a, int e);
/* -1, 0, 1 as |a| <, ==, > |b|. */
int gg_bf_cmpabs(gg_bf a, gg_bf b);
/* The e with 2^(e-1) < |a| <= 2^e (the smallest power of two >= |a|),
   for a != 0. */
int gg_bf_ceil_expo(gg_bf a);

#endif
