/* SPDX-License-Identifier: MIT */
/*
** reflect.inc.h -- the body of the accurate reflection (internal),
** included after refract.inc.h (whose four-lane helpers it uses), and
** like it twice: by optics.c as plain code and by refract_fma.c for CPUs
** with fused multiply-add. The two copies differ only where a result is
** exact either way (TwoProd, and the remainder of a division), so they
** return the same bits. Before including, define GG_INC_NAME and
** GG_INC_LINK (compiler.h, "Templates"); the function is
** GG_INC_NAME(reflect).
**
** Where no component exceeds 2^300 in magnitude and |v|, |n| >= 2^-300,
** nothing below overflows and what underflows is far below the bound, so
** the mirror image is formed from the given doubles directly; elsewhere
** (and for zero, infinite or NaN input) v and n are first scaled by powers
** of two. docs/optics.md, "The fast paths", gives the bound and its proof.
*/
#if !defined(GG_INC_NAME) || !defined(GG_INC_LINK)
#error "define GG_INC_NAME and GG_INC_LINK before including reflect.inc.h"
#endif

/* gg_v4u and gg_v2 come from refract.inc.h (C99 allows no repeated
   typedef). */

/* Lane shuffles and tests (the fma build spells them as AVX intrinsics,
   which GCC otherwise assembles from several instructions; the values are
   the same). v4lo and v4hi: lanes 0-1 and 2-3; v4unpack: (a0, b0, a2, b2)
   or (a1, b1, a3, b3); v4_any: some lane of
   a comparison's result is true; v4_out: some |a_i| or |b_i| is not below
   m (or is NaN). */
#if defined(GG_DD_FMA)
GG_INLINE gg_v2 v4lo(gg_v4 a)
{
    return (gg_v2)_mm256_castpd256_pd128((__m256d)a);
}
GG_INLINE gg_v2 v4hi(gg_v4 a)
{
    return (gg_v2)_mm256_extractf128_pd((__m256d)a, 1);
}
GG_INLINE gg_v4 v4unpack(gg_v4 a, gg_v4 b, int hi)
{
    return hi ? (gg_v4)_mm256_unpackhi_pd((__m256d)a, (__m256d)b)
              : (gg_v4)_mm256_unpacklo_pd((__m256d)a, (__m256d)b);
}
GG_INLINE int v4_any(gg_v4u c)
{
    return !_mm256_testz_pd((__m256d)c, (__m256d)c);
}
/* max returns its second operand if either is NaN */
GG_INLINE int v4_out(gg_v4 a, gg_v4 b, gg_v4 m)
{
    return v4_any(
        (gg_v4u)_mm256_cmp_pd(_mm256_max_pd((__m256d)b, (__m256d)a), (__m256d)m, _CMP_NLT_UQ));
}
#else
GG_INLINE gg_v2 v4lo(gg_v4 a)
{
    gg_v2 r = {a[0], a[1]};
    return r;
}
GG_INLINE gg_v2 v4hi(gg_v4 a)
{
    gg_v2 r = {a[2], a[3]};
    return r;
}
GG_INLINE gg_v4 v4unpack(gg_v4 a, gg_v4 b, int hi)
{
    gg_v4 r = {a[hi], b[hi], a[2 + hi], b[2 + hi]};
    return r;
}
GG_INLINE int v4_any(gg_v4u c)
{
    return (c[0] | c[1] | c[2] | c[3]) != 0;
}
GG_INLINE int v4_out(gg_v4 a, gg_v4 b, gg_v4 m)
{
    return v4_any(~((gg_v4u)(a < m) & (gg_v4u)(b < m)));
}
#endif

/* (p->x, p->y, p->z, p->z). A masked load would be one instruction, but
   it cannot take its data from the caller's pending stores of p
   (store-to-load forwarding) and is slower. */
GG_INLINE gg_v4 v4load(const ggVec3 *p)
{
    gg_v4 r = {p->x, p->y, p->z, p->z};
    return r;
}

GG_INLINE gg_v4 v4abs(gg_v4 a)
{
    const gg_v4u m = {~0ull >> 1, ~0ull >> 1, ~0ull >> 1, ~0ull >> 1};
    return (gg_v4)((gg_v4u)a & m);
}

/* From t = (a_h, m_h) and lo = (a_l, m_l): q = a_h / m_h rounded and
   kl = ((rho + a_l) - q m_l) / m_h, each in every lane of *Q and *KL;
   0 (nothing written) if m_h < 2^-600 or NaN.
   rho = a_h - q m_h is a double (the remainder of a quotient rounded to
   nearest, barring underflow), so one fma or TwoProd and two subtractions
   give it exactly. The fma build works on the pairs (a_h, a_h), (m_h, m_h)
   so that q and kl come out already in both lanes; the values are the
   same. */
