#!/usr/bin/env python3
"""The docs' recipes run as written: every shell block of README.md and of the pages in docs/ (a
fenced block tagged sh, bash or shell, or an indented block, the docs' way of showing a command line;
output is shown in a fenced block tagged text) runs in a scratch
directory with the built programs first on PATH, under `bash -e -o pipefail`, each in a session of
its own with a time limit. A block fails if it exits non-zero, runs out of time, or leaves a
process running (a recipe that orphans a program is broken even if it exits 0).

The blocks that cannot run here are skipped by name below, each with its reason, and the test
prints them; a block that is neither run nor skipped by name does not exist: every block is run
unless it is listed. Fenced blocks without a shell tag (a synopsis, a diagram) are not commands.

Usage: readme_recipes.py <build dir> [FILE.md | FOLDER]...
(default: README.md; a FOLDER stands for every *.md in it)
"""
import glob
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

# A substring of a block's first line -> why it does not run in this test.
SKIPPED = {
    "install the dependencies (apt)": "installs packages with apt and builds the tree (this test runs on the build)",
    "cmake --preset mpi": "needs the MPI build and mpirun/srun on a cluster (tests/mpi covers the runner)",
    "#!/bin/bash": "a Slurm batch script for sbatch on a cluster",
    "openocd": "flashes an STM32F4 board through an ST-LINK (hardware)",
    "qemu-system-arm": "waits for a plant in another shell; the QEMU image is run by targets.cortexm_qemu_*",
    "dynweigh dem --scene default": "the DEM calibration runs for minutes on two cores (tests/grid covers it)",
    "# build the Debian package": "builds in the source tree (tests/package builds the package and checks it)",
    "# on the controller: install the package": "installs a package as root (tests/package unpacks it and runs it)",
    "# one instance per scale": "needs root and systemd as init (tests/package verifies the unit and its launcher)",
    "python3 tests/targets/outside_plant.py": "runs from the source tree (targets.outside_plant_* run it)",
}
SHELL_TAGS = {"sh", "bash", "shell", "console"}
TIME_LIMIT_S = 120


def blocks(text):
    """(line number, code) for each shell block."""
    lines = text.split("\n")
    found, i = [], 0
    while i < len(lines):
        fence = re.match(r"^(```+|~~~+)\s*(\S*)", lines[i])
        if fence:
            j = i + 1
            while j < len(lines) and not lines[j].startswith(fence.group(1)):
                j += 1
            if fence.group(2).lower() in SHELL_TAGS:
                found.append((i + 1, "\n".join(lines[i + 1:j])))
            i = j + 1
            continue
        if lines[i].startswith("    ") and lines[i].strip() and (i == 0 or not lines[i - 1].strip()):
            j = i
            while j < len(lines) and (lines[j].startswith("    ") or
                                      (not lines[j].strip() and j + 1 < len(lines) and lines[j + 1].startswith("    "))):
                j += 1
            found.append((i + 1, "\n".join(l[4:] for l in lines[i:j])))
            i = j
            continue
        i += 1
    return found


def session_members(sid):
    members = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat") as f:
                fields = f.read().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[3]) == sid and fields[0] != "Z":  # fields: state ppid pgrp session
            members.append(int(entry))
    return members


def run(code, build, work):
    env = dict(os.environ, PATH=build + os.pathsep + os.environ.get("PATH", ""))
    script = "set -e -o pipefail\n" + code + "\n"
    # Output to a file, not a pipe: a program the recipe leaves behind must not hold the test up.
    with open(os.path.join(work, ".readme-block-output"), "w+") as log:
        process = subprocess.Popen(["bash", "-c", script], cwd=work, env=env, start_new_session=True,
                                   stdout=log, stderr=subprocess.STDOUT, text=True)
        try:
            process.wait(timeout=TIME_LIMIT_S)
            problem = None if process.returncode == 0 else f"exit status {process.returncode}"
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()
            problem = f"still running after {TIME_LIMIT_S} s"
        log.seek(0)
        output = log.read()
    time.sleep(0.3)  # a background program the recipe ended is given its moment to go
    left = session_members(process.pid)
    if left:
        names = []
        for pid in left:
            try:
                with open(f"/proc/{pid}/cmdline", "rb") as f:
                    names.append(f.read().replace(b"\0", b" ").decode().strip())
            except OSError:
                pass
            try:
                os.kill(pid, signal.SIGKILL)
            except OSError:
                pass
        problem = (problem + "; " if problem else "") + f"left running: {names}"
    return problem, output


def documents(arguments):
    """The Markdown files named, a folder standing for every *.md in it (in name order)."""
    if not arguments:
        arguments = [os.path.join(os.path.dirname(__file__), "..", "..", "README.md")]
    files = []
    for argument in arguments:
        files += sorted(glob.glob(os.path.join(argument, "*.md"))) if os.path.isdir(argument) else [argument]
    return files


def main():
    build = os.path.abspath(sys.argv[1])
    failed = 0
    ran = 0
    for document in documents(sys.argv[2:]):
        name = os.path.relpath(os.path.abspath(document), os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
        for line, code in blocks(open(document).read()):
            result = run_block(f"{name}:{line}", code, build)
            ran += result is not None
            failed += result is True
    print(f"blocks_run={ran} blocks_failed={failed}")
    if ran == 0:
        print("FAIL: no block ran")
        return 1
    return 1 if failed else 0


def run_block(where, code, build):
    """Runs one block and prints its verdict: None when skipped by name, True when it failed."""
    first = next((l for l in code.split("\n") if l.strip()), "")
    reason = next((why for key, why in SKIPPED.items() if key in first), None)
    if reason:
        print(f"skip {where}: {first[:60]!r}: {reason}")
        return None
    work = tempfile.mkdtemp(prefix="readme-")
    try:
        t0 = time.monotonic()
        problem, output = run(code, build, work)
        verdict = "FAIL" if problem else "ok"
        print(f"{verdict} {where} ({time.monotonic() - t0:.1f} s): {first[:70]!r}")
        if problem:
            print(f"  {problem}\n  output:\n" + "\n".join("    " + l for l in output.splitlines()[-20:]))
        return bool(problem)
    finally:
        shutil.rmtree(work, ignore_errors=True)


sys.exit(main())
