#!/bin/sh
# SPDX-License-Identifier: MIT
# Run the cmocka suites, the fuzz-corpus replayers and the CLI tests built in
# BUILD; print each runner's output and a closing summary. Exit non-zero on
# any failure.
#   run-tests.sh BUILD test_bin... -- replay_bin... -- ggrt
build=$1; shift
tests=""; replays=""; cli=""
while [ $# -gt 0 ] && [ "$1" != "--" ]; do tests="$tests $1"; shift; done
[ $# -gt 0 ] && shift
while [ $# -gt 0 ] && [ "$1" != "--" ]; do replays="$replays $1"; shift; done
[ $# -gt 0 ] && shift
cli=$1

passed=0; failed=0; bad=""
log="$build/test.log"
: > "$log"
for t in $tests; do
  out=$("$t" 2>&1); rc=$?
  printf '%s\n' "$out" | tee -a "$log"
  p=$(printf '%s\n' "$out" | sed -n 's/^\[  PASSED  \] \([0-9]*\) test.*/\1/p' | tail -n 1)
  f=$(printf '%s\n' "$out" | sed -n 's/^\[  FAILED  \] \([0-9]*\) test.*/\1/p' | tail -n 1)
  passed=$((passed + ${p:-0})); failed=$((failed + ${f:-0}))
  if [ $rc -ne 0 ]; then
    [ -z "$f" ] && failed=$((failed + 1))
    bad="$bad $(basename "$t")"
  fi
done
for r in $replays; do
  name=$(basename "$r" | sed 's/^replay_//')
  out=$("$r" "tests/fuzz/corpus/$name" 2>&1); rc=$?
  printf '%s\n' "$out" | tee -a "$log"
  if [ $rc -eq 0 ]; then passed=$((passed + 1)); else failed=$((failed + 1)); bad="$bad replay_$name"; fi
done
if [ -n "$cli" ] && [ -f tests/cli/run.sh ]; then
  out=$(sh tests/cli/run.sh "$cli" 2>&1); rc=$?
  printf '%s\n' "$out" | tee -a "$log"
  p=$(printf '%s\n' "$out" | sed -n 's/^cli: \([0-9]*\) passed.*/\1/p' | tail -n 1)
  f=$(printf '%s\n' "$out" | sed -n 's/^cli: [0-9]* passed, \([0-9]*\) failed.*/\1/p' | tail -n 1)
  passed=$((passed + ${p:-0})); failed=$((failed + ${f:-0}))
  if [ $rc -ne 0 ]; then [ -z "$f" ] || [ "$f" = 0 ] && failed=$((failed + 1)); bad="$bad cli"; fi
fi
# The HTTP tests of ggrt serve: tests/http_test.py (the routes on one
# scene), http_scenes_test.py (every scene), http_slow_test.py (slow clients).
for py in tests/http_test.py tests/http_scenes_test.py tests/http_slow_test.py; do
  [ -n "$cli" ] && [ -f "$py" ] || continue
  out=$(python3 "$py" "$cli" 2>&1); rc=$?
  printf '%s\n' "$out" | tee -a "$log"
  p=$(printf '%s\n' "$out" | sed -n 's/^http: \([0-9]*\) passed.*/\1/p' | tail -n 1)
  f=$(printf '%s\n' "$out" | sed -n 's/^http: [0-9]* passed, \([0-9]*\) failed.*/\1/p' | tail -n 1)
  passed=$((passed + ${p:-0})); failed=$((failed + ${f:-0}))
  if [ $rc -ne 0 ]; then [ -z "$f" ] || [ "$f" = 0 ] && failed=$((failed + 1)); bad="$bad $(basename "$py" .py)"; fi
done
echo "[$build] $passed passed, $failed failed"
if [ $failed -ne 0 ] || [ -n "$bad" ]; then
  echo "[$build] failing:$bad" >&2
  exit 1
fi
