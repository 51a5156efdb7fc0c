# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: `bench spd --embree BIN` with a stand-in for
# the Embree anchor (a script printing the anchor's RESULT line: trace_s
# 0.25 s for -p 1, 0.5 s for -p 16, and what it was asked to render).
# Uses run.sh's ggrt, tmp, ok, bad.

cat > "$tmp/fake-embree" <<'EOS'
#!/bin/sh
p=; t=; r=; o=; f=
while [ $# -gt 0 ]; do
  case $1 in -p) p=$2; shift 2 ;; -t) t=$2; shift 2 ;; -r) r=$2; shift 2 ;; -o) o=$2; shift 2 ;;
    -v) echo "embree 9.9.9  ray4/8/16 native 1/1/0  (a stand-in)"; shift ;; *) f=$1; shift ;; esac
done
[ "$p" = 1 ] && s=0.2500 || s=0.5000
echo "$f: a scene"
echo "RESULT scene=$(basename "$f") res=$r threads=$t mode=$p trace_s=$s total=1000000 mrays=2 shadow=400 blocked=100 out=$o"
EOS
chmod +x "$tmp/fake-embree"
"$ggrt" bench spd --embree "$tmp/fake-embree" --size 16 --runs 1 --scenes tetra --no-pov \
  >"$tmp/bench" 2>&1; got=$?
if [ $got = 0 ] && grep -Eq '^tetra .*\| +0\.250s +0\.500s +2\.00 \|' "$tmp/bench" &&
   grep -q 'emb1/ggrt' "$tmp/bench" && grep -q '^geometric mean over 1 scenes' "$tmp/bench"
then ok "bench spd --embree: the anchor's times, rays/s and ratios"
else bad "bench spd --embree: the anchor's times, rays/s and ratios (exit $got)" "$(cat "$tmp/bench")"; fi
# the share of blocked shadow rays: ggrt's as its render counts them, the
# anchor's from its RESULT line (100 of 400)
pct=$("$ggrt" render examples/scenes/spd/tetra.nff -s 16x16 -o "$tmp/b.exr" |
  sed -n 's/^rays: .* shadow \([0-9]*\) (blocked \([0-9]*\), .*/\1 \2/p' |
  awk '{ if ($1 > 0) printf "%.1f", 100 * $2 / $1 }')
if [ -n "$pct" ] && grep -qx "shadow rays blocked, ggrt | anchor: tetra $pct% | 25.0%;" "$tmp/bench"
then ok "bench spd --embree: blocked shadow rays, ggrt's ($pct%) and the anchor's"
else bad "bench spd --embree: blocked shadow rays, ggrt's ('$pct'%) and the anchor's" "$(cat "$tmp/bench")"; fi
# under the title: the CPU, the copy of ggrt's walks (as `ggrt info` names
# it) and the anchor's -v line
trav=$("$ggrt" info examples/scenes/knot.nff | sed -n 's/^traversal  //p')
if [ -n "$trav" ] && grep -Eq '^cpu: .+ \((AVX-512F and AVX2|AVX2, no AVX-512F|no AVX2)\)$' "$tmp/bench" &&
   grep -qx "ggrt: traversal $trav" "$tmp/bench" &&
   grep -qx 'anchor: embree 9.9.9  ray4/8/16 native 1/1/0  (a stand-in)' "$tmp/bench"
then ok "bench spd --embree: names the CPU, ggrt's traversal ($trav) and the anchor's -v line"
else bad "bench spd --embree: names the CPU, ggrt's traversal ('$trav') and the anchor's -v line" "$(cat "$tmp/bench")"; fi
# GGRT_ISA=avx2 holds the walks to the AVX2 copy or below, and says so
"$ggrt" info examples/scenes/knot.nff >"$tmp/info" 2>&1
GGRT_ISA=avx2 "$ggrt" info examples/scenes/knot.nff | grep '^traversal ' >"$tmp/trav2"
if grep -Eqx 'traversal  (avx2|avx|sse2|c)' "$tmp/trav2" && grep -Eq '^traversal  ' "$tmp/info"
then ok "info: GGRT_ISA=avx2 gives $(cat "$tmp/trav2" | tr -s ' '), without it $trav"
else bad "info: GGRT_ISA=avx2 holds the traversal to AVX2 or below" "$(cat "$tmp/trav2" "$tmp/info")"; fi
# the ratio columns are the anchor's times over the same ggrt time: -p 16's
# (0.5 s) is twice -p 1's (0.25 s)
awk '/^tetra /{for(i=1;i<=NF;i++) if($i ~ /x$/) r[++n]=$i} END{
  sub("x","",r[1]); sub("x","",r[2]); exit !(r[1] > 0 && r[2]/r[1] > 1.98 && r[2]/r[1] < 2.02)}' \
  "$tmp/bench" && ok "bench spd --embree: ratio = anchor time / ggrt time" ||
  bad "bench spd --embree: ratio = anchor time / ggrt time" "$(cat "$tmp/bench")"
