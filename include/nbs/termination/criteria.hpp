// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Termination criteria (Sec. 4.6): a concept, the thesis criteria, and all/any composition.

#include <concepts>
#include <tuple>

#include "nbs/core/error.hpp"
#include "nbs/core/parameters.hpp"

namespace nbs {

/// What termination criteria look at after each scan.
struct ModelProgress {
  int scans = 0;                  ///< n_s: scans integrated so far.
  double estimated_coverage = 0;  ///< ĉ_m, Eq. (4.35), ∈ [0, 1].
  double mean_density = 0;        ///< d̄_m, mean relative point density (Eqs. 4.24–4.25), ∈ [0, 1].
};

/// A termination criterion answers `done(progress)`; it must be cheap and side-effect free.
template <class T>
concept TerminationCriterion = requires(const T& t, const ModelProgress& p) {
  { t.done(p) } -> std::convertible_to<bool>;
};

/// Stop when ĉ_m ≥ coverage and d̄_m ≥ density (Sec. 4.6; Tab. 4.3: 80 %, 20 %).
struct CoverageAndDensityReached {
  double coverage = 0.80;
  double density = 0.20;
  CoverageAndDensityReached() = default;
  CoverageAndDensityReached(double c, double d) : coverage(c), density(d) {
    detail::require_in_range("target coverage", c, 0.0, 1.0);
    detail::require_in_range("target density", d, 0.0, 1.0);
  }
  explicit CoverageAndDensityReached(const Parameters& p) : CoverageAndDensityReached(p.target_coverage, p.target_density) {}
  [[nodiscard]] bool done(const ModelProgress& p) const {
    return p.estimated_coverage >= coverage && p.mean_density >= density;
  }
};

/// Stop after n_abort scans (Tab. 4.3: 30).
struct MaxScansReached {
  int max_scans = 30;
  MaxScansReached() = default;
  explicit MaxScansReached(int n) : max_scans(n) { detail::require(n >= 1, "max scans must be >= 1, got ", n); }
  [[nodiscard]] bool done(const ModelProgress& p) const { return p.scans >= max_scans; }
};

/// Done when every criterion is done.
template <TerminationCriterion... C>
struct AllOf {
  std::tuple<C...> criteria;
  [[nodiscard]] bool done(const ModelProgress& p) const {
    return std::apply([&](const auto&... c) { return (c.done(p) && ...); }, criteria);
  }
};

/// Done when any criterion is done.
template <TerminationCriterion... C>
struct AnyOf {
  std::tuple<C...> criteria;
  [[nodiscard]] bool done(const ModelProgress& p) const {
    return std::apply([&](const auto&... c) { return (c.done(p) || ...); }, criteria);
  }
};

/// The thesis's rule: quality reached, or n_abort scans.
using DefaultTermination = AnyOf<CoverageAndDensityReached, MaxScansReached>;

/// Builds the thesis's rule from parameters.
[[nodiscard]] inline DefaultTermination default_termination(const Parameters& p) {
  p.validate();
  return DefaultTermination{{CoverageAndDensityReached(p), MaxScansReached(p.max_scans)}};
}

}  // namespace nbs
