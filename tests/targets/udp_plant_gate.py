#!/usr/bin/env python3
"""dynweigh plant's discharge gate module over udp, driven by an indicator written here: the test
sends 0x220 valve answers in lockstep and 0x228 gate commands before them, and reads the 0x1A8
feedback the plant sends with each sample. The valve fills the hopper; the gate opened at jiffy 300
reports moving then open (its stroke time), the load cell falls back to the empty hopper, the gate
closed at jiffy 600 reports moving then closed; the plant's summary says what it let out."""
import argparse
import socket
import struct
import time

from targets_common import fail, frame, key_values, parse, plant_on_udp, stop

ID_SAMPLE, ID_VALVE_COMMAND, ID_GATE_COMMAND, ID_GATE_FEEDBACK = 0x190, 0x220, 0x228, 0x1A8
JIFFIES = 700
VALVE_OPEN = range(0, 150)     # 1.5 s of full flow: about 3 kg
GATE_OPEN = range(300, 600)    # 3 s open: enough to empty it
COUNTS_PER_G = 1.0             # the default scene: 1 count per gram


a = argparse.ArgumentParser()
a.add_argument("--dynweigh", required=True)
args = a.parse_args()

sock, peer, plant = plant_on_udp(args.dynweigh, "default", JIFFIES)
gate_positions, raws = [], []
try:
    # Heartbeats until the plant's first sample: it starts once it has heard the indicator.
    sock.settimeout(0.1)
    deadline = time.monotonic() + 20
    feedback = None
    jiffy = 0
    while jiffy < JIFFIES:
        if time.monotonic() > deadline:
            fail(f"no sample {jiffy} from the plant")
        if jiffy == 0:
            sock.sendto(frame(0x701, [0x05]), peer)
        try:
            can_id, data = parse(sock.recv(64))
        except socket.timeout:
            continue
        if can_id == ID_GATE_FEEDBACK:
            if len(data) != 2:
                fail(f"0x1A8 with {len(data)} bytes")
            feedback = data[0]
        elif can_id == ID_SAMPLE:
            raw, counter = struct.unpack_from("<iH", data)
            if counter != jiffy & 0xFFFF:
                fail(f"sample counter {counter}, expected {jiffy}")
            if feedback is None:
                fail("no 0x1A8 before the sample")
            gate_positions.append(feedback)
            raws.append(raw)
            feedback = None
            gate = 2 if jiffy in GATE_OPEN else 0
            valve = 2 if jiffy in VALVE_OPEN else 0
            sock.sendto(frame(ID_GATE_COMMAND, struct.pack("<BBH", gate, 0, counter)), peer)
            sock.sendto(frame(ID_VALVE_COMMAND, struct.pack("<BBH", valve, 0, counter)), peer)
            jiffy += 1
            deadline = time.monotonic() + 20
    out, _ = plant.communicate(timeout=20)
finally:
    stop(plant)
print(out)

kv = key_values(out)
if plant.returncode != 0 or kv.get("end") != "jiffies":
    fail(f"plant exited {plant.returncode}, end={kv.get('end')}")
if set(gate_positions) - {0, 1, 3}:
    fail(f"gate positions out of range: {sorted(set(gate_positions))}")
# Feedback k is the gate as the plant stands when it sends sample k: after k - 1's command.
opening = gate_positions[GATE_OPEN.start + 1:GATE_OPEN.stop + 1]
closing = gate_positions[GATE_OPEN.stop + 1:]
if any(p != 0 for p in gate_positions[:GATE_OPEN.start + 1]):
    fail("the gate moved before it was told to")
if opening[0] != 1 or 3 not in opening or opening[-1] != 3:
    fail(f"opening: expected moving then open, got {opening[:5]}...{opening[-5:]}")
moving_jiffies = opening.index(3)
print(f"gate_open_after_jiffies={moving_jiffies}")
if not 40 <= moving_jiffies <= 60:  # the default scene's 0.5 s stroke
    fail(f"the gate took {moving_jiffies} jiffies to open, not its 0.5 s stroke")
if closing[0] != 1 or closing[-1] != 0:
    fail(f"closing: expected moving then closed, got {closing[:5]}...{closing[-5:]}")
full_g = (raws[GATE_OPEN.start] - raws[0]) / COUNTS_PER_G
emptied_g = (raws[-1] - raws[0]) / COUNTS_PER_G
print(f"filled_g={full_g:.0f} after_discharge_g={emptied_g:.0f}")
if full_g < 2000:
    fail("the valve did not fill the hopper")
if abs(emptied_g) > 5:
    fail("the hopper did not empty through the gate")
released, discharged = float(kv["released_kg"]), float(kv["discharged_kg"])
if abs(released - discharged) > 1e-6 or float(kv["final_static_kg"]) > 1e-6:
    fail(f"released {released} kg, discharged {discharged} kg: the plant's truth disagrees")
if kv.get("gate_opens") != "1":
    fail(f"gate_opens={kv.get('gate_opens')}")
print("PASS")
