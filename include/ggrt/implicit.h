/* SPDX-License-Identifier: MIT */
/*
** ggrt/implicit.h -- implicit surfaces f(x, y, z) = 0 inside a box, with
** gradient normals N = grad f.
**
** Two kinds:
**  - from a text expression ("(x^2+y^2+z^2+0.75)^2 - 4*(x^2+y^2)"). The
**    expression is compiled once; its gradient is exact (forward-mode
**    automatic differentiation) and its roots along a ray are isolated with
**    interval arithmetic, which proves where f cannot vanish: thin parts
**    are not missed and near misses are not reported as hits;
**  - from C callbacks, f and optionally grad f. Roots are bracketed with a
**    gradient (Lipschitz) bound L, |f(p) - f(q)| <= L |p - q|: no root can
**    lie within |f(p)| / L of p, so the ray advances by that much. If L is
**    too small, parts of the surface may be stepped over. The library
**    notices when two samples differ by more than L allows and raises
**    GG_IMPLICIT_WARN_GRADIENT (see ggImplicitWarnings), like POV-Ray's
**    isosurface max_gradient warning; ggImplicitMaxSlope then tells which
**    bound would have been enough along the rays traced.
**
** Hits are refined by Newton's method, safeguarded by bisection (or by the
** Illinois method when no derivative is known), to the tolerance set by
** ggImplicitSetTolerance.
**
** Threads: after creation and settings, an object may be used from any
** number of threads at once; intersection writes nothing to it except the
** warning flags and the slope maximum, which are updated atomically.
** Callbacks must then be thread-safe too.
*/
#ifndef GGRT_IMPLICIT_H
#define GGRT_IMPLICIT_H

#include "ggrt/base.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct ggImplicit ggImplicit;

/* f(p) and its gradient, supplied by the caller; `ud` is passed back
   unchanged. f may return NaN where it is undefined: no surface there. */
typedef double (*ggImplicitFn)(void *ud, ggVec3 p);
typedef ggVec3 (*ggImplicitGradFn)(void *ud, ggVec3 p);

/* Limits of ggImplicitCreateExpr; beyond them it returns GG_ERROR_LIMIT. */
#define GG_IMPLICIT_MAX_EXPR  4096 /* bytes of expression text */
#define GG_IMPLICIT_MAX_TAPE  1024 /* operations after folding and sharing */
#define GG_IMPLICIT_MAX_DEPTH 64   /* nesting of (), calls, unary signs, ^ */

/* Compile an expression in x, y, z and make the surface f = 0 inside the
   box [lo, hi] (lo < hi on every axis, all finite, and a diagonal
   |hi - lo| that is finite in double: sides up to about 1e154).
   The language: numbers (2, 0.5, .5, 1e-3), the variables x y z, the
   constant pi, + - * / ^ with the usual precedence, unary minus (-x^2 is
   -(x^2); ^ is right associative: 2^3^2 = 2^9), parentheses, and the
   functions sqrt sin cos tan exp log abs, pow(a, b), min(a, b, ...),
   max(a, b, ...). Spaces, tabs and newlines are ignored. a^n with a
   constant integer n is defined for every a (x^3 < 0 for x < 0); with any
   other constant exponent for a >= 0; with a non-constant exponent it is
   exp(n log a), for a > 0. Where f is undefined (sqrt(-1), log(0), a / 0...)
   there is no surface. Constant parts are computed once, at compile time,
   and repeated parts shared (x^2 written twice costs one product).
   On success *out receives the surface (free it with ggImplicitFree);
   on failure *out is NULL and err (optional) names the place as
   "line:column: message", counting from 1, e.g.
   "1:7: unknown function 'sinn'", which a scene loader can prefix with its
   file name and line. Returns GG_OK, GG_ERROR_PARSE, GG_ERROR_LIMIT (see
   GG_IMPLICIT_MAX_*), GG_ERROR_INVALID (NULL expr or out, bad box) or
   GG_ERROR_NOMEM. alloc may be NULL (malloc); it is copied. */
GG_API int ggImplicitCreateExpr(const char *expr, ggVec3 lo, ggVec3 hi, const ggAllocator *alloc,
                                ggImplicit **out, ggError *err);

/* Make the surface f = 0 inside [lo, hi] from callbacks. grad may be NULL:
   normals then come from central differences and root refinement does not
   use derivatives. Since nothing is known about f, a gradient bound is
   estimated here by sampling f on a 17 x 17 x 17 grid over the box (twice
   the largest difference quotient seen, so f is called 4913 times now);
   set the true bound with ggImplicitSetGradientBound when you know it.
   Returns GG_OK, GG_ERROR_INVALID (NULL f or out, bad box) or
   GG_ERROR_NOMEM; *out is NULL on failure. */
GG_API int ggImplicitCreateFn(ggImplicitFn f, ggImplicitGradFn grad, void *ud, ggVec3 lo, ggVec3 hi,
                              const ggAllocator *alloc, ggImplicit **out, ggError *err);

/* Free the surface; NULL is a no-op. */
GG_API void ggImplicitFree(ggImplicit *imp);

/* ---- settings (before the object is shared between threads) ---- */

