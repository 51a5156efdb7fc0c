# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: find, check and diff --tile I/N and ggrt
# merge --reports (docs/cluster.md, "The debugger across tiles"). The
# reports of 1, 2 and 7 tiles of three scenes (one under --spd), each
# tile its own process, merge into the file one process writes, byte for
# byte; also with a plan's cut, and for --path. Every bad input to merge
# --reports names the report and the reason, exits 2 and writes nothing.
# Uses run.sh's ggrt, tmp, sample, ok, bad, expect_err.

rd="$tmp/reports"
mkdir -p "$rd"

# reports_same NAME N CMD ARGS...: N tiles of `ggrt CMD ARGS -f json
# --tile I/N` merge into `ggrt CMD ARGS -f json`'s output (cmp).
reports_same() {
  name=$1; n=$2; shift 2
  rm -f "$rd"/r-*.json
  i=0
  while [ $i -lt "$n" ]; do
    "$ggrt" "$@" -f json --tile $i/"$n" >"$rd/r-$i.json" 2>"$tmp/err"
    [ $? -le 1 ] || [ "$1" = check ] || { bad "$name: tile $i of $n" "$(cat "$tmp/err")"; return; }
    i=$((i + 1))
  done
  "$ggrt" "$@" -f json >"$rd/one.json" 2>/dev/null
  "$ggrt" merge -q --reports "$rd"/r-*.json -o "$rd/m.json" 2>"$tmp/err" ||
    { bad "$name: merge --reports of $n" "$(cat "$tmp/err")"; return; }
  if [ -s "$rd/one.json" ] && cmp -s "$rd/m.json" "$rd/one.json"; then
    ok "$name: $n tiles' reports merge into one process's, byte for byte"
  else
    bad "$name: $n tiles' reports merge into one process's" "$(cmp "$rd/m.json" "$rd/one.json")"
  fi
}

# 1, 2 and 7 tiles; when run.sh samples (GG_TEST_SAMPLE), 7 for the
# first scene and 2 for the others.
report_tiles="1 2 7"
for spec in "examples/scenes/spd/gears.nff --spd -s 96x64" \
            "examples/scenes/glass.nff -s 80x48" \
            "examples/scenes/texture.nff -s 64x40 -n 4"; do
  [ "$sample" = 1 ] || { case $spec in *gears*) report_tiles=7 ;; *) report_tiles=2 ;; esac; }
  # shellcheck disable=SC2086
  for n in $report_tiles; do
    # shellcheck disable=SC2086
    reports_same "find $spec" $n find $spec -w 'some(kind == reflect)' --limit 30
    # shellcheck disable=SC2086
    reports_same "check $spec" $n check $spec
    # shellcheck disable=SC2086
    reports_same "diff $spec" $n diff $spec --b depth=3 --worst 12
  done
done
# shellcheck disable=SC2086
reports_same "find --path, gears" 7 find examples/scenes/spd/gears.nff --spd -s 96x64 --path 'C<TS>+B'
reports_same "diff --path, glass" 7 diff examples/scenes/glass.nff -s 80x48 --b depth=3 --path 'C<TS>+B' --limit 5
reports_same "find --limit 0, glass" 2 find examples/scenes/glass.nff -s 80x48 -w 'some(kind == tir)' --limit 0
# A predicate of pixel values alone, through pixel corners: its counts
# came from a render that shares corners between pixels (and a tile's
# cast its edge row again: 3 tiles said 156 eye rays, the whole 130).
reports_same "find of values alone, --spd" 3 find examples/scenes/glass.nff -s 12x9 --spd -w 'x >= 0'
reports_same "find of values alone, --corners" 3 find examples/scenes/texture.nff -s 12x9 --corners -w 'y >= 3'
a=$("$ggrt" find examples/scenes/glass.nff -s 12x9 --spd -q -f json -w 'x >= 0' | grep -o '"eye":[0-9]*')
b=$("$ggrt" find examples/scenes/glass.nff -s 12x9 --spd -q -f json -w 'x >= 0 && some(kind == eye)' |
  grep -o '"eye":[0-9]*')
