#!/usr/bin/env bash
# Builds the libFuzzer target fuzz/fuzz_scene.cpp with clang (ASan + UBSan, build-fuzz/) and
# runs it for a bounded time.
#
#   RADIOSITY_FUZZ_SECONDS  total fuzzing time (default 60)
#   RADIOSITY_FUZZ_JOBS     build parallelism (default: all cores)
#
# A finding (crash, sanitizer report, non-finite output, a run over 20 s, over 2 GB) stops
# the run and leaves the input in build-fuzz/artifacts/; reproduce it with
#   ./build-fuzz/fuzz/fuzz_scene build-fuzz/artifacts/<file>
# and turn it into a regression test in tests/native/test_extremes.cpp.
set -euo pipefail
cd "$(dirname "$0")/.."
# A fixed seed (RADIOSITY_FUZZ_SEED) keeps CI reproducible; findings become seeds in
# fuzz/seeds/ (run first every time) and regression tests in tests/native/test_extremes.cpp.
SECONDS_TOTAL=${RADIOSITY_FUZZ_SECONDS:-60}
JOBS=${RADIOSITY_FUZZ_JOBS:-$(nproc)}
CXX_BIN=${RADIOSITY_FUZZ_CXX:-clang++}
if ! command -v "$CXX_BIN" >/dev/null; then
  echo "fuzz.sh: $CXX_BIN not found (scripts/install_deps.sh installs clang)" >&2
  exit 1
fi

cmake -S . -B build-fuzz -DCMAKE_CXX_COMPILER="$CXX_BIN" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DRADIOSITY_FUZZ=ON -DRADIOSITY_TESTS=OFF -DRADIOSITY_PYTHON=OFF -DRADIOSITY_BENCH=OFF >/dev/null
cmake --build build-fuzz -j"$JOBS" --target fuzz_scene

# The corpus grows across local runs (build-fuzz/ is not in git); CI starts from the seeds.
mkdir -p build-fuzz/corpus build-fuzz/artifacts
# Leaks are findings too (no suppressions needed: neither we nor Embree/TBB leak).
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
echo "== fuzz: fuzz_scene for ${SECONDS_TOTAL} s"
./build-fuzz/fuzz/fuzz_scene build-fuzz/corpus fuzz/seeds \
  -max_total_time="$SECONDS_TOTAL" -timeout=20 -rss_limit_mb=2048 -max_len=2048 \
  -seed="${RADIOSITY_FUZZ_SEED:-1}" \
  -artifact_prefix=build-fuzz/artifacts/ -print_final_stats=1