/* Root-finding tolerance in scene units: hits are located to within about
   tol (usually far better: Newton's last step squares the error), and
   parts of the surface thinner than about tol may be missed. Default
   1e-12 times the box diagonal. Returns GG_ERROR_INVALID unless tol is
   finite and > 0. */
GG_API int ggImplicitSetTolerance(ggImplicit *imp, double tol);

/* The gradient (Lipschitz) bound L >= max |grad f| over the box, in f
   units per scene unit, used by the Lipschitz method. A larger L is safer
   and slower (steps are |f| / L). Returns GG_ERROR_INVALID unless L is
   finite and > 0. */
GG_API int ggImplicitSetGradientBound(ggImplicit *imp, double L);
/* The bound in use: the one set, or the estimate (0 for an expression
   surface that was never switched to the Lipschitz method). */
GG_API double ggImplicitGradientBound(const ggImplicit *imp);

/* GG_IMPLICIT_LIPSCHITZ steps along the ray by |f| / L, never less than
   1e-9 times the box diagonal (more after 16 such steps in a row, when a
   ray crawls along the surface), so parts thinner than that may be missed.
   Steps are also at most 1/16 of the ray's way through the box, so that a
   bound far too small shows as GG_IMPLICIT_WARN_GRADIENT. It suits f that
   grow like the distance to the surface (signed distance functions, L =
   1); where f vanishes to second order or more (the quartic form of a thin
   torus), steps shrink with |f| and the interval method is far faster. */
#define GG_IMPLICIT_INTERVAL  0 /* interval arithmetic (expressions; the default) */
#define GG_IMPLICIT_LIPSCHITZ 1 /* stepping by |f| / L (callbacks: always) */

/* Choose how roots are found. Callback surfaces have no interval form, so
   GG_IMPLICIT_INTERVAL is refused for them (GG_ERROR_UNSUPPORTED). An
   expression surface switched to GG_IMPLICIT_LIPSCHITZ without a bound set
   estimates one as ggImplicitCreateFn does (from its exact gradient). This
   is for comparing the methods; the default is the better one. Returns
   GG_OK, GG_ERROR_INVALID or GG_ERROR_UNSUPPORTED. */
GG_API int ggImplicitSetMethod(ggImplicit *imp, int method);

/* At most this many evaluations of f per ray. A ray that needs more (an f
   too wild for the method, a bound far too large) stops as a miss, raises
   GG_IMPLICIT_WARN_BUDGET and is counted in ggRayStats.implicit_cut. The
   default: 100000 for callbacks and the Lipschitz method; for an
   expression with the interval method 2^18 / (n + 16) for n operations
   after folding, within [256, 4096] -- at most about 2 ms of work per ray,
   so a 64x48 render of any expression takes seconds (the example scenes'
   rays need at most 138). Returns GG_ERROR_INVALID unless max_evals >= 16. */
GG_API int ggImplicitSetBudget(ggImplicit *imp, long max_evals);

/* Surface normals during rendering: h = 0 (the default) uses the exact
   gradient (ggGradientNormal); h > 0 uses ggGradientCentral with step h,
   for measuring what central differences cost in accuracy. Returns
   GG_ERROR_INVALID unless h is finite and >= 0. */
GG_API int ggImplicitSetNormalStep(ggImplicit *imp, double h);

/* ---- queries ---- */

/* The box given at creation, into *lo and *hi (either may be NULL); a
   NULL imp writes nothing. */
GG_API void ggImplicitBounds(const ggImplicit *imp, ggVec3 *lo, ggVec3 *hi);

/* First hit of ray.o + t ray.d with tmin < t < tmax inside the box
   (ray.d need not be unit length; t is in units of |ray.d|). Returns 1
   and sets *t on a hit, 0 on a miss (also for a zero or non-finite
   direction or origin, or tmin >= tmax). *t is within the tolerance of a
   sign change of f as computed, usually within rounding of it.
   Secondary rays: when the ray starts inside the box at t = tmin on the
   surface it leaves, that surface is not reported again. For expression
   surfaces this holds for an origin anywhere within rounding error of the
   surface (where interval arithmetic cannot tell the sign of f); for
   callbacks only when f is exactly 0 there, so push the origin off the
   surface, to the side the ray goes, by more than the error of the hit
   point. t is required: NULL gives 0 (base.h rule 1). Thread-safe. */
GG_API int ggImplicitIntersect(const ggImplicit *imp, ggRay ray, double tmin, double tmax,
                               double *t);

#define GG_IMPLICIT_WARN_GRADIENT 1u /* f changed faster than the bound: holes possible */
/* some ray ran out of evaluations (see SetBudget), or of subdivision
   depth: a segment more than 2^250 times the tolerance */
#define GG_IMPLICIT_WARN_BUDGET 2u

/* The warnings raised by intersections since creation or the last
   ggImplicitClearWarnings: an OR of GG_IMPLICIT_WARN_*, 0 if none. They
   stay set (sticky) so a renderer can check once after the image. */
