#!/bin/sh
# SPDX-License-Identifier: MIT
# A real install, as a user makes one: `make install PREFIX=<temporary
# folder>` (no DESTDIR), the folder registered with the dynamic linker the
# way its README section says (root: an /etc/ld.so.conf.d entry and
# ldconfig, removed again on exit; otherwise an rpath), then every compile
# line of README.md that builds prog.c, run as written on an example
# (ray_color.c, which uses libm; core_static.c for ggrt-core), and each
# program run without LD_LIBRARY_PATH; core_static.c linked with plain
# `pkg-config --cflags --libs ggrt-core` (no --static) and run; then
# README's library program, compiled as pasted and run on a good and on a
# broken scene; last, the installed files' modes and `make uninstall`.
#   sh tests/build/install.sh BUILD          (make installcheck runs it)
build=$1
make=${MAKE:-make}
here=$(pwd)
prefix=$(mktemp -d /tmp/ggrt-prefix-XXXXXX)
conf=""
cleanup() {
  if [ -n "$conf" ]; then
    rm -f "$conf"
    flock /tmp/.ggrt-ldconfig.lock ldconfig 2>/dev/null || ldconfig
  fi
  rm -rf "$prefix"
}
trap cleanup EXIT
trap 'exit 129' HUP
trap 'exit 130' INT
trap 'exit 143' TERM
fail() { echo "installcheck: $*"; exit 1; }

$make --no-print-directory install BUILD="$build" PREFIX="$prefix" >"$prefix.log" 2>&1 ||
  { cat "$prefix.log"; rm -f "$prefix.log"; fail "make install PREFIX=$prefix failed"; }
sed -n 's/^install: /installcheck: make install said: /p' "$prefix.log"
rm -f "$prefix.log"

rpath=""
if [ "$(id -u)" = 0 ] && [ -w /etc/ld.so.conf.d ] && command -v ldconfig >/dev/null 2>&1; then
  conf=/etc/ld.so.conf.d/zz-ggrt-installcheck-$$.conf
  echo "$prefix/lib" > "$conf"
  flock /tmp/.ggrt-ldconfig.lock ldconfig 2>/dev/null || ldconfig
  ldconfig -p | grep -qF "=> $prefix/lib/libggrt.so.0" || fail "ldconfig did not pick up $conf"
  way="registered with the dynamic linker ($conf + ldconfig)"
else
  rpath="-Wl,-rpath,$prefix/lib"
  way="not registered (needs root): programs linked with $rpath"
fi
echo "installcheck: real install into $prefix, $way"

out=$prefix/progs
mkdir -p "$out"
PKG_CONFIG_PATH=$prefix/lib/pkgconfig
export PKG_CONFIG_PATH
unset LD_LIBRARY_PATH
grep '^    cc .* prog\.c' README.md > "$out/lines"
[ -s "$out/lines" ] || fail "README.md has no compile line for prog.c"
n=0
while IFS= read -r line; do
  n=$((n + 1))
  cmd=${line#    }; cmd=${cmd%%#*}; cmd=$(printf '%s' "$cmd" | sed 's/ *$//')
  case "$cmd" in *ggrt-core*) ex=core_static ;; *) ex=ray_color ;; esac
  shared=1
  case "$cmd" in *-static*|*libggrt.a*) shared=0 ;; esac
  run=$(printf '%s' "$cmd" | sed "s#prog\\.c#$here/examples/$ex.c#")
  [ $shared = 1 ] && run="$run $rpath"
  (cd "$out" && sh -c "$run") || fail "README line failed: $cmd"
  (cd "$out" && ./prog >"$out/run.log" 2>&1) ||
    { cat "$out/run.log"; fail "the program of '$cmd' ($ex.c) failed"; }
  if [ $shared = 1 ]; then
    ldd "$out/prog" | grep -qF "libggrt.so.0 => $prefix/lib/libggrt.so.0" ||
      fail "'$cmd': libggrt.so.0 not found in $prefix/lib: $(ldd "$out/prog")"
    # the symbols' version (lib/libggrt.map) is recorded in the program
    objdump -p "$out/prog" | grep -A3 'required from libggrt.so.0' | grep -q 'GGRT_0$' ||
      fail "'$cmd': the program records no GGRT_0 symbol version: $(objdump -p "$out/prog" | grep -A3 libggrt)"
    how="found libggrt.so.0 in $prefix/lib, symbols at GGRT_0"
  elif readelf -d "$out/prog" | grep -q 'NEEDED.*libggrt'; then
    fail "'$cmd' needs libggrt.so"
  else
    how="libggrt linked in"
    readelf -d "$out/prog" | grep -q NEEDED || how="fully static"
  fi
  echo "installcheck: README: $cmd -> $ex.c ran without LD_LIBRARY_PATH ($how)"
  rm -f "$out/prog"
done < "$out/lines"
echo "installcheck: $n README compile lines built and ran against the real install"

