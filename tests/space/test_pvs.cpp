// SPDX-License-Identifier: BSD-3-Clause
// ProbabilisticVoxelSpace front end: log-odds model by hand, bounds, bad input, statistics.
#include "nbs_catch.hpp"

#include <cmath>
#include <limits>
#include <random>

#include "nbs/space/log_odds_model.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"
#include "support/single_beam.hpp"
#include "support/random_scan.hpp"
#include "support/synthetic_scan.hpp"
#include "support/test_boxes.hpp"
#include "nbs_random.hpp"

namespace {
using nbs::Vec3;
using nbs::VoxelKey;
using LogOddsSpace = nbs::ProbabilisticVoxelSpace<nbs::HashedBlockBackend<nbs::LogOddsState>, nbs::LogOddsModel>;
using nbs_test::kCubeBox;
// Forces the generic (traits) path of ProbabilisticVoxelSpace: any backend that is not HashedBlockBackend.
template <class StateT = nbs::ThesisState>
struct Wrapped {
  using State = StateT;
  nbs::HashedBlockBackend<State> b;
  explicit Wrapped(double r) : b(r) {}
  double resolution_m() const { return b.resolution_m(); }
  State get(const VoxelKey& k) const { return b.get(k); }
  bool observed(const VoxelKey& k) const { return b.observed(k); }
  void set(const VoxelKey& k, const State& s) { b.set(k, s); }
  template <class F>
  void for_each(F&& f) const { b.for_each(f); }
  std::size_t size() const { return b.size(); }
  std::size_t memory_bytes() const { return b.memory_bytes(); }
  nbs::KeyBox observed_key_bounds() const { return b.observed_key_bounds(); }
  nbs::KeyBox key_range() const { return b.key_range(); }
};
}  // namespace

TEST_CASE("log-odds model: one beam, values as OctoMap computes them", "[space][pvs]") {
  LogOddsSpace space(0.005, kCubeBox);
  const auto st = space.integrate(nbs::test::beams_scan({{Vec3(-0.3, 0.0025, 0.0025), Vec3(0.0525, 0.0025, 0.0025)}}));
  const float miss = static_cast<float>(std::log(0.4 / 0.6)), hit = static_cast<float>(std::log(0.7 / 0.3));
  for (int x = -20; x <= 9; ++x) REQUIRE(space.state(VoxelKey{x, 0, 0}).log_odds == miss);
  REQUIRE(space.state(VoxelKey{10, 0, 0}).log_odds == hit);
  REQUIRE_FALSE(space.observed(VoxelKey{11, 0, 0}));
  REQUIRE_FALSE(space.observed(VoxelKey{-21, 0, 0}));
  REQUIRE(space.occupied(VoxelKey{10, 0, 0}));
  REQUIRE_FALSE(space.occupied(VoxelKey{9, 0, 0}));
  REQUIRE(st.voxel_updates == 31);
  // Clamping at 0.971 / 0.1192 after many independent scans.
  for (int i = 0; i < 20; ++i)
    (void)space.integrate(nbs::test::beams_scan({{Vec3(-0.3, 0.0025, 0.0025), Vec3(0.0525, 0.0025, 0.0025)}}));
  REQUIRE(space.state(VoxelKey{10, 0, 0}).log_odds == nbs::LogOddsModel::logodds(0.971));
  REQUIRE(space.state(VoxelKey{0, 0, 0}).log_odds == nbs::LogOddsModel::logodds(0.1192));
}

TEST_CASE("end points take precedence over pass-through within one scan", "[space][pvs]") {
  LogOddsSpace space(0.005, kCubeBox);
  // Beam 1 passes through voxel (10,0,0); beam 2 ends there. Order must not matter.
  (void)space.integrate(nbs::test::beams_scan({{Vec3(-0.3, 0.0025, 0.0025), Vec3(0.0825, 0.0025, 0.0025)},
                                               {Vec3(0.0525, -0.3, 0.0025), Vec3(0.0525, 0.0025, 0.0025)}}));
  REQUIRE(space.state(VoxelKey{10, 0, 0}).log_odds == nbs::LogOddsModel::logodds(0.7));
}

