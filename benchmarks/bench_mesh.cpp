// SPDX-License-Identifier: BSD-3-Clause
// Streaming mesh benchmarks (issue 4). Headlines:
//  mesh.points_per_s           incoming stripe-profiler points per second, 1 core, Tab. 4.3 radii, into the planner's
//                              default mesh (NoiseRobustStreamingMesh, PlannerSetting::noise_robust_mesh): the bundled
//                              bunny at 160 mm scanned by the Embree simulated scanner (thesis LSP dlr_lsp(): 640 rays
//                              per profile, 1 mm profile spacing, thesis noise) along six 160 mm paths around it, all
//                              six scans integrated into one mesh. Without nbs::embree: the synthetic sphere below.
//  mesh.points_per_s_thesis    the same stream into StreamingMesh with its default settings (the thesis's stream as
//                              written: a slab of noisy layers, more stored points)
//  mesh.points_per_s_sphere    a 160 mm sphere scanned by a dense synthetic stream (640 rays per profile, 0.3 mm
//                              profile step, 50 µm noise) into StreamingMesh with its default (thesis) settings.
//                              Without nbs::embree this is also the figure reported as mesh.points_per_s.
//  mesh.cost_growth_10k_to_1m  time per incoming point with a 1M-vertex model ÷ with a 10k-vertex model (plane)
//  mesh.bytes_per_vertex       StreamingMesh::memory_bytes() / vertex_count() of the 1M-vertex model
// Tools for optimisation work (then nothing else runs):
//  bench_mesh --mesh_hash       FNV-1a hash of the mesh (positions, normals, faces, stats) built from several streams,
//                               to check that a speed-up leaves the output bit-identical.
//  bench_mesh --mesh_prefix=N   streams the first N points of the bunny stream (sphere without nbs::embree) inside
//                               stream_prefix(), e.g. for valgrind --tool=callgrind --toggle-collect='*stream_prefix*'.
//  bench_mesh --mesh_prefix_robust=N  the same into a StreamingMesh with the noise-robust settings.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdio>
#include <cmath>
#include <cstring>
#include <memory>
#include <random>
#include <string_view>
#include <vector>

#include "headline.hpp"
#include "nbs/mesh/boundaries.hpp"
#include "nbs/mesh/holes.hpp"
#include "nbs/mesh/streaming_mesh.hpp"
#include "nbs/mesh/surface_features.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"
#ifdef NBS_BENCH_MESH_BUNNY
#include <numbers>

#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/sensor/presets.hpp"
#endif

namespace {
using nbs::Vec3;

struct Stream {
  std::vector<Vec3> points, los;
};

/// Dense stripe-profiler stream over a sphere of radius r (160 mm object), sensor 200 mm above the top, moving in y.
Stream sphere_stream(double r, double path_m, unsigned seed) {
  Stream s;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 5e-5);
  const int rays = 640;
  const double fov = 0.6, step = 0.0003;
  for (double y = -path_m / 2; y <= path_m / 2; y += step) {
    const Vec3 o(0, y, r + 0.2);
    for (int i = 0; i < rays; ++i) {
      const double th = -fov / 2 + fov * (i + 0.5) / rays;
      const Vec3 d(std::sin(th), 0, -std::cos(th));
      const double b = o.dot(d), c = o.squaredNorm() - r * r, disc = b * b - c;
      if (disc < 0) continue;
      const double t = -b - std::sqrt(disc);
      s.points.push_back(o + (t + noise(rng)) * d);
      s.los.push_back(d);
    }
  }
  return s;
}

void feed(nbs::StreamingMesh& m, const Stream& s) {
  for (std::size_t i = 0; i < s.points.size(); ++i) (void)m.insert(s.points[i], s.los[i]);
}

/// Plane model with about n vertices (grid at 0.7 mm, seeded jitter), los straight down.
void build_plane(nbs::StreamingMesh& m, std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> j(-5e-5, 5e-5);
  const int side = static_cast<int>(std::sqrt(static_cast<double>(n)));
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      // One draw per statement, z, y, x: the order gcc 12 drew the former one-expression form.
      const double jz = j(rng), jy = j(rng), jx = j(rng);
      (void)m.insert(Vec3(x * 7e-4 + jx, y * 7e-4 + jy, jz), Vec3(0, 0, -1));
    }
}

