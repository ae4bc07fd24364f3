// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// NbsPlanner: the Next-Best-Scan planner of Fig. 4.1 composed from policies at compile time — voxel space (Sec.
/// 3.3.2), streaming mesh (Sec. 3.3.1), candidate search (Boundary Search Secs. 4.2–4.3, Hole Rescan Sec. 4.4,
/// sphere Sec. 4.7.2), replanning (Alg. 3), utility (Sec. 4.5.3), termination and process control (Sec. 4.6).
///
/// Use: `NbsPlanner<> p(params, presets::dlr_lsp(), unknown_area);` then, per scan, `p.integrate(scan)` and
/// `p.next_best_scan()` until `p.done()`. Frames: world (types.hpp), metres, seconds.
/// Thread-safety: not thread-safe; candidate evaluation and the voxel space's integrate (a ParallelIntegratingSpace)
/// run on `setting().threads` std::threads, with results identical for any thread count (so is every plan: the rest
/// is sequential and deterministic).

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "nbs/coverage/coverage_estimator.hpp"
#include "nbs/planner/detail/components.hpp"
#include "nbs/planner/detail/planner_parts.hpp"
#include "nbs/planner/planner_types.hpp"
#include "nbs/planner/robot_policy.hpp"
#include "nbs/planner/search_policy.hpp"
#include "nbs/planner/utility_policy.hpp"
#include "nbs/core/detail/random.hpp"
#include "nbs/registration/registration.hpp"

