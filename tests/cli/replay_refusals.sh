#!/usr/bin/env bash
# dynweigh replay of raw samples with --send/--dose: a line the indicator answers ERR shows that ERR
# on stderr (one line) and exits 4; so does a line the samples end before it could be sent. A line
# answered OK (and a dose that runs) exits 0.
set -uo pipefail
bin=$(cd "$1" && pwd); work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
failures=0
printf 'dose 3000\n' | "$bin/dynweigh-fw" --csv run.csv >/dev/null || { echo "cannot make a run CSV"; exit 1; }

expect() {  # expect STATUS PATTERN ARGS...: replay exits STATUS, stderr is one line matching PATTERN
  local want=$1 pattern=$2 rc; shift 2
  timeout 60 "$bin/dynweigh" replay run.csv --quiet "$@" >stdout 2>stderr </dev/null
  rc=$?
  if [ "$rc" -ne "$want" ]; then echo "FAIL (exit $rc, not $want): replay $*"; cat stderr; failures=$((failures + 1)); return; fi
  if [ "$want" -ne 0 ] && { [ "$(grep -c '' stderr)" -ne 1 ] || ! grep -q -- "$pattern" stderr; }; then
    echo "FAIL (stderr is not one line with '$pattern'): replay $*"; cat stderr; failures=$((failures + 1)); return
  fi
  echo "ok (exit $rc): replay $* -> $(cat stderr)"
}

expect 4 "refused 'bogus': ERR 1 " --send bogus
expect 4 "refused 'dose 99999999': ERR 2 " --dose 99999999
expect 4 "refused 'bogus': ERR 1 .*(and 1 more)" --send status --send bogus --send 'also bogus'
expect 4 "samples ended before 'dose 3000'" --dose 3000 --at 5000
expect 0 "" --send status
expect 0 "" --dose 3000
grep -qx 'results=1' stdout || { echo "FAIL: the good dose has no result"; failures=$((failures + 1)); }

[ "$failures" -eq 0 ] || { echo "$failures replays did not say what the indicator refused"; exit 1; }
