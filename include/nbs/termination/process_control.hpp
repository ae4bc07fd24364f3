// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Process control (Sec. 4.6): switch from Boundary Search to Hole Rescan when ĉ_m stagnates, Eq. (4.38).

#include "nbs/core/error.hpp"

namespace nbs {

/// Which candidate generator the planner uses.
enum class SearchMode { BoundarySearch, HoleRescan };

/// Tracks ĉ_m after each scan and switches BoundarySearch → HoleRescan once ĉ_m^i − ĉ_m^{i−1} < `min_gain`
/// (Eq. 4.38, 1 %). The switch is one-way: on switching, the remaining boundary candidates are to be discarded and
/// holes detected once (`holes_pending()` is true until `mark_holes_detected()`). Not thread-safe.
class ProcessControl {
public:
  explicit ProcessControl(double min_gain = 0.01) : min_gain_(min_gain) {
    detail::require_in_range("min coverage gain", min_gain, 0.0, 1.0);
  }

  /// Reports ĉ_m after a scan; returns the mode for planning the next scan.
  SearchMode update(double estimated_coverage) {
    detail::require_in_range("estimated coverage", estimated_coverage, 0.0, 1.0);
    if (mode_ == SearchMode::BoundarySearch && has_previous_ && estimated_coverage - previous_ < min_gain_) {
      mode_ = SearchMode::HoleRescan;
      holes_pending_ = true;
    }
    previous_ = estimated_coverage;
    has_previous_ = true;
    return mode_;
  }

  [[nodiscard]] SearchMode mode() const { return mode_; }
  [[nodiscard]] bool holes_pending() const { return holes_pending_; }
  void mark_holes_detected() { holes_pending_ = false; }

private:
  double min_gain_;
  double previous_ = 0.0;
  bool has_previous_ = false;
  SearchMode mode_ = SearchMode::BoundarySearch;
  bool holes_pending_ = false;
};

}  // namespace nbs
