// SPDX-License-Identifier: BSD-3-Clause
// nbs_model — the main job: simulated autonomous modeling of the bundled Stanford bunny (or --mesh) with the
// Next-Best-Scan planner (default nbs's SGU_H with the settled stop rule; --method C_H --thesis-mesh is the thesis's
// best method as written, Sec. 4.7). A first
// scan along one of the 13 initial paths (Sec. 4.7.2, chosen by --seed), then plan → scan (Embree simulated laser
// stripe profiler, --sensor, default the DLR LSP) → integrate until the planner is done or n_abort scans were
// taken. Prints one line per scan with the planner's estimates and the true c_a; writes mesh, voxel space,
// candidates (per iteration, PLY line segments coloured red → green by utility, Fig. 4.16), PNG pictures and
// report.json. --color scans in colour (Sec. 5.3) and measures the model's mean colour error. Run `nbs_model --help`; the options shared with the other tools are in tools/common/options.hpp.

// Planner headers first (see nbs/planner/detail/components.hpp).
#include "nbs/planner/runtime_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "nbs/core/parameters.hpp"
#include "nbs/embree/render.hpp"
#include "nbs/driver/pose_error_driver.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/io/color.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/io/write_candidates_ply.hpp"
#include "nbs/io/write_json.hpp"
#include "nbs/io/write_ply.hpp"
#include "nbs/mesh/conversion.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/mesh/ply.hpp"
#include "nbs/png/write_png.hpp"
#include "nbs/robot/shape_mesh.hpp"
#include "nbs/robot/transfer.hpp"
#include "nbs/sensor/presets.hpp"
#include "nbs/sim/metrics.hpp"
#include "nbs/sim/surface_color.hpp"
#include "nbs/space/export_ply.hpp"

#include "common/data_dir.hpp"
#include "common/options.hpp"
#include "common/robot_option.hpp"
#include "viewer/write_viewer.hpp"

