// SPDX-License-Identifier: BSD-3-Clause
// CoverageEstimator conformance: ThesisCoverage, UnseenLoopCoverage (with and without the enclosure and free-space
// tests), SelectableCoverage (all four forms) and a user-written estimator, on a cube and on the cube without its
// top face.
// Oracle: the analytic areas — A_filled = 5 s², one border loop of 4 edges with A_hole = s² (Eq. 4.37), so Eq. 4.35
// gives 5/6; the unseen forms weight the loop by the share of its fan samples that are not seen (Sec. 4.5.1's
// surface voxels, or walled in with the enclosure test, or measured free with the free-space test).
#include "nbs_catch.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "coverage_estimator_conformance.hpp"
#include "indexed_edge_mesh.hpp"
#include "my_voxel_space.hpp"

namespace {

using nbs::Vec3;
constexpr double kSide = 0.0425;  // the top face lies mid-voxel at l_v = 5 mm (voxel z key 8)

/// The cube [0, s]³ with outward counter-clockwise faces, without its top face if `open`.
nbs::conformance::IndexedEdgeMesh box_mesh(bool open) {
  nbs::IndexedMesh m;
  const double s = kSide;
  m.vertices = {{0, 0, 0}, {s, 0, 0}, {s, s, 0}, {0, s, 0}, {0, 0, s}, {s, 0, s}, {s, s, s}, {0, s, s}};
  m.triangles = {{0, 2, 1}, {0, 3, 2}, {0, 1, 5}, {0, 5, 4}, {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6},
                 {3, 0, 4}, {3, 4, 7}};
  if (!open) {
    m.triangles.push_back({4, 5, 6});
    m.triangles.push_back({4, 6, 7});
  }
  return nbs::conformance::IndexedEdgeMesh(std::move(m));
}

const nbs::Aabb kBox{Vec3(-0.1, -0.1, -0.1), Vec3(0.15, 0.15, 0.15)};

/// One scan from 0.12 m above the box's centre: a 43 × 43 grid of points (1 mm apart, covering [0, s]²) at height
/// `z` (m). Every beam crosses the top face's plane; its voxels become surface (z = s) or free (z below it).
nbs::Scan grid_scan_at(double z) {
  nbs::Scan scan;
  nbs::Pose o = nbs::Pose::Identity();
  o.translation() = Vec3(kSide / 2, kSide / 2, 0.12);
  scan.profile_poses.push_back(o);
  for (int i = 0; i <= 42; ++i)
    for (int j = 0; j <= 42; ++j) scan.add_point(Vec3(0.001 * i + 0.0002, 0.001 * j + 0.0002, z), 0);
  return scan;
}

/// Points on the missing top face: its voxels become surface (p > 0.6).
nbs::Scan top_face_scan() { return grid_scan_at(kSide); }

/// Beams through the missing top face onto the floor (z = 0.2 mm): the top face's voxels are measured free (several
/// beams each), the floor's are surface — looking into a cup.
nbs::Scan into_box_scan() { return grid_scan_at(0.0002); }

/// Three spherical layers of points around the box (radii 70–76 mm), each beam 2 mm long from just inside its point:
/// a closed shell of surface voxels that walls the top face in (and leaves the box's voxels unknown).
nbs::Scan shell_scan() {
  nbs::Scan scan;
  const Vec3 c = Vec3::Constant(kSide / 2);
  const int n = 20000;
  for (const double r : {0.070, 0.073, 0.076})
    for (int j = 0; j < n; ++j) {
      const double z = 1.0 - 2.0 * (j + 0.5) / n, rho = std::sqrt(1.0 - z * z);
      const double a = j * std::numbers::pi * (3.0 - std::sqrt(5.0));
      const Vec3 d(rho * std::cos(a), rho * std::sin(a), z);
      nbs::Pose o = nbs::Pose::Identity();
      o.translation() = c + (r - 0.002) * d;
      scan.profile_poses.push_back(o);
      scan.add_point(c + r * d, static_cast<std::uint32_t>(scan.profile_poses.size() - 1));
    }
  return scan;
}

/// A user's estimator: the filled area over an area the user knows the object has (clamped to 1).
struct KnownAreaCoverage {
  struct Setting {
    double object_area_m2 = 6 * kSide * kSide;
  };
  Setting setting{};
  template <class Mesh, class Space>
  [[nodiscard]] nbs::CoverageResult estimate(const nbs::CoverageInput<Mesh, Space>& in) const {
    return {std::min(1.0, nbs::filled_area(in.mesh) / setting.object_area_m2), 0};
  }
};

template <class C>
nbs::CoverageResult on_open_box(const C& c, const MyVoxelSpace& space, const nbs::Parameters& params = {}) {
  const auto open = box_mesh(true);
  return c.estimate(nbs::CoverageInput<nbs::conformance::IndexedEdgeMesh, MyVoxelSpace>{open, space, params, kBox});
}

}  // namespace

TEMPLATE_TEST_CASE("CoverageEstimator conformance", "[conformance][coverage]", nbs::ThesisCoverage,
                   nbs::UnseenLoopCoverage, nbs::SelectableCoverage, KnownAreaCoverage) {
  const MyVoxelSpace space(0.005, kBox);
  nbs::conformance::check_coverage_estimator_conformance(TestType{}, nbs::conformance::IndexedEdgeMesh({}),
                                                          box_mesh(false), box_mesh(true), space, nbs::Parameters{},
                                                          kBox);
}

