# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: outputs (-o, --svg, stdout), cancellation by
# signals and exit codes. Uses run.sh's ggrt, tmp, ok, bad and t_args.sh's
# expect_msg.

g=examples/scenes/glass.nff
mkdir -p "$tmp/o"
printf 'old\n' > "$tmp/o/target.png"
ln -s target.png "$tmp/o/link.png"
expect_msg 3 "refusing to write '$tmp/o/link.png': it is a symbolic link" \
  "-o onto a symbolic link is refused" "$ggrt" render $g -s 8x6 -q -o "$tmp/o/link.png"
[ -L "$tmp/o/link.png" ] && [ "$(cat "$tmp/o/target.png")" = old ] &&
  ok "the link and its target are untouched" || bad "the link and its target are untouched"
printf 'old\n' > "$tmp/o/ro.png"; chmod 444 "$tmp/o/ro.png"
expect_msg 3 "refusing to write '$tmp/o/ro.png': the file is read-only" \
  "-o onto a read-only file is refused (also as root)" "$ggrt" render $g -s 8x6 -q -o "$tmp/o/ro.png"
[ "$(cat "$tmp/o/ro.png")" = old ] && ok "the read-only file is untouched" ||
  bad "the read-only file is untouched"
mkdir "$tmp/o/dir.png"
expect_msg 3 "refusing to write '$tmp/o/dir.png': it is a directory" \
  "-o onto a directory is refused" "$ggrt" render $g -s 8x6 -q -o "$tmp/o/dir.png"
mkfifo "$tmp/o/fifo.svg"
expect_msg 3 "refusing to write '$tmp/o/fifo.svg': it is not a regular file" \
  "--svg onto a FIFO is refused" "$ggrt" trace $g --pixel 1,1 --svg "$tmp/o/fifo.svg"
expect_msg 3 "refusing to write '$tmp/o/link.png': it is a symbolic link" \
  "--obj onto a symbolic link is refused" "$ggrt" trace $g --pixel 1,1 --obj "$tmp/o/link.png"
ls "$tmp/o" | grep -q tmp && bad "refusals leave no temporary file" "$(ls "$tmp/o")" ||
  ok "refusals leave no temporary file"

# The summary's last line times each step, the write too (an OpenEXR
# file can take half as long as the render), for PNG and EXR.
for out in s.png s.exr; do
  "$ggrt" render $g -s 64x48 -o "$tmp/o/$out" >"$tmp/o/sum.out" 2>&1
  grep -Eq '^time: parse [0-9.]+s, prepare [0-9.]+s, render [0-9.]+s \([0-9.]+ Mrays/s\), write [0-9.]+s$' \
    "$tmp/o/sum.out" && ok "render -o $out: the time line has parse, prepare, render and write" ||
    bad "render -o $out: the time line has parse, prepare, render and write" "$(tail -1 "$tmp/o/sum.out")"
done

# A replaced file keeps its permissions (a private one stays private),
# through the library's writer (-o) and the CLI's (plan -o).
printf 'old\n' > "$tmp/o/private.png"; chmod 600 "$tmp/o/private.png"
printf 'old\n' > "$tmp/o/private.json"; chmod 640 "$tmp/o/private.json"
"$ggrt" render $g -s 8x6 -q -o "$tmp/o/private.png" &&
  "$ggrt" plan $g -s 8x6 --tiles 2 --cost rays -o "$tmp/o/private.json" >/dev/null &&
  [ "$(stat -c %a "$tmp/o/private.png")" = 600 ] && [ "$(stat -c %a "$tmp/o/private.json")" = 640 ] &&
  ok "a replaced file keeps its mode (600, 640)" ||
  bad "a replaced file keeps its mode (600, 640)" "$(stat -c '%a %n' "$tmp/o/private."*)"
# Names up to NAME_MAX bytes: the temporary file beside them must fit too.
long=$(printf 'a%.0s' $(seq 240))
"$ggrt" render $g -s 8x6 -q -o "$tmp/o/$long.png" &&
  "$ggrt" plan $g -s 8x6 --tiles 2 --cost rays -o "$tmp/o/$long.json" >/dev/null &&
  [ -s "$tmp/o/$long.png" ] && [ -s "$tmp/o/$long.json" ] &&
  ok "outputs named with 244 bytes are written" || bad "outputs named with 244 bytes are written"
