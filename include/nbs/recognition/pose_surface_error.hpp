// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Surface-based pose errors of a recognised object (issue 21: the symmetry-aware error): how far the model's
/// surface placed by an estimated pose lies from the same surface placed by the true pose, over samples of the model.
/// - ADD (Hinterstoisser et al. 2012): mean over samples s of ‖T_est·s − T_true·s‖ — every rotation counts;
/// - ADD-S: mean over s of min over samples s' of ‖T_est·s − T_true·s'‖ — zero (to the sampling density) for a pose
///   that differs from the truth by a symmetry of the surface (a cylinder turned about its axis, a plate turned over),
///   but not for a mug whose handle is turned;
/// - ADD-S max: the largest of those nearest distances (a part of the surface placed where the truth has none);
/// - ADD-S max over covered samples: the same, leaving out the estimate's samples whose nearest truth-placed sample
///   lies on a rim (near the open border of a partial model, e.g. one NBS modeled without its underside): a sample
///   placed over a hole of the truth's surface says nothing about where the surface is. Equal to ADD-S max for a
///   metric built without rim points.
/// Model frame samples, world poses, metres.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"
#include "nbs/sim/detail/point_kd_tree.hpp"

namespace nbs {

/// The errors of one pose estimate, metres.
struct SurfacePoseError {
  double add_m = 0.0;       ///< ADD: mean distance of corresponding samples
  double add_s_m = 0.0;     ///< ADD-S: mean distance to the nearest truth-placed sample
  double add_s_max_m = 0.0; ///< the largest nearest distance
  double add_s_max_covered_m = 0.0;  ///< the largest nearest distance whose nearest truth sample is not a rim sample
};

/// ADD / ADD-S over fixed model samples (model frame; e.g. surface_samples of the model mesh). Holds a kd-tree of the
/// samples, built once; `error` transforms the estimate's samples into the truth's model frame (T_true⁻¹·T_est), so
/// the tree is never rebuilt. Thread-safety: const members may run concurrently. Cost of `error`:
/// O(samples · log samples).
class SurfacePoseMetric {
public:
  /// Throws InvalidArgument if `samples` is empty or a sample is not finite.
  explicit SurfacePoseMetric(std::span<const Vec3> samples) {
    detail::require(!samples.empty(), "SurfacePoseMetric: no model samples");
    for (std::size_t i = 0; i < samples.size(); ++i)
      detail::require(samples[i].allFinite(), "SurfacePoseMetric: model sample ", i, " is not finite: (",
                      samples[i].transpose(), ")");
    tree_ = detail::PointKdTree(std::vector<Vec3>(samples.begin(), samples.end()));
    rim_.assign(samples.size(), false);
  }

  /// As above, and the samples within `rim_distance_m` of a point of `rim` (model frame, e.g. border_points of a
  /// partial model's mesh) are rim samples (SurfacePoseError::add_s_max_covered_m). Throws InvalidArgument if a rim
  /// point is not finite or rim_distance_m is negative or not finite.
  SurfacePoseMetric(std::span<const Vec3> samples, std::span<const Vec3> rim, double rim_distance_m)
      : SurfacePoseMetric(samples) {
    detail::require(std::isfinite(rim_distance_m) && rim_distance_m >= 0.0,
                    "SurfacePoseMetric: rim_distance_m must be finite and >= 0, got ", rim_distance_m);
    for (std::size_t i = 0; i < rim.size(); ++i)
      detail::require(rim[i].allFinite(), "SurfacePoseMetric: rim point ", i, " is not finite: (", rim[i].transpose(),
                      ")");
    const detail::PointKdTree rim_tree(std::vector<Vec3>(rim.begin(), rim.end()));
    const std::vector<Vec3>& s = tree_.points();
    for (std::size_t i = 0; i < s.size(); ++i) rim_[i] = rim_tree.any_within(s[i], rim_distance_m);
  }

  /// The errors of `T_est` against `T_true` (both model → world). Throws InvalidArgument naming the pose unless
  /// both are finite and rigid.
  [[nodiscard]] SurfacePoseError error(const Pose& T_est, const Pose& T_true) const {
    validate_pose(T_est, "SurfacePoseMetric: estimated pose");
    validate_pose(T_true, "SurfacePoseMetric: true pose");
    const Pose rel = T_true.inverse(Eigen::Isometry) * T_est;  // estimate's samples in the truth's model frame
    const std::vector<Vec3>& s = tree_.points();
    SurfacePoseError e;
    for (const Vec3& p : s) {
      const Vec3 q = rel * p;
      e.add_m += (q - p).norm();
      const auto [nearest, d2] = tree_.nearest(q);
      const double d = std::sqrt(d2);
      e.add_s_m += d;
      e.add_s_max_m = std::max(e.add_s_max_m, d);
      if (!rim_[nearest]) e.add_s_max_covered_m = std::max(e.add_s_max_covered_m, d);
    }
    e.add_m /= static_cast<double>(s.size());
    e.add_s_m /= static_cast<double>(s.size());
    return e;
  }

  [[nodiscard]] std::size_t size() const { return tree_.size(); }

  /// Whether sample `i` (< size()) is a rim sample.
  [[nodiscard]] bool rim(std::size_t i) const { return rim_[i]; }

private:
  detail::PointKdTree tree_;
  std::vector<bool> rim_;  ///< per sample
};

}  // namespace nbs
