# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: only regular files are read as scenes and
# textures (docs/scene-format.md, "NFF"). A FIFO without a writer, a directory and a
# device get exit 3 and "not a regular file" at once; `timeout` turns a
# block into a failure (exit 124). Uses run.sh's ggrt, tmp, ok, bad and
# t_args.sh's expect_msg.

fl="$tmp/files"
mkdir -p "$fl/dir.nff"
mkfifo "$fl/fifo.nff"
for f in "$fl/fifo.nff" "$fl/dir.nff" /dev/null /dev/zero; do
  expect_msg 3 "ggrt render: $f: not a regular file" "$(basename "$f") as the scene: refused at once" \
    timeout 20 "$ggrt" render "$f" -q -o "$fl/x.png"
  printf 'texture "%s"\ns 0 0 0 1\n' "$f" >"$fl/t.nff"
  expect_msg 3 "ggrt info: $fl/t.nff:1:9: cannot read texture: $f: not a regular file" \
    "$(basename "$f") as a texture: refused at once" timeout 20 "$ggrt" info "$fl/t.nff"
done
[ ! -e "$fl/x.png" ] && ok "refused files leave no image" || bad "refused files leave no image"
