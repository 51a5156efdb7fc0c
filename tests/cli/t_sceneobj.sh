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
