// SPDX-License-Identifier: BSD-3-Clause
// nbs::ompl: transfer motions between scan paths (Sec. 3.2.2) against a brute-force oracle — every straight motion
// of the returned path is re-checked densely with the same collision checker — plus reproducibility and bad input.
#include "nbs_catch.hpp"

#include <cmath>

#include <ompl/util/Console.h>

#include "nbs/ompl/transfer_planner.hpp"

using nbs::Aabb;
using nbs::Pose;
using nbs::Vec3;

namespace {

/// A wall x ∈ [−0.01, 0.01], y ∈ [−0.2, 0.2], z ≤ 0.3 between the two poses: the straight line collides; the
/// sensor (a point at T_WS's origin) must pass above it. A CollisionChecker model.
struct Wall {
  Aabb box{Vec3(-0.01, -0.2, -1.0), Vec3(0.01, 0.2, 0.3)};
  [[nodiscard]] bool collides(const Pose& T) const { return box.contains(T.translation()); }
};

Pose at(double x, double y, double z, double yaw) {
  Pose p = Pose::Identity();
  p.linear() = Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix();
  p.translation() = Vec3(x, y, z);
  return p;
}

nbs::ompl::TransferSetting setting() {
  nbs::ompl::TransferSetting s;
  s.workspace = Aabb{Vec3(-0.4, -0.4, 0.0), Vec3(0.4, 0.4, 0.5)};
  return s;
}

/// The oracle: every waypoint and every point of the straight motions, 1 mm apart, is collision-free and inside.
bool free_everywhere(const nbs::ompl::TransferPath& path, const Wall& wall, const Aabb& workspace) {
  for (std::size_t i = 1; i < path.poses.size(); ++i) {
    const Vec3 a = path.poses[i - 1].translation(), b = path.poses[i].translation();
    const int n = static_cast<int>(std::ceil((b - a).norm() / 0.001)) + 1;
    for (int k = 0; k <= n; ++k) {
      Pose p = path.poses[i - 1];
      p.translation() = a + (b - a) * (static_cast<double>(k) / n);
      if (wall.collides(p) || !workspace.contains(p.translation())) return false;
    }
  }
  return true;
}

}  // namespace

TEST_CASE("ompl transfer: around a wall, collision-free by a dense re-check, exact ends", "[ompl]") {
  ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
  const Wall wall;
  const Pose from = at(-0.2, 0.0, 0.1, 0.0), to = at(0.2, 0.05, 0.15, 1.0);
  const auto path = nbs::ompl::plan_transfer(from, to, wall, setting());
  REQUIRE(path.solved);
  REQUIRE(path.poses.size() >= 3);  // the straight motion collides, so at least one waypoint
  CHECK(path.poses.front().matrix() == from.matrix());
  CHECK(path.poses.back().matrix() == to.matrix());
  CHECK(free_everywhere(path, wall, setting().workspace));
  // Around the wall (over it or past its side), so longer than the straight line; the length is the waypoint sum.
  CHECK(path.length_m > (to.translation() - from.translation()).norm());
  double sum = 0.0;
  for (std::size_t i = 1; i < path.poses.size(); ++i)
    sum += (path.poses[i].translation() - path.poses[i - 1].translation()).norm();
  CHECK(path.length_m == Approx(sum));
}

TEST_CASE("ompl transfer: the same seed gives the same path; a free straight motion is one segment", "[ompl]") {
  const Wall wall;
  const Pose from = at(-0.2, 0.0, 0.1, 0.0), to = at(0.2, 0.05, 0.15, 1.0);
  const auto a = nbs::ompl::plan_transfer(from, to, wall, setting());
  const auto b = nbs::ompl::plan_transfer(from, to, wall, setting());
  REQUIRE(a.solved);
  REQUIRE(a.poses.size() == b.poses.size());
  for (std::size_t i = 0; i < a.poses.size(); ++i) CHECK(a.poses[i].matrix() == b.poses[i].matrix());

  const nbs::NoCollisions nothing;
  const auto straight = nbs::ompl::plan_transfer(from, to, nothing, setting());
  REQUIRE(straight.solved);
  CHECK(straight.poses.size() == 2);
  CHECK(straight.length_m == Approx((to.translation() - from.translation()).norm()));
}

TEST_CASE("ompl transfer: blocked ends are not solved; bad input throws", "[ompl]") {
  const Wall wall;
  const auto blocked = nbs::ompl::plan_transfer(at(0.0, 0.0, 0.1, 0.0), at(0.2, 0.0, 0.1, 0.0), wall, setting());
  CHECK_FALSE(blocked.solved);
  CHECK(blocked.poses.empty());
  const auto outside = nbs::ompl::plan_transfer(at(0.9, 0.0, 0.1, 0.0), at(0.2, 0.0, 0.1, 0.0), wall, setting());
  CHECK_FALSE(outside.solved);

  nbs::ompl::TransferSetting bad = setting();
  bad.workspace = Aabb{};
  CHECK_THROWS_AS(nbs::ompl::plan_transfer(at(0, 0, 0.1, 0), at(0.1, 0, 0.1, 0), wall, bad), nbs::InvalidArgument);
  bad = setting();
  bad.range_m = 0.0;
  CHECK_THROWS_AS(nbs::ompl::plan_transfer(at(0, 0, 0.1, 0), at(0.1, 0, 0.1, 0), wall, bad), nbs::InvalidArgument);
  Pose nan_pose = at(0, 0, 0.1, 0);
  nan_pose.translation().x() = NAN;
  CHECK_THROWS_AS(nbs::ompl::plan_transfer(nan_pose, at(0.1, 0, 0.1, 0), wall, setting()), nbs::InvalidArgument);
}
