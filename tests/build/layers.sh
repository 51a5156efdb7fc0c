#!/bin/sh
# SPDX-License-Identifier: MIT
# The library's layering, checked from the build's own flags (make layers):
#  - no layer can include a header of a layer it does not see (above it):
#    preprocessing `#include "H"` with the layer's flags must fail;
#  - a positive control: every layer can include core.h;
#  - no source climbs out of its folder with #include "../...";
#  - a header named *_int.h is private to its folder;
#  - no library file includes a .c (a source built for several instruction
#    sets is compiled again by the Makefile, ISA_AGAIN), and a header that
#    asks its includer for GG_INC_NAME (a template, compiler.h) is named
#    *.inc.h.
# Prints one line per rule and exits non-zero on the first broken one.
cd "$(dirname "$0")/../.." || exit 1
cc=${CC:-cc}
# (MAKEFLAGS cleared: under make -j the jobserver is not ours to use.)
flags=$(MAKEFLAGS= make -s --no-print-directory layers) || exit 1
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

echo "$flags" | while IFS=: read -r layer inc; do
  refused=0
  for hdr in lib/*/*.h; do
    dir=$(basename "$(dirname "$hdr")")
    case " $inc " in *" -Ilib/$dir "*) continue ;; esac
    printf '#include "%s"\n' "$(basename "$hdr")" > "$tmp/probe.c"
    if (cd "$tmp" && $cc -E -Iinclude $(echo "$inc" | sed "s|-Ilib/|-I$OLDPWD/lib/|g") \
          -I"$OLDPWD/include" probe.c >/dev/null 2>&1); then
      echo "layers: lib/$layer can include $hdr (a layer it must not see)"; exit 1
    fi
    refused=$((refused + 1))
  done
  printf '#include "core.h"\n' > "$tmp/probe.c"
  (cd "$tmp" && $cc -E $(echo "$inc" | sed "s|-Ilib/|-I$OLDPWD/lib/|g") -I"$OLDPWD/include" \
      probe.c >/dev/null 2>&1) || { echo "layers: lib/$layer cannot include core.h"; exit 1; }
  echo "layers: lib/$layer (sees$inc): $refused headers of other layers refused"
done || exit 1
if grep -n '#include "\.\.' lib/*/*.c lib/*/*.h; then
  echo "layers: includes above must not climb out of their folder"; exit 1
fi
for h in lib/*/*_int.h; do
  dir=$(dirname "$h"); name=$(basename "$h")
  users=$(grep -l "#include \"$name\"" lib/*/*.c lib/*/*.h | grep -v "^$dir/")
  if [ -n "$users" ]; then echo "layers: $h is private to $dir but included by $users"; exit 1; fi
done
if grep -nE '#include *"[^"]*\.c"' lib/*/*.c lib/*/*.h; then
  echo "layers: a library file includes a .c (Makefile, ISA_AGAIN, builds one source twice)"; exit 1
fi
for h in $(grep -l 'defined(GG_INC_NAME)' lib/*/*.h); do
  case $h in *.inc.h) ;; *) echo "layers: $h is a template but not named *.inc.h"; exit 1 ;; esac
done
echo "layers: ok (no upward include compiles; *_int.h headers stay in their folders; no .c includes a .c)"
