// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The UpdateModel concept: how one beam changes the state of the voxels it crosses (Sec. 3.3.2).
///
/// ProbabilisticVoxelSpace asks the model per beam for `beam(range_m, unit_direction)` (nullopt rejects the beam),
/// then updates each voxel at most once per scan: first the voxels within ±band_half_width_m(beam) of the end point
/// with `update_band(state, beam, offset_m, end_voxel)` (offset_m = signed distance of the voxel centre's projection
/// on the beam beyond the measured range; end_voxel = the voxel containing the end point), then the remaining voxels
/// between the bounding box entry and the end point with `update_free(state, beam)`. Both return whether they
/// changed the state.

#include <concepts>
#include <optional>

#include "nbs/core/types.hpp"

namespace nbs {

/// Outcome of one voxel update.
enum class VoxelUpdate {
  updated,       ///< the state changed
  unchanged,     ///< outside the model's support (e.g. beyond the band)
  similar_beam,  ///< rejected: a beam of similar direction was already integrated here (beam independence)
};

template <class M>
concept UpdateModel = std::default_initializable<typename M::State> &&
    requires(const M& m, typename M::State& s, const typename M::State& cs, const typename M::Beam& b,
             double range_m, const Vec3& dir) {
      { m.beam(range_m, dir) } -> std::same_as<std::optional<typename M::Beam>>;
      { m.band_half_width_m(b) } -> std::convertible_to<double>;
      { m.update_band(s, b, range_m, true) } -> std::same_as<VoxelUpdate>;
      { m.update_free(s, b) } -> std::same_as<VoxelUpdate>;
      { m.probability(cs) } -> std::convertible_to<double>;
      { m.log_odds(cs) } -> std::convertible_to<double>;
      { m.occupied(cs) } -> std::convertible_to<bool>;
    };

}  // namespace nbs
