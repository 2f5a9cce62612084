# Sourced by the calibrate tests (tests/grid, and tests/mpi after mpi_common.sh): a small DEM
# calibration and its comparison; needs bin=<build dir> (and mpirun=<launcher> for RANKS > 0).
# Two doses of 300 discs, 5 discs across the bore, a three-width Beverloo sweep: a few seconds per
# run, yet every stage of the fit (sweep, start-up, relaxation, --compare, --csv).
small_dem=(--from dem --scene default --seeds 2 --particles 300 --discs-across 5 --sweep 6,8,10 --close 0.3)

# calibrate NAME RANKS [options]: into NAME.txt, NAME.json, NAME.csv, NAME.err; RANKS 0: no mpirun.
calibrate() {
  local name=$1 ranks=$2; shift 2
  local launch=(); if [ "$ranks" != 0 ]; then launch=("$mpirun" -np "$ranks" --oversubscribe); fi
  "${launch[@]}" "$bin/dynweigh" calibrate "${small_dem[@]}" --quiet --compare --csv "$name.csv" --out "$name.json" \
    --name small "$@" >"$name.txt" 2>"$name.err"
}
# The CPU seconds (of each DEM run, the lumped runs and their ratio) are measurements, not results:
# a fresh run measures them anew. Everything else must be the same bytes.
without_cpu_times() {
  sed -E -e '/^(dem_cpu_seconds_per_dose|cost_ratio_dem_dose_to_lumped)=/d' -e 's/cpu_s:[^ ]+/cpu_s:-/' \
         -e 's/^(\| [^|]* \| )[0-9][0-9.e+-]* \|/\1- |/' -e "s|^out=.*|out=|" -e "s|^csv=.*|csv=|" "$1"
}
same_calibration() {  # same_calibration A B: scene file, CSV and stdout without CPU times
  cmp "$1.json" "$2.json" && cmp "$1.csv" "$2.csv"
  diff <(without_cpu_times "$1.txt") <(without_cpu_times "$2.txt")
}
