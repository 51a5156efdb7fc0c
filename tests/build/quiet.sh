#!/bin/sh
# SPDX-License-Identifier: MIT
# The library never exits, aborts or prints (README.md): no object of
# BUILD/libggrt.a or BUILD/libggrt-core.a may call a function that ends
# the process (exit, abort, assert's __assert_fail, raise...), that
# writes to the terminal (printf, puts, perror...) or name the standard
# streams (stdout, stderr, stdin: fprintf(stderr, ...) and the like).
# Each offender is printed as "object: symbol". Then the same scan runs
# on an archive planted with a printf, an abort, an assert and an
# fputs(stderr) and must report all four, so the test cannot pass by
# finding nothing. Run it on a release build: a sanitizer's objects call
# its own reporters, which abort by design.
#   sh tests/build/quiet.sh BUILD          (make check runs it)
cd "$(dirname "$0")/../.." || exit 1
build=${1:-build}
cc=${CC:-cc}
fail() { echo "quiet: $*"; exit 1; }
command -v nm >/dev/null || fail "needs nm (binutils)"
tmp=$(mktemp -d /tmp/ggrt-quiet-XXXXXX)
trap 'rm -rf "$tmp"' EXIT

DENY='exit _exit _Exit quick_exit atexit at_quick_exit abort raise kill
pthread_exit __assert_fail __assert_perror_fail __assert __stack_chk_fail_local
printf vprintf __printf_chk __vprintf_chk puts putchar putchar_unlocked
perror psignal psiginfo warn warnx err errx verr verrx vwarn vwarnx error
error_at_line stdout stderr stdin _IO_stdin_ _IO_stdout_ _IO_stderr_
system popen execv execve execvp execl execlp fork'

# scan ARCHIVE: "object: symbol" for every denied symbol an object uses.
scan() {
  nm -A -u "$1" 2>/dev/null | awk -v deny="$DENY" '
    BEGIN { n = split(deny, d, /[ \n]+/); for (i = 1; i <= n; i++) if (d[i] != "") bad[d[i]] = 1 }
    { s = $NF; sub(/@.*/, "", s); if (s in bad) { f = $1; sub(/:$/, "", f); print f ": " s } }'
}

for a in "$build/libggrt.a" "$build/libggrt-core.a"; do
  [ -f "$a" ] || fail "$a is missing (build it first: make lib BUILD=$build)"
  nm -u "$a" >/dev/null 2>&1 || fail "nm cannot read $a"
  found=$(scan "$a")
  [ -z "$found" ] || { echo "$found"; fail "$a calls what ends the process or prints"; }
  nm --defined-only "$a" | awk 'NF >= 3 {print $3}' | sort -u > "$tmp/def"
  ext=$(nm -u "$a" | awk 'NF >= 2 {print $NF}' | sort -u | comm -23 - "$tmp/def" | wc -l)
  echo "quiet: $a: $ext symbols from outside, none that exits, aborts or prints"
done

# The planted archive: each kind of offence the scan must see.
cat > "$tmp/planted.c" <<'EOF'
#include <assert.h>
#include <stdio.h>
#include <stdlib.h>
int planted_print(int x) { printf("%d\n", x); return x; }
void planted_abort(void) { abort(); }
int planted_assert(int x) { assert(x > 0); return x; }
void planted_stderr(const char *s) { fputs(s, stderr); }
EOF
$cc -std=c99 -O2 -c "$tmp/planted.c" -o "$tmp/planted.o" || fail "cannot compile the planted object"
ar rcs "$tmp/libplanted.a" "$tmp/planted.o"
found=$(scan "$tmp/libplanted.a")
for want in abort __assert_fail stderr; do
  echo "$found" | grep -q ": $want\$" || fail "the planted $want was not reported (got: $found)"
done
echo "$found" | grep -Eq ': (printf|puts|putchar|__printf_chk)$' ||
  fail "the planted printf was not reported (got: $found)"
echo "quiet: the planted printf, abort, assert and stderr were each reported"
