#!/bin/sh
# SPDX-License-Identifier: MIT
# Render SCENE in N tiles as a Slurm array job and merge them in a job that
# starts when all N succeeded (docs/cluster.md).
#   sh examples/cluster/slurm.sh SCENE N OUT.png|OUT.exr [render options...]
# Prints the two job ids. The tiles and the logs go to PARTS (default
# OUT's folder/OUT.parts), which must be on a file system the nodes share,
# as SCENE and OUT must; it must not hold another render's tiles (merge
# would refuse them). GGRT: the ggrt binary on the nodes (default ggrt).
# Extra sbatch options (a partition, a time limit) go in SBATCH_* variables
# (SBATCH_PARTITION, SBATCH_TIMELIMIT), which sbatch reads itself. PLAN=1
# cuts the rows by cost first, here (ggrt plan: PARTS/plan.json, about 3/16
# of the render's work), rather than in equal bands.
set -eu
[ $# -ge 3 ] || { echo "usage: slurm.sh SCENE N OUT.png|OUT.exr [render options...]" >&2; exit 1; }
scene=$1 n=$2 out=$3
shift 3
here=$(cd "$(dirname "$0")" && pwd)
parts=${PARTS:-$out.parts}
mkdir -p "$parts"
if [ "${PLAN:-0}" = 1 ]; then
  "${GGRT:-ggrt}" plan "$scene" --tiles "$n" -q -o "$parts/plan.json" "$@"
  PLAN_FILE=$parts/plan.json
  export PLAN_FILE # sbatch passes the environment on to tile.sbatch
fi
# --parsable prints "JOBID" or "JOBID;CLUSTER".
array=$(sbatch --parsable --array=0-$((n - 1)) --output="$parts/tile-%a.log" \
  "$here/tile.sbatch" "$scene" "$n" "$parts" "$@")
array=${array%%;*}
merge=$(sbatch --parsable --dependency=afterok:"$array" --kill-on-invalid-dep=yes \
  --output="$parts/merge.log" "$here/merge.sbatch" "$parts" "$out")
merge=${merge%%;*}
echo "tiles: job $array (array 0-$((n - 1))); merge: job $merge, after all of them"
echo "wait: squeue -j $array,$merge; logs: $parts/*.log"
