#pragma once
/// \file
/// Protocol between benchmark executables and scripts/bench.sh.
///
/// Every benchmark executable runs its Google Benchmark cases side by side with the incumbent (OctoMap, a raw
/// Embree loop, nanoflann) in the same process, then calls `report_headline("area.figure", value)` for each
/// headline figure (usually a ratio nbs ÷ incumbent). scripts/bench.sh collects the lines `HEADLINE name: value`
/// from stdout, prints them as `name: value` and writes the table to docs/performance.md.
/// `quick_mode()` is true when bench.sh runs with --quick (environment NBS_BENCH_QUICK=1): use fewer repetitions.

#include <cstdio>
#include <cstdlib>
#include <string_view>

namespace nbs::bench {

inline bool quick_mode() {
  const char* q = std::getenv("NBS_BENCH_QUICK");
  return q != nullptr && std::string_view(q) == "1";
}

/// Prints `HEADLINE <name>: <value>` on a line of its own (flushes immediately).
inline void report_headline(std::string_view name, double value, std::string_view note = {}) {
  std::printf("HEADLINE %.*s: %.4g", static_cast<int>(name.size()), name.data(), value);
  if (!note.empty()) std::printf("  (%.*s)", static_cast<int>(note.size()), note.data());
  std::printf("\n");
  std::fflush(stdout);
}

}  // namespace nbs::bench
