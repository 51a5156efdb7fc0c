/* SPDX-License-Identifier: MIT */
/*
** optics_cases.h -- the hard-case classes of `ggrt optics check` and
** `ggrt optics seeds` (optics_cases.c): inputs where reflection,
** refraction and Fresnel code usually goes wrong.
*/
#ifndef GG_CLI_OPTICS_CASES_H
#define GG_CLI_OPTICS_CASES_H

#include "ggrt.h"

#include <stdint.h>

/* What is being checked: the signature of the function. */
enum oc_kind { OC_REFRACT, OC_REFLECT, OC_FRESNEL, OC_CONDUCTOR };

/* One input. Directions: v, n, ni, nt. Reflectances: c (cos_i), ni (the
   outside index), nt (the inside n), k (conductor's extinction). */
typedef struct oc_case {
    ggVec3 v, n;
    double ni, nt, c, k;
} oc_case;

typedef struct oc_rng {
    uint64_t s;
} oc_rng;

/* The classes of a kind, in order; NULL-terminated. */
const char *const *oc_classes(int kind);

/* Case number i of class cls (an index into oc_classes(kind)). */
void oc_make(int kind, int cls, oc_rng *r, oc_case *c);

uint64_t oc_next(oc_rng *r);

#endif
