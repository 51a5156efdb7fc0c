#!/bin/sh
# SPDX-License-Identifier: MIT
# Instructions executed in ggRender (callgrind), 256x256, one thread, on the
# SPD scenes: the stable measure of a speed change (docs/performance.md).
# usage: sh bench/instr.sh GGRT [SCENE...]   (from the top of a checkout)
usage() { echo "usage: sh bench/instr.sh GGRT [SCENE...]   (e.g. build/ggrt gears)" >&2; exit 1; }
[ $# -ge 1 ] && [ -x "$1" ] || usage
g=$1; shift
command -v valgrind >/dev/null || { echo "bench/instr.sh: needs valgrind (apt-get install valgrind)" >&2; exit 1; }
scenes=${*:-balls-s4 gears rings tetra mount tree teapot-s12}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
for s in $scenes; do
  valgrind --tool=callgrind --callgrind-out-file="$tmp/cg" --toggle-collect=ggRender \
    "$g" render "examples/scenes/spd/$s.nff" -s 256x256 -j 1 -q -o "$tmp/x.png" >/dev/null 2>&1 || exit 1
  printf "%-11s %s\n" "$s" "$(callgrind_annotate "$tmp/cg" 2>/dev/null | sed -n 's/^\([0-9,]*\) .*PROGRAM TOTALS.*/\1/p')"
done
