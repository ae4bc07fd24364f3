// SPDX-License-Identifier: BSD-3-Clause
// bench_planner: NBS planning time of the composed planner (issue 5). The default planner NbsPlanner<> (SGU_H:
// surface gain + unseen surface, Boundary Search + Hole Rescan, the settled stop rule), bunny normalised to 160 mm on the pedestal, Tab. 4.3 parameters, DLR LSP, 2 threads, seed 1.
// Headlines: planner.t_nbs_median_s (median over the planning steps of one closed loop; target ≤ 0.05 s, thesis
// Tab. 4.5: 1.37 s) and planner.t_nbs_per_candidate_ms (median of t_nbs / candidates scored), with the default
// PlannerSetting (noise-robust mesh, unseen_open ĉ_m); planner.t_nbs_median_s_thesis_mesh: the same loop with the
// thesis's method C_H, mesh, ĉ_m and stop rule (nbs::ThesisMeshPlanner). planner.t_integrate_median_s(_thesis_mesh): median time of
// NbsPlanner::integrate per scan in the same loops and planner.t_coverage_median_s(_thesis_mesh) its ĉ_m part
// (reported, no target).
// Google Benchmark case: one planning step after the first scan (planner rebuilt outside the timing).
// NBS_BENCH_STEPS=1 prints each step's breakdown (generate / replan / evaluate seconds, candidate counts, c_m, the
// chosen candidate's utility u), each scan's integrate() split and the largest c_m of the run; NBS_BENCH_SEED=N
// replaces the simulation seed 1 (which initial scan is taken);
// NBS_BENCH_REFINE=F,K replaces the coarse-to-fine setting of the closed loop (PlannerSetting::refine; 1,K = off).
// NBS_BENCH_REFINE_STUDY=1: after each scan, scores the remaining set S once with every ray of the planner's sampling
// and with several coarse-to-fine settings, and prints whether each picks the same candidate and the full-sampling
// value of its pick relative to the best (the choice quality of CoarseToFine).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "headline.hpp"
#include "nbs/planner/nbs_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/sensor/presets.hpp"

