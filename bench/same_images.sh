#!/bin/sh
# SPDX-License-Identifier: MIT
# Does a change keep every image and ray count? Renders every
# examples/scenes/*.nff and examples/scenes/spd/*.nff at 96x96 -- plain,
# --spd, --corners and -n 4 -- with two builds of ggrt and compares the EXR
# bytes and the printed ray counts. Exit 1 on any difference.
# usage: sh bench/same_images.sh NEW_GGRT OLD_GGRT   (from the top of a checkout;
#   an old build: git worktree add /tmp/old COMMIT && make -C /tmp/old)
new=$1; old=$2
[ -x "$new" ] && [ -x "$old" ] || { echo "usage: sh bench/same_images.sh NEW_GGRT OLD_GGRT" >&2; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
bad=0; n=0
for s in examples/scenes/*.nff examples/scenes/spd/*.nff; do
  for o in "" "--spd" "--corners" "-n 4"; do
    "$old" render "$s" -s 96x96 -j 2 $o -o "$tmp/old.exr" 2>&1 | grep '^rays' >"$tmp/old.txt"
    "$new" render "$s" -s 96x96 -j 2 $o -o "$tmp/new.exr" 2>&1 | grep '^rays' >"$tmp/new.txt"
    n=$((n + 1))
    if ! cmp -s "$tmp/old.exr" "$tmp/new.exr" || ! cmp -s "$tmp/old.txt" "$tmp/new.txt"; then
      echo "differs: $s $o"; bad=1
    fi
  done
done
if [ $bad = 0 ]; then echo "$n renders compared, all identical"; else echo "$n renders compared, some differ"; fi
exit $bad