/// Probe: dense random points on a 20 mm square in the middle of the model (rescan: rejections + refinements).
Stream plane_probe(double centre, unsigned seed) {
  Stream s;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.01, 0.01), z(-5e-5, 5e-5);
  for (int i = 0; i < 200000; ++i) {
    const double pz = z(rng), py = u(rng), px = u(rng);  // one draw per statement, gcc 12's former order
    s.points.emplace_back(centre + px, centre + py, pz);
    s.los.emplace_back(0, 0, -1);
  }
  return s;
}

double seconds_per_point(std::size_t model_vertices) {
  nbs::StreamingMesh m;
  build_plane(m, model_vertices, 1);
  const double side = std::sqrt(static_cast<double>(model_vertices)) * 7e-4;
  const Stream probe = plane_probe(side / 2, 2);
  const auto t0 = std::chrono::steady_clock::now();
  feed(m, probe);
  const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return dt / static_cast<double>(probe.points.size());
}

#ifdef NBS_BENCH_MESH_BUNNY
/// Six vertical 160 mm LSP scans of the bunny (0.16 m, on the pedestal) from 0.3 m around its axis, as in
/// bench_scanner; seeded noise, so the stream is reproducible.
std::vector<nbs::Scan> simulate_bunny_scans() {
  nbs::IndexedMesh mesh = nbs::load_mesh(NBS_DATA_DIR "/meshes/stanford-bunny.obj");
  nbs::normalize_on_pedestal(mesh, 0.16, nbs::UpAxis::y);
  const nbs::embree::SimulatedScanner scanner(mesh);
  const nbs::LaserStripeProfiler lsp = nbs::presets::dlr_lsp();
  std::vector<nbs::Scan> scans;
  for (int k = 0; k < 6; ++k) {
    const double a = 2.0 * std::numbers::pi * k / 6.0;
    const auto v = nbs::Viewpoint::look_at({0.3 * std::cos(a), 0.3 * std::sin(a), 0.0}, {0, 0, 0.0}, Vec3::UnitZ());
    const Vec3 step = 0.16 * v.y_axis() * (v.y_axis().z() > 0 ? 1.0 : -1.0);
    nbs::Pose start = v.pose();
    start.translation().z() = 0.0;
    scans.push_back(scanner.scan(nbs::LinearScanPath(nbs::Viewpoint(start), start.translation() + step), lsp,
                                 static_cast<std::uint64_t>(k + 1)));
  }
  return scans;
}
/// The six scans, simulated once per process (every case and tool below shares them).
const std::vector<nbs::Scan>& bunny_scans() {
  static const std::vector<nbs::Scan> scans = simulate_bunny_scans();
  return scans;
}

std::size_t point_count(const std::vector<nbs::Scan>& scans) {
  std::size_t n = 0;
  for (const auto& s : scans) n += s.size();
  return n;
}

void BM_StreamBunny(benchmark::State& state) {
  const std::vector<nbs::Scan>& scans = bunny_scans();
  for (auto _ : state) {
    nbs::StreamingMesh m;
    for (const auto& s : scans) (void)m.integrate(s);
    benchmark::DoNotOptimize(m.face_count());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * point_count(scans)));
}
BENCHMARK(BM_StreamBunny)->Unit(benchmark::kMillisecond);

// Mesh analysis run after every scan, over the 6-scan bunny mesh (≈ 170k vertices): holes (Sec. 4.4) and boundaries
// (Alg. 1, all of the mesh is M_cur of its last scan's sensor pose).
const nbs::StreamingMesh& bunny_mesh() {
  static const auto m = [] {
    auto mesh = std::make_unique<nbs::StreamingMesh>();  // not movable: the triangulator borrows its members
    for (const auto& s : bunny_scans()) (void)mesh->integrate(s);
    return mesh;
  }();
  return *m;
}
void BM_FindHolesBunny(benchmark::State& state) {
  const auto& m = bunny_mesh();
  for (auto _ : state) benchmark::DoNotOptimize(nbs::find_holes(m, nbs::Parameters{}).size());
}
BENCHMARK(BM_FindHolesBunny)->Unit(benchmark::kMillisecond);
void BM_DetectBoundariesBunny(benchmark::State& state) {
  const auto& m = bunny_mesh();
  const nbs::Pose sensor = nbs::Viewpoint::look_at({0.3, 0.0, 0.0}, {0, 0, 0.0}, Vec3::UnitZ()).pose();
  for (auto _ : state) benchmark::DoNotOptimize(nbs::detect_boundaries(m, sensor, nbs::Parameters{}).size());
}
BENCHMARK(BM_DetectBoundariesBunny)->Unit(benchmark::kMillisecond);
// Surface features (Sec. 4.5.1) of the voxels the last scan touched, over a 2 mm voxel space of the scans.
void BM_UpdateSurfaceFeaturesBunny(benchmark::State& state) {
  const auto& m = bunny_mesh();
  nbs::ProbabilisticVoxelSpace<> space(0.002, nbs::Aabb{Vec3(-0.12, -0.12, -0.01), Vec3(0.12, 0.12, 0.2)});
  for (const auto& s : bunny_scans()) (void)space.integrate(s);
  nbs::SurfaceFeatureMap features;
  for (auto _ : state) benchmark::DoNotOptimize(nbs::update_surface_features(features, space, m, nbs::Parameters{}));
}
BENCHMARK(BM_UpdateSurfaceFeaturesBunny)->Unit(benchmark::kMillisecond);
#endif