rm -f "$tmp/o/$long.png" "$tmp/o/$long.json"
# Extensions in any case, as ggImageWrite takes them.
"$ggrt" render $g -s 8x6 -q -o "$tmp/o/case.Png" && "$ggrt" render $g -s 8x6 -q -o "$tmp/o/case.EXR" &&
  [ -s "$tmp/o/case.Png" ] && [ -s "$tmp/o/case.EXR" ] &&
  ok "-o x.Png and x.EXR are written" || bad "-o x.Png and x.EXR are written"
# An existing, writable output in a folder that cannot take the new file
# is refused before the work, as a new one is. Root may write anywhere:
# as root, the check runs as nobody through setpriv.
as_user=
if [ "$(id -u)" = 0 ] && command -v setpriv >/dev/null; then
  as_user="setpriv --reuid=65534 --regid=65534 --clear-groups"
fi
if [ "$(id -u)" != 0 ] || [ -n "$as_user" ]; then
  ro=$(mktemp -d /tmp/ggrt-ro-XXXXXX)
  cp $g "$ro/s.nff"; printf 'old\n' > "$ro/own.png"; chmod 666 "$ro/own.png"; chmod 555 "$ro"
  $as_user "$ggrt" render "$ro/s.nff" -s 8x6 -q -o "$ro/own.png" 2>"$tmp/o/ro.err"; rc=$?
  [ $rc = 3 ] && grep -qF "cannot write '$ro/own.png': $ro: Permission denied" "$tmp/o/ro.err" &&
    ok "an existing output in a folder that cannot be written is refused (exit 3)" ||
    bad "an existing output in a folder that cannot be written is refused (exit 3)" "rc $rc: $(cat "$tmp/o/ro.err")"
  chmod 755 "$ro"; rm -rf "$ro"
else
  skip "an existing output in a folder that cannot be written is refused" "root without setpriv"
fi

# --no-srgb decodes what the PNG writer encodes: an EXR's floats are not
# for it, so it is a usage error there, and nothing is written.
expect_err 1 "ggrt render: --no-srgb is for a PNG: -o must end in .png" \
  "render --no-srgb with an .exr is refused" "$ggrt" render $g -s 8x6 -q --no-srgb -o "$tmp/o/ns.exr"
[ ! -e "$tmp/o/ns.exr" ] && ok "render --no-srgb with an .exr writes nothing" ||
  bad "render --no-srgb with an .exr writes nothing"
expect_exit 0 "render --no-srgb to a .png" "$ggrt" render $g -s 8x6 -q --no-srgb -o "$tmp/o/ns.png"

# An output that is also an input is refused before any work (exit 1),
# whatever path names it: merge onto one of its tiles, plan onto its scene.
"$ggrt" render $g -s 16x12 -q --tiles 0-2/3 -o "$tmp/o/part-%d.exr"
cp "$tmp/o/part-0.exr" "$tmp/o/part-0.copy"
expect_err 1 "ggrt merge: -o '$tmp/o/./part-0.exr' is the input '$tmp/o/part-0.exr': writing it would destroy it" \
  "merge -o onto one of its tiles is refused" \
  "$ggrt" merge "$tmp/o/part-0.exr" "$tmp/o/part-1.exr" "$tmp/o/part-2.exr" -o "$tmp/o/./part-0.exr"
cmp -s "$tmp/o/part-0.exr" "$tmp/o/part-0.copy" && ok "merge: the tile is untouched" ||
  bad "merge: the tile is untouched"
cp $g "$tmp/o/scene.nff"
expect_err 1 "ggrt plan: -o '$tmp/o/scene.nff' is the input '$tmp/o/scene.nff': writing it would destroy it" \
  "plan -o onto its scene is refused" "$ggrt" plan "$tmp/o/scene.nff" --tiles 2 -s 16x12 -q -o "$tmp/o/scene.nff"