namespace {

using nbs::bench::median;

struct Fixture {
  nbs::IndexedMesh mesh;
  nbs::Aabb box;
  Fixture() : mesh(nbs::load_mesh(NBS_DATA_DIR "/meshes/stanford-bunny.obj")) {
    nbs::normalize_on_pedestal(mesh, 0.16, nbs::UpAxis::y);
    box = mesh.bounds();
    box.min -= nbs::Vec3(0.01, 0.01, 0.0);
    box.max += nbs::Vec3(0.01, 0.01, 0.01);
  }
};
const Fixture& fixture() {
  static const Fixture f;
  return f;
}
nbs::PlannerSetting two_threads() {
  nbs::PlannerSetting s;
  s.threads = 2;
  return s;
}

void BM_first_planning_step(benchmark::State& state) {
  const nbs::embree::SimulatedScanner scanner(fixture().mesh);
  for (auto _ : state) {
    state.PauseTiming();
    nbs::NbsPlanner<> planner({}, nbs::presets::dlr_lsp(), fixture().box, two_threads());
    (void)planner.integrate(scanner.scan(planner.first_scan(1), planner.sensor(), 1));
    state.ResumeTiming();
    benchmark::DoNotOptimize(planner.next_best_scan());
  }
}
BENCHMARK(BM_first_planning_step)->Unit(benchmark::kMillisecond)->Iterations(3);

/// One closed loop of the default planner with `ps` (seed 1 unless NBS_BENCH_SEED); medians of t_nbs and of
/// t_nbs per candidate over its planning steps. `verbose`: NBS_BENCH_STEPS / NBS_BENCH_REFINE_STUDY output.
struct LoopTimes {
  double t_nbs_median_s = 0.0, per_candidate_ms = 0.0;
  double t_integrate_median_s = 0.0;  ///< NbsPlanner::integrate (space, mesh, features, ĉ_m), median over the scans
  double t_coverage_median_s = 0.0;   ///< of it: loops, ĉ_m and d̄_m (IntegrationReport::t_coverage_s)
  int scans = 0;
  double best_coverage = 0.0;
};
template <class Planner>
LoopTimes closed_loop(const nbs::embree::SimulatedScanner& scanner, const nbs::PlannerSetting& ps, bool verbose) {
  Planner planner({}, nbs::presets::dlr_lsp(), fixture().box, ps);
  nbs::SimulationSetting sim;
  sim.seed = 1;
  if (const char* seed = std::getenv("NBS_BENCH_SEED")) sim.seed = std::strtoull(seed, nullptr, 10);
  sim.max_scans = nbs::bench::quick_mode() ? 8 : 30;
  std::vector<double> t_nbs, per_candidate_ms, t_integrate, t_coverage;
  const bool steps = verbose && std::getenv("NBS_BENCH_STEPS") != nullptr;
  double best_coverage = 0.0;
  int scans = 0;
  const bool study = verbose && std::getenv("NBS_BENCH_REFINE_STUDY") != nullptr;
  const std::vector<nbs::CoarseToFine> settings{{2, 8}, {2, 16}, {4, 8}, {4, 16}, {4, 32}, {8, 16}, {8, 32}};
  std::vector<int> same(settings.size(), 0);
  std::vector<double> worst(settings.size(), 1.0);
  int studied = 0;
  (void)nbs::run_simulation(planner, scanner, sim, [&](const nbs::ScanRecord& r) {
    if (study && planner.candidate_set().size() > 1) {
      std::vector<nbs::LinearScanPath> paths;
      for (const nbs::ScanCandidate& c : planner.candidate_set()) paths.push_back(c.path);
      nbs::UtilityContext uctx = planner.utility_context();
      uctx.seed = 1;
      const auto score = [&](const nbs::CoarseToFine& c) {
        nbs::EvaluationSetting es = planner.evaluation_setting();
        es.refine = c;
        return planner.utility.evaluate(paths, planner.sensor(), planner.space(), uctx, es);
      };
      const nbs::EvaluationResult full = score({1, 1});
      std::printf("study scan %2d: %3zu candidates, full %.4fs", r.scan, paths.size(), full.t_nbs_s);
      for (std::size_t k = 0; k < settings.size(); ++k) {
        const nbs::EvaluationResult c = score(settings[k]);
        const double rel = full.values[c.best] / full.values[full.best];
        same[k] += c.best == full.best;
        worst[k] = std::min(worst[k], rel);
        std::printf("  %zu,%zu: %s %.3f %.4fs", settings[k].coarse_factor, settings[k].refine_top,
                    c.best == full.best ? "=" : "x", rel, c.t_nbs_s);
      }
      std::printf("\n");
      ++studied;
    }
    best_coverage = std::max(best_coverage, r.integration.estimated_coverage);
    t_integrate.push_back(r.integration.t_integrate_s);
    t_coverage.push_back(r.integration.t_coverage_s);
    if (steps)
      std::printf("scan %2d integrate %.4f s: space %.4f mesh %.4f features %.4f coverage %.4f\n", r.scan,
                  r.integration.t_integrate_s, r.integration.t_space_s, r.integration.t_mesh_s,
                  r.integration.t_features_s, r.integration.t_coverage_s);
    scans = r.scan;
    if (r.scan == 1 || r.planning.evaluated == 0) return;
    const nbs::IterationStats& p = r.planning;
    if (steps)
      std::printf("step %2d %s gen %3zu drop %3zu eval %3zu  t_gen %.4f t_replan %.4f t_eval %.4f t_nbs %.4f  c_m %.4f u %.17g\n",
                  r.scan, nbs::to_string(p.mode).data(), p.generated, p.dropped, p.evaluated, p.t_generate_s,
                  p.t_replan_s, p.t_evaluate_s, p.t_nbs_s, p.estimated_coverage, p.best_utility);
    t_nbs.push_back(r.planning.t_nbs_s);
    per_candidate_ms.push_back(1e3 * r.planning.t_nbs_s / static_cast<double>(r.planning.evaluated));
  });
  for (std::size_t k = 0; study && k < settings.size(); ++k)
    std::printf("study %zu,%zu: same pick %d / %d, worst relative value %.3f\n", settings[k].coarse_factor,
                settings[k].refine_top, same[k], studied, worst[k]);
  if (steps) std::printf("seed %llu: %d scans, largest c_m %.4f\n", static_cast<unsigned long long>(sim.seed), scans, best_coverage);
  return {median(t_nbs), median(per_candidate_ms), median(t_integrate), median(t_coverage), scans, best_coverage};
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  const nbs::embree::SimulatedScanner scanner(fixture().mesh);
  nbs::PlannerSetting ps = two_threads();
  if (const char* refine = std::getenv("NBS_BENCH_REFINE")) {
    char* end = nullptr;
    ps.refine.coarse_factor = std::strtoull(refine, &end, 10);
    ps.refine.refine_top = *end == ',' ? std::strtoull(end + 1, nullptr, 10) : 0;  // 0: rejected by validate()
  }
  const LoopTimes def = closed_loop<nbs::NbsPlanner<>>(scanner, ps, true);
  // The thesis's mesh and ĉ_m (StreamingMesh, ThesisCoverage), same loop.
  const LoopTimes th = closed_loop<nbs::ThesisMeshPlanner<>>(scanner, ps, false);
  char note[160];
  std::snprintf(note, sizeof note, "default (SGU_H), bunny 160 mm, Tab. 4.3, 2 threads, %d scans; target <= 0.05 s", def.scans);
  nbs::bench::report_headline("planner.t_nbs_median_s", def.t_nbs_median_s, note);
  nbs::bench::report_headline("planner.t_nbs_per_candidate_ms", def.per_candidate_ms, "report");
  nbs::bench::report_headline("planner.t_integrate_median_s", def.t_integrate_median_s,
                              "report: integrate() per scan (space, mesh, features, c_m with unseen_open)");
  nbs::bench::report_headline("planner.t_coverage_median_s", def.t_coverage_median_s,
                              "report: of it loops, c_m (unseen_open: enclosure rays) and mean density");
  std::snprintf(note, sizeof note, "C_H with the thesis's mesh, c_m and stop, %d scans (largest c_m %.3f)", th.scans,
                th.best_coverage);
  nbs::bench::report_headline("planner.t_nbs_median_s_thesis_mesh", th.t_nbs_median_s, note);
  nbs::bench::report_headline("planner.t_integrate_median_s_thesis_mesh", th.t_integrate_median_s,
                              "report: the same with the thesis's mesh and c_m");
  nbs::bench::report_headline("planner.t_coverage_median_s_thesis_mesh", th.t_coverage_median_s,
                              "report: of it holes, c_m (thesis) and mean density");
  return 0;
}
