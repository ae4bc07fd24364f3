// SPDX-License-Identifier: BSD-3-Clause
// nbs_soak: long-run memory and time (issue 17). Not a Google Benchmark and not run by ctest.
//  (a) object soak: N LSP scans of the bundled bunny (0.16 m, on the pedestal) from viewpoints on a 0.3 m sphere
//      (Fibonacci directions, upper half, cycled in a seeded order), each integrated into a 2 mm voxel space and a
//      StreamingMesh. Every 50 scans: VmRSS, VmHWM (/proc/self/status), vertices, faces, mean scan time.
//      Verdict `soak_object_rss_growth_last_half: <MiB>` = VmRSS(end) − VmRSS(N/2).
//  (b) workspace stream (run first, so VmHWM is its own peak): a 4 × 4 × 2 m box at 5 mm, an area sensor (160 × 120 rays, 0.5–3.5 m) 1.6 m above the
//      floor looking down, moved along a lawnmower sweep over a floor with boxes; block flushing on (idle 3 scans,
//      into the system temp folder). RSS and flush counters along the way; `soak_workspace_peak_rss_mib: <value>`.
// Usage: nbs_soak [--quick] [--workspace | --object]   (--quick: 100 object scans and 40 workspace frames; full: 1000
// and 800; --workspace / --object: run only that part).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <numeric>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "common/process_memory.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/mesh/streaming_mesh.hpp"
#include "nbs/sensor/presets.hpp"
#include "nbs/sensor/area_sensor.hpp"
#include "nbs/space/block_flush.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"

