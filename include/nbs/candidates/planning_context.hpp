// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The read-only input of every scan-candidate generator: mesh, voxel space, last sensor pose, sensor geometry,
/// parameters (Sec. 4.1–4.4).

#include <cmath>
#include <concepts>
#include <numbers>
#include <span>

#include "nbs/core/parameters.hpp"
#include "nbs/mesh/mesh_concept.hpp"
#include "nbs/sensor/area_sensor.hpp"
#include "nbs/sensor/laser_stripe_profiler.hpp"
#include "nbs/space/concepts.hpp"

namespace nbs {

/// What the generators need to know about the range sensor. A line sensor (laser stripe profiler) sees a fan in
/// its x–z plane and sweeps along s_y; an area sensor sees a pyramid. Angles in radians (full opening).
struct SensorGeometry {
  enum class Kind : std::uint8_t { line, area };
  Kind kind = Kind::line;
  WorkingRange range{0.15, 0.45};  ///< metres along a ray
  double fov_x_rad = 0.5;          ///< full opening across s_x (LSP fan angle / horizontal FOV)
  double fov_y_rad = 0.0;          ///< full opening across s_y (0 for a line sensor)

  [[nodiscard]] static SensorGeometry of(const LaserStripeProfiler& s) {
    s.validate();
    return {Kind::line, s.range, s.fan_angle_rad, 0.0};
  }
  [[nodiscard]] static SensorGeometry of(const AreaSensor& s) {
    s.validate();
    return {Kind::area, s.range, s.horizontal_fov_rad, s.vertical_fov_rad};
  }
  /// Middle of the working range: the default optimal distance d_s (Sec. 4.3.1).
  [[nodiscard]] double mid_range_m() const { return 0.5 * (range.min_m + range.max_m); }
  /// l_b of Eq. 4.14: width of the FOV across s_x at distance d (m).
  [[nodiscard]] double baseline_m(double d) const { return 2.0 * d * std::tan(0.5 * fov_x_rad); }

  /// Throws InvalidArgument naming the bad field.
  void validate() const {
    range.validate("SensorGeometry");
    detail::require(std::isfinite(fov_x_rad) && fov_x_rad > 0.0 && fov_x_rad < std::numbers::pi,
                    "SensorGeometry.fov_x_rad must be in (0, pi), got ", fov_x_rad);
    const bool y_ok = kind == Kind::line ? fov_y_rad == 0.0 : (fov_y_rad > 0.0 && fov_y_rad < std::numbers::pi);
    detail::require(std::isfinite(fov_y_rad) && y_ok, "SensorGeometry.fov_y_rad must be 0 for a line sensor and in ",
                    "(0, pi) for an area sensor, got ", fov_y_rad);
  }
};

/// Read-only planning context; holds references only, so it must not outlive its arguments. Cheap to copy.
/// Frames: world (types.hpp). `last_sensor` is T_WS of the last scan's first profile (StreamingMesh::current_sensor);
/// a line sensor then moved `last_path_length_m` along that pose's +s_y. Thread-safety: generators only read.
template <EdgeMesh Mesh, VoxelSpace Space>
struct PlanningContext {
  const Mesh& mesh;
  const Space& space;
  const Parameters& params;
  Pose last_sensor = Pose::Identity();
  double last_path_length_m = 0.0;
  SensorGeometry sensor{};
  Aabb unknown_area{};        ///< bounding box of the unknown area (Sec. 4.1); used by the sphere baseline.
  double standoff_m = 0.0;    ///< d_s; 0 = sensor.mid_range_m().
  /// Threads a generator may use (≥ 1; Boundary Search: topology beside boundary detection, then the boundaries in
  /// parallel). Generators return the same candidates for any count.
  unsigned threads = 1;
  /// T_WS of the first profile of every scan integrated so far, oldest first (NbsPlanner fills it; may be empty).
  /// SEE uses it not to propose a view that was flown already.
  std::span<const Pose> scan_starts{};

  /// d_s in metres.
  [[nodiscard]] double standoff() const { return standoff_m > 0.0 ? standoff_m : sensor.mid_range_m(); }

  /// Throws InvalidArgument if the parameters, the sensor, the pose, the path length or d_s are invalid.
  void validate() const {
    params.validate();
    sensor.validate();
    validate_pose(last_sensor, "PlanningContext.last_sensor");
    detail::require_non_negative("PlanningContext.last_path_length_m", last_path_length_m);
    detail::require_non_negative("PlanningContext.standoff_m", standoff_m);
    detail::require(threads >= 1 && threads <= 1024, "PlanningContext.threads must be in [1, 1024], got ", threads);
    const double d = standoff();
    detail::require(sensor.range.contains(d), "PlanningContext: d_s = ", d, " m lies outside the working range [",
                    sensor.range.min_m, ", ", sensor.range.max_m, "]");
    detail::require(unknown_area.empty() || (unknown_area.min.allFinite() && unknown_area.max.allFinite()),
                    "PlanningContext.unknown_area must be finite or empty");
  }
};

}  // namespace nbs
