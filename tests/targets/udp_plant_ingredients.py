#!/usr/bin/env python3
"""dynweigh plant's ingredient valve modules over udp, driven by an indicator written here, on the
batching scene (three ingredients). The test answers each sample with 0x220 (ingredient 0 kept
closed) and opens ingredient 1 with 0x221 before it; the plant sends 0x1A1 and 0x1A2 with each
sample (and no 0x1A3..0x1A7: the scene has three ingredients), 0x1A1 reports moving, open, moving,
closed; the load cell rises by what ingredient 1's silo let out. One 0x227 (an ingredient the scene
lacks) is ignored and counted in ignored_ingredient_commands."""
import argparse
import socket
import struct
import time

from targets_common import fail, frame, key_values, parse, plant_on_udp, stop

ID_SAMPLE, ID_VALVE_COMMAND = 0x190, 0x220
ID_INGREDIENT_1_COMMAND, ID_INGREDIENT_7_COMMAND = 0x221, 0x227
ID_INGREDIENT_FEEDBACK = range(0x1A1, 0x1A8)
JIFFIES = 400
INGREDIENT_1_OPEN = range(20, 170)  # 1.5 s of barley
LACKING_AT = 30
COUNTS_PER_G = 1.0

a = argparse.ArgumentParser()
a.add_argument("--dynweigh", required=True)
args = a.parse_args()

sock, peer, plant = plant_on_udp(args.dynweigh, "batching", JIFFIES)
positions, raws, others = [], [], set()
try:
    sock.settimeout(0.1)
    deadline = time.monotonic() + 20
    feedback = {}
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
        if can_id in ID_INGREDIENT_FEEDBACK:
            if len(data) != 2:
                fail(f"0x{can_id:X} with {len(data)} bytes")
            feedback[can_id] = data[0]
        elif can_id == ID_SAMPLE:
            raw, counter = struct.unpack_from("<iH", data)
            if counter != jiffy & 0xFFFF:
                fail(f"sample counter {counter}, expected {jiffy}")
            if set(feedback) != {0x1A1, 0x1A2}:
                fail(f"ingredient feedback before sample {jiffy}: {sorted(hex(i) for i in feedback)}, expected 0x1A1 and 0x1A2")
            positions.append(feedback[0x1A1])
            others.add(feedback[0x1A2])
            raws.append(raw)
            feedback = {}
            ingredient = 2 if jiffy in INGREDIENT_1_OPEN else 0
            sock.sendto(frame(ID_INGREDIENT_1_COMMAND, struct.pack("<BBH", ingredient, 0, counter)), peer)
            if jiffy == LACKING_AT:
                sock.sendto(frame(ID_INGREDIENT_7_COMMAND, struct.pack("<BBH", 2, 0, counter)), peer)
            sock.sendto(frame(ID_VALVE_COMMAND, struct.pack("<BBH", 0, 0, counter)), peer)
            jiffy += 1
            deadline = time.monotonic() + 20
    out, _ = plant.communicate(timeout=20)
finally:
    stop(plant)
print(out)

kv = key_values(out)
if plant.returncode != 0 or kv.get("end") != "jiffies":
    fail(f"plant exited {plant.returncode}, end={kv.get('end')}")
if others != {0}:
    fail(f"ingredient 2's valve moved: {sorted(others)}")
# Feedback k is the valve as the plant stands when it sends sample k: after k - 1's command.
if any(p != 0 for p in positions[:INGREDIENT_1_OPEN.start + 1]):
    fail("ingredient 1's valve moved before it was told to")
opening = positions[INGREDIENT_1_OPEN.start + 1:INGREDIENT_1_OPEN.stop + 1]
closing = positions[INGREDIENT_1_OPEN.stop + 1:]
if opening[0] not in (0, 1) or 1 not in opening or opening[-1] != 3:
    fail(f"opening: expected (dead time,) moving then open, got {opening[:12]}...{opening[-3:]}")
if 1 not in closing or closing[-1] != 0:
    fail(f"closing: expected moving then closed, got {closing[:12]}...{closing[-3:]}")
released_1 = float(kv["ingredient1_released_kg"])
filled_g = (raws[-1] - raws[0]) / COUNTS_PER_G
print(f"ingredient1_released_kg={released_1:.3f} filled_g={filled_g:.0f}")
if released_1 < 1.5:
    fail("ingredient 1 let out too little")
if abs(float(kv["released_kg"]) - released_1) > 1e-9:
    fail("something other than ingredient 1 was released")
if abs(filled_g - 1000.0 * released_1) > 20:
    fail(f"the load cell says {filled_g:.0f} g, ingredient 1 let out {1000 * released_1:.0f} g")
if float(kv["ingredient2_released_kg"]) != 0.0:
    fail("ingredient 2 released material")
if kv.get("ignored_ingredient_commands") != "1":
    fail(f"ignored_ingredient_commands={kv.get('ignored_ingredient_commands')}, expected 1 (the 0x227)")
if kv.get("ingredient_commands") != str(JIFFIES):
    fail(f"ingredient_commands={kv.get('ingredient_commands')}, expected {JIFFIES}")
if kv.get("valve_opens") != "0":
    fail(f"valve_opens={kv.get('valve_opens')}: ingredient 0 was never opened")
print("PASS")
