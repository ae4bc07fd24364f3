// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Working range [min, max] of a range sensor along its rays.

#include "nbs/core/error.hpp"

namespace nbs {

/// Distances (metres, along the ray) within which a sensor measures. A surface whose true distance is outside
/// [min_m, max_m] yields no point (a closer surface still occludes what lies behind it).
struct WorkingRange {
  double min_m = 0.0;  ///< > 0
  double max_m = 0.0;  ///< > min_m

  [[nodiscard]] bool contains(double d_m) const { return d_m >= min_m && d_m <= max_m; }

  /// Throws InvalidArgument naming `owner` and the field unless 0 < min_m < max_m, both finite.
  void validate(const char* owner) const {
    detail::require(std::isfinite(min_m) && min_m > 0.0, owner, ".range.min_m must be finite and > 0, got ", min_m);
    detail::require(std::isfinite(max_m) && max_m > min_m, owner, ".range.max_m must be finite and > min_m (",
                    min_m, "), got ", max_m);
  }
};

}  // namespace nbs
