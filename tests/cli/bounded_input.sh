#!/usr/bin/env bash
# Bounded input, prompt exit: a console line that never ends is dropped past the console's 80
# characters as it comes, so `dynweigh-fw < /dev/zero` stays small; SIGTERM and SIGINT end
# dynweigh-fw within a second while it waits on an idle stdin, a pty or a CAN link; stdio answers
# end in a bare LF.
set -uo pipefail
bin=$1; work=$(mktemp -d); pids=()
cleanup() { for p in "${pids[@]}"; do kill -9 "$p" 2>/dev/null; done; rm -rf "$work"; }
trap cleanup EXIT
cd "$work"
fw="$bin/dynweigh-fw"
failed=0
check() { if eval "$2"; then echo "ok: $1"; else echo "FAIL: $1"; failed=1; fi; }
rss_kb() { awk '/^VmRSS:/ { print $2 }' "/proc/$1/status" 2>/dev/null || echo 0; }
# Waits up to $2 tenths of a second for process $1 to end; true if it did.
ended_within() { for _ in $(seq "$2"); do kill -0 "$1" 2>/dev/null || return 0; sleep 0.1; done; ! kill -0 "$1" 2>/dev/null; }

# An endless line of NULs, and one of letters: memory stays bounded, SIGTERM ends the program.
for source in "cat /dev/zero" "tr '\\0' x < /dev/zero"; do
  bash -c "$source" | "$fw" > /dev/null 2>&1 & pid=$!; pids+=("$pid")
  sleep 1; rss1=$(rss_kb "$pid"); sleep 2; rss=$(rss_kb "$pid")
  check "$source | dynweigh-fw: ${rss1} kB after 1 s, ${rss} kB after 3 s (no growth)" \
    '[ "${rss:-0}" -gt 0 ] && [ $((rss - rss1)) -lt 1024 ] && [ "$rss" -lt 65536 ]'
  kill -TERM "$pid"
  check "$source | dynweigh-fw: SIGTERM ends it within 1 s" 'ended_within $pid 10'
done

# A line of 100,000 characters is one refused line; the next line is answered.
{ head -c 100000 /dev/zero | tr '\0' x; printf '\nstatus\n'; } | "$fw" > long.out 2>&1
check "a 100,000-character line answers ERR 2 line too long, then the next line is served" \
  '[ "$(head -n1 long.out)" = "ERR 2 line too long" ] && grep -q "^STATUS state=idle" long.out'
check "stdio answers end in LF, without CR" '! grep -q $'"'"'\r'"'"' long.out'

# SIGTERM / SIGINT while waiting for input: stdin a fifo that stays open and silent.
mkfifo idle
exec 3<> idle  # holds the fifo open: the program sees no end of input
wait_signal() {  # <signal> <description> <dynweigh-fw args...>
  local sig=$1 what=$2; shift 2
  # A background job starts with SIGINT ignored; a user's Ctrl-C reaches a program that has it.
  env --default-signal=INT "$fw" "$@" < idle > sig.out 2> sig.err & local pid=$!; pids+=("$pid")
  sleep 0.7
  kill -"$sig" "$pid"
  check "$what: SIG$sig ends it within 1 s" "ended_within $pid 10"
}
wait_signal TERM "idle stdin, in-process plant"
wait_signal INT "idle stdin, in-process plant"
wait_signal TERM "idle stdin, in-process plant, real time" --realtime
wait_signal TERM "pty console" --console pty --pty-link "$work/console"
check "the --pty-link symlink is removed at exit" '[ ! -e "$work/console" ] && [ ! -L "$work/console" ]'
port=$(python3 -c 'import socket; s=socket.socket(socket.AF_INET, socket.SOCK_DGRAM); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
wait_signal TERM "idle stdin, CAN plant (none there)" --plant "can:udp:$port@127.0.0.1:9"
exec 3>&-
exit $failed
