#!/usr/bin/env bash
# dynweigh term against `dynweigh-fw --console pty`: commands answered, readtestdata captured into
# CSV; pyserial (an independent client) reads the same records through the same pty; and
# dynweigh term talks to a pty that python3 drives as a fake indicator.
set -euo pipefail
bin=$1; work=$(mktemp -d)
fw_pid=""
cleanup() {
  if [ -n "$fw_pid" ]; then kill "$fw_pid" 2>/dev/null || true; wait "$fw_pid" 2>/dev/null || true; fi
  rm -rf "$work"
}
trap cleanup EXIT
cd "$work"
# Debian's python3 carries python3-serial; a python3 earlier in PATH (pyenv, venv) may not.
py=/usr/bin/python3; [ -x "$py" ] || py=python3
"$py" -c 'import serial' || { echo "pyserial missing: apt-get install python3-serial"; exit 1; }

"$bin/dynweigh-fw" --console pty > fw.out 2> fw.err &
fw_pid=$!
for _ in $(seq 100); do grep -q '^console=' fw.out && break; sleep 0.05; done
dev=$(sed -n 's/^console=//p' fw.out)
[ -c "$dev" ] || { echo "no pty from dynweigh-fw: $(cat fw.out fw.err)"; exit 1; }

# A test cycle, then its records: readtestdata is retried while the cycle still records (ERR 3).
timeout 40 "$bin/dynweigh" term "$dev" --send 'version' --send 'starttestdata 20 300' --send 'readtestdata' \
  --out term.csv --timeout 30 > term.txt
cat term.txt
grep -q '^dynweigh ' term.txt
grep -qx 'records=1000' term.txt
[ "$(head -n1 term.csv)" = "jiffy,raw,filtered,marker" ]
[ "$(wc -l < term.csv)" -eq 1001 ]
awk -F, 'NR > 1 && (($1 >= 20 && $1 < 300) != ($4 == 2)) { bad = 1 } END { exit bad }' term.csv \
  || { echo "markers do not follow starttestdata 20 300"; exit 1; }

# pyserial, 115200 8N1, reads the same last cycle.
timeout 40 "$py" - "$dev" term.csv <<'PY'
import sys, time, serial
dev, csv_path = sys.argv[1], sys.argv[2]
port = serial.Serial(dev, 115200, bytesize=8, parity="N", stopbits=1, timeout=5)
port.reset_input_buffer()
def ask(command):
    port.write((command + "\n").encode())
    lines = []
    deadline = time.time() + 20
    while time.time() < deadline:
        line = port.readline().decode().rstrip("\r\n")
        if line == "OK" or line.startswith("ERR"):
            return lines, line
        if line:
            lines.append(line)
    raise SystemExit(f"no answer to {command}")
lines, answer = ask("status")
assert answer == "OK" and lines[0].startswith("STATUS state=idle"), (lines, answer)
lines, answer = ask("readtestdata")
assert answer == "OK", answer
records = [",".join(l.split()) for l in lines]
with open(csv_path) as f:
    captured = f.read().split("\n")[1:-1]
assert records == captured, "pyserial and dynweigh term disagree"
lines, answer = ask("nosuchcommand")
assert answer.startswith("ERR 1"), answer
print("pyserial_records=%d" % len(records))
PY

# An ERR answer makes term exit non-zero with one line.
if err=$(timeout 20 "$bin/dynweigh" term "$dev" --send 'dose' --quiet 2>&1 >/dev/null); then
  echo "ERR answer not reported"; exit 1
fi
[ "$(wc -l <<<"$err")" -eq 1 ] && grep -q "ERR 2" <<<"$err"
kill "$fw_pid"; wait "$fw_pid" 2>/dev/null || true; fw_pid=""

# A fake indicator on a pty made by python: term must stop at its answer, send in order, and time
# out (non-zero, one line) when nothing answers.
timeout 40 "$py" - "$bin/dynweigh" <<'PY'
import os, subprocess, sys, threading, time
master, slave = os.openpty()
name = os.ttyname(slave)
seen = []
def fake():
    buf = b""
    while True:
        try:
            data = os.read(master, 1024)
        except OSError:
            return
        buf += data
        while b"\n" in buf:
            line, buf = buf.split(b"\n", 1)
            seen.append(line.decode())
            if line == b"hello":
                os.write(master, b"hi there\r\nOK\r\n")
            elif line == b"silent":
                pass
threading.Thread(target=fake, daemon=True).start()
out = subprocess.run([sys.argv[1], "term", name, "--send", "hello", "--quiet"], capture_output=True, text=True, timeout=20)
assert out.returncode == 0 and "hi there" in out.stdout and "sent=1" in out.stdout, out
out = subprocess.run([sys.argv[1], "term", name, "--send", "silent", "--timeout", "1", "--quiet"], capture_output=True, text=True, timeout=20)
assert out.returncode != 0 and out.stderr.count("\n") == 1 and "no OK or ERR" in out.stderr, out
assert seen == ["hello", "silent"], seen
# Interactive, on a terminal: type with a typo, fix it with the arrows and backspace, send; then
# up arrow recalls the line, Enter sends it again; Ctrl-D quits.
import pty, select
pid, fd = pty.fork()
if pid == 0:
    os.execv(sys.argv[1], [sys.argv[1], "term", name])
def typed(keys):
    os.write(fd, keys)
    time.sleep(0.3)
def drain():
    out = b""
    while select.select([fd], [], [], 0.2)[0]:
        try:
            out += os.read(fd, 4096)
        except OSError:
            break
    return out
time.sleep(0.5)
typed(b"helo")
typed(b"\x1b[D")      # left: before the o
typed(b"l\r")          # hello
typed(b"\x1b[A\r")     # up, Enter: hello again
typed(b"ab\x7fc\x01x\r") # a, b, backspace, c, Ctrl-A, x: "xac"
typed(b"\x04")         # Ctrl-D on an empty line quits
screen = drain().decode(errors="replace")
_, status = os.waitpid(pid, 0)
assert os.WIFEXITED(status) and os.WEXITSTATUS(status) == 0, status
assert seen[2:] == ["hello", "hello", "xac"], seen
assert "hi there" in screen, screen
print("interactive=ok")
print("fake_indicator=ok")
PY
if timeout 10 "$bin/dynweigh" term /nonexistent/tty --send x 2>/dev/null; then echo "opened a missing device"; exit 1; fi
if timeout 10 "$bin/dynweigh" term /dev/null --send x 2>/dev/null; then echo "accepted /dev/null as a serial device"; exit 1; fi