namespace nbs {

/// A mesh the planner can own: an EdgeMesh with relative density (d̄_m), current-scan tracking (M_cur) and
/// `integrate(scan)` returning the number of meshed points, built as Mesh(params, unknown_area) (pass-through box):
/// the mesh type chooses its own settings (StreamingMesh: the thesis's Sec. 3.3.1; NoiseRobustStreamingMesh: the
/// noise-robust options). A mesh constructible from a settings object can also be given one
/// (NbsPlanner(params, sensor, box, setting, mesh_settings)).
template <class M>
concept PlannerMesh = DensityMesh<M> && TracksCurrentScan<M> && std::constructible_from<M, const Parameters&, const Aabb&> &&
                      requires(M& m, const Scan& scan) {
  { m.integrate(scan) } -> std::convertible_to<std::size_t>;
};

/// Capability of a PlannerMesh: `m.check_scan(scan)` throws what `m.integrate(scan)` would throw for a bad scan and
/// changes nothing, so the planner can check before it changes the voxel space.
template <class M>
concept ChecksScans = requires(const M& m, const Scan& scan) { m.check_scan(scan); };

/// A sensor the planner can plan for: candidate rays can be simulated and SensorGeometry::of describes it.
template <class S>
concept PlannerSensor = CandidateRaySensor<S> && requires(const S& s) {
  { SensorGeometry::of(s) } -> std::same_as<SensorGeometry>;
};

/// A collision checker that snapshots the voxel space and must see each new scan: `c.update(space)` (e.g.
/// nbs::fcl::FclCollisionChecker). The planner calls it after every integrated scan.
template <class C, class Space>
concept SpaceTrackingCollisionChecker = CollisionChecker<C> && requires(C& c, const Space& s) { c.update(s); };

/// Every policy of NbsPlanner, checked once at the class (each concept names what its policy lacks).
template <class Utility, class Search, class Sensor, class Collision, class Termination, class Space, class Mesh,
          class Coverage, class Registration, class Reach = FreeFlying>
concept PlannerPolicies = VoxelSpace<Space> && PlannerMesh<Mesh> && CandidateSearchPolicy<Search, Mesh, Space> &&
                          UtilityPolicy<Utility, Space, Sensor> && TerminationCriterion<Termination> &&
                          CollisionChecker<Collision> && PlannerSensor<Sensor> &&
                          CoverageEstimator<Coverage, Mesh, Space> && RegistrationPolicy<Registration, Mesh> &&
                          RobotPolicy<Reach, Space>;

/// The composed Next-Best-Scan planner. Policies, in the order users change them (defaults = nbs's planner SGU_H
/// with the settled stop rule, noise-robust mesh and ĉ_m; ThesisPlanner is the thesis's best method C_H, Tab. 4.5):
/// - `Utility`: UtilityPolicy (public member `utility`, with a `setting`);
/// - `Search`: CandidateSearch<Explore, Rescan> (public member `search`);
/// - `Sensor`: LaserStripeProfiler or AreaSensor (PlannerSensor);
/// - `Collision`: CollisionChecker for Alg. 3 (public member `collision`; default: infinite free workspace, Sec. 4.7;
///   a SpaceTrackingCollisionChecker is updated after every scan);
/// - `Termination`: TerminationCriterion (public member `termination`; default: ĉ_m held, settled or stalled with d̄_m
///   reached, or n_abort; ThesisTermination: ĉ_m and d̄_m reached, or n_abort);
/// - `Space`: voxel space owned by the planner (VoxelSpace, space/concepts.hpp);
/// - `Mesh`: surface mesh owned by the planner (PlannerMesh; NoiseRobustStreamingMesh, or StreamingMesh for the
///   thesis's Sec. 3.3.1);
/// - `Coverage`: the ĉ_m form (CoverageEstimator, public member `coverage`; ThesisCoverage for Eq. 4.35 as written);
/// - `Registration`: the registration step before each scan is integrated (RegistrationPolicy, public member
///   `registration`; NoRegistration for exact poses, Icp for a robot's pose error, Sec. 3.2.3);
/// - `Reach`: who carries the sensor (robot_policy.hpp, public member `robot`): FreeFlying (nothing checked) or
///   `RobotReach<R>` (Alg. 3 keeps only candidates R can fly; the chosen one is re-checked; see next_best_scan).
template <class Utility = SurfaceGainUnseenUtility, class Search = BoundaryHoleSpace,
          class Sensor = LaserStripeProfiler, class Collision = NoCollisions, class Termination = DefaultTermination,
          class Space = ProbabilisticVoxelSpace<>, class Mesh = NoiseRobustStreamingMesh,
          class Coverage = UnseenLoopCoverage, class Registration = NoRegistration, class Reach = FreeFlying>
  requires PlannerPolicies<Utility, Search, Sensor, Collision, Termination, Space, Mesh, Coverage, Registration,
                           Reach>
class NbsPlanner {
public:
  using SpaceType = Space;
  using MeshType = Mesh;
  using SearchType = Search;
  using UtilityType = Utility;
  using SensorType = Sensor;
  using CoverageType = Coverage;
  using ReachType = Reach;
  using Setting = PlannerSetting;

private:
  // Declared first: the public policies below are initialised from them.
  Parameters params_;
  Sensor sensor_;
  SensorGeometry geometry_;
  Aabb box_;
  Setting setting_;
  std::unique_ptr<Space> space_;
  std::unique_ptr<Mesh> mesh_;

public:
  /// Builds empty models over the bounding box of the unknown area `unknown_area` (world, metres; Sec. 4.1: it
  /// must contain the whole object, its bottom on the pedestal plane); the mesh as Mesh(params, unknown_area).
  /// Throws InvalidArgument (naming the field) for invalid parameters, sensor, box or setting.
  NbsPlanner(const Parameters& params, const Sensor& sensor, const Aabb& unknown_area, const Setting& setting = {})
      : NbsPlanner(MeshFactory{}, params, sensor, unknown_area, setting, [](const Parameters& p, const Aabb& box) {
          return std::make_unique<Mesh>(p, box);
        }) {}
  /// Same, with the mesh built as Mesh(mesh_settings) (e.g. StreamingMeshSettings; its pass-through box should be
  /// the unknown area, as StreamingMeshSettings::from(params, unknown_area) sets it).
  template <class MeshSettings>
    requires std::constructible_from<Mesh, const MeshSettings&>
  NbsPlanner(const Parameters& params, const Sensor& sensor, const Aabb& unknown_area, const Setting& setting,
             const MeshSettings& mesh_settings)
      : NbsPlanner(MeshFactory{}, params, sensor, unknown_area, setting,
                   [&](const Parameters&, const Aabb&) { return std::make_unique<Mesh>(mesh_settings); }) {}

  // ---- Policies (public, each with its own Setting) ---------------------------------------------------------------
  Search search{};
  Utility utility{};
  Termination termination;
  Collision collision;
  Coverage coverage{};
  Registration registration{};
  /// The robot carrying the sensor (FreeFlying: none). Its configuration follows the scans: integrate() sets it to
  /// the IK solution of each scan's last sensor pose (kept if unreachable).
  Reach robot{};

