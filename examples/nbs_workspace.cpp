// SPDX-License-Identifier: BSD-3-Clause
// nbs_workspace: workspace modeling at room scale (thesis Sec. 5.5; issue 22 item 1), simulated. A mobile platform
// with a pan-tilt head and an RGB-D camera (Asus Xtion preset) explores a shelf and a conveyor-like table with objects
// (sim/workspace_scene.hpp) in a 4 × 4 × 2 m box at 5 mm: NBV by IG (Eq. 4.30, ω = 0) × the platform penalty
// (Eq. 5.2) until the free-voxel count stagnates, with the voxel space's blocks flushed to disk under a memory
// budget. Then the collision model (p ≥ 0.25 kept, free-floating groups and inner voxels removed) is written as a
// mesh and, with the OctoMap adapter, as an OctoMap file. One line per view; pictures of the scene and the model.
//
//   nbs_workspace [--scale 1] [--voxel 0.005] [--seed 1] [--out workspace_out] [--budget-gib 1]
//   (--scale 0.25: a 1 × 1 × 0.5 m box, seconds instead of minutes; --budget-gib 0: no flushing)


#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "common/data_dir.hpp"
#include "common/process_memory.hpp"
#include "nbs/embree/render.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/io/write_json.hpp"
#include "nbs/mesh/ply.hpp"
#include "nbs/driver/simulated_driver.hpp"
#include "nbs/png/write_png.hpp"
#include "nbs/sensor/presets.hpp"
#include "nbs/sim/workspace_scene.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"
#include "nbs/workspace/collision_model.hpp"
#include "nbs/workspace/workspace_loop.hpp"
#ifdef NBS_WORKSPACE_OCTOMAP
#include "nbs/octomap/collision_model_io.hpp"
#endif

using namespace nbs;

