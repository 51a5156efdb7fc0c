#!/bin/sh
# SPDX-License-Identifier: MIT
# Alternate two builds of bench_render (with and without the ray-tree
# recorder compiled in) on the same scenes, seven rounds, and print the
# median times and their ratio; with valgrind, also the instructions of
# ggRender in each. `make bench-trace` builds both and runs it.
# usage: sh bench/trace_overhead.sh WITH WITHOUT   (from the top of a checkout)
[ $# -eq 2 ] && [ -x "$1" ] && [ -x "$2" ] || {
  echo "usage: sh bench/trace_overhead.sh WITH WITHOUT   (two bench_render builds, e.g." >&2
  echo "       build/bench/bench_render build/norec/bench/bench_render; make bench-trace runs it)" >&2
  exit 1
}
with=$1; without=$2
scenes="examples/scenes/spd/balls-s4.nff examples/scenes/spd/gears.nff examples/scenes/glass.nff"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
for round in 1 2 3 4 5 6 7; do
  "$with" -s 512 -r 1 $scenes >>"$tmp/with" || exit 1
  "$without" -s 512 -r 1 $scenes >>"$tmp/without" || exit 1
done
echo "render seconds at 512x512, 2 threads, median of 7 alternated rounds"
printf '%-36s %12s %12s %8s\n' scene "recorder-in" "recorder-out" ratio
for s in $scenes; do
  a=$(grep "^$s " "$tmp/with" | awk '{print $2}' | sort -n | sed -n 4p)
  b=$(grep "^$s " "$tmp/without" | awk '{print $2}' | sort -n | sed -n 4p)
  awk -v s="$s" -v a="$a" -v b="$b" 'BEGIN { printf "%-36s %11.4fs %11.4fs %7.3f\n", s, a, b, a / b }'
done

# Wall times on a shared 2-core machine move by several percent from run to
# run; instruction counts do not. With valgrind, count the instructions of
# ggRender alone, single-threaded, in both builds.
if command -v valgrind >/dev/null 2>&1; then
  echo
  echo "instructions executed in ggRender (valgrind --tool=callgrind, 128x128, 1 thread)"
  printf '%-36s %14s %14s %8s\n' scene "recorder-in" "recorder-out" ratio
  for s in $scenes; do
    for b in with without; do
      bin=$with; [ $b = without ] && bin=$without
      valgrind --tool=callgrind --callgrind-out-file="$tmp/cg.$b" --toggle-collect=ggRender \
        "$bin" -s 128 -r 1 -t 1 "$s" >/dev/null 2>"$tmp/vg.$b" || exit 1
      grep -o 'refs: *[0-9,]*' "$tmp/vg.$b" | tr -d ', ' | sed 's/refs://' > "$tmp/ir.$b"
    done
    awk -v s="$s" -v a="$(cat "$tmp/ir.with")" -v b="$(cat "$tmp/ir.without")" \
      'BEGIN { printf "%-36s %14d %14d %8.4f\n", s, a, b, a / b }'
  done
fi
