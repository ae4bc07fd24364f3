// SPDX-License-Identifier: BSD-3-Clause
// The planner with a robot (issue 19, item 2): FreeFlyingSensor gives today's plans; a robot that cannot reach a
// half-space never gets a path there; the unreachable count of a step is exact; nothing reachable is a status.

#include "nbs_catch.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <optional>
#include <utility>

#include "nbs/planner/nbs_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"
#include "nbs/robot/free_flying.hpp"
#include "nbs/robot/transfer.hpp"
#include "support/analytic_scanner.hpp"
#include "support/same_plan.hpp"

namespace {

using nbs::test::light_lsp;
using nbs::test::sphere_box;

/// FreeFlyingSensor that reaches no sensor position with x > x_max (metres, world), or nothing at all, or (if
/// `only` is set) only positions within 1 µm of the segment only->first – only->second.
struct HalfSpaceFlyer {
  double x_max = 0.0;
  bool reach_nothing = false;
  std::optional<std::pair<nbs::Vec3, nbs::Vec3>> only;
  nbs::FreeFlyingSensor free{};
  [[nodiscard]] std::size_t joint_count() const { return 6; }
  [[nodiscard]] nbs::JointLimits joint_limits() const { return free.joint_limits(); }
  [[nodiscard]] nbs::Pose fk(const nbs::JointVector& q) const { return free.fk(q); }
  [[nodiscard]] std::optional<nbs::JointVector> ik(const nbs::Pose& T, const nbs::JointVector& seed) const {
    if (reach_nothing || T.translation().x() > x_max) return std::nullopt;
    if (only) {
      const nbs::Vec3 p = T.translation(), a = only->first, d = only->second - only->first;
      const double t = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
      if ((a + t * d - p).norm() > 1e-6) return std::nullopt;
    }
    return free.ik(T, seed);
  }
  [[nodiscard]] std::vector<nbs::PlacedShape> collision_shapes(const nbs::JointVector& q) const {
    return free.collision_shapes(q);
  }
  [[nodiscard]] nbs::Pose hand_eye() const { return nbs::Pose::Identity(); }
};
static_assert(nbs::Robot<HalfSpaceFlyer>);


nbs::PlannerSetting setting(unsigned threads) {
  nbs::PlannerSetting s;
  s.threads = threads;
  return s;
}
nbs::SimulationSetting sim(std::uint64_t seed, int max_scans) {
  nbs::SimulationSetting s;
  s.seed = seed;
  s.max_scans = max_scans;
  return s;
}
const nbs::JointVector kStart = nbs::JointVector::Zero(6);

/// A TransferPlanner that records every call and fails from call `fail_at` on (1-based; 0: never): its path is the
/// straight motion from → to, its sensor length the FreeFlyingSensor's straight distance.
struct RecordingTransfer {
  struct Call {
    nbs::JointVector from, to;
    int scans = 0;  ///< scans integrated into the space when the call was made (voxels observed: a proxy)
  };
  std::shared_ptr<std::vector<Call>> calls = std::make_shared<std::vector<Call>>();
  int fail_at = 0;
  [[nodiscard]] std::size_t joint_count() const { return 6; }
  template <nbs::VoxelSpace Space>
  [[nodiscard]] nbs::TransferPlan plan(const nbs::JointVector& from, const nbs::JointVector& to, const Space&) const {
    calls->push_back({from, to, 0});
    nbs::TransferPlan p;
    if (fail_at > 0 && static_cast<int>(calls->size()) >= fail_at) {
      p.failure = "test: no motion";
      return p;
    }
    p.waypoints = {from, to};
    p.sensor_length_m = (to.head<3>() - from.head<3>()).norm();
    return p;
  }
};
static_assert(nbs::TransferPlanner<RecordingTransfer, nbs::ProbabilisticVoxelSpace<>>);
static_assert(nbs::TransferPlanner<nbs::NoTransfer, nbs::ProbabilisticVoxelSpace<>>);

}  // namespace