# libggrt-core is an archive only, so even a link without --static takes
# it whole and needs its libraries (libm, pthreads) from plain --libs: a
# program linked dynamically against libc with `pkg-config --cflags --libs
# ggrt-core`, as docs/internals.md and scene.h name it, must link and run.
cmd='cc -o prog core_static.c $(pkg-config --cflags --libs ggrt-core)'
cp "$here/examples/core_static.c" "$out/core_static.c"
(cd "$out" && sh -c "$cmd" >"$out/cc.log" 2>&1) ||
  { tail -n 5 "$out/cc.log"; fail "'$cmd' (no --static) does not link: pkg-config --libs ggrt-core gives $(pkg-config --libs ggrt-core)"; }
(cd "$out" && ./prog >"$out/run.log" 2>&1) || { cat "$out/run.log"; fail "'$cmd': the program failed"; }
echo "installcheck: $cmd linked ($(pkg-config --libs ggrt-core | sed 's/ *$//')) and ran"
rm -f "$out/prog" "$out/core_static.c"

# README's library program, pasted as it stands: built by the compile line
# its own comment gives (with -std=c99 -Wall -Wextra -pedantic -Werror, so
# that a missing #include fails too), run on a scene (a PNG must come out)
# and on a broken one (it must say file:line:col and exit non-zero, so the
# program checks the status of every call).
awk '/^## The library/ { on = 1; next } on && /^## / { exit }
     on && /^    / { code = 1; print substr($0, 5); next }
     on && code && /^$/ { print; next } on && code { exit }' README.md > "$out/prog.c"
grep -q 'int main' "$out/prog.c" || fail "README.md's library section has no program (int main)"
cline=$(sed -n 's|.*/\* *\(cc .* prog\.c.*[^ ]\) *\*/.*|\1|p' "$out/prog.c" | head -n 1)
[ -n "$cline" ] || fail "README.md's library program names no compile line (/* cc ... prog.c ... */)"
(cd "$out" && sh -c "$cline -std=c99 -Wall -Wextra -pedantic -Werror $rpath" 2>"$out/cc.log") ||
  { cat "$out/cc.log"; fail "README's library program does not compile: $cline"; }
cp "$here/examples/scenes/default.nff" "$out/scene.nff"
(cd "$out" && ./prog >"$out/run.log" 2>&1) || { cat "$out/run.log"; fail "README's library program failed on default.nff"; }
[ "$(od -An -tx1 -N4 "$out/out.png" 2>/dev/null | tr -d ' ')" = 89504e47 ] ||
  fail "README's library program wrote no PNG (out.png)"
printf 's 0 0 zero 1\n' > "$out/scene.nff"
rm -f "$out/out.png"
if (cd "$out" && ./prog >"$out/run.log" 2>&1); then
  fail "README's library program exits 0 on a broken scene"
fi
grep -q '^scene\.nff:1:7: ' "$out/run.log" ||
  { cat "$out/run.log"; fail "README's library program does not print the error (scene.nff:1:7: ...)"; }
[ ! -e "$out/out.png" ] || fail "README's library program wrote out.png from a broken scene"
echo "installcheck: README's library program compiled ($cline -Werror), rendered default.nff to a PNG, and reported a broken scene ($(head -n 1 "$out/run.log"))"

# The bash completion, where bash-completion looks for it (BASHCOMPDIR),
# completing with the installed ggrt found on PATH.
comp="$prefix/share/bash-completion/completions/ggrt"
[ -f "$comp" ] || fail "make install put no bash completion at $comp"
got=$(PATH="$prefix/bin:$PATH" bash -c '. "$1"; COMP_WORDS=(ggrt rend); COMP_CWORD=1; _ggrt; echo "${COMPREPLY[*]}"' sh "$comp")
[ "$got" = render ] || fail "the installed bash completion gave '$got' for 'ggrt rend', not 'render'"
echo "installcheck: the installed bash completion completes 'ggrt rend' to 'render'"

# The installed files' modes: nothing under lib/ is executable (the shared
# library is mode 644, as Debian's policy 8.1 wants). Then make uninstall
# removes every file make install put there and nothing else: a file of
# someone else's in include/ggrt/ stays, and so does the folder, until a
# second uninstall finds it empty and removes it.
x=$(find "$prefix/lib" -type f -perm /111)
[ -z "$x" ] || fail "make install left executable files under lib/: $x"
touch "$prefix/include/ggrt/other.h"
$make --no-print-directory uninstall BUILD="$build" PREFIX="$prefix" >"$prefix/progs/un.log" 2>&1 ||
  { cat "$prefix/progs/un.log"; fail "make uninstall PREFIX=$prefix failed"; }
left=$(cd "$prefix" && find . -path ./progs -prune -o \( -type f -o -type l \) -print |
  grep -vx './include/ggrt/other.h')
[ -z "$left" ] || fail "make uninstall left files behind: $left"
[ -f "$prefix/include/ggrt/other.h" ] || fail "make uninstall removed include/ggrt/other.h, which it did not install"
rm -f "$prefix/include/ggrt/other.h"
$make --no-print-directory uninstall BUILD="$build" PREFIX="$prefix" >"$prefix/progs/un.log" 2>&1 ||
  { cat "$prefix/progs/un.log"; fail "a second make uninstall PREFIX=$prefix failed"; }
[ ! -d "$prefix/include/ggrt" ] || fail "make uninstall kept the empty include/ggrt"
echo "installcheck: lib/ holds no executable file; make uninstall removed what install put there and kept a foreign include/ggrt/other.h"
