#!/bin/sh
# Alternate two builds of bench_render (with and without the ray-tree
# recorder compiled in) on the same scenes, five rounds, and print the
# median times and their ratio.
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