GG_API unsigned ggImplicitWarnings(const ggImplicit *imp);
/* The largest |f(p) - f(q)| / |p - q| seen between two samples along the
   rays traced with the Lipschitz method (POV-Ray's "max_gradient found"):
   a gradient bound a little above it avoids GG_IMPLICIT_WARN_GRADIENT for
   those rays. 0 before any such ray. */
GG_API double ggImplicitMaxSlope(const ggImplicit *imp);
/* Reset the warnings and the slope maximum (not while other threads
   intersect). */
GG_API void ggImplicitClearWarnings(ggImplicit *imp);

/* f(p); NaN where f is undefined. Evaluated anywhere, not only in the box. */
GG_API double ggImplicitEval(const ggImplicit *imp, ggVec3 p);

/* Unnormalised grad f at p, the outward normal of the surface f = 0 where
   f < 0 is inside. Exact for expressions (dual numbers) and when a gradient
   callback was given; otherwise ggGradientCentral with its default step. */
GG_API ggVec3 ggGradientNormal(const ggImplicit *imp, ggVec3 p);

/* grad f at p by central differences, (f(p + h e) - f(p - h e)) / 2h on
   each axis (divided by the step actually taken after rounding). Costs six
   evaluations of f. The error is about h^2 |f'''| / 6 from truncation plus
   eps |f| / h from rounding, smallest near h = eps^(1/3) times the scale on
   which f varies. h <= 0 or NaN selects that default: cbrt(DBL_EPSILON)
   times half the largest side of the box. */
GG_API ggVec3 ggGradientCentral(const ggImplicit *imp, ggVec3 p, double h);

/* ---- tessellation ---- */

/* Triangles approximating the surface f = 0 inside the box, for drawing
   it (ggrt serve's 3D view) or exporting it. */
typedef struct ggTriangulation {
    int resolution;  /* cells along the box's longest side, as asked */
    int cells[3];    /* cells along x, y and z (see ggImplicitTriangulate) */
    size_t nverts;   /* points on the surface */
    size_t ntris;    /* triangles */
    ggVec3 *verts;   /* nverts points, each within the refinement of a sign change of f */
    ggVec3 *normals; /* nverts unit normals: ggGradientNormal there, normalised */
    uint32_t *tris;  /* 3 ntris indices into verts, counter-clockwise seen from the
                        side where f > 0 (the normals' side) */
} ggTriangulation;

/* Resolutions ggImplicitTriangulate takes: 1 .. this many cells along the
   box's longest side. */
#define GG_TRIANGULATE_MAX_RESOLUTION 256

/* Marching tetrahedra over a grid of cells that fill the box, as near
   cubes as whole counts allow: `resolution` cells along the box's
   longest side, ceil(resolution side / longest) along each other side
   (at least 1; in cells[]), each cell a side / count long. So a flat box
   gets few layers of cells, not flat cells. Each cell is cut into the
   six tetrahedra around its main diagonal (the Freudenthal-Kuhn split,
   the same across shared faces). f is sampled at the grid points (the
   cells[a] + 1 along each axis); a vertex is made on each grid edge
   whose ends have f < 0 and f >= 0 (or f >= 0 and f < 0), placed on the
   edge by linear interpolation refined by six steps of the Illinois
   method, and shared by every triangle that cuts that edge. So:
     - the mesh is closed (every edge in exactly two triangles, with
       opposite directions) wherever the surface does not leave the box
       and f is defined: the box's faces cut it, and no triangle is made
       in a tetrahedron with a corner where f is NaN;
     - a part of the surface that no grid edge crosses (smaller than a
       cell, or two sheets within one cell) is not drawn: the mesh shows
       f's sign at the grid points, not the interval proof the
       intersector uses;
     - triangles may have zero area (a vertex on a grid point where f is
       exactly 0); none is dropped, so that the mesh stays closed.
   Normals are the renderer's gradient (ggGradientNormal: exact for
   expressions and gradient callbacks), normalised; where it is zero or
   not finite, the direction of the grid edge from its f < 0 end.
   max_triangles bounds the result (0: only the grid does: at most 12
   triangles a cell); one more fails with GG_ERROR_LIMIT (after at
   most the work of the whole grid), so a caller with a budget may retry at a
   lower resolution. Costs an evaluation of f per grid point (at most
   (resolution + 1)^3) and about five more per vertex; memory: the result
   and two layers of the grid.
   *out receives the result, made with alloc (NULL: malloc; copied), to
   free with ggTriangulationFree; a surface with no sign change on the
   grid gives zero triangles (and NULL arrays). On failure *out is NULL.
   Returns GG_OK, GG_ERROR_INVALID (NULL imp or out, resolution < 1),
   GG_ERROR_LIMIT (resolution > GG_TRIANGULATE_MAX_RESOLUTION, more than
   max_triangles) or GG_ERROR_NOMEM. Reads imp only: thread-safe as
   ggImplicitIntersect is. */
GG_API int ggImplicitTriangulate(const ggImplicit *imp, int resolution, size_t max_triangles,
                                 const ggAllocator *alloc, ggTriangulation **out);
/* Free a triangulation; NULL is a no-op. */
GG_API void ggTriangulationFree(ggTriangulation *t);

#ifdef __cplusplus
}
#endif
#endif
