// SPDX-License-Identifier: BSD-3-Clause
// ADD / ADD-S (recognition/pose_surface_error.hpp) against analytic cases and a brute-force nearest neighbour.
#include "nbs_catch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "nbs/mesh/border_edges.hpp"
#include "nbs/recognition/pose_surface_error.hpp"

namespace {

using nbs::Pose;
using nbs::Vec3;

/// Side samples of a cylinder about z: radius r, `around` angles k·2π/around, `heights` rings in [0, h].
std::vector<Vec3> surface_error_cylinder(double r, double h, int around, int heights) {
  std::vector<Vec3> s;
  for (int j = 0; j < heights; ++j)
    for (int k = 0; k < around; ++k) {
      const double a = 2.0 * std::numbers::pi * k / around;
      s.emplace_back(r * std::cos(a), r * std::sin(a), h * j / (heights - 1));
    }
  return s;
}

Pose surface_error_pose(double angle_z, const Vec3& t) {
  Pose T = Pose::Identity();
  T.linear() = Eigen::AngleAxisd(angle_z, Vec3::UnitZ()).toRotationMatrix();
  T.translation() = t;
  return T;
}

/// An open tube about z (radius 0.04 m, height 0.1 m) as a grid: 72 angles × 21 rings, with a window (angles 0–55°,
/// rings 5–15) cut out of the mesh. Samples: the grid vertices not strictly inside the window; `handle`: plus a
/// radial line of 7 samples out to 0.03 m beyond the tube at 180°, ring 10 (in the samples only).
struct WindowTube {
  nbs::IndexedMesh mesh;
  std::vector<Vec3> samples;
  static constexpr int around = 72, rings = 21;
  static constexpr double r = 0.04, h = 0.1;
  static bool in_window(int k, int j) { return k >= 0 && k < 11 && j >= 5 && j < 15; }  // cell (k, j)
  explicit WindowTube(bool handle) {
    const auto at = [](int k, double radius, int j) {
      const double a = 2.0 * std::numbers::pi * k / around;
      return Vec3(radius * std::cos(a), radius * std::sin(a), h * j / (rings - 1));
    };
    for (int j = 0; j < rings; ++j)
      for (int k = 0; k < around; ++k) {
        mesh.vertices.push_back(at(k, r, j));
        if (!(k > 0 && k < 11 && j > 5 && j < 15)) samples.push_back(at(k, r, j));
      }
    const auto id = [](int k, int j) { return static_cast<std::uint32_t>(j * around + (k % around)); };
    for (int j = 0; j + 1 < rings; ++j)
      for (int k = 0; k < around; ++k)
        if (!in_window(k, j)) {
          mesh.triangles.push_back({id(k, j), id(k + 1, j), id(k + 1, j + 1)});
          mesh.triangles.push_back({id(k, j), id(k + 1, j + 1), id(k, j + 1)});
        }
    if (handle)
      for (int i = 1; i <= 6; ++i) samples.push_back(at(around / 2, r + 0.005 * i, 10));
  }
};

}  // namespace

TEST_CASE("ADD-S is zero for a turn by a symmetry of the samples, ADD is the chord", "[recognition][pose_error]") {
  const double r = 0.04;
  const std::vector<Vec3> s = surface_error_cylinder(r, 0.1, 36, 5);
  const nbs::SurfacePoseMetric m(s);
  const Vec3 at(0.3, -0.2, 0.75);
  const Pose truth = surface_error_pose(0.4, at);
  const double turn = 2.0 * std::numbers::pi * 5 / 36;  // 50°: maps the samples onto themselves
  const nbs::SurfacePoseError e = m.error(truth * surface_error_pose(turn, Vec3::Zero()), truth);
  CHECK(e.add_s_m == Approx(0.0).margin(1e-12));
  CHECK(e.add_s_max_m == Approx(0.0).margin(1e-12));
  CHECK(e.add_m == Approx(2.0 * r * std::sin(turn / 2.0)).epsilon(1e-12));  // every sample moves by the chord
  const nbs::SurfacePoseError same = m.error(truth, truth);
  CHECK(same.add_m == Approx(0.0).margin(1e-15));
  CHECK(same.add_s_m == Approx(0.0).margin(1e-15));
}

TEST_CASE("ADD is the shift of a translation; ADD-S equals a brute-force nearest neighbour", "[recognition][pose_error]") {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  std::vector<Vec3> s(400);
  for (Vec3& p : s) p = Vec3(u(rng), u(rng), 0.5 * u(rng));
  const nbs::SurfacePoseMetric m(s);
  const Pose truth = surface_error_pose(-1.1, Vec3(0.1, 0.2, 0.0));
  const Vec3 shift(0.003, -0.004, 0.0);  // 5 mm in the model frame
  Pose est = truth * surface_error_pose(0.0, shift);
  CHECK(m.error(est, truth).add_m == Approx(0.005).epsilon(1e-12));
  est = truth * surface_error_pose(0.3, shift);
  const nbs::SurfacePoseError e = m.error(est, truth);
  double mean = 0.0, worst = 0.0;
  for (const Vec3& p : s) {
    const Vec3 q = truth.inverse() * est * p;
    double best = std::numeric_limits<double>::infinity();
    for (const Vec3& o : s) best = std::min(best, (q - o).norm());
    mean += best;
    worst = std::max(worst, best);
  }
  CHECK(e.add_s_m == Approx(mean / s.size()).epsilon(1e-12));
  CHECK(e.add_s_max_m == Approx(worst).epsilon(1e-12));
  CHECK(e.add_s_m <= e.add_m);
}

