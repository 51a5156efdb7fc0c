#!/bin/sh
# SPDX-License-Identifier: MIT
# End-to-end tests of the ggrt command line. Run from the repository root:
#   sh tests/cli/run.sh build/ggrt
# Prints TAP (tests/run-tests.sh reads it): "ok N - name" or "not ok N -
# name" and the details as "# " lines, per check; the plan "1..N" last.
# GG_TEST_SAMPLE=N (the ASan tree sets 8, the clang tree 4): the loops over every scene times
# every expression or layer left out take one combination in N, rotating,
# so that each scene and each expression is still run, and t_tiles.sh and
# t_reports.sh cut each scene fewer ways, every path still taken; 1
# (default) takes them all.
ggrt=$1
sample=${GG_TEST_SAMPLE:-1}
[ -x "$ggrt" ] || { echo "not ok 1 - no ggrt binary at '$ggrt'"; echo "1..1"; exit 1; }
tmp=$(mktemp -d /tmp/ggrt-cli-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
pass=0; fail=0; tap_n=0

# A TAP description: '#' would start a directive, so it is escaped.
tap_desc() { case $1 in *'#'*) printf '%s' "$1" | sed 's/#/\\#/g' ;; *) printf '%s' "$1" ;; esac; }
ok()   { pass=$((pass + 1)); tap_n=$((tap_n + 1)); printf 'ok %d - %s\n' $tap_n "$(tap_desc "$1")"; }
bad()  { fail=$((fail + 1)); tap_n=$((tap_n + 1)); printf 'not ok %d - %s\n' $tap_n "$(tap_desc "$1")"
         [ -n "$2" ] && printf '%s\n' "$2" | sed 's/^/# /'; }
# skip NAME REASON: a check this machine cannot run.
skip() { tap_n=$((tap_n + 1)); printf 'ok %d - %s # SKIP %s\n' $tap_n "$(tap_desc "$1")" "$2"; }

# expect_exit CODE NAME CMD...: run CMD, check its exit code.
expect_exit() {
  want=$1; name=$2; shift 2
  "$@" >"$tmp/out" 2>"$tmp/err"; got=$?
  if [ "$got" = "$want" ]; then ok "$name"; else bad "$name (exit $got, want $want)" "$(cat "$tmp/err")"; fi
}

# expect_msg CODE TEXT NAME CMD...: exit code, and TEXT somewhere on stderr.
# (Here, not in a part: parts sourced before t_args.sh use it too.)
expect_msg() {
  want=$1; text=$2; name=$3; shift 3
  "$@" >"$tmp/out" 2>"$tmp/err"; got=$?
  if [ "$got" = "$want" ] && grep -qF -- "$text" "$tmp/err"; then ok "$name"
  else bad "$name (exit $got, want $want)" "want: $text
got:  $(cat "$tmp/err")"; fi
}

