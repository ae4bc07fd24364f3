// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The quality q_h of a pose hypothesis, thesis Eq. (3.10): the model rendered at the hypothesis pose compared
/// pixel by pixel with the measured depths of the current cluster.

#include <cmath>
#include <cstddef>
#include <span>

#include "nbs/core/error.hpp"

namespace nbs {

/// Pixel counts of Eq. (3.10).
struct HypothesisQuality {
  std::size_t rendered = 0;  ///< N_r: pixels where the model was rendered (finite rendered depth).
  std::size_t cluster = 0;   ///< N_c: pixels of the cluster (finite measured depth).
  std::size_t matching = 0;  ///< N_m: pixels with both depths finite and |rendered − measured| ≤ tolerance.
  /// q_h = N_m / N_r · (N_m / N_c)², in [0, 1]; 0 if N_r or N_c is 0.
  [[nodiscard]] double q_h() const {
    if (rendered == 0 || cluster == 0) return 0.0;
    const double m = static_cast<double>(matching);
    const double c = m / static_cast<double>(cluster);
    return m / static_cast<double>(rendered) * c * c;
  }
};

/// Compares two depth images of the same pixels (any layout, index-aligned; metres along the sensor's z): `rendered`
/// holds the model's depth at the hypothesis pose, `measured` the cluster's measured depth; a non-finite value
/// (NaN, ±inf) means "no depth" in either. Throws InvalidArgument if the sizes differ or tolerance_m is not
/// finite and ≥ 0.
[[nodiscard]] inline HypothesisQuality hypothesis_quality(std::span<const double> rendered,
                                                          std::span<const double> measured, double tolerance_m) {
  detail::require(rendered.size() == measured.size(), "hypothesis_quality: ", rendered.size(),
                  " rendered pixels for ", measured.size(), " measured pixels");
  detail::require_non_negative("hypothesis_quality: tolerance_m", tolerance_m);
  HypothesisQuality q;
  for (std::size_t i = 0; i < rendered.size(); ++i) {
    const bool r = std::isfinite(rendered[i]);
    const bool c = std::isfinite(measured[i]);
    q.rendered += r;
    q.cluster += c;
    q.matching += r && c && std::abs(rendered[i] - measured[i]) <= tolerance_m;
  }
  return q;
}

}  // namespace nbs
