#!/usr/bin/env bash
# dynweigh bench seeds every fill from its series and its index in the series, never from the
# thread (or rank) that runs it: any --jobs gives the same bytes, and a series gives the same
# line whether it runs alone or in a larger grid, first or last.
set -euo pipefail
bin=$1; work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
cd "$work"
grid=(--scenes default,material-change --targets 500,2000,10000 --quiet)
"$bin/dynweigh" bench --strategies model,preact,twostage "${grid[@]}" --seeds 6 --jobs 1 --csv j1.csv > j1.txt
for jobs in 2 3 7; do
  "$bin/dynweigh" bench --strategies model,preact,twostage "${grid[@]}" --seeds 6 --jobs $jobs --csv j$jobs.csv > j$jobs.txt
  cmp j1.txt j$jobs.txt
  cmp j1.csv j$jobs.csv
done
# The series of twostage alone, and of the grid in another order, are the same lines.
"$bin/dynweigh" bench --strategies twostage "${grid[@]}" --seeds 6 --jobs 2 > alone.txt
"$bin/dynweigh" bench --strategies twostage,preact,model "${grid[@]}" --seeds 6 --jobs 3 > reordered.txt
diff <(grep '^strategy=twostage ' j1.txt) <(grep '^strategy=' alone.txt)
diff <(grep '^strategy=' j1.txt | sort) <(grep '^strategy=' reordered.txt | sort)
# Not a constant: other seeds give other figures.
"$bin/dynweigh" bench --strategies model,preact,twostage "${grid[@]}" --seeds 7 --jobs 2 > seeds7.txt
if cmp -s j1.txt seeds7.txt; then echo "other seeds gave the same figures"; exit 1; fi
echo "seeding: the same bytes with 1, 2, 3 and 7 threads"
