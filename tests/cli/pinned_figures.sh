#!/usr/bin/env bash
# The figures pinned to committed constants, on every host build (Release, Debug, ASan): the main
# job's dose gives these bytes of CSV and this RESULT, and a recording made by an earlier build
# (tests/data) still replays bit for bit. A change that moves them moves the constants, on purpose.
set -euo pipefail
bin=$(cd "$1" && pwd); data=$(cd "$(dirname "$0")/../data" && pwd); work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
cd "$work"

# 1. The main job: dose 10000 g on the default plant, seed 1 (tools/main-job.sh).
expected_csv_sha256=6527565c326288912b3eb318136bd95555050931be01f0adfd9f64da68bbdcd8
expected_result='RESULT target=10000 final=9984 error=-16 time=5520 cutoff=474 strategy=model'
printf 'dose 10000\n' | "$bin/dynweigh-fw" --csv cycle.csv > cycle.txt
# RESULT's six fields; the fields after them (tolerance=, topups=, seq=, ...) are read by key elsewhere.
result=$(grep '^RESULT' cycle.txt)
[ "${result%% tolerance=*}" = "$expected_result" ] || { echo "RESULT moved: $result"; exit 1; }
actual=$(sha256sum cycle.csv | cut -d' ' -f1)
[ "$actual" = "$expected_csv_sha256" ] || { echo "the dose's CSV moved: sha256 $actual"; exit 1; }

# 2. A committed recording made by an earlier build (dynweigh-fw --record, dose 2000 on the default
#    plant, seed 1; its settings record is version 4) still reads and replays. That build closed at
#    jiffy 143 (final 2075 g); this one's plan aims a close made before the stream is measured short of
#    the target, for top-ups to finish: it closes at jiffy 110, and the recording's 222 jiffies end
#    before its top-ups do, so the replay reports the mismatch (status 3) and no result.
recording=$data/dose_2000_default_seed1.rec
status=0
"$bin/dynweigh" replay "$recording" -q --console-out console.txt > summary.txt 2> replay.err || status=$?
cat summary.txt
[ "$status" = 0 ] || [ "$status" = 3 ] || { echo "replay of $recording: status $status: $(cat replay.err)"; exit 1; }
for line in format=inputs jiffies=222 open_loop=0 cutoff_jiffy=110 results=0 mismatch_jiffy=110; do
  grep -qxF "$line" summary.txt || { echo "replay of $recording: no $line"; exit 1; }
done

# 3. A recording this build makes replays bit for bit: the console, every jiffy.
printf 'dose 2000\n' | "$bin/dynweigh-fw" --record now.rec > now.txt
"$bin/dynweigh" replay now.rec -q --console-out now_console.txt > now_summary.txt
grep -qxF matches_recording=1 now_summary.txt || { echo "this build's recording replays differently"; cat now_summary.txt; exit 1; }
cmp now_console.txt now.txt
echo PASS
