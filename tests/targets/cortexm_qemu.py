#!/usr/bin/env python3
"""The Cortex-M4F image in QEMU (mps2-an386, -icount: deterministic instruction timing), its console
on UART0 (-serial stdio) and the plant on UART1 as SLCAN over a unix socket
(`dynweigh plant --can slcan:<socket>`).
  --mode testdata: starttestdata 50 600, wait for the cycle, readtestdata -> 1000 records + OK
  --mode dose:     dose 5000 -> RESULT line; then 8 doses of 1000 g, so that the last ones time
                   their close with the material's full history of doses (dose_history.hpp, the
                   heaviest fit); the plant's truth within 100 g of the targets' sum.
                   --scene, --first-g, --small-doses, --small-g change the plant and the doses:
                   `--scene tall-drop --first-g 500 --small-doses 1 --small-g 500` tops up every
                   dose three times, each pulse certified dynamically on a platform that rings
                   long (the settling fit over its whole window, every jiffy)
  --plugin SO:     count the instructions of Indicator::step per jiffy (goal < 20,000 while dosing)
"""
import argparse
import io
import os
import queue
import re
import subprocess
import sys
import tempfile
import threading
import time

from targets_common import fail, skip, stop, key_values, field, which

a = argparse.ArgumentParser()
a.add_argument("--elf", required=True)
a.add_argument("--dynweigh", required=True)
a.add_argument("--fw", help="host dynweigh-fw, to print the host build's result beside the image's")
a.add_argument("--mode", choices=["testdata", "dose"], required=True)
a.add_argument("--seed", default="1")
a.add_argument("--plugin")
a.add_argument("--budget", type=int, default=20000)
a.add_argument("--timeout", type=float, default=55)
a.add_argument("--scene", default="default")
a.add_argument("--first-g", type=int, default=5000)
a.add_argument("--small-doses", type=int, default=8)  # 13 kg in all, of the default silo's 18
a.add_argument("--small-g", type=int, default=1000)
args = a.parse_args()
SMALL_DOSES, SMALL_DOSE_G = args.small_doses, args.small_g

qemu = which("qemu-system-arm")
if not qemu:
    skip("qemu-system-arm is not installed (apt-get install qemu-system-arm)")
if not os.path.isfile(args.elf):
    skip(f"no Cortex-M image at {args.elf}: the arm-none-eabi toolchain is not installed "
         "(apt-get install gcc-arm-none-eabi libnewlib-arm-none-eabi libstdc++-arm-none-eabi-newlib)")
deadline = time.monotonic() + args.timeout


def marker_addresses():
    nm = which("arm-none-eabi-nm") or which("nm")
    out = subprocess.run([nm, args.elf], capture_output=True, text=True, check=True).stdout
    symbols = {m.group(2): int(m.group(1), 16) for m in re.finditer(r"^([0-9a-f]+) T (\w+)$", out, re.M)}
    return {k: symbols[f"dw_step_{v}"] for k, v in (("begin", "begin"), ("idle", "end_idle"), ("active", "end_active"))}