cmp -s "$tmp/o/scene.nff" $g && ok "plan: the scene is untouched" || bad "plan: the scene is untouched"
# trace's files too: --svg, --obj, --scene-obj, --paths-jsonl and
# --paths-obj on the scene (by another path for some) are refused and the
# scene stays.
# trace_onto OPT FILE [options]
trace_onto() {
  opt=$1; out=$2; shift 2
  expect_err 1 "ggrt trace: $opt '$out' is the input '$tmp/o/scene.nff': writing it would destroy it" \
    "trace $opt onto its scene is refused" \
    "$ggrt" trace "$tmp/o/scene.nff" --pixel 1,1 -s 16x12 "$@" "$opt" "$out"
}
trace_onto --svg "$tmp/o/scene.nff"
trace_onto --obj "$tmp/o/../o/scene.nff"
trace_onto --scene-obj "$tmp/o/./scene.nff"
trace_onto --paths-jsonl "$tmp/o/scene.nff" --path 'C.*L'
trace_onto --paths-obj "$tmp/o/./scene.nff" --path 'C.*L'
cmp -s "$tmp/o/scene.nff" $g && ok "trace: the scene is untouched" || bad "trace: the scene is untouched"
# Two outputs of one command that are one file, by whatever path: refused
# before the work (one would overwrite the other, or the second write fail
# after a whole scan, leaving a file emptied).
expect_err 1 "ggrt find: -o '$tmp/o/same.png' and --overlay '$tmp/o/./same.png' are the same file: one would overwrite the other" \
  "find -o and --overlay onto one file are refused" \
  "$ggrt" find $g -s 16x12 -w 'some(hit)' -o "$tmp/o/same.png" --overlay "$tmp/o/./same.png"
echo keep > "$tmp/o/keep.txt"
expect_exit 1 "find --paths-jsonl and --paths-obj onto one existing file are refused" \
  "$ggrt" find $g -s 16x12 --path 'C.*' --paths-jsonl "$tmp/o/keep.txt" --paths-obj "$tmp/o/../o/keep.txt"
[ "$(cat "$tmp/o/keep.txt")" = keep ] && ok "find: the file named twice is untouched" ||
  bad "find: the file named twice is untouched" "$(cat "$tmp/o/keep.txt")"
expect_exit 1 "trace --svg and --obj onto one file are refused" \
  "$ggrt" trace $g -s 16x12 -p 1,1 --svg "$tmp/o/t.svg" --obj "$tmp/o/t.svg"
mkdir -p "$tmp/o/aov"
expect_exit 1 "render -o onto one of its --aov-png files is refused" \
  "$ggrt" render $g -s 16x12 -q --aov 'main=C<RD>L' --aov-png "$tmp/o/aov" -o "$tmp/o/aov/main.png"
cp $g "$tmp/o/aov/all.png"
expect_exit 1 "render --aov-png onto its scene (named like a layer file) is refused" \
  "$ggrt" render "$tmp/o/aov/all.png" -s 16x12 -q --aov 'all=C.*' --aov-png "$tmp/o/aov" -o "$tmp/o/aov/o.exr"
cmp -s "$tmp/o/aov/all.png" $g && ok "render: that scene is untouched" || bad "render: that scene is untouched"
# Nor may an output be a file the scene reads besides itself: a mesh, its
# material library, a texture (trace --obj models/knot.obj replaced the
# scene's mesh; render -o texture.png its texture).
mkdir -p "$tmp/o/k/models"
cp examples/scenes/knot.nff examples/scenes/texture.nff examples/scenes/texture.png "$tmp/o/k/"
cp examples/scenes/models/knot.obj examples/scenes/models/blob.ply "$tmp/o/k/models/"
cp tests/data/meshes/cube.obj tests/data/meshes/cube.mtl "$tmp/o/k/"
(cd "$tmp/o/k" && md5sum models/knot.obj models/blob.ply texture.png cube.obj cube.mtl) >"$tmp/o/k.md5"
k="$tmp/o/k"
expect_err 1 "ggrt trace: --obj '$k/models/knot.obj' is '$k/models/knot.obj', which the scene reads: writing it would destroy it" \
  "trace --obj onto the scene's mesh is refused" "$ggrt" trace "$k/knot.nff" -s 16x12 -p 8,6 --obj "$k/models/knot.obj"
