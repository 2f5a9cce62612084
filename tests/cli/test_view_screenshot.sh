#!/usr/bin/env bash
# dynweigh view under Xvfb: a headless run renders the scene and the force trace; its screenshot's
# pixels show the trace (its yellow) and the valve marker (its green) in the trace panel, far more
# of them after 3 s of a dose than after one frame. Skipped (exit 77) when view was not built
# (no SDL2 at configure time) or Xvfb is missing.
set -euo pipefail
bin=$1; work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
cd "$work"
# Under AddressSanitizer: the OpenGL driver (Mesa, loaded at run time) keeps a few allocations
# until exit, which LeakSanitizer reports though they are not ours; every other check stays on.
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
if ! "$bin/dynweigh" --help | grep -q '^  view '; then echo "SKIP: dynweigh view not built (no SDL2/OpenGL at configure time)"; exit 77; fi
if ! command -v xvfb-run > /dev/null; then echo "SKIP: xvfb-run missing (apt-get install xvfb xauth)"; exit 77; fi
view() { timeout 40 xvfb-run -a -s "-screen 0 1280x800x24" "$bin/dynweigh" view --scene default --open-at 0.3 "$@"; }
view --frames 150 --screenshot dose.png | tee dose.txt
grep -qx 'frames=150' dose.txt
grep -qx 'sim_s=3.00' dose.txt
fps=$(sed -n 's/^fps=//p' dose.txt)
awk -v f="$fps" 'BEGIN { exit !(f >= 25) }' || { echo "only $fps frames/s"; exit 1; }
view --frames 1 --screenshot first.png > /dev/null
# Count trace-coloured pixels in the trace panel (right two thirds) with a small PNG reader.
/usr/bin/env python3 - dose.png first.png <<'PY'
import struct, sys, zlib
def pixels(path):
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    at, idat, w, h = 8, b"", 0, 0
    while at < len(data):
        n, kind = struct.unpack(">I4s", data[at:at + 8])
        body = data[at + 8:at + 8 + n]
        if kind == b"IHDR":
            w, h, depth, colour = struct.unpack(">IIBB", body[:10])
            assert depth == 8 and colour == 2, "expected 8-bit RGB"
        elif kind == b"IDAT":
            idat += body
        at += 12 + n
    raw = zlib.decompress(idat)
    rows = []
    for y in range(h):
        line = raw[y * (3 * w + 1):(y + 1) * (3 * w + 1)]
        assert line[0] == 0, "filter type 0 expected"
        rows.append(line[1:])
    return w, h, rows
def count(path, want):
    w, h, rows = pixels(path)
    n = 0
    for row in rows:
        for x in range(w // 3, w):
            r, g, b = row[3 * x:3 * x + 3]
            if want(r, g, b):
                n += 1
    return n
trace = lambda r, g, b: r > 200 and 150 < g < 240 and b < 60          # the force: yellow
valve = lambda r, g, b: r < 90 and g > 170 and 60 < b < 130            # the valve marker: green
dose_trace, first_trace = count(sys.argv[1], trace), count(sys.argv[2], trace)
dose_valve = count(sys.argv[1], valve)
print(f"trace_pixels={dose_trace} trace_pixels_first_frame={first_trace} valve_pixels={dose_valve}")
assert dose_trace > 500, "the force trace does not show"
assert dose_trace > 10 * max(first_trace, 1), "the trace did not grow while the scene ran"
assert dose_valve > 100, "the valve marker does not show"
import os
w, h, _ = pixels(sys.argv[1])
size = os.path.getsize(sys.argv[1])
print(f"png_bytes={size} raw_bytes={3 * w * h}")
assert size < 3 * w * h // 4, "the screenshot is not compressed"
PY
# Bad options: one line, non-zero.
if err=$("$bin/dynweigh" view --scene nosuch --frames 1 2>&1 >/dev/null); then echo "accepted a bad scene"; exit 1; fi
[ "$(wc -l <<<"$err")" -eq 1 ]
if "$bin/dynweigh" view --screenshot x.png 2>/dev/null; then echo "screenshot without --frames accepted"; exit 1; fi
