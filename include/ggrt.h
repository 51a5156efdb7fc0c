/* SPDX-License-Identifier: MIT */
/*
** ggrt.h -- the one public header of ggrt, a Whitted-style ray tracer.
**
**   #include <ggrt.h>      cc prog.c $(pkg-config --cflags --libs ggrt)
**
** The rules every function follows -- NULL handles, statistics structs,
** allocator ownership -- are at the top of ggrt/base.h.
**
** Five minutes to learn:
**   ggrt/base.h      status codes, ggError, ggAllocator, ggVec3, ggColor, ggRay
**   ggrt/optics.h    ggReflection, ggRefract, Fresnel, Beer-Lambert
**   ggrt/image.h     ggImage, PNG/EXR read and write, texture sampling
**   ggrt/implicit.h  implicit surfaces f(x,y,z)=0 and gradient normals
**   ggrt/scene.h     ggScene: load NFF or build in code; materials, lights
**   ggrt/render.h    ggRender, ggRayColor, ray statistics, the effect set
**   ggrt/trace.h     the ray tree of one pixel, recorded
**   ggrt/debug.h     find, check, explain (ledger) and diff at image level
*/
#ifndef GGRT_H
#define GGRT_H

#include "ggrt/base.h"
#include "ggrt/optics.h"
#include "ggrt/image.h"
#include "ggrt/implicit.h"
#include "ggrt/scene.h"
#include "ggrt/render.h"
#include "ggrt/trace.h"
#include "ggrt/debug.h"

#endif
