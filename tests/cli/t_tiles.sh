# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: ggrt render --tile/--tiles, ggrt plan and
# ggrt merge (docs/cluster.md). Tiles of three scenes (one under --spd,
# whose pixels share their corner rays with the rows above and below)
# merged from 1, 2, 7 and 16 equal bands, and from 2, 7 and 16 bands of a
# ggrt plan, give the very files one process writes, EXR and PNG (cmp);
# every bad input to merge names the tile and the reason, exits 2 and
# writes nothing; a plan for another scene, other options or another size
# is refused. Uses run.sh's ggrt, tmp, sample, ok, bad, expect_err.

td="$tmp/tiles"
mkdir -p "$td"

# merge_same NAME N SCENE [options]: N tiles (rendered by a mix of
# --tile and --tiles processes, with differing -j) merge into one
# process's EXR and PNG, byte for byte. With $plan set, the tiles are
# the cut of that plan file (--plan, and --tile I without /N).
merge_same() {
  name=$1; n=$2; shift 2
  rm -f "$td"/p-*.exr
  half=$((n / 2))
  if [ -n "$plan" ]; then pl="--plan $plan"; of=""; else pl=""; of="/$n"; fi
  if [ "$n" = 1 ]; then
    # shellcheck disable=SC2086
    "$ggrt" render "$@" -q $pl --tile 0$of -o "$td/p-0.exr" 2>"$tmp/err" ||
      { bad "$name: render --tile 0$of" "$(cat "$tmp/err")"; return; }
  else
    # The first tile alone with one thread, the rest in one process
    # (a range, then the single indices if any: no trailing comma).
    rest=$(seq -s, 1 $((half - 1)) | sed 's/,$//')
    # shellcheck disable=SC2086
    "$ggrt" render "$@" -q -j 1 $pl --tile 0$of -o "$td/p-0.exr" 2>"$tmp/err" &&
    "$ggrt" render "$@" -q $pl \
      --tiles "$half-$((n - 1))${rest:+,$rest}$of" \
      -o "$td/p-%d.exr" 2>>"$tmp/err" ||
      { bad "$name: render --tiles of $n" "$(cat "$tmp/err")"; return; }
  fi
  "$ggrt" merge -q "$td"/p-*.exr -o "$td/m.exr" 2>"$tmp/err" &&
  "$ggrt" merge -q "$td"/p-*.exr -o "$td/m.png" 2>>"$tmp/err" ||
    { bad "$name: merge of $n tiles" "$(cat "$tmp/err")"; return; }
  if cmp -s "$td/m.exr" "$td/one.exr" && cmp -s "$td/m.png" "$td/one.png"; then
    ok "$name: $n tiles merge into one process's EXR and PNG, byte for byte"
  else
    bad "$name: $n tiles merge into one process's EXR and PNG" \
      "$(cmp "$td/m.exr" "$td/one.exr"; cmp "$td/m.png" "$td/one.png")"
  fi
}

# Equal bands of 1, 2, 7 and 16 tiles and plans of 2, 7 and 16 for each
# scene; when run.sh samples (GG_TEST_SAMPLE), one of each per scene,
# rotating, so that 1, 7 and 16 bands and plans of 2, 7 and 16 each run
# once (--tile alone, --tiles, a plan's cut: every path).
si=0
for spec in "examples/scenes/spd/gears.nff --spd -s 96x64" \
            "examples/scenes/glass.nff -s 80x48" \
            "examples/scenes/texture.nff -s 64x40 -n 4"; do
  bands="1 2 7 16" plans="2 7 16"
  if [ "$sample" != 1 ]; then
    bands=$(echo "16 1 7" | cut -d' ' -f$((si + 1))) plans=$(echo "7 16 2" | cut -d' ' -f$((si + 1)))
  fi
  si=$((si + 1))
  # shellcheck disable=SC2086
  set -- $spec
  "$ggrt" render "$@" -q -o "$td/one.exr" && "$ggrt" render "$@" -q -o "$td/one.png" ||
    { bad "one-process render of $spec"; continue; }
  plan=
  for n in $bands; do
    # shellcheck disable=SC2086
    merge_same "$spec" "$n" $spec
  done
  for n in $plans; do
    plan="$td/plan-$n.json"
    # shellcheck disable=SC2086
    "$ggrt" plan $spec -q --tiles $n -o "$plan" 2>"$tmp/err" ||
      { bad "plan of $n tiles of $spec" "$(cat "$tmp/err")"; continue; }
    # shellcheck disable=SC2086
    merge_same "$spec, plan" "$n" $spec
  done
  plan=