TEST_CASE("robot planner: FreeFlyingSensor gives the default planner's plans bit for bit, over thread counts",
          "[planner][robot]") {
  const nbs::test::SphereOnPedestal sphere;
  nbs::NbsPlanner<> plain({}, light_lsp(), sphere_box(), setting(1));
  nbs::RobotPlanner<nbs::FreeFlyingSensor> flying({}, light_lsp(), sphere_box(), setting(2));
  flying.robot = nbs::RobotReach<nbs::FreeFlyingSensor>({}, kStart);
  const auto a = nbs::run_simulation(plain, sphere, sim(3, 5));
  const auto b = nbs::run_simulation(flying, sphere, sim(3, 5));
  REQUIRE(a.records.size() >= 3);
  nbs::test::check_same_plan(a, b);
  for (std::size_t i = 1; i < b.records.size(); ++i) {
    CHECK(b.records[i].planning.reach_checks > 0);  // the checks ran ...
    CHECK(b.records[i].planning.unreachable == 0);  // ... and refused nothing
    CHECK(b.records[i].planning.dropped == a.records[i].planning.dropped);
  }
  // The robot follows the scans: its configuration is the end of the last scan.
  const nbs::Pose end = b.records.back().path.pose_at(1.0);
  CHECK(nbs::poses_agree(nbs::FreeFlyingSensor{}.fk(flying.robot.configuration()), end, 1e-9, 1e-9));
}

TEST_CASE("robot planner: a path the robot cannot fly is never returned; same plans for 1 and 2 threads",
          "[planner][robot]") {
  const nbs::test::SphereOnPedestal sphere;
  const HalfSpaceFlyer robot{0.0, false, {}};
  nbs::RobotPlanner<HalfSpaceFlyer> p1({}, light_lsp(), sphere_box(), setting(1));
  nbs::RobotPlanner<HalfSpaceFlyer> p2({}, light_lsp(), sphere_box(), setting(2));
  p1.robot = nbs::RobotReach<HalfSpaceFlyer>(robot, kStart);
  p2.robot = p1.robot;
  const auto a = nbs::run_simulation(p1, sphere, sim(3, 6));
  const auto b = nbs::run_simulation(p2, sphere, sim(3, 6));
  nbs::test::check_same_plan(a, b);
  REQUIRE(a.records.size() >= 3);
  std::size_t unreachable = 0;
  for (std::size_t i = 1; i < a.records.size(); ++i) {
    INFO("scan " << i + 1);
    const nbs::IterationStats& st = a.records[i].planning;
    CHECK(st.unreachable == b.records[i].planning.unreachable);
    CHECK(st.unreachable == st.unreachable_by_failure[static_cast<std::size_t>(nbs::PathFailure::unreachable)]);
    unreachable += st.unreachable;
    // Independent of the planner: every sample of the returned path is at x <= 0.
    const nbs::ScanPathReach r = nbs::check_scan_path(robot, a.records[i].path, kStart);
    CHECK(r.ok());
    CHECK(a.records[i].path.start().position().x() <= 0.0);
    CHECK(a.records[i].path.end_position().x() <= 0.0);
  }
  CHECK(unreachable > 0);  // the half-space refused candidates, so the test tests something
}

TEST_CASE("robot planner: the unreachable count of a step is exact; nothing reachable gives no_reachable_candidate",
          "[planner][robot]") {
  const nbs::test::SphereOnPedestal sphere;
  nbs::PlannerSetting s = setting(1);
  s.rescan_when_explore_empty = false;  // the same generators in both planners, however many survive
  nbs::NbsPlanner<> plain({}, light_lsp(), sphere_box(), s);
  nbs::RobotPlanner<HalfSpaceFlyer> blocked({}, light_lsp(), sphere_box(), s);
  blocked.robot = nbs::RobotReach<HalfSpaceFlyer>(HalfSpaceFlyer{0.0, true, {}}, kStart);
  const nbs::Scan first = sphere.scan(plain.initial_scan(0), plain.sensor(), 7);
  (void)plain.integrate(first);
  (void)blocked.integrate(first);
  const nbs::PlanResult ok = plain.next_best_scan();
  const nbs::PlanResult none = blocked.next_best_scan();
  REQUIRE(ok.ok());
  const std::size_t accepted = ok.stats.generated - ok.stats.dropped;  // Alg. 3 kept these without a robot
  REQUIRE(accepted > 0);
  CHECK(none.status == nbs::PlanStatus::no_reachable_candidate);
  CHECK(!none.candidate.has_value());
  CHECK(none.joints.empty());
  CHECK(none.stats.generated == ok.stats.generated);
  CHECK(none.stats.unreachable == accepted);  // exactly the candidates Alg. 3 would have kept
  CHECK(none.stats.unreachable_by_failure[static_cast<std::size_t>(nbs::PathFailure::unreachable)] == accepted);
  CHECK(none.stats.dropped == ok.stats.generated);
  CHECK(none.stats.reach_rotated == 0);
  CHECK(blocked.candidate_set().empty());
  CHECK(std::string(nbs::to_string(none.status)).find("no reachable candidate") != std::string::npos);
  // The loop ends on it, not in an endless loop.
  nbs::RobotPlanner<HalfSpaceFlyer> looped({}, light_lsp(), sphere_box(), s);
  looped.robot = blocked.robot;
  const auto run = nbs::run_simulation(looped, sphere, sim(3, 30));
  CHECK(run.records.size() == 1);
  CHECK(run.last_plan == nbs::PlanStatus::no_reachable_candidate);
  CHECK(run.stop == nbs::LoopStop::no_candidates);
}

