// SPDX-License-Identifier: BSD-3-Clause
// plan_joint_transfer with the shipped arm (data/robots/lwr4.urdf) around a bunny-sized box of unknown voxels: two
// scan start poses level with the box on either side of the base's line of sight (the straight joint motion drives a
// link through the box); the path found passes LinkCollisionChecker 4× denser than the planner checked it (the
// checker itself is tested against brute-force oracles in tests/robot and tests/kdl), within the limits, exact ends.
#include "nbs_catch.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>

#include <ompl/util/Console.h>

#include "nbs/kdl/urdf_robot.hpp"
#include "nbs/ompl/joint_transfer_planner.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"

using namespace nbs;

namespace {

/// The sensor pose looking at `centre` from 0.3 m at elevation 0 and azimuth az (radians), +y horizontal.
Pose level_view(const Vec3& centre, double az) {
  const Vec3 eye = centre + 0.3 * Vec3(std::cos(az), std::sin(az), 0.0);
  const Vec3 z = (centre - eye).normalized();
  const Vec3 x = Vec3::UnitZ().cross(z).normalized();
  Pose T = Pose::Identity();
  T.linear() << x, z.cross(x), z;
  T.translation() = eye;
  return T;
}

}  // namespace

TEST_CASE("joint transfer: lwr4.urdf between two views level with a box of unknown voxels", "[ompl][joint][kdl]") {
  ::ompl::msg::setLogLevel(::ompl::msg::LOG_WARN);
  const auto robot =
      kdl::UrdfRobot::load(std::filesystem::path(NBS_DATA_DIR) / "robots" / "lwr4.urdf", "world", "lwr_flange",
                           "sensor");
  const ProbabilisticVoxelSpace<> space(0.005, Aabb{Vec3(-0.08, -0.08, 0.0), Vec3(0.08, 0.08, 0.16)});
  LinkCollisionSetting link_setting;
  link_setting.table_exempt_links = {"lwr_base_link"};
  const LinkCollisionChecker links(robot, space, link_setting);

  JointVector home(7);
  home << 0, 0.6, 0, -1.2, 0, 0.9, 0;
  const double pi = std::numbers::pi;
  const auto from = robot.ik(level_view(Vec3(0, 0, 0.08), 0.75 * pi), home);
  REQUIRE(from);
  const auto to = robot.ik(level_view(Vec3(0, 0, 0.08), 1.25 * pi), *from);
  REQUIRE(to);
  REQUIRE_FALSE(links.collides(*from));
  REQUIRE_FALSE(links.collides(*to));
  bool straight_collides = false;
  for (int k = 0; k <= 1000 && !straight_collides; ++k)
    straight_collides = links.collides(*from + (*to - *from) * (k / 1000.0));
  REQUIRE(straight_collides);

  nbs::ompl::JointTransferSetting setting;
  const auto t = nbs::ompl::plan_joint_transfer(robot, links, *from, *to, setting);
  INFO(t.reason);
  REQUIRE(t.ok());
  CHECK(t.iterations > 0);
  REQUIRE(t.waypoints.size() >= 3);
  CHECK(t.waypoints.front() == *from);
  CHECK(t.waypoints.back() == *to);
  const JointLimits lim = robot.joint_limits();
  bool free = true;
  for (std::size_t i = 1; i < t.waypoints.size(); ++i) {
    const JointVector& a = t.waypoints[i - 1];
    const JointVector& b = t.waypoints[i];
    const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / (0.25 * setting.check_resolution))));
    for (int k = 0; k <= n; ++k) {
      const JointVector q = a + (b - a) * (static_cast<double>(k) / n);
      free = free && lim.contains(q) && !links.collides(q);
    }
  }
  CHECK(free);
  CHECK(t.sensor_length_m >= (robot.fk(*to).translation() - robot.fk(*from).translation()).norm());
}
