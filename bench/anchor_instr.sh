#!/bin/sh
# SPDX-License-Identifier: MIT
# Instructions of ggrt's render against the Embree anchor's render threads
# (callgrind, 256x256, one thread) on the SPD scenes, with the ratios: the
# stable side of the comparison that compare.sh makes in wall time.
# valgrind runs no AVX-512, so the anchor is built here with -march=haswell
# and Embree takes its AVX2 kernels; ggrt takes its AVX2 copy as always
# under valgrind (docs/log/2026-12-03-embree-shading-and-tree.md, "Where
# this stands (2026-12-03)").
# usage: sh bench/anchor_instr.sh GGRT ANCHOR_SRC_DIR [SCENE...]
#   (from the top of a checkout; ANCHOR_SRC_DIR holds the anchor's main.c,
#   e.g. ../shared/anchors/embree-whitted; needs libembree-dev, valgrind)
. "$(dirname "$0")/anchor_setup.sh"
anchor_setup anchor_instr.sh "$@"
# callgrind's total for one run of the anchor: "$@" is the command, $1 the
# function to count
count() {
  f=$1; shift
  valgrind --tool=callgrind --callgrind-out-file="$tmp/cg" --toggle-collect="$f" "$@" \
    >/dev/null 2>&1 || return 1
  callgrind_annotate "$tmp/cg" 2>/dev/null | sed -n 's/^\([0-9,]*\) .*PROGRAM TOTALS.*/\1/p' | tr -d ,
}
printf "%-11s %14s %14s %14s %9s %9s\n" scene ggrt anchor-p1 anchor-p16 p1/ggrt p16/ggrt
for s in $scenes; do
  n=examples/scenes/spd/$s.nff
  # ggrt's figure is bench/instr.sh's, by the same command
  a=$(sh bench/instr.sh "$g" "$s" | awk '{ gsub(",", "", $2); print $2 }')
  [ -n "$a" ] || exit 1
  b=$(count worker_main "$tmp/anchor" -t 1 -r 256 -p 1 -o - "$n") || exit 1
  c=$(count worker_main "$tmp/anchor" -t 1 -r 256 -p 16 -o - "$n") || exit 1
  awk -v s="$s" -v a="$a" -v b="$b" -v c="$c" \
    'BEGIN { printf "%-11s %14d %14d %14d %9.2f %9.2f\n", s, a, b, c, b / a, c / a }'
done
