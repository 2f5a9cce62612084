#!/usr/bin/env python3
"""A PLC (pymodbus) drives dynweigh-fw --modbus on the simulated plant, as a batching plant would:
write the set point and the strategy, start, poll state and result_seq, read the result. Each
--case checks the registers against the console's RESULT line, the plant's truth (--csv) and the
same dose typed on the console; or what bad requests and vanished PLCs get.

--measure prints the register round trip (median of 1,000 reads of net_dg) and the loop's worst
jiffy under 10 clients polling every 10 ms; it checks nothing."""
import argparse
import csv
import os
import shutil
import signal
import socket
import statistics
import struct
import subprocess
import sys
import tempfile
import threading
import time

from targets_common import SKIP, fail, field, free_udp_ports, key_values

try:
    from pymodbus.client import ModbusSerialClient, ModbusTcpClient
except ImportError:
    print("SKIP: python3-pymodbus is not installed", flush=True)
    sys.exit(SKIP)

TARGET_G = 5000
COMMAND_RUNNING = 0xFFFF
# Input registers (docs/plc-modbus.md).
NET, STATE, FAULT, VALVE, RESULT_SEQ, FINAL, ERROR, TIME, TOLERANCE, TOPUPS, IN_FLIGHT, FLOW = (
    0, 2, 3, 4, 5, 6, 8, 10, 12, 13, 14, 16)


def int32(registers, at):
    return struct.unpack(">i", struct.pack(">HH", registers[at], registers[at + 1]))[0]


def uint32(registers, at):
    return (registers[at] << 16) | registers[at + 1]


def free_tcp_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


class Firmware:
    """dynweigh-fw with stdin held open (a console with nothing typed yet), its output collected."""

    def __init__(self, fw, args):
        self.process = subprocess.Popen([fw] + args, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                        stderr=subprocess.PIPE, text=True, bufsize=1)
        self.lines, self.errors = [], []
        self._readers = [threading.Thread(target=self._collect, args=(self.process.stdout, self.lines), daemon=True),
                         threading.Thread(target=self._collect, args=(self.process.stderr, self.errors), daemon=True)]
        for r in self._readers:
            r.start()

    @staticmethod
    def _collect(stream, into):
        for line in stream:
            into.append(line.rstrip("\n"))

    def type(self, line):
        self.process.stdin.write(line + "\n")
        self.process.stdin.flush()

    def wait_for_line(self, predicate, timeout_s, what):
        end = time.monotonic() + timeout_s
        while time.monotonic() < end:
            for line in list(self.lines):
                if predicate(line):
                    return line
            if self.process.poll() is not None:
                break
            time.sleep(0.02)
        fail(f"no {what} on the console within {timeout_s} s; console said: {self.lines[-10:]}, "
             f"stderr: {self.errors[-10:]}")

    def wait_serving(self, count=1):
        end = time.monotonic() + 10
        while time.monotonic() < end:
            if sum(1 for e in self.errors if e.startswith("dynweigh-fw: modbus: serving")) >= count:
                return
            if self.process.poll() is not None:
                fail(f"dynweigh-fw exited {self.process.returncode}: {self.errors}")
            time.sleep(0.02)
        fail("dynweigh-fw never said it serves Modbus")

    def stop(self):
        """SIGTERM; the exit summary's key=value lines."""
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGTERM)
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
            fail("dynweigh-fw did not end on SIGTERM")
        for r in self._readers:
            r.join(timeout=5)
        return key_values("\n".join(self.errors))

    def results(self):
        return [l for l in self.lines if l.startswith("RESULT ")]


def ok(response, what):
    if response.isError():
        fail(f"{what}: {response}")
    return response


def inputs(client, unit):
    return ok(client.read_input_registers(0, 18, slave=unit), "read input registers").registers


def holding(client, unit):
    return ok(client.read_holding_registers(0, 6, slave=unit), "read holding registers").registers


def start_dose(client, unit, target_g, strategy=0):
    ok(client.write_registers(0, [target_g >> 16, target_g & 0xFFFF, strategy], slave=unit), "write set point")
    ok(client.write_register(5, 1, slave=unit), "write command 1 (dose)")


