#!/usr/bin/env bash
# Runs the peer LAMMPS 2D silo (shared/peers/in.silo2d.fill then in.silo2d.dis) and dynweigh's
# DEM on the same problem, one after the other, on one core, and prints both speeds and
# discharge rates side by side. Compare ratios, not absolute times (peers/README.md).
#
# usage: tools/granular/compare_lammps.sh [ORIFICE ...]     (default: 8)
# env:   DYNWEIGH_GRANULAR  path of the dynweigh-granular runner (default: searched in build dirs)
#        PEERS              folder with in.silo2d.fill / in.silo2d.dis (default: ../shared/peers)
#        LMP                LAMMPS binary (default: lmp)
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
peers="${PEERS:-$repo/../shared/peers}"
lmp="${LMP:-lmp}"
orifices=("${@:-8}")

if ! command -v "$lmp" > /dev/null 2>&1; then
  echo "compare_lammps: skipped: LAMMPS ('$lmp') is not installed (apt-get install -y lammps)"
  exit 0
fi
if [[ ! -f "$peers/in.silo2d.fill" || ! -f "$peers/in.silo2d.dis" ]]; then
  echo "compare_lammps: skipped: peer inputs not found in $peers"
  exit 0
fi
runner="${DYNWEIGH_GRANULAR:-}"
if [[ -z "$runner" ]]; then
  for candidate in "$repo"/build*/tools/granular/dynweigh-granular /tmp/build-granular/tools_granular/dynweigh-granular; do
    if [[ -x "$candidate" ]]; then runner="$candidate"; break; fi
  done
fi
if [[ -z "$runner" || ! -x "$runner" ]]; then
  echo "compare_lammps: error: dynweigh-granular not found; build it or set DYNWEIGH_GRANULAR" >&2
  exit 1
fi

export OMP_NUM_THREADS=1
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cp "$peers/in.silo2d.fill" "$peers/in.silo2d.dis" "$work/"

# "Loop time of T on 1 procs for N steps with M atoms" -> T N M
loop_line() { grep -E '^Loop time of' "$1" | tail -n 1 | awk '{print $4, $9, $12}'; }

echo "== LAMMPS fill (in.silo2d.fill)"
(cd "$work" && "$lmp" -in in.silo2d.fill -log fill.log -screen none)
read -r fill_t fill_n fill_m < <(loop_line "$work/fill.log")
lmp_fill_rate=$(awk -v t="$fill_t" -v n="$fill_n" -v m="$fill_m" 'BEGIN{printf "%.4g", n*m/t}')
echo "lammps_fill_particle_steps_per_s=$lmp_fill_rate"

for n in "${orifices[@]}"; do
  echo "== orifice $n d"
  (cd "$work" && "$lmp" -in in.silo2d.dis -var n "$n" -log "dis_$n.log" -screen none)
  read -r dis_t dis_n dis_m < <(loop_line "$work/dis_$n.log")
  # thermo rows after "Step Time Atoms v_nab CPU": discharge rate = -slope of v_nab over time,
  # leaving out the first 10 % of the discharge, as dynweigh does.
  lmp_rate=$(awk '
    /^ *Step +Time +Atoms/ {on=1; next}
    /^Loop time/ {on=0}
    on && NF>=5 && $1 ~ /^[0-9]+$/ {t[k]=$2; v[k]=$4; a[k]=$3; k++}
    END {
      total=v[0]-v[k-1]; m=0
      for(i=0;i<k;i++) if (v[0]-v[i] >= 0.1*total) {tt[m]=t[i]; vv[m]=v[i]; m++}
      st=0; sv=0; for(i=0;i<m;i++){st+=tt[i]; sv+=vv[i]}; st/=m; sv/=m
      num=0; den=0; for(i=0;i<m;i++){num+=(tt[i]-st)*(vv[i]-sv); den+=(tt[i]-st)^2}
      printf "%.4f %d", -num/den, a[0]
    }' "$work/dis_$n.log")
  read -r lmp_q lmp_start_atoms <<< "$lmp_rate"
  # Atoms fall from start to end of the run: count the mean.
  lmp_dis_rate=$(awk -v t="$dis_t" -v n="$dis_n" -v a="$lmp_start_atoms" -v b="$dis_m" 'BEGIN{printf "%.4g", n*(a+b)/2/t}')
  echo "lammps_discharge_rate=$lmp_q"
  echo "lammps_particle_steps_per_s=$lmp_dis_rate"

  echo "-- dynweigh DEM, same silo"
  ours="$("$runner" dem --silo2d --orifice "$n" --fill-steps 120000 --steps 600000)"
  echo "$ours" | grep -E '^(fill_particle_steps_per_s|particle_steps_per_s|discharge_rate)='
  our_fill=$(echo "$ours" | sed -n 's/^fill_particle_steps_per_s=//p')
  our_dis=$(echo "$ours" | sed -n 's/^particle_steps_per_s=//p')
  our_q=$(echo "$ours" | sed -n 's/^discharge_rate=//p')
  awk -v a="$our_fill" -v b="$lmp_fill_rate" -v c="$our_dis" -v d="$lmp_dis_rate" -v q="$our_q" -v r="$lmp_q" -v n="$n" 'BEGIN{
    printf "summary orifice=%s speed_ratio_fill=%.2f speed_ratio_discharge=%.2f discharge_rate_ratio=%.3f\n", n, a/b, c/d, q/r }'
done
