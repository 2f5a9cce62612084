#!/usr/bin/env python3
"""The console on a pty, reached by an independent client (pyserial): `dynweigh-fw --console pty`
prints console=<device>; starttestdata 50 600, wait for the cycle, readtestdata -> 1000 records.
Every answer line ends in CR LF, as on a serial line (a terminal program needs the CR). A person
typing with corrections (DEL and backspace) gets the command they meant; `param echo 1` echoes
what is typed, erasures as BS SP BS."""
import argparse
import re
import subprocess
import sys
import time

from targets_common import fail, skip, stop, read_line_matching

try:
    import serial  # Debian: python3-serial
except ImportError:
    skip("pyserial is not installed (apt-get install python3-serial)")

a = argparse.ArgumentParser()
a.add_argument("--fw", required=True)
a.add_argument("--plant", default=None, help="extra --plant option for dynweigh-fw")
args = a.parse_args()

deadline = time.monotonic() + 50
command = [args.fw, "--console", "pty"] + (["--plant", args.plant] if args.plant else [])
fw = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
try:
    m, seen = read_line_matching(fw.stdout, r"^console=(\S+)", deadline)
    if not m:
        fail(f"no console= line: {seen} {fw.stderr.read() if fw.poll() is not None else ''}")
    device = m.group(1)
    print(f"console={device}")
    port = serial.Serial(device, 115200, timeout=0.5)

    def answer(cmd):
        """Sends one command; returns its lines up to and including OK or ERR."""
        port.write((cmd + "\r\n").encode())
        lines = []
        while time.monotonic() < deadline:
            raw = port.readline()
            if not raw:
                continue
            if not raw.endswith(b"\r\n"):
                fail(f"an answer to {cmd!r} ends in {raw[-2:]!r}, not CR LF: {raw!r}")
            line = raw.decode(errors="replace").rstrip("\r\n")
            if not line:
                continue
            lines.append(line)
            if line == "OK" or line.startswith("ERR "):
                return lines
        fail(f"no answer to {cmd!r} in time; got {lines[-5:]}")

    first = answer("starttestdata 50 600")
    if first[-1] != "OK":
        fail(f"starttestdata answered {first}")
    # Wait for the cycle by asking, as a user would: readtestdata is busy until it is recorded.
    while True:
        status = answer("status")
        if status[-1] != "OK":
            fail(f"status answered {status}")
        if "state=idle" in status[0]:
            lines = answer("readtestdata")
            if lines[-1] == "ERR 3 busy":
                continue
            break
        if time.monotonic() > deadline:
            fail("the test cycle never ended")
        time.sleep(0.05)  # pacing of the poll only; the handshake is the status answer
    records = [l for l in lines[:-1] if re.fullmatch(r"\d+ -?\d+ -?\d+ [012]", l)]
    if lines[-1] != "OK" or len(records) != 1000 or len(lines) != 1001:
        fail(f"readtestdata gave {len(records)} records of {len(lines)} lines, last {lines[-1]!r}")
    if [int(r.split()[0]) for r in records] != list(range(1000)):
        fail("jiffies are not 0..999")
    markers = [int(r.split()[3]) for r in records]
    if markers[40] != 0 or markers[300] != 2 or markers[900] != 0:
        fail(f"valve markers do not follow the 50/600 schedule: {markers[40]} {markers[300]} {markers[900]}")
    print("records=1000")

    # Typing as a person does: a slip corrected with DEL, another with backspace.
    typed = answer("statx\x7fu\x08us")
    if typed[-1] != "OK" or not typed[0].startswith("STATUS "):
        fail(f"'statx<DEL>u<BS>us' answered {typed}, not STATUS then OK")
    if answer("param echo 1")[-1] != "OK":
        fail("param echo 1 refused")
    port.reset_input_buffer()
    port.write(b"versoin\x7f\x7f\x7fion\r")
    echoed = b""
    while time.monotonic() < deadline and not echoed.endswith(b"OK\r\n"):
        echoed += port.read(64)
    if not echoed.startswith(b"versoin\b \b\b \b\b \bion\r\n") or b"dynweigh " not in echoed:
        fail(f"with echo on, typing 'versoin' and three DELs then 'ion' showed {echoed!r}")
    if answer("param echo 0")[-1] != "OK":
        fail("param echo 0 refused")
    print("line_editing=ok echo=ok")
    print("PASS")
finally:
    stop(fw)
