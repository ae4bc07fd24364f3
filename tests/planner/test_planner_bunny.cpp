// The closed loop on the bundled Stanford bunny (160 mm on the pedestal) with the Embree scanner: thread-count
// determinism and the acceptance target ĉ_m ≥ 0.8 within n_abort = 30 scans (method C_H, Tab. 4.3).
// Set NBS_PLANNER_VERBOSE=1 to print one line per scan.

#include <catch2/catch.hpp>

#include <cstdio>
#include <cstdlib>

#include "nbs/planner/nbs_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/sensor/presets.hpp"
#include "support/same_plan.hpp"

namespace {

struct Bunny {
  nbs::IndexedMesh mesh;
  nbs::Aabb box;  // bounding box of the unknown area: object box + 1 cm sideways and on top, bottom at z = 0
  Bunny() : mesh(nbs::load_mesh(NBS_DATA_DIR "/meshes/stanford-bunny.obj")) {
    nbs::normalize_on_pedestal(mesh, 0.16, nbs::UpAxis::y);
    box = mesh.bounds();
    box.min -= nbs::Vec3(0.01, 0.01, 0.0);
    box.max += nbs::Vec3(0.01, 0.01, 0.01);
  }
};

const Bunny& bunny() {
  static const Bunny b;
  return b;
}

void print(const nbs::ScanRecord& r) {
  if (std::getenv("NBS_PLANNER_VERBOSE") == nullptr) return;
  std::printf("scan %2d  %s  c_m %.3f  d_m %.3f  points %6zu  cand %3zu (+%zu, rot %zu, drop %zu)  t_nbs %.3f s  l_s %.2f m\n",
              r.scan, std::string(nbs::to_string(r.integration.mode)).c_str(), r.integration.estimated_coverage,
              r.integration.mean_density, r.points, r.planning.evaluated, r.planning.generated, r.planning.replanned,
              r.planning.dropped, r.planning.t_nbs_s, r.total_path_length_m);
  std::fflush(stdout);
}

}  // namespace

TEST_CASE("bunny loop: same seed gives the same scan sequence with 1 and 2 threads", "[planner][bunny]") {
  const nbs::embree::SimulatedScanner scanner(bunny().mesh);
  nbs::SimulationSetting sim;
  sim.seed = 5;
  sim.max_scans = 4;
  nbs::PlannerSetting s1, s2;
  s1.threads = 1;
  s2.threads = 2;
  nbs::NbsPlanner<> p1({}, nbs::presets::dlr_lsp(), bunny().box, s1);
  nbs::NbsPlanner<> p2({}, nbs::presets::dlr_lsp(), bunny().box, s2);
  const auto a = nbs::run_simulation(p1, scanner, sim);
  const auto b = nbs::run_simulation(p2, scanner, sim);
  REQUIRE(a.records.size() == 4);
  nbs::test::check_same_plan(a, b);
}

// The acceptance target of issue 5, default NbsPlanner<> (noise-robust mesh, unseen_open ĉ_m). Release (2 threads):
// seed 1 stops at ĉ_m 0.806 after 8 scans; the thesis's mesh and ĉ_m (ThesisMeshPlanner, second case):
// 0.818 after 14. Under ASan + UBSan the loops run six scans only (time), which checks memory safety, not the target.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif
namespace {
/// The C_H loop on the bunny with Planner (2 threads, seed 1): Release reaches ĉ_m ≥ 0.8 within n_abort scans;
/// under the sanitizers six scans run and raise ĉ_m.
template <class Planner>
void bunny_loop() {
  const nbs::embree::SimulatedScanner scanner(bunny().mesh);
  nbs::PlannerSetting setting;
  setting.threads = 2;
  nbs::Parameters params;  // Tab. 4.3
  Planner planner(params, nbs::presets::dlr_lsp(), bunny().box, setting);
  nbs::SimulationSetting sim;
  sim.seed = 1;
  sim.max_scans = kSanitized ? 6 : params.max_scans;
  const auto res = nbs::run_simulation(planner, scanner, sim, print);
  REQUIRE(!res.records.empty());
  double best = 0.0;
  for (const auto& r : res.records) best = std::max(best, r.integration.estimated_coverage);
  INFO("scans " << res.records.size() << ", final c_m " << res.records.back().integration.estimated_coverage
                << ", d_m " << res.records.back().integration.mean_density << ", stop " << int(res.stop));
  if constexpr (kSanitized) {
    CHECK(res.records.size() == 6);
    CHECK(best > res.records.front().integration.estimated_coverage);
  } else {
    // The stop rule must fire before n_abort (measured: 8 and 14 scans); running into the cap fails.
    CHECK(res.stop == nbs::LoopStop::done);
    CHECK(res.records.size() < static_cast<std::size_t>(params.max_scans));
    CHECK(best >= 0.8);
  }
}
}  // namespace

TEST_CASE(kSanitized ? "bunny loop (sanitizers): six C_H scans run and raise the estimated coverage"
                     : "bunny loop: C_H reaches estimated coverage 0.8 within 30 scans",
          "[planner][bunny][slow]") {
  bunny_loop<nbs::NbsPlanner<>>();
}

TEST_CASE(kSanitized ? "bunny loop, thesis mesh (sanitizers): six C_H scans run and raise the estimated coverage"
                     : "bunny loop, thesis mesh and c_m: C_H reaches estimated coverage 0.8 within 30 scans",
          "[planner][bunny][slow]") {
  bunny_loop<nbs::ThesisMeshPlanner<>>();
}
