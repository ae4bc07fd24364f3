// SPDX-License-Identifier: BSD-3-Clause
// 05 — your own voxel space: any type that models nbs::VoxelSpace (nbs/space/concepts.hpp) can be the planner's
// Space policy; examples/my_voxel_space.hpp is a complete one in ~50 lines (a log-odds hash map). Capabilities
// such as BatchRayCastingSpace or a BlockBackend unlock fast paths; without them the generic ones serve.
// Usage: 05_your_own_voxel_space [scans = 4]; exits 1 unless every planned scan adds points and ĉ_m grows.

#include <cstdio>
#include <cstdlib>
#include <exception>

#include "my_voxel_space.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/planner/nbs_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"
#include "nbs/sensor/presets.hpp"

// The default planner over MyVoxelSpace: Utility, Search, Sensor, Collision, Termination as the defaults, then the
// Space.
using Planner = nbs::NbsPlanner<nbs::SurfaceGainUnseenUtility, nbs::BoundaryHoleSpace, nbs::LaserStripeProfiler,
                                nbs::NoCollisions, nbs::DefaultTermination, MyVoxelSpace>;

int main(int argc, char** argv) {
  try {
    const int scans = argc > 1 ? std::max(2, std::atoi(argv[1])) : 4;
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
    bool every_scan_sees = true;
    const auto result = nbs::run_simulation(planner, scanner, sim, [&](const nbs::ScanRecord& r) {
      every_scan_sees = every_scan_sees && r.points > 0;
      std::printf("scan %d  c_m %.3f  d_m %.3f  candidates %zu  points %zu\n", r.scan, r.integration.estimated_coverage,
                  r.integration.mean_density, r.planning.evaluated, r.points);
    });
    std::size_t observed = 0;
    planner.space().for_each([&](const nbs::VoxelKey&, float) { ++observed; });
    std::printf("%zu scans, %zu observed voxels in MyVoxelSpace, %zu surface-feature voxels\n", result.records.size(),
                observed, planner.features().size());
    const bool ok = every_scan_sees && result.records.size() >= 2 &&
                    planner.estimated_coverage() > result.records.front().integration.estimated_coverage;
    if (!ok) std::fprintf(stderr, "05_your_own_voxel_space: a scan saw nothing or c_m did not grow\n");
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "05_your_own_voxel_space: %s\n", e.what());
    return 1;
  }
}
