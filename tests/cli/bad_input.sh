#!/usr/bin/env bash
# Programs refuse bad options and files with one line on stderr and a non-zero exit.
set -uo pipefail
bin=$1; work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
expect_failure() {
  local err
  if err=$("$@" 2>&1 >/dev/null </dev/null); then echo "succeeded: $*"; exit 1; fi
  [ "$(wc -l <<<"$err")" -eq 1 ] || { echo "not one line: $*: $err"; exit 1; }
  echo "ok: $* -> $err"
}
expect_failure "$bin/dynweigh-fw" --plant sim:nosuch
expect_failure "$bin/dynweigh-fw" --plant bogus
expect_failure "$bin/dynweigh-fw" --console serial
expect_failure "$bin/dynweigh-fw" --seed x
expect_failure "$bin/dynweigh-fw" --csv /nonexistent/dir/x.csv
expect_failure "$bin/dynweigh" nosuch
expect_failure "$bin/dynweigh" plot "$work/missing.csv" -o "$work/x.png"
printf 'a,b\n1,2\n' > "$work/wrong.csv"
expect_failure "$bin/dynweigh" plot "$work/wrong.csv" -o "$work/x.png"
head -c 3000 /dev/urandom > "$work/binary.csv"
expect_failure "$bin/dynweigh" plot "$work/binary.csv" -o "$work/x.png"
printf 't_s,jiffy,static_kg,in_flight_kg,force_n,raw,filtered_g,valve\n0.00,0,x,0,0,0,0,0\n' > "$work/nan.csv"
expect_failure "$bin/dynweigh" plot "$work/nan.csv" -o "$work/x.png"
expect_failure "$bin/dynweigh" plot "$work/nan.csv" -o "$work/x.jpg"
"$bin/dynweigh-fw" --help | grep -q -- --plant
"$bin/dynweigh" --help | grep -q plot
