// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// match_ppf: Drost et al.'s (2010) voting (thesis Sec. 3.4) of a scene cloud with normals (e.g. one segmented
/// cluster) against a PpfModel, followed by pose clustering. Serial and deterministic.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/recognition/oriented_points.hpp"
#include "nbs/recognition/pose_clustering.hpp"
#include "nbs/recognition/ppf_model.hpp"
#include "nbs/sim/detail/point_kd_tree.hpp"

namespace nbs {

/// Settings of the matching.
struct PpfMatchSetting {
  std::size_t reference_step = 5;     ///< every n-th subsampled scene point is a reference point (Drost: 5), ≥ 1.
  std::size_t peaks_per_reference = 3;  ///< accumulator peaks taken per reference point, ≥ 1.
  std::size_t max_hypotheses = 10;    ///< clusters returned, ≥ 1.
  /// Translation cut-off of pose clustering as a fraction of the model diameter (Drost: 0.1), in (0, 1].
  double cluster_translation_ratio = 0.1;
  double cluster_rotation_rad = 2.0 * std::numbers::pi / 30;  ///< rotation cut-off, radians, in (0, π].

  void validate() const {
    detail::require(reference_step >= 1, "PpfMatchSetting::reference_step must be >= 1, got ", reference_step);
    detail::require(peaks_per_reference >= 1, "PpfMatchSetting::peaks_per_reference must be >= 1, got ",
                    peaks_per_reference);
    detail::require(max_hypotheses >= 1, "PpfMatchSetting::max_hypotheses must be >= 1, got ", max_hypotheses);
    detail::require(std::isfinite(cluster_translation_ratio) && cluster_translation_ratio > 0.0 &&
                        cluster_translation_ratio <= 1.0,
                    "PpfMatchSetting::cluster_translation_ratio must be in (0, 1], got ", cluster_translation_ratio);
    detail::require(std::isfinite(cluster_rotation_rad) && cluster_rotation_rad > 0.0 &&
                        cluster_rotation_rad <= std::numbers::pi,
                    "PpfMatchSetting::cluster_rotation_rad must be in (0, pi], got ", cluster_rotation_rad);
  }
};

/// Pose hypotheses T_SM (model → scene frame) of `model` in `scene`, best first (at most max_hypotheses), scored by
/// summed votes. The scene is subsampled on the model's distance-step grid; each reference point s_r is paired with
/// every subsampled scene point within the model diameter; each table entry (m_r, α_m) of the pair's feature votes
/// for (m_r, α = α_s − α_m) in a (model point × angle bin) accumulator with ⌈2π / d_angle⌉ bins; the highest cells
/// give T_SM = (R_{s→g}, s_r)⁻¹ · R_x(α) · (R_{m→g}, m_r). Empty if no pair votes. Throws InvalidArgument if the scene
/// or setting is invalid.
template <class = void>  // lazy: instantiated where called, not where included (docs/robustness.md)
[[nodiscard]] inline std::vector<PoseHypothesis> match_ppf(const PpfModel& model, const OrientedPoints& scene,
                                                           const PpfMatchSetting& setting = {}) {
  setting.validate();
  scene.validate("match_ppf: scene");
  const PpfQuantizer& q = model.quantizer();
  const OrientedPoints s = grid_subsample(scene, q.distance_step_m);
  const detail::PointKdTree tree(s.points);
  const double two_pi = 2.0 * std::numbers::pi;
  const auto alpha_bins = static_cast<std::uint32_t>(std::ceil(two_pi / q.angle_step_rad - 1e-9));
  const std::size_t n_model = model.points().size();
  std::vector<std::uint32_t> acc(n_model * alpha_bins);
  std::vector<std::size_t> neighbours;
  std::vector<PoseHypothesis> raw;

  for (std::size_t r = 0; r < s.size(); r += setting.reference_step) {
    const Vec3& sr = s.points[r];
    const Vec3& nr = s.normals[r];
    const Mat3 rs = align_normal_to_x(nr);
    neighbours.clear();
    tree.for_each_within(sr, model.diameter_m(), [&](std::size_t i, double) { neighbours.push_back(i); });
    std::sort(neighbours.begin(), neighbours.end());  // the kd-tree's order is not part of its contract
    std::fill(acc.begin(), acc.end(), 0U);
    bool voted = false;
    for (const std::size_t i : neighbours) {
      if (i == r || s.points[i] == sr) continue;
      const double alpha_s = pair_angle(rs, sr, s.points[i]);
      for (const PpfEntry& e : model.find(q.key(point_pair_feature(sr, nr, s.points[i], s.normals[i])))) {
        double a = alpha_s - static_cast<double>(e.alpha);  // in (−2π, 2π)
        if (a < 0.0) a += two_pi;
        const auto bin = std::min(static_cast<std::uint32_t>(a / q.angle_step_rad), alpha_bins - 1);
        ++acc[e.reference * alpha_bins + bin];
        voted = true;
      }
    }
    if (!voted) continue;
    // The highest cells (ties: lowest index), peaks_per_reference of them, each with ≥ 1 vote.
    for (std::size_t k = 0; k < setting.peaks_per_reference; ++k) {
      std::size_t best = 0;
      for (std::size_t c = 1; c < acc.size(); ++c)
        if (acc[c] > acc[best]) best = c;
      if (acc[best] == 0) break;
      const std::size_t m = best / alpha_bins;
      const double alpha = (static_cast<double>(best % alpha_bins) + 0.5) * q.angle_step_rad;
      Pose t_mg = Pose::Identity(), t_sg = Pose::Identity();
      t_mg.linear() = model.alignment(m);
      t_mg.translation() = -(model.alignment(m) * model.points().points[m]);
      t_sg.linear() = rs;
      t_sg.translation() = -(rs * sr);
      PoseHypothesis h;
      h.pose = t_sg.inverse() * Pose(Eigen::AngleAxisd(alpha, Vec3::UnitX())) * t_mg;
      h.score = acc[best];
      raw.push_back(h);
      acc[best] = 0;
    }
  }
  std::vector<PoseHypothesis> clusters = cluster_poses(
      raw, {setting.cluster_translation_ratio * model.diameter_m(), setting.cluster_rotation_rad});
  if (clusters.size() > setting.max_hypotheses) clusters.resize(setting.max_hypotheses);
  return clusters;
}

}  // namespace nbs
