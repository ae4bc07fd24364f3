// SPDX-License-Identifier: BSD-3-Clause
// The closed loop on the bundled Stanford bunny (160 mm on the pedestal) with the Embree scanner: thread-count
// determinism and the acceptance target ĉ_m ≥ 0.8 within n_abort = 30 scans (method C_H, Tab. 4.3); the
// default planner's stop against the truth on the test objects (issue 18).
// Set NBS_PLANNER_VERBOSE=1 to print one line per scan.

#include "nbs_catch.hpp"

#include <cstdio>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "nbs/planner/nbs_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/sensor/presets.hpp"
#include "nbs/sim/ground_truth.hpp"
#include "nbs/sim/metrics.hpp"
#include "nbs/sim/test_objects.hpp"
#include "support/same_plan.hpp"
#include "nbs_sanitizer.hpp"

namespace {

struct Bunny {
  nbs::IndexedMesh mesh;
  nbs::Aabb box;  // bounding box of the unknown area: object box + 1 cm sideways and on top, bottom at z = 0
  Bunny() : mesh(nbs::load_mesh(NBS_DATA_DIR "/meshes/stanford-bunny.obj")) {
    nbs::normalize_on_pedestal(mesh, 0.16, nbs::UpAxis::y);
    box = mesh.bounds();
    box.min -= nbs::Vec3(0.01, 0.01, 0.0);
    box.max += nbs::Vec3(0.01, 0.01, 0.01);
  }
};

const Bunny& bunny() {
  static const Bunny b;
  return b;
}

void print(const nbs::ScanRecord& r) {
  if (std::getenv("NBS_PLANNER_VERBOSE") == nullptr) return;
  std::printf("scan %2d  %s  c_m %.3f  d_m %.3f  points %6zu  cand %3zu (+%zu, rot %zu, drop %zu)  t_nbs %.3f s  l_s %.2f m\n",
              r.scan, std::string(nbs::to_string(r.integration.mode)).c_str(), r.integration.estimated_coverage,
              r.integration.mean_density, r.points, r.planning.evaluated, r.planning.generated, r.planning.replanned,
              r.planning.dropped, r.planning.t_nbs_s, r.total_path_length_m);
  std::fflush(stdout);
}

}  // namespace

TEST_CASE("bunny loop: same seed gives the same scan sequence with 1 and 2 threads", "[planner][bunny]") {
  const nbs::embree::SimulatedScanner scanner(bunny().mesh);
  nbs::SimulationSetting sim;
  sim.seed = 5;
  sim.max_scans = 4;
  nbs::PlannerSetting s1, s2;
  s1.threads = 1;
  s2.threads = 2;
  nbs::NbsPlanner<> p1({}, nbs::presets::dlr_lsp(), bunny().box, s1);
  nbs::NbsPlanner<> p2({}, nbs::presets::dlr_lsp(), bunny().box, s2);
  const auto a = nbs::run_simulation(p1, scanner, sim);
  const auto b = nbs::run_simulation(p2, scanner, sim);
  REQUIRE(a.records.size() == 4);
  nbs::test::check_same_plan(a, b);
}

// The acceptance target of issue 5, C_H as the default was then (ThesisPlanner: noise-robust mesh, unseen_open ĉ_m). Release (2 threads):
// seed 1 stops at ĉ_m 0.806 after 8 scans; the thesis's mesh and ĉ_m (ThesisMeshPlanner, second case):
// 0.818 after 14. Under ASan + UBSan the loops run six scans only (time), which checks memory safety, not the target.
constexpr bool kSanitized = nbs_test::kAddressSanitizer;
namespace {
/// The C_H loop on the bunny with Planner (2 threads, seed 1): Release reaches ĉ_m ≥ 0.8 within n_abort scans;
/// under the sanitizers six scans run and raise ĉ_m.
template <class Planner>
void bunny_loop() {
  const nbs::embree::SimulatedScanner scanner(bunny().mesh);
  nbs::PlannerSetting setting;
  setting.threads = 2;
  nbs::Parameters params;  // Tab. 4.3
  Planner planner(params, nbs::presets::dlr_lsp(), bunny().box, setting);
  nbs::SimulationSetting sim;
  sim.seed = 1;
  sim.max_scans = kSanitized ? 6 : params.max_scans;
  const auto res = nbs::run_simulation(planner, scanner, sim, print);
  REQUIRE(!res.records.empty());
  double best = 0.0;
  for (const auto& r : res.records) best = std::max(best, r.integration.estimated_coverage);
  INFO("scans " << res.records.size() << ", final c_m " << res.records.back().integration.estimated_coverage
                << ", d_m " << res.records.back().integration.mean_density << ", stop " << int(res.stop));
  if constexpr (kSanitized) {
    CHECK(res.records.size() == 6);
    CHECK(best > res.records.front().integration.estimated_coverage);
  } else {
    // The stop rule must fire before n_abort (measured: 8 and 14 scans); running into the cap fails.
    CHECK(res.stop == nbs::LoopStop::done);
    CHECK(res.records.size() < static_cast<std::size_t>(params.max_scans));
    CHECK(best >= 0.8);
  }
}
}  // namespace