  // ---- The loop ----------------------------------------------------------------------------------------------------
  /// Integrates one scan (Fig. 4.1): registration (the Registration policy, Sec. 3.2.3; a correction moves the whole
  /// scan, a refusal leaves it as measured, both reported), voxel space, mesh, surface features of the voxels touched by M_cur (Sec. 4.5.1),
  /// ĉ_m (the Coverage policy, Eq. 4.35), d̄_m, process control (Eq. 4.38). Counts the scan (n_s) even if none of its
  /// points lies inside the bounding box of the unknown area (status says so; the models are then unchanged). Throws
  /// InvalidArgument (nothing changed) for an invalid scan; if the space's integrate throws (e.g. FileError for an
  /// unreadable flushed block), the scan count, mesh and next plan are unchanged.
  IntegrationReport integrate(const Scan& scan_in) {
    const auto t0 = std::chrono::steady_clock::now();
    scan_in.validate();
    IntegrationReport r;
    // Registration (Sec. 3.2.3) before anything changes: the policy corrects the whole scan or refuses; a refused
    // scan is integrated as measured.
    Scan corrected;
    const Scan* registered = &scan_in;
    if (!scan_in.empty()) {
      // scan_in was validated above: a policy that offers it skips its own check (PrevalidatedScan).
      if constexpr (TakesPrevalidatedScan<Registration, Mesh>)
        r.registration = registration.register_scan(scan_in, std::as_const(*mesh_), prevalidated_scan);
      else
        r.registration = registration.register_scan(scan_in, std::as_const(*mesh_));
      if (r.registration.applied()) {
        corrected = transformed(scan_in, r.registration.correction);
        registered = &corrected;
      }
    }
    const Scan& scan = *registered;
    r.t_registration_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.points = scan.size();
    for (const Vec3& p : scan.points) r.points_inside += box_.contains(p) ? 1 : 0;
    if (scan.empty()) {
      r.status = IntegrationStatus::empty_scan;
    } else if (r.points_inside == 0) {
      r.status = IntegrationStatus::outside_unknown_area;
    } else {
      auto lap = [t = std::chrono::steady_clock::now()]() mutable {
        const auto now = std::chrono::steady_clock::now();
        const double s = std::chrono::duration<double>(now - t).count();
        t = now;
        return s;
      };
      // A mesh that can reject a scan the space accepts checks it first, so that it cannot throw after the space
      // changed (StreamingMesh: coordinates outside its spatial hash's range).
      if constexpr (ChecksScans<Mesh>) mesh_->check_scan(scan);
      // All or nothing: a throw leaves the planner unchanged (n_s not counted). On setting().threads threads where
      // the space can (the same space for any count).
      r.space = integrate_scan(*space_, scan, setting_.threads);
      r.t_space_s = lap();
      r.meshed = mesh_->integrate(scan);
      r.t_mesh_s = lap();
      r.features_written = update_surface_features(features_, *space_, *mesh_, params_);
      r.t_features_s = lap();
      if constexpr (SpaceTrackingCollisionChecker<Collision, Space>) collision.update(*space_);
      last_sensor_ = scan.profile_poses.front();
      scan_starts_.push_back(last_sensor_);
      last_path_length_ = (scan.profile_poses.back().translation() - scan.profile_poses.front().translation()).norm();
      CoverageResult cov = coverage.estimate(CoverageInput<Mesh, Space>{*mesh_, *space_, params_, box_});
      r.holes = cov.holes;
      coverage_ = cov.coverage;
      unseen_ = std::move(cov.unseen);
      density_ = std::clamp(nbs::mean_relative_density(*mesh_), 0.0, 1.0);
      r.t_coverage_s = lap();
    }
    ++scans_;  // after the models: a throw above leaves n_s unchanged
    if (r.status == IntegrationStatus::ok) coverage_history_.push_back(coverage_);  // a scan that changed the models
    scores_.reset();  // S is scored anew after a scan (reselect)
    if constexpr (kHasRobot) {
      if (robot.active() && !scan_in.profile_poses.empty()) robot.scanned(scan_in.profile_poses.back());
    }
    // Process control, Eq. (4.38): one-way switch BS → HR when ĉ_m grows by less than mode_switch_gain.
    const SearchMode proposed = control_.update(coverage_);
    if constexpr (Search::kHasRescan) {
      if (proposed == SearchMode::HoleRescan && mode_ == SearchMode::BoundarySearch) {
        mode_ = SearchMode::HoleRescan;
        rescan_pending_ = true;
        r.switched = true;
      }
    }
    r.scans = scans_;
    r.estimated_coverage = coverage_;
    r.mean_density = density_;
    r.mode = mode_;
    r.done = done();
    r.t_integrate_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
  }

