#!/usr/bin/env bash
# `printf 'dose 10000\n' | dynweigh-fw --csv` prints a RESULT whose fill, by the plant's truth in the
# CSV, is within 100 g; the program exits 0 at end of input; `dynweigh plot` draws the CSV.
set -euo pipefail
bin=$1; work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
out=$(printf 'dose 10000\n' | "$bin/dynweigh-fw" --csv "$work/cycle.csv")
echo "$out"
result=$(grep '^RESULT ' <<<"$out")
[ "$(tail -n1 <<<"$out")" = OK ] || { echo "no OK after RESULT"; exit 1; }
[ "$(head -n1 "$work/cycle.csv")" = "t_s,jiffy,static_kg,in_flight_kg,force_n,raw,filtered_g,valve" ]
truth=$(awk -F, 'END { print $3 * 1000 }' "$work/cycle.csv")
python3 - "$result" "$truth" <<'PY'
import sys
fields = dict(kv.split("=") for kv in sys.argv[1].split()[1:])
truth = float(sys.argv[2])
assert fields["strategy"] == "model", fields
assert abs(truth - 10000) <= 100, f"true fill {truth} g"
assert abs(int(fields["final"]) - truth) <= 3, f"reported {fields['final']} vs true {truth}"
print(f"true_fill_g={truth:.1f} reported_final_g={fields['final']}")
PY
"$bin/dynweigh" plot "$work/cycle.csv" -o "$work/cycle.png" | grep -q '^plot='
[ "$(head -c 8 "$work/cycle.png" | od -An -tx1 | tr -d ' ')" = 89504e470d0a1a0a ]  # PNG signature
"$bin/dynweigh" plot "$work/cycle.csv" -o "$work/cycle.svg" >/dev/null
grep -q '<svg' "$work/cycle.svg"
