// SPDX-License-Identifier: BSD-3-Clause
// libFuzzer target for the recorded-session readers (io/session.hpp, io/pose_file.hpp): the first byte chooses
// parse_session_manifest (even) or parse_poses (odd) on the rest. Each must throw FileError or return a result that
// satisfies its documented guarantees (a manifest: relative file names, min < max, rigid poses; poses: rigid).
// Anything else — another exception, a crash, a sanitizer report, a hang — is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "nbs/io/pose_file.hpp"
#include "nbs/io/session.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    if ((data[0] & 1u) == 0) {
      const nbs::SessionManifest m = nbs::parse_session_manifest("session.json", text);
      if (!(m.scale == 1.0 || m.scale == 1e-3)) std::abort();
      if (m.info.unknown_area && (m.info.unknown_area->min.array() >= m.info.unknown_area->max.array()).any())
        std::abort();
      if (m.info.hand_eye && !nbs::pose_problem(*m.info.hand_eye).empty()) std::abort();
      for (const nbs::SessionScanEntry& e : m.scans)
        if (e.points.empty() || e.poses.empty() || e.points.front() == '/' || e.poses.front() == '/') std::abort();
    } else {
      for (const nbs::Pose& T : nbs::parse_poses("fuzz.poses", text, 1e-3))
        if (!nbs::pose_problem(T).empty()) std::abort();
    }
  } catch (const nbs::FileError&) {
  }
  return 0;
}
