#!/usr/bin/env bash
# --nvm keeps parameters across runs; without it nothing persists.
set -euo pipefail
bin=$1; work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
printf 'param fall_mm 1500\n' | "$bin/dynweigh-fw" --nvm "$work/nvm.bin" | grep -q 'fall_mm=1500'
printf 'param fall_mm\n' | "$bin/dynweigh-fw" --nvm "$work/nvm.bin" | grep -q 'fall_mm=1500'
printf 'param fall_mm\n' | "$bin/dynweigh-fw" | grep -q 'fall_mm=1200'
