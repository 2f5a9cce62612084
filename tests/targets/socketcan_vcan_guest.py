#!/usr/bin/env python3
"""SocketCAN for real: boots a QEMU x86-64 guest (Debian's kernel, a busybox initramfs, the can,
can-raw, can-dev and vcan modules), runs `dynweigh plant --can socketcan:vcan0` and
`dynweigh-fw --plant can:socketcan:vcan0` on the batching scene with `dose 5000`, `discharge`, then
`batch 1:1500 2:1000`, and `candump -L vcan0` beside them. Passes when the dose reaches its target by
the plant's truth, the discharge answers OK and empties the hopper, the batch answers BATCH ok=1, and
candump shows well-formed frames of every kind in docs/can-protocol.md: the gate's 0x228 (open, then
closed, each with the counter of the sample it answers) and its 0x1A8 feedback (open, then closed),
and the ingredient valves' 0x221 and 0x222 (open, then closed, with the sample's counter) and their
0x1A1 and 0x1A2 feedback (open, then closed) included. The host kernel has no CAN, hence the guest.

The kernel comes from `apt-get download linux-image-6.1.0-<abi>-amd64` unpacked with `dpkg -x` into
$DYNWEIGH_GUEST_KERNEL (default /opt/dynweigh-guest-kernel); .ci/run does that. The host binaries
go into the initramfs with the shared libraries ldd names (libstdc++, libc, the loader), so the
same build is tested rather than a special static one."""
import argparse
import glob
import os
import re
import shutil
import subprocess
import tempfile

from targets_common import fail, skip, which

a = argparse.ArgumentParser()
a.add_argument("--dynweigh", required=True)
a.add_argument("--fw", required=True)
a.add_argument("--timeout", type=float, default=110)
args = a.parse_args()

qemu = which("qemu-system-x86_64")
if not qemu:
    skip("qemu-system-x86_64 is not installed (apt-get install qemu-system-x86)")
kernel_root = os.environ.get("DYNWEIGH_GUEST_KERNEL", "/opt/dynweigh-guest-kernel")
vmlinuz = sorted(glob.glob(os.path.join(kernel_root, "boot", "vmlinuz-*")))
if not vmlinuz:
    skip(f"no Debian kernel unpacked in {kernel_root} (apt-get download linux-image-6.1.0-<abi>-amd64; "
         f"dpkg -x linux-image-*.deb {kernel_root})")
busybox = which("busybox")
if not busybox or subprocess.run(["ldd", busybox], capture_output=True, text=True).returncode == 0:
    skip("busybox-static is not installed (apt-get install busybox-static)")
candump = which("candump")
if not candump:
    skip("candump is not installed (apt-get install can-utils)")
modules = {}
for name in ("can", "can-raw", "can-dev", "vcan"):
    found = glob.glob(os.path.join(kernel_root, "lib", "modules", "*", "kernel", "**", f"{name}.ko"), recursive=True)
    if not found:
        skip(f"module {name}.ko not found under {kernel_root}")
    modules[name] = found[0]