expect_exit 1 "render -o onto the scene's texture is refused" "$ggrt" render "$k/texture.nff" -s 16x12 -q -o "$k/texture.png"
expect_exit 1 "find --overlay onto the scene's texture by another path is refused" \
  "$ggrt" find "$k/knot.nff" -s 16x12 -q -w 'some(hit)' --overlay "$k/models/../texture.png"
expect_exit 1 "diff -o onto the scene's texture is refused" "$ggrt" diff "$k/knot.nff" -s 8x6 -q --b depth=2 -o "$k/texture.png"
expect_exit 1 "plan -o onto the scene's mesh is refused" "$ggrt" plan "$k/knot.nff" -s 16x12 --tiles 2 -q -o "$k/models/blob.ply"
expect_exit 1 "trace --scene-obj onto a model's material library is refused" \
  "$ggrt" trace "$k/cube.obj" -s 16x12 -p 8,6 --scene-obj "$k/cube.mtl"
# render's other outputs too: a tile, a layer's PNG
printf 'texture "part-1.exr"\ns 0 0 0 1\n' >"$k/tile.nff"
"$ggrt" render "$k/texture.nff" -s 16x12 -q -o "$k/part-1.exr"
cp "$k/part-1.exr" "$k/part-1.copy"
expect_exit 1 "render --tiles onto the scene's texture is refused" \
  "$ggrt" render "$k/tile.nff" -s 16x12 -q --tiles 0-1/2 -o "$k/part-%d.exr"
cmp -s "$k/part-1.exr" "$k/part-1.copy" && ok "render --tiles: the texture is untouched" ||
  bad "render --tiles: the texture is untouched"
mkdir -p "$k/layers" && cp examples/scenes/texture.png "$k/layers/all.png"
printf 'texture "layers/all.png"\ns 0 0 0 1\n' >"$k/layer.nff"
expect_exit 1 "render --aov-png onto the scene's texture is refused" \
  "$ggrt" render "$k/layer.nff" -s 16x12 -q --aov 'all=C.*' --aov-png "$k/layers" -o "$k/l.exr"
cmp -s "$k/layers/all.png" examples/scenes/texture.png && ok "render --aov-png: the texture is untouched" ||
  bad "render --aov-png: the texture is untouched"
(cd "$k" && md5sum -c --quiet "$tmp/o/k.md5") >/dev/null 2>&1 && ok "the scenes' meshes, material library and texture are untouched" ||
  bad "the scenes' meshes, material library and texture are untouched"
# "-" is not standard output here: it would be a file named "-"
gabs=$(cd "$(dirname "$ggrt")" && pwd)/$(basename "$ggrt"); sabs=$(pwd)/$g
(cd "$tmp/o" && "$gabs" plan "$sabs" --tiles 2 -s 16x12 -q -o - >/dev/null 2>&1; echo $? >"$tmp/o/rc1"
 "$gabs" trace "$sabs" -s 16x12 -p 1,1 --svg - >/dev/null 2>&1; echo $? >"$tmp/o/rc2")
if [ "$(cat "$tmp/o/rc1" "$tmp/o/rc2" | tr '\n' ' ')" = "1 1 " ] && [ ! -e "$tmp/o/-" ]; then
  ok "'-' as an output name is refused (plan -o -, trace --svg -): no file named -"
else bad "'-' as an output name is refused" "$(cat "$tmp/o/rc1" "$tmp/o/rc2"; ls "$tmp/o")"; fi
expect_exit 0 "merge onto a new file still works" \
  "$ggrt" merge "$tmp/o/part-0.exr" "$tmp/o/part-1.exr" "$tmp/o/part-2.exr" -q -o "$tmp/o/whole.exr"

