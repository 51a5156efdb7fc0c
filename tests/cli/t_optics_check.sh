# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: `ggrt optics check` and `ggrt optics seeds`.
# ggrt's own refraction and reflection pass every class; the
# textbook library (examples/textbook_refract.c, built next to ggrt) fails
# at grazing incidence and near the critical angle; load errors exit 2.
bdir=$(dirname "$ggrt")
tb="$bdir/libtextbook_refract.so"

expect_exit 0 "optics check: ggRefract passes" "$ggrt" optics check --cases 300
if grep -q "^PASS: worst 0\.[0-9]* ulp" "$tmp/out" && ! grep -q "FAIL" "$tmp/out"; then
  ok "optics check: ggRefract's worst class is below 1 ulp"
else bad "optics check: ggRefract's table" "$(cat "$tmp/out")"; fi
expect_exit 0 "optics check: ggReflection passes" "$ggrt" optics check --kind reflect --cases 300
expect_exit 0 "optics check: ggFresnelDielectric passes" "$ggrt" optics check --kind fresnel --cases 300
expect_exit 0 "optics check: ggFresnelConductor passes" "$ggrt" optics check --kind conductor --cases 300

if [ -f "$tb" ]; then
  expect_exit 4 "optics check: the textbook formula fails" \
    "$ggrt" optics check --lib "$tb" --symbol textbook_refract --cases 300
  for class in "grazing " "near critical " "huge eta, tilted "; do
    if grep "^$class" "$tmp/out" | grep -q "FAIL"; then ok "optics check: textbook fails '$class'"
    else bad "optics check: textbook passes '$class'?" "$(cat "$tmp/out")"; fi
  done
  if grep -q "^  near critical *v={-*0x" "$tmp/out"; then ok "optics check: worst inputs as hex floats"
  else bad "optics check: no hex-float input" "$(cat "$tmp/out")"; fi
  # Every textbook result in "subnormal sine" is non-finite: no worst ulp
  # or worst input to show (it printed 0 ulp and an all-zero input).
  if grep -q "^subnormal sine *300 *- " "$tmp/out" && grep -q "^  subnormal sine *none: no finite result" "$tmp/out"
  then ok "optics check: a class with no finite result shows no worst ulp or input"
  else bad "optics check: a class with no finite result" "$(grep "subnormal" "$tmp/out")"; fi
  expect_exit 4 "optics check: textbook json" \
    "$ggrt" optics check --lib "$tb" --symbol textbook_refract --cases 100 --format json
  if python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert not d["pass"] and len(d["classes"]) == 16' "$tmp/out"
  then ok "optics check: json parses, pass false, 16 classes"
  else bad "optics check: json" "$(cat "$tmp/out")"; fi
  if python3 -c '
import json, sys
c = [c for c in json.load(open(sys.argv[1]))["classes"] if c["name"] == "subnormal sine"][0]
assert c["nonfinite"] == c["cases"] and c["worst_ulp"] is None and c["worst_input"] is None
r = [c for c in json.load(open(sys.argv[1]))["classes"] if c["name"] == "random"][0]
assert r["worst_ulp"] > 1 and r["worst_input"].startswith("v={")' "$tmp/out"
  then ok "optics check: json, null worst ulp and input where nothing was finite"
  else bad "optics check: json worst of a class with no finite result" "$(cat "$tmp/out")"; fi
  expect_exit 4 "optics check: textbook reflection (tangent, huge)" \
    "$ggrt" optics check --lib "$tb" --symbol textbook_reflect --kind reflect --cases 300
  expect_exit 4 "optics check: the textbook Fresnel formula fails" \
    "$ggrt" optics check --lib "$tb" --symbol textbook_fresnel --kind fresnel --cases 300
  expect_exit 2 "optics check: unknown symbol" "$ggrt" optics check --lib "$tb" --symbol nope
  # A bare name is looked up in the library paths, not in this folder:
  # the message says so when the file is here.
  (cd "$bdir" && ./ggrt optics check --lib libtextbook_refract.so --symbol textbook_refract) \
    >/dev/null 2>"$tmp/lib.err"
  grep -qF "give ./libtextbook_refract.so for the file here" "$tmp/lib.err" &&
    ok "optics check --lib NAME (no '/'), the file here: the message says ./NAME" ||
    bad "optics check --lib NAME (no '/'), the file here: the message says ./NAME" "$(cat "$tmp/lib.err")"
else
  bad "optics check: $tb was not built"
fi
expect_exit 2 "optics check: missing library" "$ggrt" optics check --lib "$tmp/none.so" --symbol f
expect_exit 1 "optics check: --symbol without --lib" "$ggrt" optics check --symbol f
expect_exit 1 "optics check: bad --kind" "$ggrt" optics check --kind refraction

expect_exit 0 "optics seeds: writes a corpus" "$ggrt" optics seeds "$tmp/seeds" --cases 4
n=$(ls "$tmp/seeds" | wc -l)
if [ "$n" -eq 64 ]; then ok "optics seeds: 4 seeds for each of 16 classes"
else bad "optics seeds: $n files, want 64"; fi
expect_exit 3 "optics seeds: unwritable directory" "$ggrt" optics seeds /nonexistent/dir/seeds