done

# ---- plans: a cut of their own, reproducible, in the manifest ----
gears="examples/scenes/spd/gears.nff --spd -s 96x64"
# shellcheck disable=SC2086
"$ggrt" plan $gears -q --cost rays --tiles 7 -o "$td/gplan.json" &&
  "$ggrt" render $gears -q --plan "$td/gplan.json" --tile 3 -o "$td/gp-3.exr" ||
  bad "plan and render of gears"
grows=$(grep '^"rows"' "$td/gplan.json")
# shellcheck disable=SC2086
"$ggrt" plan $gears -q -j 1 --cost rays --tiles 7 -o "$td/again-7.json" 2>"$tmp/err" ||
  bad "plan of gears with -j 1" "$(cat "$tmp/err")"
# The seconds differ between runs; the rows may not.
rows2=$(grep '^"rows"' "$td/again-7.json")
if [ -n "$grows" ] && [ "$grows" = "$rows2" ]; then ok "a plan by rays is the same with -j 1 and -j 2"
else bad "a plan by rays is the same with -j 1 and -j 2" "$grows / $rows2"; fi
if [ "$grows" != '"rows":[0,9,18,27,36,45,54,64],' ] && [ "$grows" != '"rows":[0,9,18,27,36,45,54,64]' ] &&
   [ -n "$grows" ]; then ok "gears' plan is not the equal cut ($grows)"
else bad "gears' plan is not the equal cut" "$grows"; fi
# By time: --runs renders, each pixel's least time kept; recorded.
# shellcheck disable=SC2086
"$ggrt" plan $gears -q --runs 2 --tiles 7 -o "$td/runs.json" 2>"$tmp/err" ||
  bad "plan --runs 2" "$(cat "$tmp/err")"
if grep -q '"cost":"time","heatmap":\[24,16\],"runs":2,' "$td/runs.json"; then ok "a plan by time records its --runs"
else bad "a plan by time records its --runs" "$(head -1 "$td/runs.json")"; fi
# shellcheck disable=SC2086
expect_err 1 "ggrt plan: bad value '0' for --runs: expected a whole number from 1 to 100 (out of range)" \
  "plan --runs 0 is refused" "$ggrt" plan $gears --runs 0 --tiles 7 -o "$td/runs0.json"
# shellcheck disable=SC2086
expect_err 1 "ggrt plan: --runs goes with --cost time (rays are the same every run)" \
  "plan --cost rays --runs is refused, not recorded as 1" \
  "$ggrt" plan $gears --cost rays --runs 7 --tiles 7 -o "$td/runs7.json"
want=$(echo "$grows" | sed 's/^"rows":\[\(.*\)\],*$/plan \1/')
# (strings runs the attribute's value into the next name: a non-digit.)
if strings -n 6 "$td/gp-3.exr" | grep -q "^$want\([^0-9,].*\)*\$"; then ok "a plan's tile carries the cut '$want'"
else bad "a plan's tile carries the cut '$want'" "$(strings -n 6 "$td/gp-3.exr" | grep plan)"; fi

# ---- the manifest and the refusals of render ----
"$ggrt" render examples/scenes/glass.nff -s 80x48 -q --tiles 0-6/7 -o "$td/g-%d.exr" 2>"$tmp/err" ||
  bad "render --tiles 0-6/7" "$(cat "$tmp/err")"
expect_err 1 "ggrt render: --tiles writes several files: -o needs a %d (a plain one, for the tile's number)" \
  "--tiles needs %d in -o" "$ggrt" render examples/scenes/glass.nff --tiles 0,1/4 -o "$td/x.exr"
expect_err 1 "ggrt render: --tiles writes several files: -o needs a %d (a plain one, for the tile's number)" \
  "--tiles takes a plain %d, not %05d" "$ggrt" render examples/scenes/glass.nff --tiles 0,1/4 -o "$td/x-%05d.exr"
expect_err 1 "ggrt render: tiles are OpenEXR files: -o must end in .exr" "a tile is an EXR" \
  "$ggrt" render examples/scenes/glass.nff --tile 0/4 -o "$td/x.png"
# a name with no image extension: the tiles' rule, not "end in .png or .exr"
expect_err 1 "ggrt render: tiles are OpenEXR files: -o must end in .exr" "a tile named without .exr" \
  "$ggrt" render examples/scenes/glass.nff --tiles 0-1/4 -o "$td/part-%d"
