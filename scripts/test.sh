#!/usr/bin/env bash
# Installs what is missing, then builds and runs every test twice with -Wall -Wextra -Werror:
#   1. Release            (build/test-release)
#   2. ASan + UBSan       (build/test-asan; tests only — the examples are compiled, -Werror, in step 1)
# and finally builds a downstream project against the installed package (find_package(nbs)).
# Prints CTest's summary for each configuration and "ALL TESTS PASSED" at the end; exits non-zero on failure.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
scripts/install-deps.sh
jobs=${NBS_JOBS:-$(nproc)}

run_config() {  # name, extra cmake args...
  local name=$1; shift
  local dir=build/test-$name
  echo "=== [$name] configure + build"
  cmake -S . -B "$dir" -DNBS_WERROR=ON -DNBS_BUILD_TESTS=ON -DNBS_BUILD_EXAMPLES=ON "$@" >/dev/null
  cmake --build "$dir" -j "$jobs"
  echo "=== [$name] test"
  (cd "$dir" && ctest --output-on-failure -j "$jobs" --timeout 900)
}

run_config release -DCMAKE_BUILD_TYPE=Release -DNBS_BUILD_BENCHMARKS=ON
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  run_config asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DNBS_SANITIZE=ON -DNBS_BUILD_EXAMPLES=OFF

echo "=== [downstream] install + find_package(nbs)"
prefix=$root/build/test-install
rm -rf "$prefix"
cmake --install build/test-release --prefix "$prefix" >/dev/null
cmake -S tests/downstream -B build/test-downstream -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build/test-downstream -j "$jobs"
build/test-downstream/nbs_downstream
echo "ALL TESTS PASSED"
