#!/usr/bin/env bash
# Installs everything the build, the tests and the demo need on a fresh Debian 12 machine
# (Debian packages and PyPI only). Safe to run again.
set -euo pipefail
SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO=sudo; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends \
  cmake g++ make libembree-dev libtbb-dev libgtest-dev googletest python3-dev python3-numpy python3-pip \
  libbenchmark-dev \
  blender xvfb \
  clang-tidy \
  clang libclang-rt-dev  # scripts/fuzz.sh: clang and its libFuzzer/sanitizer runtimes
PY=${PYTHON:-python3}
# Debian's own python3 is "externally managed" (PEP 668): pip refuses to install into it unless
# told to. A fresh machine has only that interpreter, so allow it there (a venv or pyenv
# interpreter is not externally managed and is left alone). Debian's python3-numpy (above) is
# kept: Debian's Blender 3.4 runs on the same interpreter and was built against numpy 1.x
# (the bpy wheel below may lift it to a later 1.x, numpy<2 by its own requirement).
if "$PY" -c 'import sys, sysconfig, os; sys.exit(0 if os.path.exists(os.path.join(sysconfig.get_path("stdlib"), "EXTERNALLY-MANAGED")) else 1)'; then
  export PIP_BREAK_SYSTEM_PACKAGES=1
fi
NUMPY=numpy
if "$PY" -c 'import numpy' 2>/dev/null; then NUMPY=""; fi
# pybind11 >= 2.12 supports numpy 1.x (Debian's Blender) and 2.x (bpy wheels) at run time, and
# >= 2.13 Python 3.13 (the second solver module, for Blender 5.1+).
# matplotlib: the benchmark reports' plots (bench/tradeoff/report_tradeoff.py, run_scaling.py),
# which run in this Python, not in Blender's.
$PY -m pip install -q "pybind11>=2.13" "pytest>=7" $NUMPY matplotlib
if [ "${RADIOSITY_SKIP_BPY:-0}" != 1 ]; then
  # Blender as a Python module: the newest wheel for this Python (cp311: 4.5/5.0).
  $PY -m pip install -q bpy || echo "warning: pip could not install bpy; the bpy flavour of the add-on tests will be skipped"
fi
# Blender 5.1 and later embed CPython 3.13: the build makes a second solver module with its
# headers (native/python/extra_pythons.cmake) and the module313 flavour of the add-on tests runs
# bpy 5.2 (LTS, cp313 wheels only) in it. Debian 12 has no 3.13 package; the project's machine
# image has one in pyenv, which scripts/find_python.sh finds (or name one in $PYTHON313).
if PY313=$(bash "$(dirname "$0")/find_python.sh" 3.13); then
  if [ "${RADIOSITY_SKIP_BPY:-0}" != 1 ]; then
    "$PY313" -m pip install -q "bpy==${RADIOSITY_BPY313_VERSION:-5.2.3}" \
      || echo "warning: pip could not install bpy for $PY313; the module313 flavour of the add-on tests will be skipped"
  fi
else
  echo "warning: no CPython 3.13 (PATH, pyenv or \$PYTHON313): the add-on zip will not load in" \
       "Blender 5.1 and later, and the module313 flavour of the add-on tests will be skipped." \
       "Install a CPython 3.13 with its headers (e.g. pyenv install 3.13) and run this again."
fi