INIT = r"""#!/bin/busybox sh
/bin/busybox --install -s /bin
export PATH=/bin
mount -t proc proc /proc; mount -t sysfs sys /sys; mount -t devtmpfs dev /dev; mkdir -p /tmp
finish() { echo "GUEST_STATUS=$1"; printf "\\$(printf %03o $1)" | dd of=/dev/port bs=1 seek=244 count=1 2>/dev/null; sleep 5; }
for m in can can-raw can-dev vcan; do insmod /modules/$m.ko || { echo "insmod $m failed"; finish 2; }; done
ip link add dev vcan0 type vcan && ip link set up vcan0 || { echo "no vcan0"; finish 3; }
echo "vcan0=up"
/opt/dw/candump -L vcan0 > /tmp/candump.log 2>&1 &
CANDUMP=$!
/opt/dw/dynweigh plant --can socketcan:vcan0 --scene /opt/dw/batching.json --seed 1 --wait 30 --timeout 30 > /tmp/plant.log 2>&1 &
PLANT=$!
printf 'dose 5000\ndischarge\nbatch 1:1500 2:1000\n' | /opt/dw/dynweigh-fw --plant can:socketcan:vcan0 > /tmp/fw.log 2>&1
FW=$?
wait $PLANT
PLANT_STATUS=$?
sleep 1
kill $CANDUMP
echo "===fw exit=$FW"; cat /tmp/fw.log
echo "===plant exit=$PLANT_STATUS"; cat /tmp/plant.log
echo "===candump"; grep -m 3 ' 190#' /tmp/candump.log; grep -m 3 ' 220#' /tmp/candump.log
grep -m 2 ' 1A0#' /tmp/candump.log; grep -m 2 ' 181#' /tmp/candump.log; grep -m 3 ' 7[0-9A-F][0-9A-F]#' /tmp/candump.log
echo "candump_lines=$(wc -l < /tmp/candump.log)"
grep -m 2 ' 228#' /tmp/candump.log; grep -m 2 ' 1A8#' /tmp/candump.log
grep -m 2 ' 221#' /tmp/candump.log; grep -m 2 ' 1A1#' /tmp/candump.log
for id in 190 220 1A0 181 701 710 720 228 1A8 728 221 1A1 222 1A2 721 722; do echo "candump_$id=$(grep -c " $id#" /tmp/candump.log)"; done
echo "candump_bad=$(grep -vcE '^\([0-9]+\.[0-9]+\) vcan0 [0-9A-F]{3}#([0-9A-F]{2})*$' /tmp/candump.log)"
# The gate's frames, summarised here rather than copied over the serial console: the runs of
# 0x228 commands and 0x1A8 positions, and every 0x228 whose counter is not that of a 0x190 sample
# or not that of the 0x220 sent right after it in the same jiffy.
awk '
  { split($3, f, "#"); id = f[1]; d = f[2] }
  id == "190" { samples[substr(d, 9, 4)] = 1 }
  pending != "" && id == "220" { if (substr(d, 5, 4) != pending) bad_next++; pending = "" }
  id == "228" { if (length(d) != 8) bad_len++; c = substr(d, 1, 2)
                if (c != last_cmd) { cmds = cmds (cmds == "" ? "" : ",") c; last_cmd = c } pending = substr(d, 5, 4)
                if (!(pending in samples)) bad_sample++ }
  id == "1A8" { if (length(d) != 4) bad_len++; p = substr(d, 1, 2)
                if (p != last_pos) { pos = pos (pos == "" ? "" : ",") p; last_pos = p } }
  id ~ /^22[12]$/ { if (length(d) != 8) bad_len++; c = substr(d, 1, 2)
                   if (c != last_i[id]) { icmds[id] = icmds[id] (icmds[id] == "" ? "" : ",") c; last_i[id] = c }
                   if (!(substr(d, 5, 4) in samples)) bad_i_sample++ }
  id ~ /^1A[12]$/ { if (length(d) != 4) bad_len++; p = substr(d, 1, 2)
                    if (p != last_p[id]) { ipos[id] = ipos[id] (ipos[id] == "" ? "" : ",") p; last_p[id] = p } }
  END { printf "gate_commands=%s\ngate_positions=%s\ngate_frames_bad_length=%d\n", cmds, pos, bad_len
        printf "gate_counter_not_a_sample=%d\ngate_counter_not_the_valve_answer=%d\n", bad_sample, bad_next
        printf "ingredient1_commands=%s\ningredient2_commands=%s\n", icmds["221"], icmds["222"]
        printf "ingredient1_positions=%s\ningredient2_positions=%s\n", ipos["1A1"], ipos["1A2"]
        printf "ingredient_counter_not_a_sample=%d\n", bad_i_sample }
' /tmp/candump.log
echo "===end"
finish 0
"""


def copy_with_libraries(binary, root, dest):
    shutil.copy2(binary, os.path.join(root, dest.lstrip("/")))
    out = subprocess.run(["ldd", binary], capture_output=True, text=True).stdout
    for path in re.findall(r"(/\S+\.so\S*)", out):
        target = os.path.join(root, path.lstrip("/"))
        os.makedirs(os.path.dirname(target), exist_ok=True)
        if not os.path.exists(target):
            shutil.copy2(os.path.realpath(path), target)


with tempfile.TemporaryDirectory() as tmp:
    root = os.path.join(tmp, "root")
    for d in ("bin", "proc", "sys", "dev", "tmp", "modules", "opt/dw", "lib64", "lib/x86_64-linux-gnu"):
        os.makedirs(os.path.join(root, d), exist_ok=True)
    shutil.copy2(busybox, os.path.join(root, "bin", "busybox"))
    for name, path in modules.items():
        shutil.copy2(path, os.path.join(root, "modules", f"{name}.ko"))
    for binary, name in ((args.dynweigh, "dynweigh"), (args.fw, "dynweigh-fw"), (candump, "candump")):
        copy_with_libraries(binary, root, f"/opt/dw/{name}")
    # The scene the batch runs on, as a file (the guest has no data directory).
    shutil.copy2(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scenes", "batching.json"),
                 os.path.join(root, "opt", "dw", "batching.json"))
    with open(os.path.join(root, "init"), "w") as f:
        f.write(INIT)
    os.chmod(os.path.join(root, "init"), 0o755)
    initrd = os.path.join(tmp, "initramfs.cpio.gz")
    subprocess.run(f"find . | {busybox} cpio -o -H newc 2>/dev/null | gzip -1 > {initrd}", shell=True, cwd=root,
                   check=True)
    # The initramfs unpacks into RAM: a sanitizer build's tools (debug info and all) need room.
    guest_mb = "512" if os.path.getsize(initrd) < 64 * 1024 * 1024 else "2048"
    command = [qemu, "-kernel", vmlinuz[-1], "-initrd", initrd, "-m", guest_mb, "-smp", "1", "-nic", "none",
               "-nographic", "-no-reboot", "-device", "isa-debug-exit,iobase=0xf4,iosize=4",
               "-append", "console=ttyS0 quiet panic=-1"]
    try:
        guest = subprocess.run(command, capture_output=True, text=True, timeout=args.timeout,
                               stdin=subprocess.DEVNULL)
    except subprocess.TimeoutExpired as e:
        fail(f"the guest did not finish within {args.timeout} s:\n{(e.stdout or b'')[-3000:]}")

