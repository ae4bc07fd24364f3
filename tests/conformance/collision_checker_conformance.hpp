// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Conformance harness for nbs::CollisionChecker (include/nbs/candidates/collision.hpp). Checked contract, for random
// rigid poses in a box around the obstacles:
//  - collides(T_WS) agrees with a brute-force oracle (tests/fcl/box_oracle.hpp: the head box against every obstacle
//    box by corner projection on the 15 separating axes, independent of nbs's SAT code); poses within `margin` of
//    contact are not judged;
//  - it is const and may run concurrently: two threads over the same poses give the sequential answers;
//  - a non-finite or non-rigid pose either gives an answer or throws InvalidArgument, nothing else;
//  - collision_free_fraction over it is in [0, 1] and 1 exactly when every portion end is free.
#include "nbs_catch.hpp"

#include <random>
#include <thread>
#include <vector>

#include "../fcl/box_oracle.hpp"
#include "nbs/candidates/collision.hpp"

namespace nbs::conformance {

struct CollisionCase {
  std::vector<Aabb> obstacles;  ///< every obstacle as a world AABB (voxels and static boxes)
  SensorHeadBox head{};         ///< the checker's head box
  Vec3 lo = Vec3::Constant(-0.2), hi = Vec3::Constant(0.2);  ///< sensor positions are drawn from [lo, hi]
  int poses = 300;
  double margin = 1e-4;         ///< oracle tolerance, metres
  bool expect_both = true;      ///< require hits and misses among the judged poses
};

template <class C>
void check_collision_checker_conformance(const C& checker, const CollisionCase& c, std::uint64_t seed = 1) {
  static_assert(CollisionChecker<C>);
  std::mt19937_64 rng(seed);
  std::vector<Pose> poses;
  for (int i = 0; i < c.poses; ++i) poses.push_back(test::random_pose(rng, c.lo, c.hi));
  std::vector<char> got(poses.size());
  int hits = 0, misses = 0, unjudged = 0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    got[i] = static_cast<bool>(checker.collides(poses[i])) ? 1 : 0;
    const int o = test::oracle_collides(c.obstacles, c.head, poses[i], c.margin);
    if (o < 0) {
      ++unjudged;
      continue;
    }
    INFO("pose " << i << "\n" << poses[i].matrix());
    REQUIRE(got[i] == o);
    (o == 1 ? hits : misses) += 1;
  }
  CHECK(unjudged <= c.poses / 10);
  if (c.expect_both) {
    CHECK(hits >= c.poses / 20);
    CHECK(misses >= c.poses / 20);
  }
  // Concurrent const calls: each thread checks every pose.
  std::vector<std::vector<char>> par(2, std::vector<char>(poses.size()));
  {
    std::vector<std::thread> threads;
    for (std::size_t t = 0; t < par.size(); ++t)
      threads.emplace_back([&, t] {
        for (std::size_t i = 0; i < poses.size(); ++i) par[t][i] = static_cast<bool>(checker.collides(poses[i]));
      });
    for (auto& th : threads) th.join();
  }
  for (const auto& p : par) CHECK(p == got);
  // Bad poses: an answer or InvalidArgument.
  Pose skew = poses.front();
  skew.linear()(0, 1) += 0.5;
  Pose nan = poses.front();
  nan.translation().x() = std::numeric_limits<double>::quiet_NaN();
  for (const Pose& bad : {skew, nan}) {
    try {
      (void)checker.collides(bad);
    } catch (const InvalidArgument&) {
    }
  }
  // Swept paths: fraction of free 10 mm portions.
  for (int i = 0; i < 10; ++i) {
    const Pose a = poses[static_cast<std::size_t>(i)];
    const LinearScanPath path(Viewpoint(a), a.translation() + a.linear().col(1) * 0.05 * i);
    const double f = collision_free_fraction(checker, path);
    CHECK(f >= 0.0);
    CHECK(f <= 1.0);
    const std::size_t n = path_portions(path.length(), 0.01);
    bool all_free = true;
    for (std::size_t k = 0; k <= n; ++k)
      all_free = all_free && !checker.collides(path.pose_at(static_cast<double>(k) / static_cast<double>(n)));
    CHECK((f == 1.0) == all_free);
  }
}

}  // namespace nbs::conformance
