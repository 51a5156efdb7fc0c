/* SPDX-License-Identifier: MIT */
/*
** lpe.h -- path layers as the shading runs them (internal): each layer's
** path expression compiled to a deterministic automaton over the events
** the shading knows, so that a ray carries one small state per layer and
** a step is one table lookup. lib/debug compiles them (path_layers.c,
** ggPathLayersCompile, by subset construction over the matcher of
** path_match.c); shade.c's layer copy steps them (docs/debugging.md,
** "Path layers").
*/
#ifndef GG_LPE_H
#define GG_LPE_H

#include "core.h"
#include "ggrt/debug.h"

#include <stdint.h>

/* The events of a path as the shading meets them, by kind; every event of
   a kind that names a surface (RS .. O) also has the hit's object and
   material, L has the light's number. */
enum {
    GG_LPE_C,      /* the eye */
    GG_LPE_RS,     /* a mirror ray */
    GG_LPE_RS_TIR, /* a mirror ray carrying total internal reflection ('tir') */
    GG_LPE_TS,     /* a refracted ray */
    GG_LPE_RD,     /* the diffuse term and ambient at a hit */
    GG_LPE_RG,     /* the Phong highlight at a hit */
    GG_LPE_L,      /* a light (after RD or RG) */
    GG_LPE_A,      /* ambient (after RD) */
    GG_LPE_O,      /* emission */
    GG_LPE_B,      /* the background */
    GG_LPE_KINDS
};

#define GG_LPE_LABELS GG_PATH_LAYER_LABELS /* numbers and materials one layer may name */

/* One layer's automaton. Objects, lights and materials fall into classes:
   the k-th number (or material) the expression names is class k, every
   other one class nnum (nmat). The symbol of an event is kind * ncls +
   the class of (number, material), ncls = (nnum + 1) * (nmat + 1); events
   without a surface (C, A, B) and L (no material) use the "other" class
   for what they lack. State 0 is dead (no path through it can match).

   term[state * ncls + cls] holds, for a hit of class cls reached in that
   state, which of the terms that end a path there the automaton accepts:
   bit u (GG_LPE_T_RDL + u) <RD>L for a light of number class u, bit
   GG_LPE_T_RGL + u <RG>L, GG_LPE_T_A <RD>A, GG_LPE_T_O O; and, whatever
   cls, GG_LPE_T_B: B after the state (a miss). The shading then does one
   lookup per layer at a hit instead of a step per event. */
#define GG_LPE_T_RDL 0
#define GG_LPE_T_RGL 12
#define GG_LPE_T_A   (1u << 24)
#define GG_LPE_T_O   (1u << 25)
#define GG_LPE_T_B   (1u << 26)
#define GG_LPE_T_L   0xfffu /* the light bits of either, shifted down */
#if GG_LPE_LABELS + 1 > GG_LPE_T_RGL
#error "lpe.h: a layer's light classes do not fit the term bits"
#endif
typedef struct gg_lpe_dfa {
    int nstates, nsym, ncls, nnum, nmat;
    long num[GG_LPE_LABELS], mat[GG_LPE_LABELS];
    uint16_t start;        /* the state after C */
    uint16_t *next;        /* next[state * nsym + symbol] */
    unsigned char *accept; /* per state */
    unsigned char *quiet;  /* per state: no term but B is accepted at any hit (in accept's block) */
    uint32_t *term;        /* term[state * ncls + cls], the GG_LPE_T_* bits */
} gg_lpe_dfa;

/* ggPathLayers (render.h): the layers of one render. */
#define GG_LAYERS_MAX GG_PATH_LAYERS_MAX
struct ggPathLayers {
    ggAllocator alloc_copy;
    const ggAllocator *alloc;
    int n;
    unsigned live; /* bit l: layer l's start state is not dead */
    uint16_t start[GG_LAYERS_MAX]; /* layer[l].start, side by side for an eye ray's copy */
    gg_lpe_dfa layer[GG_LAYERS_MAX];
};

static inline int gg_lpe_num_class(const gg_lpe_dfa *d, long v)
{
    int k;
    for (k = 0; k < d->nnum; k++)
        if (d->num[k] == v) return k;
    return d->nnum;
}

static inline int gg_lpe_mat_class(const gg_lpe_dfa *d, long v)
{
    int k;
    for (k = 0; k < d->nmat; k++)
        if (d->mat[k] == v) return k;
    return d->nmat;
}

/* The class of a surface event at object obj of material mat; of an L
   event of light li (surface 0); of an event without surface or light. */
static inline int gg_lpe_surface(const gg_lpe_dfa *d, int obj, int mat)
{
    if (!(d->nnum | d->nmat)) return 0; /* no labels: one class (the common case) */
    return gg_lpe_num_class(d, obj) * (d->nmat + 1) + gg_lpe_mat_class(d, mat);
}
static inline int gg_lpe_light(const gg_lpe_dfa *d, int li)
{
    return gg_lpe_num_class(d, li) * (d->nmat + 1) + d->nmat;
}
static inline int gg_lpe_none(const gg_lpe_dfa *d)
{
    return d->ncls - 1;
}

/* The state after an event of kind k and class cls from state s. */
static inline unsigned gg_lpe_step(const gg_lpe_dfa *d, unsigned s, int k, int cls)
{
    return d->next[(size_t)s * (size_t)d->nsym + (size_t)(k * d->ncls + cls)];
}

#endif
