// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Scan path length l_s (Sec. 4.7.2, Tab. 4.5): the summed length of the executed linear scan paths.

#include <span>

#include "nbs/core/scan_path.hpp"

namespace nbs {

/// l_s = Σ |s_p^2 − s_p^1| over the executed paths, metres (the thesis measure; travel between paths excluded).
[[nodiscard]] inline double scan_path_length(std::span<const LinearScanPath> paths) {
  double l = 0.0;
  for (const auto& p : paths) l += p.length();
  return l;
}

/// Straight-line travel between consecutive paths, Σ |start(i+1) − end(i)|, metres. Not part of l_s; a lower bound
/// of the robot's repositioning motion (reported separately).
[[nodiscard]] inline double travel_length(std::span<const LinearScanPath> paths) {
  double l = 0.0;
  for (std::size_t i = 1; i < paths.size(); ++i) l += (paths[i].start().position() - paths[i - 1].end_position()).norm();
  return l;
}

}  // namespace nbs
