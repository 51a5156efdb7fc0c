#!/bin/sh
# SPDX-License-Identifier: MIT
# Render the seven SPD scenes at 160x160 with ggrt and with POV-Ray 3.7 into
# docs/spd/, then compose docs/spd-compare.png. ggrt writes with --no-srgb,
# storing values as POV-Ray does, so tones compare directly.
#   sh scripts/spd-thumbs.sh [build/ggrt] [examples/scenes/spd-pov]
set -e
ggrt=${1:-build/ggrt}; pov=${2:-examples/scenes/spd-pov}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
mkdir -p docs/spd
cp "$pov/spd_globals.inc" "$tmp/"
for s in balls-s4 gears rings tetra mount tree teapot-s12; do
  "$ggrt" render "examples/scenes/spd/$s.nff" -o "docs/spd/ggrt-$s.png" -s 160x160 -q --no-srgb
  gzip -dc "$pov/$s.pov.gz" > "$tmp/$s.pov"
  (cd "$tmp" && povray "+I$s.pov" +HIspd_globals.inc "+O$s.png" +FN +W160 +H160 -A +WT1 -D >/dev/null 2>&1)
  cp "$tmp/$s.png" "docs/spd/pov-$s.png"
done
python3 scripts/spd-compare.py
