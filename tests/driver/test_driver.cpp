// SPDX-License-Identifier: BSD-3-Clause
// Drivers (include/nbs/driver/): the ScanDriver conformance suite on SimulatedDriver, ReplayDriver and a
// user-written flange robot; record (RecordingDriver) → replay (ReplayDriver) through run_loop into a fresh planner
// gives the in-memory planner state; the replay's errors (more scans than recorded, a path off the recorded one
// beyond the tolerance, an empty session) and bad input.

#include "nbs_catch.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "../io/temp_dir.hpp"
#include "nbs/driver/concepts.hpp"
#include "nbs/driver/recording_driver.hpp"
#include "nbs/driver/replay_driver.hpp"
#include "nbs/driver/simulated_driver.hpp"
#include "nbs/planner/nbs_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"
#include "nbs/sensor/presets.hpp"
#include "nbs/sim/initial_scan_paths.hpp"
#include "scan_driver_conformance.hpp"
#include "support/analytic_scanner.hpp"
#include "support/same_plan.hpp"

namespace {

using nbs::Aabb;
using nbs::Pose;
using nbs::Vec3;

using nbs::test::light_lsp;
using nbs::test::sphere_box;

nbs::SimulationSetting loop_setting(std::uint64_t seed, int max_scans) {
  nbs::SimulationSetting sim;
  sim.seed = seed;
  sim.max_scans = max_scans;
  return sim;
}

nbs::SessionInfo sphere_info() {
  nbs::SessionInfo info;
  info.sensor = "dlr_lsp";
  info.unknown_area = sphere_box();
  return info;
}

/// A fresh, not yet existing directory under the per-process temp dir.
std::filesystem::path fresh_dir(const std::string& stem) {
  static int n = 0;
  return nbs_test::temp_dir() / (stem + "_" + std::to_string(n++));
}

/// The user-written model: a robot that moves its flange (T_WF) and carries an LSP with hand-eye T_FS; it converts
/// at the boundary (T_WS = T_WF · T_FS) and scans the floor z = 0 without noise.
class FloorRobot {
public:
  FloorRobot() { T_FS_.translation() = Vec3(0.0, 0.0, 0.08); }
  [[nodiscard]] nbs::Scan acquire(const nbs::LinearScanPath& path) {
    nbs::Scan out;
    out.profile_poses = lsp_.profile_poses(path);
    for (std::size_t k = 0; k < out.profile_poses.size(); ++k)
      for (int i = 0; i < lsp_.points_per_profile; ++i, ++out.rays_cast) {
        const Pose& p = out.profile_poses[k];
        const Vec3 d = p.linear() * lsp_.ray_direction_sensor(i);
        const double t = d.z() < 0.0 ? -p.translation().z() / d.z() : -1.0;
        if (t > 0.0 && lsp_.range.contains(t)) out.add_point(p.translation() + t * d, static_cast<std::uint32_t>(k));
      }
    T_WF_ = nbs::flange_from_sensor(path.pose_at(1.0), T_FS_);
    return out;
  }
  void move_to(const Pose& T_WS) {
    nbs::validate_pose(T_WS, "FloorRobot::move_to: target pose");
    T_WF_ = nbs::flange_from_sensor(T_WS, T_FS_);
  }
  [[nodiscard]] Pose current_pose() const { return nbs::sensor_from_flange(T_WF_, T_FS_); }

private:
  nbs::LaserStripeProfiler lsp_ = [] {
    auto s = light_lsp();
    s.points_per_profile = 50;
    return s;
  }();
  Pose T_FS_ = Pose::Identity();
  Pose T_WF_ = Pose::Identity();
};

/// Two planners hold the same state: scans, space totals, mesh, ĉ_m, and they plan the same next scan.
template <class P>
void check_same_state(P& a, P& b) {
  CHECK(a.scans() == b.scans());
  CHECK(a.space().totals().integrated == b.space().totals().integrated);
  CHECK(a.space().totals().voxel_updates == b.space().totals().voxel_updates);
  CHECK(a.space().totals().points == b.space().totals().points);
  CHECK(a.mesh().vertex_count() == b.mesh().vertex_count());
  CHECK(a.mesh().face_count() == b.mesh().face_count());
  CHECK(a.estimated_coverage() == b.estimated_coverage());
  const nbs::PlanResult pa = a.next_best_scan(), pb = b.next_best_scan();
  REQUIRE(pa.status == pb.status);
  REQUIRE(pa.ok());
  CHECK(pa.path().start().pose().matrix() == pb.path().start().pose().matrix());
  CHECK(pa.path().end_position() == pb.path().end_position());
}

/// Records a `scans`-scan session of the loop (seed 7) on the sphere into a fresh directory.
std::filesystem::path record_sphere_session(int scans) {
  const nbs::test::SphereOnPedestal sphere;
  const auto dir = fresh_dir("sphere");
  nbs::NbsPlanner<> planner({}, light_lsp(), sphere_box());
  nbs::SimulatedDriver sim(sphere, light_lsp(), 7);
  nbs::RecordingDriver rec(sim, dir, sphere_info());
  (void)nbs::run_loop(planner, rec, loop_setting(7, scans));
  return dir;
}

}  // namespace

