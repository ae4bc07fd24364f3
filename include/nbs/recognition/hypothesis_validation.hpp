// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Validation of a pose hypothesis against the probabilistic voxel space, thesis Eq. (3.11): the model's vertices at
/// the hypothesis pose are grouped by the occupancy probability of the voxel they lie in.

#include <concepts>
#include <cstddef>
#include <span>

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"

namespace nbs {

/// What v_h needs of a voxel space: the occupancy probability p of the voxel holding a world point (every
/// VoxelSpace provides it; 0.5 outside its bounds).
template <class S>
concept OccupancyProbability = requires(const S& s, const Vec3& x) {
  { s.probability(x) } -> std::convertible_to<double>;
};

/// The vertex groups of Eq. (3.11) and v_h.
struct HypothesisValidation {
  std::size_t free = 0;      ///< |V_free|: p < 0.25
  std::size_t unknown = 0;   ///< |V_unk|: 0.25 ≤ p < 0.75
  std::size_t occupied = 0;  ///< |V_occ|: p ≥ 0.75
  /// v_h = (0.5 |V_unk| + |V_occ|) / (|V_free| + 0.5 |V_unk| + |V_occ|), in [0, 1]; 0 without vertices.
  [[nodiscard]] double v_h() const {
    const double num = 0.5 * static_cast<double>(unknown) + static_cast<double>(occupied);
    const double den = static_cast<double>(free) + num;
    return den > 0.0 ? num / den : 0.0;
  }
  /// The thesis's rule: the hypothesis is valid if v_h ≥ `threshold` (0.66), else the object counts as unknown.
  [[nodiscard]] bool valid(double threshold = 0.66) const { return v_h() >= threshold; }
};

/// Groups the model vertices `vertices_m` (model frame, metres) placed at T_WM = `model_pose` by the probability
/// `space.probability(T_WM · v)`. Throws InvalidArgument for an invalid pose, a non-finite vertex or a probability
/// that is NaN (nothing else is checked; nothing changes).
template <OccupancyProbability S>
[[nodiscard]] HypothesisValidation validate_hypothesis(const S& space, std::span<const Vec3> vertices_m,
                                                       const Pose& model_pose) {
  validate_pose(model_pose, "validate_hypothesis: model_pose");
  HypothesisValidation out;
  for (std::size_t i = 0; i < vertices_m.size(); ++i) {
    detail::require(vertices_m[i].allFinite(), "validate_hypothesis: vertex ", i, " is not finite");
    const double p = space.probability(Vec3(model_pose * vertices_m[i]));
    detail::require(p == p, "validate_hypothesis: the space gives probability NaN at vertex ", i);
    if (p < 0.25) ++out.free;
    else if (p < 0.75) ++out.unknown;
    else ++out.occupied;
  }
  return out;
}

}  // namespace nbs
