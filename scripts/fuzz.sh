#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Builds the libFuzzer targets of tests/fuzz with clang (ASan + UBSan incl. float-cast-overflow) and runs each one.
# Usage: scripts/fuzz.sh [--quick] [--time S] [--runs N] [--target fuzz_ply|fuzz_obj|fuzz_pcd|fuzz_session|fuzz_scan_ingestion] [--jobs J]
#   --quick   15 s per target (what scripts/test.sh runs)
#   --time S  S seconds per target (default 300)
#   --runs N  stop each target after N executions instead (e.g. 10000000 for a campaign)
# The repository's seed corpus (tests/fuzz/corpus/<kind>) is copied into build/fuzz/corpus-<target>, which keeps
# what libFuzzer finds between runs; the repository is never written. A finding (crash, sanitizer report, timeout
# > 10 s, > 2 GiB) leaves its input in build/fuzz/findings/ and makes the script exit non-zero.
# Prints per target "fuzz_<target>_execs: N", "fuzz_<target>_exec_per_s: R" and "fuzz_<target>_findings: 0|1".
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
seconds=300 runs="" targets=(fuzz_ply fuzz_obj fuzz_pcd fuzz_session fuzz_scan_ingestion) jobs=${NBS_JOBS:-$(nproc)}
while (($#)); do
  case $1 in
    --quick) seconds=15 ;;
    --time) seconds=$2; shift ;;
    --runs) runs=$2; shift ;;
    --target) targets=("$2"); shift ;;
    --jobs) jobs=$2; shift ;;
    *) echo "fuzz.sh: unknown argument '$1' (see the header of scripts/fuzz.sh)" >&2; exit 2 ;;
  esac
  shift
done
[[ $seconds =~ ^[0-9]+$ && $seconds -gt 0 ]] || { echo "fuzz.sh: --time needs a positive integer, got '$seconds'" >&2; exit 2; }
[[ -z $runs || $runs =~ ^[0-9]+$ ]] || { echo "fuzz.sh: --runs needs a positive integer, got '$runs'" >&2; exit 2; }
scripts/install-deps.sh --with-fuzz

build=build/fuzz
cmake -S tests/fuzz -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=None >/dev/null
cmake --build "$build" -j "$jobs" --target "${targets[@]}"
mkdir -p "$build/findings"
status=0
for t in "${targets[@]}"; do
  kind=${t#fuzz_}; kind=${kind%_ingestion}
  corpus=$build/corpus-$t
  mkdir -p "$corpus"
  opts=(); [[ -f tests/fuzz/$kind.dict ]] && opts=(-dict="tests/fuzz/$kind.dict")
  # The planner target is large: libFuzzer's entropic schedule spent half its time in its feature bookkeeping
  # (UpdateFeatureFrequency); the plain schedule ran 1.7x as many inputs and found more coverage in the same time.
  [[ $t == fuzz_scan_ingestion ]] && opts+=(-entropic=0)
  limit=(-max_total_time="$seconds"); [[ -n $runs ]] && limit=(-runs="$runs")
  log=$build/$t.log
  if [[ -n $runs ]]; then label="$runs runs"; else label="$seconds s"; fi
  echo "=== [fuzz] $t ($label)"
  if ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
     "$build/$t" "$corpus" "tests/fuzz/corpus/$kind" "${opts[@]}" "${limit[@]}" -max_len=8192 -timeout=10 \
       -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$build/findings/$t-" >"$log" 2>&1; then
    found=0
  else
    found=1; status=1
    echo "fuzz.sh: $t found a problem; its input is in $build/findings/, the log is $log:" >&2
    grep -E "ERROR|SUMMARY|runtime error|terminate|Test unit written" "$log" | head -20 >&2 || true
  fi
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  echo "${t}_execs: ${execs:-0}"
  echo "${t}_exec_per_s: ${rate:-0}"
  echo "${t}_findings: $found"
done
exit $status
