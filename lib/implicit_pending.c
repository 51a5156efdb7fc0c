/*
** implicit_pending.c -- TEMPORARY stand-ins so the geometry branch links
** before the implicit-surface branch lands. The lead deletes this file at
** the merge; nothing here is the real behaviour (every ray misses).
*/
#include "implicit_int.h"

void gg_implicit_bounds(const ggImplicit *imp, ggVec3 *lo, ggVec3 *hi)
{
    (void)imp;
    lo->x = lo->y = lo->z = -1;
    hi->x = hi->y = hi->z = 1;
}

int gg_implicit_intersect(const ggImplicit *imp, ggVec3 o, ggVec3 d, double tmin, double tmax,
                          double *t)
{
    (void)imp, (void)o, (void)d, (void)tmin, (void)tmax, (void)t;
    return 0;
}

GG_API ggVec3 ggGradientNormal(const ggImplicit *imp, ggVec3 p)
{
    ggVec3 z;
    (void)imp, (void)p;
    z.x = z.y = z.z = 0;
    return z;
}
