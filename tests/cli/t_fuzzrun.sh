# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: tests/fuzz/run.sh (make fuzz) runs every
# harness whatever the others found, prints a summary of all of them and
# exits 1 if any found something. Two stand-in harnesses, shell scripts
# that take libFuzzer's arguments: one "finds" a crash (writes an artifact,
# exits 1), the other finds nothing. Uses run.sh's tmp, ok and bad.

mkdir -p "$tmp/fz"
cat > "$tmp/fz/fuzz_aaa" <<'SH'
#!/bin/sh
for a in "$@"; do case $a in -artifact_prefix=*) p=${a#-artifact_prefix=};; esac; done
echo "stat::number_of_executed_units: 7"
printf x > "${p}crash-0123"
exit 1
SH
cat > "$tmp/fz/fuzz_bbb" <<'SH'
#!/bin/sh
echo "stat::number_of_executed_units: 9"
SH
chmod +x "$tmp/fz/fuzz_aaa" "$tmp/fz/fuzz_bbb"
sh tests/fuzz/run.sh "$tmp/fz/out" 1 "$tmp/fz/fuzz_aaa" "$tmp/fz/fuzz_bbb" "$tmp/fz/fuzz_ccc" \
  >"$tmp/fz/log" 2>&1; got=$?
if [ $got = 1 ] &&
   grep -qF "aaa: FOUND something (exit 1, 7 runs): $tmp/fz/out/aaa-crash-0123" "$tmp/fz/log" &&
   grep -qF "bbb: nothing found in 1 s (9 runs)" "$tmp/fz/log" &&
   grep -qF "ccc: did not build (no $tmp/fz/fuzz_ccc)" "$tmp/fz/log" &&
   grep -qF "fuzz: summary, 3 harnesses of 1 s each:" "$tmp/fz/log" &&
   grep -qF "fuzz: 2 of 3 harnesses found something" "$tmp/fz/log"
then ok "make fuzz goes on after a finding and sums up every harness (exit 1)"
else bad "make fuzz goes on after a finding and sums up every harness (exit $got)" "$(cat "$tmp/fz/log")"; fi
sh tests/fuzz/run.sh "$tmp/fz/out2" 1 "$tmp/fz/fuzz_bbb" >"$tmp/fz/log" 2>&1; got=$?
[ $got = 0 ] && grep -qF "fuzz: nothing found" "$tmp/fz/log" &&
  ok "make fuzz exits 0 when nothing is found" ||
  bad "make fuzz exits 0 when nothing is found (exit $got)" "$(cat "$tmp/fz/log")"
