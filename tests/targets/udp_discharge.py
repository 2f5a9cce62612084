#!/usr/bin/env python3
"""dynweigh-fw's CAN node drives the discharge gate of dynweigh plant over udp: `dose 2000` then
`discharge`. The firmware sends 0x228 (the plant counts gate_opens and lets the hopper out) and
proves the gate by the 0x1A8 feedback it reads (open, then closed: `discharge` answers OK); the
plant's truth says the hopper is empty again."""
import argparse

from targets_common import fail, firmware_on_udp_plant, key_values

a = argparse.ArgumentParser()
a.add_argument("--dynweigh", required=True)
a.add_argument("--fw", required=True)
args = a.parse_args()

fw, plant_out, plant_exit = firmware_on_udp_plant(
    args.dynweigh, args.fw, "default", "dose 2000\ndischarge\nstatus\n", 40)

if fw.returncode != 0 or plant_exit != 0:
    fail(f"dynweigh-fw exited {fw.returncode}, dynweigh plant {plant_exit}")
lines = fw.stdout.splitlines()
results = [i for i, l in enumerate(lines) if l.startswith("RESULT ")]
if len(results) != 1 or lines[results[0] + 1] != "OK":
    fail("expected the dose's RESULT then OK")
if lines[results[0] + 2] != "OK":
    fail(f"discharge answered {lines[results[0] + 2]!r}, not OK (the gate's 0x1A8 feedback not read?)")
if "fault=none" not in fw.stdout or "state=idle" not in fw.stdout:
    fail("the indicator is not idle without fault after the discharge")
kv = key_values(plant_out)
if kv.get("late_answers") != "0" or kv.get("answers") != kv.get("jiffies"):
    fail("lockstep broken: every sample must be answered exactly once with its counter")
if kv.get("gate_opens") != "1":
    fail(f"the plant's gate opened {kv.get('gate_opens')} times, not once (no 0x228 from the firmware?)")
if float(kv["discharged_kg"]) < 1.9 or float(kv["final_static_kg"]) > 0.02:
    fail(f"the hopper was not emptied: discharged_kg={kv['discharged_kg']} final_static_kg={kv['final_static_kg']}")
print("PASS")
