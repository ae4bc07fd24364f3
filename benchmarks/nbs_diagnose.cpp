// SPDX-License-Identifier: BSD-3-Clause
// nbs_diagnose: how good are the planner's choices? Runs the closed simulation loop of a planner (default the
// thesis's C_H, as in docs/evaluation.md's diagnoses; --selection, --search) on a mesh and, at every planning step,
// executes EVERY candidate in the simulated scanner and measures its
// true gain: the number of not-yet-covered ground-truth samples (non-bottom) within r (3 mm) of the candidate's
// measured points. Prints per step: candidates, utility of the chosen one, its true gain, the best true gain, the
// rank of the chosen one by true gain, and the Spearman correlation between utility and true gain; then the source of
// the chosen candidate (BS: Boundary Search, HR: Hole Rescan) and its utility, and for the Hole Rescan candidates in S
// their number, best utility, best true gain and mean path length next to the Boundary Search candidates' mean length.
// With --oracle the planner picks the candidate of largest true gain (an upper bound for the selection given the
// generated candidates). A research tool, not part of the headline benchmarks.
//
// usage: nbs_diagnose [--mesh PATH] [--up x|y|z] [--size M] [--seed N] [--method CODE] [--sensor NAME] [--scans N]
//                     [--search S|B|H] [--selection R|I|Q|C|OA|UV|RSV|RSE|PC|AE|VG|SG|SGU] [--oracle] [--sampling P,R]
//                     [--threads N] [--hmax N] [--thesis-mesh] [--config FILE]   (`--help`; options shared with the
// other tools: tools/common/options.hpp; a bad value prints the option and the value and exits 2)
// The planner's defaults: noise-robust mesh, unknown_open ĉ_m. --thesis-mesh uses the thesis's mesh and ĉ_m
// (RuntimeModels::thesis).
// Environment: NBS_DIAG_FEATURES=1 prints per step the number of voxels with surface features and their mean b_i, d̄_i
// and 1 − q_i (Eqs. 4.26, 4.28, 4.33), the share with b_i > 0; NBS_DIAG_DUMP=PREFIX
// writes PREFIX_<step>.csv (utility, true gain, rays, voxels, path ends, view direction, length and source of every
// candidate; NBS_DIAG_ALT=CODE,CODE adds the utilities of those selections for the same candidates as columns, GU:
// SGU's unseen-surface gain g_u alone, GU<mm>: from the samples at least mm from their loop's edge);
// NBS_DIAG_UNSEEN=PREFIX writes PREFIX_<scan>.csv: where ĉ_m puts the missing surface (UtilityContext::unseen_surface,
// SGU's input; benchmarks/unseen_locator.py compares it with NBS_DIAG_UNCOVERED's dump);
// NBS_DIAG_COVERAGE=1 skips the true gains and prints per scan the terms of ĉ_m (Eqs. 4.35–4.37) next to the truth
// (see print_coverage_terms); with it, NBS_DIAG_LOOPS=K also prints the K loops of largest unseen area and where the
// triangle area lies by face tilt (see print_loops).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "nbs/candidates/hole_rescan.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/planner/nbs_planner.hpp"
#include "nbs/planner/runtime_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"
#include "nbs/sensor/presets.hpp"
#include "nbs/core/detail/parallel_for.hpp"
#include "nbs/sim/detail/point_kd_tree.hpp"
#include "nbs/sim/ground_truth.hpp"

#include "common/data_dir.hpp"
#include "common/options.hpp"

