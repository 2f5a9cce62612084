#!/usr/bin/env python3
"""dynweigh-fw --plant can:udp against a minimal plant written here (not sim/): a load-cell module
that sends 0x190 samples over the udp transport (16-byte struct can_frame datagrams) and requires the
0x220 answer to each, as a lockstep plant and a valve module's watchdog do.

Cases (--case):
  console_polled  2 s of samples before the first console line, each answered; console lines act
                  (`valve 2` shows in the 0x220 command byte); at end of input the program exits 0.
  signal          SIGTERM while samples flow and stdin is idle ends dynweigh-fw within 1 s; stdin from
                  /dev/zero keeps the loop answering and the memory bounded; `dynweigh plant` waiting
                  for an indicator ends within 1 s of SIGTERM too.
  no_plant        nothing at the other end: stderr says what it waits for; lockstep gives up after
                  --plant-timeout with one line and exit status 3; real time raises can_silence.
  pty_unread      --console pty with a client that sends commands and never reads the answers: the
                  pty fills, and every sample is still answered within 1 s (nothing waits on it).
  new_nvm         a new --nvm file starts without calibration (`dose` -> ERR 5 not calibrated), said
                  on stderr; without --nvm the default scene's factory calibration, said on stderr.
"""
import argparse
import os
import queue
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import time

from targets_common import fail, frame, free_udp_ports, parse, stop

ID_SAMPLE, ID_VALVE_COMMAND, ID_VALVE_FEEDBACK = 0x190, 0x220, 0x1A0


class Plant:
    """The load-cell module (about 500 g on the default calibration; a valve that reports closed):
    one sample, then its 0x220."""

    def __init__(self, port, fw_port):
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.bind(("127.0.0.1", port))
        self.fw = ("127.0.0.1", fw_port)
        self.counter = 0
        self.commands = []  # the command byte of each answered sample

    def wait_for_indicator(self, timeout=10.0):
        """The indicator's boot-up heartbeat (0x701) says its socket is bound: samples reach it."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            self.sock.settimeout(max(0.001, deadline - time.monotonic()))
            try:
                can_id, _ = parse(self.sock.recv(64))
            except socket.timeout:
                break
            if can_id == 0x701:
                return
        fail("no heartbeat from the indicator")

    def sample(self, raw=12500, timeout=1.0):
        """Sends the next sample; returns its 0x220 command byte, or None if none came in `timeout`."""
        k = self.counter & 0xFFFF
        self.sock.sendto(frame(ID_VALVE_FEEDBACK, [0, 0]), self.fw)
        self.sock.sendto(frame(ID_SAMPLE, struct.pack("<iHBB", raw, k, 0, 0)), self.fw)
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            self.sock.settimeout(max(0.001, deadline - time.monotonic()))
            try:
                can_id, data = parse(self.sock.recv(64))
            except socket.timeout:
                break
            if can_id == ID_VALVE_COMMAND and len(data) == 4 and struct.unpack_from("<H", data, 2)[0] == k:
                self.counter += 1
                self.commands.append(data[0])
                return data[0]
        return None

    def pump(self, seconds, process=None, period=0.01, timeout=1.0):
        """Samples every `period` for `seconds`, each answered; stops early if `process` ended."""
        if self.counter == 0:
            self.wait_for_indicator()
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            if process is not None and process.poll() is not None:
                return
            if self.sample(timeout=timeout) is None:
                fail(f"no 0x220 answer to sample {self.counter} (after {len(self.commands)} answered)")
            time.sleep(period)


class Lines:
    """A process's text stream, read on a thread so the plant never waits on it."""

    def __init__(self, stream):
        self.queue, self.seen = queue.Queue(), []
        threading.Thread(target=self._read, args=(stream,), daemon=True).start()

    def _read(self, stream):
        for line in stream:
            self.queue.put(line.rstrip("\n"))

    def drain(self):
        while True:
            try:
                self.seen.append(self.queue.get_nowait())
            except queue.Empty:
                return self.seen