  /// Plans the next best scan (see PlanStatus): generates candidates for the current mode, replans them with
  /// Alg. 3, adds them to the candidate set S, scores S with the utility and removes and returns the best. Never
  /// returns `ok` without a path. With an active robot, Alg. 3 also requires the robot to fly the path from its
  /// current configuration, and the chosen candidate is checked again (S may hold candidates of earlier steps):
  /// if it fails, it leaves S and the next in utility order is checked; if none passes, no_reachable_candidate.
  /// With RobotReach::Setting::transfer_cost_weight λ > 0 the choice is the reachable candidate with the largest
  /// transfer_cost_score (exact: candidates are checked in utility order until no later one can score higher).
  /// The chosen path's joint trajectory is PlanResult::joints. reselect() chooses again from the same scores.
  /// Throws InvalidArgument if the utility returns ok with a value count other than the candidate count.
  [[nodiscard]] PlanResult next_best_scan() {
    const auto t0 = std::chrono::steady_clock::now();
    PlanResult out = started_plan();
    IterationStats& st = out.stats;
    const auto finish = [&](PlanStatus s) { return finished_plan(out, s, t0); };
    scores_.reset();
    if (done()) return finish(PlanStatus::done);
    if (mesh_->face_count() == 0) return finish(PlanStatus::nothing_seen_yet);

    if (mode_ == SearchMode::BoundarySearch || setting_.keep_exploring) {
      using Explore = typename Search::ExploreGenerator;
      if (!FixedCandidateSpace<Explore> || !fixed_space_generated_) {
        if constexpr (ReplacesCandidateSet<Explore>) pool_.clear();
        generate_into_pool(search.explore, st);
        fixed_space_generated_ = true;
      }
      if constexpr (Search::kHasRescan) {
        if (mode_ == SearchMode::BoundarySearch && pool_.empty() && setting_.rescan_when_explore_empty) {
          mode_ = SearchMode::HoleRescan;
          rescan_pending_ = true;
        }
      }
    }
    if constexpr (Search::kHasRescan) {
      if (mode_ == SearchMode::HoleRescan && (rescan_pending_ || (pool_.empty() && setting_.redetect_holes))) {
        if (!setting_.keep_exploring) pool_.clear();  // Sec. 4.4: the remaining Boundary Search candidates go
        generate_into_pool(search.rescan, st);
        rescan_pending_ = false;
        control_.mark_holes_detected();
      }
    }
    if (pool_.empty())
      return finish(st.unreachable > 0 ? PlanStatus::no_reachable_candidate : PlanStatus::no_candidates);

    const auto te = std::chrono::steady_clock::now();
    std::vector<LinearScanPath> paths;
    paths.reserve(pool_.size());
    for (const ScanCandidate& c : pool_) paths.push_back(c.path);
    const EvaluationResult res = utility.evaluate(std::span<const LinearScanPath>(paths), sensor_, *space_,
                                                  utility_context(), evaluation_setting());
    st.t_evaluate_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - te).count();
    st.evaluated = pool_.size();
    if (!res.ok() || res.best >= pool_.size()) return finish(PlanStatus::no_candidates);
    // A user's UtilityPolicy may break its contract: take() and reselect() index the values by candidate.
    detail::require(res.values.size() == pool_.size(), "NbsPlanner: the utility policy returned ", res.values.size(),
                    " values for ", pool_.size(), " candidates");
    scores_ = res.values;
    return finish(take(res.best, out));
  }

