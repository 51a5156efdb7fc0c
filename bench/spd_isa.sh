#!/bin/sh
# SPDX-License-Identifier: MIT
# `ggrt bench spd --embree` with both programs held to one instruction set
# on a CPU that has more: ggrt through GGRT_ISA (lib/core/cpu.c), the
# anchor through Embree's device configuration ("isa=ISA", added to the
# "threads=N" string its main.c passes to rtcNewDevice: Debian's Embree
# reads no .embree3 file). The anchor is built from its own source in a
# temporary folder, with its Makefile's flags; the source is not changed.
# How close this comes to an AVX2-only machine: the same instructions,
# not the same caches or clocks (docs/performance.md, "Held to AVX2").
# usage: sh bench/spd_isa.sh GGRT ANCHOR_SRC_DIR [ISA [RUNS [BENCH_ARGS...]]]
#   ISA: avx2 (default) or avx512; e.g.
#   sh bench/spd_isa.sh build/ggrt ../shared/anchors/embree-whitted avx2 3
g=$1 src=$2 isa=${3:-avx2} runs=${4:-1}
if [ $# -ge 4 ]; then shift 4; else shift $#; fi
[ -x "$g" ] && [ -f "$src/main.c" ] ||
  { echo "usage: sh bench/spd_isa.sh GGRT ANCHOR_SRC_DIR [ISA [RUNS [BENCH_ARGS...]]]" >&2; exit 1; }
case $isa in avx2|avx512) ;; *) echo "bench/spd_isa.sh: ISA is avx2 or avx512" >&2; exit 1 ;; esac
# Embree refuses a device with isa=avx512 on a CPU without it
# (rtcNewDevice fails): say so, rather than "the anchor failed".
if [ "$isa" = avx512 ] && ! grep -qw avx512f /proc/cpuinfo 2>/dev/null; then
  echo "bench/spd_isa.sh: this CPU has no AVX-512F: nothing to hold to avx512 (try avx2)"
  exit 0
fi
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
grep -q '"threads=%d"' "$src/main.c" ||
  { echo "bench/spd_isa.sh: $src/main.c passes no \"threads=%d\" configuration" >&2; exit 1; }
sed "s/\"threads=%d\"/\"threads=%d,isa=$isa\"/" "$src/main.c" > "$tmp/main.c"
cc -O2 -march=native -std=c11 -o "$tmp/anchor" "$tmp/main.c" -lembree3 -lpng -lpthread -lm ||
  { echo "bench/spd_isa.sh: the anchor did not build (apt-get install libembree-dev)" >&2; exit 1; }
for r in $(seq "$runs"); do
  echo "run $r of $runs: GGRT_ISA=$isa, the anchor with isa=$isa"
  GGRT_ISA=$isa "$g" bench spd --embree "$tmp/anchor" --no-pov "$@" || exit 1
done