namespace {

struct Options {
  std::string mesh = nbs::tools::bundled_data("meshes/stanford-bunny.obj");
  nbs::UpAxis up = nbs::tools::kDefaultUp;
  double size_m = 0.16;
  std::uint64_t seed = 1;
  int scans = 12;
  nbs::Method method = nbs::kThesisMethod;  // --method, or --selection and --search one by one (default C_H)
  std::string sensor = "dlr_lsp";
  bool oracle = false;
  bool thesis_mesh = false;  // the thesis's mesh and ĉ_m instead of the planner's defaults
  nbs::RaySampling sampling{4, 4};
  unsigned threads = 2;
  int hole_max_edges = 0;  // 0: Parameters default
};

/// What the diagnostic utility shares with the loop: ground truth, scanner, current coverage, the last step's log.
struct Shared {
  const nbs::embree::SimulatedScanner* scanner = nullptr;
  const nbs::SurfaceSamples* samples = nullptr;
  nbs::detail::PointKdTree sample_tree;
  std::vector<char> covered;  // per sample
  double radius_m = 0.003;
  bool oracle = false;
  nbs::Selection selection = nbs::Selection::ig_quality;
  unsigned threads = 2;
  // log of the last evaluation
  std::vector<double> utility, gain;
  std::size_t chosen = 0;
  std::function<std::vector<nbs::CandidateSource>()> sources;  // of S, in evaluation order
  std::vector<nbs::CandidateSource> last_sources;
  std::vector<double> lengths;

