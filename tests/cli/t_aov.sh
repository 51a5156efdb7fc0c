# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: path layers (render --aov, check --aov-sum).
# Uses run.sh's ggrt, tmp, ok, bad, expect_exit.
#
# The four layers below are disjoint and exhaustive (docs/debugging.md,
# "Path layers"): every path is C, then scattering events S (each <RS>,
# <RS'tir'> or <TS>), then one ending, <RD>L, <RD>A, <RG>L, O or B.
# direct: no S and not B; bg: no S and B; mirror: one S or more, all <RS>;
# glass: at least one <TS>.
aov_d='direct=C(<RD>[LA]|<RG>L|O)'
aov_m='mirror=C<RS>+(<RD>[LA]|<RG>L|O|B)'
aov_g='glass=C<RS>*<TS>[<RS><TS>]*(<RD>[LA]|<RG>L|O|B)'
aov_b='bg=CB'
g=examples/scenes/glass.nff

# mistakes: the column within the --aov argument, a caret under it
"$ggrt" render $g -s 24x18 -o "$tmp/l.exr" --aov "$aov_d" --aov 'x=C<X>' >"$tmp/out" 2>"$tmp/err"; rc=$?
if [ $rc = 1 ] && grep -qxF "ggrt render: --aov:1:5: 'X' is not an event type (C R T L O B A or .)" "$tmp/err" &&
   grep -qx '      ^' "$tmp/err"; then ok "render --aov: a mistake names its column in the argument"
else bad "render --aov: a mistake names its column (exit $rc)" "$(cat "$tmp/err")"; fi
"$ggrt" render $g -s 24x18 -o "$tmp/l.exr" --aov 'g=C.*<TS>[object == 1].*' >"$tmp/out" 2>"$tmp/err"; rc=$?
if [ $rc = 1 ] && grep -qF "ggrt render: --aov:1:10: a path layer takes no predicate" "$tmp/err"
then ok "render --aov: a predicate is refused at its column"
else bad "render --aov: a predicate is refused at its column (exit $rc)" "$(cat "$tmp/err")"; fi
expect_exit 1 "render --aov without NAME=" "$ggrt" render $g -o "$tmp/l.exr" --aov 'C.*'
expect_exit 1 "render --aov: a name twice" "$ggrt" render $g -o "$tmp/l.exr" --aov 'a=CB' --aov 'a=C.*'
expect_exit 1 "render --aov into a PNG without --aov-png" "$ggrt" render $g -o "$tmp/l.png" --aov 'a=CB'
expect_exit 1 "render --aov-png without --aov" "$ggrt" render $g -o "$tmp/l.png" --aov-png "$tmp/d"
expect_exit 1 "render --aov with --heatmap" "$ggrt" render $g -o "$tmp/l.exr" --aov 'a=CB' --heatmap rays
# --aov-png DIR is checked before the render, as -o is: a refusal writes
# nothing, -o included
mkdir -p "$tmp/ap"; printf 'x\n' > "$tmp/ap/file"; printf 'old\n' > "$tmp/ap/t.png"
expect_err 3 "ggrt render: cannot write '$tmp/ap/missing/sub': $tmp/ap/missing: No such file or directory" \
  "render --aov-png: a missing parent is refused first" \
  "$ggrt" render $g -s 8x6 -q -o "$tmp/ap/o.exr" --aov 'a=CB' --aov-png "$tmp/ap/missing/sub"
expect_err 3 "ggrt render: refusing to write into '$tmp/ap/file' (--aov-png DIR): it is not a directory" \
  "render --aov-png: a file as DIR is refused" \
  "$ggrt" render $g -s 8x6 -q -o "$tmp/ap/o.exr" --aov 'a=CB' --aov-png "$tmp/ap/file"
mkdir "$tmp/ap/d"; ln -s ../t.png "$tmp/ap/d/a.png"
expect_err 3 "ggrt render: refusing to write '$tmp/ap/d/a.png': it is a symbolic link, which ggrt would replace by a file (give the path of the file it points to)" \
  "render --aov-png: a symbolic link at DIR/NAME.png is refused" \
  "$ggrt" render $g -s 8x6 -q -o "$tmp/ap/o.exr" --aov 'a=CB' --aov-png "$tmp/ap/d"
