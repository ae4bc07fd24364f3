// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Statistics of the evaluation harness (thesis Sec. 4.7.2, Tab. 4.5, Eq. 4.41) and the per-method summary.
///
/// Quantile definition (one for median, quartiles and IQR): linear interpolation between order statistics at
/// position h = (n − 1)·p of the sorted sample x_0 ≤ … ≤ x_{n−1}, i.e. Q(p) = x_⌊h⌋ + (h − ⌊h⌋)(x_⌊h⌋+1 − x_⌊h⌋)
/// (Hyndman & Fan type 7; numpy's and matplotlib's boxplot default). Median = Q(0.5), IQR = Q(0.75) − Q(0.25).
/// Notch (Eq. 4.41, Chambers et al. 1983): ±1.57 · IQR / √s with s the number of runs.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace nbs::eval {

/// Q(p) of type 7 (see file comment). Throws std::invalid_argument for an empty sample or p ∉ [0, 1].
[[nodiscard]] inline double quantile(std::span<const double> sample, double p) {
  if (sample.empty()) throw std::invalid_argument("quantile of an empty sample");
  if (!(p >= 0.0 && p <= 1.0)) throw std::invalid_argument("quantile: p must be in [0, 1]");
  std::vector<double> x(sample.begin(), sample.end());
  std::sort(x.begin(), x.end());
  const double h = static_cast<double>(x.size() - 1) * p;
  const auto lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, x.size() - 1);
  return x[lo] + (h - static_cast<double>(lo)) * (x[hi] - x[lo]);
}

[[nodiscard]] inline double median(std::span<const double> sample) { return quantile(sample, 0.5); }

/// Interquartile range Q(0.75) − Q(0.25).
[[nodiscard]] inline double iqr(std::span<const double> sample) {
  return quantile(sample, 0.75) - quantile(sample, 0.25);
}

/// Half-width of the median notch, Eq. (4.41): 1.57 · IQR / √s, s = sample size.
[[nodiscard]] inline double notch(std::span<const double> sample) {
  return 1.57 * iqr(sample) / std::sqrt(static_cast<double>(sample.size()));
}

/// Arithmetic mean. Throws std::invalid_argument for an empty sample.
[[nodiscard]] inline double mean(std::span<const double> sample) {
  if (sample.empty()) throw std::invalid_argument("mean of an empty sample");
  double s = 0.0;
  for (double v : sample) s += v;  // in order: independent of threads
  return s / static_cast<double>(sample.size());
}

/// What one run contributes to its method's summary row (Tab. 4.5).
struct RunOutcome {
  double n_s = 0;           ///< scan at which the set-up's stop rule held, else n_abort
  double ca_at_stop = 0;    ///< c_a(n_s)
  double ca_at_end = 0;     ///< c_a(n_abort) (last scan if the loop ended early)
  double path_length_m = 0; ///< l_s over all scans of the run
  double mean_t_nbs_s = 0;  ///< mean NBS selection time of the run's planning steps (0 if none)
  double c_obs = 0;         ///< observability ceiling of the mesh
  // Truth-based (issue 18): k_x = first scan after which c_a ≥ x · c_obs, n_abort + 1 when never.
  double k95 = 0;           ///< k_0.95
  double k99 = 0;           ///< k_0.99
  double path_to_k99_m = 0; ///< l_s after scan k99; when never reached, l_s over all scans (a lower bound)
  double stop_minus_k99 = 0;///< n_s − k99 (negative: the planner's criterion held before the truth reached 0.99)
  /// With --pose-error / --registration: the run's mean residual pose error over its scans (mm, deg) and its
  /// double_surface_share.
  bool pose = false;
  double mean_pose_t_mm = 0, mean_pose_r_deg = 0, double_surface_share = 0;
  /// With --robot: the means over the run's transfers (scans 2, 3, …) of the joint-space length (rad), the sensor's
  /// path length (m) and the motion-planning time (s); 0 for a run of one scan.
  bool robot = false;
  double mean_transfer_joint_rad = 0, mean_transfer_sensor_m = 0, mean_t_motion_s = 0;
};

/// One row of Tab. 4.5 (plus c_obs and the quartiles).
struct MethodSummary {
  std::string method;
  std::size_t runs = 0;
  double median_scans = 0, q1_scans = 0, q3_scans = 0, notch = 0;
  double mean_ca_at_stop = 0, mean_ca_at_30 = 0, mean_path_length_m = 0, mean_t_nbs_s = 0, mean_c_obs = 0;
  double median_k95 = 0, median_k99 = 0, mean_path_to_k99_m = 0, median_stop_minus_k99 = 0;  ///< truth-based
  /// Only when every run has them (RunOutcome::pose): means over the runs.
  bool pose = false;
  double mean_pose_t_mm = 0, mean_pose_r_deg = 0, mean_double_surface_share = 0;
  /// Only when every run has them (RunOutcome::robot): means over the runs of the per-run transfer means.
  bool robot = false;
  double mean_transfer_joint_rad = 0, mean_transfer_sensor_m = 0, mean_t_motion_s = 0;
};

/// Summarises the runs of one method. Throws std::invalid_argument if `runs` is empty.
[[nodiscard]] inline MethodSummary summarize(const std::string& method, std::span<const RunOutcome> runs) {
  if (runs.empty()) throw std::invalid_argument("summarize: method " + method + " has no runs");
  const auto column = [&](double RunOutcome::*f) {
    std::vector<double> v;
    v.reserve(runs.size());
    for (const RunOutcome& r : runs) v.push_back(r.*f);
    return v;
  };
  const std::vector<double> ns = column(&RunOutcome::n_s);
  MethodSummary s;
  s.method = method;
  s.runs = runs.size();
  s.median_scans = median(ns);
  s.q1_scans = quantile(ns, 0.25);
  s.q3_scans = quantile(ns, 0.75);
  s.notch = notch(ns);
  s.mean_ca_at_stop = mean(column(&RunOutcome::ca_at_stop));
  s.mean_ca_at_30 = mean(column(&RunOutcome::ca_at_end));
  s.mean_path_length_m = mean(column(&RunOutcome::path_length_m));
  s.mean_t_nbs_s = mean(column(&RunOutcome::mean_t_nbs_s));
  s.mean_c_obs = mean(column(&RunOutcome::c_obs));
  s.median_k95 = median(column(&RunOutcome::k95));
  s.median_k99 = median(column(&RunOutcome::k99));
  s.mean_path_to_k99_m = mean(column(&RunOutcome::path_to_k99_m));
  s.median_stop_minus_k99 = median(column(&RunOutcome::stop_minus_k99));
  s.pose = std::all_of(runs.begin(), runs.end(), [](const RunOutcome& r) { return r.pose; });
  if (s.pose) {
    s.mean_pose_t_mm = mean(column(&RunOutcome::mean_pose_t_mm));
    s.mean_pose_r_deg = mean(column(&RunOutcome::mean_pose_r_deg));
    s.mean_double_surface_share = mean(column(&RunOutcome::double_surface_share));
  }
  s.robot = std::all_of(runs.begin(), runs.end(), [](const RunOutcome& r) { return r.robot; });
  if (s.robot) {
    s.mean_transfer_joint_rad = mean(column(&RunOutcome::mean_transfer_joint_rad));
    s.mean_transfer_sensor_m = mean(column(&RunOutcome::mean_transfer_sensor_m));
    s.mean_t_motion_s = mean(column(&RunOutcome::mean_t_motion_s));
  }
  return s;
}

}  // namespace nbs::eval
