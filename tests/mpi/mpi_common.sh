# Sourced by the MPI tests: the built tool, the launcher, and a bench run under it.
#   bin=<build dir>  mpirun=<mpiexec of FindMPI>
set -euo pipefail
bin=$1; mpirun=$2
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
cd "$work"
# OpenMPI refuses root without these; CI containers run as root.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
have_png=0; if command -v gnuplot >/dev/null; then have_png=1; fi

# bench NAME RANKS [options]: dynweigh bench into NAME.txt, NAME.csv (+ NAME.png), NAME.err;
# RANKS 0 runs the tool without mpirun (a plain single process).
bench() {
  local name=$1 ranks=$2; shift 2
  local draw=(); if [ $have_png = 1 ]; then draw=(--png "$name.png"); fi
  local launch=(); if [ "$ranks" != 0 ]; then launch=("$mpirun" -np "$ranks" --oversubscribe); fi
  "${launch[@]}" "$bin/dynweigh" bench --quiet --csv "$name.csv" "${draw[@]}" "$@" >"$name.txt" 2>"$name.err"
}
same_bytes() {  # same_bytes A B: stdout, CSV and PNG of two runs
  cmp "$1.txt" "$2.txt" && cmp "$1.csv" "$2.csv"
  if [ $have_png = 1 ]; then cmp "$1.png" "$2.png"; fi
}
field() { grep -o "$1=[0-9,]*" "$2" | tail -1 | cut -d= -f2; }
