#!/usr/bin/env bash
# Under mpirun -np 2 the writer journals every row as it arrives; a resume after the journal was
# cut mid-line, or lost half its rows, computes exactly the missing series and gives the same bytes
# as the uninterrupted run (and as a plain single process).
source "$(dirname "$0")/mpi_common.sh"
grid=(--strategies model,preact --scenes default,ideal --targets 500,2000 --seeds 4)
series=8
bench plain 0 "${grid[@]}"
bench ref 2 "${grid[@]}"
same_bytes plain ref
[ "$(wc -l < ref.csv.journal)" = $((series + 1)) ]

cp ref.csv.journal cut.csv.journal
truncate -s -30 cut.csv.journal
bench cut 2 "${grid[@]}" --resume
same_bytes ref cut
[ "$(field computed cut.err)" = 1 ] && [ "$(field skipped cut.err)" = $((series - 1)) ]

head -n $((series / 2 + 1)) ref.csv.journal > half.csv.journal
bench half 2 "${grid[@]}" --resume
same_bytes ref half
[ "$(field computed half.err)" = $((series / 2)) ] && [ "$(field skipped half.err)" = $((series / 2)) ]
diff <(tail -n +$((series / 2 + 2)) ref.csv.journal | cut -f1 | sort) \
     <(tail -n +$((series / 2 + 2)) half.csv.journal | cut -f1 | sort)
echo "mpi resume: same bytes, only the missing series computed"