def wait_for_result(client, unit, seq_before, timeout_s=60):
    """Polls state and result_seq as a PLC does, until a new result and the command's answer."""
    end = time.monotonic() + timeout_s
    states = set()
    while time.monotonic() < end:
        regs = inputs(client, unit)
        states.add(regs[STATE])
        command = holding(client, unit)[5]
        if regs[RESULT_SEQ] != seq_before and command != COMMAND_RUNNING:
            return regs, command, states
        time.sleep(0.02)
    fail(f"no result within {timeout_s} s (result_seq stays {seq_before})")


def console_dose(fw_path, seed, target_g):
    """The same dose typed on the console: its RESULT line."""
    run = subprocess.run([fw_path, "--seed", str(seed)], input=f"dose {target_g} model\n", capture_output=True,
                         text=True, timeout=60)
    lines = [l for l in run.stdout.splitlines() if l.startswith("RESULT ")]
    if run.returncode != 0 or len(lines) != 1:
        fail(f"the console's own dose failed: {run.stdout} {run.stderr}")
    return lines[0]


def check_result_against(regs, command, result_line, csv_path, console_line):
    print(f"registers: {regs}\nconsole:   {result_line}\ntyped:     {console_line}")
    if command != 0:
        fail(f"register 5 reads {command} after the dose, not 0 (OK)")
    if result_line != console_line:
        fail("the PLC's dose and the same dose typed on the console gave different RESULT lines")
    final_g, error_g, time_ms = (int(field(result_line, k)) for k in ("final", "error", "time"))
    if int32(regs, FINAL) != final_g * 10 or int32(regs, ERROR) != error_g * 10 or uint32(regs, TIME) != time_ms:
        fail(f"result registers final={int32(regs, FINAL)} dg error={int32(regs, ERROR)} dg "
             f"time={uint32(regs, TIME)} ms disagree with the console's RESULT")
    verdicts = {"ok": 0, "warn_low": 1, "warn_high": 2, "low": 3, "high": 4}
    if regs[TOLERANCE] != verdicts[field(result_line, "tolerance")] or regs[TOPUPS] != int(field(result_line, "topups")):
        fail(f"tolerance {regs[TOLERANCE]} and topups {regs[TOPUPS]} registers disagree with the console's RESULT")
    if regs[STATE] != 0 or regs[VALVE] != 0 or regs[FAULT] != 0:
        fail(f"after the result: state {regs[STATE]}, valve {regs[VALVE]}, fault {regs[FAULT]}; want 0, 0, 0")
    # The result is certified from the platform's ringing, before the reading has settled.
    if abs(int32(regs, NET) / 10.0 - final_g) > 0.05 * final_g:
        fail(f"net_dg {int32(regs, NET)} is far from the certified {final_g} g")
    with open(csv_path) as f:
        rows = list(csv.DictReader(f))
    true_g = float(rows[-1]["static_kg"]) * 1000.0
    print(f"plant truth {true_g:.1f} g, certified {final_g} g")
    if abs(true_g - final_g) > 5.0:
        fail(f"the certified final {final_g} g disagrees with the plant's truth {true_g:.1f} g")


def case_tcp_dose(args, tmp):
    port, seed = free_tcp_port(), 3
    trace = os.path.join(tmp, "trace.csv")
    fw = Firmware(args.fw, ["--modbus", f"tcp:127.0.0.1:{port}", "--seed", str(seed), "--csv", trace])
    fw.wait_serving()
    plc, hmi = ModbusTcpClient("127.0.0.1", port=port), ModbusTcpClient("127.0.0.1", port=port)
    if not plc.connect() or not hmi.connect():
        fail("cannot connect")
    if holding(plc, 1)[5] != 0 or inputs(plc, 1)[RESULT_SEQ] != 0:
        fail("a fresh indicator: command register 0, result_seq 0")
    start_dose(plc, 1, TARGET_G)
    regs, command, _ = wait_for_result(plc, 1, 0)
    seen_by_hmi = inputs(hmi, 1)
    result_line = fw.wait_for_line(lambda l: l.startswith("RESULT "), 10, "RESULT")
    plc.close()
    hmi.close()
    summary = fw.stop()
    if seen_by_hmi[RESULT_SEQ] != 1 or seen_by_hmi[FINAL:TIME + 2] != regs[FINAL:TIME + 2]:
        fail("a second client (an HMI) reads another result than the PLC")
    check_result_against(regs, command, result_line, trace, console_dose(args.fw, seed, TARGET_G))
    if int(summary.get("modbus_requests", "0")) < 4:
        fail(f"the exit summary counts {summary.get('modbus_requests')} Modbus requests")


