#!/bin/sh
# SPDX-License-Identifier: MIT
# Install the Debian packages that a make target needs and this machine
# lacks, and nothing else. Safe to run again: with everything present it only
# checks.
#   sh scripts/deps.sh GROUP...     (make demo: demo; make check: check; ...)
#   sh scripts/deps.sh --list GROUP print the group's packages and exit
#   GG_NO_DEPS=1                    skip (for machines managed some other way)
set -e

# The groups: a name, a colon and its packages; "@name" includes another
# group. To add a package, put it in the group of the target that needs it
# (a package only one test needs goes in check, not in build). The compiler
# and make are assumed (build-essential).
groups() {
  cat <<'GROUPS'
build:   pkg-config libpng-dev libopenexr-dev
demo:    @build @serve
check:   @build @serve libcmocka-dev python3 assimp-testmodels valgrind clang
fuzz:    @build clang
serve:   libmicrohttpd-dev
browser: chromium chromium-driver python3-selenium
cluster: @build slurm-wlm munge parallel openssh-server openssh-client rsync
GROUPS
}
# check: assimp-testmodels holds the OBJ and PLY files tests/unit/load/test_assimp.c
#   loads (/usr/share/assimp/models); valgrind replays the image fuzz corpus
#   (tests/cli/t_truncated.sh); clang is make check's second compiler
#   (CHECK_CC2 in the Makefile).
# demo: the build and serve, since the README goes on from `make demo` to
#   `ggrt serve`.
# serve: ggrt serve (cli/serve/) is built with libmicrohttpd when
#   pkg-config finds it, and opens it when it starts; without it the rest
#   of ggrt builds and `ggrt serve` says what to install. browser:
#   tests/browser* drive Chromium through Selenium.
# cluster: make check-cluster (tests/cluster/check.sh) runs a one-node
#   Slurm with munge, and GNU parallel, on the recipes of examples/cluster/;
#   parallel goes over ssh to a private sshd on 127.0.0.1 (openssh-server,
#   openssh-client) and moves files with rsync (--basefile, --return).

# expand GROUP: its packages, includes resolved (at most 8 levels deep).
expand() {
  depth=${2:-0}
  [ "$depth" -lt 8 ] || { echo "deps: group '$1' includes itself" >&2; exit 1; }
  line=$(groups | sed -n "s/^$1:[[:space:]]*//p")
  [ -n "$line" ] || { echo "deps: no group '$1' (groups: $(groups | cut -d: -f1 | tr '\n' ' '))" >&2; exit 1; }
  for w in $line; do
    case $w in
      @*) expand "${w#@}" $((depth + 1)) ;;
      *) echo "$w" ;;
    esac
  done
}

list=0
[ "${1:-}" = --list ] && { list=1; shift; }
[ $# -gt 0 ] || set -- check
for g in "$@"; do
  groups | grep -q "^$g:" ||
    { echo "deps: no group '$g' (groups: $(groups | cut -d: -f1 | tr '\n' ' '))" >&2; exit 1; }
done
pkgs=$(for g in "$@"; do expand "$g"; done | awk '!seen[$0]++' | tr '\n' ' ')
if [ $list = 1 ]; then echo "$pkgs"; exit 0; fi
[ "${GG_NO_DEPS:-0}" = 1 ] && exit 0

if ! command -v dpkg-query >/dev/null 2>&1 || ! command -v apt-get >/dev/null 2>&1; then
  echo "deps: not a Debian-like system; make sure these (Debian names) are installed: $pkgs" >&2
  exit 0
fi
missing=""
for p in $pkgs; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed"; then
    missing="$missing $p"
  fi
done
[ -z "$missing" ] && exit 0

echo "deps ($*): installing$missing"
if [ "$(id -u)" = 0 ]; then
  SUDO=""
elif command -v sudo >/dev/null 2>&1; then
  SUDO="sudo"
else
  echo "deps: need root to install:$missing" >&2
  echo "deps: run as root: apt-get install -y$missing" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
# A fresh machine may have no package lists at all.
$SUDO apt-get update -qq
# shellcheck disable=SC2086
$SUDO apt-get install -y -qq --no-install-recommends $missing >/dev/null
echo "deps: done"
