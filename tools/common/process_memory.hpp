// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// This process's resident memory, for the examples and benchmarks that report it (nbs_workspace, bench_workspace,
/// bench_soak). Linux: /proc/self/status (VmRSS, VmHWM); elsewhere the peak from getrusage and no current figure.

#include <sys/resource.h>

#include <cstdint>
#include <fstream>
#include <string>

namespace nbs::tools {

/// Resident set sizes of this process, bytes (0 when unknown).
struct ProcessMemory {
  std::uint64_t rss_bytes = 0;   ///< now (VmRSS)
  std::uint64_t peak_bytes = 0;  ///< the peak so far (VmHWM; else ru_maxrss)
};

/// Reads /proc/self/status; falls back to getrusage's ru_maxrss (KiB on Linux, bytes on macOS) for the peak.
[[nodiscard]] inline ProcessMemory process_memory() {
  ProcessMemory m;
  std::ifstream in("/proc/self/status");
  std::string line;
  const auto kib = [&] { return static_cast<std::uint64_t>(std::stoull(line.substr(line.find(':') + 1))) * 1024; };
  while (std::getline(in, line)) {
    if (line.rfind("VmRSS:", 0) == 0) m.rss_bytes = kib();
    if (line.rfind("VmHWM:", 0) == 0) m.peak_bytes = kib();
  }
  if (m.peak_bytes == 0) {
    rusage u{};
#if defined(__APPLE__)
    if (getrusage(RUSAGE_SELF, &u) == 0) m.peak_bytes = static_cast<std::uint64_t>(u.ru_maxrss);  // bytes there
#else
    if (getrusage(RUSAGE_SELF, &u) == 0) m.peak_bytes = static_cast<std::uint64_t>(u.ru_maxrss) * 1024;  // KiB
#endif
  }
  return m;
}

}  // namespace nbs::tools
