// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Unseen-surface gain (ours; issue 18, docs/evaluation.md "Unseen-surface gain"): how much of the surface that the
/// coverage estimate ĉ_m counts as missing (CoverageResult::unseen, the Eq. 4.37 fan samples of the open border
/// loops) a view's beams would reach.
///
///   g_u(i) = Σ over the unobserved voxels v that a beam of candidate i reaches (first visit) of a_v / l_v²
///
/// a_v = the area (m²) of the unseen fan samples inside v, l_v = voxel edge: g_u counts surface voxels' worth of
/// area. A beam stops at the first occupied voxel, so surface behind measured surface is not counted. Samples in
/// observed voxels (a beam has crossed or hit them) do not count: a view through them adds no evidence, and counting
/// the observed-free ones let the planner fly view after view at the same gap (fandisk: median k99 30.5 → 17.5,
/// 20 runs).
/// Where the samples come from: CoverageResult::unseen; samples whose UnseenSample::edge_distance_m (distance to the
/// midpoint of their fan triangle's loop edge) is below SelectionOptions::unseen_min_edge_distance_m are
/// triangulation gaps and are dropped (UnseenSurfaceMap::build).

#include <cmath>
#include <cstddef>
#include <optional>
#include <span>
#include <unordered_map>

#include "nbs/core/error.hpp"
#include "nbs/mesh/holes.hpp"
#include "nbs/space/voxel_key.hpp"
#include "nbs/utility/utility_term.hpp"

namespace nbs {

/// Unseen fan-sample area per voxel, in units of l_v² (a voxel face). Immutable after build; concurrent reads are
/// safe.
class UnseenSurfaceMap {
public:
  UnseenSurfaceMap() = default;
  /// Bins `samples` (world, m; area ≥ 0, m²) into the voxels of `grid`, those with edge_distance_m ≥
  /// `min_edge_distance_m` (m, ≥ 0) only. Samples outside the key range are skipped. Throws InvalidArgument (naming
  /// the value) for a negative or non-finite min_edge_distance_m, and for a sample with a non-finite position or a
  /// negative or non-finite area or edge distance.
  static UnseenSurfaceMap build(std::span<const UnseenSample> samples, const VoxelGrid& grid,
                                double min_edge_distance_m = 0.0) {
    detail::require(std::isfinite(min_edge_distance_m) && min_edge_distance_m >= 0.0,
                    "UnseenSurfaceMap: min_edge_distance_m must be finite and >= 0, got ", min_edge_distance_m);
    UnseenSurfaceMap m;
    const double unit = grid.resolution_m() * grid.resolution_m();
    for (const UnseenSample& s : samples) {
      detail::require(s.position.allFinite(), "UnseenSurfaceMap: sample position is not finite: (",
                      s.position.transpose(), ")");
      detail::require(std::isfinite(s.area_m2) && s.area_m2 >= 0.0,
                      "UnseenSurfaceMap: sample area must be finite and >= 0, got ", s.area_m2);
      detail::require(std::isfinite(s.edge_distance_m) && s.edge_distance_m >= 0.0,
                      "UnseenSurfaceMap: sample edge distance must be finite and >= 0, got ", s.edge_distance_m);
      if (s.edge_distance_m < min_edge_distance_m) continue;
      const std::optional<VoxelKey> k = grid.key_of(s.position);
      if (!k) continue;
      m.area_[*k] += s.area_m2 / unit;
      m.total_ += s.area_m2 / unit;
    }
    return m;
  }
  /// a_v / l_v² of voxel k (0 if none).
  [[nodiscard]] double at(const VoxelKey& k) const {
    const auto it = area_.find(k);
    return it == area_.end() ? 0.0 : it->second;
  }
  /// Σ a_v / l_v² over the binned samples (A_empty / l_v² when every sample was kept)
  [[nodiscard]] double total() const { return total_; }
  [[nodiscard]] bool empty() const { return area_.empty(); }
  [[nodiscard]] std::size_t voxels() const { return area_.size(); }

private:
  std::unordered_map<VoxelKey, double, VoxelKeyHash> area_;
  double total_ = 0.0;
};

/// g_u (file comment) as a UtilityTerm. Counts a voxel once per candidate (first visits only). The map (borrowed;
/// null: g_u = 0) must outlive the term.
class UnseenSurfaceVI {
public:
  UnseenSurfaceVI() = default;
  explicit UnseenSurfaceVI(const UnseenSurfaceMap* map) : map_(map) {}
  void begin_candidate(std::size_t) { sum_ = 0.0; }
  void begin_ray() {}
  void visit(const VoxelVisit& v) {
    if (map_ != nullptr && v.first_visit && !v.observed) sum_ += map_->at(v.key);
  }
  void end_ray(const RayEnd&) {}
  [[nodiscard]] double value() const { return sum_; }
  [[nodiscard]] bool first_visits_only() const { return true; }

private:
  const UnseenSurfaceMap* map_ = nullptr;
  double sum_ = 0.0;
};

static_assert(UtilityTerm<UnseenSurfaceVI>);

}  // namespace nbs
