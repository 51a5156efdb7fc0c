#!/bin/sh
# SPDX-License-Identifier: MIT
# Install the Debian packages ggrt needs that this machine lacks, and nothing
# else. Safe to run again: with everything present it only checks.
#   GG_NO_DEPS=1  skip (for machines managed some other way)
set -e
[ "${GG_NO_DEPS:-0}" = 1 ] && exit 0

PKGS="libpng-dev libopenexr-dev libcmocka-dev pkg-config clang python3"

missing=""
for p in $PKGS; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed"; then
    missing="$missing $p"
  fi
done
[ -z "$missing" ] && exit 0

echo "deps: installing$missing"
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
