# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: bounded time. The ray budget cuts the ray
# trees of nested glass at depth 64 and the render summary says so; an
# implicit surface whose rays run out of evaluations is reported, and a
# 64x48 render of a pathological expression finishes within seconds. Uses
# run.sh's ggrt, tmp, ok and bad.

# expect_summary NAME SECONDS TEXT CMD...: exit 0 within SECONDS (timeout
# 124 otherwise) and TEXT in the summary (stdout) or a warning (stderr).
expect_summary() {
  name=$1; secs=$2; text=$3; shift 3
  timeout "$secs" "$@" >"$tmp/out" 2>"$tmp/err"; got=$?
  if [ "$got" = 0 ] && cat "$tmp/out" "$tmp/err" | grep -qF -- "$text"; then ok "$name"
  else bad "$name (exit $got)" "want: $text
got:  $(cat "$tmp/out" "$tmp/err")"; fi
}

expect_summary "nested glass at depth 64: the ray budget acts and is reported" 60 \
  "ggrt render: warning: the ray budget (1024 rays per eye ray) left " \
  "$ggrt" render tests/data/nested-glass.nff -s 16x12 -o "$tmp/nested.png"
expect_summary "--ray-budget is what the warning names" 60 \
  "ggrt render: warning: the ray budget (50 rays per eye ray) left " \
  "$ggrt" render tests/data/nested-glass.nff -s 16x12 --ray-budget 50 -o "$tmp/nested.png"
"$ggrt" render examples/scenes/glass.nff -s 16x12 -o "$tmp/g.png" >"$tmp/out" 2>&1
grep -q "warning" "$tmp/out" && bad "no budget warning where no budget acts" "$(cat "$tmp/out")" ||
  ok "no budget warning where no budget acts"

# sin(1/x) - sin(1/x) + 1e-3 has no root, but no enclosure of it near x = 0
# shows that: rays crossing x = 0 run out of evaluations.
printf 'v from 3 -3 0.3 at 0 0 0 up 0 0 1 angle 40 resolution 64 48\nl 3 -3 5\n%s\n%s\n' \
  'f 0.9 0.3 0.2 0.7 0.3 40 0 0' \
  'implicit "sin(1/x) - sin(1/x) + 1e-3" -1 -1 -1 1 1 1' > "$tmp/wild.nff"
expect_summary "an implicit surface out of evaluations is reported" 60 \
  "ray tests of implicit surfaces ran out of their evaluation budget" \
  "$ggrt" render "$tmp/wild.nff" -o "$tmp/wild.png"
# x^-1000000000 - 1 ran for minutes: every ray used its
# 100000 evaluations. Now its planes |x| = 1 are found in far fewer.
printf 'v from 0 -4 2 at 0 0 0 up 0 0 1 angle 40 resolution 64 48\nl 3 -3 5\n%s\n%s\n' \
  'f 0.9 0.3 0.2 0.7 0.3 40 0 0' \
  'implicit "x^-1000000000 - 1" -1.4 -1.4 -1.4 1.4 1.4 1.4' > "$tmp/steep.nff"
expect_summary "64x48 of x^-1000000000 - 1 within 20 s, one thread" 20 "rays: eye 3072 (hit " \
  "$ggrt" render "$tmp/steep.nff" -j 1 -o "$tmp/steep.png"
grep -q "evaluation budget" "$tmp/out" && bad "x^-1000000000 - 1 needs no cut" "$(cat "$tmp/out")" ||
  ok "x^-1000000000 - 1 needs no cut"

# An OBJ label is built once per (o, g) pair: 100,000 `g x` lines under
# a 400,000-byte o name copied and hashed it at every line (10,000 lines
# took 5.35 s, 300,000 over 20 s).
python3 -c '
import sys
with open(sys.argv[1], "w") as f:
    f.write("o " + "a" * 400000 + "\n" + "g x\n" * 100000 + "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
' "$tmp/og.obj"
expect_summary "100,000 g lines under a 400,000-byte o name within 10 s" 10 \
  "1 triangles, 3 vertices, normals computed; objects #0..#0, 2 groups" "$ggrt" info "$tmp/og.obj"
