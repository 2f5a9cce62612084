#!/usr/bin/env bash
# --nvm keeps parameters across runs; without it nothing persists.
set -euo pipefail
bin=$1; work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
printf 'param fall_mm 1500\n' | "$bin/dynweigh-fw" --nvm "$work/nvm.bin" | grep -q 'fall_mm=1500'
printf 'param fall_mm\n' | "$bin/dynweigh-fw" --nvm "$work/nvm.bin" | grep -q 'fall_mm=1500'
printf 'param fall_mm\n' | "$bin/dynweigh-fw" | grep -q 'fall_mm=1200'
# Two slots: damage the newest record and the previous one is still there.
printf 'param fall_mm 1600\n' | "$bin/dynweigh-fw" --nvm "$work/nvm.bin" | grep -q 'fall_mm=1600'
printf 'param fall_mm\n' | "$bin/dynweigh-fw" --nvm "$work/nvm.bin" | grep -q 'fall_mm=1600'
python3 - "$work/nvm.bin" <<'PY'
import struct, sys
path = sys.argv[1]
data = bytearray(open(path, "rb").read())
slot = 16 + struct.unpack_from("<I", data, 8)[0]  # header and record; the logbook follows the two slots
sequences = [struct.unpack_from("<I", data, offset + 4)[0] for offset in (0, slot)]
newest = 0 if sequences[0] > sequences[1] else slot
data[newest + 40] ^= 0xFF  # a bit-flipped parameter in the newest record
open(path, "wb").write(data)
PY
printf 'param fall_mm\n' | "$bin/dynweigh-fw" --nvm "$work/nvm.bin" | grep -q 'fall_mm=1500'
# A new file is as large as the docs say it is.
printf '' | "$bin/dynweigh-fw" --nvm "$work/new.bin" >/dev/null
size=$(stat -c %s "$work/new.bin")
docs="$(dirname "$0")/../../docs"
for quoted in "$(grep -o 'A new FILE is created at once ([0-9,]* bytes' "$docs/programs.md")" \
              "$(grep -o 'the file is then [0-9,]* bytes' "$docs/console.md")"; do
  said=$(printf '%s' "$quoted" | grep -o '[0-9][0-9,]*' | tr -d ,)
  if [ "$said" != "$size" ]; then
    echo "a new --nvm file has $size bytes; the docs say: '$quoted'" >&2
    exit 1
  fi
done
