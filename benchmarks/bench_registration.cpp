// SPDX-License-Identifier: BSD-3-Clause
// bench_registration: nbs::Icp (the thesis's ICP, Sec. 3.2.3, default IcpSetting: radius 3 mm, normal gate 60°,
// 2 iterations) against Open3D 0.16 and PCL 1.13 point-to-plane ICP on the same scan pairs (issue 20).
//
// Scan pairs from the real pipeline: the bundled bunny normalised to 0.16 m on the pedestal, the Embree scanner with
// the DLR LSP preset (range noise on), a ThesisPlanner<> (C_H, the default before 2026-12-07) that integrates its first kExactScans scans with exact
// poses; then each next planned scan is a pair: it is displaced by a known seeded rigid error E (translation of a
// fixed length in a random direction, rotation of a fixed angle about a random axis through the sensor origin at the
// path start) and registered to the current model by each method, and afterwards integrated exactly (the model
// grows as in a real run). Two error sizes, reported separately: 1 mm / 0.1° (the headline) and 3 mm / 0.5°.
// Several displacement seeds per pair.
//
// Same inputs to all: the model = the planner mesh's vertices that have a normal (positions and those normals), the
// source = the displaced scan's points; identity initial guess; correspondence distance = IcpSetting::radius_m;
// iterations = IcpSetting::iterations. What each timing includes:
//   nbs     Icp::register_scan(scan, planner.mesh()): reads the model from the mesh, builds its kd-tree(s) and
//           estimates the scan's normals inside the call (plus the 60° normal gate and the refusal checks).
//   Open3D  pipelines::registration::RegistrationICP(source, target, radius, I, TransformationEstimationPointToPlane,
//           ICPConvergenceCriteria(0, 0, iterations)): builds its KDTreeFlann over the target inside the call, copies
//           the source, and runs iterations + 1 correspondence searches (the last one only scores the result).
//           Relative-fitness/RMSE criteria 0 = never stops early. OpenMP threads set to 1 (nbs::Icp is
//           single-threaded); the PointCloud objects (data layout) are built outside the timing.
//   PCL     IterativeClosestPointWithNormals<PointNormal, PointNormal> with TransformationEstimationPointToPlaneLLS
//           (target normals), setMaxCorrespondenceDistance(radius), setMaximumIterations(iterations), a new object
//           per call so align() builds the target's kd-tree inside the timing; float points (PCL's own types),
//           built outside the timing. No normal gate in either incumbent (they only use the target's normals).
// Work that differs: nbs alone estimates the scan's normals (PCA in a normal_radius ball, for its 60° normal gate;
// printed as "of it estimate_scan_normals") and gates correspondences; both incumbents use only the model's normals.
// All three agree that 2 iterations leave ~30 % of a 1 mm/0.1° error at the centroid and that the rotation part grows
// (0.10° → 0.15°): a scan patch seen from 0.3 m constrains rotation about the sensor weakly.
// Times: the best of `reps` interleaved repetitions per (pair, seed), then the median over (pair, seed). Quick mode
// (NBS_BENCH_QUICK=1): 8 pairs × 2 seeds, best of 2 (the 3 mm case, whose times are not headlines: 1); else 16 × 4,
// best of 5.
// Residual pose error: R = C·E (C the method's correction); translation |R·c − c| at the exact scan's centroid c
// (mm) and rotation angle of R (deg), mean over (pair, seed). A refused nbs registration counts with C = identity.
//
// Headlines (1 mm / 0.1° case): registration.icp_vs_open3d (Open3D time ÷ nbs time; goal ≥ 2),
// registration.icp_error_vs_open3d (nbs mean residual translation ÷ Open3D's; goal ≤ 1), registration.icp_ms_per_scan
// (nbs median ms per scan), registration.icp_vs_pcl, registration.icp_error_vs_pcl; the 3 mm / 0.5° case's error
// ratios as registration.icp_error_vs_open3d@3mm and registration.icp_error_vs_pcl@3mm. The incumbents are
// benchmark-only and optional (benchmarks/registration.cmake; each in a unit of its own, registration_open3d.cpp and
// registration_pcl.cpp): without one, its figures are left out.
// NBS_BENCH_VERBOSE=1 prints every (pair, seed).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "headline.hpp"
#include "registration_incumbents.hpp"
#include "nbs/core/detail/random.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/planner/nbs_planner.hpp"
#include "nbs/registration/icp.hpp"
#include "nbs/registration/scan_normals.hpp"
#include "nbs/sensor/presets.hpp"

