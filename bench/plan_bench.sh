#!/bin/sh
# SPDX-License-Identifier: MIT
# make bench-plan: ggrt plan's cut against equal bands, in time.
#   sh bench/plan_bench.sh GGRT [SCENE [N [REPS [render options...]]]]
# Renders SCENE (default gears, examples/scenes/spd/gears.nff, at
# 1024x1024 with 4 samples) in N tiles (default 8), each tile its own
# process with one thread (-j 1), with three cuts: equal bands (--tile
# I/N) and the plans of ggrt plan --cost rays and --cost time (made once;
# their own lines printed). Each tile is rendered REPS times (default 3)
# and its best times kept, the least disturbed by whatever else runs:
#   wall: the tile line's seconds (its render and EXR write, not the load);
#   cpu:  the process's user + system seconds (GNU time) less those of
#         the same render of one pixel (--crop 0,0,1,1: load, prepare,
#         the image), which a busy machine disturbs much less.
# Prints each tile's seconds and, per cut and measure, the slowest over
# the fastest tile. Figures, not a test: nothing fails on a slow machine.
ggrt=${1:?usage: plan_bench.sh GGRT [SCENE [N [REPS [options...]]]]}
scene=${2:-examples/scenes/spd/gears.nff}
n=${3:-8}
reps=${4:-3}
if [ $# -gt 4 ]; then shift 4; else set -- -s 1024x1024 -n 4; fi
command -v /usr/bin/time >/dev/null || { echo "bench-plan: needs GNU time (/usr/bin/time)"; exit 1; }
tmp=$(mktemp -d /tmp/ggrt-bench-plan-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
trap 'exit 1' INT TERM

echo "bench-plan: $scene $*, $n tiles, best of $reps per tile, each tile -j 1"
for cost in rays time; do
  "$ggrt" plan "$scene" "$@" --tiles "$n" --cost $cost -o "$tmp/$cost.json" >"$tmp/out" ||
    { cat "$tmp/out"; exit 1; }
  echo "  $(head -1 "$tmp/out" | sed "s|$tmp/||")"
  echo "    $(grep '^"rows"' "$tmp/$cost.json")"
done

# best A B: the smaller.
best() { echo "${1:-$2} $2" | awk '{ print ($2 < $1) ? $2 : $1 }'; }
# cpu_of CMD...: user + system seconds of the command (output dropped).
cpu_of() {
  /usr/bin/time -f '%U %S' -o "$tmp/time" "$@" >"$tmp/line" || { echo "bench-plan: $* failed" >&2; kill $$; }
  awk '{ print $1 + $2 }' "$tmp/time"
}

base=
r=0
while [ $r -lt "$reps" ]; do
  base=$(best "$base" "$(cpu_of "$ggrt" render "$scene" "$@" -j 1 -q --crop 0,0,1,1 -o "$tmp/b.exr")")
  r=$((r + 1))
done
echo "  load, prepare and a 1-pixel render: $base s cpu (taken off each tile's cpu)"

# tile CUT I [options]: "WALL CPU", each the best of $reps.
tile() {
  w=; c=; r=0
  if [ "$1" = equal ]; then which="--tile $2/$n"; else which="--plan $tmp/$1.json --tile $2"; fi
  shift 2
  while [ $r -lt "$reps" ]; do
    # shellcheck disable=SC2086
    c=$(best "$c" "$(cpu_of "$ggrt" render "$scene" "$@" -j 1 $which -o "$tmp/t.exr")")
    w=$(best "$w" "$(sed -n 's/.*(\([0-9.]*\)s)$/\1/p' "$tmp/line")")
    r=$((r + 1))
  done
  echo "$w $(echo "$c $base" | awk '{ printf "%.2f", $1 - $2 }')"
}

for cut in equal rays time; do
  i=0
  : >"$tmp/times"
  while [ $i -lt "$n" ]; do
    tile $cut $i "$@" >>"$tmp/times"
    i=$((i + 1))
  done
  awk -v cut="$cut" '
    { w[NR] = $1; c[NR] = $2 }
    function show(name, v,   i, lo, hi, s) {
      lo = hi = v[1]; s = ""
      for (i = 1; i <= NR; i++) { if (v[i] < lo) lo = v[i]; if (v[i] > hi) hi = v[i]; s = s " " v[i] }
      printf "  %-5s %-4s s:%s  slowest/fastest %.2fx\n", cut, name, s, (lo > 0 ? hi / lo : 0)
    }
    END { show("wall", w); show("cpu", c) }' "$tmp/times"
done
echo "  uptime: $(uptime)"