TEST_CASE("ScanDriver conformance: SimulatedDriver over the analytic sphere scanner", "[driver][conformance]") {
  const nbs::test::SphereOnPedestal sphere;
  nbs::conformance::DriverCase c;
  for (int i : {0, 5}) c.paths.push_back(nbs::initial_scan_path(sphere_box(), 0.3, i));
  nbs::conformance::check_scan_driver_conformance(
      [&] { return nbs::SimulatedDriver(sphere, light_lsp(), 3); }, c);
}

TEST_CASE("ScanDriver conformance: ReplayDriver over a recorded session", "[driver][conformance]") {
  const nbs::test::SphereOnPedestal sphere;
  nbs::conformance::DriverCase c;
  for (int i : {0, 5}) c.paths.push_back(nbs::initial_scan_path(sphere_box(), 0.3, i));
  const auto dir = fresh_dir("conformance");
  {
    nbs::SimulatedDriver sim(sphere, light_lsp(), 3);
    nbs::RecordingDriver rec(sim, dir, sphere_info());
    for (const auto& p : c.paths) (void)rec.acquire(p);
    CHECK(rec.writer().size() == 2);
  }
  nbs::conformance::check_scan_driver_conformance([&] { return nbs::ReplayDriver(dir); }, c);
  // The replay hands back exactly what the simulation measured.
  nbs::SimulatedDriver sim(sphere, light_lsp(), 3);
  nbs::ReplayDriver replay(dir);
  for (const auto& p : c.paths) CHECK(nbs::conformance::detail::same_scan(replay.acquire(p), sim.acquire(p)));
}

TEST_CASE("ScanDriver conformance: a user-written flange robot", "[driver][conformance]") {
  const nbs::Viewpoint down = nbs::Viewpoint::from_axes(Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, -1), Vec3(0, 0, 0.3));
  nbs::conformance::DriverCase c;
  c.paths = {nbs::LinearScanPath(down, Vec3(0, -0.05, 0.3)), nbs::LinearScanPath(down)};
  c.pose_tol_m = 1e-15;  // T_WS → T_WF → T_WS rounds
  nbs::conformance::check_scan_driver_conformance([] { return FloorRobot{}; }, c);
}

TEST_CASE("replay round trip: record the loop, replay it into a fresh planner, same planner state",
          "[driver][loop]") {
  const nbs::test::SphereOnPedestal sphere;
  const nbs::SimulationSetting sim = loop_setting(7, 3);
  const auto dir = fresh_dir("round_trip");
  nbs::NbsPlanner<> live({}, light_lsp(), sphere_box());
  nbs::SimulatedDriver sim_driver(sphere, light_lsp(), sim.seed);
  nbs::RecordingDriver rec(sim_driver, dir, sphere_info());
  const auto a = nbs::run_loop(live, rec, sim);
  REQUIRE(a.records.size() == 3);
  CHECK(rec.writer().size() == 3);

  // Recording changes nothing: the same run as run_simulation.
  nbs::NbsPlanner<> plain({}, light_lsp(), sphere_box());
  nbs::test::check_same_plan(a, nbs::run_simulation(plain, sphere, sim));

  nbs::NbsPlanner<> replayed({}, light_lsp(), sphere_box());
  nbs::ReplayDriver replay(dir);
  CHECK(replay.info().sensor == "dlr_lsp");
  const auto b = nbs::run_loop(replayed, replay, sim);
  nbs::test::check_same_plan(a, b);
  CHECK(b.stop == a.stop);
  CHECK(replay.replayed() == 3);
  CHECK(replay.remaining() == 0);
  CHECK(replay.current_pose().matrix() == a.records.back().path.pose_at(1.0).matrix());
  check_same_state(live, replayed);
}

TEST_CASE("replay: more scans than recorded, or another path, throw InvalidArgument and change nothing",
          "[driver][loop]") {
  const auto dir = record_sphere_session(2);
  {  // a longer run: the third acquire finds the session exhausted; the planner keeps its two scans
    nbs::NbsPlanner<> p({}, light_lsp(), sphere_box());
    nbs::ReplayDriver replay(dir);
    CHECK_THROWS_WITH(nbs::run_loop(p, replay, loop_setting(7, 4)),
                      nbs_test::Contains("scan 3 requested, but " + dir.string() + " has only 2 scans"));
    CHECK(p.scans() == 2);
    CHECK(replay.replayed() == 2);
  }
  {  // another initial path: the first acquire is refused before anything is integrated
    nbs::NbsPlanner<> p({}, light_lsp(), sphere_box());
    nbs::ReplayDriver replay(dir);
    nbs::SimulationSetting other = loop_setting(7, 4);
    other.initial_index = (nbs::random_initial_scan_index(7) + 1) % nbs::kInitialScanPathCount;
    CHECK_THROWS_WITH(nbs::run_loop(p, replay, other), nbs_test::Contains("is not the recorded one"));
    CHECK(p.scans() == 0);
    CHECK(replay.replayed() == 0);
  }
}

