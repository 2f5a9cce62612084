#!/usr/bin/env bash
# Runs the peer LAMMPS 2D silo (in.silo2d.fill, then in.silo2d.dis -var n N for each
# orifice) and dynweigh's DEM on the same problem (same discs, Hooke + history contact, friction,
# step, orifice, stop count and fit window), one after the other on one core, and prints a table:
# discharge rates (discs per sqrt(d/g)) and particle-steps per second of both.
#
# Speed is taken from CPU time: LAMMPS' "Loop time" x its "% CPU use" line, ours from std::clock();
# on a machine shared with other jobs wall-clock rates mostly measure the load (both are printed
# as key=value lines as well). Compare ratios measured back to back, not absolute rates
# (the LAMMPS runs were measured that way too). The LAMMPS fill runs once; its restart feeds every orifice.
#
# usage: tools/granular/compare_lammps.sh [ORIFICE ...]     (default: 5 8 10 15)
# env:   DYNWEIGH_GRANULAR  path of the dynweigh-granular runner (default: searched in build dirs)
#        PEERS              folder with the LAMMPS inputs in.silo2d.fill / in.silo2d.dis (default: tools/granular/lammps)
#        LMP                LAMMPS binary (default: lmp)
#        FILL_STEPS         settling steps (peer: 120000)
#        MAX_STEPS          discharge steps at most (peer: 600000)
#        FILL_TOP           top of the peer's fill region in d (peer: 95.0, 3612 discs); a smaller
#                           value makes a quick smoke run (fewer discs, the same silo)
# exit:  0 done, 77 skipped (LAMMPS or the peer inputs missing), 1 error
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
peers="${PEERS:-$here/lammps}"
lmp="${LMP:-lmp}"
fill_steps="${FILL_STEPS:-120000}"
max_steps="${MAX_STEPS:-600000}"
fill_top="${FILL_TOP:-95.0}"
if [[ $# -gt 0 ]]; then orifices=("$@"); else orifices=(5 8 10 15); fi

if ! command -v "$lmp" > /dev/null 2>&1; then
  echo "compare_lammps: skipped: LAMMPS ('$lmp') is not installed (apt-get install -y lammps)"
  exit 77
fi
if [[ ! -f "$peers/in.silo2d.fill" || ! -f "$peers/in.silo2d.dis" ]]; then
  echo "compare_lammps: skipped: peer inputs not found in $peers"
  exit 77
fi
runner="${DYNWEIGH_GRANULAR:-}"
if [[ -z "$runner" ]]; then
  for candidate in "$repo"/build*/tools/granular/dynweigh-granular; do
    if [[ -x "$candidate" ]]; then runner="$candidate"; break; fi
  done
fi
if [[ -z "$runner" || ! -x "$runner" ]]; then
  echo "compare_lammps: error: dynweigh-granular not found; build it or set DYNWEIGH_GRANULAR" >&2
  exit 1
fi

# The peer fill: 43 columns of lattice sites (spacing 1.12, origin 0.5) with 1.5 <= y <= FILL_TOP;
# the discharge stops below 2300 of 3612 discs above the bottom: the same fraction for fewer.
rows=$(awk -v top="$fill_top" 'BEGIN{n=0; for(i=1;(i+0.5)*1.12<=top;i++) if((i+0.5)*1.12>=1.5) n++; print n}')
particles=$((43 * rows))
stop_below=$(awk -v p="$particles" 'BEGIN{printf "%d", p*2300/3612}')

export OMP_NUM_THREADS=1
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
# The peer inputs, unchanged except for the run lengths, the fill top and the stop count when
# those are asked to differ from the peer's.
sed -e "s/^run          120000/run          $fill_steps/" \
    -e "s/^\(region       fill block 1.0 49.0 1.5\) 95.0/\1 $fill_top/" "$peers/in.silo2d.fill" > "$work/in.silo2d.fill"
sed -e "s/^run          600000/run          $max_steps/" \
    -e "s/v_nab < 2300/v_nab < $stop_below/" "$peers/in.silo2d.dis" > "$work/in.silo2d.dis"
grep -q "run          $fill_steps" "$work/in.silo2d.fill" && grep -q "run          $max_steps" "$work/in.silo2d.dis" &&
  grep -q "v_nab < $stop_below" "$work/in.silo2d.dis" && grep -q "1.5 $fill_top -0.5" "$work/in.silo2d.fill" ||
  { echo "compare_lammps: error: the peer inputs changed; update the sed lines of this script" >&2; exit 1; }

# CPU seconds of a LAMMPS run: "Loop time of T ..." times "P% CPU use ...".
lammps_cpu_seconds() {
  awk '/^Loop time of/ {t=$4} /% CPU use with/ {p=$1; sub("%","",p)} END {printf "%.6g", t*p/100}' "$1"
}
lammps_wall_seconds() { awk '/^Loop time of/ {t=$4} END {printf "%.6g", t}' "$1"; }
# Particle-steps of a LAMMPS run: the atom count of the thermo rows, integrated over the steps.
lammps_particle_steps() {
  awk -v col="$2" 'BEGIN {k=0}
    /^ *Step / {on=1; next}
    /^Loop time/ {on=0}
    on && $1 ~ /^[0-9]+$/ {s[k]=$1; a[k]=$col; k++}
    END {w=0; for(i=1;i<k;i++) w+=(s[i]-s[i-1])*(a[i]+a[i-1])/2; printf "%.6g", w}' "$1"
}
# Discharge rate of a LAMMPS run: minus the least-squares slope of v_nab over time, leaving out
# the first 10 % of the discharged discs, as dynweigh's fit_discharge_rates.
lammps_discharge_rate() {
  awk 'BEGIN {k=0}
    /^ *Step +v_t +Atoms +v_nab/ {on=1; next}
    /^Loop time/ {on=0}
    on && $1 ~ /^[0-9]+$/ {t[k]=$2; v[k]=$4; k++}
    END {
      if (k < 2) {print "nan"; exit}
      total=v[0]-v[k-1]; m=0
      for(i=0;i<k;i++) if (v[0]-v[i] >= 0.1*total) {tt[m]=t[i]; vv[m]=v[i]; m++}
      if (m < 4) {print "nan"; exit}
      st=0; sv=0; for(i=0;i<m;i++){st+=tt[i]; sv+=vv[i]}; st/=m; sv/=m
      num=0; den=0; for(i=0;i<m;i++){num+=(tt[i]-st)*(vv[i]-sv); den+=(tt[i]-st)^2}
      printf "%.4f", -num/den
    }' "$1"
}
value() { sed -n "s/^$1=//p" <<< "$2"; }

echo "== LAMMPS fill ($particles discs, $fill_steps steps)"
(cd "$work" && "$lmp" -in in.silo2d.fill -log fill.log -screen none)
lmp_fill_ps=$(lammps_particle_steps "$work/fill.log" 2)
lmp_fill_cpu=$(lammps_cpu_seconds "$work/fill.log")
lmp_fill_wall=$(lammps_wall_seconds "$work/fill.log")
echo "lammps_fill_particle_steps=$lmp_fill_ps lammps_fill_cpu_seconds=$lmp_fill_cpu lammps_fill_seconds=$lmp_fill_wall"

rows_out=()
for n in "${orifices[@]}"; do
  echo "== orifice $n d: LAMMPS"
  (cd "$work" && "$lmp" -in in.silo2d.dis -var n "$n" -log "dis_$n.log" -screen none)
  lmp_q=$(lammps_discharge_rate "$work/dis_$n.log")
  lmp_ps=$(lammps_particle_steps "$work/dis_$n.log" 3)
  lmp_cpu=$(lammps_cpu_seconds "$work/dis_$n.log")
  lmp_wall=$(lammps_wall_seconds "$work/dis_$n.log")
  echo "lammps_discharge_rate=$lmp_q lammps_particle_steps=$lmp_ps lammps_cpu_seconds=$lmp_cpu lammps_seconds=$lmp_wall"
  echo "== orifice $n d: dynweigh"
  ours="$("$runner" dem --silo2d --orifice "$n" --particles "$particles" --fill-steps "$fill_steps" \
          --steps "$max_steps" --stop-below "$stop_below" --sample-every 2000 --no-calibration)"
  grep -E '^(fill_cpu_seconds|fill_particle_steps|cpu_seconds|seconds|particle_steps|discharge_rate|steps|list_rebuilds)=' <<< "$ours" | paste -sd' '
  rows_out+=("$n $lmp_q $(value discharge_rate "$ours") $lmp_ps $lmp_cpu $lmp_wall $(value particle_steps "$ours") \
$(value cpu_seconds "$ours") $(value seconds "$ours") $(value fill_particle_steps "$ours") $(value fill_cpu_seconds "$ours") \
$(value fill_seconds "$ours")")
done

echo
echo "== dynweigh DEM against LAMMPS, 2D silo of $peers ($particles discs; rates in discs per sqrt(d/g);"
echo "   speed in million particle-steps per CPU second, one core)"
printf '%-8s %12s %12s %8s %12s %12s %7s\n' orifice lammps_rate ours_rate diff_% lammps_Mps/s ours_Mps/s ratio
for row in "${rows_out[@]}"; do
  awk -v row="$row" 'BEGIN {
    split(row, f, " ")
    diff = (f[2] > 0) ? 100 * (f[3] - f[2]) / f[2] : 0
    l = (f[5] > 0) ? f[4] / f[5] / 1e6 : 0
    o = (f[8] > 0) ? f[7] / f[8] / 1e6 : 0
    ratio = (l > 0) ? o / l : 0
    printf "%-8s %12.3f %12.3f %+8.1f %12.2f %12.2f %7.2f\n", (f[1] " d"), f[2], f[3], diff, l, o, ratio
  }'
done
# The fill (same for every orifice on our side; the last one's run is shown).
awk -v row="${rows_out[-1]}" -v lps="$lmp_fill_ps" -v lcpu="$lmp_fill_cpu" 'BEGIN {
  split(row, f, " ")
  l = (lcpu > 0) ? lps / lcpu / 1e6 : 0
  o = (f[11] > 0) ? f[10] / f[11] / 1e6 : 0
  ratio = (l > 0) ? o / l : 0
  printf "%-8s %12s %12s %8s %12.2f %12.2f %7.2f\n", "fill", "-", "-", "-", l, o, ratio
}'
# 2D Beverloo W = C (D - k d)^1.5 fitted to each code's rates (least squares on W^(2/3), as
# fit_beverloo_2d); LAMMPS' own fit over orifices of 5..15 d is C = (4/pi) 1.003 = 1.277, k = 1.50.
if [[ ${#rows_out[@]} -ge 3 ]]; then
  printf '%s\n' "${rows_out[@]}" | awk '
    function fit(col, name,   i, mx, my, sxy, sxx, b, a) {
      mx = 0; my = 0
      for (i = 1; i <= n; i++) { mx += d[i]; my += (r[i, col] > 0 ? r[i, col] ^ (2 / 3) : 0) }
      mx /= n; my /= n; sxy = 0; sxx = 0
      for (i = 1; i <= n; i++) { sxy += (d[i] - mx) * ((r[i, col] > 0 ? r[i, col] ^ (2 / 3) : 0) - my); sxx += (d[i] - mx) ^ 2 }
      b = sxy / sxx; a = my - b * mx
      if (b > 0) printf "beverloo_%s C=%.3f k=%.2f\n", name, b ^ 1.5, -a / b
    }
    { n++; d[n] = $1; r[n, 2] = $2; r[n, 3] = $3 }
    END { fit(2, "lammps"); fit(3, "dynweigh") }'
fi
# key=value lines for scripts (and the wall-clock rates, for honesty about the load)
for row in "${rows_out[@]}"; do
  awk -v row="$row" 'BEGIN {
    split(row, f, " ")
    diff = (f[2] > 0) ? 100 * (f[3] - f[2]) / f[2] : 0
    cpu = (f[5] > 0 && f[8] > 0) ? (f[7] / f[8]) / (f[4] / f[5]) : 0
    wall = (f[6] > 0 && f[9] > 0) ? (f[7] / f[9]) / (f[4] / f[6]) : 0
    printf "summary orifice=%s lammps_rate=%s ours_rate=%s rate_diff_percent=%.2f speed_ratio_cpu=%.3f speed_ratio_wall=%.3f\n", f[1], f[2], f[3], diff, cpu, wall
  }'
done
