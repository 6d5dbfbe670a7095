#!/usr/bin/env bash
# Checks that no function of the solver is longer than 80 lines (clang-tidy's
# readability-function-size, counting every line of the body): the sources in native/src, the
# inline functions of its headers (native/include/radiosity/*.h, native/src/*.h) and the Python
# binding (native/python/module.cpp). A long function hides the steps a reader must follow;
# split it into named parts. A function may stay longer only with a suppression on the line
# before its name that gives the reason in the same comment:
#   // NOLINTNEXTLINE(readability-function-size): <why this one reads better whole>
# A NOLINT of any kind without a reason after it is a finding too.
# Usage: scripts/check_function_size.sh [BUILD_DIR]. BUILD_DIR must hold a compile_commands.json
# of this tree that lists the binding (a build with the Python module); without one, a small
# build dir of the solver library and the module alone is configured (again) in build-tidy/
# (with $PYTHON, else python3, as the build uses). Prints each finding and exits 1 on any.
set -euo pipefail
BUILD_DIR=${1:-}
if [ -n "$BUILD_DIR" ]; then BUILD_DIR=$(cd "$BUILD_DIR" && pwd); fi
cd "$(dirname "$0")/.."
ROOT=$(pwd)
THRESHOLD=80
if [ -z "$BUILD_DIR" ]; then
  # Configured every time (a second): a source file added since lists only after a configure.
  # The module for this build's Python alone: the others compile the same module.cpp.
  BUILD_DIR=$ROOT/build-tidy
  cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DCMAKE_EXPORT_COMPILE_COMMANDS=ON \
    -DRADIOSITY_TESTS=OFF -DRADIOSITY_BENCH=OFF -DRADIOSITY_PYTHON=ON -DRADIOSITY_EXTRA_PYTHONS= \
    -DPython_EXECUTABLE="$(command -v "${PYTHON:-python3}")" >/dev/null
fi
DB=$BUILD_DIR/compile_commands.json
if [ ! -f "$DB" ]; then
  echo "no compile_commands.json in $BUILD_DIR (configure with -DCMAKE_EXPORT_COMPILE_COMMANDS=ON)" >&2
  exit 2
fi
TIDY=$(command -v clang-tidy || command -v clang-tidy-14 || true)
if [ -z "$TIDY" ]; then
  echo "clang-tidy not found (scripts/install_deps.sh installs it)" >&2
  exit 2
fi
SOURCES=(native/src/*.cpp native/python/module.cpp)
# For a file the database does not list, clang-tidy guesses flags from a listed one: a build
# dir of another tree would have it read that tree's headers. Every file must be listed.
ROOT_P=$(pwd -P)  # the path with symbolic links resolved, as CMake may have recorded it
for f in "${SOURCES[@]}"; do
  if ! grep -qF -e "\"$ROOT/$f\"" -e "\"$ROOT_P/$f\"" "$DB"; then
    echo "$DB does not list $ROOT/$f (a build dir of another tree, one without the Python module, or configure it again)" >&2
    exit 2
  fi
done

status=0
if grep -nE 'NOLINT(NEXTLINE|BEGIN|END)?(\([^)]*\))?[[:space:]:.-]*$' \
    "${SOURCES[@]}" native/src/*.h native/include/radiosity/*.h; then
  echo "a NOLINT above gives no reason after it" >&2
  status=1
fi

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# The solver's own headers (not Embree's, TBB's or pybind11's): their inline functions are
# checked in every source that includes them, and reported once below.
HEADERS='/native/(include/radiosity|src)/[^/]+\.h$'
export TIDY BUILD_DIR THRESHOLD HEADERS out
# One clang-tidy per file, two at a time, each into its own file (the report keeps the files'
# order). A file that does not compile makes clang-tidy exit non-zero: a failure too.
if ! printf '%s\n' "${SOURCES[@]}" | xargs -P2 -I{} sh -c '
    "$TIDY" -p "$BUILD_DIR" --quiet --checks="-*,readability-function-size" --header-filter="$HEADERS" \
      --config="{CheckOptions: [{key: readability-function-size.LineThreshold, value: $THRESHOLD}]}" \
      "$1" >"$out/$(basename "$1").txt" 2>"$out/$(basename "$1").err" || { cat "$out/$(basename "$1").err" >&2; exit 1; }
  ' sh {}; then
  cat "$out"/*.txt
  echo "clang-tidy failed on some file (its errors are above)" >&2
  exit 1
fi
# Each finding with the lines that follow it (source excerpt, notes), a header's once however
# many sources include it.
report=$(cat "$out"/*.txt | awk '
  / warning: / { keep = !seen[$0]++ }
  keep')
if [ -n "$report" ]; then printf '%s\n' "$report"; fi
findings=$(printf '%s\n' "$report" | grep -c 'warning: .*\[readability-function-size\]' || true)
if [ "$findings" != 0 ]; then
  echo "$findings function(s) over $THRESHOLD lines in the solver: split them, or suppress with a reason"
  status=1
else
  echo "function size: no function of the solver (native/src, its headers, the binding) over $THRESHOLD lines"
fi
exit $status
