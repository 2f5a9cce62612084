#!/usr/bin/env python3
"""dynweigh-fw's CAN node runs a batch on dynweigh plant's batching scene over udp:
`batch 0:2000 1:1500 2:1000`. Sand flows from the valve (0x220), barley and flour from their own
ingredient valves, opened by the firmware's 0x221 and 0x222 and proven by their 0x1A1 and 0x1A2
feedback: each ingredient's RESULT is what the plant says that ingredient released. A material whose
valve the plant has no module for (3) is refused before anything opens."""
import argparse

from targets_common import fail, field, firmware_on_udp_plant, key_values

a = argparse.ArgumentParser()
a.add_argument("--dynweigh", required=True)
a.add_argument("--fw", required=True)
args = a.parse_args()

fw, plant_out, plant_exit = firmware_on_udp_plant(
    args.dynweigh, args.fw, "batching", "status\nbatch 3:100\nbatch 0:2000 1:1500 2:1000\nstatus\n", 60)

if fw.returncode != 0 or plant_exit != 0:
    fail(f"dynweigh-fw exited {fw.returncode}, dynweigh plant {plant_exit}")
lines = fw.stdout.splitlines()
if not any(l.startswith("ERR 2 no valve for that material") for l in lines):
    fail("batch 3:100 was not refused on a plant with ingredient valves 0..2")
results = [l for l in lines if l.startswith("RESULT ")]
batch = [l for l in lines if l.startswith("BATCH ")]
if len(results) != 3 or len(batch) != 1 or field(batch[0], "ok") != "1":
    fail("expected three RESULT lines and BATCH ... ok=1")
if [field(r, "material") for r in results] != ["0", "1", "2"]:
    fail("the RESULT lines do not name materials 0, 1, 2 in turn")
kv = key_values(plant_out)
if kv.get("late_answers") != "0" or kv.get("answers") != kv.get("jiffies"):
    fail("lockstep broken: every sample must be answered exactly once with its counter")
if int(kv.get("ingredient_commands", "0")) == 0 or kv.get("ignored_ingredient_commands") != "0":
    fail("the plant heard no 0x221/0x222 from the firmware, or commands for valves it lacks")
for i in (1, 2):
    released_g = 1000.0 * float(kv[f"ingredient{i}_released_kg"])
    final_g = float(field(results[i], "final"))
    # The RESULT is certified once everything released has landed: the same mass, within 2 d.
    if abs(released_g - final_g) > 2.0:
        fail(f"ingredient {i}: the plant released {released_g:.1f} g, the RESULT says {final_g:.0f} g")
if "fault=none" not in lines[-2]:
    fail("the indicator is not without fault after the batch")
print("PASS")
