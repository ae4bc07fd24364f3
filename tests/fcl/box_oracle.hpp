// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Test support for sensor-head collisions: random poses, and oracles, independent of nbs's SAT code: box overlap by projecting the 8 corners of
// both boxes on the 15 candidate axes; obstacle voxels enumerated one by one over the bounding box of the unknown area.
#include <algorithm>
#include <array>
#include <limits>
#include <random>
#include <vector>

#include "nbs/candidates/collision.hpp"
#include "nbs_random.hpp"

namespace nbs::test {

// Corners of a box with centre c, axes (columns) r and half sizes h.
inline std::array<Vec3, 8> corners(const Vec3& c, const Mat3& r, const Vec3& h) {
  std::array<Vec3, 8> out;
  for (int i = 0; i < 8; ++i)
    out[i] = c + r * Vec3((i & 1 ? 1 : -1) * h.x(), (i & 2 ? 1 : -1) * h.y(), (i & 4 ? 1 : -1) * h.z());
  return out;
}

// Overlap of the head box (grown by `grow` m on every side; negative shrinks) with a world AABB: no separating axis
// among the 3 + 3 face normals and the 9 edge cross products (degenerate cross products skipped).
inline bool head_overlaps(const SensorHeadBox& head, const Pose& T_WS, const Aabb& b, double grow) {
  const Vec3 h = (0.5 * head.size_m).array() + grow;
  const Vec3 bh = (0.5 * (b.max - b.min)).array() + grow;
  if ((h.array() < 0.0).any() || (bh.array() < 0.0).any()) return false;
  const auto a = corners(T_WS * head.center_m, T_WS.linear(), h);
  const auto c = corners(b.center(), Mat3::Identity(), bh);
  std::vector<Vec3> axes;
  for (int i = 0; i < 3; ++i) {
    axes.push_back(Vec3::Unit(i));
    axes.push_back(T_WS.linear().col(i));
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const Vec3 n = Vec3::Unit(i).cross(T_WS.linear().col(j));
      if (n.norm() > 1e-9) axes.push_back(n.normalized());
    }
  for (const Vec3& ax : axes) {
    double amin = std::numeric_limits<double>::infinity(), amax = -amin, cmin = amin, cmax = -amin;
    for (const Vec3& p : a) {
      amin = std::min(amin, p.dot(ax));
      amax = std::max(amax, p.dot(ax));
    }
    for (const Vec3& p : c) {
      cmin = std::min(cmin, p.dot(ax));
      cmax = std::max(cmax, p.dot(ax));
    }
    if (amax < cmin || cmax < amin) return false;
  }
  return true;
}

// Every obstacle of the setting as a world AABB: voxels of the bounding box of the unknown area with
// p > obstacle_probability, plus the static boxes.
template <class Space>
std::vector<Aabb> obstacle_boxes(const Space& space, const CollisionSetting& s) {
  std::vector<Aabb> out;
  const KeyBox kb = space.bounds_keys();
  const double l = space.resolution_m();
  for (std::int32_t z = kb.min.z; z <= kb.max.z; ++z)
    for (std::int32_t y = kb.min.y; y <= kb.max.y; ++y)
      for (std::int32_t x = kb.min.x; x <= kb.max.x; ++x)
        if (space.probability(VoxelKey{x, y, z}) > s.obstacle_probability)
          out.push_back({Vec3(x * l, y * l, z * l), Vec3((x + 1) * l, (y + 1) * l, (z + 1) * l)});
  for (const Aabb& b : s.static_scene) out.push_back(b);
  return out;
}

// Oracle verdict for one pose: 1 = collides even with the head shrunk by `margin`, 0 = free even with the head
// grown by `margin`, -1 = too close to call.
inline int oracle_collides(const std::vector<Aabb>& obstacles, const SensorHeadBox& head, const Pose& T_WS,
                           double margin) {
  Aabb reach;  // world AABB of the grown head's corners: boxes outside it cannot meet the head
  for (const Vec3& c : corners(T_WS * head.center_m, T_WS.linear(), (0.5 * head.size_m).array() + margin))
    reach.extend(c);
  bool grown = false;
  for (const Aabb& b : obstacles) {
    if ((b.max.array() + margin < reach.min.array()).any() || (b.min.array() - margin > reach.max.array()).any())
      continue;
    if (head_overlaps(head, T_WS, b, -margin)) return 1;
    grown = grown || head_overlaps(head, T_WS, b, margin);
  }
  return grown ? -1 : 0;
}

// A pose with a uniformly random rotation and a position uniform in the box [lo, hi].
inline Pose random_pose(std::mt19937_64& rng, const Vec3& lo, const Vec3& hi) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g;
  Pose p = Pose::Identity();
  p.linear() = nbs_test::random_quaternion(g, rng).normalized().toRotationMatrix();
  for (int i = 0; i < 3; ++i) p.translation()[i] = lo[i] + u(rng) * (hi[i] - lo[i]);
  return p;
}

}  // namespace nbs::test
