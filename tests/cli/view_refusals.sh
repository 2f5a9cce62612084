#!/usr/bin/env bash
# dynweigh view refuses what it cannot do, in one line and exit 1: a --screenshot it cannot write
# (not .png, or an unwritable path) before any frame, and an interactive window without a display.
# Without a display, --frames N renders offscreen and exits 0. Skipped (77) without view.
set -uo pipefail
bin=$(cd "$1" && pwd); work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"  # Mesa's own allocations at exit
if ! "$bin/dynweigh" --help | grep -q '^  view '; then echo "SKIP: dynweigh view not built"; exit 77; fi
headless=(env -u DISPLAY -u WAYLAND_DISPLAY -u SDL_VIDEODRIVER)
failures=0

refused() {  # refused PATTERN ARGS...: view exits 1 with one stderr line matching PATTERN, writes nothing
  local pattern=$1 rc; shift
  timeout 30 "${headless[@]}" "$bin/dynweigh" view "$@" >stdout 2>stderr </dev/null
  rc=$?
  if [ "$rc" -ne 1 ] || [ "$(grep -c '' stderr)" -ne 1 ] || ! grep -q -- "$pattern" stderr || [ -s stdout ]; then
    echo "FAIL (exit $rc): view $*"; cat stdout stderr; failures=$((failures + 1))
  else
    echo "ok: view $* -> $(cat stderr)"
  fi
}

refused "does not end in .png" --frames 2 --screenshot shot.jpg
[ ! -e shot.jpg ] || { echo "FAIL: shot.jpg was written"; failures=$((failures + 1)); }
refused "does not end in .png" --frames 2 --screenshot shot.PNG.gif
refused "cannot write /nonexistent" --frames 2 --screenshot /nonexistent/dir/shot.png
refused "no display" --scene default
refused "no display" --open-at 0.3
refused "unknown scene" --frames 2 --screenshot left.png --scene nosuch
[ ! -e left.png ] || { echo "FAIL: a refused view left left.png behind"; failures=$((failures + 1)); }

# Headless with --frames: rendered offscreen, a real PNG.
timeout 60 "${headless[@]}" "$bin/dynweigh" view --frames 3 --screenshot shot.png >out.txt 2>err.txt
rc=$?
if [ "$rc" -ne 0 ] || ! grep -qx 'frames=3' out.txt || [ "$(head -c 4 shot.png | od -An -c | tr -d ' ')" != '211PNG' ]; then
  echo "FAIL: headless --frames 3 --screenshot shot.png (exit $rc)"; cat out.txt err.txt; failures=$((failures + 1))
else
  echo "ok: headless --frames 3 --screenshot shot.png"
fi

[ "$failures" -eq 0 ] || { echo "$failures view refusals went wrong"; exit 1; }
