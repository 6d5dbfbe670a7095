#!/usr/bin/env bash
# Builds the native tests with AddressSanitizer + UBSan (build-asan/) and runs them.
#
#   RADIOSITY_SANITIZE_FILTER  gtest filter for native_tests (default below; "*" runs all)
#   RADIOSITY_SANITIZE_JOBS    build parallelism (default: all cores)
#
# extremes_tests runs in full except the two 100k-vertex n-gon cases (a 100k-piece scene
# costs minutes and gigabytes under ASan; they run in the Release suite). native_tests runs
# filtered: its furnace over every preset and the convergence / energy / dynamic-room
# cases take minutes each in Release, far too long under ASan; the selection keeps one
# case of each code path (furnace, clustering, scale, moves, material changes, bad moves,
# replayed rays, lamp rays included), and parallel_for on TBB (exceptions, nesting, arenas).
set -euo pipefail
cd "$(dirname "$0")/.."
JOBS=${RADIOSITY_SANITIZE_JOBS:-$(nproc)}
DEFAULT_FILTER='Parallel.*:Visibility.*:AnalyticKernel.*:FrontPart.*:SolverTransport.*:AllPresets/Furnace.ClosedCubeAndRoomWithBoxAreExact/3:Solver.NoEmitterGivesZerosAndAWarning:Solver.ScaleInvariance:Solver.BackFacesNothingLightsCostNothing:Solver.UniformlyLitWallStaysOneElement:Dynamic.FurnaceConservedAfterMoves:Dynamic.BadMovesAreRejectedOrSafe:Topology.FurnaceStaysExact:Topology.BadInputIsRefused:Topology.ExtremeChangesStaySafe:Topology.AddingIntoAClosedPocketSolvesInFull:Dynamic.ReplayedRaysGiveExactlyWhatCastingEveryRayGives:Dynamic.ReplayedLampRaysGiveExactlyWhatCastingThemGives:Environment.TexturePiecesGiveElementsAndPointsTheirOwnValue:Environment.TexturePiecesGiveElementsTheirOwnEmission:FinalGather.FurnaceStaysExact:SharedGather.CornersAtTheFootOfABoxKeepTheirOwnGather:Gaps.*:ResolutionLimit.LinksAtTheLimitCarryTheirCoupling:Preview.*'
FILTER=${RADIOSITY_SANITIZE_FILTER:-$DEFAULT_FILTER}

# RelWithDebInfo: optimised enough to run in minutes, with line numbers in reports.
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRADIOSITY_SANITIZE=ON \
  -DRADIOSITY_PYTHON=OFF -DRADIOSITY_BENCH=OFF -DRADIOSITY_TESTS=ON >/dev/null
cmake --build build-asan -j"$JOBS" --target native_tests extremes_tests

# Leaks are checked too, with no suppressions: measured, neither the solver nor Embree/TBB
# report any (if a third-party leak ever shows, suppress that library only, in a file
# passed through LSAN_OPTIONS=suppressions=...).
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"

status=0
echo "== sanitize: extremes_tests (all but the 100k-vertex n-gons)"
./build-asan/tests/native/extremes_tests --gtest_brief=1 --gtest_filter='-*HundredThousand*' || status=1
echo "== sanitize: native_tests --gtest_filter=$FILTER"
./build-asan/tests/native_tests --gtest_brief=1 --gtest_filter="$FILTER" || status=1
exit $status
