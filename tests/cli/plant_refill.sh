#!/usr/bin/env bash
# A silo refilled from upstream: on a scene with silo.refill_below_kg, `dose 2000; dose 5000;
# dose 15000` in a row does not run the 18 kg silo dry; `plant` reports the silo and what was
# refilled, and `plant refill <kg>` pours material in.
set -euo pipefail
bin=$1; work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
python3 - "$work/refilled.json" <<'PY'
import json, sys
json.dump({"name": "refilled", "silo": {"fill_kg": 18.0, "refill_below_kg": 8.0, "refill_rate_kg_s": 4.0}},
          open(sys.argv[1], "w"))
PY
out=$(printf 'dose 2000\ndose 5000\ndose 15000\nplant\nplant refill 2.5\nplant\nplant refill -1\n' |
      "$bin/dynweigh-fw" --plant "sim:$work/refilled.json")
echo "$out"
if grep -q '^ERR 4' <<<"$out"; then echo "a dose faulted: the silo ran dry"; exit 1; fi
[ "$(grep -c '^RESULT ' <<<"$out")" = 3 ] || { echo "expected three RESULT lines"; exit 1; }
python3 - "$out" <<'PY'
import sys
lines = sys.argv[1].splitlines()
plants = [dict(kv.split("=") for kv in l.split()[1:]) for l in lines if l.startswith("PLANT ")]
assert len(plants) == 2, plants
first, second = plants
assert float(first["refilled_kg"]) > 0.0, first
assert float(first["silo_kg"]) > 0.0, first
assert abs(float(second["silo_kg"]) - float(first["silo_kg"]) - 2.5) < 1e-3, (first, second)
assert abs(float(second["refilled_kg"]) - float(first["refilled_kg"]) - 2.5) < 1e-3, (first, second)
assert lines[-1].startswith("ERR 2 "), lines[-1]
print(f"silo_kg={first['silo_kg']} refilled_kg={first['refilled_kg']}")
PY
