#!/usr/bin/env bash
# Outputs that cannot be written are refused before any work and never spill onto stdout:
# dynweigh plot to a missing folder writes no PNG bytes to stdout; dynweigh bench checks --csv,
# --png (a .png, gnuplot present) and --journal before the grid runs, so nothing is computed (no
# table on stdout). Each: one line on stderr, non-zero exit, no empty file left behind.
set -uo pipefail
bin=$(cd "$1" && pwd); work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
failures=0

refused_quietly() {  # refused_quietly COMMAND...: non-zero, one line on stderr, stdout empty
  local rc
  timeout 60 "$@" >stdout 2>stderr </dev/null
  rc=$?
  local why=""
  if [ "$rc" -eq 0 ]; then why="exit 0"
  elif [ "$rc" -ge 124 ]; then why="exit $rc (a signal or the timeout)"
  elif [ -s stdout ]; then why="$(wc -c <stdout) bytes on stdout"
  elif [ "$(grep -c '' stderr)" -ne 1 ]; then why="$(grep -c '' stderr) lines on stderr"
  fi
  if [ -n "$why" ]; then
    echo "FAIL ($why): ${*#"$bin/"}"; head -c 300 stderr | tr -c '[:print:]\n' '?'; echo
    failures=$((failures + 1))
  else
    echo "ok: ${*#"$bin/"} -> $(cat stderr)"
  fi
}

printf 'dose 3000\n' | "$bin/dynweigh-fw" --csv cycle.csv >/dev/null || { echo "cannot make a cycle CSV"; exit 1; }
mkdir adir dir.png

refused_quietly "$bin/dynweigh" plot cycle.csv -o /nonexistent/dir/x.png
refused_quietly "$bin/dynweigh" plot cycle.csv -o dir.png
refused_quietly "$bin/dynweigh" plot missing.csv -o left.png
[ ! -e left.png ] || { echo "FAIL: a refused plot left left.png behind"; failures=$((failures + 1)); }
"$bin/dynweigh" plot cycle.csv -o good.png | grep -qx 'kind=cycle' || { echo "FAIL: a good plot"; failures=$((failures + 1)); }
[ "$(head -c 4 good.png | od -An -c | tr -d ' ')" = '211PNG' ] || { echo "FAIL: good.png is no PNG"; failures=$((failures + 1)); }

if "$bin/dynweigh" --help | grep -q '^  bench '; then
  grid=(bench --strategies preact --scenes default --targets 5000 --seeds 2 --quiet)
  refused_quietly "$bin/dynweigh" "${grid[@]}" --csv adir
  refused_quietly "$bin/dynweigh" "${grid[@]}" --csv /nonexistent/dir/x.csv
  refused_quietly "$bin/dynweigh" "${grid[@]}" --png /nonexistent/dir/x.png
  refused_quietly "$bin/dynweigh" "${grid[@]}" --png dir.png
  refused_quietly "$bin/dynweigh" "${grid[@]}" --png x.svg
  refused_quietly "$bin/dynweigh" "${grid[@]}" --journal /nonexistent/dir/x.journal
  refused_quietly "$bin/dynweigh" "${grid[@]}" --csv ok.csv --png /nonexistent/dir/x.png
  [ ! -e ok.csv ] || { echo "FAIL: a refused bench left ok.csv behind"; failures=$((failures + 1)); }
  "$bin/dynweigh" "${grid[@]}" --csv b.csv --png b.png >/dev/null 2>&1 || { echo "FAIL: a good bench"; failures=$((failures + 1)); }
  [ "$(head -n1 b.csv | cut -d, -f1)" = strategy ] && [ -s b.png ] || { echo "FAIL: a good bench's files"; failures=$((failures + 1)); }
fi

[ "$failures" -eq 0 ] || { echo "$failures outputs not refused cleanly"; exit 1; }