TEST_CASE("robot planner: candidates of S the robot cannot fly now are refused at the choice, counted and removed",
          "[planner][robot]") {
  const nbs::test::SphereOnPedestal sphere;
  nbs::PlannerSetting s = setting(1);
  s.rescan_when_explore_empty = false;
  s.refine = nbs::CoarseToFine{1, 1};  // every candidate scored with the full sampling: values comparable one by one
  nbs::RobotPlanner<HalfSpaceFlyer> p({}, light_lsp(), sphere_box(), s);
  p.robot = nbs::RobotReach<HalfSpaceFlyer>(HalfSpaceFlyer{1e9, false, {}}, kStart);  // reaches everything
  (void)p.integrate(sphere.scan(p.initial_scan(0), p.sensor(), 7));
  const nbs::PlanResult first = p.next_best_scan();
  REQUIRE(first.ok());
  const std::size_t accepted = first.stats.generated - first.stats.dropped;
  const std::size_t left = p.candidate_set().size();
  REQUIRE(left == accepted - 1);
  REQUIRE(left > 0);

  SECTION("a robot that flies only the worst candidate of S: the better ones are refused at the choice") {
    std::vector<nbs::LinearScanPath> paths;
    for (const nbs::ScanCandidate& c : p.candidate_set()) paths.push_back(c.path);
    const nbs::EvaluationResult values = p.utility.evaluate(std::span<const nbs::LinearScanPath>(paths), p.sensor(),
                                                            p.space(), p.utility_context(), p.evaluation_setting());
    const auto worst = static_cast<std::size_t>(std::ranges::min_element(values.values) - values.values.begin());
    HalfSpaceFlyer only{1e9, false, {}};
    only.only = {paths[worst].start().position(), paths[worst].end_position()};
    p.robot = nbs::RobotReach<HalfSpaceFlyer>(only, kStart);
    const nbs::PlanResult plan = p.next_best_scan();
    REQUIRE(plan.ok());
    CHECK(plan.path().start().position() == paths[worst].start().position());
    CHECK(plan.joints.size() == nbs::scan_path_samples(plan.path(), 0.01));
    // Its utility is its own (the value it got among the others), not that of a refused one.
    CHECK(plan.stats.best_utility == values.values[worst]);
    // Every other candidate of S the first step left was refused at the choice (each better, or a tie of lower
    // index) and left S; the new ones are not flown either, so S is empty.
    CHECK(plan.stats.unreachable >= left - 1);
    CHECK(p.candidate_set().empty() == (plan.stats.generated - plan.stats.dropped == 0));
  }
  SECTION("a robot that reaches nothing: the new ones dropped by Alg. 3, the old ones refused at the choice") {
    p.robot = nbs::RobotReach<HalfSpaceFlyer>(HalfSpaceFlyer{0.0, true, {}}, kStart);
    const nbs::PlanResult none = p.next_best_scan();
    CHECK(none.status == nbs::PlanStatus::no_reachable_candidate);
    CHECK(none.stats.generated == first.stats.generated);  // the same model: the same new candidates
    CHECK(none.stats.unreachable == accepted + left);
    CHECK(p.candidate_set().empty());
  }
}

