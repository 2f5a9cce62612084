#!/usr/bin/env bash
# The batch recipe of docs/console.md on the in-process batching scene (sand, barley, flour, each
# from its own valve into one hopper): three RESULT lines, one per material in turn, BATCH ... ok=1
# with their sum; by the plant's truth (--csv: the mass on the scale when each valve first opens and
# at the end) each ingredient is within its OIML R61 X(1) initial-verification limit of its target,
# and its RESULT says what it delivered. Recorded, the batch replays to the same outputs.
set -euo pipefail
bin=$1; work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
out=$(printf 'material 0 name sand\nmaterial 1 name barley\nmaterial 1 density 700\nmaterial 2 name flour\nmaterial 2 density 500\nbatch 0:10000 1:5000 2:4000\n' |
      "$bin/dynweigh-fw" --plant sim:batching --csv "$work/batch.csv" --record "$work/batch.rec")
echo "$out"
python3 - "$out" "$work/batch.csv" 10000 5000 4000 <<'PY'
import csv, sys
out, path, targets = sys.argv[1], sys.argv[2], [int(t) for t in sys.argv[3:]]
lines = out.splitlines()
kv = lambda line: dict(w.split("=", 1) for w in line.split()[1:] if "=" in w)
results = [kv(l) for l in lines if l.startswith("RESULT ")]
batches = [kv(l) for l in lines if l.startswith("BATCH ")]
assert len(results) == 3, f"expected three RESULT lines: {results}"
assert [r["material"] for r in results] == ["0", "1", "2"], results
assert [int(r["target"]) for r in results] == targets, results
assert len(batches) == 1 and batches[0]["ok"] == "1" and batches[0]["ingredients"] == "3", batches
assert int(batches[0]["total_g"]) == sum(int(r["final"]) for r in results), batches
assert lines[-1] == "OK", lines[-1]

def x1_initial_g(m):  # OIML R61 X(1), initial verification
    for upto, limit in ((50, 0.063 * m), (100, 3.15), (200, 0.0315 * m), (300, 6.3), (500, 0.021 * m),
                        (1000, 10.5), (10000, 0.0105 * m), (15000, 105.0)):
        if m <= upto:
            return limit
    return 0.007 * m

rows = list(csv.DictReader(open(path)))
# Each ingredient is one opening of a valve and one more per top-up pulse its RESULT counts (a close
# the model's plan aimed short is topped up whatever tol_action says), and what it delivered is the
# mass on the scale at the next ingredient's first opening (or the end) less that at its own.
opens = [i for i in range(1, len(rows)) if rows[i]["valve"] != "0" and rows[i - 1]["valve"] == "0"]
openings = [1 + int(r["topups"]) for r in results]
assert len(opens) == sum(openings), f"expected {sum(openings)} valve openings, found {len(opens)}"
firsts = [opens[sum(openings[:k])] for k in range(len(results))]
marks = [float(rows[i]["static_kg"]) * 1000.0 for i in firsts] + [float(rows[-1]["static_kg"]) * 1000.0]
failed = []
for k, (target, result) in enumerate(zip(targets, results)):
    truth = marks[k + 1] - marks[k]
    limit = x1_initial_g(target)
    print(f"material {k}: target={target} truth={truth:.1f} error={truth - target:+.1f} X(1)={limit:.1f} "
          f"result={result['final']}")
    if abs(truth - target) > limit:
        failed.append(f"material {k} off by {truth - target:+.1f} g, beyond X(1) {limit:.1f} g")
    if abs(truth - float(result["final"])) > 2.0:
        failed.append(f"material {k}: RESULT final={result['final']} but the plant delivered {truth:.1f} g")
assert not failed, failed
PY
replayed=$("$bin/dynweigh" replay "$work/batch.rec")
grep -qx 'matches_recording=1' <<<"$replayed" || { echo "$replayed"; echo "the recorded batch does not replay"; exit 1; }
