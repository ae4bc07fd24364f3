// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Planned recognition views (Sec. 3.1: "for recognition views, NBVs may be planned with the same planner"): when a
/// cluster's pose is ambiguous (a known model whose telling part — the mug's handle — is hidden), the next overview
/// looks from where the most unobserved voxels of its box can be seen, instead of the ring's next fixed view.
/// Candidates on a sphere around the boxes, scored by `evaluate_candidates` over the scene's voxel space (its
/// occupied voxels — the neighbours — stop the beams, so a view the neighbours block scores low).

#include <cmath>
#include <cstddef>
#include <numbers>
#include <span>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/scan_path.hpp"
#include "nbs/core/viewpoint.hpp"
#include "nbs/explore/overview_ring_setting.hpp"
#include "nbs/sensor/area_sensor.hpp"
#include "nbs/space/concepts.hpp"
#include "nbs/utility/evaluate_candidates.hpp"
#include "nbs/utility/voxel_visit.hpp"

namespace nbs::explore {

/// UtilityTerm: the number of distinct unobserved voxels inside any of `boxes` (keys of the evaluated space) that a
/// candidate's beams reach (each beam stops at its first occupied voxel).
struct UnobservedInBoxes {
  std::vector<KeyBox> boxes;
  std::size_t count = 0;
  void begin_candidate(std::size_t) { count = 0; }
  void begin_ray() {}
  void visit(const VoxelVisit& v) {
    if (!v.first_visit || v.observed) return;
    for (const KeyBox& b : boxes)
      if (b.contains(v.key)) {
        ++count;
        return;
      }
  }
  void end_ray(const RayEnd&) {}
  [[nodiscard]] double value() const { return static_cast<double>(count); }
  [[nodiscard]] bool first_visits_only() const { return true; }
};

/// Where the planned recognition views may look from: eyes at `OverviewRingSetting::distance_m` from the centre of
/// the boxes, at `azimuths` azimuths (from the ring's step azimuth on, evenly spaced) × the elevations below.
struct RecognitionViewSetting {
  int azimuths = 24;                                             ///< ≥ 1
  std::vector<double> elevations_rad{35.0 * std::numbers::pi / 180.0, 60.0 * std::numbers::pi / 180.0};
  RaySampling sampling{8, 8};                                    ///< beam sub-sampling of the scoring
  unsigned threads = 1;                                          ///< scoring threads (the choice does not depend on it)

  void validate() const {
    detail::require(azimuths >= 1, "RecognitionViewSetting.azimuths must be >= 1, got ", azimuths);
    detail::require(!elevations_rad.empty(), "RecognitionViewSetting.elevations_rad must not be empty");
    for (const double e : elevations_rad)
      detail::require(std::isfinite(e) && e > 0.0 && e < 0.5 * std::numbers::pi,
                      "RecognitionViewSetting.elevations_rad must be in (0, pi/2) (above the table), got ", e);
    sampling.validate();
    detail::require(threads >= 1, "RecognitionViewSetting.threads must be >= 1, got ", threads);
  }
};

/// A planned recognition view: the eye, the point it looks at, its azimuth and elevation around that point, and
/// its score (unobserved voxels of the boxes it reaches; 0: no candidate reaches any).
struct RecognitionView {
  Vec3 eye = Vec3::Zero();
  Vec3 target = Vec3::Zero();
  double azimuth_rad = 0.0;
  double elevation_rad = 0.0;
  double score = 0.0;
};

/// The candidate from which `sensor` reaches the most unobserved voxels of `boxes` in `space` (boxes clipped to the
/// space's key range); ties go to the lower candidate (elevation first, then azimuth from the ring's azimuth of
/// `step` on). World frame, metres. Throws InvalidArgument if `boxes` is empty or holds an empty or non-finite box,
/// or a setting is invalid.
template <VoxelSpace Space>
[[nodiscard]] RecognitionView plan_recognition_view(const Space& space, const AreaSensor& sensor,
                                                    std::span<const Aabb> boxes, const OverviewRingSetting& ring,
                                                    int step, const RecognitionViewSetting& setting = {}) {
  ring.validate();
  setting.validate();
  detail::require(!boxes.empty(), "plan_recognition_view: no box to look at");
  Aabb all;
  UnobservedInBoxes term;
  for (const Aabb& b : boxes) {
    detail::require(!b.empty() && b.min.allFinite() && b.max.allFinite(),
                    "plan_recognition_view: a box is empty or not finite");
    all.extend(b.min);
    all.extend(b.max);
    term.boxes.push_back(space.grid().key_box(b));
  }
  const Vec3 target = all.center();
  std::vector<LinearScanPath> paths;
  std::vector<RecognitionView> views;
  for (const double el : setting.elevations_rad)
    for (int k = 0; k < setting.azimuths; ++k) {
      RecognitionView v;
      v.azimuth_rad = ring.step_azimuth(step) + 2.0 * std::numbers::pi * k / setting.azimuths;
      v.elevation_rad = el;
      v.target = target;
      v.eye = ring.eye(target, v.azimuth_rad, el);
      paths.emplace_back(Viewpoint::look_at(v.eye, target));
      views.push_back(v);
    }
  EvaluationSetting eval(setting.threads, setting.sampling);
  const EvaluationResult r = evaluate_candidates(paths, sensor, space, term, eval);
  RecognitionView best = views[r.best];
  best.score = r.values[r.best];
  return best;
}

}  // namespace nbs::explore