TEST_CASE("bad input: errors before any change, rejections counted", "[space][pvs]") {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  REQUIRE_THROWS_AS(nbs::ProbabilisticVoxelSpace<>(0.0), nbs::InvalidArgument);
  REQUIRE_THROWS_AS(nbs::ProbabilisticVoxelSpace<>(-0.01), nbs::InvalidArgument);
  REQUIRE_THROWS_AS(nbs::ProbabilisticVoxelSpace<>(nan), nbs::InvalidArgument);
  REQUIRE_THROWS_AS(nbs::ProbabilisticVoxelSpace<>(0.01, nbs::Aabb{Vec3(nan, 0, 0), Vec3(1, 1, 1)}),
                    nbs::InvalidArgument);

  nbs::ProbabilisticVoxelSpace<> space(0.005, kCubeBox);
  auto bad = nbs::test::beams_scan({{Vec3(-0.3, 0.0025, 0.0025), Vec3(0.0525, 0.0025, 0.0025)},
                                    {Vec3(-0.3, 0.0025, 0.0025), Vec3(inf, 0.0, 0.0)}});
  REQUIRE_THROWS_AS(space.integrate(bad), nbs::InvalidArgument);
  bad.points[1] = Vec3(0.01, nan, 0.0);
  REQUIRE_THROWS_AS(space.integrate(bad), nbs::InvalidArgument);
  bad.points[1] = Vec3(0.01, 0.0, 0.0);
  bad.profile_poses[1].translation() = Vec3(nan, 0, 0);  // non-finite origin
  REQUIRE_THROWS_AS(space.integrate(bad), nbs::InvalidArgument);
  bad.profile_poses[1].translation() = Vec3(-0.3, 0.0, 0.0);
  bad.profile_of_point[1] = 7;
  REQUIRE_THROWS_AS(space.integrate(bad), nbs::InvalidArgument);
  REQUIRE(nbs::observed_count(space.backend()) == 0);
  REQUIRE(space.totals().points == 0);

  const auto st = space.integrate(nbs::test::beams_scan({
      {Vec3(0.01, 0.01, 0.01), Vec3(0.01, 0.01, 0.01)},  // zero length
      {Vec3(-0.3, 0.0, 0.0), Vec3(0.2, 0.0, 0.0)},        // end point outside the unknown area
      {Vec3(-0.3, 0.0, 0.0), Vec3(0.05, 0.0, 0.0)},
  }));
  REQUIRE(st.points == 3);
  REQUIRE(st.rejected_zero_length == 1);
  REQUIRE(st.rejected_outside_bounds == 1);
  REQUIRE(st.integrated == 1);
  REQUIRE(st.points == st.integrated + st.rejected_zero_length + st.rejected_outside_bounds + st.rejected_model);

  nbs::ThesisModel::Setting s;
  s.sigma_m = [](double d) { return d > 0.2 ? std::numeric_limits<double>::quiet_NaN() : 0.001; };
  nbs::ProbabilisticVoxelSpace<> noisy(0.005, kCubeBox, nbs::ThesisModel(s));
  const auto st2 = noisy.integrate(nbs::test::beams_scan({{Vec3(-0.3, 0.0, 0.0), Vec3(0.05, 0.0, 0.0)},
                                                          {Vec3(-0.1, 0.0, 0.0), Vec3(0.05, 0.0, 0.0)}}));
  REQUIRE(st2.rejected_model == 1);
  REQUIRE(st2.integrated == 1);
}

TEST_CASE("scans far outside the unknown area leave the space unchanged", "[space][pvs]") {
  nbs::ProbabilisticVoxelSpace<> space(0.005, kCubeBox);
  const auto st = space.integrate(nbs::test::beams_scan({{Vec3(1.0, 1.0, 1.0), Vec3(1.5, 1.0, 1.0)},
                                                         {Vec3(1e6, 0.0, 0.0), Vec3(1e6, 1.0, 0.0)}}));
  REQUIRE(st.rejected_outside_bounds == 2);
  REQUIRE(nbs::observed_count(space.backend()) == 0);
}

