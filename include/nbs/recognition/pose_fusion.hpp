// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Multi-view pose fusion (thesis Sec. 3.4, evaluated in Sec. 5.6.2): the pose hypotheses of one object from many
/// views (world frame) are clustered with separate translation and rotation cut-offs (cluster_poses), and the mean
/// pose of the largest cluster is the fused estimate; outliers form their own small clusters.

#include <cmath>
#include <optional>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/recognition/pose_clustering.hpp"

namespace nbs {

/// Accumulates hypotheses T_WM of one object over views. Thread-safety: const members may run concurrently; add()
/// needs exclusive access.
class PoseFusion {
public:
  explicit PoseFusion(const PoseClusterSetting& setting = {}) : setting_(setting) { setting_.validate(); }

  /// Adds one hypothesis (world frame; its score weights it in the mean, e.g. q_h or votes). Throws
  /// InvalidArgument and changes nothing if the pose is not rigid and finite or the score is not finite and ≥ 0.
  void add(const PoseHypothesis& h) {
    validate_pose(h.pose, "PoseFusion::add: pose");
    detail::require(std::isfinite(h.score) && h.score >= 0.0, "PoseFusion::add: score must be finite and >= 0, got ",
                    h.score);
    hypotheses_.push_back(h);
  }

  /// The fused pose: of the clusters of all hypotheses so far (cluster_poses with the cut-offs), the one with the
  /// most members (ties: the higher summed score, then cluster_poses' order), with its score-weighted mean pose,
  /// summed score and member count. Empty before the first add(). Deterministic for the same sequence of add().
  [[nodiscard]] std::optional<PoseHypothesis> fused() const {
    if (hypotheses_.empty()) return std::nullopt;
    const std::vector<PoseHypothesis> clusters = cluster_poses(hypotheses_, setting_);
    const PoseHypothesis* best = &clusters.front();
    for (const PoseHypothesis& c : clusters)
      if (c.members > best->members) best = &c;  // clusters are by descending score: the first of a size wins
    return *best;
  }

  [[nodiscard]] std::size_t size() const { return hypotheses_.size(); }
  [[nodiscard]] const std::vector<PoseHypothesis>& hypotheses() const { return hypotheses_; }
  [[nodiscard]] const PoseClusterSetting& setting() const { return setting_; }
  void clear() { hypotheses_.clear(); }

private:
  PoseClusterSetting setting_;
  std::vector<PoseHypothesis> hypotheses_;
};

}  // namespace nbs
