#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Write the seed corpus of tests/fuzz/fuzz_optics.c: hard cases for
reflection, refraction, Fresnel and Beer-Lambert. Each seed is 12
little-endian doubles (v, n, ni, nt, cos_i, k, lambda, distance) and an
optional shaping byte. Run from the repository root:
    python3 tests/fuzz/optics_seeds.py
"""
import math
import os
import struct

OUT = "tests/fuzz/corpus/optics"
inf, nan = float("inf"), float("nan")


def up(x):
    return math.nextafter(x, inf)


def down(x):
    return math.nextafter(x, -inf)


B = dict(c=0.7, k=3.0, lam=0.5, d=1.0)
seeds = {}


def seed(name, v, n, ni, nt, c=B["c"], k=B["k"], lam=B["lam"], d=B["d"], shape=None):
    data = struct.pack("<12d", *v, *n, ni, nt, c, k, lam, d)
    if shape is not None:
        data += bytes([shape])
    seeds[name] = data


# benign
seed("benign", (0.3, -0.9, 0.1), (0, 1, 0), 1.0, 1.5)
seed("water_to_air", (0.6, -0.8, 0), (0, 1, 0), 1.33, 1.0)
# grazing
seed("grazing_matched", (1, -1e-17, 0), (0, 1, 0), 1.5, 1.5)
seed("grazing_2m60", (1, -2.0 ** -60, 0), (0, 3, 0), 1.5, up(1.5))
seed("grazing_denser", (1, -1e-12, 1e-3), (0, 1, 0), 1.0, 1.33)
seed("grazing_cos", (0.3, -0.9, 0.1), (0, 1, 0), 1.0, 1.5, c=1e-300)
# eta near 1
seed("eta_1_plus_ulp", (0.6, -0.8, 0), (0, 1, 0), 1.5, up(1.5))
seed("eta_1_minus_ulp", (0.6, -0.8, 0), (0, 1, 0), 1.5, down(1.5))
seed("eta_1_fresnel", (0.6, -0.8, 0), (0, 1, 0), 1.5, up(up(1.5)), c=0.999999)
# critical angle: sin = 3/5, eta = 5/3 exactly critical, and 1 ulp off
seed("critical_exact", (3, -4, 0), (0, 1, 0), 5, 3)
seed("critical_above", (up(3.0), -4, 0), (0, 1, 0), 5, 3)
seed("critical_below", (down(3.0), -4, 0), (0, 1, 0), 5, 3)
seed("critical_index", (3, -4, 0), (0, -1, 0), up(5.0), 3)
seed("critical_neg", (3, -4, 0), (0, 1, 0), -5, -3)
seed("critical_fresnel", (0.3, -0.9, 0.1), (0, 1, 0), 1.5, 1.0, c=math.sqrt(1 - 1 / 2.25))
# 2^-104 from critical: p^2 + q^2 = h^2 + 1 (Berggren walk)
seed("critical_2m104", (float.fromhex("0x1.79bc95ee3f21ep+51"), float.fromhex("-0x1.7b0c73fd2450cp+51"), 0),
     (0, -1, 0), float.fromhex("0x1.0b907d67bdf42p+52"), float.fromhex("0x1.79bc95ee3f21ep+51"))
# normal incidence
seed("normal_exact", (0, 0, -1), (0, 0, 1), 1.0, 1.5)
seed("normal_scaled", (0, 0, -3), (0, 0, 0.5), 2.4, -1.0)
seed("normal_huge_eta", (0, 2, 0), (0, 1, 0), 1e300, 1e-300)
seed("near_normal_huge_eta", (1e-200, 2, 0), (0, 1, 0), 1e300, 1e-300)
seed("near_normal_tiny_eta", (1e-200, 2, 0), (0, 1, 0), 1e-300, 1e300)
# negative indices (metamaterials)
seed("negative_nt", (0.6, -0.8, 0), (0, 1, 0), 1.0, -1.5)
seed("negative_both", (0.6, -0.8, 0), (0, 1, 0), -1.0, -1.5)
seed("perfect_lens", (0.6, -0.8, 0), (0, 1, 0), 1.0, -1.0)
# invalid
seed("nan_v", (nan, -0.8, 0), (0, 1, 0), 1.0, 1.5)
seed("nan_index", (0.6, -0.8, 0), (0, 1, 0), nan, 1.5)
seed("inf_n", (0.6, -0.8, 0), (inf, 1, 0), 1.0, 1.5)
seed("zero_normal", (0.6, -0.8, 0), (0, 0, 0), 1.0, 1.5)
seed("zero_v", (0, 0, 0), (0, 1, 0), 1.0, 1.5)
seed("zero_index", (0.6, -0.8, 0), (0, 1, 0), 0.0, 1.5)
seed("neg_zero_index", (0.6, -0.8, 0), (0, 1, 0), 1.0, -0.0)
# tangent v, and v.n = 2^-104 with products of 1
seed("tangent", (2, 0, 0), (0, 0, 1), 1.0, 1.5)
a, c = 1 + 2.0 ** -52, 1 + 2.0 ** -51
seed("dot_2m104", (a, c, 0), (a, -1, 0), 1.0, 1.5)
seed("dot_minus_2m104", (c, a, 0), (1, -a, 0), 1.0, 1.5)
# scales
seed("huge_vectors", (1e300, -1e300, 1e299), (1e-300, 3e-300, 0), 1.0, 1.5)
seed("max_vectors", (1.7e308, -1.7e308, 1e308), (1.7e308, 1e308, 0), 1.0, 1.5)
seed("subnormal", (5e-324, -1e-320, 0), (0, 5e-324, 0), 1.0, 1.5)
seed("extreme_eta", (0.6, -0.8, 0), (0, 1, 0), 1.7e308, 5e-324)
seed("extreme_eta_inv", (0.6, -0.8, 0), (0, 1, 0), 5e-324, 1.7e308)
# Fresnel and Beer-Lambert corners
seed("fresnel_normal", (0.6, -0.8, 0), (0, 1, 0), 1.0, 1.5, c=1.0, k=0.0)
seed("fresnel_gold", (0.6, -0.8, 0), (0, 1, 0), 1.0, 0.14, c=0.5, k=3.697)
seed("conductor_huge", (0.6, -0.8, 0), (0, 1, 0), 1e-300, 1e300, c=1e-290, k=1e300)
seed("conductor_tiny", (0.6, -0.8, 0), (0, 1, 0), 1e300, 1e-300, c=0.5, k=1e-300)
seed("beer_zero_k", (0.6, -0.8, 0), (0, 1, 0), 1.0, 1.5, k=0.0, lam=0.65e-6, d=inf)
seed("beer_inf_d", (0.6, -0.8, 0), (0, 1, 0), 1.0, 1.5, k=1.6e-8, lam=0.65e-6, d=inf)
seed("beer_tiny_lambda", (0.6, -0.8, 0), (0, 1, 0), 1.0, 1.5, k=1e300, lam=5e-324, d=1e300)
seed("beer_water", (0.6, -0.8, 0), (0, 1, 0), 1.0, 1.33, k=1.76e-8, lam=650e-9, d=1.0)
seed("beer_negative", (0.6, -0.8, 0), (0, 1, 0), 1.0, 1.5, k=-1.0, lam=1.0, d=1.0)
# shaping bytes: eta near 1, near critical, grazing, normal, matched
for s in range(1, 6):
    seed("shape%d" % s, (0.3, -0.9, 0.1), (0.2, 1, -0.3), 1.7, 1.2, c=0.123456789, shape=s)
# inputs the fuzzer found (kept as regressions)
import base64
seeds["found_subnormal_normal_components"] = base64.b64decode(
    "AAAAAAAA8D+X1EZGB/GYQwAAAAAAAAAAAAAAOgAAAAAAAAAA+D8AAAAAAAD4P2ZmZmZmZuY/AAAAAAAACEAAAAAgAADgPwAAAAAAAPA/")
seeds["found_huge_eta_near_normal"] = base64.b64decode(
    "MzMzmpmZPZmZAAAAAP8/AAAAAAAAAAAA8P+amZnJMzMz4wAAPwAAAAA/mpmZmQAAAAAAAAAAAAL8//8AAAAAAAA=")
seeds["found_huge_eta_reprojection"] = base64.b64decode(
    "djt3MNFC7n9CQkJCdtFC7v+gampqampqyOuF8+HMf3Y7AAAAAAAAAGDI64Xz4SwAAAAAAAAAQu5/oMgNhfPM4X8AAAAAAAAAAMsAAAAAAABA+D9mZtg9ZmZmZuY/AAAAPw==")
seeds["found_underflowing_products_a"] = base64.b64decode(
    "MzMzmpmZPZmZ/z8AAAAAAAAAAAAAAAAAAAAAAAAAAAAA8P+amZnJMzMz6+vr6+vr6+vr6+vr6+vr6+vr6+vr6+vr6+vr6+vr6+vr6+vr6+vr6+vr6+vr6+vr6+vr6+vr6+MAAD8AAAAAP5qZmZkAAAAAAAAAAAAAAAAAAAA=")
seeds["found_underflowing_products_b"] = base64.b64decode(
    "8wAAEAAAAAAAAAAAAAAAAAAZAAAAAAAgAAAAf/2pPJogAAAACw==")
seeds["found_almost_parallel_huge_eta"] = base64.b64decode(
    "MzMzMzMz0y9hAAAAAAAAAJqZmZmZmbk/mpmZmZmZyT8AAAAAAADwPwAAAAAAAABBvzMzMzO/M9MzMwAACFQ/Mwg=")
seeds["found_tir_band_2m110"] = base64.b64decode(
    "AAAAAAAACEAAAAAAAAAQwAAAAAAAAAAAAQAAAAAAADkAAAAAACjwPwAAAAAAAAAAAAAAAAAAFEAAAAAAAAAIQAA=")
# |eta| about 2^1334 and a (subnormal) tangential part of n 2^-1333 of its
# normal one, |eta sin(theta_i)| = 1.43: the scaling rounded that part away
# and the totally reflected ray was transmitted (lib/optics/refract_big.c)
h = float.fromhex
seed("found_huge_eta_spread_components", (0.0, 0.0, -h("0x1.445489d6cac2bp+741")),
     (0.0, h("0x0.00000000005e1p-1022"), h("0x1.e0718013dcbf8p+269")),
     h("0x1.8553485eb58e4p+513"), -h("0x1.aa967d3fcb8e1p-821"))
# short inputs use the defaults for what is missing
seeds["short_v_only"] = struct.pack("<3d", 0.1, -1.0, 0.2)
seeds["empty"] = b""

os.makedirs(OUT, exist_ok=True)
for name, data in sorted(seeds.items()):
    with open(os.path.join(OUT, name), "wb") as f:
        f.write(data)
print("wrote %d seeds to %s" % (len(seeds), OUT))