[ -n "$a" ] && [ "$a" = "$b" ] && ok "find --spd: the same pixels, the same counts, however the predicate reads them" ||
  bad "find --spd: the same pixels, the same counts, however the predicate reads them" "$a / $b"

# A plan's cut (by rays: the same cut every run).
"$ggrt" plan examples/scenes/spd/gears.nff --spd -s 96x64 --cost rays -q --tiles 7 -o "$rd/plan.json" ||
  bad "plan for the reports"
rm -f "$rd"/r-*.json
for i in 0 1 2 3 4 5 6; do
  "$ggrt" check examples/scenes/spd/gears.nff --spd -s 96x64 -f json --plan "$rd/plan.json" --tile $i \
    >"$rd/r-$i.json"
done
"$ggrt" check examples/scenes/spd/gears.nff --spd -s 96x64 -f json >"$rd/one.json"
if "$ggrt" merge -q --reports "$rd"/r-*.json -o "$rd/m.json" && cmp -s "$rd/m.json" "$rd/one.json" &&
   grep -q '"cut":"plan 0,' "$rd/r-3.json"; then
  ok "check: a plan's 7 tiles' reports merge into one process's"
else bad "check: a plan's 7 tiles' reports merge into one process's"; fi

# check --path: its share is a mean of floating-point shares, which merge
# recombines from the tiles' means (cli/render/report_merge.c, share_of)
# where one process sums its rows' shares (lib/debug/check.c): they round
# apart in the last digits; the rest is byte for byte, the share within
# 1e-12.
rm -f "$rd"/r-*.json
for i in 0 1; do
  "$ggrt" check examples/scenes/glass.nff -s 80x48 --path "C.*<RS'tir'>.*" -f json --tile $i/2 >"$rd/r-$i.json"
done
"$ggrt" check examples/scenes/glass.nff -s 80x48 --path "C.*<RS'tir'>.*" -f json >"$rd/one.json"
"$ggrt" merge -q --reports "$rd"/r-*.json -o "$rd/m.json"
if python3 - "$rd/m.json" "$rd/one.json" >"$tmp/out" 2>&1 <<'PY'
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
sa, sb = a.pop("share"), b.pop("share")
assert a == b, "reports differ beyond the share"
assert sa > 0 and abs(sa - sb) <= 1e-12 * sb, (sa, sb)
PY
then ok "check --path: 2 tiles' reports merge into one process's (share within 1e-12)"
else bad "check --path: 2 tiles' reports merge into one process's" "$(cat "$tmp/out")"; fi

# ---- usage ----
expect_err 1 "ggrt find: --tile writes a JSON report: add -f json" "find --tile needs -f json" \
  "$ggrt" find examples/scenes/glass.nff -w 'some(kind == tir)' --tile 0/2
expect_err 1 "ggrt check: --tile writes the JSON report alone: not with -o, --overlay, --paths-jsonl, --paths-obj or --crop" \
  "check --tile refuses --crop" "$ggrt" check examples/scenes/glass.nff -f json --tile 0/2 --crop 0,0,4,4
expect_err 1 "ggrt diff: --plan goes with --tile" "diff --plan without --tile" \
  "$ggrt" diff examples/scenes/glass.nff -f json --plan "$rd/plan.json"
# merge --reports writes JSON: an image's name for it is refused before
# anything is read, and a missing input is named as a report
rm -f "$rd/fr.png"
expect_err 1 "ggrt merge: --reports writes a JSON report, not an image: '$rd/fr.png'" \
  "merge --reports refuses -o an image" "$ggrt" merge --reports "$rd"/r-*.json -o "$rd/fr.png"
[ ! -e "$rd/fr.png" ] && ok "merge --reports -o an image writes nothing" ||
  bad "merge --reports -o an image writes nothing" "$(head -c 200 "$rd/fr.png")"
expect_err 1 "ggrt merge: need a report" "merge --reports without files asks for a report" \
  "$ggrt" merge --reports -o "$rd/x.json"
expect_err 1 "ggrt merge: need a tile" "merge without files asks for a tile" \
  "$ggrt" merge -o "$rd/x.png"

# ---- bad input: the report, the reason, exit 2, nothing written ----
g=examples/scenes/glass.nff
for i in 0 1 2 3; do
  "$ggrt" find $g -s 80x48 -w 'some(kind == tir)' -f json --tile $i/4 >"$rd/g-$i.json"
