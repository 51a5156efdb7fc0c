#!/bin/sh
# SPDX-License-Identifier: MIT
# What README.md promises of the build, checked against the Makefile and
# scripts/deps.sh rather than a finished build (which `make check` makes
# with more than the README's commands do):
#  - plain `make` builds build/libtextbook_refract.so, which README's
#    `ggrt optics check --lib build/libtextbook_refract.so` line needs;
#  - every line of the build, the tests and the benchmarks that compiles C
#    takes the user's CPPFLAGS;
#  - every pkg-config lookup goes through PKG_CONFIG;
#  - the library's floating point stays IEEE whatever CFLAGS say: its
#    compile lines end with -ffp-contract=off after the user's CFLAGS, and
#    -ffast-math or -ffinite-math-only stops the build with a reason;
#  - `make demo` installs what `ggrt serve` needs, which README shows next;
#  - no command README shows writes into a file the repository tracks
#    (its `trace --svg docs/trace-glass.svg` once rewrote the picture
#    beside it, differently), or into one git does not ignore;
#  - with a build folder given, README's `optics check --lib` line runs as
#    written (build/ replaced by that folder) and measures the library.
#   sh tests/build/targets.sh [BUILD]       (make check runs it)
cd "$(dirname "$0")/../.." || exit 1
build=${1:-}
make=${MAKE:-make}
tmp=$(mktemp -d /tmp/ggrt-targets-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "targets: $*"; exit 1; }

# A dry run into an empty folder lists every command plain `make` runs.
MAKEFLAGS= MFLAGS= $make -n --no-print-directory BUILD="$tmp/b" all > "$tmp/plan" 2>&1 ||
  { cat "$tmp/plan"; fail "make -n all failed"; }
grep -q -- "-o $tmp/b/libtextbook_refract.so " "$tmp/plan" ||
  fail "plain make does not build libtextbook_refract.so (README's optics check line needs it)"
echo "targets: plain make builds libtextbook_refract.so"

# Every line that compiles C takes the user's CPPFLAGS (Debian's
# dpkg-buildflags puts -D_FORTIFY_SOURCE=2 there): a dry run of the
# build, the test programs and the benchmarks with a marker in CPPFLAGS.
MAKEFLAGS= MFLAGS= $make -n --no-print-directory BUILD="$tmp/c" CPPFLAGS=-DGG_TEST_CPPFLAGS \
  all tests bench > "$tmp/cpp" 2>&1 || { cat "$tmp/cpp"; fail "make -n CPPFLAGS=... all tests bench failed"; }
awk '{ c = 0; o = 0; for (i = 1; i <= NF; i++) { if ($i ~ /[.]c$/) c = 1; if ($i == "-o") o = 1 } }
     c && o' "$tmp/cpp" > "$tmp/cc"
[ -s "$tmp/cc" ] || fail "make -n all tests bench shows no line that compiles a .c file"
if grep -v -- ' -DGG_TEST_CPPFLAGS ' "$tmp/cc" > "$tmp/nocpp"; then
  cat "$tmp/nocpp"; fail "$(wc -l < "$tmp/nocpp") compile lines above ignore CPPFLAGS"
fi
echo "targets: all $(wc -l < "$tmp/cc") compile lines of make all tests bench take the user's CPPFLAGS"

# The library's arithmetic is not a CFLAGS knob (lib/core/compiler.h):
# contraction stays off after the user's flags, and fast math is refused.
MAKEFLAGS= MFLAGS= $make -n --no-print-directory BUILD="$tmp/f" CFLAGS="-O2 -ffp-contract=fast" lib \
  > "$tmp/fp" 2>&1 || { cat "$tmp/fp"; fail "make -n CFLAGS=-ffp-contract=fast lib failed"; }
grep -- ' lib/.*[.]c ' "$tmp/fp" | grep -- ' -o ' > "$tmp/fpcc"
[ -s "$tmp/fpcc" ] || fail "make -n lib shows no line that compiles the library"
if grep -v -- '-ffp-contract=fast.* -ffp-contract=off ' "$tmp/fpcc" > "$tmp/fpbad"; then
  head -3 "$tmp/fpbad"; fail "$(wc -l < "$tmp/fpbad") library compile lines let CFLAGS turn contraction on"
