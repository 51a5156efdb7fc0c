# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: the rough edges a new user hit (issue 30,
# item 5), one section each. Uses run.sh's ggrt, tmp, ok, bad and
# t_args.sh's expect_msg.

ed="$tmp/edges"
mkdir -p "$ed"
g=examples/scenes/glass.nff
printf 's 0 0 zero 1\n' >"$ed/bad.nff"

# prefixed PREFIX NAME CMD...: CMD fails, every stderr line that starts
# with "ggrt" starts with "PREFIX: ", the first line does, and no library
# function name ("ggDiff: ") appears.
prefixed() {
  want=$1; name=$2; shift 2
  "$@" >"$ed/out" 2>"$ed/err"; got=$?
  if [ $got != 0 ] && head -n 1 "$ed/err" | grep -q "^$want: " &&
     ! grep '^ggrt' "$ed/err" | grep -qv "^$want: " &&
     ! grep -q 'gg[A-Z][A-Za-z]*: ' "$ed/err"
  then ok "$name"; else bad "$name (exit $got)" "want: $want: ...
got:  $(cat "$ed/err")"; fi
}

# ---- 1. one message style: "ggrt CMD: ..." from every command ----
for c in render trace find check diff info serve; do
  case $c in
    render) o="-o $ed/x.png" ;; trace) o="--pixel 1,1" ;; find) o="--where some(depth>9)" ;; *) o="" ;;
  esac
  # shellcheck disable=SC2086
  prefixed "ggrt $c" "prefix: $c with a bad argument" "$ggrt" $c $g $o --bogus
  # shellcheck disable=SC2086
  prefixed "ggrt $c" "prefix: $c with a bad scene" "$ggrt" $c "$ed/bad.nff" $o
done
for f in refract reflect fresnel absorb check seeds; do
  prefixed "ggrt optics $f" "prefix: optics $f with a bad argument" "$ggrt" optics $f --bogus
done
prefixed "ggrt optics fresnel" "prefix: optics fresnel with a bad value" \
  "$ggrt" optics fresnel --angle 100
prefixed "ggrt optics seeds" "prefix: optics seeds with an unwritable folder" \
  "$ggrt" optics seeds /nonexistent/seeds
prefixed "ggrt bench" "prefix: bench with a bad argument" "$ggrt" bench spd --bogus
prefixed "ggrt bench accuracy" "prefix: bench accuracy with a bad scene" "$ggrt" bench accuracy "$ed/bad.nff"
# The library's "ggDiff: the images differ in size" reached the user as is.
sed 's/^resolution .*/resolution 10 10/' $g >"$ed/small.nff"
prefixed "ggrt diff" "prefix: diff of two sizes names no library function" \
  "$ggrt" diff $g "$ed/small.nff"
# ... and says what to do, before any work (exit 1: the options do not fit)
"$ggrt" diff $g "$ed/small.nff" >/dev/null 2>"$ed/err"; got=$?
[ $got = 1 ] && grep -q "(a 400x300, b 10x10): give -s WxH for both" "$ed/err" &&
  ok "diff of two sizes: exit 1 and the remedy" ||
  bad "diff of two sizes: exit 1 and the remedy (exit $got)" "$(cat "$ed/err")"
"$ggrt" diff $g "$ed/small.nff" -s 8x6 -q >/dev/null 2>"$ed/err" &&
  ok "diff of two sizes with -s runs" || bad "diff of two sizes with -s runs" "$(cat "$ed/err")"
# trace --diff compared pixel 1,1 of a 400x300 image with pixel 1,1 of a
# 10x10 one: two different rays, shown side by side as one
"$ggrt" trace $g "$ed/small.nff" --pixel 1,1 --diff >"$ed/out" 2>"$ed/err"; got=$?
[ $got = 1 ] && [ ! -s "$ed/out" ] && grep -q "^ggrt trace: the two sides are images of different sizes (a 400x300, b 10x10)" "$ed/err" &&
  ok "trace --diff of two sizes: exit 1, nothing traced" ||
  bad "trace --diff of two sizes: exit 1, nothing traced (exit $got)" "$(cat "$ed/err")"
"$ggrt" trace $g -s 8x6 --pixel 1,1 --diff --b size=4x4 >/dev/null 2>"$ed/err"; got=$?
[ $got = 1 ] && grep -q "(a 8x6, b 4x4)" "$ed/err" && ok "trace --diff: a size= on one side is checked too" ||
  bad "trace --diff: a size= on one side is checked too (exit $got)" "$(cat "$ed/err")"

