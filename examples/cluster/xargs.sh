#!/bin/sh
# SPDX-License-Identifier: MIT
# Render SCENE in N tiles on this machine, P processes at a time with
# xargs -P, then merge (docs/cluster.md). One process with all the cores
# (plain ggrt render) is usually as fast: tiles pay off across machines,
# or to bound each process's memory and time.
#   P=4 sh examples/cluster/xargs.sh SCENE N OUT.png|OUT.exr [render options...]
# PLAN=1 cuts the rows by cost first (ggrt plan: PARTS/plan.json) rather
# than in equal bands.
set -eu
[ $# -ge 3 ] || { echo "usage: xargs.sh SCENE N OUT.png|OUT.exr [render options...]" >&2; exit 1; }
scene=$1 n=$2 out=$3
shift 3
parts=${PARTS:-$out.parts}
mkdir -p "$parts"
ggrt=${GGRT:-ggrt}
p=${P:-$(getconf _NPROCESSORS_ONLN)}
# Each process gets its share of the cores (-j), so P of them do not
# oversubscribe the machine; the image does not depend on -j.
j=$(( $(getconf _NPROCESSORS_ONLN) / p )); [ "$j" -ge 1 ] || j=1
if [ "${PLAN:-0}" = 1 ]; then
  "$ggrt" plan "$scene" --tiles "$n" -q -o "$parts/plan.json" "$@"
  # --plan goes with the render options, each word quoted (PARTS may
  # hold a space).
  set -- --plan "$parts/plan.json" "$@"
fi
seq 0 $((n - 1)) | xargs -P "$p" -I{} \
  "$ggrt" render "$scene" --tile {}/"$n" -q -j "$j" -o "$parts/part-{}.exr" "$@"
"$ggrt" merge "$parts"/part-*.exr -o "$out"