TEST_CASE(kSanitized ? "bunny loop (sanitizers): six C_H scans run and raise the estimated coverage"
                     : "bunny loop: C_H reaches estimated coverage 0.8 within 30 scans",
          "[planner][bunny][slow]") {
  bunny_loop<nbs::ThesisPlanner<>>();
}

TEST_CASE(kSanitized ? "bunny loop, thesis mesh (sanitizers): six C_H scans run and raise the estimated coverage"
                     : "bunny loop, thesis mesh and c_m: C_H reaches estimated coverage 0.8 within 30 scans",
          "[planner][bunny][slow]") {
  bunny_loop<nbs::ThesisMeshPlanner<>>();
}

// Ground-truth band (issue 17): after a short C_H loop (8 scans, 2 threads) the model is checked against the true
// bunny, not only against the planner's own estimate ĉ_m. Metrics as in nbs_eval (Sec. 4.7.2, Tab. 5.2): c_a = share
// of the non-bottom truth samples within r = 3 mm of a model vertex, relative to the observability ceiling c_obs
// (LSP range, any incidence: the scanner's rule); ē = RMS distance of the model vertices to the true surface, metres.
namespace {
struct TruthMetrics {
  double c_a = 0.0;      // achieved completeness vs the truth, [0, 1]
  double c_obs = 0.0;    // observability ceiling, [0, 1]
  double e_bar_m = 0.0;  // RMS model-to-truth distance, metres (0 for an empty model)
  double c_m = 0.0;      // the planner's estimate ĉ_m
  std::size_t vertices = 0;
  [[nodiscard]] double relative() const { return c_obs > 0.0 ? c_a / c_obs : 0.0; }
};

// Bands; see the test case for the measurements behind them.
constexpr double kBandRelCoverage = 0.95;    // c_a / c_obs after ≤ 8 scans, at least
constexpr double kBandRmsErrorM = 1.5e-3;    // ē, at most
constexpr double kBandEstimateGap = 0.25;    // |ĉ_m − c_a / c_obs|, at most

bool in_band(const TruthMetrics& m) {
  return m.vertices > 0 && m.relative() >= kBandRelCoverage && m.e_bar_m <= kBandRmsErrorM &&
         std::abs(m.c_m - m.relative()) <= kBandEstimateGap;
}

// The truth with samples at 2·10⁵ /m² (≈ 2.2 mm spacing, below r = 3 mm) and c_obs from 200 directions per sample:
// coarser than nbs_eval's instrument, to keep the test fast.
struct Truth {
  nbs::GroundTruth truth;
  double c_obs;
  explicit Truth(const nbs::embree::SimulatedScanner& scanner)
      : truth(bunny().mesh, [] {
          nbs::GroundTruth::Setting s;
          s.sample_density_per_m2 = 2.0e5;
          return s;
        }()) {
    // The scanner's rule, as nbs_eval; 200 directions (coarse).
    const auto os = nbs::embree::SimulatedScanner::observability_settings(nbs::presets::dlr_lsp(), 200);
    c_obs = truth.observability(scanner.scene(), os).c_obs();
  }
  [[nodiscard]] TruthMetrics measure(const std::vector<nbs::Vec3>& vertices, double c_m) const {
    TruthMetrics m;
    m.c_obs = c_obs;
    m.c_m = c_m;
    m.vertices = vertices.size();
    m.c_a = truth.completeness(vertices).c_a();
    m.e_bar_m = vertices.empty() ? 0.0 : truth.rms_error(vertices);
    return m;
  }
};
}  // namespace

