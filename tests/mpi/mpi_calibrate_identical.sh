#!/usr/bin/env bash
# dynweigh calibrate --from dem under mpirun writes the same scene file and CSV, and prints the same
# figures (CPU times aside), as the plain single process: with 1 and 2 ranks.
source "$(dirname "$0")/../grid/dem_calibration_runs.sh"
source "$(dirname "$0")/mpi_common.sh"
jobs=5  # two doses, three sweep widths
calibrate plain 0 --jobs 1
grep -q '^beverloo_k=' plain.txt && grep -q '"beverloo_C"' plain.json && [ "$(grep -c '^compare_' plain.txt)" = 4 ]
[ "$(grep -c '^sweep_orifice_m=' plain.txt)" = 4 ] && grep -q "^jobs=$jobs$" plain.txt
for ranks in 1 2; do
  calibrate np$ranks $ranks
  same_calibration plain np$ranks
  [ "$(field ranks np$ranks.err)" = $ranks ] && [ "$(field computed np$ranks.err)" = $jobs ]
done
# Not a constant: other seeds give another scene.
calibrate seed5 2 --seed 5
if cmp -s plain.json seed5.json; then echo "other seeds gave the same scene"; exit 1; fi
echo "mpi calibrate: plain, -np 1 and -np 2 give the same scene, CSV and figures"
