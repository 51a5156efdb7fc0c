# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: bytes (docs/scene-format.md, "Bytes, decided on purpose"). A NUL byte is an
# error at its line and column, a BOM and CR line endings are read, bytes
# that are not UTF-8 appear in messages as \xHH, and the JSON of trace,
# check and find stays valid JSON (python3's json) when a file name, an
# OBJ group or a material name is not UTF-8. Uses run.sh's ggrt, tmp, ok,
# bad and t_args.sh's expect_msg.

by="$tmp/bytes"
mkdir -p "$by"
printf 's 0 0 1\0junk 1\n' >"$by/nul.nff"
expect_msg 2 "ggrt info: $by/nul.nff:1:8: NUL byte in a text file" "a NUL byte inside a number" \
  "$ggrt" info "$by/nul.nff"
printf 'implicit "x^2 + y^2 + z^2 - 1\0 + w" -1 -1 -1 1 1 1\n' >"$by/nul2.nff"
expect_msg 2 "ggrt info: $by/nul2.nff:1:30: NUL byte in a text file" "a NUL byte inside an implicit expression" \
  "$ggrt" info "$by/nul2.nff"
printf '\357\273\277v\rfrom 0 0 5\rat 0 0 0\rup 0 1 0\rangle 40\rresolution 8 6\r\nl 0 5 5\rs 0 0 0 1\r' >"$by/bomcr.nff"
expect_exit 0 "a BOM, CR and CRLF line endings are read" "$ggrt" render "$by/bomcr.nff" -q -o "$by/x.png"
printf 's 0 0 0 1\rs 0 0 \377 1\r' >"$by/cr.nff"
expect_msg 2 "ggrt info: $by/cr.nff:2:7: expected a number after 's', got '\\xFF'" \
  "CR-only lines count as lines; a byte that is not UTF-8 shows as \\xFF" "$ggrt" info "$by/cr.nff"

# A model whose file name, group and material name are not UTF-8.
mtl=$(printf 'm\376.mtl'); obj=$(printf '%s/m\377.obj' "$by")
printf 'newmtl mat\374\nKd 1 0 0\n' >"$by/$mtl"
printf 'mtllib m\376.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\ng gr\375\nusemtl mat\374\nf 1 2 3 4\n' >"$obj"
json_ok() { # NAME FILE KEY=VALUE...: FILE is UTF-8 JSON and has each key with that string value
  name=$1; f=$2; shift 2
  if python3 - "$f" "$@" <<'PY'
import json, sys
doc = json.loads(open(sys.argv[1], encoding="utf-8", errors="strict").read())
found = set()
def walk(x):
    if isinstance(x, dict):
        for k, v in x.items():
            if isinstance(v, str): found.add(k + "=" + v)
            walk(v)
    elif isinstance(x, list):
        for v in x: walk(v)
walk(doc)
for kv in sys.argv[2:]:
    assert kv in found, kv
PY
  then ok "$name"; else bad "$name" "$(head -c 600 "$f")"; fi
}
"$ggrt" trace "$obj" --pixel 256,256 --format json >"$by/t.json" 2>"$tmp/err"
json_ok "trace --format json with names that are not UTF-8 is valid JSON" "$by/t.json" \
  "scene=$by/m\\xFF.obj" 'group=gr\xFD' 'material_name=mat\xFC'
"$ggrt" check "$obj" -s 8x8 --format json >"$by/c.json" 2>"$tmp/err"
json_ok "check --format json with a file name that is not UTF-8 is valid JSON" "$by/c.json" "scene=$by/m\\xFF.obj"
"$ggrt" find "$obj" -s 8x8 --where 'some(kind == eye)' --format json >"$by/f.json" 2>"$tmp/err"
json_ok "find --format json with a file name that is not UTF-8 is valid JSON" "$by/f.json" "scene=$by/m\\xFF.obj"