  /// New non-bottom samples within r of the points of a scan along `path`.
  [[nodiscard]] double true_gain(const nbs::LinearScanPath& path, const nbs::LaserStripeProfiler& lsp) const {
    const nbs::Scan s = scanner->scan(path, lsp, 12345);
    std::vector<char> fresh(covered.size(), 0);
    std::size_t n = 0;
    for (const nbs::Vec3& p : s.points)
      sample_tree.for_each_within(p, radius_m, [&](std::size_t i, double) {
        if (!covered[i] && !fresh[i] && !samples->bottom[i]) {
          fresh[i] = 1;
          ++n;
        }
      });
    return static_cast<double>(n);
  }
};

Shared* g_shared = nullptr;

/// The C selection (IG/Quality) plus the true gain of every candidate; with `oracle`, the true gain decides.
struct DiagnosticUtility {
  struct Setting {};
  Setting setting{};
  template <class Space, nbs::CandidateRaySensor Sensor>
  [[nodiscard]] nbs::EvaluationResult evaluate(std::span<const nbs::LinearScanPath> paths, const Sensor& sensor,
                                               const Space& space, const nbs::UtilityContext& ctx,
                                               const nbs::EvaluationSetting& eval) const {
    Shared& sh = *g_shared;
    nbs::SelectionUtility u;
    u.setting.selection = sh.selection;
    nbs::EvaluationResult r = u.evaluate(paths, sensor, space, ctx, eval);
    if (std::getenv("NBS_DIAG_COVERAGE")) return r;  // coverage terms only: no true gains
    sh.utility = r.values;
    if (sh.sources) sh.last_sources = sh.sources();
    sh.gain.assign(paths.size(), 0.0);
    sh.lengths.clear();
    for (const auto& p : paths) sh.lengths.push_back(p.length());
    nbs::detail::parallel_for(paths.size(), sh.threads, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) sh.gain[i] = sh.true_gain(paths[i], sensor);
    });
    if (std::getenv("NBS_DIAG_FEATURES")) {  // surface features the quality term (Eq. 4.33) can see
      double b = 0.0, d = 0.0, rescan = 0.0, border_voxels = 0.0;
      const nbs::SurfaceFeatureMap none;
      const nbs::SurfaceFeatureMap& features = eval.features ? *eval.features : none;
      features.for_each([&](const auto&, const nbs::SurfaceFeatures& f) {
        b += f.border_share;
        d += f.mean_density;
        border_voxels += f.border_share > 0.0f ? 1.0 : 0.0;
        rescan += 1.0 - nbs::voxel_quality(f.border_share, f.mean_density, ctx.params->quality_weight);
      });
      const double n = std::max<double>(1.0, static_cast<double>(features.size()));
      std::printf("features in space %zu: mean b_i %.3f, mean d_i %.3f, share with b_i > 0 %.3f, mean 1 - q_i %.3f\n",
                  features.size(), b / n, d / n, border_voxels / n, rescan / n);
    }
    if (sh.oracle) {
      r.values = sh.gain;
      r.best = nbs::best_index(r.values);
    }
    sh.chosen = r.best;
    if (const char* dump = std::getenv("NBS_DIAG_DUMP")) {
      static int step = 0;
      ++step;
      const std::string name = std::string(dump) + "_" + std::to_string(step) + ".csv";
      if (std::FILE* f = std::fopen(name.c_str(), "w")) {
        // NBS_DIAG_ALT="RSE,PC,Q": the utilities of other selections for the same candidates, as extra columns.
        std::vector<std::string> alt_names;
        std::vector<std::vector<double>> alt;
        if (const char* codes = std::getenv("NBS_DIAG_ALT")) {
          std::string list = codes;
          for (std::size_t p = 0; p <= list.size();) {
            const std::size_t q = std::min(list.find(',', p), list.size());
            if (q > p && list.compare(p, 2, "GU") == 0) {  // GU[mm]: g_u alone (voxel faces), samples at least mm
              const std::string mm = list.substr(p + 2, q - p - 2);   // from their loop's edge (all if no number)
              char* end = nullptr;
              const double d_mm = mm.empty() ? 0.0 : std::strtod(mm.c_str(), &end);
              if (!mm.empty() && (end != mm.c_str() + mm.size() || !(d_mm >= 0.0)))
                throw nbs::InvalidArgument("NBS_DIAG_ALT: bad edge distance in '" + list.substr(p, q - p) +
                                           "' (GU or GU<mm>, mm >= 0)");
              const nbs::UnseenSurfaceMap map = nbs::UnseenSurfaceMap::build(ctx.unseen_surface, space.grid(), 1e-3 * d_mm);
              alt_names.push_back(list.substr(p, q - p));
              alt.push_back(nbs::evaluate_candidates(paths, sensor, space, nbs::UnseenSurfaceVI(&map), eval).values);
            } else if (q > p) {
              nbs::SelectionUtility v;
              v.setting.selection = nbs::parse_selection(list.substr(p, q - p));
              alt_names.push_back(list.substr(p, q - p));
              alt.push_back(v.evaluate(paths, sensor, space, ctx, eval).values);
            }
            p = q + 1;
          }
        }
        std::fprintf(f, "i,utility,gain,rays,voxels,x0,y0,z0,x1,y1,z1,vx,vy,vz,len,source");
        for (const auto& n : alt_names) std::fprintf(f, ",%s", n.c_str());
        std::fprintf(f, "\n");
        for (std::size_t i = 0; i < paths.size(); ++i) {
          const nbs::Vec3 a = paths[i].start().position(), b = paths[i].end_position();
          const nbs::Vec3 v = paths[i].start().pose().linear().col(2);
          std::fprintf(f, "%zu,%g,%g,%llu,%llu,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.3f,%.3f,%.3f", i, sh.utility[i],
                       sh.gain[i], (unsigned long long)r.rays[i], (unsigned long long)r.voxels[i], a.x(), a.y(), a.z(),
                       b.x(), b.y(), b.z(), v.x(), v.y(), v.z());
          const bool hole = i < sh.last_sources.size() && sh.last_sources[i] == nbs::CandidateSource::hole_rescan;
          std::fprintf(f, ",%.4f,%s", sh.lengths[i], hole ? "HR" : "BS");
          for (const auto& a : alt) std::fprintf(f, ",%g", a[i]);
          std::fprintf(f, "\n");
        }
        std::fclose(f);
      }
    }
    return r;
  }
};

std::vector<double> ranks(const std::vector<double>& v) {
  std::vector<std::size_t> idx(v.size());
  std::iota(idx.begin(), idx.end(), 0);
  std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return v[a] < v[b]; });
  std::vector<double> r(v.size());
  for (std::size_t i = 0; i < idx.size();) {
    std::size_t j = i;
    while (j + 1 < idx.size() && v[idx[j + 1]] == v[idx[i]]) ++j;
    for (std::size_t k = i; k <= j; ++k) r[idx[k]] = 0.5 * double(i + j);
    i = j + 1;
  }
  return r;
}

double spearman(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() < 3) return 0.0;
  const std::vector<double> ra = ranks(a), rb = ranks(b);
  const double n = double(a.size()), m = (n - 1) / 2;
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (ra[i] - m) * (rb[i] - m);
    saa += (ra[i] - m) * (ra[i] - m);
    sbb += (rb[i] - m) * (rb[i] - m);
  }
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : 0.0;
}

