#!/usr/bin/env python3
"""HIL replay: a `readtestdata` capture from one run is played by `dynweigh plant --replay` over
udp into a second dynweigh-fw; that firmware's own readtestdata shows the same raw samples."""
import argparse
import os
import subprocess
import tempfile

from targets_common import fail, free_udp_ports, key_values, stop

a = argparse.ArgumentParser()
a.add_argument("--dynweigh", required=True)
a.add_argument("--fw", required=True)
args = a.parse_args()

# 1. A recording: a test cycle on the in-process plant.
rec = subprocess.run([args.fw, "--seed", "3"], input="starttestdata 50 600\nreadtestdata\n",
                     capture_output=True, text=True, timeout=30)
records = [l.split() for l in rec.stdout.splitlines() if len(l.split()) == 4]
if rec.returncode != 0 or len(records) != 1000:
    fail(f"recording failed: exit {rec.returncode}, {len(records)} records\n{rec.stderr}")

with tempfile.TemporaryDirectory() as d:
    capture = os.path.join(d, "capture.txt")
    with open(capture, "w") as f:  # twice: the replayed cycle and its printing need more than 1000 jiffies
        f.write(rec.stdout + rec.stdout)
    plant_port, fw_port = free_udp_ports(2)
    plant = subprocess.Popen([args.dynweigh, "plant", "--can", f"udp:{plant_port}@127.0.0.1:{fw_port}",
                              "--replay", capture, "--wait", "20", "--timeout", "20"],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        # 2. Replayed into a fresh indicator: the same test cycle, started at the first sample.
        # The commands from a file, there before the first sample: the board polls stdin and does not
        # wait for it, so a pipe's first line could come a few samples in.
        commands = os.path.join(d, "commands.txt")
        with open(commands, "w") as f:
            f.write("starttestdata 50 600\nreadtestdata\n")
        with open(commands) as stdin:
            fw = subprocess.run([args.fw, "--plant", f"can:udp:{fw_port}@127.0.0.1:{plant_port}"],
                                stdin=stdin, capture_output=True, text=True, timeout=40)
        plant_out, _ = plant.communicate(timeout=10)
    finally:
        stop(plant)

print("--- dynweigh plant --replay ---\n" + plant_out)
kv = key_values(plant_out)
replayed = [l.split() for l in fw.stdout.splitlines() if len(l.split()) == 4]
if fw.returncode != 0 or len(replayed) != 1000:
    fail(f"replayed run: exit {fw.returncode}, {len(replayed)} records\n{fw.stderr}")
if kv.get("replay_samples") != "2000" or kv.get("late_answers") != "0" or kv.get("end") != "indicator_stopped":
    fail("the plant did not replay the samples in lockstep until the indicator stopped")
# The firmware recorded exactly the raw samples it was fed, in order (jiffy column aside).
original = [r[1] for r in records]
seen = [r[1] for r in replayed]
offset = next((k for k in range(0, 5) if seen[: 1000 - k] == original[k:]), None)
if offset is None:
    fail("replayed raw samples differ from the recording")
# The valve schedule follows the commands the replayed firmware gave.
if kv.get("first_open_jiffy") in (None, "-1"):
    fail("the replayed firmware never opened the valve")
print(f"replay_offset_jiffies={offset}")
print("PASS")
