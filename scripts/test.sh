#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Installs what is missing, then builds and runs the tests with -Wall -Wextra -Werror:
#   1. Release                           (build/test-release: every test and the examples; the benchmarks and the
#                                         research tool nbs_diagnose are built by scripts/bench.sh, with -Werror)
#   2. ASan + UBSan + float-cast-overflow (build/test-asan-clang; every test — the examples are compiled in step 1)
#   3. ThreadSanitizer                   (build/test-tsan; only the tests that run threads, tsan_tests below)
# Steps 1 and 2 are unity builds (CMAKE_UNITY_BUILD: the sources of one test executable compiled as one unit, so the
# library's templates are instantiated and compiled once per executable, not once per file); step 3 builds each
# file on its own, which also checks that the test files of those executables include what they use.
# then checks the installed package (scripts/test-package.sh: relocatable, find_package COMPONENTS with every
# adapter, errors for missing ones, pkg-config) and finally runs each libFuzzer target for 15 s
# (scripts/fuzz.sh --quick, clang), and generates the API reference (scripts/docs.sh: Doxygen, no warnings).
# Chromium (install-deps --with-browser) and three.js (scripts/install-viewer.sh) are for viewer.browser, the
# session viewer of nbs_model --viewer in headless Chromium (tests/viewer).
# Prints CTest's summary for each configuration and "ALL TESTS PASSED" at the end; exits non-zero on failure.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
scripts/install-deps.sh --with-browser --with-fuzz
scripts/install-viewer.sh || echo "test: three.js not installed; viewer.browser will be skipped" >&2
jobs=${NBS_JOBS:-$(nproc)}

# The tests that run threads (parallel candidate evaluation, parallel ray casts, flushing, the planner loop).
# planner_bunny is left out: Embree builds its scene on TBB threads that TSan cannot see (uninstrumented), and
# TSan reports a race inside SimulatedScanner construction that is not ours.
tsan_tests=(space utility_terms candidate_generators sim planner)

run_config() {  # name, "target..." ("" = all), ctest regex ("" = all), extra cmake args...
  local name=$1 targets=$2 regex=$3; shift 3
  local dir=build/test-$name start=$SECONDS
  echo "=== [$name] configure + build"
  cmake -S . -B "$dir" -DNBS_WERROR=ON -DNBS_BUILD_TESTS=ON -DNBS_BUILD_EXAMPLES=ON "$@" >/dev/null
  if [[ -z $targets ]]; then cmake --build "$dir" -j "$jobs"; else cmake --build "$dir" -j "$jobs" --target $targets; fi
  echo "=== [$name] test"
  (cd "$dir" && ctest --output-on-failure -j "$jobs" --timeout 900 ${regex:+-R "$regex"})
  echo "=== [$name] took $((SECONDS - start)) s"
}
phase() {  # name, command...: runs the command and prints how long it took
  local name=$1 start=$SECONDS; shift
  "$@"
  echo "=== [$name] took $((SECONDS - start)) s"
}

# The ASan build uses clang (summed target time of its build about a third of gcc's, the CI's ASan step about
# half: the CI's time is compile time; the code is also built -Werror by two compilers), at -O0 -g1 (file:line
# stacks), except the tests that run long (tests/CMakeLists.txt NBS_SLOW_TESTS: -O1, Eigen unoptimised is ~8×
# slower). Its folder names the compiler:
# CMake drops a cache whose compiler changes, with every option in it. Release and TSan use the default c++ (gcc
# on Debian); TSan keeps -O1 (it builds only five executables).
asan_flags="-O0 -g1 -DNDEBUG" tsan_flags="-O1 -g1 -DNDEBUG"
run_config release "" "" -DCMAKE_BUILD_TYPE=Release -DCMAKE_UNITY_BUILD=ON
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  run_config asan-clang "" "" -DCMAKE_BUILD_TYPE=None -DCMAKE_CXX_FLAGS="$asan_flags" -DNBS_SANITIZE=ON -DNBS_BUILD_EXAMPLES=OFF \
  -DCMAKE_UNITY_BUILD=ON -DNBS_SLOW_TEST_FLAGS=-O1 -DCMAKE_CXX_COMPILER=clang++
TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1 \
  run_config tsan "${tsan_tests[*]/#/test_}" "^($(IFS='|'; echo "${tsan_tests[*]}"))\$" \
  -DCMAKE_BUILD_TYPE=None -DCMAKE_CXX_FLAGS="$tsan_flags" -DNBS_SANITIZE_THREAD=ON -DNBS_BUILD_EXAMPLES=OFF

echo "=== [package] install, relocate, find_package(nbs COMPONENTS ...), pkg-config"
phase package scripts/test-package.sh build/test-release "$jobs"

echo "=== [fuzz] libFuzzer, 15 s per target (scripts/fuzz.sh --quick)"
phase fuzz scripts/fuzz.sh --quick --jobs "$jobs"

echo "=== [docs] API reference (scripts/docs.sh: Doxygen over every public header, no warnings)"
phase docs scripts/docs.sh
echo "ALL TESTS PASSED in $SECONDS s"