printf '#!/bin/sh\necho no result\n' > "$tmp/mute-embree"; chmod +x "$tmp/mute-embree"
"$ggrt" bench spd --embree "$tmp/mute-embree" --size 16 --runs 1 --scenes tetra --no-pov \
  >"$tmp/bench" 2>&1; got=$?
[ $got = 2 ] && grep -q 'the anchor failed' "$tmp/bench" &&
  ok "bench spd --embree: an anchor without a RESULT line fails (exit 2)" ||
  bad "bench spd --embree: an anchor without a RESULT line fails (exit 2, got $got)" "$(cat "$tmp/bench")"
expect_exit 1 "bench counts --embree is a usage error" "$ggrt" bench counts --embree "$tmp/fake-embree"
# --accuracy: ggrt's knobs for bench spd, named under the title
"$ggrt" bench spd --embree "$tmp/fake-embree" --size 16 --runs 1 --scenes gears --no-pov \
  --accuracy shadows=opaque >"$tmp/bench" 2>&1; got=$?
[ $got = 0 ] && grep -qx 'ggrt with --accuracy shadows=opaque' "$tmp/bench" && grep -q '^gears ' "$tmp/bench" &&
  ok "bench spd --accuracy shadows=opaque: named under the title" ||
  bad "bench spd --accuracy shadows=opaque: named under the title (exit $got)" "$(cat "$tmp/bench")"
expect_exit 1 "bench counts --accuracy is a usage error" "$ggrt" bench counts --accuracy shadows=opaque
expect_err 1 "ggrt bench: unknown benchmark 'spf'; did you mean 'spd'? (spd, counts, effects, accuracy, scaling, rays, limit)" \
  "bench spf: the nearest benchmark named" "$ggrt" bench spf
expect_err 1 "ggrt bench counts: --size does not apply to this benchmark (it renders at the SPD table's 513x513)" \
  "bench counts --size is a usage error" "$ggrt" bench counts --scenes tetra --size 64
# bench scaling: the per-scene thread table with the serial share
"$ggrt" bench scaling --size 16 --runs 1 --scenes tetra >"$tmp/scal" 2>&1; got=$?
if [ $got = 0 ] && grep -q 'against threads (median of 1; serial = time outside the tile loop)' "$tmp/scal" &&
   grep -Eq '^tetra +[0-9.]+s +[0-9.]+s +[0-9.]+x +[0-9.]+s +[0-9.]+%$' "$tmp/scal"
then ok "bench scaling: 1 and 2 threads, speed-up and serial share per scene"
else bad "bench scaling: 1 and 2 threads, speed-up and serial share per scene (exit $got)" "$(cat "$tmp/scal")"; fi
# bench rays: the rays it casts are the render's, kind by kind (the counts
# `ggrt render` prints for the same size: eye, reflect + refract, shadow),
# for an SPD scene (--scenes) and for a scene file (two meshes in
# knot.nff, a row named by the file).
# usage: rays_match NAME SCENE ROW BENCH_ARGS...
rays_match() {
  rm_name=$1 rm_scene=$2 rm_row=$3; shift 3
  "$ggrt" bench rays --size 16 --runs 1 "$@" >"$tmp/rays" 2>&1; got=$?
  "$ggrt" render "$rm_scene" -s 16x16 -j 1 -o "$tmp/rays.exr" 2>&1 |
    sed -n 's/^rays: eye \([0-9]*\) .*reflect \([0-9]*\) .*refract \([0-9]*\), shadow \([0-9]*\) .*/\1 \2 \3 \4/p' >"$tmp/rays.want"
  if [ $got = 0 ] && [ -s "$tmp/rays.want" ] &&
     awk -v row="$rm_row" 'NR == FNR { e = $1; s = $2 + $3; sh = $4; next }
          $1 == row { ok = $2 == e && $5 == s && $8 == sh && $4 > 0 && $10 > 0 }
          END { exit !ok }' "$tmp/rays.want" "$tmp/rays"
  then ok "$rm_name"
  else bad "$rm_name (exit $got)" "$(cat "$tmp/rays" "$tmp/rays.want")"; fi
}
rays_match "bench rays: the render's eye, secondary and shadow rays, with Mrays/s" \
  examples/scenes/spd/gears.nff gears --scenes gears
