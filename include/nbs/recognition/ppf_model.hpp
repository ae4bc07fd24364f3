// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// PpfModel: the global model description of Drost et al. (2010) (thesis Sec. 3.4): every ordered pair of the
/// subsampled model points, keyed by its discretised point-pair feature (Eq. 3.9), stored with the reference index
/// and the pair angle α_m. Immutable after construction; the build is deterministic.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <span>
#include <vector>

#include "nbs/core/detail/cell_key.hpp"
#include "nbs/core/error.hpp"
#include "nbs/recognition/oriented_points.hpp"
#include "nbs/recognition/point_pair_feature.hpp"

namespace nbs {

/// Settings of the model description (defaults: Drost et al. 2010).
struct PpfModelSetting {
  double distance_step_ratio = 0.05;                    ///< τ_d: d_dist = τ_d · model diameter, in (0, 1].
  double angle_step_rad = 2.0 * std::numbers::pi / 30;  ///< d_angle, radians, in [π/4096, π].
  std::size_t max_points = 2000;                        ///< most subsampled model points (pairs grow as n²).

  void validate() const {
    detail::require(std::isfinite(distance_step_ratio) && distance_step_ratio > 0.0 && distance_step_ratio <= 1.0,
                    "PpfModelSetting::distance_step_ratio must be in (0, 1], got ", distance_step_ratio);
    PpfQuantizer{1.0, angle_step_rad}.validate();
    detail::require(max_points >= 2, "PpfModelSetting::max_points must be >= 2, got ", max_points);
  }
};

/// One hash-table entry: the model reference point and the angle α_m of the pair, radians in (−π, π].
struct PpfEntry {
  std::uint32_t reference = 0;
  float alpha = 0.0F;
};

/// The model description. Thread-safety: immutable; const members may run concurrently.
class PpfModel {
public:
  /// Builds the description of `model` (model frame, metres). The diameter is the diagonal of the points'
  /// axis-aligned bounding box (≥ the true diameter, at most √3 times it). Throws InvalidArgument if the model or setting is invalid, the
  /// diameter is 0, or the subsampled model has fewer than 2 or more than max_points points.
  explicit PpfModel(const OrientedPoints& model, const PpfModelSetting& setting = {}) : setting_(setting) {
    setting.validate();
    model.validate("PpfModel: model");
    diameter_ = diameter_of(model.points);
    detail::require(diameter_ > 0.0, "PpfModel: model diameter is ", diameter_, " (all points coincide)");
    quantizer_ = {setting.distance_step_ratio * diameter_, setting.angle_step_rad};
    points_ = grid_subsample(model, quantizer_.distance_step_m);
    const std::size_t n = points_.size();
    detail::require(n >= 2 && n <= setting.max_points, "PpfModel: ", n,
                    " subsampled model points, need 2 to max_points = ", setting.max_points);
    build_table();
  }

  /// The stored table of a model description (ppf_model_io.hpp reads and writes it): the subsampled points, the
  /// distinct keys in ascending order, CSR offsets (bucket b holds entries[offsets[b], offsets[b + 1])) and the
  /// entries.
  struct Table {
    PpfModelSetting setting;
    double diameter_m = 0.0;
    OrientedPoints points;
    std::vector<std::uint64_t> keys;
    std::vector<std::uint32_t> offsets;
    std::vector<PpfEntry> entries;
  };

  /// Restores a description from its table without recomputing the pairs. Checks the table's structure (not that
  /// the entries are the pairs of the points): throws InvalidArgument naming the first inconsistency — setting,
  /// diameter, points, keys not strictly ascending, offsets not rising from 0 to the entry count, a reference out of
  /// range or an α_m not in [−π, π].
  explicit PpfModel(Table t) : setting_(t.setting) {
    setting_.validate();
    detail::require(std::isfinite(t.diameter_m) && t.diameter_m > 0.0, "PpfModel table: diameter ", t.diameter_m,
                    " must be finite and > 0");
    t.points.validate("PpfModel table: points");
    const std::size_t n = t.points.size();
    detail::require(n >= 2 && n <= setting_.max_points, "PpfModel table: ", n, " points, need 2 to max_points = ",
                    setting_.max_points);
    detail::require(t.offsets.size() == t.keys.size() + 1, "PpfModel table: ", t.offsets.size(), " offsets for ",
                    t.keys.size(), " keys");
    detail::require(t.offsets.front() == 0 && t.offsets.back() == t.entries.size(), "PpfModel table: offsets span [",
                    t.offsets.front(), ", ", t.offsets.back(), "], entries ", t.entries.size());
    for (std::size_t b = 0; b < t.keys.size(); ++b) {
      detail::require(t.offsets[b] < t.offsets[b + 1], "PpfModel table: bucket ", b, " is empty or offsets fall");
      detail::require(b == 0 || t.keys[b - 1] < t.keys[b], "PpfModel table: key ", b, " is not above key ", b - 1);
    }
    for (std::size_t k = 0; k < t.entries.size(); ++k)
      detail::require(t.entries[k].reference < n && std::abs(t.entries[k].alpha) <= 3.1416F, "PpfModel table: entry ",
                      k, " (reference ", t.entries[k].reference, ", alpha ", t.entries[k].alpha, ") out of range");
    diameter_ = t.diameter_m;
    quantizer_ = {setting_.distance_step_ratio * diameter_, setting_.angle_step_rad};
    points_ = std::move(t.points);
    keys_ = std::move(t.keys);
    offsets_ = std::move(t.offsets);
    entries_ = std::move(t.entries);
    align_.resize(n);
    for (std::size_t i = 0; i < n; ++i) align_[i] = align_normal_to_x(points_.normals[i]);
    buckets_ = detail::CellKeyMap(keys_.size() + 1);
    for (std::size_t b = 0; b < keys_.size(); ++b) buckets_.try_emplace(keys_[b], static_cast<std::uint32_t>(b));
  }