# A failed write to stdout or to a file is exit 3 with the reason.
for c in "trace $g --pixel 1,1" "trace $g --pixel 1,1 --format json" "info $g" "render --help" \
         "--version" "optics reflect --v 1,-1,0 --n 0,1,0"; do
  # shellcheck disable=SC2086
  "$ggrt" $c >/dev/full 2>"$tmp/err"; got=$?
  # the prefix names the command: "ggrt optics reflect: ", "ggrt: " for --version
  who=$(printf '%s\n' "$c" | sed 's/ *examples.*//; s/ *--.*//; s/^\(.\)/ \1/')
  if [ $got = 3 ] && grep -qxF "ggrt$who: error writing standard output: No space left on device" "$tmp/err"
  then ok "ggrt $c > /dev/full: exit 3"; else bad "ggrt $c > /dev/full: exit 3 (got $got)" "$(cat "$tmp/err")"; fi
done
# A check that fails (exit 4) whose report is lost: the I/O error wins.
for f in text json; do
  "$ggrt" check tests/data/debug/nan.nff -q -f $f >/dev/full 2>"$tmp/err"; got=$?
  if [ $got = 3 ] && grep -qxF "ggrt check: error writing standard output: No space left on device" "$tmp/err"
  then ok "check -f $f of a failing scene > /dev/full: exit 3, not 4"
  else bad "check -f $f of a failing scene > /dev/full: exit 3, not 4 (got $got)" "$(cat "$tmp/err")"; fi
done
# A file that cannot grow (RLIMIT_FSIZE; SIGXFSZ ignored so write fails with
# EFBIG): the image and the SVG are not written, the old files stay.
printf 'old\n' > "$tmp/o/big.exr"; printf 'old\n' > "$tmp/o/big.svg"
( trap '' XFSZ; ulimit -f 8; "$ggrt" render $g -s 200x150 -q -o "$tmp/o/big.exr" ) 2>"$tmp/err"; got=$?
if [ $got = 3 ] && grep -q "File too large" "$tmp/err" && [ "$(cat "$tmp/o/big.exr")" = old ]; then
  ok "a failed image write: exit 3 with the reason, old file kept"
else bad "a failed image write: exit 3 with the reason, old file kept (exit $got)" "$(cat "$tmp/err")"; fi
( trap '' XFSZ; ulimit -f 8; "$ggrt" trace $g --pixel 110,100 --svg "$tmp/o/big.svg" >/dev/null ) 2>"$tmp/err"; got=$?
if [ $got = 3 ] && grep -q "^ggrt trace: $tmp/o/big.svg: .*File too large" "$tmp/err" &&
   [ "$(cat "$tmp/o/big.svg")" = old ]; then
  ok "a failed --svg write: exit 3 with the reason, old file kept"
else bad "a failed --svg write: exit 3 with the reason, old file kept (exit $got)" "$(cat "$tmp/err")"; fi
ls "$tmp/o" | grep -q tmp && bad "failed writes leave no temporary file" "$(ls "$tmp/o")" ||
  ok "failed writes leave no temporary file"

# Exit codes come from one map (cli_exit_code): a scene error is 2, also
# when the library calls it invalid (a material), and a usage error 1.
printf 'f -1 1 1 1 0 1 0 0\ns 0 0 0 1\n' > "$tmp/badmat.nff"
for c in render trace info; do
  o="-o $tmp/x.png"; [ $c = trace ] && o="--pixel 1,1"; [ $c = info ] && o=""
  # shellcheck disable=SC2086
  expect_msg 2 "badmat.nff:1:3: the colour must not be negative, got -1" "$c: a material error is exit 2 at the f line" "$ggrt" $c "$tmp/badmat.nff" $o
done
expect_msg 1 "pixel 9999,1 is outside the" "trace: a pixel outside the image is exit 1" \
  "$ggrt" trace $g --pixel 9999,1
expect_msg 1 "--pixel 999,1 is outside the 400x300 image" "render: --pixel outside is exit 1" \
  "$ggrt" render $g -o "$tmp/x.png" -s 400x300 --pixel 999,1