namespace {

struct Options {
  std::string mesh = nbs::tools::bundled_data("meshes/stanford-bunny.obj");
  nbs::UpAxis up = nbs::tools::kDefaultUp;
  double size_m = nbs::Parameters{}.object_size_m;
  std::uint64_t seed = 1;
  nbs::Method method{};
  std::string sensor = "dlr_lsp";
  int scans = nbs::Parameters{}.max_scans;
  unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  std::string out = "out";
  bool images = true;
  bool initial_only = false;
  bool thesis_mesh = false;
  std::optional<nbs::StopRule> stop_rule;
  bool viewer = false;
  bool color = false;
  nbs::tools::PoseErrorOptions pose;  ///< --pose-error, --registration
  nbs::tools::RobotOptions robot;     ///< --robot, --robot-links
};

/// The command line (tools/common/options.hpp: the shared options, --help, exit 2 on a bad value).
void add_options(CLI::App& app, Options& o) {
  namespace tools = nbs::tools;
  tools::set_conventions(app);
  tools::add_object_options(app, o);
  tools::add_run_options(app, o);
  tools::add_stop_rule(app, o.stop_rule);
  tools::add_pose_error_options(app, o.pose);
  tools::add_robot_options(app, o.robot);
  tools::add_out(app, o.out);
  app.add_flag_callback("--no-images", [&o] { o.images = false; }, "do not write the PNG pictures");
  app.add_flag("--initial-only", o.initial_only,
               "no planning: scan along all 13 initial paths of Sec. 4.7.2 and write DIR/points.ply");
  app.add_flag("--viewer", o.viewer,
               "also write DIR/viewer/index.html: the session in 3D (mesh per scan, paths, candidates), offline");
  app.add_flag("--color", o.color,
               "colour (Sec. 5.3): a mesh without vertex colours gets a seeded checker pattern (a coloured mesh is "
               "scanned in colour with or without this flag); coloured pictures, DIR/truth.png, mean colour error in "
               "report.json");
  tools::add_config(app);
  app.footer("The object stands on a pedestal at z = 0. Writes DIR/mesh.ply, DIR/voxels.ply, DIR/candidates_NN.ply,\n"
             "DIR/view_NN.png, DIR/final.png and DIR/report.json (with --color also DIR/truth.png).");
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string file(const Options& o, const std::string& name) { return (std::filesystem::path(o.out) / name).string(); }

std::string numbered(const char* stem, int n, const char* ext) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s_%02d.%s", stem, n, ext);
  return buf;
}

/// What every picture shows besides the mesh (issue 24): the pedestal as a disc under the unknown area, the world
/// axes at its corner (x red, y green, z blue) and the scan paths flown so far (dark grey, 2 px).
struct Stage {
  nbs::embree::Disc pedestal;
  std::array<nbs::embree::Segment, 3> axes;
  std::vector<nbs::embree::Segment> flown;
};

/// --robot (issue 19 item 5): the arm at the chosen scan's start configuration (its collision shapes as triangles,
/// grey-orange) and the sensor's path along the transfer to it (magenta, 2 px; empty for the first scan).
struct ArmPicture {
  nbs::IndexedMesh arm;
  std::vector<nbs::Vec3> transfer;
};

/// The arm of `robot` at joints `q` and the sensor path along the transfer `waypoints` (fk every ≤ 0.02 rad).
template <nbs::Robot R>
ArmPicture arm_picture(const R& robot, const nbs::JointVector& q, const std::vector<nbs::JointVector>& waypoints) {
  return {nbs::shapes_mesh(robot.collision_shapes(q)), nbs::sensor_path(robot, waypoints, 0.02)};
}

/// Picture (800 × 600, compressed PNG) of `mesh` (may be empty) on `stage` with candidate segments coloured by
/// utility; the chosen one (index `chosen`, if any) blue and wider; `arm` (if given) drawn as ArmPicture says.
/// Without `arm` the picture is the one nbs_model wrote before --robot existed, byte for byte. With `color` the mesh is
/// drawn in its vertex colours (if it has them).
void write_picture(const std::string& path, const nbs::IndexedMesh& mesh, const nbs::embree::Camera& cam,
                   const Stage& stage, const std::vector<nbs::LinearScanPath>& paths,
                   const std::vector<double>& utility, std::optional<std::size_t> chosen, unsigned threads,
                   const ArmPicture* arm = nullptr, bool color = false) {
  std::optional<nbs::embree::Scene> scene, arm_scene;
  if (!mesh.triangles.empty()) scene.emplace(mesh);
  if (arm != nullptr && !arm->arm.triangles.empty()) arm_scene.emplace(arm->arm);
  const std::vector<double> u01 = nbs::normalize_utilities(utility);
  std::vector<nbs::embree::Segment> segs(stage.flown.begin(), stage.flown.end());
  segs.insert(segs.end(), stage.axes.begin(), stage.axes.end());
  for (std::size_t i = 0; i < paths.size(); ++i)
    if (i != chosen) segs.push_back({paths[i].start().position(), paths[i].end_position(), nbs::utility_color(u01[i]), 1});
  if (arm != nullptr)
    for (std::size_t i = 1; i < arm->transfer.size(); ++i)
      segs.push_back({arm->transfer[i - 1], arm->transfer[i], {200, 0, 160}, 2});
  if (chosen) segs.push_back({paths[*chosen].start().position(), paths[*chosen].end_position(), {0, 90, 255}, 3});
  nbs::embree::RenderSetting rs;
  rs.width = 800;
  rs.height = 600;
  rs.threads = threads;
  rs.pedestal = stage.pedestal;
  const std::array<nbs::embree::SceneLayer, 2> layers{
      nbs::embree::SceneLayer{scene ? &*scene : nullptr, rs.surface,
                              color && scene && !mesh.colors.empty() ? &mesh : nullptr},
      nbs::embree::SceneLayer{arm_scene ? &*arm_scene : nullptr, {225, 150, 85}}};
  const nbs::embree::Image img = nbs::embree::render(layers, cam, segs, rs);
  nbs::png::write_png(path, img.width, img.height, img.rgb);
}

/// Ground truth of the model as it grows: c_a / c_b over the mesh vertices (points with a robust normal) and ē
/// accumulated over the same vertices (they never move).
struct TruthTracker {
  const nbs::GroundTruth& truth;
  nbs::CoverageTracker coverage;
  std::vector<bool> added;
  std::size_t vertices = 0;
  double sum_sq_m2 = 0.0;

