// SPDX-License-Identifier: BSD-3-Clause
// Probabilistic voxel space against OctoMap 1.9 on the same rays: six LSP scans (DLR LSP preset, noise Eq. 4.39)
// of the bunny (0.16 m) from the Embree scanner, unknown area 0.24 × 0.24 × 0.2 m. Headlines (1 thread unless noted):
//   space.insert_vs_octomap@5mm/@2mm/@1mm — rays/s of ProbabilisticVoxelSpace<> (thesis model) ÷ OctoMap
//                                            insertPointCloud (one call per profile, BBX limit = the same box)
//   space.memory_vs_octomap@2mm           — memory_bytes() ÷ OcTree::memoryUsage() after the same scans
//   space.thesis_update_vs_logodds        — time of the thesis model ÷ the log-odds model (native backend, 2 mm)
//   space.raycast_vs_octomap              — planning ray casts/s (native log-odds space) ÷ OctoMap computeRayKeys +
//                                            search per voxel until an occupied voxel, same trees, same segments
//   space.raycast_2thread_scaling         — cast_rays on 2 threads ÷ 1 thread
//   space.area_frame_integrate_s          — median over 5 frames (quick: 3) of the wall time (s) of integrate() of
//                                            one Asus Xtion frame (640 × 480) of the bunny on a table, 5 mm, 2 threads
//   space.area_frame_integrate_s@1thread  — the same on 1 thread (report)
//   space.area_frame_vs_octomap           — OctoMap insertPointCloud time ÷ the 1-thread time, same points, frames
// Each figure is the ratio of the best of N alternating repetitions measured in this process.
#include <benchmark/benchmark.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <string_view>
#include <functional>
#include <numbers>
#include <vector>

#include "headline.hpp"
#include "nbs/embree/scene_scanner.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/explore/overview_ring_setting.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/octomap/insert_scan.hpp"
#include "nbs/octomap/octree_backend.hpp"
#include "nbs/scene/scene_generator.hpp"
#include "nbs/sensor/presets.hpp"
#include "nbs/space/log_odds_model.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"

namespace {

using nbs::bench::median;

using nbs::Vec3;
using LogOddsSpace = nbs::ProbabilisticVoxelSpace<nbs::HashedBlockBackend<nbs::LogOddsState>, nbs::LogOddsModel>;

Vec3 to_float(const Vec3& v) { return v.cast<float>().cast<double>(); }

struct Fixture {
  nbs::LaserStripeProfiler sensor = nbs::presets::dlr_lsp();
  nbs::Aabb box{to_float(Vec3(-0.12, -0.12, 0.0)), to_float(Vec3(0.12, 0.12, 0.2))};
  std::vector<nbs::Scan> scans;
  // per scan, per profile: OctoMap point cloud and origin
  std::vector<std::vector<std::pair<octomap::Pointcloud, octomap::point3d>>> clouds;
  std::size_t points = 0;

  Fixture() {
    nbs::IndexedMesh m = nbs::load_mesh(NBS_DATA_DIR "/meshes/stanford-bunny.obj");
    nbs::normalize_on_pedestal(m, 0.16, nbs::UpAxis::y);
    const nbs::embree::SimulatedScanner scanner(m);
    for (int k = 0; k < 6; ++k) {  // six vertical 0.16 m paths at 0.3 m around the bunny, 20° elevation
      const double a = 2.0 * std::numbers::pi * k / 6.0;
      const Vec3 pos(0.3 * std::cos(a), 0.3 * std::sin(a), 0.03);
      const auto v = nbs::Viewpoint::look_at(pos, {0, 0, 0.0}, Vec3::UnitZ());
      const Vec3 step = 0.16 * v.y_axis() * (v.y_axis().z() > 0 ? 1.0 : -1.0);
      nbs::Scan s = scanner.scan(nbs::LinearScanPath(v, pos + step), sensor, 17 + k);
      for (auto& p : s.points) p = to_float(p);
      for (auto& pose : s.profile_poses) pose.translation() = to_float(pose.translation());
      points += s.size();
      std::vector<std::pair<octomap::Pointcloud, octomap::point3d>> c(s.profile_poses.size());
      for (std::size_t j = 0; j < s.profile_poses.size(); ++j) {
        const Vec3 o = s.profile_poses[j].translation();
        c[j].second = octomap::point3d(float(o.x()), float(o.y()), float(o.z()));
      }
      for (std::size_t i = 0; i < s.size(); ++i)
        c[s.profile_of_point[i]].first.push_back(float(s.points[i].x()), float(s.points[i].y()),
                                                 float(s.points[i].z()));
      clouds.push_back(std::move(c));
      scans.push_back(std::move(s));
    }
  }