void BM_StreamSphere(benchmark::State& state) {
  const Stream s = sphere_stream(0.08, 0.1, 3);
  for (auto _ : state) {
    nbs::StreamingMesh m;
    feed(m, s);
    benchmark::DoNotOptimize(m.face_count());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * s.points.size()));
}
BENCHMARK(BM_StreamSphere)->Unit(benchmark::kMillisecond);

/// FNV-1a 64 over the bytes of the mesh: positions, normals, faces in order, and the stream counters.
std::uint64_t mesh_hash(const nbs::StreamingMesh& m) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  auto bytes = [&](const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 0x100000001b3ull;
  };
  for (std::size_t v = 0; v < m.vertex_count(); ++v) {
    bytes(m.position(static_cast<nbs::VertexId>(v)).data(), 3 * sizeof(double));
    bytes(m.normal(static_cast<nbs::VertexId>(v)).data(), 3 * sizeof(double));
  }
  m.for_each_face([&](const nbs::MeshFace& f) { bytes(&f, sizeof f); });
  const nbs::StreamingStats& s = m.stats();
  for (std::uint64_t c : {s.received, s.outside, s.too_close, s.stored, s.meshed, s.normal_failures})
    bytes(&c, sizeof c);
  return h;
}

void print_hash(const char* name, const nbs::StreamingMesh& m) {
  std::printf("%-28s %016llx  vertices %zu faces %zu\n", name, static_cast<unsigned long long>(mesh_hash(m)),
              m.vertex_count(), m.face_count());
}

int hash_streams() {
  {
    const Stream s = sphere_stream(0.08, 0.1, 3);
    nbs::StreamingMesh m;
    feed(m, s);
    print_hash("sphere", m);
    nbs::StreamingMeshSettings st;
    st.normal_radius_m = 0.006;  // R_m < R_n: the other ball order
    st.mesh_radius_m = 0.004;
    nbs::StreamingMesh m2(st);
    feed(m2, s);
    print_hash("sphere R_m < R_n", m2);
  }
  {
    nbs::StreamingMesh m;
    build_plane(m, 10000, 1);
    feed(m, plane_probe(0.035, 2));
    print_hash("plane 10k + probe", m);
  }
#ifdef NBS_BENCH_MESH_BUNNY
  const std::vector<nbs::Scan>& scans = bunny_scans();
  {
    nbs::StreamingMesh m;
    for (const auto& s : scans) (void)m.integrate(s);
    print_hash("bunny 6 scans", m);
  }
  {
    nbs::NoiseRobustStreamingMesh m;
    for (const auto& s : scans) (void)m.integrate(s);
    print_hash("bunny 6 scans, noise-robust", m);
  }
  {
    nbs::StreamingMesh m(nbs::Parameters{}, nbs::Aabb{Vec3(-0.05, -0.05, 0.0), Vec3(0.05, 0.05, 0.1)});
    for (std::size_t k = 3; k < scans.size(); ++k) (void)m.integrate(scans[k]);
    print_hash("bunny scans 4-6, box", m);
  }
#endif
  return 0;
}

/// The first n points of the headline stream, in one function so that callgrind can count only this.
[[gnu::noinline]] std::size_t stream_prefix(nbs::StreamingMesh& m, const std::vector<Vec3>& pts,
                                            const std::vector<Vec3>& los) {
  for (std::size_t i = 0; i < pts.size(); ++i) (void)m.insert(pts[i], los[i]);
  return m.face_count();
}