# --aov-png alone was ignored by a tile (a whole render refuses it without --aov)
for o in "--aov all=C.* --aov-png $td" "--aov-png $td"; do
  expect_err 1 "ggrt render: --tile and --tiles take no --aov or --aov-png" "--tile with $o refused" \
    "$ggrt" render examples/scenes/glass.nff --tile 0/4 $o -o "$td/x.exr"
done
expect_err 1 "ggrt render: bad value '4/4' for --tile: tile index '4' is not in 0..3" \
  "--tile index out of range" "$ggrt" render examples/scenes/glass.nff --tile 4/4 -o "$td/x.exr"
# a range backwards or a trailing comma is a mistake, not an empty list
for tl in "0,3-1/4" "3-1/4"; do
  expect_err 1 "ggrt render: bad value '$tl' for --tiles: range 3-1 runs backwards: give 1-3" \
    "--tiles $tl is refused" "$ggrt" render examples/scenes/glass.nff --tiles "$tl" -o "$td/x%d.exr"
done
expect_err 1 "ggrt render: bad value '0,1,/4' for --tiles: expected a tile index after the last ','" \
  "--tiles with a trailing comma is refused" \
  "$ggrt" render examples/scenes/glass.nff --tiles 0,1,/4 -o "$td/x%d.exr"
for tn in 0 2000000000; do
  expect_err 1 "ggrt render: bad value '0/$tn' for --tile: N, the number of tiles: expected a whole number from 1 to 65536 (out of range)" \
    "--tile 0/$tn: the message names N's range" "$ggrt" render examples/scenes/glass.nff --tile 0/$tn -o "$td/x.exr"
done
expect_err 1 "ggrt render: 49 tiles of 48 rows: at most one tile per row" "more tiles than rows" \
  "$ggrt" render examples/scenes/glass.nff -s 80x48 --tile 0/49 -o "$td/x.exr"
expect_err 1 "ggrt render: --tile and --tiles take none of --heatmap, --pixel, --no-srgb and --crop" \
  "--tile refuses --crop" "$ggrt" render examples/scenes/glass.nff --tile 0/4 --crop 0,0,4,4 -o "$td/x.exr"
# Every tile's file is checked before the first is rendered: a directory
# in the way of tile 1, or tile 1's name being the scene (here a link to
# it), leaves no tile 0 behind.
rm -rf "$td"/q-*; mkdir "$td/q-1.exr"
expect_err 3 "ggrt render: refusing to write '$td/q-1.exr': it is a directory (give a file name)" \
  "--tiles: a bad path for a later tile is refused before rendering" \
  "$ggrt" render examples/scenes/glass.nff -s 16x12 -q --tiles 0,1/3 -o "$td/q-%d.exr"
[ ! -e "$td/q-0.exr" ] && ok "--tiles with a bad later path writes no tile" ||
  bad "--tiles with a bad later path writes no tile" "$(ls "$td")"
rm -rf "$td"/q-*; ln -s "$PWD/examples/scenes/glass.nff" "$td/q-1.exr"
expect_err 1 "ggrt render: -o '$td/q-1.exr' is the input 'examples/scenes/glass.nff': writing it would destroy it" \
  "--tiles: a tile's path that is the scene is refused" \
  "$ggrt" render examples/scenes/glass.nff -s 16x12 -q --tiles 0,1/3 -o "$td/q-%d.exr"
[ ! -e "$td/q-0.exr" ] && ok "--tiles with a later path on the scene writes no tile" ||
  bad "--tiles with a later path on the scene writes no tile" "$(ls "$td")"
rm -rf "$td"/q-*

# ---- a tile warns as the whole render does (also under -q) ----
# NaN and negative pixels, with the ggrt trace that replays the worst (in
# the image's coordinates): the one tile of the whole image says what the
# whole render says, named; of two, each its own rows' (their counts add
# up). The ray budget's cut too.
"$ggrt" render tests/data/debug/nan.nff -s 64x48 -q -o "$td/nan.exr" 2>"$td/nan-one.err"
"$ggrt" render tests/data/debug/nan.nff -s 64x48 -q --tile 0/1 -o "$td/nan-0.exr" 2>"$td/nan-t.err"
if grep -q "pixels are NaN" "$td/nan-one.err" &&
   sed 's|^ggrt render: warning: tile 0/1: |ggrt render: warning: |' "$td/nan-t.err" |
   cmp -s - "$td/nan-one.err"; then ok "--tile 0/1 warns of NaN pixels as the whole render does"