# SIGINT and SIGTERM during a render (cancel.py says how).
python3 tests/cli/cancel.py "$ggrt" "$tmp" >"$tmp/cancel" 2>&1
while IFS= read -r line; do
  case "$line" in
    "ok   "*) ok "${line#ok   }" ;;
    *) bad "${line#FAIL }" ;;
  esac
done < "$tmp/cancel"
grep -q . "$tmp/cancel" || bad "cancel.py ran" "no output"

# Heat maps' scales (cli/common/heatmap.h): a count keeps its largest value
# even with a few pixels far over the rest (outlier.nff: 16 rays in a small
# glass sphere's pixels, 1 or 2 elsewhere); a time map says which form it
# took, the largest value or the 99.9th percentile with the pixels over it.
expect_exit 0 "render --heatmap rays on outlier.nff" \
  "$ggrt" render tests/data/outlier.nff --heatmap rays -o "$tmp/heat.png"
if grep -qx "heat map: rays per pixel, 0 to 16" "$tmp/out"; then ok "a rays heat map's scale is its largest count"
else bad "a rays heat map's scale" "$(cat "$tmp/out")"; fi
expect_exit 0 "render --heatmap time" "$ggrt" render $g --heatmap time -j 2 -o "$tmp/heat.png"
if grep -Eqx "heat map: time s per pixel, 0 to [0-9.e+-]+( \(the 99\.9th percentile; [0-9]+ pixels? over it, up to [0-9.e+-]+\))?" "$tmp/out"
then ok "a time heat map names its scale"
else bad "a time heat map's scale" "$(cat "$tmp/out")"; fi

# Usage errors the library finds (a crop window, a sample, a pixel
# outside the image) end with the --help hint, as the parser's do.
for a in "render $g --crop 0,0,9999,9999 -o $tmp/x.png" "trace $g --pixel 10,10 --sample 99" "trace $g --pixel 700,1"; do
  cmd=${a%% *}
  # shellcheck disable=SC2086
  "$ggrt" $a >"$tmp/out" 2>"$tmp/err"; rc=$?
  if [ $rc -eq 1 ] && [ "$(sed -n 2p "$tmp/err")" = "(see 'ggrt $cmd --help')" ] && [ "$(wc -l < "$tmp/err")" -eq 2 ]
  then ok "ggrt $a: exit 1, the message and the hint"
  else bad "ggrt $a (exit $rc)" "$(cat "$tmp/err")"; fi
done

# A NaN pixel reads "nan" in every command's text, as in the tree, the
# JSON and the page (glibc's printf says "-nan" for a negative one).
n=tests/data/debug/nan.nff
{ "$ggrt" trace $n -s 24x18 --pixel 14,12 --path 'C.*'
  "$ggrt" trace $n -s 24x18 --pixel 14,12 --ledger
  "$ggrt" render $n -s 24x18 -q -o "$tmp/o/nan.exr" --pixel 14,12 --aov 'a=C.*' 2>/dev/null
  "$ggrt" find $n -s 24x18 -q --where 'x == 14 && y == 12'
  "$ggrt" diff $n -s 24x18 --b depth=2 --worst 3
  "$ggrt" trace $n -s 24x18 --pixel 14,12 --diff --b depth=2; } >"$tmp/o/nan.txt" 2>&1
if grep -q 'nan inf inf' "$tmp/o/nan.txt" && ! grep -q -- '-nan' "$tmp/o/nan.txt"; then
  ok "a NaN pixel is 'nan' in trace --path, --ledger and --diff, render --pixel, find and diff"
else bad "a NaN pixel is 'nan' in trace --path, --ledger and --diff, render --pixel, find and diff" \
  "$(grep -- '-nan' "$tmp/o/nan.txt" | head -3)"; fi

