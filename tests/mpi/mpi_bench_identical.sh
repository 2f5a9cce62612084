#!/usr/bin/env bash
# dynweigh bench under mpirun prints, writes and draws the same bytes as the plain single process:
# 1, 2 and 3 ranks (more ranks than cores), and more ranks than series.
source "$(dirname "$0")/mpi_common.sh"
grid=(--strategies model,preact --scenes default,ideal --targets 500,2000 --seeds 4)
bench plain 0 "${grid[@]}" --jobs 1
[ -s plain.txt ] && [ "$(grep -c '^strategy=' plain.txt)" = 8 ]
for ranks in 1 2 3; do
  bench np$ranks $ranks "${grid[@]}"
  same_bytes plain np$ranks
  [ "$(field ranks np$ranks.err)" = $ranks ] && [ "$(field computed np$ranks.err)" = 8 ]
done
# The issue's small bench: two series over three ranks (one rank gets nothing to do).
small=(--strategies model,preact --scenes default --targets 2000 --seeds 4)
bench small_plain 0 "${small[@]}"
bench small_np3 3 "${small[@]}"
same_bytes small_plain small_np3
echo "mpi: plain, -np 1, -np 2 and -np 3 give the same bytes"
