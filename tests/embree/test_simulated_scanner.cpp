// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <cmath>

#include "analytic_meshes.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/sensor/presets.hpp"

using nbs_test::Contains;
using nbs::Vec3;

namespace {

/// LSP looking straight down from height h above (0, 0), moving `length` along world x (sensor y).
nbs::LinearScanPath down_path(double h, double length) {
  const auto v = nbs::Viewpoint::from_axes({0, 1, 0}, {1, 0, 0}, {0, 0, -1}, {-0.5 * length, 0, h});
  return nbs::LinearScanPath(v, v.position() + length * v.y_axis());
}

nbs::LaserStripeProfiler noiseless_lsp() {
  auto s = nbs::presets::dlr_lsp();
  s.noise = nbs::RangeNoise();
  s.points_per_profile = 101;
  return s;
}

}  // namespace

TEST_CASE("scanning a plane without noise returns the analytic points; counts follow the path", "[embree][scanner]") {
  const double z0 = 0.05;
  const nbs::embree::SimulatedScanner scanner(nbs_test::plane_mesh(0.3, z0));
  const auto sensor = noiseless_lsp();
  const auto path = down_path(z0 + 0.3, 0.04);
  const nbs::Scan scan = scanner.scan(path, sensor, 1);
  REQUIRE_NOTHROW(scan.validate());
  CHECK(scan.profile_poses.size() == 41);
  CHECK(scan.rays_cast == 41u * 101u);
  CHECK(scan.size() == scan.rays_cast);  // the plane covers the whole fan
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const Vec3 los = scan.line_of_sight(i);
    const double d_true = (z0 - scan.origin(i).z()) / los.z();  // ray–plane distance
    CHECK((scan.points[i] - scan.origin(i)).norm() == Approx(d_true).margin(2e-6));
    CHECK(scan.points[i].z() == Approx(z0).margin(2e-6));
  }
}

TEST_CASE("scanning a sphere without noise returns points on the sphere, as the brute-force oracle",
          "[embree][scanner]") {
  const Vec3 c(0.0, 0.0, 0.06);
  const double r = 0.05;
  const nbs::IndexedMesh mesh = nbs_test::sphere_mesh(c, r, 96);
  const double sag = r * (1.0 - std::cos(std::sqrt(2.0) * std::numbers::pi / 192));  // see sphere_mesh
  const nbs::embree::SimulatedScanner scanner(mesh);
  nbs::AreaSensor cam = nbs::presets::asus_xtion_pro();
  cam.width_px = 40;
  cam.height_px = 30;
  cam.range = {0.1, 1.0};
  cam.noise = nbs::RangeNoise();
  const auto view = nbs::Viewpoint::look_at({0.3, 0.1, 0.2}, c);
  const nbs::Scan scan = scanner.scan(view, cam, 3);
  CHECK(scan.rays_cast == 1200);
  REQUIRE(scan.size() > 50);
  for (const Vec3& p : scan.points) CHECK((p - c).norm() == Approx(r).margin(sag + 1e-6));
  // Oracle: the brute-force caster over the same rays with the same range rule.
  const nbs::BruteForceRayCaster oracle(mesh);
  std::size_t expected = 0, matched = 0;
  for (const Vec3& d : cam.frame_directions(view)) {
    const auto hit = oracle.first_hit(view.position(), d, cam.range.max_m);
    if (!hit || !cam.range.contains(hit->distance) || view.position().z() + hit->distance * d.z() < 0.0) continue;
    ++expected;
    const Vec3 p = view.position() + hit->distance * d;
    for (const Vec3& q : scan.points)
      if ((q - p).norm() < 1e-5) {
        ++matched;
        break;
      }
  }
  CHECK(scan.size() == expected);
  CHECK(matched == expected);
}