TEST_CASE("ADD-S is not zero for a turn that is no symmetry (an L of samples)", "[recognition][pose_error]") {
  std::vector<Vec3> s;
  for (int i = 0; i <= 20; ++i) s.emplace_back(0.005 * i, 0.0, 0.0), s.emplace_back(0.0, 0.003 * i, 0.0);
  const nbs::SurfacePoseMetric m(s);
  const nbs::SurfacePoseError e = m.error(surface_error_pose(std::numbers::pi, Vec3::Zero()), Pose::Identity());
  CHECK(e.add_s_max_m == Approx(0.1).epsilon(1e-12));  // the long arm's tip (0.1, 0) lands at (−0.1, 0)
  CHECK(e.add_s_m > 0.02);
}

TEST_CASE("SurfacePoseMetric bad input", "[recognition][pose_error][bad]") {
  CHECK_THROWS_WITH(nbs::SurfacePoseMetric(std::vector<Vec3>{}), nbs_test::Contains("no model samples"));
  const std::vector<Vec3> nan{Vec3::Zero(), Vec3(std::nan(""), 0.0, 0.0)};
  CHECK_THROWS_WITH(nbs::SurfacePoseMetric(nan), nbs_test::Contains("model sample 1 is not finite"));
  const nbs::SurfacePoseMetric m(std::vector<Vec3>{Vec3::Zero(), Vec3::UnitX()});
  Pose bad = Pose::Identity();
  bad.linear() *= 2.0;
  CHECK_THROWS_WITH((void)m.error(bad, Pose::Identity()), nbs_test::Contains("estimated pose"));
  CHECK_THROWS_WITH((void)m.error(Pose::Identity(), bad), nbs_test::Contains("true pose"));
}

TEST_CASE("ADD-S max over covered samples leaves out a partial model's holes, not a moved handle", "[recognition][pose_error]") {
  const WindowTube plain(false);
  const std::vector<Vec3> rim = nbs::border_points(plain.mesh, 0.001);
  const nbs::SurfacePoseMetric m(plain.samples, rim, 0.001);
  const Pose quarter = surface_error_pose(0.5 * std::numbers::pi, Vec3::Zero());  // a symmetry of the grid
  nbs::SurfacePoseError e = m.error(quarter, Pose::Identity());
  // The turned samples that land in the window lie up to ~5 grid steps from its rim: ADD-S max sees the hole ...
  CHECK(e.add_s_max_m > 0.015);
  // ... the covered max does not: every other sample lands on a sample, those in the window have a rim sample nearest
  CHECK(e.add_s_max_covered_m == Approx(0.0).margin(1e-12));
  const nbs::SurfacePoseMetric closed_form(plain.samples);  // no rim: the covered max is the max
  e = closed_form.error(quarter, Pose::Identity());
  CHECK(e.add_s_max_covered_m == e.add_s_max_m);

  // A handle turned by 90° lands in the air over the tube's surface, far from the window: it still counts (its tip
  // lies 0.03 m radially above a sample of the tube).
  const WindowTube mug(true);
  const nbs::SurfacePoseMetric with_handle(mug.samples, nbs::border_points(mug.mesh, 0.001), 0.001);
  e = with_handle.error(quarter, Pose::Identity());
  CHECK(e.add_s_max_covered_m == Approx(0.03).epsilon(1e-9));

  // Any pose: against brute force (nearest sample by a full scan, rim by distance to every rim point).
  const Pose est = surface_error_pose(0.7, Vec3(0.004, -0.003, 0.01));
  e = m.error(est, Pose::Identity());
  const std::vector<Vec3>& s = plain.samples;
  std::vector<bool> on_rim(s.size(), false);
  for (std::size_t i = 0; i < s.size(); ++i)
    for (const Vec3& p : rim) on_rim[i] = on_rim[i] || (p - s[i]).norm() <= 0.001;
  double covered = 0.0;
  std::size_t rims = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    std::size_t nearest = 0;
    const Vec3 q = est * s[i];
    for (std::size_t k = 0; k < s.size(); ++k)
      if ((q - s[k]).norm() < best) best = (q - s[k]).norm(), nearest = k;
    CHECK(m.rim(i) == on_rim[i]);
    rims += on_rim[i];
    if (!on_rim[nearest]) covered = std::max(covered, best);
  }
  CHECK(rims > 0);
  CHECK(e.add_s_max_covered_m == Approx(covered).epsilon(1e-12));
  CHECK(e.add_s_max_covered_m < e.add_s_max_m);
}

TEST_CASE("SurfacePoseMetric with rim points: bad input", "[recognition][pose_error][bad]") {
  const std::vector<Vec3> s{Vec3::Zero(), Vec3::UnitX()};
  const std::vector<Vec3> rim{Vec3::Zero()};
  CHECK_THROWS_WITH(nbs::SurfacePoseMetric(s, rim, -1.0), nbs_test::Contains("rim_distance_m must be finite and >= 0, got -1"));
  CHECK_THROWS_WITH(nbs::SurfacePoseMetric(s, rim, std::nan("")), nbs_test::Contains("rim_distance_m"));
  const std::vector<Vec3> bad_rim{Vec3::Zero(), Vec3(0.0, std::nan(""), 0.0)};
  CHECK_THROWS_WITH(nbs::SurfacePoseMetric(s, bad_rim, 0.1), nbs_test::Contains("rim point 1 is not finite"));
  const nbs::SurfacePoseMetric m(s, rim, 0.5);
  CHECK(m.rim(0));
  CHECK(!m.rim(1));
}
