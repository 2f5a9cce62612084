#!/usr/bin/env bash
# The file readers (dynweigh replay, the scene loader of dynweigh sim and dynweigh-fw, dynweigh
# plot) fed empty, binary, truncated and enormous files: each refuses with exactly one line on
# stderr naming the file and a non-zero exit that is not a signal, within a time bound, without
# reading gigabytes into memory (an address-space limit, except under AddressSanitizer).
set -uo pipefail
bin=$(cd "$1" && pwd); scenes=$(cd "$(dirname "$0")/../../scenes" && pwd); work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
seconds_allowed=${DYNWEIGH_BAD_FILE_SECONDS:-30}
memory_limit_kb=1048576  # 1 GiB of address space: far more than a refusal needs, far less than the files
if grep -q __asan_init "$bin/dynweigh"; then
  memory_limit_kb=unlimited  # ASan reserves terabytes
  seconds_allowed=${DYNWEIGH_BAD_FILE_SECONDS:-90}  # and reads 10 M lines about four times slower
fi
failures=0

refuses() {  # refuses FILE COMMAND...: the command must refuse FILE
  local file=$1; shift
  local start=$SECONDS rc
  (ulimit -v "$memory_limit_kb"; exec timeout 120 "$@" >/dev/null 2>"$work/stderr" </dev/null)
  rc=$?
  local elapsed=$((SECONDS - start)) lines
  lines=$(grep -c '' "$work/stderr")
  local why=""
  if [ "$rc" -eq 0 ]; then why="exit 0"
  elif [ "$rc" -ge 124 ]; then why="exit $rc (a signal, a timeout or out of memory)"
  elif [ "$lines" -ne 1 ]; then why="$lines lines on stderr"
  elif ! grep -qF "$(basename "$file")" "$work/stderr"; then why="the message does not name the file"
  elif [ "$elapsed" -gt "$seconds_allowed" ]; then why="took ${elapsed}s"
  fi
  if [ -n "$why" ]; then
    echo "FAIL ($why): ${*#"$bin/"}"; head -c 600 "$work/stderr"; echo
    failures=$((failures + 1))
  else
    echo "ok (${elapsed}s, exit $rc): ${*#"$bin/"} -> $(head -c 200 "$work/stderr")"
  fi
}

# The files.
cd "$work" || exit 1
yes '1,' | tr -d '\n' | head -c 200000000 >ones  # 200 MB of "1," without a line end
for ext in json csv rec; do
  : >"empty.$ext"
  head -c 3000 /dev/urandom >"random.$ext"
  head -c 3000 /dev/zero >"nul.$ext"
  truncate -s 2G "sparse.$ext"  # 2 GiB that take no disk
  ln ones "ones.$ext"
done
truncate -s 3G huge_sparse.csv
head -c 100 "$scenes/default.json" >truncated.json
printf '{"name": "x", "colum\n' >cut_in_a_key.json
printf 't_s,jiffy,static_kg,in_flight_kg,force_n,raw,filtered_g,valve\n0.00,0,0,0,0,8000,0,0\n0.01,1,0,0,0,80' >truncated.csv
{ echo 'jiffy,raw'; yes '1,8000' | head -n 12000000; } >too_many_rows.csv  # past the 10 M samples replay takes
printf 'status\n' | "$bin/dynweigh-fw" --record whole.rec >/dev/null || { echo "cannot record"; exit 1; }
head -c $(($(stat -c %s whole.rec) / 2)) whole.rec >truncated.rec
cp whole.rec damaged.rec && printf '\xff\xff\xff\xff' | dd of=damaged.rec bs=1 seek=300 conv=notrunc status=none

# dynweigh replay: captures, CSV and recordings.
for f in empty.csv random.csv nul.csv sparse.csv ones.csv huge_sparse.csv truncated.csv too_many_rows.csv \
         empty.rec random.rec nul.rec sparse.rec ones.rec truncated.rec damaged.rec; do
  refuses "$f" "$bin/dynweigh" replay "$work/$f" --quiet
done
# The scene loader, through both programs that take a scene file.
for f in empty.json random.json nul.json sparse.json ones.json truncated.json cut_in_a_key.json; do
  refuses "$f" "$bin/dynweigh" sim --scene "$work/$f" --schedule open@5,close@10 --duration 0.1
  refuses "$f" "$bin/dynweigh-fw" --plant "sim:$work/$f"
done
# dynweigh plot reads the same kinds of CSV.
for f in empty.csv random.csv sparse.csv ones.csv huge_sparse.csv; do
  refuses "$f" "$bin/dynweigh" plot "$work/$f" -o "$work/out.png"
done

[ "$failures" -eq 0 ] || { echo "$failures refusals went wrong"; exit 1; }
