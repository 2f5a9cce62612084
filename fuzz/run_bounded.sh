#!/usr/bin/env bash
# One bounded libFuzzer run for CTest: over a fresh copy of the committed corpus (the tree's corpus
# stays as committed), failing on any crash, leak, timeout or out-of-memory; prints the number of
# executions. Usage: run_bounded.sh FUZZER CORPUS_DIR WORK_DIR SECONDS [DICTIONARY]
set -uo pipefail
fuzzer=$1 corpus=$2 work=$3 seconds=$4 dict=${5:-}
rm -rf "$work" && mkdir -p "$work/corpus" "$work/artifacts" || exit 1
cp -R "$corpus"/. "$work/corpus/" || exit 1
# A fixed seed: CI replays the input sequence that was run here (DYNWEIGH_FUZZ_SEED=0 for a random one).
args=(-max_total_time="$seconds" -seed="${DYNWEIGH_FUZZ_SEED:-1}" -print_final_stats=1 -timeout=10 -rss_limit_mb=2048 -max_len=4096
      -artifact_prefix="$work/artifacts/")
[ -n "$dict" ] && args+=(-dict="$dict")
"$fuzzer" "${args[@]}" "$work/corpus" >"$work/log" 2>&1
status=$?
executions=$(sed -n 's/^stat::number_of_executed_units: *//p' "$work/log")
echo "$(basename "$fuzzer"): executions=${executions:-?} seconds=$seconds corpus=$(ls "$work/corpus" | wc -l) exit=$status"
if [ "$status" != 0 ] || [ -z "$executions" ]; then
  tail -n 60 "$work/log"
  ls "$work/artifacts"
  exit 1
fi
