// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Pose clustering of Drost et al. (2010) (thesis Sec. 3.4): hypotheses grouped with separate translation and
/// rotation cut-offs; a cluster's score is its summed votes, its pose the score-weighted mean of its members
/// (rotations: the quaternion mean of Markley et al. 2007).

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"

namespace nbs {

/// A pose hypothesis T_SM (model frame → scene frame) with its score (votes, or summed votes of a cluster).
struct PoseHypothesis {
  Pose pose = Pose::Identity();
  double score = 0.0;
  std::size_t members = 1;  ///< hypotheses merged into this one (1 for a raw hypothesis).
};

/// Cut-offs of pose clustering.
struct PoseClusterSetting {
  double max_translation_m = 0.01;  ///< largest translation difference to a cluster's seed, metres (≥ 0).
  double max_rotation_rad = 0.2;    ///< largest rotation angle between member and seed, radians, in [0, π].

  void validate() const {
    detail::require_non_negative("PoseClusterSetting::max_translation_m", max_translation_m);
    detail::require_in_range("PoseClusterSetting::max_rotation_rad", max_rotation_rad, 0.0, 3.141592653589793);
  }
};

/// Rotation angle between two rotations, radians in [0, π].
[[nodiscard]] inline double rotation_angle_between(const Mat3& a, const Mat3& b) {
  const Eigen::Quaterniond q(a.transpose() * b);
  return 2.0 * std::atan2(q.vec().norm(), std::abs(q.w()));
}

/// The weighted mean rotation of `rotations` (≥ 1): the unit eigenvector of the largest eigenvalue of Σ w q qᵀ
/// (sign-free), returned with w ≥ 0. `weights`: empty (all 1) or one finite weight ≥ 0 per rotation, sum > 0.
template <class = void>  // lazy: instantiated where called, not where included (docs/robustness.md)
[[nodiscard]] inline Mat3 mean_rotation(const std::vector<Mat3>& rotations, const std::vector<double>& weights = {}) {
  detail::require(!rotations.empty(), "mean_rotation: no rotations");
  detail::require(weights.empty() || weights.size() == rotations.size(), "mean_rotation: ", weights.size(),
                  " weights for ", rotations.size(), " rotations");
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  for (std::size_t i = 0; i < rotations.size(); ++i) {
    const Eigen::Vector4d q = Eigen::Quaterniond(rotations[i]).normalized().coeffs();
    m += (weights.empty() ? 1.0 : weights[i]) * q * q.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> es(m);
  Eigen::Vector4d v = es.eigenvectors().col(3);  // eigenvalues ascending
  if (v[3] < 0.0) v = -v;                        // coeffs order x, y, z, w
  return Eigen::Quaterniond(v[3], v[0], v[1], v[2]).normalized().toRotationMatrix();
}

/// Greedy clustering: hypotheses in order of descending score (ties: input order); each joins the first existing
/// cluster whose seed (its first, highest-scored member) is within both cut-offs, else it seeds a new one. Returns
/// the clusters by descending summed score (ties: seed order), each with the score-weighted mean pose of its members
/// (unweighted if all its scores are 0). Deterministic. Throws InvalidArgument if the setting is invalid or a score
/// is not finite and ≥ 0.
template <class = void>  // lazy: instantiated where called, not where included (docs/robustness.md)
[[nodiscard]] inline std::vector<PoseHypothesis> cluster_poses(const std::vector<PoseHypothesis>& hypotheses,
                                                               const PoseClusterSetting& setting = {}) {
  setting.validate();
  for (std::size_t i = 0; i < hypotheses.size(); ++i)
    detail::require(std::isfinite(hypotheses[i].score) && hypotheses[i].score >= 0.0,
                    "cluster_poses: score of hypothesis ", i, " must be finite and >= 0, got ", hypotheses[i].score);
  std::vector<std::size_t> order(hypotheses.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return hypotheses[a].score > hypotheses[b].score; });
  std::vector<std::vector<std::size_t>> clusters;
  for (const std::size_t h : order) {
    const Pose& p = hypotheses[h].pose;
    bool joined = false;
    for (auto& c : clusters) {
      const Pose& seed = hypotheses[c.front()].pose;
      if ((p.translation() - seed.translation()).norm() <= setting.max_translation_m &&
          rotation_angle_between(p.linear(), seed.linear()) <= setting.max_rotation_rad) {
        c.push_back(h);
        joined = true;
        break;
      }
    }
    if (!joined) clusters.push_back({h});
  }
  std::vector<PoseHypothesis> out;
  out.reserve(clusters.size());
  for (const auto& c : clusters) {
    PoseHypothesis r;
    r.members = c.size();
    Vec3 t = Vec3::Zero();
    std::vector<Mat3> rotations;
    std::vector<double> weights;
    for (const std::size_t h : c) {
      r.score += hypotheses[h].score;
      t += hypotheses[h].score * hypotheses[h].pose.translation();
      rotations.push_back(hypotheses[h].pose.linear());
      weights.push_back(hypotheses[h].score);
    }
    if (r.score > 0.0) {
      r.pose.linear() = mean_rotation(rotations, weights);
      r.pose.translation() = t / r.score;
    } else {  // all scores 0: unweighted
      r.pose.linear() = mean_rotation(rotations);
      r.pose.translation() = Vec3::Zero();
      for (const std::size_t h : c) r.pose.translation() += hypotheses[h].pose.translation() / static_cast<double>(c.size());
    }
    out.push_back(r);
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const PoseHypothesis& a, const PoseHypothesis& b) { return a.score > b.score; });
  return out;
}

}  // namespace nbs