  explicit TruthTracker(const nbs::GroundTruth& t) : truth(t), coverage(t.tracker()) {}
  void update(const nbs::StreamingMesh& mesh) {
    added.resize(mesh.vertex_count(), false);
    std::vector<nbs::Vec3> fresh;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
      const auto id = static_cast<nbs::VertexId>(v);
      if (added[v] || !mesh.has_normal(id)) continue;
      added[v] = true;
      fresh.push_back(mesh.position(id));
    }
    if (fresh.empty()) return;
    coverage.add(fresh);
    const double rms = truth.rms_error(fresh);
    sum_sq_m2 += rms * rms * double(fresh.size());
    vertices += fresh.size();
  }
  [[nodiscard]] double rms_m() const { return vertices ? std::sqrt(sum_sq_m2 / double(vertices)) : 0.0; }
};

/// --color (Sec. 5.3): the model's mean colour error (nbs::mean_color_error: per vertex, the colour distance to the true
/// colour at the nearest surface point), split by nearness to a colour edge. A vertex is near an edge if the true colour
/// at the surface points nearest to p ± r·e_k (k = x, y, z; r = `radius_m`) differs from the one nearest to p by more
/// than 0.1 (color_distance): there the fused mean of the points around the vertex blends the two sides.
struct ColorErrorSplit {
  double mean = 0.0, near_edge = 0.0, rest = 0.0;  ///< mean colour error: all, near an edge, the others
  std::size_t vertices = 0, near_edge_vertices = 0;
};

ColorErrorSplit color_error_split(const nbs::MeshDistance& truth, const nbs::IndexedMesh& model, double radius_m,
                                  unsigned threads) {
  ColorErrorSplit out;
  out.vertices = model.vertices.size();
  out.mean = nbs::mean_color_error(truth, model, threads);
  std::vector<double> err(model.vertices.size());
  std::vector<char> edge(model.vertices.size(), 0);
  const auto true_color = [&](const nbs::Vec3& p) {
    const nbs::MeshDistance::Closest c = truth.closest(p);
    return nbs::surface_color(truth.mesh(), c.triangle, c.point);
  };
  nbs::detail::parallel_for(model.vertices.size(), threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const nbs::Vec3& p = model.vertices[i];
      const nbs::Rgb c = true_color(p);
      err[i] = nbs::color_distance(model.colors[i], c);
      for (int k = 0; k < 3 && !edge[i]; ++k)
        for (const double sgn : {-1.0, 1.0})
          if (nbs::color_distance(true_color(p + sgn * radius_m * nbs::Vec3::Unit(k)), c) > 0.1) edge[i] = 1;
    }
  });
  double sum_edge = 0.0, sum_rest = 0.0;
  for (std::size_t i = 0; i < err.size(); ++i) (edge[i] ? sum_edge : sum_rest) += err[i];
  out.near_edge_vertices = static_cast<std::size_t>(std::count(edge.begin(), edge.end(), 1));
  const std::size_t rest = out.vertices - out.near_edge_vertices;
  out.near_edge = out.near_edge_vertices ? sum_edge / double(out.near_edge_vertices) : 0.0;
  out.rest = rest ? sum_rest / double(rest) : 0.0;
  return out;
}

/// One row of the per-scan series of report.json.
struct Row {
  int scan = 0;
  std::string mode;
  double c_m = 0, d_m = 0, c_a = 0, c_b = 0, e_m = 0, l_s = 0, t_nbs = 0;
  std::size_t candidates = 0, points = 0, vertices = 0;
  double utility = 0.0;
  std::size_t unreachable = 0;  ///< candidates of the planning step the robot could not fly (--robot)
  double t_reach = 0.0;         ///< of t_nbs: the reach checks, seconds (--robot)
  /// --robot: the arm's transfer to this scan's start (0 for the first scan): joint-space length Σ‖Δq‖ (rad), the
  /// sensor's path along it (m), motion-planning time (s).
  double transfer_rad = 0.0, transfer_m = 0.0, t_motion = 0.0;
  int transfer_failures = 0;  ///< --robot: failed transfers to other candidates before this scan's
};