done
# reports_refuse NAME MESSAGE FILES...
reports_refuse() {
  what=$1; msg=$2; shift 2
  rm -f "$rd"/out.*
  expect_err 2 "$msg" "merge --reports refuses $what" "$ggrt" merge --reports "$@" -o "$rd/out.json"
  if [ -z "$(ls "$rd" | grep '^out\.')" ]; then ok "merge --reports of $what writes nothing"
  else bad "merge --reports of $what writes nothing" "$(ls "$rd" | grep '^out')"; fi
}
reports_refuse "a missing tile" "ggrt merge: tile 2 of 4 (rows 24..35) is missing" \
  "$rd/g-0.json" "$rd/g-1.json" "$rd/g-3.json"
# a cut as ggrt writes it, digits only: "rows +4" is not "rows 4"
for i in 0 1 2 3; do sed 's/"cut":"rows 4"/"cut":"rows +4"/' "$rd/g-$i.json" >"$rd/sign-$i.json"; done
reports_refuse "a cut with a sign" "ggrt merge: $rd/sign-0.json: bad cut 'rows +4': not a cut of 48 rows" \
  "$rd"/sign-[0-3].json
cp "$rd/g-1.json" "$rd/dup-1.json"
reports_refuse "a duplicate" "ggrt merge: $rd/dup-1.json: tile 1 again (also in $rd/g-1.json)" \
  "$rd"/g-[0-3].json "$rd/dup-1.json"
reports_refuse "a report given twice" "ggrt merge: $rd/g-1.json: given twice (tile 1)" \
  "$rd"/g-[0-3].json "$rd/g-1.json"
"$ggrt" find $g -s 80x48 -d 3 -w 'some(kind == tir)' -f json --tile 2/4 >"$rd/opt-2.json"
reports_refuse "a tile of other options" \
  "ggrt merge: $rd/opt-2.json: different render options from $rd/g-0.json: 'depth=3', not 'depth=5'" \
  "$rd/g-0.json" "$rd/g-1.json" "$rd/opt-2.json" "$rd/g-3.json"
# -j changes no pixel: diff tiles of another -j merge (into what one
# process with the first tile's -j writes), for options_b as for
# options_a; another --b is refused
"$ggrt" diff $g -s 64x48 --b sphere=textbook -f json --tile 0/2 -j 2 >"$rd/dj-0.json"
"$ggrt" diff $g -s 64x48 --b sphere=textbook -f json --tile 1/2 -j 1 >"$rd/dj-1.json"
"$ggrt" diff $g -s 64x48 --b sphere=textbook -f json -j 2 >"$rd/dj-one.json"
rm -f "$rd"/dj-m.json
if "$ggrt" merge -q --reports "$rd/dj-0.json" "$rd/dj-1.json" -o "$rd/dj-m.json" 2>"$tmp/err" &&
   cmp -s "$rd/dj-m.json" "$rd/dj-one.json"; then
  ok "merge --reports joins diff tiles that differ only in -j"
else bad "merge --reports joins diff tiles that differ only in -j" "$(cat "$tmp/err")"; fi
"$ggrt" diff $g -s 64x48 --b depth=3 -f json --tile 1/2 -j 1 >"$rd/db-1.json"
reports_refuse "a diff tile of another --b" \
  "ggrt merge: $rd/db-1.json: different \"options_b\" from $rd/dj-0.json: \"size=64x48 depth=3 threads=1\", not \"size=64x48 threads=2 sphere=textbook\"" \
  "$rd/dj-0.json" "$rd/db-1.json"
# numbers and escapes outside JSON's grammar, which merge would copy out
sed 's/"color":\[0\.[0-9]*,/"color":[0x1p-1,/' "$rd/g-0.json" >"$rd/hex-0.json"
at=$(awk 'NR == 1 { print index($0, "[0x1p-1") + 1 }' "$rd/hex-0.json") # the x
reports_refuse "a number in hex" \
  "ggrt merge: $rd/hex-0.json: not a JSON report: expected ',' or ']' at byte $at" \
  "$rd/hex-0.json" "$rd"/g-[1-3].json
