#!/usr/bin/env python3
"""Size report of the Cortex-M4F image: flash (text + data initialisers) and RAM (data + bss + stack,
the 1000-record test-data buffer included) against the budget (flash < 128 KB, RAM < 32 KB), and
proof that no allocator and no double arithmetic (software routines on the M4F's single-precision
FPU) is linked."""
import argparse
import os
import re
import subprocess

from targets_common import fail, skip, which

a = argparse.ArgumentParser()
a.add_argument("--elf", required=True)
args = a.parse_args()
if not os.path.isfile(args.elf):
    skip(f"no Cortex-M image at {args.elf}: the arm-none-eabi toolchain is not installed")
size = which("arm-none-eabi-size")
nm = which("arm-none-eabi-nm")
sections = {}
for line in subprocess.run([size, "-A", "-d", args.elf], capture_output=True, text=True, check=True).stdout.splitlines():
    m = re.match(r"^(\.\S+)\s+(\d+)\s+(\d+)", line)
    if m:
        sections[m.group(1)] = int(m.group(2))
flash = sum(sections.get(s, 0) for s in (".isr_vector", ".text", ".ARM.exidx", ".init_array", ".data"))
ram = sum(sections.get(s, 0) for s in (".data", ".bss", ".stack"))
symbols = subprocess.run([nm, "-S", "-C", "--size-sort", args.elf], capture_output=True, text=True, check=True).stdout
recorder = [l for l in symbols.splitlines() if "g_indicator" in l]
print(f"flash_bytes={flash}")
print(f"ram_bytes={ram}")
print(f"text_bytes={sections.get('.text', 0)} data_bytes={sections.get('.data', 0)} "
      f"bss_bytes={sections.get('.bss', 0)} stack_bytes={sections.get('.stack', 0)}")
if recorder:
    print(f"indicator_object_bytes={int(recorder[0].split()[1], 16)}")
for name in ("malloc", "_malloc_r", "_sbrk", "operator new"):
    if re.search(rf"\b[TtWw] {re.escape(name)}\b", symbols):
        fail(f"{name} is linked into the image")
doubles = sorted(set(re.findall(r"\b[TtWw] (__aeabi_d\w+|__aeabi_\w+2d|__\w+df[23])\b", symbols)))
if doubles:
    fail(f"double arithmetic is linked into the image: {' '.join(doubles)}")
if flash >= 128 * 1024:
    fail(f"flash {flash} B over 128 KB")
if ram >= 32 * 1024:
    fail(f"RAM {ram} B over 32 KB")
print("PASS")
