// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// OctoMap-compatible update model: clamped log-odds, +log(p_hit/(1−p_hit)) for the end-point voxel of a beam,
/// +log(p_miss/(1−p_miss)) for every voxel the beam passes (Hornung et al., 2013). Same float arithmetic and the
/// same defaults as OctoMap 1.9 (hit 0.7, miss 0.4, clamping 0.1192 / 0.971, occupancy threshold 0.5), so the
/// native space and OctoMap classify voxels identically.

#include <cmath>
#include <optional>

#include "nbs/core/error.hpp"
#include "nbs/space/update_model.hpp"

namespace nbs {

/// State of the log-odds model: l = log(p / (1 − p)) as float; 0 = unknown (p = 0.5).
struct LogOddsState {
  float log_odds = 0.0f;
  [[nodiscard]] friend bool operator==(const LogOddsState&, const LogOddsState&) = default;
};

/// Clamped log-odds update (OctoMap). Thread-safety: const members are safe to call concurrently.
class LogOddsModel {
public:
  using State = LogOddsState;
  struct Setting {
    double prob_hit = 0.7;              ///< P(occ) for the voxel containing the end point
    double prob_miss = 0.4;             ///< P(occ) for voxels the beam passes
    double clamp_min = 0.1192;          ///< lower clamping probability
    double clamp_max = 0.971;           ///< upper clamping probability
    double occupancy_threshold = 0.5;   ///< p ≥ this: occupied
    /// Throws InvalidArgument unless 0 < clamp_min ≤ prob_miss < 0.5 < prob_hit ≤ clamp_max < 1 and the
    /// threshold is in (0, 1).
    void validate() const {
      detail::require(clamp_min > 0.0 && clamp_min <= prob_miss && prob_miss < 0.5 && prob_hit > 0.5 &&
                          prob_hit <= clamp_max && clamp_max < 1.0,
                      "LogOddsModel: need 0 < clamp_min <= prob_miss < 0.5 < prob_hit <= clamp_max < 1, got ",
                      clamp_min, ", ", prob_miss, ", ", prob_hit, ", ", clamp_max);
      detail::require(occupancy_threshold > 0.0 && occupancy_threshold < 1.0,
                      "LogOddsModel: occupancy_threshold must be in (0, 1), got ", occupancy_threshold);
    }
  };
  /// Nothing per beam.
  struct Beam {};

  LogOddsModel() : LogOddsModel(Setting{}) {}
  explicit LogOddsModel(const Setting& s) : setting_(s) {
    s.validate();
    hit_ = logodds(s.prob_hit);
    miss_ = logodds(s.prob_miss);
    min_ = logodds(s.clamp_min);
    max_ = logodds(s.clamp_max);
    occupied_ = logodds(s.occupancy_threshold);
  }

  [[nodiscard]] const Setting& setting() const { return setting_; }

  /// Per-beam data; never rejects a beam.
  [[nodiscard]] std::optional<Beam> beam(double /*range_m*/, const Vec3& /*unit_direction*/) const { return Beam{}; }
  /// Only the end-point voxel is updated as a hit.
  [[nodiscard]] double band_half_width_m(const Beam&) const { return 0.0; }

  /// Hit update of a voxel in the band; only the end-point voxel (`end_voxel`) changes.
  VoxelUpdate update_band(State& s, const Beam&, double /*offset_m*/, bool end_voxel) const {
    if (!end_voxel) return VoxelUpdate::unchanged;
    add(s, hit_);
    return VoxelUpdate::updated;
  }
  /// Miss update of a voxel the beam passes.
  VoxelUpdate update_free(State& s, const Beam&) const {
    add(s, miss_);
    return VoxelUpdate::updated;
  }

  /// Log-odds of occupancy.
  [[nodiscard]] double log_odds(const State& s) const { return s.log_odds; }
  /// p = 1 − 1 / (1 + exp(l)), as OctoMap's getOccupancy().
  [[nodiscard]] double probability(const State& s) const { return 1.0 - 1.0 / (1.0 + std::exp(s.log_odds)); }
  /// l ≥ log-odds(occupancy_threshold), as OctoMap's isNodeOccupied(); the unknown state (l = 0 exactly) is never
  /// occupied (OctoMap has no node there).
  [[nodiscard]] bool occupied(const State& s) const { return s.log_odds >= occupied_ && s.log_odds != 0.0f; }

  /// OctoMap's logodds(): float(log(p / (1 − p))).
  [[nodiscard]] static float logodds(double p) { return static_cast<float>(std::log(p / (1.0 - p))); }

private:
  void add(State& s, float delta) const {
    // OctoMap: early exit when already clamped in the update's direction, else add then clamp.
    if ((delta >= 0 && s.log_odds >= max_) || (delta <= 0 && s.log_odds <= min_)) return;
    s.log_odds += delta;
    if (s.log_odds < min_) s.log_odds = min_;
    if (s.log_odds > max_) s.log_odds = max_;
  }

  Setting setting_;
  float hit_ = 0, miss_ = 0, min_ = 0, max_ = 0, occupied_ = 0;
};

}  // namespace nbs
