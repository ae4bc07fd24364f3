// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Protocol between benchmark executables and scripts/bench.sh.
///
/// Every benchmark executable runs its Google Benchmark cases side by side with the incumbent (OctoMap, a raw
/// Embree loop, nanoflann) in the same process, then calls `report_headline("area.figure", value)` for each
/// headline figure (usually a ratio nbs ÷ incumbent). scripts/bench.sh collects the lines `HEADLINE name: value`
/// from stdout, prints them as `name: value` and writes the table to docs/performance.md.
/// `quick_mode()` is true when bench.sh runs with --quick (environment NBS_BENCH_QUICK=1): use fewer repetitions.
/// `best_times` is the side-by-side timing the headline ratios use; `machine_2thread_scaling` is the reference for
/// two-thread scaling figures.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <string_view>
#include <thread>
#include <vector>

namespace nbs::bench {

inline bool quick_mode() {
  const char* q = std::getenv("NBS_BENCH_QUICK");
  return q != nullptr && std::string_view(q) == "1";
}

/// The number in the environment variable `name` (a development knob of a benchmark), `fallback` if it is unset.
/// Exits the benchmark with status 2 and a message naming the variable and its text if that is not a number in
/// [lo, hi] (an integer if `integer`).
inline double env_number(const char* name, double fallback, double lo, double hi, bool integer = false) {
  const char* text = std::getenv(name);
  if (text == nullptr) return fallback;
  char* end = nullptr;
  const double v = std::strtod(text, &end);
  const bool in_range = v >= lo && v <= hi;  // false for NaN; guards the integer cast below
  const bool whole = !integer || (in_range && v == static_cast<double>(static_cast<long long>(v)));
  if (end == text || *end != '\0' || !in_range || !whole) {
    std::fprintf(stderr, "%s must be %s in [%g, %g], got '%s'\n", name, integer ? "an integer" : "a number", lo, hi,
                 text);
    std::exit(2);
  }
  return v;
}

/// Prints `HEADLINE <name>: <value>` on a line of its own (flushes immediately).
inline void report_headline(std::string_view name, double value, std::string_view note = {}) {
  std::printf("HEADLINE %.*s: %.4g", static_cast<int>(name.size()), name.data(), value);
  if (!note.empty()) std::printf("  (%.*s)", static_cast<int>(note.size()), note.data());
  std::printf("\n");
  std::fflush(stdout);
}

/// Median of `v` (the mean of the two middle values for an even count); 0 for an empty vector.
inline double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Wall-clock seconds of one call of fn (steady clock).
inline double seconds(const std::function<void()>& fn) {
  const auto t0 = std::chrono::steady_clock::now();
  fn();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Best (smallest) time of each of `fns` over `reps` rounds; within a round the candidates run in turn, so a
/// change in machine load affects them alike.
inline std::vector<double> best_times(int reps, const std::vector<std::function<void()>>& fns) {
  std::vector<double> best(fns.size(), 1e300);
  for (int r = 0; r < reps; ++r)
    for (std::size_t i = 0; i < fns.size(); ++i) best[i] = std::min(best[i], seconds(fns[i]));
  return best;
}

/// The machine's own two-thread speed-up for throughput-bound code: eight independent integer multiply–add chains
/// per thread (no memory traffic), 2·10^8 iterations split over 1 and over 2 std::threads, best of `reps` rounds
/// each, interleaved. Shared or hyper-threaded virtual cores give less than 2 here; parallel benchmarks report
/// their scaling next to this ceiling.
inline double machine_2thread_scaling(int reps) {
  const auto run = [](unsigned threads) {
    constexpr std::uint64_t kIterations = 200'000'000;
    std::vector<std::uint64_t> out(8 * threads);  // one cache line per thread
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < threads; ++t)
      pool.emplace_back([&out, t, threads] {
        std::uint64_t c[8] = {1 + t, 2, 3, 4, 5, 6, 7, 8};
        for (std::uint64_t i = 0; i < kIterations / threads; ++i)
          for (int k = 0; k < 8; ++k) c[k] = c[k] * (2 * k + 3) + i;
        std::uint64_t x = 0;
        for (std::uint64_t v : c) x ^= v;
        out[8 * t] = x;
      });
    for (auto& th : pool) th.join();
    std::uint64_t x = 0;
    for (std::uint64_t v : out) x ^= v;
    volatile std::uint64_t sink = x;
    (void)sink;
  };
  const auto t = best_times(reps, {[&] { run(1); }, [&] { run(2); }});
  return t[0] / t[1];
}

}  // namespace nbs::bench
