// SPDX-License-Identifier: BSD-3-Clause
// Workspace modeling at room scale (Sec. 5.5; issue 22 items 1 and 5): the simulated workspace of
// sim/workspace_scene.hpp in a 4 × 4 × 2 m box at 5 mm (256 M voxels in the box), an Asus Xtion frame per view, the
// platform + pan-tilt candidates of the scene, blocks flushed to disk above a 1 GiB budget. Headlines:
//   space.workspace_rss_gib     — peak resident memory of this process (VmHWM) after the run, GiB; the full-size
//                                 box, not a scaled figure (quick: the first 4 views; else until the stop, ≤ 30 views)
//   workspace.t_nbv_median_s    — median wall time of one NBV planning step (all candidates, IG × Eq. 5.2, plan
//                                 with every 16th pixel row and column, 2 threads)
//   space.flush_reload_mb_per_s — block data (MB = 10^6 bytes) written by flush_all() and read back by reload_all(),
//                                 counted once each way, per second of both calls; a space of ≈ 1 × 1 × 0.5 m at
//                                 5 mm after two frames, on the build directory's disk (report; no incumbent)
// Report figures: no incumbent holds a workspace NBV loop.

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <vector>

#include "common/process_memory.hpp"
#include "headline.hpp"
#include "nbs/driver/simulated_driver.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/sensor/presets.hpp"
#include "nbs/sim/workspace_scene.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"
#include "nbs/workspace/workspace_loop.hpp"

namespace {

using namespace nbs;

double peak_rss_gib() { return double(tools::process_memory().peak_bytes) / double(std::uint64_t{1} << 30); }

struct Scratch {  // a folder for flushed blocks, removed at the end
  std::filesystem::path dir = std::filesystem::temp_directory_path() / "nbs_bench_workspace";
  Scratch() { std::filesystem::create_directories(dir); }
  ~Scratch() {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
};

}  // namespace

int main() {
  const bool quick = bench::quick_mode();
  const std::vector<IndexedMesh> meshes = example_workspace_objects(NBS_DATA_DIR "/meshes/stanford-bunny.obj");
  const Scratch scratch;
  {
    WorkspaceSceneSetting ss;  // 4 × 4 × 2 m
    const WorkspaceScene scene = make_workspace_scene(ss, meshes);
    WorkspaceSetting ws;
    ws.sensor = presets::asus_xtion_pro();
    ws.platform = scene.platform;
    ws.planning_downscale = 16;
    ws.stop.max_views = quick ? 4 : 30;
    ws.threads = 2;
    ws.flush.directory = scratch.dir;
    ws.flush.memory_budget_bytes = std::size_t{1} << 30;
    ProbabilisticVoxelSpace<> space(0.005, ss.box);
    const embree::SimulatedScanner scanner(scene.mesh);
    SimulatedDriver<embree::SimulatedScanner, AreaSensor> driver(scanner, ws.sensor, 1);
    const WorkspaceResult r = run_workspace_modeling(space, driver, ws);
    std::vector<double> t_plan;
    for (const WorkspaceStep& s : r.steps) t_plan.push_back(s.t_plan_s);
    const auto& fs = space.backend().flush_stats();
    std::printf("workspace 4 x 4 x 2 m at 5 mm: %zu views (stop %s), blocks flushed %llu, reloaded %llu, failed %llu\n",
                r.steps.size(), to_string(r.stop), static_cast<unsigned long long>(fs.blocks_written),
                static_cast<unsigned long long>(fs.blocks_reloaded), static_cast<unsigned long long>(fs.failed_writes));
    bench::report_headline("space.workspace_rss_gib", peak_rss_gib(),
                           quick ? "4 x 4 x 2 m at 5 mm, first 4 views, flush budget 1 GiB"
                                 : "4 x 4 x 2 m at 5 mm, until the stop, flush budget 1 GiB");
    bench::report_headline("workspace.t_nbv_median_s", bench::median(t_plan), "all candidates, 2 threads");
  }
  {
    WorkspaceSceneSetting ss;
    ss.box = Aabb{Vec3(-0.5, -0.5, 0.0), Vec3(0.5, 0.5, 0.5)};
    const WorkspaceScene scene = make_workspace_scene(ss, meshes);
    const AreaSensor cam = presets::asus_xtion_pro();
    ProbabilisticVoxelSpace<> space(0.005, ss.box);
    const embree::SimulatedScanner scanner(scene.mesh);
    const std::vector<PanTiltCandidate> views = pan_tilt_candidates(scene.platform);
    for (const std::size_t k : {views.size() / 3, 2 * views.size() / 3})
      space.integrate(scanner.scan(LinearScanPath(Viewpoint(views[k].T_WS)), cam, k));
    auto& backend = space.mutable_backend();
    backend.set_flush_policy(BlockFlushSetting{scratch.dir, 0, 0});
    const double bytes = static_cast<double>(space.memory_bytes());
    const auto t0 = std::chrono::steady_clock::now();
    backend.flush_all();
    backend.reload_all();
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("flush + reload: %.1f MB in %.3f s\n", 2.0 * bytes / 1e6, t);
    bench::report_headline("space.flush_reload_mb_per_s", 2.0 * bytes / 1e6 / t, "memory_bytes() out and in");
  }
  return 0;
}