namespace {

using nbs::Vec3;

struct Rss {
  double rss_mib = 0.0;  // VmRSS
  double hwm_mib = 0.0;  // VmHWM (peak RSS)
};
/// VmRSS and VmHWM of this process, MiB (0 if unknown).
Rss read_rss() {
  const nbs::tools::ProcessMemory m = nbs::tools::process_memory();
  return {double(m.rss_bytes) / 1048576.0, double(m.peak_bytes) / 1048576.0};
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// (a) Object soak into Mesh (the planner's default NoiseRobustStreamingMesh, or the thesis's plain StreamingMesh);
/// returns the RSS growth over the second half, MiB.
template <class Mesh>
double object_soak(int scans, const char* mesh_name) {
  nbs::IndexedMesh mesh = nbs::load_mesh(NBS_DATA_DIR "/meshes/stanford-bunny.obj");
  nbs::normalize_on_pedestal(mesh, 0.16, nbs::UpAxis::y);
  const nbs::embree::SimulatedScanner scanner(mesh);
  const nbs::LaserStripeProfiler lsp = nbs::presets::dlr_lsp();
  nbs::Aabb box = mesh.bounds();
  box.min -= Vec3(0.01, 0.01, 0.0);
  box.max += Vec3(0.01, 0.01, 0.01);
  nbs::ProbabilisticVoxelSpace<> space(0.002, box);
  Mesh model(nbs::Parameters{}, box);
  // 64 Fibonacci directions on the upper half sphere, radius 0.3 m around the object centre, in a seeded order.
  const Vec3 centre(0.0, 0.0, 0.08);
  std::vector<nbs::Viewpoint> views;
  const int n_dirs = 128;
  for (int i = 0; i < n_dirs; ++i) {
    const double z = 1.0 - (i + 0.5) / n_dirs * 2.0;
    if (z < 0.05) continue;
    const double phi = i * std::numbers::pi * (3.0 - std::sqrt(5.0));
    const double s = std::sqrt(1.0 - z * z);
    const Vec3 eye = centre + 0.3 * Vec3(s * std::cos(phi), s * std::sin(phi), z);
    views.push_back(nbs::Viewpoint::look_at(eye, centre, std::abs(z) > 0.95 ? Vec3::UnitX() : Vec3::UnitZ()));
  }
  std::vector<std::size_t> order(views.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::mt19937_64 rng(7);
  std::shuffle(order.begin(), order.end(), rng);

  std::printf("object soak (%s): %d LSP scans of the bunny, %zu viewpoints cycled, 2 mm voxels\n", mesh_name, scans,
              views.size());
  std::printf("%6s %10s %10s %10s %10s %12s %12s\n", "scan", "VmRSS_MiB", "VmHWM_MiB", "vertices", "faces",
              "ms/scan(50)", "points(50)");
  double rss_half = 0.0, rss_end = 0.0, t_window = 0.0, t_total = 0.0;
  std::size_t points_window = 0;
  for (int k = 1; k <= scans; ++k) {
    const nbs::Viewpoint& v = views[order[static_cast<std::size_t>(k - 1) % views.size()]];
    // A 160 mm linear path along the view's y axis, centred on the viewpoint.
    const Vec3 step = 0.16 * v.y_axis();
    nbs::Pose start = v.pose();
    start.translation() -= 0.5 * step;
    const auto t0 = std::chrono::steady_clock::now();
    const nbs::Scan scan = scanner.scan(nbs::LinearScanPath(nbs::Viewpoint(start), start.translation() + step), lsp,
                                        static_cast<std::uint64_t>(k));
    (void)space.integrate(scan);
    (void)model.integrate(scan);
    const double t = seconds_since(t0);
    t_window += t;
    t_total += t;
    points_window += scan.size();
    if (k % 50 == 0 || k == scans) {
      const Rss r = read_rss();
      const int n = k % 50 == 0 ? 50 : k % 50;
      std::printf("%6d %10.1f %10.1f %10zu %10zu %12.1f %12zu\n", k, r.rss_mib, r.hwm_mib, model.vertex_count(),
                  model.face_count(), 1e3 * t_window / n, points_window / static_cast<std::size_t>(n));
      std::fflush(stdout);
      t_window = 0.0;
      points_window = 0;
      if (k <= scans / 2) rss_half = r.rss_mib;
      rss_end = r.rss_mib;
    }
  }
  std::printf("object soak: %.1f s in scans, mesh %.1f MiB, voxel space %.1f MiB\n", t_total,
              model.memory_bytes() / 1048576.0, space.memory_bytes() / 1048576.0);
  return rss_end - rss_half;
}

/// Appends an axis-aligned box [lo, hi] (12 triangles) to m.
void add_box(nbs::IndexedMesh& m, const Vec3& lo, const Vec3& hi) {
  const auto b = static_cast<std::uint32_t>(m.vertices.size());
  for (int i = 0; i < 8; ++i)
    m.vertices.emplace_back((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(), (i & 4) ? hi.z() : lo.z());
  const std::uint32_t f[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                  {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (const auto& t : f) m.triangles.push_back({b + t[0], b + t[1], b + t[2]});
}

/// (b) Workspace stream; returns the peak RSS (VmHWM) at the end, MiB.
double workspace_soak(int frames) {
  nbs::IndexedMesh scene;
  add_box(scene, Vec3(-2.0, -2.0, -0.02), Vec3(2.0, 2.0, 0.0));  // floor
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> pos(-1.8, 1.6), size(0.1, 0.4), height(0.05, 0.8);
  for (int i = 0; i < 40; ++i) {
    // One draw per statement, in the order gcc 12 drew the former one-expression form (the reported scene).
    const double y = pos(rng), x = pos(rng);
    const double h = height(rng), sy = size(rng), sx = size(rng);
    const Vec3 lo(x, y, 0.0);
    add_box(scene, lo, lo + Vec3(sx, sy, h));
  }
  const nbs::embree::SimulatedScanner scanner(scene);
  nbs::AreaSensor cam;
  cam.width_px = 160;
  cam.height_px = 120;
  const nbs::Aabb area(Vec3(-2.0, -2.0, 0.0), Vec3(2.0, 2.0, 2.0));
  nbs::ProbabilisticVoxelSpace<> space(0.005, area);
  const std::filesystem::path dir = std::filesystem::temp_directory_path();
  nbs::BlockFlushSetting flush;
  flush.directory = dir;
  flush.idle_scans = 3;
  space.mutable_backend().set_flush_policy(flush);
  // Lawnmower: 8 lanes along x at y = −1.75 … 1.75, frames evenly spaced along the whole sweep, 1.6 m high.
  const int lanes = 8;
  const double lane_len = 3.6;
  const double total = lanes * lane_len;
  std::printf("workspace stream: %d frames, 4 x 4 x 2 m at 5 mm, %dx%d area sensor, flush idle %u scans into %s\n",
              frames, cam.width_px, cam.height_px, flush.idle_scans, dir.string().c_str());
  std::printf("%6s %10s %10s %12s %10s %10s %8s %10s\n", "frame", "VmRSS_MiB", "VmHWM_MiB", "space_MiB", "written",
              "reloaded", "failed", "ms/frame");
  double t_window = 0.0;
  const int every = std::max(1, frames / 20);
  for (int k = 0; k < frames; ++k) {
    const double s = total * (k + 0.5) / frames;
    const int lane = std::min(lanes - 1, static_cast<int>(s / lane_len));
    const double along = s - lane * lane_len;
    const double x = (lane % 2 == 0) ? -1.8 + along : 1.8 - along;
    const double y = -1.75 + 3.5 * lane / (lanes - 1);
    const Vec3 eye(x, y, 1.6);
    const auto v = nbs::Viewpoint::look_at(eye, eye + Vec3(0.0, 0.3, -1.6), Vec3::UnitZ());
    const auto t0 = std::chrono::steady_clock::now();
    (void)space.integrate(scanner.scan(v, cam, static_cast<std::uint64_t>(k + 1)));
    t_window += seconds_since(t0);
    if ((k + 1) % every == 0 || k + 1 == frames) {
      const Rss r = read_rss();
      const auto& st = space.backend().flush_stats();
      std::printf("%6d %10.1f %10.1f %12.1f %10llu %10llu %8llu %10.1f\n", k + 1, r.rss_mib, r.hwm_mib,
                  space.memory_bytes() / 1048576.0, static_cast<unsigned long long>(st.blocks_written),
                  static_cast<unsigned long long>(st.blocks_reloaded),
                  static_cast<unsigned long long>(st.failed_writes), 1e3 * t_window / every);
      std::fflush(stdout);
      t_window = 0.0;
    }
  }
  if (!space.backend().flush_stats().last_error.empty())
    std::printf("last flush error: %s\n", space.backend().flush_stats().last_error.c_str());
  return read_rss().hwm_mib;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false, workspace = true, object = true;
  for (int i = 1; i < argc; ++i) {
    const std::string_view a(argv[i]);
    if (a == "--quick") quick = true;
    else if (a == "--workspace") object = false;
    else if (a == "--object") workspace = false;
    else {
      std::fprintf(stderr, "nbs_soak: unknown argument '%s' (usage: nbs_soak [--quick] [--workspace | --object])\n", argv[i]);
      return 2;
    }
  }
  if (!workspace && !object) {
    std::fprintf(stderr, "nbs_soak: --workspace and --object exclude each other\n");
    return 2;
  }
  if (workspace) {
    // The workspace stream first, so that its VmHWM is its own peak.
    const double peak = workspace_soak(quick ? 40 : 800);
    std::printf("soak_workspace_peak_rss_mib: %.1f\n", peak);
    std::fflush(stdout);
  }
  if (!object) return 0;
  const int scans = quick ? 100 : 1000;
  // The planner's default mesh (density limit along the line of sight, PlannerSetting::noise_robust_mesh) ...
  const double growth = object_soak<nbs::NoiseRobustStreamingMesh>(scans, "NoiseRobustStreamingMesh");
  std::printf("soak_object_rss_growth_last_half: %.1f\n", growth);
  std::fflush(stdout);
  // ... and the thesis's stream as written (R_r ball only), which keeps a slab of noisy layers and grows for longer.
  const double growth_thesis = object_soak<nbs::StreamingMesh>(scans, "StreamingMesh");
  std::printf("soak_object_thesis_mesh_rss_growth_last_half: %.1f\n", growth_thesis);
  return 0;
}
