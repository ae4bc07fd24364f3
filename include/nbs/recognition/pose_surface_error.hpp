// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Surface-based pose errors of a recognised object (issue 21: the symmetry-aware error): how far the model's
/// surface placed by an estimated pose lies from the same surface placed by the true pose, over samples of the model.
/// - ADD (Hinterstoisser et al. 2012): mean over samples s of ‖T_est·s − T_true·s‖ — every rotation counts;
/// - ADD-S: mean over s of min over samples s' of ‖T_est·s − T_true·s'‖ — zero (to the sampling density) for a pose
///   that differs from the truth by a symmetry of the surface (a cylinder turned about its axis, a plate turned over),
///   but not for a mug whose handle is turned;
/// - ADD-S max: the largest of those nearest distances (a part of the surface placed where the truth has none).
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
      const double d = std::sqrt(tree_.nearest(q).second);
      e.add_s_m += d;
      e.add_s_max_m = std::max(e.add_s_max_m, d);
    }
    e.add_m /= static_cast<double>(s.size());
    e.add_s_m /= static_cast<double>(s.size());
    return e;
  }

  [[nodiscard]] std::size_t size() const { return tree_.size(); }

private:
  detail::PointKdTree tree_;
};

}  // namespace nbs
