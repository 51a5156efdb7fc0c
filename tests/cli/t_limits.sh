# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: bounded memory (docs/scene-format.md, "NFF"). Small
# hostile inputs fail fast with the limit and the value in the message, and
# none makes ggrt use more than 1 GB: each runs under `ulimit -v` 1 GiB
# (address space, which is more than resident memory), and its peak RSS is
# printed. Under ASan (build/asan) the same messages are checked without
# the ulimit, which ASan's shadow memory cannot run under.
# Uses run.sh's ggrt, tmp, ok and bad.

lim="$tmp/limits"
mkdir -p "$lim/out"
python3 tests/data/hostile.py "$lim" --full
case $ggrt in */asan/*) asan=1 ;; *) asan= ;; esac

# under_1g CODE TEXT NAME CMD...: exit code and message, under 1 GiB of
# address space; the name gets the peak RSS.
under_1g() {
  want=$1; text=$2; name=$3; shift 3
  if [ -n "$asan" ]; then
    "$@" >/dev/null 2>"$tmp/err"; got=$?; mb="?"
  else
    (ulimit -v 1048576 && python3 -c '
import resource, subprocess, sys
rc = subprocess.run(sys.argv[2:], stdout=subprocess.DEVNULL, stderr=open(sys.argv[1], "w")).returncode
print(rc, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss // 1024)' "$tmp/err" "$@") >"$tmp/rss"
    read -r got mb <"$tmp/rss"
  fi
  # An empty TEXT: nothing on stderr at all.
  if [ "$got" = "$want" ] && if [ -z "$text" ]; then [ ! -s "$tmp/err" ]; else grep -qF -- "$text" "$tmp/err"; fi
  then ok "$name (peak RSS $mb MB)"
  else bad "$name (exit $got, want $want; peak RSS $mb MB)" "want: $text
got:  $(cat "$tmp/err")"; fi
}

lim_head() { printf 'v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 32 24\nl 1 1 5\n'; }

# A 70-byte scene asking for a 16384 x 16384 image; the same asked by -s.
printf 'v from 0 0 1 at 0 0 0 up 0 1 0 angle 45 resolution 16384 16384\ns 0 0 0 1\n' >"$lim/res.nff"
under_1g 2 "res.nff:1:41: resolution 16384x16384 exceeds the limit of 16777216 pixels" \
  "a $(wc -c <"$lim/res.nff")-byte scene asking for 16384x16384" \
  "$ggrt" render "$lim/res.nff" -q -o "$lim/out/res.png"
under_1g 1 "bad value '16384x16384' for --size: expected WxH, two whole numbers from 1 to 65536, at most 16777216 pixels (16384x16384 is 268435456 pixels)" \
  "render -s 16384x16384" "$ggrt" render examples/scenes/glass.nff -s 16384x16384 -q -o "$lim/out/s.png"
under_1g 1 "bad value '16384x16384' for --size: expected WxH, two whole numbers from 1 to 65536, at most 16777216 pixels (16384x16384 is 268435456 pixels)" \
  "check -s 16384x16384" "$ggrt" check examples/scenes/glass.nff -s 16384x16384
[ -z "$(ls "$lim/out")" ] && ok "refused sizes leave no image and no *.tmp* file" ||
  bad "refused sizes leave no image and no *.tmp* file" "$(ls "$lim/out")"

# Textures: small files declaring 16384 x 16384, a lying chunk length.
for f in big.png big.exr; do
  { lim_head; printf 'f 1 1 1 1 0 0 0 0\ntexture "%s"\nrect -1 -1 0 2 0 0 0 2 0\n' $f; } >"$lim/t_$f.nff"
  under_1g 2 "t_$f.nff:10:9: cannot read texture: $lim/$f: image of 16384 x 16384 pixels exceeds the limit (65536 per side, 16777216 pixels)" \
    "a $(wc -c <"$lim/$f")-byte $f declaring 16384x16384" "$ggrt" render "$lim/t_$f.nff" -q -o "$lim/out/t.png"
done
{ lim_head; printf 'texture "lie.png"\nrect -1 -1 0 2 0 0 0 2 0\n'; } >"$lim/lie.nff"
under_1g 2 "lie.nff:9:9: cannot read texture: $lim/lie.png: invalid PNG: truncated file" \
  "a PNG whose IDAT length says 2 GB" "$ggrt" render "$lim/lie.nff" -q -o "$lim/out/t.png"

# One texture decoding to 1 MB named 250 times: decoded once.
{ lim_head; i=0; while [ $i -lt 250 ]; do printf 'texture "tex1m.png"\ns %d 0 0 0.5\n' $i; i=$((i + 1)); done; } \
  >"$lim/many.nff"
under_1g 0 "" "a 1 MB-decoded texture named 250 times" "$ggrt" render "$lim/many.nff" -q -o "$lim/out/m.png"
if [ -z "$asan" ] && [ "${mb:-999}" -lt 100 ]; then ok "... decoded once: peak RSS $mb MB < 100 MB"
elif [ -z "$asan" ]; then bad "... decoded once: peak RSS $mb MB < 100 MB"; fi

# The largest image the limits allow (4096 x 4096, 192 MiB decoded) is
# read; a second file of that size is over the 256 MiB texture budget.
{ lim_head; printf 'texture "full_a.png"\nrect -1 -1 0 2 0 0 0 2 0\n'; } >"$lim/full.nff"
under_1g 0 "" "a 4096x4096 texture ($(wc -c <"$lim/full_a.png") bytes)" \
  "$ggrt" render "$lim/full.nff" -q -o "$lim/out/f.png"
{ cat "$lim/full.nff"; printf 'texture "full_b.png"\ns 0 0 0 1\n'; } >"$lim/full2.nff"
under_1g 2 "full2.nff:11:9: cannot read texture: $lim/full_b.png: 4096 x 4096 pixels decode to 201326592 bytes, over the texture budget (67108864 bytes left of 268435456)" \
  "two 4096x4096 textures: the second is over the budget" \
  "$ggrt" render "$lim/full2.nff" -q -o "$lim/out/f2.png"

# One 20000-triangle OBJ (435 KB) named 200 times: refused when repeats
# pass GG_MESH_REPEAT_MAX (was 1354 MB for ggrt info). Release build only:
# loading 2 million triangles takes a while under ASan.
if [ -z "$asan" ]; then
  python3 -c '
import sys
n = 100
with open(sys.argv[1], "w") as f:
    for j in range(n + 1):
        for i in range(n + 1): f.write("v %d %d 0\n" % (i, j))
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i + 1
            f.write("f %d %d %d\nf %d %d %d\n" % (a, a + 1, a + n + 2, a, a + n + 2, a + n + 1))' "$lim/g.obj"
  i=0; while [ $i -lt 200 ]; do echo 'mesh "g.obj"'; i=$((i + 1)); done >"$lim/gm.nff"
  under_1g 2 "gm.nff:106:6: mesh: $lim/g.obj: named again: at 20008 triangles' worth (20000 triangles, its records and names) it would bring the meshes named more than once to 2100840, over the limit of 2097152" \
    "a $(wc -c <"$lim/g.obj")-byte OBJ named 200 times" "$ggrt" info "$lim/gm.nff"
  # The same file under 200 names (g.obj, ./g.obj, ././g.obj, then links):
  # the limit counts files, not spellings (compared as strings, 250
  # spellings of a 193 KB PLY took 997 MB).
  { echo 'mesh "g.obj"'; echo 'mesh "./g.obj"'; echo 'mesh "././g.obj"'; i=4
    while [ $i -le 200 ]; do ln -sf g.obj "$lim/l$i.obj"; echo "mesh \"l$i.obj\""; i=$((i + 1)); done
  } >"$lim/gs.nff"
  under_1g 2 "gs.nff:106:6: mesh: $lim/l106.obj: named again: at 20008 triangles' worth (20000 triangles, its records and names) it would bring the meshes named more than once to 2100840, over the limit of 2097152" \
    "one OBJ named 200 times under 200 spellings" "$ggrt" info "$lim/gs.nff"
fi

# A one-triangle OBJ named 300,000 times (4.2 MB): each line searched
# the meshes before it, 80,000 lines took 185 s; the first of a file is
# now found by hashing, and each repeat costs its records (8 triangles'
# worth). Under a KILL at 60 s.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$lim/t1.obj"
python3 -c '
import sys
open(sys.argv[1], "w").write("mesh \"t1.obj\"\n" * 300000)' "$lim/t1.nff"
under_1g 2 "t1.nff:233018:6: mesh: $lim/t1.obj: named again: at 9 triangles' worth (1 triangle, its records and names) it would bring the meshes named more than once to 2097153, over the limit of 2097152" \
  "a one-triangle OBJ named 300,000 times" timeout -s KILL 60 "$ggrt" info "$lim/t1.nff"
# The same with a 100,000-byte o name, named 20,000 times (2 GB of
# names): each repeat counts its names too.
python3 -c '
import sys
open(sys.argv[1], "w").write("o " + "n" * 100000 + "\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")' "$lim/tn.obj"
i=0; while [ $i -lt 20000 ]; do echo 'mesh "tn.obj"'; i=$((i + 1)); done >"$lim/tn.nff"
under_1g 2 "tn.nff:5258:6: mesh: $lim/tn.obj: named again: at 399 triangles' worth (1 triangle, its records and names) it would bring the meshes named more than once to 2097543, over the limit of 2097152" \
  "a one-triangle OBJ with a 100,000-byte name named 20,000 times" timeout -s KILL 60 "$ggrt" info "$lim/tn.nff"

# One 400,000-byte o name and 10,000 g names (559 KB): every (o, g) pair
# stored its whole label, 4 GB (500 names took 200 MB). The labels may
# pass the file's size by 16 MiB (GG_MESH_LABELS_MAX).
python3 -c '
import sys
with open(sys.argv[1], "w") as f:
    f.write("o " + "a" * 400000 + "\nv 0 0 0\nv 1 0 0\nv 0 1 0\n")
    f.write("".join("g g%d\nf 1 2 3\n" % i for i in range(10000)))' "$lim/og.obj"
under_1g 2 "og.obj:89:3: the group labels would pass $(($(wc -c <"$lim/og.obj") + 16777216)) bytes, the file's size plus 16 MiB" \
  "a $(wc -c <"$lim/og.obj")-byte OBJ of one long o name and 10,000 g names" "$ggrt" info "$lim/og.obj"

# Scenes without bound: a huge sparse file, /dev/zero.
: >"$lim/sparse.nff"
if truncate -s 100G "$lim/sparse.nff" 2>/dev/null; then
  under_1g 2 "sparse.nff: 107374182400 bytes exceed the limit of 268435456" \
    "a 100 GB sparse scene file" "$ggrt" render "$lim/sparse.nff" -q -o "$lim/out/z.png"
fi
rm -f "$lim/sparse.nff"
under_1g 3 "ggrt render: /dev/zero: not a regular file" "/dev/zero as the scene" \
  "$ggrt" render /dev/zero -q -o "$lim/out/z.png"
# Options whose recorded ray trees could not fit: refused before any
# work, in each command that records them (a trace at -n 4096
# --ray-budget 16777216 grew past 6.8 GB).
big="-s 1x1 -n 4096 -d 64 --ray-budget 16777216"
for c in "trace -p 0,0" "find -w some(hit)" "check" "diff --b depth=3"; do
  # shellcheck disable=SC2086 # the command and its options
  under_1g 1 "ggrt ${c%% *}: the ray trees of one pixel could take" \
    "${c%% *}: trees that could not fit are refused before the work" \
    "$ggrt" $c tests/data/nested-glass.nff $big
done
# The bound counts the scene's depth and the children a hit can have in
# it: a mirror has one, so 50,000 lights and no glass fit at depth 5 (5
# nodes, 34 MiB a pixel); it took depth 0 as none and four children a hit
# (the ray budget's 1025 nodes, 7039 MiB).
awk 'BEGIN { print "v\nfrom 0 -10 5\nat 0 0 0\nup 0 0 1\nangle 40\nhither 0.01\nresolution 2 2"
  for (i = 0; i < 50000; i++) printf "l %d %d %d 0.002 0.002 0.002\n", i % 40 - 20, int(i / 40) % 40 - 20, 5 + i % 7
  print "f 0.8 0.7 0.6 0.8 0.2 10 0 0\ns 0 0 1 1\np 4\n-5 -5 0\n5 -5 0\n5 5 0\n-5 5 0" }' >"$lim/lights.nff"
for c in "trace -p 1,1" "find -q -w some(hit)" "check -q" "diff -q --b depth=5"; do
  # shellcheck disable=SC2086 # the command and its options
  expect_exit 0 "${c%% *}: 50,000 lights and a mirror: the trees' bound lets it run" \
    "$ggrt" $c "$lim/lights.nff"
done
rm -f "$lim/lights.nff"
rm -f "$lim/out/m.png" "$lim/out/f.png"
[ -z "$(ls "$lim/out")" ] && ok "failed loads leave no image and no *.tmp* file" ||
  bad "failed loads leave no image and no *.tmp* file" "$(ls "$lim/out")"

# A scene spanning less than GG_SCENE_SIZE_MIN (1e-60): refused when it is
# prepared, the file named (renders of it were wrong without a word).
cat > "$lim/tiny.nff" <<'NFF'
v
from 0 -5e-70 3e-70
at 0 0 0
up 0 0 1
angle 40
hither 1e-72
resolution 32 32
l 1e-70 -1e-70 2e-70
f 1 0 0 1 0 0 0 1
s 0 0 0 1e-70
NFF
expect_err 2 "ggrt render: $lim/tiny.nff: preparing the scene: its objects and the camera's eye span only 6e-70, under 1e-60 (GG_SCENE_SIZE_MIN), where intersection tests underflow; scale it up" \
  "a scene under GG_SCENE_SIZE_MIN is refused, the file named" "$ggrt" render "$lim/tiny.nff" -o "$lim/out/tiny.png"
