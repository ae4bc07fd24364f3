// SPDX-License-Identifier: BSD-3-Clause
// The planner with the shipped arm (issue 19, item 2): every planned scan path comes with a joint trajectory that
// the arm can fly — re-checked here independently with RobotPathChecker against the planner's voxel space.

#include "nbs_catch.hpp"

#include <filesystem>

#include "nbs/kdl/urdf_robot.hpp"
#include "nbs/planner/nbs_planner.hpp"
#include "support/analytic_scanner.hpp"

using namespace nbs;
using nbs::kdl::UrdfRobot;

TEST_CASE("lwr4.urdf in the planner: each planned scan path is executable, the robot follows the scans",
          "[kdl][planner]") {
  const UrdfRobot arm =
      UrdfRobot::load(std::filesystem::path(NBS_DATA_DIR) / "robots" / "lwr4.urdf", "world", "lwr_flange", "sensor");
  JointVector home(7);
  home << 0, 0.6, 0, -1.2, 0, 0.9, 0;
  RobotReach<UrdfRobot>::Setting reach;
  reach.links.table_exempt_links = {"lwr_base_link"};  // stands on the table at z = 0 by design
  const test::SphereOnPedestal sphere;
  RobotPlanner<UrdfRobot> planner({}, test::light_lsp(), test::sphere_box());
  planner.robot = RobotReach<UrdfRobot>(arm, home, reach);

  (void)planner.integrate(sphere.scan(planner.initial_scan(0), planner.sensor(), 1));
  int planned = 0;
  for (int step = 0; step < 2; ++step) {
    const PlanResult plan = planner.next_best_scan();
    INFO("step " << step << ": " << to_string(plan.status) << ", unreachable " << plan.stats.unreachable);
    REQUIRE(plan.ok());
    const LinearScanPath& path = plan.path();
    REQUIRE(plan.joints.size() == scan_path_samples(path, reach.path.max_sample_step_m));
    CHECK(poses_agree(arm.fk(plan.joints.front()), path.pose_at(0.0), 1e-4, 1e-3));
    CHECK(poses_agree(arm.fk(plan.joints.back()), path.pose_at(1.0), 1e-4, 1e-3));
    // Independently: the same path from the trajectory's first configuration, links against the same space.
    const RobotPathChecker<UrdfRobot, ProbabilisticVoxelSpace<>> checker(arm, planner.space(), reach.links, reach.path);
    const ScanPathReach again = checker.check(path, plan.joints.front());
    INFO("re-check: " << to_string(again.failure) << " at step " << again.step << " link " << again.link);
    CHECK(again.ok());
    (void)planner.integrate(sphere.scan(path, planner.sensor(), 2 + step));
    // The robot now stands at the end of the scan it flew.
    CHECK(poses_agree(arm.fk(planner.robot.configuration()), path.pose_at(1.0), 1e-4, 1e-3));
    ++planned;
  }
  CHECK(planned == 2);
}
