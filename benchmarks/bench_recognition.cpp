// SPDX-License-Identifier: BSD-3-Clause
// bench_recognition: point-pair-feature recognition (issue 21, Sec. 3.4), nbs against PCL 1.13's PPFRegistration
// when PCL is found (recognition.cmake; recognition_pcl.cpp), else nbs alone.
//
// Model: the bundled bunny normalised to 0.16 m (up = y), 20000 area-uniform samples (seed 1), PpfModel with the
// defaults (τ_d = 0.05, d_angle = 2π/30). Clusters: partial views as the tests build them — 20000 samples of the mesh
// (seed 1000 + k), back faces culled against a random view direction (n · v > 0.1; no self-occlusion), moved by a
// random pose, 0.5 mm Gaussian position noise and ~2° normal noise; views k = 1..12 (quick: 1..4).
// Timed: match_ppf(model, cluster) with the default PpfMatchSetting (subsampling of the cluster, kd-tree, voting,
// pose clustering), best of 3 (quick: 1) per view, then the median over the views.
// Headline: recognition.ppf_match_ms_per_cluster (ms, median). Also printed: the model build time and the top
// hypothesis's translation and rotation error per view (no ICP refinement).
// PCL (headline recognition.ppf_vs_pcl = median over the views of PCL time ÷ nbs time, both timed alternately, best
// of 3): the model is nbs's subsampled model points (PpfModel::points(), all ordered pairs through PPFEstimation into
// PPFHashMapSearch(d_angle, d_dist) with nbs's d_dist and d_angle); the scene is the cluster subsampled on the same
// d_dist grid (grid_subsample, outside PCL's timed call; nbs subsamples inside its call), every 5th point a
// reference point, pose clustering at 0.1 · nbs's model diameter and d_angle. What differs, by PCL's design: PCL
// pairs a reference point with the scene points within half its model diameter (largest pair distance; nbs: the
// full bounding-box diagonal), takes one accumulator peak per reference point (nbs: 3), and returns the best
// cluster only. Quick mode times PCL on the first 2 views only. Recall: the share of views whose
// top hypothesis lies within 10 mm and 10° of the truth.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <numbers>
#include <random>
#include <vector>

#include "headline.hpp"
#include "nbs/core/detail/random.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/recognition/ppf_match.hpp"
#include "nbs/sim/surface_samples.hpp"
#include "recognition_incumbents.hpp"

namespace {

using nbs::bench::median;

struct View {
  nbs::OrientedPoints cluster;
  nbs::Pose truth;
};

View partial_view(const nbs::IndexedMesh& m, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  // One draw per statement (the order of draws within one expression is unspecified), in the order gcc 12 drew
  // the former one-expression form, so that a seed gives the views the reported figures were measured on.
  const auto gauss3 = [&] {
    const double z = g(rng), y = g(rng), x = g(rng);
    return nbs::Vec3(x, y, z);
  };
  const nbs::Vec3 view = gauss3().normalized();
  const nbs::Vec3 axis = gauss3().normalized();
  const double angle = std::numbers::pi * nbs::detail::uniform01(rng);
  const double tz = nbs::detail::uniform01(rng), ty = nbs::detail::uniform01(rng), tx = nbs::detail::uniform01(rng);
  View out;
  out.truth = Eigen::Translation3d(0.5 * nbs::Vec3(tx, ty, tz)) * Eigen::AngleAxisd(angle, axis);
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
  const int reps = quick ? 1 : 3;
  std::unique_ptr<nbs::bench::RecognitionIncumbent> pcl;
#ifdef NBS_BENCH_HAVE_PCL
  {
    pcl = nbs::bench::make_pcl_ppf();
    const nbs::PpfMatchSetting defaults;
    nbs::bench::PpfParameters pp;
    pp.distance_step_m = model.quantizer().distance_step_m;
    pp.angle_step_rad = model.quantizer().angle_step_rad;
    pp.reference_step = static_cast<unsigned>(defaults.reference_step);
    pp.cluster_translation_m = defaults.cluster_translation_ratio * model.diameter_m();
    pp.cluster_rotation_rad = defaults.cluster_rotation_rad;
    const double pcl_build_s =
        nbs::bench::seconds([&] { pcl->set_model(model.points().points, model.points().normals, pp); });
    std::printf("pcl model: %zu points, %zu ordered pairs, built in %.1f ms\n", model.points().size(),
                model.points().size() * model.points().size(), 1e3 * pcl_build_s);
  }
#endif
  // Top hypothesis within 10 mm and 10° of the truth.
  const auto correct = [](const nbs::Pose& pose, const nbs::Pose& truth, double& et, double& er) {
    et = (pose.translation() - truth.translation()).norm();
    er = nbs::rotation_angle_between(pose.linear(), truth.linear());
    return et <= 0.01 && er <= 10.0 * std::numbers::pi / 180.0;
  };
  std::vector<double> ms, pcl_ms, ratio;
  int nbs_ok = 0, pcl_ok = 0;
  constexpr int kQuickPclViews = 2;  // quick mode: PCL on views 1..2 only
  for (int k = 1; k <= views; ++k) {
    const View v = partial_view(mesh, static_cast<std::uint64_t>(k));
    std::vector<nbs::PoseHypothesis> h;
    std::vector<std::function<void()>> fns{[&] { h = nbs::match_ppf(model, v.cluster); }};
    Eigen::Matrix4d pcl_pose = Eigen::Matrix4d::Identity();
    const bool with_pcl = pcl && (!quick || k <= kQuickPclViews);
    if (with_pcl) {
      const nbs::OrientedPoints s = nbs::grid_subsample(v.cluster, model.quantizer().distance_step_m);
      pcl->set_scene(s.points, s.normals);
      fns.emplace_back([&] { pcl_pose = pcl->match(); });
    }
    const std::vector<double> t = nbs::bench::best_times(reps, fns);
    ms.push_back(1e3 * t[0]);
    double et = INFINITY, er = INFINITY;
    if (!h.empty() && correct(h[0].pose, v.truth, et, er)) ++nbs_ok;
    std::printf("view %2d: %5zu cluster points, nbs %.1f ms, top score %.0f, error %.2f mm %.2f deg", k,
                v.cluster.size(), 1e3 * t[0], h.empty() ? 0.0 : h[0].score, 1e3 * et, er * 180 / std::numbers::pi);
    if (with_pcl) {
      pcl_ms.push_back(1e3 * t[1]);
      ratio.push_back(t[1] / t[0]);
      if (correct(nbs::Pose(pcl_pose), v.truth, et, er)) ++pcl_ok;
      std::printf("; pcl %.1f ms, error %.2f mm %.2f deg", 1e3 * t[1], 1e3 * et, er * 180 / std::numbers::pi);
    }
    std::printf("\n");
  }
  std::printf("recall (top hypothesis within 10 mm and 10 deg): nbs %d/%d", nbs_ok, views);
  if (pcl) std::printf(", pcl %d/%zu; median pcl %.1f ms", pcl_ok, pcl_ms.size(), median(pcl_ms));
  std::printf("\n");
  nbs::bench::report_headline("recognition.ppf_match_ms_per_cluster", median(ms), "bunny partial views, 1 thread");
  if (pcl) {
    char note[160];
    std::snprintf(note, sizeof note, "target >= 3; recall nbs %d/%d, pcl %d/%zu (10 mm, 10 deg)", nbs_ok, views,
                  pcl_ok, pcl_ms.size());
    nbs::bench::report_headline("recognition.ppf_vs_pcl", median(ratio), note);
  }
  return 0;
}
