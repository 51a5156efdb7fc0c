# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: light-path expressions (find --path, trace
# --path). Uses run.sh's ggrt, tmp, ok, bad, expect_exit.

g=examples/scenes/glass.nff
# errors: exit 1, the column, a caret under it
"$ggrt" find $g --path "C<TS" >"$tmp/out" 2>"$tmp/err"; rc=$?
if [ $rc = 1 ] && grep -qxF "ggrt find: --path:1:5: expected '>' to close the '<' of column 2, got the end" "$tmp/err" &&
   grep -qx '      ^' "$tmp/err"; then ok "find --path: a mistake names its column"
else bad "find --path: a mistake names its column (exit $rc)" "$(cat "$tmp/err")"; fi
"$ggrt" trace $g -p 1,1 --path "C<TS>[objct == 2]" >"$tmp/out" 2>"$tmp/err"; rc=$?
if [ $rc = 1 ] && grep -qF "ggrt trace: --path:1:7: unknown field 'objct'" "$tmp/err"; then
  ok "trace --path: a predicate's mistake names its column in the whole text"
else bad "trace --path: a predicate's mistake names its column (exit $rc)" "$(cat "$tmp/err")"; fi
expect_exit 1 "find: --where and --path together" "$ggrt" find $g --where 'some(hit)' --path 'C.*'
expect_exit 1 "find: neither --where nor --path" "$ggrt" find $g
expect_exit 1 "trace --path with --sample" "$ggrt" trace $g -p 1,1 --sample 0 --path 'C.*'
expect_exit 1 "trace --path with --ledger" "$ggrt" trace $g -p 1,1 --ledger --path 'C.*'

# trace --path: only the matching terms, with events that match as written
"$ggrt" trace $g -s 24x18 -p 10,1 --path "C<TS>.*<RS'tir'>.*" >"$tmp/tp" 2>"$tmp/err"
if grep -qF "paths matching C<TS>.*<RS'tir'>.*: 1 of 2," "$tmp/tp" &&
   grep -qF "C<TS'1'><RS'2''tir'><TS'1'>B" "$tmp/tp"; then ok "trace --path: the matching path and its events"
else bad "trace --path: the matching path and its events" "$(cat "$tmp/tp" "$tmp/err")"; fi
"$ggrt" trace $g -s 24x18 -p 12,8 --path "C.*" -f json >"$tmp/tp.json" 2>"$tmp/err"
"$ggrt" trace $g -s 24x18 -p 12,8 -f json >"$tmp/t.json" 2>>"$tmp/err"
if python3 -c "
import json, sys
p = json.load(open(sys.argv[1])); t = json.load(open(sys.argv[2]))
assert p['ggrt_paths'] == 1 and p['matched'] == p['paths'] == len(t['ledger']['terms']) > 0
assert abs(p['share'] - 1) < 1e-6, p['share']  # the float pixel: 2^-24
" "$tmp/tp.json" "$tmp/t.json" 2>"$tmp/py"; then ok "trace --path C.* -f json: every ledger term, share 1 within the float pixel's rounding"
else bad "trace --path C.* -f json: every ledger term, share 1" "$(cat "$tmp/py" "$tmp/err")"; fi