fi
for f in -ffast-math -Ofast -ffinite-math-only; do
  if ${CC:-cc} -std=c99 $f -Iinclude -Ilib/core -fsyntax-only lib/core/cpu.c > "$tmp/fm" 2>&1 ||
     ! grep -q 'libggrt needs IEEE arithmetic' "$tmp/fm"; then
    cat "$tmp/fm"; fail "the library compiles with $f"
  fi
done
echo "targets: $(wc -l < "$tmp/fpcc") library compile lines keep -ffp-contract=off after CFLAGS; -ffast-math, -Ofast, -ffinite-math-only refused"

# PKG_CONFIG is the one pkg-config (a cross build names its own): a
# wrapper that logs its questions answers every lookup, and the examples'
# compile lines name it. Make runs $(shell ...) even with -n.
printf '#!/bin/sh\necho "$*" >> %s/pc.log\nexec pkg-config "$@"\n' "$tmp" > "$tmp/pc"
chmod +x "$tmp/pc"
MAKEFLAGS= MFLAGS= $make -n --no-print-directory BUILD="$tmp/p" PKG_CONFIG="$tmp/pc" all examples \
  > "$tmp/pcplan" 2>&1 || { cat "$tmp/pcplan"; fail "make -n PKG_CONFIG=... all examples failed"; }
for q in 'libpng' 'libmicrohttpd'; do
  grep -q -- "--cflags $q" "$tmp/pc.log" 2>/dev/null || fail "the build asks pkg-config, not \$(PKG_CONFIG), for $q"
done
if grep -q '`pkg-config ' "$tmp/pcplan"; then
  grep '`pkg-config ' "$tmp/pcplan"; fail "the lines above call pkg-config, not \$(PKG_CONFIG)"
fi
grep -q "\`$tmp/pc --cflags --libs ggrt\`" "$tmp/pcplan" || fail "make examples does not use \$(PKG_CONFIG)"
echo "targets: PKG_CONFIG answers the build's $(wc -l < "$tmp/pc.log") lookups and the examples' compile lines"

demo=" $(sh scripts/deps.sh --list demo) "
for p in $(sh scripts/deps.sh --list build) $(sh scripts/deps.sh --list serve); do
  case "$demo" in *" $p "*) ;; *) fail "make demo does not install $p (deps group demo: $demo)" ;; esac
done
echo "targets: make demo installs the build's and serve's packages:$demo"

# The output paths of README's command lines: -o, --svg, --obj, --overlay.
grep '^    build/ggrt ' README.md | sed 's/ *#.*//' | tr ' ' '\n' |
  awk 'prev ~ /^(-o|--svg|--obj|--overlay)$/ { print } { prev = $0 }' > "$tmp/outs"
[ -s "$tmp/outs" ] || fail "found no output path in README's ggrt command lines"
while read -r f; do
  if git ls-files --error-unmatch -- "$f" >/dev/null 2>&1 || { [ ! -d .git ] && [ -e "$f" ]; }; then
    fail "README's command line writes $f, a file of the repository"
  fi
  if git rev-parse --is-inside-work-tree >/dev/null 2>&1 && ! git check-ignore -q --no-index -- "$f"; then
    fail "README's command line writes $f, which .gitignore does not name (git status would list it)"
  fi
done < "$tmp/outs"
echo "targets: README's $(wc -l < "$tmp/outs") output paths are none of the repository's files, and git ignores them"

[ -n "$build" ] || exit 0
line=$(grep '^    build/ggrt optics check --lib ' README.md | head -n 1 | sed 's/^    //; s/ *#.*//')
[ -n "$line" ] || fail "README.md shows no 'build/ggrt optics check --lib' line"
run=$(printf '%s' "$line" | sed "s#build/#$build/#g")
sh -c "$run" > "$tmp/out" 2>&1
rc=$?
# The textbook formula misses the 1-ulp bound: exit 4 and a table, not
# exit 2 (cannot load the library or find the symbol).
[ $rc = 4 ] && grep -q 'textbook_refract from ' "$tmp/out" ||
  { cat "$tmp/out"; fail "README's '$line' exited $rc (want 4, the textbook formula measured)"; }
echo "targets: README's '$line' ran: $(tail -n 1 "$tmp/out")"
