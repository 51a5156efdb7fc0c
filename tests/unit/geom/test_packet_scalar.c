/* SPDX-License-Identifier: MIT */
/*
** test_packet_scalar.c -- the packet suite again, on the portable C
** traversal (linked with the geom layer built with GG_BVH_NO_SIMD, as
** test_bvh_scalar is: Makefile).
*/
#define GG_TEST_SUITE "packet_scalar"
#include "test_packet.c"