/// One line per scan: the terms of the estimated coverage ĉ_m = A_filled / (A_filled + A_empty) (Eqs. 4.35–4.37)
/// next to the truth. `true` is the covered true area c_a · A (non-bottom); `filled` is Eq. 4.36 and `proj` the same
/// with each triangle projected on its mean vertex normal (insensitive to noise across the surface); then the border
/// loops with ≤ h_max edges (the holes of ĉ_m) and with more, each as count, Eq. 4.37 area and the part of them that
/// Hole Rescan's probe calls measured (surface seen in the voxel space at the loop centre: a triangulation gap).
/// Voxel probability below which print_loops calls a fan sample "free" (observed empty; the prior is 0.5).
constexpr double kFreeBelow = 0.45;

/// NBS_DIAG_LOOPS=K: the K loops of largest unseen area (A_hole · (1 − fan_seen_share)), each with its edge count,
/// area, seen share, the states of its fan samples in the voxel space (occupied / free / unknown) and, from the
/// truth, the mean distance of the samples to the true surface, the share of samples whose nearest true sample is a
/// non-bottom one not yet covered (really missing surface) and the share whose nearest is a bottom sample.
template <class Planner>
void print_loops(const Planner& planner, const nbs::Parameters& params, const std::vector<nbs::Hole>& loops, int top) {
  using namespace nbs;
  const auto& mesh = planner.mesh();
  const auto& space = planner.space();
  // the unseen share as the planner's ĉ_m form counts it per sample (without unknown_open's per-loop free-seam rule)
  const auto seen = planner.coverage.seen(space, params, planner.unknown_area());
  std::vector<std::pair<double, std::size_t>> order;
  double total = 0.0;
  for (std::size_t i = 0; i < loops.size(); ++i) {
    const double u = loops[i].area_m2 * (1.0 - fan_seen_share(mesh, loops[i], seen));
    total += u;
    order.emplace_back(u, i);
  }
  std::sort(order.rbegin(), order.rend());
  std::printf("LOOPS %zu, unseen area %.6f m2\n", loops.size(), total);
  // Where A_filled's excess lies: triangle area by the angle between the face normal and its mean vertex normal.
  double by_angle[4] = {0, 0, 0, 0};
  mesh.for_each_face([&](const MeshFace& f) {
    const Vec3 a = mesh.position(f.a);
    const Vec3 c = (mesh.position(f.b) - a).cross(mesh.position(f.c) - a);
    const Vec3 n = (mesh.normal(f.a) + mesh.normal(f.b) + mesh.normal(f.c)).normalized();
    const double deg = std::acos(std::clamp(std::abs(c.normalized().dot(n)), 0.0, 1.0)) * 180.0 / M_PI;
    by_angle[deg < 15 ? 0 : deg < 30 ? 1 : deg < 60 ? 2 : 3] += 0.5 * c.norm();
  });
  std::printf("FACES area by face-vs-vertex-normal angle: <15 %.5f, 15-30 %.5f, 30-60 %.5f, >=60 %.5f m2\n",
              by_angle[0], by_angle[1], by_angle[2], by_angle[3]);
  // The same after moving every meshed vertex onto the weighted-PCA plane of ALL stored points within R_n now (an
  // offline test of whether the zig-zag comes from projecting onto the first, sparse plane).
  {
    const std::size_t nv = mesh.vertex_count();
    std::vector<Vec3> stored(nv);
    for (std::size_t v = 0; v < nv; ++v) stored[v] = mesh.stored_position(static_cast<VertexId>(v));
    const detail::PointKdTree tree(stored);
    const double rn = params.normal_radius_m, inv = 1.0 / (rn * rn);
    std::vector<Vec3> moved(nv), normal(nv);
    std::vector<Vec3> pts;
    std::vector<double> wts;
    for (std::size_t v = 0; v < nv; ++v) {
      moved[v] = mesh.position(static_cast<VertexId>(v));
      if (!mesh.has_normal(static_cast<VertexId>(v))) continue;
      normal[v] = mesh.normal(static_cast<VertexId>(v));
      Vec3 mean = Vec3::Zero();
      double wsum = 0.0;
      Mat3 cov = Mat3::Zero();
      pts.clear();
      wts.clear();
      tree.for_each_within(stored[v], rn, [&](std::size_t q, double d2) {
        pts.push_back(stored[q]);
        wts.push_back(detail::pca_weight(d2, inv));
      });
      for (std::size_t i = 0; i < pts.size(); ++i) mean += wts[i] * pts[i], wsum += wts[i];
      mean /= wsum;
      for (std::size_t i = 0; i < pts.size(); ++i) cov += wts[i] * (pts[i] - mean) * (pts[i] - mean).transpose();
      const Eigen::SelfAdjointEigenSolver<Mat3> es(cov);
      Vec3 n = es.eigenvectors().col(0);
      if (n.dot(normal[v]) < 0) n = -n;
      normal[v] = n;
      moved[v] = stored[v] - (stored[v] - mean).dot(n) * n;
    }
    double again[4] = {0, 0, 0, 0}, total_area = 0.0;
    mesh.for_each_face([&](const MeshFace& f) {
      const Vec3 c = (moved[f.b] - moved[f.a]).cross(moved[f.c] - moved[f.a]);
      const Vec3 n = (normal[f.a] + normal[f.b] + normal[f.c]).normalized();
      const double deg = std::acos(std::clamp(std::abs(c.normalized().dot(n)), 0.0, 1.0)) * 180.0 / M_PI;
      again[deg < 15 ? 0 : deg < 30 ? 1 : deg < 60 ? 2 : 3] += 0.5 * c.norm();
      total_area += 0.5 * c.norm();
    });
    std::printf("FACES re-projected on all stored points in R_n: total %.5f m2; <15 %.5f, 15-30 %.5f, 30-60 %.5f, >=60 %.5f\n",
                total_area, again[0], again[1], again[2], again[3]);
  }
  for (int j = 0; j < top && j < static_cast<int>(order.size()); ++j) {
    const Hole& h = loops[order[j].second];
    const std::size_t k = h.vertices.size();
    int occ = 0, fr = 0, unk = 0, missing = 0, bottom = 0;
    double dsum = 0.0, zmin = 1e9, zmax = -1e9;
    for (const VertexId v : h.vertices) {
      zmin = std::min(zmin, mesh.position(v).z());
      zmax = std::max(zmax, mesh.position(v).z());
    }
    for_each_fan_sample(mesh, h, [&](const Vec3& x) {
      const double p = space.probability(x);
      (p > params.occupied_threshold ? occ : p < kFreeBelow ? fr : unk)++;
      const auto [idx, d2] = g_shared->sample_tree.nearest(x);
      dsum += std::sqrt(d2);
      if (g_shared->samples->bottom[idx]) ++bottom;  // on the pedestal: no scan can cover it
      else missing += g_shared->covered[idx] ? 0 : 1;
    });
    const double n = 3.0 * static_cast<double>(k);
    std::printf("  loop %4zu edges area %.6f unseen %.6f | occ %.2f free %.2f unk %.2f | truth: dist %.2f mm missing %.2f"
                " bottom %.2f | z %.3f..%.3f c (%.3f %.3f %.3f) n (%.2f %.2f %.2f)\n",
                k, h.area_m2, order[j].first, occ / n, fr / n, unk / n, 1e3 * dsum / n, missing / n, bottom / n, zmin,
                zmax, h.center.x(),
                h.center.y(), h.center.z(), h.normal.x(), h.normal.y(), h.normal.z());
  }
}

