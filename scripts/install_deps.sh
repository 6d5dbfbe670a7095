#!/usr/bin/env bash
# Installs everything the build, the tests and the demo need on a fresh Debian 12 machine
# (Debian packages and PyPI only). Safe to run again.
set -euo pipefail
SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO=sudo; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends \
  cmake g++ make libembree-dev libgtest-dev googletest python3-dev python3-numpy python3-pip \
  blender xvfb \
  clang libclang-rt-dev  # scripts/fuzz.sh: clang and its libFuzzer/sanitizer runtimes
PY=${PYTHON:-python3}
# pybind11 >= 2.12 supports numpy 1.x (Debian's Blender) and 2.x (bpy wheels) at run time.
# matplotlib: the benchmark reports' plots (bench/tradeoff/report_tradeoff.py, run_scaling.py),
# which run in this Python, not in Blender's.
$PY -m pip install -q "pybind11>=2.12" "pytest>=7" numpy matplotlib
if [ "${RADIOSITY_SKIP_BPY:-0}" != 1 ]; then
  # Blender as a Python module: the newest wheel for this Python (cp311: 4.5/5.0).
  $PY -m pip install -q bpy || echo "warning: pip could not install bpy; the bpy flavour of the add-on tests will be skipped"
fi
