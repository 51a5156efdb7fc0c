# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: only regular files are read as scenes,
# textures (docs/scene-format.md, "NFF"), plans, reports and optics libraries. A FIFO without a writer, a directory and a
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
# The command line's own inputs too: a plan, merge's reports, optics
# check's library (a FIFO here waited for a writer; /dev/zero was read
# up to 256 MiB).
g=examples/scenes/glass.nff
for f in "$fl/fifo.nff" "$fl/dir.nff" /dev/zero; do
  b=$(basename "$f")
  expect_msg 3 "ggrt render: the plan $f: not a regular file" "$b as render --plan: refused at once" \
    timeout 20 "$ggrt" render $g -s 16x12 -q --plan "$f" --tile 0 -o "$fl/t.exr"
  expect_msg 3 "ggrt find: the plan $f: not a regular file" "$b as find --plan: refused at once" \
    timeout 20 "$ggrt" find $g -s 16x12 -w 'some(hit)' --plan "$f" --tile 0/2 -f json
  expect_msg 3 "ggrt merge: $f: not a regular file" "$b as a merge --reports input: refused at once" \
    timeout 20 "$ggrt" merge --reports "$f" -o "$fl/r.json"
done
expect_msg 3 "ggrt optics check: $fl/fifo.nff: not a regular file" \
  "a FIFO as optics check --lib: refused at once" \
  timeout 20 "$ggrt" optics check --lib "$fl/fifo.nff" --symbol x
