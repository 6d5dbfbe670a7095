#!/usr/bin/env bash
# The README's demo command: install, build, then solve the built-in box room and print
# the stats per error threshold.
set -euo pipefail
cd "$(dirname "$0")/.."
RADIOSITY_SKIP_BPY=1 bash scripts/install_deps.sh
bash scripts/build.sh
./build/bench/bench_static box_room 0.2 0.05
