#!/bin/sh
# SPDX-License-Identifier: MIT
# Two builds of the same sources, by different compilers (or flags), are
# one build: ggBuildId is computed from the sources alone, so `ggrt merge`
# joins their tiles (docs/cluster.md), and that is only right if they
# render the same bytes. This renders every scene file (examples/scenes,
# tests/data/debug and the top of tests/data, as the HTTP scene suite
# lists them) at 64x48 with both, plainly and with --corners -n 4, and
# compares the EXR files and the printed ray counts. `make check` runs it
# on its GCC and clang release trees. Exit 1 on any difference.
# usage: sh tests/build/compilers.sh GGRT_A GGRT_B   (from the top of a checkout)
a=$1; b=$2
if [ ! -x "$a" ] || [ ! -x "$b" ]; then
  echo "usage: sh tests/build/compilers.sh GGRT_A GGRT_B" >&2
  exit 2
fi
ida=$("$a" --version | sed -n 's/.*(build \(.*\)).*/\1/p')
idb=$("$b" --version | sed -n 's/.*(build \(.*\)).*/\1/p')
if [ -z "$ida" ] || [ "$ida" != "$idb" ]; then
  echo "compilers: build ids '$ida' and '$idb' differ: not the same sources" >&2
  exit 1
fi
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
n=0; bad=0
scenes=$(find examples/scenes tests/data/debug -name '*.nff' -o -name '*.obj' -o -name '*.ply' | sort;
         ls tests/data/*.nff)
for s in $scenes; do
  for o in "" "--corners -n 4"; do
    # shellcheck disable=SC2086 # $o is two options or none
    "$a" render "$s" -s 64x48 -j 2 $o -o "$tmp/a.exr" >"$tmp/a.txt" 2>&1
    ra=$?
    # shellcheck disable=SC2086
    "$b" render "$s" -s 64x48 -j 2 $o -o "$tmp/b.exr" >"$tmp/b.txt" 2>&1
    rb=$?
    n=$((n + 1))
    if [ $ra != 0 ] || [ $rb != 0 ]; then
      echo "compilers: $s $o: exit $ra and $rb"; bad=1; continue
    fi
    grep '^rays' "$tmp/a.txt" >"$tmp/ra.txt"; grep '^rays' "$tmp/b.txt" >"$tmp/rb.txt"
    if ! cmp -s "$tmp/a.exr" "$tmp/b.exr" || ! cmp -s "$tmp/ra.txt" "$tmp/rb.txt" ||
       [ ! -s "$tmp/ra.txt" ]; then
      echo "compilers: $s $o: the images or ray counts differ"; bad=1
    fi
  done
done
if [ $bad = 0 ]; then
  echo "compilers: build $ida, $n renders of $((n / 2)) scene files: the same bytes and ray counts from $a and $b"
fi
exit $bad
