// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Sensor presets: the thesis simulation sensor (Sec. 4.7, Eq. 4.39) and the sensors of Tab. 5.1.
/// Numbers not given in the thesis are marked "assumption" with the reasoning.

#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <string_view>
#include <variant>

#include "nbs/core/error.hpp"

#include "nbs/sensor/area_sensor.hpp"
#include "nbs/sensor/laser_stripe_profiler.hpp"

namespace nbs::presets {

namespace detail {
[[nodiscard]] constexpr double deg(double d) { return d * std::numbers::pi / 180.0; }
}  // namespace detail

/// DLR laser stripe profiler as simulated in the thesis (Sec. 4.7): working range 0.15–0.45 m, noise Eq. (4.39).
/// Assumptions (the thesis gives neither): fan angle 30°, so that at mid-range (0.3 m) a stripe spans 0.16 m,
/// the benchmark object size; 640 points per profile (as the ScanControl of Tab. 5.1); one profile per 1 mm.
[[nodiscard]] inline LaserStripeProfiler dlr_lsp() {
  return {.points_per_profile = 640,
          .fan_angle_rad = detail::deg(30.0),
          .range = {0.15, 0.45},
          .profile_spacing_m = 0.001,
          .noise = RangeNoise::thesis_lsp()};
}

/// Micro-Epsilon ScanControl 2700-100 (Tab. 5.1): 640 points, 14.25° fan, 0.3–0.6 m.
/// Noise (assumption): constant σ = 0.5 mm / 3, reading the thesis' "maximum measuring error of approximately
/// 0.5 mm for the laser striper" (Sec. 5.1) as 3σ. Profile spacing 1 mm (assumption).
[[nodiscard]] inline LaserStripeProfiler scancontrol_2700_100() {
  return {.points_per_profile = 640,
          .fan_angle_rad = detail::deg(14.25),
          .range = {0.3, 0.6},
          .profile_spacing_m = 0.001,
          .noise = RangeNoise::constant(0.0005 / 3.0)};
}

/// Asus Xtion Pro (Tab. 5.1): 640×480, 58°×45°, 0.5–3.5 m.
/// Noise (assumption): σ = 1.425e-3 m⁻¹ · d², the random depth error that Khoshelham & Elberink (2012) measured
/// for the Kinect, which uses the same PrimeSense structured-light design (≈ 4 cm at 5 m).
[[nodiscard]] inline AreaSensor asus_xtion_pro() {
  return {.width_px = 640,
          .height_px = 480,
          .horizontal_fov_rad = detail::deg(58.0),
          .vertical_fov_rad = detail::deg(45.0),
          .range = {0.5, 3.5},
          .noise = RangeNoise::quadratic(1.425e-3)};
}

/// Stereo pair of two Guppy Pro F-125 (Tab. 5.1): 1292×964, 57.4°×44.3°, range > 0.2 m, baseline 0.08 m (Sec. 5.1).
/// Assumptions: maximal range 2.0 m (Tab. 5.1 gives none); noise from stereo triangulation σ = d² σ_disp / (f b)
/// with a disparity error σ_disp = 0.25 px, focal length f = (1292/2) / tan(57.4°/2) ≈ 1180 px and b = 0.08 m,
/// i.e. σ ≈ 2.65e-3 m⁻¹ · d².
[[nodiscard]] inline AreaSensor guppy_pro_stereo() {
  constexpr double width = 1292.0;
  const double hfov = detail::deg(57.4);
  const double focal_px = 0.5 * width / std::tan(0.5 * hfov);
  constexpr double baseline_m = 0.08;
  constexpr double disparity_sigma_px = 0.25;
  return {.width_px = 1292,
          .height_px = 964,
          .horizontal_fov_rad = hfov,
          .vertical_fov_rad = detail::deg(44.3),
          .range = {0.2, 2.0},
          .noise = RangeNoise::quadratic(disparity_sigma_px / (focal_px * baseline_m))};
}

/// A preset of either sensor kind, as named in session files and on the command line.
using AnySensor = std::variant<LaserStripeProfiler, AreaSensor>;

/// The preset names `by_name` accepts, in this order: dlr_lsp, scancontrol_2700_100, asus_xtion_pro,
/// guppy_pro_stereo.
inline constexpr std::array<std::string_view, 4> kNames = {"dlr_lsp", "scancontrol_2700_100", "asus_xtion_pro",
                                                           "guppy_pro_stereo"};

/// The preset called `name` (exact, lower case). Throws InvalidArgument naming `name` and listing kNames otherwise.
[[nodiscard]] inline AnySensor by_name(std::string_view name) {
  if (name == kNames[0]) return dlr_lsp();
  if (name == kNames[1]) return scancontrol_2700_100();
  if (name == kNames[2]) return asus_xtion_pro();
  if (name == kNames[3]) return guppy_pro_stereo();
  std::string valid;
  for (std::string_view n : kNames) (valid += valid.empty() ? "" : ", ") += n;
  throw InvalidArgument(nbs::detail::concat("unknown sensor preset '", name, "'; valid names: ", valid));
}

/// The laser stripe profiler preset called `name`; throws InvalidArgument if `name` is unknown or an area sensor.
[[nodiscard]] inline LaserStripeProfiler lsp_by_name(std::string_view name) {
  AnySensor s = by_name(name);
  if (auto* lsp = std::get_if<LaserStripeProfiler>(&s)) return *lsp;
  throw InvalidArgument(nbs::detail::concat("sensor preset '", name,
                                            "' is an area sensor; this needs a laser stripe profiler (dlr_lsp, "
                                            "scancontrol_2700_100)"));
}

}  // namespace nbs::presets