// Measured (Release, 2 threads, this instrument): seed 1 stops after 8 scans with c_a/c_obs 0.967 (c_a 0.915,
// c_obs 0.947), ē 0.81 mm, ĉ_m 0.806; seed 2 after 7 with 0.972, 0.95 mm, ĉ_m 0.822. Bands: c_a/c_obs ≥
// 0.95, ē ≤ 1.5 mm (r/2; a mesh that integrates noise or misplaced points exceeds it), |ĉ_m − c_a/c_obs| ≤ 0.25 (ĉ_m
// is conservative by 0.16–0.17 here). An empty model fails (c_a = 0); a planner picking random candidates
// (RandomUtility, hidden case below) reaches only 0.905 / 0.890 (seeds 1 / 2) and fails.
namespace {
template <class Planner>
void truth_band(bool expect_in_band) {
  const nbs::embree::SimulatedScanner scanner(bunny().mesh);
  const Truth truth(scanner);
  const std::uint64_t seed = GENERATE(1, 2);
  nbs::PlannerSetting setting;
  setting.threads = 2;
  Planner planner({}, nbs::presets::dlr_lsp(), bunny().box, setting);
  nbs::SimulationSetting sim;
  sim.seed = seed;
  sim.max_scans = kSanitized ? 3 : 8;
  const auto res = nbs::run_simulation(planner, scanner, sim, print);
  REQUIRE(!res.records.empty());
  std::vector<nbs::Vec3> vertices;
  for (std::size_t v = 0; v < planner.mesh().vertex_count(); ++v)
    vertices.push_back(planner.mesh().position(static_cast<nbs::VertexId>(v)));
  const TruthMetrics m = truth.measure(vertices, res.records.back().integration.estimated_coverage);
  INFO("seed " << seed << ", scans " << res.records.size() << ", vertices " << m.vertices << ", c_a " << m.c_a
               << ", c_obs " << m.c_obs << ", c_a/c_obs " << m.relative() << ", e_bar " << 1e3 * m.e_bar_m
               << " mm, c_m " << m.c_m);
  if (std::getenv("NBS_PLANNER_VERBOSE") != nullptr)
    std::printf("truth band: seed %d scans %zu vertices %zu c_a %.4f c_obs %.4f rel %.4f e_bar %.4f mm c_m %.4f\n",
                int(seed), res.records.size(), m.vertices, m.c_a, m.c_obs, m.relative(), 1e3 * m.e_bar_m, m.c_m);
  // An empty model must fail the band.
  CHECK_FALSE(in_band(truth.measure({}, 0.0)));
  if constexpr (!kSanitized) CHECK(in_band(m) == expect_in_band);
}
}  // namespace

TEST_CASE("bunny loop: after 8 C_H scans the model is within the ground-truth band", "[planner][bunny][slow]") {
  truth_band<nbs::ThesisPlanner<>>(true);
}

// The band's discrimination: the same loop picking random candidates must miss it (hidden; run by name).
TEST_CASE("bunny loop: random candidate picks miss the ground-truth band", "[.][planner][bunny][sabotage]") {
  truth_band<nbs::ThesisPlanner<nbs::RandomUtility>>(false);
}

