#!/usr/bin/env bash
# CI smoke run of every benchmark: each with --quick, a tiny configuration that goes
# through its whole pipeline (Blender, the add-on, Cycles references, the native module, the
# report and its plots) in well under a minute. Nothing is judged but that each one finishes
# without a crash or an exception: no timing, no figure. Results go to temporary directories,
# never over bench/results/ or the cached references. Needs the build (scripts/build.sh) and
# the dependencies (scripts/install_deps.sh: matplotlib for the plots).
#   bash scripts/bench_quick.sh            (from anywhere; .ci/run calls it after the tests)
#   RADIOSITY_BUILD_DIR=build-x bash scripts/bench_quick.sh    (another build directory)
set -uo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-python3}
BUILD=${RADIOSITY_BUILD_DIR:-build}
B=$BUILD/bench
export RADIOSITY_NATIVE_DIR=$BUILD/native   # update_examples.py, add_remove_examples.py
ZIP=$BUILD/radiosity.zip
benches=(
  "$B/bench_static --quick"
  "$B/bench_gather --quick"
  "$B/bench_dynamic --quick"
  "$B/bench_light_move --quick"
  "$PY bench/update_examples.py --quick"
  "$PY bench/add_remove_examples.py --quick"
  "$PY bench/tradeoff/run_scaling.py --quick --exe $B/bench_scaling"
  "$PY bench/tradeoff/run_tradeoff.py --quick --zip $ZIP"
  "$PY bench/tradeoff/run_table2.py --quick --zip $ZIP"
  "$PY bench/live_drag.py --quick --addon-dir $BUILD/addon/stage"
  "$PY bench/interior/run_interior.py --quick --zip $ZIP"
)
passed=0
failed=()
log=$(mktemp)
for cmd in "${benches[@]}"; do
  start=$SECONDS
  echo "== $cmd"
  # Output goes to a log, shown only on failure: the benchmarks print long tables.
  if $cmd >"$log" 2>&1; then
    passed=$((passed + 1))
    echo "   ok ($((SECONDS - start)) s)"
  else
    failed+=("$cmd")
    echo "   FAILED ($((SECONDS - start)) s); its last lines:"
    tail -n 40 "$log" | sed 's/^/   | /'
  fi
done
rm -f "$log"
echo "bench: ${passed} passed, ${#failed[@]} failed"
for cmd in "${failed[@]}"; do echo "   failed: $cmd"; done
[ "${#failed[@]}" -eq 0 ]
