# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: the shared argument parser (cli/common/args.c) and
# the replay commands ggrt prints. Uses run.sh's ggrt, tmp, ok, bad, expect_msg.

g=examples/scenes/glass.nff
pix="expected X,Y, two whole numbers from 0 to 65535"
size="expected WxH, two whole numbers from 1 to 65536, at most 16777216 pixels"
crop="expected X0,Y0,X1,Y1, four whole numbers from 0 to 65536"
for c in render trace; do
  o="-o $tmp/x.png"; [ $c = trace ] && o="--pixel 1,1"
  op="-o $tmp/x.png"; [ $c = trace ] && op="" # the --pixel tests' own
  expect_msg 1 "bad value '1,2junk' for --pixel: $pix ('junk' after Y)" \
    "$c: trailing junk in --pixel" "$ggrt" $c $g $op --pixel 1,2junk
  expect_msg 1 "bad value '1,2,3' for --pixel: $pix (more than 2 numbers)" \
    "$c: extra field in --pixel" "$ggrt" $c $g $op --pixel 1,2,3
  expect_msg 1 "bad value '4294967297,1' for --pixel: $pix (X is out of range)" \
    "$c: --pixel overflow is reported as given, not wrapped" "$ggrt" $c $g $op --pixel 4294967297,1
  expect_msg 1 "bad value '99999999999999999999,1' for --pixel: $pix (X is out of range)" \
    "$c: --pixel beyond long" "$ggrt" $c $g $op --pixel 99999999999999999999,1
  expect_msg 1 "--pixel given twice ('1,1', then '2,2'): give it once" \
    "$c: --pixel given twice is refused" "$ggrt" $c $g $op --pixel 1,1 -s 8x6 --pixel 2,2
  expect_msg 1 "bad value '16x12junk' for --size: $size ('junk' after H)" \
    "$c: trailing junk in -s" "$ggrt" $c $g $o -s 16x12junk
  expect_msg 1 "bad value '8x6x4' for --size: $size (more than 2 numbers)" \
    "$c: extra field in -s" "$ggrt" $c $g $o -s 8x6x4
  expect_msg 1 "bad value '8' for --size: $size (only 1 number)" \
    "$c: -s W alone" "$ggrt" $c $g $o -s 8
  expect_msg 1 "bad value '0' for --depth: expected a whole number from 1 to 64 (out of range)" \
    "$c: depth range named" "$ggrt" $c $g $o -d 0
  expect_msg 1 "bad value ' 4' for --samples: expected a whole number from 1 to 4096" \
    "$c: space before a number" "$ggrt" $c $g $o -n " 4"
  expect_msg 1 "unknown option '--depht'; did you mean '--depth'?" \
    "$c: unknown option with a suggestion" "$ggrt" $c $g $o --depht 3
  expect_msg 1 "unknown option '--pix'; did you mean '--pixel'?" \
    "$c: a word that starts one option names it" "$ggrt" $c $g $o --pix 1,1
  expect_err 1 "ggrt $c: unknown option '--frob'" \
    "$c: no suggestion two edits from a four-letter word" "$ggrt" $c $g $o --frob 1
  expect_msg 1 "refract must be accurate, textbook or exact, got 'fast'" \
    "$c: --accuracy names the allowed values" "$ggrt" $c $g $o --accuracy refract=fast
done
expect_msg 1 "intersect must be double or float, got 'half'" \
  "--accuracy intersect names the allowed values" "$ggrt" render $g -o "$tmp/x.png" --accuracy intersect=half
expect_exit 0 "--accuracy intersect=float renders" "$ggrt" render $g -s 16x12 -q -o "$tmp/x.png" \
  --accuracy intersect=float
expect_msg 1 "shadows must be colored or opaque, got 'grey'" \
  "--accuracy shadows names the allowed values" "$ggrt" render $g -o "$tmp/x.png" --accuracy shadows=grey
expect_msg 1 "phong must be exact or fast, got 'cheap'" \
  "--accuracy phong names the allowed values" "$ggrt" render $g -o "$tmp/x.png" --accuracy phong=cheap
expect_msg 1 "bad value '0,0,4,4junk' for --crop: $crop ('junk' after Y1)" \
  "trailing junk in --crop" "$ggrt" render $g -o "$tmp/x.png" --crop 0,0,4,4junk
expect_msg 1 "bad value '0,0,4' for --crop: $crop (only 3 numbers)" \
  "missing field in --crop" "$ggrt" render $g -o "$tmp/x.png" --crop 0,0,4
expect_msg 1 "--quiet takes no value" "a flag with a value" \
  "$ggrt" render $g -o "$tmp/x.png" --quiet=yes
expect_msg 1 "bad value '0.5,1' for --v: expected X,Y,Z, three finite numbers (only 2 numbers)" \
  "optics: a short vector" "$ggrt" optics refract --v 0.5,1 --n 0,1,0
