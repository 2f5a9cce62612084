#!/usr/bin/env bash
# A wrong argument to each option of every dynweigh subcommand and of dynweigh-fw: each is refused
# with exactly one line on stderr, nothing on stdout and a non-zero exit that is not a signal or a
# timeout, before any work is done.
set -uo pipefail
bin=$(cd "$1" && pwd); work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
failures=0

refused() {  # refused COMMAND...: COMMAND must refuse its arguments
  local rc start=$SECONDS
  timeout 30 "$@" >stdout 2>stderr </dev/null
  rc=$?
  local why=""
  if [ "$rc" -eq 0 ]; then why="exit 0"
  elif [ "$rc" -ge 124 ]; then why="exit $rc (a signal or the timeout)"
  elif [ "$(grep -c '' stderr)" -ne 1 ]; then why="$(grep -c '' stderr) lines on stderr"
  elif [ -s stdout ]; then why="$(wc -c <stdout) bytes on stdout"
  fi
  if [ -n "$why" ]; then
    echo "FAIL ($why): ${*#"$bin/"}"; head -c 400 stderr; echo
    failures=$((failures + 1))
  else
    echo "ok ($((SECONDS - start))s): ${*#"$bin/"} -> $(cat stderr)"
  fi
}

has() { "$bin/dynweigh" --help | grep -q "^  $1 "; }
printf 't_s,jiffy,static_kg,in_flight_kg,force_n,raw,filtered_g,valve\n0.00,0,0,0,0,8000,0,0\n0.01,1,0,0,0,8001,0,0\n' >cycle.csv
printf 'jiffy,raw\n0,8000\n1,8001\n' >raw.csv
mkdir adir
missing=$work/missing/file
unwritable=/nonexistent/dir/out

# dynweigh itself
refused "$bin/dynweigh" nosuch
refused "$bin/dynweigh" --bogus

# dynweigh-fw (each option; --plant, --console and --nvm belong to the firmware's own checks)
fw="$bin/dynweigh-fw"
refused "$fw" --bogus
refused "$fw" --plant sim:nosuch
refused "$fw" --plant bogus
refused "$fw" --console serial
refused "$fw" --seed x
refused "$fw" --seed -1
refused "$fw" --seed 1e3
refused "$fw" --realtime=3
refused "$fw" --plant-timeout -1
refused "$fw" --nvm-reset
refused "$fw" --csv "$unwritable.csv"
refused "$fw" --csv adir
refused "$fw" --record "$unwritable.rec"
refused "$fw" --record adir

# plot
refused "$bin/dynweigh" plot
refused "$bin/dynweigh" plot cycle.csv
refused "$bin/dynweigh" plot cycle.csv -o x.png --bogus
refused "$bin/dynweigh" plot "$missing.csv" -o x.png
refused "$bin/dynweigh" plot cycle.csv -o x.jpg
refused "$bin/dynweigh" plot cycle.csv -o "$unwritable.png"
refused "$bin/dynweigh" plot cycle.csv -o adir
refused "$bin/dynweigh" plot cycle.csv -o x.png --replay "$missing.csv"
refused "$bin/dynweigh" plot cycle.csv -o x.png --target x
refused "$bin/dynweigh" plot cycle.csv -o x.png --g x
refused "$bin/dynweigh" plot cycle.csv -o x.png --g nan
refused "$bin/dynweigh" plot cycle.csv -o x.png --target nan

if has sim; then
  refused "$bin/dynweigh" sim --bogus
  refused "$bin/dynweigh" sim --scene nosuch
  refused "$bin/dynweigh" sim --schedule sideways@3
  refused "$bin/dynweigh" sim --duration -1
  refused "$bin/dynweigh" sim --duration x
  refused "$bin/dynweigh" sim --duration nan
  refused "$bin/dynweigh" sim --csv "$unwritable.csv"
  refused "$bin/dynweigh" sim --csv adir
  refused "$bin/dynweigh" sim --seed x
  refused "$bin/dynweigh" sim --step 0.003
  refused "$bin/dynweigh" sim --step x
  refused "$bin/dynweigh" sim --step nan
  refused "$bin/dynweigh" sim --describe --scene nosuch
fi