# the documented examples against an independent matcher on every example scene
bulk python3 tests/cli/lpe_check.py "$ggrt" docs/debugging.md examples/scenes/*.nff >"$tmp/lpe" 2>&1
while IFS= read -r line; do
  case "$line" in
    "ok   "*) ok "lpe: ${line#ok   }" ;;
    "FAIL "*) bad "lpe: ${line#FAIL }" ;;
    *) bad "lpe_check.py: $line" ;;
  esac
done < "$tmp/lpe"
grep -q '^ok' "$tmp/lpe" || bad "lpe_check.py ran" "$(cat "$tmp/lpe")"

# diff --path: the pixels whose light moved between path classes, against the
# independent matcher over both sides' trace JSON (acc-distant: the textbook
# sphere loses and gains hits, so paths change class)
bulk python3 tests/cli/lpe_diff_check.py "$ggrt" examples/scenes/acc-distant.nff sphere=textbook \
  "C<RS>+.*" "C<RD>L" "C.*B" "C<RS'2'>.*" "C[^R]*" >"$tmp/lpediff" 2>&1
while IFS= read -r line; do
  case "$line" in
    "ok   "*) ok "lpe: ${line#ok   }" ;;
    "FAIL "*) bad "lpe: ${line#FAIL }" ;;
    *) bad "lpe_diff_check.py: $line" ;;
  esac
done < "$tmp/lpediff"
grep -q '^ok' "$tmp/lpediff" || bad "lpe_diff_check.py ran" "$(cat "$tmp/lpediff")"
"$ggrt" diff examples/scenes/acc-distant.nff -s 64x48 --b sphere=textbook --path "C<RS>+.*" \
  --limit 2 -q >"$tmp/dp" 2>"$tmp/err"
if grep -qF "light moved (paths C<RS>+.*): 160 pixels, the first 2 in row order" "$tmp/dp" &&
   [ "$(grep -c 'first divergence: ray #0 (eye): a leaves the scene, b hits object' "$tmp/dp")" -ge 2 ]; then
  ok "diff --path: the count, and each listed pixel with the decision that flipped"
else bad "diff --path: the count and the decision that flipped" "$(cat "$tmp/dp" "$tmp/err")"; fi
"$ggrt" diff examples/scenes/acc-distant.nff -s 32x24 --path "C<RS>+.*" -f json -q >"$tmp/d0.json" 2>"$tmp/err"
if python3 -c "
import json, sys
d = json.load(open(sys.argv[1]))
assert d['moved'] == 0 and d['moves'] == [] and d['tree_differ'] == 0
" "$tmp/d0.json" 2>"$tmp/py"; then ok "diff --path of a render with itself: moved 0, moves []"
else bad "diff --path of a render with itself: moved 0, moves []" "$(cat "$tmp/py" "$tmp/err")"; fi
expect_exit 1 "diff --path: a malformed expression" "$ggrt" diff examples/scenes/acc-distant.nff --path "C<TS"

# check --path: only the pixels find --path finds are checked, with find's shares
"$ggrt" check $g -s 48x36 -q --path "C.*<RS'tir'>.*" -f json >"$tmp/cp.json" 2>"$tmp/err"; rc=$?
"$ggrt" find $g -s 48x36 -q --limit 0 --path "C.*<RS'tir'>.*" -f json >"$tmp/fp.json" 2>>"$tmp/err"
"$ggrt" check $g -s 48x36 -q -f json >"$tmp/c.json" 2>>"$tmp/err"
if [ $rc = 4 ] && python3 -c "
import json, sys
c, f, a = (json.load(open(p)) for p in sys.argv[1:4])
share = {tuple(m['pixel']): m['share'] for m in f['matches']}
assert c['scanned'] == 1728 and c['checked'] == f['matched'] == len(share) > 0, (c['checked'], f['matched'])
assert abs(c['share'] - sum(share.values()) / len(share)) < 1e-9
assert a['checked'] == a['scanned'] == 1728 and a['share'] == 0
n = 0
for ci, ai in zip(c['invariants'], a['invariants']):
    assert ci['pixels'] <= ai['pixels'], ci['name']
    for p in ci['worst_pixels']:
        assert abs(p['share'] - share[tuple(p['pixel'])]) < 1e-9, p
        n += 1
t = [i for i in c['invariants'] if i['name'] == 'truncation'][0]
assert n > 0 and 0 < t['pixels'] < [i for i in a['invariants'] if i['name'] == 'truncation'][0]['pixels']
" "$tmp/cp.json" "$tmp/fp.json" "$tmp/c.json" 2>"$tmp/py"; then
  ok "check --path: the pixels find --path finds, their shares, a subset of the failures"
else bad "check --path: the pixels find --path finds (exit $rc)" "$(cat "$tmp/py" "$tmp/err")"; fi
expect_exit 0 "check --path: a class no pixel has checks nothing and passes" "$ggrt" check $g -s 24x18 -q --path "C<TS>{9}.*"
expect_exit 1 "check --path: a malformed expression" "$ggrt" check $g --path "C<TS"

# path export: find --path --paths-jsonl/--paths-obj against the traces and the
# independent matcher; trace --path writes the same lines for its pixel
for e in "C<TS>.*<RS'tir'>.*" "C.*<RD>L" "C<RS>+.*B"; do
  rm -f "$tmp/p.jsonl" "$tmp/p.obj"
  "$ggrt" find $g -s 24x18 -q --path "$e" --limit 0 --paths-jsonl "$tmp/p.jsonl" \
    --paths-obj "$tmp/p.obj" -f json >/dev/null 2>"$tmp/err"
  line=$(bulk python3 tests/cli/lpe_export_check.py "$ggrt" $g 24x18 "$e" "$tmp/p.jsonl" "$tmp/p.obj" 2>&1)
  case "$line" in
    "ok   "*) ok "lpe: ${line#ok   }" ;;
    *) bad "lpe: path export of $e" "$line
$(cat "$tmp/err")" ;;
  esac
done
"$ggrt" trace $g -s 24x18 -p 10,1 --path "C<TS>.*<RS'tir'>.*" --paths-jsonl "$tmp/t.jsonl" \
  --paths-obj "$tmp/t.obj" >/dev/null 2>"$tmp/err"
"$ggrt" find $g -s 24x18 -q --crop 10,1,11,2 --path "C<TS>.*<RS'tir'>.*" --paths-jsonl "$tmp/f.jsonl" \
  --paths-obj "$tmp/f.obj" >/dev/null 2>>"$tmp/err"
if [ -s "$tmp/t.jsonl" ] && cmp -s "$tmp/t.jsonl" "$tmp/f.jsonl" && cmp -s "$tmp/t.obj" "$tmp/f.obj"; then
  ok "trace --path --paths-jsonl/--paths-obj: the same files as a find of that pixel"
else bad "trace --path --paths-jsonl/--paths-obj: the same files as a find of that pixel" "$(cat "$tmp/err")"; fi
expect_exit 1 "--paths-jsonl without --path" "$ggrt" trace $g -p 1,1 --paths-jsonl "$tmp/x.jsonl"
expect_exit 1 "--paths-obj without --path" "$ggrt" find $g --where 'some(hit)' --paths-obj "$tmp/x.obj"
# outputs are checked before the work: a folder as the file fails at once (exit 3)
mkdir "$tmp/dir"
expect_exit 3 "--paths-jsonl naming a folder fails before the work" \
  "$ggrt" find $g -s 512x512 --path 'C.*' --paths-jsonl "$tmp/dir" -q
if grep -qF "refusing to write '$tmp/dir': it is a directory" "$tmp/err" && [ ! -s "$tmp/out" ]; then
  ok "--paths-jsonl: the message names the file, nothing was found first"
else bad "--paths-jsonl: the message names the file" "$(cat "$tmp/out" "$tmp/err")"; fi
expect_exit 3 "--paths-obj naming a folder fails before the work" \
  "$ggrt" trace $g -p 1,1 --path 'C.*' --paths-obj "$tmp/dir"
# --paths-max: the two files' bytes at most; exactly their size passes,
# one byte less writes nothing (exit 2), in find and in trace
mkdir "$tmp/pm"
"$ggrt" find $g -s 24x18 -q --path 'C.*' --paths-jsonl "$tmp/pm/a.jsonl" --paths-obj "$tmp/pm/a.obj" >/dev/null
n=$(($(wc -c <"$tmp/pm/a.jsonl") + $(wc -c <"$tmp/pm/a.obj")))
expect_exit 0 "find --paths-max: the files' own size ($n bytes) is enough" \
  "$ggrt" find $g -s 24x18 -q --path 'C.*' --paths-jsonl "$tmp/pm/b.jsonl" --paths-obj "$tmp/pm/b.obj" --paths-max $n
cmp -s "$tmp/pm/a.jsonl" "$tmp/pm/b.jsonl" && cmp -s "$tmp/pm/a.obj" "$tmp/pm/b.obj" &&
  ok "find --paths-max: under it, the same files" || bad "find --paths-max: under it, the same files"
rm -f "$tmp/pm/"*
expect_msg 2 "ggrt find: the paths passed --paths-max ($((n - 1)) bytes) at pixel " \
  "find --paths-max: a byte less is refused, the pixel named" \
  "$ggrt" find $g -s 24x18 -q --path 'C.*' --paths-jsonl "$tmp/pm/b.jsonl" --paths-obj "$tmp/pm/b.obj" --paths-max $((n - 1))
[ -z "$(ls "$tmp/pm")" ] && ok "find --paths-max: past it, no file and no temporary file" ||
  bad "find --paths-max: past it, no file and no temporary file" "$(ls "$tmp/pm")"
expect_msg 2 "ggrt trace: the paths passed --paths-max (1024 bytes) at pixel 10,1" \
  "trace --paths-max 1K: refused past 1024 bytes" \
  "$ggrt" trace $g -s 24x18 -p 10,1 --path 'C.*' --paths-jsonl "$tmp/pm/t.jsonl" --paths-max 1K
[ -z "$(ls "$tmp/pm")" ] && ok "trace --paths-max: past it, no file" || bad "trace --paths-max: past it, no file" "$(ls "$tmp/pm")"
for v in 1.5G -1 1KB 0x10 "" 1048577G; do
  expect_exit 1 "--paths-max '$v' is a usage error" "$ggrt" find $g --path 'C.*' --paths-jsonl "$tmp/pm/x" --paths-max "$v"
done
expect_exit 0 "--paths-max 0: no limit" "$ggrt" trace $g -s 24x18 -p 10,1 --path 'C.*' --paths-jsonl "$tmp/pm/t.jsonl" --paths-max 0