else bad "--tile 0/1 warns of NaN pixels as the whole render does" "$(cat "$td/nan-t.err")"; fi
"$ggrt" render tests/data/debug/nan.nff -s 64x48 -q --tiles 0-1/2 -o "$td/nan-%d.exr" 2>"$td/nan-t.err"
n1=$(sed -n 's/.*warning: \([0-9]*\) pixels are NaN.*/\1/p' "$td/nan-one.err")
n0=$(sed -n 's|.*warning: tile 0/2: \([0-9]*\) pixels are NaN.*|\1|p' "$td/nan-t.err")
n2=$(sed -n 's|.*warning: tile 1/2: \([0-9]*\) pixels are NaN.*|\1|p' "$td/nan-t.err")
w2=$(sed -n 's|^  ggrt trace .* --pixel [0-9]*,\([0-9]*\)$|\1|p' "$td/nan-t.err" | tail -1)
if [ -n "$n1" ] && [ -n "$n0" ] && [ -n "$n2" ] && [ $((n0 + n2)) = "$n1" ] && [ "${w2:-0}" -ge 24 ]; then
  ok "--tiles 0-1/2: each tile warns of its NaN pixels, the replay in its rows"
else bad "--tiles 0-1/2: each tile warns of its NaN pixels" "$(cat "$td/nan-t.err")"; fi
expect_msg 0 "ggrt render: warning: tile 1/2: the ray budget (2 rays per eye ray) left " \
  "a tile warns of the rays its ray budget left uncast" \
  "$ggrt" render examples/scenes/glass.nff -s 64x48 --ray-budget 2 -q --tile 1/2 -o "$td/budget.exr"

# ggrt --help's line for merge names both kinds of input
if "$ggrt" --help | grep -q "^ *merge .*tiles.*reports"; then ok "ggrt --help: merge joins tiles or reports"
else bad "ggrt --help: merge joins tiles or reports" "$("$ggrt" --help | grep merge)"; fi

# ---- bad input to merge: the tile, the reason, exit 2, nothing written ----
# merge_refuses NAME MESSAGE FILES...: exit 2, the exact message, and no
# output file (nor a temporary one) afterwards.
merge_refuses() {
  what=$1; msg=$2; shift 2
  rm -f "$td"/out.*
  expect_err 2 "$msg" "merge refuses $what" "$ggrt" merge "$@" -o "$td/out.png"
  if [ -z "$(ls "$td" | grep '^out\.')" ]; then ok "merge of $what writes nothing"
  else bad "merge of $what writes nothing" "$(ls "$td" | grep '^out')"; fi
}
g="$td/g"
merge_refuses "a missing tile" "ggrt merge: tile 4 of 7 (rows 27..33) is missing" \
  "$g-0.exr" "$g-1.exr" "$g-2.exr" "$g-3.exr" "$g-5.exr" "$g-6.exr"
cp "$g-3.exr" "$td/dup-3.exr"
merge_refuses "a duplicate" "ggrt merge: $td/dup-3.exr: tile 3 again (also in $g-3.exr)" \
  "$g"-[0-6].exr "$td/dup-3.exr"
merge_refuses "a tile given twice" "ggrt merge: $g-3.exr: given twice (tile 3)" \
  "$g"-[0-6].exr "$g-3.exr"
"$ggrt" render examples/scenes/glass.nff -s 80x48 -d 3 -q --tile 2/7 -o "$td/opt-2.exr"
merge_refuses "a tile of other options" \
  "ggrt merge: $td/opt-2.exr: different render options from $g-0.exr: 'depth=3', not 'depth=5'" \
  "$g-0.exr" "$g-1.exr" "$td/opt-2.exr" "$g-3.exr" "$g-4.exr" "$g-5.exr" "$g-6.exr"
# the ray budget is an option too (it was left out of the manifest once)
"$ggrt" render examples/scenes/glass.nff -s 80x48 --ray-budget 2 -q --tile 2/7 -o "$td/budget-2.exr" 2>/dev/null
merge_refuses "a tile of another ray budget" \
  "ggrt merge: $td/budget-2.exr: different render options from $g-0.exr: 'ray-budget=2', not 'ray-budget=1024'" \
  "$g-0.exr" "$g-1.exr" "$td/budget-2.exr" "$g-3.exr" "$g-4.exr" "$g-5.exr" "$g-6.exr"
# options that resolve to the same render are the same: -d 5, -n 1 and
# --ray-budget 1024 are glass.nff's depth, samples and budget anyway
"$ggrt" render examples/scenes/glass.nff -s 80x48 -d 5 -n 1 --ray-budget 1024 -q --tile 2/7 \
  -o "$td/same-2.exr" && "$ggrt" merge "$g-0.exr" "$g-1.exr" "$td/same-2.exr" "$g-3.exr" "$g-4.exr" \
  "$g-5.exr" "$g-6.exr" -q -o "$td/same.exr" 2>"$tmp/err" &&
  ok "merge takes a tile whose options are the defaults spelt out" ||
  bad "merge takes a tile whose options are the defaults spelt out" "$(cat "$tmp/err")"
