#!/bin/sh
# SPDX-License-Identifier: MIT
# After a live `make install` or `make uninstall` (no DESTDIR): refresh the
# dynamic linker's cache where the platform keeps one (Linux: ldconfig), and
# say what to do when LIBDIR is not among the folders the linker searches.
#   sh scripts/ldcache.sh install|uninstall LIBDIR SONAME [LDCONFIG]
# LDCONFIG is the program to run (default ldconfig, found in PATH or /sbin);
# an empty LDCONFIG skips this.
what=$1; libdir=$2; soname=$3
ldc=${4-ldconfig}
[ -n "$ldc" ] || exit 0
[ "$(uname -s)" = Linux ] || exit 0 # other systems' loaders need no cache step here
if ! command -v "$ldc" >/dev/null 2>&1; then
  [ -x "/sbin/$ldc" ] && ldc=/sbin/$ldc || { echo "$what: no $ldc here: nothing to refresh"; exit 0; }
fi
if [ "$(id -u)" != 0 ]; then
  echo "$what: not root, so the linker cache was not refreshed: run '$ldc' as root"
  exit 0
fi
# Serialised: two ldconfigs at once (parallel installchecks) share a temporary file.
if command -v flock >/dev/null 2>&1; then
  flock /tmp/.ggrt-ldconfig.lock "$ldc"
else
  "$ldc"
fi || { echo "$what: warning: $ldc failed"; exit 0; }
[ "$what" = install ] || exit 0
if "$ldc" -p | grep -qF "=> $libdir/$soname"; then
  echo "install: ran $ldc: programs find $libdir/$soname"
else
  echo "install: $libdir is not a folder the dynamic linker searches, so programs linked"
  echo "install: with -lggrt will not start until you register it (as root):"
  echo "install:   echo $libdir > /etc/ld.so.conf.d/ggrt.conf && $ldc"
  echo "install: or link them with -Wl,-rpath,$libdir (or run them with LD_LIBRARY_PATH=$libdir)"
fi
