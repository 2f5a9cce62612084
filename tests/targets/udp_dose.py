#!/usr/bin/env python3
"""dynweigh plant and dynweigh-fw as two processes over udp on loopback: `dose 5000` reaches its
target, judged by the plant's truth (final_static_kg), not the firmware's claim."""
import argparse
import subprocess
import sys

from targets_common import fail, free_udp_ports, key_values, field, stop

TOLERANCE_G = 100.0  # the class the in-process build reaches (tests/test_dose.cpp: worst 100 g)

a = argparse.ArgumentParser()
a.add_argument("--dynweigh", required=True)
a.add_argument("--fw", required=True)
a.add_argument("--seed", default="1")
args = a.parse_args()

plant_port, fw_port = free_udp_ports(2)
plant = subprocess.Popen([args.dynweigh, "plant", "--can", f"udp:{plant_port}@127.0.0.1:{fw_port}",
                          "--scene", "default", "--seed", args.seed, "--wait", "20", "--timeout", "20"],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
try:
    fw = subprocess.run([args.fw, "--plant", f"can:udp:{fw_port}@127.0.0.1:{plant_port}"],
                        input="dose 5000\n", capture_output=True, text=True, timeout=40)
    plant_out, _ = plant.communicate(timeout=10)
finally:
    stop(plant)
print("--- dynweigh-fw ---\n" + fw.stdout + fw.stderr)
print("--- dynweigh plant ---\n" + plant_out)

if fw.returncode != 0:
    fail(f"dynweigh-fw exited {fw.returncode}")
if plant.returncode != 0:
    fail(f"dynweigh plant exited {plant.returncode}")
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
