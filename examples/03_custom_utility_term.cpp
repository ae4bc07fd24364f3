// SPDX-License-Identifier: BSD-3-Clause
// 03 — plug in your own utility term: a UtilityTerm sees every simulated ray of a candidate and every voxel it
// crosses (nbs/utility/utility_term.hpp); wrap it in TermUtility<> and the planner selects scans by it.
// Usage: 03_custom_utility_term [scans = 4]; exits 1 unless every planned scan had a positive gain and ĉ_m grew.

#include <cstdio>
#include <cstdlib>
#include <string>

#include "nbs/planner/nbs_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/sensor/presets.hpp"

/// A "frontier gain" of our own: the unknown voxels a candidate would see for the first time, discounted by how far
/// along the ray they lie: Σ over first visits of unobserved voxels of 1 / (1 + distance / 0.1 m). Higher = more new
/// space, nearer.
struct NearUnknownGain {
  double sum = 0.0;
  void begin_candidate(std::size_t) { sum = 0.0; }
  void begin_ray() {}
  void visit(const nbs::VoxelVisit& v) {
    if (v.first_visit && !v.observed) sum += 1.0 / (1.0 + v.distance_m / 0.1);
  }
  void end_ray(const nbs::RayEnd&) {}
  [[nodiscard]] double value() const { return sum; }
};
static_assert(nbs::UtilityTerm<NearUnknownGain>);  // fails here, at your line, if a member is missing

using Planner = nbs::NbsPlanner<nbs::TermUtility<NearUnknownGain>>;  // the other policies: the defaults

int main(int argc, char** argv) {
  try {
    const int scans = argc > 1 ? std::max(1, std::atoi(argv[1])) : 4;
    nbs::IndexedMesh object = nbs::load_mesh(NBS_DATA_DIR "/meshes/stanford-bunny.obj");
    nbs::normalize_on_pedestal(object, 0.16, nbs::UpAxis::y);
    nbs::Aabb unknown_area = object.bounds();
    unknown_area.min -= nbs::Vec3(0.01, 0.01, 0.0);
    unknown_area.max += nbs::Vec3(0.01, 0.01, 0.01);
    nbs::PlannerSetting setting;
    setting.threads = 2;
    Planner planner(nbs::Parameters{}, nbs::presets::dlr_lsp(), unknown_area, setting);
    const nbs::embree::SimulatedScanner scanner(object);
    nbs::SimulationSetting sim;
    sim.max_scans = scans;
    bool gains_positive = true;
    const auto result = nbs::run_simulation(planner, scanner, sim, [&](const nbs::ScanRecord& r) {
      if (r.scan > 1 && !(r.planning.best_utility > 0.0)) gains_positive = false;  // scan 1 is the initial path
      std::printf("scan %d  %s  c_m %.3f  d_m %.3f  candidates %zu  gain of the chosen scan %.1f  t_nbs %.3f s\n",
                  r.scan, std::string(nbs::to_string(r.integration.mode)).c_str(), r.integration.estimated_coverage,
                  r.integration.mean_density, r.planning.evaluated, r.planning.best_utility, r.planning.t_nbs_s);
    });
    std::printf("%zu scans, l_s %.2f m\n", result.records.size(), result.records.back().total_path_length_m);
    const double c_first = result.records.front().integration.estimated_coverage;
    const bool ok = gains_positive && (result.records.size() < 2 || planner.estimated_coverage() > c_first);
    if (!ok) std::fprintf(stderr, "03_custom_utility_term: a planned scan had no gain or c_m did not grow\n");
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "03_custom_utility_term: %s\n", e.what());
    return 1;
  }
}
