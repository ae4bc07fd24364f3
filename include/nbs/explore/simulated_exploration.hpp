// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The parts of the scene-exploration loop (scene_exploration.hpp) for a simulated or real scanner: an OverviewSource
/// over any area-sensor ScanSimulator (a ring of views around the table), an ObjectModeler that runs a planner (default
/// `ThesisPlanner<>`: method C_H, laser stripe profiler) with run_loop on the cluster's box, and a driver wrapper that
/// feeds every scan into the scene's voxel space (the space v_h is validated against). nbs_explore wires them to Embree
/// (nbs::embree::SceneScanner, SimulatedScanner). Include planner headers first (planner/detail/components.hpp).

#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <numbers>
#include <optional>
#include <span>
#include <thread>
#include <utility>

#include "nbs/planner/nbs_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"
#include "nbs/driver/simulated_driver.hpp"
#include "nbs/explore/overview_ring_setting.hpp"
#include "nbs/explore/recognition_view.hpp"
#include "nbs/explore/scene_exploration.hpp"
#include "nbs/mesh/conversion.hpp"
#include "nbs/sensor/presets.hpp"

namespace nbs::explore {

/// A ScanDriver that integrates every acquired scan into `space` as well (borrowed): the scene's shared voxel space,
/// on `threads` threads where the space can (0 = hardware concurrency; the same space for any count).
template <ScanDriver Driver, VoxelSpace Space>
struct SpaceSharingDriver {
  Driver inner;
  Space* space;
  unsigned threads = 0;
  void move_to(const Pose& T_WS) { inner.move_to(T_WS); }
  [[nodiscard]] Pose current_pose() const { return inner.current_pose(); }
  Scan acquire(const LinearScanPath& path) {
    Scan s = inner.acquire(path);
    if (!s.empty()) (void)integrate_scan(*space, s, threads);
    return s;
  }
};

/// AimedOverviewSource: per step `frames_per_step` area-sensor frames around the target, all integrated into
/// `space` (with the thesis's update model one frame leaves surface voxels below p = 0.75, so v_h needs several), the
/// middle one returned. `overview(step)` looks from the ring (`setting`); `overview(step, boxes)` from the planned
/// recognition view of the boxes (plan_recognition_view over `space` with `aim`; the frames spread in azimuth around
/// it as on the ring), kept in `last_aimed`. Frame i of the whole run uses noise seed seed · 1000 + i. Frames are
/// integrated on `threads` threads where the space can (0 = hardware concurrency; the same space for any count).
/// Borrows scanner and space.
template <class Scanner, VoxelSpace Space>
  requires ScanSimulator<Scanner, AreaSensor>
struct OverviewRing {
  const Scanner* scanner;
  AreaSensor sensor;
  Space* space;
  OverviewRingSetting setting;
  std::uint64_t seed = 1;
  RecognitionViewSetting aim{};
  std::optional<RecognitionView> last_aimed{};  ///< the planned view of the last overview (none: the ring's)
  unsigned threads = 0;

