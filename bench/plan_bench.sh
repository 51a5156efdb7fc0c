#!/bin/sh
# SPDX-License-Identifier: MIT
# make bench-plan: ggrt plan's cut against equal bands, in time.
#   sh bench/plan_bench.sh GGRT [SCENE [N [REPS [render options...]]]]
# Renders SCENE (default gears, examples/scenes/spd/gears.nff, at
# 1024x1024 with 4 samples) in N tiles (default 8), each tile its own
# process with one thread (-j 1), with three cuts: equal bands (--tile
# I/N) and the plans of ggrt plan --cost rays and --cost time (made once;
# their own lines printed). Each tile is rendered REPS times (default 5),
# in rounds over all the tiles, and its best times kept, the least
# disturbed by whatever else runs:
#   wall: the tile line's seconds (its render and EXR write, not the load);
#   cpu:  the process's user + system seconds (GNU time) less those of
#         the same render of one pixel (--crop 0,0,1,1: load, prepare,
#         the image), which a busy machine disturbs much less.
# Prints each tile's seconds and, per cut and measure, the slowest over
# the fastest tile. Figures, not a test: nothing fails on a slow machine.
ggrt=${1:?usage: plan_bench.sh GGRT [SCENE [N [REPS [options...]]]]}
scene=${2:-examples/scenes/spd/gears.nff}
n=${3:-8}
reps=${4:-5}
if [ $# -gt 4 ]; then shift 4; else set -- -s 1024x1024 -n 4; fi
command -v /usr/bin/time >/dev/null || { echo "bench-plan: needs GNU time (/usr/bin/time)"; exit 1; }
tmp=$(mktemp -d /tmp/ggrt-bench-plan-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
trap 'exit 1' INT TERM

echo "bench-plan: $scene $*, $n tiles, best of $reps rounds per tile, each tile -j 1"
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

# one CUT I [options]: "WALL CPU" of one render of tile I of CUT.
one() {
  if [ "$1" = equal ]; then which="--tile $2/$n"; else which="--plan $tmp/$1.json --tile $2"; fi
  shift 2
  # shellcheck disable=SC2086
  c=$(cpu_of "$ggrt" render "$scene" "$@" -j 1 $which -o "$tmp/t.exr")
  echo "$(sed -n 's/.*(\([0-9.]*\)s)$/\1/p' "$tmp/line") $c"
}

# Rounds: every tile of every cut once per round, so that a slow spell
# of the machine falls on different tiles in different rounds rather than
# on all the repeats of one tile.
r=0
while [ $r -lt "$reps" ]; do
  for cut in equal rays time; do
    i=0
    while [ $i -lt "$n" ]; do
      echo "$cut $i $(one $cut $i "$@")" >>"$tmp/runs"
      i=$((i + 1))
    done
  done
  r=$((r + 1))
done

for cut in equal rays time; do
  awk -v cut="$cut" -v base="$base" -v n="$n" '
    $1 == cut { i = $2 + 1
                if (!(i in w) || $3 < w[i]) w[i] = $3
                if (!(i in c) || $4 - base < c[i]) c[i] = $4 - base }
    function show(name, v,   i, lo, hi, s) {
      lo = hi = v[1]; s = ""
      for (i = 1; i <= n; i++) { if (v[i] < lo) lo = v[i]; if (v[i] > hi) hi = v[i]; s = s sprintf(" %.3f", v[i]) }
      printf "  %-5s %-4s s:%s  slowest/fastest %.2fx\n", cut, name, s, (lo > 0 ? hi / lo : 0)
    }
    END { show("wall", w); show("cpu", c) }' "$tmp/runs"
done
echo "  uptime: $(uptime)"