# A heat map at the size limit (65536 rows: a side's limit) has no room
# for its legend's rows: the map alone, and a note (it was "out of memory
# for the heat map", exit 2, after the whole render).
printf 'v\nfrom 0 -10 0\nat 0 0 0\nup 0 0 1\nangle 30\nhither 0.01\nresolution 8 8\nb 0.2 0.3 0.4\nf 1 1 1 1 0 100000 0 0\ns 1000 1000 1000 0.001\n' >"$tmp/o/empty.nff"
"$ggrt" render "$tmp/o/empty.nff" -s 1x65536 -j 1 --heatmap depth -o "$tmp/o/tall.png" >"$tmp/o/tall.out" 2>&1; rc=$?
if [ $rc = 0 ] && grep -q "no legend under it" "$tmp/o/tall.out" &&
   [ "$(od -An -tx1 -j16 -N8 "$tmp/o/tall.png" | tr -d ' \n')" = 0000000100010000 ]; then
  ok "a heat map 65536 rows high: written without its legend (1x65536), with a note"
else bad "a heat map 65536 rows high: written without its legend, with a note" "rc $rc: $(cat "$tmp/o/tall.out")"; fi

# check --aov-sum with no finite pixel compared nothing: that is no pass
# (it said "ok ... in all 0 pixels", exit 0).
"$ggrt" render tests/data/debug/nan.nff -s 1x1 -q -o "$tmp/o/allnan.exr" --aov 'all=C.*' 2>/dev/null
"$ggrt" check --aov-sum "$tmp/o/allnan.exr" >"$tmp/o/allnan.out" 2>&1; rc=$?
[ $rc = 4 ] && grep -q "^FAIL: no pixel is finite in the image and all its layers" "$tmp/o/allnan.out" &&
  ok "check --aov-sum of an image without a finite pixel fails (exit 4)" ||
  bad "check --aov-sum of an image without a finite pixel fails (exit 4)" "rc $rc: $(cat "$tmp/o/allnan.out")"

# A scene named '-x.nff': the replay line find prints names it ./-x.nff,
# which pastes as a file, not as options.
cp $g "$tmp/o/-dash.nff"
abs=$(cd "$(dirname "$ggrt")" && pwd)/$(basename "$ggrt")
line=$(cd "$tmp/o" && "$abs" find -s 64x48 -q --where 'some(kind==tir)' --limit 1 -- -dash.nff |
  grep -o 'ggrt trace .*')
if [ -n "$line" ] && (cd "$tmp/o" && eval "\"$abs\" ${line#ggrt }" >/dev/null 2>&1); then
  ok "find's replay line for a scene named -dash.nff runs ($line)"
else bad "find's replay line for a scene named -dash.nff runs" "$line"; fi

# Usage errors found after the options are read end with the hint too.
for c in "plan examples/scenes/glass.nff -s 16x48 --tiles 49 -o $tmp/o/p.json" \
         "render examples/scenes/glass.nff -s 16x12 --tile 0/13 -o $tmp/o/t.exr" \
         "trace examples/scenes/glass.nff --pixel 1,1 --svg -" "bench accuracy" \
         "diff examples/scenes/glass.nff -s 8x6 --b size=9x9"; do
  # shellcheck disable=SC2086
  "$ggrt" $c >/dev/null 2>"$tmp/o/hint.err"; rc=$?
  cmd=$(echo "$c" | cut -d' ' -f1); [ "$cmd" = bench ] && cmd="bench accuracy"
  [ $rc = 1 ] && [ "$(tail -1 "$tmp/o/hint.err")" = "(see 'ggrt $cmd --help')" ] &&
    ok "ggrt $c: exit 1 and the hint" || bad "ggrt $c: exit 1 and the hint" "rc $rc: $(cat "$tmp/o/hint.err")"
done

# optics seeds writes each seed whole or not at all (a full disk left an
# empty seed file behind).
( trap '' XFSZ; ulimit -f 0; "$ggrt" optics seeds "$tmp/o/seeds" ) >/dev/null 2>"$tmp/o/seeds.err"; rc=$?
[ $rc = 3 ] && [ -z "$(ls -A "$tmp/o/seeds" 2>/dev/null)" ] &&
  ok "optics seeds on a full disk: exit 3, no seed file left" ||
  bad "optics seeds on a full disk: exit 3, no seed file left" "rc $rc: $(ls -A "$tmp/o/seeds" | head -3)"