sed 's/^l 3 -3 6$/l 3 -3 7/' examples/scenes/glass.nff >"$td/glass2.nff"
cmp -s "$td/glass2.nff" examples/scenes/glass.nff && bad "glass2.nff differs from glass.nff"
"$ggrt" render "$td/glass2.nff" -s 80x48 -q --tile 5/7 -o "$td/scene-5.exr"
h1=$(strings -n 8 "$g-0.exr" | sed -n 's/.*\(fnv1a64:[0-9a-f]*\).*/\1/p')
h2=$(strings -n 8 "$td/scene-5.exr" | sed -n 's/.*\(fnv1a64:[0-9a-f]*\).*/\1/p')
merge_refuses "a tile of another scene" \
  "ggrt merge: $td/scene-5.exr: different scene (hash) from $g-0.exr: '$h2', not '$h1'" \
  "$g-0.exr" "$g-1.exr" "$g-2.exr" "$g-3.exr" "$g-4.exr" "$td/scene-5.exr" "$g-6.exr"
"$ggrt" render examples/scenes/glass.nff -s 80x48 -q --tile 6/8 -o "$td/cut-6.exr"
merge_refuses "a tile of another cut" \
  "ggrt merge: $td/cut-6.exr: different cut from $g-0.exr: 'rows 8', not 'rows 7'" \
  "$g-0.exr" "$g-1.exr" "$g-2.exr" "$g-3.exr" "$g-4.exr" "$g-5.exr" "$td/cut-6.exr"
# Cut inside its pixels: the header reads, the pixels do not.
size=$(wc -c <"$g-1.exr")
head -c $((size - 100)) "$g-1.exr" >"$td/trunc-1.exr"
rm -f "$td"/out.*
expect_msg 2 "ggrt merge: $td/trunc-1.exr: invalid OpenEXR file: " "merge refuses a truncated tile" \
  "$ggrt" merge "$g-0.exr" "$td/trunc-1.exr" "$g"-[2-6].exr -o "$td/out.png"
if [ -z "$(ls "$td" | grep '^out\.')" ]; then ok "merge of a truncated tile writes nothing"
else bad "merge of a truncated tile writes nothing" "$(ls "$td")"; fi
"$ggrt" render examples/scenes/glass.nff -s 80x48 -q -o "$td/whole.exr"
merge_refuses "an EXR that is not a tile" \
  "ggrt merge: $td/whole.exr: not a ggrt tile: no ggrt.version attribute" "$td/whole.exr"