# expect_err CODE MESSAGE NAME CMD...: exit code and an exact stderr line.
# bulk CMD...: a checker that runs ggrt hundreds of times (a trace per
# pixel, a find per scene and expression). Under AddressSanitizer its
# processes skip LeakSanitizer's scan at exit, 36 of the 95 ms such a
# process takes: the same commands are leak-checked elsewhere in the suite.
bulk() { ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" "$@"; }

expect_err() {
  want=$1; msg=$2; name=$3; shift 3
  "$@" >"$tmp/out" 2>"$tmp/err"; got=$?
  if [ "$got" = "$want" ] && grep -qxF "$msg" "$tmp/err"; then ok "$name"
  else bad "$name (exit $got, want $want)" "want: $msg
got:  $(cat "$tmp/err")"; fi
}

# ---- usage and help ----
expect_exit 0 "ggrt --help" "$ggrt" --help
expect_exit 1 "ggrt with no command" "$ggrt"
expect_exit 1 "unknown command" "$ggrt" frobnicate
expect_exit 1 "unknown top-level option" "$ggrt" --bogus
expect_exit 1 "unknown top-level short option" "$ggrt" -x
expect_exit 1 "--version with an argument" "$ggrt" --version extra
expect_exit 0 "ggrt --version" "$ggrt" --version
for c in render trace info optics bench; do
  expect_exit 0 "ggrt $c --help" "$ggrt" $c --help
done
expect_exit 1 "render without -o" "$ggrt" render examples/scenes/glass.nff
expect_exit 1 "render with a bad size" "$ggrt" render examples/scenes/glass.nff -o "$tmp/x.png" -s 12by4
expect_exit 1 "render to an unknown format" "$ggrt" render examples/scenes/glass.nff -o "$tmp/x.bmp"

# ---- bad input: file:line:col, exit 2; I/O: exit 3; never a crash ----
expect_err 3 "ggrt render: $tmp/none.nff: No such file or directory" "missing scene" \
  "$ggrt" render "$tmp/none.nff" -o "$tmp/x.png"
printf 'f 1 1 1 1 0 1 0 0\ns 0 0 0 1\ns 1 2\n' > "$tmp/trunc.nff"
expect_err 2 "ggrt render: $tmp/trunc.nff:4:1: expected a number after 's', got end of file" \
  "truncated scene" "$ggrt" render "$tmp/trunc.nff" -o "$tmp/x.png"
printf 'p 4\n0 0 0\n1 0 0\n1 1 0\ns 0 0 0 1\n' > "$tmp/count.nff"
expect_err 2 "ggrt render: $tmp/count.nff:5:1: expected a number after 'p', got 's'" \
  "wrong vertex count" "$ggrt" render "$tmp/count.nff" -o "$tmp/x.png"
printf 's 0 0 zero 1\n' > "$tmp/nonnum.nff"
expect_err 2 "ggrt render: $tmp/nonnum.nff:1:7: expected a number after 's', got 'zero'" \
  "not a number" "$ggrt" render "$tmp/nonnum.nff" -o "$tmp/x.png"
printf 'l 0 0 NaN\n' > "$tmp/nan.nff"
expect_err 2 "ggrt render: $tmp/nan.nff:1:7: expected a number after 'l', got 'NaN'" \
  "NaN" "$ggrt" render "$tmp/nan.nff" -o "$tmp/x.png"
printf 'v from 0 0 1 at 0 0 0 up 0 1 0 angle 45 resolution 99999999 2\n' > "$tmp/huge.nff"
expect_err 2 "ggrt render: $tmp/huge.nff:1:52: a width after 'resolution' must be a whole number from 1 to 65536, got 99999999" \
  "huge resolution" "$ggrt" render "$tmp/huge.nff" -o "$tmp/x.png"
printf 'f 1 1 1 1 0 1 0 0\ntexture "nowhere.png"\ns 0 0 0 1\n' > "$tmp/tex.nff"
expect_err 3 "ggrt render: $tmp/tex.nff:2:9: cannot read texture: ${tmp}/nowhere.png: No such file or directory" \
  "missing texture" "$ggrt" render "$tmp/tex.nff" -o "$tmp/x.png"
expect_exit 3 "unwritable output" "$ggrt" render examples/scenes/glass.nff -s 8x6 -q -o /nonexistent/dir/x.png
[ ! -e "$tmp/x.png" ] && ok "failed renders leave no image" || bad "failed renders leave no image"

# ---- render ----
expect_exit 0 "render PNG" "$ggrt" render examples/scenes/glass.nff -s 80x60 -q -o "$tmp/g.png"
expect_exit 0 "render EXR" "$ggrt" render examples/scenes/glass.nff -s 80x60 -q -o "$tmp/g.exr"
[ -s "$tmp/g.png" ] && [ -s "$tmp/g.exr" ] && ok "images written" || bad "images written"
ls "$tmp" | grep -q tmp && bad "no temporary files left" "$(ls "$tmp")" || ok "no temporary files left"

# ---- info ----
"$ggrt" info examples/scenes/water.nff >"$tmp/info" 2>&1
if grep -q "absorption" "$tmp/info" && grep -q "water.nff:" "$tmp/info" && grep -q "bvh" "$tmp/info"; then
  ok "info lists effects with reasons"; else bad "info lists effects with reasons" "$(cat "$tmp/info")"; fi

# ---- trace ----
# check_pixel SCENE X,Y [options]: the traced colour equals the rendered
# pixel bit for bit, the tree's ray counts equal the renderer's for that
# pixel, and the JSON follows docs/trace-json.md.
check_pixel() {
  scene=$1; pix=$2; shift 2
  x=${pix%,*}; y=${pix#*,}
  "$ggrt" trace "$scene" --pixel "$pix" --format json "$@" >"$tmp/t.json" 2>"$tmp/err" ||
    { bad "trace $scene $pix" "$(cat "$tmp/err")"; return; }
  # --sample is the trace's own; the render takes every other option.
  ropts=$(echo "$*" | sed 's/--sample [0-9]*//')
  "$ggrt" render "$scene" -o "$tmp/p.exr" --pixel "$pix" --crop "$x,$y,$((x + 1)),$((y + 1))" $ropts \
    >"$tmp/r.txt" 2>"$tmp/err" || { bad "render $scene $pix" "$(cat "$tmp/err")"; return; }
  if python3 tests/cli/check_trace.py "$tmp/t.json" "$tmp/r.txt" >"$tmp/py" 2>&1; then
    ok "trace $scene $pix $*: colour, counts and schema"
  else
    bad "trace $scene $pix $*: colour, counts and schema" "$(cat "$tmp/py")"
  fi
}
check_pixel examples/scenes/glass.nff 200,150
check_pixel examples/scenes/glass.nff 200,150 -n 4
check_pixel examples/scenes/glass.nff 200,150 -n 4 --sample 2
check_pixel examples/scenes/water.nff 240,250
check_pixel examples/scenes/prism.nff 270,150
check_pixel examples/scenes/gold.nff 120,150
check_pixel examples/scenes/torus.nff 200,140
# a shadow ray through the kt 1 sphere (visible, all of the light) and
# one dimmed only by the glass around it (attenuated, no occluder)
check_pixel examples/scenes/glass.nff 187,19
check_pixel tests/data/light-in-glass.nff 16,12
check_pixel examples/scenes/spd/gears.nff 250,260
check_pixel examples/scenes/spd/mount.nff 256,300 --spd
check_pixel examples/scenes/spd/balls-s3.nff 300,200

# A pixel on the glass sphere: refraction, TIR and the exit ray.
"$ggrt" trace examples/scenes/glass.nff --pixel 110,100 --ascii >"$tmp/glass.txt" 2>&1
if grep -q "refract #" "$tmp/glass.txt" && grep -q "^.*tir #" "$tmp/glass.txt" &&
   grep -q "back face" "$tmp/glass.txt"; then
  ok "glass pixel shows refraction, TIR and the exit"
else bad "glass pixel shows refraction, TIR and the exit" "$(head -60 "$tmp/glass.txt")"; fi

# A pixel in shadow names its occluder (the matte sphere of default.nff).
"$ggrt" trace examples/scenes/default.nff --pixel 180,280 --ascii >"$tmp/sh.txt" 2>&1
if grep -q "blocked by sphere #[0-9]* (examples/scenes/default.nff:[0-9]*)" "$tmp/sh.txt"; then
  ok "shadowed pixel names the occluder"
else bad "shadowed pixel names the occluder" "$(head -40 "$tmp/sh.txt")"; fi

expect_exit 0 "trace --svg --obj" "$ggrt" trace examples/scenes/glass.nff --pixel 110,100 \
  --svg "$tmp/t.svg" --obj "$tmp/t.obj"
if python3 -c "import sys, xml.dom.minidom; xml.dom.minidom.parse(sys.argv[1])" "$tmp/t.svg" 2>/dev/null &&
   grep -q "^l 1 2" "$tmp/t.obj"; then ok "SVG parses as XML, OBJ has lines"; else bad "SVG parses as XML, OBJ has lines"; fi
expect_exit 1 "trace pixel outside the image" "$ggrt" trace examples/scenes/glass.nff --pixel 9999,1

# ggrt serve opens libmicrohttpd when it starts (cli/serve/serve_http.c):
# ggrt does not need it, so no other command loads it and its TLS
# libraries (5 ms of every start).
if readelf -d "$ggrt" | grep -q 'NEEDED.*libmicrohttpd'; then
  bad "ggrt does not link libmicrohttpd (serve opens it)" "$(readelf -d "$ggrt" | grep NEEDED)"
else ok "ggrt does not link libmicrohttpd (serve opens it)"; fi

# The other parts: each tests/cli/t_*.sh, sourced here (they share the
# counters and helpers above), each with its seconds as a TAP comment.
for part in tests/cli/t_*.sh; do
  part_t0=$(date +%s)
  [ -f "$part" ] && . "./$part"
  echo "# $part: $(($(date +%s) - part_t0)) s"
done

echo "1..$tap_n"
echo "# cli: $pass passed, $fail failed"
[ "$fail" = 0 ]
