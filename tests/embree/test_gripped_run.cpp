// SPDX-License-Identifier: BSD-3-Clause
// Gripped-object modeling (Sec. 5.4) end to end: the bunny (100 mm) held by two box fingers on the palm plane z = 0 of
// the object frame O, the sensor fixed; NbsPlanner<> plans sensor poses in O, GrippedDriver maps them by Eq. 5.1 to
// object poses and removes the finger points; the Embree scanner sees object + fingers. c_a is computed on the
// object's samples only, split into the finger region (within 5 mm of a finger) and the rest.
// NBS_GRIPPED_VERBOSE=1 prints the numbers; the hidden case "[.gripped_measure]" is the measurement of
// docs/evaluation.md (the planner's own stop rule, n_abort = 30).

#include "nbs_catch.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <vector>

#include "gripped_bunny.hpp"
#include "nbs/driver/simulated_driver.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/gripped/gripped_driver.hpp"
#include "nbs/gripped/gripped_simulation.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/planner/nbs_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"
#include "nbs/sensor/presets.hpp"
#include "nbs/sim/ground_truth.hpp"
#include "nbs_sanitizer.hpp"

namespace {

using nbs::Vec3;

constexpr double kFingerRegionM = 0.005;  // finger region of the c_a split: one voxel (l_v = 5 mm)

using nbs_test::GrippedBunny;

const GrippedBunny& gripped() {
  static const GrippedBunny g;
  return g;
}

struct GrippedRun {
  std::size_t scans = 0;
  std::size_t removed = 0;
  double min_vertex_finger_distance_m = 0.0;
  nbs::FingerRegionCompleteness c;
  nbs::Completeness all;
};

GrippedRun run_gripped(int max_scans, bool own_stop, bool filter = true, std::uint64_t seed = 1,
                       bool fingers = true) {
  GrippedBunny g = gripped();
  if (!fingers) g.setup.fingers.clear();  // the baseline: the same object and box, nothing holds it
  const nbs::embree::SimulatedScanner scanner(nbs::gripped_scene_mesh(g.setup, g.object));
  nbs::PlannerSetting setting;
  setting.threads = 2;
  nbs::Parameters params;
  nbs::NbsPlanner<> planner(params, nbs::presets::dlr_lsp(), g.setup.tool_box, setting);
  nbs::SimulatedDriver inner(scanner, planner.sensor(), seed);
  nbs::GrippedDriver driver(inner, g.setup);
  nbs::SimulationSetting sim;
  sim.seed = seed;
  sim.max_scans = max_scans;
  const auto res = filter ? nbs::run_loop(planner, driver, sim) : nbs::run_loop(planner, inner, sim);
  if (!own_stop) REQUIRE(res.records.size() == static_cast<std::size_t>(max_scans));
  REQUIRE(driver.object_paths().size() == (filter ? res.records.size() : 0));

  GrippedRun out;
  out.scans = res.records.size();
  out.removed = driver.removed_points();
  std::vector<Vec3> vertices;
  out.min_vertex_finger_distance_m = std::numeric_limits<double>::infinity();
  for (std::size_t v = 0; v < planner.mesh().vertex_count(); ++v) {
    vertices.push_back(planner.mesh().position(static_cast<nbs::VertexId>(v)));
    out.min_vertex_finger_distance_m =
        std::min(out.min_vertex_finger_distance_m, nbs::finger_distance(g.setup.fingers, vertices.back()));
  }
  nbs::GroundTruth::Setting ts;
  ts.sample_density_per_m2 = 2.0e5;  // ≈ 2.2 mm spacing, below r = 3 mm (as the bunny truth band)
  const nbs::GroundTruth truth(g.object, ts);  // the object only: finger surface is no object surface
  auto tracker = truth.tracker();
  tracker.add(vertices);
  out.all = tracker.completeness();
  // The split always by the gripped set-up's fingers: the baseline reports the same samples.
  out.c = nbs::finger_region_completeness(truth.samples(), tracker.covered(), gripped().setup.fingers,
                                          kFingerRegionM);
  if (std::getenv("NBS_GRIPPED_VERBOSE") != nullptr)
    std::printf("gripped bunny (seed %llu, %s): scans %zu (stop %s), finger points removed %zu, vertices %zu, min vertex-finger "
                "distance %.2f mm, c_a %.4f, c_a outside the finger region %.4f (%zu samples), in it %.4f (%zu "
                "samples), c_m %.3f\n",
                static_cast<unsigned long long>(seed), fingers ? "fingers" : "no fingers", out.scans,
                nbs::to_string(res.stop), out.removed, vertices.size(),
                1e3 * out.min_vertex_finger_distance_m, out.all.c_a(), out.c.rest.c_a(), out.c.rest.non_bottom,
                out.c.finger.c_a(), out.c.finger.non_bottom, res.records.back().integration.estimated_coverage);
  return out;
}

}  // namespace

// Measured (Release, 2 threads, seed 1, 6 scans): 18597 finger points removed; the nearest model vertex 1.65 mm
// from a finger (the mesh moves vertices a little: below the 2 mm margin, far from 0); c_a outside the finger region
// 0.884 (4354 samples), in it 0.872 (195 samples). Without the filter (the inner driver directly) the model has
// vertices on and in the fingers (nearest −4.6 mm, i.e. inside) and the finger region looks covered (c_a 0.995) by
// finger points: the bound discriminates.
constexpr bool kSanitized = nbs_test::kAddressSanitizer;  // ASan + UBSan: 3 scans, the filter only (time)
TEST_CASE("gripped bunny: no fused vertex on a finger, the object outside the finger region is modeled",
          "[embree][gripped]") {
  const GrippedRun r = run_gripped(kSanitized ? 3 : 6, false);
  CHECK(r.removed > 0);  // the fingers were seen and removed
  CHECK(r.min_vertex_finger_distance_m > 0.001);
  CHECK(r.c.finger.non_bottom > 0);
  if (kSanitized) return;
  CHECK(r.c.rest.c_a() >= 0.85);
  const GrippedRun unfiltered = run_gripped(6, false, false);
  CHECK(unfiltered.removed == 0);
  CHECK(unfiltered.min_vertex_finger_distance_m < 0.0005);
}

TEST_CASE("gripped bunny measurement (docs/evaluation.md)", "[.gripped_measure]") {
  for (const bool fingers : {true, false})
    for (std::uint64_t seed = 1; seed <= 5; ++seed) (void)run_gripped(30, true, true, seed, fingers);
}
