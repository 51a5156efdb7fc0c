# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: trace --scene-obj, the scene as OBJ faces, on
# every scene file (tests/cli/scene_obj_check.py: one object each, where the
# renderer hits it), and its refusals. Uses run.sh's ggrt, tmp, ok, bad,
# bulk, expect_exit.

scenes=$(find examples/scenes tests/data/debug \( -name '*.nff' -o -name '*.obj' -o -name '*.ply' \) |
         sort; ls tests/data/*.nff)
# shellcheck disable=SC2086 # one argument per scene file
bulk python3 tests/cli/scene_obj_check.py "$ggrt" $scenes >"$tmp/sobj" 2>&1
while IFS= read -r line; do
  case "$line" in
    "ok   "*) ok "${line#ok   }" ;;
    "FAIL "*) bad "${line#FAIL }" ;;
    "# "*) echo "$line" ;;
    *) bad "scene_obj_check.py: $line" ;;
  esac
done < "$tmp/sobj"
grep -q '^ok' "$tmp/sobj" || bad "scene_obj_check.py ran" "$(cat "$tmp/sobj")"

g=examples/scenes/glass.nff
expect_exit 1 "trace --scene-obj with --diff" "$ggrt" trace $g -p 1,1 --diff --b depth=2 --scene-obj "$tmp/s.obj"
expect_exit 1 "trace --scene-obj onto the scene itself is refused" "$ggrt" trace $g -p 1,1 --scene-obj $g
expect_exit 3 "trace --scene-obj into a missing folder" "$ggrt" trace $g -p 1,1 --scene-obj "$tmp/no/s.obj"

# Rough implicit surfaces: at 64 cells each made over a million triangles
# (eight of them: 436 MB in 13 s). They share a total budget, each
# written coarser with a warning naming it. (sin(150 x) aliases at 48
# cells into a smooth surface, which keeps the check fast.)
for c in 0 0.3 0.6; do
  echo "implicit \"sin(150*x)+sin(150*y)+sin(150*z)+$c\" -1 -1 -1 1 1 1"
done >"$tmp/rough.nff"
expect_msg 0 "warning: --scene-obj: implicit #2 ($tmp/rough.nff:3) would take more than its share" \
  "trace --scene-obj: a rough implicit surface is written coarser, with a warning" \
  "$ggrt" trace "$tmp/rough.nff" -p 8,8 --scene-obj "$tmp/rough.obj"
n=$(grep -c '^f ' "$tmp/rough.obj" 2>/dev/null)
size=$(wc -c <"$tmp/rough.obj" 2>/dev/null)
if [ "${n:-0}" -gt 0 ] && [ "$n" -le 500000 ] && [ "${size:-0}" -lt 30000000 ]; then
  ok "trace --scene-obj: rough surfaces stay within 500000 triangles ($n, $size bytes)"
else
  bad "trace --scene-obj: rough surfaces stay within 500000 triangles" "$n faces, $size bytes"
fi
