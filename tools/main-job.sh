#!/usr/bin/env bash
# The main job on a fresh Debian 12: install the dependencies, build, and run one simulated dosing
# cycle (`dose 10000` in the default scene), printing its RESULT and writing cycle.csv and cycle.png.
set -euo pipefail
cd "$(dirname "$0")/.."
SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO=sudo; fi
$SUDO apt-get update
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y $(cat .ci/packages)
cmake --preset host
cmake --build --preset host
printf 'dose 10000\n' | ./build/host/dynweigh-fw --csv cycle.csv
./build/host/dynweigh plot cycle.csv -o cycle.png
awk -F, 'END { printf "true_final_kg=%s\n", $3 }' cycle.csv
