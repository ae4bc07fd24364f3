// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// NBV candidates of a mobile platform with a pan-tilt head (Sec. 5.5, workspace modeling; issue 22 item 1): the
/// platform moves along a line in fixed steps, the head samples a pan × tilt grid at each platform position.

#include <cmath>
#include <cstddef>
#include <numbers>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"
#include "nbs/core/viewpoint.hpp"

namespace nbs {

/// Geometry of the platform and its pan-tilt unit (PTU). World frame W, +z up, metres and radians.
///
/// - Platform point at offset s along the line: p(s) = line_origin_m + s · line_direction, for s = platform_min_m +
///   i · platform_step_m, i = 0, 1, … while s ≤ platform_max_m (+1e-9 m); the platform does not turn.
/// - The PTU's pan/tilt centre is p(s) + ptu_offset_m (a world-frame offset: height and lateral offset).
/// - Viewing direction at pan φ, tilt θ: s_z = Rz(φ) · (cos θ · b + sin θ · ẑ) with b = base_view_direction
///   (horizontal, facing the scene). φ > 0 turns left (counter-clockwise seen from above), θ > 0 looks up.
/// - Sensor frame (docs/architecture.md "Frames", area sensor): s_x = Rz(φ) · (b × ẑ) (right, horizontal), s_y =
///   s_z × s_x (down in the image), s_z viewing direction. The optical centre is the pan/tilt centre plus
///   sensor_offset_m given in that sensor frame (zero: the optical centre is on both axes).
/// - Pan values pan_min_rad + j · pan_step_rad ≤ pan_max_rad (+1e-9), tilt likewise. Defaults as the thesis: 0.25 m
///   platform steps, pan −20…20°, tilt −60…20°, both in 20° steps (3 × 5 = 15 head poses per platform position).
struct PlatformPanTiltSetting {
  Vec3 line_origin_m = Vec3::Zero();         ///< platform point at offset 0 (world)
  Vec3 line_direction = Vec3::UnitY();       ///< unit, horizontal (z = 0): the platform's direction of travel
  double platform_min_m = -1.0;              ///< first offset along the line
  double platform_max_m = 1.0;               ///< last offset along the line (≥ min)
  double platform_step_m = 0.25;             ///< > 0
  Vec3 ptu_offset_m = Vec3(0.0, 0.0, 1.2);   ///< pan/tilt centre − platform point (world)
  Vec3 base_view_direction = Vec3::UnitX();  ///< unit, horizontal: the head's look at pan = tilt = 0
  Vec3 sensor_offset_m = Vec3::Zero();       ///< optical centre − pan/tilt centre, in the sensor frame
  double pan_min_rad = -20.0 * std::numbers::pi / 180.0;
  double pan_max_rad = 20.0 * std::numbers::pi / 180.0;
  double pan_step_rad = 20.0 * std::numbers::pi / 180.0;
  double tilt_min_rad = -60.0 * std::numbers::pi / 180.0;  ///< > −90°
  double tilt_max_rad = 20.0 * std::numbers::pi / 180.0;   ///< < 90°
  double tilt_step_rad = 20.0 * std::numbers::pi / 180.0;

  /// Throws InvalidArgument naming the first invalid field and its value: non-finite values, a direction that is not
  /// unit length (±1e-6) or not horizontal (|z| > 1e-9), steps ≤ 0, min > max, |tilt| ≥ 90°, more than 10⁶ values
  /// along one axis.
  void validate() const {
    const auto finite3 = [](const Vec3& v) { return v.allFinite(); };
    detail::require(finite3(line_origin_m), "PlatformPanTiltSetting.line_origin_m is not finite: (",
                    line_origin_m.transpose(), ")");
    detail::require(finite3(ptu_offset_m), "PlatformPanTiltSetting.ptu_offset_m is not finite: (",
                    ptu_offset_m.transpose(), ")");
    detail::require(finite3(sensor_offset_m), "PlatformPanTiltSetting.sensor_offset_m is not finite: (",
                    sensor_offset_m.transpose(), ")");
    const auto horizontal_unit = [](const Vec3& v) {
      return v.allFinite() && std::abs(v.norm() - 1.0) <= 1e-6 && std::abs(v.z()) <= 1e-9;
    };
    detail::require(horizontal_unit(line_direction), "PlatformPanTiltSetting.line_direction must be a horizontal unit "
                    "vector (z = 0), got (", line_direction.transpose(), ")");
    detail::require(horizontal_unit(base_view_direction), "PlatformPanTiltSetting.base_view_direction must be a "
                    "horizontal unit vector (z = 0), got (", base_view_direction.transpose(), ")");
    check_axis("platform", platform_min_m, platform_max_m, platform_step_m);
    check_axis("pan", pan_min_rad, pan_max_rad, pan_step_rad);
    check_axis("tilt", tilt_min_rad, tilt_max_rad, tilt_step_rad);
    constexpr double kRight = 0.5 * std::numbers::pi;
    detail::require(tilt_min_rad > -kRight && tilt_max_rad < kRight,
                    "PlatformPanTiltSetting: tilt must stay inside (-90 deg, 90 deg), got [", tilt_min_rad, ", ",
                    tilt_max_rad, "] rad");
    const auto count = [](double min, double max, double step) { return std::floor((max - min) / step + 1e-9) + 1.0; };
    const double n_platform = count(platform_min_m, platform_max_m, platform_step_m),
                 n_pan = count(pan_min_rad, pan_max_rad, pan_step_rad),
                 n_tilt = count(tilt_min_rad, tilt_max_rad, tilt_step_rad);
    detail::require(n_platform * n_pan * n_tilt <= 1e6, "PlatformPanTiltSetting: ", n_platform, " platform positions x ",
                    n_pan, " pans x ", n_tilt, " tilts are more than 10^6 candidates");
  }

