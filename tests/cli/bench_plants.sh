#!/usr/bin/env bash
# dynweigh bench --plants: a tiny family run prints one well-formed line per strategy x plant x
# target it holds, a summary per strategy and the model's speed comparison, the same bytes twice; wrong --plants specs and options
# that do not go with it are refused in one line with a non-zero exit, before any work.
set -uo pipefail
bin=$(cd "$1" && pwd); work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
"$bin/dynweigh" --help | grep -q '^  bench ' || exit 77
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

refused() {  # refused ARGS...: dynweigh bench ARGS must refuse them
  timeout 60 "$bin/dynweigh" bench "$@" >stdout 2>stderr </dev/null
  local rc=$?
  if [ "$rc" -eq 0 ] || [ "$rc" -ge 124 ]; then fail "exit $rc: bench $*"
  elif [ "$(grep -c '' stderr)" -ne 1 ]; then fail "$(grep -c '' stderr) lines on stderr: bench $*"; cat stderr
  elif [ -s stdout ]; then fail "output on stdout: bench $*"
  else echo "ok: bench $* -> $(cat stderr)"
  fi
}

for spec in random:0 random:x foo:3 random:3@-1 random: random:3@ random:3@x random:10001 'random:2 '; do
  refused --plants "$spec" --quiet
done
refused --plants random:2 --fills 1 --quiet
refused --plants random:2 --scenes default --quiet
refused --plants random:2 --seeds 5 --quiet
refused --plants random:2 --strategies oracle --quiet
refused --plants random:2 --strategies sideways --quiet
refused --plants random:2 --targets x --quiet
refused --fills 3 --scenes default --targets 500 --seeds 2 --quiet
refused --plants random:2 --ceiling --strategies model --quiet
refused --ceiling --scenes default --targets 500 --seeds 2 --quiet
"$bin/dynweigh" bench --help | grep -q -- '--plants' || fail "bench --help does not mention --plants"

run=(--plants random:2@3 --fills 2 --targets 500,2000 --strategies model,twostage --quiet)
timeout 300 "$bin/dynweigh" bench "${run[@]}" --jobs 2 >out.txt 2>err.txt || fail "the tiny run failed: $(cat err.txt)"
[ -s err.txt ] && fail "the tiny run wrote to stderr: $(cat err.txt)"
cells='^strategy=(model|twostage) plant=random-[12] target_g=(500|2000) class_first=(X\([0-9.]+\)|none) '
cells+='class_steady=(X\([0-9.]+\)|none) time_ratio=[0-9.]+ topups=[0-9]+ first_error_g=-?[0-9.]+ '
cells+='steady_bias_g=-?[0-9.]+ steady_maxdev_g=[0-9.]+ failed=[0-9]+ failure=[^ ]+$'
summary='^summary strategy=(model|twostage) plants=2 seed=3 fills=2 cells=[0-9]+ first_x1_share=[01]\.[0-9]{3} steady_x1_share=[01]\.[0-9]{3}$'
comparison='^summary comparison=model baselines=twostage cells=[0-9]+ faster_cells=[0-9]+ faster_share=[01]\.[0-9]{3} '
comparison+='faster_cells_x1=[0-9]+ faster_share_x1=[01]\.[0-9]{3} unbeaten_cells=[0-9]+ unbeaten_share=[01]\.[0-9]{3}$'
n_cells=$(grep -cE "$cells" out.txt)
n_summaries=$(grep -cE "$summary" out.txt)
[ "$n_summaries" -eq 2 ] || fail "$n_summaries summary lines, not 2"
[ "$n_cells" -ge 2 ] && [ "$n_cells" -le 8 ] || fail "$n_cells cell lines, not 2..8"
tail -1 out.txt | grep -qE "$comparison" || fail "the last line is not the comparison: $(tail -1 out.txt)"
[ "$((n_cells + n_summaries + 1))" -eq "$(grep -c '' out.txt)" ] || fail "lines neither cells nor summaries"
[ "$(grep -c '^strategy=model ' out.txt)" -eq "$(grep -c '^strategy=twostage ' out.txt)" ] ||
  fail "the strategies met different cells"
