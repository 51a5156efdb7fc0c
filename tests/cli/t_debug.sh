# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: ggrt find, check, diff and trace --ledger /
# --diff (the image-level debugger). Uses run.sh's ggrt, tmp, ok, bad.

for c in find check diff; do
  "$ggrt" $c --help >"$tmp/out" 2>&1 && grep -q "^usage: ggrt $c" "$tmp/out" &&
    ok "ggrt $c --help" || bad "ggrt $c --help" "$(cat "$tmp/out")"
done

g=examples/scenes/glass.nff
# An image output the writer would refuse (not .png or .exr) is a usage
# error at parse time, as render -o a.jpg is, not exit 2 after the scan.
for o in "find $g -w some(kind==tir) -o $tmp/x.jpg:the output must end in .png or .exr: '$tmp/x.jpg'" \
         "find $g -w some(kind==tir) --overlay $tmp/x.txt:--overlay must end in .png or .exr: '$tmp/x.txt'" \
         "diff $g --b depth=2 -o $tmp/x.jpg:the output must end in .png or .exr: '$tmp/x.jpg'"; do
  c=${o%%:*}
  # shellcheck disable=SC2086
  expect_err 1 "ggrt ${c%% *}: ${o#*:}" "${c%% *}: an unknown image extension is refused before the scan" \
    "$ggrt" $c -s 16x12 -q
done
[ ! -e "$tmp/x.jpg" ] && [ ! -e "$tmp/x.txt" ] && ok "find, diff: nothing written for a refused extension" ||
  bad "find, diff: nothing written for a refused extension"
# diff compares one window for both sides: crop= in --a or --b was
# silently ignored (b) or blackened b around it (a).
for side in a b; do
  expect_err 1 "ggrt diff: --$side: crop= is the window of both sides: give it as --crop" \
    "diff --$side crop=... is refused" "$ggrt" diff $g -s 16x12 -q --$side crop=0,0,4,4
done

# find: the TIR region of glass.nff holds pixel 110,100; the listed replay
# command, pasted, gives the listed value; the mask is written.
"$ggrt" find $g --where 'some(kind == tir)' --limit 0 -o "$tmp/tir.png" -q >"$tmp/find" 2>"$tmp/err"
line=$(grep -E '^ +110,100 ' "$tmp/find")
if [ -n "$line" ] && [ -s "$tmp/tir.png" ] && head -1 "$tmp/find" | grep -q "pixels match some(kind == tir)"; then
  ok "find: glass.nff's TIR region lists 110,100 and writes the mask"
else bad "find: glass.nff's TIR region lists 110,100 and writes the mask" "$(head -3 "$tmp/find"; cat "$tmp/err")"; fi
cmd=$(echo "$line" | sed 's/.*   ggrt /ggrt /; s/^ggrt //')
want=$(echo "$line" | awk '{print $2, $3, $4}')
got=$(eval "\"\$ggrt\" $cmd" | sed -n 's/^colour //p' | awk '{printf "%.6g %.6g %.6g", $1, $2, $3}')
[ "$got" = "$want" ] && ok "find: the listed replay command gives the listed value" ||
  bad "find: the listed replay command gives the listed value" "want '$want' got '$got' from: $cmd"

# JSON: the count, and every match listed with --limit 0
"$ggrt" find $g -s 60x45 --where 'some(kind == refract && depth >= 3)' --limit 0 -f json >"$tmp/f.json" 2>"$tmp/err"
if python3 -c "
import json, sys
d = json.load(open(sys.argv[1]))
assert d['ggrt_find'] == 1 and d['traced'] is True
assert d['matched'] == len(d['matches']) > 0, (d['matched'], len(d['matches']))
assert d['scanned'] == 60 * 45 and d['size'] == [60, 45]
" "$tmp/f.json" 2>"$tmp/py"; then ok "find --format json: count and matches"
else bad "find --format json: count and matches" "$(cat "$tmp/py" "$tmp/err")"; fi

# a mistake in the predicate: exit 1, its column, a caret under it
"$ggrt" find $g --where 'some(kind == tri)' >"$tmp/out" 2>"$tmp/err"; rc=$?
if [ $rc = 1 ] && grep -qF "ggrt find: --where:1:14: 'tri' is not a kind (eye, reflect, refract, tir, shadow)" "$tmp/err" &&
   grep -qx '               ^' "$tmp/err"; then ok "find: a bad predicate names its column"
else bad "find: a bad predicate names its column (exit $rc)" "$(cat "$tmp/err")"; fi

