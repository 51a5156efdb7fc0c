#!/bin/sh
# SPDX-License-Identifier: MIT
# The one test runner. Every suite prints TAP (the Test Anything Protocol:
# "ok N - name", "not ok N - name", "# " diagnostics, a plan "1..N"):
# the cmocka suites with CMOCKA_MESSAGE_OUTPUT=TAP, the fuzz-corpus
# replayers (tests/fuzz/replay.c), the CLI suite (tests/cli/run.sh) and the
# HTTP suites (tests/http/tap.py). This script reads only TAP.
#
#   run-tests.sh --run FILE CMD...    run one suite: its output (stdout and
#       stderr) to FILE; a non-zero exit with no "not ok" line (a crash, a
#       sanitizer report at exit) adds "Bail out!"; print one line for it.
#       Exits 0 whatever the suite did, so that make runs the others.
#   run-tests.sh --report NAME FILE...  read the TAP files: each failing
#       check with its diagnostics, each broken suite (bailed out, no plan,
#       fewer results than planned) with the end of its output, then a
#       closing summary; exit 1 on any failure.
# The Makefile's test target runs every suite with --run (in parallel under
# make -j, each to its own file) and then --report.

# tap_awk BRIEF NAME FILE...: the reader. BRIEF=1: one line per suite;
# BRIEF=0: failures in full and the summary, headed [NAME].
tap_awk() {
  brief=$1; name=$2; shift 2
  awk -v brief="$brief" -v name="$name" '
    function base(f) { sub(/^.*\/tap\//, "", f); sub(/\.tap$/, "", f); return f }
    function tree(f) { sub(/\/tap\/.*$/, "", f); return f }
    function start(f) {
      file = f; plan = -1; n = 0; pass = 0; fail = 0; skip = 0; bail = ""; secs = ""
      details = ""; indetail = 0; nctx = 0
    }
    function finish(   why, i, k) {
      if (file == "") return
      why = ""
      if (bail != "") why = why "; " bail
      if (plan < 0) why = why "; no plan (the suite stopped before its end)"
      else if (plan != n) why = why "; planned " plan ", ran " n
      suites++; tpass += pass; tfail += fail; tskip += skip
      ok = (fail == 0 && why == "")
      if (!ok) badlist = badlist " " base(file)
      if (brief) {
        printf "%-4s %-20s %-32s %4d passed", ok ? "ok" : "FAIL", tree(file), base(file), pass
        if (fail) printf ", %d failed", fail
        if (skip) printf ", %d skipped", skip
        if (why != "") printf " (%s)", substr(why, 3)
        printf "%s\n", secs != "" ? ", " secs : ""
        return
      }
      if (ok) return
      print "---- " base(file) " (" file ")"
      printf "%s", details
      if (why != "") {
        print "  " substr(why, 3) "; the end of its output:"
        k = nctx > 40 ? nctx - 40 : 0
        for (i = k; i < nctx; i++) print "  | " ctx[i % 40]
      }
    }
    FNR == 1 { finish(); start(FILENAME) }
    /^(not )?ok([ \t]|$)/ {
      n++; indetail = 0
      line = $0; up = toupper(line)
      directive = ""
      if (match(up, /[^\\]#[ \t]*(SKIP|TODO)/)) directive = substr(up, RSTART + 1)
      if (directive ~ /^#[ \t]*SKIP/) { skip++; next }
      if (line ~ /^ok/) { pass++; next }
      if (directive ~ /^#[ \t]*TODO/) next
      fail++; indetail = 1
      details = details "  " line "\n"
      next
    }
    /^1\.\.[0-9]+/ { p = $0; sub(/^1\.\./, "", p); plan = p + 0; indetail = 0; next }
    /^Bail out!/ { bail = $0; next }
    /^# time [0-9.]+ s$/ { secs = $3 " s"; next }
    /^#/ { if (indetail) details = details "    " $0 "\n"; next }
    { ctx[nctx % 40] = $0; nctx++ }
    END {
      finish()
      if (brief) exit
      printf "[%s] %d suites: %d checks passed, %d failed, %d skipped\n", name, suites, tpass, tfail, tskip
      if (badlist != "") { printf "[%s] failing:%s\n", name, badlist; exit 1 }
    }' "$@"
}

case $1 in
  --run)
    out=$2; shift 2
    mkdir -p "$(dirname "$out")"
    t0=$(date +%s.%N)
    "$@" >"$out.part" 2>&1 </dev/null; rc=$?
    if [ $rc -ne 0 ] && ! grep -q '^not ok' "$out.part"; then
      echo "Bail out! $(basename "$1") exited with status $rc" >>"$out.part"
    fi
    echo "# time $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }') s" >>"$out.part"
    mv "$out.part" "$out"
    tap_awk 1 "" "$out"
    exit 0 ;;
  --report)
    name=$2; shift 2
    [ $# -gt 0 ] || { echo "run-tests: no TAP files"; exit 1; }
    tap_awk 0 "$name" "$@" ;;
  *)
    echo "usage: run-tests.sh --run FILE CMD... | --report NAME FILE..." >&2
    exit 2 ;;
esac
