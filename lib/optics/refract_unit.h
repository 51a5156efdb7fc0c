/* SPDX-License-Identifier: MIT */
/*
** refract_unit.h -- the renderer's refraction (internal, inlined into
** the shading loop; tests/unit/optics/test_refract_unit.c measures it).
*/
#ifndef GG_REFRACT_UNIT_H
#define GG_REFRACT_UNIT_H

#include "ggrt.h"
#include "vec.h"

#include <math.h>
#include <stdbool.h>

/* The renderer's refraction of unit v about unit n: the plain-double
   formula t = eta v + (eta c - cos_t) n where it is well conditioned, and
   the exact ggRefract everywhere else. The plain form's rounding is a few
   units of 2^-53 in c and eta, which the square root of
   k = cos_t^2 = 1 - eta^2 (1 - c^2) magnifies by about eta^2 / k: with
   k >= 1/16 and eta <= 2 that stays below 2^-45 relative (measured by
   tests/unit/optics/test_refract_unit.c), the size of the error the unit inputs carry
   anyway (the normal of a hit point is itself good to a few ulp). Near the
   critical angle, and for total internal reflection, the problem is
   ill-conditioned and ggRefract's exact decision and double-double
   arithmetic are worth their cost, as for rays grazing the surface so
   closely that the side they come from is in doubt. GG_ACC_REFRACT_EXACT sends every ray
   to ggRefract. */
static inline bool gg_refract_unit(ggVec3 v, ggVec3 n, double ni, double nt, ggVec3 *t)
{
    double c = -v3dot(v, n), eta = ni / nt, k;
    /* |c| >= 2^-40: which side v comes from is certain (the dot product
       of unit vectors is good to a few 2^-53); below that, a ray in the
       plane of the surface, ggRefract works the side out exactly. */
    if (eta > 0.5 && eta < 2 && fabs(c) >= 0x1p-40) {
        if (c < 0) n = v3neg(n), c = -c;
        k = 1.0 - eta * eta * ((1.0 - c) * (1.0 + c));
        if (k >= 0.0625) {
            *t = v3add(v3scale(v, eta), v3scale(n, eta * c - sqrt(k)));
            return true;
        }
    }
    return ggRefract(v, n, ni, nt, t);
}

#endif