# ---- tiles and plans of another ggrt build, or of one before build ids ----
# ggBuildId (ggrt --version): a checksum of the library's sources, in the
# manifest beside the version. A tile of another build is made here by
# editing its manifest (the same length: the EXR's sizes hold); one of a
# ggrt before build ids has no ggrt.buildId (here renamed).
bid=$("$ggrt" --version | sed -n 's/^ggrt [0-9.]* (build \(src-[0-9]*\))$/\1/p')
if [ -n "$bid" ]; then ok "ggrt --version names the build ($bid)"
else bad "ggrt --version names the build" "$("$ggrt" --version)"; fi
obid=old-${bid#src-}
# exr_edit IN OUT OLD NEW: OUT is IN with the bytes OLD, found once, made NEW.
exr_edit() {
  python3 -c 'import sys
b = open(sys.argv[1], "rb").read()
o, n = sys.argv[3].encode(), sys.argv[4].encode()
assert len(o) == len(n) and b.count(o) == 1, "not once: %r" % o
open(sys.argv[2], "wb").write(b.replace(o, n))' "$@"
}
exr_edit "$g-3.exr" "$td/build-3.exr" "$bid" "$obid" || bad "edit the build id of a tile"
merge_refuses "a tile of another ggrt build" \
  "ggrt merge: $td/build-3.exr: different ggrt build from $g-0.exr: '$obid', not '$bid'" \
  "$g-0.exr" "$g-1.exr" "$g-2.exr" "$td/build-3.exr" "$g-4.exr" "$g-5.exr" "$g-6.exr"
exr_edit "$g-4.exr" "$td/older-4.exr" "ggrt.buildId" "ggrt.buildIX" || bad "rename the build id of a tile"
merge_refuses "a tile of a ggrt before build ids" \
  "ggrt merge: $td/older-4.exr: a tile of an older ggrt: no ggrt.buildId attribute (render it again with this one)" \
  "$g-0.exr" "$g-1.exr" "$g-2.exr" "$g-3.exr" "$td/older-4.exr" "$g-5.exr" "$g-6.exr"

# ---- plans: refused for another scene, other options or size, a bad file ----
"$ggrt" plan examples/scenes/glass.nff -s 80x48 -q --tiles 7 -o "$td/gl.json" 2>"$tmp/err" ||
  bad "plan of glass" "$(cat "$tmp/err")"
rm -f "$td"/x.exr
expect_err 2 "ggrt render: $td/gl.json is a plan for other render options: 'depth=5', not 'depth=3'" \
  "render refuses a plan for other options" \
  "$ggrt" render examples/scenes/glass.nff -s 80x48 -d 3 --plan "$td/gl.json" --tile 2 -o "$td/x.exr"
expect_err 2 "ggrt render: $td/gl.json is a plan for other render options: 'size=80x48', not 'size=80x40'" \
  "render refuses a plan for another size" \
  "$ggrt" render examples/scenes/glass.nff -s 80x40 --plan "$td/gl.json" --tile 2 -o "$td/x.exr"
expect_exit 0 "render takes a plan with the default depth spelt out (-d 5)" \
  "$ggrt" render examples/scenes/glass.nff -s 80x48 -d 5 -q --plan "$td/gl.json" --tile 2 -o "$td/x.exr"
rm -f "$td"/x.exr
expect_err 2 "ggrt render: $td/gl.json is a plan for another scene: its hash '$h1', not '$h2'" \
  "render refuses a plan for another scene" \
  "$ggrt" render "$td/glass2.nff" -s 80x48 --plan "$td/gl.json" --tile 2 -o "$td/x.exr"
if [ -e "$td/x.exr" ]; then bad "a refused plan writes no tile"; else ok "a refused plan writes no tile"; fi
sed "s/\"buildId\":\"$bid\"/\"buildId\":\"$obid\"/" "$td/gl.json" >"$td/build.json"
expect_err 2 "ggrt render: $td/build.json is a plan of another ggrt build: its '$obid', not '$bid' (ggrt --version)" \
  "render refuses a plan of another ggrt build" \
  "$ggrt" render examples/scenes/glass.nff -s 80x48 --plan "$td/build.json" --tile 2 -o "$td/x.exr"
sed 's/"buildId":"[^"]*",//' "$td/gl.json" >"$td/older.json"
expect_err 2 "ggrt render: $td/older.json: not a ggrt plan: no \"buildId\" (a plan of an older ggrt: make it again)" \
  "render refuses a plan of a ggrt before build ids" \
  "$ggrt" render examples/scenes/glass.nff -s 80x48 --plan "$td/older.json" --tile 2 -o "$td/x.exr"
expect_err 1 "ggrt render: $td/gl.json cuts 7 tiles, not 8: give --tile I (or I/7)" \
  "render refuses --tile I/N with a plan of other N" \
  "$ggrt" render examples/scenes/glass.nff -s 80x48 --plan "$td/gl.json" --tile 2/8 -o "$td/x.exr"
expect_err 1 "ggrt render: $td/gl.json: tile index '7' is not in 0..6" "a plan's tile index out of range" \
  "$ggrt" render examples/scenes/glass.nff -s 80x48 --plan "$td/gl.json" --tiles 5-7 -o "$td/x%d.exr"
expect_err 1 "ggrt render: --tile I and --tiles I,J need /N, the number of tiles, or --plan" \
  "--tile I without /N needs a plan" \
  "$ggrt" render examples/scenes/glass.nff --tile 2 -o "$td/x.exr"
expect_err 1 "ggrt render: --plan goes with --tile or --tiles" "--plan without --tile" \
  "$ggrt" render examples/scenes/glass.nff --plan "$td/gl.json" -o "$td/x.exr"
expect_err 3 "ggrt render: the plan $td/none.json: No such file or directory" "a missing plan file" \
  "$ggrt" render examples/scenes/glass.nff -s 80x48 --plan "$td/none.json" --tile 2 -o "$td/x.exr"
# a plan is JSON: one written under an image's name was taken (exit 0)
expect_err 1 "ggrt plan: a plan is JSON, not an image: '$td/p.png'" "plan -o p.png is refused" \
  "$ggrt" plan examples/scenes/glass.nff -s 80x48 -q --tiles 3 -o "$td/p.png"
[ ! -e "$td/p.png" ] && ok "plan -o p.png writes nothing" || bad "plan -o p.png writes nothing"
mkdir -p "$td/dir.json"
expect_err 3 "ggrt render: the plan $td/dir.json: not a regular file" "a folder as the plan" \
  "$ggrt" render examples/scenes/glass.nff -s 80x48 --plan "$td/dir.json" --tile 2 -o "$td/x.exr"
{ cat "$td/gl.json"; head -c 1048576 /dev/zero | tr '\0' ' '; } >"$td/big.json"
expect_err 2 "ggrt render: $td/big.json: not a ggrt plan: larger than 1 MiB" "a plan over 1 MiB" \
  "$ggrt" render examples/scenes/glass.nff -s 80x48 --plan "$td/big.json" --tile 2 -o "$td/x.exr"
printf '{"ggrt_plan":1}\n' >"$td/bad.json"
expect_err 2 "ggrt render: $td/bad.json: not a ggrt plan: no \"sceneHash\"" "a plan file without a hash" \
  "$ggrt" render examples/scenes/glass.nff -s 80x48 --plan "$td/bad.json" --tile 2 -o "$td/x.exr"
# a \u escape cut off by the end of the file
printf '{"ggrt_plan":1,"options":"\\u12' >"$td/bad.json"
expect_err 2 "ggrt render: $td/bad.json: not a ggrt plan: a \\u escape without 4 hex digits at byte 27" \
  "a plan that ends inside an escape" \
  "$ggrt" render examples/scenes/glass.nff -s 80x48 --plan "$td/bad.json" --tile 2 -o "$td/x.exr"
# plans are read with merge --reports' JSON grammar: no hex numbers; escapes
# are decoded ("size\u003d80x48" is the plan's own options)
sed 's/"size":\[80,/"size":[0x50,/' "$td/gl.json" >"$td/bad.json"
at=$(grep -bo '"size":\[0x' "$td/bad.json" | cut -d: -f1)
at=$((at + 9))
expect_err 2 "ggrt render: $td/bad.json: not a ggrt plan: expected ',' or ']' at byte $at" \
  "a plan with a hex number" \
  "$ggrt" render examples/scenes/glass.nff -s 80x48 --plan "$td/bad.json" --tile 2 -o "$td/x.exr"
sed 's/"options":"size=80x48 /"options":"size\\u003d80x48 /' "$td/gl.json" >"$td/esc.json"
if grep -qF 'size\u003d' "$td/esc.json" &&
   "$ggrt" render examples/scenes/glass.nff -s 80x48 -q --plan "$td/esc.json" --tile 2 -o "$td/esc.exr"; then
  ok "a plan's escaped options read as the text they stand for"
else bad "a plan's escaped options read as the text they stand for" "$(grep options "$td/esc.json")"; fi
sed 's/^"rows":\[.*\]/"rows":[0,10,20,30,40,45,47,50]/' "$td/gl.json" >"$td/bad.json"
expect_err 2 "ggrt render: $td/bad.json: not a ggrt plan: its row 7 is not a boundary of rows 0..48" \
  "a plan whose rows pass the image" \
  "$ggrt" render examples/scenes/glass.nff -s 80x48 --plan "$td/bad.json" --tile 2 -o "$td/x.exr"
expect_err 1 "ggrt plan: 49 tiles of 48 rows: at most one tile per row" "plan: more tiles than rows" \
  "$ggrt" plan examples/scenes/glass.nff -s 80x48 --tiles 49 -o "$td/x.json"
# A plan's tile among equal bands' tiles: another cut.
"$ggrt" render examples/scenes/glass.nff -s 80x48 -q --plan "$td/gl.json" --tile 5 -o "$td/pl-5.exr"
pcut=$(sed -n 's/^"rows":\[\(.*\)\],*$/plan \1/p' "$td/gl.json")
merge_refuses "a plan's tile among equal bands" \
  "ggrt merge: $td/pl-5.exr: different cut from $g-0.exr: '$pcut', not 'rows 7'" \
  "$g-0.exr" "$g-1.exr" "$g-2.exr" "$g-3.exr" "$g-4.exr" "$td/pl-5.exr" "$g-6.exr"

# ---- examples/cluster/xargs.sh as pasted: equal bands and a plan ----
"$ggrt" render examples/scenes/spd/gears.nff --spd -s 96x64 -q -o "$td/x-one.png" 2>/dev/null
for plan in 0 1; do
  PLAN=$plan P=2 PARTS="$td/x$plan.parts" GGRT=$ggrt sh examples/cluster/xargs.sh \
    examples/scenes/spd/gears.nff 5 "$td/x$plan.png" --spd -s 96x64 >"$tmp/out" 2>"$tmp/err"
  what="equal bands"; cut="rows 5"
  if [ $plan = 1 ]; then
    what="a plan's cut ($(grep -o '"rows":\[[0-9,]*\]' "$td/x1.parts/plan.json" 2>/dev/null))"
    cut="plan $(sed -n 's/^"rows":\[\(.*\)\],*$/\1/p' "$td/x1.parts/plan.json" 2>/dev/null)"
  fi
  # (the tile's manifest records its cut; strings runs it into the next name)
  if [ -s "$td/x-one.png" ] && cmp -s "$td/x$plan.png" "$td/x-one.png" &&
     strings -n 6 "$td/x$plan.parts/part-3.exr" | grep -q "^$cut\([^0-9,].*\)*\$"; then
    ok "examples/cluster/xargs.sh: 5 tiles in $what merge into one process's PNG"
  else bad "examples/cluster/xargs.sh, PLAN=$plan" "$(cat "$tmp/out" "$tmp/err")"; fi
done
# a scene, OUT and PARTS with spaces in their names, and a plan (whose
# path is one argument of each tile's render)
cp examples/scenes/spd/gears.nff "$td/my gears.nff"
PLAN=1 P=2 GGRT=$ggrt sh examples/cluster/xargs.sh "$td/my gears.nff" 5 "$td/out y.png" \
  --spd -s 96x64 >"$tmp/out" 2>"$tmp/err"
if [ -s "$td/x-one.png" ] && cmp -s "$td/out y.png" "$td/x-one.png" && [ -s "$td/out y.png.parts/plan.json" ]
then ok "examples/cluster/xargs.sh: PLAN=1 with spaces in the scene's, OUT's and PARTS' names"
else bad "examples/cluster/xargs.sh: PLAN=1 with spaces in the names" "$(cat "$tmp/out" "$tmp/err")"; fi

# ---- examples/cluster/parallel.sh on this machine (HOSTS=:) ----
if command -v parallel >/dev/null 2>&1; then
  case $ggrt in /*) ag=$ggrt ;; *) ag=$PWD/$ggrt ;; esac
  # GGRT with a space in its path: parallel runs the command quoted
  mkdir -p "$td/g g"; ln -sf "$ag" "$td/g g/ggrt"
  "$ggrt" render examples/scenes/glass.nff -s 64x48 -q -o "$td/pg-one.png"
  HOSTS=: PARTS="$td/pg.parts" GGRT="$td/g g/ggrt" sh examples/cluster/parallel.sh \
    examples/scenes/glass.nff 3 "$td/pg.png" -s 64x48 >"$tmp/out" 2>"$tmp/err"
  if cmp -s "$td/pg.png" "$td/pg-one.png"; then ok "examples/cluster/parallel.sh: GGRT with a space in its path"
  else bad "examples/cluster/parallel.sh: GGRT with a space in its path" "$(cat "$tmp/out" "$tmp/err")"; fi
  # the scene read where it is: a texture beside it (run from its folder),
  # an OBJ model (read by its extension)
  "$ggrt" render examples/scenes/texture.nff -s 64x48 -q -o "$td/pt-one.png"
  (cd examples/scenes && HOSTS=: PARTS="$td/pt.parts" GGRT=$ag sh ../cluster/parallel.sh \
    texture.nff 4 "$td/pt.png" -s 64x48) >"$tmp/out" 2>"$tmp/err"
  if cmp -s "$td/pt.png" "$td/pt-one.png"; then ok "examples/cluster/parallel.sh: a scene with a texture beside it"
  else bad "examples/cluster/parallel.sh: a scene with a texture beside it" "$(cat "$tmp/out" "$tmp/err")"; fi
  "$ggrt" render examples/scenes/models/knot.obj -s 64x48 -q -o "$td/pk-one.png" 2>/dev/null
  HOSTS=: PARTS="$td/pk.parts" GGRT=$ag sh examples/cluster/parallel.sh \
    examples/scenes/models/knot.obj 3 "$td/pk.png" -s 64x48 >"$tmp/out" 2>"$tmp/err"
  if cmp -s "$td/pk.png" "$td/pk-one.png"; then ok "examples/cluster/parallel.sh: an OBJ model"
  else bad "examples/cluster/parallel.sh: an OBJ model" "$(cat "$tmp/out" "$tmp/err")"; fi
else
  skip "examples/cluster/parallel.sh" "no GNU parallel (scripts/deps.sh cluster)"
fi