template <class Planner>
void print_coverage_terms(const Planner& planner, const nbs::Parameters& params, int scan, double c_a,
                          double true_area_m2) {
  using namespace nbs;
  const auto& mesh = planner.mesh();
  double proj = 0.0;
  mesh.for_each_face([&](const MeshFace& f) {
    const Vec3 n = (mesh.normal(f.a) + mesh.normal(f.b) + mesh.normal(f.c)).normalized();
    const Vec3 a = mesh.position(f.a);
    proj += 0.5 * std::abs((mesh.position(f.b) - a).cross(mesh.position(f.c) - a).dot(n));
  });
  struct Loops {
    std::size_t n = 0, n_measured = 0;
    double area = 0.0, area_measured = 0.0;
  } small, large;
  const HoleRescan probe;
  const std::vector<Hole> loops = find_all_loops(mesh, params);
  for (const Hole& h : loops) {
    Loops& l = static_cast<int>(h.vertices.size()) <= params.hole_max_edges ? small : large;
    const bool measured = probe.measured(planner.space(), h);
    ++l.n;
    l.area += h.area_m2;
    l.n_measured += measured ? 1 : 0;
    l.area_measured += measured ? h.area_m2 : 0.0;
  }
  if (const char* top = std::getenv("NBS_DIAG_LOOPS")) print_loops(planner, params, loops, std::atoi(top));
  std::printf("COV %2d c_m %.3f | true %.5f filled %.5f proj %.5f m2 | loops<=h_max %zu %.5f m2 (measured %zu %.5f) |"
              " loops>h_max %zu %.5f m2 (measured %zu %.5f)\n",
              scan, planner.estimated_coverage(), c_a * true_area_m2, filled_area(mesh), proj, small.n, small.area,
              small.n_measured, small.area_measured, large.n, large.area, large.n_measured, large.area_measured);
}