if has bench; then
  b=(--scenes default --targets 500 --seeds 2 --quiet)
  refused "$bin/dynweigh" bench --bogus
  refused "$bin/dynweigh" bench "${b[@]}" --strategies sideways
  refused "$bin/dynweigh" bench "${b[@]}" --scenes nosuch
  refused "$bin/dynweigh" bench --scenes default --targets x --seeds 2 --quiet
  refused "$bin/dynweigh" bench --scenes default --targets 99999999 --seeds 2 --quiet
  refused "$bin/dynweigh" bench --scenes default --targets 500 --seeds 1 --quiet
  refused "$bin/dynweigh" bench "${b[@]}" --jobs 0
  refused "$bin/dynweigh" bench "${b[@]}" --sweep=x
  refused "$bin/dynweigh" bench "${b[@]}" --csv "$unwritable.csv"
  refused "$bin/dynweigh" bench "${b[@]}" --csv adir
  refused "$bin/dynweigh" bench "${b[@]}" --png "$unwritable.png"
  refused "$bin/dynweigh" bench "${b[@]}" --png x.svg
  refused "$bin/dynweigh" bench "${b[@]}" --journal "$unwritable.journal"
  refused "$bin/dynweigh" bench "${b[@]}" --resume
  refused "$bin/dynweigh" bench "${b[@]}" --quiet=x
  refused "$bin/dynweigh" bench --step --benchmark_bogus
  refused "$bin/dynweigh" bench --sim --bogus
fi

if has soc; then
  refused "$bin/dynweigh" soc --bogus
  refused "$bin/dynweigh" soc --dim 4
  refused "$bin/dynweigh" soc --size 2
  refused "$bin/dynweigh" soc --grains 0
  refused "$bin/dynweigh" soc --drop sideways
  refused "$bin/dynweigh" soc --seed x
  refused "$bin/dynweigh" soc --critical-slope 0
  refused "$bin/dynweigh" soc --grains 10 --csv "$unwritable.csv"
  refused "$bin/dynweigh" poisson --bogus
  refused "$bin/dynweigh" poisson --grid 2
  refused "$bin/dynweigh" poisson --shape hexagon
  refused "$bin/dynweigh" poisson --solver magic
  refused "$bin/dynweigh" poisson --tol -1
  refused "$bin/dynweigh" poisson --tol nan
  refused "$bin/dynweigh" poisson --side nan
  refused "$bin/dynweigh" poisson --source nan
  refused "$bin/dynweigh" poisson --source x
  refused "$bin/dynweigh" poisson --side 0
  refused "$bin/dynweigh" poisson --max-iterations 0
  refused "$bin/dynweigh" poisson --grid 9 --csv "$unwritable.csv"
  refused "$bin/dynweigh" dem --bogus
  refused "$bin/dynweigh" dem --scene nosuch
  refused "$bin/dynweigh" dem --close 0
  refused "$bin/dynweigh" dem --close nan
  refused "$bin/dynweigh" dem --discs-across 1
  refused "$bin/dynweigh" dem --orifice 0
  refused "$bin/dynweigh" dem --particles 0
  refused "$bin/dynweigh" dem --steps -1
  refused "$bin/dynweigh" dem --fill-steps -1
  refused "$bin/dynweigh" dem --stop-below -1
  refused "$bin/dynweigh" dem --sample-every 0
  refused "$bin/dynweigh" dem --seed x
  refused "$bin/dynweigh" dem --container-drop -1
  refused "$bin/dynweigh" dem --container-drop nan
  refused "$bin/dynweigh" dem --discs-across nan
  refused "$bin/dynweigh" dem --calibration-every 0
  refused "$bin/dynweigh" dem --silo2d --particles 50 --steps 10 --csv "$unwritable.csv"
  refused "$bin/dynweigh" calibrate
  refused "$bin/dynweigh" calibrate --from magic
  refused "$bin/dynweigh" calibrate --from soc --scene nosuch
  refused "$bin/dynweigh" calibrate --from soc --out "$unwritable.json"
  refused "$bin/dynweigh" calibrate --from dem --seeds 0
  refused "$bin/dynweigh" calibrate --from dem --jobs 0
  refused "$bin/dynweigh" calibrate --from dem --journal "$unwritable.journal" --seeds 1
  refused "$bin/dynweigh" calibrate --from dem --resume
  refused "$bin/dynweigh" calibrate --from dem --close 0
  refused "$bin/dynweigh" calibrate --from dem --close nan
  refused "$bin/dynweigh" calibrate --from dem --discs-across nan
  refused "$bin/dynweigh" calibrate --from dem --discs-across 1
  refused "$bin/dynweigh" calibrate --from dem --particles 1
  refused "$bin/dynweigh" calibrate --from dem --sweep x
  refused "$bin/dynweigh" calibrate --from soc --grains 1
  refused "$bin/dynweigh" calibrate --from soc --large-size -1
  refused "$bin/dynweigh" calibrate --from soc --critical-step 0
  refused "$bin/dynweigh" calibrate --from fluid --grid 2
  refused "$bin/dynweigh" calibrate --from dem --csv "$unwritable.csv" --seeds 1
  refused "$bin/dynweigh" calibrate --from soc --seed x