TEST_CASE("replay: the path tolerance is 1 µm and 1 µrad by default, and settable", "[driver]") {
  nbs::RecordedSession session = nbs::read_session(record_sphere_session(1));
  REQUIRE(session.scans.size() == 1);
  REQUIRE(session.scans[0].path);
  const nbs::LinearScanPath rec = *session.scans[0].path;
  const auto shifted = [&](double dx) {
    Pose s = rec.start().pose();
    s.translation().x() += dx;
    return nbs::LinearScanPath(nbs::Viewpoint(s), rec.end_position() + Vec3(dx, 0, 0));
  };
  Pose turned_pose = rec.start().pose();
  turned_pose.linear() = turned_pose.linear() * Eigen::AngleAxisd(2e-6, Vec3::UnitZ()).toRotationMatrix();
  const nbs::LinearScanPath turned(nbs::Viewpoint(turned_pose), rec.end_position());

  CHECK(nbs::ReplayDriver(session).acquire(shifted(0.5e-6)).size() == session.scans[0].scan.size());
  for (const nbs::LinearScanPath& off : {shifted(2e-6), turned}) {
    nbs::ReplayDriver d(session);
    const Pose before = d.current_pose();
    CHECK_THROWS_WITH(d.acquire(off), nbs_test::Contains("scan 1 of recorded session") &&
                                          nbs_test::Contains("rad apart (tolerance "));
    CHECK(d.replayed() == 0);
    CHECK(d.current_pose().matrix() == before.matrix());
  }
  nbs::ReplayTolerance loose;
  loose.position_m = 1e-5;
  loose.angle_rad = 1e-5;
  CHECK_NOTHROW(nbs::ReplayDriver(session, loose).acquire(shifted(2e-6)));
  CHECK_NOTHROW(nbs::ReplayDriver(session, loose).acquire(turned));
  // A scan recorded without a path is handed back for any path.
  nbs::RecordedSession no_path = session;
  no_path.scans[0].path.reset();
  nbs::ReplayDriver d(no_path);
  CHECK(d.acquire(shifted(0.1)).size() == session.scans[0].scan.size());
  CHECK(d.current_pose().matrix() == shifted(0.1).pose_at(1.0).matrix());
}

TEST_CASE("drivers: bad input throws naming the value and changes nothing", "[driver]") {
  const nbs::test::SphereOnPedestal sphere;
  nbs::RecordedSession empty;
  CHECK_THROWS_WITH(nbs::ReplayDriver(empty), nbs_test::Contains("recorded session has no scans"));
  CHECK_THROWS_AS(nbs::ReplayDriver(fresh_dir("missing")), nbs::FileError);
  nbs::RecordedSession one = nbs::read_session(record_sphere_session(1));
  for (double bad : {-1e-6, std::numeric_limits<double>::quiet_NaN()}) {
    nbs::ReplayTolerance t;
    t.position_m = bad;
    CHECK_THROWS_WITH(nbs::ReplayDriver(one, t), nbs_test::Contains("ReplayTolerance.position_m"));
    t = {};
    t.angle_rad = bad;
    CHECK_THROWS_WITH(nbs::ReplayDriver(one, t), nbs_test::Contains("ReplayTolerance.angle_rad"));
  }
  Pose bad_home = Pose::Identity();
  bad_home.linear() *= 2.0;
  CHECK_THROWS_WITH(nbs::SimulatedDriver(sphere, light_lsp(), 1, bad_home), nbs_test::Contains("home pose"));
  CHECK_THROWS_WITH(nbs::ReplayDriver(one, {}, bad_home), nbs_test::Contains("home pose"));
  // An invalid loop setting throws before the driver is touched.
  nbs::NbsPlanner<> p({}, light_lsp(), sphere_box());
  nbs::SimulatedDriver sim(sphere, light_lsp(), 1);
  CHECK_THROWS_WITH(nbs::run_loop(p, sim, loop_setting(1, 0)), nbs_test::Contains("max_scans must be >= 1, got 0"));
  CHECK(sim.scans() == 0);
  CHECK(p.scans() == 0);
  // Recording into a directory that already holds a session is refused.
  const auto dir = record_sphere_session(1);
  CHECK_THROWS_AS(nbs::RecordingDriver(sim, dir, sphere_info()), nbs::FileError);
}
