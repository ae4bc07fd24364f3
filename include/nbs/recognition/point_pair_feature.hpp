// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The point-pair feature of Drost et al. (2010), thesis Eq. (3.9), its discretisation into a 64-bit hash key, and
/// the local frame in which the voting angle α is measured.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"

namespace nbs {

/// Angle between two non-zero vectors in [0, π], radians (atan2 of |a × b| and a · b: accurate near 0 and π).
[[nodiscard]] inline double vector_angle(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// F(m1, m2) = (‖d‖, ∠(n1, d), ∠(n2, d), ∠(n1, n2)) with d = p2 − p1, Eq. (3.9). Metres and radians.
/// Preconditions: p1 ≠ p2, n1 and n2 non-zero (unit in practice).
[[nodiscard]] inline Eigen::Vector4d point_pair_feature(const Vec3& p1, const Vec3& n1, const Vec3& p2,
                                                        const Vec3& n2) {
  const Vec3 d = p2 - p1;
  return {d.norm(), vector_angle(n1, d), vector_angle(n2, d), vector_angle(n1, n2)};
}

/// Discretisation of the feature: ⌊‖d‖ / distance_step_m⌋ and ⌊angle / angle_step_rad⌋, the angle bins clamped to
/// the last bin that starts below π (so an angle of exactly π shares the bin of angles just below it).
struct PpfQuantizer {
  double distance_step_m = 0.01;                        ///< d_dist, metres (> 0).
  double angle_step_rad = 2.0 * std::numbers::pi / 30;  ///< d_angle, radians, in [π/4096, π].

  void validate() const {
    detail::require_positive("PpfQuantizer::distance_step_m", distance_step_m);
    detail::require(std::isfinite(angle_step_rad) && angle_step_rad >= std::numbers::pi / 4096 &&
                        angle_step_rad <= std::numbers::pi,
                    "PpfQuantizer::angle_step_rad must be in [pi/4096, pi], got ", angle_step_rad);
  }
  /// Number of angle bins of a feature angle in [0, π]: ⌈π / angle_step_rad⌉.
  [[nodiscard]] std::uint32_t angle_bins() const {
    return static_cast<std::uint32_t>(std::ceil(std::numbers::pi / angle_step_rad - 1e-9));
  }
  /// Bin of an angle in [0, π] (values outside are clamped).
  [[nodiscard]] std::uint32_t angle_bin(double a) const {
    const double b = std::floor(std::clamp(a, 0.0, std::numbers::pi) / angle_step_rad);
    return std::min(static_cast<std::uint32_t>(b), angle_bins() - 1);
  }
  /// Bin of a distance ≥ 0; capped at kMaxDistanceBin (callers bound distances by the model diameter).
  [[nodiscard]] std::uint32_t distance_bin(double d) const {
    const double b = std::floor(std::max(d, 0.0) / distance_step_m);
    return b >= kMaxDistanceBin ? kMaxDistanceBin : static_cast<std::uint32_t>(b);
  }
  /// The feature's hash key: four 16-bit bins, distance highest. Never ~0 (the bins stay below 0xFFFF).
  [[nodiscard]] std::uint64_t key(const Eigen::Vector4d& f) const {
    return (std::uint64_t{distance_bin(f[0])} << 48) | (std::uint64_t{angle_bin(f[1])} << 32) |
           (std::uint64_t{angle_bin(f[2])} << 16) | std::uint64_t{angle_bin(f[3])};
  }
  static constexpr std::uint32_t kMaxDistanceBin = 0xFFFE;
};

/// The rotation R with R · n = +x for a unit normal n (the rotational part of Drost's T_{m→g}; the translation
/// is −R · p). For n = −x, a rotation by π about z.
[[nodiscard]] inline Mat3 align_normal_to_x(const Vec3& n) {
  return Eigen::Quaterniond::FromTwoVectors(n, Vec3::UnitX()).toRotationMatrix();
}

/// The angle of the pair's second point about the x axis in the aligned frame: with g = R (p2 − p1),
/// atan2(g_z, g_y) in (−π, π]. Rotating the model frame by R_x(α_s − α_m) maps a model pair onto a scene pair.
[[nodiscard]] inline double pair_angle(const Mat3& r_align, const Vec3& p1, const Vec3& p2) {
  const Vec3 g = r_align * (p2 - p1);
  return std::atan2(g.z(), g.y());
}

}  // namespace nbs
