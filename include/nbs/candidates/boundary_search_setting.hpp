// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Setting of the Boundary Search (Sec. 4.3.1) for what the thesis leaves open.

#include <cmath>
#include <numbers>

#include "nbs/core/error.hpp"

namespace nbs {

/// Choices of the Boundary Search the thesis leaves open (ours). Angles in radians, lengths in metres.
struct BoundarySearchSetting {
  double region_fraction = 0.25;  ///< box depth into the mesh: this fraction of the mesh extent along the trend axis
  double step_fraction = 0.01;    ///< Δp (Tab. 4.2) as a fraction of the baseline l_b; the end is bisected exactly
  double max_step_angle_rad = 10.0 * std::numbers::pi / 180.0;  ///< angle limit between consecutive steps
  double fov_edge_margin_rad = 2.0 * std::numbers::pi / 180.0;  ///< closer to the FOV edge = "on the limiting ray"
  double fov_edge_margin_m = 0.01;  ///< the same at the start/end of a line sensor's last path
  int max_targets = 16;             ///< surface targets per candidate (sub-sampled boundary vertices)

  void validate() const {
    detail::require(std::isfinite(region_fraction) && region_fraction > 0.0 && region_fraction <= 1.0,
                    "BoundarySearch.region_fraction must be in (0, 1], got ", region_fraction);
    detail::require_in_range("BoundarySearch.step_fraction", step_fraction, 1e-4, 0.5);  // bounds the walk
    detail::require(std::isfinite(max_step_angle_rad) && max_step_angle_rad > 0.0 &&
                        max_step_angle_rad <= std::numbers::pi,
                    "BoundarySearch.max_step_angle_rad must be in (0, pi], got ", max_step_angle_rad);
    detail::require_in_range("BoundarySearch.fov_edge_margin_rad", fov_edge_margin_rad, 0.0, std::numbers::pi / 2);
    detail::require_non_negative("BoundarySearch.fov_edge_margin_m", fov_edge_margin_m);
    detail::require(max_targets >= 1, "BoundarySearch.max_targets must be >= 1, got ", max_targets);
  }
};

}  // namespace nbs
