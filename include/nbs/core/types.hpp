// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Basic geometric types and the frame conventions of nbs.
///
/// Frames (the single place they are defined; see also docs/frames.md):
/// - **World frame W**: right-handed, metres. The object stands on a pedestal whose top is the plane z = 0;
///   +z points up. The object's bottom (z ≈ 0) cannot be scanned.
/// - **Sensor frame S** (Eq. 4.12): origin at the optical centre; **+z is the viewing direction**; for a laser
///   stripe profiler the laser fan lies in the x–z plane (a profile is a line along x), and a linear scan path
///   moves the sensor along its y axis. Area sensors: x to the right of the image, y down, z forward.
/// - A `Pose` is the transform T_WS mapping sensor coordinates into world coordinates (columns of its rotation are
///   s_x, s_y, s_z of Eq. 4.12; its translation is s_p).

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "nbs/core/error.hpp"

namespace nbs {

using Vec3 = Eigen::Vector3d;
/// 8-bit RGB colour (red, green, blue), e.g. of a measured point or a mesh vertex.
using Rgb = std::array<std::uint8_t, 3>;
using Mat3 = Eigen::Matrix3d;
/// Rigid transform T_WS (sensor -> world), metres.
using Pose = Eigen::Isometry3d;

/// The unit vector at azimuth `azimuth_rad` (from +x towards +y) and elevation `elevation_rad` (above the x–y plane):
/// (cos el cos az, cos el sin az, sin el).
[[nodiscard]] inline Vec3 unit_from_angles(double azimuth_rad, double elevation_rad) {
  return {std::cos(elevation_rad) * std::cos(azimuth_rad), std::cos(elevation_rad) * std::sin(azimuth_rad),
          std::sin(elevation_rad)};
}

/// Tolerance used to decide that a rotation matrix is orthonormal with determinant +1.
inline constexpr double kOrthonormalTolerance = 1e-6;

/// True if every coefficient of `v` is finite.
template <class Derived>
[[nodiscard]] bool all_finite(const Eigen::MatrixBase<Derived>& v) {
  return v.allFinite();
}

/// What makes `p` not a finite rigid transform, or "" if it is one: every coefficient finite, an orthonormal,
/// right-handed rotation (|RᵀR − I|∞ ≤ 1e-6, det R = +1 ± 1e-6) and bottom row (0 0 0 1).
[[nodiscard]] inline std::string pose_problem(const Pose& p) {
  const auto& m = p.matrix();
  if (!m.allFinite()) return detail::concat("has a non-finite coefficient:\n", m);
  if ((m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > kOrthonormalTolerance)
    return detail::concat("has bottom row ", m.row(3), " instead of (0 0 0 1)");
  const Mat3 r = p.linear();
  const double ortho_err = (r.transpose() * r - Mat3::Identity()).cwiseAbs().maxCoeff();
  if (ortho_err > kOrthonormalTolerance)
    return detail::concat("rotation is not orthonormal (|RᵀR−I|∞ = ", ortho_err, ")");
  const double det = r.determinant();
  if (std::abs(det - 1.0) > kOrthonormalTolerance)
    return detail::concat("rotation has determinant ", det, " (must be +1)");
  return {};
}

/// Throws InvalidArgument, the message starting with `name`, unless pose_problem(p) is "".
inline void validate_pose(const Pose& p, std::string_view name = "pose") {
  if (std::string why = pose_problem(p); !why.empty()) throw InvalidArgument(detail::concat(name, " ", why));
}

/// Throws InvalidArgument unless `v` is finite.
template <class Derived>
void validate_finite(const Eigen::MatrixBase<Derived>& v, const char* name) {
  detail::require(v.allFinite(), name, " is not finite: (", v.transpose(), ")");
}

/// Axis-aligned box in world coordinates, metres. Empty when any min > max.
struct Aabb {
  Vec3 min = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 max = Vec3::Constant(-std::numeric_limits<double>::infinity());

  [[nodiscard]] bool empty() const { return (min.array() > max.array()).any(); }
  void extend(const Vec3& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  [[nodiscard]] bool contains(const Vec3& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
  [[nodiscard]] Vec3 center() const { return 0.5 * (min + max); }
  [[nodiscard]] Vec3 extent() const { return empty() ? Vec3::Zero() : Vec3(max - min); }
};

}  // namespace nbs