GG_INLINE int reflect_quotient(gg_v2 t, gg_v2 lo, gg_v4 *Q, gg_v4 *KL)
{
#if defined(GG_DD_FMA)
    __m128d m = _mm_unpackhi_pd((__m128d)t, (__m128d)t), a, q, L = (__m128d)lo, num, kl;
    if (!_mm_comige_sd(m, _mm_set_sd(0x1p-600))) return 0;
    a = _mm_movedup_pd((__m128d)t), q = _mm_div_pd(a, m);
    num = _mm_sub_pd(_mm_add_pd(_mm_fnmadd_pd(q, m, a), _mm_movedup_pd(L)),
                     _mm_mul_pd(q, _mm_unpackhi_pd(L, L)));
    kl = _mm_div_pd(num, m);
    *Q = (gg_v4)_mm256_insertf128_pd(_mm256_castpd128_pd256(q), q, 1);
    *KL = (gg_v4)_mm256_insertf128_pd(_mm256_castpd128_pd256(kl), kl, 1);
#else
    double q, rho;
    gg_dd p;
    if (!(t[1] >= 0x1p-600)) return 0;
    q = t[0] / t[1], p = dd_two_prod(q, t[1]), rho = (t[0] - p.hi) - p.lo;
    *Q = v4splat(q);
    *KL = v4splat(((rho + lo[0]) - q * lo[1]) / t[1]);
#endif
    return 1;
}

/* *out = V - k N, k = 2 (v.n)/(n.n), each component rounded once. The
   dot products 2 v.n and n.n (lanes 0 and 1) are formed as hi + lo by
   Dot2 of Ogita, Rump and Oishi without its final renormalising TwoSum;
   k = q + kl with q the rounded quotient of the high parts. Returns 0, and
   writes nothing, if n.n < 2^-600 (or NaN). Error: docs/optics.md, "The
   fast paths". */
GG_INLINE int reflect_mirror(gg_v4 V, gg_v4 N, ggVec3 *out)
{
    gg_v4 V2 = V + V, Ph = V2 * N, Qh = N * N, Pl, Ql;
    /* components 0 and 1 summed in lanes 0, 1 (2 v.n, n.n), then 2 added */
    gg_v4 H0 = v4unpack(Ph, Qh, 0), H1 = v4unpack(Ph, Qh, 1), L0, L01, S, B, SL, E, R, Q, KL;
    gg_v2 s, h2, t, c, lo;
    gg_v4dd pk;
    /* the low parts once the high parts are shuffled (so GCC can overwrite
       the high parts rather than copy N) */
    Pl = v4_two_prod(V2, N).lo, Ql = v4_two_prod(N, N).lo;
    L0 = v4unpack(Pl, Ql, 0), L01 = L0 + v4unpack(Pl, Ql, 1);
    S = H0 + H1, B = S - H0, SL = (H0 - (S - B)) + (H1 - B);
    s = v4lo(S), h2 = v4hi(H0), t = s + h2, c = t - s;
    lo = (v4lo(L01) + (v4hi(L0) + v4lo(SL))) + ((s - (t - c)) + (h2 - c));
    if (!reflect_quotient(t, lo, &Q, &KL)) return 0;
    /* S + E = V - q N exactly (TwoProd, then TwoSum of V and -q N) */
    pk = v4_two_prod(Q, N);
    S = V - pk.hi, B = S - V;
    E = (V - (S - B)) - (pk.hi + B);
    R = S + ((E - pk.lo) - KL * N);
    *out = v3(R[0], R[1], R[2]);
    return 1;
}

/* Zero, non-finite or extreme input: the largest components scaled into
   [1, 2), mirrored, scaled back. */
static GG_NOINLINE GG_COLD ggVec3 reflect_scaled(const ggVec3 *vp, const ggVec3 *np)
{
    ggVec3 v = *vp, n = *np, r;
    uint64_t mv = max_bits(v), mn = max_bits(n), e = mv >> 52, b;
    double s;
    if (e == 2047 || mn == 0 || (mn >> 52) == 2047) return v3nan();
    if (mv == 0) return v;
    reflect_mirror(scale_unit(v, mv), scale_unit(n, mn), &r);
    if (e >= 1 && e <= 2045) {
        b = e << 52;
        memcpy(&s, &b, sizeof s);
        return v3scale(r, s);
    }
    return v3scale2(r, dd_expo(v3maxabs(v)));
}

/* The accurate reflection (ggReflection's contract). */
GG_INC_LINK ggVec3 GG_INC_NAME(reflect)(const ggVec3 *v, const ggVec3 *n)
{
    /* (lane 3 repeats lane 2: bounds there that decide nothing, and that
       keep the constants from being broadcast from one double) */
    const gg_v4 big = {0x1p300, 0x1p300, 0x1p300, 0x1p301},
                tiny = {0x1p-300, 0x1p-300, 0x1p-300, 0x1p-299};
    gg_v4 V = v4load(v), N = v4load(n), AV = v4abs(V);
    ggVec3 r;
    /* every |component| below 2^300: no product overflows; the largest
       of v at least 2^-300; and n.n >= 2^-600 (reflect_mirror) */
    if (!v4_out(AV, v4abs(N), big) && v4_any((gg_v4u)(AV >= tiny)) && reflect_mirror(V, N, &r))
        return r;
    return reflect_scaled(v, n);
}
