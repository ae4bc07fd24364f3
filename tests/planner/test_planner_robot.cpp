// SPDX-License-Identifier: BSD-3-Clause
// The planner with a robot (issue 19, item 2): FreeFlyingSensor gives today's plans; a robot that cannot reach a
// half-space never gets a path there; the unreachable count of a step is exact; nothing reachable is a status.

#include "nbs_catch.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <optional>
#include <sstream>
#include <span>
#include <vector>
#include <utility>

#include "nbs/planner/nbs_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"
#include "nbs/robot/free_flying.hpp"
#include "nbs/robot/transfer.hpp"
#include "support/analytic_scanner.hpp"
#include "support/loop_settings.hpp"
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


using nbs::test::loop_setting;
using nbs::test::setting;
const nbs::JointVector kStart = nbs::JointVector::Zero(6);

/// A TransferPlanner that records every call and fails calls fail_at, …, fail_at + fail_count − 1 (1-based; 0: never):
/// its path is the straight motion from → to, its sensor length the FreeFlyingSensor's straight distance.
struct RecordingTransfer {
  struct Call {
    nbs::JointVector from, to;
    int scans = 0;  ///< scans integrated into the space when the call was made (voxels observed: a proxy)
  };
  std::shared_ptr<std::vector<Call>> calls = std::make_shared<std::vector<Call>>();
  int fail_at = 0;
  int fail_count = 1 << 30;
  [[nodiscard]] std::size_t joint_count() const { return 6; }
  template <nbs::VoxelSpace Space>
  [[nodiscard]] nbs::TransferPlan plan(const nbs::JointVector& from, const nbs::JointVector& to, const Space&) const {
    calls->push_back({from, to, 0});
    nbs::TransferPlan p;
    const int n = static_cast<int>(calls->size());
    if (fail_at > 0 && n >= fail_at && n - fail_at < fail_count) {
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

/// A utility of hand-computable values: u = 1 + z of the path's start (metres), the largest first. `drop` > 0 breaks
/// the UtilityPolicy contract: that many values are left off the end (best still chosen among the rest).
struct StartHeightUtility {
  std::size_t drop = 0;
  template <class Sensor, class Space>
  [[nodiscard]] nbs::EvaluationResult evaluate(std::span<const nbs::LinearScanPath> paths, const Sensor&,
                                               const Space&, const nbs::UtilityContext&,
                                               const nbs::EvaluationSetting&) const {
    nbs::EvaluationResult r;
    for (const nbs::LinearScanPath& p : paths) r.values.push_back(1.0 + p.start().position().z());
    r.refined.assign(paths.size(), 1);
    r.rays.assign(paths.size(), 0);
    r.voxels.assign(paths.size(), 0);
    if (paths.empty()) return r;
    r.values.resize(r.values.size() - std::min(drop, r.values.size() - 1));
    r.status = nbs::EvaluationStatus::ok;
    r.best = nbs::top_indices(r.values, 1).front();
    return r;
  }
};
using HeightPlanner =
    nbs::NbsPlanner<StartHeightUtility, nbs::BoundaryHoleSpace, nbs::LaserStripeProfiler, nbs::NoCollisions,
                    nbs::DefaultTermination, nbs::ProbabilisticVoxelSpace<>, nbs::NoiseRobustStreamingMesh,
                    nbs::UnseenLoopCoverage, nbs::NoRegistration, nbs::RobotReach<nbs::FreeFlyingSensor>>;

}  // namespace

TEST_CASE("robot planner: FreeFlyingSensor gives the default planner's plans bit for bit, over thread counts",
          "[planner][robot]") {
  const nbs::test::SphereOnPedestal sphere;
  nbs::NbsPlanner<> plain({}, light_lsp(), sphere_box(), setting(1));
  nbs::RobotPlanner<nbs::FreeFlyingSensor> flying({}, light_lsp(), sphere_box(), setting(2));
  flying.robot = nbs::RobotReach<nbs::FreeFlyingSensor>({}, kStart);
  const auto a = nbs::run_simulation(plain, sphere, loop_setting(3, 5));
  const auto b = nbs::run_simulation(flying, sphere, loop_setting(3, 5));
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
  nbs::SimulationSetting sim = loop_setting(3, 6);
  for (int i = nbs::kInitialScanPathCount - 1; i >= 0; --i) {  // a first scan the robot can fly (x <= 0)
    const nbs::LinearScanPath path = p1.initial_scan(i);
    if (path.start().position().x() <= 0.0 && path.end_position().x() <= 0.0) sim.initial_index = i;
  }
  REQUIRE(sim.initial_index.has_value());
  const auto a = nbs::run_simulation(p1, sphere, sim);
  const auto b = nbs::run_simulation(p2, sphere, sim);
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
  // The loop ends on it, not in an endless loop (a robot that flies only the first scan's path).
  nbs::RobotPlanner<HalfSpaceFlyer> looped({}, light_lsp(), sphere_box(), s);
  const nbs::LinearScanPath p0 = looped.initial_scan(nbs::random_initial_scan_index(3));
  looped.robot = nbs::RobotReach<HalfSpaceFlyer>(
      HalfSpaceFlyer{1e9, false, std::pair{p0.start().position(), p0.end_position()}}, kStart);
  const auto run = nbs::run_simulation(looped, sphere, loop_setting(3, 30));
  CHECK(run.records.size() == 1);
  CHECK(run.last_plan == nbs::PlanStatus::no_reachable_candidate);
  CHECK(run.stop == nbs::LoopStop::no_reachable_candidate);
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
  const auto a = nbs::run_simulation(plain, sphere, loop_setting(3, 4));
  const auto b = nbs::run_simulation(free_loop, sphere, nbs::NoTransfer{}, loop_setting(3, 4));
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
  const auto c = nbs::run_simulation(flying, sphere, rec, loop_setting(3, 4));
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

TEST_CASE("robot loop: a failed transfer excludes its candidate, the next best is tried; all failing stops the loop",
          "[planner][robot][transfer]") {
  const nbs::test::SphereOnPedestal sphere;
  nbs::PlannerSetting s = setting(1);
  s.refine = nbs::CoarseToFine{1, 1};  // every candidate scored with the full sampling: values comparable one by one
  nbs::RobotPlanner<nbs::FreeFlyingSensor> p({}, light_lsp(), sphere_box(), s);
  p.robot = nbs::RobotReach<nbs::FreeFlyingSensor>({}, kStart);
  const nbs::FreeFlyingSensor fly;

  SECTION("the transfers to the best two candidates fail: the third best is scanned, 2 failures recorded") {
    // The oracle: a twin run to the same state (scans 1, 2), then S ranked by the utility's values.
    nbs::RobotPlanner<nbs::FreeFlyingSensor> twin({}, light_lsp(), sphere_box(), s);
    twin.robot = p.robot;
    (void)nbs::run_simulation(twin, sphere, RecordingTransfer{}, loop_setting(3, 2));
    const nbs::PlanResult first = twin.next_best_scan();
    REQUIRE(first.ok());
    // S as it was scored (the utility may normalise over the set): the chosen one first, then the rest.
    std::vector<nbs::LinearScanPath> S{first.path()};
    for (const nbs::ScanCandidate& c : twin.candidate_set()) S.push_back(c.path);
    REQUIRE(S.size() >= 3);
    const nbs::EvaluationResult v = twin.utility.evaluate(std::span<const nbs::LinearScanPath>(S), twin.sensor(),
                                                          twin.space(), twin.utility_context(),
                                                          twin.evaluation_setting());
    std::vector<std::size_t> order;  // S without the chosen one, by value, largest first
    for (const std::size_t i : nbs::top_indices(v.values, S.size()))
      if (i != 0) order.push_back(i);

    RecordingTransfer rec;
    rec.fail_at = 2;     // the transfer to scan 3 fails ...
    rec.fail_count = 2;  // ... twice
    const auto r = nbs::run_simulation(p, sphere, rec, loop_setting(3, 3));
    REQUIRE(r.records.size() == 3);
    CHECK(r.stop == nbs::LoopStop::max_scans);
    REQUIRE(rec.calls->size() == 4);
    CHECK(r.records[1].transfer->failed_attempts == 0);
    const nbs::TransferRecord& t = *r.records[2].transfer;
    CHECK(t.ok());
    CHECK(t.failed_attempts == 2);
    // Tries: the planner's choice, then the best and second best of the rest; the last is scanned.
    CHECK(nbs::poses_agree(fly.fk((*rec.calls)[1].to), first.path().pose_at(0.0), 1e-9, 1e-9));
    CHECK(nbs::poses_agree(fly.fk((*rec.calls)[2].to), S[order[0]].pose_at(0.0), 1e-9, 1e-9));
    CHECK(nbs::poses_agree(fly.fk((*rec.calls)[3].to), S[order[1]].pose_at(0.0), 1e-9, 1e-9));
    CHECK(r.records[2].path.start().pose().matrix() == S[order[1]].start().pose().matrix());
    CHECK(r.records[2].planning.best_utility == Approx(v.values[order[1]]).epsilon(1e-12));
    CHECK(r.records[2].planning.reach_checks == first.stats.reach_checks + 2);  // one per reselect
  }
  SECTION("every try fails: transfer_failed after 1 + transfer_retries tries, no candidate scanned") {
    for (const int retries : {0, 2}) {
      INFO("retries " << retries);
      nbs::RobotPlanner<nbs::FreeFlyingSensor> q({}, light_lsp(), sphere_box(), s);
      q.robot = p.robot;
      RecordingTransfer rec;
      rec.fail_at = 2;  // every transfer from scan 3 on fails
      nbs::SimulationSetting sim = loop_setting(3, 10);
      sim.transfer_retries = retries;
      int callbacks = 0;
      const auto r = nbs::run_simulation(q, sphere, rec, sim, [&](const nbs::ScanRecord&) { ++callbacks; });
      CHECK(r.stop == nbs::LoopStop::transfer_failed);
      CHECK(std::string(nbs::to_string(r.stop)) == "transfer_failed");
      CHECK(r.records.size() == 2);
      CHECK(callbacks == 2);
      CHECK(q.scans() == 2);  // nothing integrated after the failure
      CHECK(static_cast<int>(rec.calls->size()) == 1 + 1 + retries);
      REQUIRE(r.failed_transfer.has_value());
      CHECK(r.failed_transfer->failure == "test: no motion");
      CHECK(r.failed_transfer->failed_attempts == 1 + retries);
      CHECK(r.last_plan == nbs::PlanStatus::ok);
    }
  }
  SECTION("a negative retry count is refused before any work") {
    nbs::SimulationSetting sim = loop_setting(3, 10);
    sim.transfer_retries = -1;
    CHECK_THROWS_WITH(nbs::run_simulation(p, sphere, RecordingTransfer{}, sim),
                      nbs_test::Contains("transfer_retries must be >= 0, got -1"));
    CHECK(p.scans() == 0);
  }
}

TEST_CASE("robot loop: the first scan is one the robot can fly: the seeded path or the next; else refused before any work",
          "[planner][robot][transfer]") {
  const nbs::test::SphereOnPedestal sphere;
  nbs::RobotPlanner<HalfSpaceFlyer> p({}, light_lsp(), sphere_box(), setting(1));
  p.robot = nbs::RobotReach<HalfSpaceFlyer>(HalfSpaceFlyer{0.0, false, {}}, kStart);  // flies x <= 0 only
  const auto flyable = [&](int i) {
    const nbs::LinearScanPath path = p.initial_scan(i);
    return path.start().position().x() <= 0.0 && path.end_position().x() <= 0.0;
  };
  // Seed 3 draws initial path 9 (x > 0): the loop takes the next flyable one in cyclic order (brute force).
  const int seeded = nbs::random_initial_scan_index(3);
  REQUIRE_FALSE(flyable(seeded));
  int expected = seeded;
  while (!flyable(expected)) expected = (expected + 1) % nbs::kInitialScanPathCount;
  const auto run = nbs::run_simulation(p, sphere, loop_setting(3, 1));
  REQUIRE(run.records.size() == 1);
  CHECK(run.records[0].initial_index == expected);
  CHECK(run.records[0].path.start().pose().matrix() == p.initial_scan(expected).start().pose().matrix());

  // A forced initial path the robot cannot fly: refused, naming it.
  nbs::RobotPlanner<HalfSpaceFlyer> q({}, light_lsp(), sphere_box(), setting(1));
  q.robot = p.robot;
  nbs::SimulationSetting sim = loop_setting(3, 5);
  sim.initial_index = seeded;
  const nbs::Vec3 a = q.initial_scan(seeded).start().position();
  std::ostringstream where;
  where.precision(17);  // as nbs::InvalidArgument's messages
  where << "initial path " << seeded << " of 13 (sensor from (" << a.x() << ", " << a.y() << ", " << a.z() << ") m";
  const RecordingTransfer rec;
  std::string message;
  try {
    (void)nbs::run_simulation(q, sphere, rec, sim);
  } catch (const nbs::InvalidArgument& e) {
    message = e.what();
  }
  CHECK_THAT(message, nbs_test::Contains("the robot cannot fly the first scan, " + where.str()));
  CHECK_THAT(message, nbs_test::Contains("unreachable at sample 0"));
  // A robot that flies none of the 13: refused with or without a transfer planner.
  q.robot = nbs::RobotReach<HalfSpaceFlyer>(HalfSpaceFlyer{0.0, true, {}}, kStart);
  CHECK_THROWS_WITH(nbs::run_simulation(q, sphere, loop_setting(3, 5)),
                    nbs_test::Contains("can fly none of the 13 initial scan paths; the seeded one: initial path"));
  CHECK(q.scans() == 0);
  CHECK(rec.calls->empty());
}

TEST_CASE("robot planner: the transfer cost reorders candidates as u·exp(−λ·d) says; λ < 0 or NaN is refused",
          "[planner][robot][transfer]") {
  CHECK(nbs::transfer_cost_score(2.0, 1.0, std::log(2.0)) == Approx(1.0).epsilon(1e-15));
  CHECK(nbs::transfer_cost_score(-2.0, 1.0, std::log(2.0)) == Approx(-4.0).epsilon(1e-15));
  CHECK(nbs::transfer_cost_score(3.0, 5.0, 0.0) == 3.0);

  const nbs::test::SphereOnPedestal sphere;
  nbs::PlannerSetting s = setting(1);
  s.rescan_when_explore_empty = false;
  HeightPlanner plain({}, light_lsp(), sphere_box(), s);
  plain.robot = nbs::RobotReach<nbs::FreeFlyingSensor>({}, kStart);
  const nbs::Scan scan = sphere.scan(plain.initial_scan(0), plain.sensor(), 7);
  (void)plain.integrate(scan);
  const nbs::JointVector q = plain.robot.configuration();
  const nbs::PlanResult top = plain.next_best_scan();
  REQUIRE(top.ok());
  // S as it was scored: the chosen one (the highest start, u = 1 + z) and the rest.
  std::vector<nbs::LinearScanPath> S{top.path()};
  for (const nbs::ScanCandidate& c : plain.candidate_set()) S.push_back(c.path);
  const nbs::FreeFlyingSensor fly;
  const auto u = [](const nbs::LinearScanPath& p) { return 1.0 + p.start().position().z(); };
  const auto d = [&](const nbs::LinearScanPath& p) { return (*fly.ik(p.start().pose(), q) - q).norm(); };
  // λ that makes the nearest candidate of lower utility beat the chosen one: λ = 2·ln(u_0/u_1)/(d_0 − d_1).
  std::size_t near = 0;
  for (std::size_t i = 1; i < S.size(); ++i)
    if (d(S[i]) < d(S[near])) near = i;
  REQUIRE(near != 0);
  REQUIRE(u(S[near]) < u(S[0]));
  const double lambda = 2.0 * std::log(u(S[0]) / u(S[near])) / (d(S[0]) - d(S[near]));
  // Brute-force oracle: the largest u·exp(−λ·d) over S (ties to the lower index).
  std::size_t expected = 0;
  for (std::size_t i = 1; i < S.size(); ++i)
    if (u(S[i]) * std::exp(-lambda * d(S[i])) > u(S[expected]) * std::exp(-lambda * d(S[expected]))) expected = i;
  REQUIRE(expected != 0);  // the cost reorders

  HeightPlanner costed({}, light_lsp(), sphere_box(), s);
  nbs::RobotReach<nbs::FreeFlyingSensor>::Setting rs;
  rs.transfer_cost_weight = lambda;
  costed.robot = nbs::RobotReach<nbs::FreeFlyingSensor>({}, kStart, rs);
  (void)costed.integrate(scan);
  const nbs::PlanResult chosen = costed.next_best_scan();
  REQUIRE(chosen.ok());
  CHECK(chosen.path().start().pose().matrix() == S[expected].start().pose().matrix());
  CHECK(chosen.stats.best_utility == u(S[expected]));  // the utility, not the score

  for (const double bad : {-1.0, std::nan("")}) {
    rs.transfer_cost_weight = bad;
    CHECK_THROWS_WITH((nbs::RobotReach<nbs::FreeFlyingSensor>({}, kStart, rs)),
                      nbs_test::Contains("transfer_cost_weight must be finite and >= 0"));
  }
}

TEST_CASE("robot loop: a transfer planner for another joint count is refused before any work",
          "[planner][robot][transfer]") {
  const nbs::test::SphereOnPedestal sphere;
  nbs::NbsPlanner<> plain({}, light_lsp(), sphere_box(), setting(1));  // no robot: 0 joints
  const RecordingTransfer rec;
  CHECK_THROWS_WITH(nbs::run_simulation(plain, sphere, rec, loop_setting(3, 4)),
                    nbs_test::Contains("transfer planner has 6 joints but the planner's robot has 0"));
  CHECK(plain.scans() == 0);
  CHECK(rec.calls->empty());
}

TEST_CASE("robot planner: a utility policy returning fewer values than candidates is refused naming both counts",
          "[planner][robot]") {
  const nbs::test::SphereOnPedestal sphere;
  HeightPlanner p({}, light_lsp(), sphere_box(), setting(1));
  p.robot = nbs::RobotReach<nbs::FreeFlyingSensor>({}, kStart);
  (void)p.integrate(sphere.scan(p.initial_scan(0), p.sensor(), 7));
  p.utility.drop = 1;
  try {
    (void)p.next_best_scan();
    FAIL("no exception");
  } catch (const nbs::InvalidArgument& e) {
    const std::size_t n = p.candidate_set().size();
    REQUIRE(n > 1);
    CHECK_THAT(std::string(e.what()), nbs_test::Contains("the utility policy returned " + std::to_string(n - 1) +
                                                         " values for " + std::to_string(n) + " candidates"));
  }
  p.utility.drop = 0;
  CHECK(p.reselect().status == nbs::PlanStatus::no_candidates);  // nothing was scored
  CHECK(p.next_best_scan().ok());
}

TEST_CASE("transfer_with_retries: the failed tries' planning time is in the returned record; a last reselect() that "
          "finds nothing flyable keeps its reach checks",
          "[planner][robot][transfer]") {
  const nbs::test::SphereOnPedestal sphere;
  nbs::PlannerSetting s = setting(1);
  s.rescan_when_explore_empty = false;
  nbs::RobotPlanner<HalfSpaceFlyer> p({}, light_lsp(), sphere_box(), s);
  p.robot = nbs::RobotReach<HalfSpaceFlyer>(HalfSpaceFlyer{1e9, false, {}}, kStart);  // reaches everything
  (void)p.integrate(sphere.scan(p.initial_scan(0), p.sensor(), 7));
  nbs::PlanResult plan = p.next_best_scan();
  REQUIRE(plan.ok());
  const std::size_t left = p.candidate_set().size();
  REQUIRE(left >= 3);
  int calls = 0;
  const auto fail_twice = [&](const nbs::PlanResult&) {  // 0.25 s each; the third try succeeds
    nbs::TransferRecord t;
    t.t_plan_s = 0.25;
    if (++calls <= 2) t.failure = "test: no motion";
    return std::optional<nbs::TransferRecord>(t);
  };
  const std::optional<nbs::TransferRecord> ok = nbs::transfer_with_retries(p, plan, 5, fail_twice);
  REQUIRE(ok.has_value());
  CHECK(ok->ok());
  CHECK(ok->failed_attempts == 2);
  CHECK(ok->t_plan_s == 0.75);  // all three tries

  // Every transfer fails and the robot now reaches nothing: the reselect() after the first failure checks the
  // rest of S, finds nothing flyable, and its checks stay in the plan's statistics (its utility does not).
  const std::size_t rest = p.candidate_set().size();
  REQUIRE(rest == left - 2);
  p.robot = nbs::RobotReach<HalfSpaceFlyer>(HalfSpaceFlyer{0.0, true, {}}, kStart);
  const nbs::IterationStats before = plan.stats;
  calls = -100;
  const std::optional<nbs::TransferRecord> failed = nbs::transfer_with_retries(p, plan, 5, fail_twice);
  REQUIRE(failed.has_value());
  CHECK_FALSE(failed->ok());
  CHECK(failed->failed_attempts == 1);
  CHECK(failed->t_plan_s == 0.25);
  CHECK(plan.stats.reach_checks == before.reach_checks + rest);
  CHECK(plan.stats.unreachable == before.unreachable + rest);
  CHECK(plan.stats.best_utility == before.best_utility);
  CHECK(p.candidate_set().empty());
}
