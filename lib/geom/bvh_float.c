/* SPDX-License-Identifier: MIT */
/*
** bvh_float.c -- the traversals once more (bvh_trav.inc.h) for the queries of
** single precision (GG_ISECT_FLOAT, include/ggrt/render.h): the plain
** copy's node walk, with leaves that test triangles by the float kernel
** (gg_tri_kernel_f, shape_tri.h). A copy of its own so that the double
** copies carry no test of the precision per element: bvh.c picks it once
** per query.
*/
#include "bvh_int.h"

/* The plain copy's hooks (bvh_hooks.h) with the float loops, for the
   leaf tests and for the slots the walk also tests outside them. */
#define GG_TX_FLOAT    1
#define GG_INC_NAME(f) gg_##f##_float
#define GG_INC_LINK    /* external: declared in bvh_int.h */
#define GG_TRAV_SINGLE /* no packets: bvh.c sends float queries one by one */
#include "bvh_hooks.h"
#include "bvh_trav.inc.h"
