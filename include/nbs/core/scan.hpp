// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// A range scan: per-profile sensor poses and the measured points with their lines of sight.

#include <cstdint>
#include <string>
#include <vector>

#include "nbs/core/types.hpp"

namespace nbs {

/// Measurements of one scan (one linear scan path of a stripe profiler, or one area-sensor frame).
///
/// Invariants (checked by `validate()`):
/// - `points`, `profile_of_point` have the same size; every index in `profile_of_point` < `profile_poses.size()`;
/// - every point is finite; the sensor origin of point i is `profile_poses[profile_of_point[i]].translation()`;
/// - the line of sight of point i is the unit vector from that origin to the point (`line_of_sight(i)`);
/// - `colors` is empty (the sensor measures no colour) or holds the colour of every point (same size as `points`).
/// All coordinates are in the world frame, metres. Code that moves points keeps `colors` index-aligned (registration's
/// `transformed`, PoseErrorDriver move points in place); recorded sessions (io/session*) do not store colours: a
/// replayed scan has none.
struct Scan {
  std::vector<Pose> profile_poses;                 ///< T_WS of each profile (or of the single frame).
  std::vector<Vec3> points;                        ///< measured surface points, world frame.
  std::vector<std::uint32_t> profile_of_point;     ///< index into profile_poses for each point.
  std::vector<Rgb> colors;                         ///< optional colour of each point: empty, or one per point.
  std::uint64_t rays_cast = 0;                     ///< rays the sensor emitted (hits + misses).

  [[nodiscard]] std::size_t size() const { return points.size(); }
  [[nodiscard]] bool empty() const { return points.empty(); }

  /// Sensor origin of point i (world frame).
  [[nodiscard]] Vec3 origin(std::size_t i) const { return profile_poses[profile_of_point[i]].translation(); }

  /// Unit line of sight from the sensor origin to point i. Zero if the point coincides with the origin.
  [[nodiscard]] Vec3 line_of_sight(std::size_t i) const {
    const Vec3 d = points[i] - origin(i);
    const double n = d.norm();
    return n > 0.0 ? Vec3(d / n) : Vec3::Zero();
  }

  [[nodiscard]] bool has_colors() const { return !colors.empty(); }

  /// Appends a point measured from profile `profile` (of a scan without colour).
  void add_point(const Vec3& p, std::uint32_t profile) {
    points.push_back(p);
    profile_of_point.push_back(profile);
  }
  /// Appends a point measured from profile `profile` with its colour (of a scan with colour).
  void add_point(const Vec3& p, std::uint32_t profile, const Rgb& color) {
    add_point(p, profile);
    colors.push_back(color);
  }

  /// Throws InvalidArgument if the invariants above are violated (names the first offending index).
  void validate() const {
    detail::require(points.size() == profile_of_point.size(), "scan has ", points.size(), " points but ",
                    profile_of_point.size(), " profile indices");
    detail::require(colors.empty() || colors.size() == points.size(), "scan has ", points.size(), " points but ",
                    colors.size(), " colours (must be 0 or one per point)");
    for (std::size_t k = 0; k < profile_poses.size(); ++k)
      if (std::string why = pose_problem(profile_poses[k]); !why.empty())
        throw InvalidArgument(detail::concat("scan profile pose ", k, " ", why));
    for (std::size_t i = 0; i < points.size(); ++i) {
      detail::require(points[i].allFinite(), "scan point ", i, " is not finite: (", points[i].transpose(), ")");
      detail::require(profile_of_point[i] < profile_poses.size(), "scan point ", i, " refers to profile ",
                      profile_of_point[i], " but the scan has ", profile_poses.size(), " profiles");
    }
  }
};

}  // namespace nbs