namespace {

struct Options {
  double scale = 1.0;
  double voxel_m = 0.005;
  std::uint64_t seed = 1;
  std::string out = "workspace_out";
  double budget_gib = 1.0;
  std::size_t planning_downscale = 16;
  std::size_t max_views = 30;
  unsigned threads = 0;
  bool include_unknown = false;
};

void write_picture(const std::filesystem::path& path, const IndexedMesh& mesh, const Aabb& box, Rgb albedo) {
  const embree::Scene scene(mesh);
  embree::RenderSetting rs;
  rs.width = 800;
  rs.height = 600;
  rs.surface = albedo;
  rs.threads = 2;
  embree::Camera cam = embree::Camera::around(box, -1.9, 0.55, 0.6, 0.95);  // from the front left, above
  const embree::Image img = embree::render(&scene, cam, {}, rs);
  png::write_png(path.string(), img.width, img.height, img.rgb);
}

int run(const Options& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  std::filesystem::create_directories(opt.out);
  // The scene: the furniture of a 4 × 4 × 2 m workspace × scale, objects from the bundled meshes.
  const std::vector<IndexedMesh> meshes = example_workspace_objects(tools::bundled_data("meshes/stanford-bunny.obj"));
  WorkspaceSceneSetting ss;
  ss.box = Aabb{Vec3(-2.0, -2.0, 0.0) * opt.scale, Vec3(2.0, 2.0, 2.0) * opt.scale};
  ss.seed = opt.seed;
  const WorkspaceScene scene = make_workspace_scene(ss, meshes);

  WorkspaceSetting ws;
  ws.sensor = presets::asus_xtion_pro();
  ws.platform = scene.platform;
  ws.planning_downscale = opt.planning_downscale;
  ws.stop.max_views = opt.max_views;
  ws.threads = opt.threads;
  if (opt.budget_gib > 0.0) {
    ws.flush.directory = std::filesystem::path(opt.out) / "blocks";
    std::filesystem::create_directories(ws.flush.directory);
    ws.flush.memory_budget_bytes = static_cast<std::size_t>(opt.budget_gib * double(std::uint64_t{1} << 30));
  }
  ProbabilisticVoxelSpace<> space(opt.voxel_m, ss.box);
  const embree::SimulatedScanner scanner(scene.mesh);
  SimulatedDriver<embree::SimulatedScanner, AreaSensor> driver(scanner, ws.sensor, opt.seed);
  std::printf("workspace %.2f x %.2f x %.2f m at %.1f mm (%.0f M voxels), %zu objects, %zu candidates, flushing %s\n",
              ss.box.extent().x(), ss.box.extent().y(), ss.box.extent().z(), 1e3 * opt.voxel_m,
              double(space.bounds_keys().volume()) / 1e6, scene.objects.size(),
              pan_tilt_candidates(ws.platform).size(),
              opt.budget_gib > 0.0 ? ("on, budget " + std::to_string(opt.budget_gib) + " GiB").c_str() : "off");
  nlohmann::ordered_json jsteps = nlohmann::json::array();
  // One line per view as it is taken (a full-size view plans for several seconds).
  const WorkspaceResult r = run_workspace_modeling(space, driver, ws, [&](const WorkspaceStep& s) {
    std::printf("view %2zu  platform %+.2f m (moved %.2f)  pan %+4.0f°  tilt %+4.0f°  IG %.4f  utility %.4f  "
                "free %10llu  points %6zu  plan %.2f s  integrate %.2f s\n",
                jsteps.size() + 1, s.platform_offset_m, s.platform_move_m, s.pan_rad * 180 / 3.14159265358979,
                s.tilt_rad * 180 / 3.14159265358979, s.information_gain, s.utility,
                static_cast<unsigned long long>(s.free_voxels), s.integrated_points, s.t_plan_s, s.t_integrate_s);
    std::fflush(stdout);
    jsteps.push_back({{"platform_offset_m", s.platform_offset_m}, {"platform_move_m", s.platform_move_m},
                      {"pan_rad", s.pan_rad}, {"tilt_rad", s.tilt_rad}, {"information_gain", s.information_gain},
                      {"utility", s.utility}, {"free_voxels", s.free_voxels}, {"points", s.points},
                      {"integrated_points", s.integrated_points}, {"t_plan_s", s.t_plan_s},
                      {"t_integrate_s", s.t_integrate_s}});
  });
  const std::uint64_t rss_loop = tools::process_memory().peak_bytes;
  const auto& fs = space.backend().flush_stats();
  const std::filesystem::path out(opt.out);
  // The run's report first (rewritten with the model below), so that a failure of the model step keeps it.
  nlohmann::ordered_json j;
  j["box_min"] = {ss.box.min.x(), ss.box.min.y(), ss.box.min.z()};
  j["box_max"] = {ss.box.max.x(), ss.box.max.y(), ss.box.max.z()};
  j["voxel_m"] = opt.voxel_m;
  j["seed"] = opt.seed;
  j["flush_budget_gib"] = opt.budget_gib;
  j["steps"] = jsteps;
  j["stop"] = to_string(r.stop);
  j["peak_rss_gib"] = double(rss_loop) / double(std::uint64_t{1} << 30);
  j["blocks_flushed"] = fs.blocks_written;
  j["blocks_reloaded"] = fs.blocks_reloaded;
  write_json((out / "report.json").string(), j);
  // The collision model.
  const auto tc = std::chrono::steady_clock::now();
  // Obstacles: voxels with more evidence of a surface than of free space (p ≥ 0.55: one hit gives up to 0.7, one
  // free beam 0.4); unseen space only with --include-unknown (the thesis's conservative model: at 5 mm the space
  // behind the shelf alone is tens of millions of voxels).
  CollisionModelSetting cms;
  cms.free_below = 0.5;
  cms.occupied_from = 0.55;
  cms.include_unknown = opt.include_unknown;
  // Floor contact is judged through unseen space only when it is in the model: without it, an object on a board
  // whose supports were not seen would count as free-floating and be erased.
  cms.remove_floating = opt.include_unknown;
  cms.remove_inner = false;  // the OctoMap file is solid (it prunes full interiors); the mesh is the same either way
  const CollisionModel model = build_collision_model(space, cms);
  const IndexedMesh model_mesh = collision_mesh(model);
  const double t_model = std::chrono::duration<double>(std::chrono::steady_clock::now() - tc).count();
  write_mesh_ply((out / "collision_model.ply").string(), model_mesh);
  std::string octree = "(OctoMap adapter not built)";
#ifdef NBS_WORKSPACE_OCTOMAP
  octree = (out / "collision_model.bt").string();
  nbs::octomap::write_collision_octree(model, octree);
#endif
  write_picture(out / "scene.png", scene.mesh, ss.box, Rgb{205, 205, 215});
  write_picture(out / "collision_model.png", model_mesh, ss.box, Rgb{230, 150, 60});
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("stop    %s after %zu views; peak RSS %.2f GiB (loop), blocks flushed %llu, reloaded %llu, failed %llu\n",
              to_string(r.stop), r.steps.size(), double(rss_loop) / double(std::uint64_t{1} << 30),
              static_cast<unsigned long long>(fs.blocks_written), static_cast<unsigned long long>(fs.blocks_reloaded),
              static_cast<unsigned long long>(fs.failed_writes));
  std::printf("model   %zu voxels (%llu inner, %llu free-floating removed), %zu triangles, %.2f s -> %s, %s\n",
              model.size(), static_cast<unsigned long long>(model.counts.removed_inner),
              static_cast<unsigned long long>(model.counts.removed_floating), model_mesh.triangles.size(), t_model,
              (out / "collision_model.ply").string().c_str(), octree.c_str());
  std::printf("wall    %.1f s; pictures %s, %s\n", wall, (out / "scene.png").string().c_str(),
              (out / "collision_model.png").string().c_str());
  j["model_voxels"] = model.size();
  j["model_triangles"] = model_mesh.triangles.size();
  j["model_include_unknown"] = opt.include_unknown;
  j["wall_s"] = wall;
  write_json((out / "report.json").string(), j);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  CLI::App app("nbs_workspace: simulated workspace modeling (Sec. 5.5): platform + pan-tilt NBV, collision model",
               "nbs_workspace");
  app.add_option("--scale", opt.scale, "workspace box 4 x 4 x 2 m times this")->capture_default_str()
      ->check(CLI::Range(0.125, 4.0));
  app.add_option("--voxel", opt.voxel_m, "voxel edge, metres")->capture_default_str()->check(CLI::Range(0.001, 0.2));
  app.add_option("--seed", opt.seed, "scene and noise seed")->capture_default_str();
  app.add_option("--out", opt.out, "output directory")->capture_default_str();
  app.add_option("--budget-gib", opt.budget_gib, "flush blocks to OUT/blocks above this memory, GiB (0: no flushing)")
      ->capture_default_str()->check(CLI::Range(0.0, 64.0));
  app.add_option("--planning-downscale", opt.planning_downscale, "plan with every k-th pixel row and column")
      ->capture_default_str()->check(CLI::Range(1, 64));
  app.add_option("--views", opt.max_views, "most views")->capture_default_str()->check(CLI::Range(1, 1000));
  app.add_option("--threads", opt.threads, "threads (0: all)")->capture_default_str();
  app.add_flag("--include-unknown", opt.include_unknown, "keep unseen and undecided voxels in the collision model");
  app.footer("Writes OUT/collision_model.ply (and .bt with OctoMap), OUT/scene.png, OUT/collision_model.png, "
             "OUT/report.json.");
  CLI11_PARSE(app, argc, argv);
  try {
    return run(opt);
  } catch (const nbs::Error& e) {
    std::cerr << "nbs_workspace: " << e.what() << "\n";
    return 1;
  }
}
