#!/usr/bin/env bash
# A rank killed in the middle of a run (SIGKILL, as a node failure or an OOM kill does): mpirun
# ends the job, the rows journalled before stay, and `--resume` computes only the rest, giving the
# same bytes as an uninterrupted run.
source "$(dirname "$0")/mpi_common.sh"
grid=(--strategies model,twostage --sweep --scenes default,tall-drop,slow-valve --targets 500,2000,5000,10000,15000
      --seeds 20)
series=$(( (6 + 5) * 3 * 5 ))  # model: 6 fine-feed settings, twostage: 5 bands
bench plain 0 "${grid[@]}" --jobs 2 --journal plain.journal
[ "$(grep -c '^strategy=' plain.txt)" = $series ]

draw=(); if [ $have_png = 1 ]; then draw=(--png killed.png); fi
"$mpirun" -np 2 --oversubscribe "$bin/dynweigh" bench --quiet --csv killed.csv "${draw[@]}" "${grid[@]}" \
  >killed.txt 2>killed.err &
launcher=$!
# Wait for a tenth of the rows, then kill rank 1 (a child of this mpirun, found by its rank).
for _ in $(seq 600); do
  [ -f killed.csv.journal ] && [ "$(wc -l < killed.csv.journal)" -gt $((series / 10)) ] && break
  sleep 0.05
done
victim=""
for pid in $(pgrep -P $launcher); do
  if tr '\0' '\n' < /proc/$pid/environ 2>/dev/null | grep -qx 'OMPI_COMM_WORLD_RANK=1'; then victim=$pid; fi
done
[ -n "$victim" ] || { echo "rank 1 not found (the run ended before the kill?)"; exit 1; }
kill -KILL "$victim"
if wait $launcher; then echo "mpirun succeeded although rank 1 was killed"; exit 1; fi
kept=$(tail -n +2 killed.csv.journal | grep -c $'\t' || true)
echo "journal kept $kept of $series rows when rank 1 died"
[ "$kept" -gt 0 ] && [ "$kept" -lt $series ]

bench killed 2 "${grid[@]}" --resume
same_bytes plain killed
computed=$(field computed killed.err); skipped=$(field skipped killed.err)
[ $((computed + skipped)) = $series ] && [ "$computed" -gt 0 ] && [ "$skipped" -ge $((kept - 1)) ]
# Both ranks worked on the resume.
[ "$(field computed_by_rank killed.err | cut -d, -f2)" -gt 0 ]
echo "mpi rank death: $skipped rows kept, $computed computed on resume, same bytes"