out = guest.stdout.replace("\r", "")
body = out[out.find("vcan0=up"):] if "vcan0=up" in out else out[-4000:]
print(body)
# isa-debug-exit: status (value << 1) | 1; a guest that panicked exits 0.
if guest.returncode % 2 != 1:
    fail(f"the guest never reached its end (QEMU exit {guest.returncode})")
if "GUEST_STATUS=0" not in out:
    fail("the guest script failed before the run")
kv = dict(re.findall(r"^([a-z_0-9A-F]+)=(\S*)$", out, re.M))
results = [l for l in out.splitlines() if l.startswith("RESULT ")]
batches = [l for l in out.splitlines() if l.startswith("BATCH ")]
if "===fw exit=0" not in out or "===plant exit=0" not in out or len(results) != 3:
    fail("dynweigh-fw or dynweigh plant failed in the guest")
if kv.get("end") != "indicator_stopped" or kv.get("late_answers") != "0":
    fail("lockstep on vcan0 broken")
# The discharge emptied the container: what was filled is what went out through the gate (the
# batch's ingredients, dosed after it, are all that is left in the hopper).
batch_kg = float(kv["ingredient1_released_kg"]) + float(kv["ingredient2_released_kg"])
left_kg = float(kv["final_static_kg"]) - batch_kg
true_g = (float(kv["discharged_kg"]) + left_kg) * 1000.0
print(f"true_fill_g={true_g:.1f}")
if abs(true_g - 5000) > 100:
    fail(f"filled {true_g:.1f} g for a 5000 g target")
fw_lines = out[out.find("===fw exit="):out.find("===plant exit=")].splitlines()
after = fw_lines[fw_lines.index(results[0]) + 1:][:2]
if after != ["OK", "OK"]:
    fail(f"expected the dose's OK then the discharge's OK after RESULT, got {after}")
if kv.get("gate_opens") != "1" or left_kg > 0.02:
    fail(f"the gate opened {kv.get('gate_opens')} times and left {left_kg:.3f} kg in the hopper")
if len(batches) != 1 or " ok=1" not in batches[0] or [re.search(r"material=(\d+)", r).group(1) for r in results] != ["0", "1", "2"]:
    fail("the batch did not answer BATCH ... ok=1 after RESULT lines for materials 1 and 2")
for cob in ("190", "220", "1A0", "181", "701", "710", "720", "228", "1A8", "728", "221", "1A1", "222", "1A2", "721", "722"):
    if int(kv.get(f"candump_{cob}", "0")) == 0:
        fail(f"candump saw no frame {cob}")
# One 0x220 per 0x190; the plant's last sample may cross the indicator's goodbye unanswered.
if not 0 <= int(kv["candump_190"]) - int(kv["candump_220"]) <= 1:
    fail("candump: not exactly one 0x220 per 0x190")
# The gate is commanded open (02) then closed (00); its feedback goes from open (03) to closed (00),
# through moving (01) if the plant reports it.
if kv.get("gate_commands") != "02,00":
    fail(f"0x228 commands ran {kv.get('gate_commands')!r}, not open then closed (02,00)")
positions = kv.get("gate_positions", "").split(",")
if "03" not in positions or positions[-1] != "00":
    fail(f"0x1A8 positions ran {kv.get('gate_positions')!r}: never open (3) then closed (0)")
if kv.get("gate_frames_bad_length") != "0":
    fail("candump shows 0x228 or 0x1A8 frames of the wrong length")
if kv.get("gate_counter_not_a_sample") != "0" or kv.get("gate_counter_not_the_valve_answer") != "0":
    fail("0x228 frames that do not carry the counter of the sample they answer")
# Each ingredient valve is commanded open (02, through half 01 if the model feeds fine) then closed
# (00), with the counter of a sample; its feedback reaches open (03) and ends closed (00).
for i in (1, 2):
    commands = kv.get(f"ingredient{i}_commands", "").split(",")
    if commands[0] != "02" or commands[-1] != "00":
        fail(f"0x22{i} commands ran {kv.get(f'ingredient{i}_commands')!r}, not open then closed")
    positions = kv.get(f"ingredient{i}_positions", "").split(",")
    if "03" not in positions or positions[-1] != "00":
        fail(f"0x1A{i} positions ran {kv.get(f'ingredient{i}_positions')!r}: never open (3) then closed (0)")
if kv.get("ingredient_counter_not_a_sample") != "0":
    fail("0x221/0x222 frames that do not carry the counter of a sample")
if kv.get("candump_bad") != "0":
    fail("candump shows frames that are not classic CAN data frames on vcan0")
print("PASS")