rays_match "bench rays SCENE: the file's eye, secondary and shadow rays, with Mrays/s" \
  examples/scenes/knot.nff knot.nff examples/scenes/knot.nff
expect_err 1 "ggrt bench rays: --scenes picks SPD scenes; give scene files or --scenes, not both" \
  "bench rays with scene files and --scenes is a usage error" \
  "$ggrt" bench rays examples/scenes/glass.nff --scenes gears
# bench accuracy --knobs: the default row and the named knob's rows only
# (no other knob, no scaling tables); float fails on acc-distant
"$ggrt" bench accuracy examples/scenes/acc-distant.nff --size 32 --runs 1 --knobs intersect \
  --out "$tmp" >"$tmp/acc" 2>&1; got=$?
if [ $got = 0 ] && grep -q '^default ' "$tmp/acc" && grep -Eq '^intersect +double ' "$tmp/acc" &&
   grep -Eq '^intersect +float ' "$tmp/acc" && ! grep -q 'float.*no effect' "$tmp/acc" &&
   ! grep -Eq '^(sphere|offset|depth) ' "$tmp/acc" && ! grep -q '^scaling' "$tmp/acc" &&
   [ "$(grep -c ',intersect,' "$tmp/accuracy.csv")" = 2 ]
then ok "bench accuracy --knobs intersect: the default and the intersect rows only"
else bad "bench accuracy --knobs intersect: the default and the intersect rows only (exit $got)" "$(cat "$tmp/acc")"; fi
# --size 1: 3/4 of a pixel high is 1 row, printed and rendered (not 0,
# which the library reads as the scene's own height)
"$ggrt" bench accuracy examples/scenes/glass.nff --size 1 --runs 1 --knobs sphere \
  --out "$tmp" >"$tmp/acc" 2>&1; got=$?
if [ $got = 0 ] && grep -q '^ggrt bench accuracy: 1x1,' "$tmp/acc" &&
   grep -q '^examples/scenes/glass.nff,default,all accurate,1,[0-9.]*,1,' "$tmp/accuracy.csv"
then ok "bench accuracy --size 1: renders the 1x1 it prints"
else bad "bench accuracy --size 1: renders the 1x1 it prints (exit $got)" "$(cat "$tmp/acc" "$tmp/accuracy.csv")"; fi
expect_exit 1 "bench spd --knobs is a usage error" "$ggrt" bench spd --knobs intersect --no-pov
# Names and folders every benchmark that takes them checks: a --scenes
# name the benchmark does not run, an empty one, --scenes where it takes
# scene files, an unknown --knobs name: usage errors (exit 1) naming the
# choices; a --spd folder without the scenes: exit 3, the file named.
for b in spd counts effects scaling rays limit; do
  for list in nosuch gears,,tetra; do
    "$ggrt" bench "$b" --scenes "$list" --size 16 --runs 1 --no-pov >"$tmp/out" 2>"$tmp/err"; got=$?
    [ $got = 1 ] && grep -q "^ggrt bench $b: --scenes: no scene '[a-z]*' in this benchmark (its scenes: " "$tmp/err" &&
      ok "bench $b --scenes $list: a usage error naming its scenes" ||
      bad "bench $b --scenes $list: a usage error naming its scenes (exit $got)" "$(cat "$tmp/out" "$tmp/err")"
  done
done
for b in spd counts scaling rays limit; do
  # each with the options it reads: counts none of size and runs, only spd POV-Ray
  more="--size 16 --runs 1"; [ $b = counts ] && more=; [ $b = spd ] && more="$more --no-pov"
  # shellcheck disable=SC2086
  "$ggrt" bench "$b" --spd "$tmp/no-such-folder" --scenes gears $more \
    >"$tmp/out" 2>"$tmp/err"; got=$?
  [ $got = 3 ] && grep -q "no-such-folder/[a-z0-9-]*\.nff: No such file or directory" "$tmp/out" "$tmp/err" &&
    ok "bench $b --spd with no scenes in it: exit 3, the file named" ||
    bad "bench $b --spd with no scenes in it: exit 3, the file named (exit $got)" "$(cat "$tmp/out" "$tmp/err")"