int run_prefix(std::size_t n, bool robust) {
  std::vector<Vec3> pts, los;
#ifdef NBS_BENCH_MESH_BUNNY
  for (const auto& s : bunny_scans())
    for (std::size_t i = 0; i < s.size() && pts.size() < n; ++i) {
      pts.push_back(s.points[i]);
      los.push_back(s.line_of_sight(i));
    }
#else
  const Stream s = sphere_stream(0.08, 0.1, 3);
  pts.assign(s.points.begin(), s.points.begin() + static_cast<std::ptrdiff_t>(std::min(n, s.points.size())));
  los.assign(s.los.begin(), s.los.begin() + static_cast<std::ptrdiff_t>(pts.size()));
#endif
  nbs::StreamingMeshSettings settings;
  if (robust) settings = nbs::NoiseRobustStreamingMesh::robust(settings);
  nbs::StreamingMesh m(settings);
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t faces = stream_prefix(m, pts, los);
  const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("%zu points, %zu vertices, %zu faces, %.0f points/s, hash %016llx\n", pts.size(), m.vertex_count(),
              faces, static_cast<double>(pts.size()) / dt, static_cast<unsigned long long>(mesh_hash(m)));
  const nbs::StreamingStats& st = m.stats();
  std::printf("stats: too_close %llu, stored %llu, meshed %llu, normal failures %llu\n",
              static_cast<unsigned long long>(st.too_close), static_cast<unsigned long long>(st.stored),
              static_cast<unsigned long long>(st.meshed), static_cast<unsigned long long>(st.normal_failures));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view a(argv[i]);
    if (a == "--mesh_hash") return hash_streams();
    if (a.starts_with("--mesh_prefix=")) return run_prefix(std::strtoull(argv[i] + 14, nullptr, 10), false);
    if (a.starts_with("--mesh_prefix_robust="))
      return run_prefix(std::strtoull(argv[i] + 21, nullptr, 10), true);
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  double sphere_rate = 0.0;
  {
    const Stream s = sphere_stream(0.08, 0.1, 3);
    nbs::StreamingMesh m;
    const auto t0 = std::chrono::steady_clock::now();
    feed(m, s);
    const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    sphere_rate = static_cast<double>(s.points.size()) / dt;
  }
#ifdef NBS_BENCH_MESH_BUNNY
  // The planner's default mesh (noise-robust: density cylinder + vertex projection) and the thesis's on one stream.
  const auto bunny_rate = [](auto& m, const char* name, const char* what, const char* target) {
    const std::vector<nbs::Scan>& scans = bunny_scans();
    const auto t0 = std::chrono::steady_clock::now();
    for (const auto& s : scans) (void)m.integrate(s);
    const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double n = static_cast<double>(point_count(scans));
    char note[200];
    std::snprintf(note, sizeof note, "%sbunny 160 mm, 6 dlr_lsp scans, %.0f points, %.0f %% stored%s", what, n,
                  100.0 * static_cast<double>(m.stats().stored) / n, target);
    nbs::bench::report_headline(name, n / dt, note);
  };
  {
    nbs::NoiseRobustStreamingMesh m;
    bunny_rate(m, "mesh.points_per_s", "NoiseRobustStreamingMesh, ", "; target >= 320000");
  }
  {
    nbs::StreamingMesh m;
    bunny_rate(m, "mesh.points_per_s_thesis", "StreamingMesh (thesis settings), ", "");
  }
  nbs::bench::report_headline("mesh.points_per_s_sphere", sphere_rate,
                              "synthetic 160 mm sphere stream, 640 rays/profile, 0.3 mm profile step");
#else
  nbs::bench::report_headline("mesh.points_per_s", sphere_rate,
                              "no nbs::embree: synthetic 160 mm sphere stream into StreamingMesh (thesis settings), "
                              "640 rays/profile; target >= 320000");
#endif
  const std::size_t big = nbs::bench::quick_mode() ? 250000 : 1000000;
  const double small_t = seconds_per_point(10000);
  const double big_t = seconds_per_point(big);
  nbs::bench::report_headline("mesh.cost_growth_10k_to_1m", big_t / small_t,
                              nbs::bench::quick_mode() ? "quick: 250k-vertex model; target <= 1.5" : "target <= 1.5");
  {
    nbs::StreamingMesh m;
    build_plane(m, big, 1);
    nbs::bench::report_headline("mesh.bytes_per_vertex",
                                static_cast<double>(m.memory_bytes()) / static_cast<double>(m.vertex_count()));
  }
  benchmark::Shutdown();
  return 0;
}
