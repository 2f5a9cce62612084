"""Helpers of the process-level target tests: bounded waits, key=value parsing, skip status."""
import os
import re
import socket
import struct
import subprocess
import sys
import time

SKIP = 77  # ctest SKIP_RETURN_CODE


def skip(reason):
    print(f"SKIP: {reason}", flush=True)
    sys.exit(SKIP)


def fail(reason):
    print(f"FAIL: {reason}", flush=True)
    sys.exit(1)


def free_udp_ports(count):
    """Ports free on 127.0.0.1 right now (bound then released by the kernel's choice)."""
    sockets, ports = [], []
    for _ in range(count):
        s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        s.bind(("127.0.0.1", 0))
        sockets.append(s)
        ports.append(s.getsockname()[1])
    for s in sockets:
        s.close()
    return ports


def plant_on_udp(dynweigh, scene, jiffies, wait_s=20):
    """`dynweigh plant` on the udp transport, with this script as the indicator: (socket, plant's
    address, plant process). The socket is bound where the plant sends."""
    plant_port, own_port = free_udp_ports(2)
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.bind(("127.0.0.1", own_port))
    plant = subprocess.Popen([dynweigh, "plant", "--can", f"udp:{plant_port}@127.0.0.1:{own_port}",
                              "--scene", scene, "--jiffies", str(jiffies), "--wait", str(wait_s),
                              "--timeout", str(wait_s)],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    return sock, ("127.0.0.1", plant_port), plant


def firmware_on_udp_plant(dynweigh, fw, scene, console_input, timeout, plant_options=()):
    """dynweigh-fw's CAN node against `dynweigh plant` on udp, `console_input` typed on its stdio;
    both outputs printed. Returns (the firmware's CompletedProcess, the plant's output, its exit)."""
    plant_port, fw_port = free_udp_ports(2)
    plant = subprocess.Popen([dynweigh, "plant", "--can", f"udp:{plant_port}@127.0.0.1:{fw_port}",
                              "--scene", scene, *plant_options, "--wait", "20", "--timeout", "20"],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        firmware = subprocess.run([fw, "--plant", f"can:udp:{fw_port}@127.0.0.1:{plant_port}"],
                                  input=console_input, capture_output=True, text=True, timeout=timeout)
        plant_out, _ = plant.communicate(timeout=10)
    finally:
        stop(plant)
    print("--- dynweigh-fw ---\n" + firmware.stdout + firmware.stderr)
    print("--- dynweigh plant ---\n" + plant_out)
    return firmware, plant_out, plant.returncode


def key_values(text):
    return dict(re.findall(r"^([a-z][a-z0-9_]*)=(\S*)$", text, re.M))


def field(line, name):
    m = re.search(rf"\b{name}=(\S+)", line)
    return m.group(1) if m else None


def stop(process, timeout=5):
    """Ends a process we started: SIGTERM, then SIGKILL."""
    if process.poll() is None:
        process.terminate()
        try:
            process.wait(timeout)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


def read_line_matching(stream, pattern, deadline):
    """Reads lines from a pipe until one matches (a handshake, not a sleep); None at EOF/deadline."""
    regex = re.compile(pattern)
    seen = []
    while time.monotonic() < deadline:
        line = stream.readline()
        if not line:
            break
        seen.append(line)
        m = regex.search(line)
        if m:
            return m, seen
    return None, seen


def which(program):
    for d in os.environ.get("PATH", "").split(os.pathsep) + ["/usr/bin", "/usr/sbin", "/sbin"]:
        p = os.path.join(d, program)
        if os.path.isfile(p) and os.access(p, os.X_OK):
            return p
    return None


def frame(can_id, data):
    """A CAN frame as the udp: transport carries it: id (u32), length (u8), 3 pad bytes, 8 data bytes."""
    return struct.pack("<IB3x8s", can_id, len(data), bytes(data).ljust(8, b"\0"))


def parse(datagram):
    """(id, data) of a udp: datagram; (None, b"") for one of the wrong size."""
    if len(datagram) != 16:
        return None, b""
    can_id, length = struct.unpack_from("<IB", datagram)
    return can_id, datagram[8:8 + length]