with tempfile.TemporaryDirectory() as tmp:
    sock = os.path.join(tmp, "plant.sock")
    command = [qemu, "-M", "mps2-an386", "-display", "none", "-monitor", "none", "-serial", "stdio",
               "-chardev", f"socket,id=plant,path={sock},server=on,wait=on", "-serial", "chardev:plant",
               "-semihosting-config", "enable=on,target=native",
               "-icount", "shift=5,align=off,sleep=off", "-kernel", args.elf]
    insn_file = os.path.join(tmp, "insn.txt")
    if args.plugin:
        marks = marker_addresses()
        command += ["-plugin", f"{args.plugin},begin={marks['begin']:#x},idle={marks['idle']:#x},"
                               f"active={marks['active']:#x},out={insn_file}", "-d", "plugin"]
    board = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True, bufsize=1)
    # The console UART as bytes arrive: its lines must end in CR LF (a terminal on a serial line).
    board_stdout = io.TextIOWrapper(board.stdout.buffer, newline="")
    bare_lf_lines = []
    plant = None
    try:
        # Handshake: QEMU says it waits for the plant's connection before the board starts.
        line = board.stderr.readline()
        if "waiting for connection" not in line:
            fail(f"QEMU did not start: {line}{board.stderr.read() if board.poll() is not None else ''}")
        threading.Thread(target=lambda: board.stderr.read(), daemon=True).start()
        plant = subprocess.Popen([args.dynweigh, "plant", "--can", f"slcan:{sock}", "--scene", args.scene,
                                  "--seed", args.seed, "--wait", "20", "--timeout", "20"],
                                 stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        lines = queue.Queue()

        def reader():
            for l in board_stdout:
                if l.endswith("\n") and not l.endswith("\r\n"):
                    bare_lf_lines.append(l)
                lines.put(l.rstrip("\r\n"))
            lines.put(None)

        threading.Thread(target=reader, daemon=True).start()
        transcript = []

        def answer(cmd):
            board.stdin.write(cmd + "\n")
            board.stdin.flush()
            got = []
            while True:
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    fail(f"no answer to {cmd!r} in time; last lines {transcript[-5:]}")
                try:
                    l = lines.get(timeout=remaining)
                except queue.Empty:
                    continue
                if l is None:
                    fail(f"the board's console closed during {cmd!r}; last lines {transcript[-5:]}")
                transcript.append(l)
                if not l or l.startswith("dynweigh "):  # banner
                    continue
                got.append(l)
                if l == "OK" or l.startswith("ERR "):
                    return got

        if args.mode == "testdata":
            if answer("starttestdata 50 600")[-1] != "OK":
                fail("starttestdata refused")
            while True:
                status = answer("status")
                if "state=idle" in status[0]:
                    out = answer("readtestdata")
                    if out[-1] == "ERR 3 busy":
                        continue
                    break
            records = [l for l in out[:-1] if re.fullmatch(r"\d+ -?\d+ -?\d+ [012]", l)]
            if out[-1] != "OK" or len(records) != 1000 or len(out) != 1001:
                fail(f"readtestdata: {len(records)} records in {len(out)} lines, last {out[-1]!r}")
            if [int(r.split()[0]) for r in records] != list(range(1000)):
                fail("jiffies are not 0..999")
            markers = [int(r.split()[3]) for r in records]
            if markers[40] != 0 or markers[300] != 2 or markers[900] != 0:
                fail("the valve markers do not follow the 50/600 schedule")
            print("records=1000")
        else:
            out = answer(f"dose {args.first_g}")
            results = [l for l in out if l.startswith("RESULT ")]
            if out[-1] != "OK" or len(results) != 1:
                fail(f"dose answered {out}")
            print(results[0])
            for _ in range(SMALL_DOSES):
                out = answer(f"dose {SMALL_DOSE_G}")
                results = [l for l in out if l.startswith("RESULT ")]
                if out[-1] != "OK" or len(results) != 1:
                    fail(f"dose {SMALL_DOSE_G} answered {out}")
                print(results[0])
        if bare_lf_lines:
            fail(f"console lines end in a bare LF, not CR LF: {bare_lf_lines[:3]}")
        print("console_line_ending=CRLF")
    finally:
        stop(board)  # the plant then sees its link close and prints its summary
        if plant:
            try:
                plant_out, _ = plant.communicate(timeout=10)
            finally:
                stop(plant)
    print("--- dynweigh plant ---\n" + plant_out)
    kv = key_values(plant_out)
    if kv.get("late_answers") != "0" or kv.get("malformed_frames") != "0":
        fail("lockstep over SLCAN broken: late answers or malformed frames")
    if args.mode == "dose":
        true_g = float(kv["final_static_kg"]) * 1000.0
        targets_g = args.first_g + SMALL_DOSES * SMALL_DOSE_G
        print(f"cortexm_true_fill_g={true_g:.1f} cortexm_true_error_g={true_g - targets_g:.1f}")
        if args.fw:
            host = subprocess.run([args.fw, "--seed", args.seed, "--plant", f"sim:{args.scene}"],
                                  input=f"dose {args.first_g}\n", capture_output=True, text=True, timeout=30)
            host_result = next((l for l in host.stdout.splitlines() if l.startswith("RESULT ")), "")
            print(f"host_build: {host_result}")
        if abs(true_g - targets_g) > 100:
            fail(f"the image filled {true_g:.1f} g for {targets_g} g of targets (within 100 g)")
    if args.plugin:
        text = open(insn_file).read() if os.path.exists(insn_file) else ""
        summary = key_values(text)
        print("\n".join(f"{k}={v}" for k, v in summary.items()))
        if not summary or int(summary.get("insn_active_jiffies", "0")) == 0:
            fail("the plugin counted no jiffy while dosing")
        worst = int(summary["insn_active_max"])
        if worst >= args.budget:
            fail(f"Indicator::step took up to {worst} instructions in a jiffy while dosing (budget {args.budget})")
    print("PASS")
