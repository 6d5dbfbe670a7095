#!/usr/bin/env bash
# Configures and builds everything (solver, module, add-on zip, tests, benchmarks) in build/.
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-python3}
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPython_EXECUTABLE="$(command -v "$PY")"
cmake --build build -j"$(nproc)"
