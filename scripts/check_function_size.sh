#!/usr/bin/env bash
# Checks that no function in native/src is longer than 80 lines (clang-tidy's
# readability-function-size, counting every line of the body). A long function hides the steps a
# reader must follow; split it into named parts. A function may stay longer only with a
# suppression on the line before its name that gives the reason in the same comment:
#   // NOLINTNEXTLINE(readability-function-size): <why this one reads better whole>
# A NOLINT of any kind without a reason after it is a finding too.
# Usage: scripts/check_function_size.sh [BUILD_DIR]. BUILD_DIR must hold a compile_commands.json
# of this tree; without one, a small build dir of the solver library alone is configured (again)
# in build-tidy/. Prints each finding and exits 1 on any.
set -euo pipefail
BUILD_DIR=${1:-}
if [ -n "$BUILD_DIR" ]; then BUILD_DIR=$(cd "$BUILD_DIR" && pwd); fi
cd "$(dirname "$0")/.."
ROOT=$(pwd)
THRESHOLD=80
if [ -z "$BUILD_DIR" ]; then
  # Configured every time (a second): a source file added since lists only after a configure.
  BUILD_DIR=$ROOT/build-tidy
  cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DCMAKE_EXPORT_COMPILE_COMMANDS=ON \
    -DRADIOSITY_TESTS=OFF -DRADIOSITY_BENCH=OFF -DRADIOSITY_PYTHON=OFF >/dev/null
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
# For a file the database does not list, clang-tidy guesses flags from a listed one: a build
# dir of another tree would have it read that tree's headers. Every file must be listed.
ROOT_P=$(pwd -P)  # the path with symbolic links resolved, as CMake may have recorded it
for f in native/src/*.cpp; do
  if ! grep -qF -e "\"$ROOT/$f\"" -e "\"$ROOT_P/$f\"" "$DB"; then
    echo "$DB does not list $ROOT/$f (a build dir of another tree, or configure it again)" >&2
    exit 2
  fi
done

status=0
if grep -nE 'NOLINT(NEXTLINE|BEGIN|END)?(\([^)]*\))?[[:space:]:.-]*$' native/src/*.cpp native/src/*.h; then
  echo "a NOLINT above gives no reason after it" >&2
  status=1
fi

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
export TIDY BUILD_DIR THRESHOLD out
# One clang-tidy per file, two at a time, each into its own file (the report keeps the files'
# order). A file that does not compile makes clang-tidy exit non-zero: a failure too.
if ! printf '%s\n' native/src/*.cpp | xargs -P2 -I{} sh -c '
    "$TIDY" -p "$BUILD_DIR" --quiet --checks="-*,readability-function-size" \
      --config="{CheckOptions: [{key: readability-function-size.LineThreshold, value: $THRESHOLD}]}" \
      "$1" >"$out/$(basename "$1").txt" 2>"$out/$(basename "$1").err" || { cat "$out/$(basename "$1").err" >&2; exit 1; }
  ' sh {}; then
  cat "$out"/*.txt
  echo "clang-tidy failed on some file (its errors are above)" >&2
  exit 1
fi
cat "$out"/*.txt
findings=$(cat "$out"/*.txt | grep -c 'warning: .*\[readability-function-size\]' || true)
if [ "$findings" != 0 ]; then
  echo "$findings function(s) over $THRESHOLD lines in native/src: split them, or suppress with a reason"
  status=1
else
  echo "function size: no function in native/src over $THRESHOLD lines"
fi
exit $status