fi

if has plant; then
  port=$((40000 + $$ % 20000))
  can="udp:$port@127.0.0.1:$((port + 1))"
  refused "$bin/dynweigh" plant
  refused "$bin/dynweigh" plant --can "$can" --bogus
  refused "$bin/dynweigh" plant --can bogus
  refused "$bin/dynweigh" plant --can udp:x@y:z
  refused "$bin/dynweigh" plant --can "$can" --scene nosuch
  refused "$bin/dynweigh" plant --can "$can" --seed x
  refused "$bin/dynweigh" plant --can "$can" --replay "$missing.csv"
  refused "$bin/dynweigh" plant --can "$can" --replay adir
  refused "$bin/dynweigh" plant --can "$can" --jiffies -1
  refused "$bin/dynweigh" plant --can "$can" --wait x
  refused "$bin/dynweigh" plant --can "$can" --wait -1
  refused "$bin/dynweigh" plant --can "$can" --timeout -1
  refused "$bin/dynweigh" plant --can "$can" --wait nan
  refused "$bin/dynweigh" plant --can "$can" --timeout nan
  refused "$bin/dynweigh" plant --can "$can" --realtime=x
fi

if has replay; then
  refused "$bin/dynweigh" replay
  refused "$bin/dynweigh" replay raw.csv --quiet --bogus
  refused "$bin/dynweigh" replay "$missing.csv"
  refused "$bin/dynweigh" replay raw.csv --quiet --dose 100 --strategy sideways
  refused "$bin/dynweigh" replay raw.csv --quiet --dose x
  refused "$bin/dynweigh" replay raw.csv --quiet --at x
  refused "$bin/dynweigh" replay raw.csv --quiet --at -5 --dose 100
  refused "$bin/dynweigh" replay raw.csv --quiet --csv "$unwritable.csv"
  refused "$bin/dynweigh" replay raw.csv --quiet --console-out "$unwritable.txt"
  refused "$bin/dynweigh" replay raw.csv --quiet --scene nosuch
  refused "$bin/dynweigh" replay raw.csv --quiet --seed x
  refused "$bin/dynweigh" replay raw.csv --quiet --nvm "$missing.nvm"
  refused "$bin/dynweigh" replay raw.csv --quiet --zero-counts x
  refused "$bin/dynweigh" replay raw.csv --quiet --counts-per-gram -1
  refused "$bin/dynweigh" replay raw.csv --quiet --counts-per-gram nan
  refused "$bin/dynweigh" replay raw.csv --quiet --zero-counts nan
fi

if has term; then
  refused "$bin/dynweigh" term
  refused "$bin/dynweigh" term "$missing"
  refused "$bin/dynweigh" term /dev/null --bogus
  refused "$bin/dynweigh" term /dev/null --baud 12
  refused "$bin/dynweigh" term /dev/null --baud x
  refused "$bin/dynweigh" term /dev/null --timeout 0
  refused "$bin/dynweigh" term /dev/null --out "$unwritable.csv" --send status
  refused "$bin/dynweigh" term /dev/null --no-retry=x
fi

if has view; then
  refused "$bin/dynweigh" view --bogus
  refused "$bin/dynweigh" view --scene nosuch --frames 1
  refused "$bin/dynweigh" view --seed x
  refused "$bin/dynweigh" view --fps 0
  refused "$bin/dynweigh" view --speed 0
  refused "$bin/dynweigh" view --fps nan
  refused "$bin/dynweigh" view --speed nan
  refused "$bin/dynweigh" view --open-at nan
  refused "$bin/dynweigh" view --open-at x
  refused "$bin/dynweigh" view --close-at x
  refused "$bin/dynweigh" view --frames 0
  refused "$bin/dynweigh" view --screenshot x.png
  refused "$bin/dynweigh" view --frames 1 --screenshot x.jpg
  refused "$bin/dynweigh" view --frames 1 --screenshot "$unwritable.png"
  refused "$bin/dynweigh" view --width 10
  refused "$bin/dynweigh" view --height 10
fi

[ "$failures" -eq 0 ] || { echo "$failures wrong arguments not refused in one line"; exit 1; }
