# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: the trace JSON of version 2 (docs/trace-json.md).
# `weight` means one thing everywhere -- the
# factor a ray's colour is multiplied by in the pixel. For every ray of a
# few pixels (glass: refraction and TIR; water: absorption; gears with 4
# samples; the knot mesh), the trace JSON's `weight` is exactly what
# ggrt find's `weight` field sees: `some(id-like match && weight.r == W)`
# matches that pixel for each node's own W. Uses run.sh's ggrt, tmp, ok, bad.
for spec in "examples/scenes/glass.nff 110,100" "examples/scenes/water.nff 240,250" \
            "examples/scenes/spd/gears.nff 250,260 -n 4" "examples/scenes/knot.nff 200,150"; do
  set -- $spec
  scene=$1; pix=$2; shift 2
  x=${pix%,*}; y=${pix#*,}
  "$ggrt" trace "$scene" --pixel "$pix" --format json "$@" >"$tmp/w.json" 2>"$tmp/err" ||
    { bad "weight: trace $scene $pix" "$(cat "$tmp/err")"; continue; }
  # One predicate per ray: its kind, depth, sample-independent place and
  # its weight's three channels, printed with 17 digits (exact doubles).
  python3 - "$tmp/w.json" >"$tmp/w.preds" <<'EOF'
import json, sys
doc = json.load(open(sys.argv[1]))
def walk(n):
    yield n
    for k in n["children"]:
        yield from walk(k)
for r in doc["roots"]:
    for n in walk(r):
        w = n["weight"]
        if any(isinstance(c, str) for c in w):
            continue
        print("some(kind == %s && depth == %d && weight.r == %.17g && weight.g == %.17g && weight.b == %.17g)"
              % (n["kind"], n["depth"], w[0], w[1], w[2]))
EOF
  total=0; missed=""
  while IFS= read -r pred; do
    total=$((total + 1))
    "$ggrt" find "$scene" "$@" --crop "$x,$y,$((x + 1)),$((y + 1))" --where "$pred" -f json -q \
      >"$tmp/w.find" 2>&1
    grep -q '"matched":1' "$tmp/w.find" || missed="$missed
$pred"
  done <"$tmp/w.preds"
  if [ "$total" -gt 0 ] && [ -z "$missed" ]; then
    ok "weight: trace JSON's weight is find's weight for all $total rays of $scene $pix $*"
  else
    bad "weight: trace JSON's weight is find's weight for all rays of $scene $pix $* ($total)" "$missed"
  fi
done

# Non-finite values: the trace JSON writes them as "nan", "inf", "-inf"
# (docs/trace-json.md, version 2), strict JSON, and as the text does.
# nan.nff's pixel 16,15 is NaN in red and infinite in green and blue.
"$ggrt" trace tests/data/debug/nan.nff --pixel 16,15 --format json >"$tmp/nf.json" 2>"$tmp/err" &&
  "$ggrt" trace tests/data/debug/nan.nff --pixel 16,15 >"$tmp/nf.txt" 2>>"$tmp/err"
if python3 - "$tmp/nf.json" "$tmp/nf.txt" >"$tmp/nf.out" 2>&1 <<'EOF'
import json, sys
def refuse(name):
    raise ValueError("not strict JSON: " + name)
doc = json.load(open(sys.argv[1]), parse_constant=refuse)
text = open(sys.argv[2]).read().splitlines()
assert doc["color"] == ["nan", "inf", "inf"], doc["color"]
assert text[1] == "colour nan inf inf", text[1]
root = doc["roots"][0]
assert root["color"][0] == "nan" and root["contribution"][0] == "nan", root["color"]
assert "nan" in doc["ledger"]["pixel"], doc["ledger"]["pixel"]
assert root["hit"]["numeric"]["edge"] is None  # null: does not apply (a sphere)
EOF
then ok "trace JSON: NaN and infinity as \"nan\"/\"inf\" (strict JSON); the text says nan inf inf"
else bad "trace JSON: NaN and infinity as \"nan\"/\"inf\" (strict JSON); the text says nan inf inf" "$(cat "$tmp/nf.out" "$tmp/err")"; fi