template <class Search, class Mesh>
int run(const Options& opt) {
  using namespace nbs;
  IndexedMesh mesh = load_mesh(opt.mesh);
  normalize_on_pedestal(mesh, opt.size_m, opt.up);
  Parameters params;
  if (opt.hole_max_edges > 0) params.hole_max_edges = opt.hole_max_edges;
  GroundTruth::Setting gts;
  gts.seed = opt.seed;
  const GroundTruth truth(mesh, gts);
  const embree::SimulatedScanner scanner(mesh);
  Aabb unknown = mesh.bounds();
  unknown.min -= Vec3(0.01, 0.01, 0.0);
  unknown.max += Vec3(0.01, 0.01, 0.01);
  Shared sh;
  sh.scanner = &scanner;
  sh.samples = &truth.samples();
  sh.sample_tree = detail::PointKdTree(truth.samples().points);
  sh.covered.assign(truth.samples().size(), 0);
  sh.radius_m = params.completeness_radius_m;
  sh.oracle = opt.oracle;
  sh.selection = opt.method.selection;
  sh.threads = opt.threads;
  g_shared = &sh;
  PlannerSetting ps;
  ps.threads = opt.threads;
  ps.seed = opt.seed;
  ps.sampling = opt.sampling;
  const RuntimeModels models = opt.thesis_mesh ? RuntimeModels::thesis() : RuntimeModels{};
  NbsPlanner<DiagnosticUtility, Search, LaserStripeProfiler, NoCollisions, MaxScansReached, ProbabilisticVoxelSpace<>,
             Mesh, SelectableCoverage>
      planner(params, presets::lsp_by_name(opt.sensor), unknown, ps, models.mesh_settings(params, unknown));
  planner.coverage.setting.form = models.coverage_estimate;
  // NBS_DIAG_FORM=NAME: the ĉ_m form by name (kCoverageEstimateNames), e.g. observable_open.
  if (const char* form = std::getenv("NBS_DIAG_FORM")) {
    const auto it = std::ranges::find(kCoverageEstimateNames, std::string_view(form));
    if (it == std::end(kCoverageEstimateNames)) throw InvalidArgument(std::string("NBS_DIAG_FORM: unknown form ") + form);
    planner.coverage.setting.form = static_cast<CoverageEstimate>(it - std::begin(kCoverageEstimateNames));
  }
  planner.termination = MaxScansReached(opt.scans);
  sh.sources = [&planner] {
    std::vector<CandidateSource> out;
    for (const ScanCandidate& c : planner.candidate_set()) out.push_back(c.source);
    return out;
  };
  CoverageTracker cov = truth.tracker();
  std::printf("scan mode  c_m^    c_a %%  points  cand  chosen_gain  best_gain  rank  spearman\n");
  SimulationSetting sim;
  sim.seed = opt.seed;
  sim.max_scans = opt.scans;
  double sum_rho = 0.0;
  int steps = 0;
  (void)run_simulation(planner, scanner, sim, [&](const ScanRecord& r) {
    std::vector<Vec3> v;
    const StreamingMesh& m = planner.mesh();
    for (std::size_t i = 0; i < m.vertex_count(); ++i)
      if (m.has_normal(static_cast<VertexId>(i))) v.push_back(m.position(static_cast<VertexId>(i)));
    cov.add(v);
    const std::vector<bool>& c = cov.covered();
    for (std::size_t i = 0; i < c.size(); ++i) sh.covered[i] = c[i] ? 1 : 0;
    const char* mode = r.scan == 1 ? "init" : (r.planning.mode == SearchMode::HoleRescan ? "HR" : "BS");
    if (const char* dump = std::getenv("NBS_DIAG_UNCOVERED")) {  // the samples still uncovered and their voxels
      const std::string name = std::string(dump) + "_" + std::to_string(r.scan) + ".csv";
      if (std::FILE* f = std::fopen(name.c_str(), "w")) {
        std::fprintf(f, "x,y,z,nx,ny,nz,p,observed\n");
        const SurfaceSamples& smp = truth.samples();
        for (std::size_t i = 0; i < c.size(); ++i) {
          if (c[i] || smp.bottom[i]) continue;
          const Vec3& x = smp.points[i];
          const auto k = planner.space().grid().key_of(x);
          std::fprintf(f, "%.4f,%.4f,%.4f,%.3f,%.3f,%.3f,%.3f,%d\n", x.x(), x.y(), x.z(), smp.normals[i].x(),
                       smp.normals[i].y(), smp.normals[i].z(), planner.space().probability(x),
                       k ? int(planner.space().observed(*k)) : -1);
        }
        std::fclose(f);
      }
    }
    if (const char* dump = std::getenv("NBS_DIAG_UNSEEN")) {  // where ĉ_m puts the missing surface (SGU's input)
      const std::string name = std::string(dump) + "_" + std::to_string(r.scan) + ".csv";
      if (std::FILE* f = std::fopen(name.c_str(), "w")) {
        std::fprintf(f, "x,y,z,area,d\n");
        for (const nbs::UnseenSample& u : planner.utility_context().unseen_surface)
          std::fprintf(f, "%.4f,%.4f,%.4f,%.4g,%.4f\n", u.position.x(), u.position.y(), u.position.z(), u.area_m2,
                       u.edge_distance_m);
        std::fclose(f);
      }
    }
    if (std::getenv("NBS_DIAG_COVERAGE")) {
      const auto& bottom = truth.samples().bottom;
      const auto n = static_cast<double>(std::count(bottom.begin(), bottom.end(), false));
      print_coverage_terms(planner, params, r.scan, cov.completeness().c_a(), n / gts.sample_density_per_m2);
    }
    if (r.scan == 1 || sh.gain.empty()) {
      std::printf("%4d %-4s %6.3f %7.2f %7zu\n", r.scan, mode, r.integration.estimated_coverage,
                  100 * cov.completeness().c_a(), r.points);
      return;
    }
    const double best = *std::max_element(sh.gain.begin(), sh.gain.end());
    const double got = sh.gain[sh.chosen];
    const auto rank = std::count_if(sh.gain.begin(), sh.gain.end(), [&](double g) { return g > got; });
    const double rho = spearman(sh.utility, sh.gain);
    sum_rho += rho;
    ++steps;
    std::size_t holes = 0;
    double hole_u = 0.0, hole_g = 0.0, hole_len = 0.0, bs_len = 0.0;
    std::size_t bs = 0;
    for (std::size_t i = 0; i < sh.last_sources.size() && i < sh.gain.size(); ++i) {
      if (sh.last_sources[i] == CandidateSource::hole_rescan) {
        ++holes;
        hole_u = std::max(hole_u, sh.utility[i]);
        hole_g = std::max(hole_g, sh.gain[i]);
        hole_len += sh.lengths[i];
      } else {
        ++bs;
        bs_len += sh.lengths[i];
      }
    }
    std::printf("%4d %-4s %6.3f %7.2f %7zu %5zu %12.0f %10.0f %5ld %9.3f  chosen %s u %.3g | holes %zu best_u %.3g best_gain %.0f "
                "mean_len %.3f | bs mean_len %.3f\n",
                r.scan, mode, r.integration.estimated_coverage, 100 * cov.completeness().c_a(), r.points,
                sh.gain.size(), got, best, static_cast<long>(rank), rho,
                r.candidate && r.candidate->source == CandidateSource::hole_rescan ? "HR" : "BS",
                sh.utility[sh.chosen], holes, hole_u, hole_g, holes ? hole_len / holes : 0.0, bs ? bs_len / bs : 0.0);
    sh.gain.clear();
  });
  std::printf("final c_a %.2f %%, mean spearman %.3f\n", 100 * cov.completeness().c_a(), steps ? sum_rho / steps : 0.0);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  namespace tools = nbs::tools;
  Options opt;
  CLI::App app("nbs_diagnose: the true gain of every candidate next to its utility, step by step", "nbs_diagnose");
  tools::set_conventions(app);
  tools::add_object_options(app, opt);
  tools::add_run_options(app, opt);
  app.get_option("--threads")->description("threads (default 2)");
  app.add_option_function<std::string>(
         "--search",
         [&opt](const std::string& v) {
           if (v == "S") opt.method.search = nbs::SearchSpace::sphere;
           else if (v == "B") opt.method.search = nbs::SearchSpace::boundary;
           else if (v == "H") opt.method.search = nbs::SearchSpace::boundary_hole;
           else throw tools::UsageError("--search", "expects S, B or H, got '" + v + "'");
         },
         "search space alone (any selection): S, B or H")
      ->type_name("S|B|H");
  app.add_option_function<std::string>(
         "--selection",
         [&opt](const std::string& v) {
           try {
             opt.method.selection = nbs::parse_selection(v);
           } catch (const nbs::InvalidArgument& e) {
             throw tools::UsageError("--selection", e.what());
           }
         },
         "selection criterion alone (any search space): R I Q C OA UV RSV RSE PC AE VG SG SGU")
      ->type_name("CODE");
  app.add_flag("--oracle", opt.oracle, "pick the candidate of largest true gain");
  app.add_option_function<std::string>(
         "--sampling",
         [&opt](const std::string& v) {
           const auto comma = v.find(',');
           std::string p = v.substr(0, comma), r = comma == std::string::npos ? "" : v.substr(comma + 1);
           if (comma == std::string::npos || !tools::integer_in(1, 1u << 20)(p).empty() ||
               !tools::integer_in(1, 1u << 20)(r).empty())
             throw tools::UsageError("--sampling", "expects P,R (profile and ray strides, integers >= 1), got '" + v + "'");
           opt.sampling = {std::stoul(p), std::stoul(r)};
         },
         "utility evaluation strides: every P-th profile, every R-th ray (default 4,4)")
      ->type_name("P,R");
  app.add_option("--hmax", opt.hole_max_edges, "Parameters::hole_max_edges (default: Parameters')")
      ->check(tools::integer_in(1, 1000000));
  tools::add_config(app);
  if (const auto code = tools::parse(app, argc, argv)) return *code;
  try {
    if (opt.method.search == nbs::SearchSpace::sphere) return run<nbs::SphereSpace, nbs::StreamingMesh>(opt);
    if (opt.method.search == nbs::SearchSpace::boundary) return run<nbs::BoundarySpace, nbs::StreamingMesh>(opt);
    return run<nbs::BoundaryHoleSpace, nbs::StreamingMesh>(opt);
  } catch (const nbs::Error& e) {  // the mesh file or its normalisation
    std::fprintf(stderr, "nbs_diagnose: %s\n", e.what());
    return tools::kUsageExit;
  }
}