done
# An option a benchmark reads nothing from is refused, not ignored.
for c in "counts --runs 2" "rays --threads 2" "effects --spd x" "accuracy --spd x"; do
  b=${c%% *}; o=${c#* }; o=${o%% *}
  # shellcheck disable=SC2086
  expect_err 1 "ggrt bench $b: $o does not apply to this benchmark (it reads nothing from it)" \
    "bench $b $o is a usage error" "$ggrt" bench $c
done
for c in "limit --no-pov:spd" "scaling --out x:accuracy" "spd --knobs sphere:accuracy" \
         "accuracy --pov x:spd" "rays --embree x:spd" "counts -a shadows=opaque:spd"; do
  b=${c%% *}; o=${c#* }; o=${o%:*}; owner=${c##*:}; long=${o%% *}; [ "$long" = -a ] && long=--accuracy
  # shellcheck disable=SC2086
  expect_err 1 "ggrt bench $b: $long is an option of bench $owner only" \
    "bench $b $long: an option of bench $owner only" "$ggrt" bench $b $o
done
# ggrt bench NAME --help lists exactly the options NAME reads: every other
# option of ggrt bench --help is refused by NAME, and (where a scene folder
# that does not exist stops it before it measures) each listed one is not.
longs_of() { "$ggrt" bench $1 --help | sed -n 's/^ *\(-[a-zA-Z], \)\{0,1\}\(--[a-z-]*\).*/\2/p' | sort; }
all=$(longs_of "")
nref=0 nacc=0 failed=""
for b in spd counts effects accuracy scaling rays limit; do
  own=$(longs_of $b)
  "$ggrt" bench $b --help | head -n 1 | grep -q "^usage: ggrt bench $b " || failed="$failed
$b --help: $("$ggrt" bench $b --help | head -n 1)"
  for o in $all; do
    [ $o = --help ] && continue
    case $o in --no-pov) v= ;; --size|--threads|--runs) v=1 ;; --accuracy) v=shadows=opaque ;;
               --scenes) v=gears ;; --knobs) v=sphere ;; *) v=$tmp/x ;; esac
    if printf '%s\n' "$own" | grep -qx -- "$o"; then
      case $b:$o in effects:*|accuracy:*|*:--spd|*:--scenes|counts:--embree) continue ;; esac
      # shellcheck disable=SC2086
      "$ggrt" bench $b $o $v --spd "$tmp/no-such-folder" --scenes gears >"$tmp/out" 2>&1; got=$?
      nacc=$((nacc + 1))
      [ $got = 3 ] || failed="$failed
$b $o $v (listed): exit $got, $(head -n 2 "$tmp/out")"
    else
      # shellcheck disable=SC2086
      "$ggrt" bench $b $o $v >"$tmp/out" 2>&1; got=$?
      nref=$((nref + 1))
      [ $got = 1 ] && grep -q "^ggrt bench $b: $o \(does not apply\|is an option of bench\)" "$tmp/out" ||
        failed="$failed
$b $o (not listed): exit $got, $(head -n 2 "$tmp/out")"
    fi
  done
done
[ -z "$failed" ] && [ $nref -ge 20 ] && [ $nacc -ge 10 ] &&
  ok "bench NAME --help: its own options; the $nref others refused, $nacc listed ones taken" ||
  bad "bench NAME --help: its own options ($nref refused, $nacc taken)" "$failed"
# A scene that fails to load: its row says why and so does stderr, in the
# tool's message style (as bench accuracy does), exit 2.
mkdir -p "$tmp/badspd"; printf 's 0 0 zero 1\n' >"$tmp/badspd/gears.nff"
for b in rays limit spd; do
  what=$tmp/badspd/gears.nff; [ $b = spd ] && what="--spd $tmp/badspd --scenes gears --no-pov"
  # shellcheck disable=SC2086
  expect_err 2 "ggrt bench $b: $tmp/badspd/gears.nff:1:7: expected a number after 's', got 'zero'" \
    "bench $b: a scene that fails to load is named on stderr" "$ggrt" bench $b $what --size 8 --runs 1
done
expect_err 1 "ggrt bench accuracy: --scenes does not apply to this benchmark (it takes scene files)" \
  "bench accuracy --scenes is a usage error" "$ggrt" bench accuracy examples/scenes/glass.nff --scenes gears
expect_err 1 "ggrt bench limit: --scenes picks SPD scenes; give scene files or --scenes, not both" \
  "bench limit with scene files and --scenes is a usage error" \
  "$ggrt" bench limit examples/scenes/glass.nff --scenes gears
"$ggrt" bench accuracy examples/scenes/glass.nff --knobs intersect,nosuch >"$tmp/out" 2>"$tmp/err"; got=$?
[ $got = 1 ] && grep -q "^ggrt bench accuracy: --knobs: no knob 'nosuch' (the knobs: offset, sphere, .*intersect" "$tmp/err" &&
  ok "bench accuracy --knobs with an unknown knob: a usage error naming the knobs" ||
  bad "bench accuracy --knobs with an unknown knob: a usage error naming the knobs (exit $got)" "$(cat "$tmp/out" "$tmp/err")"
