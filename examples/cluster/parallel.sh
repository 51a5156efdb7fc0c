#!/bin/sh
# SPDX-License-Identifier: MIT
# Render SCENE in N tiles with GNU parallel over ssh hosts, then merge
# them here (docs/cluster.md).
#   HOSTS=2/alpha,4/beta,: sh examples/cluster/parallel.sh SCENE N OUT [render options...]
# HOSTS is parallel's --sshlogin list: "K/host" runs K jobs at a time on
# host, ":" is this machine without ssh (the default: HOSTS=:). Each host
# needs ggrt on its PATH (or GGRT, the same path on every host). Options
# for ssh (a port, a key) go in PARALLEL_SSH, parallel's --ssh:
#   PARALLEL_SSH='ssh -p 2222 -i key' HOSTS=2/me@alpha sh parallel.sh ...
# With HOSTS=: (this machine alone) each tile reads SCENE where it is,
# with the files it reads (textures, meshes) beside it. Otherwise each
# tile runs in a working folder of its own on its host (--workdir ...:
# under ~/.parallel/tmp/), the scene is copied there with it
# (--transferfile, under its own extension: .nff, .obj or .ply), the
# tile comes back (--return) into PARTS (default OUT.parts), and the
# folder is removed (--cleanup); a scene that reads other files
# (textures, meshes) needs them on the hosts, at the absolute paths it
# names them by (or give the hosts the same tree and absolute paths).
# PLAN=1 cuts the rows by cost first, here (ggrt plan: PARTS/plan.json,
# sent with each tile), rather than in equal bands. parallel runs the
# command quoted (-q): GGRT, SCENE and the options may hold spaces.
set -eu
[ $# -ge 3 ] || { echo "usage: parallel.sh SCENE N OUT.png|OUT.exr [render options...]" >&2; exit 1; }
scene=$1 n=$2 out=$3
shift 3
parts=${PARTS:-$out.parts}
mkdir -p "$parts"
ggrt=${GGRT:-ggrt}
hosts=${HOSTS:-:}
# Tiles are written relative to the remote working folder and returned to
# the same relative path here, so run from PARTS.
case $scene in /*) ;; *) scene=$(pwd)/$scene ;; esac
case $out in /*) ;; *) out=$(pwd)/$out ;; esac
# ggrt reads a scene by its extension: the copy keeps it.
base=${scene##*/}
case $base in *.*) sc=scene.${base##*.} ;; *) sc=scene ;; esac
if [ "$hosts" = ":" ]; then
  sc=$scene
else
  cp "$scene" "$parts/$sc"
fi
cd "$parts"
if [ "${PLAN:-0}" = 1 ]; then
  "$ggrt" plan "$sc" --tiles "$n" -q -o plan.json "$@"
  set -- --plan plan.json "$@"
fi
# Remote hosts work in a folder of their own per tile (--workdir ...),
# removed afterwards; parallel refuses a relative --basefile with those,
# so the scene goes with each tile. ":" alone needs no transfer.
xfer=
if [ "$hosts" != ":" ]; then
  xfer="--workdir ... --transferfile $sc --return part-{}.exr --cleanup"
  if [ "${PLAN:-0}" = 1 ]; then xfer="$xfer --transferfile plan.json"; fi
fi
# --halt now,fail=1: one failed tile stops the run (merge would refuse anyway).
# shellcheck disable=SC2086
seq 0 $((n - 1)) | parallel --will-cite -q -S "$hosts" --halt now,fail=1 $xfer \
  "$ggrt" render "$sc" --tile {}/"$n" -q -o part-{}.exr "$@"
"$ggrt" merge part-*.exr -o "$out"
