// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The 13 initial scan paths of Sec. 4.7.2: along the five sides and eight edges of the object's bounding box that
/// do not touch the pedestal (top face, 4 vertical side faces, 4 top edges, 4 vertical edges).

#include <array>
#include <cstdint>
#include <vector>

#include "nbs/core/scan_path.hpp"
#include "nbs/core/detail/random.hpp"

namespace nbs {

/// Number of initial scan paths (Sec. 4.7.2).
inline constexpr int kInitialScanPathCount = 13;

/// Initial scan path `index` ∈ [0, 13) for the box `box` (world frame, metres) at standoff `standoff_m`.
///
/// Geometry: let m be the centre of the face or the midpoint of the edge, c the box centre and u = (m − c)/|m − c|.
/// The sensor looks along s_z = −u (through c at the middle of the path) from m + standoff_m·u, so its distance to
/// the box is exactly standoff_m there. The path moves along s_y, a horizontal direction ⟂ u (for the top face
/// world +y); its length is the box's extent along s_y, so the laser fan (the s_x–s_z plane) sweeps the whole box.
/// The path is centred on m + standoff_m·u, so every sensor height is ≥ c_z (> 0 for a box standing on z = 0).
///
/// Index order: 0 top face; 1–4 side faces +x, −x, +y, −y; 5–8 top edges at +x, −x, +y, −y;
/// 9–12 vertical edges at (+x,+y), (−x,+y), (−x,−y), (+x,−y).
/// Throws InvalidArgument if the box is empty or not finite, its extent is not > 0 on every axis,
/// standoff_m is not finite and > 0, or index is out of range.
[[nodiscard]] inline LinearScanPath initial_scan_path(const Aabb& box, double standoff_m, int index) {
  detail::require(!box.empty() && box.min.allFinite() && box.max.allFinite(),
                  "initial_scan_path: box must be finite and non-empty, got min (", box.min.transpose(), ") max (",
                  box.max.transpose(), ")");
  detail::require((box.extent().array() > 0.0).all(), "initial_scan_path: box extent must be > 0 on every axis, got (",
                  box.extent().transpose(), ")");
  detail::require_positive("initial_scan_path: standoff_m", standoff_m);
  detail::require(index >= 0 && index < kInitialScanPathCount, "initial_scan_path: index must be in [0, 13), got ",
                  index);
  // Outward offset of m from c in units of the half extents: face centres and edge midpoints not on the bottom.
  static constexpr std::array<std::array<int, 3>, kInitialScanPathCount> kOffsets = {{
      {0, 0, 1},                                              // top face
      {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0},           // side faces
      {1, 0, 1}, {-1, 0, 1}, {0, 1, 1}, {0, -1, 1},           // top edges
      {1, 1, 0}, {-1, 1, 0}, {-1, -1, 0}, {1, -1, 0},         // vertical edges
  }};
  const auto& o = kOffsets[static_cast<std::size_t>(index)];
  const Vec3 c = box.center();
  const Vec3 half = 0.5 * box.extent();
  const Vec3 m = c + Vec3(o[0] * half.x(), o[1] * half.y(), o[2] * half.z());
  const Vec3 u = (m - c).normalized();
  const Vec3 s_z = -u;
  // Motion direction: z × u = (−u_y, u_x, 0) is horizontal and ⟂ u whenever u is not vertical; top face: world +y.
  const Vec3 s_y = (index == 0) ? Vec3(Vec3::UnitY()) : Vec3(Vec3::UnitZ().cross(u).normalized());
  const Vec3 s_x = s_y.cross(s_z);
  const Vec3 centre = m + standoff_m * u;
  const double length = half.cwiseProduct(s_y.cwiseAbs()).sum() * 2.0;  // box extent along s_y
  const Viewpoint start = Viewpoint::from_axes(s_x, s_y, s_z, centre - 0.5 * length * s_y);
  return LinearScanPath(start, centre + 0.5 * length * s_y);
}

/// All 13 initial scan paths in index order (see initial_scan_path).
[[nodiscard]] inline std::vector<LinearScanPath> initial_scan_paths(const Aabb& box, double standoff_m) {
  std::vector<LinearScanPath> paths;
  paths.reserve(kInitialScanPathCount);
  for (int i = 0; i < kInitialScanPathCount; ++i) paths.push_back(initial_scan_path(box, standoff_m, i));
  return paths;
}

/// The seeded random choice of the thesis (one of the 13, Sec. 4.7.2): index = splitmix64(seed) mod 13.
[[nodiscard]] inline int random_initial_scan_index(std::uint64_t seed) {
  return static_cast<int>(detail::splitmix64(seed) % kInitialScanPathCount);
}

}  // namespace nbs
