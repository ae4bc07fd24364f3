// SPDX-License-Identifier: BSD-3-Clause
// The thesis update model (Sec. 3.3.2, Eqs. 3.4–3.8) against hand-computed values.
#include "nbs_catch.hpp"

#include <cmath>
#include <numbers>

#include "nbs/space/probabilistic_voxel_space.hpp"
#include "support/single_beam.hpp"
#include "support/test_boxes.hpp"

namespace {

using nbs::Vec3;
using nbs::VoxelKey;
using Space = nbs::ProbabilisticVoxelSpace<>;  // native backend, thesis model

double logit(double p) { return std::log(p / (1.0 - p)); }
int fixed(double l) { return static_cast<int>(std::lround(1024.0 * l)); }
// Inverse model of the file comment with p_hit 0.7, p_free 0.4.
double inverse(double z) {
  const double g = std::exp(-0.5 * z * z);
  return z <= 0 ? 0.4 + 0.3 * g : 0.5 + 0.2 * g;
}
// z after quantisation to the 1025-entry table over [−3, 3].
double lut_z(double z) { return std::lround((z + 3.0) * 1024.0 / 6.0) * 6.0 / 1024.0 - 3.0; }

nbs::ThesisModel model_with_sigma(double sigma) {
  nbs::ThesisModel::Setting s;
  s.sigma_m = [sigma](double) { return sigma; };
  return nbs::ThesisModel(s);
}

using nbs_test::kCubeBox;
const Vec3 kEnd(0.0525, 0.0025, 0.0025);  // centre of voxel (10, 0, 0) at 5 mm

}  // namespace

TEST_CASE("thesis model: hand-computed single-beam update", "[space][thesis]") {
  Space space(0.005, kCubeBox, model_with_sigma(0.002));  // band ±6 mm
  const auto st = space.integrate(nbs::test::beams_scan({{Vec3(-0.3, 0.0025, 0.0025), kEnd}}));
  REQUIRE(st.integrated == 1);
  const int e_free = fixed(logit(0.4));
  REQUIRE(e_free == -415);
  for (int x = -20; x <= 8; ++x) {  // from the box face x = −0.1 up to the band
    const auto s = space.state(VoxelKey{x, 0, 0});
    REQUIRE(s.free == e_free);
    REQUIRE(s.surf == 0);
    REQUIRE(s.spec == 0);
  }
  REQUIRE_FALSE(space.observed(VoxelKey{-21, 0, 0}));  // outside the unknown area
  // Band voxel in front: z = −2.5 → evidence < 0 goes to the free state.
  const auto s9 = space.state(VoxelKey{9, 0, 0});
  REQUIRE(s9.free == fixed(logit(inverse(lut_z(-2.5)))));
  REQUIRE(s9.surf == 0);
  // End-point voxel: peak evidence log(0.7/0.3).
  const auto s10 = space.state(VoxelKey{10, 0, 0});
  REQUIRE(s10.surf == 868);
  REQUIRE(s10.free == 0);
  REQUIRE(space.probability(VoxelKey{10, 0, 0}) == Approx(1.0 - 1.0 / (1.0 + std::exp(868.0 / 1024.0))));
  // Behind the surface: z = +2.5 → weak positive evidence, returning to unknown beyond the band.
  REQUIRE(space.state(VoxelKey{11, 0, 0}).surf == fixed(logit(inverse(lut_z(2.5)))));
  REQUIRE_FALSE(space.observed(VoxelKey{12, 0, 0}));
  REQUIRE(space.probability(VoxelKey{12, 0, 0}) == 0.5);
  REQUIRE(space.probability(VoxelKey{0, 0, 0}) == Approx(1.0 - 1.0 / (1.0 + std::exp(-415.0 / 1024.0))));
  REQUIRE(st.voxel_updates == 29 + 3);
}

TEST_CASE("thesis model: specular state (Eq. 3.6) and occupancy (Eq. 3.8)", "[space][thesis]") {
  Space space(0.005, kCubeBox, model_with_sigma(0.002));
  (void)space.integrate(nbs::test::beams_scan({{Vec3(-0.3, 0.0025, 0.0025), kEnd}}));
  // A beam along +y passes through the hit voxel: it is measured free now.
  (void)space.integrate(nbs::test::beams_scan({{Vec3(0.0525, -0.3, 0.0025), Vec3(0.0525, 0.0825, 0.0025)}}));
  const auto s = space.state(VoxelKey{10, 0, 0});
  REQUIRE(s.surf == 868);
  REQUIRE(s.free == -415);
  const int spec_q = static_cast<int>(std::lround(868.0 * 255.0 / (3.0 * 1024.0)));  // min(log L_surf / 3, 1)
  REQUIRE(s.spec == spec_q);
  const double spec = spec_q / 255.0;
  const double l = 868.0 / 1024.0 + std::log(std::exp(-415.0 / 1024.0) * (1.0 - spec) + spec);
  REQUIRE(space.model().log_odds(s) == Approx(l).epsilon(1e-12));
  REQUIRE(space.probability(VoxelKey{10, 0, 0}) == Approx(1.0 - 1.0 / (1.0 + std::exp(l))));
}

