// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Actual completeness c_a (without bottom) and c_b (with bottom) of a model against ground-truth samples
/// (Sec. 4.7.2, Tab. 5.2): a sample is covered if a model vertex lies within r of it.

#include <cmath>
#include <cstddef>
#include <span>
#include <vector>

#include "nbs/core/detail/parallel_for.hpp"
#include "nbs/sim/detail/point_kd_tree.hpp"
#include "nbs/sim/surface_samples.hpp"

namespace nbs {

/// Counts behind c_a and c_b. Fractions in [0, 1].
struct Completeness {
  std::size_t covered = 0;             ///< covered samples (all).
  std::size_t covered_non_bottom = 0;  ///< covered samples that are not bottom.
  std::size_t samples = 0;             ///< all samples.
  std::size_t non_bottom = 0;          ///< samples that are not bottom.

  /// c_a: covered share of the non-bottom samples (0 if there are none).
  [[nodiscard]] double c_a() const { return non_bottom ? double(covered_non_bottom) / double(non_bottom) : 0.0; }
  /// c_b: covered share of all samples.
  [[nodiscard]] double c_b() const { return samples ? double(covered) / double(samples) : 0.0; }
};

/// Completeness from per-sample coverage flags.
[[nodiscard]] inline Completeness count_completeness(const SurfaceSamples& samples, const std::vector<bool>& covered) {
  Completeness c;
  c.samples = samples.size();
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const bool b = samples.bottom[i];
    c.non_bottom += b ? 0 : 1;
    if (covered[i]) {
      ++c.covered;
      c.covered_non_bottom += b ? 0 : 1;
    }
  }
  return c;
}

/// One-shot completeness: kd-tree over `model_vertices`, one inclusive radius query (|v − s| ≤ r) per sample.
/// Throws InvalidArgument if r is not finite and > 0, or a model vertex is not finite. An empty model gives 0.
/// Independent of `threads` (0 = hardware concurrency).
[[nodiscard]] inline Completeness completeness(const SurfaceSamples& samples, std::span<const Vec3> model_vertices,
                                               double radius_m, unsigned threads = 0) {
  detail::require_positive("completeness radius_m", radius_m);
  for (std::size_t i = 0; i < model_vertices.size(); ++i) validate_finite(model_vertices[i], "model vertex");
  const detail::PointKdTree tree(std::vector<Vec3>(model_vertices.begin(), model_vertices.end()));
  std::vector<char> hit(samples.size(), 0);
  detail::parallel_for(samples.size(), threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) hit[i] = tree.any_within(samples.points[i], radius_m) ? 1 : 0;
  });
  return count_completeness(samples, std::vector<bool>(hit.begin(), hit.end()));
}

/// Incremental completeness for a growing model: `add` marks every sample within r of each new model vertex. After
/// adding the vertex set V, the flags equal those of `completeness(samples, V, r)` (the relation |v − s| ≤ r is
/// symmetric). Each `add` takes the cheaper direction: with many uncovered samples, one radius query per new vertex
/// in a kd-tree over the samples; with few (fewer than kSampleDrivenRatio per new vertex), one query per uncovered
/// sample in a kd-tree over the new vertices. Borrows nothing. Not thread-safe for concurrent `add`.
class CoverageTracker {
public:
  static constexpr std::size_t kSampleDrivenRatio = 8;

  /// Throws InvalidArgument if r is not finite and > 0 or the samples are empty.
  CoverageTracker(const SurfaceSamples& samples, double radius_m)
      : samples_(samples), radius_m_(radius_m), covered_(samples.size(), false), uncovered_(samples.size()) {
    detail::require_positive("CoverageTracker radius_m", radius_m);
    detail::require(samples.size() > 0, "CoverageTracker: no samples");
    tree_ = detail::PointKdTree(samples.points);
  }

  /// Marks samples covered by `model_vertices`. Throws InvalidArgument (before any change) on a non-finite vertex.
  void add(std::span<const Vec3> model_vertices) {
    for (std::size_t i = 0; i < model_vertices.size(); ++i) validate_finite(model_vertices[i], "model vertex");
    if (model_vertices.empty()) return;
    if (uncovered_ < kSampleDrivenRatio * model_vertices.size()) {
      const detail::PointKdTree fresh(std::vector<Vec3>(model_vertices.begin(), model_vertices.end()));
      for (std::size_t s = 0; s < covered_.size(); ++s)
        if (!covered_[s] && fresh.any_within(samples_.points[s], radius_m_)) mark(s);
      return;
    }
    for (const Vec3& v : model_vertices)
      tree_.for_each_within(v, radius_m_, [&](std::size_t s, double) {
        if (!covered_[s]) mark(s);
      });
  }

  [[nodiscard]] const std::vector<bool>& covered() const { return covered_; }
  [[nodiscard]] Completeness completeness() const { return count_completeness(samples_, covered_); }
  [[nodiscard]] double radius_m() const { return radius_m_; }

private:
  void mark(std::size_t s) {
    covered_[s] = true;
    --uncovered_;
  }

  SurfaceSamples samples_;
  double radius_m_;
  std::vector<bool> covered_;
  std::size_t uncovered_;
  detail::PointKdTree tree_;
};

}  // namespace nbs