def case_material_dose(args, tmp):
    """Register 3 selects the material as the console's `material <n>` does (an undefined one is
    defined with the defaults), on the PLC's next dose; the dose and its RESULT use it."""
    port = free_tcp_port()
    fw = Firmware(args.fw, ["--modbus", f"tcp:127.0.0.1:{port}", "--seed", "3"])
    fw.wait_serving()
    plc = ModbusTcpClient("127.0.0.1", port=port)
    if not plc.connect():
        fail("cannot connect")
    if holding(plc, 1)[3] != 0:
        fail(f"a fresh indicator's material register reads {holding(plc, 1)[3]}, not the selected 0")
    expect_exception(port, struct.pack(">BHH", 0x06, 3, 16), 3, "material 16")
    doses = [(5, True), (5, False), (0, True)]  # (material, written before the dose)
    for i, (material, written) in enumerate(doses):
        seq = inputs(plc, 1)[RESULT_SEQ]
        block = [0, 2000, 0, material, 0, 1] if written else [0, 2000, 0]
        ok(plc.write_registers(0, block, slave=1), f"write set point, material {material} and dose")
        if not written:
            ok(plc.write_register(5, 1, slave=1), "write command 1 (dose)")
        regs, command, _ = wait_for_result(plc, 1, seq)
        if command != 0:
            fail(f"dose {i + 1} (material {material}): register 5 reads {command}, not 0 (OK)")
        results = fw.results()
        if len(results) != i + 1 or field(results[-1], "material") != str(material):
            fail(f"dose {i + 1}: want RESULT material={material}, console shows {results}")
        if holding(plc, 1)[3] != material:
            fail(f"after dose {i + 1} the material register reads {holding(plc, 1)[3]}, not {material}")
    plc.close()
    fw.stop()
    selections = [l for l in fw.lines if l.startswith("MATERIAL ")]
    print("\n".join(selections))
    # Material 5 is defined by its selection, as on the console; a dose of the material already
    # selected selects nothing (the settings are not rewritten).
    if len(selections) != 2 or "n=5 name=material5 density=1550" not in selections[0] or "n=0 " not in selections[1]:
        fail(f"want one `material 5` (defined with the defaults) and one `material 0` on the console: {selections}")


def case_rtu_dose(args, tmp):
    """Over RTU through a socat pty pair, with TCP served at once (--modbus given twice)."""
    if not shutil.which("socat"):
        print("SKIP: socat is not installed", flush=True)
        sys.exit(SKIP)
    fw_end, plc_end = os.path.join(tmp, "fw-tty"), os.path.join(tmp, "plc-tty")
    socat = subprocess.Popen(["socat", f"pty,raw,echo=0,link={fw_end}", f"pty,raw,echo=0,link={plc_end}"],
                             stderr=subprocess.DEVNULL)
    try:
        end = time.monotonic() + 10
        while not (os.path.exists(fw_end) and os.path.exists(plc_end)):
            if time.monotonic() > end:
                fail("socat made no pty pair")
            time.sleep(0.05)
        port, seed, unit = free_tcp_port(), 5, 7
        trace = os.path.join(tmp, "trace.csv")
        # 8N1: a pty refuses pyserial's parity settings (termios EINVAL); the framing is the
        # line's business, the decoding is the same.
        fw = Firmware(args.fw, ["--modbus", f"rtu:{fw_end}:38400:8N1:{unit}", "--modbus", f"tcp:127.0.0.1:{port}",
                                "--seed", str(seed), "--csv", trace])
        fw.wait_serving(2)
        plc = ModbusSerialClient(method="rtu", port=plc_end, baudrate=38400, parity="N", bytesize=8, stopbits=1,
                                 timeout=1)
        hmi = ModbusTcpClient("127.0.0.1", port=port)
        if not plc.connect() or not hmi.connect():
            fail("cannot open the RTU side or connect over TCP")
        start_dose(plc, unit, TARGET_G)
        regs, command, _ = wait_for_result(plc, unit, 0)
        over_tcp = inputs(hmi, 1)
        # Another unit id on the line is not this indicator: no answer at all.
        other = plc.read_input_registers(0, 2, slave=unit + 1)
        plc.close()
        hmi.close()
        result_line = fw.wait_for_line(lambda l: l.startswith("RESULT "), 10, "RESULT")
        fw.stop()
        if not other.isError():
            fail("unit id 8 was answered by the indicator at unit id 7")
        if over_tcp[RESULT_SEQ:TIME + 2] != regs[RESULT_SEQ:TIME + 2]:
            fail("TCP and RTU read different results")
        check_result_against(regs, command, result_line, trace, console_dose(args.fw, seed, TARGET_G))
    finally:
        socat.terminate()
        socat.wait(timeout=5)


