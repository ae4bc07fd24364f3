// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Shared fixtures of the utility-term tests: a small log-odds voxel space with hand-known probabilities.
#include <cmath>
#include <cstdint>
#include <set>
#include <vector>

#include "nbs/core/scan.hpp"
#include "nbs/space/hashed_block_backend.hpp"
#include "nbs/space/log_odds_model.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"
#include "nbs/space/ray_traversal.hpp"
#include "nbs/utility/evaluate_candidates.hpp"
#include "entropy_oracle.hpp"

namespace nbs_test {

using LogOddsSpace = nbs::ProbabilisticVoxelSpace<nbs::HashedBlockBackend<nbs::LogOddsState>, nbs::LogOddsModel>;

/// 1 cm voxels, bounding box [0, 0.0999]^3 = keys 0..9 on each axis (1000 voxels).
inline LogOddsSpace make_space() {
  nbs::Aabb box;
  box.min = nbs::Vec3::Zero();
  box.max = nbs::Vec3::Constant(0.0999);
  return LogOddsSpace(0.01, box);
}

/// One scan of beams along +x from x = −0.05 at voxel-centre rows (y, z) ∈ rows, each ending in voxel x = end_x:
/// voxels x = 0 .. end_x−1 of those rows get one miss (p = 0.4), voxel end_x one hit (p = 0.7).
inline nbs::Scan rows_scan(const std::vector<std::pair<int, int>>& rows, int end_x) {
  nbs::Scan s;
  for (std::uint32_t i = 0; i < rows.size(); ++i) {
    nbs::Pose p = nbs::Pose::Identity();
    p.translation() = nbs::Vec3(-0.05, 0.01 * rows[i].first + 0.005, 0.01 * rows[i].second + 0.005);
    s.profile_poses.push_back(p);
    s.add_point(nbs::Vec3(0.01 * end_x + 0.005, p.translation().y(), p.translation().z()), i);
  }
  return s;
}

/// Evaluation setting with `n` threads.
inline nbs::EvaluationSetting threads(unsigned n) {
  nbs::EvaluationSetting s;
  s.threads = n;
  return s;
}

inline nbs::VoxelKey key(int x, int y, int z) { return {x, y, z}; }

// Brute-force oracle of e_v's sum for one candidate: enumerate each ray's voxels with traverse_segment, keep those in
// the box, stop after the first occupied one, count each key once.
inline double oracle_entropy_sum(const nbs_test::LogOddsSpace& space, const std::vector<nbs::Ray>& rays) {
  std::set<std::uint64_t> seen;
  double sum = 0.0;
  const nbs::KeyBox box = space.bounds_keys();
  for (const nbs::Ray& r : rays) {
    nbs::traverse_segment(space.grid(), r.origin, r.end, [&](const nbs::VoxelKey& k) {
      if (!box.contains(k)) return true;
      if (seen.insert(k.pack()).second) sum += H(space.probability(k));
      return !space.occupied(k);
    });
  }
  return sum;
}

/// n scan candidates on a ring around the space of make_space (radius 0.15 m, heights −3, 0, +3 cm, 3 cm paths).
inline std::vector<nbs::LinearScanPath> ring_candidates(int n) {
  std::vector<nbs::LinearScanPath> c;
  const nbs::Vec3 centre(0.05, 0.05, 0.05);
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * 3.141592653589793 * i / n;
    const nbs::Vec3 p = centre + nbs::Vec3(0.15 * std::cos(a), 0.15 * std::sin(a), 0.03 * (i % 3 - 1));
    const nbs::Viewpoint v = nbs::Viewpoint::look_at(p, centre);
    c.emplace_back(v, p + 0.03 * v.y_axis());
  }
  return c;
}

}  // namespace nbs_test
