/* SPDX-License-Identifier: MIT */
/*
** ggrt/optics.h -- reflection, refraction, Fresnel reflectance and
** Beer-Lambert absorption.
**
** Conventions (docs/optics.md derives every formula):
**  - v is the direction of the incoming ray: it travels TOWARDS the
**    surface. n is the surface normal; it may face either way.
**  - ni is the refractive index on v's side, nt the one on the far side.
**    Only eta = ni/nt matters for directions. A negative index describes a
**    metamaterial (Veselago 1968, Pendry 2000): the ray bends to the same
**    side of the normal.
**  - Angles are measured from the normal; cos_i = |v.n| / (|v| |n|).
**  - Reflectances are fractions of power in [0, 1]; "unpolarised" is the
**    mean of the s (TE) and p (TM) reflectances.
**  - Nothing here allocates, prints, aborts or keeps state: every function
**    is thread-safe. No function raises FE_INVALID, FE_DIVBYZERO or
**    FE_OVERFLOW for finite arguments (overflow of an unrepresentable
**    result excepted, see ggReflection).
*/
#ifndef GGRT_OPTICS_H
#define GGRT_OPTICS_H

#include "ggrt/base.h"

#ifdef __cplusplus
extern "C" {
#endif

/* r = v - 2 n (v.n) for a unit n; v is the incoming direction, n the
   normal, of any length: n/|n| is used, so r always has the length of
   v and is its mirror image in the plane normal to n. Each component is
   within 1 ulp of |v| of the exact mirror image of the given doubles (it
   is evaluated in double-double and rounded once; docs/optics.md). A
   component is subnormal, and may carry another 2^-1075, only when
   |v| < 2^-1021.
   Non-finite components or a zero n give (NaN, NaN, NaN); a zero v gives
   v. Overflow (FE_OVERFLOW) is possible only when a component of the exact
   result exceeds DBL_MAX, i.e. |v| > DBL_MAX. */
GG_API ggVec3 ggReflection(ggVec3 v, ggVec3 n);

/* Refract direction v (travelling towards the surface) through a surface
   with normal n, which may face either way, from index ni (v's side) into
   nt; v and n of any length (below). Returns true and writes the unit
   transmitted direction to *t; on total internal reflection returns false
   and writes the mirror direction. A negative nt (a metamaterial, as in
   Veselago's and Pendry's work) bends the ray to the same side of the
   normal.

   Details (docs/optics.md derives and measures all of this):
    - v and n need not be unit length; only their directions are used
      (both are rescaled internally by powers of two), and *t is always
      unit length. Scaling v, n or both indices by powers of two gives
      bit-identical results, and so does replacing n by -n. Where the
      double-double fallback decides (see Cost) and |eta| <= 2^400,
      components smaller than 2^-480 times the largest component of the
      same vector are treated as zero in forming *t (they move it by less
      than 2^-80 ulp); the side v comes from, and so whether it crosses,
      is still decided from the exact v.n of the given doubles, for a
      normal part of v down to 2^-1074 of its tangential part.
    - Accuracy, for every finite non-zero v, n, ni and nt (any eta, from
      2^-2098 to 2^2098, of either sign): each component of *t is within
      1 ulp (2^-53, the spacing of doubles in [0.5, 1)) of the exact
      refraction or reflection of the directions of the given doubles --
      at grazing incidence, for eta near 1, at normal incidence, near the
      critical angle, for negative indices. The one exception is a
      transmitted ray within 2^-40 rad of the surface (only inputs within
      about 2^-80 of the critical angle give one), where the bound is
      4 ulp. Components of *t below 2^-1022 are subnormal (still within
      the bound); *t cannot overflow.
    - The total-internal-reflection decision is the sign of the
      discriminant nt^2 |v|^2 cos^2(theta_t), evaluated in double-double
      arithmetic: for every eta it agrees with exact arithmetic on the
      given doubles unless |cos^2(theta_t)| < 2^-96, i.e. unless the
      incidence angle is within about 2^-97 (relative) of the critical
      one. At exactly the critical angle the ray is transmitted along the
      surface (returns true).
    - ni == nt gives t = v/|v| (and true unless v.n == 0 exactly);
      normal incidence gives t = v/|v|.
    - v exactly tangent to the surface (v.n == 0 in exact arithmetic)
      never crosses it: returns false and writes v/|v| (its own mirror
      direction).
    - Invalid input -- a non-finite component or index, a zero v or n, or
      ni == 0 or nt == 0 -- returns false and writes (NaN, NaN, NaN).
    - t may be NULL: only the decision is returned.
    - Cost: a fast path in double-double with a running error bound
      certifies the 1-ulp result wherever it can (0 < eta <= 4, away from
      the critical angle and the surface plane); the rest goes to a full
      double-double evaluation, and inputs with |ni/nt| > 2^450 whose v
      or n has a component more than 1022 binades below its largest, or
      that are transmitted, to a 512-bit one (some 20 microseconds).
      Figures: make bench-optics, docs/performance.md. */
GG_API bool ggRefract(ggVec3 v, ggVec3 n, double ni, double nt, ggVec3 *t);

/* The textbook formula, kept for the accuracy study and the benchmark:
      c = -v.n (n flipped to face v), eta = ni/nt,
      k = 1 - eta^2 (1 - c^2);  TIR if k < 0, else
      t = eta v + (eta c - sqrt(k)) n.
   Same return convention as ggRefract, but v and n must be unit vectors,
   nothing is validated (NaN in, NaN out) and the result loses accuracy at
   grazing incidence, near the critical angle and for eta near 1 (see
   docs/optics.md). ni and nt must be non-zero. */
GG_API bool ggRefractTextbook(ggVec3 v, ggVec3 n, double ni, double nt, ggVec3 *t);

/* The critical angle in radians, asin(|nt| / |ni|), beyond which light
   going from ni into nt is totally reflected; pi/2 when |nt| >= |ni| (no
   total internal reflection). NaN if an index is zero or not finite.
   Computed as atan2(|nt|, sqrt((|ni|-|nt|)(|ni|+|nt|))), accurate also
   when nt is close to ni. */
GG_API double ggCriticalAngle(double ni, double nt);

/* Fresnel reflectance of a smooth interface between two dielectrics,
   unpolarised: (Rs + Rp) / 2, for light arriving from index ni at an
   angle whose cosine is cos_i (its sign is ignored; |cos_i| > 1 is
   clamped to 1). Returns 1 under total internal reflection and at grazing
   incidence (cos_i == 0), 0 when ni == nt, ((ni-nt)/(ni+nt))^2 at normal
   incidence. The transmittance is 1 - R (no absorption at the interface).
   Negative indices are taken as Veselago media with both epsilon and mu
   negative, whose impedance equals that of |n|: the reflectance is that of
   |ni|, |nt|. NaN if an argument is not finite or an index is zero.
   Evaluated without cancellation (the numerators of the amplitude
   coefficients are rewritten with nt^2 - ni^2 as a factor) in
   double-double: within 1 ulp of R (2^-53 times the smallest power of two
   >= R) for every finite input, also near the critical angle, for ni close
   to nt (where R is tiny), for subnormal cosines and for any index ratio
   (up to 2^2097). */
GG_API double ggFresnelDielectric(double cos_i, double ni, double nt);

/* The same with both polarisations: *rs (s, TE, E perpendicular to the
   plane of incidence) and *rp (p, TM). Either pointer may be NULL. Each is
   within 1 ulp of itself, Rp also at and near Brewster's angle, where it
   vanishes. */
GG_API void ggFresnelDielectricPolarized(double cos_i, double ni, double nt, double *rs,
                                         double *rp);

/* Fresnel reflectance, unpolarised, of a conductor (or any absorbing
   medium) with complex refractive index n + i k, seen from a dielectric of
   real index n_outside, at incidence cosine cos_i (sign ignored, clamped
   to 1). With k == 0 it equals ggFresnelDielectric(cos_i, n_outside, n).
   At normal incidence it is ((n-n1)^2 + k^2) / ((n+n1)^2 + k^2), n1 =
   |n_outside|. Requires n >= 0, k >= 0, not both zero, n_outside != 0;
   otherwise (or for a non-finite argument) NaN. Typical values (n, k):
   gold at 650 nm (0.14, 3.70), silver at 550 nm (0.06, 3.59), aluminium
   at 550 nm (0.96, 6.69).
   Within 1 ulp of R (2^-53 times the smallest power of two >= R) for
   every valid input, where R is at least 2^-1022; a smaller R is
   subnormal and within 2^-1074 (at normal incidence R underflows to 0
   when n == n_outside and k is below about 2^-537 n; towards grazing
   cosines it grows to 1 for every k down to 2^-1074, whose bits are all
   kept). That includes a tiny k between nearly or
   exactly matched indices (R down to 2^-110 and below), the critical
   angle of a weakly absorbing medium, grazing incidence (exactly 1 at
   cos_i == 0) and every index ratio (for |n + ik| < 2^-299 |n_outside|, R
   is within 2^-296 of 1 and returned as 1). Evaluated in double-double
   from forms in which only differences of exact products can cancel
   (docs/optics.md, "Conductors"). 1 - R (the absorbed fraction) computed
   from the result is exact for R >= 1/2 but keeps R's absolute error of
   up to 2^-54, so it is within 1 ulp of itself only while 1 - R >= 1/4. */
GG_API double ggFresnelConductor(double cos_i, double n_outside, double n, double k);

/* The same with both polarisations, each evaluated to the same precision
   and rounded once; either pointer may be NULL. (The 1-ulp bound above is
   for R: Rs and Rp are not bounded separately; near the pseudo-Brewster
   angle Rp is a negligible part of R, docs/optics.md, "Conductors".) */
GG_API void ggFresnelConductorPolarized(double cos_i, double n_outside, double n, double k,
                                        double *rs, double *rp);

/* Schlick's approximation of ggFresnelDielectric: R0 + (1 - R0)(1 - c)^5,
   R0 = ((ni - nt)/(ni + nt))^2. c is cos_i when |ni| <= |nt|; going into a
   less dense medium it is the cosine of the transmitted angle (as Schlick
   prescribes), and the result is 1 under total internal reflection.
   Cheaper, and off by up to about 0.05 near grazing angles. Same argument
   conventions and invalid results as ggFresnelDielectric. */
GG_API double ggFresnelSchlick(double cos_i, double ni, double nt);

/* Absorption coefficient alpha = 4 pi k / lambda of a medium with
   extinction coefficient k (the imaginary part of its refractive index)
   at vacuum wavelength lambda, in inverse units of lambda. NaN if k < 0,
   lambda <= 0 or either is not finite; +inf if it overflows (only for
   absurdly small lambda). */
GG_API double ggAbsorptionCoefficient(double k, double lambda);

/* Beer-Lambert transmittance exp(-alpha d), alpha = 4 pi k / lambda, of a
   path of length `distance` (same unit as lambda) through a medium with
   extinction coefficient k. Exactly 1 when k == 0 or distance == 0
   (whatever the other argument, even +inf); decreases to 0 (also for
   distance == +inf). T(d1 + d2) = T(d1) T(d2) up to rounding. NaN if
   k < 0, lambda <= 0, distance < 0, or an argument is NaN or an infinite
   k or lambda. Example: pure water absorbs about 0.34 per metre at 650 nm
   and 0.0092 per metre at 450 nm (Pope and Fry 1997), i.e. k about 1.8e-8
   and 3.3e-10: one metre transmits 71% of red and 99% of blue light. */
GG_API double ggBeerLambert(double k, double lambda, double distance);

/* Per-channel Beer-Lambert: each channel of k and lambda is one wavelength
   sample. Invalid channels give NaN in that channel only. */
GG_API ggColor ggBeerLambertColor(ggColor k, ggColor lambda, double distance);

/* ------------------------------------------------------------------ */
/* Measuring anyone's result (lib/optics/error.c)                       */
/* ------------------------------------------------------------------ */

/* The error of a candidate reflected or refracted direction, filled by
   ggReflectionError and ggRefractError.

   The unit ("ulp") of max_ulp and norm_ulp is 2^-53 times the smallest
   power of two >= the largest component magnitude of the exact result:
   2^-53 for a unit vector (whose largest component is in (0.577, 1]), the
   spacing of doubles in [0.5, 1); for a reflection it is the ulp of |v|'s
   binade. comp_ulp[i] uses each component's own unit, 2^-53 times the
   smallest power of two >= |exact_i|. No unit is below 2^-1074, the
   spacing of subnormals: where the exact value underflows, a correctly
   rounded subnormal or zero is at most 1/2 unit off. */
typedef struct ggDirectionError {
    double max_ulp;      /* max_i |candidate_i - exact_i| / unit */
    double norm_ulp;     /* |candidate - exact| (Euclidean) / unit */
    double comp_ulp[3];  /* |candidate_i - exact_i| in component i's own unit: 0
                            if equal, +inf if exact_i == 0 != candidate_i */
    double unit;         /* the unit of max_ulp and norm_ulp, a power of two */
    ggVec3 exact;        /* the exact direction, rounded to nearest */
    int finite;          /* the candidate's components are all finite */
    int exact_tir;       /* refraction: 1 total internal reflection, 0
                            transmitted, -1 v in the surface (v.n == 0 exactly:
                            not transmitted). 0 for a reflection */
    int tir_agrees;      /* the candidate's decision is the exact one */
    int certain;         /* exact_tir is outside the reference's own error band
                            (|cos2_t| > 2^-499, or no rounding at all) */
    double cos2_t;       /* the margin: exact cos^2(theta_t), that is
                            1 - eta^2 sin^2(theta_i), rounded; negative under
                            TIR, 0 exactly at the critical angle; 1 for v in
                            the surface and for a reflection */
    double critical_rad; /* theta_i - theta_c in radians (positive: beyond the
                            critical angle, TIR); NaN when |ni| <= |nt| */
} ggDirectionError;

/* Measure candidate, someone's refraction of v through a surface with
   normal n from index ni into nt (ggRefract's arguments and conventions),
   against the exact result for the given doubles.

   candidate_tir is the candidate's decision: true if it reports total
   internal reflection (or otherwise no transmission), i.e. the negation of
   what a function with ggRefract's signature returned. The error is
   measured against the exact direction of the branch the candidate chose:
   the unit transmitted direction (with cos(theta_t) taken as 0 if the
   exact answer is TIR), or the unit mirror direction; for v exactly in the
   surface, v/|v| either way (ggRefract's convention). e->tir_agrees and
   e->cos2_t say whether that branch was the right one and by what margin.
   A non-finite candidate component gives +inf errors.

   The exact value is evaluated in 512-bit binary floating point (bigf.h)
   from sums of products of the given doubles (docs/optics.md). Its own
   error is below 2^-190 ulp in each component, plus 2^-450 |ni/nt| ulp
   when the tangential part of v had to be rounded, which takes components
   of v and n more than about 100 binades apart; the decision
   e->exact_tir is exact whenever e->certain is set.

   Returns GG_OK, or GG_ERROR_INVALID (e zeroed) if e is NULL or the
   arguments are ones for which ggRefract returns NaN: a non-finite or zero
   vector, a non-finite or zero index. Thread-safe, allocates nothing;
   some 40 microseconds a call. */
GG_API int ggRefractError(ggVec3 v, ggVec3 n, double ni, double nt, ggVec3 candidate,
                          bool candidate_tir, ggDirectionError *e);

/* The same for a reflection: candidate against the exact mirror image of
   v in the plane normal to n, v - 2 n (v.n)/(n.n), which has the length of
   v (ggReflection's convention). The reference's own error is below
   2^-450 ulp. exact_tir is 0, tir_agrees and certain 1, cos2_t 1.
   Returns GG_OK, or GG_ERROR_INVALID if e is NULL, v or n is zero or has a
   non-finite component. */
GG_API int ggReflectionError(ggVec3 v, ggVec3 n, ggVec3 candidate, ggDirectionError *e);

/* The error of a candidate reflectance, filled by ggFresnelDielectricError
   and ggFresnelConductorError. Units: 2^-53 times the smallest power of two
   >= the exact value (of R for ulp, of 1 - R for complement_ulp), or
   2^-1074 (the spacing of subnormals, the contract's unit where R
   underflows) if that is larger: a correctly rounded subnormal or zero R
   is at most 1/2 ulp off. */
typedef struct ggReflectanceError {
    double ulp;              /* |candidate - R| in units of R */
    double exact;            /* R, rounded to nearest */
    double complement_ulp;   /* |(1 - candidate) - (1 - R)|, in units of 1 - R
                                (the transmitted or absorbed fraction) */
    double complement_exact; /* 1 - R, rounded to nearest */
    int finite;              /* the candidate is finite */
} ggReflectanceError;

/* candidate, someone's unpolarised dielectric reflectance for
   ggFresnelDielectric's arguments (same conventions: the sign of cos_i is
   ignored, |cos_i| > 1 is 1, cos_i == 0 gives 1, |ni| == |nt| gives 0),
   against the exact R evaluated in 512-bit arithmetic; the reference's own
   error is below 2^-340 ulp of R. Returns GG_OK, or GG_ERROR_INVALID if e
   is NULL or ggFresnelDielectric would return NaN. */
GG_API int ggFresnelDielectricError(double cos_i, double ni, double nt, double candidate,
                                    ggReflectanceError *e);

/* The same for ggFresnelConductor's arguments (n + ik seen from
   n_outside). The reference's absolute error is below 2^-480, so below
   2^-400 ulp of R and of 1 - R unless that is below 2^-27 (docs/optics.md,
   "The reference", also for cosines down to 2^-1074). Returns GG_OK,
   or GG_ERROR_INVALID if e is NULL or ggFresnelConductor would return
   NaN. */
GG_API int ggFresnelConductorError(double cos_i, double n_outside, double n, double k,
                                   double candidate, ggReflectanceError *e);

#ifdef __cplusplus
}
#endif
#endif
