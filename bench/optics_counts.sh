#!/bin/sh
# SPDX-License-Identifier: MIT
# optics_counts.sh BENCH -- instructions per call of the accurate refraction,
# reflection and Fresnel reflectances against their plain forms, counted by
# callgrind (stable on a loaded machine, unlike the times). `bench_optics --count` runs each
# kernel once over its 4096 inputs and dumps the count of each run on its
# own (CALLGRIND_DUMP_STATS_AT); this script divides and prints the ratios.
bench=$1
if ! command -v valgrind >/dev/null 2>&1; then
    echo "optics_counts: valgrind not found, no instruction counts"
    exit 0
fi
dir=$(mktemp -d) || exit 1
trap 'rm -rf "$dir"' EXIT
valgrind --tool=callgrind --callgrind-out-file="$dir/cg.out" "$bench" --count >/dev/null 2>&1 || {
    echo "optics_counts: valgrind failed"
    exit 1
}
for f in "$dir"/cg.out.*; do
    name=$(sed -n 's/^desc: Trigger: Client Request: //p' "$f")
    total=$(sed -n 's/^totals: //p' "$f")
    [ -n "$name" ] && echo "$name $total"
done | awk '
    { ir[$1 " " $2] = $3 / 4096 }
    END {
        print "\ninstructions per call (callgrind, one pass over the 4096 inputs):"
        printf "%-24s %9s %9s %9s\n", "", "random", "hard", ""
        row("ggRefractTextbook", "textbook", "", "")
        row("ggRefract", "refract", "textbook", "x textbook")
        row("v - 2 (v.n) n, inline", "reflect_inline", "", "")
        row("ggReflection", "reflect", "reflect_inline", "x inline")
        row("textbook Fresnel, inline", "fresnel_inline", "", "")
        row("ggFresnelDielectric", "fresnel", "fresnel_inline", "x inline")
        row("textbook conductor, inl.", "conductor_inline", "", "")
        row("ggFresnelConductor", "conductor", "conductor_inline", "x inline")
    }
    function row(label, k, base, unit,    r, h) {
        r = ir[k " random"]; h = ir[k " hard"]
        if (base == "") printf "%-24s %9.1f %9.1f\n", label, r, h
        else printf "%-24s %9.1f %9.1f   ratio %5.2f random, %5.2f hard (%s)\n", label, r, h,
            r / ir[base " random"], h / ir[base " hard"], unit
    }'