  /// Chooses again from the candidates the last next_best_scan() scored, without generating or scoring anything:
  /// the best one left in S by the same rule (utility order — the largest value first, ties to the lower index —,
  /// reach, transfer cost). For a loop whose transfer to the chosen scan failed: that candidate has already left S,
  /// so this is the next best. Statuses: ok, no_reachable_candidate (S had candidates, none flyable; they leave S),
  /// no_candidates (S is empty, or no next_best_scan() since the last integrate()). PlanResult::stats counts only
  /// this call (reach checks, unreachable, best_utility, t_nbs_s).
  [[nodiscard]] PlanResult reselect() {
    const auto t0 = std::chrono::steady_clock::now();
    PlanResult out = started_plan();
    PlanStatus status = PlanStatus::no_candidates;
    if (scores_ && !pool_.empty()) {
      out.stats.evaluated = pool_.size();
      const std::vector<std::size_t> top = top_indices(std::span<const double>(*scores_), 1);
      if (!top.empty()) status = take(top.front(), out);
    }
    return finished_plan(out, status, t0);
  }

  /// Can the planner's robot fly `path` from its current configuration, links checked against the voxel space
  /// now? With FreeFlying or an inactive robot: always (an empty trajectory). Throws as RobotPathChecker does.
  [[nodiscard]] ScanPathReach reach(const LinearScanPath& path) const {
    if constexpr (kHasRobot) {
      if (robot.active()) return robot.checker(*space_).check(path, robot.configuration());
    }
    return {};
  }

  /// The robot's current joint configuration (the end of the last scan, RobotReach::configuration()); empty with
  /// FreeFlying or an inactive robot. The loop's transfers start here (run_loop with a TransferPlanner).
  [[nodiscard]] JointVector robot_configuration() const {
    if constexpr (kHasRobot) {
      if (robot.active()) return robot.configuration();
    }
    return {};
  }

  /// True when the termination criterion holds for progress() (n_s, ĉ_m, d̄_m, the ĉ_m history).
  [[nodiscard]] bool done() const { return termination.done(progress()); }

  /// A first scan path (Sec. 4.1, 4.7.2): one of the 13 initial paths around the bounding box of the unknown area,
  /// index random_initial_scan_index(seed), at d_s.
  [[nodiscard]] LinearScanPath first_scan(std::uint64_t seed) const {
    return initial_scan(random_initial_scan_index(seed));
  }
  /// Initial path `index` ∈ [0, 13) of Sec. 4.7.2 around the bounding box of the unknown area, at d_s.
  [[nodiscard]] LinearScanPath initial_scan(int index) const { return initial_scan_path(box_, standoff(), index); }

