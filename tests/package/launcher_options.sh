#!/usr/bin/env bash
# The service's launcher (dynweigh-fw-service, the unit's ExecStart) turns an instance file's
# variables into dynweigh-fw's options: plant, console (a pty linked in the runtime folder),
# Modbus endpoint (none when empty), settings file, further options; a stdio console or a missing
# plant is refused. A stand-in dynweigh-fw beside a copy of the launcher prints what it was given.
set -euo pipefail
. "$(dirname "$0")/common.sh"
root=$1
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
mkdir -p "$scratch/libexec/dynweigh" "$scratch/bin"
cp "$root/usr/libexec/dynweigh/dynweigh-fw-service" "$scratch/libexec/dynweigh/"
printf '#!/bin/sh\nfor a in "$@"; do printf "[%%s]" "$a"; done\necho\n' > "$scratch/bin/dynweigh-fw"
chmod +x "$scratch/bin/dynweigh-fw"
launch() { env -i PATH=/usr/bin:/bin "$@" "$scratch/libexec/dynweigh/dynweigh-fw-service" scale1; }
expect() {
  local want=$1 got
  shift
  got=$(launch "$@") || fail "the launcher failed with $*"
  [ "$got" = "$want" ] || fail "with $*: dynweigh-fw got $got, not $want"
}

expect "[--plant][can:socketcan:can0][--console][/dev/ttyS1][--nvm][/var/lib/dynweigh/scale1.nvm][--modbus][tcp:0.0.0.0:502][--realtime][--seed][3]" \
  DYNWEIGH_PLANT=can:socketcan:can0 DYNWEIGH_CONSOLE=/dev/ttyS1 DYNWEIGH_MODBUS=tcp:0.0.0.0:502 \
  DYNWEIGH_NVM=/var/lib/dynweigh/scale1.nvm "DYNWEIGH_OPTIONS=--realtime  --seed 3"
expect "[--plant][sim:default][--console][pty][--nvm][/var/lib/dynweigh/scale1.nvm][--pty-link][/run/dynweigh/scale1/console]" \
  DYNWEIGH_PLANT=sim:default DYNWEIGH_MODBUS=
expect "[--plant][sim][--console][pty][--nvm][/x/s.nvm][--pty-link][/run/x/console][--modbus][rtu:/dev/ttyUSB0:19200:8E1:7]" \
  DYNWEIGH_PLANT=sim DYNWEIGH_CONSOLE=pty RUNTIME_DIRECTORY=/run/x DYNWEIGH_NVM=/x/s.nvm \
  DYNWEIGH_MODBUS=rtu:/dev/ttyUSB0:19200:8E1:7 "DYNWEIGH_OPTIONS="

# The shipped example instance file, read as systemd reads it (KEY=value lines).
example=$(grep -E '^[A-Z_]+=' "$root/etc/dynweigh/example.conf")
mapfile -t assignments <<< "$example"
expect "[--plant][sim:default][--console][pty][--nvm][/var/lib/dynweigh/example.nvm][--pty-link][/run/dynweigh/scale1/console][--realtime]" \
  "${assignments[@]}"

if launch DYNWEIGH_PLANT=sim DYNWEIGH_CONSOLE=stdio > /dev/null 2> "$scratch/err"; then fail "a stdio console was taken"; fi
grep -q "stdio" "$scratch/err" || fail "the refusal of stdio does not say why: $(cat "$scratch/err")"
if launch DYNWEIGH_CONSOLE=pty > /dev/null 2> "$scratch/err"; then fail "a missing DYNWEIGH_PLANT was taken"; fi
grep -q "DYNWEIGH_PLANT" "$scratch/err" || fail "the refusal of a missing plant does not say why"
echo PASS
