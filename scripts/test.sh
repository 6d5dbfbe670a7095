#!/usr/bin/env bash
# The README's test command: install, build, run every test (native, module, add-on core,
# add-on in real Blender 3.4 and in the PyPI bpy module), then the native tests under
# ASan+UBSan (scripts/sanitize.sh) and a bounded fuzzing run (scripts/fuzz.sh).
# Skip those locally with RADIOSITY_SKIP_SANITIZE=1 / RADIOSITY_SKIP_FUZZ=1.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
# No session or issue numbers, no cited paths that do not exist (comments say what and why).
python3 scripts/check_comments.py
# No function in addon/ over 80 lines (a longer one says why above its def).
python3 scripts/check_python_size.py
# No function of the solver (native/src, its headers, the Python binding) over 80 lines
# (clang-tidy; a longer one says why it stays whole).
bash scripts/check_function_size.sh
bash scripts/build.sh
PY=${PYTHON:-python3}
(cd build && ctest --output-on-failure -j2)
dirs=()
for d in tests/python tests/addon_core tests/blender; do [ -d "$d" ] && dirs+=("$d"); done
$PY -m pytest -q "${dirs[@]}"
if [ "${RADIOSITY_SKIP_SANITIZE:-0}" != 1 ]; then
  bash scripts/sanitize.sh
fi
if [ "${RADIOSITY_SKIP_FUZZ:-0}" != 1 ]; then
  RADIOSITY_FUZZ_SECONDS=${RADIOSITY_FUZZ_SECONDS:-60} bash scripts/fuzz.sh
fi