# The fuzz harness of examples/fuzz_your_refract.c, replayed over that
# corpus: against ggRefract it passes, against the textbook it aborts.
if [ -x "$bdir/tests/yourfuzz_ggrefract" ] && [ -x "$bdir/tests/yourfuzz_textbook" ]; then
  "$ggrt" optics seeds "$tmp/seeds2" --cases 16 >/dev/null
  expect_exit 0 "fuzz_your_refract: ggRefract passes the seed corpus" \
    "$bdir/tests/yourfuzz_ggrefract" "$tmp/seeds2"
  "$bdir/tests/yourfuzz_textbook" "$tmp/seeds2" >"$tmp/out" 2>"$tmp/err"; rc=$?
  if [ $rc -ne 0 ] && grep -q "ulp" "$tmp/err"; then ok "fuzz_your_refract: the textbook is caught"
  else bad "fuzz_your_refract: textbook not caught (exit $rc)" "$(cat "$tmp/err")"; fi
else
  bad "fuzz_your_refract: replay binaries not built in $bdir/tests"
fi

# `ggrt optics refract` prints one decision, ggRefract's, once: a normal
# part of v from 2^-1 down to 2^-1074 of the tangential part, for indices
# with no critical angle (ni <= nt, ni == nt, ni == -nt) and with one.
refract_bad=""
for p in 1 60 300 481 600 900 1000 1074; do
  for ix in "1 1" "1 1.5" "0.7 1" "-1 1" "1e-300 1e300" "2 1"; do
    set -- $ix
    "$ggrt" optics refract --v 1,0,-0x1p-$p --n 0,0,1 --ni "$1" --nt "$2" >"$tmp/out" 2>&1 || \
      refract_bad="$refract_bad [p=$p ni=$1 nt=$2: exit $?]"
    ntir=$(grep -c "^TIR:" "$tmp/out")
    if [ "$ntir" -ne 1 ]; then refract_bad="$refract_bad [p=$p ni=$1 nt=$2: $ntir TIR lines]"; fi
    if grep -q "^critical angle: *none" "$tmp/out" && grep -q "^TIR: *yes" "$tmp/out"; then
      refract_bad="$refract_bad [p=$p ni=$1 nt=$2: no critical angle, yet TIR]"; fi
    if grep -q "lies in the surface" "$tmp/out"; then
      refract_bad="$refract_bad [p=$p ni=$1 nt=$2: v.n != 0 called in the surface]"; fi
  done
done
if [ -z "$refract_bad" ]; then ok "optics refract: one decision at grazing incidence down to 2^-1074"
else bad "optics refract: contradictions" "$refract_bad"; fi
expect_exit 0 "optics refract: v in the surface" "$ggrt" optics refract --v 1,0,0 --n 0,0,1
if grep -q "^TIR: *no: v lies in the surface" "$tmp/out"; then ok "optics refract: tangent v said once"
else bad "optics refract: tangent v" "$(cat "$tmp/out")"; fi
# |eta| beyond the doubles (about 2^1334, a tangential part of n 2^-1333 of
# its normal part: the fuzz_optics input found_huge_eta_spread_components):
# the ratio printed as m * 2^e, not inf, and the ray totally reflected.
expect_exit 0 "optics refract: eta beyond the doubles" "$ggrt" optics refract \
  --v 0,0,-0x1.445489d6cac2bp+741 --n 0,0x0.00000000005e1p-1022,0x1.e0718013dcbf8p+269 \
  --ni 0x1.8553485eb58e4p+513 --nt -0x1.aa967d3fcb8e1p-821
if grep -q "eta = ni/nt = -0\.91264981939587964 \* 2^1334$" "$tmp/out" &&
   grep -q "^TIR: *yes" "$tmp/out"; then ok "optics refract: eta as m * 2^e, TIR"
else bad "optics refract: eta beyond the doubles" "$(cat "$tmp/out")"; fi

# A value an optics form cannot take is a usage error as with every
# command (exit 1, the parser's words, the hint); it was exit 2 without
# the hint, some messages without the value.
for a in "fresnel --cos 2|bad value '2' for --cos: expected a number from -1 to 1 (out of range)" \
         "fresnel --angle 95|bad value '95' for --angle: expected a number from 0 to 90 (out of range)" \
         "fresnel --ni 0 --cos 0.5|bad value '0' for --ni: expected an index other than 0" \
         "refract --v 0,0,0 --n 0,1,0|bad value '0,0,0' for --v: expected a direction other than zero" \
         "absorb --k 1 --lambda 0 --distance 1|bad value '0' for --lambda: expected a wavelength > 0" \
         "absorb --k -1 --lambda 1 --distance 1|bad value '-1' for --k: expected a finite number >= 0 (out of range)"; do
  args=${a%%|*}; msg=${a#*|}; form=${args%% *}
  # shellcheck disable=SC2086
  "$ggrt" optics $args >"$tmp/out" 2>"$tmp/err"; rc=$?
  if [ $rc -eq 1 ] && grep -qxF "ggrt optics $form: $msg" "$tmp/err" && grep -qxF "(see 'ggrt optics $form --help')" "$tmp/err"
  then ok "optics $args: exit 1, the value named, the hint"
  else bad "optics $args (exit $rc)" "$(cat "$tmp/err")"; fi
done
