#!/usr/bin/env bash
# The README's test command: install, build, run every test (native, module, add-on core,
# add-on in real Blender 3.4 and in the PyPI bpy module).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh
PY=${PYTHON:-python3}
(cd build && ctest --output-on-failure -j2)
dirs=()
for d in tests/python tests/addon_core tests/blender; do [ -d "$d" ] && dirs+=("$d"); done
$PY -m pytest -q "${dirs[@]}"
