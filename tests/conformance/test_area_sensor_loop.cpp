// SPDX-License-Identifier: BSD-3-Clause
// The closed loop with an area sensor (issue 16): NbsPlanner<..., AreaSensor> through run_simulation with the
// Embree scanner on a small analytic sphere on the pedestal. Lean: a 128 × 96 image, 5 mm voxels, four scans.

#include "nbs_catch.hpp"
#include "nbs_small_camera.hpp"

#include <vector>

#include "../embree/analytic_meshes.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/planner/nbs_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"
#include "nbs/sim/completeness.hpp"
#include "nbs/sim/surface_samples.hpp"

namespace {

using nbs::Vec3;
using AreaPlanner = nbs::NbsPlanner<nbs::IgQualityUtility, nbs::BoundaryHoleSpace, nbs::AreaSensor>;

static_assert(nbs::ScanSimulator<nbs::embree::SimulatedScanner, nbs::AreaSensor>);
static_assert(nbs::ScanSimulator<nbs::embree::SimulatedScanner, nbs::LaserStripeProfiler>);

using nbs_test::small_camera;

/// Validates every scan it returns and checks it is one frame at the start of the path it was given.
struct CheckedScanner {
  const nbs::embree::SimulatedScanner* scanner;
  mutable std::vector<Vec3> points;  // all measured points so far (single-threaded loop)
  [[nodiscard]] nbs::Scan scan(const nbs::LinearScanPath& path, const nbs::AreaSensor& s, std::uint64_t seed) const {
    nbs::Scan out = scanner->scan(path, s, seed);
    out.validate();
    REQUIRE(out.profile_poses.size() == 1);
    CHECK(out.profile_poses[0].matrix() == path.start().pose().matrix());
    CHECK(out.rays_cast == s.ray_count());
    points.insert(points.end(), out.points.begin(), out.points.end());
    return out;
  }
};

}  // namespace

TEST_CASE("area sensor closes the loop: one frame per scan, coverage grows, same seed same plan",
          "[conformance][loop][area]") {
  const nbs::IndexedMesh sphere = nbs_test::sphere_mesh(Vec3(0, 0, 0.04), 0.04, 24);
  const nbs::embree::SimulatedScanner embree(sphere);
  const nbs::Aabb box{Vec3(-0.06, -0.06, 0.0), Vec3(0.06, 0.06, 0.10)};
  nbs::Parameters params;
  params.voxel_size_m = 0.005;
  nbs::SimulationSetting sim;
  sim.seed = 11;
  sim.max_scans = 4;

  // The scanner's path overload is the viewpoint overload at path.start(), whatever the path's length.
  const nbs::LinearScanPath initial = AreaPlanner(params, small_camera(), box).initial_scan(0);
  REQUIRE(initial.length() > 0.0);
  const nbs::Scan a0 = embree.scan(initial, small_camera(), 3);
  const nbs::Scan b0 = embree.scan(initial.start(), small_camera(), 3);
  CHECK(a0.points == b0.points);
  CHECK(a0.size() > 500);

  const nbs::SurfaceSamples samples = nbs::sample_surface(sphere, 4000, 1);
  nbs::CoverageTracker truth(samples, 0.003);
  CheckedScanner checked{&embree, {}};
  std::vector<double> c_a;
  AreaPlanner p1(params, small_camera(), box);
  const auto r1 = nbs::run_simulation(p1, checked, sim, [&](const nbs::ScanRecord& rec) {
    truth.add(checked.points);
    checked.points.clear();
    c_a.push_back(truth.completeness().c_a());
    CHECK(rec.path.length() == 0.0);  // one frame: the executed path is a single viewpoint
    CHECK(rec.total_path_length_m == 0.0);
    CHECK(rec.points > 0);
    if (rec.candidate) CHECK(rec.candidate->path.start().pose().matrix() == rec.path.start().pose().matrix());
  });
  REQUIRE(r1.records.size() >= 3);  // the first frame and at least two planned ones
  CHECK(r1.records[0].initial_index == nbs::random_initial_scan_index(sim.seed));
  for (std::size_t i = 1; i < r1.records.size(); ++i) {
    REQUIRE(r1.records[i].candidate);
    CHECK(r1.records[i].candidate->path.length() == 0.0);  // area-sensor candidates are single viewpoints
  }
  INFO("c_a after each scan: " << c_a.front() << " ... " << c_a.back());
  CHECK(c_a.back() > c_a.front() + 0.05);
  CHECK(p1.estimated_coverage() > 0.0);

  AreaPlanner p2(params, small_camera(), box);
  const auto r2 = nbs::run_simulation(p2, embree, sim);
  REQUIRE(r2.records.size() == r1.records.size());
  for (std::size_t i = 0; i < r1.records.size(); ++i) {
    INFO("scan " << i + 1);
    CHECK(r2.records[i].path.start().pose().matrix() == r1.records[i].path.start().pose().matrix());
    CHECK(r2.records[i].points == r1.records[i].points);
    CHECK(r2.records[i].integration.estimated_coverage == r1.records[i].integration.estimated_coverage);
  }
}
