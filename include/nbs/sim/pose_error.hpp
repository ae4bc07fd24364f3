// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Simulated robot pose error (Sec. 3.2.3): a rigid world-frame error E_i per scan path i, constant over the path
/// (the thesis's assumption that the relative error within one scan is low), and an optional constant hand-eye
/// calibration error Δ (sensor frame). A scan measured from the true poses T is reported with the poses
/// T' = E · T · Δ; its points are the sensor-frame measurements placed with T' (p' = T' · T⁻¹ · p).
/// `PoseErrorDriver` (driver/pose_error_driver.hpp) applies it to any ScanDriver; `residual_pose_error` measures what
/// a registration correction C leaves of it.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

#include "nbs/core/detail/random.hpp"
#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"

namespace nbs {

/// Magnitudes of the simulated pose error. Zero everywhere (translation_m = rotation_rad = 0, Δ = I) is no error.
struct PoseErrorSetting {
  /// |t| of E_i, metres. Default 1 mm: for the KR16, "the absolute positioning error is in the millimeter range"
  /// (thesis Sec. 5.1.1).
  double translation_m = 0.001;
  /// Rotation angle of E_i, radians. Default 0.1°: our assumption, the thesis gives no orientation error. 0.1° of
  /// flange orientation error moves a point at the DLR LSP's ≈ 0.2–0.3 m standoff by 0.35–0.5 mm, i.e. of the
  /// same order as the 1 mm translation, as an absolute accuracy in the millimetre range implies.
  double rotation_rad = 0.1 * std::numbers::pi / 180.0;
  /// Constant hand-eye calibration error Δ (sensor frame, right-multiplied: T' = E · T · Δ). Identity: none.
  Pose hand_eye_error = Pose::Identity();
  std::uint64_t seed = 1;  ///< E_i depends on (seed, i) only

  /// Throws InvalidArgument for a negative or non-finite magnitude or a non-rigid Δ.
  void validate() const {
    detail::require(std::isfinite(translation_m) && translation_m >= 0.0,
                    "PoseErrorSetting.translation_m must be finite and >= 0, got ", translation_m);
    detail::require(std::isfinite(rotation_rad) && rotation_rad >= 0.0 && rotation_rad <= std::numbers::pi,
                    "PoseErrorSetting.rotation_rad must be in [0, pi], got ", rotation_rad);
    validate_pose(hand_eye_error, "PoseErrorSetting.hand_eye_error");
  }

  /// Whether the error is exactly zero (then scans pass unchanged, bit for bit).
  [[nodiscard]] bool zero() const {
    return translation_m == 0.0 && rotation_rad == 0.0 && hand_eye_error.matrix() == Pose::Identity().matrix();
  }
};

/// The seeded error model: `error(i, s0)` is E_i for scan path i whose sensor origin at the path start is `s0`.
class PoseErrorModel {
public:
  /// Throws InvalidArgument for an invalid setting.
  explicit PoseErrorModel(const PoseErrorSetting& s) : s_(s) { s_.validate(); }

  /// E_i (world → world): x ↦ R (x − s0) + s0 + t with |t| = translation_m in a uniformly random direction and R a
  /// rotation by exactly rotation_rad about a uniformly random axis through `s0` (the sensor's lever arm, as for a
  /// flange orientation error). Deterministic in (seed, i); independent of the other paths.
  [[nodiscard]] Pose error(std::uint64_t path_index, const Vec3& s0) const {
    std::mt19937_64 rng(detail::splitmix64(s_.seed ^ detail::splitmix64(0x504F5345ULL + path_index)));
    const Vec3 dir_t = unit(rng), axis = unit(rng);
    const Eigen::Matrix3d R = Eigen::AngleAxisd(s_.rotation_rad, axis).toRotationMatrix();
    Pose E = Pose::Identity();
    E.linear() = R;
    E.translation() = s0 - R * s0 + s_.translation_m * dir_t;
    return E;
  }

  [[nodiscard]] const PoseErrorSetting& setting() const { return s_; }

private:
  /// A uniformly random unit vector (z uniform in [−1, 1], azimuth uniform): portable, two draws.
  static Vec3 unit(std::mt19937_64& rng) {
    const double z = 2.0 * detail::uniform01(rng) - 1.0;
    const double phi = 2.0 * std::numbers::pi * detail::uniform01(rng);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return {r * std::cos(phi), r * std::sin(phi), z};
  }

  PoseErrorSetting s_;
};

/// What remains of a pose error after registration, at one point.
struct PoseResidual {
  double translation_m = 0.0;  ///< |R·c − c| at the point c, metres
  double rotation_rad = 0.0;   ///< rotation angle of R, radians in [0, π]
};

/// Residual pose error of a scan whose true → reported map is `error` (E, or E·T₀·Δ·T₀⁻¹ with a hand-eye error)
/// after the correction `correction` C (world → world; identity when registration did not apply one): R = C · error,
/// measured at `c` (the centroid of the scan's true points, world frame).
[[nodiscard]] inline PoseResidual residual_pose_error(const Pose& error, const Pose& correction, const Vec3& c) {
  const Pose R = correction * error;
  const Eigen::AngleAxisd aa(R.linear());
  return {(R * c - c).norm(), std::abs(aa.angle())};
}

}  // namespace nbs