# ---- 2. the render options are the same in every command that renders or traces ----
"$ggrt" render --help | sed -n '/^render options/,/^ *-h, --help/p' |
  grep -o '^ *\(-[a-z], \)\?--[a-z-]*' | sed 's/.*--//' | grep -vx help >"$ed/ropts"
[ "$(wc -l <"$ed/ropts")" -ge 10 ] && ok "render --help lists its render options" ||
  bad "render --help lists its render options" "$(cat "$ed/ropts")"
# value OPTION: a valid value for it on an 8x6 image.
value() {
  case $1 in
    size) echo "8x6" ;; depth) echo 3 ;; ray-budget) echo 64 ;; samples) echo 1 ;;
    threads) echo 2 ;; crop) echo "0,0,4,4" ;; accuracy) echo "shadows=opaque" ;; *) echo "" ;;
  esac
}
for c in trace find check diff serve; do
  "$ggrt" $c --help >"$ed/help"
  missing=$(while read -r o; do grep -q -- "--$o\\b" "$ed/help" || echo "$o"; done <"$ed/ropts")
  [ -z "$missing" ] && ok "render options: $c --help lists every one" ||
    bad "render options: $c --help lists every one" "missing: $missing"
  case $c in
    trace) o="--pixel 1,1" ;; find) o="--where some(depth>9) -q" ;; check) o="-q" ;; *) o="" ;;
  esac
  fails=""
  while read -r opt; do
    v=$(value "$opt")
    if [ $c = serve ]; then
      # serve would listen: a bad scene stops it after the options are read
      # shellcheck disable=SC2086
      "$ggrt" serve "$ed/bad.nff" --$opt $v >/dev/null 2>"$ed/err"; got=$?
      if [ $opt = crop ]; then
        [ $got = 1 ] && grep -q "^ggrt serve: --crop does not apply" "$ed/err" || fails="$fails crop($got)"
      else
        [ $got = 2 ] || fails="$fails $opt($got)"
      fi
      continue
    fi
    s="-s 8x6"; [ $opt = size ] && s="" # (given twice is refused)
    # shellcheck disable=SC2086
    "$ggrt" $c $g $s $o --$opt $v >/dev/null 2>"$ed/err"; got=$?
    case $c:$got in
      *:0 | check:4) ;; # check exits 4 when an invariant fails: it ran
      *) fails="$fails $opt($got: $(head -c 200 "$ed/err"))" ;;
    esac
  done <"$ed/ropts"
  [ -z "$fails" ] && ok "render options: $c takes every one" ||
    bad "render options: $c takes every one" "$fails"
done
"$ggrt" trace $g -s 8x6 --pixel 1,1 -j 2 >/dev/null 2>"$ed/err"
[ "$(grep -c '^ggrt trace: warning: -j does not apply' "$ed/err")" = 1 ] &&
  ok "trace -j: said once to do nothing" || bad "trace -j: said once to do nothing" "$(cat "$ed/err")"
expect_msg 1 "--pixel 5,5 is outside --crop 0,0,4,4" "trace --crop that leaves out the pixel" \
  "$ggrt" trace $g -s 8x6 --pixel 5,5 --crop 0,0,4,4

# ---- 3. every output path is checked before the work ----
: >"$ed/file"
for dir in /nonexistent/dir "$ed/file"; do
  for c in "render $ed/bad.nff -o $dir/x.png" "render $ed/bad.nff --heatmap rays -o $dir/x.png" \
           "trace $g -s 8x6 --pixel 1,1 --svg $dir/x.svg" "trace $g -s 8x6 --pixel 1,1 --obj $dir/x.obj" \
           "find $ed/bad.nff --where some(depth>9) -o $dir/x.png" "find $ed/bad.nff --where some(depth>9) --overlay $dir/x.png" \
           "diff $ed/bad.nff -o $dir/x.png"; do
    # shellcheck disable=SC2086
    "$ggrt" $c >"$ed/out" 2>"$ed/err"; got=$?
    cmd=${c%% *}
    if [ $got = 3 ] && [ ! -s "$ed/out" ] && [ "$(wc -l <"$ed/err")" = 1 ] &&
       grep -q "^ggrt $cmd: cannot write '$dir/x\\.[a-z]*': " "$ed/err"
    then ok "output checked first: ggrt $c"
    else bad "output checked first: ggrt $c (exit $got)" "$(cat "$ed/err"; head -3 "$ed/out")"; fi
  done
