#!/usr/bin/env bash
# dynweigh bench --resume: after a journal cut in the middle of a line, after half its rows are
# deleted, and after a line is damaged, the rerun computes exactly the missing series and prints,
# writes and draws the same bytes as the uninterrupted run.
set -euo pipefail
bin=$1; work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
cd "$work"
grid=(--strategies model,preact --scenes default,ideal --targets 500,2000 --quiet)
series=8
have_png=0; if command -v gnuplot >/dev/null; then have_png=1; fi

run() {  # run NAME [options]: the bench into NAME.txt, NAME.csv (+ NAME.png), journal NAME.csv.journal
  local name=$1; shift
  local draw=(); if [ $have_png = 1 ]; then draw=(--png "$name.png"); fi
  "$bin/dynweigh" bench "${grid[@]}" --seeds 4 --csv "$name.csv" "${draw[@]}" "$@" >"$name.txt" 2>"$name.err"
}
same_as_reference() {
  cmp ref.txt "$1.txt" && cmp ref.csv "$1.csv"
  if [ $have_png = 1 ]; then cmp ref.png "$1.png"; fi
}
field() { grep -o "$1=[0-9]*" "$2" | cut -d= -f2; }
keys_of() { tail -n +2 "$1" | cut -f1 | sort; }

run ref
[ "$(field computed ref.err)" = $series ] && [ "$(field skipped ref.err)" = 0 ]
[ "$(wc -l < ref.csv.journal)" = $((series + 1)) ]

# 1. The writer died in the middle of the last line.
cp ref.csv.journal cut.csv.journal
truncate -s -20 cut.csv.journal
run cut --resume
same_as_reference cut
[ "$(field computed cut.err)" = 1 ] && [ "$(field skipped cut.err)" = $((series - 1)) ]
[ "$(field dropped_journal_lines cut.err)" = 1 ]
diff <(keys_of ref.csv.journal) <(keys_of cut.csv.journal)   # whole again, no duplicate, no fragment

# 2. Half the rows gone: exactly those are computed again (they are what the resume appends).
head -n $((series / 2 + 1)) ref.csv.journal > half.csv.journal
run half --resume
same_as_reference half
[ "$(field computed half.err)" = $((series / 2)) ] && [ "$(field skipped half.err)" = $((series / 2)) ]
diff <(tail -n +$((series / 2 + 2)) ref.csv.journal | cut -f1 | sort) <(tail -n +$((series / 2 + 2)) half.csv.journal | cut -f1 | sort)

# 3. A line damaged in the middle of the journal (its checksum fails): recomputed, not trusted.
sed '3s/fills=4/fills=5/' ref.csv.journal > damaged.csv.journal
run damaged --resume
same_as_reference damaged
[ "$(field computed damaged.err)" = 1 ]

# 4. A finished journal: nothing to compute, the same output.
cp ref.csv.journal done.csv.journal
run done --resume
same_as_reference done
[ "$(field computed done.err)" = 0 ] && [ "$(field skipped done.err)" = $series ]

# 5. A journal of another grid (other seeds) is refused with one line, and left as it was.
cp ref.csv.journal other.csv.journal
if "$bin/dynweigh" bench "${grid[@]}" --seeds 5 --csv other.csv --resume >/dev/null 2>other.err; then
  echo "resumed a journal of another grid"; exit 1
fi
[ "$(wc -l < other.err)" = 1 ] && grep -q 'another grid' other.err
cmp ref.csv.journal other.csv.journal

# 6. --resume needs somewhere to resume from.
if "$bin/dynweigh" bench "${grid[@]}" --seeds 4 --resume >/dev/null 2>none.err; then echo "resumed nothing"; exit 1; fi
grep -q -- '--journal' none.err
echo "resume: byte-identical after a cut line, half the rows gone, a damaged line"
