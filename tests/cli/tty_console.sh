#!/usr/bin/env bash
# dynweigh-fw --console <device>: the console on an existing serial line. socat links two ptys, as a
# null-modem cable links two UARTs; pyserial (an independent client) talks on the other end; every
# answer line ends in CR LF, as on any serial line.
set -uo pipefail
bin=$1; work=$(mktemp -d)
command -v socat >/dev/null || { echo "socat absent: skipped"; exit 77; }
/usr/bin/python3 -c 'import serial' 2>/dev/null || { echo "python3-serial absent: skipped"; exit 77; }
socat pty,raw,echo=0,link="$work/indicator" pty,raw,echo=0,link="$work/client" & socat_pid=$!
trap 'kill $socat_pid $fw_pid 2>/dev/null; rm -rf "$work"' EXIT
for _ in $(seq 50); do [ -e "$work/client" ] && break; sleep 0.1; done
"$bin/dynweigh-fw" --console "$work/indicator" > "$work/fw.out" & fw_pid=$!
/usr/bin/python3 - "$work/client" <<'PY'
import sys, time, serial
port = serial.Serial(sys.argv[1], 115200, timeout=5)
def ask(line):
    port.write((line + "\r\n").encode())
    answer = []
    deadline = time.time() + 10
    while time.time() < deadline:
        raw = port.readline()
        if raw and not raw.endswith(b"\r\n"):
            raise SystemExit(f"answer line {raw!r} does not end in CR LF")
        text = raw.decode().strip()
        if text:
            answer.append(text)
        if text == "OK" or text.startswith("ERR"):
            return answer
    raise SystemExit(f"no answer to {line!r}: {answer}")
assert ask("version")[-1] == "OK"
status = ask("status")
assert status[0].startswith("STATUS state=idle"), status
assert ask("nosuch") == ["ERR 1 unknown command"]
print("tty console answers:", status[0])
PY