done

# ---- 4. an unknown optics form is named as one, with a suggestion ----
for f in refract reflect fresnel absorb check seeds; do
  typo=$(printf '%s' $f | sed 's/.$//')
  expect_msg 1 "ggrt optics: unknown form '$typo'; did you mean '$f'?" \
    "optics $typo --v ...: unknown form, did you mean $f" \
    "$ggrt" optics "$typo" --v -1,0,0 --n 0,1,0
done
expect_msg 1 "ggrt optics: unknown form 'xyzzy' (refract, reflect, fresnel, absorb, check, seeds)" \
  "optics xyzzy: unknown form, the list" "$ggrt" optics xyzzy --v -1,0,0

# ---- 5. a binary file given as a scene says what it is ----
"$ggrt" render $g -s 8x6 -q -o "$ed/img.png" && "$ggrt" render $g -s 8x6 -q -o "$ed/img.exr"
printf '\377\330\377\340\0\020JFIF\0' >"$ed/img.jpg"
gzip -c $g >"$ed/scene.gz"
printf 'PK\003\004\024\0\0\0' >"$ed/a.zip"
for f in img.png:"a PNG image" img.exr:"an OpenEXR image" img.jpg:"a JPEG image" \
         scene.gz:"gzip-compressed data" a.zip:"a ZIP archive"; do
  file=${f%%:*}; kind=${f#*:}
  cp "$ed/$file" "$ed/$file.nff"; cp "$ed/$file" "$ed/$file.obj"
  for c in render info trace; do
    o=""; [ $c = render ] && o="-o $ed/y.png"; [ $c = trace ] && o="--pixel 0,0"
    # shellcheck disable=SC2086
    expect_msg 2 "ggrt $c: $ed/$file.nff: this is $kind, not a scene file (NFF, OBJ or PLY)" \
      "binary scene: $c $file as NFF" "$ggrt" $c "$ed/$file.nff" $o
  done
  expect_msg 2 "ggrt info: $ed/$file.obj: this is $kind, not a text file (OBJ or MTL)" \
    "binary scene: info $file as OBJ" "$ggrt" info "$ed/$file.obj"
done
printf 'mesh "img.png.obj"\n' >"$ed/m.nff"
expect_msg 2 "$ed/img.png.obj: this is a PNG image, not a text file (OBJ or MTL)" \
  "binary scene: a PNG named by a mesh line" "$ggrt" info "$ed/m.nff"

# ---- 6. check's truncation says what was cut and which option raises it ----
"$ggrt" check $g -s 40x30 -q >"$ed/out" 2>&1; got=$?
if [ $got = 4 ] && grep -q "^truncation: the depth limit (5 here" "$ed/out" &&
   grep -q "^-d N raises the depth limit" "$ed/out"
then ok "check glass.nff: truncation names the depth limit and -d"
else bad "check glass.nff: truncation names the depth limit and -d (exit $got)" "$(tail -8 "$ed/out")"; fi
"$ggrt" check $g -s 40x30 -q -d 12 >"$ed/out" 2>&1; got=$?
[ $got = 0 ] && ! grep -q "^truncation:" "$ed/out" && ok "check glass.nff -d 12: no truncation, no hint" ||
  bad "check glass.nff -d 12: no truncation, no hint (exit $got)" "$(tail -4 "$ed/out")"
"$ggrt" check $g -s 40x30 -q -d 12 --ray-budget 2 >"$ed/out" 2>&1; got=$?
[ $got = 4 ] && grep -q -- "^--ray-budget N raises the budget" "$ed/out" &&
  ok "check --ray-budget 2: the hint names the ray budget" ||
  bad "check --ray-budget 2: the hint names the ray budget (exit $got)" "$(tail -6 "$ed/out")"

# ---- 7. an unknown command or option: the typo, a suggestion, one pointer (exit 1) ----
for c in render trace find check diff info optics bench serve; do
  "$ggrt" "${c}x" >"$ed/out" 2>"$ed/err"; got=$?
  if [ $got = 1 ] && [ "$(wc -l <"$ed/err")" = 2 ] &&
     grep -qxF "ggrt: unknown command '${c}x'; did you mean '$c'?" "$ed/err" &&
     grep -qxF "run 'ggrt --help' for the list of commands" "$ed/err"
  then ok "unknown command ${c}x: did you mean $c"
  else bad "unknown command ${c}x: did you mean $c (exit $got)" "$(cat "$ed/err")"; fi
done
# The one rule of every "did you mean" (cli_suggest): a word that starts
# one name names it, a swap of two letters is one edit, and a short word
# gets no guess two edits away.
for pair in ren:render tarce:trace ch:check di:diff; do
  "$ggrt" "${pair%%:*}" >"$ed/out" 2>"$ed/err"
  grep -qxF "ggrt: unknown command '${pair%%:*}'; did you mean '${pair#*:}'?" "$ed/err" &&
    ok "unknown command ${pair%%:*}: did you mean ${pair#*:}" ||
    bad "unknown command ${pair%%:*}: did you mean ${pair#*:}" "$(cat "$ed/err")"
done
"$ggrt" inf0x >"$ed/out" 2>"$ed/err"
grep -qxF "ggrt: unknown command 'inf0x'" "$ed/err" &&
  ok "unknown command inf0x: no guess two edits from a five-letter word" ||
  bad "unknown command inf0x: no guess two edits from a five-letter word" "$(cat "$ed/err")"
"$ggrt" frobnicate >"$ed/out" 2>"$ed/err"; got=$?
[ $got = 1 ] && [ "$(wc -l <"$ed/err")" = 2 ] && grep -qxF "ggrt: unknown command 'frobnicate'" "$ed/err" &&
  ok "unknown command frobnicate: two lines, no guess" ||
  bad "unknown command frobnicate: two lines, no guess (exit $got)" "$(cat "$ed/err")"
# An unknown option before any command is an option, not a command.
for o in --bogus -x; do
  "$ggrt" $o >"$ed/out" 2>"$ed/err"; got=$?
  [ $got = 1 ] && [ "$(wc -l <"$ed/err")" = 2 ] && grep -qxF "ggrt: unknown option '$o'" "$ed/err" &&
    ok "unknown option $o: two lines, exit 1" ||
    bad "unknown option $o: two lines, exit 1 (exit $got)" "$(cat "$ed/err")"
done
"$ggrt" --verison >"$ed/out" 2>"$ed/err"; got=$?
[ $got = 1 ] && grep -qxF "ggrt: unknown option '--verison'; did you mean '--version'?" "$ed/err" &&
  ok "unknown option --verison: did you mean --version" ||
  bad "unknown option --verison: did you mean --version (exit $got)" "$(cat "$ed/err")"
"$ggrt" --version extra >"$ed/out" 2>"$ed/err"; got=$?
[ $got = 1 ] && [ ! -s "$ed/out" ] && grep -qxF "ggrt: unexpected argument 'extra' (--version takes none)" "$ed/err" &&
  ok "--version extra: a usage error, no version printed" ||
  bad "--version extra: a usage error, no version printed (exit $got)" "$(cat "$ed/out" "$ed/err")"
# `ggrt help CMD` is CMD's --help; `help help` and `help version` the usage.
"$ggrt" help render >"$ed/out" 2>"$ed/err"; got=$?
"$ggrt" render --help >"$ed/out2" 2>&1
[ $got = 0 ] && [ -s "$ed/out" ] && cmp -s "$ed/out" "$ed/out2" &&
  ok "help render: render's --help" || bad "help render: render's --help (exit $got)" "$(cat "$ed/err")"
"$ggrt" --help optics check >"$ed/out" 2>"$ed/err"; got=$?
[ $got = 0 ] && head -n 1 "$ed/out" | grep -q '^usage: ggrt optics check' &&
  ok "--help optics check: that subcommand's --help" ||
  bad "--help optics check: that subcommand's --help (exit $got)" "$(cat "$ed/out" "$ed/err")"
for w in help version; do
  "$ggrt" help $w >"$ed/out" 2>"$ed/err"; got=$?
  [ $got = 0 ] && head -n 1 "$ed/out" | grep -q '^usage: ggrt <command>' &&
    ok "help $w: the usage, exit 0" || bad "help $w: the usage, exit 0 (exit $got)" "$(cat "$ed/out" "$ed/err")"
done
"$ggrt" help frobnicate >"$ed/out" 2>"$ed/err"; got=$?
[ $got = 1 ] && grep -qxF "ggrt: unknown command 'frobnicate'" "$ed/err" &&
  ok "help frobnicate: unknown command, exit 1" ||
  bad "help frobnicate: unknown command, exit 1 (exit $got)" "$(cat "$ed/err")"

# ---- 8. a scene with no lights or no objects renders with a warning ----
printf 'b 0.1 0.1 0.1\n' >"$ed/empty.nff"
printf 'l 0 5 5\n' >"$ed/onlylight.nff"
printf 'f 1 0 0 1 0 0 0 0\ns 0 0 0 1\n' >"$ed/dark.nff"
printf 'ambient 0.3 0.3 0.3\nf 1 0 0 1 0 0 0 0\ns 0 0 0 1\n' >"$ed/dim.nff"
# A scene lit by emission alone means it (examples/scenes/prism.nff): no warning.
printf 'f 1 0 0 1 0 0 0 0\nemission 1 1 1\ns 0 0 0 1\n' >"$ed/glow.nff"
"$ggrt" render "$ed/glow.nff" -s 8x6 -o "$ed/w.png" >/dev/null 2>"$ed/err"
grep -q "warning" "$ed/err" && bad "render glow.nff: emission alone, no warning" "$(cat "$ed/err")" ||
  ok "render glow.nff: emission alone, no warning"
for f in empty:"has no objects: the image is its background" \
         onlylight:"has no objects: the image is its background" \
         dark:"has no lights: only ambient and emission light it" \
         dim:"has no lights: only ambient and emission light it"; do
  n=${f%%:*}; w=${f#*:}
  for q in "" -q; do
    "$ggrt" render "$ed/$n.nff" -s 8x6 $q -o "$ed/w.png" >/dev/null 2>"$ed/err"; got=$?
    [ $got = 0 ] && [ "$(grep -c "^ggrt render: warning: $ed/$n.nff $w\$" "$ed/err")" = 1 ] &&
      ok "render $n.nff $q: warned once" || bad "render $n.nff $q: warned once (exit $got)" "$(cat "$ed/err")"
  done
done
# Every example scene and model has objects and lights: no warning.
for s in examples/scenes/*.nff examples/scenes/models/*.obj examples/scenes/models/*.ply; do
  "$ggrt" render "$s" -s 8x6 -q -o "$ed/w.png" >/dev/null 2>"$ed/err"
  grep -q "warning: .* has no" "$ed/err" && bad "no false warning: $s" "$(cat "$ed/err")" || ok "no false warning: $s"
done


# ---- 9. ray counts say that reflect includes the total internal reflections ----
# render's summary and trace's header in the same words, and the numbers
# add up: total is eye + reflect + refract + shadow, tir a part of reflect,
# blocked and attenuated parts of shadow.
for s in examples/scenes/glass.nff examples/scenes/water.nff examples/scenes/default.nff; do
  line=$("$ggrt" render "$s" -s 40x30 -o "$ed/c.png" | grep '^rays: ')
  nums=$(printf '%s\n' "$line" | sed -n 's/^rays: eye \([0-9]*\) (hit [0-9]*), reflect \([0-9]*\) (tir \([0-9]*\) of them), refract \([0-9]*\), shadow \([0-9]*\) (blocked \([0-9]*\), attenuated \([0-9]*\)), total \([0-9]*\)$/\1 \2 \3 \4 \5 \6 \7 \8/p')
  read -r c_eye c_refl c_tir c_refr c_sh c_bl c_at c_tot <<NUMS
$nums
NUMS
  [ -n "$nums" ] && [ $((c_eye + c_refl + c_refr + c_sh)) = "$c_tot" ] && [ "$c_tir" -le "$c_refl" ] &&
    [ $((c_bl + c_at)) -le "$c_sh" ] &&
    ok "render $s: reflect (tir N of them), shadow (blocked, attenuated), the total adds up" ||
    bad "render $s: reflect (tir N of them), shadow (blocked, attenuated), the total adds up" "$line"
  "$ggrt" trace "$s" -s 40x30 --pixel 20,15 |
    grep -q '^rays: eye [0-9]*, reflect [0-9]* (tir [0-9]* of them), refract [0-9]*, shadow [0-9]* (blocked [0-9]*, attenuated [0-9]*)$' &&
    ok "trace $s: reflect (tir N of them), shadow (blocked, attenuated)" ||
    bad "trace $s: reflect (tir N of them), shadow (blocked, attenuated)"
done
