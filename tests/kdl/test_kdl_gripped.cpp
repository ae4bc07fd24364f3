// SPDX-License-Identifier: BSD-3-Clause
// The LWR holding the object (Sec. 5.4, gripped/gripped_robot.hpp): RobotReach<GrippedRobot<UrdfRobot>> keeps only
// scan paths whose object poses (Eq. 5.1) the arm takes — every sample of a planned path re-checked here: the arm's
// fk of the planned joints equals object_pose_for(T_BS, the sensor pose in O).

#include "nbs_catch.hpp"

#include <cstdio>
#include <cstdlib>

#include "kdl/lwr_fixture.hpp"
#include "nbs/gripped/gripped_robot.hpp"
#include "nbs/planner/nbs_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"
#include "support/analytic_scanner.hpp"

using namespace nbs;
using nbs::kdl::UrdfRobot;

namespace {

// B = the URDF's world (LWR base at (−0.65, 0, 0)); the fixed sensor at (0.2, 0, 0.5) looking along −x (its y axis
// down), so an object 0.3 m in front of it is at (−0.1, 0, 0.5): 0.55 m in front of the arm's base.
Pose fixed_sensor() {
  Pose T = Pose::Identity();
  T.linear() << 0, 0, -1, 1, 0, 0, 0, -1, 0;  // columns x_S = y_B, y_S = −z_B, z_S = −x_B
  T.translation() = Vec3(0.2, 0, 0.5);
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
PlacedShape sensor_housing() {
  PlacedShape s;
  s.link = "fixed sensor";
  s.shape.size = Vec3(0.12, 0.06, 0.10);
  Pose T_SG = Pose::Identity();
  T_SG.translation() = Vec3(0, 0, -0.05);
  s.T_WG = fixed_sensor() * T_SG;
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
      const double t = plan.joints.size() == 1 ? 0.0 : static_cast<double>(i) / static_cast<double>(plan.joints.size() - 1);
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
