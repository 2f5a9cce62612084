#!/usr/bin/env bash
# The installed unit dynweigh-fw@.service: systemd-analyze verify finds nothing to say about an
# instance of it (its ExecStart pointed at the launcher in the unpacked package, which must
# exist and be executable), and it says what docs/targets.md promises: the instance file, its own
# user, the settings folder, restart on failure, SIGTERM on stop.
set -euo pipefail
. "$(dirname "$0")/common.sh"
root=$1
unit=$root/usr/lib/systemd/system/dynweigh-fw@.service
[ -f "$unit" ] || fail "no unit in the package"
for line in "EnvironmentFile=/etc/dynweigh/%i.conf" "ExecStart=/usr/libexec/dynweigh/dynweigh-fw-service %i" \
            "DynamicUser=yes" "User=dynweigh" "StateDirectory=dynweigh" "Restart=on-failure" "KillSignal=SIGTERM" \
            "WantedBy=multi-user.target"; do
  grep -qxF "$line" "$unit" || fail "the unit has no line $line"
done
command -v systemd-analyze > /dev/null || skip "no systemd-analyze (Debian package systemd)"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
sed "s#^ExecStart=/usr/#ExecStart=$root/usr/#" "$unit" > "$scratch/dynweigh-fw@.service"
out=$(systemd-analyze verify --man=no "$scratch/dynweigh-fw@scale1.service" 2>&1) || fail "systemd-analyze verify: $out"
[ -z "$out" ] || fail "systemd-analyze verify says: $out"
echo PASS
