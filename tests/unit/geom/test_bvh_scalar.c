/* SPDX-License-Identifier: MIT */
/*
** test_bvh_scalar.c -- the BVH suite again, on the portable C traversal
** (the one targets without SSE2 compile). The Makefile links this test
** with its own build of the geom layer, compiled with GG_BVH_NO_SIMD
** ($(BUILD)/scalar/), instead of the library's.
*/
#define GG_TEST_SUITE     "bvh_scalar"
#define GG_TEST_TRAVERSAL "c"
#include "test_bvh.c"
