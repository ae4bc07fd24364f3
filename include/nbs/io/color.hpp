// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// 8-bit RGB colours and the colour map of the candidate pictures and candidate PLY files (Fig. 4.16).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "nbs/core/types.hpp"  // Rgb

namespace nbs {

/// Colour of a normalised utility u ∈ [0, 1]: red (u = 0, low) → yellow (0.5) → green (u = 1, high), as in
/// Fig. 4.16. Values outside [0, 1] are clamped; NaN maps to red.
[[nodiscard]] inline Rgb utility_color(double u) {
  const double t = std::isnan(u) ? 0.0 : std::clamp(u, 0.0, 1.0);
  const auto c = [](double v) { return static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(v, 0.0, 1.0))); };
  return {c(2.0 * (1.0 - t)), c(2.0 * t), 0};
}

/// Normalises `values` to [0, 1] by min/max (all equal → 1, i.e. green); non-finite values give 0.
[[nodiscard]] inline std::vector<double> normalize_utilities(std::span<const double> values) {
  double lo = INFINITY, hi = -INFINITY;
  for (double v : values)
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  std::vector<double> out(values.size(), 0.0);
  for (std::size_t i = 0; i < values.size(); ++i)
    if (std::isfinite(values[i])) out[i] = hi > lo ? (values[i] - lo) / (hi - lo) : 1.0;
  return out;
}

}  // namespace nbs
