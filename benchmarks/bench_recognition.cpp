// SPDX-License-Identifier: BSD-3-Clause
// bench_recognition: point-pair-feature recognition (issue 21, Sec. 3.4), nbs alone (no incumbent yet: PCL's
// PPFRegistration is the planned comparison, recognition.ppf_vs_pcl).
//
// Model: the bundled bunny normalised to 0.16 m (up = y), 20000 area-uniform samples (seed 1), PpfModel with the
// defaults (τ_d = 0.05, d_angle = 2π/30). Clusters: partial views as the tests build them — 20000 samples of the mesh
// (seed 1000 + k), back faces culled against a random view direction (n · v > 0.1; no self-occlusion), moved by a
// random pose, 0.5 mm Gaussian position noise and ~2° normal noise; views k = 1..12 (quick: 1..4).
// Timed: match_ppf(model, cluster) with the default PpfMatchSetting (subsampling of the cluster, kd-tree, voting,
// pose clustering), best of 3 (quick: 1) per view, then the median over the views.
// Headline: recognition.ppf_match_ms_per_cluster (ms, median). Also printed: the model build time and the top
// hypothesis's translation and rotation error per view (no ICP refinement).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "headline.hpp"
#include "nbs/core/detail/random.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/recognition/ppf_match.hpp"
#include "nbs/sim/surface_samples.hpp"

namespace {

struct View {
  nbs::OrientedPoints cluster;
  nbs::Pose truth;
};

View partial_view(const nbs::IndexedMesh& m, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  const auto gauss3 = [&] { return nbs::Vec3(g(rng), g(rng), g(rng)); };
  const nbs::Vec3 view = gauss3().normalized();
  View out;
  out.truth = Eigen::Translation3d(0.5 * nbs::Vec3(nbs::detail::uniform01(rng), nbs::detail::uniform01(rng),
                                                   nbs::detail::uniform01(rng))) *
              Eigen::AngleAxisd(std::numbers::pi * nbs::detail::uniform01(rng), gauss3().normalized());
  const nbs::SurfaceSamples s = nbs::sample_surface(m, 20000, seed + 1000);
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s.normals[i].dot(view) <= 0.1) continue;
    out.cluster.points.push_back(out.truth * s.points[i] + 0.0005 * gauss3());
    out.cluster.normals.push_back((out.truth.linear() * s.normals[i] + 0.02 * gauss3()).normalized());
  }
  return out;
}

nbs::IndexedMesh bunny() {
  nbs::IndexedMesh m = nbs::load_mesh(NBS_DATA_DIR "/meshes/stanford-bunny.obj");
  nbs::normalize_on_pedestal(m, 0.16, nbs::UpAxis::y);
  return m;
}

void BM_PpfMatch(benchmark::State& state) {
  static const nbs::IndexedMesh mesh = bunny();
  static const nbs::PpfModel model(nbs::oriented_points(nbs::sample_surface(mesh, 20000, 1)));
  static const View view = partial_view(mesh, 1);
  for (auto _ : state) benchmark::DoNotOptimize(nbs::match_ppf(model, view.cluster));
}
BENCHMARK(BM_PpfMatch)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  const bool quick = nbs::bench::quick_mode();
  const nbs::IndexedMesh mesh = bunny();
  const nbs::OrientedPoints samples = nbs::oriented_points(nbs::sample_surface(mesh, 20000, 1));
  std::vector<nbs::PpfModel> built;
  const double build_s = nbs::bench::seconds([&] { built.emplace_back(samples); });
  const nbs::PpfModel& model = built.front();
  std::printf("model: %zu points, %zu pairs, %zu keys, diameter %.1f mm, built in %.1f ms\n", model.points().size(),
              model.pair_count(), model.key_count(), 1e3 * model.diameter_m(), 1e3 * build_s);
  const int views = quick ? 4 : 12;
  std::vector<double> ms;
  for (int k = 1; k <= views; ++k) {
    const View v = partial_view(mesh, static_cast<std::uint64_t>(k));
    std::vector<nbs::PoseHypothesis> h;
    const double t = nbs::bench::best_times(quick ? 1 : 3, {[&] { h = nbs::match_ppf(model, v.cluster); }})[0];
    ms.push_back(1e3 * t);
    const double et = h.empty() ? INFINITY : (h[0].pose.translation() - v.truth.translation()).norm();
    const double er = h.empty() ? INFINITY : nbs::rotation_angle_between(h[0].pose.linear(), v.truth.linear());
    std::printf("view %2d: %5zu cluster points, %.1f ms, top score %.0f, error %.2f mm %.2f deg\n", k,
                v.cluster.size(), 1e3 * t, h.empty() ? 0.0 : h[0].score, 1e3 * et, er * 180 / std::numbers::pi);
  }
  std::sort(ms.begin(), ms.end());
  const double median = ms.size() % 2 ? ms[ms.size() / 2] : 0.5 * (ms[ms.size() / 2 - 1] + ms[ms.size() / 2]);
  nbs::bench::report_headline("recognition.ppf_match_ms_per_cluster", median, "bunny partial views, 1 thread");
  return 0;
}
