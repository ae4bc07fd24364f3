// SPDX-License-Identifier: BSD-3-Clause
// Integer 3D-DDA against brute-force enumeration of the voxels a segment crosses (exact rational arithmetic).
#include "nbs_catch.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include "nbs/space/detail/segment_walker.hpp"
#include "nbs/space/ray_traversal.hpp"
#include "nbs_random.hpp"

namespace {

using nbs::Vec3;
using nbs::VoxelKey;
using nbs::detail::SegmentWalker;
using i128 = __int128;

struct Frac {  // n / d with d > 0
  i128 n, d;
};
bool lt(Frac a, Frac b) { return a.n * b.d < b.n * a.d; }
bool le(Frac a, Frac b) { return a.n * b.d <= b.n * a.d; }

// Does the quantised segment S→E meet the voxel k? closed: the closed box; otherwise the open box.
bool meets(const std::int64_t S[3], const std::int64_t E[3], const VoxelKey& k, bool closed) {
  Frac enter{0, 1}, exit{1, 1};
  for (int a = 0; a < 3; ++a) {
    const std::int64_t lo = std::int64_t{k[a]} * SegmentWalker::kOne, hi = lo + SegmentWalker::kOne;
    const std::int64_t D = E[a] - S[a];
    if (D == 0) {
      const bool in = closed ? (S[a] >= lo && S[a] <= hi) : (S[a] > lo && S[a] < hi);
      if (!in) return false;
      continue;
    }
    Frac t0{lo - S[a], D}, t1{hi - S[a], D};
    if (D < 0) {
      t0 = {S[a] - lo, -D};
      t1 = {S[a] - hi, -D};
      std::swap(t0, t1);
    }
    if (lt(enter, t0)) enter = t0;
    if (lt(t1, exit)) exit = t1;
  }
  return closed ? le(enter, exit) : lt(enter, exit);
}

std::vector<VoxelKey> walk(const Vec3& a, const Vec3& b) {
  SegmentWalker w(a, b);
  std::vector<VoxelKey> out{w.key()};
  while (w.remaining() > 0) {
    w.step();
    out.push_back(w.key());
  }
  return out;
}

void check_segment(const Vec3& a, const Vec3& b, bool brute_force) {
  std::int64_t S[3], E[3];
  for (int i = 0; i < 3; ++i) {
    S[i] = SegmentWalker::to_fixed(a[i]);
    E[i] = SegmentWalker::to_fixed(b[i]);
  }
  const auto keys = walk(a, b);
  INFO("segment " << a.transpose() << " -> " << b.transpose());
  const VoxelKey ks{SegmentWalker::key_of_fixed(S[0]), SegmentWalker::key_of_fixed(S[1]),
                    SegmentWalker::key_of_fixed(S[2])};
  const VoxelKey ke{SegmentWalker::key_of_fixed(E[0]), SegmentWalker::key_of_fixed(E[1]),
                    SegmentWalker::key_of_fixed(E[2])};
  REQUIRE(keys.front() == ks);
  REQUIRE(keys.back() == ke);
  REQUIRE(keys.size() == 1u + std::abs(ke.x - ks.x) + std::abs(ke.y - ks.y) + std::abs(ke.z - ks.z));
  for (std::size_t i = 1; i < keys.size(); ++i) {  // face neighbours
    const int d = std::abs(keys[i].x - keys[i - 1].x) + std::abs(keys[i].y - keys[i - 1].y) +
                  std::abs(keys[i].z - keys[i - 1].z);
    REQUIRE(d == 1);
  }
  std::size_t outside_closed = 0;
  for (const auto& k : keys) outside_closed += meets(S, E, k, true) ? 0 : 1;
  REQUIRE(outside_closed == 0);  // DDA ⊆ closed
  if (!brute_force) return;
  std::set<std::tuple<int, int, int>> dda;
  for (const auto& k : keys) dda.insert({k.x, k.y, k.z});
  REQUIRE(dda.size() == keys.size());
  std::size_t missed = 0;
  for (int x = std::min(ks.x, ke.x); x <= std::max(ks.x, ke.x); ++x)
    for (int y = std::min(ks.y, ke.y); y <= std::max(ks.y, ke.y); ++y)
      for (int z = std::min(ks.z, ke.z); z <= std::max(ks.z, ke.z); ++z)
        if (meets(S, E, VoxelKey{x, y, z}, false)) missed += dda.count({x, y, z}) == 1 ? 0 : 1;
  REQUIRE(missed == 0);  // open ⊆ DDA
}

}  // namespace

