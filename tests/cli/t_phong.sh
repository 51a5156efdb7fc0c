# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: the phong=fast knob (render.h,
# GG_ACC_PHONG_FAST) on every example, model, SPD and test-data scene.
# ggrt diff of the knob against the default must find the same ray tree
# in every pixel and no pixel off by more than 2^-20: the power it
# replaces is within (shine - 1) 2^-53 of pow's. One scene in $sample
# (GG_TEST_SAMPLE, run.sh). Uses run.sh's ggrt, tmp, sample, ok, bad.
phong_bad=""; phong_n=0; phong_k=0
for s in examples/scenes/*.nff examples/scenes/models/*.obj examples/scenes/models/*.ply \
         examples/scenes/spd/*.nff tests/data/*.nff tests/data/debug/*.nff; do
  phong_k=$((phong_k + 1))
  [ $((phong_k % sample)) = 1 ] || [ "$sample" = 1 ] || continue
  phong_n=$((phong_n + 1))
  "$ggrt" diff "$s" --b phong=fast -s 24x18 -f json -q >"$tmp/ph.json" 2>"$tmp/err" ||
    { phong_bad="$phong_bad
$s: exit $? $(cat "$tmp/err")"; continue; }
  # "tree_differ":0, "max_delta" <= 2^-20, every pixel scanned
  tr=$(sed -n 's/.*"scanned":\([0-9]*\),.*"tree_differ":\([0-9]*\),"max_delta":\([^,]*\),.*/\1 \2 \3/p' "$tmp/ph.json")
  echo "$tr" | awk '{ exit !($1 == 432 && $2 == 0 && $3 + 0 <= 2 ^ -20) }' ||
    phong_bad="$phong_bad
$s: $tr"
done
if [ -z "$phong_bad" ] && [ "$phong_n" -gt $((30 / sample)) ]; then
  ok "diff --b phong=fast: same ray trees, pixels within 2^-20, on $phong_n scenes"
else bad "diff --b phong=fast: same ray trees, pixels within 2^-20 ($phong_n scenes)" "$phong_bad"; fi
