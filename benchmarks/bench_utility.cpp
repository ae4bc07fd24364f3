// SPDX-License-Identifier: BSD-3-Clause
// Candidate evaluation (Sec. 4.5.3) on a realistic planning state: the bundled bunny (0.16 m on its pedestal)
// scanned along 4 of the 13 initial scan paths (top, +x, +y, vertical edge (−x, −y)) (DLR LSP preset, Embree scanner), integrated into
// ProbabilisticVoxelSpace<> (thesis model) at 5 mm with the unknown area = object box grown by 2 cm, mesh and
// surface features from StreamingMesh; candidates = the 81 sphere-search paths (0.3 m radius, 0.3 m long) or every
// 4th of them (20 paths); term = f_utility (WeightedUtility, ω(n_s = 3)).
// Headlines:
//   utility.eval_ns_per_voxel_visit   — 1 thread, default planner sampling: wall time ÷ voxel visits
//   utility.eval_ms_per_candidate     — 1 thread, default planner sampling (kPlannerRaySampling)
//   utility.eval_ms_per_candidate_full — 1 thread, every ray (RaySampling{1, 1})
//   utility.eval_2thread_scaling      — 1-thread time ÷ 2-thread time, 20 candidates, default sampling
//   utility.eval_vs_bare_raycast      — evaluation time ÷ a plain loop of space.cast_ray with a counting visitor
//                                        over the same (pre-generated) rays: the overhead of the evaluation layer
//   utility.planning_step_s@2threads  — 40 candidates, default sampling, 2 threads (issue 5: ≤ 0.05 s)
//   utility.ranking_*                 — with NBS_BENCH_RANKING=1: agreement of the default sampling's ranking with
//                                        every ray (Kendall τ; full value of the chosen ÷ best), ω ∈ {0, ω(3), 1}
// Each time is the best of N alternating repetitions in this process.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <numeric>
#include <vector>

#include "headline.hpp"
#include "nbs/candidates/sphere_search.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/mesh/streaming_mesh.hpp"
#include "nbs/mesh/surface_features.hpp"
#include "nbs/sensor/presets.hpp"
#include "nbs/sim/initial_scan_paths.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"
#include "nbs/utility/evaluate_candidates.hpp"
#include "nbs/utility/thesis_terms.hpp"

namespace {

using nbs::Vec3;

constexpr nbs::RaySampling kDefault = nbs::kPlannerRaySampling;

struct Fixture {
  nbs::LaserStripeProfiler sensor = nbs::presets::dlr_lsp();
  nbs::Aabb object;
  nbs::Aabb area;
  std::vector<nbs::Scan> scans;
  std::unique_ptr<nbs::ProbabilisticVoxelSpace<>> space;
  nbs::SurfaceFeatureMap features;  // what the planner keeps beside the space
  std::vector<nbs::LinearScanPath> sphere;  // 81
  std::vector<nbs::LinearScanPath> twenty;  // every 4th
  std::vector<nbs::LinearScanPath> forty;   // every 2nd
  double n_v = 1.0;

  Fixture() {
    nbs::IndexedMesh m = nbs::load_mesh(NBS_DATA_DIR "/meshes/stanford-bunny.obj");
    nbs::normalize_on_pedestal(m, 0.16, nbs::UpAxis::y);
    object = m.bounds();
    area.min = object.min - Vec3::Constant(0.02);
    area.max = object.max + Vec3::Constant(0.02);
    const nbs::embree::SimulatedScanner scanner(m);
    const auto paths = nbs::initial_scan_paths(object, 0.3);
    for (int k : {0, 1, 3, 10}) scans.push_back(scanner.scan(paths[static_cast<std::size_t>(k)], sensor, 7 + k));
    space = std::make_unique<nbs::ProbabilisticVoxelSpace<>>(0.005, area, thesis_model());
    nbs::Parameters params;
    nbs::StreamingMesh mesh(params, area);
    for (const auto& s : scans) {
      (void)space->integrate(s);
      (void)mesh.integrate(s);
      (void)nbs::update_surface_features(features, *space, mesh, params);
    }
    n_v = nbs::non_free_voxel_count(*space);
    sphere = nbs::sphere_scan_paths(object.center(), 0.3);
    for (std::size_t i = 0; i < sphere.size(); ++i) {
      if (i % 4 == 0) twenty.push_back(sphere[i]);
      if (i % 2 == 0) forty.push_back(sphere[i]);
    }
    std::printf("utility: %zu observed voxels, %zu feature voxels, N_v %.0f\n", nbs::observed_count(space->backend()),
                features.size(), n_v);
  }

