#!/usr/bin/env bash
# Same seed, same bytes of CSV; another seed, other bytes.
set -euo pipefail
bin=$1; work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
for run in a b; do printf 'starttestdata 50 600\n' | "$bin/dynweigh-fw" --seed 5 --csv "$work/$run.csv" >/dev/null; done
printf 'starttestdata 50 600\n' | "$bin/dynweigh-fw" --seed 6 --csv "$work/c.csv" >/dev/null
cmp "$work/a.csv" "$work/b.csv"
! cmp -s "$work/a.csv" "$work/c.csv"
sha256sum "$work/a.csv"