TEST_CASE("DDA visits exactly the voxels a random segment crosses", "[space][dda]") {
  std::mt19937_64 rng(20240611);
  std::uniform_real_distribution<double> u(-6.0, 6.0), v(-20.0, 20.0);
  for (int i = 0; i < 3000; ++i) {
    const Vec3 a = nbs_test::random_vec3(u, rng);
    check_segment(a, nbs_test::random_vec3(u, rng), true);
  }
  for (int i = 0; i < 100; ++i) {
    const Vec3 a = nbs_test::random_vec3(v, rng);
    check_segment(a, nbs_test::random_vec3(v, rng), true);
  }
}

TEST_CASE("DDA on degenerate segments: axis-parallel, through edges and corners, single voxel", "[space][dda]") {
  check_segment(Vec3(0.5, 0.5, 0.5), Vec3(7.5, 0.5, 0.5), true);
  check_segment(Vec3(0.5, 0.5, 0.5), Vec3(-7.5, 0.5, 0.5), true);
  check_segment(Vec3(0.0, 0.0, 0.0), Vec3(5.0, 5.0, 5.0), true);    // through voxel corners
  check_segment(Vec3(-3.0, 2.0, 0.5), Vec3(3.0, -4.0, 0.5), true);  // through voxel edges
  check_segment(Vec3(1.0, 1.0, 1.0), Vec3(1.0, 1.0, 1.0), true);
  check_segment(Vec3(1.2, 1.3, 1.4), Vec3(1.7, 1.6, 1.5), true);
  check_segment(Vec3(2.0, 0.5, 0.5), Vec3(-2.0, 0.5, 0.5), true);   // starts on a boundary, moving down
}

TEST_CASE("DDA over the whole key range does not overflow", "[space][dda]") {
  std::mt19937_64 rng(99);
  const double lim = 1048575.0;
  std::uniform_real_distribution<double> u(-lim, lim);
  for (int i = 0; i < 3; ++i) {
    const Vec3 a = nbs_test::random_vec3(u, rng);
    check_segment(a, nbs_test::random_vec3(u, rng), false);
  }
  check_segment(Vec3(-lim - 0.5, -lim - 0.5, -lim - 0.5), Vec3(lim, lim, lim), false);
}

TEST_CASE("traverse_segment works in world units and rejects bad input", "[space][dda]") {
  const nbs::VoxelGrid g(0.01);
  std::vector<VoxelKey> keys;
  const auto n = nbs::traverse_segment(g, Vec3(0.005, 0.005, 0.005), Vec3(0.035, 0.005, 0.005),
                                       [&](const VoxelKey& k) { keys.push_back(k); });
  REQUIRE(n == 4);
  REQUIRE(keys == std::vector<VoxelKey>{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}});
  const auto m = nbs::traverse_segment(g, Vec3(0.005, 0.005, 0.005), Vec3(0.035, 0.005, 0.005),
                                       [&](const VoxelKey& k) { return k.x < 1; });
  REQUIRE(m == 2);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  REQUIRE_THROWS_AS(nbs::traverse_segment(g, Vec3(nan, 0, 0), Vec3(0, 0, 0), [](const VoxelKey&) {}),
                    nbs::InvalidArgument);
  REQUIRE_THROWS_AS(nbs::traverse_segment(g, Vec3(0, 0, 0), Vec3(0, 0, 1e9), [](const VoxelKey&) {}),
                    nbs::InvalidArgument);
}

namespace {
// Axis sequence of SegmentWalker::step vs its CommonDenominatorStepper on the same segment; returns whether the
// stepper was available (make() declines long segments and downward axes ending on a voxel face).
bool same_steps(const Vec3& a, const Vec3& b) {
  const nbs::detail::SegmentSetup q(a, b);
  auto fast = nbs::detail::CommonDenominatorStepper::make(q);
  if (!fast) return false;
  SegmentWalker w(q);
  INFO("segment " << a.transpose() << " -> " << b.transpose());
  while (w.remaining() > 0) REQUIRE(fast->step() == w.step());
  return true;
}
}  // namespace