TEST_CASE("native and generic paths agree on a synthetic LSP scan", "[space][pvs]") {
  const nbs::test::SphereLspSetup setup{.profiles = 20, .rays_per_profile = 60, .noise_sigma_m = 0.0005};
  const nbs::Aabb box{Vec3(-0.1, -0.1, 0.0), Vec3(0.1, 0.1, 0.2)};
  nbs::ProbabilisticVoxelSpace<> native(0.004, box);
  nbs::ProbabilisticVoxelSpace<Wrapped<>, nbs::ThesisModel> generic(0.004, box);
  for (int i = 0; i < 4; ++i) {
    const auto scan = nbs::test::sphere_lsp_scan(setup, nbs::test::ring_position(setup, i, 4, 0.3), 11 + i);
    const auto a = native.integrate(scan), b = generic.integrate(scan);
    REQUIRE(a.voxel_updates == b.voxel_updates);
    REQUIRE(a.voxels_same_scan == b.voxels_same_scan);
    REQUIRE(a.voxels_similar_beam == b.voxels_similar_beam);
  }
  REQUIRE(nbs::observed_count(native.backend()) == nbs::observed_count(generic.backend()));
  std::size_t occupied = 0;
  native.for_each([&](const VoxelKey& k, const nbs::ThesisState& s) {
    REQUIRE(generic.state(k) == s);
    occupied += native.model().occupied(s) ? 1 : 0;
  });
  REQUIRE(occupied > 100);
}

namespace {
// Integrates the same seeded random scans into the native space (block walk, common-denominator DDA) and the generic
// one (SegmentWalker, per-voxel backend access, hash set of touched voxels): every statistic and voxel state agrees.
template <class Model>
void check_native_equals_generic(double resolution_m, const Model& model, int scans, int profiles, int rays) {
  using State = typename Model::State;
  const nbs::Aabb box{Vec3(-0.1, -0.1, 0.0), Vec3(0.1, 0.1, 0.2)};
  nbs::ProbabilisticVoxelSpace<nbs::HashedBlockBackend<State>, Model> native(resolution_m, box, model);
  nbs::ProbabilisticVoxelSpace<Wrapped<State>, Model> generic(resolution_m, box, model);
  std::mt19937_64 rng(static_cast<std::uint64_t>(resolution_m * 1e7) + static_cast<std::uint64_t>(scans));
  for (int k = 0; k < scans; ++k) {
    const nbs::Scan scan = nbs::test::random_scan(rng, profiles, rays);
    const auto a = native.integrate(scan), b = generic.integrate(scan);
    INFO("resolution " << resolution_m << ", scan " << k);
    REQUIRE(a.integrated == b.integrated);
    REQUIRE(a.rejected_outside_bounds == b.rejected_outside_bounds);
    REQUIRE(a.voxel_updates == b.voxel_updates);
    REQUIRE(a.voxels_same_scan == b.voxels_same_scan);
    REQUIRE(a.voxels_similar_beam == b.voxels_similar_beam);
    REQUIRE(a.voxels_same_scan > 0);  // the scans do revisit voxels within a scan
  }
  REQUIRE(nbs::observed_count(native.backend()) == nbs::observed_count(generic.backend()));
  std::size_t mismatches = 0;
  native.for_each([&](const VoxelKey& k, const State& s) { mismatches += generic.state(k) == s ? 0 : 1; });
  REQUIRE(mismatches == 0);
}
}  // namespace

TEST_CASE("native update walk equals the straightforward per-voxel walk on seeded random scans", "[space][pvs]") {
  nbs::ThesisModel::Setting noisy;
  noisy.sigma_m = [](double d) { return 0.002 * d * d + 0.0002; };
  for (const double res : {0.01, 0.004, 0.0013}) {
    check_native_equals_generic(res, nbs::ThesisModel{}, 3, 12, 80);
    check_native_equals_generic(res, nbs::ThesisModel(noisy), 3, 12, 80);
    check_native_equals_generic(res, nbs::LogOddsModel{}, 3, 12, 80);
  }
  // 0.1 mm voxels: free paths of ≥ 1024 voxels along an axis take SegmentWalker's steps (no common-denominator stepper).
  check_native_equals_generic(0.0001, nbs::ThesisModel{}, 1, 2, 6);
}