expect_msg 1 "bad value '1.5x' for --nt: expected a finite number ('x' after the number)" \
  "optics: junk after a number" "$ggrt" optics refract --v 0,-1,0 --n 0,1,0 --nt 1.5x
expect_msg 1 "bad value '1e999' for --ni: expected a finite number (not finite)" \
  "optics: overflow" "$ggrt" optics refract --v 0,-1,0 --n 0,1,0 --ni 1e999
expect_msg 1 "bad value '0' for --runs: expected a whole number from 1 to 64 (out of range)" \
  "bench: range named" "$ggrt" bench spd --runs 0
# -s over the 16777216-pixel cap is the parser's usage error in every
# command that takes it, before a scene is loaded (plan rendered its
# measure first); 4096x4096, the cap, passes the parser (the missing
# folder of -o is what fails then).
for c in "render $g -o $tmp/x.png" "trace $g --pixel 1,1" "plan $g --tiles 2 -o $tmp/p.json" \
         "find $g -w some(kind==tir)" "check $g" "diff $g"; do
  # shellcheck disable=SC2086
  expect_err 1 "(see 'ggrt ${c%% *} --help')" "${c%% *}: -s 5000x5000 is over the pixel cap" \
    "$ggrt" $c -s 5000x5000
  grep -qF "bad value '5000x5000' for --size: $size (5000x5000 is 25000000 pixels)" "$tmp/err" &&
    ok "${c%% *}: -s 5000x5000 names the cap" || bad "${c%% *}: -s 5000x5000 names the cap" "$(cat "$tmp/err")"
done
[ ! -e "$tmp/p.json" ] && ok "plan -s 5000x5000 writes no plan" || bad "plan -s 5000x5000 writes no plan"
expect_exit 3 "-s 4096x4096 is within the cap" "$ggrt" render $g -s 4096x4096 -o "$tmp/none/x.png"
expect_exit 0 "-s8x6 and grouped short flags" "$ggrt" render $g -qs8x6 -o "$tmp/x.png"
expect_exit 0 "--size=8x6 and --depth=2" "$ggrt" render $g --size=8x6 --depth=2 -q -o "$tmp/x.png"
# A value option twice was a silent override (the last won): refused, both
# values named, whichever spelling each used; the options whose values add
# up may repeat, and so may flags.
expect_msg 1 "--size given twice ('8x6', then '4x4'): give it once" \
  "-s and --size together are refused" "$ggrt" render $g -qs8x6 --size=4x4 -o "$tmp/x.png"
expect_msg 1 "--output given twice" "-o twice is refused" \
  "$ggrt" render $g -s 8x6 -o "$tmp/x.png" -o "$tmp/y.png"
expect_msg 1 "--format given twice" "find: -f twice is refused" \
  "$ggrt" find $g -s 8x6 --where "depth>1" -f json -f text
expect_exit 0 "-a twice adds up" "$ggrt" render $g -s 8x6 -q -a phong=fast -a offset=1e-6 -o "$tmp/x.png"
expect_exit 0 "a flag twice is a flag" "$ggrt" render $g -s 8x6 -q -q -o "$tmp/x.png"
expect_msg 1 "--severity" "check --severity twice adds up (a bad second value is read)" \
  "$ggrt" check $g -s 8x6 -q --severity energy=info --severity bogus=info
expect_exit 0 "a value that starts with '-' (optics --v -1,...)" \
  "$ggrt" optics reflect --v -1,-1,0 --n 0,1,0
expect_exit 0 "--help wins over errors" "$ggrt" render --bogus --help

# A replay command, pasted: two lights of 1e308 overflow to infinite pixels,
# so render prints the ggrt trace command for the worst one. The scene's
# name needs quoting; -s must come back whole (the old parser cut argv at
# the 'x' and printed "-s 32").
mkdir -p "$tmp/re play"
printf 'v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 40 30\nb 0 0 0\nl 0 0 10 1e308 1e308 1e308\nl 0 1 10 1e308 1e308 1e308\nf 1 1 1 1 0 0 0 0\ns 0 0 0 1\n' \
  > "$tmp/re play/it's hot.nff"
"$ggrt" render "$tmp/re play/it's hot.nff" -o "$tmp/hot.exr" -q -s 32x24 -n 4 --spd -j 2 \
  --crop 0,0,20,20 --accuracy cutoff=1e-3,sphere=textbook >"$tmp/out" 2>"$tmp/err"
replay=$(sed -n 's/^  ggrt trace /trace /p' "$tmp/err")
if [ -z "$replay" ]; then
  bad "render prints a replay command for a bad pixel" "$(cat "$tmp/err")