TEST_CASE("common-denominator stepper takes the same steps as SegmentWalker, ties included", "[space][dda]") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-30.0, 30.0);
  std::uniform_int_distribution<int> q(-8 * 1024, 8 * 1024), g(-6, 6);
  int compared = 0;  // make() declines ends on faces moving down (about 1 in 700 random segments)
  for (int i = 0; i < 20000; ++i) {
    const Vec3 a = nbs_test::random_vec3(u, rng);
    compared += same_steps(a, nbs_test::random_vec3(u, rng));
  }
  REQUIRE(compared > 19900);
  compared = 0;
  // End points on the 1/1024 lattice and on voxel corners: many exact ties between axes and at the end.
  const auto vec = [&](auto& d, double scale) {
    const double x = d(rng) * scale, y = d(rng) * scale, z = d(rng) * scale;
    return Vec3(x, y, z);
  };
  const auto lattice = [&] { return vec(q, 1.0 / 1024.0); };
  const auto corner = [&] { return vec(g, 1.0); };
  // One draw per statement: the two end points of one call would be drawn in an unspecified order.
  const auto same_steps_of = [&](const auto& draw, const Vec3& shift) {
    const Vec3 a = draw();
    return same_steps(a, draw() + shift) ? 1 : 0;
  };
  for (int i = 0; i < 20000; ++i) compared += same_steps_of(lattice, Vec3::Zero());
  REQUIRE(compared > 19000);
  compared = 0;
  for (int i = 0; i < 5000; ++i) compared += same_steps_of(corner, Vec3::Zero());
  for (int i = 0; i < 5000; ++i) compared += same_steps_of(corner, Vec3(0.0, 0.0, 0.5));
  REQUIRE(compared > 1000);  // corner to corner: mostly declined (downward axes end on faces)
  // Ends on faces moving up, and starts on faces moving down, are served: their extra crossings have t > 1.
  REQUIRE(same_steps(Vec3(0.5, 0.5, 0.5), Vec3(3.0, 2.0, 0.5)));
  REQUIRE(same_steps(Vec3(3.0, 2.0, 1.0), Vec3(0.5, 0.3, 0.7)));
  REQUIRE(same_steps(Vec3(3.5, 2.5, 1.5), Vec3(1.0, 0.5, 0.7)));  // x moves down to the face x = 1
  REQUIRE(same_steps(Vec3(3.5, 2.5, 1.5), Vec3(1.0, 0.0, 0.7)));  // x and y move down to faces
  REQUIRE_FALSE(same_steps(Vec3(3.5, 0.5, 1.5), Vec3(1.0, 2.0, 0.7)));  // declined: x down, y up to faces
  // Ends on faces on random axes (the clipped planning rays end on the unknown-area box): every step equal.
  std::uniform_int_distribution<int> axis_mask(1, 7);
  compared = 0;
  int declined = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 a = lattice();
    Vec3 b = lattice();
    const int m = axis_mask(rng);
    for (int k = 0; k < 3; ++k)
      if ((m >> k) & 1) b[k] = std::round(b[k]);
    const bool ok = same_steps(a, b);
    compared += ok ? 1 : 0;
    declined += ok ? 0 : 1;
  }
  REQUIRE(compared > 10000);
  REQUIRE(declined > 1000);  // the SegmentWalker cases are still met
  REQUIRE(same_steps(Vec3(0.5, 0.5, 0.5), Vec3(0.5, 0.5, 0.5)));
  REQUIRE(same_steps(Vec3(2.0, 0.5, 0.5), Vec3(-2.3, 0.5, 0.5)));  // starts on a face moving down
  REQUIRE_FALSE(same_steps(Vec3(0.0, 0.0, 0.0), Vec3(-5.0, 5.0, -5.0)));  // declined: ends on faces moving down
  // Up to 1024 voxels per axis the products stay below 2^61; longer segments fall back to SegmentWalker.
  REQUIRE(same_steps(Vec3(-0.001, 0.3, -0.7), Vec3(1023.99, 1023.7, -1024.6)));
  REQUIRE(same_steps(Vec3(0, 0, 0), Vec3(1000.5, 0.5, 0.5)));
  REQUIRE_FALSE(nbs::detail::CommonDenominatorStepper::make({Vec3(0, 0, 0), Vec3(1024.5, 2.5, 1.5)}).has_value());
}

TEST_CASE("the walk's fixed-point keys are VoxelGrid::key_of of the same point", "[space][dda]") {
  using nbs::detail::SegmentSetup;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  std::uniform_int_distribution<int> q(-300, 300);
  for (const double res : {0.005, 0.002, 0.001, 0.0013}) {
    const nbs::VoxelGrid g(res);
    for (int i = 0; i < 20000; ++i) {
      // random points and points on (or one ulp beside) voxel faces, where floor decides
      Vec3 p = nbs_test::random_vec3(u, rng);
      if (i % 2 == 1) {
        const double x = q(rng) * res, y = q(rng) * res, z = q(rng) * res;
        p = Vec3(std::nextafter(x, i % 4 == 1 ? -1.0 : 1.0), y, z);
      }
      REQUIRE(SegmentSetup::key_of_fixed(SegmentSetup::to_fixed(Vec3(p * g.inverse_resolution()))) == *g.key_of(p));
    }
  }
}
