#!/usr/bin/env python3
"""Stopping the service closes the valve. The service's launcher and dynweigh-fw from the unpacked
package run as the unit runs them (the instance's variables, a pty console linked in the runtime
folder, real time) against `dynweigh plant --realtime` on udp (the load-cell and valve modules);
`dose 10000` is typed on the console, and once the indicator has opened the valve the launcher's
process gets SIGTERM, as `systemctl stop` sends it. dynweigh-fw must end within 1 s with status 0,
and the valve module must have heard a close after the open: not its 50 ms watchdog, and before the
indicator's NMT-stopped heartbeat ended the plant."""
import argparse
import os
import select
import signal
import subprocess
import sys
import tempfile
import time

a = argparse.ArgumentParser()
a.add_argument("--root", required=True)
a.add_argument("--targets", required=True, help="tests/targets, for targets_common")
args = a.parse_args()
sys.path.insert(0, args.targets)
from targets_common import fail, free_udp_ports, key_values, stop  # noqa: E402

fw = os.path.join(args.root, "usr/bin/dynweigh-fw")
tool = os.path.join(args.root, "usr/bin/dynweigh")
launcher = os.path.join(args.root, "usr/libexec/dynweigh/dynweigh-fw-service")


def wait_for(predicate, seconds, what):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if predicate():
            return
        time.sleep(0.02)
    fail(f"no {what} within {seconds} s")


class Console:
    """The console's pty as a terminal program opens it: a command, then its lines up to OK / ERR."""

    def __init__(self, path):
        self.fd = os.open(path, os.O_RDWR | os.O_NOCTTY)
        self.pending = b""
        self.transcript = []  # every line read, for a failure's message

    def command(self, line, seconds=5):
        os.write(self.fd, line.encode() + b"\r")
        deadline, lines = time.monotonic() + seconds, []
        while time.monotonic() < deadline:
            ready, _, _ = select.select([self.fd], [], [], 0.1)
            if ready:
                self.pending += os.read(self.fd, 4096)
            while b"\n" in self.pending:
                raw, self.pending = self.pending.split(b"\n", 1)
                text = raw.decode(errors="replace").strip()
                lines.append(text)
                self.transcript.append(text)
                if text == "OK" or text.startswith("ERR"):
                    return lines
        fail(f"no answer to {line!r} within {seconds} s: {lines}")

    def status(self, key):
        """One field of status's line: valve= (0 closed, 1 half, 2 open), weight= (none before a reading)."""
        status = [line for line in self.command("status") if line.startswith("STATUS ")]
        return status[0].split(f"{key}=")[1].split()[0] if status else None

    def valve(self):
        value = self.status("valve")
        return int(value) if value is not None else None

    def close(self):
        os.close(self.fd)


with tempfile.TemporaryDirectory() as scratch:
    nvm = os.path.join(scratch, "scale1.nvm")
    # The settings file a commissioned scale would have: the simulated plant's calibration.
    subprocess.run([fw, "--nvm", nvm], input="", check=True, capture_output=True, timeout=20)

    plant_port, fw_port = free_udp_ports(2)
    plant = subprocess.Popen([tool, "plant", "--can", f"udp:{plant_port}@127.0.0.1:{fw_port}", "--scene", "default",
                              "--realtime"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    env = {"PATH": "/usr/bin:/bin", "RUNTIME_DIRECTORY": scratch, "DYNWEIGH_MODBUS": "", "DYNWEIGH_NVM": nvm,
           "DYNWEIGH_PLANT": f"can:udp:{fw_port}@127.0.0.1:{plant_port}", "DYNWEIGH_CONSOLE": "pty",
           "DYNWEIGH_OPTIONS": "--realtime"}
    service = subprocess.Popen([launcher, "scale1"], env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    console = None
    service_out = plant_out = ""
    try:
        link = os.path.join(scratch, "console")
        wait_for(lambda: os.path.exists(link), 20, "console link")
        console = Console(link)
        # A slow machine (a sanitizer build) may start the plant's stream after the console: a dose
        # typed before the first reading is refused, so wait for one as an operator would.
        try:
            wait_for(lambda: console.status("weight") not in (None, "none"), 20, "reading from the plant")
            if console.status("fault") != "none":
                console.command("clearfault")  # the bus was silent while the plant started
            os.write(console.fd, b"dose 10000\r")
            wait_for(lambda: console.valve() == 2, 20, "open valve during the dose")
        except SystemExit:
            print("--- console ---\n" + "\n".join(console.transcript[-20:]))
            raise
        time.sleep(0.3)  # the stream is running
        if console.valve() != 2:
            fail("the valve closed before the stop (a fault?): nothing to show")
        t0 = time.monotonic()
        service.send_signal(signal.SIGTERM)
        try:
            service_out, _ = service.communicate(timeout=1.0)
        except subprocess.TimeoutExpired:
            fail("dynweigh-fw did not end within 1 s of SIGTERM")
        print(f"stop_s={time.monotonic() - t0:.3f} status={service.returncode}")
        try:
            plant_out, _ = plant.communicate(timeout=5)
        except subprocess.TimeoutExpired:
            fail("the plant did not hear the indicator leave")
    finally:
        if console is not None:
            console.close()
        stop(service)
        stop(plant)
        if not service_out:
            service_out = service.communicate()[0]
        if not plant_out:
            plant_out = plant.communicate()[0]
        print("--- service ---\n" + service_out + "--- dynweigh plant ---\n" + plant_out)

    if service.returncode != 0:
        fail(f"dynweigh-fw ended with status {service.returncode} on SIGTERM, not 0")
    if os.path.lexists(os.path.join(scratch, "console")):
        fail("the console link outlived the service")
    kv = key_values(plant_out)
    if kv.get("end") != "indicator_stopped":
        fail(f"the plant ended with {kv.get('end')}, not indicator_stopped")
    opened, closed = int(kv["first_open_jiffy"]), int(kv["last_close_jiffy"])
    if opened < 0:
        fail("the plant's valve never opened")
    if closed < opened:
        fail("the indicator left with the valve open: no close after the open reached the valve module")
    if kv.get("watchdog_closes") != "0":
        fail("the valve module's watchdog closed the valve, not the indicator")
    released = float(kv["released_kg"])
    print(f"valve open at jiffy {opened}, closed at {closed}; released {released:.3f} kg of the 10 kg dose")
    print("PASS")