/// --initial-only: the 13 initial scan paths of Sec. 4.7.2, no planning; metrics of the merged point cloud.
int run_initial_only(const Options& opt, const nbs::IndexedMesh& mesh, const nbs::GroundTruth& truth,
                     const nbs::embree::SimulatedScanner& scanner) {
  using namespace nbs;
  const auto t0 = std::chrono::steady_clock::now();
  const LaserStripeProfiler lsp = presets::lsp_by_name(opt.sensor);
  const double standoff_m = 0.5 * (lsp.range.min_m + lsp.range.max_m);
  const std::vector<LinearScanPath> paths = initial_scan_paths(mesh.bounds(), standoff_m);
  CoverageTracker coverage = truth.tracker();
  std::vector<Vec3> cloud;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const Scan scan = scanner.scan(paths[i], lsp, nbs::detail::splitmix64(opt.seed ^ (0x5CA9ULL + i)));
    coverage.add(scan.points);
    cloud.insert(cloud.end(), scan.points.begin(), scan.points.end());
    std::printf("scan %2zu  path %2zu  length %.3f m  points %7zu  c_a %6.2f %%\n", i + 1, i, paths[i].length(),
                scan.size(), 100.0 * coverage.completeness().c_a());
  }
  write_ply_points(file(opt, "points.ply"), cloud);
  const Observability obs = truth.observability(scanner.scene(), embree::SimulatedScanner::observability_settings(lsp));
  const Completeness c = coverage.completeness();
  std::printf("points  %zu written to %s\nc_a %6.2f %%  c_b %6.2f %%  c_obs %6.2f %%  e_rms %.3f mm  l_s %.3f m  "
              "time %.1f s\n",
              cloud.size(), file(opt, "points.ply").c_str(), 100.0 * c.c_a(), 100.0 * c.c_b(), 100.0 * obs.c_obs(),
              1e3 * (cloud.empty() ? 0.0 : truth.rms_error(cloud)), scan_path_length(paths), seconds_since(t0));
  return 0;
}

std::string_view stop_name(nbs::LoopStop s) {
  switch (s) {
    case nbs::LoopStop::done: return "done (termination criterion holds: the model is complete by its stop rule)";
    case nbs::LoopStop::max_scans: return "n_abort scans reached";
    case nbs::LoopStop::no_candidates: return "no candidate left";
    case nbs::LoopStop::transfer_failed: return "transfer failed (the arm found no motion to the chosen scan's start)";
    case nbs::LoopStop::no_reachable_candidate: return "no reachable candidate (the arm can fly none of S)";
  }
  return "?";
}

