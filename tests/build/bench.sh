#!/bin/sh
# SPDX-License-Identifier: MIT
# The benchmarks still run: every program of bench/ and every `ggrt bench`
# subcommand at its smallest size, each exiting 0 and printing its table's
# first line; nothing left in the source tree; and the one figure that is a
# bound rather than a measurement, issue 32's: ggRefract executes at most
# 4.5 times the textbook formula's instructions (callgrind, when valgrind
# is installed; counts, not times, so a loaded machine does not move it).
# The figures themselves are not judged: docs/performance.md has them.
# A benchmark nobody runs rots (docs/log/2026-12-07-bench-audit.md: an 8%
# regression of ggRefract's instructions went unseen for a day).
#   sh tests/build/bench.sh BUILD        (make check runs it on the release tree)
cd "$(dirname "$0")/../.." || exit 1
b=${1:?usage: sh tests/build/bench.sh BUILD}
g=$b/ggrt
tmp=$(mktemp -d /tmp/ggrt-bench-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "bench: $*"; exit 1; }
n=0
before=$(git status --porcelain 2>/dev/null)

# run WANT CMD...: CMD exits 0 and its output has a line starting with WANT.
run() {
  want=$1
  shift
  "$@" > "$tmp/out" 2>&1 || { tail -n 5 "$tmp/out"; fail "'$*' exited $?"; }
  grep -q "^$want" "$tmp/out" || { tail -n 5 "$tmp/out"; fail "'$*' printed no line starting '$want'"; }
  n=$((n + 1))
}

tetra=examples/scenes/spd/tetra.nff
run 'bench_debug: 16x16' "$b/bench/bench_debug" -s 16 -r 1 -t 1 "$tetra"
run "$tetra" "$b/bench/bench_render" -s 16 -r 1 -t 1 "$tetra"
run 'ggrt: traversal ' "$b/bench/bench_geometry" -n 16 -r 100 "$tetra"
run 'torus-' "$b/bench/bench_mesh" --sizes 1000 --repeat 1
run '  ggTextureChecker' "$b/bench/bench_image"
run '  callback, central' "$b/bench/bench_implicit"
run 'function (inputs)' "$b/bench/bench_optics"
run 'scene ' "$g" bench spd --size 16 --runs 1
run 'scene ' "$g" bench counts
run 'scene ' "$g" bench effects --size 16 --runs 1
run 'scene ' "$g" bench rays --size 16 --runs 1 "$tetra"
run 'scene ' "$g" bench limit --size 16 --runs 1 "$tetra"
run 'scene ' "$g" bench scaling --size 16 --runs 1
run 'knob ' "$g" bench accuracy "$tetra" --size 16 --runs 1 --knobs sphere --out "$tmp"
[ -s "$tmp/accuracy.csv" ] && [ -s "$tmp/accuracy.svg" ] || fail "bench accuracy --out wrote no csv and svg"
echo "bench: $n benchmarks ran at their smallest sizes and printed their tables"

if command -v valgrind >/dev/null 2>&1; then
  sh bench/optics_counts.sh "$b/bench/bench_optics" > "$tmp/counts" 2>&1
  r=$(awk '$1 == "ggRefract" && $4 == "ratio" { sub(/,$/, "", $5); print $5 }' "$tmp/counts")
  [ -n "$r" ] || { cat "$tmp/counts"; fail "optics_counts.sh printed no ggRefract ratio"; }
  awk -v r="$r" 'BEGIN { exit !(r <= 4.5) }' ||
    { grep -E '^ggRefract' "$tmp/counts"; fail "ggRefract executes $r times the textbook formula's instructions (at most 4.5: issue 32)"; }
  echo "bench: ggRefract executes $r times the textbook formula's instructions (at most 4.5)"
else
  echo "bench: valgrind not installed: ggRefract's instruction bound not checked"
fi

[ "$(git status --porcelain 2>/dev/null)" = "$before" ] ||
  { git status --short; fail "the source tree changed while the benchmarks ran (above; nothing may write there)"; }