sed 's/"where":"some(kind == tir)"/"where":"some(kind == \\x41)"/' "$rd/g-0.json" >"$rd/esc-0.json"
grep -qF '\x41' "$rd/esc-0.json" || bad "esc-0.json has its escape"
at=$(awk 'NR == 1 { print index($0, "\\x41") }' "$rd/esc-0.json") # the x
reports_refuse "a string with a bad escape" \
  "ggrt merge: $rd/esc-0.json: not a JSON report: not a JSON escape in a string at byte $at" \
  "$rd/esc-0.json" "$rd"/g-[1-3].json
sed 's/^l 3 -3 6$/l 3 -3 7/' $g >"$rd/glass2.nff"
"$ggrt" find "$rd/glass2.nff" -s 80x48 -w 'some(kind == tir)' -f json --tile 3/4 >"$rd/scene-3.json"
h1=$(sed -n 's/.*"sceneHash":"\([^"]*\)".*/\1/p' "$rd/g-0.json")
h2=$(sed -n 's/.*"sceneHash":"\([^"]*\)".*/\1/p' "$rd/scene-3.json")
reports_refuse "a tile of another scene" \
  "ggrt merge: $rd/scene-3.json: different scene (hash) from $rd/g-0.json: \"$h2\", not \"$h1\"" \
  "$rd"/g-[0-2].json "$rd/scene-3.json"
"$ggrt" find $g -s 80x48 -w 'some(kind == tir)' -f json --tile 3/5 >"$rd/cut-3.json"
reports_refuse "a tile of another cut" \
  "ggrt merge: $rd/cut-3.json: different cut from $rd/g-0.json: \"rows 5\", not \"rows 4\"" \
  "$rd"/g-[0-2].json "$rd/cut-3.json"
# another ggrt build (ggBuildId, ggrt --version), or one before build ids
rbid=$(sed -n 's/.*"buildId":"\([^"]*\)".*/\1/p' "$rd/g-0.json")
sed "s/\"buildId\":\"$rbid\"/\"buildId\":\"old-${rbid#src-}\"/" "$rd/g-1.json" >"$rd/build-1.json"
reports_refuse "a tile of another ggrt build" \
  "ggrt merge: $rd/build-1.json: different ggrt build from $rd/g-0.json: \"old-${rbid#src-}\", not \"$rbid\"" \
  "$rd/g-0.json" "$rd/build-1.json" "$rd/g-2.json" "$rd/g-3.json"
sed 's/"buildId":"[^"]*",//' "$rd/g-2.json" >"$rd/older-2.json"
reports_refuse "a tile of a ggrt before build ids" \
  "ggrt merge: $rd/older-2.json: a tile's report of an older ggrt: no \"buildId\" in its manifest (run it again with this one)" \
  "$rd/g-0.json" "$rd/g-1.json" "$rd/older-2.json" "$rd/g-3.json"
"$ggrt" find $g -s 80x48 -w 'some(kind == tir)' --limit 3 -f json --tile 1/4 >"$rd/lim-1.json"
reports_refuse "a tile of another --limit" \
  "ggrt merge: $rd/lim-1.json: different command options from $rd/g-0.json: 'limit=3', not 'limit=20'" \
  "$rd/g-0.json" "$rd/lim-1.json" "$rd/g-2.json" "$rd/g-3.json"
# check's and diff's options in their own words, only the one that differs
"$ggrt" check $g -s 80x48 -f json --tile 0/2 >"$rd/c-0.json" 2>/dev/null
"$ggrt" check $g -s 80x48 --severity self-hit=error -f json --tile 1/2 >"$rd/cs-1.json" 2>/dev/null
reports_refuse "a check tile of another --severity" \
  "ggrt merge: $rd/cs-1.json: different command options from $rd/c-0.json: 'severity.self-hit=error', not 'severity.self-hit=warning'" \
  "$rd/c-0.json" "$rd/cs-1.json"
"$ggrt" check $g -s 80x48 --truncation 0.2 -f json --tile 1/2 >"$rd/ct-1.json" 2>/dev/null
reports_refuse "a check tile of another --truncation" \
  "ggrt merge: $rd/ct-1.json: different command options from $rd/c-0.json: 'truncation=0.2', not 'truncation=0.1'" \
  "$rd/c-0.json" "$rd/ct-1.json"
