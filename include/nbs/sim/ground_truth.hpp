// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// GroundTruth: the known object of a simulation run with everything the metrics need built once — surface samples,
/// the exact distance structure — so evaluating a model after each scan is cheap (Sec. 4.7.2, Tab. 5.2).

#include <cstdint>
#include <span>

#include "nbs/core/parameters.hpp"
#include "nbs/sim/completeness.hpp"
#include "nbs/sim/mesh_distance.hpp"
#include "nbs/sim/observability.hpp"
#include "nbs/sim/surface_samples.hpp"

namespace nbs {

/// Owns the ground-truth mesh (inside its MeshDistance), its samples and the completeness radius.
/// Thread-safety: const member functions may be called concurrently.
class GroundTruth {
public:
  struct Setting {
    double sample_density_per_m2 = 4.0e6;  ///< ≈ 0.5 mm mean sample spacing, well below r = 3 mm.
    std::uint64_t seed = 1;                ///< seed of the surface samples.
    double completeness_radius_m = Parameters{}.completeness_radius_m;  ///< r of c_a / c_b (3 mm, Sec. 4.7.2).
    BottomRule bottom{};                   ///< which samples the pedestal hides.
  };

  /// Throws InvalidArgument on an invalid mesh or setting.
  GroundTruth(const IndexedMesh& mesh, const Setting& setting)
      : setting_((detail::require_positive("GroundTruth completeness_radius_m", setting.completeness_radius_m),
                  setting)),
        distance_(mesh),
        samples_(sample_surface_density(distance_.mesh(), setting.sample_density_per_m2, setting.seed,
                                        setting.bottom)) {}
  explicit GroundTruth(const IndexedMesh& mesh) : GroundTruth(mesh, Setting{}) {}

  [[nodiscard]] const IndexedMesh& mesh() const { return distance_.mesh(); }
  [[nodiscard]] const SurfaceSamples& samples() const { return samples_; }
  [[nodiscard]] const MeshDistance& distance() const { return distance_; }
  [[nodiscard]] const Setting& setting() const { return setting_; }

  /// c_a / c_b of a model with vertices `model_vertices` (one-shot).
  [[nodiscard]] Completeness completeness(std::span<const Vec3> model_vertices, unsigned threads = 0) const {
    return nbs::completeness(samples_, model_vertices, setting_.completeness_radius_m, threads);
  }
  /// An incremental tracker for a growing model (feed it each scan's new vertices).
  [[nodiscard]] CoverageTracker tracker() const { return CoverageTracker(samples_, setting_.completeness_radius_m); }
  /// RMS error ē of model points to the true surface, metres (Tab. 5.2).
  [[nodiscard]] double rms_error(std::span<const Vec3> model_points, unsigned threads = 0) const {
    return distance_.rms_error(model_points, threads);
  }
  /// Observability ceiling; `caster` must cast against mesh().
  template <RayCaster R>
  [[nodiscard]] Observability observability(const R& caster, const ObservabilitySettings& s = {}) const {
    return nbs::observability(samples_, caster, s);
  }

private:
  Setting setting_;
  MeshDistance distance_;
  SurfaceSamples samples_;
};

}  // namespace nbs
