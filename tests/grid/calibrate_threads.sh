#!/usr/bin/env bash
# dynweigh calibrate --from dem seeds every DEM run from its job, never from the thread that runs
# it: --jobs 1 and --jobs 2 write the same scene file and CSV and print the same figures (CPU times
# aside); a journal cut mid-line is resumed to the same output, computing only the lost job.
set -euo pipefail
source "$(dirname "$0")/dem_calibration_runs.sh"
bin=$1; work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
cd "$work"
jobs=5  # two doses, three sweep widths
calibrate j1 0 --jobs 1 --journal j1.journal
grep -q '^beverloo_k=' j1.txt && grep -q '"beverloo_C"' j1.json && [ "$(wc -l < j1.journal)" = $((jobs + 1)) ]
calibrate j2 0 --jobs 2
same_calibration j1 j2

cp j1.journal cut.journal
truncate -s -30 cut.journal
calibrate cut 0 --jobs 2 --journal cut.journal --resume
same_calibration j1 cut
grep -q "computed=1 skipped=$((jobs - 1)) dropped_journal_lines=1" cut.err
echo "calibrate: the same scene with 1 and 2 threads, and after a resume"