if [ ! -e "$tmp/ap/o.exr" ] && [ ! -e "$tmp/ap/missing" ] && [ -L "$tmp/ap/d/a.png" ] &&
   [ "$(cat "$tmp/ap/t.png")" = old ]; then ok "render --aov-png: the refusals wrote nothing"
else bad "render --aov-png: the refusals wrote nothing" "$(ls -lR "$tmp/ap")"; fi
expect_exit 0 "render --aov-png: a missing DIR is created" \
  "$ggrt" render $g -s 8x6 -q -o "$tmp/ap/o.exr" --aov 'a=CB' --aov-png "$tmp/ap/new"
[ -s "$tmp/ap/new/a.png" ] && ok "render --aov-png: DIR/a.png written" || bad "render --aov-png: DIR/a.png written"
# Written whole or not at all, -o and the layers together: a file size
# limit (SIGXFSZ ignored, so write fails with EFBIG) that a layer PNG
# passes and the EXR does not, and one that the first PNG fails. Either
# way -o keeps its old bytes and DIR gets no layer and no temporary file.
for lim in "bg=CB 8" "all=C.* 1"; do
  rm -rf "$tmp/ax"; mkdir -p "$tmp/ax"; printf 'old\n' >"$tmp/ax/o.exr"
  ( trap '' XFSZ; ulimit -f ${lim#* }; "$ggrt" render $g -s 200x150 -q -o "$tmp/ax/o.exr" \
      --aov "${lim% *}" --aov-png "$tmp/ax/d" ) 2>"$tmp/err"; got=$?
  if [ $got = 3 ] && [ "$(cat "$tmp/ax/o.exr")" = old ] && [ -z "$(ls -A "$tmp/ax/d" 2>/dev/null)" ] &&
     ! grep -q '\.tmp' "$tmp/err"
  then ok "render --aov-png, write fails ($lim): nothing written, -o kept, the file named"
  else bad "render --aov-png, write fails ($lim): nothing written, -o kept (exit $got)" \
    "$(cat "$tmp/err"; ls -lA "$tmp/ax" "$tmp/ax/d")"; fi
done
# An EXR whose header cannot be written (512 bytes allowed, sh's unit:
# the layer attributes take more) fails at once. The core reported the
# error with its context locked and the library's handler locked it
# again: a hang that not even SIGTERM ended (ggrt catches it to cancel),
# hence KILL.
rm -f "$tmp/ax/h.exr"
( trap '' XFSZ; ulimit -f 1; timeout -s KILL 30 "$ggrt" render $g -s 16x12 -q -o "$tmp/ax/h.exr" \
    --aov 'all=C.*' ) 2>"$tmp/err"; got=$?
if [ $got = 3 ] && grep -q "^ggrt render: .*h.exr: .*File too large" "$tmp/err" &&
   [ -z "$(ls "$tmp/ax" | grep '^h\.exr')" ]
then ok "render to an EXR whose header cannot be written: exit 3, no hang"
else bad "render to an EXR whose header cannot be written: exit 3, no hang (exit $got)" "$(cat "$tmp/err")"; fi
# Memory: what the layers take is allocated before the render, once. Under
# 192 MiB of address space, 16 layers of 768x768 (108 MiB) render and are
# written: they used to be copied into images for writing, twice the
# memory, and failed after the render ("out of memory for the path
# layers", exit 2, at least 245 MiB needed). 16 layers of 2048x2048 fail
# at once, saying what they need: no render, no summary, no file. Not
# under ASan, whose shadow memory cannot run under the ulimit.
case $ggrt in
*/asan/*) ;;
*)
  printf 'v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 64 64\nl 1 1 5\nf 1 0 0 1 0 0 0 0\ns 0 0 0 1\n' \
    >"$tmp/sph.nff"
  set --; k=1
  while [ $k -le 16 ]; do set -- "$@" --aov "l$k=C.*"; k=$((k + 1)); done
  rm -f "$tmp/m.exr"
  ( ulimit -v 196608; "$ggrt" render "$tmp/sph.nff" -s 768x768 -j 2 -q -o "$tmp/m.exr" "$@" ) 2>"$tmp/err"; got=$?
  if [ $got = 0 ] && [ -s "$tmp/m.exr" ] && [ ! -s "$tmp/err" ]
  then ok "render --aov: 16 layers of 768x768 are written under 192 MiB (held once)"
  else bad "render --aov: 16 layers of 768x768 are written under 192 MiB (exit $got)" "$(cat "$tmp/err")"; fi
  for png in "" "--aov-png"; do
    rm -rf "$tmp/m.exr" "$tmp/mp"
    ( ulimit -v 196608; "$ggrt" render "$tmp/sph.nff" -s 2048x2048 -j 2 -o "$tmp/m.exr" "$@" \
        ${png:+$png "$tmp/mp"} ) >"$tmp/out" 2>"$tmp/err"; got=$?
    want="ggrt render: out of memory for the path layers: 16 layers of 2048x2048 need 768 MiB"
    [ -n "$png" ] && want="${want%768 MiB}816 MiB with --aov-png's conversion"
    if [ $got = 2 ] && [ "$(cat "$tmp/err")" = "$want" ] && [ ! -s "$tmp/out" ] &&
       [ ! -e "$tmp/m.exr" ] && [ ! -e "$tmp/mp" ]
    then ok "render --aov${png:+ $png}: layers that cannot fit fail before the render, with their need"
    else bad "render --aov${png:+ $png}: layers that cannot fit fail before the render (exit $got)" \
      "want: $want
got:  $(cat "$tmp/err" "$tmp/out")"; fi
  done
  set --
  ;;
esac
"$ggrt" render $g -s 24x18 -q -o "$tmp/plain.exr"
expect_exit 2 "check --aov-sum: a file without layers" "$ggrt" check --aov-sum "$tmp/plain.exr"
expect_exit 1 "check --aov-sum with --path" "$ggrt" check --aov-sum "$tmp/plain.exr" --path 'C.*'
expect_exit 1 "check without a scene or --aov-sum" "$ggrt" check
# a SCENE named is read before the layers are compared: a missing one
# passed when the layers added up (exit 0)
"$ggrt" render $g -s 16x12 -q --aov 'all=C.*' -o "$tmp/sum1.exr"
expect_msg 3 "ggrt check: $tmp/missing.nff: No such file or directory" \
  "check --aov-sum with a missing SCENE: exit 3 though the layers add up" \
  "$ggrt" check --aov-sum "$tmp/sum1.exr" "$tmp/missing.nff"

# the image is the render's without layers; --aov-png writes a PNG a layer
"$ggrt" render $g -s 48x36 -q -o "$tmp/a.png" --aov "$aov_d" --aov "$aov_m" --aov "$aov_g" \
  --aov "$aov_b" --aov-png "$tmp/aovpng" 2>"$tmp/err"
"$ggrt" render $g -s 48x36 -q -o "$tmp/b.png" 2>>"$tmp/err"
if cmp -s "$tmp/a.png" "$tmp/b.png" && [ -s "$tmp/aovpng/direct.png" ] && [ -s "$tmp/aovpng/mirror.png" ] &&
   [ -s "$tmp/aovpng/glass.png" ] && [ -s "$tmp/aovpng/bg.png" ]; then
  ok "render --aov: the image is unchanged, --aov-png writes one PNG a layer"
else bad "render --aov: the image is unchanged, --aov-png writes one PNG a layer" "$(ls "$tmp/aovpng"; cat "$tmp/err")"; fi

# every example, model, SPD and test-data scene: the four layers add up;
# leaving one out fails and names the missing share and a path (on one
# scene in $sample: GG_TEST_SAMPLE, run.sh)
scene_k=0
for s in examples/scenes/*.nff examples/scenes/models/*.obj examples/scenes/models/*.ply \
         examples/scenes/spd/*.nff tests/data/*.nff tests/data/debug/*.nff; do
  "$ggrt" render "$s" -s 32x24 -q -o "$tmp/l4.exr" --aov "$aov_d" --aov "$aov_m" --aov "$aov_g" \
    --aov "$aov_b" 2>"$tmp/err"
  "$ggrt" check --aov-sum "$tmp/l4.exr" >"$tmp/c4" 2>>"$tmp/err"; rc=$?
  if [ $rc = 0 ] && grep -q '^ok: the layers add up to the image' "$tmp/c4"; then
    ok "check --aov-sum: four disjoint exhaustive layers add up on $s"
  else bad "check --aov-sum: four layers add up on $s (exit $rc)" "$(cat "$tmp/c4" "$tmp/err")"; fi
  scene_k=$((scene_k + 1))
  [ $((scene_k % sample)) = 1 ] || [ "$sample" = 1 ] || continue
  failed=""; wrong=""
  for drop in direct mirror glass bg; do
    set --
    for l in "$aov_d" "$aov_m" "$aov_g" "$aov_b"; do
      case $l in "$drop="*) ;; *) set -- "$@" --aov "$l" ;; esac
    done
    "$ggrt" render "$s" -s 32x24 -q -o "$tmp/l3.exr" "$@" 2>/dev/null
    "$ggrt" check --aov-sum "$tmp/l3.exr" >"$tmp/c3" 2>&1; rc=$?
    if [ $rc = 4 ]; then
      if grep -qE '^gap: +[1-9][0-9]* pixels, [0-9.e+-]+% of the image' "$tmp/c3" &&
         grep -q '^  a path no layer matches: C' "$tmp/c3" && grep -qE '^overlap: +0 pixels' "$tmp/c3"
      then failed="$failed $drop"; else wrong="$wrong $drop"; fi
    elif [ $rc != 0 ]; then wrong="$wrong $drop(exit $rc)"; fi
  done
  if [ -n "$failed" ] && [ -z "$wrong" ]; then
    ok "check --aov-sum: $s without one layer fails and names the gap (without:$failed)"
  else bad "check --aov-sum: $s without one layer fails and names the gap" "failed:$failed wrong:$wrong
$(cat "$tmp/c3")"; fi
done

# an overlap is told apart from a gap, with the two layers that claim it
"$ggrt" render $g -s 32x24 -q -o "$tmp/o.exr" --aov "$aov_d" --aov "$aov_m" --aov "$aov_g" \
  --aov "$aov_b" --aov 'twice=C<RD>L' 2>/dev/null
"$ggrt" check --aov-sum "$tmp/o.exr" >"$tmp/co" 2>&1; rc=$?
if [ $rc = 4 ] && grep -qE '^gap: +0 pixels' "$tmp/co" && grep -qE '^overlap: +[1-9]' "$tmp/co" &&
   grep -qE "^  a path two layers match: C<RD'[0-9]+'><L.'[0-9]+'>, .* \[direct\] \[twice\]" "$tmp/co"
then ok "check --aov-sum: an overlap, with the path and the two layers"
else bad "check --aov-sum: an overlap, with the path and the two layers (exit $rc)" "$(cat "$tmp/co")"; fi

# the layers against an independent matcher over the trace JSON
bulk python3 tests/cli/aov_check.py "$ggrt" $g 24x18 8,6,16,12 "$aov_d" "$aov_m" "$aov_g" "$aov_b" \
  "tir=C.*<RS'tir'>.*" "obj1=C<.S'1'>+.*" >"$tmp/ac" 2>&1
case $(cat "$tmp/ac") in
  "ok   "*) ok "aov: $(sed 's/^ok   //' "$tmp/ac")" ;;
  *) bad "aov: layers against the independent matcher" "$(cat "$tmp/ac")" ;;
esac

# find --path without predicates is answered by the layer copy: the same
# document as the recorder's (an always-true predicate forces it) on every
# example, model, SPD and test-data scene
bulk python3 tests/cli/find_layers_check.py "$ggrt" examples/scenes/*.nff examples/scenes/models/*.obj \
  examples/scenes/models/*.ply examples/scenes/spd/*.nff tests/data/*.nff tests/data/debug/*.nff \
  >"$tmp/fl" 2>&1
while IFS= read -r line; do
  case "$line" in
    "ok   "*) ok "${line#ok   }" ;;
    "FAIL "*) bad "${line#FAIL }" ;;
    *) bad "find_layers_check.py: $line" ;;
  esac
done < "$tmp/fl"
grep -q '^ok' "$tmp/fl" || bad "find_layers_check.py ran" "$(cat "$tmp/fl")"
