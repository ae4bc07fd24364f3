// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The stop rule of workspace modeling (Sec. 5.5): "repeated until the number of voxels which are free in the space
/// does not change significantly anymore", made exact.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>

#include "nbs/core/error.hpp"
#include "nbs/space/concepts.hpp"

namespace nbs {

/// Free voxels of the space: observed voxels inside its unknown-area box (`bounds_keys()`) with occupancy
/// probability p < `free_below` (default 0.5, as StagnationSetting; the thesis's V_free is p < 0.25, l. 742).
/// Unobserved voxels are unknown (p = 0.5), never free. Reads flushed blocks from disk.
template <VoxelSpace Space>
[[nodiscard]] std::uint64_t free_voxel_count(const Space& space, double free_below = 0.5) {
  detail::require_in_range("free_voxel_count: free_below", free_below, 0.0, 1.0);
  const KeyBox box = space.bounds_keys();
  std::uint64_t n = 0;
  space.for_each([&](const VoxelKey& k, const auto& s) {
    if (box.contains(k) && space.model().probability(s) < free_below) ++n;
  });
  return n;
}

/// Why the workspace loop stopped (or that it has not).
enum class WorkspaceStop {
  running,              ///< no rule fired
  stagnated,            ///< the free-voxel count stagnated (StagnationSetting)
  max_views,            ///< StagnationSetting::max_views views taken
  no_information_gain,  ///< the best candidate's utility is ≤ 0 or no candidate has a finite one (loop only)
  candidates_exhausted, ///< every candidate has been taken (loop only)
};

/// The enumerator's name ("running", "stagnated", …).
[[nodiscard]] constexpr const char* to_string(WorkspaceStop s) {
  switch (s) {
    case WorkspaceStop::running: return "running";
    case WorkspaceStop::stagnated: return "stagnated";
    case WorkspaceStop::max_views: return "max_views";
    case WorkspaceStop::no_information_gain: return "no_information_gain";
    case WorkspaceStop::candidates_exhausted: return "candidates_exhausted";
  }
  return "?";
}

/// Stagnation stop. With c_n the free-voxel count (free_voxel_count, p < free_below) after view n (n = 1, 2, …):
/// stop after view n as **stagnated** if n > window and c_n − c_{n−window} < min_relative_growth · c_n (a shrinking count
/// stagnates too; an all-zero history does not, as 0 < 0 is false); otherwise as **max_views** if n ≥ max_views. Defaults: growth below 1 % of the current count over the last 2 views,
/// at most 30 views. Free means p < 0.5 by default (evidence of free space, no hit), not the thesis's V_free (p < 0.25,
/// l. 742): with ThesisModel's prob_free = 0.4 a voxel needs three independent beams to fall below 0.25, and one view
/// of an area sensor gives most voxels one (the beam-independence rule rejects its neighbouring rays), so p < 0.25
/// counts revisits, not exploration, and stagnated after six views of a 1 × 1 × 0.5 m workspace seen once.
struct StagnationSetting {
  double free_below = 0.5;            ///< free: p < free_below, in [0, 1]
  double min_relative_growth = 0.01;  ///< ≥ 0
  std::size_t window = 2;             ///< k ≥ 1 views
  std::size_t max_views = 30;         ///< ≥ 1
  void validate() const {
    detail::require_in_range("StagnationSetting.free_below", free_below, 0.0, 1.0);
    detail::require(std::isfinite(min_relative_growth) && min_relative_growth >= 0.0,
                    "StagnationSetting.min_relative_growth must be finite and >= 0, got ", min_relative_growth);
    detail::require(window >= 1, "StagnationSetting.window must be >= 1, got ", window);
    detail::require(max_views >= 1, "StagnationSetting.max_views must be >= 1, got ", max_views);
  }
};

/// The rule above on `free_counts` = (c_1, …, c_n), the counts after each view so far. Throws InvalidArgument for an
/// invalid setting.
[[nodiscard]] inline WorkspaceStop stagnation_check(std::span<const std::uint64_t> free_counts,
                                                    const StagnationSetting& setting) {
  setting.validate();
  const std::size_t n = free_counts.size();
  if (n > setting.window) {
    const double now = static_cast<double>(free_counts[n - 1]);
    const double before = static_cast<double>(free_counts[n - 1 - setting.window]);
    if (now - before < setting.min_relative_growth * now) return WorkspaceStop::stagnated;
  }
  return n >= setting.max_views ? WorkspaceStop::max_views : WorkspaceStop::running;
}

}  // namespace nbs
