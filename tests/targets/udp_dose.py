#!/usr/bin/env python3
"""dynweigh plant and dynweigh-fw as two processes over udp on loopback: `dose 5000` reaches its
target, judged by the plant's truth (final_static_kg), not the firmware's claim."""
import argparse

from targets_common import fail, field, firmware_on_udp_plant, key_values

TOLERANCE_G = 100.0  # the class the in-process build reaches (tests/test_dose.cpp: worst 100 g)

a = argparse.ArgumentParser()
a.add_argument("--dynweigh", required=True)
a.add_argument("--fw", required=True)
a.add_argument("--seed", default="1")
args = a.parse_args()

fw, plant_out, plant_exit = firmware_on_udp_plant(
    args.dynweigh, args.fw, "default", "dose 5000\n", 40, plant_options=("--seed", args.seed))

if fw.returncode != 0:
    fail(f"dynweigh-fw exited {fw.returncode}")
if plant_exit != 0:
    fail(f"dynweigh plant exited {plant_exit}")
results = [l for l in fw.stdout.splitlines() if l.startswith("RESULT ")]
if len(results) != 1 or fw.stdout.splitlines()[-1] != "OK":
    fail("expected one RESULT line then OK")
kv = key_values(plant_out)
if kv.get("end") != "indicator_stopped":
    fail(f"plant ended with {kv.get('end')}, not indicator_stopped")
if kv.get("late_answers") != "0" or kv.get("answers") != kv.get("jiffies"):
    fail("lockstep broken: every sample must be answered exactly once with its counter")
true_g = float(kv["final_static_kg"]) * 1000.0
target = float(field(results[0], "target"))
reported = float(field(results[0], "final"))
print(f"true_fill_g={true_g:.1f} reported_final_g={reported:.0f} true_error_g={true_g - target:.1f}")
if abs(true_g - target) > TOLERANCE_G:
    fail(f"true fill {true_g:.1f} g is more than {TOLERANCE_G} g from the target {target:.0f} g")
if abs(reported - true_g) > 5.0:
    fail(f"the certified final {reported} g disagrees with the plant's truth {true_g:.1f} g")
print("PASS")
