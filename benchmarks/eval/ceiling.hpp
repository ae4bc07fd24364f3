// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The observability ceiling c_obs of an nbs_eval output (issue 18): computed with the rule of the simulated scanner
/// that produced the runs, stamped into eval.json and into every runs.jsonl record, and the `nbs_eval c-obs DIR...`
/// command that recomputes it for existing outputs.

#include <chrono>
#include <cmath>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "eval/config.hpp"
#include "eval/records.hpp"
#include "nbs/embree/simulated_scanner.hpp"
#include "nbs/io/load_mesh.hpp"
#include "nbs/mesh/normalize.hpp"
#include "nbs/sim/ground_truth.hpp"

namespace nbs::eval::detail {

/// eval.json key of the incidence limit (rad) c_obs was computed with. An output without it, or with another value,
/// holds a c_obs of an older rule (the planner's 70° cut-off, which the scanner does not apply) and is recomputed.
inline constexpr const char* kCObsIncidenceKey = "c_obs_incidence_rad";

/// The ground truth of an eval: samples with the completeness radius of the run's parameters, seed 1 (the measuring
/// instrument is the same for every --seed).
[[nodiscard]] inline GroundTruth eval_ground_truth(const IndexedMesh& mesh, double completeness_radius_m) {
  GroundTruth::Setting gts;
  gts.completeness_radius_m = completeness_radius_m;
  gts.seed = 1;
  return GroundTruth(mesh, gts);
}

/// c_obs with the scanner's own measurement rule: the sensor's working range and the scanner's incidence limit
/// (SimulatedScanner::max_incidence_rad: none), so that c_a ≤ c_obs up to the completeness radius. The planner's
/// incidence cut-off (Tab. 4.3, 70°) is the utility's quality rule, not a limit of the measurement.
[[nodiscard]] inline double compute_c_obs(const embree::SimulatedScanner& scanner, const GroundTruth& truth,
                                          const LaserStripeProfiler& sensor, unsigned threads, std::ostream& log) {
  const auto t0 = std::chrono::steady_clock::now();
  const ObservabilitySettings os = embree::SimulatedScanner::observability_settings(sensor, 1000, threads);
  const double c_obs = truth.observability(scanner.scene(), os).c_obs();
  log << "nbs_eval: c_obs " << 100.0 * c_obs << " % (" << truth.samples().size() << " samples, incidence up to "
      << os.incidence_cutoff_rad << " rad, "
      << std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() << " s)\n";
  return c_obs;
}

/// True if eval.json `config` holds a c_obs computed with the current rule.
[[nodiscard]] inline bool c_obs_current(const Json& config) {
  return config.contains("c_obs") && config.contains(kCObsIncidenceKey) &&
         config.at(kCObsIncidenceKey).get<double>() == embree::SimulatedScanner::max_incidence_rad;
}

/// Sets c_obs and its rule in eval.json `config`.
inline void stamp_c_obs(Json& config, double c_obs) {
  config["c_obs"] = c_obs;
  config[kCObsIncidenceKey] = embree::SimulatedScanner::max_incidence_rad;
}

/// Sets "c_obs" of every run record (Json objects with a "c_obs" field) to `c_obs`; returns how many changed.
template <class RunMap>
std::size_t restamp_runs(RunMap& runs, double c_obs) {
  std::size_t changed = 0;
  for (auto& [key, j] : runs) {
    if (j.at("c_obs").template get<double>() != c_obs) ++changed;
    j["c_obs"] = c_obs;
  }
  return changed;
}

/// The ground-truth mesh at `path`, placed as every run places it (normalize_on_pedestal to `size_m` with `up`).
/// Throws UsageError naming the file.
[[nodiscard]] inline IndexedMesh load_eval_mesh(const std::string& path, double size_m, UpAxis up) {
  try {
    IndexedMesh mesh = load_mesh(path);
    if (mesh.triangles.empty() || mesh.vertices.size() < 3)
      throw UsageError("mesh '" + path + "' is not a mesh: it has no triangle");
    normalize_on_pedestal(mesh, size_m, up);
    return mesh;
  } catch (const Error& e) {
    throw UsageError("mesh '" + path + "': " + e.what());
  }
}

/// The mesh of an eval.json (path relative to the working directory, as nbs_eval was called), placed as the runs
/// placed it. Throws UsageError naming the file.
[[nodiscard]] inline IndexedMesh eval_mesh(const Json& config) {
  const std::string up = config.at("up").get<std::string>();
  const std::optional<UpAxis> axis = tools::parse_up(up);
  if (!axis) throw UsageError("eval.json: up must be x, y or z, got '" + up + "'");
  return load_eval_mesh(config.at("mesh").get<std::string>(), config.at("size_m").get<double>(), *axis);
}

}  // namespace nbs::eval::detail
