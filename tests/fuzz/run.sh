#!/bin/sh
# SPDX-License-Identifier: MIT
# Run each libFuzzer harness for SECONDS, one after the other, whatever the
# others found, and report on all of them at the end. Exit 1 if any harness
# found something (a crash, leak, timeout or out-of-memory input: its
# artifact is kept) or could not run.
#   sh tests/fuzz/run.sh OUTDIR SECONDS build/fuzz/fuzz_expr ...
# Each harness NAME grows OUTDIR/corpus_NAME from tests/fuzz/corpus/NAME,
# logs to OUTDIR/NAME.log and leaves artifacts as OUTDIR/NAME-crash-*, ...
out=$1; secs=$2; shift 2
mkdir -p "$out"
summary=""; found=0; total=0
for bin in "$@"; do
  name=$(basename "$bin" | sed 's/^fuzz_//')
  total=$((total + 1))
  if [ ! -x "$bin" ]; then
    found=$((found + 1))
    line="$name: did not build (no $bin)"
    echo "fuzz: $line"
    summary="$summary
  $line"
    continue
  fi
  mkdir -p "$out/corpus_$name"
  before=$(ls "$out" | grep "^$name-" | sort)
  echo "fuzz: $name for $secs s (log: $out/$name.log)"
  "$bin" -max_total_time="$secs" -print_final_stats=1 -artifact_prefix="$out/$name-" \
    "$out/corpus_$name" "tests/fuzz/corpus/$name" >"$out/$name.log" 2>&1
  rc=$?
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$out/$name.log" | tail -n 1)
  new=$(ls "$out" | grep "^$name-" | sort | while read -r a; do
    printf '%s\n' "$before" | grep -qxF "$a" || printf ' %s' "$out/$a"; done)
  if [ $rc -eq 0 ] && [ -z "$new" ]; then
    line="$name: nothing found in $secs s (${runs:-?} runs)"
  else
    found=$((found + 1))
    line="$name: FOUND something (exit $rc, ${runs:-?} runs):${new:- no artifact, see the log}"
    tail -n 30 "$out/$name.log" | sed "s/^/  $name| /"
  fi
  echo "fuzz: $line"
  summary="$summary
  $line"
done
echo "fuzz: summary, $total harnesses of $secs s each:$summary"
if [ $found -ne 0 ]; then
  echo "fuzz: $found of $total harnesses found something (logs and artifacts in $out)"
  exit 1
fi
echo "fuzz: nothing found"
