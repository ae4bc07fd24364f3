// SPDX-License-Identifier: BSD-3-Clause
// The LWR holding the object (Sec. 5.4, gripped/gripped_robot.hpp): RobotReach<GrippedRobot<UrdfRobot>> keeps only
// scan paths whose object poses (Eq. 5.1) the arm takes — every sample of a planned path re-checked here: the arm's
// fk of the planned joints equals object_pose_for(T_BS, the sensor pose in O).

#include "nbs_catch.hpp"

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "kdl/lwr_fixture.hpp"
#include "nbs/gripped/gripped_robot.hpp"
#include "nbs/planner/nbs_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"
#include "support/analytic_scanner.hpp"
#if defined(NBS_TEST_EMBREE)
#include "embree/gripped_bunny.hpp"
#include "nbs/driver/simulated_driver.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/gripped/gripped_driver.hpp"
#include "nbs/gripped/gripped_simulation.hpp"
#include "nbs/sensor/presets.hpp"
#include "nbs/sim/ground_truth.hpp"
#endif

using namespace nbs;
using nbs::kdl::UrdfRobot;

namespace {

// B = the URDF's world (LWR base at (−0.65, 0, 0)); the fixed sensor 0.5 m up looking along −x (its y axis down),
// 0.3 m in front of an object `reach_m` in front of the arm's base (default 0.55 m: the sensor at (0.2, 0, 0.5)).
Pose fixed_sensor(double reach_m = 0.55) {
  Pose T = Pose::Identity();
  T.linear() << 0, 0, -1, 1, 0, 0, 0, -1, 0;  // columns x_S = y_B, y_S = −z_B, z_S = −x_B
  T.translation() = Vec3(-0.65 + reach_m + 0.3, 0, 0.5);
  return T;
}

// The LWR carrying O 30 mm above its flange (z along the flange's z): hand_eye = T_FO.
UrdfRobot lwr_holding_object() {
  UrdfRobot arm = UrdfRobot::load(nbs_test::kLwrUrdf, "world", "lwr_flange", "lwr_flange");
  Pose T_FO = Pose::Identity();
  T_FO.translation() = Vec3(0, 0, 0.03);
  arm.set_hand_eye(T_FO);
  return arm;
}

// The fixed sensor's housing (as the URDF's sensor link), in B.
PlacedShape sensor_housing(double reach_m = 0.55) {
  PlacedShape s;
  s.link = "fixed sensor";
  s.shape.size = Vec3(0.12, 0.06, 0.10);
  Pose T_SG = Pose::Identity();
  T_SG.translation() = Vec3(0, 0, -0.05);
  s.T_WG = fixed_sensor(reach_m) * T_SG;
  return s;
}

}  // namespace

TEST_CASE("LWR holding the object: every planned scan path's object poses are reached by IK", "[kdl][gripped]") {
  const Pose T_BS = fixed_sensor();
  const GrippedRobot<UrdfRobot> robot(lwr_holding_object(), T_BS, {"lwr_flange"}, {sensor_housing()});
  // Start: the sensor 0.3 m above O looking down at the object (the palm faces the sensor).
  const Pose top = Viewpoint::look_at(Vec3(0, 0, 0.35), Vec3(0, 0, 0.05), Vec3::UnitX()).pose();
  JointVector seed(7);
  seed << 0, 0.6, 0, -1.2, 0, 0.9, 0;
  const std::optional<JointVector> home = robot.ik(top, seed);
  REQUIRE(home);

  RobotReach<GrippedRobot<UrdfRobot>>::Setting reach;
  reach.links.check_table = false;  // z = 0 of O is the palm plane; the arm is checked against the voxel space in O
  const test::SphereOnPedestal sphere;
  RobotPlanner<GrippedRobot<UrdfRobot>> planner({}, test::light_lsp(), test::sphere_box());
  planner.robot = RobotReach<GrippedRobot<UrdfRobot>>(robot, *home, reach);

  const int first = reachable_initial_index(planner, 1, std::nullopt);
  (void)planner.integrate(sphere.scan(planner.initial_scan(first), planner.sensor(), 1));
  std::size_t unreachable = 0;
  for (int step = 0; step < 2; ++step) {
    const PlanResult plan = planner.next_best_scan();
    INFO("step " << step << ": " << to_string(plan.status) << ", unreachable " << plan.stats.unreachable);
    REQUIRE(plan.ok());
    unreachable += plan.stats.unreachable;
    const LinearScanPath& path = plan.path();
    REQUIRE(plan.joints.size() == scan_path_samples(path, reach.path.max_sample_step_m));
    for (std::size_t i = 0; i < plan.joints.size(); ++i) {
      const double n = static_cast<double>(plan.joints.size() - 1);
      const double t = plan.joints.size() == 1 ? 0.0 : static_cast<double>(i) / n;
      INFO("sample " << i);
      // The arm's own fk (flange · T_FO) against Eq. 5.1 for the planned sensor pose: KDL's tolerance 1e-5.
      CHECK(poses_agree(robot.arm().fk(plan.joints[i]), object_pose_for(T_BS, path.pose_at(t)), 1e-4, 1e-3));
      CHECK(robot.arm().joint_limits().contains(plan.joints[i]));
    }
    (void)planner.integrate(sphere.scan(path, planner.sensor(), 2 + step));
    CHECK(poses_agree(robot.fk(planner.robot.configuration()), path.pose_at(1.0), 1e-4, 1e-3));
  }
  if (std::getenv("NBS_GRIPPED_VERBOSE") != nullptr)
    std::printf("LWR gripped sphere: %zu candidates removed by the reach check over 2 steps\n", unreachable);
}