namespace {

/// The seed of the test-object loops (the first one tried, the same for every object).
constexpr std::uint64_t kObjectSeed = 1;

/// What the default planner is held to on one test object (issue 18, item 1): c_a ≥ `band` c_obs at the stop and
/// n_s ≤ k99 + `late`. The criterion is band 0.95 (ours), late 2; an object listed with a looser bound is a
/// known miss, measured and written down in docs/evaluation.md ("The default planner"), kept from getting worse.
struct Expected {
  nbs::TestObject object;
  double band;
  int late;
};

/// Issue 18: the default planner's stop against the truth on a purpose-built test object (sim/test_objects.hpp).
/// Checks the stop (done before n_abort: never runs on once the truth is complete), the band at the stop and
/// n_s ≤ k99 + late (k99: first scan with c_a ≥ 0.99 c_obs). Coarse truth (0.5 samples/mm², 300 directions) to stay
/// fast. Under the sanitizers (time) only four scans run and the stop is not judged.
void object_loop(const Expected& want) {
  nbs::IndexedMesh mesh = nbs::make_test_object(want.object);
  nbs::normalize_on_pedestal(mesh, 0.16, nbs::UpAxis::z);
  nbs::Aabb box = mesh.bounds();
  box.min -= nbs::Vec3(0.01, 0.01, 0.0);
  box.max += nbs::Vec3(0.01, 0.01, 0.01);
  const nbs::embree::SimulatedScanner scanner(mesh);
  nbs::GroundTruth::Setting gts;
  gts.sample_density_per_m2 = 0.5e6;
  const nbs::GroundTruth truth(mesh, gts);
  // The scanner's rule, as nbs_eval; 300 directions (coarse).
  const auto os = nbs::embree::SimulatedScanner::observability_settings(nbs::presets::dlr_lsp(), 300, 2);
  const double c_obs = truth.observability(scanner.scene(), os).c_obs();
  REQUIRE(c_obs > 0.8);  // coarse truth: the car 0.85 (under its body), the others ≥ 0.95
  nbs::PlannerSetting setting;
  setting.threads = 2;
  nbs::NbsPlanner<> planner({}, nbs::presets::dlr_lsp(), box, setting);
  nbs::SimulationSetting sim;
  sim.seed = kObjectSeed;
  const int n_abort = nbs::Parameters{}.max_scans;
  sim.max_scans = kSanitized ? 4 : n_abort;
  nbs::CoverageTracker tracker = truth.tracker();
  std::vector<double> share;  // c_a / c_obs after each scan
  const auto res = nbs::run_simulation(planner, scanner, sim, [&](const nbs::ScanRecord& r) {
    print(r);
    std::vector<nbs::Vec3> v;
    const auto& m = planner.mesh();
    for (std::size_t i = 0; i < m.vertex_count(); ++i)
      if (m.has_normal(static_cast<nbs::VertexId>(i))) v.push_back(m.position(static_cast<nbs::VertexId>(i)));
    tracker.add(v);
    share.push_back(tracker.completeness().c_a() / c_obs);
  });
  const auto n_s = static_cast<int>(res.records.size());
  int k99 = n_abort + 1;  // as nbs_eval: n_abort + 1 when never reached
  for (int k = n_s; k >= 1; --k)
    if (share[static_cast<std::size_t>(k - 1)] >= 0.99) k99 = k;
  const std::string name(nbs::test_object_name(want.object));
  INFO(name << ": c_obs " << c_obs << ", n_s " << n_s << ", k99 " << k99 << ", c_a/c_obs at the stop "
            << share.back() << ", c_m " << res.records.back().integration.estimated_coverage);
  if (std::getenv("NBS_PLANNER_VERBOSE") != nullptr)
    std::printf("%s: c_obs %.4f n_s %d k99 %d c_a/c_obs %.4f\n", name.c_str(), c_obs, n_s, k99, share.back());
  if constexpr (kSanitized) {
    CHECK(share.back() > share.front());  // the model grows
  } else {
    CHECK(res.stop == nbs::LoopStop::done);
    CHECK(n_s < n_abort);
    CHECK(share.back() >= want.band);
    CHECK(n_s <= k99 + want.late);  // k99 within the run when the stop is late: the stop is judged exactly
  }
}

}  // namespace

TEST_CASE("test objects: the default planner stops near k99 with c_a in the band (issue 18)", "[planner][slow]") {
  // Seed 1 (the first tried), Release, 2 threads; the criterion on three, two known misses. Measured
  // (n_s, k99, c_a/c_obs at the stop): table 12, 11, 0.997; car 13, never, 0.918; mug 10, 7, 1.003; mushroom 9,
  // never, 0.962; plate 6, 5, 1.000. On another machine (AMD EPYC, 2026-12-07), where the same seed's runs part
  // from those after 2–3 scans (not traced; Embree picks its code path by CPU): table 12, never, 0.990; car 13,
  // never, 0.915; the others as above.
  const Expected objects[] = {
      {nbs::TestObject::table, 0.95, 2},
      {nbs::TestObject::car, 0.90, 2},  // miss: stops early at 0.92 c_obs (the surface under the body is seen late)
      {nbs::TestObject::mug, 0.95, 3},  // miss: stops 3 scans after k99
      {nbs::TestObject::mushroom, 0.95, 2},
      {nbs::TestObject::plate, 0.95, 2},
  };
  if constexpr (kSanitized) {
    object_loop(objects[2]);  // memory safety on one object
  } else {
    for (const Expected& e : objects) object_loop(e);
  }
}
