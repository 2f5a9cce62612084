#!/usr/bin/env bash
# dynweigh plant --replay plays a dynweigh-fw --record inputs recording as what it is: each
# jiffy's raw sample (as many as the recording has jiffies), not one sample parsed from its binary;
# any other binary file is refused in one line naming it.
set -uo pipefail
bin=$(cd "$1" && pwd); work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
if ! "$bin/dynweigh" --help | grep -q '^  plant '; then echo "SKIP: dynweigh plant not built"; exit 77; fi
printf 'dose 3000\n' | "$bin/dynweigh-fw" --record run.rec >/dev/null || { echo "cannot record"; exit 1; }
jiffies=$("$bin/dynweigh" replay run.rec --quiet | sed -n 's/^jiffies=//p')
[ "${jiffies:-0}" -gt 200 ] || { echo "the recording has ${jiffies:-no} jiffies"; exit 1; }

port=$((20000 + (RANDOM * 2 + $$) % 40000))
# Real time plays without waiting for an indicator; 20 jiffies are enough to learn what it loaded.
timeout 30 "$bin/dynweigh" plant --can "udp:$port@127.0.0.1:$((port + 1))" --realtime --jiffies 20 --replay run.rec >out.txt 2>err.txt
rc=$?
cat out.txt err.txt
[ "$rc" -eq 0 ] || { echo "FAIL: plant --replay run.rec exited $rc"; exit 1; }
grep -qx "replay_samples=$jiffies" out.txt || { echo "FAIL: not the recording's $jiffies samples"; exit 1; }

head -c 3000 /dev/urandom >noise.bin
printf '\x7fELF\x02\x01\x01\n1 2 3 4\n' >looks_like_a_line.bin
for f in noise.bin looks_like_a_line.bin; do
  timeout 30 "$bin/dynweigh" plant --can "udp:$port@127.0.0.1:$((port + 1))" --realtime --jiffies 20 --replay "$f" >out.txt 2>err.txt
  rc=$?
  { [ "$rc" -ne 0 ] && [ "$rc" -lt 124 ] && [ "$(grep -c '' err.txt)" -eq 1 ] && grep -q "$f" err.txt; } ||
    { echo "FAIL: plant --replay $f: exit $rc"; cat out.txt err.txt; exit 1; }
  echo "ok: --replay $f -> $(cat err.txt)"
done