#if defined(NBS_TEST_EMBREE)
// The measurement of docs/evaluation.md "Gripped object", held by the LWR: the gripped bunny (tests/embree/
// gripped_bunny.hpp), the DLR LSP, the planner's own stop, n_abort 30; the same planner type without the robot
// (RobotReach default-constructed: nothing checked) as the free-floating baseline. NBS_GRIPPED_VERBOSE=1 prints;
// NBS_GRIPPED_REACH (metres, default 0.55) moves the object (and the sensor 0.3 m beyond it) away from the arm.

TEST_CASE("LWR holding the gripped bunny: measurement (docs/evaluation.md)", "[.gripped_lwr_measure]") {
  const char* reach_env = std::getenv("NBS_GRIPPED_REACH");
  const double reach_m = reach_env != nullptr ? std::atof(reach_env) : 0.55;
  nbs_test::GrippedBunny g;
  g.setup.T_BS = fixed_sensor(reach_m);
  const embree::SimulatedScanner scanner(gripped_scene_mesh(g.setup, g.object));
  GroundTruth::Setting ts;
  ts.sample_density_per_m2 = 2.0e5;
  const GroundTruth truth(g.object, ts);
  const GrippedRobot<UrdfRobot> robot(lwr_holding_object(), g.setup.T_BS, {"lwr_flange"}, {sensor_housing(reach_m)});
  JointVector seed(7);
  seed << 0, 0.6, 0, -1.2, 0, 0.9, 0;
  const std::optional<JointVector> home =
      robot.ik(Viewpoint::look_at(Vec3(0, 0, 0.35), Vec3(0, 0, 0.05), Vec3::UnitX()).pose(), seed);
  REQUIRE(home);
  for (const bool with_arm : {true, false})
    for (std::uint64_t s = 1; s <= 3; ++s) {
      const auto t0 = std::chrono::steady_clock::now();
      PlannerSetting setting;
      setting.threads = 2;
      RobotPlanner<GrippedRobot<UrdfRobot>> planner({}, presets::dlr_lsp(), g.setup.tool_box, setting);
      RobotReach<GrippedRobot<UrdfRobot>>::Setting reach;
      reach.links.check_table = false;
      if (with_arm) planner.robot = RobotReach<GrippedRobot<UrdfRobot>>(robot, *home, reach);
      SimulatedDriver inner(scanner, planner.sensor(), s);
      GrippedDriver driver(inner, g.setup);
      SimulationSetting sim;
      sim.seed = s;
      sim.max_scans = 30;
      const auto res = run_loop(planner, driver, sim);
      std::size_t unreachable = 0, checks = 0, evaluated = 0, bad = 0;
      for (const ScanRecord& r : res.records) {
        unreachable += r.planning.unreachable;
        checks += r.planning.reach_checks;
        evaluated += r.planning.evaluated;
      }
      // Every executed path's object poses reached by the arm (sampled every 10 mm from the end of the last scan).
      JointVector q = *home;
      for (const ScanRecord& r : res.records) {
        const ScanPathReach p = check_scan_path(robot, r.path, q);
        bad += p.ok() ? 0 : 1;
        if (p.ok()) q = p.joints.back();
      }
      std::vector<Vec3> vertices;
      for (std::size_t v = 0; v < planner.mesh().vertex_count(); ++v)
        vertices.push_back(planner.mesh().position(static_cast<VertexId>(v)));
      auto tracker = truth.tracker();
      tracker.add(vertices);
      const FingerRegionCompleteness c =
          finger_region_completeness(truth.samples(), tracker.covered(), g.setup.fingers, 0.005);
      const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (std::getenv("NBS_GRIPPED_VERBOSE") != nullptr)
        std::printf("object %.2f m in front of the base, %s seed %llu: scans %zu (stop %s, initial %d), c_a %.4f, "
                    "outside finger region %.4f, in it %.4f, "
                    "candidates evaluated %zu, reach checks %zu, removed as unreachable %zu, executed paths the arm "
                    "cannot fly %zu, %.1f s\n",
                    reach_m, with_arm ? "LWR" : "free", static_cast<unsigned long long>(s), res.records.size(),
                    to_string(res.stop), res.records.front().initial_index, tracker.completeness().c_a(),
                    c.rest.c_a(), c.finger.c_a(), evaluated, checks, unreachable, bad, secs);
      if (with_arm) CHECK(bad == 0);
    }
}
#endif