  // ---- State -------------------------------------------------------------------------------------------------------
  /// (n_s, ĉ_m, d̄_m) and ĉ_m after each scan that changed the models (coverage_history: an empty scan or one outside
  /// the unknown area adds nothing; borrowed: valid until the next integrate()).
  [[nodiscard]] ModelProgress progress() const {
    return {scans_, coverage_, density_, std::span<const double>(coverage_history_)};
  }
  [[nodiscard]] int scans() const { return scans_; }
  [[nodiscard]] double estimated_coverage() const { return coverage_; }
  [[nodiscard]] double mean_density() const { return density_; }
  [[nodiscard]] SearchMode mode() const { return mode_; }
  [[nodiscard]] const std::vector<ScanCandidate>& candidate_set() const { return pool_; }
  [[nodiscard]] const IterationStats& last_stats() const { return last_stats_; }
  [[nodiscard]] const Space& space() const { return *space_; }
  /// Surface features d̄_i, n̄_i, b_i per voxel (Sec. 4.5.1), computed from the mesh after each scan (M_cur's voxels
  /// with p ≥ params.occupied_threshold); the utility reads them.
  [[nodiscard]] const SurfaceFeatureMap& features() const { return features_; }
  [[nodiscard]] const Mesh& mesh() const { return *mesh_; }
  [[nodiscard]] const Parameters& params() const { return params_; }
  [[nodiscard]] const Sensor& sensor() const { return sensor_; }
  [[nodiscard]] const SensorGeometry& sensor_geometry() const { return geometry_; }
  [[nodiscard]] const Aabb& unknown_area() const { return box_; }
  [[nodiscard]] const Setting& setting() const { return setting_; }
  /// What next_best_scan() scores S with: the UtilityContext of this step (n_s, the per-step seed of Random,
  /// parameters, where the sensor rests: the end of the last scan path) and the EvaluationSetting (threads, sampling, coarse-to-fine, the surface features). Use both to
  /// score other paths exactly as the planner would.
  [[nodiscard]] UtilityContext utility_context() const {
    return {scans_, detail::splitmix64(setting_.seed ^ detail::splitmix64(std::uint64_t(scans_))), &params_,
            last_sensor_.translation() + last_path_length_ * last_sensor_.linear().col(1),
            std::span<const UnseenSample>(unseen_)};
  }
  [[nodiscard]] EvaluationSetting evaluation_setting() const {
    EvaluationSetting eval{setting_.threads, setting_.sampling, setting_.refine};
    eval.features = &features_;
    eval.occluder = setting_.occluder;
    return eval;
  }
  /// Replaces the setting (validated first; throws InvalidArgument, nothing changed).
  void set_setting(const Setting& s) { setting_ = checked(s, geometry_); }
  /// d_s in metres.
  [[nodiscard]] double standoff() const { return setting_.standoff_m > 0.0 ? setting_.standoff_m : geometry_.mid_range_m(); }

private:
  [[nodiscard]] static Setting checked(Setting s, const SensorGeometry& g) {
    s.validate();
    const double d = s.standoff_m > 0.0 ? s.standoff_m : g.mid_range_m();
    detail::require(g.range.contains(d), "PlannerSetting.standoff_m = ", d, " m lies outside the working range [",
                    g.range.min_m, ", ", g.range.max_m, "]");
    return s;
  }
  [[nodiscard]] PlanningContext<Mesh, Space> context() const {
    return {*mesh_,        *space_,           params_,           last_sensor_,
            last_path_length_, geometry_,     box_,              setting_.standoff_m,
            setting_.threads,  std::span<const Pose>(scan_starts_)};
  }
  struct MeshFactory {};  // tag of the constructor every public one delegates to
  template <class MakeMesh>
  NbsPlanner(MeshFactory, const Parameters& params, const Sensor& sensor, const Aabb& unknown_area,
             const Setting& setting, MakeMesh&& make_mesh)
      : params_((params.validate(), params)),
        sensor_((sensor.validate(), sensor)),
        geometry_(SensorGeometry::of(sensor)),
        box_((detail::require_unknown_area(unknown_area), unknown_area)),
        setting_(checked(setting, geometry_)),
        space_(detail::make_planner_space<Space>(params_, box_, sensor_)),
        mesh_(make_mesh(params_, box_)),
        termination(detail::make_termination<Termination>(params_)),
        collision(detail::make_collision<Collision>(*space_)),
        control_(params_.mode_switch_gain) {
    detail::apply_flush_setting(*space_, setting_.flush);
  }

