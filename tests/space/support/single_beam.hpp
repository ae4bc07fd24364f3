// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Scans made of a few hand-placed beams.
#include <initializer_list>
#include <utility>

#include "nbs/core/scan.hpp"

namespace nbs::test {

// One profile per beam (origin, end point), world metres.
inline Scan beams_scan(std::initializer_list<std::pair<Vec3, Vec3>> beams) {
  Scan s;
  for (const auto& [o, p] : beams) {
    Pose pose = Pose::Identity();
    pose.translation() = o;
    s.profile_poses.push_back(pose);
    s.add_point(p, static_cast<std::uint32_t>(s.profile_poses.size() - 1));
  }
  s.rays_cast = s.points.size();
  return s;
}

}  // namespace nbs::test
