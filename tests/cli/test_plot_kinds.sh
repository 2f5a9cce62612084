#!/usr/bin/env bash
# dynweigh plot draws each kind of CSV it knows from the header: a cycle (with a replay's
# prediction on it), a replay's decisions, and a bench's Pareto fronts; PNG and SVG.
set -euo pipefail
bin=$1; work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
cd "$work"
png() { [ "$(head -c 8 "$1" | od -An -tx1 | tr -d ' ')" = 89504e470d0a1a0a ] || { echo "$1 is no PNG"; exit 1; }; }

printf 'dose 3000\n' | "$bin/dynweigh-fw" --record run.rec --csv cycle.csv > /dev/null
"$bin/dynweigh" replay run.rec --csv replay.csv --quiet > /dev/null
"$bin/dynweigh" plot cycle.csv --replay replay.csv -o cycle.png | tee out.txt
grep -qx 'kind=cycle' out.txt
png cycle.png
"$bin/dynweigh" plot replay.csv --target 3000 -o replay.svg | grep -qx 'kind=replay'
grep -q '<svg' replay.svg
grep -q 'predicted final weight' replay.svg

cat > bench.csv <<'CSV'
strategy,knob,scene,target_g,time_ratio,sd_g,maxdev_g
model,0.5,default,10000,1.00,1.1,3.5
model,1.0,default,10000,1.05,0.9,2.4
model,2.0,default,10000,1.20,0.8,2.6
preact,100,default,10000,1.00,6.0,18.0
preact,200,default,10000,1.10,4.0,11.0
preact,400,default,10000,1.40,3.0,7.5
twostage,0.9,default,10000,1.60,1.5,4.0
CSV
"$bin/dynweigh" plot bench.csv -o bench.png | tee out.txt
grep -qx 'kind=bench' out.txt
grep -qx 'strategies=3' out.txt
png bench.png
# Wrong or damaged CSVs: one line, non-zero.
printf 'strategy,time_ratio,maxdev_g\nmodel,x,1\n' > bad_bench.csv
if "$bin/dynweigh" plot bad_bench.csv -o x.png 2> err.txt; then echo "accepted bad bench"; exit 1; fi
[ "$(wc -l < err.txt)" -eq 1 ]
if "$bin/dynweigh" plot cycle.csv --replay bad_bench.csv -o x.png 2> err.txt; then echo "accepted bad replay"; exit 1; fi
[ "$(wc -l < err.txt)" -eq 1 ]
