#!/bin/sh
# SPDX-License-Identifier: MIT
# Wall time of two builds of ggrt side by side: ROUNDS rounds of one render
# each of one SPD scene, in the order old, new then new, old (ABBA), the
# median and the fastest of each and old/new (above 1: the new build is
# faster; interference only slows a render, so the fastest is the steadier).
# Alternating keeps a drifting machine from favouring either; swapping the
# order each round matters too: on the shared 2-core machine the second
# render of a pair ran 5-10% slower (docs/performance.md).
# usage: sh bench/ab_time.sh OLD_GGRT NEW_GGRT SCENE [SIZE] [THREADS] [ROUNDS]
#   (from the top of a checkout; defaults 512, 1, 7). SCENE is an SPD
#   scene's name (gears) or a scene file's path (the meshes of
#   scripts/make-mesh-scenes.py, say).
old=$1 new=$2 s=$3 size=${4:-512} thr=${5:-1} n=${6:-7}
[ -x "$old" ] && [ -x "$new" ] && [ -n "$s" ] ||
  { echo "usage: sh bench/ab_time.sh OLD_GGRT NEW_GGRT SCENE [SIZE] [THREADS] [ROUNDS]" >&2; exit 1; }
case $s in
*/* | *.nff | *.obj | *.ply) path=$s ;;
*) path=examples/scenes/spd/$s.nff ;;
esac
[ -f "$path" ] || { echo "bench/ab_time.sh: no scene $path" >&2; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
i=0
while [ $i -lt "$n" ]; do
  order="old new"
  [ $((i % 2)) -eq 1 ] && order="new old"
  for b in $order; do
    eval bin=\$$b
    "$bin" render "$path" -s "${size}x$size" -j "$thr" -o "$tmp/x.exr" 2>&1 |
      sed -n "s/.*render \([0-9.]*\)s.*/$b \1/p" >>"$tmp/t"
  done
  i=$((i + 1))
done
med() { awk -v k="$1" '$1 == k { print $2 }' "$tmp/t" | sort -n | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }'; }
fastest() { awk -v k="$1" '$1 == k { print $2 }' "$tmp/t" | sort -n | head -1; }
mo=$(med old) mn=$(med new) fo=$(fastest old) fn=$(fastest new)
[ -n "$mo" ] && [ -n "$mn" ] || { echo "bench/ab_time.sh: no render time from $s" >&2; exit 1; }
echo "$s $mo $mn $fo $fn" | awk '{ printf "%-11s median old %.3f s  new %.3f s  old/new %.3f | fastest old %.3f s  new %.3f s  old/new %.3f\n", $1, $2, $3, $2 / $3, $4, $5, $4 / $5 }'
