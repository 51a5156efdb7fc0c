# SPDX-License-Identifier: MIT
# Sourced by bench/anchor_instr.sh and bench/anchor_split.sh:
# anchor_setup NAME GGRT ANCHOR_SRC_DIR [SCENE...] checks the arguments and
# valgrind, sets g (ggrt), scenes and tmp (removed on exit), and builds the
# anchor as $tmp/anchor with -march=haswell (valgrind runs no AVX-512, so
# Embree takes its AVX2 kernels).
anchor_setup() {
  me=$1 g=$2 src=$3
  [ -x "$g" ] && [ -f "$src/main.c" ] ||
    { echo "usage: sh bench/$me GGRT ANCHOR_SRC_DIR [SCENE...]" >&2; exit 1; }
  shift 3
  command -v valgrind >/dev/null || { echo "bench/$me: needs valgrind" >&2; exit 1; }
  scenes=${*:-balls-s4 gears rings tetra mount tree teapot-s12}
  tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
  cc -O2 -march=haswell -std=c11 -o "$tmp/anchor" "$src/main.c" -lembree3 -lpng -lpthread -lm ||
    { echo "bench/$me: the anchor did not build (apt-get install libembree-dev)" >&2; exit 1; }
}
