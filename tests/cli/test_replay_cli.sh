#!/usr/bin/env bash
# dynweigh replay: a `dynweigh-fw --record` run replays bit for bit (console bytes, valve and
# filtered weight per jiffy); raw samples replay open loop and say so; bad files are refused with
# one line and a non-zero exit.
set -euo pipefail
bin=$1; work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
cd "$work"

# 1. Live run, recorded; replay; compare.
printf 'dose 3000\n' | "$bin/dynweigh-fw" --record live.rec --csv live.csv > live.txt
grep -q '^RESULT target=3000' live.txt
"$bin/dynweigh" replay live.rec --csv replay.csv --console-out replay.txt > summary.txt
cat summary.txt
grep -qx 'format=inputs' summary.txt
grep -qx 'open_loop=0' summary.txt
grep -qx 'matches_recording=1' summary.txt
grep -qx 'results=1' summary.txt
cmp live.txt replay.txt  # the console, byte for byte
[ "$(head -n1 replay.csv)" = "t_s,jiffy,raw,gross_g,filtered_g,prediction_g,valve,state,recorded_valve" ]
# per jiffy: raw, filtered weight and valve as the live run's CSV has them
cut -d, -f6,7,8 live.csv | tail -n +2 > live.cols
awk -F, 'NR > 1 { print $3 "," $5 "," $7 }' replay.csv > replay.cols
[ "$(wc -l < live.cols)" -gt 200 ]  # the dose to its RESULT (the test data records on, unwaited)
cmp live.cols replay.cols
cutoff=$(grep '^cutoff_jiffy=' summary.txt | cut -d= -f2)
live_cutoff=$(awk -F, 'NR > 2 && prev != 0 && $8 == 0 { print $2; exit } { prev = $8 }' live.csv)
[ "$cutoff" = "$live_cutoff" ] || { echo "cutoff $cutoff, live $live_cutoff"; exit 1; }

# 2. The same samples as a raw CSV, replayed open loop with the same command at the same jiffy (the
#    dose was sent at jiffy 0 and opened once the scale had rested): same decisions.
"$bin/dynweigh" replay live.csv --dose 3000 --at 0 --console-out raw.txt > raw_summary.txt 2> raw_err.txt
grep -qx 'open_loop=1' raw_summary.txt
grep -q 'OPEN LOOP' raw_err.txt
grep -q '^RESULT' raw.txt
[ "$(grep '^RESULT' raw.txt)" = "$(grep '^RESULT' live.txt)" ]

# 3. A readtestdata capture, as the indicator printed it (OK lines and all).
printf 'starttestdata 50 600\nreadtestdata\n' | "$bin/dynweigh-fw" > capture.txt
"$bin/dynweigh" replay capture.txt --dose auto --csv capture_replay.csv --quiet > cap_summary.txt
cat cap_summary.txt
grep -qx 'format=readtestdata' cap_summary.txt
grep -qx 'jiffies=1000' cap_summary.txt
grep -qx 'open_loop=1' cap_summary.txt
grep -qx 'recorded_cutoff_jiffy=600' cap_summary.txt
grep -q '^cutoff_jiffy=[1-9]' cap_summary.txt
"$bin/dynweigh" plot capture_replay.csv -o replay.png | grep -qx 'kind=replay'
[ "$(head -c 8 replay.png | od -An -tx1 | tr -d ' ')" = 89504e470d0a1a0a ]

# 4. Damaged and wrong files: one line, non-zero exit, never a crash.
expect_failure() {
  local err status=0
  err=$(timeout 20 "$@" 2>&1 >/dev/null) || status=$?
  [ "$status" -ne 0 ] || { echo "succeeded: $*"; exit 1; }
  [ "$status" -lt 128 ] && [ "$status" -ne 124 ] || { echo "crashed or hung ($status): $*"; exit 1; }
  [ "$(wc -l <<<"$err")" -eq 1 ] || { echo "not one line: $*: $err"; exit 1; }
  echo "ok: $* -> $err"
}
head -c -3 live.rec > truncated.rec
expect_failure "$bin/dynweigh" replay truncated.rec
head -c 40 live.rec > header_only.rec
expect_failure "$bin/dynweigh" replay header_only.rec
head -c 100000 /dev/urandom > binary.bin
expect_failure "$bin/dynweigh" replay binary.bin
{ printf 'dynweigh-inputs\n'; head -c 5000 /dev/urandom; } > fake.rec
expect_failure "$bin/dynweigh" replay fake.rec
truncate -s 3G enormous.bin
expect_failure "$bin/dynweigh" replay enormous.bin
head -c 20000000 /dev/zero | tr '\0' '7' > one_long_line.txt
expect_failure "$bin/dynweigh" replay one_long_line.txt
: > empty.txt
expect_failure "$bin/dynweigh" replay empty.txt
expect_failure "$bin/dynweigh" replay missing.rec
expect_failure "$bin/dynweigh" replay .
expect_failure "$bin/dynweigh" replay live.rec --dose 100
expect_failure "$bin/dynweigh" replay live.rec --strategy sideways
expect_failure "$bin/dynweigh" replay capture.txt --dose -5
"$bin/dynweigh" replay --help | grep -q 'OPEN LOOP'

# A recording begun on a board whose logbook already holds a result numbers its RESULT on from it,
# and so does the replay.
printf 'dose 1000\n' | "$bin/dynweigh-fw" --nvm board.nvm > /dev/null
printf 'dose 1000\n' | "$bin/dynweigh-fw" --nvm board.nvm --record second.rec > second.txt
grep -q '^RESULT .* seq=2' second.txt
"$bin/dynweigh" replay second.rec -q > second_summary.txt
grep -qxF result_seq=2 second_summary.txt
grep -qxF matches_recording=1 second_summary.txt
