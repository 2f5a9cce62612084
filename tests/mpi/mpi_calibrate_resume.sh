#!/usr/bin/env bash
# dynweigh calibrate --from dem under mpirun -np 2 journals each DEM job as it arrives; a resume
# after the journal was cut mid-line computes only the missing job and writes the same scene (and
# the same figures, CPU times aside) as the uninterrupted run.
source "$(dirname "$0")/../grid/dem_calibration_runs.sh"
source "$(dirname "$0")/mpi_common.sh"
jobs=5
calibrate plain 0
calibrate ref 2 --journal ref.journal
same_calibration plain ref
[ "$(wc -l < ref.journal)" = $((jobs + 1)) ]

cp ref.journal cut.journal
truncate -s -30 cut.journal
calibrate cut 2 --journal cut.journal --resume
same_calibration ref cut
[ "$(field computed cut.err)" = 1 ] && [ "$(field skipped cut.err)" = $((jobs - 1)) ]
[ "$(field dropped_journal_lines cut.err)" = 1 ]
diff <(tail -n +2 ref.journal | cut -f1 | sort) <(tail -n +2 cut.journal | cut -f1 | sort)

# A finished journal: nothing computed, the same output; the DEM runs' CPU time comes from the
# journal (only the lumped runs of --compare are timed anew).
cp ref.journal done.journal
calibrate done 2 --journal done.journal --resume
same_calibration ref done
diff <(grep '^dem_cpu_seconds_per_dose=' ref.txt) <(grep '^dem_cpu_seconds_per_dose=' done.txt)
[ "$(field computed done.err)" = 0 ] && [ "$(field skipped done.err)" = $jobs ]

# A journal of another calibration (other discs) is refused with one line.
cp ref.journal other.journal
if "$bin/dynweigh" calibrate "${small_dem[@]/#300/400}" --quiet --journal other.journal --resume \
     >/dev/null 2>other.err; then
  echo "resumed a journal of another calibration"; exit 1
fi
[ "$(wc -l < other.err)" = 1 ] && grep -q 'another grid' other.err
echo "mpi calibrate resume: same scene, only the missing DEM job computed"
