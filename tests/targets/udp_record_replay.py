#!/usr/bin/env python3
"""dynweigh-fw --record with a plant on CAN: dynweigh plant and dynweigh-fw --plant can:udp:... over
loopback, `dose 2000` recorded; `dynweigh replay` of that recording decides the same, every jiffy
(matches_recording=1), and prints the very console the live run printed."""
import argparse
import os
import subprocess
import tempfile

from targets_common import fail, free_udp_ports, key_values, stop

a = argparse.ArgumentParser()
a.add_argument("--dynweigh", required=True)
a.add_argument("--fw", required=True)
args = a.parse_args()

work = tempfile.mkdtemp()
recording = os.path.join(work, "can.rec")
console_out = os.path.join(work, "console.txt")
plant_port, fw_port = free_udp_ports(2)
plant = subprocess.Popen([args.dynweigh, "plant", "--can", f"udp:{plant_port}@127.0.0.1:{fw_port}",
                          "--scene", "default", "--seed", "1", "--wait", "20", "--timeout", "20"],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
try:
    fw = subprocess.run([args.fw, "--plant", f"can:udp:{fw_port}@127.0.0.1:{plant_port}", "--record", recording],
                        input="dose 2000\nstatus\n", capture_output=True, text=True, timeout=40)
    print("--- dynweigh-fw ---\n" + fw.stdout + fw.stderr)
    if fw.returncode != 0:
        fail(f"dynweigh-fw --record with a plant on CAN exited {fw.returncode}")
    plant_out, _ = plant.communicate(timeout=10)
finally:
    stop(plant)
if not any(l.startswith("RESULT ") for l in fw.stdout.splitlines()):
    fail("the live run printed no RESULT")

replay = subprocess.run([args.dynweigh, "replay", recording, "-q", "--console-out", console_out],
                        capture_output=True, text=True, timeout=60)
print("--- dynweigh replay ---\n" + replay.stdout + replay.stderr)
if replay.returncode != 0:
    fail(f"dynweigh replay of the CAN recording exited {replay.returncode}")
kv = key_values(replay.stdout)
plant_kv = key_values(plant_out)
if kv.get("format") != "inputs" or kv.get("matches_recording") != "1" or kv.get("results") != "1":
    fail("the CAN recording does not replay bit for bit")
source = [l for l in replay.stdout.splitlines() if l.startswith("source=")]
if not source or "--plant can:udp:" not in source[0]:
    fail(f"the recording's source note does not name the CAN plant: {source}")
if int(kv.get("jiffies", "0")) < int(plant_kv.get("answers", "1")):
    fail(f"the recording has {kv.get('jiffies')} jiffies, the plant was answered {plant_kv.get('answers')} times")
with open(console_out) as f:
    if f.read() != fw.stdout:
        fail("the replay's console differs from the live run's")
print("PASS")