TEST_CASE("thesis model: repeated independent observations converge", "[space][thesis]") {
  Space space(0.005, kCubeBox, model_with_sigma(0.001));
  const Vec3 target(0.0025, 0.0025, 0.0025);  // centre of voxel (0, 0, 0)
  double p_hit = 0.5, p_free = 0.5;
  for (int i = 0; i < 24; ++i) {
    const double a = i * 2.0 * std::numbers::pi / 24.0;
    const Vec3 dir(std::cos(a), std::sin(a), 0.3);
    // Beam i ends in voxel (0,0,0); it also passes through voxel (0,0,4)-ish? No: a second beam crosses (0,0,6).
    const Vec3 free_target(0.0025, 0.0025, 0.0325);
    const auto st = space.integrate(
        nbs::test::beams_scan({{target + 0.3 * dir.normalized(), target},
                               {free_target + 0.3 * dir.normalized(), free_target - 0.03 * dir.normalized()}}));
    REQUIRE(st.integrated == 2);
    const double ph = space.probability(VoxelKey{0, 0, 0});
    const double pf = space.probability(VoxelKey{0, 0, 6});
    REQUIRE(ph >= p_hit);
    REQUIRE(pf <= p_free);
    p_hit = ph;
    p_free = pf;
  }
  REQUIRE(p_hit > 0.999);
  REQUIRE(p_free < 0.001);
}

TEST_CASE("thesis model: beam independence rejects repeated and similar beams", "[space][thesis]") {
  Space space(0.005, kCubeBox, model_with_sigma(0.002));
  const auto scan = nbs::test::beams_scan({{Vec3(-0.3, 0.0025, 0.0025), kEnd}});
  const auto first = space.integrate(scan);
  const auto before = space.state(VoxelKey{0, 0, 0});
  const auto again = space.integrate(scan);  // same origin and direction: not independent
  REQUIRE(again.voxel_updates == 0);
  REQUIRE(again.voxels_similar_beam == first.voxel_updates);
  REQUIRE(space.state(VoxelKey{0, 0, 0}) == before);
  // Within one scan each voxel is updated once: a duplicate beam only counts skips.
  Space twice(0.005, kCubeBox, model_with_sigma(0.002));
  const auto dup = twice.integrate(nbs::test::beams_scan({{Vec3(-0.3, 0.0025, 0.0025), kEnd},
                                                          {Vec3(-0.3, 0.0026, 0.0025), kEnd}}));
  REQUIRE(dup.voxel_updates == first.voxel_updates);
  REQUIRE(dup.voxels_same_scan >= first.voxel_updates - 1);
  REQUIRE(twice.state(VoxelKey{0, 0, 0}) == before);
}

TEST_CASE("thesis model: far-range noise widens the occupied band", "[space][thesis]") {
  nbs::ThesisModel::Setting s;
  s.sigma_m = [](double d) { return 0.01 * d; };  // σ grows with range
  const auto band = [&](double range) {
    Space space(0.001, {}, nbs::ThesisModel(s));
    const Vec3 end(0.0005, 0.0005, 0.0005);
    (void)space.integrate(nbs::test::beams_scan({{end - Vec3(range, 0, 0), end}}));
    int n = 0;
    for (int x = -100; x <= 100; ++x) n += space.probability(VoxelKey{x, 0, 0}) > 0.5 ? 1 : 0;
    return n;
  };
  const int near = band(0.15), far = band(0.45);  // σ = 1.5 mm and 4.5 mm
  // P > 0.5 for z ∈ (−1.48, 3]: ≈ 4.48 σ / 1 mm voxels.
  REQUIRE(near >= 5);
  REQUIRE(near <= 8);
  REQUIRE(far >= 18);
  REQUIRE(far <= 22);
}

TEST_CASE("thesis model: lookup table and settings", "[space][thesis]") {
  const nbs::ThesisModel m;
  REQUIRE(m.lut(512) == 868);  // z = 0
  REQUIRE(m.lut(0) == fixed(logit(inverse(-3.0))));
  REQUIRE(m.lut(1024) == fixed(logit(inverse(3.0))));
  REQUIRE(m.free_evidence() == -415);
  REQUIRE(m.probability(nbs::ThesisState{}) == 0.5);
  nbs::ThesisModel::Setting bad;
  bad.prob_hit = 0.4;
  REQUIRE_THROWS_AS(nbs::ThesisModel(bad), nbs::InvalidArgument);
  bad = {};
  bad.sigma_m = nullptr;
  REQUIRE_THROWS_AS(nbs::ThesisModel(bad), nbs::InvalidArgument);
}