"$ggrt" diff $g examples/scenes/gold.nff -s 80x48 -q -f json --tile 0/2 >"$rd/db-0.json"
"$ggrt" diff $g $g -s 80x48 -q -f json --tile 1/2 >"$rd/db-1.json"
hb=$(grep -o 'scene-b=fnv1a64:[0-9a-f]*' "$rd/db-1.json")
ha=$(grep -o 'scene-b=fnv1a64:[0-9a-f]*' "$rd/db-0.json")
reports_refuse "a diff tile of another second scene" \
  "ggrt merge: $rd/db-1.json: different command options from $rd/db-0.json: '$hb', not '$ha'" \
  "$rd/db-0.json" "$rd/db-1.json"
grep -q '"params":"worst=10 limit=all scene-b=' "$rd/db-0.json" &&
  ok "a diff tile's params: limit=all, scene-b=HASH" ||
  bad "a diff tile's params: limit=all, scene-b=HASH" "$(grep -o '"params":"[^"]*"' "$rd/db-0.json")"
"$ggrt" find $g -s 80x48 -w 'some(kind == refract)' -f json --tile 1/4 >"$rd/where-1.json"
reports_refuse "a tile of another predicate" \
  "ggrt merge: $rd/where-1.json: different \"where\" from $rd/g-0.json: \"some(kind == refract)\", not \"some(kind == tir)\"" \
  "$rd/g-0.json" "$rd/where-1.json" "$rd/g-2.json" "$rd/g-3.json"
"$ggrt" check $g -s 80x48 -f json --tile 1/4 >"$rd/check-1.json"
reports_refuse "a check report among find reports" \
  "ggrt merge: $rd/check-1.json: a ggrt_check report, not ggrt_find as $rd/g-0.json" \
  "$rd/g-0.json" "$rd/check-1.json" "$rd/g-2.json" "$rd/g-3.json"
mkdir -p "$rd/dir-1.json"
rm -f "$rd"/out.*
expect_err 3 "ggrt merge: $rd/dir-1.json: not a regular file" "merge --reports refuses a folder" \
  "$ggrt" merge --reports "$rd/g-0.json" "$rd/dir-1.json" "$rd/g-2.json" "$rd/g-3.json" -o "$rd/out.json"
head -c 200 "$rd/g-1.json" >"$rd/trunc-1.json"
rm -f "$rd"/out.*
expect_msg 2 "ggrt merge: $rd/trunc-1.json: not a JSON report: " "merge --reports refuses a truncated report" \
  "$ggrt" merge --reports "$rd/g-0.json" "$rd/trunc-1.json" "$rd/g-2.json" "$rd/g-3.json" -o "$rd/out.json"
# cut off inside a string: the end of the text, not a control character
printf '{"ggrt_find":1,"scene":"exam' >"$rd/trunc-s.json"
expect_err 2 "ggrt merge: $rd/trunc-s.json: not a JSON report: the text ends in a string at byte 28" \
  "merge --reports: a report cut off inside a string" \
  "$ggrt" merge --reports "$rd/trunc-s.json" -o "$rd/out.json"
if [ -z "$(ls "$rd" | grep '^out\.')" ]; then ok "merge --reports of a truncated report writes nothing"
else bad "merge --reports of a truncated report writes nothing" "$(ls "$rd")"; fi
"$ggrt" find $g -s 80x48 -w 'some(kind == tir)' -f json >"$rd/whole.json"
reports_refuse "a report that is not a tile's" \
  "ggrt merge: $rd/whole.json: not a tile's report: no \"tile\" manifest (find, check or diff --tile)" \
  "$rd/whole.json"
sed 's/,"params":"[^"]*"//' "$rd/g-2.json" >"$rd/noparams-2.json"
reports_refuse "a manifest without params" \
  "ggrt merge: $rd/noparams-2.json: the tile manifest has no \"params\" string" \
  "$rd/g-0.json" "$rd/g-1.json" "$rd/noparams-2.json" "$rd/g-3.json"
