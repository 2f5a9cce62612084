#!/usr/bin/env bash
# The installed programs, run from the unpacked package (not the build tree, not the source's
# scenes/): --help, --version, the installed scenes found by name, a short simulated dose.
set -euo pipefail
. "$(dirname "$0")/common.sh"
root=$1 version=$2
unset DYNWEIGH_SCENES
fw=$root/usr/bin/dynweigh-fw
tool=$root/usr/bin/dynweigh
scenes=$root/usr/share/dynweigh/scenes
cd /  # no scenes/ in the working directory either

[ "$("$fw" --version)" = "dynweigh-fw $version" ] || fail "dynweigh-fw --version: $("$fw" --version)"
[ "$("$tool" --version)" = "dynweigh $version" ] || fail "dynweigh --version: $("$tool" --version)"
"$fw" --help | grep -q -- "--plant" || fail "dynweigh-fw --help names no --plant"
# The firmware's console says the package's version too.
console_version=$(printf 'version\n' | "$fw")
console_version=${console_version%%$'\n'*}
[ "$console_version" = "dynweigh $version" ] || fail "the console's version says $console_version, the package $version"
"$tool" --help | grep -q "^  sim " || fail "dynweigh --help lists no sim"

# A scene that exists only in the unpacked package: found by name, so the lookup is the package's.
sed 's/"name": *"[^"]*"/"name": "packaged-only"/' "$scenes/slow-valve.json" > "$scenes/packaged-only.json"
trap 'rm -f "$scenes/packaged-only.json"' EXIT
listed=$("$tool" sim --list)
for scene in "$scenes"/*.json; do
  grep -qx "$(basename "$scene" .json)" <<< "$listed" || fail "dynweigh sim --list lacks $(basename "$scene"): $listed"
done
"$tool" sim --scene packaged-only --describe | grep -qx "scene=packaged-only" ||
  fail "dynweigh sim does not find the installed scene packaged-only"

out=$(printf 'dose 2000\n' | "$fw" --plant sim:packaged-only)
echo "$out"
result=$(grep '^RESULT ' <<< "$out") || fail "no RESULT from a dose on the installed scene"
final=$(sed -n 's/.* final=\([0-9.]*\).*/\1/p' <<< "$result")
awk -v f="$final" 'BEGIN { exit !(f > 1500 && f < 2500) }' || fail "final=$final for target 2000"
[ "$(tail -1 <<< "$out")" = OK ] || fail "the dose did not end OK"
echo "PASS"