# The summaries come last and count the cells above them.
tail -3 out.txt | head -1 | grep -q '^summary strategy=model ' || fail "the summaries are not the last lines"
model_cells=$(grep -c '^strategy=model ' out.txt)
grep -q "^summary strategy=model .* cells=$model_cells " out.txt || fail "the model summary miscounts its cells"
# The comparison, counted again here: the model faster than twostage at an equal or better steady
# class (no class: worse than any), the same with every class within X(1) taken as X(1), and the
# model with a class that twostage did not reach in at most its time.
expected=$(awk '
  function cls(line) { if (match(line, /class_steady=X\([0-9.]+\)/)) return substr(line, RSTART + 15, RLENGTH - 16) + 0; return 1e9 }
  function field(line, key) { match(line, " " key "=[^ ]+"); return substr(line, RSTART + length(key) + 2, RLENGTH - length(key) - 2) }
  /^strategy=/ { key = field($0, "plant") " " field($0, "target_g"); c[$1, key] = cls($0); t[$1, key] = field($0, "time_ratio") + 0; keys[key] = 1 }
  END {
    for (k in keys) {
      m = c["strategy=model", k]; b = c["strategy=twostage", k]; tm = t["strategy=model", k]; tb = t["strategy=twostage", k]
      if (tb <= 0) tb = 1e9
      n++; f += (m <= b && tm < tb); f1 += ((m < 1 ? 1 : m) <= (b < 1 ? 1 : b) && tm < tb)
      u += (m < 1e9 && !(b <= m && tb <= tm))
    }
    printf "cells=%d faster_cells=%d ", n, f; printf "faster_cells_x1=%d unbeaten_cells=%d\n", f1, u
  }' out.txt)
got=$(tail -1 out.txt |
  sed -E 's/.*(cells=[0-9]+ faster_cells=[0-9]+) .*(faster_cells_x1=[0-9]+) .*(unbeaten_cells=[0-9]+).*/\1 \2 \3/')
[ "$got" = "$expected" ] || fail "the comparison says $got, the cells say $expected"
timeout 300 "$bin/dynweigh" bench "${run[@]}" --jobs 1 >again.txt 2>/dev/null
cmp -s out.txt again.txt || fail "a second run (one thread) printed other bytes"
cat out.txt

# --ceiling: a line per cell with two chances, and a summary whose shares are their means.
timeout 300 "$bin/dynweigh" bench --plants random:2@3 --ceiling --targets 500 --quiet --jobs 2 >ceiling.txt 2>err.txt ||
  fail "the ceiling run failed: $(cat err.txt)"
ceiling_cells=$(grep -cE '^ceiling plant=random-[12] target_g=500 first=[01]\.[0-9]{3} steady=[01]\.[0-9]{3}$' ceiling.txt)
[ "$ceiling_cells" -ge 1 ] && [ "$((ceiling_cells + 1))" -eq "$(grep -c '' ceiling.txt)" ] ||
  fail "the ceiling run printed other lines: $(cat ceiling.txt)"
means=$(awk '/^ceiling /{ split($4, f, "="); split($5, s, "="); n++; a += f[2]; b += s[2] }
  END { printf "cells=%d first_x1_share=%.3f steady_x1_share=%.3f", n, a / n, b / n }' ceiling.txt)
tail -1 ceiling.txt | grep -qE "^summary ceiling plants=2 seed=3 fills=6 pulses=3 $means$" ||
  fail "the ceiling summary is not the cells' means ($means): $(tail -1 ceiling.txt)"
cat ceiling.txt

# Three plants of families no change was tuned on whose valves (about 78 ms of dead time, 11 ms of
# jitter) had a close faulted `valve_stuck_open`: the bench starts every fill from a power-up, and the
# one opening timed since came out 2.5 sigmas short. The dead time the material kept now sets the
# limit (docs/console.md, Faults).
for case in "183@11 500,1000 random-183" "123@13 500,1000 random-123" "58@17 500,1000,2000,5000,10000 random-58"; do
  read -r family targets plant <<<"$case"
  timeout 300 "$bin/dynweigh" bench --plants "random:$family" --targets "$targets" --strategies model --quiet \
    --jobs 2 >restart.txt 2>/dev/null || fail "the run of random:$family failed"
  n_fills=$(grep -c "^strategy=model plant=$plant " restart.txt)
  n_clean=$(grep -c "^strategy=model plant=$plant .* failed=0 failure=-$" restart.txt)
  [ "$n_fills" -ge 2 ] && [ "$n_fills" -eq "$n_clean" ] ||
    fail "random:$family, $plant: $((n_fills - n_clean)) of $n_fills cells with a failed fill: $(grep "plant=$plant " restart.txt)"
done

[ "$failures" -eq 0 ] && echo "bench --plants: all checks passed" || exit 1
