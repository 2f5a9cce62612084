#!/usr/bin/env bash
# The main job on a fresh Debian 12: install the dependencies, build, and run one simulated dosing
# cycle (`dose 10000` in the default scene), printing its RESULT and writing cycle.csv and cycle.png.
# `--batch`: instead, a batch of three materials (sand, barley, flour) into one hopper on the batching
# scene (the recipe of docs/console.md, tested by tests/cli/batch_recipe.sh), writing batch.csv and
# batch.png. `--no-install`: skip apt-get on a machine that has the packages.
set -euo pipefail
cd "$(dirname "$0")/.."
batch=0; install=1
for arg in "$@"; do
  case "$arg" in
    --batch) batch=1 ;;
    --no-install) install=0 ;;
    *) echo "main-job.sh: unknown option '$arg' (expected --batch, --no-install)" >&2; exit 2 ;;
  esac
done
if [ "$install" = 1 ]; then
  SUDO=""
  if [ "$(id -u)" != 0 ]; then SUDO=sudo; fi
  $SUDO apt-get update
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y $(cat .ci/packages)
fi
cmake --preset host
cmake --build --preset host
if [ "$batch" = 1 ]; then
  printf 'material 0 name sand\nmaterial 1 name barley\nmaterial 1 density 700\nmaterial 2 name flour\nmaterial 2 density 500\nbatch 0:10000 1:5000 2:4000\n' |
    ./build/host/dynweigh-fw --plant sim:batching --csv batch.csv
  ./build/host/dynweigh plot batch.csv -o batch.png
  awk -F, 'END { printf "true_final_kg=%s\n", $3 }' batch.csv
  exit 0
fi
printf 'dose 10000\n' | ./build/host/dynweigh-fw --csv cycle.csv
./build/host/dynweigh plot cycle.csv -o cycle.png
awk -F, 'END { printf "true_final_kg=%s\n", $3 }' cycle.csv
