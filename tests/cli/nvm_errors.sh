#!/usr/bin/env bash
# --nvm storage errors are loud: a path that cannot keep settings is refused in one line with a
# non-zero exit; a corrupt, truncated or empty file starts from defaults with a warning (and is
# rewritten whole); --nvm-reset starts from defaults without one; a write that fails while running
# raises the fault nvm_error instead of answering OK.
set -uo pipefail
bin=$1; work=$(mktemp -d); fw_pid=""
cleanup() {
  [ -n "$fw_pid" ] && kill "$fw_pid" 2>/dev/null
  chmod -R u+w "$work" 2>/dev/null; rm -rf "$work"
}
trap cleanup EXIT
cd "$work"
fw="$bin/dynweigh-fw"
failed=0
check() { if eval "$2"; then echo "ok: $1"; else echo "FAIL: $1"; failed=1; fi; }

# A bad path: refused with one line on stderr, non-zero exit, before any command runs.
refused() {  # <what> <path>
  printf 'status\n' | "$fw" --nvm "$2" > out.txt 2> err.txt; local status=$?
  echo "  $1: status $status, stderr: $(cat err.txt)"
  check "$1 refused" '[ $status -ne 0 ] && [ "$(wc -l < err.txt)" -eq 1 ] && grep -q -- "--nvm" err.txt && [ ! -s out.txt ]'
}
refused "a missing folder" "$work/no/such/folder/scale.nvm"
mkdir adir; refused "a directory" "$work/adir"
refused "a character device" /dev/null
if [ "$(id -u)" -ne 0 ]; then  # root writes where it likes
  mkdir locked; chmod a-w locked; refused "a folder without write permission" "$work/locked/scale.nvm"
  printf 'param fall_mm 1500\n' | "$fw" --nvm ro.nvm > /dev/null; chmod a-w ro.nvm
  refused "a read-only file" "$work/ro.nvm"
fi

# Damaged files: a warning, defaults, and the file works again afterwards.
damaged() {  # <what> <file>
  printf 'param fall_mm\n' | "$fw" --nvm "$2" > out.txt 2> err.txt; local status=$?
  echo "  $1: status $status, stderr: $(cat err.txt)"
  check "$1 starts from defaults with a warning" \
    '[ $status -eq 0 ] && grep -qx "fall_mm=1200" out.txt && grep -q "warning: --nvm .*holds no intact settings record" err.txt'
  printf 'param fall_mm 1500\n' | "$fw" --nvm "$2" > /dev/null 2> err2.txt
  printf 'param fall_mm\n' | "$fw" --nvm "$2" > out.txt 2> err3.txt
  check "$1 keeps settings again, without a warning" 'grep -qx "fall_mm=1500" out.txt && [ ! -s err2.txt ] && [ ! -s err3.txt ]'
}
head -c 672 /dev/urandom > corrupt.nvm; damaged "a corrupt file" corrupt.nvm
: > empty.nvm; damaged "an empty file" empty.nvm
printf 'param fall_mm 1400\n' | "$fw" --nvm cut.nvm > /dev/null; truncate -s 100 cut.nvm
damaged "a truncated file" cut.nvm

# A file cut inside its second slot still holds the first (here the older record: the start-up
# defaults, before fall_mm 1400 went to the second slot): used, with a warning that it is short.
# The slot's size from its header (16 bytes and the record's length at byte 8): the logbook follows them.
printf 'param fall_mm 1400\n' | "$fw" --nvm short.nvm > /dev/null
slot=$(( 16 + $(od -An -tu4 -j8 -N4 short.nvm) )); truncate -s $(( slot + slot / 2 )) short.nvm
printf 'param fall_mm\n' | "$fw" --nvm short.nvm > out.txt 2> err.txt
check "a truncated file with one intact slot: its record, with a warning" \
  'grep -qx "fall_mm=1200" out.txt && grep -q "warning: --nvm short.nvm is [0-9]* bytes, not [0-9]* (truncated)" err.txt'

# --nvm-reset: defaults, no warning.
printf 'param fall_mm\n' | "$fw" --nvm corrupt.nvm --nvm-reset > out.txt 2> err.txt
check "--nvm-reset starts from defaults quietly" 'grep -qx "fall_mm=1200" out.txt && [ ! -s err.txt ]'

# A write that fails at run time (the file replaced by a directory: root cannot write it either).
mkfifo commands
"$fw" --nvm run.nvm < commands > run.out 2> run.err & fw_pid=$!
exec 3> commands
printf 'param fall_mm 1500\n' >&3
for _ in $(seq 100); do grep -q '^OK' run.out && break; sleep 0.05; done
rm run.nvm; mkdir run.nvm
printf 'param fall_mm 1600\nstatus\nparam fall_mm\n' >&3
exec 3>&-
wait "$fw_pid"; status=$?; fw_pid=""
echo "  run time:"; sed 's/^/    /' run.out
check "the first change is saved: OK" '[ "$(sed -n 2p run.out)" = OK ]'
check "a change that cannot be saved answers ERR 4 fault nvm_error, not OK" \
  '[ "$(sed -n 4p run.out)" = "ERR 4 fault nvm_error" ]'
check "status shows the fault" 'grep -q "^STATUS state=fault .*fault=nvm_error" run.out'
check "the program still ends 0 at end of input" '[ $status -eq 0 ]'
exit $failed
