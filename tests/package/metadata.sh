#!/usr/bin/env bash
# The .deb's control data (dpkg-deb -I): name, version, architecture, a Depends that names the
# Debian package of every shared library the programs need, the conffiles, maintainer scripts that
# parse; and its contents: every file the install puts where docs/targets.md says (the docs pages included), owned by root.
set -euo pipefail
. "$(dirname "$0")/common.sh"
root=$1 version=$2 source=$3
arch=$(dpkg --print-architecture)
deb=$(dirname "$root")/dynweigh_${version}_${arch}.deb
[ -f "$deb" ] || fail "no $deb"

field() { dpkg-deb -f "$deb" "$1"; }
[ "$(field Package)" = dynweigh ] || fail "Package: $(field Package)"
[ "$(field Version)" = "$version" ] || fail "Version: $(field Version), not $version"
[ "$(field Architecture)" = "$arch" ] || fail "Architecture: $(field Architecture), not $arch"
depends=$(field Depends)
echo "Depends: $depends"
[ -n "$(field Maintainer)" ] && [ -n "$(field Description)" ] || fail "no Maintainer or Description"

# Each library a program links (its NEEDED entries) comes from a package the .deb depends on. dpkg
# knows each file by one name (merged /usr): both are asked, in one query (each takes seconds).
libraries=$(ldconfig -p)
declare -A real_of
for program in "$root/usr/bin/dynweigh-fw" "$root/usr/bin/dynweigh"; do
  for soname in $(readelf -d "$program" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p'); do
    path=$(awk -v lib="$soname" '$1 == lib && /x86-64/ {print $NF; exit}' <<< "$libraries")
    [ -n "$path" ] || fail "$(basename "$program") needs $soname, which this machine does not have"
    real_of[$soname]=$(readlink -f "$path")
  done
done
owners=$(for real in "${real_of[@]}"; do echo "$real"; echo "${real#/usr}"; done | xargs dpkg -S 2> /dev/null || true)
for soname in "${!real_of[@]}"; do
  real=${real_of[$soname]}
  owner=$(awk -v a="$real" -v b="${real#/usr}" '$NF == a || $NF == b {sub(/[:,].*/, "", $1); print $1; exit}' <<< "$owners")
  [ -n "$owner" ] || fail "no Debian package has $real ($soname)"
  tr ',|' '\n\n' <<< "$depends" | awk '{print $1}' | grep -qxF "$owner" ||
    fail "$soname (package $owner) is needed, but Depends does not name it: $depends"
done
echo "needed: $(for s in "${!real_of[@]}"; do printf '%s ' "$s"; done)"

# Control files: the example instance file is a conffile; the maintainer scripts are sh that parses.
control=$(mktemp -d)
trap 'rm -rf "$control"' EXIT
dpkg-deb -e "$deb" "$control"
grep -qx /etc/dynweigh/example.conf "$control/conffiles" || fail "conffiles: $(cat "$control/conffiles")"
for script in postinst prerm postrm; do
  [ -x "$control/$script" ] || fail "no executable $script"
  sh -n "$control/$script" || fail "$script does not parse"
done

contents=$(dpkg-deb -c "$deb")
expect() { grep -Eq " \./${1#/}$" <<< "$contents" || fail "the package has no $1"; }
for path in /usr/bin/dynweigh-fw /usr/bin/dynweigh /usr/libexec/dynweigh/dynweigh-fw-service \
            /usr/lib/systemd/system/dynweigh-fw@.service /etc/dynweigh/example.conf \
            /usr/share/man/man1/dynweigh-fw.1.gz /usr/share/man/man1/dynweigh.1.gz \
            /usr/share/doc/dynweigh/README.md; do
  expect "$path"
done
for scene in "$source"/scenes/*.json; do expect "/usr/share/dynweigh/scenes/$(basename "$scene")"; done
for doc in "$source"/docs/*; do expect "/usr/share/doc/dynweigh/docs/$(basename "$doc")"; done
if awk '{print $2}' <<< "$contents" | grep -v '^root/root$' | grep -q .; then
  fail "files not owned by root: $(awk '$2 != "root/root"' <<< "$contents" | head -3)"
fi
echo "PASS: $(basename "$deb") $(stat -c %s "$deb") bytes, $(wc -l <<< "$contents") entries"