int run(const Options& opt) {
  using namespace nbs;
  const auto t_start = std::chrono::steady_clock::now();
  std::optional<tools::LoadedRobot> robot;  // --robot: loaded first, so that a bad file fails before any work
  try {
    if (opt.robot.active()) robot = tools::load_robot(opt.robot);
  } catch (const Error& e) {
    std::cerr << "nbs_model: --robot: " << e.what() << "\n";
    return tools::kUsageExit;
  }
  IndexedMesh mesh;
  try {
    mesh = load_mesh(opt.mesh);
    normalize_on_pedestal(mesh, opt.size_m, opt.up);
    if (opt.color && mesh.colors.empty()) mesh.colors = procedural_colors(mesh, opt.seed);  // ground-truth colours
  } catch (const Error& e) {  // a bad --mesh is a usage error
    std::cerr << "nbs_model: --mesh: " << e.what() << "\n";
    return tools::kUsageExit;
  }
  std::filesystem::create_directories(opt.out);
  Parameters params;
  params.max_scans = opt.scans;
  const LaserStripeProfiler lsp = presets::lsp_by_name(opt.sensor);
  GroundTruth::Setting gts;
  gts.seed = opt.seed;
  gts.completeness_radius_m = params.completeness_radius_m;
  const GroundTruth truth(mesh, gts);
  const embree::SimulatedScanner scanner(mesh);
  const Aabb box = mesh.bounds();
  std::printf("object  %s: %zu vertices, %zu triangles, box %.3f x %.3f x %.3f m on the pedestal z = 0\n",
              opt.mesh.c_str(), mesh.vertices.size(), mesh.triangles.size(), box.extent().x(), box.extent().y(),
              box.extent().z());
  if (opt.initial_only) return run_initial_only(opt, mesh, truth, scanner);

  // Bounding box of the unknown area (Sec. 4.1): the object's box + 1 cm sideways and on top, bottom on z = 0.
  Aabb unknown = box;
  unknown.min -= Vec3(0.01, 0.01, 0.0);
  unknown.max += Vec3(0.01, 0.01, 0.01);
  PlannerSetting ps;
  RuntimeModels models = tools::run_models(opt.thesis_mesh, opt.stop_rule);
  if (opt.pose.registration) models.registration = *opt.pose.registration;
  ps.threads = opt.threads;
  ps.seed = opt.seed;
  try {
    // The object must be in the arm's reach before any work (issue 19): 25 % of the view hemisphere at d_s.
    if (robot)
      require_object_in_reach(robot->robot, unknown.center(), 0.5 * (lsp.range.min_m + lsp.range.max_m),
                              robot->start);
  } catch (const Error& e) {
    std::cerr << "nbs_model: --robot: " << e.what() << "\n";
    return tools::kUsageExit;
  }
  RuntimePlanner planner(opt.method, params, lsp, unknown, ps, models);
  if (robot) planner.set_robot(robot->robot, robot->start, robot->setting);
  int first = 0;  // --robot: the seeded initial path or the next one the arm can fly, checked before any work
  try {
    first = reachable_initial_index(planner, opt.seed, std::nullopt);
    if (first != random_initial_scan_index(opt.seed))
      std::printf("first   initial path %d (the seeded %d is out of the arm's reach)\n", first,
                  random_initial_scan_index(opt.seed));
  } catch (const Error& e) {
    std::cerr << "nbs_model: --robot: " << e.what() << "\n";
    return tools::kUsageExit;
  }
  const std::string code = planner.code();
  std::printf("planner %s, n_abort %d, unknown area %.3f x %.3f x %.3f m, voxel %.1f mm, seed %llu, %u threads\n",
              code.c_str(), params.max_scans, unknown.extent().x(), unknown.extent().y(), unknown.extent().z(),
              1e3 * planner.space().resolution_m(), static_cast<unsigned long long>(opt.seed), opt.threads);
  if (robot)
    std::printf("robot   %s (%zu joints, base %s, flange %s, sensor %s): candidates kept only if it can fly them\n",
                opt.robot.urdf.c_str(), robot->robot.joint_count(), opt.robot.base_link.c_str(),
                opt.robot.flange_link.c_str(), opt.robot.sensor_link.c_str());
  std::printf("scan mode  c_m^     d_m^    cand  t_nbs s   points   c_a %%   c_b %%   e mm   l_s m%s%s\n",
              robot ? "  unreach  t_reach s  transfer rad  transfer m  t_motion s" : "",
              opt.pose.active() ? "  registration             pose mm  pose deg" : "");
  // Scan i uses the noise seed splitmix64(seed ^ (0x5CA9 + i)) (SimulatedDriver); the pose error (none without
  // --pose-error: the scans are then bit-identical) is applied to the reported scan.
  PoseErrorDriver driver(SimulatedDriver(scanner, planner.sensor(), opt.seed), opt.pose.setting(opt.seed));

  // Fixed camera framing the object with a margin of 0.4 d_s, so that it fills a good part of the picture; the
  // candidate paths (≈ d_s = 0.3 m from the surface) are drawn where they enter the frame.
  Aabb view = unknown;
  const double margin = 0.4 * 0.5 * (lsp.range.min_m + lsp.range.max_m);
  view.min -= Vec3(margin, margin, 0.0);
  view.max += Vec3(margin, margin, margin);
  const embree::Camera cam = embree::Camera::around(view, -1.0, 0.5, 0.5, 1.0);
  Stage stage{embree::Disc{Vec3(unknown.center().x(), unknown.center().y(), 0.0),
                           0.6 * std::max(unknown.extent().x(), unknown.extent().y()), {235, 225, 205}},
              embree::axes(Vec3(unknown.min.x(), unknown.min.y(), 0.0), 0.03), {}};
  double t_render = 0.0;

  TruthTracker gt(truth);
  std::optional<tools::viewer::SessionRecorder> viewer;  // --viewer (tools/viewer/write_viewer.hpp)
  if (opt.viewer) viewer.emplace();
  std::vector<Row> rows;
  double l_s = 0.0;
  const auto execute = [&](const LinearScanPath& path, const IterationStats& plan, std::size_t candidates,
                           double utility, const std::optional<TransferRecord>& transfer) {
    const std::size_t i = rows.size();
    driver.move_to(path.start().pose());
    const Scan scan = driver.acquire(path);
    const IntegrationReport rep = planner.integrate(scan);
    l_s += path.length();
    stage.flown.push_back({path.start().position(), path.end_position(), {60, 60, 60}, 2});
    gt.update(planner.mesh());
    if (viewer) viewer->add_scan(planner.mesh(), path);
    const Completeness c = gt.coverage.completeness();
    Row r{static_cast<int>(i) + 1, std::string(to_string(plan.mode)), rep.estimated_coverage, rep.mean_density,
          c.c_a(), c.c_b(), gt.rms_m(), l_s, plan.t_nbs_s, candidates, scan.size(), gt.vertices, utility,
          plan.unreachable, plan.t_reach_s};
    if (transfer) {
      r.transfer_rad = transfer->joint_length_rad;
      r.transfer_m = transfer->sensor_length_m;
      r.t_motion = transfer->t_plan_s;
      r.transfer_failures = transfer->failed_attempts;
    }
    if (i == 0) r.mode = "init";
    rows.push_back(r);
    std::printf("%4d %-4s %6.3f  %6.3f  %6zu  %6.3f  %7zu  %6.2f  %6.2f  %5.3f  %6.3f", r.scan, r.mode.c_str(), r.c_m,
                r.d_m, r.candidates, r.t_nbs, r.points, 100.0 * r.c_a, 100.0 * r.c_b, 1e3 * r.e_m, r.l_s);
    if (robot)
      std::printf("  %7zu  %9.3f  %12.3f  %10.3f  %10.4f", r.unreachable, r.t_reach, r.transfer_rad, r.transfer_m,
                  r.t_motion);
    if (opt.pose.active()) {
      const PoseErrorRecord& e = driver.last_error();
      const PoseResidual res = residual_pose_error(e.true_to_reported, rep.registration.correction, e.true_centroid);
      std::printf("  %-24s  %7.3f  %8.4f", std::string(to_string(rep.registration.status)).c_str(),
                  1e3 * res.translation_m, res.rotation_rad * 180.0 / std::numbers::pi);
    }
    std::printf("\n");
    std::fflush(stdout);
  };

  // First scan: one of the 13 initial paths, chosen by the seed (Sec. 4.7.2).
  {
    const LinearScanPath p0 = planner.initial_scan(first);
    std::optional<ArmPicture> arm;  // --robot: the arm at the first path's start (IK from the start joints), else
    if (robot && (opt.images || viewer))  // at the start joints (the arm cannot reach it)
      arm = arm_picture(robot->robot, robot->robot.ik(p0.start().pose(), robot->start).value_or(robot->start), {});
    if (viewer && arm) viewer->add_arm(1, arm->arm, arm->transfer);
    if (opt.images) {
      const auto t = std::chrono::steady_clock::now();
      write_picture(file(opt, numbered("view", 1, "png")), IndexedMesh{}, cam, stage, {p0}, {1.0}, std::size_t{0},
                    opt.threads, arm ? &*arm : nullptr, opt.color);
      t_render += seconds_since(t);
    }
    execute(p0, IterationStats{}, 1, 0.0, std::nullopt);
  }
  LoopStop stop = LoopStop::max_scans;
  PlanStatus last = PlanStatus::ok;
  // --robot: the arm's transfers between scans (OMPL, joint space, against the voxel space after each scan).
  std::optional<tools::ToolTransferPlanner> transfer_planner;
  if (robot) transfer_planner.emplace(tools::transfer_planner(*robot));
  std::string transfer_failure;
  while (static_cast<int>(rows.size()) < params.max_scans) {
    if (planner.done()) {
      stop = LoopStop::done;
      break;
    }
    PlanResult plan = planner.next_best_scan();
    last = plan.status;
    if (!plan.ok()) {
      stop = loop_stop(plan.status);
      break;
    }
    // The transfer first, so that the pictures mark the candidate that is scanned: a failed transfer excludes its
    // candidate and the next best is tried (run_loop's rule); if all fail, plan holds the last one tried.
    std::optional<TransferRecord> transfer;
    if (transfer_planner)
      transfer = transfer_with_retries(planner, plan, robot->transfer_retries, [&](const PlanResult& p) {
        return std::optional<TransferRecord>(plan_scan_transfer(planner, *transfer_planner, p));
      });
    // The candidate set S of this step with utilities: the chosen one (its utility from the planner) and the rest
    // of S (without the candidates whose transfer failed) re-scored in the same state (RuntimePlanner does not
    // expose the values of next_best_scan()).
    std::vector<LinearScanPath> paths{plan.candidate->path};
    std::vector<double> utility{plan.stats.best_utility};
    std::visit(
        [&](auto& p) {
          for (const ScanCandidate& c : p.candidate_set()) paths.push_back(c.path);
          if (paths.size() == 1) return;
          const std::span<const LinearScanPath> rest(paths.data() + 1, paths.size() - 1);
          EvaluationSetting es = p.evaluation_setting();
          es.refine = {};  // every candidate with the full sampling
          const EvaluationResult res = p.utility.evaluate(rest, p.sensor(), p.space(), p.utility_context(), es);
          for (double v : res.values) utility.push_back(v);
        },
        planner.variant());
    const int n = static_cast<int>(rows.size()) + 1;
    write_candidates_ply(file(opt, numbered("candidates", n, "ply")), paths, utility);
    if (viewer) viewer->add_candidates(n, paths, utility);
    std::optional<ArmPicture> arm;  // --robot: the arm at the chosen path's start, the transfer to it (if planned)
    if (robot && (opt.images || viewer))
      arm = arm_picture(robot->robot, plan.joints.empty() ? planner.robot_configuration() : plan.joints.front(),
                        transfer ? transfer->waypoints : std::vector<JointVector>{});
    if (opt.images) {
      const auto t = std::chrono::steady_clock::now();
      write_picture(file(opt, numbered("view", n, "png")), to_indexed_mesh(planner.mesh()), cam, stage, paths,
                    utility, std::size_t{0}, opt.threads, arm ? &*arm : nullptr, opt.color);
      t_render += seconds_since(t);
    }
    if (transfer) {
      if (!transfer->ok()) {
        stop = LoopStop::transfer_failed;
        transfer_failure = transfer->failure + " (" + std::to_string(transfer->failed_attempts) + " tries)";
        break;
      }
    }
    if (viewer && arm) viewer->add_arm(n, arm->arm, arm->transfer);
    execute(plan.candidate->path, plan.stats, plan.stats.evaluated, plan.stats.best_utility, transfer);
  }

  const IndexedMesh model = to_indexed_mesh(planner.mesh());
  if (!model.triangles.empty()) write_mesh_ply(file(opt, "mesh.ply"), model);
  const std::uint64_t voxels = write_voxels_ply(planner.space(), file(opt, "voxels.ply"));
  if (opt.images && !model.triangles.empty()) {
    const auto t = std::chrono::steady_clock::now();
    const Stage final_stage{stage.pedestal, stage.axes, {}};
    const embree::Camera final_cam = embree::Camera::around(unknown, -1.0, 0.5, 0.5, 0.95);
    write_picture(file(opt, "final.png"), model, final_cam, final_stage, {}, {}, std::nullopt, opt.threads, nullptr,
                  opt.color);
    if (opt.color)  // the ground truth in its colours, from the same camera
      write_picture(file(opt, "truth.png"), mesh, final_cam, final_stage, {}, {}, std::nullopt, opt.threads, nullptr,
                    true);
    t_render += seconds_since(t);
  }
  std::optional<ColorErrorSplit> color;  // --color: the model's colour error, 1 voxel as the edge radius
  if (opt.color && !model.colors.empty())
    color = color_error_split(truth.distance(), model, planner.space().resolution_m(), opt.threads);
  const auto t_obs = std::chrono::steady_clock::now();
  const Observability obs = truth.observability(scanner.scene(), embree::SimulatedScanner::observability_settings(lsp));
  const double obs_s = seconds_since(t_obs);
  const Row& fin = rows.back();
  const double runtime = seconds_since(t_start);
  double t_nbs_sum = 0.0;
  for (const Row& r : rows) t_nbs_sum += r.t_nbs;

  std::printf("stop    %s after %zu scans (last plan: %s)\n", std::string(stop_name(stop)).c_str(), rows.size(),
              std::string(to_string(last)).c_str());
  if (!transfer_failure.empty()) std::printf("transfer %s\n", transfer_failure.c_str());
  std::printf("mesh    %zu vertices, %zu triangles -> %s; voxels %llu -> %s\n", model.vertices.size(),
              model.triangles.size(), file(opt, "mesh.ply").c_str(), static_cast<unsigned long long>(voxels),
              file(opt, "voxels.ply").c_str());
  std::printf("c_a     %6.2f %%  (non-bottom samples within %.1f mm of a mesh vertex)\n", 100.0 * fin.c_a,
              1e3 * gts.completeness_radius_m);
  std::printf("c_b     %6.2f %%  (all samples, bottom included)\n", 100.0 * fin.c_b);
  std::printf("c_obs   %6.2f %%  (observability ceiling; c_a/c_obs %.2f %%)\n", 100.0 * obs.c_obs(),
              obs.c_obs() > 0 ? 100.0 * fin.c_a / obs.c_obs() : 0.0);
  std::printf("e_rms   %.3f mm  (RMS distance of the mesh vertices to the true surface)\n", 1e3 * fin.e_m);
  std::printf("l_s     %.3f m  (summed scan path length)\n", fin.l_s);
  if (color)
    std::printf("colour  %.4f mean error over %zu vertices (%.1f %% within 1 voxel of a colour edge: %.4f; rest %.4f)\n",
                color->mean, color->vertices, 100.0 * double(color->near_edge_vertices) / double(color->vertices),
                color->near_edge, color->rest);
  std::printf("time    %.1f s total (planning %.1f s, pictures %.1f s, c_obs %.1f s)\n", runtime, t_nbs_sum, t_render,
              obs_s);

  // report.json (keys in this order; integers stay integers, non-finite numbers are null)
  const auto series = [&](auto get) {
    nlohmann::ordered_json v = nlohmann::ordered_json::array();
    for (const Row& r : rows) v.push_back(get(r));
    return v;
  };
  nlohmann::ordered_json js;
  js["method"] = code;
  js["seed"] = opt.seed;
  js["mesh"] = opt.mesh;
  js["size_m"] = opt.size_m;
  js["initial_path"] = first;
  auto& se = js["series"];
  se["scan"] = series([](const Row& r) { return r.scan; });
  se["c_m"] = series([](const Row& r) { return r.c_m; });
  se["d_m"] = series([](const Row& r) { return r.d_m; });
  se["c_a"] = series([](const Row& r) { return r.c_a; });
  se["c_b"] = series([](const Row& r) { return r.c_b; });
  se["e_rms_m"] = series([](const Row& r) { return r.e_m; });
  se["l_s_m"] = series([](const Row& r) { return r.l_s; });
  se["t_nbs_s"] = series([](const Row& r) { return r.t_nbs; });
  se["candidates"] = series([](const Row& r) { return r.candidates; });
  se["utility"] = series([](const Row& r) { return r.utility; });
  se["points"] = series([](const Row& r) { return r.points; });
  se["mode"] = series([](const Row& r) { return r.mode; });
  if (robot) {
    js["robot"] = opt.robot.urdf;
    se["unreachable_candidates"] = series([](const Row& r) { return r.unreachable; });
    se["t_reach_s"] = series([](const Row& r) { return r.t_reach; });
    se["transfer_joint_rad"] = series([](const Row& r) { return r.transfer_rad; });
    se["transfer_sensor_m"] = series([](const Row& r) { return r.transfer_m; });
    se["t_motion_s"] = series([](const Row& r) { return r.t_motion; });
    se["transfer_failures"] = series([](const Row& r) { return r.transfer_failures; });
  }
  auto& fi = js["final"];
  fi["c_a"] = fin.c_a;
  fi["c_b"] = fin.c_b;
  fi["c_obs"] = obs.c_obs();
  fi["e_rms_m"] = fin.e_m;
  fi["l_s_m"] = fin.l_s;
  fi["scans"] = rows.size();
  fi["stop"] = std::string(stop_name(stop));
  fi["mesh_vertices"] = model.vertices.size();
  fi["mesh_triangles"] = model.triangles.size();
  if (color) {
    fi["mean_color_error"] = color->mean;
    fi["color_vertices"] = color->vertices;
    fi["color_near_edge_vertices"] = color->near_edge_vertices;
    fi["mean_color_error_near_edge"] = color->near_edge;
    fi["mean_color_error_rest"] = color->rest;
  }
  fi["runtime_s"] = runtime;
  nbs::write_json(file(opt, "report.json"), js);
  if (viewer) tools::viewer::write_viewer(*viewer, opt.out, {unknown, &mesh, 20000, &planner.space(), 4'000'000, js});
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  CLI::App app("nbs_model: simulated autonomous modeling of a mesh with the Next-Best-Scan planner", "nbs_model");
  add_options(app, opt);
  if (const auto code = nbs::tools::parse(app, argc, argv)) return *code;
  try {
    return run(opt);
  } catch (const std::exception& e) {
    std::cerr << "nbs_model: error: " << e.what() << "\n";
    return 1;
  }
}