  /// A copy of the table (Table above); PpfModel(table()) gives an equal description.
  [[nodiscard]] Table table() const { return {setting_, diameter_, points_, keys_, offsets_, entries_}; }

  [[nodiscard]] double diameter_m() const { return diameter_; }
  [[nodiscard]] const PpfQuantizer& quantizer() const { return quantizer_; }
  [[nodiscard]] const PpfModelSetting& setting() const { return setting_; }
  /// The subsampled model points (model frame), indexed by PpfEntry::reference.
  [[nodiscard]] const OrientedPoints& points() const { return points_; }
  /// R_{m→g} of reference point i (align_normal_to_x of its normal).
  [[nodiscard]] const Mat3& alignment(std::size_t i) const { return align_[i]; }
  /// Number of stored pairs (n · (n − 1) minus coincident pairs).
  [[nodiscard]] std::size_t pair_count() const { return entries_.size(); }
  /// Number of distinct feature keys.
  [[nodiscard]] std::size_t key_count() const { return offsets_.empty() ? 0 : offsets_.size() - 1; }

  /// The entries of a feature key (empty if absent), in (reference, second point) order.
  [[nodiscard]] std::span<const PpfEntry> find(std::uint64_t key) const {
    const std::uint32_t b = buckets_.find(key);
    if (b == detail::CellKeyMap::kNone) return {};
    return {entries_.data() + offsets_[b], entries_.data() + offsets_[b + 1]};
  }

private:
  [[nodiscard]] static double diameter_of(const std::vector<Vec3>& p) {
    Vec3 lo = p.front(), hi = p.front();
    for (const Vec3& q : p) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
    return (hi - lo).norm();
  }

  void build_table() {
    const std::size_t n = points_.size();
    align_.resize(n);
    for (std::size_t i = 0; i < n; ++i) align_[i] = align_normal_to_x(points_.normals[i]);
    struct Keyed {
      std::uint64_t key;
      PpfEntry entry;
    };
    std::vector<Keyed> all;
    all.reserve(n * (n - 1));
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < n; ++j) {
        if (i == j || points_.points[i] == points_.points[j]) continue;
        const Eigen::Vector4d f =
            point_pair_feature(points_.points[i], points_.normals[i], points_.points[j], points_.normals[j]);
        const double a = pair_angle(align_[i], points_.points[i], points_.points[j]);
        all.push_back({quantizer_.key(f), {static_cast<std::uint32_t>(i), static_cast<float>(a)}});
      }
    std::stable_sort(all.begin(), all.end(), [](const Keyed& a, const Keyed& b) { return a.key < b.key; });
    entries_.reserve(all.size());
    buckets_ = detail::CellKeyMap(all.size() / 4 + 1);
    for (std::size_t k = 0; k < all.size(); ++k) {
      if (k == 0 || all[k].key != all[k - 1].key) {
        buckets_.try_emplace(all[k].key, static_cast<std::uint32_t>(offsets_.size()));
        keys_.push_back(all[k].key);
        offsets_.push_back(static_cast<std::uint32_t>(k));
      }
      entries_.push_back(all[k].entry);
    }
    offsets_.push_back(static_cast<std::uint32_t>(entries_.size()));
  }

  PpfModelSetting setting_;
  double diameter_ = 0.0;
  PpfQuantizer quantizer_;
  OrientedPoints points_;
  std::vector<Mat3> align_;
  std::vector<PpfEntry> entries_;         // grouped by key, CSR
  std::vector<std::uint64_t> keys_;       // key of bucket b, ascending
  std::vector<std::uint32_t> offsets_;    // bucket b holds entries_[offsets_[b], offsets_[b + 1])
  detail::CellKeyMap buckets_;            // key → bucket
};

}  // namespace nbs