def start_fw(args, fw_port, plant_port, extra=(), stdin=subprocess.PIPE):
    command = [args.fw, "--plant", f"can:udp:{fw_port}@127.0.0.1:{plant_port}", *extra]
    process = subprocess.Popen(command, stdin=stdin, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    return process, Lines(process.stdout), Lines(process.stderr)


def pump_until(plant, process, out, predicate, seconds, what):
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        if predicate(out.drain()):
            return
        if process.poll() is not None:
            fail(f"dynweigh-fw ended (status {process.returncode}) before {what}: {out.seen[-5:]}")
        if plant.sample() is None:
            fail(f"no 0x220 answer to sample {plant.counter} while waiting for {what}")
        time.sleep(0.01)
    fail(f"no {what} within {seconds} s; stdout {out.seen[-5:]}")


def send(process, line):
    process.stdin.write(line + "\n")
    process.stdin.flush()


def case_console_polled(args):
    fw_port, plant_port = free_udp_ports(2)
    plant = Plant(plant_port, fw_port)
    process, out, err = start_fw(args, fw_port, plant_port)
    try:
        plant.pump(2.0, process)  # no console line yet: every sample must still be answered
        if process.poll() is not None:
            fail(f"dynweigh-fw ended early: {err.drain()}")
        print(f"samples_answered_before_first_line={len(plant.commands)}")
        send(process, "status")
        pump_until(plant, process, out, lambda s: "OK" in s, 5, "the answer to status")
        if not any(l.startswith("STATUS state=idle") for l in out.seen):
            fail(f"status answered {out.seen}")
        send(process, "valve 2")
        pump_until(plant, process, out, lambda s: s.count("OK") >= 2, 5, "the answer to valve 2")
        plant.sample()
        if plant.commands[-1] != 2:
            fail(f"after `valve 2` the 0x220 command byte is {plant.commands[-1]}, not 2")
        send(process, "valve 0")
        pump_until(plant, process, out, lambda s: s.count("OK") >= 3, 5, "the answer to valve 0")
        process.stdin.close()  # end of input: the program finishes and exits 0
        end = time.monotonic() + 5
        while process.poll() is None and time.monotonic() < end:
            plant.sample(timeout=0.2)
        if process.poll() != 0:
            fail(f"at end of input dynweigh-fw did not exit 0 (status {process.poll()}): {err.drain()}")
        print(f"samples_answered={len(plant.commands)}")
    finally:
        stop(process)


def rss_kb(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    return 0


def ends_within(process, seconds):
    try:
        process.wait(seconds)
        return True
    except subprocess.TimeoutExpired:
        return False


def case_signal(args):
    fw_port, plant_port = free_udp_ports(2)
    plant = Plant(plant_port, fw_port)
    process, out, err = start_fw(args, fw_port, plant_port)
    try:
        plant.pump(0.5, process)
        process.send_signal(signal.SIGTERM)
        t0 = time.monotonic()
        while process.poll() is None and time.monotonic() - t0 < 1.0:
            plant.sample(timeout=0.05)
        if process.poll() is None:
            fail("dynweigh-fw --plant can: with an idle stdin did not end within 1 s of SIGTERM")
        print(f"sigterm_exit_s={time.monotonic() - t0:.2f} status={process.returncode}")
    finally:
        stop(process)

    # stdin /dev/zero: a line that never ends costs no memory and does not stop the answers.
    fw_port, plant_port = free_udp_ports(2)
    plant = Plant(plant_port, fw_port)
    with open("/dev/zero", "rb") as zero:
        process, out, err = start_fw(args, fw_port, plant_port, stdin=zero)
    try:
        plant.pump(1.5, process, period=0.002)
        if process.poll() is not None:
            fail(f"dynweigh-fw < /dev/zero ended: {err.drain()}")
        rss = rss_kb(process.pid)
        print(f"dev_zero_rss_kb={rss} samples_answered={len(plant.commands)}")
        if rss > 64 * 1024:
            fail(f"dynweigh-fw < /dev/zero holds {rss} kB after 1.5 s")
        process.send_signal(signal.SIGINT)
        if not ends_within(process, 1.0):
            fail("dynweigh-fw < /dev/zero did not end within 1 s of SIGINT")
    finally:
        stop(process)

    if args.dynweigh:  # the plant program waiting for an indicator
        fw_port, plant_port = free_udp_ports(2)
        plant_process = subprocess.Popen([args.dynweigh, "plant", "--can", f"udp:{plant_port}@127.0.0.1:{fw_port}"],
                                         stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        try:
            time.sleep(0.3)
            plant_process.send_signal(signal.SIGTERM)
            if not ends_within(plant_process, 1.0):
                fail("dynweigh plant did not end within 1 s of SIGTERM")
            print(f"plant_sigterm_status={plant_process.returncode}")
        finally:
            stop(plant_process)


def case_no_plant(args):
    fw_port, plant_port = free_udp_ports(2)
    t0 = time.monotonic()
    process, out, err = start_fw(args, fw_port, plant_port, ["--plant-timeout", "1"], stdin=subprocess.DEVNULL)
    try:
        if not ends_within(process, 5):
            fail("lockstep without a plant did not give up within 5 s of a 1 s --plant-timeout")
        elapsed = time.monotonic() - t0
        time.sleep(0.1)
        lines = err.drain()
        print(f"no_plant_status={process.returncode} after_s={elapsed:.2f}")
        print("\n".join("stderr: " + l for l in lines))
        if process.returncode != 3:
            fail(f"exit status {process.returncode}, not 3")
        if not any("waiting for" in l and "0x190" in l for l in lines):
            fail("stderr does not say what it waits for")
        if sum("no load-cell sample" in l for l in lines) != 1:
            fail("not exactly one line saying no sample came")
    finally:
        stop(process)

    # The default wait is said at once, before it runs out.
    process, out, err = start_fw(args, fw_port, plant_port, stdin=subprocess.PIPE)
    try:
        end = time.monotonic() + 3
        while time.monotonic() < end and not any("waiting for" in l for l in err.drain()):
            time.sleep(0.05)
        if not any("waiting for" in l for l in err.seen):
            fail(f"with the default timeout stderr says nothing of the wait: {err.seen}")
        if process.poll() is not None:
            fail("gave up long before the default 10 s")
    finally:
        stop(process)

    # Real time: the missing samples are a fault the console reports.
    process, out, err = start_fw(args, fw_port, plant_port, ["--realtime"])
    try:
        time.sleep(0.5)
        send(process, "status")
        end = time.monotonic() + 5
        while time.monotonic() < end and not any(l.startswith("STATUS") for l in out.drain()):
            time.sleep(0.05)
        status = [l for l in out.seen if l.startswith("STATUS")]
        print(f"realtime_status={status}")
        if not status or "fault=can_silence" not in status[0]:
            fail(f"real time without a plant: status {status}, not fault=can_silence")
    finally:
        stop(process)


def case_pty_unread(args):
    with tempfile.TemporaryDirectory() as work:
        link = os.path.join(work, "console")
        fw_port, plant_port = free_udp_ports(2)
        plant = Plant(plant_port, fw_port)
        process, out, err = start_fw(args, fw_port, plant_port, ["--console", "pty", "--pty-link", link])
        try:
            plant.pump(0.3, process)
            client = os.open(link, os.O_RDWR | os.O_NOCTTY)
            try:
                for _ in range(60):  # about 120 KB of `param` answers that nobody reads
                    os.write(client, b"param\r\n")
                    plant.pump(0.05, process, timeout=1.0)  # a loop blocked on the full pty never answers; 1 s spares a loaded machine
                plant.pump(1.0, process, timeout=0.2)
            finally:
                os.close(client)
            print(f"samples_answered={len(plant.commands)} with an unread pty")
        finally:
            stop(process)


def case_new_nvm(args):
    with tempfile.TemporaryDirectory() as work:
        nvm = os.path.join(work, "scale.nvm")
        for run in ("new file", "same file again"):
            fw_port, plant_port = free_udp_ports(2)
            plant = Plant(plant_port, fw_port)
            process, out, err = start_fw(args, fw_port, plant_port, ["--nvm", nvm])
            try:
                plant.pump(0.2, process)
                send(process, "dose 1000")
                pump_until(plant, process, out, lambda s: any(l.startswith(("OK", "ERR")) for l in s), 5,
                           "the answer to dose")
                said = [l for l in err.drain() if "calibration" in l]
                print(f"{run}: dose -> {out.seen[-1]}; stderr {said}")
                if out.seen[-1] != "ERR 5 not calibrated":
                    fail(f"a new --nvm indicator answered dose with {out.seen[-1]!r}")
                if not said or "none" not in said[0]:
                    fail("stderr does not say the indicator starts without calibration")
            finally:
                stop(process)
        fw_port, plant_port = free_udp_ports(2)
        plant = Plant(plant_port, fw_port)
        process, out, err = start_fw(args, fw_port, plant_port)
        try:
            plant.pump(0.2, process)
            said = [l for l in err.drain() if "calibration" in l]
            print(f"no --nvm: stderr {said}")
            if not said or "factory calibration" not in said[0]:
                fail("without --nvm stderr does not say it starts with the default scene's factory calibration")
        finally:
            stop(process)


a = argparse.ArgumentParser()
a.add_argument("--fw", required=True)
a.add_argument("--dynweigh", default=None)
a.add_argument("--case", required=True, choices=["console_polled", "signal", "no_plant", "new_nvm", "pty_unread"])
args = a.parse_args()
globals()["case_" + args.case](args)
print("PASS")