(this scene no longer makes a bad pixel: the test needs another that does)"
else
  ok "render prints a replay command for a bad pixel"
  case "$replay" in *" -s 32x24 "*) ok "the replay keeps -s WxH whole" ;;
    *) bad "the replay keeps -s WxH whole" "$replay" ;; esac
  xy=$(printf '%s\n' "$replay" | sed 's/.*--pixel //')
  eval "set -- $replay"
  if "$ggrt" "$@" >"$tmp/tr" 2>"$tmp/err2"; then ok "the pasted replay command runs"
  else bad "the pasted replay command runs" "$replay
$(cat "$tmp/err2")"; fi
  "$ggrt" render "$tmp/re play/it's hot.nff" -o "$tmp/hot.exr" -q -s 32x24 -n 4 --spd \
    --accuracy cutoff=1e-3,sphere=textbook --pixel "$xy" >"$tmp/px" 2>/dev/null
  want=$(sed -n "s/^pixel $xy //p" "$tmp/px"); got=$(sed -n 's/^colour //p' "$tmp/tr")
  if [ -n "$want" ] && [ "$want" = "$got" ]; then ok "the replay traces the same pixel value ($got)"
  else bad "the replay traces the same pixel value" "render: $want, trace: $got"; fi
  set --
fi

# The SPD flags: --spd-rules is the transmitter rule alone (a reflection
# ray from every transmitter, here one with Ks 0: more rays, the same
# picture), so with --corners it is --spd on a scene without a depth.
printf 'v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 40 30\nb 0.2 0.3 0.4\nl 0 3 10\nf 0.9 0.9 0.9 0.2 0 0 0.8 1.5\ns 0 0 0 1\nf 1 0.2 0.2 1 0 0 0 0\np 4 -4 -1.2 -4 4 -1.2 -4 4 -1.2 4 -4 -1.2 4\n' \
  > "$tmp/rule8.nff"
rays8() {
  # shellcheck disable=SC2086
  "$ggrt" render "$tmp/rule8.nff" -s 40x30 $1 -o "$tmp/r8.png" 2>&1 | sed -n 's/^rays: //p'
}
r_plain=$(rays8 ""); r_rule=$(rays8 --spd-rules); r_both=$(rays8 "--spd-rules --corners")
r_spd=$(rays8 --spd); r_corn=$(rays8 --corners)
field() { printf '%s\n' "$1" | sed -n "s/.*$2 \\([0-9]*\\).*/\\1/p"; }
if [ "$(field "$r_plain" reflect)" = 0 ] && [ "$(field "$r_rule" reflect)" -gt 0 ] &&
   [ "$(field "$r_rule" eye)" = "$(field "$r_plain" eye)" ] &&
   [ "$(field "$r_corn" eye)" -gt "$(field "$r_plain" eye)" ]; then
  ok "--spd-rules casts the transmitters' reflection rays and keeps the pixel centres"
else bad "--spd-rules casts the transmitters' reflection rays and keeps the pixel centres" "plain: $r_plain
--spd-rules: $r_rule
--corners: $r_corn"; fi
if [ -n "$r_spd" ] && [ "$r_both" = "$r_spd" ]; then ok "--spd-rules --corners casts the rays of --spd"
else bad "--spd-rules --corners casts the rays of --spd" "$r_both / $r_spd"; fi

# Every --help fits an 80-column terminal: the top level, each command and
# each form of optics and bench.
wide=""
for c in "" render plan merge trace find check diff info serve optics bench \
         "optics refract" "optics reflect" "optics fresnel" "optics absorb" "optics check" \
         "optics seeds" "bench spd" "bench counts" "bench effects" "bench scaling" \
         "bench rays" "bench limit" "bench accuracy"; do
  # shellcheck disable=SC2086
  "$ggrt" $c --help >"$tmp/help" 2>&1 || wide="$wide [$c: exit $?]"
  n=$(awk 'length($0) > 80' "$tmp/help" | wc -l)
  [ "$n" = 0 ] || wide="$wide [ggrt $c --help: $n lines over 80: $(awk 'length($0) > 80 { print; exit }' "$tmp/help")]"
done
if [ -z "$wide" ]; then ok "every --help fits in 80 columns (25 texts)"
else bad "every --help fits in 80 columns" "$wide"; fi
# An empty --crop window is refused by every command that takes --crop
# (all zeros too, which the library reads as the whole image).
for c in render trace find check diff; do
  case $c in render) o="-o $tmp/x.png" ;; trace) o="--pixel 1,1" ;; find) o="-w some(kind==eye)" ;; *) o= ;; esac
  for w in 0,0,0,0 3,3,3,5 4,1,2,6; do
    # shellcheck disable=SC2086
    expect_msg 1 "bad value '$w' for --crop: $crop (an empty window: X1 must exceed X0 and Y1 Y0)" \
      "$c --crop $w: an empty window is a usage error" "$ggrt" $c $g -s 16x12 $o --crop $w
  done
done
