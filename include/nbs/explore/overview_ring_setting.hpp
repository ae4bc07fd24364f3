// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The overview ring's geometry (OverviewRing, explore/simulated_exploration.hpp): where each overview frame looks from.

#include <cmath>
#include <numbers>
#include <utility>

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"

namespace nbs::explore {

/// Where OverviewRing looks from. World frame, metres, radians.
struct OverviewRingSetting {
  Vec3 target = Vec3(0.0, 0.0, 0.05);       ///< the point every view looks at (the table centre, a little above)
  double distance_m = 0.75;                 ///< eye to target
  double elevation_rad = 35.0 * std::numbers::pi / 180.0;
  double first_azimuth_rad = -0.5 * std::numbers::pi;  ///< step 0 looks from −y
  double step_azimuth_rad = 0.4 * std::numbers::pi;    ///< 72° further per step
  int frames_per_step = 3;                  ///< odd, ≥ 1: the middle one is returned, all are integrated
  double frame_spread_rad = 20.0 * std::numbers::pi / 180.0;  ///< azimuth between neighbouring frames of a step

  /// Azimuth (rad) of the middle frame of step `step`.
  [[nodiscard]] double step_azimuth(int step) const { return first_azimuth_rad + step * step_azimuth_rad; }

  /// The eye at azimuth `azimuth_rad` (from +x towards +y) on the ring: target + distance_m · (cos el cos a,
  /// cos el sin a, sin el), world frame, metres.
  [[nodiscard]] Vec3 eye(double azimuth_rad) const { return eye(target, azimuth_rad, elevation_rad); }

  /// The eye distance_m from `at` at azimuth `azimuth_rad` and elevation `elevation_rad` (the ring's formula
  /// around another point, at another elevation). World frame, metres, radians.
  [[nodiscard]] Vec3 eye(const Vec3& at, double azimuth_rad, double elevation_rad) const {
    return at + distance_m * unit_from_angles(azimuth_rad, elevation_rad);
  }

  void validate() const {
    detail::require(target.allFinite(), "OverviewRingSetting.target must be finite");
    detail::require_positive("OverviewRingSetting.distance_m", distance_m);
    detail::require(std::abs(elevation_rad) < 0.5 * std::numbers::pi,
                    "OverviewRingSetting.elevation_rad must be in (-pi/2, pi/2), got ", elevation_rad);
    for (const auto& [name, value] : {std::pair{"first_azimuth_rad", first_azimuth_rad},
                                      std::pair{"step_azimuth_rad", step_azimuth_rad},
                                      std::pair{"frame_spread_rad", frame_spread_rad}})
      detail::require(std::isfinite(value), "OverviewRingSetting.", name, " must be finite, got ", value);
    detail::require(frames_per_step >= 1 && frames_per_step % 2 == 1,
                    "OverviewRingSetting.frames_per_step must be odd and >= 1, got ", frames_per_step);
  }
};

}  // namespace nbs::explore