  /// Runs Alg. 3 on `fresh` (if enabled), counts, and appends the accepted candidates to S.
  void admit(std::vector<ScanCandidate> fresh, IterationStats& st) {
    st.generated += fresh.size();
    ReplanSetting rs = setting_.replan;
    rs.incidence_cutoff_rad = params_.incidence_cutoff_rad;
    rs.support_plane_z_m = box_.min.z();  // Sec. 4.1: the object stands on the plane at the bottom of the box
    if (!setting_.replan_candidates) {
      const auto below = [&](const ScanCandidate& c) { return !rs.above_support(c.path); };
      st.dropped += static_cast<std::size_t>(std::ranges::count_if(fresh, below));
      std::erase_if(fresh, below);
      if constexpr (kHasRobot) {
        if (robot.active()) {
          const auto checker = robot.checker(*space_);
          const auto unreachable = [&](const ScanCandidate& c) {
            return count_unreachable(reach_failure(checker, c.path, st), st);
          };
          const std::size_t n = fresh.size();
          std::erase_if(fresh, unreachable);
          st.dropped += n - fresh.size();
        }
      }
    } else if (!fresh.empty() && robot_active()) {
      const auto t0 = std::chrono::steady_clock::now();
      if constexpr (kHasRobot) {
        const auto checker = robot.checker(*space_);
        std::vector<ScanCandidate> kept;
        for (ScanCandidate& c : fresh) {
          PathFailure first = PathFailure::none;  // of this candidate's rotations
          const auto accept = [&](const LinearScanPath& p) {
            const PathFailure f = reach_failure(checker, p, st);
            if (first == PathFailure::none) first = f;
            return f == PathFailure::none;
          };
          const ReplanReport rep = replan(c, *space_, collision, geometry_, rs, accept);
          if (rep.outcome == ReplanOutcome::dropped_unreachable) count_unreachable(first, st);
          st.replanned += rep.outcome == ReplanOutcome::rotated ? 1 : 0;
          st.reach_rotated += rep.accepted() && rep.acceptor_refusals > 0 ? 1 : 0;
          if (rep.accepted()) kept.push_back(std::move(c));
          else ++st.dropped;
        }
        fresh = std::move(kept);
      }
      st.t_replan_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    } else if (!fresh.empty()) {
      const auto t0 = std::chrono::steady_clock::now();
      const std::vector<ReplanReport> reports = replan_candidates(fresh, *space_, collision, geometry_, rs);
      for (const ReplanReport& rep : reports) {
        st.replanned += rep.outcome == ReplanOutcome::rotated ? 1 : 0;
        st.dropped += rep.accepted() ? 0 : 1;
      }
      st.t_replan_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    for (ScanCandidate& c : fresh) pool_.push_back(std::move(c));
  }

  static constexpr bool kHasRobot = !std::same_as<Reach, FreeFlying>;
  [[nodiscard]] bool robot_active() const {
    if constexpr (kHasRobot) return robot.active();
    return false;
  }

  /// One reach check of `path` from the robot's configuration (timed and counted in `st`): its failure, none if the
  /// robot can fly it (then its trajectory goes to `joints` if given).
  template <class Checker>
  PathFailure reach_failure(const Checker& checker, const LinearScanPath& path, IterationStats& st,
                            std::vector<JointVector>* joints = nullptr) {
    const auto t0 = std::chrono::steady_clock::now();
    ScanPathReach r = checker.check(path, robot.configuration());
    ++st.reach_checks;
    st.t_reach_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (r.ok() && joints) *joints = std::move(r.joints);
    return r.failure;
  }
  /// Counts one unreachable candidate by its failure `f`; returns false for none (nothing counted).
  static bool count_unreachable(PathFailure f, IterationStats& st) {
    if (f == PathFailure::none) return false;
    ++st.unreachable;
    ++st.unreachable_by_failure[static_cast<std::size_t>(f)];
    return true;
  }

  /// A plan with the model's state in its stats (n_s, ĉ_m, d̄_m).
  [[nodiscard]] PlanResult started_plan() const {
    PlanResult out;
    out.stats.scans = scans_;
    out.stats.estimated_coverage = coverage_;
    out.stats.mean_density = density_;
    return out;
  }
  /// `out` with status `s`, the mode and t_nbs since `t0`; kept as last_stats().
  PlanResult finished_plan(PlanResult& out, PlanStatus s, std::chrono::steady_clock::time_point t0) {
    out.status = s;
    out.stats.mode = mode_;
    out.stats.t_nbs_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    last_stats_ = out.stats;
    return out;
  }

  /// Takes the chosen candidate out of S into `out` (scores_ = the values of S, `first` = the utility's choice):
  /// with an active robot the best one it can fly (choose_reachable; the refused ones leave S too). Returns ok or
  /// no_reachable_candidate.
  PlanStatus take(std::size_t first, PlanResult& out) {
    std::size_t chosen = first;
    std::vector<std::size_t> leaving;  // indices into S (and scores_) that leave S
    if constexpr (kHasRobot) {
      if (robot.active()) {
        const std::optional<std::size_t> c = choose_reachable(first, out, out.stats, leaving);
        if (!c) {
          erase_from_pool(std::move(leaving));
          return PlanStatus::no_reachable_candidate;
        }
        chosen = *c;
      }
    }
    out.stats.best_utility = (*scores_)[chosen];
    out.candidate = std::move(pool_[chosen]);
    leaving.push_back(chosen);
    erase_from_pool(std::move(leaving));
    return PlanStatus::ok;
  }

  /// The index in S of the best candidate the robot can fly now (`first` checked first, then by value; ties to the
  /// lower index), its trajectory in out.joints; the refused ones are appended to `refused` (they leave S). With
  /// λ = transfer_cost_weight > 0: the flyable one of the largest transfer_cost_score, d from its first IK
  /// configuration; the search stops at the first candidate whose value is ≤ the best score (the score is ≤ the
  /// value, so no later one can win).
  std::optional<std::size_t> choose_reachable(std::size_t first, PlanResult& out, IterationStats& st,
                                              std::vector<std::size_t>& refused) {
    const std::vector<double>& values = *scores_;
    const auto checker = robot.checker(*space_);
    const double lambda = robot.setting().transfer_cost_weight;
    std::vector<std::size_t> order{first};
    for (const std::size_t i : top_indices(std::span<const double>(values), values.size()))
      if (i != first) order.push_back(i);
    std::optional<std::size_t> chosen;
    double best = 0.0;  // the chosen one's score
    for (const std::size_t i : order) {
      if (chosen && (lambda == 0.0 || values[i] <= best)) break;
      std::vector<JointVector> joints;
      if (count_unreachable(reach_failure(checker, pool_[i].path, st, &joints), st)) {
        refused.push_back(i);
        continue;
      }
      const double d = joints.empty() ? 0.0 : (joints.front() - robot.configuration()).norm();
      const double score = transfer_cost_score(values[i], d, lambda);
      if (!chosen || score > best) {
        chosen = i;
        best = score;
        out.joints = std::move(joints);
      }
    }
    if (chosen && !out.joints.empty()) robot.planned(out.joints.back());
    return chosen;
  }
  /// Erases the candidates at `indices` (distinct) from S (and their scores), keeping the order of the rest.
  void erase_from_pool(std::vector<std::size_t> indices) {
    std::ranges::sort(indices, std::greater<>{});
    for (const std::size_t i : indices) {
      pool_.erase(pool_.begin() + static_cast<std::ptrdiff_t>(i));
      if (scores_) scores_->erase(scores_->begin() + static_cast<std::ptrdiff_t>(i));
    }
  }

  template <class Generator>
  void generate_into_pool(const Generator& g, IterationStats& st) {
    const auto t0 = std::chrono::steady_clock::now();
    CandidateSet set = g.generate(context());
    st.generator_status = set.status;
    st.t_generate_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    admit(std::move(set.candidates), st);
  }

  SurfaceFeatureMap features_;
  ProcessControl control_;
  SearchMode mode_ = SearchMode::BoundarySearch;
  bool rescan_pending_ = false;
  bool fixed_space_generated_ = false;
  std::vector<ScanCandidate> pool_;
  /// The utility values of S from the last next_best_scan(), index for index (reselect()); reset by integrate().
  std::optional<std::vector<double>> scores_;
  Pose last_sensor_ = Pose::Identity();
  std::vector<Pose> scan_starts_;  // PlanningContext::scan_starts
  double last_path_length_ = 0.0;
  int scans_ = 0;
  double coverage_ = 0.0;
  std::vector<double> coverage_history_;  // ĉ_m after each integrate() whose status was ok
  std::vector<UnseenSample> unseen_;  // where ĉ_m puts the missing surface after the last scan (CoverageResult::unseen)
  double density_ = 0.0;
  IterationStats last_stats_{};
};

/// `NbsPlanner<>` (its default policies) planning for the Robot R: set `planner.robot = RobotReach<R>(r, q_start)`.
template <Robot R>
using RobotPlanner = NbsPlanner<SurfaceGainUnseenUtility, BoundaryHoleSpace, LaserStripeProfiler, NoCollisions,
                                DefaultTermination, ProbabilisticVoxelSpace<>, NoiseRobustStreamingMesh,
                                UnseenLoopCoverage, NoRegistration, RobotReach<R>>;

/// The thesis's best method C_H (Tab. 4.5): IG/Quality selection and the thesis's stop rule, with nbs's noise-robust
/// mesh and ĉ_m (the planner NbsPlanner<> was until issue 18).
template <class Utility = IgQualityUtility, class Search = BoundaryHoleSpace, class Sensor = LaserStripeProfiler>
using ThesisPlanner = NbsPlanner<Utility, Search, Sensor, NoCollisions, ThesisTermination>;

/// C_H (or another utility / search / sensor) with the thesis's stop rule, mesh and ĉ_m as written (Secs. 3.3.1,
/// 4.4, 4.6): StreamingMesh and ThesisCoverage. Use both together: the unseen-loop forms are meaningless on the
/// layered mesh.
template <class Utility = IgQualityUtility, class Search = BoundaryHoleSpace, class Sensor = LaserStripeProfiler>
using ThesisMeshPlanner = NbsPlanner<Utility, Search, Sensor, NoCollisions, ThesisTermination,
                                     ProbabilisticVoxelSpace<>, StreamingMesh, ThesisCoverage>;

}  // namespace nbs
