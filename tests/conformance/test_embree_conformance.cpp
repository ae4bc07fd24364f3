// SPDX-License-Identifier: BSD-3-Clause
// Conformance of the Embree adapter's models: nbs::embree::Scene (RayCaster, against BruteForceRayCaster) and
// nbs::embree::SimulatedScanner (ScanSimulator, with a LaserStripeProfiler and with an AreaSensor; as a ScanDriver
// through nbs::SimulatedDriver).
#include "../embree/analytic_meshes.hpp"
#include "nbs/driver/simulated_driver.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/sensor/presets.hpp"
#include "nbs/sim/initial_scan_paths.hpp"
#include "nbs/sim/mesh_distance.hpp"
#include "ray_caster_conformance.hpp"
#include "scan_driver_conformance.hpp"
#include "scan_simulator_conformance.hpp"

using nbs::Vec3;

TEST_CASE("RayCaster conformance: nbs::embree::Scene", "[conformance][raycaster][embree]") {
  const nbs::IndexedMesh sphere = nbs_test::sphere_mesh(Vec3(0, 0, 0.04), 0.04, 8);
  const nbs::embree::Scene scene(sphere);
  nbs::conformance::check_ray_caster_conformance(scene, sphere);
  nbs::IndexedMesh plane = nbs_test::plane_mesh(0.05, 0.0, 4);
  const nbs::embree::Scene flat(plane);
  nbs::conformance::check_ray_caster_conformance(flat, plane, {}, 2);
}

TEST_CASE("ScanSimulator conformance: nbs::embree::SimulatedScanner, both sensor kinds",
          "[conformance][scanner][embree]") {
  const nbs::IndexedMesh sphere = nbs_test::sphere_mesh(Vec3(0, 0, 0.04), 0.04, 16);
  const nbs::embree::SimulatedScanner scanner(sphere);
  const nbs::MeshDistance distance(sphere);
  const nbs::Aabb box{Vec3(-0.06, -0.06, 0.0), Vec3(0.06, 0.06, 0.10)};
  nbs::conformance::ScanCase c;
  for (int i : {0, 1, 5, 9}) c.paths.push_back(nbs::initial_scan_path(box, 0.3, i));
  c.surface_distance = [&](const Vec3& p) { return distance.distance(p); };
  c.surface_tol_m = 2e-6;  // single-precision casts at 0.3 m
  nbs::LaserStripeProfiler lsp = nbs::presets::dlr_lsp();
  lsp.points_per_profile = 100;
  lsp.profile_spacing_m = 0.002;
  nbs::conformance::check_scan_simulator_conformance(scanner, lsp, c);

  nbs::AreaSensor cam;
  cam.width_px = 64;
  cam.height_px = 48;
  cam.horizontal_fov_rad = 0.6;
  cam.vertical_fov_rad = 0.45;
  cam.range = {0.15, 0.45};
  cam.noise = nbs::RangeNoise::constant(0.0005);
  // Area frames at the path starts and at single viewpoints looking at the centre.
  c.paths.push_back(nbs::LinearScanPath(nbs::Viewpoint::look_at(Vec3(0.3, 0.0, 0.1), Vec3(0, 0, 0.04))));
  nbs::conformance::check_scan_simulator_conformance(scanner, cam, c);
}

TEST_CASE("ScanDriver conformance: SimulatedDriver over nbs::embree::SimulatedScanner, both sensor kinds",
          "[conformance][driver][embree]") {
  const nbs::IndexedMesh sphere = nbs_test::sphere_mesh(Vec3(0, 0, 0.04), 0.04, 16);
  const nbs::embree::SimulatedScanner scanner(sphere);
  const nbs::Aabb box{Vec3(-0.06, -0.06, 0.0), Vec3(0.06, 0.06, 0.10)};
  nbs::conformance::DriverCase c;
  for (int i : {0, 5}) c.paths.push_back(nbs::initial_scan_path(box, 0.3, i));
  nbs::LaserStripeProfiler lsp = nbs::presets::dlr_lsp();
  lsp.points_per_profile = 100;
  lsp.profile_spacing_m = 0.002;
  nbs::conformance::check_scan_driver_conformance([&] { return nbs::SimulatedDriver(scanner, lsp, 9); }, c);
  nbs::AreaSensor cam;
  cam.width_px = 64;
  cam.height_px = 48;
  cam.horizontal_fov_rad = 0.6;
  cam.vertical_fov_rad = 0.45;
  cam.range = {0.15, 0.45};
  c.paths = {nbs::LinearScanPath(nbs::Viewpoint::look_at(Vec3(0.3, 0.0, 0.1), Vec3(0, 0, 0.04)))};
  nbs::conformance::check_scan_driver_conformance([&] { return nbs::SimulatedDriver(scanner, cam, 9); }, c);
}
