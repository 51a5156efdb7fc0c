#!/bin/sh
# SPDX-License-Identifier: MIT
# No 512-bit registers in the library. Its AVX-512 copies use AVX-512's
# mask registers and compress on 256-bit registers only: on an Intel Xeon
# (Sapphire Rapids) one 16-lane 512-bit test in the packet walk made every
# render of that copy 5-12% slower (docs/performance.md, "AVX-512 copies").
# This fails if a change, a compiler's vectoriser or an inlined struct copy
# brings zmm registers back (Makefile: ISA_avx512, GG_MOVE_MAX).
#   sh tests/build/isa.sh BUILD            (make check runs it on its release tree)
lib=${1:?usage: sh tests/build/isa.sh BUILD}/libggrt.a
fail() { echo "isa: $*"; exit 1; }
[ -f "$lib" ] || fail "no $lib (build it first)"
command -v objdump >/dev/null 2>&1 || { echo "isa: no objdump, not checked"; exit 0; }
dis=$(mktemp /tmp/ggrt-isa-XXXXXX)
trap 'rm -f "$dis"' EXIT
objdump -d "$lib" > "$dis" || fail "objdump -d $lib failed"
if ! grep -q '_avx512>:' "$dis"; then
  echo "isa: $lib has no AVX-512 copy (not an x86-64 build): nothing to check"
  exit 0
fi
n=$(grep -c '%zmm' "$dis")
[ "$n" -eq 0 ] || {
  awk '/>:$/ { f = $2 } /%zmm/ { print f }' "$dis" | sort | uniq -c | head
  fail "$n instructions on 512-bit registers in $lib (above: the functions)"
}
echo "isa: no 512-bit registers in $lib (the AVX-512 copies run on 256-bit ones)"