  Scan overview(int step) {
    check();
    last_aimed.reset();
    return frames(step, setting.step_azimuth(step), setting.elevation_rad, setting.target);
  }
  /// The ring's view (overview(step)) if `boxes` is empty or no candidate reaches an unobserved voxel of them.
  Scan overview(int step, std::span<const Aabb> boxes) {
    check();
    last_aimed.reset();
    if (boxes.empty()) return overview(step);
    const RecognitionView v = plan_recognition_view(*space, sensor, boxes, setting, step, aim);
    if (!(v.score > 0.0)) return overview(step);
    Scan s = frames(step, v.azimuth_rad, v.elevation_rad, v.target);
    last_aimed = v;
    return s;
  }

private:
  void check() const {
    detail::require(scanner != nullptr && space != nullptr, "OverviewRing: no scanner or no scene space given");
    setting.validate();
  }
  Scan frames(int step, double azimuth_rad, double elevation_rad, const Vec3& target) {
    Scan middle;
    const int half = setting.frames_per_step / 2;
    for (int k = -half; k <= half; ++k) {
      const Vec3 eye = setting.eye(target, azimuth_rad + k * setting.frame_spread_rad, elevation_rad);
      const auto frame = static_cast<std::uint64_t>(step * setting.frames_per_step + k + half);
      Scan s = scanner->scan(LinearScanPath(Viewpoint::look_at(eye, target)), sensor, seed * 1000 + frame);
      (void)integrate_scan(*space, s, threads);
      if (k == 0) middle = std::move(s);
    }
    return middle;
  }
};

/// ObjectModeler: `Planner` (default `ThesisPlanner<>`: C_H with the thesis's stop; the scene results of
/// docs/evaluation.md rest on it; `NbsPlanner<>` models the scene test's bunny better, docs/scene.md; any planner built
/// as NbsPlanner from (Parameters, LaserStripeProfiler, box, PlannerSetting), e.g. `NbsPlanner<>`, the SGU_H default)
/// with the DLR laser stripe profiler over the hypothesis box, run_loop with a SimulatedDriver over `scanner` (noise
/// seed seed + the object's number), every scan also into `space`; n_abort = min(object_scans, the budget left). The
/// planner's own voxel space covers only the box; with `predict_occlusion` (default) its simulated beams are cut at the
/// first occupied voxel of the scene's `space` outside the box (VoxelSpaceOccluder), so that it predicts which views
/// its neighbours hide (Sec. 3.1); without, it does not (as the thesis's planner, which sees only its box).
template <class Scanner, VoxelSpace Space, class Planner = ThesisPlanner<>>
  requires ScanSimulator<Scanner, LaserStripeProfiler> &&
           std::constructible_from<Planner, Parameters, LaserStripeProfiler, Aabb, PlannerSetting>
struct NbsObjectModeler {
  const Scanner* scanner;
  Space* space;
  int object_scans = 20;
  std::uint64_t seed = 1;
  unsigned threads = 0;  ///< candidate evaluation and scan integration (0: hardware concurrency; plans do not depend on it)
  Parameters params{};
  int objects = 0;  ///< modeled so far
  bool predict_occlusion = true;  ///< cut the planner's beams at the scene's occupied voxels outside the box

  ModelingResult model(const scene::ObjectHypothesis& h, int max_scans) {
    detail::require(scanner != nullptr && space != nullptr, "NbsObjectModeler: no scanner or no scene space given");
    detail::require(object_scans >= 1, "NbsObjectModeler.object_scans must be >= 1, got ", object_scans);
    detail::require(max_scans >= 1, "NbsObjectModeler::model: max_scans must be >= 1, got ", max_scans);
    Parameters p = params;
    p.max_scans = std::min(object_scans, max_scans);
    PlannerSetting ps;
    ps.threads = threads > 0 ? threads : std::max(1U, std::thread::hardware_concurrency());
    ps.seed = seed;
    if (predict_occlusion) ps.occluder = VoxelSpaceOccluder<Space>(*space, h.box);
    Planner planner(p, presets::dlr_lsp(), h.box, ps);
    using Driver = SimulatedDriver<Scanner, LaserStripeProfiler>;
    SpaceSharingDriver<Driver, Space> driver{Driver(*scanner, planner.sensor(), seed + static_cast<std::uint64_t>(++objects)),
                                             space, ps.threads};
    SimulationSetting ss;
    ss.seed = seed;
    ss.max_scans = p.max_scans;
    const SimulationResult r = run_loop(planner, driver, ss);
    ModelingResult m;
    m.mesh = to_indexed_mesh(planner.mesh());
    m.coverage = planner.estimated_coverage();
    m.scans = static_cast<int>(r.records.size());
    m.done = r.stop == LoopStop::done;
    return m;
  }
};

}  // namespace nbs::explore