# check: the planted defects fail (exit 4) with the invariant named; a clean scene passes
for p in energy:energy overflow:nonfinite nan:nonfinite cut:truncation; do
  f=${p%%:*}; inv=${p#*:}
  "$ggrt" check tests/data/debug/$f.nff -q >"$tmp/out" 2>"$tmp/err"; rc=$?
  if [ $rc = 4 ] && grep -q "^FAIL: 1 error-class invariant failed: $inv$" "$tmp/out"; then
    ok "check: planted $f.nff fails $inv (exit 4)"
  else bad "check: planted $f.nff fails $inv (exit $rc)" "$(cat "$tmp/out" "$tmp/err")"; fi
done
"$ggrt" trace tests/data/debug/nan.nff --pixel 20,15 | grep -q "^colour -*nan inf inf$" &&
  ok "check: nan.nff's pixel 20,15 is a NaN (0 * infinity in red)" ||
  bad "check: nan.nff's pixel 20,15 is a NaN" "$("$ggrt" trace tests/data/debug/nan.nff --pixel 20,15 | head -3)"
"$ggrt" check tests/data/debug/energy.nff -q | grep -q "material 1 (tests/data/debug/energy.nff:14): kd \* colour + ks + kt = 1.1" &&
  ok "check: the energy defect names the material's line" || bad "check: the energy defect names the material's line"
"$ggrt" check examples/scenes/default.nff -s 64x48 -q >"$tmp/out" 2>&1 && grep -q "^ok: no error-class" "$tmp/out" &&
  ok "check: a clean scene passes (exit 0)" || bad "check: a clean scene passes" "$(cat "$tmp/out")"
"$ggrt" check tests/data/debug/cut.nff -q -d 40 >/dev/null 2>&1 && ok "check: the cut scene passes at depth 40" ||
  bad "check: the cut scene passes at depth 40"
"$ggrt" check tests/data/debug/energy.nff -q --severity energy=warning >/dev/null 2>&1 &&
  ok "check: --severity energy=warning lets it pass" || bad "check: --severity energy=warning lets it pass"
"$ggrt" check tests/data/debug/cut.nff -f json >"$tmp/c.json" 2>/dev/null
if python3 -c "
import json, sys
d = json.load(open(sys.argv[1]))
inv = {i['name']: i for i in d['invariants']}
assert len(inv) == 7 and d['failed'] == 1
t = inv['truncation']
assert t['severity'] == 'error' and t['pixels'] > 0 and t['worst_pixels'][0]['value'] == t['worst']
" "$tmp/c.json" 2>"$tmp/py"; then ok "check --format json"; else bad "check --format json" "$(cat "$tmp/py")"; fi

# diff: nothing for identical settings; the textbook sphere's divergences on acc-distant.nff
"$ggrt" diff $g -s 64x48 -q >"$tmp/out" 2>&1
grep -q "values differ: *0 pixels" "$tmp/out" && grep -q "ray trees differ: *0 pixels" "$tmp/out" &&
  ok "diff: identical settings differ nowhere" || bad "diff: identical settings differ nowhere" "$(cat "$tmp/out")"
grep -qxF "ggrt diff: warning: both sides render with the same options ('size=64x48'), so nothing can differ: --a and --b set one side each; -a (--accuracy) sets both" "$tmp/out" &&
  ok "diff: one scene and the same options on both sides is said to differ nowhere" ||
  bad "diff: the same options on both sides are warned about" "$(cat "$tmp/out")"
a=examples/scenes/acc-distant.nff
# -a is --accuracy, on both sides: with --b the same knob, nothing differs
"$ggrt" diff $a -s 32x24 -q -a sphere=textbook --b sphere=textbook >"$tmp/out" 2>"$tmp/err"
grep -qF "warning: both sides render with the same options ('size=32x24 sphere=textbook')" "$tmp/err" &&
  ok "diff -a K --b K: the same options on both sides, warned" ||
  bad "diff -a K --b K: the same options on both sides, warned" "$(cat "$tmp/err")"
"$ggrt" trace $a -s 32x24 --pixel 3,3 --diff -a sphere=textbook >"$tmp/out" 2>"$tmp/err"
grep -qF "ggrt trace: warning: both sides render with the same options" "$tmp/err" &&
  ok "trace --diff -a K: the same options on both sides, warned" ||
  bad "trace --diff -a K: the same options on both sides, warned" "$(cat "$tmp/err")"
"$ggrt" diff $a -s 32x24 -q --b sphere=textbook >"$tmp/out" 2>"$tmp/err"
[ ! -s "$tmp/err" ] && ok "diff --b K: no warning when the sides differ" ||
  bad "diff --b K: no warning when the sides differ" "$(cat "$tmp/err")"
expect_err 1 "ggrt diff: unknown option '-b'; did you mean '--b'?" "diff -b names --b" \
  "$ggrt" diff $a -b depth=2
expect_err 1 "ggrt diff: --b:1:1: unknown setting '-d': settings are NAME=VALUE (depth=8, size=64x48), not options" \
  "diff --b '-d 8': settings are not options" "$ggrt" diff $a --b "-d 8"
"$ggrt" diff $a -s 32x24 -q --b sphere=textbook --path 'C.*' --limit 0 -f json >"$tmp/l0.json" 2>"$tmp/err"
if python3 -c "
import json, sys
d = json.load(open(sys.argv[1]))
assert d['moved'] > 2 and len(d['moves']) == d['moved'], (d['moved'], len(d['moves']))
" "$tmp/l0.json" 2>"$tmp/py"; then ok "diff --limit 0 lists every pixel, as find's does"
else bad "diff --limit 0 lists every pixel" "$(cat "$tmp/py" "$tmp/err")"; fi
"$ggrt" diff $a --a '' --b 'sphere=textbook' -o "$tmp/map.png" --worst 3 -q >"$tmp/out" 2>"$tmp/err"
if grep -q "ray trees differ: *[1-9][0-9]* pixels.*first divergence: hit [1-9]" "$tmp/out" &&
   grep -q "first divergence: ray #0 (eye): a hits object #[0-9]*, b" "$tmp/out" && [ -s "$tmp/map.png" ]; then
  ok "diff: the textbook sphere loses hits on acc-distant.nff"
else bad "diff: the textbook sphere loses hits on acc-distant.nff" "$(cat "$tmp/out" "$tmp/err")"; fi
cmd=$(grep -m1 "ggrt trace .* --diff" "$tmp/out" | sed 's/^ *ggrt //')
eval "\"\$ggrt\" $cmd" >"$tmp/td" 2>&1 && grep -q "^>> eye #0" "$tmp/td" &&
  ok "diff: its replay command shows both trees, the eye ray marked" ||
  bad "diff: its replay command shows both trees, the eye ray marked" "$cmd
$(cat "$tmp/td")"
"$ggrt" diff $a --b 'sphere=textbook' -s 80x60 -f json >"$tmp/d.json" 2>/dev/null
if python3 -c "
import json, sys
d = json.load(open(sys.argv[1]))
assert d['ggrt_diff'] == 1 and d['options_b'] == 'size=80x60 sphere=textbook', d['options_b']
assert d['tree_differ'] > 0 and d['value_differ'] >= d['tree_differ'] - d['first_divergence']['samples']
assert sum(d['first_divergence'].values()) == d['tree_differ']
" "$tmp/d.json" 2>"$tmp/py"; then ok "diff --format json"; else bad "diff --format json" "$(cat "$tmp/py")"; fi
expect_exit 1 "diff: a bad --b names its column" "$ggrt" diff $a --b 'sphere=round'
grep -qF "ggrt diff: --b:1:8: sphere must be stable or textbook, got 'round'" "$tmp/err" &&
  ok "diff: the --b message" || bad "diff: the --b message" "$(cat "$tmp/err")"
expect_err 1 "ggrt diff: --limit goes with --path" "diff --limit without --path is refused" \
  "$ggrt" diff examples/scenes/glass.nff -s 16x12 --b depth=2 --limit 5
# trace --diff --sample K: both trees are sample K's alone (one eye ray
# a side, not the pixel's 4), and a K the pixel has not is refused
"$ggrt" trace examples/scenes/glass.nff -s 32x24 -n 4 --pixel 16,12 --diff --b depth=2 --sample 3 \
  >"$tmp/ds" 2>&1; got=$?
if [ $got = 0 ] && grep -qx 'pixel 16,12, sample 3' "$tmp/ds" &&
   [ "$(grep -c '^.. *eye #0 .*| *eye #0 ' "$tmp/ds")" = 1 ] && ! grep -q 'eye #[1-9]' "$tmp/ds"
then ok "trace --diff --sample 3: one sample's trees on both sides"
else bad "trace --diff --sample 3: one sample's trees on both sides (exit $got)" "$(cat "$tmp/ds")"; fi
expect_err 1 "ggrt trace: sample 9 does not exist (the pixel has 4)" "trace --diff --sample 9 of 4 is refused" \
  "$ggrt" trace examples/scenes/glass.nff -s 32x24 -n 4 --pixel 16,12 --diff --b depth=2 --sample 9

# trace --ledger: the terms add up to the printed colour (glass, water, gears)
for p in "$g 110,100" "examples/scenes/water.nff 240,250" "examples/scenes/spd/gears.nff 250,260" "examples/scenes/spd/gears.nff 151,21"; do
  set -- $p
  "$ggrt" trace "$1" --pixel "$2" --ledger >"$tmp/l" 2>&1
  if grep -q "within the rounding bound .*: yes$" "$tmp/l" && grep -q "^  *[0-9.]*%  (" "$tmp/l"; then
    ok "trace --ledger $1 $2: the terms add up to the pixel"
  else bad "trace --ledger $1 $2: the terms add up to the pixel" "$(cat "$tmp/l")"; fi
done
"$ggrt" trace $g --pixel 110,100 -f json >"$tmp/t.json"
if python3 -c "
import json, sys
d = json.load(open(sys.argv[1]))
l = d['ledger']
assert l['holds'] is True and l['terms'][0]['kind'] == 'background'
for c in range(3):
    s = sum(t['value'][c] for t in l['terms'])
    assert abs(s - d['color'][c]) <= l['bound'][c], (s, d['color'][c])
" "$tmp/t.json" 2>"$tmp/py"; then ok "trace JSON carries the ledger, summing to the colour"
else bad "trace JSON carries the ledger, summing to the colour" "$(cat "$tmp/py")"; fi
expect_exit 1 "trace --ledger with --sample" "$ggrt" trace $g --pixel 1,1 --ledger --sample 0