TEST_CASE("robot loop: NoTransfer changes no plan; each transfer runs from the last scan's end to the next start",
          "[planner][robot][transfer]") {
  const nbs::test::SphereOnPedestal sphere;
  nbs::NbsPlanner<> plain({}, light_lsp(), sphere_box(), setting(1));
  nbs::NbsPlanner<> free_loop({}, light_lsp(), sphere_box(), setting(1));
  const auto a = nbs::run_simulation(plain, sphere, sim(3, 4));
  const auto b = nbs::run_simulation(free_loop, sphere, nbs::NoTransfer{}, sim(3, 4));
  nbs::test::check_same_plan(a, b);
  REQUIRE(b.records.size() == 4);
  CHECK_FALSE(a.records[1].transfer.has_value());  // run_loop without a transfer planner records none
  CHECK_FALSE(b.records[0].transfer.has_value());  // the first scan has no transfer
  for (std::size_t i = 1; i < b.records.size(); ++i) {
    REQUIRE(b.records[i].transfer.has_value());
    CHECK(b.records[i].transfer->ok());
    CHECK(b.records[i].transfer->waypoints.empty());
    CHECK(b.records[i].transfer->joint_length_rad == 0.0);
    CHECK(b.records[i].transfer->sensor_length_m == 0.0);
  }

  // With a robot (FreeFlyingSensor: q = the sensor pose) the transfer goes from the end pose of scan i−1 to the
  // start pose of scan i: the oracle is the executed paths themselves.
  nbs::RobotPlanner<nbs::FreeFlyingSensor> flying({}, light_lsp(), sphere_box(), setting(1));
  flying.robot = nbs::RobotReach<nbs::FreeFlyingSensor>({}, kStart);
  const RecordingTransfer rec;
  const auto c = nbs::run_simulation(flying, sphere, rec, sim(3, 4));
  nbs::test::check_same_plan(a, c);
  REQUIRE(rec.calls->size() == 3);
  const nbs::FreeFlyingSensor fly;
  for (std::size_t i = 1; i < c.records.size(); ++i) {
    INFO("scan " << i + 1);
    const RecordingTransfer::Call& call = (*rec.calls)[i - 1];
    CHECK(nbs::poses_agree(fly.fk(call.from), c.records[i - 1].path.pose_at(1.0), 1e-9, 1e-9));
    CHECK(nbs::poses_agree(fly.fk(call.to), c.records[i].path.pose_at(0.0), 1e-9, 1e-9));
    const nbs::TransferRecord& t = *c.records[i].transfer;
    REQUIRE(t.waypoints.size() == 2);
    CHECK(t.joint_length_rad == (call.to - call.from).norm());  // Σ‖Δq‖ over the one segment
    CHECK(t.sensor_length_m == (call.to.head<3>() - call.from.head<3>()).norm());
    CHECK(t.t_plan_s >= 0.0);
  }
  CHECK(nbs::joint_path_length({kStart, kStart + nbs::JointVector::Constant(6, 1.0), kStart}) ==
        Approx(2.0 * std::sqrt(6.0)).epsilon(1e-15));
}

TEST_CASE("robot loop: a failed transfer stops the loop with transfer_failed; the candidate is not scanned",
          "[planner][robot][transfer]") {
  const nbs::test::SphereOnPedestal sphere;
  nbs::RobotPlanner<nbs::FreeFlyingSensor> p({}, light_lsp(), sphere_box(), setting(1));
  p.robot = nbs::RobotReach<nbs::FreeFlyingSensor>({}, kStart);
  RecordingTransfer rec;
  rec.fail_at = 2;  // the transfer to scan 3 fails
  int callbacks = 0;
  const auto r = nbs::run_simulation(p, sphere, rec, sim(3, 10), [&](const nbs::ScanRecord&) { ++callbacks; });
  CHECK(r.stop == nbs::LoopStop::transfer_failed);
  CHECK(std::string(nbs::to_string(r.stop)) == "transfer_failed");
  CHECK(r.records.size() == 2);
  CHECK(callbacks == 2);
  CHECK(p.scans() == 2);  // nothing integrated after the failure
  REQUIRE(r.failed_transfer.has_value());
  CHECK(r.failed_transfer->failure == "test: no motion");
  CHECK(r.last_plan == nbs::PlanStatus::ok);
}

TEST_CASE("robot loop: a transfer planner for another joint count is refused before any work",
          "[planner][robot][transfer]") {
  const nbs::test::SphereOnPedestal sphere;
  nbs::NbsPlanner<> plain({}, light_lsp(), sphere_box(), setting(1));  // no robot: 0 joints
  const RecordingTransfer rec;
  CHECK_THROWS_WITH(nbs::run_simulation(plain, sphere, rec, sim(3, 4)),
                    nbs_test::Contains("transfer planner has 6 joints but the planner's robot has 0"));
  CHECK(plain.scans() == 0);
  CHECK(rec.calls->empty());
}