namespace {

using nbs::bench::median;

using nbs::Pose;
using nbs::Vec3;

constexpr int kExactScans = 3;  // scans integrated with exact poses before the first pair

double mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

/// A uniformly distributed unit vector from two draws of splitmix64 (portable: no std distribution).
Vec3 unit_vector(std::uint64_t& state) {
  const auto u01 = [&state] {
    state = nbs::detail::splitmix64(state);
    return static_cast<double>(state >> 11) * 0x1.0p-53;
  };
  const double z = 2.0 * u01() - 1.0, phi = 2.0 * std::numbers::pi * u01();
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

/// The seeded rigid pose error: rotation by `angle_rad` about a random axis through `origin`, then a translation of
/// `shift_m` in a random direction.
Pose pose_error(const Vec3& origin, double shift_m, double angle_rad, std::uint64_t seed) {
  std::uint64_t state = seed;
  const Vec3 axis = unit_vector(state), dir = unit_vector(state);
  Pose e = Pose::Identity();
  e.linear() = Eigen::AngleAxisd(angle_rad, axis).toRotationMatrix();
  e.translation() = origin - e.linear() * origin + shift_m * dir;
  return e;
}

struct Residual {
  double translation_mm = 0.0, rotation_deg = 0.0;
};
/// R = C·E: translation |R·c − c| at the centroid c (mm) and R's rotation angle (deg).
Residual residual(const Pose& correction, const Pose& error, const Vec3& centroid) {
  const Pose r = correction * error;
  return {1e3 * (r * centroid - centroid).norm(), Eigen::AngleAxisd(r.linear()).angle() * 180.0 / std::numbers::pi};
}

struct Case {
  const char* name;
  double shift_m, angle_deg;
};
constexpr Case kCases[2] = {{"1mm/0.1deg", 0.001, 0.1}, {"3mm/0.5deg", 0.003, 0.5}};

/// One method's results per error case: best-of-reps ms and residuals per (pair, seed).
struct Results {
  std::string name;
  std::vector<double> ms[2], t_mm[2], r_deg[2];
  int refused[2] = {0, 0};
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);  // accepts bench.sh's --benchmark_min_time; the figures are measured below
  const bool quick = nbs::bench::quick_mode();
  const bool verbose = std::getenv("NBS_BENCH_VERBOSE") != nullptr;
  const int pairs = quick ? 8 : 16, seeds = quick ? 2 : 4, reps = quick ? 2 : 5;

  nbs::IndexedMesh object = nbs::load_mesh(NBS_DATA_DIR "/meshes/stanford-bunny.obj");
  nbs::normalize_on_pedestal(object, 0.16, nbs::UpAxis::y);
  nbs::Aabb box = object.bounds();
  box.min -= Vec3(0.01, 0.01, 0.0);
  box.max += Vec3(0.01, 0.01, 0.01);
  const nbs::embree::SimulatedScanner scanner(object);
  nbs::PlannerSetting ps;
  ps.threads = 2;  // planning only (outside every timing)
  nbs::ThesisPlanner<> planner({}, nbs::presets::dlr_lsp(), box, ps);  // the scan pairs the figures were made on
  // Keep planning past the quality criterion (the bunny reaches it after a few scans), as benchmarks/eval does.
  std::get<nbs::CoverageAndDensityReached>(planner.termination.criteria).coverage =
      std::numeric_limits<double>::infinity();
  const nbs::Icp icp{};  // default IcpSetting
  const double radius = icp.setting.radius_m;
  const int iterations = icp.setting.iterations;

  std::vector<std::unique_ptr<nbs::bench::RegistrationIncumbent>> incumbents;
#if defined(NBS_BENCH_HAVE_OPEN3D)
  incumbents.push_back(nbs::bench::make_open3d_icp());
#endif
#if defined(NBS_BENCH_HAVE_PCL)
  incumbents.push_back(nbs::bench::make_pcl_icp());
#endif
  std::vector<Results> results(1 + incumbents.size());
  results[0].name = "nbs";
  for (std::size_t k = 0; k < incumbents.size(); ++k) results[1 + k].name = incumbents[k]->name();

  // ---- k exact scans, then `pairs` displaced-and-registered scans (each integrated exactly afterwards) -----------
  std::vector<double> initial_mm[2], normals_ms;
  std::size_t scan_points = 0, model_points = 0;
  int made = 0, nbs_status[8] = {};
  std::vector<Vec3> model_p, model_n;
  nbs::LinearScanPath path = planner.first_scan(1);
  for (int j = 0; j < kExactScans + pairs; ++j) {
    const nbs::Scan exact = scanner.scan(path, planner.sensor(), 100 + static_cast<std::uint64_t>(j));
    if (verbose) std::printf("scan %d: %zu points\n", j + 1, exact.size());
    if (j >= kExactScans && !exact.empty()) {
      // The model as the incumbents take it: the mesh's vertices with a normal (converted outside the timing).
      model_p.clear(), model_n.clear();
      const auto& mesh = planner.mesh();
      for (nbs::VertexId v = 0; v < mesh.vertex_count(); ++v)
        if (mesh.has_normal(v)) model_p.push_back(mesh.position(v)), model_n.push_back(mesh.normal(v));
      for (auto& inc : incumbents) inc->set_model(model_p, model_n);
      Vec3 centroid = Vec3::Zero();
      for (const Vec3& x : exact.points) centroid += x;
      centroid /= static_cast<double>(exact.size());
      const Vec3 origin = exact.profile_poses.front().translation();
      scan_points += exact.size(), model_points += model_p.size();
      ++made;
      for (int ci = 0; ci < 2; ++ci) {
        for (int s = 0; s < seeds; ++s) {
          const std::uint64_t seed = nbs::detail::splitmix64(0x5245475FULL + 1000u * static_cast<unsigned>(j) +
                                                             10u * static_cast<unsigned>(s) + static_cast<unsigned>(ci));
          const Pose e = pose_error(origin, kCases[ci].shift_m, kCases[ci].angle_deg * std::numbers::pi / 180.0, seed);
          const nbs::Scan displaced = nbs::transformed(exact, e);
          initial_mm[ci].push_back(residual(Pose::Identity(), e, centroid).translation_mm);
          for (auto& inc : incumbents) inc->set_source(displaced.points);
          std::vector<double> best(results.size(), 1e300);
          std::vector<Pose> corr(results.size(), Pose::Identity());
          nbs::RegistrationResult nr;
          // The larger case's times are only printed (not a headline): one repetition in quick mode.
          const int case_reps = ci == 1 && quick ? 1 : reps;
          for (int r = 0; r < case_reps; ++r) {  // the methods in turn, so that a change in load affects them alike
            best[0] = std::min(best[0], nbs::bench::seconds([&] { nr = icp.register_scan(displaced, planner.mesh()); }));
            for (std::size_t k = 0; k < incumbents.size(); ++k)
              best[1 + k] = std::min(best[1 + k], nbs::bench::seconds([&] {
                corr[1 + k].matrix() = incumbents[k]->align(radius, iterations);
              }));
          }
          if (ci == 0 && s == 0)  // the part of nbs's time that its scan normals take (public step of Icp)
            normals_ms.push_back(1e3 * nbs::bench::seconds([&] {
              benchmark::DoNotOptimize(nbs::estimate_scan_normals(
                  displaced, {.radius_m = icp.setting.normal_radius_m > 0.0 ? icp.setting.normal_radius_m : radius}));
            }));
          ++nbs_status[static_cast<int>(nr.status)];
          if (nr.applied()) corr[0] = nr.correction;
          else ++results[0].refused[ci];
          for (std::size_t k = 0; k < results.size(); ++k) {
            const Residual res = residual(corr[k], e, centroid);
            results[k].ms[ci].push_back(1e3 * best[k]);
            results[k].t_mm[ci].push_back(res.translation_mm);
            results[k].r_deg[ci].push_back(res.rotation_deg);
            if (verbose)
              std::printf("pair %2d seed %d %s %-6s %8.2f ms  residual %.4f mm %.4f deg  (initial %.4f mm)%s%s\n", made,
                          s, kCases[ci].name, results[k].name.c_str(), 1e3 * best[k], res.translation_mm,
                          res.rotation_deg, initial_mm[ci].back(), k == 0 ? "  " : "",
                          k == 0 ? nbs::to_string(nr.status).data() : "");
          }
        }
      }
    }
    (void)planner.integrate(exact);
    const nbs::PlanResult next = planner.next_best_scan();
    if (!next.ok()) {
      std::printf("bench_registration: planning stopped after %d scans: %s\n", j + 1, nbs::to_string(next.status).data());
      break;
    }
    path = next.path();
  }

  std::printf("bench_registration: %d pairs x %d seeds x 2 error cases, best of %d reps; %.0f scan points, %.0f model "
              "points (mean); radius %.1f mm, %d iterations, 1 thread (3 mm case: best of %d)\n",
              made, seeds, reps, made ? double(scan_points) / made : 0.0, made ? double(model_points) / made : 0.0,
              1e3 * radius, iterations, quick ? 1 : reps);
  for (int st = 0; st < 8; ++st)
    if (nbs_status[st] > 0)
      std::printf("  nbs status %s: %d\n", nbs::to_string(static_cast<nbs::RegistrationStatus>(st)).data(),
                  nbs_status[st]);
  if (made == 0) {
    std::fprintf(stderr, "bench_registration: no scan pair\n");
    return 1;
  }
  for (int ci = 0; ci < 2; ++ci) {
    std::printf("case %s (initial error at the centroid: %.3f mm mean):\n", kCases[ci].name, mean(initial_mm[ci]));
    for (std::size_t k = 0; k < results.size(); ++k) {
      const Results& m = results[k];
      std::printf("  %-6s median %8.2f ms  residual %.4f mm, %.4f deg (mean)", m.name.c_str(), median(m.ms[ci]),
                  mean(m.t_mm[ci]), mean(m.r_deg[ci]));
      if (k == 0) std::printf("  refused %d of %zu", m.refused[ci], m.ms[ci].size());
      if (k == 0 && ci == 0) std::printf("; of it estimate_scan_normals %.2f ms (median, 1 run)", median(normals_ms));
      std::printf("\n");
    }
  }
  const Results& n = results[0];
  nbs::bench::report_headline("registration.icp_ms_per_scan", median(n.ms[0]), "nbs::Icp, median ms per scan");
  for (std::size_t k = 1; k < results.size(); ++k) {
    const Results& m = results[k];
    const std::string err = "registration.icp_error_vs_" + m.name;
    nbs::bench::report_headline("registration.icp_vs_" + m.name, median(m.ms[0]) / median(n.ms[0]),
                                m.name + " time ÷ nbs time, median, same radius and iterations, 1 thread");
    nbs::bench::report_headline(err, mean(n.t_mm[0]) / mean(m.t_mm[0]),
                                "residual translation nbs ÷ " + m.name + ", 1 mm/0.1°; lower is better");
    nbs::bench::report_headline(err + "@3mm", mean(n.t_mm[1]) / mean(m.t_mm[1]),
                                "the same for 3 mm/0.5°; lower is better");
  }
  return 0;
}
