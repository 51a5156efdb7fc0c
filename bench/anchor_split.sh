#!/bin/sh
# SPDX-License-Identifier: MIT
# bench/anchor_instr.sh's counts split in two: the ray queries (ggrt's
# gg_geom_intersect, gg_geom_intersect_packet and gg_geom_occluded; the
# anchor's rtcIntersect1, rtcIntersect16 and rtcOccluded1, each with all it
# calls) and the rest (shading, secondary-ray set-up, camera, pixels), in
# millions of instructions (callgrind, 256x256, one thread, the anchor with
# -p 16 built with -march=haswell as there), with the anchor's over ggrt's
# for each part (docs/performance.md, "Queries and the rest").
# usage: sh bench/anchor_split.sh GGRT ANCHOR_SRC_DIR [SCENE...]
#   (from the top of a checkout; ANCHOR_SRC_DIR holds the anchor's main.c,
#   e.g. ../shared/anchors/embree-whitted; needs libembree-dev, valgrind)
. "$(dirname "$0")/anchor_setup.sh"
anchor_setup anchor_split.sh "$@"
# "total queries" of one callgrind run: $1 the function to count, $2 an awk
# pattern for the query functions' lines, the rest the command
split() {
  f=$1 pat=$2; shift 2
  valgrind --tool=callgrind --callgrind-out-file="$tmp/cg" --toggle-collect="$f" "$@" \
    >/dev/null 2>&1 || return 1
  callgrind_annotate --inclusive=yes "$tmp/cg" 2>/dev/null | awk -v pat="$pat" '
    /PROGRAM TOTALS/ { gsub(",", "", $1); t = $1 }
    $0 ~ pat { gsub(",", "", $1); q += $1 }
    END { if (t == "") exit 1; printf "%d %d\n", t, q }'
}
gq='[^/]lib/geom/bvh\.c:gg_geom_(occluded|intersect|intersect_packet) \['
aq='[?]:rtc(Occluded1|Intersect1|Intersect16) \['
printf "%-11s %8s %8s %8s | %8s %8s %8s | %7s %7s\n" scene ggrt queries rest \
  anchor queries rest queries rest
for s in $scenes; do
  n=examples/scenes/spd/$s.nff
  a=$(split ggRender "$gq" "$g" render "$n" -s 256x256 -j 1 -q -o "$tmp/x.png") || exit 1
  b=$(split worker_main "$aq" "$tmp/anchor" -t 1 -r 256 -p 16 -o - "$n") || exit 1
  echo "$s $a $b" | awk '{
    gr = $2 - $3; ar = $4 - $5
    printf "%-11s %8.1f %8.1f %8.1f | %8.1f %8.1f %8.1f | %7.2f %7.2f\n",
      $1, $2 / 1e6, $3 / 1e6, gr / 1e6, $4 / 1e6, $5 / 1e6, ar / 1e6, $5 / $3, ar / gr }'
done
