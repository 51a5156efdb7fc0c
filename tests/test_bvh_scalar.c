/* SPDX-License-Identifier: MIT */
/*
** test_bvh_scalar.c -- the BVH suite again, on the portable C traversal
** (the one non-SSE2 targets compile). bvh.c is compiled into this test
** with SSE disabled, so the linker takes its definitions instead of the
** archive's.
*/
#define GG_BVH_NO_SIMD 1
#include "bvh.c"

#define GG_TEST_SUITE "bvh_scalar"
#include "test_bvh.c"