TEST_CASE("noise along the ray: mean 0 and std σ(d) (Eq. 4.39) within chi-square bounds", "[embree][scanner]") {
  const double z0 = 0.02;
  const nbs::embree::SimulatedScanner scanner(nbs_test::plane_mesh(0.4, z0));
  auto sensor = nbs::presets::dlr_lsp();  // Eq. 4.39, σ(0.3 m) ≈ 1.14 mm
  sensor.points_per_profile = 200;
  const nbs::Scan scan = scanner.scan(down_path(z0 + 0.3, 0.1), sensor, 2024);
  REQUIRE(scan.size() == scan.rays_cast);
  const double n = static_cast<double>(scan.size());
  double sum = 0.0, sum2 = 0.0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const Vec3 los = scan.line_of_sight(i);
    const double d_true = (z0 - scan.origin(i).z()) / los.z();
    const double z = ((scan.points[i] - scan.origin(i)).norm() - d_true) / sensor.noise.sigma_m(d_true);
    sum += z;
    sum2 += z * z;
  }
  // Normalised residuals are N(0, 1): mean within 5/√n, Σz²/n within 5·√(2/n) of 1 (chi-square, n dof).
  CHECK(std::abs(sum / n) < 5.0 / std::sqrt(n));
  CHECK(std::abs(sum2 / n - 1.0) < 5.0 * std::sqrt(2.0 / n));
}

TEST_CASE("same seed gives the same scan, another seed another; packet and single paths agree",
          "[embree][scanner]") {
  const auto mesh = nbs_test::sphere_mesh({0, 0, 0.06}, 0.05, 32);
  const nbs::embree::SimulatedScanner packet(mesh);
  const nbs::embree::SimulatedScanner single(mesh, {.ray_mode = nbs::embree::RayMode::single});
  const auto sensor = nbs::presets::dlr_lsp();
  const auto v = nbs::Viewpoint::look_at({0.3, -0.05, 0.06}, {0, -0.05, 0.06});
  const nbs::LinearScanPath path(v, v.position() + 0.1 * v.y_axis());
  const auto a = packet.scan(path, sensor, 9);
  const auto b = packet.scan(path, sensor, 9);
  const auto c = packet.scan(path, sensor, 10);
  const auto d = single.scan(path, sensor, 9);
  REQUIRE(a.size() > 1000);
  CHECK(a.points == b.points);
  CHECK(a.profile_of_point == b.profile_of_point);
  CHECK(a.points == d.points);
  REQUIRE(a.size() == c.size());
  CHECK(a.points != c.points);
}

TEST_CASE("working range and pedestal: out-of-range surfaces and the bottom are not measured", "[embree][scanner]") {
  const auto sensor = noiseless_lsp();  // 0.15–0.45 m
  const nbs::embree::SimulatedScanner high(nbs_test::plane_mesh(0.3, 0.05));
  CHECK(high.scan(down_path(0.05 + 0.5, 0.01), sensor, 1).empty());   // beyond max range
  CHECK(high.scan(down_path(0.05 + 0.1, 0.01), sensor, 1).empty());   // closer than min range (occludes)
  CHECK_FALSE(high.scan(down_path(0.05 + 0.2, 0.01), sensor, 1).empty());
  // Looking up at the plane's underside from below the pedestal top: blocked unless the pedestal is disabled.
  const auto up = nbs::Viewpoint::from_axes({1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -0.2});
  const nbs::LinearScanPath up_path(up, up.position() + 0.01 * up.y_axis());
  CHECK(high.scan(up_path, sensor, 1).empty());
  const nbs::embree::SimulatedScanner no_pedestal(nbs_test::plane_mesh(0.3, 0.05), {.pedestal_top_z_m = std::nullopt});
  CHECK_FALSE(no_pedestal.scan(up_path, sensor, 1).empty());
  // Geometry below the pedestal top is hidden from above.
  const nbs::embree::SimulatedScanner sunken(nbs_test::plane_mesh(0.3, -0.02));
  CHECK(sunken.scan(down_path(0.2, 0.01), sensor, 1).empty());
}