TEST_CASE("ĉ_m forms on the open box: Eq. 4.35 is 5/6; the unseen forms drop the loop once it is seen",
          "[conformance][coverage]") {
  const nbs::UnseenLoopCoverage open_form{{.enclosure = true, .free_space = false}},
      loops_form{{.enclosure = false, .free_space = false}}, unknown_form{};
  const nbs::ThesisCoverage thesis;
  const double five_sixths = 5.0 / 6.0;
  SECTION("nothing seen: every form counts the whole loop") {
    const MyVoxelSpace empty(0.005, kBox);
    const auto t = on_open_box(thesis, empty);
    CHECK(t.coverage == Approx(five_sixths).epsilon(1e-12));
    CHECK(t.holes == 1);
    CHECK(on_open_box(loops_form, empty).coverage == Approx(five_sixths).epsilon(1e-12));
    CHECK(on_open_box(open_form, empty).coverage == Approx(five_sixths).epsilon(1e-12));
    CHECK(on_open_box(unknown_form, empty).coverage == Approx(five_sixths).epsilon(1e-12));
    CHECK(on_open_box(nbs::SelectableCoverage{}, empty).coverage == on_open_box(unknown_form, empty).coverage);
    // Where the missing surface is: the top face's fan, 3 samples per loop edge, their areas summing to its area.
    for (const nbs::CoverageResult& r : {t, on_open_box(loops_form, empty), on_open_box(unknown_form, empty)}) {
      double area = 0.0;
      for (const nbs::UnseenSample& u : r.unseen) {
        area += u.area_m2;
        CHECK(u.position.z() == Approx(kSide).margin(1e-12));  // on the top face
      }
      CHECK(area == Approx(kSide * kSide).epsilon(1e-9));
      CHECK(r.unseen.size() % 3 == 0);
    }
  }
  SECTION("the top face measured as surface: the unseen forms reach 1, Eq. 4.35 does not look at the space") {
    MyVoxelSpace seen(0.005, kBox);
    (void)seen.integrate(top_face_scan());
    CHECK(on_open_box(thesis, seen).coverage == Approx(five_sixths).epsilon(1e-12));
    CHECK(on_open_box(loops_form, seen).coverage == Approx(1.0).epsilon(1e-12));
    CHECK(on_open_box(open_form, seen).coverage == Approx(1.0).epsilon(1e-12));
    CHECK(on_open_box(unknown_form, seen).coverage == Approx(1.0).epsilon(1e-12));
    CHECK(on_open_box(unknown_form, seen).unseen.empty());
    CHECK(on_open_box(thesis, seen).unseen.size() == on_open_box(thesis, MyVoxelSpace(0.005, kBox)).unseen.size());
  }
  SECTION("beams through the top face into the box: the free-seam rule calls a long loop's free fan seen") {
    // The fan of the top loop lies in voxels a beam passed through: no surface can be there (the mug's cavity).
    MyVoxelSpace through(0.005, kBox);
    (void)through.integrate(into_box_scan());
    REQUIRE(through.probability(Vec3(kSide / 2, kSide / 2, kSide)) < 0.45);
    nbs::Parameters long_loop;  // the loop's 4 edges count as a long loop (> h_max): the rule applies
    long_loop.hole_max_edges = 3;
    CHECK(on_open_box(loops_form, through, long_loop).coverage == Approx(five_sixths).epsilon(1e-12));
    CHECK(on_open_box(open_form, through, long_loop).coverage == Approx(five_sixths).epsilon(1e-12));  // open on top
    CHECK(on_open_box(unknown_form, through, long_loop).coverage == Approx(1.0).epsilon(1e-12));
    CHECK(on_open_box(nbs::SelectableCoverage{}, through, long_loop).coverage == Approx(1.0).epsilon(1e-12));
    const nbs::SelectableCoverage old_default{{nbs::CoverageEstimate::unseen_open}};
    CHECK(on_open_box(old_default, through, long_loop).coverage == Approx(five_sixths).epsilon(1e-12));
    // A short loop (≤ h_max, a hole of Sec. 4.4) stays unseen although its fan is free: the rule is for seams.
    CHECK(on_open_box(unknown_form, through).coverage == Approx(five_sixths).epsilon(1e-12));
    // Above min_free_share = 1 nothing is a seam.
    nbs::UnseenLoopCoverage strict;
    strict.setting.min_free_share = 1.01;
    CHECK(on_open_box(strict, through, long_loop).coverage == Approx(five_sixths).epsilon(1e-12));
  }
  SECTION("the top face walled in by surface: only the enclosure test calls it seen") {
    MyVoxelSpace shell(0.005, kBox);
    (void)shell.integrate(shell_scan());
    CHECK(on_open_box(loops_form, shell).coverage == Approx(five_sixths).epsilon(1e-12));
    CHECK(on_open_box(open_form, shell).coverage == Approx(1.0).epsilon(1e-12));
    CHECK(on_open_box(unknown_form, shell).coverage == Approx(1.0).epsilon(1e-12));
    const nbs::SelectableCoverage by_name{{nbs::CoverageEstimate::unseen_loops}};
    CHECK(on_open_box(by_name, shell).coverage == on_open_box(loops_form, shell).coverage);
  }
}
