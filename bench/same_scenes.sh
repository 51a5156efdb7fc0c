#!/bin/sh
# SPDX-License-Identifier: MIT
# Does a change keep every image, ray count and ray tree? Every example
# scene (examples/scenes/**/*.nff: the examples, spd/, and the models in
# examples/scenes/models, framed as ggrt render frames them), rendered at
# 64x64 by two builds of ggrt with several option sets -- the defaults,
# --spd, every effect forced, and the knobs that change what shading does
# (offset, shadows, fresnel, intersect) -- comparing the EXR bytes and the
# printed ray counts; then `ggrt trace` of three pixels per scene, whose
# text must be the same. bench/same_images.sh is the same check on the
# top-level and SPD scenes at 96x96 with sampling options.
# usage: sh bench/same_scenes.sh NEW_GGRT OLD_GGRT   (from the top of a checkout)
new=$1; old=$2
[ -x "$new" ] && [ -x "$old" ] || { echo "usage: sh bench/same_scenes.sh NEW_GGRT OLD_GGRT" >&2; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
scenes=$(find examples/scenes -name '*.nff' | sort; ls examples/scenes/models/*.obj examples/scenes/models/*.ply 2>/dev/null)
bad=0; n=0; t=0
for s in $scenes; do
  for o in "" "--spd" "--force-effects" "-a offset=1e-6" "-a shadows=opaque" \
           "-a fresnel=schlick" "-a intersect=float" "--force-effects -a fresnel=none,offset=1e-5"; do
    "$old" render "$s" -s 64x64 -j 2 $o -o "$tmp/old.exr" 2>&1 | grep '^rays' >"$tmp/old.txt"
    "$new" render "$s" -s 64x64 -j 2 $o -o "$tmp/new.exr" 2>&1 | grep '^rays' >"$tmp/new.txt"
    n=$((n + 1))
    if ! [ -s "$tmp/old.txt" ] || ! cmp -s "$tmp/old.exr" "$tmp/new.exr" || ! cmp -s "$tmp/old.txt" "$tmp/new.txt"; then
      echo "render differs: $s $o"; bad=1
    fi
  done
  for p in 32,32 16,20 45,40; do
    "$old" trace "$s" -s 64x64 --pixel $p --ascii >"$tmp/old.tr" 2>&1
    "$new" trace "$s" -s 64x64 --pixel $p --ascii >"$tmp/new.tr" 2>&1
    t=$((t + 1))
    cmp -s "$tmp/old.tr" "$tmp/new.tr" || { echo "trace differs: $s $p"; bad=1; }
  done
done
if [ $bad = 0 ]; then r=identical; else r="some differ"; fi
echo "$n renders (ray counts and EXR bytes) and $t traces compared over $(echo "$scenes" | wc -l) scenes: $r"
exit $bad