TEST_CASE("scanner rejects invalid sensors and settings", "[embree][scanner][bad-input]") {
  const nbs::embree::SimulatedScanner scanner(nbs_test::plane_mesh(0.3, 0.05, 2));
  auto lsp = noiseless_lsp();
  lsp.profile_spacing_m = -1.0;
  CHECK_THROWS_WITH(scanner.scan(down_path(0.3, 0.01), lsp, 1), Contains("profile_spacing_m"));
  auto cam = nbs::presets::asus_xtion_pro();
  cam.width_px = 0;
  CHECK_THROWS_WITH(scanner.scan(nbs::Viewpoint(), cam, 1), Contains("width_px"));
  CHECK_THROWS_AS(nbs::embree::SimulatedScanner(nbs_test::plane_mesh(0.3, 0.05, 2),
                                                {.pedestal_top_z_m = std::nan("")}),
                  nbs::InvalidArgument);
}

TEST_CASE("observability_settings: the ceiling's rule is the scanner's — its sensor's working range, any incidence",
          "[embree][scanner]") {
  using nbs::embree::SimulatedScanner;
  auto lsp = noiseless_lsp();
  lsp.range = {0.12, 0.4};
  const nbs::ObservabilitySettings os = SimulatedScanner::observability_settings(lsp, 300, 2);
  CHECK(os.min_range_m == 0.12);
  CHECK(os.max_range_m == 0.4);
  CHECK(os.incidence_cutoff_rad == SimulatedScanner::max_incidence_rad);
  CHECK(os.directions == 300);
  CHECK(os.threads == 2);
  CHECK(os.min_sensor_z_m == nbs::embree::ScannerSettings{}.pedestal_top_z_m.value());
  CHECK(SimulatedScanner::observability_settings(lsp).directions == nbs::ObservabilitySettings{}.directions);
  CHECK_THROWS_WITH(SimulatedScanner::observability_settings(lsp, 0), Contains("directions"));
  lsp.range = {0.3, 0.2};
  CHECK_THROWS_AS(SimulatedScanner::observability_settings(lsp), nbs::InvalidArgument);
}

TEST_CASE("a two-coloured quad: every point gets the colour of its half; no colour without mesh colours",
          "[embree][scanner][color]") {
  const double z0 = 0.05, h = 0.1;
  const nbs::Rgb red{255, 0, 0}, blue{0, 0, 255};
  nbs::IndexedMesh quad;  // x < 0 red, x > 0 blue: two quads without shared vertices
  for (double x0 : {-h, 0.0}) {
    const auto b = static_cast<std::uint32_t>(quad.vertices.size());
    quad.vertices.insert(quad.vertices.end(), {Vec3(x0, -h, z0), Vec3(x0 + h, -h, z0), Vec3(x0 + h, h, z0),
                                               Vec3(x0, h, z0)});
    quad.triangles.push_back({b, b + 1, b + 2});
    quad.triangles.push_back({b, b + 2, b + 3});
    quad.colors.insert(quad.colors.end(), 4, x0 < 0 ? red : blue);
  }
  const nbs::embree::SimulatedScanner scanner(quad);
  REQUIRE(scanner.has_colors());
  const nbs::Scan scan = scanner.scan(down_path(z0 + 0.3, 0.04), noiseless_lsp(), 1);
  REQUIRE_NOTHROW(scan.validate());
  REQUIRE(scan.colors.size() == scan.size());
  std::size_t n_red = 0, n_blue = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const double x = scan.points[i].x();
    if (std::abs(x) < 1e-5) continue;  // on the seam either colour is right
    CHECK(scan.colors[i] == (x < 0 ? red : blue));
    (x < 0 ? n_red : n_blue) += 1;
  }
  CHECK(n_red > 1000);
  CHECK(n_blue > 1000);
  // The same points as without colour; a mesh without colours gives scans without colours.
  nbs::IndexedMesh plain = quad;
  plain.colors.clear();
  const nbs::embree::SimulatedScanner plain_scanner(plain);
  const nbs::Scan same = plain_scanner.scan(down_path(z0 + 0.3, 0.04), noiseless_lsp(), 1);
  CHECK_FALSE(same.has_colors());
  CHECK(same.points == scan.points);
}
