// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// One run of the experiment (Sec. 4.7.2): a seeded initial scan, then plan → scan → integrate until n_abort scans
/// (the thesis does not stop at n_s but continues to n_abort to report c_a(30)), measuring after every scan ĉ_m,
/// d̄_m, c_a, c_b, ē, l_s, t_nbs, candidates and mode. Single-threaded and deterministic in (method, seed); only
/// t_nbs is wall-clock time.

// The planner headers must come before any utility header (see nbs/planner/detail/components.hpp).
#include "nbs/planner/runtime_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"

#include <cstdint>
#include <optional>
#include <numbers>
#include <string>
#include <vector>

#include "common/options.hpp"
#include "common/robot_option.hpp"
#include "eval/records.hpp"
#include "nbs/driver/pose_error_driver.hpp"
#include "nbs/sim/pose_error.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/sim/ground_truth.hpp"
#include "nbs/core/detail/random.hpp"

namespace nbs::eval {

/// Seed of run r: depends on (base seed, r) only, so every method sees the same initial scan and noise in run r.
[[nodiscard]] inline std::uint64_t run_seed(std::uint64_t base, int run) {
  return nbs::detail::splitmix64(base ^ nbs::detail::splitmix64(0x4E42535F4556414CULL + static_cast<std::uint64_t>(run)));
}

/// The bounding box of the unknown area for a normalised object: its bounds grown by size/16 sideways and on top
/// (1 cm at 0.16 m), bottom on the pedestal z = 0 (Sec. 4.1).
[[nodiscard]] inline Aabb unknown_area_of(const IndexedMesh& mesh, double size_m) {
  Aabb box = mesh.bounds();
  const double m = size_m / 16.0;
  box.min -= Vec3(m, m, 0.0);
  box.max += Vec3(m, m, m);
  return box;
}

/// Shared, read-only state of all runs on one mesh.
struct RunContext {
  const embree::SimulatedScanner& scanner;
  const GroundTruth& truth;
  Parameters params;
  LaserStripeProfiler sensor;
  Aabb unknown_area;
  int n_abort = 30;
  double c_obs = 0.0;
  PlannerSetting setting{};  ///< keep_exploring of the config; threads and seed are set per run
  RuntimeModels models{};    ///< mesh, ĉ_m form, selection options and stop rule of the config (and the registration method)
  /// --pose-error / --registration: the error of each run (seed derived from the run's) and whether the records
  /// carry the pose fields.
  tools::PoseErrorOptions pose{};
  /// --robot: the arm every run plans for (RuntimePlanner::set_robot); the records then carry the robot fields.
  std::optional<tools::LoadedRobot> robot{};
};

/// The double-surface threshold: 2σ of the sensor's range noise (Eq. 4.39 for the DLR LSP) at the planner's
/// standoff distance d_s (PlannerSetting::standoff_m, default the middle of the working range: 0.3 m, σ ≈ 1.14 mm
/// for the DLR LSP).
[[nodiscard]] inline double double_surface_threshold_m(const RuntimePlanner& planner) {
  const double d_s = std::visit([](const auto& p) { return p.standoff(); }, planner.variant());
  return 2.0 * planner.sensor().noise.sigma_m(d_s);
}

/// Runs method `m`, run index `run` with seed `seed`. Throws what the planner or scanner throw.
[[nodiscard]] inline RunRecord run_one(const RunContext& ctx, const Method& m, int run, std::uint64_t seed) {
  PlannerSetting setting = ctx.setting;
  setting.threads = 1;
  setting.seed = seed;
  Parameters params = ctx.params;
  params.max_scans = ctx.n_abort;
  RuntimePlanner planner(m, params, ctx.sensor, ctx.unknown_area, setting, ctx.models);
  if (ctx.robot) planner.set_robot(ctx.robot->robot, ctx.robot->start, ctx.robot->setting);
  // Keep planning after the stop rule holds (Sec. 4.7.2: "we do not abort the algorithm after n_s"): the planner
  // itself stops only at n_abort; the set-up's stop rule judges n_s below, on the planner's own progress (ĉ_m
  // history included).
  const SelectableTermination quality(params, ctx.models.stop_rule);
  std::visit([&](auto& p) { p.termination = SelectableTermination(params, StopRule::max_scans); }, planner.variant());
  // The scans go through the pose-error decorator (zero error without --pose-error: bit-identical scans).
  PoseErrorDriver driver(SimulatedDriver(ctx.scanner, planner.sensor(), seed), ctx.pose.setting(seed));

  RunRecord rec;
  rec.method = format_method(m);
  rec.run = run;
  rec.seed = seed;
  rec.n_abort = ctx.n_abort;
  rec.n_s = ctx.n_abort;
  rec.c_obs = ctx.c_obs;
  rec.robot = ctx.robot.has_value();
  CoverageTracker tracker = ctx.truth.tracker();
  std::size_t seen_vertices = 0;
  double sum_sq = 0.0, sum_sq_rel = 0.0;
  // With a pose error: E₁⁻¹, the map from the model's frame (where the first scan was placed) to the true frame.
  Pose model_to_true = Pose::Identity();
  // Distances to the true surface of `points` mapped by `to_true` (empty for no points).
  const auto true_distances = [&](const std::vector<Vec3>& points, const Pose& to_true) {
    std::vector<Vec3> mapped(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) mapped[i] = to_true * points[i];
    return mapped.empty() ? std::vector<double>{} : ctx.truth.distance().distances(mapped, 1);
  };
  const auto add_sq = [&](const std::vector<Vec3>& points, const Pose& to_true, double& sum) {
    for (double d : true_distances(points, to_true)) sum += d * d;
  };
  bool reached = false;
  std::vector<Vec3> fresh;
  const auto on_scan = [&](const ScanRecord& r) {
    const StreamingMesh& mesh = planner.mesh();
    fresh.clear();
    for (std::size_t v = seen_vertices; v < mesh.vertex_count(); ++v)
      fresh.push_back(mesh.position(static_cast<VertexId>(v)));
    // Vertices are only appended. Each is counted once, at its position after the scan that added it: with the
    // noise-robust mesh a vertex that gets its normal in a later scan is counted at its measured point, not at
    // its later PCA-plane projection (docs/evaluation.md, c_a and ē).
    seen_vertices = mesh.vertex_count();
    tracker.add(fresh);
    add_sq(fresh, Pose::Identity(), sum_sq);
    if (ctx.pose.active()) {
      if (r.scan == 1) model_to_true = driver.last_error().true_to_reported.inverse();
      add_sq(fresh, model_to_true, sum_sq_rel);
    }
    const Completeness c = tracker.completeness();
    ScanRow row;
    row.c_m = r.integration.estimated_coverage;
    row.d_m = r.integration.mean_density;
    row.c_a = c.c_a();
    row.c_b = c.c_b();
    row.e_bar_m = seen_vertices ? std::sqrt(sum_sq / static_cast<double>(seen_vertices)) : 0.0;
    row.l_s_m = r.total_path_length_m;
    row.t_nbs_s = r.planning.t_nbs_s;
    row.candidates = r.planning.evaluated;
    row.mode = r.scan == 1 ? "init" : std::string(to_string(r.planning.mode));
    row.a_filled_m2 = filled_area(mesh);
    std::visit(
        [&](const auto& p) {
          for (const UnseenSample& u : p.utility_context().unseen_surface) {
            row.a_unseen_m2 += u.area_m2;
            if (u.edge_distance_m >= 0.005) row.a_unseen_5mm_m2 += u.area_m2;
            if (u.edge_distance_m >= 0.010) row.a_unseen_10mm_m2 += u.area_m2;
          }
        },
        planner.variant());
    row.unreachable_candidates = r.planning.unreachable;
    if (r.transfer) {
      row.transfer_joint_rad = r.transfer->joint_length_rad;
      row.transfer_sensor_m = r.transfer->sensor_length_m;
      row.t_motion_s = r.transfer->t_plan_s;
      row.transfer_failures = r.transfer->failed_attempts;
    }
    if (ctx.pose.active()) {
      const RegistrationResult& reg = r.integration.registration;
      const PoseErrorRecord& e = driver.last_error();
      const PoseResidual res = residual_pose_error(e.true_to_reported, reg.correction, e.true_centroid);
      row.pose_t_mm = 1e3 * res.translation_m;
      row.pose_r_deg = res.rotation_rad * 180.0 / std::numbers::pi;
      const PoseResidual rel = residual_pose_error(e.true_to_reported, model_to_true * reg.correction, e.true_centroid);
      row.pose_rel_t_mm = 1e3 * rel.translation_m;
      row.pose_rel_r_deg = rel.rotation_rad * 180.0 / std::numbers::pi;
      row.e_bar_rel_m = seen_vertices ? std::sqrt(sum_sq_rel / static_cast<double>(seen_vertices)) : 0.0;
      row.registration = std::string(to_string(reg.status));
      row.icp_s = reg.t_s;
    }
    if (r.scan == 1) rec.initial_index = r.initial_index;
    rec.scans.push_back(std::move(row));
    if (!reached && quality.done(planner.progress())) {
      reached = true;
      rec.n_s = r.scan;
    }
  };
  SimulationSetting sim;
  sim.seed = seed;
  sim.max_scans = ctx.n_abort;
  // --robot: the arm's transfers between scans are planned (OMPL, against the voxel space after each scan) and
  // recorded; a failed one excludes its candidate, the next best is tried (--transfer-retries); when all fail the
  // run ends ("transfer_failed").
  if (ctx.robot) sim.transfer_retries = ctx.robot->transfer_retries;
  const SimulationResult res = ctx.robot ? run_loop(planner, driver, tools::transfer_planner(*ctx.robot), sim, on_scan)
                                         : run_loop(planner, driver, sim, on_scan);
  if (ctx.pose.active()) {
    rec.pose = true;
    const StreamingMesh& mesh = planner.mesh();
    std::vector<Vec3> all(mesh.vertex_count());
    for (std::size_t v = 0; v < all.size(); ++v) all[v] = mesh.position(static_cast<VertexId>(v));
    const double limit = double_surface_threshold_m(planner);
    // Share of the vertices, mapped by `to_true`, farther than `limit` from the true surface.
    const auto far_share = [&](const Pose& to_true) {
      std::size_t far = 0;
      for (double d : true_distances(all, to_true)) far += d > limit ? 1 : 0;
      return all.empty() ? 0.0 : static_cast<double>(far) / static_cast<double>(all.size());
    };
    rec.double_surface_share = far_share(Pose::Identity());
    rec.double_surface_share_rel = far_share(model_to_true);
  }
  // n_abort scans taken is "max_scans" even when the termination criterion fired on the last one (the loop then
  // says done); an earlier end is the loop's stop (to_string(LoopStop)).
  rec.stop = static_cast<int>(res.records.size()) >= ctx.n_abort ? "max_scans" : to_string(res.stop);
  return rec;
}

}  // namespace nbs::eval
