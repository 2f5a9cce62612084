#!/usr/bin/env bash
# Builds the Debian package with cpack in the build folder (package/dynweigh_<version>_<arch>.deb)
# and unpacks it with dpkg-deb -x into package/root for the other package tests.
set -euo pipefail
. "$(dirname "$0")/common.sh"
cpack=$1 build=$2 version=$3
command -v dpkg-deb > /dev/null || skip "no dpkg-deb (Debian package dpkg)"

rm -rf "$build/package"
(cd "$build" && "$cpack" -G DEB > "$build/cpack.log" 2>&1) || { cat "$build/cpack.log"; fail "cpack failed"; }
deb=$build/package/dynweigh_${version}_$(dpkg --print-architecture).deb
[ -f "$deb" ] || { ls "$build/package"; fail "cpack made no $(basename "$deb")"; }
dpkg-deb -x "$deb" "$build/package/root"
echo "package=$(basename "$deb") bytes=$(stat -c %s "$deb")"