  [[nodiscard]] nbs::ThesisModel thesis_model() const {
    nbs::ThesisModel::Setting st;
    const nbs::RangeNoise noise = sensor.noise;
    st.sigma_m = [noise](double d) { return std::max(noise.sigma_m(d), 1e-5); };
    return nbs::ThesisModel(st);
  }
  [[nodiscard]] std::size_t rays(int n_scans) const {
    std::size_t n = 0;
    for (int i = 0; i < n_scans; ++i) n += scans[i].size();
    return n;
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}


void insert_octomap(octomap::OcTree& t, int n_scans) {
  const auto& f = fixture();
  for (int i = 0; i < n_scans; ++i)
    for (const auto& [cloud, origin] : f.clouds[i]) t.insertPointCloud(cloud, origin);
}

template <class Space>
void insert_nbs(Space& s, int n_scans) {
  for (int i = 0; i < n_scans; ++i) (void)s.integrate(fixture().scans[i]);
}

// ---- Google Benchmark cases (throughput tables) ----------------------------------------------------------------
// Scans inserted at resolution `res`: the headline's counts (6 at 5 mm, 3 at 2 mm, 1 at 1 mm).
int scans_at(double res) { return res < 0.0015 ? 1 : (res < 0.003 ? 3 : 6); }
template <class Make>
void bm_insert_native(benchmark::State& state, Make&& make) {
  const double res = state.range(0) * 1e-3;
  const int n = scans_at(res);
  for (auto _ : state) {
    auto s = make(res);
    insert_nbs(s, n);
    benchmark::DoNotOptimize(s.totals().voxel_updates);
  }
  state.counters["rays_per_s"] = benchmark::Counter(double(fixture().rays(n)), benchmark::Counter::kIsIterationInvariantRate);
}
void BM_InsertThesis(benchmark::State& state) {
  bm_insert_native(state, [](double res) { return nbs::ProbabilisticVoxelSpace<>(res, fixture().box, fixture().thesis_model()); });
}
void BM_InsertLogOdds(benchmark::State& state) {
  bm_insert_native(state, [](double res) { return LogOddsSpace(res, fixture().box); });
}
void BM_InsertOctomap(benchmark::State& state) {
  const double res = state.range(0) * 1e-3;
  const int n = scans_at(res);
  for (auto _ : state) {
    auto t = nbs::octomap::bbx_limited_octree(res, fixture().box);
    insert_octomap(t, n);
    benchmark::DoNotOptimize(t.size());
  }
  state.counters["rays_per_s"] = benchmark::Counter(double(fixture().rays(n)), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_InsertThesis)->Arg(5)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_InsertLogOdds)->Arg(5)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_InsertOctomap)->Arg(5)->Arg(2)->Unit(benchmark::kMillisecond);

// FNV-1a over (key, state) of every observed voxel in key order: identical spaces give identical checksums, so an
// optimisation of the update can be checked against the previous build on the bunny scans.
std::uint64_t state_checksum(const nbs::ProbabilisticVoxelSpace<>& s) {
  std::vector<std::pair<std::uint64_t, nbs::ThesisState>> v;
  s.for_each([&](const nbs::VoxelKey& k, const nbs::ThesisState& st) { v.push_back({k.pack(), st}); });
  std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::uint64_t h = 1469598103934665603ull;
  const auto mix = [&h](std::uint64_t x) {
    for (int i = 0; i < 8; ++i, x >>= 8) h = (h ^ (x & 0xFF)) * 1099511628211ull;
  };
  for (const auto& [k, st] : v) {
    mix(k);
    mix(static_cast<std::uint16_t>(st.free) | std::uint64_t{static_cast<std::uint16_t>(st.surf)} << 16 |
        std::uint64_t{st.spec} << 32 | std::uint64_t{st.direction} << 40);
  }
  return h;
}

// ---- Area-sensor frames ---------------------------------------------------------------------------------------------
// The scene of nbs_explore (examples/nbs_explore.cpp): the bunny (0.16 m) on a 0.6 × 0.45 m table (seed 1), its voxel
// space ProbabilisticVoxelSpace<> at 5 mm over the table up to 0.3 m; Asus Xtion frames (640 × 480) from the
// OverviewRing geometry (0.75 m from (0, 0, 0.05), 35° elevation, azimuths −90° + 72° k, k = 0..n_frames − 1). Each
// frame keeps only the points inside the space's bounds (integrate() skips the others; OctoMap would still clear the
// free space towards them), coordinates rounded to float (OctoMap's precision), as the LSP scans above.
void area_frame_headlines(int reps, int n_frames) {
  nbs::IndexedMesh bunny = nbs::load_mesh(NBS_DATA_DIR "/meshes/stanford-bunny.obj");
  nbs::normalize_on_pedestal(bunny, 0.16, nbs::UpAxis::y);
  nbs::scene::SceneSettings st;
  st.min_gap_m = 0.03;
  st.table_size_x_m = 0.6;
  st.table_size_y_m = 0.45;
  const std::vector<nbs::scene::ObjectSpec> specs{{"bunny", bunny}};
  const nbs::scene::SimulatedScene sc = nbs::scene::generate_scene(specs, st, 1);
  const nbs::embree::SceneScanner scanner(sc);
  const nbs::Aabb box{to_float(Vec3(-0.3, -0.225, -0.01)), to_float(Vec3(0.3, 0.225, 0.3))};
  const nbs::AreaSensor xtion = nbs::presets::asus_xtion_pro();
  const nbs::explore::OverviewRingSetting ring;  // nbs_explore's overview geometry
  std::vector<nbs::Scan> frames;
  std::vector<octomap::Pointcloud> clouds;
  std::vector<octomap::point3d> origins;
  std::size_t cast = 0;
  for (int k = 0; k < n_frames; ++k) {
    const Vec3 eye = to_float(ring.eye(ring.step_azimuth(k)));
    const nbs::Scan raw = scanner.scanner().scan(nbs::Viewpoint::look_at(eye, ring.target, Vec3::UnitZ()), xtion, 100 + k);
    cast += raw.rays_cast;
    nbs::Scan f;
    f.profile_poses = raw.profile_poses;
    f.rays_cast = raw.rays_cast;
    octomap::Pointcloud c;
    for (std::size_t i = 0; i < raw.size(); ++i) {
      const Vec3 p = to_float(raw.points[i]);
      if (!box.contains(p)) continue;
      f.points.push_back(p);
      f.profile_of_point.push_back(raw.profile_of_point[i]);
      c.push_back(float(p.x()), float(p.y()), float(p.z()));
    }
    const Vec3 o = f.profile_poses[0].translation();
    origins.emplace_back(float(o.x()), float(o.y()), float(o.z()));
    clouds.push_back(std::move(c));
    frames.push_back(std::move(f));
  }
  // Each repetition integrates the frames in order into fresh spaces (1 and 2 threads) and a fresh tree, timing every
  // call; per frame the best over the repetitions (the calls alternate), then the median over the frames.
  std::vector<double> t_one(frames.size(), INFINITY), t_two(frames.size(), INFINITY), t_octo(frames.size(), INFINITY);
  std::size_t points = 0;
  bool same = true;
  unsigned threads_used = 0;
  for (int r = 0; r < reps; ++r) {
    nbs::ProbabilisticVoxelSpace<> one(0.005, box), two(0.005, box);
    auto tree = nbs::octomap::bbx_limited_octree(0.005, box);
    points = 0;
    for (std::size_t k = 0; k < frames.size(); ++k) {
      points += frames[k].size();
      t_one[k] = std::min(t_one[k], nbs::bench::seconds([&] { (void)one.integrate(frames[k], 1); }));
      t_two[k] = std::min(t_two[k], nbs::bench::seconds([&] { (void)two.integrate(frames[k], 2); }));
      threads_used = std::max(threads_used, two.last_integrate_threads());
      t_octo[k] = std::min(t_octo[k], nbs::bench::seconds([&] { tree.insertPointCloud(clouds[k], origins[k]); }));
    }
    same = same && state_checksum(one) == state_checksum(two);
  }
  std::printf("space: area frames: %zu Xtion frames, %zu rays cast, %zu points inside the space (%.0f per frame)\n",
              frames.size(), std::size_t(cast), points, double(points) / double(frames.size()));
  for (std::size_t k = 0; k < frames.size(); ++k)
    std::printf("space: area frame %zu: %zu points, nbs %.1f ms (1 thread) / %.1f ms (2 threads), OctoMap %.1f ms\n", k,
                frames[k].size(), 1e3 * t_one[k], 1e3 * t_two[k], 1e3 * t_octo[k]);
  std::printf("space: area frames: 1- and 2-thread spaces %s; 2-thread integrate ran on %u threads\n",
              same ? "identical (state checksums)" : "DIFFER", threads_used);
  nbs::bench::report_headline("space.area_frame_integrate_s", median(t_two),
                              same ? "target <= 0.033; 2 threads (integrate(scan, 2)), 5 mm"
                                   : "INVALID: the 2-thread space differs from the 1-thread space");
  nbs::bench::report_headline("space.area_frame_integrate_s@1thread", median(t_one), "report: the same on 1 thread");
  nbs::bench::report_headline("space.area_frame_vs_octomap", median(t_octo) / median(t_one),
                              "OctoMap insertPointCloud time / nbs on 1 thread, same points");
}

// ---- Headlines ------------------------------------------------------------------------------------------------------
void headlines() {
  const auto& f = fixture();
  const int reps = nbs::bench::quick_mode() ? 2 : 5;
  std::printf("space: %zu points in %zu scans\n", f.points, f.scans.size());
  for (const auto& [mm, n] : std::vector<std::pair<int, int>>{{5, 6}, {2, 3}, {1, 1}}) {
    nbs::ProbabilisticVoxelSpace<> s(mm * 1e-3, f.box, f.thesis_model());
    insert_nbs(s, n);
    const auto& t = s.totals();
    std::printf("space: @%dmm after %d scans: %zu voxels, checksum %016llx; per ray %.1f voxel visits, %.2f updates\n",
                mm, n, nbs::observed_count(s.backend()), static_cast<unsigned long long>(state_checksum(s)),
                double(t.voxel_updates + t.voxels_same_scan + t.voxels_similar_beam) / double(t.integrated),
                double(t.voxel_updates) / double(t.integrated));
  }

  for (const auto& [mm, n] : std::vector<std::pair<int, int>>{{5, 6}, {2, 3}, {1, 1}}) {
    const double res = mm * 1e-3;
    const auto t = nbs::bench::best_times(reps, {[&] {
                                       nbs::ProbabilisticVoxelSpace<> s(res, f.box, f.thesis_model());
                                       insert_nbs(s, n);
                                     },
                                     [&] {
                                       auto tree = nbs::octomap::bbx_limited_octree(res, f.box);
                                       insert_octomap(tree, n);
                                     }});
    const double rays = double(f.rays(n));
    std::printf("space: insert @%dmm: thesis %.2f M rays/s, OctoMap %.3f M rays/s\n", mm, rays / t[0] * 1e-6,
                rays / t[1] * 1e-6);
    char name[64];
    std::snprintf(name, sizeof name, "space.insert_vs_octomap@%dmm", mm);
    nbs::bench::report_headline(name, t[1] / t[0], mm == 5 ? "target >= 4" : "target >= 6");
  }

  {  // memory and update cost at 2 mm, all six scans
    nbs::ProbabilisticVoxelSpace<> s(0.002, f.box, f.thesis_model());
    insert_nbs(s, 6);
    auto tree = nbs::octomap::bbx_limited_octree(0.002, f.box);
    insert_octomap(tree, 6);
    std::printf("space: memory @2mm: nbs %.1f MB (%zu voxels), OctoMap %.1f MB (%zu nodes)\n",
                s.memory_bytes() * 1e-6, nbs::observed_count(s.backend()), tree.memoryUsage() * 1e-6, tree.size());
    nbs::bench::report_headline("space.memory_vs_octomap@2mm", double(s.memory_bytes()) / double(tree.memoryUsage()),
                                "target <= 0.5");
    // Both sides are our own and fast (≈ 0.3 s a round): more rounds than the OctoMap comparisons, so that the
    // best of each is not at the mercy of a slow stretch of the shared machine.
    const auto t = nbs::bench::best_times(3 * reps, {[&] {
                                       nbs::ProbabilisticVoxelSpace<> a(0.002, f.box, f.thesis_model());
                                       insert_nbs(a, 6);
                                     },
                                     [&] {
                                       LogOddsSpace b(0.002, f.box);
                                       insert_nbs(b, 6);
                                     }});
    nbs::bench::report_headline("space.thesis_update_vs_logodds", t[0] / t[1], "target <= 1.3");
  }

  {  // planning ray casts at 2 mm: fans from 32 viewpoints on a sphere of 0.3 m, 0.45 m long, clipped to the box
    LogOddsSpace s(0.002, f.box);
    insert_nbs(s, 6);
    auto tree = nbs::octomap::bbx_limited_octree(0.002, f.box);
    insert_octomap(tree, 6);
    std::vector<nbs::Ray> rays;
    for (int v = 0; v < 32; ++v) {
      const double az = 2.0 * std::numbers::pi * v / 32.0, el = 0.2 + 0.8 * (v % 4) / 4.0;
      const Vec3 o = Vec3(0, 0, 0.08) + 0.3 * nbs::unit_from_angles(az, el);
      const auto vp = nbs::Viewpoint::look_at(o, Vec3(0, 0, 0.08));
      for (int i = 0; i < 32; ++i)
        for (int j = 0; j < 32; ++j) {
          const Vec3 d = (vp.view_direction() + 0.5 * (i / 31.0 - 0.5) * vp.x_axis() + 0.5 * (j / 31.0 - 0.5) * vp.y_axis()).normalized();
          double t0, t1;
          const Vec3 e = o + 0.45 * d;
          if (!nbs::detail::clip_segment(o, e, s.voxel_bounds(), t0, t1)) continue;
          rays.push_back({to_float(o + t0 * (e - o)), to_float(o + t1 * (e - o))});
        }
    }
    std::size_t nbs_voxels = 0, octo_voxels = 0, nbs_hits = 0, octo_hits = 0;
    const auto cast_nbs = [&](unsigned threads) {
      std::vector<unsigned> unknown(rays.size(), 0);
      const auto r = s.cast_rays(rays, threads, [&](std::size_t i, const nbs::VoxelKey&, const nbs::LogOddsState& st) {
        unknown[i] += st.log_odds == 0.0f ? 1u : 0u;
      });
      nbs_voxels = nbs_hits = 0;
      for (const auto& x : r) {
        nbs_voxels += x.voxels;
        nbs_hits += x.hit ? 1 : 0;
      }
    };
    const auto cast_octomap = [&] {
      octomap::KeyRay kr;
      octo_voxels = octo_hits = 0;
      std::vector<unsigned> unknown(rays.size(), 0);
      for (std::size_t i = 0; i < rays.size(); ++i) {
        const auto& r = rays[i];
        const octomap::point3d a(float(r.origin.x()), float(r.origin.y()), float(r.origin.z()));
        const octomap::point3d b(float(r.end.x()), float(r.end.y()), float(r.end.z()));
        if (!tree.computeRayKeys(a, b, kr)) continue;
        for (const auto& k : kr) {
          ++octo_voxels;
          const auto* n = tree.search(k);
          if (!n) {
            ++unknown[i];
          } else if (tree.isNodeOccupied(n)) {
            ++octo_hits;
            break;
          }
        }
      }
      benchmark::DoNotOptimize(unknown.data());
    };
    const auto t = nbs::bench::best_times(reps, {[&] { cast_nbs(1); }, cast_octomap});
    const auto ts = nbs::bench::best_times(4 * reps, {[&] { cast_nbs(1); }, [&] { cast_nbs(2); }});  // ≈ 0.1 s a round
    std::printf("space: raycast: %zu rays; nbs %.2f M rays/s (%zu voxels, %zu hits), OctoMap %.3f M rays/s (%zu voxels, %zu hits)\n",
                rays.size(), rays.size() / t[0] * 1e-6, nbs_voxels, nbs_hits, rays.size() / t[1] * 1e-6, octo_voxels,
                octo_hits);
    nbs::bench::report_headline("space.raycast_vs_octomap", t[1] / t[0], "target >= 4");
    nbs::bench::report_headline("space.raycast_2thread_scaling", ts[0] / ts[1], "target >= 1.8; 2 shared cores");
    nbs::bench::report_headline("space.machine_2thread_scaling", nbs::bench::machine_2thread_scaling(reps),
                                "report: the same machine's ceiling, a throughput-bound integer loop");
  }
  // ≈ 1.5 s a frame and round, OctoMap ≈ 90 % of it: quick mode takes 3 frames once.
  if (nbs::bench::quick_mode()) area_frame_headlines(1, 3);
  else area_frame_headlines(3, 5);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  // NBS_BENCH_NO_HEADLINES=1: only the Google Benchmark cases (e.g. under callgrind with --benchmark_filter).
  const char* skip = std::getenv("NBS_BENCH_NO_HEADLINES");
  if (skip == nullptr || std::string_view(skip) != "1") headlines();
  return 0;
}