def case_can_dose(args, tmp):
    """The same PLC dose with the plant outside, on the CAN link (dynweigh plant over udp)."""
    if not args.dynweigh:
        fail("--case can_dose needs --dynweigh")
    plant_port, fw_port = free_udp_ports(2)
    port = free_tcp_port()
    plant = subprocess.Popen([args.dynweigh, "plant", "--can", f"udp:{plant_port}@127.0.0.1:{fw_port}", "--scene",
                              "default", "--seed", "1", "--wait", "20", "--timeout", "20"],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        fw = Firmware(args.fw, ["--plant", f"can:udp:{fw_port}@127.0.0.1:{plant_port}", "--modbus",
                                f"tcp:127.0.0.1:{port}"])
        fw.wait_serving()
        plc = ModbusTcpClient("127.0.0.1", port=port)
        if not plc.connect():
            fail("cannot connect")
        start_dose(plc, 1, TARGET_G)
        regs, command, _ = wait_for_result(plc, 1, 0)
        plc.close()
        result_line = fw.wait_for_line(lambda l: l.startswith("RESULT "), 10, "RESULT")
        fw.stop()
        plant_out, _ = plant.communicate(timeout=20)
    finally:
        if plant.poll() is None:
            plant.kill()
            plant.wait()
    truth = key_values(plant_out)
    true_g = float(truth["final_static_kg"]) * 1000.0
    final_g = int(field(result_line, "final"))
    print(f"registers {regs}\nconsole {result_line}\nplant truth {true_g:.1f} g")
    if command != 0 or int32(regs, FINAL) != final_g * 10 or uint32(regs, TIME) != int(field(result_line, "time")):
        fail("the registers disagree with the console's RESULT")
    if abs(true_g - final_g) > 5.0:
        fail(f"the certified final {final_g} g disagrees with the plant's truth {true_g:.1f} g")


def wait_for_state(client, state, timeout_s, register=STATE):
    end = time.monotonic() + timeout_s
    while time.monotonic() < end:
        if inputs(client, 1)[register] == state:
            return
        time.sleep(0.02)
    fail(f"input register {register} never became {state}")


def case_disconnect_mid_dose(args, tmp):
    """A PLC that goes away mid-dose: the dose runs on to its result (watchdog off, the default)."""
    port = free_tcp_port()
    fw = Firmware(args.fw, ["--modbus", f"tcp:127.0.0.1:{port}", "--realtime"])
    fw.wait_serving()
    plc = ModbusTcpClient("127.0.0.1", port=port)
    plc.connect()
    start_dose(plc, 1, TARGET_G)
    wait_for_state(plc, 1, 10)
    plc.close()
    result_line = fw.wait_for_line(lambda l: l.startswith("RESULT "), 30, "RESULT of the orphaned dose")
    back = ModbusTcpClient("127.0.0.1", port=port)
    back.connect()
    regs, command, _ = wait_for_result(back, 1, 0, 10)
    back.close()
    fw.stop()
    if command != 0 or int32(regs, FINAL) != int(field(result_line, "final")) * 10:
        fail("the PLC that comes back does not read the dose's result")
    print("PASS: the orphaned dose ran to its result: " + result_line)


def case_watchdog(args, tmp):
    """param plc_watchdog_ms 500: a PLC that keeps polling gets its result; one that goes silent
    mid-dose gets its dose aborted with the valve closed (ERR 3 in register 5)."""
    port = free_tcp_port()
    trace = os.path.join(tmp, "trace.csv")
    fw = Firmware(args.fw, ["--modbus", f"tcp:127.0.0.1:{port}", "--realtime", "--csv", trace])
    fw.wait_serving()
    fw.type("param plc_watchdog_ms 500")
    fw.wait_for_line(lambda l: l == "OK", 10, "OK to param plc_watchdog_ms")
    plc = ModbusTcpClient("127.0.0.1", port=port)
    plc.connect()
    start_dose(plc, 1, 2000)
    regs, command, _ = wait_for_result(plc, 1, 0, 30)
    if command != 0:
        fail(f"a polling PLC's dose answered {command}, not 0")
    start_dose(plc, 1, TARGET_G)
    wait_for_state(plc, 2, 10, VALVE)  # open: material flows when the PLC goes silent
    plc.close()
    silent_from = time.monotonic()
    fw.wait_for_line(lambda l: l == "ERR 3 aborted", 10, "ERR 3 aborted of the dose")
    silent_s = time.monotonic() - silent_from
    back = ModbusTcpClient("127.0.0.1", port=port)
    back.connect()
    time.sleep(0.2)
    regs, answer = inputs(back, 1), holding(back, 1)[5]
    back.close()
    summary = fw.stop()
    print(f"aborted {silent_s:.2f} s after the PLC went silent; registers {regs}")
    if answer != 3:
        fail(f"register 5 reads {answer} after the watchdog's abort, not 3")
    if regs[STATE] != 0 or regs[VALVE] != 0 or regs[RESULT_SEQ] != 1:
        fail("after the abort: state idle, valve closed, no new result expected")
    if summary.get("plc_watchdog_aborted") != "1":
        fail("the exit summary does not count the watchdog's abort")
    with open(trace) as f:
        rows = list(csv.DictReader(f))
    if rows[-1]["valve"] != "0":
        fail("the valve is not closed at the end")
    landed_g = float(rows[-1]["static_kg"]) * 1000.0
    if landed_g > 2000 + TARGET_G - 1000:
        fail(f"{landed_g:.0f} g in the hopper: the second dose was not cut short")
    print("PASS")


def raw_request(port, pdu, unit=1, transaction=1):
    """One Modbus TCP request; the reply's PDU."""
    with socket.create_connection(("127.0.0.1", port), timeout=5) as s:
        s.sendall(struct.pack(">HHHB", transaction, 0, len(pdu) + 1, unit) + pdu)
        header = b""
        while len(header) < 7:
            chunk = s.recv(7 - len(header))
            if not chunk:
                fail(f"connection closed without a reply to {pdu.hex()}")
            header += chunk
        t, _, length, _ = struct.unpack(">HHHB", header)
        body = b""
        while len(body) < length - 1:
            body += s.recv(length - 1 - len(body))
        if t != transaction:
            fail("the reply carries another transaction id")
        return body


def expect_exception(port, pdu, code, what):
    reply = raw_request(port, pdu)
    if len(reply) != 2 or reply[0] != (pdu[0] | 0x80) or reply[1] != code:
        fail(f"{what}: expected exception {code:02d}, got {reply.hex()}")
    print(f"ok: {what} -> exception {code:02d}")


def case_bad_requests(args, tmp):
    port = free_tcp_port()
    fw = Firmware(args.fw, ["--modbus", f"tcp:127.0.0.1:{port}", "--realtime"])
    fw.wait_serving()
    # Functions and addresses.
    expect_exception(port, bytes([0x41]), 1, "unknown function 0x41")
    expect_exception(port, bytes([0x01, 0, 0, 0, 1]), 1, "read coils (no coils)")
    expect_exception(port, struct.pack(">BHH", 0x04, 17, 2), 2, "input registers 17-18")
    expect_exception(port, struct.pack(">BHH", 0x03, 6, 1), 2, "holding register 6")
    expect_exception(port, struct.pack(">BHH", 0x06, 6, 1), 2, "write holding register 6")
    expect_exception(port, struct.pack(">BHHBHHH", 0x10, 4, 3, 6, 0, 1, 0), 2, "write 4-6")
    # Values.
    expect_exception(port, struct.pack(">BHH", 0x03, 0, 0), 3, "read of 0 registers")
    expect_exception(port, struct.pack(">BHH", 0x04, 0, 126), 3, "read of 126 registers")
    expect_exception(port, struct.pack(">BHH", 0x06, 2, 4), 3, "strategy 4")
    expect_exception(port, struct.pack(">BHH", 0x06, 3, 16), 3, "material 16 (the table holds 0..15)")
    expect_exception(port, struct.pack(">BHH", 0x06, 4, 5), 3, "class_x10 5 (X(1) only)")
    expect_exception(port, struct.pack(">BHH", 0x06, 5, 0), 3, "command 0")
    expect_exception(port, struct.pack(">BHH", 0x06, 5, 9), 3, "command 9")
    expect_exception(port, struct.pack(">BHHBH", 0x10, 2, 2, 2, 1), 3, "0x10 whose byte count is short")
    expect_exception(port, struct.pack(">BHHBHH", 0x10, 1, 2, 4, 7, 9), 3, "0x10 with strategy 9")
    plc = ModbusTcpClient("127.0.0.1", port=port)
    plc.connect()
    if holding(plc, 1)[:3] != [0, 0, 0]:
        fail("a refused 0x10 wrote part of its registers")

    # A 32-bit set point in two requests takes effect with its low word; in one, at once.
    ok(plc.write_register(0, 0x0001, slave=1), "high word")
    if holding(plc, 1)[:2] != [0, 0]:
        fail("the high word alone changed the set point")
    ok(plc.write_register(1, 0x86A0, slave=1), "low word")
    if holding(plc, 1)[:2] != [0x0001, 0x86A0]:
        fail("the pair did not make 100000 g")
    # Refused by the console: over the scale's capacity (ERR 2). A discharge empties the hopper (0).
    ok(plc.write_register(5, 1, slave=1), "dose 100000")
    if wait_for_answer(plc) != 2:
        fail("a dose over the capacity must answer 2 (the console's ERR 2)")
    fw.wait_for_line(lambda l: l.startswith("ERR 2 target"), 5, "the console's ERR 2 for the PLC's dose")
    ok(plc.write_register(5, 6, slave=1), "discharge")
    if wait_for_answer(plc) != 0:
        fail("discharge must answer 0 (the plant's gate opened, the hopper emptied, the gate proven closed)")
    ok(plc.write_register(5, 3, slave=1), "tare")
    if wait_for_answer(plc) != 0:
        fail("tare must answer 0")

    # A command while the last one runs is refused (06), except abort.
    start_dose(plc, 1, TARGET_G)
    wait_for_state(plc, 1, 10)
    expect_exception(port, struct.pack(">BHH", 0x06, 5, 3), 6, "tare while the PLC's dose runs")
    ok(plc.write_register(5, 2, slave=1), "abort")
    if wait_for_answer(plc) != 0 or inputs(plc, 1)[VALVE] != 0:
        fail("abort must answer 0 and leave the valve closed")
    fw.wait_for_line(lambda l: l == "ERR 3 aborted", 5, "the aborted dose's ERR 3")

    # A truncated frame, a silent client and 100 clients at once: the others are served, the loop runs.
    truncated = socket.create_connection(("127.0.0.1", port))
    truncated.sendall(bytes([0, 1, 0, 0, 0, 6, 1, 0x04]))  # 8 of a request's 12 bytes
    silent = [socket.create_connection(("127.0.0.1", port)) for _ in range(3)]
    fw.type("dose 1500")
    crowd = [socket.create_connection(("127.0.0.1", port)) for _ in range(100)]
    for i, s in enumerate(crowd):
        s.sendall(struct.pack(">HHHBBHH", i, 0, 6, 1, 0x04, 0, 18))
    for i, s in enumerate(crowd):
        s.settimeout(10)
        reply = b""
        while len(reply) < 9 + 36:
            chunk = s.recv(64)
            if not chunk:
                break
            reply += chunk
        if len(reply) != 45 or struct.unpack(">H", reply[:2])[0] != i or reply[7] != 0x04:
            fail(f"client {i} of 100 got {reply.hex()}")
        s.close()
    print("ok: 100 clients at once, each answered")
    truncated.settimeout(5)
    if truncated.recv(16) != b"":
        fail("the truncated frame was answered instead of dropped")
    print("ok: a truncated frame is dropped with its connection")
    fw.wait_for_line(lambda l: l.startswith("RESULT target=1500"), 30, "RESULT of the console's dose")
    print("ok: the console's dose ran to its result beside silent, truncated and crowding clients")
    if inputs(plc, 1)[RESULT_SEQ] != 1:
        fail("result_seq must count the console's result too")
    for s in silent:
        s.close()
    plc.close()
    truncated.close()
    summary = fw.stop()
    if fw.process.returncode != 128 + signal.SIGTERM:
        fail(f"dynweigh-fw exited {fw.process.returncode}")
    print(f"loop_jiffy_worst_us={summary.get('loop_jiffy_worst_us')}")
    print("PASS")


def wait_for_answer(client, timeout_s=10):
    end = time.monotonic() + timeout_s
    while time.monotonic() < end:
        answer = holding(client, 1)[5]
        if answer != COMMAND_RUNNING:
            return answer
        time.sleep(0.02)
    fail("register 5 stays 0xFFFF")


def measure(args, tmp):
    port = free_tcp_port()
    fw = Firmware(args.fw, ["--modbus", f"tcp:127.0.0.1:{port}", "--realtime"])
    fw.wait_serving()
    client = ModbusTcpClient("127.0.0.1", port=port)
    client.connect()
    times = []
    for _ in range(1000):
        t0 = time.perf_counter()
        ok(client.read_input_registers(0, 2, slave=1), "read net_dg")
        times.append(time.perf_counter() - t0)
    client.close()
    print(f"net_dg_round_trip_median_us={statistics.median(times) * 1e6:.0f}")
    print(f"net_dg_round_trip_p99_us={sorted(times)[989] * 1e6:.0f}")
    fw.stop()

    fw = Firmware(args.fw, ["--modbus", f"tcp:127.0.0.1:{port}", "--realtime"])
    fw.wait_serving()
    stop = threading.Event()
    counts = []

    def poller():
        c = ModbusTcpClient("127.0.0.1", port=port)
        c.connect()
        n = 0
        while not stop.is_set():
            c.read_input_registers(0, 18, slave=1)
            c.read_holding_registers(0, 6, slave=1)
            n += 1
            time.sleep(0.01)
        c.close()
        counts.append(n)

    threads = [threading.Thread(target=poller) for _ in range(10)]
    for t in threads:
        t.start()
    fw.type(f"dose {TARGET_G}")
    fw.wait_for_line(lambda l: l.startswith("RESULT "), 60, "RESULT")
    stop.set()
    for t in threads:
        t.join()
    summary = fw.stop()
    print(f"pollers=10 polls={sum(counts)} modbus_requests={summary.get('modbus_requests')}")
    for key in ("loop_jiffies", "loop_jiffy_worst_us", "loop_jiffy_mean_us"):
        print(f"{key}={summary.get(key)}")


CASES = {"tcp_dose": case_tcp_dose, "material_dose": case_material_dose, "can_dose": case_can_dose, "rtu_dose": case_rtu_dose, "disconnect_mid_dose": case_disconnect_mid_dose,
         "watchdog": case_watchdog, "bad_requests": case_bad_requests, "measure": measure}

a = argparse.ArgumentParser()
a.add_argument("--fw", required=True)
a.add_argument("--dynweigh", help="the dynweigh tool (--case can_dose: its plant)")
a.add_argument("--case", required=True, choices=sorted(CASES))
args = a.parse_args()
with tempfile.TemporaryDirectory() as scratch:
    CASES[args.case](args, scratch)
print("PASS")
