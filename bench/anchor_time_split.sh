#!/bin/sh
# SPDX-License-Identifier: MIT
# bench/anchor_split.sh's split of a render into the ray queries and the
# rest, in time instead of instructions: ggrt and the Embree anchor (its
# -p 16, on whatever kernels Embree picks here, AVX-512 included), each
# sampled by perf while it renders at 1024x1024 with 2 threads. A render
# thread's samples (ggrt: the second thread, which only renders; the
# anchor: its two workers) give the queries' share, and the share times
# the render time (ggrt's printed "render", the anchor's trace_s) the
# seconds. Queries are ggrt's traversal functions (gg_bvh_*, the
# dispatch of lib/geom/bvh.c, the leaf kernels) and the anchor's Embree
# library (rtcIntersect16, rtcIntersect1, rtcOccluded1 and what they
# call). Medians over the rounds, which run the two programs interleaved.
# a/g is the anchor's time over ggrt's, for the whole render, the
# queries and the rest. The last two columns are the anchor's time over
# what ggrt's would be with its rest cut to the anchor's (where that is
# less) and with its rest free: what the queries alone allow
# (docs/performance.md, "Queries and the rest, in time").
# usage: sh bench/anchor_time_split.sh GGRT ANCHOR_BIN [ROUNDS] [SCENE...]
#   (from the top of a checkout; ANCHOR_BIN is the anchor built as its
#   README says; needs perf: apt-get install linux-perf)
g=$1 a=$2
[ -x "$g" ] && [ -x "$a" ] ||
  { echo "usage: sh bench/anchor_time_split.sh GGRT ANCHOR_BIN [ROUNDS] [SCENE...]" >&2; exit 1; }
rounds=${3:-3}
shift 2; [ $# -gt 0 ] && shift
scenes=${*:-balls-s4 gears rings tetra mount tree teapot-s12}
command -v perf >/dev/null || { echo "bench/anchor_time_split.sh: needs perf" >&2; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

# share PERFDATA PID KIND: the query share of the render threads' samples.
# KIND ggrt: the thread other than PID that runs the shading; anchor:
# every thread other than PID (the workers).
share() {
  perf script -i "$1" -F pid,tid,ip,sym,dso 2>/dev/null | awk -v main="$2" -v kind="$3" '
    { split($1, pt, "/"); t = pt[2]; if (t == main) next
      s = $3; d = $NF
      if (kind == "ggrt") {
        if (s ~ /^(trace_|tile_rows|gg_shade)/) render[t] = 1
        q = s ~ /^(gg_bvh_|occluded_|intersect_hinted|gg_geom_(intersect|occluded|inside_hit|frustum)|gg_leaf_|gg_tcol|gg_.*_kernel)/
      } else
        q = d ~ /libembree/ || s ~ /^rtc/
      n[t]++; nq[t] += q }
    END { for (t in n) if (kind != "ggrt" || render[t]) { all += n[t]; qq += nq[t] }
          if (all == 0) exit 1; printf "%.4f\n", qq / all }'
}

for r in $(seq "$rounds"); do
  for s in $scenes; do
    n=examples/scenes/spd/$s.nff
    perf record -q -F 4000 -e cpu-clock -o "$tmp/g.perf" \
      "$g" render "$n" -s 1024x1024 -j 2 -o "$tmp/x.exr" >"$tmp/g.out" 2>/dev/null || exit 1
    gt=$(sed -n 's/.*render \([0-9.]*\)s.*/\1/p' "$tmp/g.out")
    gp=$(perf script -i "$tmp/g.perf" -F pid 2>/dev/null | head -1 | tr -d ' ')
    gq=$(share "$tmp/g.perf" "$gp" ggrt) || exit 1
    perf record -q -F 4000 -e cpu-clock -o "$tmp/a.perf" \
      "$a" -t 2 -r 1024 -p 16 -o - "$n" >"$tmp/a.out" 2>/dev/null || exit 1
    at=$(sed -n 's/.*trace_s=\([0-9.]*\).*/\1/p' "$tmp/a.out")
    ap=$(perf script -i "$tmp/a.perf" -F pid 2>/dev/null | head -1 | tr -d ' ')
    aq=$(share "$tmp/a.perf" "$ap" anchor) || exit 1
    echo "$s $gt $gq $at $aq"
  done
done >"$tmp/raw"

awk '
  function med(k, c,   i, j, x, t) {
    for (i = 1; i <= c; i++) t[i] = v[k, i]
    for (i = 1; i <= c; i++) for (j = i + 1; j <= c; j++) if (t[j] < t[i]) { x = t[i]; t[i] = t[j]; t[j] = x }
    return c % 2 ? t[(c + 1) / 2] : (t[c / 2] + t[c / 2 + 1]) / 2 }
  { s = $1; c = ++cnt[s]; if (c == 1) ord[++m] = s
    v[s "gt", c] = $2; v[s "gq", c] = $2 * $3; v[s "gr", c] = $2 * (1 - $3)
    v[s "at", c] = $4; v[s "aq", c] = $4 * $5; v[s "ar", c] = $4 * (1 - $5) }
  END {
    printf "%-11s %6s %6s %6s | %6s %6s %6s | %5s %5s %5s | %6s %6s\n", "scene", "ggrt", "query", "rest",
      "anchor", "query", "rest", "a/g", "query", "rest", "rest=a", "rest=0"
    for (i = 1; i <= m; i++) {
      s = ord[i]; c = cnt[s]
      gt = med(s "gt", c); gq = med(s "gq", c); gr = med(s "gr", c)
      at = med(s "at", c); aq = med(s "aq", c); ar = med(s "ar", c)
      ra = at / (gq + (ar < gr ? ar : gr))
      printf "%-11s %6.3f %6.3f %6.3f | %6.3f %6.3f %6.3f | %5.2f %5.2f %5.2f | %6.2f %6.2f\n",
        s, gt, gq, gr, at, aq, ar, at / gt, aq / gq, ar / gr, ra, at / gq
      l1 += log(at / gt); l2 += log(ra); l3 += log(at / gq)
    }
    printf "%-56s %5.2f %11s | %6.2f %6.2f\n", "geometric mean", exp(l1 / m), "", exp(l2 / m), exp(l3 / m)
  }' "$tmp/raw"