  /// Values min + i · step ≤ max (+1e-9) of one axis.
  [[nodiscard]] static std::vector<double> axis_values(double min, double max, double step) {
    std::vector<double> v;
    const auto n = static_cast<std::size_t>(std::floor((max - min) / step + 1e-9)) + 1;
    v.reserve(n);
    for (std::size_t i = 0; i < n; ++i) v.push_back(min + static_cast<double>(i) * step);
    return v;
  }
  [[nodiscard]] std::vector<double> platform_offsets() const {
    return axis_values(platform_min_m, platform_max_m, platform_step_m);
  }
  [[nodiscard]] std::vector<double> pans() const { return axis_values(pan_min_rad, pan_max_rad, pan_step_rad); }
  [[nodiscard]] std::vector<double> tilts() const { return axis_values(tilt_min_rad, tilt_max_rad, tilt_step_rad); }

  /// The platform point at offset s along the line (world).
  [[nodiscard]] Vec3 platform_point(double s) const { return line_origin_m + s * line_direction; }

  /// T_WS of the sensor with the platform at offset s and the head at pan φ, tilt θ (rules above). Does not validate.
  [[nodiscard]] Pose sensor_pose(double s, double pan_rad, double tilt_rad) const {
    const Eigen::AngleAxisd rz(pan_rad, Vec3::UnitZ());
    const Vec3 sz = rz * (std::cos(tilt_rad) * base_view_direction + std::sin(tilt_rad) * Vec3::UnitZ());
    const Vec3 sx = rz * base_view_direction.cross(Vec3::UnitZ());
    const Vec3 sy = sz.cross(sx);
    Pose p = Pose::Identity();
    p.linear().col(0) = sx.normalized();
    p.linear().col(1) = sy.normalized();
    p.linear().col(2) = sz.normalized();
    p.translation() = platform_point(s) + ptu_offset_m + p.linear() * sensor_offset_m;
    return p;
  }

private:
  static void check_axis(const char* name, double min, double max, double step) {
    detail::require(std::isfinite(min) && std::isfinite(max) && std::isfinite(step), "PlatformPanTiltSetting: ",
                    name, " min / max / step must be finite, got ", min, ", ", max, ", ", step);
    detail::require(step > 0.0, "PlatformPanTiltSetting: ", name, " step must be > 0, got ", step);
    detail::require(min <= max, "PlatformPanTiltSetting: ", name, " min must be <= max, got ", min, " > ", max);
    detail::require((max - min) / step < 1e6, "PlatformPanTiltSetting: ", name, " has more than 10^6 values (min ",
                    min, ", max ", max, ", step ", step, ")");
  }
};

/// One NBV candidate of the platform + PTU: the sensor pose and how the robot reaches it.
struct PanTiltCandidate {
  Pose T_WS = Pose::Identity();       ///< sensor → world (area sensor: x right, y down, z viewing direction)
  std::size_t platform_index = 0;     ///< index into PlatformPanTiltSetting::platform_offsets()
  double platform_offset_m = 0.0;     ///< s: offset along the line
  double pan_rad = 0.0;
  double tilt_rad = 0.0;
};

/// Every candidate of `setting` (validated first; throws InvalidArgument as validate()). Order: platform position
/// outermost, then pan, then tilt: index = (i_platform · n_pan + i_pan) · n_tilt + i_tilt.
[[nodiscard]] inline std::vector<PanTiltCandidate> pan_tilt_candidates(const PlatformPanTiltSetting& setting) {
  setting.validate();
  const std::vector<double> offsets = setting.platform_offsets(), pans = setting.pans(), tilts = setting.tilts();
  std::vector<PanTiltCandidate> out;
  out.reserve(offsets.size() * pans.size() * tilts.size());
  for (std::size_t i = 0; i < offsets.size(); ++i)
    for (const double pan : pans)
      for (const double tilt : tilts) out.push_back({setting.sensor_pose(offsets[i], pan, tilt), i, offsets[i], pan, tilt});
  return out;
}

}  // namespace nbs