  [[nodiscard]] nbs::ThesisModel thesis_model() const {
    nbs::ThesisModel::Setting st;
    const nbs::RangeNoise noise = sensor.noise;
    st.sigma_m = [noise](double d) { return std::max(noise.sigma_m(d), 1e-5); };
    return nbs::ThesisModel(st);
  }
  [[nodiscard]] nbs::WeightedUtility term(double omega) const {
    nbs::WeightedUtility::Setting s;
    s.non_free_voxels = n_v;
    s.omega = omega;
    return nbs::WeightedUtility(s);
  }
  [[nodiscard]] nbs::WeightedUtility term() const { return term(nbs::modeling_weight(3.0)); }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

nbs::EvaluationResult evaluate(const std::vector<nbs::LinearScanPath>& c, nbs::RaySampling s, unsigned threads,
                               double omega = nbs::modeling_weight(3.0)) {
  const auto& f = fixture();
  nbs::EvaluationSetting setting{threads, s};
  setting.features = &f.features;
  return nbs::evaluate_candidates(c, f.sensor, *f.space, f.term(omega), setting);
}

std::uint64_t sum(const std::vector<std::uint64_t>& v) { return std::accumulate(v.begin(), v.end(), std::uint64_t{0}); }

// Kendall's tau-b between two value vectors.
double kendall_tau(const std::vector<double>& a, const std::vector<double>& b) {
  double conc = 0, disc = 0, ta = 0, tb = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = i + 1; j < a.size(); ++j) {
      const double x = a[i] - a[j], y = b[i] - b[j];
      if (x == 0 && y == 0) continue;
      if (x == 0) { ++ta; continue; }
      if (y == 0) { ++tb; continue; }
      (x * y > 0 ? conc : disc) += 1;
    }
  const double n0 = conc + disc;
  return (conc - disc) / std::sqrt((n0 + ta) * (n0 + tb));
}

// The incumbent of utility.eval_vs_bare_raycast: space.cast_ray with a counting visitor.
[[gnu::noinline]] std::uint64_t bare_cast(const nbs::ProbabilisticVoxelSpace<>& space, const std::vector<nbs::Ray>& rays) {
  std::uint64_t n = 0;
  for (const auto& ray : rays)
    n += space.cast_ray(ray, [](const nbs::VoxelKey&, const nbs::ThesisState&) { return true; }).voxels;
  return n;
}

// ---- Google Benchmark cases ----------------------------------------------------------------------------------------
void BM_Evaluate20(benchmark::State& state) {
  const auto k = static_cast<std::size_t>(state.range(0));
  std::uint64_t visits = 0;
  for (auto _ : state) {
    const auto r = evaluate(fixture().twenty, {k, k}, 1);
    visits = sum(r.voxels);
    benchmark::DoNotOptimize(r.best);
  }
  state.counters["visits"] = double(visits);
  state.counters["ms_per_candidate"] =
      benchmark::Counter(20e-3, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_Evaluate20)->Arg(8)->Arg(4)->Arg(2)->Unit(benchmark::kMillisecond);

// ---- Headlines ----------------------------------------------------------------------------------------------------
void ranking_study() {
  const auto& f = fixture();
  const bool quick = nbs::bench::quick_mode();
  const auto& cands = quick ? f.twenty : f.sphere;
  for (double omega : {0.0, nbs::modeling_weight(3.0), 1.0}) {
    const auto full = evaluate(cands, {1, 1}, 2, omega);
    for (std::size_t k : {2u, 4u, 8u}) {
      const auto sub = evaluate(cands, {k, k}, 2, omega);
      const double tau = kendall_tau(full.values, sub.values);
      const bool top1 = full.best == sub.best;
      const double regret = full.values[sub.best] / full.values[full.best];
      std::printf("utility: ranking omega %.3f stride %zu: Kendall tau %.4f, top-1 %s, full value of chosen / best "
                  "%.4f\n",
                  omega, k, tau, top1 ? "same" : "differs", regret);
      if (k == kDefault.profile_stride && omega == nbs::modeling_weight(3.0)) {
        nbs::bench::report_headline("utility.ranking_kendall_tau", tau, "default sampling vs every ray, omega(3)");
        nbs::bench::report_headline("utility.ranking_chosen_vs_best", regret, "full value of the chosen candidate");
      }
    }
  }
}

void headlines() {
  const auto& f = fixture();
  const int reps = nbs::bench::quick_mode() ? 2 : 5;
  {  // per candidate, 1 thread, default sampling and every ray
    nbs::EvaluationResult r, full;
    const auto t = nbs::bench::best_times(reps, {[&] { r = evaluate(f.twenty, kDefault, 1); }});
    const auto tf = nbs::bench::best_times(1, {[&] { full = evaluate(std::vector<nbs::LinearScanPath>(f.twenty.begin(), f.twenty.begin() + 4), {1, 1}, 1); }});
    const double visits = double(sum(r.voxels));
    std::printf("utility: 20 candidates, sampling {%zu, %zu}: %.1f ms, %llu rays, %.0f visits\n",
                kDefault.profile_stride, kDefault.ray_stride, t[0] * 1e3, (unsigned long long)sum(r.rays), visits);
    nbs::bench::report_headline("utility.eval_ns_per_voxel_visit", t[0] / visits * 1e9, "1 thread");
    nbs::bench::report_headline("utility.eval_ms_per_candidate", t[0] / 20 * 1e3, "1 thread, default sampling");
    nbs::bench::report_headline("utility.eval_ms_per_candidate_full", tf[0] / 4 * 1e3, "1 thread, every ray");
    std::printf("utility: full sampling: %.0f visits per candidate\n", double(sum(full.voxels)) / 4);
  }
  {  // thread scaling
    const auto t = nbs::bench::best_times(reps, {[&] { (void)evaluate(f.twenty, kDefault, 1); },
                                     [&] { (void)evaluate(f.twenty, kDefault, 2); }});
    nbs::bench::report_headline("utility.eval_2thread_scaling", t[0] / t[1], "20 candidates");
  }
  {  // overhead over the bare planning ray cast
    std::vector<nbs::Ray> rays;
    for (const auto& p : f.twenty) nbs::append_candidate_rays(p, f.sensor, kDefault, rays);
    std::uint64_t bare = 0;
    const auto t = nbs::bench::best_times(reps, {[&] { (void)evaluate(f.twenty, kDefault, 1); },
                                     [&] { bare = bare_cast(*f.space, rays); }});
    std::printf("utility: bare cast_ray %.1f ms for %llu visits (%.2f ns per visit)\n", t[1] * 1e3,
                (unsigned long long)bare, t[1] / double(bare) * 1e9);
    nbs::bench::report_headline("utility.eval_vs_bare_raycast", t[0] / t[1], "evaluation time / bare cast_ray loop");
  }
  {  // one planning step
    const auto t = nbs::bench::best_times(reps, {[&] { (void)evaluate(f.forty, kDefault, 2); }});
    nbs::bench::report_headline("utility.planning_step_s@2threads", t[0], "40 candidates, target <= 0.05");
  }
  if (std::getenv("NBS_BENCH_RANKING") != nullptr) ranking_study();
  if (const char* path = std::getenv("NBS_BENCH_DUMP")) {  // values for before/after comparisons (%.17g)
    std::FILE* out = std::fopen(path, "w");
    for (std::size_t k : {1u, 4u}) {
      const auto r = evaluate(f.twenty, {k, k}, 2);
      for (std::size_t i = 0; i < r.values.size(); ++i)
        std::fprintf(out, "%zu %zu %.17g %llu %llu\n", k, i, r.values[i], (unsigned long long)r.rays[i],
                     (unsigned long long)r.voxels[i]);
    }
    std::fclose(out);
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  (void)fixture();
  // For callgrind (--toggle-collect='nbs::evaluate_candidates*'): one evaluation of the 81 sphere candidates as the
  // planner runs it (default sampling, coarse-to-fine {4, 32}, 1 thread), its visits and a hash of the values (FNV-1a
  // over the bits of every value, for before/after comparisons), and one bare loop over the 20 candidates' rays.
  if (std::getenv("NBS_BENCH_PROFILE") != nullptr) {
    const auto& f = fixture();
    nbs::EvaluationSetting setting{1, kDefault, nbs::CoarseToFine{4, 32}};
    setting.features = &f.features;
    const auto r = nbs::evaluate_candidates(f.sphere, f.sensor, *f.space, f.term(), setting);
    std::uint64_t hash = 14695981039346656037ull;
    for (double v : r.values) {
      std::uint64_t bits;
      std::memcpy(&bits, &v, sizeof bits);
      hash = (hash ^ bits) * 1099511628211ull;
    }
    std::vector<nbs::Ray> rays;
    for (const auto& p : f.twenty) nbs::append_candidate_rays(p, f.sensor, kDefault, rays);
    const std::uint64_t bare = bare_cast(*f.space, rays);
    std::printf("utility: profile: %llu visits, best %zu, values hash %016llx, bare %llu\n",
                (unsigned long long)sum(r.voxels), r.best, (unsigned long long)hash, (unsigned long long)bare);
    return 0;
  }
  benchmark::RunSpecifiedBenchmarks();
  headlines();
  benchmark::Shutdown();
  return 0;
}
